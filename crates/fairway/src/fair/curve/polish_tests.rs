//! Tests of the variation polish's band: the hull rows (`hull.rs`) hold it everywhere, not only at the
//! check samples.

use super::*;
use crate::BSplineCurve;
use crate::closest::CurveProjector;
use crate::fair::FairingOptions;

/// The bench's cubic, the same file `benches/fairing.rs` and `examples/fair_timing.rs` include.
#[path = "../../../benches/common/mod.rs"]
mod bench;
use bench::noisy_curve;

fn setup(n: usize, m: f64) -> FairingSetup {
    let opts = FairingOptions::default().tolerance(m).samples(Some(10 * n));
    FairingSetup::new(&noisy_curve(n), opts).unwrap()
}

/// The largest distance from `per_span` points per knot span of `original` to `faired` (closest points
/// by the projector, independent of the fair's band checks and bounds).
fn dense_deviation(original: &BSplineCurve, faired: &BSplineCurve, per_span: usize) -> f64 {
    let proj = CurveProjector::new(faired, 16);
    let kv = original.knots().values();
    let mut worst = 0.0f64;
    for w in kv.windows(2).filter(|w| w[1] > w[0]) {
        for i in 0..per_span {
            let u = w[0] + (w[1] - w[0]) * i as f64 / per_span as f64;
            worst = worst.max(proj.project(original.point(u)).distance);
        }
    }
    worst
}

/// At 4 check samples a span (997 spans) the polish on the check samples left the band between them
/// (certified 1.06 m, then a second pass); on the hull rows the first pass holds it everywhere — certified
/// and by a dense closest-point scan of 64 points a span — and uses most of it.
#[test]
fn sparse_check_samples_hold_the_band_in_one_pass() {
    let m = 2e-3;
    let mut s = setup(1000, m);
    let first = s.fair_pass().unwrap();
    let b = crate::fair::verify::certify(s.working_curve(), &first.curve, m).unwrap();
    assert!(b.bound <= m && b.bound >= 0.9 * m, "first pass at {} m", b.bound / m);
    let dense = dense_deviation(s.working_curve(), &first.curve, 64);
    assert!(dense <= m && dense >= 0.9 * m, "dense scan {} m", dense / m);
    let r = s.fair().unwrap();
    assert_eq!(r.curve, first.curve);
    assert!(r.max_deviation >= dense * (1.0 - 1e-9) && r.max_deviation <= m);
}

/// The polish's iterates hold the band at every hull row, so the result's parametric displacement is
/// within the band everywhere: its largest value on a dense parameter grid is at most m (the parametric
/// distance bounds the closest-point one from above), and the closest-point scan agrees.
#[test]
fn the_polished_bench_cubic_holds_the_band_everywhere() {
    let m = 2e-3;
    let mut s = setup(100, m);
    let r = s.fair().unwrap();
    let c0 = s.working_curve().clone();
    let (d0, d1) = c0.domain();
    let param = (0..=40_000)
        .map(|i| {
            let u = d0 + (d1 - d0) * i as f64 / 40_000.0;
            (c0.point(u) - r.curve.point(u)).length()
        })
        .fold(0.0f64, f64::max);
    assert!(param <= m, "parametric displacement {} m", param / m);
    let dense = dense_deviation(&c0, &r.curve, 64);
    assert!(dense <= param * (1.0 + 1e-12) && dense >= 0.9 * m, "{} m", dense / m);
    assert!(r.max_deviation >= dense * (1.0 - 1e-9) && r.max_deviation <= m);
}
