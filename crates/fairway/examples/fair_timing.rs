//! Wall and CPU time of the curve fair on the bench cubic of `benches/fairing.rs` (issue 28): the full
//! fair (setup + fair), the re-fair after a tolerance change, the editor's draft preview (re-fair
//! without the polish) and the full fair at 100 / 1,000 / 10,000 / 100,000 control points (10 samples
//! per control point), per fair and per control point.
//!
//! `cargo run --release -p fairway --example fair_timing [-- SECONDS [MAX_POINTS]]`
//!
//! Each case runs for about SECONDS (default 2) after one warm-up fair; the CPU time is the process's, all
//! threads (`/proc/self/task/*/schedstat`, nanoseconds), so it excludes whatever else runs on the machine
//! and includes the work rayon's workers do for it.

use std::hint::black_box;
use std::time::{Duration, Instant};

use fairway::BSplineCurve;
use fairway::fair::FairingSetup;
use fairway::fair::network::{NetworkOptions, fair_network};

#[path = "../benches/common/mod.rs"]
mod common;
use common::{noisy_curve, opts};

/// The process's CPU time (ns), all threads, those that ended included (a network fair on 2 workers
/// builds a pool per fair, whose threads end with it), in 10 ms ticks ([`common::process_cpu_ticks_ns`]):
/// each figure spans seconds. 0 where `/proc` does not have it.
fn cpu_ns() -> u64 {
    common::process_cpu_ticks_ns().unwrap_or(0)
}

/// Runs `f` for about `secs` (at least 3 times) after one warm-up call; (wall, CPU) per call in µs.
fn time(secs: f64, mut f: impl FnMut()) -> (f64, f64, usize) {
    if secs <= 0.0 {
        return (0.0, 0.0, 0);
    }
    f();
    let budget = Duration::from_secs_f64(secs);
    let (t0, c0) = (Instant::now(), cpu_ns());
    let mut n = 0usize;
    while n < 3 || t0.elapsed() < budget {
        f();
        n += 1;
    }
    let wall = t0.elapsed().as_secs_f64() * 1e6 / n as f64;
    let cpu = cpu_ns().saturating_sub(c0) as f64 * 1e-3 / n as f64;
    (wall, cpu, n)
}

fn report(name: &str, (wall, cpu, n): (f64, f64, usize), points: usize) {
    if n == 0 {
        return;
    }
    println!(
        "{name:<44} wall {wall:>11.1} µs  cpu {cpu:>11.1} µs  ({n} runs; cpu {:.3} µs per control point)",
        cpu / points as f64
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let secs: f64 = args.get(1).map_or(2.0, |s| s.parse().expect("seconds"));
    let max_points: usize = args.get(2).map_or(100_000, |s| s.parse().expect("max points"));
    // a third argument runs only the cases whose name contains it
    let only = args.get(3).cloned().unwrap_or_default();
    let secs_for = |name: &str| if name.contains(only.as_str()) { secs } else { 0.0 };
    let cv = noisy_curve(100);
    let o = opts(1000);
    let r = FairingSetup::new(&cv, o).unwrap().fair().unwrap();
    // a fingerprint of the result: the faired control points' bits
    let hash = r.curve.points().iter().fold(0xcbf2_9ce4_8422_2325u64, |h, p| {
        [p.x, p.y, p.z]
            .iter()
            .fold(h, |h, x| (h ^ x.to_bits()).wrapping_mul(0x0100_0000_01b3))
    });
    println!(
        "bench cubic, 100 control points: max deviation {:?} (m = {:.1e}), E {:?}, solves {}, points hash {hash:016x}",
        r.max_deviation, o.tolerance, r.energy, r.solves
    );
    report(
        "full fair (setup + fair)",
        time(secs_for("full fair (setup"), || {
            black_box(FairingSetup::new(black_box(&cv), o).unwrap().fair().unwrap());
        }),
        100,
    );
    report(
        "full fair through fair_curve (+ extrema guard)",
        time(secs_for("fair_curve"), || {
            black_box(fairway::fair::fair_curve(black_box(&cv), o).unwrap());
        }),
        100,
    );
    report(
        "setup only",
        time(secs_for("setup only"), || {
            black_box(FairingSetup::new(black_box(&cv), o).unwrap());
        }),
        100,
    );
    let mut setup = FairingSetup::new(&cv, o).unwrap();
    let mut flip = false;
    report(
        "re-fair after a tolerance change",
        time(secs_for("re-fair after a tolerance"), || {
            flip = !flip;
            setup.set_tolerance(if flip { 2e-3 } else { 1.5e-3 }).unwrap();
            black_box(setup.fair().unwrap());
        }),
        100,
    );
    let mut k = 0usize;
    report(
        "re-fair after a target edit",
        time(secs_for("re-fair after a target"), || {
            k = (k + 37) % 900 + 50;
            let g = setup.target().values()[k];
            setup.target_mut().set(k, g * 1.01);
            black_box(setup.fair().unwrap());
        }),
        100,
    );
    let mut draft = FairingSetup::new(&cv, o).unwrap();
    draft.set_polish(false);
    report(
        "draft preview (no polish), tolerance change",
        time(secs_for("draft"), || {
            flip = !flip;
            draft.set_tolerance(if flip { 2e-3 } else { 1.5e-3 }).unwrap();
            black_box(draft.fair().unwrap());
        }),
        100,
    );
    // a document of 8 bench cubics side by side (no joins): "Fair all" on 1 and on 2 workers (the chains
    // are faired in parallel; the pool of 2 is built per call and its threads' CPU leaves with them: read
    // the wall time there)
    let objects: Vec<fairway::Geometry> = (0..8)
        .map(|k| {
            let pts = cv
                .points()
                .iter()
                .map(|p| *p + fairway::DVec3::new(0.0, 2.0 * k as f64, 0.0));
            BSplineCurve::try_new(3, cv.knots().values().to_vec(), pts.collect(), None, 2)
                .unwrap()
                .into()
        })
        .collect();
    for threads in [1, 2] {
        let mut no = NetworkOptions {
            curve: o,
            ..Default::default()
        };
        no.surface.threads = Some(threads);
        let name = format!("network of 8 curves, {threads} worker(s)");
        report(
            &name,
            time(secs_for(&name), || {
                black_box(fair_network(black_box(&objects), &[], &no).unwrap());
            }),
            800,
        );
    }
    for n in [100usize, 1000, 10_000, 100_000] {
        if n > max_points {
            break;
        }
        let cv = noisy_curve(n);
        let o = opts(10 * n);
        let name = format!("full fair, {n} control points, {} samples", 10 * n);
        report(
            &name,
            time(secs_for(&name), || {
                black_box(FairingSetup::new(&cv, o).unwrap().fair().unwrap());
            }),
            n,
        );
    }
    // the same at the 100-point curve's spacing (a longer wave, not a denser one: `noisy_long_curve`)
    for n in [1000usize, 10_000, 100_000] {
        if n > max_points {
            break;
        }
        let cv = common::noisy_long_curve(n);
        let o = opts(10 * n);
        let name = format!("full fair, {n} control points at the 100-point spacing");
        report(
            &name,
            time(secs_for(&name), || {
                black_box(FairingSetup::new(&cv, o).unwrap().fair().unwrap());
            }),
            n,
        );
    }
}
