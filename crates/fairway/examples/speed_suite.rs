//! The quality suite's curves (`tests/common/suite.rs`) at 1, 3 and 10 × their noise σ, with the CPU time of
//! Fairway's default full fair (`fair_curve`, setup included: CPU per fair over ≥ 0.3 s of fairs, and the fastest fair's wall time) — one JSON object a line,
//! for `scripts/bench-vs-scipy.sh`, which fits the same curves with SciPy's smoothing splines.
//!
//! `cargo run --release -p fairway --example speed_suite > suite.jsonl` (`ONLY=quintic`: those rows only)

#[path = "../benches/common/mod.rs"]
mod common;
#[path = "../tests/common/suite.rs"]
mod suite;
use common::process_cpu_ns as cpu_ns;

use std::hint::black_box;
use std::time::Instant;

use fairway::fair::{FairingOptions, fair_curve};

fn list(v: impl Iterator<Item = f64>) -> String {
    let items: Vec<String> = v.map(|x| format!("{x:?}")).collect();
    format!("[{}]", items.join(","))
}

fn main() {
    // ONLY=quintic runs only the cases whose name contains it (for a profile of one row)
    let only = std::env::var("ONLY").unwrap_or_default();
    for case in suite::cases().into_iter().filter(|c| c.name.contains(only.as_str())) {
        let c = &case.curve;
        for f in suite::TOLERANCE_FACTORS {
            let m = f * case.sigma;
            let opts = FairingOptions::default().tolerance(m);
            black_box(fair_curve(c, opts).expect("fair"));
            // at least 0.3 s of fairs: the CPU time per fair is the loop's over its count (all threads: a closed
            // curve's two passes run side by side); the fastest single fair's wall time too
            let (t0, c0) = (Instant::now(), cpu_ns());
            let (mut n, mut best) = (0u32, f64::INFINITY);
            while n < 3 || t0.elapsed().as_secs_f64() < 0.3 {
                let t = Instant::now();
                black_box(fair_curve(black_box(c), opts).expect("fair"));
                best = best.min(t.elapsed().as_secs_f64() * 1e3);
                n += 1;
            }
            let wall = t0.elapsed().as_secs_f64();
            let cpu_ms = match (c0, cpu_ns()) {
                (Some(a), Some(b)) => (b - a) as f64 * 1e-6 / n as f64,
                _ => wall * 1e3 / n as f64,
            };
            let pts = c.points();
            println!(
                "{{\"name\":\"{}\",\"factor\":{f:?},\"m\":{m:?},\"dim\":{},\"degree\":{},\"closed\":{},\"knots\":{},\"x\":{},\"y\":{},\"z\":{},\"w\":{},\"fairway_cpu_ms\":{cpu_ms:?},\"fairway_min_ms\":{best:?}}}",
                case.name,
                c.dim(),
                c.degree(),
                fairway::fair::closed::is_closed_curve(c),
                list(c.knots().values().iter().copied()),
                list(pts.iter().map(|p| p.x)),
                list(pts.iter().map(|p| p.y)),
                list(pts.iter().map(|p| p.z)),
                c.weights().map_or("null".to_string(), |w| list(w.iter().copied())),
            );
        }
    }
}
