//! Fairness on real CAD curves: every B-spline curve (IGES entity 126) of the given IGES files with at
//! least `RC_MIN_POINTS` (default 8) control points, polynomial or with equal weights, faired at a
//! tolerance of 5·10⁻⁴ × its bounding-box diagonal (issue 25's setting) by the reference smoother
//! (knot-keeping penalized least squares) and by Fairway's default; judged by `measure` (curvature
//! extrema with hysteresis, ∫(dκ/ds)² ds, torsion extrema, max deviation / m).
//!
//! `scripts/real_curves.sh` downloads public IGES data (the impeller model shipped in the `pyiges` package
//! from PyPI, MIT licence) into a throw-away folder and runs this on it; nothing of it is committed.
//!
//! `cargo run --release -p fairway --example real_curves -- FILE.igs... [--markdown]`; `RC_TORSION` sets the
//! torsion weight, `RC_ITERS` the polish iterations, `RC_DUMP=model#entity` writes that curve to `/tmp/model#entity.json`.

use std::time::Instant;

use fairway::fair::{FairingOptions, FitMode, fair_curve};
use fairway::measure::measure;
use fairway::{BSplineCurve, Geometry};

fn diagonal(c: &BSplineCurve) -> f64 {
    let (mut lo, mut hi) = (
        fairway::DVec3::splat(f64::INFINITY),
        fairway::DVec3::splat(f64::NEG_INFINITY),
    );
    for &p in c.points() {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    (hi - lo).length()
}

fn row(md: bool, cells: &[String]) {
    if md {
        println!("| {} |", cells.join(" | "));
    } else {
        println!("{}", cells.iter().map(|c| format!("{c:>11} ")).collect::<String>());
    }
}

fn main() {
    let md = std::env::args().any(|a| a == "--markdown");
    let min_points: usize = std::env::var("RC_MIN_POINTS").map_or(8, |v| v.parse().expect("RC_MIN_POINTS"));
    let files: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    let head: Vec<String> = [
        "curve",
        "points",
        "deg",
        "extrema",
        "ref",
        "fairway",
        "E_var",
        "ref",
        "fairway",
        "κ step",
        "ref",
        "fairway",
        "dev/m ref",
        "dev/m fw",
        "τ ext",
        "ref",
        "fairway",
        "ms ref",
        "ms fw",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    row(md, &head);
    if md {
        row(md, &vec!["---".to_string(); head.len()]);
    }
    let (mut total, mut wins, mut worse, mut failed) = (0, 0, 0, 0);
    // curves where the reference has the lower E_var but not more extrema, and a larger curvature step at a
    // knot (which E_var does not see) than Fairway's result
    let mut steps = 0;
    let (mut sum_o, mut sum_r, mut sum_f) = (0, 0, 0);
    let (mut tau_r, mut tau_f) = (0, 0);
    // a model repeats shapes (an impeller's blades are rotated copies): one row per shape, told apart by
    // control-point count, length and the original's measures
    let mut seen: Vec<String> = vec![];
    for file in &files {
        let bytes = std::fs::read(file).unwrap_or_else(|e| panic!("{file}: {e}"));
        let iges = fairway::io::iges::read_all(&bytes).unwrap_or_else(|e| panic!("{file}: {e}"));
        let name = std::path::Path::new(file)
            .file_stem()
            .unwrap()
            .to_string_lossy()
            .to_string();
        for (g, info) in iges.objects.iter().zip(&iges.entities) {
            let Geometry::Curve(c) = g else { continue };
            let Ok(c) = c.to_polynomial() else { continue };
            if c.n_points() < min_points {
                continue;
            }
            let o = measure(&c, &c);
            let key = format!(
                "{} {:.6e} {} {:.4e}",
                c.n_points(),
                c.length(1e-9),
                o.n_curv_extrema,
                o.E_var
            );
            if seen.contains(&key) {
                continue;
            }
            seen.push(key);
            let m = 5e-4 * diagonal(&c);
            if !(m > 0.0) {
                continue;
            }
            let mut opts = FairingOptions::default().tolerance(m);
            if let Ok(v) = std::env::var("RC_ITERS") {
                opts.polish_iterations = v.parse().expect("RC_ITERS");
            }
            if let Ok(v) = std::env::var("RC_TORSION") {
                opts.torsion_weight = v.parse().expect("RC_TORSION");
            }
            let t = Instant::now();
            let r = fair_curve(&c, opts.mode(FitMode::Smoothing));
            let rt = t.elapsed().as_secs_f64() * 1e3;
            let t = Instant::now();
            let f = fair_curve(&c, opts);
            let ft = t.elapsed().as_secs_f64() * 1e3;
            let label = format!("{name}#{}", info.entity);
            if std::env::var("RC_DUMP").is_ok_and(|d| d == label) {
                let doc = fairway::io::Document::new(Geometry::Curve(c.clone()));
                fairway::io::save(std::path::Path::new(&format!("/tmp/{label}.json")), &doc).expect("dump");
            }
            let (r, f) = match (r, f) {
                (Ok(r), Ok(f)) => (r, f),
                (r, f) => {
                    failed += 1;
                    eprintln!("{label}: reference {:?}, fairway {:?}", r.err(), f.err());
                    continue;
                }
            };
            let (mr, mf) = (measure(&c, &r.curve), measure(&c, &f.curve));
            total += 1;
            if mf.n_curv_extrema <= mr.n_curv_extrema && mf.E_var <= mr.E_var {
                wins += 1;
            } else if mf.n_curv_extrema <= mr.n_curv_extrema && mf.kappa_step_max < mr.kappa_step_max {
                steps += 1;
            }
            if mf.n_curv_extrema > o.n_curv_extrema {
                worse += 1;
            }
            sum_o += o.n_curv_extrema;
            sum_r += mr.n_curv_extrema;
            sum_f += mf.n_curv_extrema;
            tau_r += mr.n_torsion_extrema.unwrap_or(0);
            tau_f += mf.n_torsion_extrema.unwrap_or(0);
            let tau = |m: &fairway::measure::Measures| m.n_torsion_extrema.map_or("—".into(), |n| n.to_string());
            row(
                md,
                &[
                    label,
                    c.n_points().to_string(),
                    c.degree().to_string(),
                    o.n_curv_extrema.to_string(),
                    mr.n_curv_extrema.to_string(),
                    mf.n_curv_extrema.to_string(),
                    format!("{:.3e}", o.E_var),
                    format!("{:.3e}", mr.E_var),
                    format!("{:.3e}", mf.E_var),
                    format!("{:.3}", o.kappa_step_max),
                    format!("{:.3}", mr.kappa_step_max),
                    format!("{:.3}", mf.kappa_step_max),
                    format!("{:.3}", mr.dev_max / m),
                    format!("{:.3}", mf.dev_max / m),
                    tau(&o),
                    tau(&mr),
                    tau(&mf),
                    format!("{rt:.2}"),
                    format!("{ft:.2}"),
                ],
            );
        }
    }
    println!();
    println!(
        "{total} curves: Fairway at least as fair as the reference (extrema and E_var) in {wins}; of the others, with \
         no more extrema and a smaller curvature step at a knot than the reference in {steps}; more extrema than \
         the original in {worse}; Σ curvature extrema original {sum_o}, reference {sum_r}, Fairway {sum_f}; Σ \
         torsion extrema reference {tau_r}, Fairway {tau_f}; {failed} not faired"
    );
}
