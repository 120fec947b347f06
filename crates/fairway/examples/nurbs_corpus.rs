//! The NURBS faces of the real-data corpus (`tests/data/corpus`): each rational surface with unequal
//! weights faired as `tests/tests/corpus.rs` does (5·10⁻⁴ × its control box diagonal), and how: through
//! the non-rational stand-in, on its own knots and weights (the stand-in's fair added extrema), refused,
//! or failed; for each faired face the isocurve curvature extrema (1 % hysteresis, 16 isocurves) and the
//! isocurve curvature variation before and after, and the deviation bound over m.
//!
//! ```sh
//! cargo run --release -p fairway --example nurbs_corpus            # summary
//! VERBOSE=1 cargo run --release -p fairway --example nurbs_corpus  # one line per face
//! ```

use std::path::Path;

use fairway::fair::{SurfaceFairingOptions, fair_surface};
use fairway::measure_surface::iso_stats;
use fairway::{BSplineSurface, Geometry};

/// How one face fared, with (extrema, variation) before and after for a faired one.
enum Outcome {
    StandIn(Stats),
    OwnWeights(Stats),
    Refused(String),
    Failed(String),
}

struct Stats {
    extrema: (usize, usize),
    variation: (f64, f64),
    bound_over_m: f64,
}

fn fair_face(s: &BSplineSurface) -> Outcome {
    let (lo, hi) = s.control_bounds();
    let m = 5e-4 * (hi - lo).length();
    let r = match fair_surface(s, SurfaceFairingOptions::default().tolerance(m)) {
        Ok(r) => r,
        Err(e) if e.to_string().contains("could not be faired without adding") => {
            return Outcome::Refused(e.to_string());
        }
        Err(e) => return Outcome::Failed(e.to_string()),
    };
    let delta = 0.01 * iso_stats(s, 16, 0.0).max_abs_kappa;
    let (a, b) = (iso_stats(s, 16, delta), iso_stats(&r.surface, 16, delta));
    let stats = Stats {
        extrema: (a.extrema_u + a.extrema_v, b.extrema_u + b.extrema_v),
        variation: (a.e_var_u + a.e_var_v, b.e_var_u + b.e_var_v),
        bound_over_m: r.band_bound.unwrap_or(f64::INFINITY) / m,
    };
    if r.notes.iter().any(|n| n.contains("on its own knots and weights")) {
        Outcome::OwnWeights(stats)
    } else {
        Outcome::StandIn(stats)
    }
}

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/corpus");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let e = p
                .extension()
                .and_then(|e| e.to_str())
                .unwrap_or("")
                .to_ascii_lowercase();
            matches!(e.as_str(), "igs" | "iges" | "stp" | "step")
        })
        .collect();
    files.sort();
    let verbose = std::env::var("VERBOSE").is_ok();
    let mut rows: Vec<(String, Outcome)> = vec![];
    for f in &files {
        let bytes = std::fs::read(f).unwrap();
        let step = matches!(f.extension().and_then(|e| e.to_str()), Some("stp" | "step"));
        let read = if step {
            fairway::io::step::read_all(&bytes)
        } else {
            fairway::io::iges::read_all(&bytes)
        };
        let name = f.file_name().unwrap().to_string_lossy().to_string();
        for (k, g) in read.unwrap().objects.iter().enumerate() {
            if let Geometry::Surface(s) = g
                && !s.is_polynomial()
            {
                let o = fair_face(s);
                if verbose {
                    print_row(&format!("{name} object {k}"), &o);
                }
                rows.push((format!("{name} object {k}"), o));
            }
        }
    }
    summary(&rows);
}

fn print_row(what: &str, o: &Outcome) {
    match o {
        Outcome::StandIn(s) | Outcome::OwnWeights(s) => println!(
            "{what}\t{}\textrema {} -> {}\tE_var {:.4e} -> {:.4e}\tbound/m {:.3}",
            if matches!(o, Outcome::StandIn(_)) {
                "stand-in"
            } else {
                "own weights"
            },
            s.extrema.0,
            s.extrema.1,
            s.variation.0,
            s.variation.1,
            s.bound_over_m
        ),
        Outcome::Refused(e) => println!("{what}\trefused\t{e}"),
        Outcome::Failed(e) => println!("{what}\tFAILED\t{e}"),
    }
}

fn summary(rows: &[(String, Outcome)]) {
    let count = |f: &dyn Fn(&Outcome) -> bool| rows.iter().filter(|(_, o)| f(o)).count();
    println!(
        "NURBS faces: {} — {} through the stand-in, {} on their own knots and weights, {} refused, {} failed",
        rows.len(),
        count(&|o| matches!(o, Outcome::StandIn(_))),
        count(&|o| matches!(o, Outcome::OwnWeights(_))),
        count(&|o| matches!(o, Outcome::Refused(_))),
        count(&|o| matches!(o, Outcome::Failed(_)))
    );
    let own: Vec<&Stats> = rows
        .iter()
        .filter_map(|(_, o)| match o {
            Outcome::OwnWeights(s) => Some(s),
            _ => None,
        })
        .collect();
    if own.is_empty() {
        return;
    }
    let changed = own.iter().filter(|s| s.variation.1 != s.variation.0).count();
    let fewer = own.iter().filter(|s| s.extrema.1 < s.extrema.0).count();
    let same = own.iter().filter(|s| s.extrema.1 == s.extrema.0).count();
    let (e0, e1) = own.iter().fold((0, 0), |(a, b), s| (a + s.extrema.0, b + s.extrema.1));
    let mut ratios: Vec<f64> = own.iter().map(|s| s.variation.1 / s.variation.0).collect();
    ratios.sort_by(f64::total_cmp);
    let lower = ratios.iter().filter(|&&r| r < 1.0).count();
    let worst_bound = own.iter().map(|s| s.bound_over_m).fold(0.0f64, f64::max);
    println!(
        "own knots and weights: {} faces, {changed} changed; extrema {e0} -> {e1} in all ({fewer} fewer, {same} \
         the same); isocurve curvature variation after/before: median {:.3}, min {:.3}, max {:.3} ({lower} \
         lower); largest bound/m {worst_bound:.4}",
        own.len(),
        ratios[ratios.len() / 2],
        ratios[0],
        ratios[ratios.len() - 1]
    );
}
