//! Exact B-spline shapes shared by the integration tests.
#![allow(dead_code)]

use std::f64::consts::FRAC_1_SQRT_2;

use fairway::{BSplineCurve, BSplineSurface, DVec3};

/// Full circle of radius `r` (counter-clockwise, 2D) as the classic
/// 9-point rational quadratic (The NURBS Book §7.5): four quarter arcs,
/// parameter u ∈ [k/4, (k+1)/4] on quarter k.
pub fn circle(r: f64) -> BSplineCurve {
    let w = FRAC_1_SQRT_2;
    let pts = [
        (1., 0.),
        (1., 1.),
        (0., 1.),
        (-1., 1.),
        (-1., 0.),
        (-1., -1.),
        (0., -1.),
        (1., -1.),
        (1., 0.),
    ]
    .map(|(x, y)| DVec3::new(r * x, r * y, 0.0));
    let knots = vec![0., 0., 0., 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1., 1., 1.];
    BSplineCurve::try_new(2, knots, pts.to_vec(), Some(vec![1., w, 1., w, 1., w, 1., w, 1.]), 2).unwrap()
}

/// A circular arc of radius `r` from angle 0 to `angle` (< π) as one
/// rational quadratic span: middle point at the tangents' intersection,
/// weight cos(angle/2).
pub fn arc(r: f64, angle: f64) -> BSplineCurve {
    let h = 0.5 * angle;
    let p0 = DVec3::new(r, 0.0, 0.0);
    let p1 = DVec3::new(h.cos(), h.sin(), 0.0) * (r / h.cos());
    let p2 = DVec3::new(angle.cos(), angle.sin(), 0.0) * r;
    BSplineCurve::try_new(
        2,
        vec![0., 0., 0., 1., 1., 1.],
        vec![p0, p1, p2],
        Some(vec![1., h.cos(), 1.]),
        2,
    )
    .unwrap()
}

/// The parabola y = x², x ∈ [−1, 1], as a quadratic Bézier: x = 2t − 1.
pub fn parabola() -> BSplineCurve {
    BSplineCurve::bezier(
        vec![DVec3::new(-1., 1., 0.), DVec3::new(0., -1., 0.), DVec3::new(1., 1., 0.)],
        2,
    )
    .unwrap()
}

/// Arc length of y = x² from x = −1 to x: F(x) − F(−1), F(x) = x/2·√(1+4x²) + asinh(2x)/4.
pub fn parabola_length_to(x: f64) -> f64 {
    let f = |x: f64| 0.5 * x * (1.0 + 4.0 * x * x).sqrt() + 0.25 * (2.0 * x).asinh();
    f(x) - f(-1.0)
}

/// The twisted cubic (t, t², t³), t ∈ [0, 1], as a cubic Bézier.
pub fn twisted_cubic() -> BSplineCurve {
    BSplineCurve::bezier(
        vec![
            DVec3::new(0., 0., 0.),
            DVec3::new(1. / 3., 0., 0.),
            DVec3::new(2. / 3., 1. / 3., 0.),
            DVec3::new(1., 1., 1.),
        ],
        3,
    )
    .unwrap()
}

/// A 2D cubic with non-uniform knots and a double knot.
pub fn wiggly_2d() -> BSplineCurve {
    let pts = [
        (0., 0.),
        (1., 2.),
        (2.5, 1.5),
        (3., -1.),
        (4.5, 0.),
        (5., 2.),
        (6.5, 1.),
        (8., 0.),
    ];
    let pts: Vec<_> = pts.iter().map(|&(x, y)| fairway::DVec2::new(x, y)).collect();
    BSplineCurve::new_2d(3, vec![0., 0., 0., 0., 0.15, 0.4, 0.4, 0.7, 1., 1., 1., 1.], &pts).unwrap()
}

/// A 3D quartic.
pub fn quartic_3d() -> BSplineCurve {
    let pts = vec![
        DVec3::new(0., 0., 0.),
        DVec3::new(1., 2., 0.5),
        DVec3::new(2., 1., 2.),
        DVec3::new(3., -1., 1.),
        DVec3::new(4., 0., -1.),
        DVec3::new(5., 2., 0.),
        DVec3::new(6., 1., 1.5),
    ];
    BSplineCurve::new_3d(4, vec![0., 0., 0., 0., 0., 0.3, 0.6, 1.2, 1.2, 1.2, 1.2, 1.2], pts).unwrap()
}

/// A rational 3D cubic with uneven weights.
pub fn rational_3d() -> BSplineCurve {
    let c = quartic_3d();
    let pts = c.points()[..6].to_vec();
    BSplineCurve::try_new(
        3,
        vec![0., 0., 0., 0., 0.25, 0.6, 1., 1., 1., 1.],
        pts,
        Some(vec![1.0, 0.5, 2.0, 1.3, 0.7, 1.1]),
        3,
    )
    .unwrap()
}

/// An octant of the sphere of radius `r` as a rational biquadratic: a
/// quarter meridian (u, equator to pole) revolved a quarter turn (v).
/// Degenerate (Su × Sv = 0) at the pole u = 1.
pub fn sphere_octant(r: f64) -> BSplineSurface {
    let w = FRAC_1_SQRT_2;
    let prof = [(r, 0.0, 1.0), (r, r, w), (0.0, r, 1.0)]; // (ρ, z, weight)
    let rev = [(1.0, 0.0, 1.0), (1.0, 1.0, w), (0.0, 1.0, 1.0)]; // (cx, cy, weight)
    let mut pts = vec![];
    let mut wts = vec![];
    for &(rho, z, wu) in &prof {
        for &(cx, cy, wv) in &rev {
            pts.push(DVec3::new(rho * cx, rho * cy, z));
            wts.push(wu * wv);
        }
    }
    let k = vec![0., 0., 0., 1., 1., 1.];
    BSplineSurface::try_new(2, 2, k.clone(), k, 3, 3, pts, Some(wts)).unwrap()
}

/// A cylinder of radius `r` and height `h` about the z axis: the full
/// rational circle in u times a line in v.
pub fn cylinder(r: f64, h: f64) -> BSplineSurface {
    let c = circle(r);
    let mut pts = vec![];
    let mut wts = vec![];
    for (p, &w) in c.points().iter().zip(c.weights().unwrap()) {
        for z in [0.0, h] {
            pts.push(DVec3::new(p.x, p.y, z));
            wts.push(w);
        }
    }
    BSplineSurface::try_new(
        2,
        1,
        c.knots().values().to_vec(),
        vec![0., 0., 1., 1.],
        9,
        2,
        pts,
        Some(wts),
    )
    .unwrap()
}

/// A non-rational bicubic with a wavy net (non-uniform knots in u).
pub fn wavy_bicubic() -> BSplineSurface {
    let (nu, nv) = (6, 5);
    let mut pts = vec![];
    for i in 0..nu {
        for j in 0..nv {
            let (x, y) = (i as f64, j as f64 * 1.2);
            pts.push(DVec3::new(
                x + 0.1 * y,
                y,
                (0.7 * x).sin() * (0.9 * y).cos() + 0.05 * (i * j) as f64,
            ));
        }
    }
    BSplineSurface::try_new(
        3,
        3,
        vec![0., 0., 0., 0., 0.3, 0.55, 1., 1., 1., 1.],
        vec![0., 0., 0., 0., 0.5, 1., 1., 1., 1.],
        nu,
        nv,
        pts,
        None,
    )
    .unwrap()
}

/// The same net with uneven weights (rational).
pub fn wavy_rational() -> BSplineSurface {
    let s = wavy_bicubic();
    let w: Vec<f64> = (0..30).map(|k| 0.6 + 0.9 * ((k * 7 % 11) as f64 / 10.0)).collect();
    BSplineSurface::try_new(
        3,
        3,
        s.knots_u().values().to_vec(),
        s.knots_v().values().to_vec(),
        6,
        5,
        s.points().to_vec(),
        Some(w),
    )
    .unwrap()
}
