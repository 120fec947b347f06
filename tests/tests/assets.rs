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

/// The bundled curves (not the surfaces), loaded through the normal file reader, with their file names.
fn bundled_curves() -> Vec<(&'static str, fairway::BSplineCurve)> {
    generate::generate()
        .into_iter()
        .filter_map(|(name, _)| {
            let doc = fairway::io::load(&assets().join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
            match doc.geometry {
                Geometry::Curve(c) => Some((name, c)),
                _ => None,
            }
        })
        .collect()
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

/// The engine's reported `max_deviation` is a sound bound of the deviation the user would measure and
/// a sharp one: on every bundled curve, whole and over a region (across the seam on a closed one), at a
/// tolerance where the band binds and one where it does not, it is ≥ `measure`'s `dev_max` (a bound),
/// ≤ m, and within 2e-3·m of it (the certified bound of session 19 is sharp to 1e-3·m by design; before
/// it the report was the measured maximum on samples, which missed deviations between samples on long
/// curves), with the default polish and a long one. Before the final sharpening the
/// band checks' early exits reported, e.g., 9.97e-3 for a measured 6.90e-3 (car roof, region
/// [0.35, 0.75], m = 0.01); before session 8's search without a starting guess, 24 polish iterations
/// there reported 2.02e-2 for a measured 6.45e-3 (Newton settled in another local minimum).
#[test]
fn reported_deviation_is_a_sharp_bound_of_the_measured_one() {
    use fairway::fair::{FairingOptions, PolishMethod, curve::POLISH_ITERS, fair_curve};
    let mut cases = 0;
    for (name, c) in &bundled_curves() {
        let (lo, hi) = c.control_bounds();
        let size = lo.distance(hi);
        let (d0, d1) = c.domain();
        let at = |f: f64| d0 + f * (d1 - d0);
        let closed = fairway::fair::closed::is_closed_curve(c);
        let mut regions = vec![None, Some((at(0.35), at(0.75)))];
        if closed {
            regions.push(Some((at(0.8), at(0.2))));
        }
        // the default polish, a long one (the editor's slider goes to 64): the longer the polish, the
        // further the faired curve slides along itself; and the interior-point polish
        let polishes = [
            (POLISH_ITERS, PolishMethod::LineSearch),
            (24, PolishMethod::LineSearch),
            (POLISH_ITERS, PolishMethod::InteriorPoint),
        ];
        for (region, (its, polish_method)) in regions.into_iter().flat_map(|r| polishes.map(|p| (r, p))) {
            for rel in [1e-3, 5e-3] {
                let m = rel * size;
                let opts = FairingOptions::default()
                    .tolerance(m)
                    .region(region)
                    .polish_iterations(its)
                    .polish_method(polish_method);
                let r = fair_curve(c, opts).unwrap_or_else(|e| panic!("{name} {region:?} m {m}: {e}"));
                let measured = fairway::measure::measure(c, &r.curve).dev_max;
                println!(
                    "{name} {region:?} m {m:.3e}, {its} {polish_method:?} polish iterations: reported {:.6e}, measured {measured:.6e}",
                    r.max_deviation
                );
                assert!(r.max_deviation <= m, "{name}: {} > m", r.max_deviation);
                assert!(measured <= r.max_deviation + 1e-12 * size, "{name}: not a bound");
                assert!(
                    r.max_deviation - measured <= 2e-3 * m,
                    "{name} {region:?} m {m}, {its} iterations: reported {} vs measured {measured}",
                    r.max_deviation
                );
                cases += 1;
            }
        }
    }
    assert!(cases >= 30, "{cases} cases");
}

/// A looser tolerance never gives a less fair curve: each bundled curve faired whole at m = 0.003, 0.01,
/// 0.03 and 0.1 (its units), ∫(dκ/ds)² of the result does not rise by more than 10 % from one tolerance to
/// the next (measured: at most +7.6 %, `closed_section` from 0.003 to 0.01). Before session 14 it did:
/// `car_roof` 9.2 → 14.3 from 0.03 to 0.1 (the polish zig-zagged κ about the target), `spatial_curve`
/// 2.7 → 3.8 (and at region [0.2, 0.8] 6.9 → 33: curvature turned out of the osculating plane),
/// `kinked_profile` 25 → 58 → 72 from 0.01 on (its zig-zag stretch faired at the largest fairness weight).
#[test]
fn a_looser_tolerance_never_gives_a_less_fair_curve() {
    use fairway::fair::{FairingOptions, fair_curve};
    let mut curves = 0;
    for (name, c) in &bundled_curves() {
        curves += 1;
        let e0 = fairway::measure::measure(c, c).E_var;
        let mut e_var = vec![];
        for m in [0.003, 0.01, 0.03, 0.1] {
            let opts = FairingOptions::default().tolerance(m);
            let r = fair_curve(c, opts).unwrap_or_else(|e| panic!("{name} m {m}: {e}"));
            let mm = fairway::measure::measure(c, &r.curve);
            assert!(mm.dev_max <= m * (1.0 + 1e-9), "{name} m {m}: {}", mm.dev_max);
            e_var.push(mm.E_var);
        }
        println!("{name}: ∫(dκ/ds)² {e0:.4} -> {e_var:.4?} at m = 0.003, 0.01, 0.03, 0.1");
        assert!(
            e_var.iter().all(|&e| e < e0),
            "{name}: not fairer than the input: {e_var:?} vs {e0}"
        );
        for (i, w) in e_var.windows(2).enumerate() {
            assert!(
                w[1] <= 1.1 * w[0],
                "{name}: less fair at the looser tolerance (step {i}): {e_var:?}"
            );
        }
    }
    assert!(curves >= 5);
}
