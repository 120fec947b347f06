//! The fairness quality table: every curve of the suite (`tests/common/suite.rs`) at tolerances of 1, 3
//! and 10 × its noise σ — the original, the reference smoother (knot-keeping penalized least squares,
//! its weight searched to hold the band) and Fairway's default fair, judged by the independent measures
//! of `measure` (curvature extrema with hysteresis, inflections, ∫(dκ/ds)² ds, max deviation / m).
//!
//! `cargo run --release -p fairway --example quality_table [-- --markdown] [--dump DIR]`
//!
//! `--dump DIR` writes κ(s) of each row for `scripts/plot_kappa.py`. Environment knobs for comparisons:
//! `QT_CASE` (rows whose name contains it), `QT_NOISE` (noise scale; 0 = the noise-free best fits), `QT_SEED` (another noise draw: curves no test has seen),
//! `QT_POLISH` (variation | line-search | interior-point), `QT_CURVE_ENDS` (g0 | g1 | g2), `QT_BETA`
//! (target weight), `QT_ITERS` (polish iterations), `QT_TORSION` (torsion weight).

#[path = "../tests/common/suite.rs"]
mod suite;

use std::time::Instant;

use fairway::BSplineCurve;
use fairway::fair::{FairingOptions, FitMode, fair_curve};
use fairway::measure::{Measures, measure};

fn row(md: bool, cells: &[String]) {
    if md {
        println!("| {} |", cells.join(" | "));
    } else {
        println!("{}", cells.iter().map(|c| format!("{c:>12} ")).collect::<String>());
    }
}

fn fair(curve: &BSplineCurve, opts: FairingOptions) -> (BSplineCurve, f64) {
    let t = Instant::now();
    let r = fair_curve(curve, opts).expect("fair");
    (r.curve, t.elapsed().as_secs_f64() * 1e3)
}

/// κ over normalized arc length (4000 samples), for the plots of `scripts/plot_kappa.py`.
fn kappa_csv(curves: &[&BSplineCurve]) -> String {
    let n = 4000;
    let cols: Vec<Vec<f64>> = curves
        .iter()
        .map(|c| {
            fairway::measure::arc_params(c, n)
                .into_iter()
                .map(|u| c.derivs(u).curvature(c.dim()))
                .collect()
        })
        .collect();
    let mut out = String::from("s,original,reference,fairway\n");
    for k in 0..n {
        out += &format!("{}", k as f64 / (n - 1) as f64);
        for c in &cols {
            out += &format!(",{}", c[k]);
        }
        out += "\n";
    }
    out
}

/// Torsion extrema (3D), "—" in 2D.
fn tau(m: &Measures) -> String {
    m.n_torsion_extrema.map_or("—".into(), |n| n.to_string())
}

fn main() {
    let md = std::env::args().any(|a| a == "--markdown");
    let dump = std::env::args().skip_while(|a| a != "--dump").nth(1);
    let head: Vec<String> = [
        "curve",
        "m/σ",
        "extrema",
        "ref",
        "fairway",
        "infl",
        "ref",
        "fairway",
        "E_var",
        "ref",
        "fairway",
        "dev/m ref",
        "dev/m fw",
        "ms ref",
        "ms fw",
        "τ extrema",
        "ref",
        "fairway",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    row(md, &head);
    if md {
        row(md, &vec!["---".to_string(); head.len()]);
    }
    let (mut wins, mut total, mut worse_than_original) = (0, 0, 0);
    let only = std::env::var("QT_CASE").ok();
    let noise = std::env::var("QT_NOISE").map_or(1.0, |v| v.parse().expect("noise scale"));
    let draw = std::env::var("QT_SEED").map_or(0, |v| v.parse().expect("noise draw"));
    for case in suite::cases_seeded(noise, draw) {
        if only.as_deref().is_some_and(|o| !case.name.contains(o)) {
            continue;
        }
        let orig = measure(&case.curve, &case.curve);
        for f in suite::TOLERANCE_FACTORS {
            let m = f * case.sigma;
            let mut opts = FairingOptions::default().tolerance(m);
            if let Ok(v) = std::env::var("QT_POLISH") {
                opts.polish_method = v.parse().expect("polish method");
            }
            if let Ok(v) = std::env::var("QT_BETA") {
                opts.target_weight = v.parse().expect("beta");
            }
            if let Ok(v) = std::env::var("QT_CURVE_ENDS") {
                opts.curve_ends = [Some(v.parse().expect("curve ends")); 2];
            }
            if let Ok(v) = std::env::var("QT_ITERS") {
                opts.polish_iterations = v.parse().expect("iterations");
            }
            if let Ok(v) = std::env::var("QT_TORSION") {
                opts.torsion_weight = v.parse().expect("torsion weight");
            }
            let (rc, rt) = fair(&case.curve, opts.mode(FitMode::Smoothing));
            let (fc, ft) = fair(&case.curve, opts);
            let (r, w): (Measures, Measures) = (measure(&case.curve, &rc), measure(&case.curve, &fc));
            if let Some(dir) = &dump {
                let path = format!("{dir}/{}_{f}.csv", case.name);
                std::fs::write(&path, kappa_csv(&[&case.curve, &rc, &fc])).expect("write the κ table");
            }
            total += 1;
            if w.n_curv_extrema <= r.n_curv_extrema && w.E_var <= r.E_var {
                wins += 1;
            }
            if w.n_curv_extrema > orig.n_curv_extrema {
                worse_than_original += 1;
            }
            row(
                md,
                &[
                    case.name.to_string(),
                    format!("{f}"),
                    orig.n_curv_extrema.to_string(),
                    r.n_curv_extrema.to_string(),
                    w.n_curv_extrema.to_string(),
                    orig.n_inflections.to_string(),
                    r.n_inflections.to_string(),
                    w.n_inflections.to_string(),
                    format!("{:.4e}", orig.E_var),
                    format!("{:.4e}", r.E_var),
                    format!("{:.4e}", w.E_var),
                    format!("{:.3}", r.dev_max / m),
                    format!("{:.3}", w.dev_max / m),
                    format!("{rt:.2}"),
                    format!("{ft:.2}"),
                    tau(&orig),
                    tau(&r),
                    tau(&w),
                ],
            );
        }
    }
    println!();
    println!(
        "Fairway at least as fair as the reference (extrema and E_var) in {wins} of {total} cases; more extrema \
         than the original in {worse_than_original}."
    );
}
