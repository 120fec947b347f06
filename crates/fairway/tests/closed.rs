//! Closed curves faired across the seam (issue 4, item 8): knot removal, exact re-seaming,
//! the two-pass fairing of a noisy closed ellipse (seam curvature, G2, knots, band), fallback on a corner.

mod common;

use common::*;
use fairway::fair::closed::{reseam, rotate, unrotate};
use fairway::fair::*;
use fairway::{ArcLengthTable, BSplineCurve, CurveProjector, DVec2, DVec3, Error};

/// A wavy open curve of degree p with non-uniform knots.
fn wavy(p: usize, n: usize) -> BSplineCurve {
    let pts: Vec<DVec2> = (0..n)
        .map(|i| {
            let t = i as f64;
            DVec2::new(t + 0.3 * (1.7 * t).sin(), (0.9 * t).sin() + 0.2 * (3.1 * t).cos())
        })
        .collect();
    let mut k = vec![0.0; p + 1];
    let inner = n - p - 1;
    let mut x = 0.0;
    for i in 0..inner {
        x += 1.0 + 0.5 * ((i * 7) % 3) as f64;
        k.push(x);
    }
    let end = x + 1.3;
    k.extend(std::iter::repeat_n(end, p + 1));
    BSplineCurve::new_2d(p, k, &pts).unwrap()
}

/// The options these tests' thresholds were measured with: the line-search E polish and G2 at curve
/// ends (the default polish is judged against the reference smoother in tests/quality.rs).
fn ls_opts(m: f64) -> fairway::fair::FairingOptions {
    opts(m)
        .polish_method(fairway::fair::PolishMethod::LineSearch)
        .curve_ends([Some(fairway::fair::EndCondition::G2); 2])
}

#[test]
fn remove_knot_undoes_insert_knot() {
    for p in [2usize, 3, 4, 5] {
        let c = wavy(p, 12);
        let (a, b) = c.domain();
        let inner = c.knots().values()[p + 2]; // an existing simple knot
        for (u, have) in [(a + 0.37 * (b - a), 0usize), (inner, 1)] {
            for times in 1..=p - have {
                let up = c.insert_knot(u, times).unwrap();
                assert_eq!(up.knots().multiplicity(u), have + times);
                let back = up.remove_knot(u, times, 1e-9).unwrap();
                assert_eq!(back.knots().values(), c.knots().values(), "p {p} u {u} times {times}");
                let d = max_point_diff(&back, &c);
                assert!(d <= 1e-12, "p {p} u {u} times {times}: {d:e}");
            }
        }
    }
}

#[test]
fn remove_knot_undoes_insert_knot_on_a_rational_curve() {
    let c = wavy(3, 10);
    let w: Vec<f64> = (0..10).map(|i| 1.0 + 0.3 * ((i * 5) % 4) as f64).collect();
    let r = BSplineCurve::try_new(3, c.knots().values().to_vec(), c.points().to_vec(), Some(w), 2).unwrap();
    let (a, b) = r.domain();
    let u = a + 0.61 * (b - a);
    let up = r.insert_knot(u, 3).unwrap();
    let back = up.remove_knot(u, 3, 1e-9).unwrap();
    assert_eq!(back.knots().values(), r.knots().values());
    assert!(max_point_diff(&back, &r) <= 1e-12);
    let dw = back
        .weights()
        .unwrap()
        .iter()
        .zip(r.weights().unwrap())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(dw <= 1e-12, "{dw:e}");
}

#[test]
fn remove_knot_refuses_where_the_curve_is_not_smooth_enough() {
    // a generic cubic is C2 but not C3 at a simple knot: removing it would change the curve
    let c = wavy(3, 10);
    let u = c.knots().values()[5];
    match c.remove_knot(u, 1, 1e-6) {
        Err(Error::KnotNotRemovable {
            removed: 0,
            requested: 1,
            ..
        }) => {}
        other => panic!("{other:?}"),
    }
    // a real kink: the knot raised to multiplicity p, the control point on the curve moved
    let k = c.insert_knot(u, 2).unwrap();
    let mut pts = k.points().to_vec();
    let i = k.knots().values().partition_point(|&x| x <= u) - 1 - 3; // the point on the curve at u
    pts[i] += DVec3::new(0.0, 0.3, 0.0); // a corner at u
    let kinked = k.with_points(pts).unwrap();
    let e = kinked.remove_knot(u, 1, 1e-6).unwrap_err();
    assert!(matches!(e, Error::KnotNotRemovable { removed: 0, .. }), "{e}");
    assert!(e.to_string().contains("not smooth enough"), "{e}");
    // bad requests
    assert!(c.remove_knot(c.domain().0, 1, 1e-6).is_err());
    assert!(c.remove_knot(0.123456, 1, 1e-6).is_err());
    assert!(c.remove_knot(u, 1, f64::NAN).is_err());
}

/// A closed, C2 cubic near the ellipse x = 2 cos θ, y = sin θ: the uniform periodic cubic B-spline of
/// the N cyclic control points `Q_j` = ellipse(2πj/N)/((4 + 2 cos(2π/N))/6) (+ Gaussian noise σ, fixed
/// seed), written exactly as a clamped curve on [0, 1] (blossoms: P0 = (Q_{-1} + 4Q_0 + Q_1)/6,
/// P1 = (2Q_0 + Q_1)/3, P_j = Q_{j−1} for j = 2..N, P_{N+1} = (Q_{N−1} + 2Q_0)/3, P_{N+2} = P0). Its
/// seam at (≈2, 0) is the point of largest curvature; the noise is the same there as anywhere.
fn periodic_ellipse(n: usize, sigma: f64, seed: u64) -> BSplineCurve {
    let mut rng = Rng::new(seed);
    let shrink = (4.0 + 2.0 * (std::f64::consts::TAU / n as f64).cos()) / 6.0;
    let q: Vec<DVec3> = (0..n)
        .map(|j| {
            let t = std::f64::consts::TAU * j as f64 / n as f64;
            DVec3::new(2.0 * t.cos(), t.sin(), 0.0) / shrink + DVec3::new(rng.gauss(), rng.gauss(), 0.0) * sigma
        })
        .collect();
    periodic(&q, 2)
}

/// The uniform periodic cubic of the cyclic control points `q`, as a clamped curve on [0, 1].
fn periodic(q: &[DVec3], dim: usize) -> BSplineCurve {
    fairway::fair::closed::periodic_cubic(q, dim).unwrap()
}

/// `periodic_cubic` against the closed form of a uniform cubic B-spline: at the knot u = j/n the curve is
/// (Q_{j−1} + 4 Q_j + Q_{j+1})/6, and the two ends meet with equal first and second derivatives.
#[test]
fn periodic_cubic_matches_the_uniform_b_spline_at_its_knots() {
    let n = 9;
    let q: Vec<DVec3> = (0..n)
        .map(|j| DVec3::new((j as f64 * 1.7).sin(), (j as f64 * 0.9).cos(), 0.1 * j as f64))
        .collect();
    let c = fairway::fair::closed::periodic_cubic(&q, 3).unwrap();
    for j in 0..=n {
        let at = |k: isize| q[k.rem_euclid(n as isize) as usize];
        let want = (at(j as isize - 1) + at(j as isize) * 4.0 + at(j as isize + 1)) / 6.0;
        assert!(c.point(j as f64 / n as f64).distance(want) < 1e-14, "knot {j}");
    }
    let (s, e) = (c.derivs(0.0), c.derivs(1.0));
    assert!(s.d1.distance(e.d1) < 1e-12 && s.d2.distance(e.d2) < 1e-10);
    assert!(fairway::fair::closed::periodic_cubic(&q[..2], 3).is_err());
}

#[test]
fn rotation_is_exact_and_reversible() {
    let c = periodic_ellipse(80, 1e-3, 5);
    let (a, b) = c.domain();
    let l = b - a;
    let at = c.knots().values()[20];
    let r = rotate(&c, at).unwrap();
    assert_eq!(r.domain().0, at);
    assert!((r.domain().1 - (at + l)).abs() < 1e-14);
    assert_eq!(r.knots().multiplicity(b), 3);
    // the same points: c_rot(u) = c(u) on [at, b], c(u − L) beyond; the parameter map is a bijection,
    // so the max over it bounds the Hausdorff distance
    let (mut worst, mut worst_s) = (0.0f64, 0.0f64);
    for k in 0..=4000 {
        let u = at + l * k as f64 / 4000.0;
        let want = if u <= b { c.point(u) } else { c.point(u - l) };
        worst = worst.max(r.point(u).distance(want));
    }
    let (rs, mult) = reseam(&c, at, 1e-9).unwrap();
    assert_eq!(mult, 1, "a C2 seam is removed down to a simple knot");
    for k in 0..=4000 {
        let u = at + l * k as f64 / 4000.0;
        let want = if u <= b { c.point(u) } else { c.point(u - l) };
        worst_s = worst_s.max(rs.point(u).distance(want));
    }
    println!("rotated vs original {worst:.2e}, re-seamed (knot removed) {worst_s:.2e}");
    assert!(worst <= 1e-12, "{worst:e}");
    assert!(worst_s <= 1e-12, "{worst_s:e}");
    // back: the original knot vector and points
    for rot in [&r, &rs] {
        let back = unrotate(rot, &c, 1e-9).unwrap();
        assert_eq!(back.knots().values(), c.knots().values());
        let d = max_point_diff(&back, &c);
        assert!(d <= 1e-12, "{d:e}");
        assert_eq!(back.points()[0], *back.points().last().unwrap());
    }
}

/// RMS curvature error against the noise-free curve in the 10 windows of width 0.1 of `truth`'s
/// normalized arc length centred on t = 0 (the seam), 0.1, …, 0.9 (window 0 wraps around the seam).
/// Registered by closest point, not by arc length (which would charge a seam point that slid along
/// the curve with the curvature gradient there): 2000 arc-length samples of `c`, each compared with
/// the curvature of `truth` at its closest point.
fn window_errors(c: &BSplineCurve, truth: &BSplineCurve) -> [f64; 10] {
    let tt = ArcLengthTable::new(truth, 1e-10);
    let proj = CurveProjector::new(truth, 16);
    let table = ArcLengthTable::new(c, 1e-10);
    let (mut s2, mut n) = ([0.0; 10], [0usize; 10]);
    for u in table.equal_arc_params(c, 2001).into_iter().skip(1) {
        let cp = proj.project(c.point(u));
        let t = tt.length_at(truth, cp.param) / tt.length();
        let w = ((t * 10.0).round() as usize) % 10;
        let e = c.curvature(u) - truth.curvature(cp.param);
        s2[w] += e * e;
        n[w] += 1;
    }
    std::array::from_fn(|w| (s2[w] / n[w] as f64).sqrt())
}

#[test]
fn closed_curve_is_faired_across_the_seam() {
    // Six noisy closed ellipses (seeds 1–6). Fairing is judged at the seam (window 0) against the
    // antipode (window 5), the other curvature maximum of the ellipse, where every variant is an
    // interior point of a fairing pass: the seam should come out as well as the antipode.
    let m = 3e-3;
    let (mut seam_f, mut seam_h, mut anti_f, mut anti_h) = (0.0, 0.0, 0.0, 0.0);
    for seed in 1..=6 {
        let c = periodic_ellipse(80, 1e-3, seed);
        let truth = periodic_ellipse(80, 0.0, seed);
        assert!(c.is_closed(0.0));
        let (d0, d1) = c.domain();
        let r = fair_closed(&c, ls_opts(m)).unwrap();
        assert_eq!(r.seam, Seam::Faired);
        // the old behaviour: one pass, seam held
        let held = FairingSetup::new(&c, ls_opts(m)).unwrap().fair().unwrap();
        assert!(matches!(held.seam, Seam::Held(_)), "{:?}", held.seam);
        // a loop has no curve ends to ease (FairingOptions::ease_curve_ends): the same curves
        let eased = (ls_opts(m)).ease_curve_ends(true);
        assert_eq!(fair_closed(&c, eased).unwrap().curve.points(), r.curve.points());
        let held_eased = FairingSetup::new(&c, eased).unwrap().fair().unwrap();
        assert_eq!(held_eased.curve.points(), held.curve.points());
        let fmt = |e: [f64; 10]| e.iter().map(|x| format!("{x:.4}")).collect::<Vec<_>>().join(" ");
        let (eo, ef, eh) = (
            window_errors(&c, &truth),
            window_errors(&r.curve, &truth),
            window_errors(&held.curve, &truth),
        );
        println!("seed {seed}: κ RMS error in 10 % windows centred on t = 0 (seam), 0.1, …, 0.9");
        println!("  original    {}", fmt(eo));
        println!("  seam faired {}", fmt(ef));
        println!("  seam held   {}", fmt(eh));
        seam_f += ef[0] * ef[0];
        anti_f += ef[5] * ef[5];
        seam_h += eh[0] * eh[0];
        anti_h += eh[5] * eh[5];
        // form: original knots, closed, G2 (in fact C2) across the seam
        assert_eq!(r.curve.knots().values(), c.knots().values());
        assert!(r.curve.is_closed(1e-12));
        let (s0, s1) = (r.curve.derivs(d0), r.curve.derivs(d1));
        assert!(s0.p.distance(s1.p) <= 1e-12);
        let (t0, t1) = (s0.d1.normalize(), s1.d1.normalize());
        assert!(t0.distance(t1) <= 1e-9, "{:e}", t0.distance(t1));
        let (k0, k1) = (s0.curvature(2), s1.curvature(2));
        assert!((k0 - k1).abs() <= 1e-9 * k0.abs(), "{k0} {k1}");
        // the seam itself moved (one pass holds it exactly)
        assert!((k0 - c.curvature(d0)).abs() > 1e-4, "{k0} {}", c.curvature(d0));
        // the band against the original, measured as `measure` does
        let dev = dev_max(&c, &r.curve);
        assert!(dev <= m, "{dev}");
        // the reported bound: at least the measure's value, and sharp
        assert!(reported_bound_ok(r.max_deviation, dev, m), "{dev} {}", r.max_deviation);
    }
    let (ratio_f, ratio_h) = ((seam_f / anti_f).sqrt(), (seam_h / anti_h).sqrt());
    println!("RMS over the seeds, seam / antipode error: seam faired {ratio_f:.2}, seam held {ratio_h:.2}");
    assert!(ratio_f <= 1.25, "{ratio_f}");
    assert!(ratio_h > 1.25, "the held seam passes too: {ratio_h}");
}

/// The iterative baseline fairs a whole closed curve across its seam too (the same two passes, blend
/// and verification as the fast method, `fair_closed_iterative`), so the two are compared on the same
/// problem: the result keeps the knots, is closed and G2 across a seam that moved, holds the band, and
/// reaches a lower E than the single pass that holds the seam (its objective, with the seam free).
/// Measured on this curve (seed 4): E 12.53 across the seam vs 12.73 held; the fast method 12.66, 1 %
/// above the baseline, but its curvature is much closer to the noise-free curve's (κ RMS error over
/// ten windows 0.021 vs 0.037; at the seam 0.032 vs 0.074: minimizing E against a target smoothed from
/// noisy curvature is not the same as recovering the true curvature).
#[test]
fn iterative_baseline_fairs_a_closed_curve_across_the_seam() {
    let m = 3e-3;
    let c = periodic_ellipse(40, 1e-3, 4);
    let truth = periodic_ellipse(40, 0.0, 4);
    let (d0, d1) = c.domain();
    let r = fair_closed_iterative(&c, ls_opts(m), IterativeOptions::default()).unwrap();
    assert_eq!(r.seam, Seam::Faired, "{:?}", r.seam);
    assert_eq!(r.curve.knots().values(), c.knots().values());
    assert!(r.curve.is_closed(1e-12));
    let (s0, s1) = (r.curve.derivs(d0), r.curve.derivs(d1));
    assert!(s0.d1.normalize().distance(s1.d1.normalize()) <= 1e-9);
    let (k0, k1) = (s0.curvature(2), s1.curvature(2));
    assert!((k0 - k1).abs() <= 1e-9 * k0.abs(), "{k0} {k1}");
    assert!((k0 - c.curvature(d0)).abs() > 1e-4, "the seam did not move: {k0}");
    let dev = dev_max(&c, &r.curve);
    assert!(
        dev <= m && dev <= r.max_deviation + 1e-15 && r.max_deviation <= m,
        "{dev} {}",
        r.max_deviation
    );
    // one pass of the baseline holds the seam
    let setup = FairingSetup::new(&c, ls_opts(m)).unwrap();
    let held = fair_iterative(&setup, IterativeOptions::default()).unwrap();
    assert!(matches!(held.seam, Seam::Held(_)));
    assert!(r.energy < held.energy, "E across {} vs held {}", r.energy, held.energy);
    let fast = fair_closed(&c, ls_opts(m)).unwrap();
    let rms = |e: [f64; 10]| (e.iter().map(|x| x * x).sum::<f64>() / 10.0).sqrt();
    let (ei, ef) = (window_errors(&r.curve, &truth), window_errors(&fast.curve, &truth));
    println!(
        "closed, both across the seam: E iterative {:.4} (held {:.4}), fast {:.4}; κ RMS error iterative {:.4} \
         (seam {:.4}), fast {:.4} (seam {:.4})",
        r.energy,
        held.energy,
        fast.energy,
        rms(ei),
        ei[0],
        rms(ef),
        ef[0]
    );
    assert!(rms(ef) < rms(ei), "fast {} vs iterative {}", rms(ef), rms(ei));
}

#[test]
fn corner_at_the_seam_is_held_and_said_so() {
    let c = periodic_ellipse(40, 1e-3, 9);
    let mut pts = c.points().to_vec();
    pts[1] += DVec3::new(0.0, 0.05, 0.0); // the start tangent turns: a corner at the seam
    let c = c.with_points(pts).unwrap();
    assert!(c.is_closed(0.0));
    let m = 3e-3;
    let r = fair_closed(&c, opts(m)).unwrap();
    match &r.seam {
        Seam::Held(why) => assert!(why.contains("corner"), "{why}"),
        other => panic!("{other:?}"),
    }
    // the held-seam result: the seam's control points unchanged, knots kept, the band held
    let n = c.n_points();
    for i in [0, 1, 2, n - 3, n - 2, n - 1] {
        assert_eq!(r.curve.points()[i], c.points()[i]);
    }
    assert_eq!(r.curve.knots().values(), c.knots().values());
    assert!(dev_max(&c, &r.curve) <= m);
}

#[test]
fn seam_state_of_regions_and_open_curves() {
    let c = periodic_ellipse(40, 1e-3, 3);
    let m = 3e-3;
    let with_region = |u1: f64, u2: f64| (opts(m)).region(Some((u1, u2)));
    // a region inside the domain does not touch the seam: one pass as for an open curve
    let r = fair_closed(&c, with_region(0.3, 0.6)).unwrap();
    assert_eq!(r.seam, Seam::Untouched);
    assert_eq!(r.curve.points()[0], c.points()[0]);
    // a region ending at the seam: the seam is a G2 region end, held
    let r = fair_closed(&c, with_region(0.5, 1.0)).unwrap();
    assert!(matches!(r.seam, Seam::Held(_)), "{:?}", r.seam);
    // a region covering the domain is the whole curve
    let r = fair_closed(&c, with_region(0.0, 1.0)).unwrap();
    assert_eq!(r.seam, Seam::Faired);
    // fair_curve sends a whole closed curve to fair_closed; FairingSetup is one pass: the seam is held
    assert_eq!(fair_curve(&c, opts(m)).unwrap().seam, Seam::Faired);
    let r = FairingSetup::new(&c, opts(m)).unwrap().fair().unwrap();
    assert!(matches!(r.seam, Seam::Held(_)), "{:?}", r.seam);
    // an open curve
    let o = wavy(3, 12);
    let r = fair_curve(&o, opts(1e-2)).unwrap();
    assert_eq!(r.seam, Seam::Open);
    assert!(fair_closed(&o, opts(1e-2)).is_err());
}

#[test]
fn g2_seam_with_a_speed_jump_is_held_and_said_so() {
    // G2 but not C2 at the seam: at b, c' = k c'(a) and c'' = k² c''(a) (the same curve geometry up to
    // second order, another speed). Uniform clamped knots: c'(b) ∝ P_{n−1} − P_{n−2},
    // c''(b) ∝ P_{n−3} − 3P_{n−2} + 2P_{n−1}; at a, P1 − P0 and P2 − 3P1 + 2P0.
    let c = periodic_ellipse(40, 1e-3, 4);
    let mut pts = c.points().to_vec();
    let n = pts.len();
    let k = 1.3;
    let (d1, d2) = (pts[1] - pts[0], pts[2] - pts[1] * 3.0 + pts[0] * 2.0);
    pts[n - 2] = pts[0] - d1 * k;
    pts[n - 3] = d2 * (k * k) + pts[n - 2] * 3.0 - pts[0] * 2.0;
    let c = c.with_points(pts).unwrap();
    let (s0, s1) = (c.derivs(0.0), c.derivs(1.0));
    assert!(s0.d1.normalize().distance(s1.d1.normalize()) < 1e-12);
    assert!((s0.curvature(2) - s1.curvature(2)).abs() < 1e-9 * s0.curvature(2).abs());
    let r = fair_closed(&c, opts(3e-3)).unwrap();
    match &r.seam {
        Seam::Held(why) => assert!(why.contains("not parametrically C2"), "{why}"),
        other => panic!("{other:?}"),
    }
    assert!(dev_max(&c, &r.curve) <= 3e-3);
}

#[test]
fn closed_3d_curve_is_faired_across_the_seam() {
    // a noisy closed ellipse on a tilted plane with an out-of-plane wave (non-planar: torsion ≠ 0)
    let mut rng = Rng::new(2);
    let n = 40;
    let q: Vec<DVec3> = (0..n)
        .map(|j| {
            let t = std::f64::consts::TAU * j as f64 / n as f64;
            let (x, y) = (2.0 * t.cos(), t.sin());
            DVec3::new(x, 0.8 * y, 0.6 * y + 0.2 * (2.0 * t).sin())
                + DVec3::new(rng.gauss(), rng.gauss(), rng.gauss()) * 1e-3
        })
        .collect();
    let c = periodic(&q, 3);
    assert!(c.torsion(0.3).abs() > 1e-3);
    let m = 3e-3;
    let r = fair_closed(&c, opts(m)).unwrap();
    assert_eq!(r.seam, Seam::Faired);
    assert_eq!(r.curve.knots().values(), c.knots().values());
    assert!(r.curve.is_closed(1e-12));
    let (s0, s1) = (r.curve.derivs(0.0), r.curve.derivs(1.0));
    assert!(s0.d1.normalize().distance(s1.d1.normalize()) <= 1e-9);
    assert!(s0.curvature_vector().distance(s1.curvature_vector()) <= 1e-9 * s0.curvature_vector().length());
    assert!(dev_max(&c, &r.curve) <= m);
    // the seam's control points moved (one pass holds them)
    assert!(r.curve.points()[1].distance(c.points()[1]) > 1e-7);
}

#[test]
fn coarse_closed_curves_keep_their_form() {
    // few spans: the blend weight of the control points next to the re-seaming knot is forced to 0, so
    // the rotation back is exact whatever the spacing
    for n in [8usize, 12, 20] {
        let c = periodic_ellipse(n, 2e-3, 11);
        let m = 5e-3;
        let r = fair_closed(&c, opts(m)).unwrap();
        assert_eq!(r.seam, Seam::Faired, "n = {n}");
        assert_eq!(r.curve.knots().values(), c.knots().values());
        assert!(r.curve.is_closed(1e-12));
        let (s0, s1) = (r.curve.derivs(0.0), r.curve.derivs(1.0));
        assert!(s0.d1.normalize().distance(s1.d1.normalize()) <= 1e-9);
        assert!(dev_max(&c, &r.curve) <= m);
    }
}

/// A region across the seam (u1 > u2: [u1, b] then [a, u2]) is faired as one stretch: outside it the
/// curve is unchanged (≤ 1e-12), its ends join with G2, the seam inside it moved and stays closed and
/// C2, the knots are the original's, the band holds; a seam that is not C2 or an open curve is a clear
/// error, as is a region end outside the domain.
#[test]
fn region_across_the_seam_is_one_faired_stretch() {
    let c = periodic_ellipse(60, 1e-3, 4);
    let m = 3e-3;
    let (u1, u2) = (0.8, 0.25);
    let o = (opts(m)).region(Some((u1, u2)));
    let r = fair_closed(&c, o).unwrap();
    assert_eq!(r.seam, Seam::Faired);
    // fair_curve takes the same path
    let rc = fair_curve(&c, o).unwrap();
    assert_eq!(rc.curve, r.curve);
    let f = &r.curve;
    assert_eq!(f.knots(), c.knots());
    let n = f.n_points();
    assert!(f.points()[0].distance(f.points()[n - 1]) <= 1e-12, "closed");
    assert!(
        f.points()[0].distance(c.points()[0]) > 1e-6,
        "the seam inside the region moved"
    );
    // outside the region [u2, u1] nothing moved
    for k in 0..=200 {
        let u = u2 + (u1 - u2) * k as f64 / 200.0;
        assert!(f.point(u).distance(c.point(u)) <= 1e-12, "moved at u = {u}");
    }
    // G2 at the region ends, C2 at the seam (first and second derivatives at a and b)
    // (on the region's side: right of u1, left of u2)
    for u in [u1, u2] {
        let (a, b) = common::join_derivs(&c, f, u, u == u2);
        assert!(a.p.distance(b.p) <= 1e-12);
        assert!(a.d1.angle_between(b.d1) <= 1e-9, "tangent at {u}");
        let (ka, kb) = (a.curvature_vector(), b.curvature_vector());
        assert!(ka.distance(kb) <= 1e-9 * ka.length(), "curvature at {u}");
    }
    let (s, e) = (f.derivs(0.0), f.derivs(1.0));
    assert!(s.d1.distance(e.d1) <= 1e-9 * s.d1.length() && s.d2.distance(e.d2) <= 1e-8 * s.d2.length());
    assert!(dev_max(&c, f) <= m, "band");
    // fairer: the paper's E over the region's samples, original vs result (same re-seamed setup)
    let (setup, _) = fairway::fair::closed::setup_across_seam(&c, (opts(m)).region(Some((u1, u2)))).unwrap();
    let e0 = setup.energy(setup.working_curve());
    println!("region across the seam: E {e0:.4e} -> {:.4e}", r.energy);
    assert!(r.energy < 0.5 * e0, "E {e0} -> {}", r.energy);
    // errors
    let wrap = |c: &BSplineCurve, u1: f64, u2: f64| fair_closed(c, (opts(m)).region(Some((u1, u2))));
    assert!(matches!(wrap(&c, 1.2, 0.3), Err(Error::OutOfDomain { .. })));
    // too short a stretch: the message names the user's region and the reason
    let e = wrap(&c, 0.99, 0.01).unwrap_err();
    assert!(
        matches!(&e, Error::AcrossSeam { u1: 0.99, u2: 0.01, source, .. } if matches!(**source, Error::RegionTooSmall { .. })),
        "{e:?}"
    );
    let e = e.to_string();
    assert!(
        e.contains("[0.99, 0.01] across the seam") && e.contains("too small"),
        "{e}"
    );
    let corner = {
        let mut p = c.points().to_vec();
        let last = p.len() - 1;
        p[1] += DVec3::new(0.0, 0.05, 0.0);
        p[last - 1] += DVec3::new(0.05, 0.0, 0.0);
        c.with_points(p).unwrap()
    };
    let e = wrap(&corner, 0.8, 0.25).unwrap_err().to_string();
    assert!(e.contains("re-seamed"), "{e}");
    let e = fairway::fair::closed::setup_across_seam(&wavy(3, 12), (opts(m)).region(Some((0.8, 0.25))))
        .unwrap_err()
        .to_string();
    assert!(e.contains("not closed"), "{e}");
}

/// A closed quadratic (C1 everywhere, so also at the seam): the uniform periodic quadratic of the cyclic
/// points `R_i`, clamped on [0, 1] by blossoming (the end points are the knot blossom
/// f(0, 0) = f(1, 1) = (R_{n−1} + R_0)/2, the rest are the `R_i`). The seam treatment removes the seam
/// knot down to multiplicity 1 (C1, the most a quadratic has): the seam moves, the result keeps the
/// knots, stays closed and tangent-continuous across the seam, holds the band, and its curvature is
/// closer to the ellipse's than the noisy original's.
#[test]
fn closed_quadratic_is_faired_across_the_seam() {
    let n = 48;
    let mut rng = Rng::new(21);
    let shrink = (1.0 + (std::f64::consts::TAU / n as f64).cos()) / 2.0;
    let r: Vec<DVec3> = (0..n)
        .map(|i| {
            // R_i is the control point of the span centred on the knot midpoint (i + ½)/n
            let t = std::f64::consts::TAU * (i as f64 + 0.5) / n as f64;
            DVec3::new(2.0 * t.cos(), t.sin(), 0.0) / shrink.sqrt() + DVec3::new(rng.gauss(), rng.gauss(), 0.0) * 1e-3
        })
        .collect();
    let end = (r[n - 1] + r[0]) * 0.5;
    let mut pts = vec![end];
    pts.extend(r.iter().copied());
    pts.push(end);
    let mut k = vec![0.0; 3];
    k.extend((1..n).map(|i| i as f64 / n as f64));
    k.extend([1.0; 3]);
    let c = BSplineCurve::try_new(2, k, pts, None, 2).unwrap();
    assert!(c.is_closed(1e-15));
    // parametric C1 at the seam (the construction is periodic)
    let (a0, a1) = (c.derivs(0.0), c.derivs(1.0));
    assert!(a0.d1.distance(a1.d1) <= 1e-9 * a0.d1.length());
    let m = 3e-3;
    let res = fair_closed(&c, opts(m)).unwrap();
    assert_eq!(res.seam, Seam::Faired, "{:?}", res.seam);
    let f = &res.curve;
    assert_eq!(f.knots().values(), c.knots().values());
    assert!(f.is_closed(1e-12));
    let (s0, s1) = (f.derivs(0.0), f.derivs(1.0));
    assert!(
        s0.d1.normalize().distance(s1.d1.normalize()) <= 1e-9,
        "tangent jump at the seam"
    );
    assert!(
        f.points()[1].distance(c.points()[1]) > 1e-7,
        "the seam's control points moved"
    );
    assert!(dev_max(&c, f) <= m);
    // curvature error against the ellipse x = 2 cos θ, y = sin θ, at 400 points mid-span (a quadratic's
    // curvature jumps at its knots) by the closest ellipse angle
    let kappa_err = |x: &BSplineCurve| {
        let mut s = 0.0;
        for i in 0..400 {
            let u = (i as f64 + 0.5) / 400.0;
            let p = x.point(u);
            let th = (p.y).atan2(p.x / 2.0);
            let (sn, cs) = th.sin_cos();
            let k_true = 2.0 / (4.0 * sn * sn + cs * cs).powf(1.5);
            s += (x.curvature(u) - k_true).powi(2);
        }
        (s / 400.0).sqrt()
    };
    let (e0, e1) = (kappa_err(&c), kappa_err(f));
    println!(
        "closed quadratic: κ RMS error {e0:.4} -> {e1:.4}, dev {:.2e}",
        res.max_deviation
    );
    assert!(e1 < 0.5 * e0, "{e0} -> {e1}");
}

/// The uniform periodic B-spline of degree `p` with the cyclic control points `q` (knots t_i = i/n),
/// written exactly as a clamped curve on [0, 1]: control point j of the clamped form is the blossom
/// f(k_{j+1}, …, k_{j+p}) of the clamped knots, evaluated on a span j..j+p covers (de Boor with one
/// argument per level, The NURBS Book §3.5 / Ramshaw).
fn periodic_degree(q: &[DVec3], p: usize) -> BSplineCurve {
    let n = q.len();
    let t = |i: isize| i as f64 / n as f64;
    let at = |i: isize| q[i.rem_euclid(n as isize) as usize];
    // blossom of the polynomial piece on the periodic span [t_s, t_{s+1})
    let blossom = |s: isize, x: &[f64]| {
        let mut d: Vec<DVec3> = (0..=p).map(|i| at(s - p as isize + i as isize)).collect();
        for r in 1..=p {
            for i in (r..=p).rev() {
                let gi = s - p as isize + i as isize; // global index of d[i]
                let a = (x[r - 1] - t(gi)) / (t(gi + (p + 1 - r) as isize) - t(gi));
                d[i] = d[i - 1] * (1.0 - a) + d[i] * a;
            }
        }
        d[p]
    };
    let mut k = vec![0.0; p + 1];
    k.extend((1..n).map(|i| i as f64 / n as f64));
    k.extend(vec![1.0; p + 1]);
    let m = n + p; // control points of the clamped form
    let mut pts: Vec<DVec3> = (0..m)
        .map(|j| {
            let l = (j + p).min(n + p - 1);
            blossom(l as isize - p as isize, &k[j + 1..=j + p])
        })
        .collect();
    assert!(pts[0].distance(pts[m - 1]) < 1e-12, "periodic construction");
    pts[m - 1] = pts[0];
    BSplineCurve::try_new(p, k, pts, None, 2).unwrap()
}

/// Closed curves of degree 3, 4 and 5 (a noisy closed ellipse built periodic of each degree, four
/// seeds) are faired across their seam: pass 1 holds p control points at each end, so its seam stays
/// C^{p−1} like the original's. Each result holds the band, keeps the knots, stays closed and
/// C^{p−1} across the seam. Summed over the seeds, its curvature error against the noise-free
/// construction is below the input's and below that of one pass with the seam held (what quartics
/// and quintics got before), and next to the seam below the held pass's, within 1.5× the error
/// over the whole loop and within 1.25× the error around the antipode, the other curvature maximum
/// (no seam artifact; the held seam's neighbourhood even came out worse than the input there, 0.0622
/// vs 0.0437 on one quartic seed).
#[test]
fn closed_quartic_and_quintic_are_faired_across_their_seam() {
    for p in [3usize, 4, 5] {
        // Σ over the seeds of the κ RMS error: input, faired across the seam, held seam; each over the
        // whole loop and over the tenth of the domain on each side of the seam
        let (mut all, mut seam, mut antipode) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        for seed in 0..4u64 {
            let n = 40;
            let mut rng = Rng::new(30 + p as u64 + 100 * seed);
            let clean: Vec<DVec3> = (0..n)
                .map(|i| {
                    let th = std::f64::consts::TAU * i as f64 / n as f64;
                    DVec3::new(2.0 * th.cos(), th.sin(), 0.0)
                })
                .collect();
            let q: Vec<DVec3> = clean
                .iter()
                .map(|x| *x + DVec3::new(rng.gauss(), rng.gauss(), 0.0) * 1e-3)
                .collect();
            let truth = periodic_degree(&clean, p);
            let c = periodic_degree(&q, p);
            // the construction is periodic: c' and c'' agree at the seam
            let (a0, a1) = (c.derivs(0.0), c.derivs(1.0));
            assert!(
                a0.d1.distance(a1.d1) <= 1e-9 * a0.d1.length(),
                "p = {p}: c' at the seam"
            );
            assert!(
                a0.d2.distance(a1.d2) <= 1e-9 * a0.d2.length(),
                "p = {p}: c'' at the seam"
            );
            let m = 3e-3;
            let r = fair_closed(&c, ls_opts(m)).unwrap();
            let f = &r.curve;
            assert_eq!(r.seam, Seam::Faired, "p = {p}, seed {seed}");
            assert_eq!(f.degree(), p);
            assert_eq!(f.knots().values(), c.knots().values());
            assert!(f.is_closed(1e-12));
            assert!(dev_max(&c, f) <= m, "p = {p}, seed {seed}");
            // C^{p−1} across the seam: rotated to put the seam inside (a knot of multiplicity p), the
            // seam knot is removable down to multiplicity 1 (knot removal to 1e-9 of the size)
            let (lo, hi) = f.control_bounds();
            let (_, mult) = reseam(f, 0.5, 1e-9 * (hi - lo).length()).unwrap();
            assert_eq!(mult, 1, "p = {p}, seed {seed}: the seam is not C^(p-1)");
            let held = FairingSetup::new(&c, ls_opts(m)).unwrap().fair().unwrap();
            assert!(matches!(held.seam, Seam::Held(_)));
            // curvature error against the noise-free construction, at the closest point of it
            let proj = fairway::CurveProjector::new(&truth, 8);
            // over the parameters `keep` selects
            let kappa_err = |x: &BSplineCurve, keep: &dyn Fn(f64) -> bool| {
                let us: Vec<f64> = (0..400)
                    .map(|i| (i as f64 + 0.5) / 400.0)
                    .filter(|&u| keep(u))
                    .collect();
                let s: f64 = us
                    .iter()
                    .map(|&u| {
                        let cp = proj.project(x.point(u));
                        (x.curvature(u) - truth.curvature(cp.param)).powi(2)
                    })
                    .sum();
                (s / us.len() as f64).sqrt()
            };
            for (k, x) in [&c, f, &held.curve].into_iter().enumerate() {
                all[k] += kappa_err(x, &|_| true);
                seam[k] += kappa_err(x, &|u| !(0.1..=0.9).contains(&u));
                // the same width around the antipode, the ellipse's other curvature maximum
                antipode[k] += kappa_err(x, &|u| (0.4..=0.6).contains(&u));
            }
        }
        println!(
            "closed degree {p}, Σ of 4 seeds: κ RMS error {:.4} -> {:.4} (held seam {:.4}); next to the seam {:.4} -> {:.4} (held {:.4}); \
             around the antipode {:.4} -> {:.4} (held {:.4})",
            all[0], all[1], all[2], seam[0], seam[1], seam[2], antipode[0], antipode[1], antipode[2]
        );
        assert!(all[1] < 0.9 * all[0], "p = {p}: {all:?}");
        assert!(all[1] < all[2], "p = {p}: {all:?}");
        // next to the seam: better than with the seam held, and no seam artifact — within 1.5× the
        // error over the whole loop (the held seam: 1.5–1.8×)
        assert!(seam[1] < 0.9 * seam[2], "p = {p}: {seam:?}");
        assert!(seam[1] <= 1.5 * all[1], "p = {p}: {seam:?} vs {all:?}");
        // no seam artifact: next to the seam as good as around the antipode, the other curvature
        // maximum, where the smoothed target flattens the peak the same way (measured 0.90×, 1.12×,
        // 0.97× for p = 3, 4, 5; the held seam: 1.80×, 1.70×, 1.27×). Where the faired seam is worse than the
        // input (p = 5: 0.111 vs 0.096), the input's noise happens to be small there (its antipode: 0.145).
        assert!(
            seam[1] <= 1.25 * antipode[1],
            "p = {p}: seam {seam:?} vs antipode {antipode:?}"
        );
    }
}

/// A region across the seam with separate end conditions (the editor's start / end): the start joins
/// with G1 (position and tangent direction, its curvature free), the end with G2, and the result
/// differs from the G2/G2 fair; the result has the original's knots plus those the G1 end inserts
/// (rotating back used to fail on them); outside the region nothing moves.
#[test]
fn region_across_the_seam_takes_separate_end_conditions() {
    use fairway::fair::closed::{setup_across_seam, setup_across_seam_with_ends};
    let c = periodic_ellipse(60, 1e-3, 4);
    let (u1, u2) = (0.8, 0.25);
    let o = (opts(3e-3)).region(Some((u1, u2)));
    let fair = |(mut s, back): (FairingSetup, closed::AcrossSeam)| back.back(s.fair().unwrap()).unwrap().curve;
    let g1g2 = fair(setup_across_seam_with_ends(&c, o, [EndCondition::G1, EndCondition::G2]).unwrap());
    let g2g2 = fair(setup_across_seam(&c, o).unwrap());
    assert_eq!(o.ends, EndCondition::G2);
    // G1 at u1 inserts u1 up to multiplicity p − 1 (the result keeps it, as for an open curve)
    assert_eq!(g1g2.knots().multiplicity(u1), 2);
    assert_eq!(g1g2.n_points(), c.n_points() + 2 - c.knots().multiplicity(u1));
    assert_eq!(g2g2.knots(), c.knots());
    let diff = (0..=100)
        .map(|k| u1 + (1.0 - u1 + u2) * k as f64 / 100.0)
        .map(|u| if u > 1.0 { u - 1.0 } else { u })
        .map(|u| g1g2.point(u).distance(g2g2.point(u)))
        .fold(0.0, f64::max);
    assert!(diff > 1e-9, "the start's end condition was ignored");
    let (a, f) = (c.derivs(u1), g1g2.derivs(u1));
    assert!(
        a.p.distance(f.p) <= 1e-12 && a.d1.angle_between(f.d1) <= 1e-9,
        "G1 at u1"
    );
    let (a, f) = common::join_derivs(&c, &g1g2, u2, true);
    let (ka, kf) = (a.curvature_vector(), f.curvature_vector());
    assert!(
        a.p.distance(f.p) <= 1e-12 && ka.distance(kf) <= 1e-9 * ka.length(),
        "G2 at u2"
    );
    for k in 0..=100 {
        let u = u2 + (u1 - u2) * k as f64 / 100.0;
        assert!(g1g2.point(u).distance(c.point(u)) <= 1e-12, "moved at u = {u}");
    }
}

/// `AcrossSeam::to_original` maps the re-seamed setup's sample parameters onto the original: the same
/// points, and the parameters past the old seam come back into the original's domain.
#[test]
fn across_seam_parameters_map_onto_the_original() {
    let c = periodic_ellipse(30, 1e-3, 2);
    let o = (opts(3e-3)).region(Some((0.8, 0.25)));
    let (setup, across) = fairway::fair::closed::setup_across_seam(&c, o).unwrap();
    let (a, b) = c.domain();
    let mut past_seam = 0;
    for &u in setup.params() {
        let v = across.to_original(u);
        assert!((a..=b).contains(&v), "{u} -> {v}");
        past_seam += usize::from(u > b);
        let d = setup.working_curve().point(u).distance(c.point(v));
        assert!(d < 1e-12, "{u} -> {v}: {d}");
    }
    assert!(past_seam > 0, "the region reaches past the old seam");
}

/// Regression (probe campaign, issue 4): a region across the seam is faired on the curve rotated to
/// start inside the untouched rest, and its band was verified on the arc-length samples of that
/// rotated curve — not the original's, which `measure` projects. Between the two sample sets the
/// result left the band by up to 1e-4 relative (4.6014e-4 measured for m = 4.6010e-4). The check
/// samples are now the original's (shifted by the rotation's arc-length phase): the measured
/// deviation is within the band for every region and tolerance.
#[test]
fn region_across_the_seam_holds_the_band_on_the_originals_samples() {
    let mut worst: f64 = 0.0;
    for (seed, n) in [(1u64, 24usize), (2, 32), (3, 26)] {
        let c = periodic_ellipse(n, 2e-3, seed);
        for (u1, u2) in [(0.61, 0.24), (0.57, 0.2), (0.82, 0.35)] {
            for m in [4.6e-4, 4.6e-3] {
                let o = (opts(m)).region(Some((u1, u2)));
                let r = fair_closed(&c, o).unwrap();
                let d = dev_max(&c, &r.curve);
                assert!(r.max_deviation <= m);
                worst = worst.max(d / m);
            }
        }
    }
    assert!(worst <= 1.0, "measured deviation {worst} × the tolerance");
}

/// A region across the seam whose G0 ends fall 1e-14 from knots: inserted at those knots (as for an
/// open curve), so the result has no 1e-14 span and the rotation back finds the same knot vector.
#[test]
fn region_across_the_seam_with_g0_ends_next_to_knots() {
    let c = periodic_ellipse(24, 2e-3, 1);
    let kv = c.knots().values().to_vec();
    let (k1, k2) = (kv[3 + 17], kv[3 + 7]);
    let m = 3e-3;
    let o = (opts(m)).region(Some((k1 + 1e-14, k2 - 1e-14))).ends(EndCondition::G0);
    let r = fair_closed(&c, o).unwrap();
    assert_eq!(r.seam, Seam::Faired);
    let bp = r.curve.knots().breakpoints();
    assert_eq!(bp.len(), c.knots().breakpoints().len(), "no new breakpoint");
    assert_eq!(
        (r.curve.knots().multiplicity(k1), r.curve.knots().multiplicity(k2)),
        (3, 3)
    );
    assert!(dev_max(&c, &r.curve) <= m);
}

/// A region ending at the seam of a closed curve with a G1 / G0 end there: the seam is that region end,
/// so it keeps position (and tangent for G1) but not its curvature (tangent) — as requested; the seam text
/// said it was held "like a G2 region end" (probe campaign, issue 4: 55 of 400 mixed-end cases at the
/// seam). It now names the end condition and what the seam keeps.
#[test]
fn seam_text_names_the_end_condition_at_the_seam() {
    let c = periodic_ellipse(24, 2e-3, 3);
    let o = (opts(3e-3)).region(Some((0.3, 1.0)));
    for (e, want) in [
        (EndCondition::G2, "holds like a G2 region end"),
        (
            EndCondition::G1,
            "treats as a G1 region end: the seam keeps its position and tangent, not its curvature",
        ),
        (
            EndCondition::G0,
            "treats as a G0 region end: the seam keeps its position, not its tangent and curvature",
        ),
    ] {
        let mut s = FairingSetup::new_with_ends(&c, o, [EndCondition::G2, e]).unwrap();
        let r = s.fair().unwrap();
        match &r.seam {
            Seam::Held(why) => assert!(why.contains(want), "{e:?}: {why}"),
            other => panic!("{e:?}: {other:?}"),
        }
        let n = r.curve.n_points();
        assert!(r.curve.points()[0].distance(r.curve.points()[n - 1]) <= 1e-12, "closed");
    }
}
