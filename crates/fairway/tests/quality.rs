//! Fairness judged by measures the engine does not optimize (`measure`: curvature extrema with the 1 %
//! hysteresis, ∫(dκ/ds)² ds, deviation by projection) against an independent peer, the reference
//! smoother (knot-keeping penalized least squares, its weight searched to hold the same band): on every
//! curve of the quality suite (tests/common/suite.rs) at 1, 3 and 10 × its noise, the default fair holds
//! the band, has no more curvature extrema and no larger ∫(dκ/ds)² than the smoother, and no more
//! extrema than the original. `cargo run --release -p fairway --example quality_table` prints the table.

#[path = "common/suite.rs"]
mod suite;

use fairway::BSplineCurve;
use fairway::fair::{FairingOptions, FairingResult, FitMode, TORSION_WEIGHT, fair_curve};
use fairway::measure::{deviations, measure};

/// The reference smoother's and the default fair's results at tolerance `m` (with `torsion_weight`).
fn reference_and_fair(c: &BSplineCurve, m: f64, torsion_weight: f64) -> (FairingResult, FairingResult) {
    let opts = FairingOptions::default().tolerance(m).torsion_weight(torsion_weight);
    let reference = fair_curve(c, opts.mode(FitMode::Smoothing)).unwrap();
    (reference, fair_curve(c, opts).unwrap())
}

#[test]
fn the_default_fair_is_at_least_as_fair_as_the_reference_smoother_on_every_suite_curve() {
    let mut failures = vec![];
    let (mut tau_orig, mut tau_ref, mut tau_fw) = (0, 0, 0);
    for case in suite::cases() {
        let orig = measure(&case.curve, &case.curve);
        for f in suite::TOLERANCE_FACTORS {
            let m = f * case.sigma;
            let (reference, fair) = reference_and_fair(&case.curve, m, 0.0);
            let (r, w) = (
                measure(&case.curve, &reference.curve),
                measure(&case.curve, &fair.curve),
            );
            if let (Some(a), Some(b), Some(c)) = (orig.n_torsion_extrema, r.n_torsion_extrema, w.n_torsion_extrema) {
                (tau_orig, tau_ref, tau_fw) = (tau_orig + a, tau_ref + b, tau_fw + c);
            }
            println!(
                "{} m = {f}σ: extrema {} / ref {} / fairway {}, E_var {:.4e} / {:.4e} / {:.4e}, dev/m {:.3} / {:.3}",
                case.name,
                orig.n_curv_extrema,
                r.n_curv_extrema,
                w.n_curv_extrema,
                orig.E_var,
                r.E_var,
                w.E_var,
                r.dev_max / m,
                w.dev_max / m
            );
            // both hold the band as `measure` sees it (2000 arc-length samples of the original projected)
            assert!(
                r.dev_max <= m * (1.0 + 1e-9) && w.dev_max <= m * (1.0 + 1e-9),
                "{} {f}σ",
                case.name
            );
            // and nearly so by a denser projection, both ways: the band is verified at 2000 arc-length
            // samples, and on the clustered knots' short spans (shorter than their spacing) a result can
            // bulge past it between two of them (measured: 0.24 % of m); a check per knot span is issue 26
            for (name, c) in [("reference", &reference.curve), ("fairway", &fair.curve)] {
                let there = deviations(&case.curve, c, 8000).into_iter().fold(0.0, f64::max);
                let back = deviations(c, &case.curve, 8000).into_iter().fold(0.0, f64::max);
                assert!(
                    there <= m * 1.01 && back <= m * 1.01,
                    "{} {f}σ {name}: {there} / {back} vs {m}",
                    case.name
                );
            }
            // the reference uses the band (it is a real peer, not the input left alone)
            assert!(
                r.dev_max > 0.3 * m,
                "{} {f}σ: the reference moved only {}",
                case.name,
                r.dev_max
            );
            if w.n_curv_extrema > r.n_curv_extrema {
                failures.push(format!(
                    "{} {f}σ: extrema {} > reference {}",
                    case.name, w.n_curv_extrema, r.n_curv_extrema
                ));
            }
            if w.E_var > r.E_var * (1.0 + 1e-9) {
                failures.push(format!("{} {f}σ: E_var {} > reference {}", case.name, w.E_var, r.E_var));
            }
            if w.n_curv_extrema > orig.n_curv_extrema {
                failures.push(format!(
                    "{} {f}σ: extrema {} > original {}",
                    case.name, w.n_curv_extrema, orig.n_curv_extrema
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
    println!("Σ torsion extrema over the 3D rows: original {tau_orig}, reference {tau_ref}, fairway {tau_fw}");
}

/// At every tolerance of `case`, the default fair (torsion faired, as by default) holds the band and has no
/// more curvature extrema than the reference smoother or the original and no larger E_var than the smoother.
fn assert_at_least_as_fair_as_the_reference(case: &suite::Case, label: &str) {
    let orig = measure(&case.curve, &case.curve);
    for f in suite::TOLERANCE_FACTORS {
        let m = f * case.sigma;
        let (reference, fair) = reference_and_fair(&case.curve, m, TORSION_WEIGHT);
        let (r, w) = (
            measure(&case.curve, &reference.curve),
            measure(&case.curve, &fair.curve),
        );
        let row = format!(
            "{label} {f}σ: extrema {} / ref {} / fairway {}, E_var {:.4e} / {:.4e} / {:.4e}",
            orig.n_curv_extrema, r.n_curv_extrema, w.n_curv_extrema, orig.E_var, r.E_var, w.E_var
        );
        println!("{row}");
        assert!(w.dev_max <= m * (1.0 + 1e-9), "{row}: dev {:.4e}", w.dev_max);
        assert!(w.n_curv_extrema <= r.n_curv_extrema.min(orig.n_curv_extrema), "{row}");
        assert!(w.E_var <= r.E_var, "{row}");
    }
}

/// Curves no tuning has seen: the suite's shapes and knots with other noise draws
/// (`QT_SEED=k cargo run --release -p fairway --example quality_table` prints the whole table of a draw).
/// Over draws 0–27 these were the rows that lost to the reference smoother before the polish ranked its
/// iterates with `measure`'s dead band and its close calls were measured as the reference is judged: the
/// clustered knots at 1σ (draw 2: E_var +6 %; draw 26: 16 extrema against 14) and the closed trefoil at 1σ
/// (draw 2: 12 extrema against 11, its loop being two blended passes). Every tolerance of those cases
/// is checked here.
#[test]
fn the_default_fair_beats_the_reference_smoother_on_other_noise_draws() {
    for (draw, name) in [(2, "clustered_knots"), (26, "clustered_knots"), (2, "closed_trefoil")] {
        let case = suite::cases_seeded(1.0, draw)
            .into_iter()
            .find(|c| c.name == name)
            .expect("a suite case");
        assert_at_least_as_fair_as_the_reference(&case, &format!("{name} draw {draw}"));
    }
}

/// Shapes of a family no tuning saw (`suite::unseen_shape`; `cargo run --release -p fairway --example
/// unseen_shapes -- 0 80` prints 240 rows). Shape 9 (3D, quintic, 125 control points) at 1σ lost before the
/// polish's result was checked on 10 Gauss nodes a span: 67 extrema against the smoother's 78 but
/// ∫(dκ/ds)² 1.8·10⁹ against 2.7·10⁸ (a curvature spike between the polish's 6 nodes). The first twelve
/// shapes, every tolerance.
#[test]
fn the_default_fair_beats_the_reference_smoother_on_shapes_no_test_was_tuned_on() {
    for k in 0..12 {
        let case = suite::unseen_shape(k);
        assert_at_least_as_fair_as_the_reference(&case, &format!("shape {k}"));
    }
}

/// The reference smoother is what a SciPy user builds by hand: on the shared reference S-curve its result
/// holds the band the reference's own smoothed curve was made for (3σ, σ = 1e-3 of its data) with no more
/// curvature extrema than the original, and the default fair is at least as fair as both.
#[test]
fn the_reference_smoother_is_comparable_to_the_shared_reference() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/reference/s_curve.json"
    ));
    let Ok(text) = text else {
        panic!("tests/data/reference/s_curve.json is missing");
    };
    let c = match fairway::io::json::from_str(&text).unwrap() {
        fairway::Geometry::Curve(c) => c,
        _ => panic!("a curve"),
    };
    let peer = match fairway::io::json::from_str(
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/data/reference/s_curve.smoothed.json"
        ))
        .unwrap(),
    )
    .unwrap()
    {
        fairway::Geometry::Curve(c) => c,
        _ => panic!("a curve"),
    };
    let mp = measure(&c, &peer);
    let m = mp.dev_max;
    let ours = fair_curve(&c, FairingOptions::default().tolerance(m).mode(FitMode::Smoothing)).unwrap();
    let fair = fair_curve(&c, FairingOptions::default().tolerance(m)).unwrap();
    let (mo, mf, m0) = (measure(&c, &ours.curve), measure(&c, &fair.curve), measure(&c, &c));
    println!(
        "S-curve at m = {m:.3e}: extrema original {}, SciPy-made reference {}, our smoother {}, fairway {}; E_var {:.4} / {:.4} / {:.4} / {:.4}",
        m0.n_curv_extrema,
        mp.n_curv_extrema,
        mo.n_curv_extrema,
        mf.n_curv_extrema,
        m0.E_var,
        mp.E_var,
        mo.E_var,
        mf.E_var
    );
    assert!(mo.dev_max <= m * (1.0 + 1e-9) && mf.dev_max <= m * (1.0 + 1e-9));
    assert!(mo.n_curv_extrema <= m0.n_curv_extrema);
    assert!(mf.n_curv_extrema <= mp.n_curv_extrema.min(mo.n_curv_extrema));
    assert!(mf.E_var <= mp.E_var.min(mo.E_var));
}

/// By default the torsion of 3D curves is faired too ([`TORSION_WEIGHT`]): over the suite's 3D rows fewer
/// torsion extrema than the reference smoother and the original, and still no more curvature extrema than
/// the smoother and no larger E_var, row by row. (Without the torsion term the sum is 712, the
/// reference's 451.)
#[test]
fn the_default_fairs_3d_torsion_better_than_the_reference_smoother() {
    let (mut tau_orig, mut tau_ref, mut tau_fw) = (0, 0, 0);
    for case in suite::cases().into_iter().filter(|c| c.curve.dim() == 3) {
        let orig = measure(&case.curve, &case.curve);
        for f in suite::TOLERANCE_FACTORS {
            let m = f * case.sigma;
            let (reference, fair) = reference_and_fair(&case.curve, m, TORSION_WEIGHT);
            let (r, w) = (
                measure(&case.curve, &reference.curve),
                measure(&case.curve, &fair.curve),
            );
            assert!(w.dev_max <= m * (1.0 + 1e-9));
            assert!(w.n_curv_extrema <= r.n_curv_extrema, "{} {f}σ", case.name);
            assert!(w.E_var <= r.E_var, "{} {f}σ", case.name);
            tau_orig += orig.n_torsion_extrema.unwrap();
            tau_ref += r.n_torsion_extrema.unwrap();
            tau_fw += w.n_torsion_extrema.unwrap();
        }
    }
    println!("Σ torsion extrema: original {tau_orig}, reference {tau_ref}, default fair {tau_fw}");
    assert!(
        tau_fw < tau_ref && tau_fw < tau_orig,
        "{tau_orig} / {tau_ref} / {tau_fw}"
    );
}
