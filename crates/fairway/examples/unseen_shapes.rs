//! Shapes no test has seen: random planar curves from random curvature profiles and random 3D curves
//! (a few Fourier terms), degrees 2–5, 20–150 control points, made noisy as the suite's are, each at 1, 3
//! and 10 × its noise — the default against the reference smoother, judged by `measure`.
//!
//! `cargo run --release -p fairway --example unseen_shapes [-- FIRST COUNT [closed]]` (shapes
//! FIRST..FIRST+COUNT; `closed`: the closed family, `suite::unseen_closed_shape`)

#[path = "../tests/common/suite.rs"]
mod suite;

use fairway::fair::{FairingOptions, FitMode, fair_curve};
use fairway::measure::measure;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let first: u64 = args.get(1).map_or(0, |s| s.parse().expect("first shape"));
    let count: u64 = args.get(2).map_or(20, |s| s.parse().expect("count"));
    let closed = args.get(3).is_some_and(|a| a == "closed");
    let (mut rows, mut wins, mut worse) = (0, 0, 0);
    for k in first..first + count {
        let suite::Case { curve, sigma, .. } = if closed {
            suite::unseen_closed_shape(k)
        } else {
            suite::unseen_shape(k)
        };
        let (dim, p, n) = (curve.dim(), curve.degree(), curve.n_points());
        let orig = measure(&curve, &curve);
        for f in [1.0, 3.0, 10.0] {
            let m = f * sigma;
            let opts = FairingOptions::default().tolerance(m);
            let (Ok(r), Ok(w)) = (
                fair_curve(&curve, opts.mode(FitMode::Smoothing)),
                fair_curve(&curve, opts),
            ) else {
                println!("shape {k}: a fair failed");
                continue;
            };
            let (r, w) = (measure(&curve, &r.curve), measure(&curve, &w.curve));
            rows += 1;
            let win = w.n_curv_extrema <= r.n_curv_extrema && w.E_var <= r.E_var;
            wins += usize::from(win);
            worse += usize::from(w.n_curv_extrema > orig.n_curv_extrema);
            println!(
                "shape {k:>3} d{dim} p{p} n{n:>3} {f:>2}σ: extrema {:>3} / ref {:>3} / fw {:>3}  E_var {:.4e} / {:.4e} / {:.4e}  dev/m {:.3} {}",
                orig.n_curv_extrema,
                r.n_curv_extrema,
                w.n_curv_extrema,
                orig.E_var,
                r.E_var,
                w.E_var,
                w.dev_max / m,
                if win { "" } else { "LOSES" }
            );
        }
    }
    println!("at least as fair as the reference in {wins} of {rows}; more extrema than the original in {worse}");
}
