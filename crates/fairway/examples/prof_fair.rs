//! Profiling driver (temporary).
use fairway::fair::{FairingOptions, FairingSetup};
use fairway::{BSplineCurve, DVec2, KnotVector};
use std::time::Instant;
fn noisy_curve(n: usize) -> BSplineCurve {
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let pts: Vec<DVec2> = (0..n)
        .map(|i| {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let noise = ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.01;
            let t = i as f64 / (n - 1) as f64;
            DVec2::new(4.0 * t, 0.5 * (3.0 * t).sin() + noise)
        })
        .collect();
    BSplineCurve::new_2d(3, KnotVector::uniform(3, n).unwrap().values().to_vec(), &pts).unwrap()
}
fn main() {
    let n: usize = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(100);
    let iters: usize = std::env::args().nth(2).map(|s| s.parse().unwrap()).unwrap_or(200);
    let cv = noisy_curve(n);
    let o = FairingOptions { tolerance: 2e-3, samples: Some(10 * n), ..Default::default() };
    let t0 = Instant::now();
    let mut ts = 0.0;
    let mut r = None;
    for _ in 0..iters {
        let a = Instant::now();
        let mut s = FairingSetup::new(&cv, o).unwrap();
        ts += a.elapsed().as_secs_f64();
        r = Some(s.fair().unwrap());
    }
    let tot = t0.elapsed().as_secs_f64() / iters as f64;
    let r = r.unwrap();
    println!("n={n} full {:.1} us, setup {:.1} us; mu {:.3e} alpha {} solves {} dev {:.3e} E {:.4e}", tot * 1e6, ts / iters as f64 * 1e6, r.mu, r.alpha, r.solves, r.max_deviation, r.energy);
}
