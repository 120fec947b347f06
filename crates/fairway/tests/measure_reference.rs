//! `measure` against the reference outputs of an independent implementation
//! (`tests/data/reference/NAME.smoothed.measures.json`, see the README in
//! shared/reference): counts exact, deviations ≤ 1e-6 relative, energies ≤ 1e-3 relative.

use fairway::io::json;
use fairway::measure::measure;
use serde_json::Value;

fn load(name: &str) -> fairway::BSplineCurve {
    let path = format!("{}/../../tests/data/reference/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    json::from_str(&text).unwrap().as_curve().unwrap().clone()
}

fn check(case: &str) {
    let orig = load(&format!("{case}.json"));
    let faired = load(&format!("{case}.smoothed.json"));
    let path = format!(
        "{}/../../tests/data/reference/{case}.smoothed.measures.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let want: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let got = serde_json::to_value(measure(&orig, &faired)).unwrap();
    let mut bad = vec![];
    for (key, rel) in [
        ("dev_max", 1e-6),
        ("dev_rms", 1e-6),
        ("dev_max_reverse", 1e-6),
        ("hausdorff", 1e-6),
        ("length_original", 1e-6),
        ("length", 1e-6),
        ("threshold_delta", 1e-6),
        ("kappa_max_abs", 1e-6),
        ("E_var", 1e-3),
        ("E_bend", 1e-3),
        ("E_var_dimless", 1e-3),
        ("E_bend_dimless", 1e-3),
        ("E_paper", 1e-3),
        ("E_paper_self", 1e-3),
        ("E_paper_norm", 1e-3),
        ("E_paper_self_norm", 1e-3),
    ] {
        let (w, g) = (want[key].as_f64().unwrap(), got[key].as_f64().unwrap());
        if (w - g).abs() > rel * w.abs() {
            bad.push(format!("{key}: want {w} got {g}"));
        }
    }
    for key in [
        "n_curv_extrema",
        "n_curv_extrema_fine",
        "n_curv_extrema_raw",
        "n_inflections",
        "n_inflections_fine",
        "n_inflections_raw",
        "degree",
        "n_ctrl",
    ] {
        if want[key] != got[key] {
            bad.push(format!("{key}: want {} got {}", want[key], got[key]));
        }
    }
    assert!(bad.is_empty(), "{case}:\n{}", bad.join("\n"));
}

#[test]
fn s_curve_matches_reference() {
    check("s_curve");
}

#[test]
fn conical_spiral_matches_reference() {
    check("conical_spiral");
}
