//! Trim loops: where a face bounds its B-spline surface, as closed loops in the surface's own parameter
//! space (u, v).
//!
//! A trimmed face read from STEP (`ADVANCED_FACE` bounds) or IGES (type 144 with 142 boundaries) keeps its
//! loops here, with the surface object. They are stored in (u, v), not in space: fairing keeps the
//! surface's knots and parameterisation, so a uv loop still bounds the same part of the faired surface,
//! and the 3D edges are recomputed on the faired surface when the face is written ([`edge_on_surface`]).
//! Each edge is a 2D B-spline whose points are `(u, v, 0)`: a parameter-space curve of the file where
//! there is one (exact), else the 3D edge sampled and projected onto the surface as a uv polyline
//! ([`project_path`]). Both derived curves are held to [`fit_tolerance`]: [`FIT_FRACTION`] × the
//! diagonal of the surface's control box.

use glam::{DVec2, DVec3};

use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::fit::{Smoothing, fit_curve_points};
use crate::knots::KnotVector;
use crate::measure_surface::SurfaceProjector;
use crate::surface::BSplineSurface;

/// The tolerance of the curves a trim derives (uv polylines of 3D edges, 3D edges written on export),
/// as a fraction of the diagonal of the surface's control box.
pub const FIT_FRACTION: f64 = 1e-6;

/// The most samples one edge is projected at, and the most spans a written 3D edge may have.
const MAX_EDGE_SAMPLES: usize = 8192;

/// One closed loop of edges in the surface's (u, v), in the order the loop runs, each edge oriented
/// along it (its end is the next edge's start).
#[derive(Debug, Clone, PartialEq)]
pub struct TrimLoop {
    /// The outer boundary (else a hole).
    pub outer: bool,
    /// The edges: 2D B-splines, points `(u, v, 0)`.
    pub edges: Vec<BSplineCurve>,
}

/// The loops that bound a face on its surface.
#[derive(Debug, Clone, PartialEq)]
pub struct FaceTrim {
    /// Outer loop(s) first as the file gave them, then the holes.
    pub loops: Vec<TrimLoop>,
}

impl FaceTrim {
    /// How many loops are outer boundaries.
    pub fn outer_loops(&self) -> usize {
        self.loops.iter().filter(|l| l.outer).count()
    }

    /// How many loops are holes.
    pub fn inner_loops(&self) -> usize {
        self.loops.len() - self.outer_loops()
    }

    /// What `fairway info` says of it: "trimmed: 1 outer loop, 2 inner loops, 9 edges".
    pub fn summary(&self) -> String {
        let n = |k: usize, what: &str| format!("{k} {what} loop{}", if k == 1 { "" } else { "s" });
        let edges: usize = self.loops.iter().map(|l| l.edges.len()).sum();
        format!(
            "trimmed: {}, {}, {edges} edge{}",
            n(self.outer_loops(), "outer"),
            n(self.inner_loops(), "inner"),
            if edges == 1 { "" } else { "s" }
        )
    }

    /// Each loop as a closed uv polyline, `per_edge` segments an edge (the last point repeats the first).
    pub fn polylines(&self, per_edge: usize) -> Vec<Vec<DVec2>> {
        let per_edge = per_edge.max(1);
        self.loops
            .iter()
            .map(|l| {
                let mut out: Vec<DVec2> = vec![];
                for e in &l.edges {
                    let (a, b) = e.domain();
                    let start = usize::from(!out.is_empty());
                    out.extend((start..=per_edge).map(|k| {
                        let q = e.point(a + (b - a) * k as f64 / per_edge as f64);
                        DVec2::new(q.x, q.y)
                    }));
                }
                out
            })
            .collect()
    }

    /// The largest gap between an edge's end and the next edge's start (around each loop), in (u, v).
    pub fn largest_gap(&self) -> f64 {
        let mut worst = 0.0f64;
        for l in &self.loops {
            for (k, e) in l.edges.iter().enumerate() {
                let next = &l.edges[(k + 1) % l.edges.len()];
                let end = e.point(e.domain().1);
                worst = worst.max(end.distance(next.point(next.domain().0)));
            }
        }
        worst
    }
}

/// The tolerance of a trim's derived curves on `s`: [`FIT_FRACTION`] × its control box's diagonal.
pub fn fit_tolerance(s: &BSplineSurface) -> f64 {
    let (lo, hi) = s.control_bounds();
    FIT_FRACTION * (hi - lo).length().max(f64::MIN_POSITIVE)
}

/// The part of `c` between its parameters `a < b`, clamped on `[a, b]` (knots inserted until each end
/// has the multiplicity of the degree; the same points, nothing refitted).
pub fn sub_curve(c: &BSplineCurve, a: f64, b: f64) -> Result<BSplineCurve> {
    let (lo, hi) = c.domain();
    let (a, b) = (a.max(lo), b.min(hi));
    if !(a < b) {
        return Err(Error::InvalidInput(format!(
            "an edge from parameter {a} to {b} of its curve is empty"
        )));
    }
    let p = c.degree();
    let mut w = c.clone();
    for u in [a, b] {
        let m = w.knots().multiplicity(u);
        if u > lo && u < hi && m < p {
            w = w.insert_knot(u, p - m)?;
        }
    }
    let kv = w.knots().values();
    let last_a = kv.iter().rposition(|&t| t == a).unwrap_or(p);
    let k = (last_a + 1).saturating_sub(p).max(1);
    let m = kv.iter().position(|&t| t == b).unwrap_or(w.n_points());
    let mut knots = vec![a; p + 1];
    knots.extend(kv[k + p..m].iter().copied());
    knots.extend(std::iter::repeat_n(b, p + 1));
    let pts = w.points()[k - 1..m].to_vec();
    let weights = w.weights().map(|ws| ws[k - 1..m].to_vec());
    BSplineCurve::try_new(p, knots, pts, weights, c.dim())
}

/// A path in space, `path(t)` for `t` in `range`, as a uv polyline on `s`: samples projected onto `s`
/// (each from the last one's (u, v)), doubled until the surface point at each segment's uv midpoint is
/// within `tol` of the path's midpoint. Returns the polyline (degree 1, the path's parameter) and the
/// largest of those midpoint errors and the samples' distances from `s`; an error where the path lies
/// farther than `off` from the surface (it is not on this face).
pub fn project_path(
    s: &BSplineSurface,
    path: &dyn Fn(f64) -> DVec3,
    (t0, t1): (f64, f64),
    tol: f64,
    off: f64,
) -> Result<(BSplineCurve, f64)> {
    let proj = SurfaceProjector::new(s, 4);
    let mut n = 16usize;
    loop {
        let ts: Vec<f64> = (0..=n).map(|k| t0 + (t1 - t0) * k as f64 / n as f64).collect();
        let mut uvs: Vec<(f64, f64)> = Vec::with_capacity(n + 1);
        let mut worst = 0.0f64;
        for &t in &ts {
            let q = path(t);
            let near = uvs.last().map(|&uv| proj.project_near(q, uv));
            let sp = match near {
                Some(sp) if sp.distance <= off => sp,
                _ => proj.project(q),
            };
            if !(sp.distance <= off) {
                return Err(Error::InvalidInput(format!(
                    "the edge passes {:.3e} from the surface at its parameter {t} (more than {off:.3e}): it is not \
                     on this face's surface",
                    sp.distance
                )));
            }
            worst = worst.max(sp.distance);
            uvs.push(sp.uv);
        }
        for k in 0..n {
            let mid = ((uvs[k].0 + uvs[k + 1].0) / 2.0, (uvs[k].1 + uvs[k + 1].1) / 2.0);
            let e = s.point(mid.0, mid.1).distance(path((ts[k] + ts[k + 1]) / 2.0));
            worst = worst.max(e);
        }
        if worst <= tol || 2 * n > MAX_EDGE_SAMPLES {
            let mut knots = vec![t0];
            knots.extend(ts.iter().copied());
            knots.push(t1);
            let pts = uvs.iter().map(|&(u, v)| DVec3::new(u, v, 0.0)).collect();
            return Ok((BSplineCurve::try_new(1, knots, pts, None, 2)?, worst));
        }
        n *= 2;
    }
}

/// The 3D curve of the uv edge `e` on `s`: a cubic (or the surface's higher degree) B-spline on `e`'s
/// breakpoints (the continuity of `e` kept), fitted by least squares to `s(e(t))`, ends interpolated, its
/// spans halved until the largest distance at 64 samples a span is within `tol`. Returns the curve and
/// that largest distance.
pub fn edge_on_surface(s: &BSplineSurface, e: &BSplineCurve, tol: f64) -> Result<(BSplineCurve, f64)> {
    const FIT: usize = 12;
    const CHECK: usize = 64;
    let on = |t: f64| {
        let q = e.point(t);
        s.point(q.x, q.y)
    };
    let p = e.degree();
    let q = p
        .max(3)
        .max(s.degree_u())
        .max(s.degree_v())
        .min(crate::knots::MAX_DEGREE);
    let kv = e.knots();
    let bps = kv.breakpoints();
    let (a, b) = e.domain();
    let mut interior: Vec<(f64, usize)> = bps[1..bps.len() - 1]
        .iter()
        .map(|&u| (u, (kv.multiplicity(u) + q - p).min(q)))
        .collect();
    loop {
        let mut knots = vec![a; q + 1];
        for &(u, m) in &interior {
            knots.extend(std::iter::repeat_n(u, m));
        }
        knots.extend(std::iter::repeat_n(b, q + 1));
        let n_pts = knots.len() - q - 1;
        let kvq = KnotVector::try_new(knots.clone(), q, n_pts, "edge knots")?;
        let spans: Vec<(f64, f64)> = kvq.breakpoints().windows(2).map(|w| (w[0], w[1])).collect();
        let params: Vec<f64> = spans
            .iter()
            .flat_map(|&(s0, s1)| (0..FIT).map(move |k| s0 + (s1 - s0) * (k as f64 + 0.5) / FIT as f64))
            .collect();
        let targets: Vec<DVec3> = params.iter().map(|&t| on(t)).collect();
        let mut fixed = vec![None; n_pts];
        fixed[0] = Some(on(a));
        fixed[n_pts - 1] = Some(on(b));
        let pts = fit_curve_points(&kvq, &params, &targets, None, Smoothing::NONE, &fixed)?;
        let curve = BSplineCurve::try_new(q, knots, pts, None, 3)?;
        let mut worst = 0.0f64;
        let mut split = vec![];
        for &(s0, s1) in &spans {
            let e = (0..=CHECK)
                .map(|k| s0 + (s1 - s0) * k as f64 / CHECK as f64)
                .map(|t| curve.point(t).distance(on(t)))
                .fold(0.0f64, f64::max);
            worst = worst.max(e);
            if e > tol {
                split.push((0.5 * (s0 + s1), 1));
            }
        }
        if !worst.is_finite() {
            return Err(Error::InvalidInput(
                "the edge's curve on the surface is not finite".into(),
            ));
        }
        if split.is_empty() || spans.len() + split.len() > MAX_EDGE_SAMPLES {
            return Ok((curve, worst));
        }
        interior.extend(split);
        interior.sort_by(|x, y| x.0.total_cmp(&y.0));
    }
}

/// The fallback 3D edge of the uv edge `e` on `s` (where [`edge_on_surface`] fails, which a valid uv
/// curve does not make it): a polyline through the surface's points at 65 parameters of `e`.
pub fn polyline_on_surface(s: &BSplineSurface, e: &BSplineCurve) -> Result<BSplineCurve> {
    const N: usize = 64;
    let (a, b) = e.domain();
    let ts: Vec<f64> = (0..=N).map(|k| a + (b - a) * k as f64 / N as f64).collect();
    let pts = ts.iter().map(|&t| {
        let q = e.point(t);
        s.point(q.x, q.y)
    });
    let mut knots = vec![a];
    knots.extend(ts.iter().copied());
    knots.push(b);
    BSplineCurve::try_new(1, knots, pts.collect(), None, 3)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cubic() -> BSplineCurve {
        let pts = vec![
            DVec3::new(0.1, 0.1, 0.0),
            DVec3::new(0.3, 0.5, 0.0),
            DVec3::new(0.5, 0.2, 0.0),
            DVec3::new(0.7, 0.6, 0.0),
            DVec3::new(0.9, 0.4, 0.0),
        ];
        BSplineCurve::try_new(3, vec![0., 0., 0., 0., 0.4, 1., 1., 1., 1.], pts, None, 2).unwrap()
    }

    #[test]
    fn a_sub_curve_is_the_same_curve_on_its_range() {
        let c = cubic();
        for (a, b) in [(0.0, 1.0), (0.1, 0.7), (0.4, 0.9), (0.0, 0.4), (0.25, 1.0)] {
            let s = sub_curve(&c, a, b).unwrap();
            assert_eq!(s.domain(), (a, b));
            for k in 0..=40 {
                let t = a + (b - a) * k as f64 / 40.0;
                assert!(s.point(t).distance(c.point(t)) < 1e-14, "{a} {b} {t}");
            }
        }
        assert!(sub_curve(&c, 0.5, 0.5).is_err());
    }

    #[test]
    fn an_edge_on_a_surface_is_fitted_within_the_tolerance() {
        let n = 6;
        let k = KnotVector::uniform(3, n).unwrap().values().to_vec();
        let pts = (0..n * n)
            .map(|i| {
                let (x, y) = ((i / n) as f64, (i % n) as f64);
                DVec3::new(x, y, (0.9 * x).sin() * (0.6 * y).cos())
            })
            .collect();
        let s = BSplineSurface::try_new(3, 3, k.clone(), k, n, n, pts, None).unwrap();
        let tol = fit_tolerance(&s);
        let e = cubic();
        let (c, err) = edge_on_surface(&s, &e, tol).unwrap();
        assert!(err <= tol, "{err} > {tol}");
        let proj = SurfaceProjector::new(&s, 4);
        for k in 0..=500 {
            let q = c.point(k as f64 / 500.0);
            assert!(proj.project(q).distance <= tol, "{k}");
        }
        // and back: the 3D edge projected onto the surface is the uv edge again
        let (uv, err) = project_path(&s, &|t| c.point(t), (0.0, 1.0), tol, 1e-3).unwrap();
        assert!(err <= tol);
        for k in 0..=50 {
            let t = k as f64 / 50.0;
            assert!(uv.point(t).distance(e.point(t)) < 1e-4, "{t}");
        }
    }
}
