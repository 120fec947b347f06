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

/// `kappa_step_max` by closed form: a quadratic with knots 0 0 0 1 2 2 2 is two Bézier arcs meeting at
/// M = (P1 + P2)/2; the curvature at a quadratic Bézier end is h / (2 |leg|²) (h the far point's distance from
/// the end leg's line), here +1/√2 before the knot and −1/√2 after it: a signed step of √2. The same
/// curve with a knot inserted twice into a span (a C2 point in the geometry, multiplicity 2 > p − 2) has
/// no step.
#[test]
fn curvature_step_at_a_knot_matches_the_bezier_end_curvatures() {
    use fairway::DVec2;
    use fairway::measure::curvature_step_max;
    let pts = [
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(2.0, 1.0),
        DVec2::new(3.0, 1.0),
    ];
    let c = fairway::BSplineCurve::new_2d(2, vec![0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0], &pts).unwrap();
    let step = curvature_step_max(&c);
    assert!((step - 2f64.sqrt()).abs() < 1e-6, "step {step}");
    let m = measure(&c, &c);
    assert!((m.kappa_step_max - step / m.kappa_max_abs).abs() < 1e-3 * step / m.kappa_max_abs);
    let smooth = fairway::BSplineCurve::new_2d(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0, 2.0],
        &[pts[0], pts[1], pts[2], pts[3], DVec2::new(4.0, 0.0)],
    )
    .unwrap()
    .insert_knot(0.5, 2)
    .unwrap();
    assert!(curvature_step_max(&smooth) < 1e-6, "{}", curvature_step_max(&smooth));
}
