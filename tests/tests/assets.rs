//! The bundled samples in `assets/` are exactly what the documented generator
//! (`cargo run -p fairway --example make_assets`) produces, and each one loads
//! through the normal file reader with the geometry its README promises.

#[path = "../../crates/fairway/examples/make_assets/generate.rs"]
#[allow(dead_code)]
mod generate;

use std::path::PathBuf;

use fairway::Geometry;

fn assets() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../assets")
}

#[test]
fn assets_are_reproduced_by_the_generator() {
    let generated = generate::generate();
    assert!(generated.len() >= 5);
    for (name, text) in generated {
        let on_disk = std::fs::read_to_string(assets().join(name))
            .unwrap_or_else(|e| panic!("assets/{name}: {e} (run the make_assets example)"));
        assert!(
            on_disk == text,
            "assets/{name} differs from the generator's output; rerun `cargo run -p fairway --example make_assets`"
        );
    }
}

#[test]
fn assets_load_with_the_promised_kinds() {
    let mut curves_2d = 0;
    let mut curves_3d = 0;
    let mut surfaces = 0;
    let mut with_inflections = 0;
    let mut closed = 0;
    for (name, _) in generate::generate() {
        let doc = fairway::io::load(&assets().join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        match &doc.geometry {
            Geometry::Curve(c) if c.dim() == 2 => {
                curves_2d += 1;
                if fairway::fair::closed::is_closed_curve(c) {
                    closed += 1;
                }
                if !c.inflections(8).is_empty() {
                    with_inflections += 1;
                }
            }
            Geometry::Curve(_) => curves_3d += 1,
            Geometry::Surface(_) => surfaces += 1,
        }
    }
    assert!(curves_2d >= 2, "2D curves: {curves_2d}");
    assert!(with_inflections >= 1, "a 2D curve with inflections");
    assert!(closed >= 1, "a closed 2D curve");
    assert!(
        curves_3d >= 1 && surfaces >= 1,
        "3D curves {curves_3d}, surfaces {surfaces}"
    );
}
