//! The surface fairness quality table: every surface of the suite (`tests/common/surface_suite.rs`) at
//! tolerances of 1, 3 and 10 × its noise σ — the original, the reference smoother (tensor-product
//! penalized least squares with the curvature-variation energy, its strength searched to hold the band,
//! `SurfaceMethod::Smoothing`), the isocurve fairing alone (`SurfaceMethod::Isocurves`, the default
//! before the step-8 choice) and Fairway's default, judged by the measures of `measure_surface`:
//! isocurve curvature extrema (20 isocurves per direction, dead band 1 % of the original's max |κ_n|),
//! `∫∫|∇H|² dA`, the deviation by projection both ways (101 × 101 samples) over m.
//!
//! `cargo run --release -p fairway --example surface_quality_table [-- --markdown]`
//!
//! `SQT_N` sets the suite's net size (default 16); `SQT_CASE` keeps the rows whose name contains it.

#[path = "../tests/common/surface_suite.rs"]
mod surface_suite;

use std::time::Instant;

use fairway::BSplineSurface;
use fairway::fair::{SurfaceFairingOptions, SurfaceFairingResult, SurfaceMethod, fair_surface};
use fairway::measure_surface::{N_ISO, deviation, iso_stats, mean_curvature_variation};

fn row(md: bool, cells: &[String]) {
    if md {
        println!("| {} |", cells.join(" | "));
    } else {
        println!("{}", cells.iter().map(|c| format!("{c:>11} ")).collect::<String>());
    }
}

fn fair(s: &BSplineSurface, m: f64, method: SurfaceMethod) -> (SurfaceFairingResult, f64) {
    let t = Instant::now();
    let r = fair_surface(s, SurfaceFairingOptions::default().tolerance(m).method(method)).expect("fair");
    (r, t.elapsed().as_secs_f64() * 1e3)
}

fn main() {
    let md = std::env::args().any(|a| a == "--markdown");
    let n = std::env::var("SQT_N").map_or(16, |v| v.parse().expect("net size"));
    let only = std::env::var("SQT_CASE").ok();
    let head: Vec<String> = [
        "surface",
        "m/σ",
        "extrema",
        "ref",
        "today",
        "fairway",
        "∫∫|∇H|²",
        "ref",
        "today",
        "fairway",
        "dev/m ref",
        "dev/m fw",
        "bound/m fw",
        "ms ref",
        "ms today",
        "ms fw",
        "pick",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    row(md, &head);
    if md {
        row(md, &vec!["---".to_string(); head.len()]);
    }
    let (mut total, mut vs_ref, mut vs_today, mut vs_orig, mut today_vs_ref) = (0, 0, 0, 0, 0);
    let mut certified = 0;
    let mut sums = [0usize; 4];
    let cases = surface_suite::surface_cases(n)
        .into_iter()
        .chain(surface_suite::asset_cases());
    for case in cases {
        if only.as_deref().is_some_and(|o| !case.name.contains(o)) {
            continue;
        }
        let s = &case.surface;
        let delta = 0.01 * iso_stats(s, N_ISO, 0.0).max_abs_kappa;
        let ext = |x: &BSplineSurface| {
            let st = iso_stats(x, N_ISO, delta);
            st.extrema_u + st.extrema_v
        };
        let dev = |x: &BSplineSurface| deviation(s, x, 101).0.max(deviation(x, s, 101).0);
        let (e0, h0) = (ext(s), mean_curvature_variation(s));
        for f in surface_suite::TOLERANCE_FACTORS {
            let m = f * case.sigma;
            let (r, rt) = fair(s, m, SurfaceMethod::Smoothing);
            let (t, tt) = fair(s, m, SurfaceMethod::Isocurves);
            let (w, wt) = fair(s, m, SurfaceMethod::Fairway);
            let (er, et, ew) = (ext(&r.surface), ext(&t.surface), ext(&w.surface));
            let (hr, ht, hw) = (
                mean_curvature_variation(&r.surface),
                mean_curvature_variation(&t.surface),
                mean_curvature_variation(&w.surface),
            );
            total += 1;
            certified += usize::from(w.band_bound.is_some_and(|b| b <= m));
            vs_ref += usize::from(ew <= er && hw <= hr);
            vs_today += usize::from(ew <= et && hw <= ht);
            vs_orig += usize::from(ew <= e0 && hw <= h0);
            today_vs_ref += usize::from(et <= er && ht <= hr);
            for (acc, e) in sums.iter_mut().zip([e0, er, et, ew]) {
                *acc += e;
            }
            row(
                md,
                &[
                    case.name.to_string(),
                    format!("{f}"),
                    e0.to_string(),
                    er.to_string(),
                    et.to_string(),
                    ew.to_string(),
                    format!("{h0:.4e}"),
                    format!("{hr:.4e}"),
                    format!("{ht:.4e}"),
                    format!("{hw:.4e}"),
                    format!("{:.3}", dev(&r.surface) / m),
                    format!("{:.3}", dev(&w.surface) / m),
                    w.band_bound.map_or("—".into(), |b| format!("{:.3}", b / m)),
                    format!("{rt:.0}"),
                    format!("{tt:.0}"),
                    format!("{wt:.0}"),
                    format!("{:?}", w.pick),
                ],
            );
        }
    }
    println!();
    println!(
        "Fairway's default at least as fair as the reference (extrema and ∫∫|∇H|²) in {vs_ref} of {total} rows, as \
         today's isocurve fairing in {vs_today}, as the original in {vs_orig} (today's as the reference in \
         {today_vs_ref}); Σ extrema original {}, reference {}, today {}, fairway {}.",
        sums[0], sums[1], sums[2], sums[3]
    );
    println!(
        "The band certified everywhere by the sound bound (fair::verify::surface_band_bound ≤ m) in {certified} of \
         {total} rows."
    );
}
