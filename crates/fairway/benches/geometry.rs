//! Geometry benchmarks: evaluation, curvature, surface derivatives, arc
//! length, equal-arc sampling and closest points, on a cubic with 100
//! control points (2D) and a bicubic 30 × 30 surface.
//!
//! ```sh
//! cargo bench -p fairway --bench geometry
//! ```

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use fairway::{ArcLengthTable, BSplineCurve, BSplineSurface, CurveProjector, DVec2, DVec3, KnotVector};

fn curve(n: usize) -> BSplineCurve {
    let pts: Vec<DVec2> = (0..n)
        .map(|i| {
            let t = i as f64 / (n - 1) as f64;
            DVec2::new(4.0 * t, 0.5 * (3.0 * t).sin() + 0.01 * ((i * 7919 % 13) as f64 / 13.0))
        })
        .collect();
    BSplineCurve::new_2d(3, KnotVector::uniform(3, n).unwrap().values().to_vec(), &pts).unwrap()
}

fn surface(n: usize) -> BSplineSurface {
    let mut pts = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
            pts.push(DVec3::new(x, y, (3.0 * x).sin() * (2.0 * y).cos()));
        }
    }
    let k = KnotVector::uniform(3, n).unwrap().values().to_vec();
    BSplineSurface::try_new(3, 3, k.clone(), k, n, n, pts, None).unwrap()
}

fn benches(c: &mut Criterion) {
    let cv = curve(100);
    let us: Vec<f64> = (0..1000).map(|i| i as f64 / 999.0).collect();
    c.bench_function("curve100/point x1000", |b| {
        b.iter(|| {
            us.iter()
                .map(|&u| cv.point(black_box(u)))
                .fold(DVec3::ZERO, |a, p| a + p)
        })
    });
    c.bench_function("curve100/derivs+curvature x1000", |b| {
        b.iter(|| us.iter().map(|&u| cv.derivs(black_box(u)).curvature(2)).sum::<f64>())
    });
    let sf = surface(30);
    c.bench_function("surface30x30/derivs+curvature x1000", |b| {
        b.iter(|| {
            us.iter()
                .map(|&u| sf.derivs(black_box(u), 1.0 - u).curvature().mean)
                .sum::<f64>()
        })
    });
    c.bench_function("curve100/arc-length table 1e-10", |b| {
        b.iter(|| ArcLengthTable::new(black_box(&cv), 1e-10).length())
    });
    let table = ArcLengthTable::new(&cv, 1e-10);
    let mut out = Vec::with_capacity(1000);
    c.bench_function("curve100/1000 equal-arc params", |b| {
        b.iter(|| {
            table.equal_arc_params_into(black_box(&cv), 1000, &mut out);
            out[500]
        })
    });
    c.bench_function("curve100/table + 1000 equal-arc params", |b| {
        b.iter(|| {
            let t = ArcLengthTable::new(black_box(&cv), 1e-10);
            t.equal_arc_params_into(&cv, 1000, &mut out);
            out[500]
        })
    });
    let proj = CurveProjector::new(&cv, 16);
    let qs: Vec<DVec3> = (0..100)
        .map(|i| {
            let u = i as f64 / 99.0;
            cv.point(u) + DVec3::new(0.01 * (i as f64).sin(), 0.02, 0.0)
        })
        .collect();
    c.bench_function("curve100/closest point x100 (global)", |b| {
        b.iter(|| qs.iter().map(|&q| proj.project(black_box(q)).distance).sum::<f64>())
    });
    c.bench_function("curve100/closest point x100 (near guess)", |b| {
        b.iter(|| {
            qs.iter()
                .enumerate()
                .map(|(i, &q)| proj.project_near(black_box(q), i as f64 / 99.0, 0.02).distance)
                .sum::<f64>()
        })
    });
    c.bench_function("curve100/projector build (16 per span)", |b| {
        b.iter(|| CurveProjector::new(black_box(&cv), 16))
    });
    // the guard of every full CurveFairing::fair: measure's curvature extrema of the result
    let c100 = curve(100);
    let delta = fairway::measure::extrema_threshold(&c100);
    c.bench_function("curve100/curvature extrema (the fair's final guard)", |b| {
        b.iter(|| fairway::measure::curvature_extrema_at(black_box(&c100), delta))
    });
    // issue 26: the measures' cost per control point stays flat with the curve's size
    let mut group = c.benchmark_group("measure (all measures of a curve against a shifted copy)");
    group.sample_size(10);
    for n in [100usize, 1000, 10_000] {
        let a = curve(n);
        let b = a
            .with_points(a.points().iter().map(|p| *p + DVec3::new(0.0, 1e-3, 0.0)).collect())
            .unwrap();
        group.bench_function(format!("{n} control points"), |bn| {
            bn.iter(|| fairway::measure::measure(black_box(&a), black_box(&b)))
        });
    }
    group.finish();
}

criterion_group!(geometry, benches);
criterion_main!(geometry);
