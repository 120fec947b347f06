//! Curve fairing engine (issue 4): known answers on noisy circle / ellipse /
//! clothoid arcs (fixed seed), properties (tolerance, held control points,
//! G2 joins) by proptest, fast vs iterative, degenerate input, 3D frames,
//! closed curves, target edits.

mod common;

use common::*;
use fairway::fair::*;
use fairway::measure::measure;
use fairway::{BSplineCurve, DVec2, DVec3, Error, KnotVector};
use proptest::prelude::*;

/// Knots of `b` missing in `a` (with multiplicity): the G0/G1 insertions.
fn extra_knots(a: &BSplineCurve, b: &BSplineCurve) -> Vec<f64> {
    let mut ka = a.knots().values().to_vec();
    let mut extra = vec![];
    for &x in b.knots().values() {
        match ka.iter().position(|&y| y == x) {
            Some(i) => {
                ka.remove(i);
            }
            None => extra.push(x),
        }
    }
    extra
}

/// The options these tests were written for: the line-search E polish and `ends` at the curve ends too
/// (the default polish and curve ends are judged in tests/quality.rs).
fn line_search_opts(tol: f64, ends: EndCondition) -> FairingOptions {
    (opts(tol))
        .polish_method(fairway::fair::PolishMethod::LineSearch)
        .curve_ends([Some(ends); 2])
}

#[test]
fn known_answers_noisy_arcs() {
    // (shape, tolerance, min factor of the curvature error, true interior extrema count)
    let cases = [
        (Shape::Circle { r: 1.0, a: 2.0 }, 3e-3, 0),
        (
            Shape::Ellipse {
                a: 2.0,
                b: 1.0,
                th: 2.5,
            },
            3e-3,
            1,
        ),
        (Shape::Clothoid { a: 1.0, l: 2.0 }, 3e-3, 0),
    ];
    // G2 ends (the default) keep the noisy curve's end curvature (on the circle 3.9 and 2.2 where the
    // true one is 1), so the curvature must climb to it: extra extrema near the ends. G1 ends release it
    // (the target's ends are free) but keep the noisy end tangents, which fix the total turning (see
    // circle_with_the_true_target_and_free_ends_is_recovered). G0 ends free the tangent too, and the
    // target fills the unreliable end knot span from the interior (Target::extrapolate_end): the true
    // count. What a designer picks for noisy data.
    for (shape, tol, true_extrema) in cases {
        let c = noisy_curve(shape, 40, 1e-3, 7);
        let (rms0, max0) = curvature_error(&c, shape);
        let kmax = shape.dense(200).1.iter().fold(0.0f64, |m, k| m.max(k.abs()));
        let delta = 0.05 * kmax;
        let e0 = extrema(&c, delta);
        for ends in [EndCondition::G2, EndCondition::G1, EndCondition::G0] {
            let r = fair_curve(&c, (line_search_opts(tol, ends)).ends(ends)).unwrap();
            let (rms1, max1) = curvature_error(&r.curve, shape);
            let e1 = extrema(&r.curve, delta);
            println!(
                "{shape:?}, {ends:?} ends: κ error rms {rms0:.4} -> {rms1:.4} (factor {:.1}), max {max0:.3} -> \
                 {max1:.3}, extrema(δ = 5% max κ) {e0} -> {e1} (true {true_extrema}), dev {:.2e}",
                rms0 / rms1,
                r.max_deviation
            );
            assert!(dev_max(&c, &r.curve) <= tol);
            assert!(rms1 < rms0 / 3.0, "{shape:?}, {ends:?}: {rms0} -> {rms1}");
            assert!(e1 < e0, "{shape:?}, {ends:?}: extrema {e0} -> {e1}");
            if ends == EndCondition::G1 {
                // measured: circle 1 (true 0), ellipse 1 (1), clothoid 0 (0)
                assert!(e1 <= true_extrema + 1, "{shape:?}: extrema {e1}, true {true_extrema}");
            }
            if ends == EndCondition::G0 {
                // measured: circle 0, ellipse 1, clothoid 0 (factors 12.2, 3.4, 25.9); on seeds 8 and 9
                // the circle gives 1 and 0, the ellipse 1 and 1, the clothoid 0 and 0
                assert_eq!(e1, true_extrema, "{shape:?}, G0 ends");
            }
        }
    }
}

/// Where the circle's remaining extremum comes from. The noisy arc lies within 0.7e-3 of the true
/// circle (band 3e-3), so a curve of constant curvature 1 is inside the band. With G0 ends and the
/// true curvature as the target (what a designer can type in point by point), the engine recovers the
/// circle: 0 interior extrema, κ error < 1e-3 — integration, fit and band reproduce a known answer
/// exactly. With G1 ends the same target still leaves an extremum: the held noisy end tangents fix the
/// total turning (mean κ 1.037 instead of 1), and spread over the arc the excess would move its middle
/// out of the band, so it has to sit near the ends. The automatic target's extremum with free ends is
/// the heat flow conserving the noisy end spans' excess curvature.
#[test]
fn circle_with_the_true_target_and_free_ends_is_recovered() {
    let shape = Shape::Circle { r: 1.0, a: 2.0 };
    let c = noisy_curve(shape, 40, 1e-3, 7);
    // the true circle is inside the band: every point of the noisy arc is within 1e-3 of it
    let (truth, _) = shape.dense(4000);
    let off = (0..=400)
        .map(|i| {
            let (d0, d1) = c.domain();
            let q = c.point(d0 + (d1 - d0) * i as f64 / 400.0);
            truth.iter().map(|p| p.distance(q)).fold(f64::INFINITY, f64::min)
        })
        .fold(0.0f64, f64::max);
    assert!(off < 1e-3, "{off}");
    for (ends, want) in [(EndCondition::G0, 0), (EndCondition::G1, 1)] {
        let mut s = FairingSetup::new(&c, (opts(3e-3)).ends(ends)).unwrap();
        for k in 0..s.target().len() {
            s.target_mut().set(k, 1.0);
        }
        let r = s.fair().unwrap();
        let (rms, max) = curvature_error(&r.curve, shape);
        let e = extrema(&r.curve, 0.05);
        println!("{ends:?} ends, target ≡ 1: extrema {e}, κ error rms {rms:.2e} max {max:.2e}");
        assert!(dev_max(&c, &r.curve) <= 3e-3);
        assert_eq!(e, want, "{ends:?}");
        if ends == EndCondition::G0 {
            assert!(max < 1e-3, "{max}");
        }
    }
}

/// A G1 end does not keep the end curvature: on a noisy circle arc (end curvature 3.9 where the true
/// one is 1) the faired end curvature comes much closer to 1; with G2 it stays.
#[test]
fn g1_ends_fair_the_end_curvature_g2_ends_keep_it() {
    let shape = Shape::Circle { r: 1.0, a: 2.0 };
    let c = noisy_curve(shape, 40, 1e-3, 7);
    let (d0, d1) = c.domain();
    let k_end = |x: &BSplineCurve| [x.curvature(d0), x.curvature(d1)];
    let k0 = k_end(&c);
    for ends in [EndCondition::G2, EndCondition::G1] {
        let r = fair_curve(&c, (line_search_opts(3e-3, ends)).ends(ends)).unwrap();
        let k1 = k_end(&r.curve);
        println!("{ends:?}: end curvature {k0:.3?} -> {k1:.3?} (true 1)");
        for (a, b) in k0.iter().zip(&k1) {
            if ends == EndCondition::G2 {
                assert!((a - b).abs() < 1e-9 * a.abs(), "G2 keeps the end curvature: {a} -> {b}");
            } else {
                assert!((b - 1.0).abs() < 0.5 * (a - 1.0).abs(), "G1: {a} -> {b}");
            }
        }
    }
}

#[test]
fn a_fair_circle_arc_hardly_changes() {
    // noise-free circle arc, least-squares cubic with 60 control points
    let shape = Shape::Circle { r: 1.0, a: 2.0 };
    let c = noisy_curve(shape, 60, 0.0, 1);
    let (krms, kmax) = curvature_error(&c, shape);
    println!("input curvature error: rms {krms:.2e}, max {kmax:.2e}");
    for integrator in [Integrator::Arc, Integrator::Rk2] {
        let r = fair_curve(&c, FairingOptions::default().tolerance(1e-3).integrator(integrator)).unwrap();
        let moved = c
            .points()
            .iter()
            .zip(r.curve.points())
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max);
        let d = dev_max(&c, &r.curve).max(dev_max(&r.curve, &c));
        println!("{integrator:?}: control points moved ≤ {moved:.2e}, Hausdorff {d:.2e}");
        // With 60 control points the cubic's own curvature error (up to 1e-4, largest near the ends) is
        // what the smoothed target removes: measured 5.7e-6 (Arc). The finer representation below, fair to
        // 1e-5 in curvature, moves by < 1e-6.
        assert!(d < 1e-5, "{integrator:?}: {d}");
        let (k1, _) = curvature_error(&r.curve, shape);
        assert!(k1 <= krms * 1.1, "{integrator:?}: κ error {krms} -> {k1}");
    }
}

/// The "an already fair circle arc changes by < 1e-6": a cubic is never exactly a circle, and the
/// change follows the representation's own curvature error δκ (the fairing removes it): measured
/// Hausdorff ≈ 0.055 δκ_max for 60…300 control points (2-rad arc, L = 2). A circle arc represented to
/// δκ < 1e-5 (200 control points) moves by < 1e-6.
#[test]
fn a_finely_represented_circle_arc_moves_less_than_1e_6() {
    let shape = Shape::Circle { r: 1.0, a: 2.0 };
    for n in [60, 200] {
        let c = noisy_curve(shape, n, 0.0, 1);
        let (_, kmax) = curvature_error(&c, shape);
        let r = fair_curve(&c, opts(1e-3)).unwrap();
        let d = dev_max(&c, &r.curve).max(dev_max(&r.curve, &c));
        println!("{n} control points: input κ error max {kmax:.2e}, Hausdorff change {d:.2e}");
        assert!(d <= 0.1 * kmax, "{n}: change {d} vs the input's curvature error {kmax}");
        if n == 200 {
            assert!(kmax < 1e-5 && d < 1e-6, "{n}: κ error {kmax}, change {d}");
        }
    }
}

/// The issue asks for fast E ≤ iterative E. Measured here: iterative 9.0836e-2; fast 1.018e-1 after the
/// band search alone, 9.0578e-2 with the Gauss–Newton polish of E inside the band (0.3 % below the
/// baseline); both hold the band.
#[test]
fn fast_energy_no_worse_than_iterative() {
    let c = noisy_curve(
        Shape::Ellipse {
            a: 2.0,
            b: 1.0,
            th: 2.5,
        },
        16,
        1e-3,
        3,
    );
    let mut setup = FairingSetup::new(&c, opts(3e-3)).unwrap();
    let e_orig = setup.energy(&c);
    let it = fair_iterative(&setup, IterativeOptions::default()).unwrap();
    let fast = setup.fair().unwrap();
    println!(
        "E original {e_orig:.4e}, iterative {:.4e}, fast {:.4e}",
        it.energy, fast.energy
    );
    assert!(it.energy < e_orig);
    assert!(
        fast.energy <= it.energy,
        "fast {} vs iterative {}",
        fast.energy,
        it.energy
    );
    assert!(fast.energy < 0.65 * e_orig);
    // both report a sound bound of the deviation, sharp to what `measure` finds
    for r in [&it, &fast] {
        let d = dev_max(&c, &r.curve);
        assert!(d <= 3e-3);
        assert!(
            reported_bound_ok(r.max_deviation, d, 3e-3),
            "{d} vs {}",
            r.max_deviation
        );
    }
}

/// The bench curve (crates/fairway/benches/fairing.rs: 100 control points through a noisy sine, 1000
/// samples, m = 2e-3). More polish iterations never raise E, and the band holds for every count. The
/// interior point on E ([`PolishMethod::InteriorPoint`]) holds the band where the iterative baseline does,
/// at the check samples, and with 24 iterations reaches a lower E than the baseline. The default
/// (variation) polish holds it at the hull of the difference curve, i.e. everywhere, a slightly smaller
/// set: its E stays within 3 % of the baseline's (measured 173.0 against 169.7).
#[test]
fn more_polish_iterations_reach_the_iterative_energy_on_the_bench_curve() {
    let c = bench_curve();
    let o = (opts(2e-3)).samples(Some(1000));
    let setup = FairingSetup::new(&c, o).unwrap();
    let it = fair_iterative(&setup, IterativeOptions::default()).unwrap();
    for method in [PolishMethod::Variation, PolishMethod::InteriorPoint] {
        let mut energies = vec![];
        for n in [0, 8, 24] {
            let mut s = setup.clone();
            s.set_polish_method(method);
            s.set_polish_iterations(n);
            let r = s.fair().unwrap();
            assert!(dev_max(&c, &r.curve) <= 2e-3, "{method:?}, {n} iterations: band broken");
            energies.push(r.energy);
        }
        println!(
            "E iterative {:.4e}; {method:?} with 0 / 8 / 24 polish iterations {energies:?}",
            it.energy
        );
        assert!(
            energies[0] > energies[1] && energies[1] >= energies[2],
            "{method:?} {energies:?}"
        );
        let allowed = if method == PolishMethod::Variation { 1.03 } else { 1.0 };
        assert!(
            energies[2] <= it.energy * allowed,
            "{method:?} {energies:?} vs iterative {}",
            it.energy
        );
    }
}

/// A straight line whose control polygon steps back once (the curve runs forward, back and forward
/// again over the same stretch, found by the probe campaign): fairing slides its points along the line,
/// so every check sample's true distance is round-off while its parametric displacement is up to 1e-2,
/// and the nearest point of the faired curve lies on another pass over the stretch. The reported
/// deviation must still be the measured one (session 8: 8.8e-3 reported for 5e-15 measured).
#[test]
fn reported_deviation_on_a_line_that_doubles_back_is_the_measured_one() {
    let step = DVec2::new(0.04912354669824471, -0.04008998861122006);
    let pts: Vec<DVec2> = [0, 1, 2, 3, 4, 5, 6, 7, 8, 7, 10, 11, 12, 13, 14]
        .iter()
        .map(|&i| step * i as f64)
        .collect();
    let knots = vec![
        2.146338136318855,
        2.146338136318855,
        2.146338136318855,
        2.146338136318855,
        2.2378286142286967,
        2.2929565571818395,
        2.4301143651909607,
        2.4341165647650826,
        2.5053428123506007,
        2.5720387341467448,
        2.677153915905066,
        2.8119985486822765,
        2.8404025142381637,
        3.061548131564958,
        3.0689000803375333,
        3.146338136318855,
        3.146338136318855,
        3.146338136318855,
        3.146338136318855,
    ];
    let c = BSplineCurve::new_2d(3, knots, &pts).unwrap();
    let m = 8.876850146894601e-3;
    let r = fair_curve(&c, (opts(m)).region(Some((2.228952169259838, 3.0701126685965985)))).unwrap();
    let measured = measure(&c, &r.curve).dev_max;
    let moved = c
        .points()
        .iter()
        .zip(r.curve.points())
        .fold(0.0f64, |a, (p, q)| a.max(p.distance(*q)));
    println!(
        "reported {:e}, measured {measured:e}, largest point move {moved:e}",
        r.max_deviation
    );
    // the case is the one described: the points slid along the line by more than the band
    assert!(moved > m, "{moved}");
    assert!(r.max_deviation <= m);
    // (the measure finds round-off; the bound is far inside the band, not the points' slide)
    assert!(
        reported_bound_ok(r.max_deviation, measured, m),
        "reported {} vs measured {measured}",
        r.max_deviation
    );
}

#[test]
fn degenerate_input() {
    let line = BSplineCurve::new_2d(
        3,
        KnotVector::uniform(3, 10).unwrap().values().to_vec(),
        &(0..10)
            .map(|i| DVec2::new(i as f64, 0.5 * i as f64))
            .collect::<Vec<_>>(),
    )
    .unwrap();
    // a straight line (κ ≡ 0) is already fair: a no-op up to round-off
    let r = fair_curve(&line, opts(1e-3)).unwrap();
    for (a, b) in line.points().iter().zip(r.curve.points()) {
        assert!(a.distance(*b) < 1e-12, "{a} {b}");
    }
    // tolerance 0 / negative / NaN / infinite
    for m in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        match FairingSetup::new(&line, opts(m)) {
            Err(Error::BadTolerance { value }) => assert!(value.to_bits() == m.to_bits(), "{value}"),
            other => panic!("tolerance {m}: {other:?}"),
        }
    }
    let mut s = FairingSetup::new(&line, opts(1e-3)).unwrap();
    assert!(s.set_tolerance(-1.0).is_err());
    // regions: outside the domain, empty, tiny (fewer than p + 1 spans), NaN
    let region = |a: f64, b: f64| (opts(1e-3)).region(Some((a, b)));
    assert!(matches!(
        FairingSetup::new(&line, region(1.2, 1.5)),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        FairingSetup::new(&line, region(-0.5, 0.5)),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        FairingSetup::new(&line, region(0.6, 0.4)),
        Err(Error::EmptyRegion { u1: 0.6, u2: 0.4 })
    ));
    assert!(matches!(
        FairingSetup::new(&line, region(f64::NAN, 0.4)),
        Err(Error::RegionNotFinite { .. })
    ));
    match FairingSetup::new(&line, region(0.40, 0.55)) {
        Err(Error::RegionTooSmall { u1, u2, .. }) => assert_eq!((u1, u2), (0.40, 0.55)),
        other => panic!("{other:?}"),
    }
    // all control points coincident: zero length
    let dot = BSplineCurve::new_2d(
        3,
        KnotVector::uniform(3, 8).unwrap().values().to_vec(),
        &[DVec2::new(1.0, 2.0); 8],
    )
    .unwrap();
    assert!(matches!(FairingSetup::new(&dot, opts(1e-3)), Err(Error::Degenerate(_))));
    // two coincident control points inside: a clear error or a result that keeps the band
    let mut pts: Vec<DVec2> = (0..12).map(|i| DVec2::new(i as f64, (i as f64 * 0.7).sin())).collect();
    pts[6] = pts[5];
    let c = BSplineCurve::new_2d(3, KnotVector::uniform(3, 12).unwrap().values().to_vec(), &pts).unwrap();
    match fair_curve(&c, opts(1e-2)) {
        Ok(r) => assert!(dev_max(&c, &r.curve) <= 1e-2),
        Err(e) => assert!(!e.to_string().is_empty()),
    }
    // degree 1: no curvature
    let poly = BSplineCurve::new_2d(1, vec![0.0, 0.0, 0.5, 1.0, 1.0], &[DVec2::ZERO, DVec2::X, DVec2::ONE]).unwrap();
    assert!(matches!(
        FairingSetup::new(&poly, opts(1e-3)),
        Err(Error::DegreeTooLowToFair { degree: 1 })
    ));
}

/// A rotation taking the xy plane to a tilted plane.
fn rotate(p: DVec3) -> DVec3 {
    let q = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.9);
    q * p
}

#[test]
fn planar_curve_in_3d_fairs_like_2d() {
    // an S-curve (one inflection) with noise: in 3D the signed curvature along the
    // transported normal must not fold at the inflection, so 3D = rotated 2D
    let c2 = noisy_curve(Shape::Clothoid { a: 1.0, l: 2.0 }, 24, 1e-3, 11);
    let pts: Vec<DVec3> = c2.points().iter().map(|p| DVec3::new(p.x - 0.5, p.y, 0.0)).collect();
    let c2 = c2.with_points(pts).unwrap();
    // make an S: reflect the second half's curvature by composing with its mirror
    let s_pts: Vec<DVec3> = c2
        .points()
        .iter()
        .map(|p| DVec3::new(p.x, p.y - 0.4 * (2.0 * p.x).sin(), 0.0))
        .collect();
    let c2 = c2.with_points(s_pts).unwrap();
    assert!(!c2.inflections(8).is_empty(), "the test curve has an inflection");
    let c3 = BSplineCurve::new_3d(
        3,
        c2.knots().values().to_vec(),
        c2.points().iter().map(|&p| rotate(p)).collect(),
    )
    .unwrap();
    let r2 = fair_curve(&c2, opts(2e-3)).unwrap();
    let r3 = fair_curve(&c3, opts(2e-3)).unwrap();
    let diff = r2
        .curve
        .points()
        .iter()
        .zip(r3.curve.points())
        .map(|(a, b)| rotate(*a).distance(*b))
        .fold(0.0, f64::max);
    println!(
        "3D vs rotated 2D: {diff:.2e}; E {:.6e} (2D) vs {:.6e} (3D)",
        r2.energy, r3.energy
    );
    // The band search alone gives 3D = 2D to 2.6e-16. The E polish after it takes discrete steps
    // (active set near the band edge, line search, E must drop, up to 8 Gauss–Newton steps), which can
    // go differently on the rounding differences between the 2D and the 3D curvature formulas: measured
    // 5.3e-5 = 2.6 % of the tolerance, with E equal to 6e-5 relative. A fold of the target at the
    // inflection would show at the scale of the tolerance and in E.
    assert!(diff < 0.05 * 2e-3, "{diff}");
    // E at the samples is sensitive to the control points (a 6.5e-7 difference moves it by 0.2 %)
    assert!((r2.energy - r3.energy).abs() <= 1e-2 * r2.energy);
    assert!(dev_max(&c3, &r3.curve) <= 2e-3);
}

#[test]
fn closed_curve_one_pass_holds_its_seam_fair_curve_fairs_it() {
    // a noisy full ellipse; closed by making the last control point the first, and G2 at the
    // seam by mirroring the two neighbours on each side (tangent and curvature equal)
    let c = noisy_curve(
        Shape::Ellipse {
            a: 2.0,
            b: 1.0,
            th: std::f64::consts::TAU,
        },
        40,
        1e-3,
        5,
    );
    let mut pts = c.points().to_vec();
    let n = pts.len();
    pts[n - 1] = pts[0];
    // uniform clamped knots (interior step h): c'(0) = 3(P1 − P0)/h, c''(0) = (6/h²)((P2 − P1)/2 − (P1 − P0)),
    // and mirrored at the end; equal first and second derivatives (C2 seam) give:
    pts[n - 2] = pts[0] * 2.0 - pts[1];
    pts[n - 3] = pts[0] * 6.0 - pts[1] * 6.0 + pts[2];
    let c = c.with_points(pts).unwrap();
    assert!(c.is_closed(0.0));
    let (d0, d1) = c.domain();
    let (s0, s1) = (c.derivs(d0), c.derivs(d1));
    assert!(s0.d1.distance(s1.d1) < 1e-9 * s0.d1.length() && s0.d2.distance(s1.d2) < 1e-9 * s0.d2.length());
    // one pass (FairingSetup) holds the seam and says so
    let r = FairingSetup::new(&c, opts(3e-3)).unwrap().fair().unwrap();
    assert!(matches!(r.seam, Seam::Held(_)), "{:?}", r.seam);
    assert!(r.curve.is_closed(1e-12));
    for u in [d0, d1] {
        let (a, b) = (c.derivs(u), r.curve.derivs(u));
        assert!(a.p.distance(b.p) <= 1e-12);
        assert!(a.d1.normalize().distance(b.d1.normalize()) <= 1e-12);
        assert!((a.curvature(2) - b.curvature(2)).abs() <= 1e-9 * a.curvature(2).abs().max(1.0));
    }
    assert!(dev_max(&c, &r.curve) <= 3e-3);
    let (m0, m1) = (measure(&c, &c), measure(&c, &r.curve));
    assert!(m1.E_var < m0.E_var, "{} {}", m1.E_var, m0.E_var);
    // fair_curve fairs across the seam (tests/closed.rs has the details): still closed and G2 there,
    // the original knots, the band, and a fairer curve than the held seam's
    let f = fair_curve(&c, opts(3e-3)).unwrap();
    assert_eq!(f.seam, Seam::Faired);
    assert!(f.curve.is_closed(1e-12));
    assert_eq!(f.curve.knots().values(), c.knots().values());
    let (a, b) = (f.curve.derivs(d0), f.curve.derivs(d1));
    assert!(a.d1.normalize().distance(b.d1.normalize()) <= 1e-9);
    assert!((a.curvature(2) - b.curvature(2)).abs() <= 1e-9 * a.curvature(2).abs());
    assert!(dev_max(&c, &f.curve) <= 3e-3);
    let m2 = measure(&c, &f.curve);
    println!(
        "E_var original {:.4e}, seam held {:.4e}, seam faired {:.4e}",
        m0.E_var, m1.E_var, m2.E_var
    );
    assert!(m2.E_var < m1.E_var, "{} {}", m2.E_var, m1.E_var);
}

#[test]
fn target_edits_are_followed() {
    let c = noisy_curve(Shape::Circle { r: 1.0, a: 2.0 }, 30, 1e-3, 2);
    let mut setup = FairingSetup::new(&c, opts(5e-3)).unwrap();
    let n = setup.target().len();
    let a = setup.fair().unwrap();
    // flatten the middle third to its mean and pin one sample to a larger value
    setup.target_mut().flatten_range(n / 3, 2 * n / 3);
    let k = n / 6;
    setup.target_mut().set(k, 1.3);
    setup.target_mut().pin(k);
    setup
        .target_mut()
        .smooth_range(0, n / 3 - 1, TargetMethod::Binomial, 50);
    assert_eq!(setup.target().values()[k], 1.3, "pinned values survive smoothing");
    let b = setup.fair().unwrap();
    let kappa = |cv: &BSplineCurve, i: usize| cv.curvature(setup.params()[i]);
    // the edited result is closer to the edited target than the unedited one
    assert!(setup.energy(&b.curve) < setup.energy(&a.curve));
    assert!((kappa(&b.curve, k) - 1.3).abs() < (kappa(&a.curve, k) - 1.3).abs());
    setup.target_mut().reset();
    assert_eq!(setup.target().values(), setup.target().original());
    assert!(dev_max(&c, &b.curve) <= 5e-3);
}

fn end_condition() -> impl Strategy<Value = EndCondition> {
    prop_oneof![Just(EndCondition::G0), Just(EndCondition::G1), Just(EndCondition::G2)]
}

fn integrator() -> impl Strategy<Value = Integrator> {
    prop_oneof![Just(Integrator::Euler), Just(Integrator::Rk2), Just(Integrator::Arc)]
}

fn target_method() -> impl Strategy<Value = TargetMethod> {
    prop_oneof![
        Just(TargetMethod::Average),
        Just(TargetMethod::Binomial),
        Just(TargetMethod::Fit)
    ]
}

fn polish_method() -> impl Strategy<Value = PolishMethod> {
    prop_oneof![
        Just(PolishMethod::Variation),
        Just(PolishMethod::LineSearch),
        Just(PolishMethod::InteriorPoint)
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: prop_cases(16), ..ProptestConfig::default() })]

    #[test]
    fn tolerance_held_points_and_g2_joins(
        seed in 1u64..1000,
        ncp in 14usize..30,
        u1 in 0.0f64..0.5,
        w in 0.3f64..0.8,
        log_tol in -3.5f64..-1.5,
        ends in end_condition(),
        integrator in integrator(),
        target in target_method(),
        polish_method in polish_method(),
    ) {
        let c = noisy_curve(Shape::Ellipse { a: 2.0, b: 1.0, th: 3.0 }, ncp, 2e-3, seed);
        let u2 = (u1 + w).min(1.0);
        let tol = 10f64.powf(log_tol);
        let o = FairingOptions::default().region(Some((u1, u2))).tolerance(tol).ends(ends).integrator(integrator).target(target).polish_method(polish_method);
        let setup = match FairingSetup::new(&c, o) {
            Ok(s) => s,
            Err(Error::RegionTooSmall { .. }) => return Ok(()),
            Err(e) => panic!("{e}"),
        };
        let mut setup = setup;
        let r = setup.fair().unwrap();
        // hard tolerance, measured independently: measure's 2000 arc-length samples, and the dense
        // check of tests/common (its own evaluation and projection, 20 per span and the span ends,
        // peaks sharpened), which the reported bound must cover
        let d = dev_max(&c, &r.curve);
        prop_assert!(d <= tol, "dev {} > tol {}", d, tol);
        prop_assert!(r.max_deviation <= tol);
        prop_assert!(reported_bound_ok_dense(r.max_deviation, d, &c, &r.curve, tol), "reported {} vs measured {}", r.max_deviation, d);
        // fairer by the independent measures (the default polish promises it: a result that is not
        // leaves the curve as it was): no more curvature extrema, ∫(dκ/ds)² not above the input's
        if polish_method == PolishMethod::Variation {
            let (m0, m1) = (measure(&c, &c), measure(&c, &r.curve));
            prop_assert!(m1.n_curv_extrema <= m0.n_curv_extrema, "extrema {} -> {}", m0.n_curv_extrema, m1.n_curv_extrema);
            prop_assert!(m1.E_var <= m0.E_var * (1.0 + 1e-9), "E_var {} -> {}", m0.E_var, m1.E_var);
        }
        // control points whose support leaves [u1, u2] are unchanged
        let work = c.refine(&extra_knots(&c, &r.curve)).unwrap();
        prop_assert_eq!(work.n_points(), r.curve.n_points());
        for i in 0..work.n_points() {
            let (lo, hi) = work.knots().support(i);
            if lo < u1 - 1e-12 || hi > u2 + 1e-12 {
                prop_assert!(work.points()[i].distance(r.curve.points()[i]) <= 1e-12, "point {} moved", i);
            }
        }
        // the joins at the ends of the moving stretch: G2 (G1 / G0 as asked) to 1e-9 relative
        let (a, b) = setup.moving_range();
        let (d0, d1) = c.domain();
        for u in [a, b] {
            if u <= d0 || u >= d1 {
                continue; // a curve end: end point, tangent and curvature held by the kept points
            }
            let eps = 1e-9 * (d1 - d0);
            let side = if u == a { u - eps } else { u + eps };
            // on the moving side: right of a, left of b
            let (o, f) = common::join_derivs(&c, &r.curve, u, u == b);
            let scale = c.control_bounds().1.distance(c.control_bounds().0);
            prop_assert!(o.p.distance(f.p) <= 1e-9 * scale);
            if ends != EndCondition::G0 {
                prop_assert!(o.d1.normalize().distance(f.d1.normalize()) <= 1e-9);
            }
            if ends == EndCondition::G2 {
                let (k0, k1) = (o.curvature(2), f.curvature(2));
                prop_assert!((k0 - k1).abs() <= 1e-9 * k0.abs().max(1.0), "κ {} vs {}", k0, k1);
            }
            // outside, the curves coincide
            prop_assert!(c.point(side).distance(r.curve.point(side)) <= 1e-12 * scale.max(1.0));
        }
    }
}

/// Regression (probe campaign, issue 4): a planar curve in 3D left its plane — by up to 1e-6 of its
/// size (78 of 500 random planar 3D cases, worst at a large tolerance, where the fairness weight is at
/// its cap and the per-coordinate fit's rounding is amplified by the condition number). Its update is
/// now projected onto the plane: every control point stays in it to rounding.
#[test]
fn planar_curve_in_3d_stays_in_its_plane() {
    let c2 = noisy_curve(Shape::Clothoid { a: 1.0, l: 2.0 }, 24, 3e-3, 5);
    let off = DVec3::new(0.3, -1.2, 2.5);
    let c3 = BSplineCurve::new_3d(
        3,
        c2.knots().values().to_vec(),
        c2.points().iter().map(|&p| rotate(p) + off).collect(),
    )
    .unwrap();
    let n = rotate(DVec3::Z);
    let size = {
        let (lo, hi) = c3.control_bounds();
        (hi - lo).length()
    };
    // the largest distance of a control point from the plane
    let off_plane = |c: &BSplineCurve| c.points().iter().map(|p| (*p - off).dot(n).abs()).fold(0.0, f64::max);
    let mut worst: f64 = 0.0;
    for m in [1e-3, 3e-2, 0.2, 1.0] {
        for region in [None, Some((0.2, 0.9))] {
            let r = fair_curve(&c3, (opts(m)).region(region)).unwrap();
            worst = worst.max(off_plane(&r.curve) / size);
        }
    }
    assert!(worst <= 1e-13, "out of the plane by {worst:e} of the size");
    // the iterative baseline moves one point at a time by downhill simplex in 3D: E does not see the
    // normal direction, so its points drifted out of the plane by up to the tolerance (29 of 30 random
    // planar cases); its moves are now constrained by the setup as well
    let s = FairingSetup::new(&c3, opts(0.2)).unwrap();
    let r = fair_iterative(&s, IterativeOptions::default()).unwrap();
    let d = off_plane(&r.curve);
    assert!(d <= 1e-13 * size, "iterative: out of the plane by {d:e}");
    assert!(max_point_diff(&r.curve, &c3) > 1e-4, "faired");
}

/// `FairingOptions::ease_curve_ends`: G2 curve ends still keep position, tangent and curvature, the band
/// holds, and on the known-answer arcs (8 seeds each) the extra extrema drop against the default target,
/// which climbs to the noisy end curvature from far inside (on the ellipse they do not rise), and so does
/// the curvature error of the circle and the clothoid.
#[test]
fn eased_g2_curve_ends_keep_the_end_and_fair_the_end_span() {
    let tol = 3e-3;
    let eased_opts = (line_search_opts(tol, EndCondition::G2)).ease_curve_ends(true);
    for shape in KNOWN_SHAPES {
        let kmax = shape.dense(200).1.iter().fold(0.0f64, |m, k| m.max(k.abs()));
        let (mut rms, mut ext) = ([0.0; 2], [0; 2]);
        for seed in 1..=8 {
            let c = noisy_curve(shape, 40, 1e-3, seed);
            let (d0, d1) = c.domain();
            for (j, o) in [line_search_opts(tol, EndCondition::G2), eased_opts]
                .into_iter()
                .enumerate()
            {
                let r = fair_curve(&c, o).unwrap();
                assert!(dev_max(&c, &r.curve) <= tol, "{shape:?} seed {seed}");
                for u in [d0, d1] {
                    assert!(c.point(u).distance(r.curve.point(u)) < 1e-12);
                    assert!(c.tangent(u).angle_between(r.curve.tangent(u)) < 1e-9);
                    let (k0, k1) = (c.curvature(u), r.curve.curvature(u));
                    assert!(
                        (k0 - k1).abs() < 1e-9 * k0.abs().max(1.0),
                        "{shape:?} seed {seed}: {k0} -> {k1}"
                    );
                }
                rms[j] += curvature_error(&r.curve, shape).0;
                ext[j] += extrema(&r.curve, 0.05 * kmax);
            }
        }
        println!(
            "{shape:?}, 8 seeds: Σ κ RMS error {:.3} -> {:.3} eased, Σ extrema {} -> {}",
            rms[0], rms[1], ext[0], ext[1]
        );
        // the ellipse's default target gained from the polish's roughness cap (session 14: Σ extrema 15 → 13,
        // the eased target's 13): easing no longer adds to that there, and must not lose it
        if matches!(shape, Shape::Ellipse { .. }) {
            assert!(ext[1] <= ext[0], "{shape:?}: {ext:?}");
        } else {
            assert!(ext[1] < ext[0], "{shape:?}: {ext:?}");
        }
        // the ellipse's ends are not the arc's worst error: its κ RMS error stays about the same
        // (measured 0.152 -> 0.156); the circle's and the clothoid's drop
        if !matches!(shape, Shape::Ellipse { .. }) {
            assert!(rms[1] < 0.8 * rms[0], "{shape:?}: {rms:?}");
        }
    }
}

/// The option only touches G2 ends that are ends of an open curve: a region inside the curve and G1 ends
/// give the same curve bit for bit.
#[test]
fn easing_leaves_region_joins_and_g1_ends_alone() {
    let c = noisy_curve(Shape::Circle { r: 1.0, a: 2.0 }, 40, 1e-3, 7);
    let (d0, d1) = c.domain();
    let region = Some((d0 + 0.2 * (d1 - d0), d0 + 0.8 * (d1 - d0)));
    for o in [(opts(3e-3)).region(region), (opts(3e-3)).ends(EndCondition::G1)] {
        let plain = fair_curve(&c, o).unwrap();
        let eased = fair_curve(&c, o.ease_curve_ends(true)).unwrap();
        assert_eq!(plain.curve.points(), eased.curve.points(), "{o:?}");
    }
}

/// Probe campaign (session 12): fairing never leaves the paper's E above the original's. On a wave with
/// its knots crowded at the start (u⁴ spacing) and noise of ±3e-3, the band-holding fit raised E from
/// 10.6 to 34.1 (the tiny spans near u = 0 turn a small move into a large curvature change), and the
/// polish, which only accepts steps that lower E, started from there. Now it starts from the original
/// when the fit is worse than it: E 10.6 -> 3.9. (14 of 59 seeds of this family took that path; none
/// of the other tests does.)
#[test]
fn fairing_never_raises_e_above_the_original() {
    let mut rng = common::Rng::new(16);
    let n = 30;
    let mut inner: Vec<f64> = (0..n - 4).map(|_| rng.uniform().powi(4)).collect();
    inner.sort_by(f64::total_cmp);
    let mut knots = vec![0.0; 4];
    knots.extend(inner);
    knots.extend([1.0; 4]);
    let pts: Vec<DVec2> = (0..n)
        .map(|i| {
            let t = i as f64 / (n - 1) as f64;
            DVec2::new(4.0 * t, 0.5 * (3.0 * t).sin() + (rng.uniform() - 0.5) * 6e-3)
        })
        .collect();
    let c = BSplineCurve::new_2d(3, knots, &pts).unwrap();
    let m = 3e-3;
    let mut s = FairingSetup::new(&c, opts(m)).unwrap();
    let e0 = s.energy(s.working_curve());
    let r = s.fair().unwrap();
    println!("E {e0:.4} -> {:.4}, α {}, μ {:e}", r.energy, r.alpha, r.mu);
    assert!(r.energy <= e0, "E {e0} -> {}", r.energy);
    assert!(r.max_deviation <= m && dev_max(&c, &r.curve) <= m);
    // and the polish did lower it (not merely the original returned)
    assert!(r.energy < 0.5 * e0, "E {e0} -> {}", r.energy);
}

/// A helix x = cos t, y = sin t, z = 0.3 t over 1.5 turns (curvature 1/1.09 everywhere, torsion 0.3/1.09)
/// sampled with noise σ = `sigma` on all three coordinates and fitted by a cubic with 40 control points.
fn noisy_helix(sigma: f64, seed: u64) -> BSplineCurve {
    let (ncp, nsamp) = (40, 480);
    let mut rng = common::Rng::new(seed);
    let data: Vec<DVec3> = (0..nsamp)
        .map(|k| {
            let t = 3.0 * std::f64::consts::PI * k as f64 / (nsamp - 1) as f64;
            let noise = if k == 0 || k + 1 == nsamp {
                DVec3::ZERO
            } else {
                DVec3::new(rng.gauss(), rng.gauss(), rng.gauss()) * sigma
            };
            DVec3::new(t.cos(), t.sin(), 0.3 * t) + noise
        })
        .collect();
    let params: Vec<f64> = (0..nsamp).map(|k| k as f64 / (nsamp - 1) as f64).collect();
    let knots = fairway::KnotVector::uniform(3, ncp).unwrap();
    let cp = fairway::fit::fit_curve_points(&knots, &params, &data, None, fairway::fit::Smoothing::NONE, &[]).unwrap();
    BSplineCurve::try_new(3, knots.values().to_vec(), cp, None, 3).unwrap()
}

/// RMS of κ − 1/1.09 (the helix's) at 900 equal-arc samples over the middle 90 % of `c`.
fn helix_curvature_error(c: &BSplineCurve) -> f64 {
    let table = fairway::ArcLengthTable::new(c, 1e-10);
    let us = table.equal_arc_params(c, 1001);
    let e2: f64 = us[50..=950]
        .iter()
        .map(|&u| (c.curvature(u) - 1.0 / 1.09).powi(2))
        .sum();
    (e2 / 901.0).sqrt()
}

/// Regression (session 14): in 3D the polish followed the target only along the setup's normal, so it
/// could turn the curvature vector out of the osculating plane for free. A looser tolerance then gave a
/// *less* fair curve than a tight one: on this helix (seed 1) at m = 0.02 ∫(dκ/ds)² 1.99 → 2.24 against
/// m = 5e-3 and 50 curvature extrema where the input had 34; on `assets/spatial_curve.json`, region
/// [0.2, 0.8], m = 0.02: ∫(dκ/ds)² 9.1 → 33, extrema 36 → 50. E now also counts the curvature along the
/// binormal: at every tolerance the result is fairer than the input (∫(dκ/ds)²), loosening the tolerance
/// never makes it less fair, and at the tight one the curvature error against the true helix drops
/// (measured 3.7× and 6.7×). (The extrema count is not asserted: the helix's curvature is constant, so
/// it counts ripples of any size.) (Looser tolerances take the curve further from the
/// noisy input and from the exact helix: the error to it rises again, 0.0095 → 0.0099 → 0.013 on seed 1.)
/// The torsion is faired as well: its extrema fall from 34 to at most 7 (27–32 without the torsion term).
#[test]
fn a_spatial_curve_is_fairer_at_a_looser_tolerance() {
    for seed in [1, 2] {
        let c = noisy_helix(2e-3, seed);
        let before = helix_curvature_error(&c);
        let m0 = measure(&c, &c);
        let mut e_var = vec![];
        for m in [5e-3, 2e-2, 5e-2] {
            let r = fair_curve(&c, opts(m)).unwrap();
            assert!(dev_max(&c, &r.curve) <= m * (1.0 + 1e-9));
            let m1 = measure(&c, &r.curve);
            let after = helix_curvature_error(&r.curve);
            println!(
                "seed {seed}, m = {m}: κ RMS error {before:.4} -> {after:.4} ({:.1}×), ∫(dκ/ds)² {:.3} -> {:.3}, extrema {} -> {}",
                before / after,
                m0.E_var,
                m1.E_var,
                m0.n_curv_extrema,
                m1.n_curv_extrema
            );
            assert!(m1.E_var < m0.E_var, "seed {seed}, m = {m}");
            // the torsion is faired too (FairingOptions::torsion_weight): without its term 34 → 27–32
            let (t0, t1) = (m0.n_torsion_extrema.unwrap(), m1.n_torsion_extrema.unwrap());
            assert!(3 * t1 <= t0, "seed {seed}, m = {m}: torsion extrema {t0} -> {t1}");
            if m == 5e-3 {
                assert!(after < 0.5 * before, "seed {seed}: κ error {before} -> {after}");
            }
            e_var.push(m1.E_var);
        }
        for w in e_var.windows(2) {
            assert!(
                w[1] <= 1.05 * w[0],
                "seed {seed}: a looser tolerance is less fair: {e_var:?}"
            );
        }
    }
}

/// The join checks above look at the moving side of each end of the moving stretch: at its end `b` that
/// is the left limit. Shown to catch a broken join on a quadratic (C1 at its knots, so a curvature jump
/// at a knot is possible; a cubic with simple knots is C2 there whatever its points): a region fair
/// with G2 ends, then the last control point whose support ends at `b` pushed off by 1e-3 — position
/// and tangent at `b` stay, the faired side's curvature there changes. The left-limit check sees the jump; the right limit (the untouched
/// span, what the checks evaluated before) compares the original with itself and sees nothing.
#[test]
fn the_join_check_at_the_stretch_end_sees_a_broken_curvature_join() {
    let c = noisy_curve_of_degree(
        Shape::Ellipse {
            a: 2.0,
            b: 1.0,
            th: 3.0,
        },
        2,
        40,
        2e-3,
        7,
    );
    let o = (opts(5e-3)).region(Some((0.3, 0.7))).ends(EndCondition::G2);
    let mut setup = FairingSetup::new(&c, o).unwrap();
    let r = setup.fair().unwrap();
    let (_, b) = setup.moving_range();
    let jump = |x: &BSplineCurve, y: &BSplineCurve, left: bool| {
        let (o, f) = join_derivs(x, y, b, left);
        (o.p.distance(f.p), o.curvature_vector().distance(f.curvature_vector()))
    };
    // the fair itself keeps the join, seen from both sides
    let (dp, dk) = jump(&c, &r.curve, true);
    assert!(
        dp <= 1e-12 && dk <= 1e-9 * c.curvature(b).abs().max(1.0),
        "faired join: {dp} {dk}"
    );
    // break it: the control point whose support ends at b
    let k = (0..r.curve.n_points())
        .find(|&i| r.curve.knots().support(i).1 == b)
        .expect("a point whose support ends at b");
    let mut pts = r.curve.points().to_vec();
    pts[k] += DVec3::new(1e-3, 1e-3, 0.0);
    let broken = r.curve.with_points(pts).unwrap();
    let (dp, dk) = jump(&c, &broken, true);
    assert!(dp <= 1e-12, "position at b stays: {dp}");
    assert!(dk > 1e-3, "the left-limit check sees the curvature jump: {dk}");
    let (dp, dk) = jump(&c, &broken, false);
    assert!(dp <= 1e-12 && dk <= 1e-12, "the right limit cannot: {dp} {dk}");
}

/// A G0 / G1 region end a hair past a knot (1.1e-5, 2e-4 of its span: a mouse drag that lands next to a
/// knot) is moved onto that knot instead of making a moving sliver span: the moving stretch ends at the
/// knot, ∫(dκ/ds)² comes out below the input's (it was 5.6e15 for 7.6 before, the proptest case kept in
/// fair_curves.proptest-regressions), and nothing outside the asked region moves. A knot outside the
/// region is never snapped to (that would move geometry outside it).
#[test]
fn a_region_end_next_to_a_knot_snaps_onto_it_inward_only() {
    let c = noisy_curve(
        Shape::Ellipse {
            a: 2.0,
            b: 1.0,
            th: 3.0,
        },
        24,
        2e-3,
        156,
    );
    let knot = c.knots().values()[c.knots().values().partition_point(|&k| k < 0.7)];
    for ends in [EndCondition::G0, EndCondition::G1] {
        for (u2, snapped) in [(knot + 1.1e-5, true), (knot - 1.1e-5, false)] {
            let o = (opts(0.03)).region(Some((0.16, u2))).ends(ends);
            let mut setup = FairingSetup::new(&c, o).unwrap();
            let r = setup.fair().unwrap();
            let b = setup.moving_range().1;
            if snapped {
                assert_eq!(b, knot, "{ends:?}: the end {u2} moves onto the knot {knot}");
            } else {
                assert_eq!(b, u2, "{ends:?}: the end {u2} stays where it was asked");
            }
            let (m0, m1) = (measure(&c, &c), measure(&c, &r.curve));
            assert!(
                m1.E_var <= m0.E_var,
                "{ends:?} {u2}: E_var {} -> {}",
                m0.E_var,
                m1.E_var
            );
            for k in 0..=100 {
                let u = u2 + (1.0 - u2) * k as f64 / 100.0;
                assert!(c.point(u).distance(r.curve.point(u)) <= 1e-12, "{ends:?}: moved at {u}");
            }
        }
    }
}

/// A Bézier chain (triple knots, G1 joints, which stay G1) whose last patch is a sliver — 1e-4 of the others, as on an
/// edge of a public impeller model (pyiges' `impeller.igs`, `scripts/real_curves.sh`). Faired whole, the
/// sliver stays as it is, the joints stay G1 and the curve ends fairer; before, its joint moved a few band widths,
/// several times the sliver's own length, and ∫(dκ/ds)² went from 1.1e4 to 1.5e14 with the band held.
#[test]
fn a_sliver_span_at_the_curve_end_stays_and_the_fair_is_fairer() {
    let mut rng = common::Rng::new(7);
    // 4 patches along a gently twisting wave, noisy inner points, joints at the midpoints (G1)
    let mut pts: Vec<DVec3> = (0..13)
        .map(|i| {
            let t = i as f64 / 12.0;
            DVec3::new(
                4.0 * t,
                0.6 * (2.5 * t).sin() + 2e-3 * rng.gauss(),
                0.2 * t * t + 2e-3 * rng.gauss(),
            )
        })
        .collect();
    for j in [3, 6, 9] {
        pts[j] = 0.5 * (pts[j - 1] + pts[j + 1]);
    }
    // the sliver: three more points along the end tangent, 1e-5 apart
    let t = (pts[12] - pts[11]).normalize();
    for k in 1..=3 {
        pts.push(pts[12] + t * (1e-5 * k as f64));
    }
    let mut knots = vec![0.0; 4];
    for k in 1..=4 {
        knots.extend([k as f64; 3]);
    }
    knots.extend([4.001; 4]);
    let c = BSplineCurve::new_3d(3, knots, pts).unwrap();
    let m = 2e-3;
    let r = fair_curve(&c, opts(m)).unwrap();
    assert!(dev_max(&c, &r.curve) <= m * (1.0 + 1e-9));
    for i in 12..16 {
        assert_eq!(r.curve.points()[i], c.points()[i], "sliver point {i} moved");
    }
    let (m0, m1) = (measure(&c, &c), measure(&c, &r.curve));
    println!(
        "∫(dκ/ds)² {:.4e} -> {:.4e}, extrema {} -> {}",
        m0.E_var, m1.E_var, m0.n_curv_extrema, m1.n_curv_extrema
    );
    // the curvature steps at the joints (G1, C0 in the parameter): Σ (κ⁺ − κ⁻)², which measure's
    // quadrature inside the spans does not see
    let steps = |c: &BSplineCurve| -> f64 {
        [1.0, 2.0, 3.0]
            .iter()
            .map(|&u| {
                let h = 1e-9;
                (c.curvature(u + h) - c.curvature(u - h)).powi(2)
            })
            .sum()
    };
    let (s0, s1) = (steps(&c), steps(&r.curve));
    println!("Σ curvature steps² at the joints {s0:.4e} -> {s1:.4e}");
    // fairer by the independent measures: no more extrema and no larger ∫(dκ/ds)² inside the spans (the
    // polish prices the steps at the joints too, but runs on without those prices where its result would
    // lose to the reference smoother on ∫(dκ/ds)²); and not a no-op: a lower ∫(dκ/ds)² or smaller steps
    assert!(m1.n_curv_extrema <= m0.n_curv_extrema);
    assert!(m1.E_var <= m0.E_var, "E_var {} -> {}", m0.E_var, m1.E_var);
    assert!(
        m1.E_var < m0.E_var * (1.0 - 1e-3) || s1 < 0.9 * s0,
        "the fair did nothing: E_var {} -> {}, steps {s0} -> {s1}",
        m0.E_var,
        m1.E_var
    );
    // the chain's joints (triple knots, G1 in the original to rounding) stay G1: before, the fair opened
    // them into kinks of about a degree (1.25° at joint 3) inside the band; now ≤ 1e-6 rad (measured
    // 1.5e-8)
    let q = r.curve.points();
    for j in [3, 6, 9] {
        let angle = (q[j] - q[j - 1]).angle_between(q[j + 1] - q[j]);
        assert!(angle <= 1e-6, "joint {j} kinked by {:.3e}°", angle.to_degrees());
    }
}

/// A NURBS curve (unequal weights) fairs: through a non-rational stand-in within a tenth of the band, the
/// band held against the rational original by `measure`'s projection, the reported bound covering it,
/// the result fairer by `measure`, and a note saying what was faired. (Before: refused, "fairing needs a
/// non-rational B-spline".)
#[test]
fn a_rational_curve_with_unequal_weights_fairs_through_a_stand_in() {
    let mut rng = common::Rng::new(11);
    // a noisy rational quadratic spiral arc: 14 control points, weights between 0.6 and 1.4
    let n = 14;
    let pts: Vec<DVec3> = (0..n)
        .map(|i| {
            let t = i as f64 / (n - 1) as f64 * 3.0;
            let r = 1.0 + 0.2 * t;
            DVec3::new(r * t.cos() + 3e-3 * rng.gauss(), r * t.sin() + 3e-3 * rng.gauss(), 0.0)
        })
        .collect();
    let weights: Vec<f64> = (0..n).map(|i| 1.0 + 0.4 * ((i * 5 % 7) as f64 / 3.0 - 1.0)).collect();
    let mut knots = vec![0.0; 3];
    knots.extend((1..n - 2).map(|i| i as f64 / (n - 2) as f64));
    knots.extend([1.0; 3]);
    let c = BSplineCurve::try_new(2, knots, pts, Some(weights), 2).unwrap();
    assert!(c.to_polynomial().is_err(), "the weights are unequal");
    let m = 0.01;
    let r = fair_curve(&c, opts(m)).unwrap();
    assert!(!r.curve.is_rational());
    assert_eq!(r.curve.degree(), 3);
    let measured = dev_max(&c, &r.curve);
    assert!(measured <= m * (1.0 + 1e-9), "{measured} > {m}");
    assert!(
        measured <= r.max_deviation * (1.0 + 1e-9),
        "{measured} above the bound {}",
        r.max_deviation
    );
    assert!(r.max_deviation <= m * (1.0 + 1e-9));
    assert!(r.notes.iter().any(|n| n.contains("rational curve")), "{:?}", r.notes);
    let (m0, m1) = (measure(&c, &c), measure(&c, &r.curve));
    println!(
        "E_var {:.4e} -> {:.4e}, extrema {} -> {}, bound {:.4e}, measured {measured:.4e}",
        m0.E_var, m1.E_var, m0.n_curv_extrema, m1.n_curv_extrema, r.max_deviation
    );
    assert!(m1.E_var < m0.E_var && m1.n_curv_extrema <= m0.n_curv_extrema);
    // the tolerance can change on the same preparation, and a much tighter one approximates afresh
    let mut f = CurveFairing::new(&c, opts(m)).unwrap();
    f.set_tolerance(1e-3).unwrap();
    let tight = f.fair(Pass::Full).unwrap().result;
    assert!(tight.max_deviation <= 1e-3 * (1.0 + 1e-9));
    assert!(dev_max(&c, &tight.curve) <= 1e-3 * (1.0 + 1e-9));
}

/// A single-span quartic edge written by OpenCASCADE (`tests/data/corpus/impeller-faces-occ.step`,
/// object 57): its curvature rises monotonically (no interior extremum). The default fair at 5·10⁻⁴ × its
/// diagonal must not give it one (measure's count): the engine's result there did, so the fair returns
/// the edge as it was, and says so.
#[test]
fn a_fair_never_ends_with_more_curvature_extrema_than_the_input() {
    use fairway::fair::{CurveFairing, Pass};
    let pts = [
        DVec3::new(-10.99126662438, 15.204012441519, -5.665044710781),
        DVec3::new(-10.86520812146, 14.930810595662, -5.804364470066),
        DVec3::new(-10.77344421365, 14.737033215198, -5.907685538412),
        DVec3::new(-10.71740210698, 14.619331228697, -5.97102149791),
        DVec3::new(-10.69723943557, 14.577132965258, -5.993783684),
    ];
    let knots = vec![0.9375, 0.9375, 0.9375, 0.9375, 0.9375, 1.0, 1.0, 1.0, 1.0, 1.0];
    let c = BSplineCurve::try_new(4, knots, pts.to_vec(), None, 3).unwrap();
    let (lo, hi) = pts.iter().fold((pts[0], pts[0]), |(a, b), &q| (a.min(q), b.max(q)));
    let m = 5e-4 * (hi - lo).length();
    let before = fairway::measure::measure(&c, &c).n_curv_extrema;
    assert_eq!(before, 0);
    let f = CurveFairing::new(&c, FairingOptions::default().tolerance(m))
        .unwrap()
        .fair(Pass::Full)
        .unwrap();
    let after = fairway::measure::measure(&c, &f.result.curve);
    assert!(after.n_curv_extrema <= before, "{} -> {}", before, after.n_curv_extrema);
    assert!(after.dev_max <= m, "{} > {m}", after.dev_max);
    if f.result.curve == c {
        assert!(
            f.result.notes.iter().any(|n| n.starts_with("left as it was")),
            "{:?}",
            f.result.notes
        );
    }
}

/// `set_fairest_mu(false)` stops the fit at the band's largest μ; on (the default) μ steps down from
/// there by factors of 16 while the fit's E falls. On noisy circle arcs (the fit alone, no polish): both
/// hold the band; where the two differ, the default's μ is the band's limit divided by a power of 16 and
/// its E is lower; and on some of them it does differ (the step down is what the option turns off).
#[test]
fn fairest_mu_steps_down_from_the_bands_largest() {
    let mut stepped = 0;
    for (ncp, sigma, seed) in [
        (12, 1e-2, 3),
        (24, 1e-2, 1),
        (60, 1e-2, 1),
        (60, 1e-3, 1),
        (24, 1e-3, 2),
    ] {
        let c = noisy_curve(KNOWN_SHAPES[0], ncp, sigma, seed);
        for f in [1.0, 3.0, 10.0] {
            let m = f * sigma;
            let o = FairingOptions::default().tolerance(m).polish(false);
            let on = FairingSetup::new(&c, o).unwrap().fair().unwrap();
            let mut s = FairingSetup::new(&c, o).unwrap();
            s.set_fairest_mu(false);
            let off = s.fair().unwrap();
            let case = format!("{ncp} cps, σ {sigma}, seed {seed}, m = {f} σ");
            assert!(on.max_deviation <= m && off.max_deviation <= m, "{case}");
            if on.mu != off.mu {
                stepped += 1;
                let steps = (off.mu / on.mu).ln() / 16f64.ln();
                assert!(
                    steps >= 1.0 - 1e-9 && (steps - steps.round()).abs() < 1e-9,
                    "{case}: μ {} against the band's {}",
                    on.mu,
                    off.mu
                );
                assert!(on.energy < off.energy, "{case}: E {} against {}", on.energy, off.energy);
            }
        }
    }
    assert!(stepped >= 3, "the step down changed μ on {stepped} of 15 cases");
}
