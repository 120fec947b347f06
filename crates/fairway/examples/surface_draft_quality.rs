//! The editor's surface draft (`SurfaceFairingOptions::draft`) against the draft before session 29 (its
//! isocurves stepping μ below the band's limit: `fairest_isocurves` on) and against the full fair, on
//! the surface suite (`tests/common/surface_suite.rs`) at 1, 3 and 10 × its noise σ: isocurve curvature
//! extrema (as in `surface_quality_table`), `∫∫|∇H|² dA`, the reported deviation and sound band bound
//! over m, the distance to the full fair over m (projection both ways, 61 × 61), and the best of 5 wall
//! times of each draft.
//!
//! `cargo run --release -p fairway --example surface_draft_quality [-- --markdown]`   (`SQT_N`: net size, default 30)

#[path = "../tests/common/surface_suite.rs"]
mod surface_suite;

use std::time::Instant;

use fairway::BSplineSurface;
use fairway::fair::{SurfaceFairingOptions, SurfaceFairingResult, fair_surface};
use fairway::measure_surface::{N_ISO, deviation, iso_stats, mean_curvature_variation};

/// The best of 5 wall times (ms) of the fair with `opts`, and its result.
fn timed(s: &BSplineSurface, opts: SurfaceFairingOptions) -> (SurfaceFairingResult, f64) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..5 {
        let t = Instant::now();
        let r = fair_surface(s, opts).expect("draft");
        best = best.min(t.elapsed().as_secs_f64() * 1e3);
        out = Some(r);
    }
    (out.expect("five runs"), best)
}

fn main() {
    let md = std::env::args().any(|a| a == "--markdown");
    let n = std::env::var("SQT_N").map_or(30, |v| v.parse().expect("net size"));
    let row = |cells: &[String]| {
        if md {
            println!("| {} |", cells.join(" | "));
        } else {
            println!("{}", cells.iter().map(|c| format!("{c:>14} ")).collect::<String>());
        }
    };
    let head = [
        "surface",
        "m/σ",
        "extrema full",
        "before",
        "draft",
        "∫∫|∇H|² full",
        "before",
        "draft",
        "bound/m draft",
        "to full/m before",
        "draft",
        "ms before",
        "draft",
    ];
    row(&head.map(String::from));
    if md {
        row(&vec!["---".to_string(); head.len()]);
    }
    let cases = surface_suite::surface_cases(n)
        .into_iter()
        .chain(surface_suite::asset_cases());
    for case in cases {
        let s = &case.surface;
        let delta = 0.01 * iso_stats(s, N_ISO, 0.0).max_abs_kappa;
        let ext = |x: &BSplineSurface| {
            let st = iso_stats(x, N_ISO, delta);
            st.extrema_u + st.extrema_v
        };
        for f in surface_suite::TOLERANCE_FACTORS {
            let m = f * case.sigma;
            let full = fair_surface(s, SurfaceFairingOptions::default().tolerance(m)).expect("full fair");
            let draft = SurfaceFairingOptions::default().tolerance(m).draft();
            let (before, tb) = timed(s, draft.fairest_isocurves(true));
            let (now, tn) = timed(s, draft);
            let to_full =
                |x: &BSplineSurface| deviation(x, &full.surface, 61).0.max(deviation(&full.surface, x, 61).0) / m;
            row(&[
                case.name.to_string(),
                format!("{f}"),
                ext(&full.surface).to_string(),
                ext(&before.surface).to_string(),
                ext(&now.surface).to_string(),
                format!("{:.4e}", mean_curvature_variation(&full.surface)),
                format!("{:.4e}", mean_curvature_variation(&before.surface)),
                format!("{:.4e}", mean_curvature_variation(&now.surface)),
                now.band_bound.map_or("—".into(), |b| format!("{:.3}", b / m)),
                format!("{:.2}", to_full(&before.surface)),
                format!("{:.2}", to_full(&now.surface)),
                format!("{tb:.1}"),
                format!("{tn:.1}"),
            ]);
        }
    }
}
