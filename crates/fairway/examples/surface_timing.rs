//! Where the time of a surface fairing goes: isocurve fairing, combination,
//! fit and tolerance verification, for noisy bicubic nets of growing size
//! (the same surfaces as `benches/surface_fairing.rs`).
//!
//! ```sh
//! cargo run --release -p fairway --example surface_timing [-- REPEATS]
//! RAYON_NUM_THREADS=1 cargo run --release -p fairway --example surface_timing [-- REPEATS]
//! ISO_LEVELS=1 cargo run --release -p fairway --example surface_timing   # one isocurve tolerance only
//! COMBINE=weighted cargo run --release -p fairway --example surface_timing   # the default combination
//! REFAIR_LEVELS=1 cargo run --release -p fairway --example surface_timing   # isocurves re-faired per level
//! DRAFT=1 cargo run …   # the editor's draft preview (`SurfaceFairingOptions::draft`; the other knobs ignored)
//! METHOD=isocurves ISO_LEVELS=1 COMBINE=weighted cargo run …   # the draft preview before session 29
//! SIZES=30,50 cargo run --release -p fairway --example surface_timing      # only these net sizes
//! SPS=2 … / NOAUTO=1 …   # 2 grid isocurves per knot span (default 3) / no auto smoothing (the options' own)
//! CANCEL_TOKEN=1 …   # through fair_surface_with and a token never set (the hash must not change)
//! CACHE=1 …   # each timed fair follows one at 1.05 × the tolerance with the same IsocurveCache (a drag)
//! CACHE=full …   # … follows the default full fair at 1.05 × (with DRAFT=1: a drag's first draft in the editor)
//! ```
//!
//! The last column is an FNV-1a hash of the result's control-point bits, to check that a speed-up
//! leaves the result bit-identical.
//!
//! The isocurves are faired on all cores unless `RAYON_NUM_THREADS` says
//! otherwise; `cpu_ms` is the CPU time of the calling thread, so it is
//! the whole work only when nothing runs on rayon's pool; `proc_cpu_ms` is the CPU time of the
//! whole process (all its threads).

use std::time::{Duration, Instant};

use fairway::DVec3;
use fairway::fair::{
    Combine, SurfaceFairingOptions, SurfaceMethod, fair_surface, fair_surface_cached, fair_surface_with,
};

#[path = "../benches/common/mod.rs"]
mod common;
use common::noisy_net;

/// The process's CPU time (ns), all threads ([`common::process_cpu_ns`]), 0 where `/proc` does not have it.
fn process_cpu_ns() -> u64 {
    common::process_cpu_ns().unwrap_or(0)
}

/// CPU time of this thread in ns (Linux `/proc/thread-self/schedstat`), to
/// separate the work from waiting on a loaded machine; 0 if unavailable.
fn thread_cpu_ns() -> u64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next().and_then(|x| x.parse().ok()))
        .unwrap_or(0)
}

/// FNV-1a over the bits of every coordinate of `pts`.
fn points_hash(pts: &[DVec3]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for c in pts.iter().flat_map(|p| p.to_array()) {
        for b in c.to_bits().to_le_bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn main() {
    let repeats: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(5);
    println!(
        "n\tpoints\tcpu_ms\twall_ms\tiso_ms\tcombine_ms\tfit_ms\tverify_ms\trounds\tm_iso/m\tstrength\talpha\tdev\tref_ms\tproc_cpu_ms\thash"
    );
    // SIZES=30,50 runs only those net sizes
    let sizes: Vec<usize> = std::env::var("SIZES").map_or_else(
        |_| vec![10, 20, 30, 50, 70, 100],
        |s| {
            s.split(',')
                .map(|x| x.trim().parse().expect("SIZES: comma-separated net sizes"))
                .collect()
        },
    );
    for n in sizes {
        let s = noisy_net(n);
        let opts = SurfaceFairingOptions::default()
            .tolerance(3e-3)
            .combine(std::env::var("COMBINE").map_or(Combine::Border, |c| c.parse().expect("combine")))
            .iso_levels(
                std::env::var("ISO_LEVELS")
                    .ok()
                    .and_then(|x| x.parse().ok())
                    .unwrap_or(3),
            )
            .refair_levels(std::env::var("REFAIR_LEVELS").is_ok())
            .samples_per_span(std::env::var("SPS").map_or(3, |x| x.parse().unwrap()))
            .auto_smoothing(std::env::var("NOAUTO").is_err())
            .method(std::env::var("METHOD").map_or(SurfaceMethod::Fairway, |m| m.parse().expect("method")));
        let opts = if std::env::var("DRAFT").is_ok() {
            SurfaceFairingOptions::default().tolerance(opts.tolerance).draft()
        } else {
            opts
        };
        // best wall time of `repeats` (least disturbed by other load on the machine), with its thread CPU time
        // CACHE=1: each timed fair follows one at 1.05 × the tolerance with the same isocurve cache (a
        // re-fair while the tolerance is dragged)
        let cache = std::env::var("CACHE").is_ok().then(fairway::fair::IsocurveCache::new);
        let mut best: Option<(Duration, f64, f64, fairway::fair::SurfaceFairingResult)> = None;
        for _ in 0..repeats {
            if let Some(cache) = &cache {
                // the draft before, at another tolerance: its setups are the timed fair's (CACHE=full: the
                // full fair before it, as when a drag starts after the editor's full fair)
                let before = if std::env::var("CACHE").is_ok_and(|c| c == "full") {
                    cache.clear();
                    SurfaceFairingOptions::default()
                } else {
                    opts
                };
                fair_surface_cached(
                    &s,
                    before.tolerance(opts.tolerance * 1.05),
                    &fairway::Cancel::new(),
                    cache,
                )
                .unwrap();
            }
            let (c0, p0) = (thread_cpu_ns(), process_cpu_ns());
            let t = Instant::now();
            let r = if let Some(cache) = &cache {
                fair_surface_cached(&s, opts, &fairway::Cancel::new(), cache).unwrap()
            } else if std::env::var("CANCEL_TOKEN").is_ok() {
                fair_surface_with(&s, opts, &fairway::Cancel::new()).unwrap()
            } else {
                fair_surface(&s, opts).unwrap()
            };
            let e = t.elapsed();
            let cpu = (thread_cpu_ns() - c0) as f64 * 1e-6;
            let pcpu = process_cpu_ns().saturating_sub(p0) as f64 * 1e-6;
            if best.as_ref().is_none_or(|b| e < b.0) {
                best = Some((e, cpu, pcpu, r));
            }
        }
        let (e, cpu, pcpu, r) = best.unwrap();
        let t = r.timings;
        println!(
            "{n}\t{}\t{cpu:.2}\t{:.2}\t{:.2}\t{:.2}\t{:.2}\t{:.2}\t{}\t{:.3}\t{}\t{:.3}\t{:.2e}\t{:.2}\t{pcpu:.2}\t{:016x}",
            n * n,
            ms(e),
            ms(t.isocurves),
            ms(t.combine),
            ms(t.fit),
            ms(t.verify),
            r.rounds,
            r.iso_tolerance / opts.tolerance,
            r.smoothing.strength_u,
            r.alpha,
            r.max_deviation,
            ms(t.reference),
            points_hash(r.surface.points())
        );
    }
}
