//! Closest point on a curve: coarse search on a dense polyline, then a
//! safeguarded Newton iteration on `f(t) = c'(t)·(c(t) − q)` (the first-order
//! condition of `min |c(t) − q|²`, derivative `c''·(c − q) + |c'|²`), with
//! bisection whenever Newton leaves the bracket. The domain ends are
//! candidates too, so a point beyond an end projects onto it.

use glam::DVec3;

use crate::curve::BSplineCurve;

/// Result of a projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClosestPoint {
    /// Parameter of the closest point.
    pub param: f64,
    /// The closest point on the curve.
    pub point: DVec3,
    /// Its distance to the query.
    pub distance: f64,
}

impl ClosestPoint {
    /// The curve point `point` = c(`param`) as a candidate for the query `q`.
    fn of(param: f64, point: DVec3, q: DVec3) -> Self {
        Self {
            param,
            point,
            distance: point.distance(q),
        }
    }

    /// The nearer of two candidates (`self` on a tie).
    fn closer(self, other: Self) -> Self {
        if other.distance < self.distance { other } else { self }
    }
}

/// Projects points onto one curve; build once, query many times.
#[derive(Debug, Clone)]
pub struct CurveProjector<'a> {
    curve: &'a BSplineCurve,
    params: Vec<f64>,
    pts: Vec<DVec3>,
}

impl<'a> CurveProjector<'a> {
    /// Prepare a projector with `samples_per_span` polyline points per knot span (≥ 2; 16 is plenty for cubics).
    pub fn new(curve: &'a BSplineCurve, samples_per_span: usize) -> Self {
        let m = samples_per_span.max(2);
        let bp = curve.knots().breakpoints();
        let mut params = Vec::with_capacity((bp.len() - 1) * m + 1);
        for w in bp.windows(2) {
            for k in 0..m {
                params.push(w[0] + (w[1] - w[0]) * k as f64 / m as f64);
            }
        }
        params.push(*bp.last().unwrap());
        let pts = params.iter().map(|&u| curve.point(u)).collect();
        Self { curve, params, pts }
    }

    /// The curve.
    pub fn curve(&self) -> &BSplineCurve {
        self.curve
    }

    /// The closest point of the curve to `q`.
    pub fn project(&self, q: DVec3) -> ClosestPoint {
        self.project_points(q, 0, self.pts.len() - 1)
    }

    /// The closest point to `q` of the stretch `[a, b]` of the curve, widened to the polyline points
    /// around it (the same search as [`Self::project`] on the polyline's segments there only: its
    /// cost grows with the stretch, not with the curve).
    pub fn project_between(&self, q: DVec3, a: f64, b: f64) -> ClosestPoint {
        let n = self.params.len();
        let i0 = self.params.partition_point(|&p| p <= a).saturating_sub(1);
        let i1 = self
            .params
            .partition_point(|&p| p < b)
            .min(n - 1)
            .max((i0 + 1).min(n - 1));
        self.project_points(q, i0, i1)
    }

    /// [`Self::project`] over the polyline's points `i0..=i1` (the refinement may look up to two
    /// segments beyond them).
    fn project_points(&self, q: DVec3, i0: usize, i1: usize) -> ClosestPoint {
        // best segments by distance to the polyline; keep up to three local minima
        let mut cand: [(f64, usize); 3] = [(f64::INFINITY, usize::MAX); 3];
        let n = self.pts.len();
        for i in i0..i1 {
            let d = seg_dist2(self.pts[i], self.pts[i + 1], q);
            if d < cand[2].0 {
                // avoid adjacent duplicates: replace a neighbour if better
                if let Some(k) = cand.iter().position(|c| c.1 != usize::MAX && c.1.abs_diff(i) <= 1) {
                    if d < cand[k].0 {
                        cand[k] = (d, i);
                    }
                } else {
                    cand[2] = (d, i);
                }
                cand.sort_by(|a, b| a.0.total_cmp(&b.0));
            }
        }
        let mut best = self.at(self.params[i0], q).closer(self.at(self.params[i1], q));
        for (rank, &(_, i)) in cand.iter().enumerate() {
            if i == usize::MAX {
                continue;
            }
            // The curve is within `chord + gap` of q (the segment's distance, plus how far the curve strays
            // from the segment, estimated at the middle parameter), and not nearer than `chord − gap`: a
            // further candidate (larger chord distance) whose `chord − 4 gap` exceeds the best distance
            // found cannot win and is skipped
            let chord = seg_dist2(self.pts[i], self.pts[i + 1], q).sqrt();
            let mid = self.curve.point(0.5 * (self.params[i] + self.params[i + 1]));
            let gap = seg_dist2(self.pts[i], self.pts[i + 1], mid).sqrt();
            if rank > 0 && chord - 4.0 * gap > best.distance {
                continue;
            }
            // two segments on each side: the candidate list keeps one segment per run of neighbours, and a
            // run can cross a corner, leaving the minimum on its other side a segment or two away
            let (j0, j1) = (i.saturating_sub(2), (i + 3).min(n - 1));
            let (a, b) = (self.params[j0], self.params[j1]);
            // a smooth window with a bracket (f(a) < 0 < f(b), b's side from the left: a knot there may
            // start a span of another speed or direction) holds one minimum; otherwise the window may still
            // hold a minimum between a local maximum and its end, or a corner: no assumptions then
            let smooth_bracket = self.smooth_window(j0, j1) && !self.corner_inside(a, b) && {
                let (fa, _, _) = self.f(a, q);
                let (fb, _, _) = self.f(b - (b - a) * 1e-9, q);
                fa < 0.0 && fb > 0.0
            };
            let mut r = if smooth_bracket {
                self.bracketed(q, a, b, 0.5 * (self.params[i] + self.params[i + 1]))
                    .closer(self.at(a, q))
                    .closer(self.at(b, q))
            } else {
                self.refine_nonsmooth(q, a, b)
            };
            // a refinement above `chord + gap` landed on another, worse local minimum (a feature the
            // polyline does not resolve, a stationary stretch): search the window without assumptions
            if r.distance > chord + 2.0 * gap + 1e-12 * self.pts[i].distance(self.pts[i + 1]) {
                r = r.closer(self.refine_nonsmooth(q, a, b));
            }
            best = best.closer(r);
        }
        best
    }

    /// Whether the polyline turns gently over points `j0..=j1` (no zero-length segment, no turn above
    /// ~25°): then the distance has one minimum there at most and `f = c'·(c − q)` is continuous, so
    /// the bracketed Newton of [`Self::refine`] finds it. A corner (a C0 knot), a cusp or a stretch
    /// traversed back and forth fails this test and goes to [`Self::refine_nonsmooth`].
    fn smooth_window(&self, j0: usize, j1: usize) -> bool {
        let seg = |j: usize| self.pts[j + 1] - self.pts[j];
        (j0..j1).all(|j| seg(j).length_squared() > 0.0)
            && (j0..j1.saturating_sub(1)).all(|j| {
                let (u, v) = (seg(j), seg(j + 1));
                u.dot(v) > 0.9 * (u.length() * v.length())
            })
    }

    /// Whether a knot of multiplicity ≥ p (where the curve may have a corner and `f` jump) lies in `(a, b)`.
    fn corner_inside(&self, a: f64, b: f64) -> bool {
        let kv = self.curve.knots().values();
        let p = self.curve.degree();
        let mut i = kv.partition_point(|&k| k <= a);
        while i < kv.len() && kv[i] < b {
            let k = kv[i];
            let m = kv[i..].iter().take_while(|&&x| x == k).count();
            if m >= p {
                return true;
            }
            i += m;
        }
        false
    }

    /// Minimise |c(t) − q| over `[a, b]` without assuming smoothness. The window is split at the knots
    /// inside it (the curve is a polynomial between knots, so `f = c'·(c − q)` is continuous there,
    /// while at a C0 knot it jumps); on each piece `f` is sampled on a grid of [`NONSMOOTH_GRID`]
    /// intervals (the piece's right end from the left), every sign change − → + is refined by the
    /// bracketed Newton of [`Self::bracketed`], and the grid points and piece ends are candidates too.
    /// Every candidate is a point of the curve, so the result bounds the true distance from above.
    fn refine_nonsmooth(&self, q: DVec3, a: f64, b: f64) -> ClosestPoint {
        const G: usize = NONSMOOTH_GRID;
        let mut best = self.at(a, q).closer(self.at(b, q));
        let kv = self.curve.knots().values();
        // the knots strictly inside (a, b) only (a scan of the whole vector made a projection cost
        // time proportional to the curve)
        let (i0, i1) = (kv.partition_point(|&k| k <= a), kv.partition_point(|&k| k < b));
        let inner = kv[i0..i1.max(i0)].iter().copied();
        let mut x = a;
        for y in inner.chain(std::iter::once(b)) {
            if y <= x {
                continue;
            }
            let mut prev: Option<(f64, f64)> = None;
            for k in 0..=G {
                // the right end from the left: a point just inside the piece
                let t = if k == G {
                    y - (y - x) * 1e-9
                } else {
                    x + (y - x) * k as f64 / G as f64
                };
                let (ft, _, pt) = self.f(t, q);
                best = best.closer(ClosestPoint::of(t, pt, q));
                if let Some((tp, fp)) = prev
                    && fp < 0.0
                    && ft > 0.0
                {
                    best = best.closer(self.bracketed(q, tp, t, 0.5 * (tp + t)));
                }
                prev = Some((t, ft));
            }
            x = y;
        }
        best
    }

    /// Refine near a known parameter `guess`, searching `[guess − h, guess + h]`.
    /// Much cheaper than [`Self::project`] when the answer is known to be close.
    pub fn project_near(&self, q: DVec3, guess: f64, h: f64) -> ClosestPoint {
        let (lo, hi) = self.curve.domain();
        let a = (guess - h).max(lo);
        let b = (guess + h).min(hi);
        self.refine(q, a, b, guess.clamp(a, b))
    }

    fn at(&self, t: f64, q: DVec3) -> ClosestPoint {
        ClosestPoint::of(t, self.curve.point(t), q)
    }

    fn f(&self, t: f64, q: DVec3) -> (f64, f64, DVec3) {
        let d = self.curve.derivs(t);
        let r = d.p - q;
        (d.d1.dot(r), d.d2.dot(r) + d.d1.length_squared(), d.p)
    }

    /// Minimise |c(t) − q| over `[a, b]` starting at `t0`.
    fn refine(&self, q: DVec3, a: f64, b: f64, t0: f64) -> ClosestPoint {
        let (fa, _, pa) = self.f(a, q);
        let (fb, _, pb) = self.f(b, q);
        let best = ClosestPoint::of(a, pa, q).closer(ClosestPoint::of(b, pb, q));
        if !(fa < 0.0 && fb > 0.0) {
            // no interior minimum bracketed: the ends (and the guess) are the candidates
            return best.closer(self.at(t0, q));
        }
        best.closer(self.bracketed(q, a, b, t0))
    }

    /// Safeguarded Newton on `f = c'·(c − q)` in `[a, b]`, `f(a) < 0 < f(b)`, started at `t0`
    /// (bisection whenever Newton leaves the bracket).
    fn bracketed(&self, q: DVec3, a: f64, b: f64, t0: f64) -> ClosestPoint {
        let (mut lo, mut hi) = (a, b);
        let mut t = t0.clamp(a, b);
        for _ in 0..100 {
            let (f, df, _) = self.f(t, q);
            if f == 0.0 {
                break;
            }
            if f < 0.0 {
                lo = t
            } else {
                hi = t
            }
            let mut next = if df > 0.0 { t - f / df } else { f64::NAN };
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            let done = (next - t).abs() <= 1e-15 * (1.0 + t.abs()) || hi - lo <= 1e-15 * (1.0 + t.abs());
            t = next;
            if done {
                break;
            }
        }
        self.at(t, q)
    }
}

/// Grid intervals of [`CurveProjector::refine_nonsmooth`].
const NONSMOOTH_GRID: usize = 8;

#[inline]
fn seg_dist2(a: DVec3, b: DVec3, q: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 {
        ((q - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t).distance_squared(q)
}

impl BSplineCurve {
    /// The closest point of the curve to `q` (convenience; build a
    /// [`CurveProjector`] for many queries).
    pub fn closest_point(&self, q: DVec3) -> ClosestPoint {
        CurveProjector::new(self, 16).project(q)
    }
}
