//! Profiling driver (temporary).
use fairway::fair::{FairingOptions, FairingSetup};
use fairway::{BSplineCurve, DVec2, KnotVector};
use std::time::Instant;
fn noisy_curve(n: usize) -> BSplineCurve {
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let pts: Vec<DVec2> = (0..n)
        .map(|i| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let noise = ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.01;
            let t = i as f64 / (n - 1) as f64;
            DVec2::new(4.0 * t, 0.5 * (3.0 * t).sin() + noise)
        })
        .collect();
    BSplineCurve::new_2d(3, KnotVector::uniform(3, n).unwrap().values().to_vec(), &pts).unwrap()
}
fn main() {
    if std::env::var("PAPER").is_ok() {
        let cv = noisy_curve(100);
        let o = FairingOptions {
            tolerance: 2e-3,
            samples: Some(1000),
            mode: fairway::fair::FitMode::Paper,
            ..Default::default()
        };
        let mut s = FairingSetup::new(&cv, o).unwrap();
        let mut best = f64::INFINITY;
        let mut r = None;
        for _ in 0..20 {
            let t = Instant::now();
            for _ in 0..50 {
                r = Some(s.fair().unwrap());
            }
            best = best.min(t.elapsed().as_secs_f64() / 50.0);
        }
        let r = r.unwrap();
        let e0 = s.energy(&cv);
        println!(
            "paper-mode fair (given setup) {:.1} us, E {:.1} -> {:.1}, dev {:.3e}",
            best * 1e6,
            e0,
            r.energy,
            r.max_deviation
        );
        return;
    }
    if std::env::var("ITER").is_ok() {
        let cv = noisy_curve(100);
        let o = FairingOptions {
            tolerance: 2e-3,
            samples: Some(1000),
            ..Default::default()
        };
        let s = FairingSetup::new(&cv, o).unwrap();
        let t = Instant::now();
        let r = fairway::fair::fair_iterative(&s, Default::default()).unwrap();
        println!(
            "iterative {:.1} ms E {:e} dev {:.3e}",
            t.elapsed().as_secs_f64() * 1e3,
            r.energy,
            r.max_deviation
        );
        return;
    }
    let n: usize = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(100);
    let iters: usize = std::env::args().nth(2).map(|s| s.parse().unwrap()).unwrap_or(200);
    let cv = noisy_curve(n);
    let pit: usize = std::env::var("PIT").ok().and_then(|v| v.parse().ok()).unwrap_or(8);
    let o = FairingOptions {
        tolerance: 2e-3,
        samples: Some(10 * n),
        polish: std::env::var("POLISH").map(|v| v != "0").unwrap_or(true),
        ..Default::default()
    };
    let t0 = Instant::now();
    let mut ts = 0.0;
    let mut r = None;
    for _ in 0..iters {
        let a = Instant::now();
        let mut s = FairingSetup::new(&cv, o).unwrap();
        s.set_polish_iterations(pit);
        ts += a.elapsed().as_secs_f64();
        r = Some(s.fair().unwrap());
    }
    let tot = t0.elapsed().as_secs_f64() / iters as f64;
    let r = r.unwrap();
    let mut s = FairingSetup::new(&cv, o).unwrap();
    s.set_polish_iterations(pit);
    s.fair().unwrap();
    let mut solves = 0;
    let mut bestb = f64::INFINITY;
    for _ in 0..10 {
        let a = Instant::now();
        for i in 0..iters / 10 {
            s.set_tolerance(if i % 2 == 0 { 1.5e-3 } else { 2e-3 }).unwrap();
            solves += s.fair().unwrap().solves;
        }
        bestb = bestb.min(a.elapsed().as_secs_f64() / (iters / 10) as f64);
    }
    let mut bestf = f64::INFINITY;
    for _ in 0..10 {
        let a = Instant::now();
        for _ in 0..iters / 10 {
            let mut s = FairingSetup::new(&cv, o).unwrap();
            s.set_polish_iterations(pit);
            std::hint::black_box(s.fair().unwrap());
        }
        bestf = bestf.min(a.elapsed().as_secs_f64() / (iters / 10) as f64);
    }
    println!(
        "re-fair after tolerance change {:.1} us (best batch), {:.1} solves; full best batch {:.1} us",
        bestb * 1e6,
        solves as f64 / iters as f64,
        bestf * 1e6
    );
    println!(
        "n={n} full {:.1} us, setup {:.1} us; mu {:.3e} alpha {} solves {} dev {:.3e} E {:e}",
        tot * 1e6,
        ts / iters as f64 * 1e6,
        r.mu,
        r.alpha,
        r.solves,
        r.max_deviation,
        r.energy
    );
}
#[allow(dead_code)]
fn unused() {}
