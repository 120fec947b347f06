//! Joins between the objects of a scene (curve networks, patch layouts) and their measured continuity.
//!
//! * **Curve joins**: two curve ends that coincide within [`JOIN_TOLERANCE`] × the scene's diagonal (the
//!   bounding box of every control point). Each is measured ([`CurveContinuity`]): the position gap, the
//!   angle between the direction the curve arrives by and the one the other leaves by, and the jump of
//!   the curvature vector κN relative to the larger curvature — G0, G1 (angle ≤ [`G1_ANGLE_RAD`]) or G2
//!   (also a curvature jump ≤ [`G2_CURVATURE_JUMP`]). A curve's own two ends (a closed curve) are not a
//!   join. Where three or more ends meet, every pair is a join.
//! * **Surface joins**: two patches whose boundary sides coincide within the same tolerance (both end
//!   points, and [`EDGE_SAMPLES`] points along the side within it of the other side). Measured along
//!   the edge ([`SurfaceContinuity`]): the largest position gap, the largest angle between the two
//!   normals and the largest jump of the normal curvature across the edge (in the tangent direction
//!   perpendicular to it), relative to the larger one.
//!
//! [`crate::fair::network`] fairs a scene keeping these joins.

use glam::DVec3;

use crate::closest::CurveProjector;
use crate::curve::BSplineCurve;
use crate::geometry::Geometry;
use crate::surface::BSplineSurface;

/// Ends closer than this fraction of the scene's diagonal are one point: a join.
pub const JOIN_TOLERANCE: f64 = 1e-6;
/// A join whose tangent (normal) directions differ by at most this angle, in radians (0.01°), is G1.
pub const G1_ANGLE_RAD: f64 = 1.745_329_251_994_33e-4;
/// A G1 join whose curvature (normal curvature across the edge) jumps by at most this fraction of the
/// larger one is G2.
pub const G2_CURVATURE_JUMP: f64 = 1e-3;
/// Points along a shared edge where a surface join is checked and measured.
pub const EDGE_SAMPLES: usize = 21;

/// The order of geometric continuity of a join.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
pub enum Continuity {
    /// Position only (a corner, or a tangent break below the corner angle).
    G0,
    /// Position and tangent direction (surfaces: the normal).
    G1,
    /// Also the curvature (surfaces: the normal curvature across the edge).
    G2,
}

impl Continuity {
    /// "G0", "G1" or "G2".
    pub fn name(self) -> &'static str {
        match self {
            Self::G0 => "G0",
            Self::G1 => "G1",
            Self::G2 => "G2",
        }
    }
}

/// Which end of a curve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum End {
    /// The start of the domain.
    Start,
    /// The end of the domain.
    End,
}

impl End {
    /// "start" or "end".
    pub fn name(self) -> &'static str {
        match self {
            End::Start => "start",
            End::End => "end",
        }
    }
}

/// One end of one curve of the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct CurveEnd {
    /// The object's index in the scene.
    pub object: usize,
    /// Which end.
    pub end: End,
}

/// The measured continuity of a curve join.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CurveContinuity {
    /// Distance between the two end points.
    pub gap: f64,
    /// Angle between the direction of travel arriving on one curve and leaving on the other, radians.
    pub angle: f64,
    /// |κ₁N₁ − κ₂N₂| / max(κ₁, κ₂): 0 where the curvature is continuous (0 where both are straight).
    pub curvature_jump: f64,
    /// κ₂ / κ₁ (1 at G2; 1 where both are straight).
    pub curvature_ratio: f64,
    /// The class: G0, G1 or G2.
    pub class: Continuity,
}

/// A join of two curve ends.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CurveJoin {
    /// The end arrived by.
    pub a: CurveEnd,
    /// The end left by.
    pub b: CurveEnd,
    /// The joint (the midpoint of the two end points).
    pub point: DVec3,
    /// Its continuity.
    pub continuity: CurveContinuity,
}

/// A side of a surface's domain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Side {
    /// u = u₀.
    U0,
    /// u = u₁.
    U1,
    /// v = v₀.
    V0,
    /// v = v₁.
    V1,
}

impl Side {
    /// All four sides.
    pub const ALL: [Side; 4] = [Side::U0, Side::U1, Side::V0, Side::V1];

    /// "u0", "u1", "v0" or "v1".
    pub fn name(self) -> &'static str {
        match self {
            Side::U0 => "u0",
            Side::U1 => "u1",
            Side::V0 => "v0",
            Side::V1 => "v1",
        }
    }

    /// The side's boundary curve (along v for U0/U1, along u for V0/V1).
    pub fn curve(self, s: &BSplineSurface) -> BSplineCurve {
        let ((u0, u1), (v0, v1)) = s.domain();
        match self {
            Side::U0 => s.iso_v(u0),
            Side::U1 => s.iso_v(u1),
            Side::V0 => s.iso_u(v0),
            Side::V1 => s.iso_u(v1),
        }
    }

    /// The surface parameters of the side's point at parameter `t` of [`Self::curve`].
    pub fn uv(self, s: &BSplineSurface, t: f64) -> (f64, f64) {
        let ((u0, u1), (v0, v1)) = s.domain();
        match self {
            Side::U0 => (u0, t),
            Side::U1 => (u1, t),
            Side::V0 => (t, v0),
            Side::V1 => (t, v1),
        }
    }
}

/// The measured continuity of a surface join, along the shared edge.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SurfaceContinuity {
    /// Largest distance between the two sides at the edge samples.
    pub gap: f64,
    /// Largest angle between the two normals, radians.
    pub normal_angle: f64,
    /// Largest jump of the normal curvature across the edge, relative to the larger one.
    pub curvature_jump: f64,
    /// The class: G0, G1 or G2.
    pub class: Continuity,
}

/// Two patches sharing an edge.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SurfaceJoin {
    /// The first patch and its side.
    pub a: (usize, Side),
    /// The second patch and its side.
    pub b: (usize, Side),
    /// The two sides run in opposite directions.
    pub reversed: bool,
    /// Its continuity.
    pub continuity: SurfaceContinuity,
}

/// The joins of a scene.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
pub struct Joins {
    /// The distance under which points are one: [`JOIN_TOLERANCE`] × the scene's diagonal.
    pub tolerance: f64,
    /// The joins of curve ends.
    pub curves: Vec<CurveJoin>,
    /// The edges that patches share.
    pub surfaces: Vec<SurfaceJoin>,
}

/// The diagonal of the bounding box of every control point of `objects` (0 if there are none).
pub fn scene_diagonal(objects: &[Geometry]) -> f64 {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for g in objects {
        let (a, b) = match g {
            Geometry::Curve(c) => c.control_bounds(),
            Geometry::Surface(s) => s.control_bounds(),
        };
        lo = lo.min(a);
        hi = hi.max(b);
    }
    if lo.x.is_finite() { (hi - lo).length() } else { 0.0 }
}

/// The joins of `objects` (module docs).
pub fn find_joins(objects: &[Geometry]) -> Joins {
    let tol = JOIN_TOLERANCE * scene_diagonal(objects);
    let curves: Vec<(usize, &BSplineCurve)> = objects
        .iter()
        .enumerate()
        .filter_map(|(i, g)| g.as_curve().map(|c| (i, c)))
        .collect();
    let mut joins = Joins {
        tolerance: tol,
        ..Default::default()
    };
    let ends = |c: &BSplineCurve| {
        let (a, b) = c.domain();
        [(End::Start, c.point(a)), (End::End, c.point(b))]
    };
    for (x, &(i, ci)) in curves.iter().enumerate() {
        for &(j, cj) in &curves[x + 1..] {
            for (ei, pi) in ends(ci) {
                for (ej, pj) in ends(cj) {
                    if pi.distance(pj) <= tol {
                        // arrive by the end of a curve where possible
                        let (a, b) = if ei == End::Start && ej == End::End {
                            (CurveEnd { object: j, end: ej }, CurveEnd { object: i, end: ei })
                        } else {
                            (CurveEnd { object: i, end: ei }, CurveEnd { object: j, end: ej })
                        };
                        let continuity = curve_continuity(objects, a, b);
                        joins.curves.push(CurveJoin {
                            a,
                            b,
                            point: (pi + pj) * 0.5,
                            continuity,
                        });
                    }
                }
            }
        }
    }
    let surfaces: Vec<(usize, &BSplineSurface)> = objects
        .iter()
        .enumerate()
        .filter_map(|(i, g)| g.as_surface().map(|s| (i, s)))
        .collect();
    // the corners of each side (a clamped net's corner points): a cheap test before the edge's own
    let corners = |s: &BSplineSurface| {
        let (nu, nv) = (s.nu() - 1, s.nv() - 1);
        let c = |i, j| s.point_at(i, j);
        [
            (c(0, 0), c(0, nv)),
            (c(nu, 0), c(nu, nv)),
            (c(0, 0), c(nu, 0)),
            (c(0, nv), c(nu, nv)),
        ]
    };
    let near = |(a0, a1): (DVec3, DVec3), (b0, b1): (DVec3, DVec3)| {
        (a0.distance(b0) <= tol && a1.distance(b1) <= tol) || (a0.distance(b1) <= tol && a1.distance(b0) <= tol)
    };
    let all_corners: Vec<_> = surfaces.iter().map(|(_, s)| corners(s)).collect();
    for (x, &(i, si)) in surfaces.iter().enumerate() {
        for (y, &(j, sj)) in surfaces.iter().enumerate().skip(x + 1) {
            // faces on one surface (a trimmed face split in two): its untrimmed boundaries are no edges
            // between them
            if si == sj {
                continue;
            }
            for (ka, a) in Side::ALL.into_iter().enumerate() {
                for (kb, b) in Side::ALL.into_iter().enumerate() {
                    if !near(all_corners[x][ka], all_corners[y][kb]) {
                        continue;
                    }
                    if let Some(reversed) = shared_edge(si, a, sj, b, tol) {
                        let continuity = surface_continuity(si, a, sj, b, reversed);
                        joins.surfaces.push(SurfaceJoin {
                            a: (i, a),
                            b: (j, b),
                            reversed,
                            continuity,
                        });
                    }
                }
            }
        }
    }
    joins
}

/// A curve end's point, the direction of travel arriving at it (`arriving`) or leaving it, and its
/// curvature vector κN (the same either way).
pub fn end_frame(c: &BSplineCurve, end: End, arriving: bool) -> (DVec3, DVec3, DVec3) {
    let (a, b) = c.domain();
    let u = if end == End::Start { a } else { b };
    let d = c.derivs(u);
    // leaving by the start / arriving by the end is the curve's own direction
    let forward = (end == End::End) == arriving;
    let t = d.d1.normalize_or_zero();
    (d.p, if forward { t } else { -t }, c.curvature_vector(u))
}

/// The continuity of the join arriving by `a` and leaving by `b` (module docs).
pub fn curve_continuity(objects: &[Geometry], a: CurveEnd, b: CurveEnd) -> CurveContinuity {
    let curve = |e: CurveEnd| objects[e.object].as_curve().expect("a curve end");
    continuity_of(curve(a), a.end, curve(b), b.end)
}

/// [`curve_continuity`] of two curves: arriving by `ea` of `ca`, leaving by `eb` of `cb`.
pub fn continuity_of(ca: &BSplineCurve, ea: End, cb: &BSplineCurve, eb: End) -> CurveContinuity {
    let (pa, ta, ka) = end_frame(ca, ea, true);
    let (pb, tb, kb) = end_frame(cb, eb, false);
    let angle = ta.cross(tb).length().atan2(ta.dot(tb));
    let kmax = ka.length().max(kb.length());
    let (jump, ratio) = if kmax > 0.0 {
        let ratio = if ka.length() > 0.0 {
            kb.length() / ka.length()
        } else {
            f64::INFINITY
        };
        ((ka - kb).length() / kmax, ratio)
    } else {
        (0.0, 1.0)
    };
    let class = if angle > G1_ANGLE_RAD {
        Continuity::G0
    } else if jump > G2_CURVATURE_JUMP {
        Continuity::G1
    } else {
        Continuity::G2
    };
    CurveContinuity {
        gap: pa.distance(pb),
        angle,
        curvature_jump: jump,
        curvature_ratio: ratio,
        class,
    }
}

/// Whether side `a` of `sa` and side `b` of `sb` are one edge within `tol`: `Some(reversed)` if so.
fn shared_edge(sa: &BSplineSurface, a: Side, sb: &BSplineSurface, b: Side, tol: f64) -> Option<bool> {
    let (ca, cb) = (a.curve(sa), b.curve(sb));
    let ((a0, a1), (b0, b1)) = (ca.domain(), cb.domain());
    let (pa0, pa1, pb0, pb1) = (ca.point(a0), ca.point(a1), cb.point(b0), cb.point(b1));
    let reversed = if pa0.distance(pb0) <= tol && pa1.distance(pb1) <= tol {
        false
    } else if pa0.distance(pb1) <= tol && pa1.distance(pb0) <= tol {
        true
    } else {
        return None;
    };
    // a degenerate side (a pole) is no edge
    if pa0.distance(pa1) <= tol && ca.point(0.5 * (a0 + a1)).distance(pa0) <= tol {
        return None;
    }
    let proj = CurveProjector::new(&cb, 16);
    (0..EDGE_SAMPLES)
        .all(|k| {
            let t = a0 + (a1 - a0) * k as f64 / (EDGE_SAMPLES - 1) as f64;
            proj.project(ca.point(t)).distance <= tol
        })
        .then_some(reversed)
}

/// The normal curvature of `s` at `(u, v)` in the tangent direction `w` (projected into the tangent
/// plane), with the normal `n` giving its sign.
fn normal_curvature(s: &BSplineSurface, (u, v): (f64, f64), w: DVec3, n: DVec3) -> f64 {
    let d = s.derivs(u, v);
    let (e, f, g) = (d.su.dot(d.su), d.su.dot(d.sv), d.sv.dot(d.sv));
    let det = e * g - f * f;
    if !(det > 0.0) {
        return 0.0;
    }
    // w = α Su + β Sv in the least-squares sense
    let (r1, r2) = (w.dot(d.su), w.dot(d.sv));
    let (al, be) = ((g * r1 - f * r2) / det, (e * r2 - f * r1) / det);
    let first = e * al * al + 2.0 * f * al * be + g * be * be;
    let second = d.suu.dot(n) * al * al + 2.0 * d.suv.dot(n) * al * be + d.svv.dot(n) * be * be;
    if first > 0.0 { second / first } else { 0.0 }
}

/// The continuity of the edge that side `a` of `sa` and side `b` of `sb` share (module docs).
pub fn surface_continuity(
    sa: &BSplineSurface,
    a: Side,
    sb: &BSplineSurface,
    b: Side,
    reversed: bool,
) -> SurfaceContinuity {
    let (ca, cb) = (a.curve(sa), b.curve(sb));
    let ((a0, a1), (b0, b1)) = (ca.domain(), cb.domain());
    let proj = CurveProjector::new(&cb, 16);
    let (mut gap, mut angle, mut jump) = (0.0f64, 0.0f64, 0.0f64);
    for k in 0..EDGE_SAMPLES {
        let f = k as f64 / (EDGE_SAMPLES - 1) as f64;
        let ta = a0 + (a1 - a0) * f;
        let guess = if reversed {
            b1 - (b1 - b0) * f
        } else {
            b0 + (b1 - b0) * f
        };
        let q = ca.point(ta);
        let near = proj.project_near(q, guess, 0.05 * (b1 - b0));
        let tb = near.param;
        gap = gap.max(near.distance);
        let (uva, uvb) = (a.uv(sa, ta), b.uv(sb, tb));
        let na = sa.normal(uva.0, uva.1);
        let mut nb = sb.normal(uvb.0, uvb.1);
        if na.dot(nb) < 0.0 {
            nb = -nb;
        }
        angle = angle.max(na.cross(nb).length().atan2(na.dot(nb)));
        // across the edge: the tangent direction perpendicular to it
        let w = na.cross(ca.d1(ta)).normalize_or_zero();
        let (ka, kb) = (normal_curvature(sa, uva, w, na), normal_curvature(sb, uvb, w, na));
        let kmax = ka.abs().max(kb.abs());
        if kmax > 0.0 {
            jump = jump.max((ka - kb).abs() / kmax);
        }
    }
    let class = if angle > G1_ANGLE_RAD {
        Continuity::G0
    } else if jump > G2_CURVATURE_JUMP {
        Continuity::G1
    } else {
        Continuity::G2
    };
    SurfaceContinuity {
        gap,
        normal_angle: angle,
        curvature_jump: jump,
        class,
    }
}

/// [`surface_continuity`] of a join found by [`find_joins`] on `objects`.
pub fn surface_join_continuity(objects: &[Geometry], j: &SurfaceJoin) -> SurfaceContinuity {
    let s = |i: usize| objects[i].as_surface().expect("a surface");
    surface_continuity(s(j.a.0), j.a.1, s(j.b.0), j.b.1, j.reversed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn a_split_cubic_is_a_g2_join_and_a_kink_g0() {
        let pts: Vec<DVec2> = (0..8).map(|i| DVec2::new(i as f64, (i as f64 * 0.7).sin())).collect();
        let mut knots = vec![0.0; 4];
        knots.extend((1..5).map(|i| i as f64 / 5.0));
        knots.extend([1.0; 4]);
        let c = BSplineCurve::new_2d(3, knots, &pts).unwrap();
        let (l, r) = crate::fair::closed::split(&c, 0.4).unwrap();
        let objects: Vec<Geometry> = vec![r.clone().into(), l.clone().into()];
        let j = find_joins(&objects);
        assert_eq!(j.curves.len(), 1);
        let cj = &j.curves[0];
        assert_eq!(
            (cj.a.object, cj.a.end, cj.b.object, cj.b.end),
            (1, End::End, 0, End::Start)
        );
        assert_eq!(cj.continuity.class, Continuity::G2, "{:?}", cj.continuity);
        // the second piece turned: a corner
        let turned = r
            .with_points(
                r.points()
                    .iter()
                    .map(|q| (*q - r.points()[0]).perp_like() + r.points()[0])
                    .collect(),
            )
            .unwrap();
        let j = find_joins(&[l.into(), turned.into()]);
        assert_eq!(j.curves[0].continuity.class, Continuity::G0);
        assert!((j.curves[0].continuity.angle.to_degrees() - 90.0).abs() < 60.0);
    }

    trait PerpLike {
        fn perp_like(self) -> Self;
    }
    impl PerpLike for DVec3 {
        fn perp_like(self) -> Self {
            DVec3::new(-self.y, self.x, self.z)
        }
    }
}
