//! Tests of the variation polish's band margins (`polish.rs`).

use super::*;
use crate::fair::FairingOptions;
use crate::{BSplineCurve, DVec2, KnotVector};

/// The bench's cubic (`benches/fairing.rs`): a sine wave with deterministic noise of ~1 % of its amplitude.
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

fn setup(n: usize, m: f64) -> FairingSetup {
    let opts = FairingOptions::default().tolerance(m).samples(Some(10 * n));
    FairingSetup::new(&noisy_curve(n), opts).unwrap()
}

/// At 4 check samples a span (997 spans) the first pass leaves the band between the samples; with the
/// sparse margin the pass holds it everywhere, not only at the samples, and uses most of it; `fair`
/// reports that pass's bound.
#[test]
fn sparse_check_samples_hold_the_band_with_the_sparse_margin() {
    let m = 2e-3;
    let mut s = setup(1000, m);
    assert!(s.sparse_check_samples());
    assert_eq!(s.var_band_margin(), VAR_BAND_MARGIN);
    let first = s.fair_pass().unwrap();
    let b1 = crate::fair::verify::certify(s.working_curve(), &first.curve, m).unwrap();
    assert!(b1.bound > m, "first pass at {} m", b1.bound / m);
    s.sparse_margin = true;
    assert!(s.var_band_margin() > 0.05, "{}", s.var_band_margin());
    let second = s.fair_pass().unwrap();
    let b2 = crate::fair::verify::certify(s.working_curve(), &second.curve, m).unwrap();
    assert!(
        b2.bound <= m && b2.bound >= 0.9 * m,
        "second pass at {} m",
        b2.bound / m
    );
    s.sparse_margin = false;
    let r = s.fair().unwrap();
    assert!(
        r.max_deviation <= m && r.max_deviation >= 0.9 * m,
        "{} m",
        r.max_deviation / m
    );
    assert!(!s.sparse_margin);
}

/// With the default 2000 check samples on 97 spans the samples are not sparse: the margin stays
/// `VAR_BAND_MARGIN` even when asked for.
#[test]
fn dense_check_samples_keep_the_small_margin() {
    let mut s = setup(100, 2e-3);
    assert!(!s.sparse_check_samples());
    s.sparse_margin = true;
    assert_eq!(s.var_band_margin(), VAR_BAND_MARGIN);
}
