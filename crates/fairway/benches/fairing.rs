//! Fairing benchmarks (issue 4): a noisy cubic curve with 100 control points
//! and 1000 arc-length samples — full fair (setup + solve), re-fair after a
//! tolerance change and after a target edit (the editor's live preview);
//! scaling with 100 / 1,000 / 10,000 control points (10 samples per
//! control point); the iterative baseline (paper §2.2) on the same setup.
//!
//! ```sh
//! nice cargo bench -p fairway --bench fairing -- --warm-up-time 1 --measurement-time 3
//! ```

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use fairway::fair::{FairingSetup, FitMode, IterativeOptions, PolishMethod, fair_iterative};

mod common;
use common::{noisy_curve, opts};

fn benches(c: &mut Criterion) {
    let cv = noisy_curve(100);
    let o = opts(1000);
    c.bench_function("curve100_s1000/full (setup + fair)", |b| {
        b.iter(|| FairingSetup::new(black_box(&cv), o).unwrap().fair().unwrap())
    });
    // the previous default (line-search polish of the paper's E, G2 curve ends) and the reference smoother
    let ls = o
        .polish_method(PolishMethod::LineSearch)
        .curve_ends([Some(fairway::fair::EndCondition::G2); 2]);
    c.bench_function("curve100_s1000/full, line-search polish (the previous default)", |b| {
        b.iter(|| FairingSetup::new(black_box(&cv), ls).unwrap().fair().unwrap())
    });
    let smoothing = o.mode(FitMode::Smoothing);
    c.bench_function("curve100_s1000/full, reference smoother (FitMode::Smoothing)", |b| {
        b.iter(|| FairingSetup::new(black_box(&cv), smoothing).unwrap().fair().unwrap())
    });
    // the sound band bound of the default result alone (part of every full fair above)
    let faired = FairingSetup::new(&cv, o).unwrap().fair().unwrap().curve;
    c.bench_function("curve100_s1000/band bound of the result (fair::band_bound)", |b| {
        b.iter(|| fairway::fair::band_bound(black_box(&cv), black_box(&faired), o.tolerance, usize::MAX).unwrap())
    });
    // the line-search polish run long enough to reach the iterative baseline's E on this curve (test
    // more_polish_iterations_reach_the_iterative_energy_on_the_bench_curve): the "equal E" comparison
    c.bench_function("curve100_s1000/full at the baseline's E (24 polish iterations)", |b| {
        b.iter(|| {
            let mut s = FairingSetup::new(black_box(&cv), ls).unwrap();
            s.set_polish_iterations(24);
            s.fair().unwrap()
        })
    });
    // the interior-point polish run to the baseline's E: 3 iterations (test
    // interior_point_reaches_the_iterative_energy_on_the_bench_curve_in_three_iterations)
    let ip = o.polish_method(PolishMethod::InteriorPoint).polish_iterations(3);
    c.bench_function(
        "curve100_s1000/full at the baseline's E (interior point, 3 iterations)",
        |b| b.iter(|| FairingSetup::new(black_box(&cv), ip).unwrap().fair().unwrap()),
    );
    let mut ip_setup = FairingSetup::new(&cv, ip).unwrap();
    c.bench_function(
        "curve100_s1000/re-fair at the baseline's E (interior point, 3 iterations)",
        |b| b.iter(|| black_box(ip_setup.fair().unwrap())),
    );
    c.bench_function("curve100_s1000/setup only", |b| {
        b.iter(|| FairingSetup::new(black_box(&cv), o).unwrap())
    });
    let mut setup = FairingSetup::new(&cv, o).unwrap();
    let mut flip = false;
    c.bench_function("curve100_s1000/re-fair after tolerance change", |b| {
        b.iter(|| {
            flip = !flip;
            setup.set_tolerance(if flip { 2e-3 } else { 1.5e-3 }).unwrap();
            black_box(setup.fair().unwrap())
        })
    });
    let mut k = 0usize;
    c.bench_function("curve100_s1000/re-fair after target edit", |b| {
        b.iter(|| {
            k = (k + 37) % 900 + 50;
            let g = setup.target().values()[k];
            setup.target_mut().set(k, g * 1.01);
            black_box(setup.fair().unwrap())
        })
    });
    // the paper's method alone (one integration, one fit, no band search or polish; the band is only
    // measured), re-run on its setup: what the default's hard tolerance and E polish add to
    let mut paper = FairingSetup::new(&cv, o.mode(FitMode::Paper)).unwrap();
    c.bench_function("curve100_s1000/re-fair, paper mode (FitMode::Paper)", |b| {
        b.iter(|| black_box(paper.fair().unwrap()))
    });
    let mut group = c.benchmark_group("scaling (10 samples per control point, full fair)");
    group.sample_size(10);
    for n in [100usize, 1000, 10_000] {
        let cv = noisy_curve(n);
        let o = opts(10 * n);
        group.bench_with_input(BenchmarkId::new("full", n), &n, |b, _| {
            b.iter(|| FairingSetup::new(&cv, o).unwrap().fair().unwrap())
        });
        group.bench_with_input(BenchmarkId::new("re-fair", n), &n, |b, _| {
            let mut s = FairingSetup::new(&cv, o).unwrap();
            b.iter(|| s.fair().unwrap())
        });
    }
    group.finish();
    let mut group = c.benchmark_group("iterative baseline");
    group.sample_size(10);
    group.bench_function("curve100_s1000/iterative", |b| {
        let setup = FairingSetup::new(&cv, o).unwrap();
        b.iter(|| fair_iterative(black_box(&setup), IterativeOptions::default()).unwrap())
    });
    group.finish();
}

criterion_group!(fairing, benches);
criterion_main!(fairing);
