//! Surface fairing benchmarks (issue 5): a full fair of noisy bicubic nets,
//! 30 × 30 (target ≤ 16 ms) and 100 × 100 (target ≤ 150 ms), and a scaling
//! series 10 … 100 to show the cost per control point, and the editor's draft of a 30 × 30 net (issue 28:
//! ≤ 4 ms): the first (its isocurve setups built) and each one after it in a tolerance drag (taken from the
//! workspace's `IsocurveCache`). The phase breakdown
//! (isocurves / combination / fit / verification) is printed by
//! `examples/surface_timing.rs` from [`SurfaceTimings`](fairway::fair::SurfaceTimings).
//!
//! ```sh
//! nice cargo bench -p fairway --bench surface_fairing -- --warm-up-time 1 --measurement-time 3
//! ```

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use fairway::fair::{IsocurveCache, SurfaceFairingOptions, fair_surface, fair_surface_cached};

mod common;
use common::noisy_net;

fn opts() -> SurfaceFairingOptions {
    SurfaceFairingOptions::default().tolerance(3e-3)
}

fn benches(c: &mut Criterion) {
    // 10 samples: a 100 × 100 fair takes seconds on a loaded 2-core machine
    let mut g = c.benchmark_group("surface fair");
    g.sample_size(10);
    for n in [30, 100] {
        let s = noisy_net(n);
        g.bench_function(format!("{n}x{n} full"), |b| {
            b.iter(|| fair_surface(black_box(&s), opts()).unwrap())
        });
    }
    let s = noisy_net(30);
    let region = opts().region(Some(((0.3, 0.7), (0.3, 0.7))));
    g.bench_function("30x30 region 0.4x0.4", |b| {
        b.iter(|| fair_surface(black_box(&s), region).unwrap())
    });
    g.finish();
    let mut g = c.benchmark_group("surface draft");
    let draft = opts().draft();
    g.bench_function("30x30 first", |b| {
        b.iter(|| fair_surface(black_box(&s), draft).unwrap())
    });
    let cache = IsocurveCache::new();
    let cancel = fairway::Cancel::new();
    // the draft before, at another point of the drag: its setups are the timed drafts'
    fair_surface_cached(&s, draft.tolerance(draft.tolerance * 1.05), &cancel, &cache).unwrap();
    g.bench_function("30x30 in a drag", |b| {
        b.iter(|| fair_surface_cached(black_box(&s), draft, &cancel, &cache).unwrap())
    });
    g.finish();
    let mut g = c.benchmark_group("surface scaling");
    g.sample_size(10);
    for n in [10, 20, 40, 60, 80] {
        let s = noisy_net(n);
        g.throughput(Throughput::Elements((n * n) as u64));
        g.bench_with_input(BenchmarkId::from_parameter(n * n), &s, |b, s| {
            b.iter(|| fair_surface(black_box(s), opts()).unwrap())
        });
    }
    g.finish();
}

criterion_group!(surface, benches);
criterion_main!(surface);
