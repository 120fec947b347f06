//! Tests of the surface engine.

use super::*;
use crate::knots::KnotVector;
use crate::measure_surface::deviation;
use proptest::{prop_assert, prop_assert_eq};

/// xorshift64* with a Box–Muller normal: a fixed, dependency-free noise source.
pub(crate) struct Rng(u64);
impl Rng {
    pub(crate) fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub(crate) fn normal(&mut self) -> f64 {
        let (a, b) = (self.uniform().max(1e-300), self.uniform());
        (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
    }
}

/// Least-squares bicubic graph of `f` over [0,1]² with an `n × n` net and uniform knots.
pub(crate) fn graph(n: usize, f: impl Fn(f64, f64) -> f64) -> BSplineSurface {
    crate::fit_surface::fit_graph(n, f).unwrap()
}

pub(crate) fn noisy(s: &BSplineSurface, sigma: f64, seed: u64) -> BSplineSurface {
    let mut r = Rng(seed);
    let pts = s
        .points()
        .iter()
        .map(|p| *p + DVec3::new(0.0, 0.0, sigma * r.normal()))
        .collect();
    s.with_points(pts).unwrap()
}

/// RMS over an interior grid of the mean-curvature and Gauss-curvature-root errors against `exact`.
fn curvature_error(s: &BSplineSurface, exact: &BSplineSurface) -> f64 {
    curvature_error_on(s, exact, |k, l| {
        (0.1 + 0.8 * k as f64 / 29.0, 0.1 + 0.8 * l as f64 / 29.0)
    })
}

/// RMS of the principal-curvature errors against `exact` at the 30 × 30 parameters `uv(k, l)`.
fn curvature_error_on(s: &BSplineSurface, exact: &BSplineSurface, uv: impl Fn(usize, usize) -> (f64, f64)) -> f64 {
    let mut sum = 0.0;
    let n = 30;
    for k in 0..n {
        for l in 0..n {
            let (u, v) = uv(k, l);
            let (a, b) = (s.curvature(u, v), exact.curvature(u, v));
            sum += (a.k_max - b.k_max).powi(2) + (a.k_min - b.k_min).powi(2);
        }
    }
    (sum / (n * n) as f64).sqrt()
}

fn fair(s: &BSplineSurface, m: f64, combine: Combine) -> SurfaceFairingResult {
    fair_surface(
        s,
        SurfaceFairingOptions {
            tolerance: m,
            combine,
            ..Default::default()
        },
    )
    .unwrap()
}

/// Interior-region fairing must make the region fairer at every tolerance (it once got worse at
/// large m: the largest band-holding fit smoothing and isocurve corrections of size m, incoherent
/// from one isocurve to the next, were taken; module docs step 6). Noisy wave, fixed seed; the
/// measures over the region drop by at least the quoted factor (measured x0.74..0.78 for Σ∫(dκ/ds)², x0.86..0.87
/// for ∫∫|∇H|²; before the fix x1.14 / x1.08 at m = 2e-3), the whole surface gets no worse.
#[test]
fn interior_region_gets_fairer_at_every_tolerance() {
    use crate::measure_surface::{iso_stats_in, mean_curvature_variation_in};
    let exact = graph(16, |u, v| 0.15 * (4.0 * u).sin() * (4.8 * v).cos() + 0.05 * u * v);
    let s = noisy(&exact, 1e-3, 11);
    let region = ((0.15, 0.85), (0.15, 0.85));
    let whole = s.domain();
    let e = |x: &BSplineSurface, r| {
        let st = iso_stats_in(x, r, 12, 0.0);
        st.e_var_u + st.e_var_v
    };
    let (e_in0, h_in0) = (e(&s, region), mean_curvature_variation_in(&s, region));
    let (e_all0, h_all0) = (e(&s, whole), mean_curvature_variation_in(&s, whole));
    for m in [2e-3, 5e-3, 1e-2, 2e-2] {
        let r = fair_surface(
            &s,
            SurfaceFairingOptions {
                region: Some(region),
                tolerance: m,
                ..Default::default()
            },
        )
        .unwrap();
        let f = &r.surface;
        let (e_in, h_in) = (e(f, region) / e_in0, mean_curvature_variation_in(f, region) / h_in0);
        let (e_all, h_all) = (e(f, whole) / e_all0, mean_curvature_variation_in(f, whole) / h_all0);
        eprintln!(
            "m {m:.0e}: region E x{e_in:.3}, |grad H|^2 x{h_in:.3}; whole E x{e_all:.3}, |grad H|^2 x{h_all:.3} \
             (m_iso {:.1e}, strength {}, dev {:.2e})",
            r.iso_tolerance, r.smoothing.strength_u, r.max_deviation
        );
        assert!(r.max_deviation <= m);
        assert!(
            e_in < 0.85 && h_in < 0.92,
            "m = {m}: region E x{e_in}, |grad H|^2 x{h_in}"
        );
        assert!(
            e_all < 1.0 && h_all < 1.0,
            "m = {m}: whole E x{e_all}, |grad H|^2 x{h_all}"
        );
    }
}

/// The default levels (the pass at m scaled) against the isocurves re-faired per level
/// (`refair_levels`): both hold the band, and the scaled levels are as fair to within 10 %.
#[test]
fn scaled_levels_are_as_fair_as_refaired_levels() {
    use crate::measure_surface::iso_stats_in;
    let exact = graph(16, |u, v| 0.15 * (4.0 * u).sin() * (4.8 * v).cos() + 0.05 * u * v);
    let s = noisy(&exact, 1e-3, 11);
    let e = |x: &BSplineSurface, r| {
        let st = iso_stats_in(x, r, 12, 0.0);
        st.e_var_u + st.e_var_v
    };
    for (region, m) in [(((0.15, 0.85), (0.15, 0.85)), 1e-2), (s.domain(), 3e-3)] {
        let run = |refair_levels| {
            fair_surface(
                &s,
                SurfaceFairingOptions {
                    region: Some(region),
                    tolerance: m,
                    refair_levels,
                    ..Default::default()
                },
            )
            .unwrap()
        };
        let (scaled, refaired) = (run(false), run(true));
        let e0 = e(&s, region);
        let (es, er) = (e(&scaled.surface, region) / e0, e(&refaired.surface, region) / e0);
        eprintln!(
            "region {region:?}, m {m:.0e}: E x{es:.3} scaled (m_iso {:.1e}), x{er:.3} refaired (m_iso {:.1e})",
            scaled.iso_tolerance, refaired.iso_tolerance
        );
        assert!(scaled.max_deviation <= m && refaired.max_deviation <= m);
        assert!(es < 1.0 && es <= 1.1 * er, "scaled x{es} vs refaired x{er}");
    }
}

#[test]
fn noisy_plane_cylinder_bump_curvature_error_drops() {
    let sigma = 1e-3;
    type Case = (&'static str, Box<dyn Fn(f64, f64) -> f64>, f64);
    let cases: [Case; 3] = [
        ("plane", Box::new(|u, v| 0.2 * u - 0.1 * v), 10.0),
        ("cylinder", Box::new(|u, _| (1.0 - (u - 0.5).powi(2)).sqrt()), 2.0),
        // the bump: measured 0.21 -> 0.13 (x1.6) since the fairness-energy choice (was 0.21 -> 0.27, worse,
        // when the largest band-holding smoothing was taken)
        (
            "bump",
            Box::new(|u, v| 0.3 * (-((u - 0.5).powi(2) + (v - 0.5).powi(2)) / 0.05).exp()),
            1.3,
        ),
    ];
    for (name, f, factor) in cases {
        let exact = graph(14, f);
        let s = noisy(&exact, sigma, 7);
        let m = 3.0 * sigma;
        let r = fair(&s, m, Combine::Weighted);
        let (e0, e1) = (curvature_error(&s, &exact), curvature_error(&r.surface, &exact));
        eprintln!(
            "{name}: curvature error {e0:.4} -> {e1:.4} (x{:.1}), dev {:.2e}, rounds {}, alpha {}",
            e0 / e1,
            r.max_deviation,
            r.rounds,
            r.alpha
        );
        assert!(r.max_deviation <= m);
        assert!(e1 * factor < e0, "{name}: {e0} -> {e1}");
        // outside nothing moved (whole-surface region here: the boundary rows are free too, so only check the band)
        let (dev, _) = deviation(&s, &r.surface, 41);
        assert!(dev <= m * (1.0 + 1e-9), "{name}: measured deviation {dev} > {m}");
    }
}

fn border_g2(a: &BSplineSurface, b: &BSplineSurface, along_u: bool, t: f64) {
    // G2 across the border line u = t (along_u) or v = t: position, normal and the second fundamental form
    // of the faired surface (evaluated on the region side) equal the original's (unchanged side).
    for k in 0..=20 {
        let w = 0.02 + 0.96 * k as f64 / 20.0;
        let (u, v) = if along_u { (t, w) } else { (w, t) };
        let (da, db) = (a.derivs(u, v), b.derivs(u, v));
        let (ca, cb) = (da.curvature(), db.curvature());
        assert!((da.p - db.p).length() < 1e-12, "position at {u},{v}");
        assert!((ca.normal - cb.normal).length() < 1e-9, "normal at {u},{v}");
        let ii = |d: &crate::surface::SurfaceDerivs, n: DVec3| [d.suu.dot(n), d.suv.dot(n), d.svv.dot(n)];
        let (ia, ib) = (ii(&da, ca.normal), ii(&db, cb.normal));
        for c in 0..3 {
            assert!(
                (ia[c] - ib[c]).abs() < 1e-7 * (1.0 + ia[c].abs()),
                "II at {u},{v}: {ia:?} {ib:?}"
            );
        }
    }
}

#[test]
fn local_region_keeps_outside_and_joins_g2() {
    for seed in [1u64, 2, 3] {
        let exact = graph(16, |u, v| 0.2 * (3.0 * u).sin() * v);
        let s = noisy(&exact, 1e-3, seed);
        let mut r = Rng(seed * 77);
        let u1 = 0.1 + 0.2 * r.uniform();
        let v1 = 0.05 + 0.2 * r.uniform();
        let region = ((u1, u1 + 0.55), (v1, v1 + 0.6));
        let m = 2e-3 + 3e-3 * r.uniform();
        let out = fair_surface(
            &s,
            SurfaceFairingOptions {
                region: Some(region),
                tolerance: m,
                ..Default::default()
            },
        )
        .unwrap();
        let f = &out.surface;
        // control points outside the free block: bit-for-bit
        for i in 0..16 {
            for j in 0..16 {
                if !(out.free_u.contains(&i) && out.free_v.contains(&j)) {
                    assert_eq!(f.point_at(i, j), s.point_at(i, j));
                }
            }
        }
        // something moved
        assert!(f.points() != s.points());
        // every free point's support is inside the region
        for i in out.free_u.clone() {
            let (a, b) = s.knots_u().support(i);
            assert!(a >= region.0.0 && b <= region.0.1);
        }
        // band, measured independently on a dense grid
        let (dev, _) = deviation(&s, f, 81);
        let (rev, _) = deviation(f, &s, 81);
        assert!(dev.max(rev) <= m * (1.0 + 1e-9), "deviation {dev} / {rev} > {m}");
        // G2 across the four border lines of the moving rectangle
        let ku = s.knots_u().values();
        let kv = s.knots_v().values();
        let (au, bu) = (ku[out.free_u.start], ku[out.free_u.end + 3]);
        let (av, bv) = (kv[out.free_v.start], kv[out.free_v.end + 3]);
        border_g2(&s, f, true, au);
        border_g2(&s, f, false, av);
        // at the far borders evaluate from the region side: just below the knot
        border_g2(&s, f, true, bu - 1e-13);
        border_g2(&s, f, false, bv - 1e-13);
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(8))]
    /// Random region, tolerance, combination and noise: the band holds (measured independently in both
    /// directions), control points outside the free block are bit-identical, and the faired patch joins
    /// the untouched surface G2 across every border line of the moving rectangle inside the domain.
    #[test]
    fn band_outside_and_g2_hold(
        seed in 1u64..1000,
        u1 in 0.0f64..0.3,
        du in 0.5f64..0.7,
        v1 in 0.0f64..0.3,
        dv in 0.5f64..0.7,
        m in 1e-3f64..1e-2,
        c in 0usize..4,
    ) {
        let combine = [Combine::Average, Combine::Border, Combine::Weighted, Combine::Smoothed][c];
        let exact = graph(14, |u, v| 0.2 * (2.0 * u).sin() * (1.0 + v * v));
        let s = noisy(&exact, 1e-3, seed);
        let (u2, v2) = ((u1 + du).min(1.0), (v1 + dv).min(1.0));
        let out = fair_surface(
            &s,
            SurfaceFairingOptions { region: Some(((u1, u2), (v1, v2))), tolerance: m, combine, ..Default::default() },
        )
        .unwrap();
        let f = &out.surface;
        prop_assert!(out.max_deviation <= m);
        let (dev, _) = deviation(&s, f, 41);
        let (rev, _) = deviation(f, &s, 41);
        prop_assert!(dev.max(rev) <= m * (1.0 + 1e-9), "deviation {} / {} > {}", dev, rev, m);
        for i in 0..14 {
            for j in 0..14 {
                if !(out.free_u.contains(&i) && out.free_v.contains(&j)) {
                    prop_assert_eq!(f.point_at(i, j), s.point_at(i, j));
                }
            }
        }
        let (ku, kv) = (s.knots_u().values(), s.knots_v().values());
        let (au, bu) = (ku[out.free_u.start], ku[out.free_u.end + 3]);
        let (av, bv) = (kv[out.free_v.start], kv[out.free_v.end + 3]);
        // border lines strictly inside the domain (a side on the domain boundary has no neighbour)
        if au > 0.0 { border_g2(&s, f, true, au); }
        if av > 0.0 { border_g2(&s, f, false, av); }
        if bu < 1.0 { border_g2(&s, f, true, bu - 1e-13); }
        if bv < 1.0 { border_g2(&s, f, false, bv - 1e-13); }
    }
}

#[test]
fn extruded_curve_matches_the_curve_engine() {
    // a noisy 3D curve in the xz plane, extruded along y with a cubic (collinear) v direction
    let n = 20;
    let k = KnotVector::uniform(3, n).unwrap();
    let mut r = Rng(11);
    let cpts: Vec<DVec3> = k
        .greville()
        .iter()
        .map(|&u| DVec3::new(u, 0.0, 0.2 * (2.0 * u).sin() + 1e-3 * r.normal()))
        .collect();
    let curve = crate::curve::BSplineCurve::new_3d(3, k.values().to_vec(), cpts.clone()).unwrap();
    let kv = KnotVector::uniform(3, 4).unwrap();
    let mut pts = Vec::new();
    for p in &cpts {
        for j in 0..4 {
            pts.push(*p + DVec3::new(0.0, j as f64 / 3.0, 0.0));
        }
    }
    let s = BSplineSurface::try_new(3, 3, k.values().to_vec(), kv.values().to_vec(), n, 4, pts, None).unwrap();
    let m = 3e-3;
    let out = fair_surface(
        &s,
        SurfaceFairingOptions {
            tolerance: m,
            combine: Combine::Weighted,
            auto_smoothing: false,
            // the isocurve fairing (steps 1-7) is what reproduces the curve engine; step 8 may return a
            // fairer candidate
            method: SurfaceMethod::Isocurves,
            ..Default::default()
        },
    )
    .unwrap();
    // the same curve-engine setup the surface engine uses for its u-isocurves (17 spans)
    let fr = isocurve_setup(
        &curve,
        &SurfaceFairingOptions::default(),
        out.iso_tolerance,
        (0.0, 1.0),
        n - 3,
    )
    .unwrap()
    .fair()
    .unwrap();
    let fc = fr.curve;
    // the v-isocurves are straight: the curve engine leaves them (|Δ_v| ~ rounding), so Weighted takes Δ_u,
    // the faired extrusion lies in the spline space and the fit reproduces it up to rounding of the solves
    let mut worst = 0.0f64;
    for i in 0..=50 {
        let u = i as f64 / 50.0;
        for j in 0..=4 {
            let v = j as f64 / 4.0;
            let want = fc.point(u) + DVec3::new(0.0, v, 0.0);
            worst = worst.max((out.surface.point(u, v) - want).length());
        }
    }
    assert!(worst < 1e-9, "extrusion differs by {worst}");
    // the paper's 0.5/0.5 average does about half of that correction (Δ_v ≈ 0 is averaged in)
    let avg = fair_surface(
        &s,
        SurfaceFairingOptions {
            tolerance: m,
            combine: Combine::Average,
            auto_smoothing: false,
            method: SurfaceMethod::Isocurves,
            ..Default::default()
        },
    )
    .unwrap();
    let change = |f: &BSplineSurface| {
        (0..=50)
            .map(|i| (f.point(i as f64 / 50.0, 0.5) - s.point(i as f64 / 50.0, 0.5)).length())
            .fold(0.0f64, f64::max)
    };
    let ratio = change(&avg.surface) / change(&out.surface);
    assert!((0.35..0.65).contains(&ratio), "average / weighted change = {ratio}");
}

#[test]
fn rectangular_nonuniform_other_degrees_and_rational() {
    // 26 × 10 net, degrees 4 × 2, non-uniform knots in u
    let (nu, nv) = (26, 10);
    let mut ku = vec![0.0; 5];
    for i in 1..nu - 4 {
        let t = i as f64 / (nu - 4) as f64;
        ku.push(t * t * (3.0 - 2.0 * t));
    }
    ku.extend([1.0; 5]);
    let kv = KnotVector::uniform(2, nv).unwrap();
    let mut r = Rng(5);
    let gu = KnotVector::try_new(ku.clone(), 4, nu, "u").unwrap().greville();
    let gv = kv.greville();
    let mut pts = Vec::new();
    for &u in &gu {
        for &v in &gv {
            pts.push(DVec3::new(2.0 * u, v, 0.3 * u * v + 1e-3 * r.normal()));
        }
    }
    let s = BSplineSurface::try_new(4, 2, ku, kv.values().to_vec(), nu, nv, pts, None).unwrap();
    let m = 2e-3;
    let out = fair_surface(
        &s,
        SurfaceFairingOptions {
            region: Some(((0.2, 0.8), (0.1, 0.9))),
            tolerance: m,
            ..Default::default()
        },
    )
    .unwrap();
    let (dev, _) = deviation(&s, &out.surface, 61);
    assert!(dev <= m * (1.0 + 1e-9));
    assert!(!out.free_u.is_empty() && !out.free_v.is_empty());
    // rational with unequal weights: faired through a non-rational stand-in, the band held against the
    // rational original (by projection, the independent measure) and the bound including the stand-in's error
    let mut w = vec![1.0; nu * nv];
    w[7] = 2.0;
    let rs = BSplineSurface::try_new(
        4,
        2,
        s.knots_u().values().to_vec(),
        s.knots_v().values().to_vec(),
        nu,
        nv,
        s.points().to_vec(),
        Some(w),
    )
    .unwrap();
    let nurbs = fair_surface(
        &rs,
        SurfaceFairingOptions {
            tolerance: m,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(!nurbs.surface.is_rational());
    let (dev, _) = deviation(&rs, &nurbs.surface, 61);
    assert!(dev <= m * (1.0 + 1e-9), "deviation {dev} > m {m}");
    assert!(
        nurbs
            .band_bound
            .is_some_and(|b| b <= m * (1.0 + 1e-9) && b >= dev * (1.0 - 1e-6)),
        "{:?}",
        nurbs.band_bound
    );
    assert!(
        nurbs.notes[0].starts_with("rational surface (unequal weights): faired through"),
        "{:?}",
        nurbs.notes
    );
    // equal weights: converted, and faired exactly like the non-rational surface
    let rs = BSplineSurface::try_new(
        4,
        2,
        s.knots_u().values().to_vec(),
        s.knots_v().values().to_vec(),
        nu,
        nv,
        s.points().to_vec(),
        Some(vec![2.5; nu * nv]),
    )
    .unwrap();
    assert!(rs.is_rational());
    let opts = SurfaceFairingOptions {
        region: Some(((0.2, 0.8), (0.1, 0.9))),
        tolerance: m,
        ..Default::default()
    };
    let fr = fair_surface(&rs, opts).unwrap();
    assert!(!fr.surface.is_rational());
    assert_eq!(fr.surface.points(), out.surface.points());
    // and its band is certified like the non-rational surface's (bounded in its polynomial form)
    let b = fr
        .band_bound
        .expect("a sound bound for the equal-weight rational input");
    assert!(b <= m * (1.0 + 1e-9), "{b} > {m}");
    assert_eq!(fr.band_bound, out.band_bound);
    // bad requests
    assert!(
        fair_surface(
            &s,
            SurfaceFairingOptions {
                tolerance: -1.0,
                ..Default::default()
            }
        )
        .is_err()
    );
    let tiny = SurfaceFairingOptions {
        region: Some(((0.5, 0.52), (0.1, 0.9))),
        ..Default::default()
    };
    assert!(matches!(fair_surface(&s, tiny), Err(Error::InvalidInput(_))));
}

#[test]
fn the_result_does_not_depend_on_the_thread_count() {
    let exact = graph(12, |u, v| 0.2 * (3.0 * u).sin() * (2.0 * v).cos());
    let s = noisy(&exact, 1e-3, 11);
    let run = |threads| {
        fair_surface(
            &s,
            SurfaceFairingOptions {
                tolerance: 3e-3,
                region: Some(((0.1, 0.95), (0.0, 0.8))),
                threads: Some(threads),
                ..Default::default()
            },
        )
        .unwrap()
    };
    let one = run(1);
    assert!(one.surface.points() != s.points(), "the fairing moved nothing");
    for t in [2, 3, 7] {
        assert_eq!(run(t).surface.points(), one.surface.points(), "{t} threads");
    }
}

/// An `n × n` bicubic net with uniform knots over `pts` (row-major in u).
fn uniform_net(n: usize, pts: Vec<DVec3>) -> BSplineSurface {
    let k = KnotVector::uniform(3, n).unwrap();
    BSplineSurface::try_new(3, 3, k.values().to_vec(), k.values().to_vec(), n, n, pts, None).unwrap()
}

/// The points of an `n × n` net with u and v swapped.
fn transposed(pts: &[DVec3], n: usize) -> Vec<DVec3> {
    (0..n).flat_map(|j| (0..n).map(move |i| pts[i * n + j])).collect()
}

/// Fair the whole of `s` at `m` (default options); the reported and the measured deviation hold the band.
fn fair_whole_checked(s: &BSplineSurface, m: f64, name: &str) -> SurfaceFairingResult {
    let r = fair_surface(
        s,
        SurfaceFairingOptions {
            tolerance: m,
            ..Default::default()
        },
    )
    .unwrap_or_else(|e| panic!("{name}: {e}"));
    let (dev, _) = deviation(s, &r.surface, 41);
    assert!(
        r.max_deviation <= m && dev <= m * (1.0 + 1e-9),
        "{name}: {} / {dev} > {m}",
        r.max_deviation
    );
    r
}

/// A surface of revolution (a paraboloid over 0.8 of a turn) with its pole at u = 0: every control point
/// of row 0 is the apex. The pole row stays (bit for bit: the pole stays one point); the two after it stay
/// too, or — where step 0 made the pole smooth — the first ring lies in one plane through the apex (the
/// pole has a tangent plane); the isocurve through the pole is left as it is instead of failing, the band
/// holds, and the rest is faired. (Before: "fairing the v-isocurve at u = 0: degenerate geometry: the
/// region [0, 1] has zero length".) The same with the pole at u = 1, and at v = 0 (transposed net).
#[test]
fn a_pole_stays_one_point_and_the_rest_is_faired() {
    let n = 16;
    let k = KnotVector::uniform(3, n).unwrap();
    let g = k.greville();
    let mut rng = Rng(29);
    let mut exact_pts = Vec::new();
    let mut noisy_pts = Vec::new();
    for &r in &g {
        for &t in &g {
            let a = 0.8 * std::f64::consts::TAU * t;
            let p = DVec3::new(r * a.cos(), r * a.sin(), 0.5 * r * r);
            exact_pts.push(p);
            let z = if r > 0.0 { 1.5e-3 * rng.normal() } else { 0.0 };
            noisy_pts.push(p + DVec3::new(0.0, 0.0, z));
        }
    }
    let (exact, s) = (uniform_net(n, exact_pts), uniform_net(n, noisy_pts));
    // the pole at u = 0, at u = 1 (rows reversed) and at v = 0 (transposed)
    let flip_u = |pts: &[DVec3]| {
        (0..n)
            .rev()
            .flat_map(|i| pts[i * n..(i + 1) * n].to_vec())
            .collect::<Vec<_>>()
    };
    let net = |pts: Vec<DVec3>| uniform_net(n, pts);
    let cases = [
        ("pole at u = 0", exact.clone(), s.clone()),
        ("pole at u = 1", net(flip_u(exact.points())), net(flip_u(s.points()))),
        (
            "pole at v = 0",
            net(transposed(exact.points(), n)),
            net(transposed(s.points(), n)),
        ),
    ];
    let m = 4.5e-3;
    for (name, exact, s) in cases {
        let r = fair_whole_checked(&s, m, name);
        // the held rows (or columns) next to the pole: bit for bit (only the pole row where step 0 made
        // the pole smooth, and then the first ring is flat)
        let rows = if r.smoothed_poles == 0 { POLE_ROWS } else { 1 };
        let held = |i: usize, j: usize| match name {
            "pole at u = 0" => i < rows,
            "pole at u = 1" => i >= n - rows,
            _ => j < rows,
        };
        let (a, b) = (s.points(), r.surface.points());
        for i in 0..n {
            for j in 0..n {
                if held(i, j) {
                    assert_eq!(a[i * n + j], b[i * n + j], "{name}: control point ({i}, {j}) moved");
                }
            }
        }
        if r.smoothed_poles > 0 {
            let ring: Vec<DVec3> = (0..n)
                .map(|k| match name {
                    "pole at u = 0" => b[n + k],
                    "pole at u = 1" => b[(n - 2) * n + k],
                    _ => b[k * n + 1],
                })
                .collect();
            let apex = a[0];
            assert!(
                ring_out_of_plane(apex, &ring) < 1e-12,
                "{name}: the first ring is not flat"
            );
        }
        assert!(a != b, "{name}: nothing was faired");
        // a region of 3 spans at the pole: its 3 movable rows are the held ones
        if name == "pole at u = 0" {
            let small = SurfaceFairingOptions {
                tolerance: m,
                region: Some(((0.0, 3.0 / 13.0), (0.0, 1.0))),
                ..Default::default()
            };
            assert_eq!(
                fair_surface(&s, small).unwrap_err().to_string(),
                format!(
                    "region [0, {}] × [0, 1] holds no movable control point: its control rows are \
                     all among the 3 held next to a pole or the seam of a closed surface (widen the region away \
                     from it)",
                    3.0 / 13.0
                )
            );
        }
        // RMS principal-curvature error against the noise-free net, 30 × 30 samples with the distance from
        // the pole (as a parameter of the pole's direction) in [d0, 0.9]: the held rows keep their noise
        // up to t_6 ≈ 0.23 (like the held strip along a region border), the rest is free
        let err = |x: &BSplineSurface, d0: f64| {
            curvature_error_on(x, &exact, |k, l| {
                let (d, w) = (d0 + (0.9 - d0) * k as f64 / 29.0, 0.1 + 0.8 * l as f64 / 29.0);
                match name {
                    "pole at u = 0" => (d, w),
                    "pole at u = 1" => (1.0 - d, w),
                    _ => (w, d),
                }
            })
        };
        let (e0, e1) = (err(&s, 0.1), err(&r.surface, 0.1));
        let (f0, f1) = (err(&s, 0.3), err(&r.surface, 0.3));
        eprintln!("{name}: curvature error {e0:.4} -> {e1:.4}, away from the pole {f0:.4} -> {f1:.4}");
        assert!(e1 < e0, "{name}: curvature error {e0} -> {e1}");
        assert!(f1 < 0.6 * f0, "{name}: curvature error away from the pole {f0} -> {f1}");
    }
}

/// The largest distance of `ring` from its least-squares plane through `apex`, over the ring's size.
fn ring_out_of_plane(apex: DVec3, ring: &[DVec3]) -> f64 {
    let mut cov = [[0.0; 3]; 3];
    for p in ring {
        let d = (*p - apex).to_array();
        for i in 0..3 {
            for j in 0..3 {
                cov[i][j] += d[i] * d[j];
            }
        }
    }
    let (values, vectors) = crate::linalg::symmetric_eigen3(cov);
    let k = (0..3).min_by(|&i, &j| values[i].total_cmp(&values[j])).unwrap();
    let normal = DVec3::new(vectors[0][k], vectors[1][k], vectors[2][k]);
    let size = ring.iter().map(|p| p.distance(apex)).fold(0.0, f64::max);
    ring.iter().map(|p| (*p - apex).dot(normal).abs()).fold(0.0, f64::max) / size
}

/// The largest angle (radians) between the surface normals at `u = 1e-7` (next to a pole at u = 0) around
/// the pole: zero where the surface has a tangent plane at the pole, the cone's spread where it has none.
fn normal_spread_at_pole(s: &BSplineSurface) -> f64 {
    let normals: Vec<DVec3> = (0..24).map(|k| s.normal(1e-7, 0.02 + 0.96 * k as f64 / 23.0)).collect();
    let mut spread = 0.0f64;
    for a in &normals {
        for b in &normals {
            spread = spread.max(a.angle_between(*b));
        }
    }
    spread
}

/// A paraboloid of revolution (0.8 of a turn, pole at u = 0) and a cone (its first ring rising 27° out
/// of the pole's plane), both with noise on every control point but the apex, faired at 10 × the
/// noise. Step 0 makes the
/// paraboloid's pole smooth: the normals around it agree (a tangent plane; the noisy original's spread
/// by more than a degree), `∫∫|∇H|²` falls by orders of magnitude below the fair that holds the pole,
/// the band holds (independent projection) and the notes say so. The cone's tip stays: its rows next to
/// the apex bit for bit, a note names the tip.
#[test]
fn a_noisy_pole_is_made_smooth_and_a_tip_is_kept() {
    let n = 16;
    let g = KnotVector::uniform(3, n).unwrap().greville();
    let net = |height: &dyn Fn(f64) -> f64, seed: u64| {
        let mut rng = Rng(seed);
        let mut pts = Vec::new();
        for &r in &g {
            for &t in &g {
                let a = 0.8 * std::f64::consts::TAU * t;
                let z = if r > 0.0 { 1.5e-3 * rng.normal() } else { 0.0 };
                pts.push(DVec3::new(r * a.cos(), r * a.sin(), height(r) + z));
            }
        }
        uniform_net(n, pts)
    };
    // at 10 × the noise the whole pole step fits in its share of the band (at 3 × it goes half-way)
    let m = 1.5e-2;
    let dome = net(&|r| 0.5 * r * r, 31);
    let r = fair_whole_checked(&dome, m, "dome");
    assert_eq!(r.smoothed_poles, 1, "{:?}", r.notes);
    assert!(
        r.notes[0].starts_with("pole at u = start: made smooth"),
        "{:?}",
        r.notes
    );
    let (before, after) = (normal_spread_at_pole(&dome), normal_spread_at_pole(&r.surface));
    assert!(before > 1f64.to_radians(), "the noisy pole: normals spread {before}");
    assert!(after < 1e-4, "the smoothed pole: normals spread {after}; {:?}", r.notes);
    let held = fair_surface(
        &dome,
        SurfaceFairingOptions::default()
            .tolerance(m)
            .method(SurfaceMethod::Isocurves),
    )
    .unwrap();
    let energy = crate::measure_surface::mean_curvature_variation;
    let (e_held, e_smooth) = (energy(&held.surface), energy(&r.surface));
    assert!(
        e_smooth < 1e-3 * e_held,
        "∫∫|∇H|²: {e_smooth} with the pole smoothed, {e_held} held"
    );
    assert!(r.band_bound.is_some_and(|b| b <= m));

    let cone = net(&|r| 0.5 * r, 37);
    let r = fair_whole_checked(&cone, m, "cone");
    assert_eq!(r.smoothed_poles, 0);
    assert!(r.notes.iter().any(|n| n.contains("a tip")), "{:?}", r.notes);
    assert_eq!(&r.surface.points()[..POLE_ROWS * n], &cone.points()[..POLE_ROWS * n]);
}

#[test]
fn a_surface_that_is_one_point_is_refused() {
    let k = KnotVector::uniform(3, 8).unwrap();
    let s = BSplineSurface::try_new(
        3,
        3,
        k.values().to_vec(),
        k.values().to_vec(),
        8,
        8,
        vec![DVec3::ONE; 64],
        None,
    )
    .unwrap();
    let e = fair_surface(&s, SurfaceFairingOptions::default()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "degenerate geometry: all control points of the surface coincide (a single point): there is no shape to fair"
    );
}

/// The ridge's tangent break on the u-isocurve of `s` at v (degrees; 0 if none at u = 0.5).
fn ridge_angle(s: &BSplineSurface, v: f64) -> f64 {
    crate::corners::corners(&s.iso_u(v), 0.0, 1.0)
        .iter()
        .find(|k| k.u == 0.5)
        .map_or(0.0, |k| k.angle_deg)
}

/// A crease (a character line: the u-knot 0.5 triple, the tangent plane breaking by ≈ 53° across it) is
/// kept by the fit on the original knots: the faired surface still breaks there, by the same angle to
/// within 1° all along the line (measured ≤ 0.71° over seeds 3–6, 11 samples along the line), and both
/// sides are faired. Rows next to the crease carry no noise here (a modelled crease); with noise on them
/// too, the angle changes by up to 4.1° (that noise wiggles the crease angle along the line by 4.5–5.9°;
/// the fair evens it out to 0.4–1.3°).
///
/// Measured and not kept: fairing the two sides as separate regions, the crease row held and
/// the isocurves ending G1 there (as the curve engine does at a kink), changed the angle by up to 2.8°
/// on these clean-neighbour roofs, evened it out less (spread 1.5–3.6°) and left ∫∫|∇H|² within 0.1 of the
/// crease 1.8–7× higher; also holding the rows next to the crease kept the angle exactly but left the sides
/// 3–7× less fair (their noise stays).
#[test]
fn a_crease_is_kept_by_the_fit_on_the_original_knots() {
    let m = 3e-3;
    for seed in [3, 6] {
        let ku = vec![
            0.0, 0.0, 0.0, 0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.5, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.0, 1.0, 1.0,
        ];
        let kv = KnotVector::uniform(3, 12).unwrap();
        let gu = KnotVector::try_new(ku.clone(), 3, ku.len() - 4, "u")
            .unwrap()
            .greville();
        let gv = kv.greville();
        let k = gu.iter().position(|&x| x == 0.5).unwrap();
        let mut rng = Rng(seed);
        let mut pts = vec![];
        for (i, &x) in gu.iter().enumerate() {
            for &y in &gv {
                // a ridge along u = 0.5 on a gently curved roof; noise off the crease and its neighbours
                let z = 0.25 * (1.0 - (2.0 * x - 1.0).abs()) + 0.1 * (std::f64::consts::PI * y).sin();
                let noise = if i + 1 >= k && i <= k + 1 {
                    0.0
                } else {
                    1e-3 * rng.normal()
                };
                pts.push(DVec3::new(x, y, z + noise));
            }
        }
        let s = BSplineSurface::try_new(3, 3, ku, kv.values().to_vec(), gu.len(), gv.len(), pts, None).unwrap();
        let r = fair_surface(
            &s,
            SurfaceFairingOptions {
                tolerance: m,
                ..Default::default()
            },
        )
        .unwrap();
        let (dev, _) = deviation(&s, &r.surface, 60);
        assert!(dev <= m * (1.0 + 1e-6), "seed {seed}: {dev}");
        for i in 0..=10 {
            let v = i as f64 / 10.0;
            let (a0, a1) = (ridge_angle(&s, v), ridge_angle(&r.surface, v));
            assert!(
                a0 > 45.0 && (a1 - a0).abs() < 1.0,
                "seed {seed}, v = {v}: crease angle {a0}° -> {a1}°"
            );
        }
        for side in [(0.0, 0.5), (0.5, 1.0)] {
            let rect = (side, (0.0, 1.0));
            let e = |x: &BSplineSurface| crate::measure_surface::mean_curvature_variation_in(x, rect);
            let (before, after) = (e(&s), e(&r.surface));
            assert!(
                after < 0.5 * before,
                "seed {seed}, u in {side:?}: ∫∫|∇H|² {before} -> {after}"
            );
        }
    }
}

/// A pinch inside the domain (a collapsed control row at a triple knot: the isocurve there is a point, but
/// its neighbours are free) is refused as before, not faired: only boundary poles are held.
#[test]
fn a_pinch_inside_the_domain_is_refused() {
    let ku = vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0];
    let kv = KnotVector::uniform(3, 10).unwrap();
    let mut rng = Rng(5);
    let mut pts = Vec::new();
    for i in 0..7 {
        let r = (i as f64 - 3.0).abs() / 3.0;
        for j in 0..10 {
            let a = 1.5 * j as f64 / 9.0;
            let z = if i == 3 { 0.0 } else { 1e-3 * rng.normal() };
            pts.push(DVec3::new(r * a.cos(), r * a.sin(), (i as f64 - 3.0) / 3.0 + z));
        }
    }
    let s = BSplineSurface::try_new(3, 3, ku, kv.values().to_vec(), 7, 10, pts, None).unwrap();
    let e = fair_surface(&s, SurfaceFairingOptions::default())
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "fairing the v-isocurve at u = 0.5: degenerate geometry: the region [0, 1] has zero length (coincident \
         control points)"
    );
}

/// A closed surface (a full turn of a paraboloid of revolution, r ∈ [0.3, 1]: the first and last control
/// columns coincide) stays closed: the three columns at each side of the seam stay bit for bit, the band
/// holds, and away from the seam the curvature error against the noise-free surface drops. (Faired
/// independently, the two sides open the seam by 2.4e-3 at m = 3e-3.) Also with the seam in u
/// (transposed net).
#[test]
fn a_closed_surface_stays_closed_at_its_seam() {
    let n = 16;
    let k = KnotVector::uniform(3, n).unwrap();
    let g = k.greville();
    let mut rng = Rng(31);
    let (mut exact_pts, mut noisy_pts) = (Vec::new(), Vec::new());
    for &t in &g {
        let r = 0.3 + 0.7 * t;
        let mut first = DVec3::ZERO;
        for (j, &w) in g.iter().enumerate() {
            let a = std::f64::consts::TAU * w;
            let p = DVec3::new(r * a.cos(), r * a.sin(), 0.5 * r * r);
            exact_pts.push(p);
            // the same noise on both sides of the seam: the input is closed
            let q = if j + 1 < n {
                p + DVec3::new(0.0, 0.0, 1.5e-3 * rng.normal())
            } else {
                first
            };
            if j == 0 {
                first = q;
            }
            noisy_pts.push(q);
        }
    }
    let (exact, s) = (uniform_net(n, exact_pts), uniform_net(n, noisy_pts));
    let net = |pts: Vec<DVec3>| uniform_net(n, pts);
    let cases = [
        ("seam in v", exact.clone(), s.clone()),
        (
            "seam in u",
            net(transposed(exact.points(), n)),
            net(transposed(s.points(), n)),
        ),
    ];
    let m = 4.5e-3;
    for (name, exact, s) in cases {
        let r = fair_whole_checked(&s, m, name);
        let (a, b) = (s.points(), r.surface.points());
        // (i, j) of the net with the seam direction second
        let at = |i: usize, j: usize| if name == "seam in v" { i * n + j } else { j * n + i };
        for i in 0..n {
            assert_eq!(b[at(i, 0)], b[at(i, n - 1)], "{name}: the seam opened at row {i}");
            for j in (0..POLE_ROWS).chain(n - POLE_ROWS..n) {
                assert_eq!(
                    a[at(i, j)],
                    b[at(i, j)],
                    "{name}: control point ({i}, {j}) next to the seam moved"
                );
            }
        }
        assert!(a != b, "{name}: nothing was faired");
        // curvature error on the half turn opposite the seam (the seam direction's parameter in [0.25, 0.75])
        let err = |x: &BSplineSurface| {
            curvature_error_on(x, &exact, |k, l| {
                let (d, w) = (0.1 + 0.8 * k as f64 / 29.0, 0.25 + 0.5 * l as f64 / 29.0);
                if name == "seam in v" { (d, w) } else { (w, d) }
            })
        };
        let (e0, e1) = (err(&s), err(&r.surface));
        eprintln!("{name}: curvature error away from the seam {e0:.4} -> {e1:.4}");
        assert!(e1 < 0.6 * e0, "{name}: curvature error {e0} -> {e1}");
    }
}

/// The fine check's skipping of cells whose control points moved by less than the peak threshold
/// (`CheckGrid::change_peaks` with `every_node` false) gives the peaks of the whole grid bit for bit, the
/// grid's maximum where it is above the threshold, and the same early stop: on nets with a double interior
/// knot (empty spans), free blocks that do and do not reach the border, and moves from all-below to
/// many-above the threshold.
#[test]
fn skipping_quiet_cells_keeps_the_fine_checks_peaks() {
    let mut knots = vec![0.0; 4];
    knots.extend([0.1, 0.25, 0.4, 0.4, 0.55, 0.7, 0.85]);
    knots.extend([1.0; 4]);
    let n = knots.len() - 4;
    let mut r = Rng(0x1234_5678_9abc_def1);
    let pts: Vec<DVec3> = (0..n * n)
        .map(|k| DVec3::new((k / n) as f64, (k % n) as f64, r.uniform()) * 0.1)
        .collect();
    let a = BSplineSurface::try_new(3, 3, knots.clone(), knots, n, n, pts, None).unwrap();
    let (us, vs) = (
        span_grid(a.knots_u(), 0.0, 1.0, 24),
        span_grid(a.knots_v(), 0.0, 1.0, 24),
    );
    let grid = check::CheckGrid::new(&a, &us, &vs, Some(1));
    let thresh = 1e-3;
    let mut seen = [0usize; 3];
    for (fu, fv) in [(0..n, 0..n), (2..n - 3, 3..n - 1)] {
        for big in [0usize, 1, 3, 12, 60] {
            for seed in 0..4u64 {
                let mut r = Rng(seed * 7919 + big as u64 + 1);
                let mut pts = a.points().to_vec();
                for i in fu.clone() {
                    for j in fv.clone() {
                        // most points move by less than the threshold; `big` random ones by up to 2.5×
                        let d = DVec3::new(r.normal(), r.normal(), r.normal()).normalize() * thresh * 0.9 * r.uniform();
                        pts[i * n + j] += d;
                    }
                }
                for _ in 0..big {
                    let (i, j) = (
                        fu.start + (r.uniform() * fu.len() as f64) as usize % fu.len(),
                        fv.start + (r.uniform() * fv.len() as f64) as usize % fv.len(),
                    );
                    pts[i * n + j] += DVec3::new(0.0, 0.0, thresh * (0.5 + 2.0 * r.uniform()));
                }
                // a coherent bump just above the threshold over a 4 × 4 block: nodes above it in cells
                // whose largest move is only a little larger
                if seed % 2 == 1 {
                    let (i0, j0) = (fu.start + seed as usize % 3, fv.end - 4 - big % 3);
                    for i in i0..i0 + 4 {
                        for j in j0..j0 + 4 {
                            pts[i * n + j] = a.points()[i * n + j] + DVec3::Z * (1.02 * thresh);
                        }
                    }
                }
                let b = a.with_points(pts).unwrap();
                for stop in [f64::INFINITY, 1.6 * thresh] {
                    let (max_all, peaks_all) = grid.change_peaks(&a, &b, &fu, &fv, thresh, stop, true);
                    let (max_q, peaks_q) = grid.change_peaks(&a, &b, &fu, &fv, thresh, stop, false);
                    assert_eq!(peaks_q, peaks_all, "big {big} seed {seed} stop {stop}");
                    if max_all > thresh {
                        assert_eq!(max_q.to_bits(), max_all.to_bits(), "big {big} seed {seed} stop {stop}");
                        seen[if max_all > stop { 2 } else { 1 }] += 1;
                    } else {
                        assert!(max_q <= thresh, "{max_q}");
                        seen[0] += 1;
                    }
                }
            }
        }
    }
    // every kind of case was met: all below, peaks above the threshold, a stop
    assert!(seen.iter().all(|&k| k > 0), "{seen:?}");
}
