//! The bench cubic and the bench surface, shared by `benches/fairing.rs`, `benches/surface_fairing.rs`,
//! `examples/fair_timing.rs`, `examples/surface_timing.rs`, the core's polish tests and the editor's
//! `tests/drafts.rs` (all but the benches include this file by path), so that all of them use the same
//! shapes. Not every user calls every function.
#![allow(dead_code)]

use fairway::fair::FairingOptions;
use fairway::{BSplineCurve, BSplineSurface, DVec2, DVec3, KnotVector};

/// A cubic with `n` control points through a sine wave, with deterministic noise of ~1 % of the amplitude.
pub fn noisy_curve(n: usize) -> BSplineCurve {
    noisy_wave(n, 1.0)
}

/// The bench cubic made longer instead of denser: `n` control points at the 100-point curve's spacing
/// (the sine wave continued over `n / 100` times the length, the same noise), so that a curve of `n`
/// points is `n / 100` bench cubics end to end — the scaling of the engine, where [`noisy_curve`] at 10,000
/// points puts noise of 12× the control point spacing (loops in the polygon). `noisy_long_curve(100)` is
/// `noisy_curve(100)`.
pub fn noisy_long_curve(n: usize) -> BSplineCurve {
    noisy_wave(n, n as f64 / 100.0)
}

/// `n` control points on the sine wave over `stretch` times the bench cubic's length, with its noise.
fn noisy_wave(n: usize, stretch: f64) -> BSplineCurve {
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let pts: Vec<DVec2> = (0..n)
        .map(|i| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let noise = ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.01;
            let t = stretch * (i as f64 / (n - 1) as f64);
            DVec2::new(4.0 * t, 0.5 * (3.0 * t).sin() + noise)
        })
        .collect();
    BSplineCurve::new_2d(3, KnotVector::uniform(3, n).unwrap().values().to_vec(), &pts).unwrap()
}

/// The bench's options: m = 2e-3, `samples` fairing samples.
pub fn opts(samples: usize) -> FairingOptions {
    FairingOptions::default().tolerance(2e-3).samples(Some(samples))
}

/// CPU time (ns) of the whole process, all its threads (`/proc/self/task/*/schedstat`; `None` where
/// `/proc` does not have it): a closed curve's two passes, a long curve's judged measures and a network's
/// chains run on rayon's workers, so the calling thread's clock alone undercounts. Only the threads
/// alive now count: across a span in which threads end (a fair on its own pool of `threads` workers,
/// which ends with it) use [`process_cpu_ticks_ns`].
pub fn process_cpu_ns() -> Option<u64> {
    let mut total = 0;
    for t in std::fs::read_dir("/proc/self/task").ok()?.flatten() {
        let s = std::fs::read_to_string(t.path().join("schedstat")).ok()?;
        total += s.split_whitespace().next()?.parse::<u64>().ok()?;
    }
    Some(total)
}

/// CPU time (ns) of the whole process including its ended threads (`utime + stime` of `/proc/self/stat`),
/// in clock ticks of 10 ms (Linux's USER_HZ of 100): for spans of seconds over which threads may end.
pub fn process_cpu_ticks_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/stat").ok()?;
    // the fields after the command's closing parenthesis: state is field 3, utime 14, stime 15
    let mut f = s.get(s.rfind(')')? + 1..)?.split_whitespace().skip(11);
    let (utime, stime): (u64, u64) = (f.next()?.parse().ok()?, f.next()?.parse().ok()?);
    Some((utime + stime) * 10_000_000)
}

/// `n × n` bicubic net over [0,1]² with uniform knots: a smooth wave with deterministic noise σ ≈ 1e-3 on z
/// (the surface benches' and `surface_timing`'s test surface).
pub fn noisy_net(n: usize) -> BSplineSurface {
    let k = KnotVector::uniform(3, n).unwrap();
    let g = k.greville();
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut pts = Vec::with_capacity(n * n);
    for &u in &g {
        for &v in &g {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let noise = ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 3.4e-3;
            pts.push(DVec3::new(u, v, 0.3 * (3.0 * u).sin() * (2.0 * v).cos() + noise));
        }
    }
    BSplineSurface::try_new(3, 3, k.values().to_vec(), k.values().to_vec(), n, n, pts, None).unwrap()
}
