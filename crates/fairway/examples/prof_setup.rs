//! Profiling driver (temporary).
use fairway::fair::{FairingOptions, FairingSetup};
use fairway::{BSplineCurve, DVec2, KnotVector};
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
    let cv = noisy_curve(100);
    let o = FairingOptions {
        tolerance: 2e-3,
        samples: Some(1000),
        ..Default::default()
    };
    let t = std::time::Instant::now();
    for _ in 0..3000 {
        std::hint::black_box(FairingSetup::new(&cv, o).unwrap());
    }
    println!("setup {:.1} us", t.elapsed().as_secs_f64() / 3000.0 * 1e6);
}
