//! Per-end conditions of the curve fairing ([`FairingSetup::new_with_ends`]):
//! each region end gets its own continuity, the rest of the curve never moves.

use fairway::fair::{EndCondition, FairingOptions, FairingSetup};
use fairway::measure::deviations;
use fairway::{BSplineCurve, DVec2};

/// A uniform clamped cubic with 40 control points on a flat arc with an
/// alternating ripple.
fn wiggly() -> BSplineCurve {
    let n = 40;
    let pts: Vec<DVec2> = (0..n)
        .map(|i| {
            let t = i as f64 / (n - 1) as f64;
            DVec2::new(
                2.0 * t,
                0.35 * (std::f64::consts::PI * t).sin() + if i % 2 == 0 { 0.003 } else { -0.003 },
            )
        })
        .collect();
    let p = 3;
    let inner = n - p - 1;
    let mut knots = vec![0.0; p + 1];
    knots.extend((1..=inner).map(|k| k as f64 / (inner + 1) as f64));
    knots.extend(vec![1.0; p + 1]);
    BSplineCurve::new_2d(p, knots, &pts).unwrap()
}

fn fair(c: &BSplineCurve, ends: [EndCondition; 2]) -> (FairingSetup, BSplineCurve, f64) {
    let m = 0.002;
    let opts = FairingOptions {
        region: Some((0.3, 0.7)),
        tolerance: m,
        ..Default::default()
    };
    let mut s = FairingSetup::new_with_ends(c, opts, ends).unwrap();
    let r = s.fair().unwrap();
    (s, r.curve, m)
}

#[test]
fn g2_start_and_g0_end() {
    let c = wiggly();
    let (s, f, m) = fair(&c, [EndCondition::G2, EndCondition::G0]);
    // knots: u1 keeps its multiplicity (G2 join), u2 is inserted up to p (C0 join)
    assert_eq!(f.knots().multiplicity(0.3), c.knots().multiplicity(0.3));
    assert_eq!(f.knots().multiplicity(0.7), 3);
    // outside the region nothing moves
    for i in 0..=400 {
        let u = i as f64 / 400.0;
        if !(0.3..=0.7).contains(&u) {
            assert!((f.point(u) - c.point(u)).length() < 1e-12, "moved at u = {u}");
        }
    }
    // G2 at u1: curvature from inside equals the untouched neighbour's
    let e = 1e-7;
    let (k_out, k_in) = (f.curvature(0.3 - e), f.curvature(0.3 + e));
    assert!((k_out - k_in).abs() < 1e-4 * k_out.abs().max(1.0), "{k_out} vs {k_in}");
    // the band holds
    let dev = deviations(&c, &f, 2000).into_iter().fold(0.0, f64::max);
    assert!(dev <= m * (1.0 + 1e-6), "{dev} > {m}");
    // G0 at the end frees more control points than G2 there
    let (s2, _, _) = fair(&c, [EndCondition::G2, EndCondition::G2]);
    assert!(s.free_points().len() > s2.free_points().len());
}

#[test]
fn same_ends_match_new() {
    let c = wiggly();
    let opts = FairingOptions {
        region: Some((0.3, 0.7)),
        tolerance: 0.002,
        ends: EndCondition::G1,
        ..Default::default()
    };
    let a = FairingSetup::new(&c, opts).unwrap().fair().unwrap();
    let b = FairingSetup::new_with_ends(&c, opts, [EndCondition::G1; 2])
        .unwrap()
        .fair()
        .unwrap();
    assert_eq!(a.curve, b.curve);
}
