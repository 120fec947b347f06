//! A sound bound of the band: how far the original curve is from the faired one, everywhere.
//!
//! The band is the promise that every point of the original lies within `m` of the faired curve
//! (closest-point distance). The fairing engine checks it at a finite set of samples; this module
//! bounds it between them, so that a reported `max_deviation` is a true upper bound whatever the
//! curve's length or knot spacing.
//!
//! For a point c₀(u) of the original and any parameter φ(u) of the faired curve c,
//! dist(c₀(u), c) ≤ |g(u)| with g(u) = c₀(u) − c(φ(u)). On an interval [a, b] where φ is linear,
//! |g(u)| ≤ max(|g(a)|, |g(b)|) + (b − a)²/8 · max |g''| (linear interpolation error, which holds for
//! vectors through the integral form of the remainder), and |g''| ≤ max|c₀''| + φ'² max|c''|. Each
//! max |c''| over a knot span is bounded by the span's second-derivative control points (convex
//! hull). Two choices of φ are used, and the smaller bound kept:
//!
//! * φ(u) = u (the curves share knots and degree): g is the B-spline of the control point
//!   differences, and a whole span is bounded by its p + 1 differences, without any evaluation —
//!   the spans the fair did not move, or moved little, cost nothing;
//! * φ linear between the closest-point parameters of the interval's ends (the faired curve may slide
//!   along the original).
//!
//! The spans are refined largest bound first (sampled at `PIECES` intervals, then bisected) until no
//! interval's bound exceeds the largest sampled distance by more than `SHARPNESS`, or the budget of
//! evaluations is spent: the bound is then the largest interval bound left, still an upper bound.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::DVec3;

use crate::closest::CurveProjector;
use crate::curve::BSplineCurve;

/// Intervals a span is first sampled at once its control-polygon bound has to be sharpened.
pub(crate) const PIECES: usize = 4;
/// Relative excess of an interval's bound over the largest sampled distance that is left unrefined.
pub(crate) const SHARPNESS: f64 = 1e-3;
/// Points of the original [`certify`] may evaluate per knot span (beyond it the bound stays coarser,
/// still sound).
pub(crate) const EVALUATIONS_PER_SPAN: usize = 64;
/// Whole-curve searches for a foot at most (for the few samples that make the bound).
const GLOBAL_SEARCHES: usize = 32;
/// Bisections of a knot span at most (an interval is not split below 2⁻²⁰ of its span).
const MAX_DEPTH: u32 = 20;

/// What [`band_bound`] found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BandBound {
    /// Upper bound of max over the original of the distance to the faired curve.
    pub bound: f64,
    /// The largest distance found at a sampled point (a lower estimate of the true maximum, up to
    /// the projection: each value is the distance to some point of the faired curve).
    pub sampled: f64,
    /// Parameter of the original where the bound is largest.
    pub at: f64,
    /// Points of the original that were evaluated and projected.
    pub evaluations: usize,
}

/// Per knot span bounds of a curve's derivatives (the original's, the faired one's, their difference).
struct SpanBounds {
    /// max |P_i| over the span's p + 1 control points (for the difference curve: the parametric
    /// deviation's bound).
    m0: Vec<f64>,
    /// max |c''| over the span (second-derivative control points).
    m2: Vec<f64>,
}

impl SpanBounds {
    fn new(knots: &[f64], p: usize, pts: &[DVec3]) -> Self {
        let n = pts.len();
        let mut m0 = vec![0.0; n];
        let mut m2 = vec![0.0; n];
        // first- and second-derivative control points (zero where the knot difference vanishes: the
        // basis function they multiply is zero there)
        let q: Vec<DVec3> = (0..n.saturating_sub(1))
            .map(|i| {
                let dk = knots[i + p + 1] - knots[i + 1];
                if dk > 0.0 {
                    (pts[i + 1] - pts[i]) * (p as f64 / dk)
                } else {
                    DVec3::ZERO
                }
            })
            .collect();
        let r: Vec<f64> = if p >= 2 {
            (0..q.len().saturating_sub(1))
                .map(|i| {
                    let dk = knots[i + p + 1] - knots[i + 2];
                    if dk > 0.0 {
                        ((q[i + 1] - q[i]) * ((p - 1) as f64 / dk)).length()
                    } else {
                        0.0
                    }
                })
                .collect()
        } else {
            vec![0.0; n]
        };
        for s in p..n {
            m0[s] = pts[s - p..=s].iter().fold(0.0f64, |a, x| a.max(x.length()));
            m2[s] = if p >= 2 {
                r[s - p..=s - 2].iter().fold(0.0f64, |a, &x| a.max(x))
            } else {
                0.0
            };
        }
        Self { m0, m2 }
    }
}

/// One sampled point of the original: c₀(u), the parameter t of its (approximate) closest point on
/// the faired curve, the distance there, and the parametric distance |c₀(u) − c(u)|.
#[derive(Debug, Clone, Copy)]
struct Sample {
    u: f64,
    t: f64,
    dist: f64,
    pdist: f64,
    /// How far the foot was searched: 0 not trusted yet (Newton did not converge near the guess),
    /// 1 Newton converged near u or a polyline search of the spans around the foot, 2 the whole
    /// curve (only where the bound is above the level to certify).
    level: u8,
}

#[derive(Debug, Clone, Copy)]
struct Piece {
    bound: f64,
    span: usize,
    depth: u32,
    /// `None`: the whole span, bounded by its control polygon only.
    ends: Option<(Sample, Sample)>,
}

impl PartialEq for Piece {
    fn eq(&self, o: &Self) -> bool {
        self.bound.total_cmp(&o.bound) == Ordering::Equal
    }
}
impl Eq for Piece {}
impl PartialOrd for Piece {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Piece {
    fn cmp(&self, o: &Self) -> Ordering {
        self.bound.total_cmp(&o.bound)
    }
}

/// Knot vectors of `a` and `b` made equal (each gets the knots of the other it lacks, with their
/// multiplicity): the same curves on a common refinement. `None` if the degrees or domains differ.
fn common_knots(a: &BSplineCurve, b: &BSplineCurve) -> Option<(BSplineCurve, BSplineCurve)> {
    if a.degree() != b.degree() || a.domain() != b.domain() {
        return None;
    }
    if a.knots().values() == b.knots().values() {
        return Some((a.clone(), b.clone()));
    }
    let missing = |x: &BSplineCurve, y: &BSplineCurve| -> Vec<f64> {
        let mut out = vec![];
        for k in y.knots().breakpoints() {
            let (mx, my) = (x.knots().multiplicity(k), y.knots().multiplicity(k));
            out.extend(std::iter::repeat_n(k, my.saturating_sub(mx)));
        }
        out
    };
    let (ma, mb) = (missing(a, b), missing(b, a));
    Some((a.refine(&ma).ok()?, b.refine(&mb).ok()?))
}

/// Upper bound of max over u ∈ domain of the distance from `original(u)` to the curve `faired`
/// (see the module docs). `level` is the band to certify: feet are searched over the whole curve
/// (a pass over it each) only for the samples whose bound is above it. `None` where the bound does not apply: rational curves, different degree
/// or domain. `budget` caps the evaluations (at least one sampling of every span that needs one is
/// not guaranteed beyond it: the bound then stays the control polygon's, still an upper bound).
pub fn band_bound(original: &BSplineCurve, faired: &BSplineCurve, level: f64, budget: usize) -> Option<BandBound> {
    if original.is_rational() || faired.is_rational() {
        return None;
    }
    let (c0, c) = common_knots(original, faired)?;
    let mut search = BandSearch::new(&c0, &c);
    let mut heap = search.initial_pieces();
    let mut out = BandBound {
        bound: 0.0,
        sampled: 0.0,
        at: search.d0,
        evaluations: 0,
    };
    while let Some(piece) = heap.pop() {
        // no interval left exceeds the sampled maximum by more than SHARPNESS (nor `level`, unless
        // by no more than rounding): the bound is its bound
        let sharp = piece.bound <= out.sampled * (1.0 + SHARPNESS) + search.slack;
        if sharp && (piece.bound <= level || piece.bound <= out.sampled * (1.0 + 1e-6) + search.slack) {
            heap.push(piece);
            break;
        }
        let new_samples = match piece.ends {
            None => match search.sample_span(piece.span, budget, &mut out) {
                Some(v) => v,
                None => {
                    heap.push(piece);
                    break;
                }
            },
            Some((l, r)) => match search.refine_ends(piece, l, r, level, budget, &mut out, &mut heap) {
                Some(v) => v,
                None => continue,
            },
        };
        search.push_halves(&new_samples, piece, &mut out, &mut heap);
    }
    search.finish(&heap, &mut out);
    Some(out)
}

/// The state of [`band_bound`]'s search: the two curves on common knots, their span bounds, the
/// rounding slack, the faired curve's corners, and the projector for the feet searched further.
struct BandSearch<'a> {
    c0: &'a BSplineCurve,
    c: &'a BSplineCurve,
    p: usize,
    kv: Vec<f64>,
    bd: SpanBounds,
    b0: SpanBounds,
    bc: SpanBounds,
    slack: f64,
    d0: f64,
    d1: f64,
    closed: bool,
    periodic: bool,
    /// The faired curve's interior C0 breakpoints (its corners).
    corners: Vec<f64>,
    projector: Option<CurveProjector<'a>>,
    /// Whole-curve searches done so far (at most GLOBAL_SEARCHES).
    globals: usize,
}

impl<'a> BandSearch<'a> {
    /// Setup: span bounds of the difference and of both curves, rounding slack, closedness, and
    /// the corners, all read once before the search.
    fn new(c0: &'a BSplineCurve, c: &'a BSplineCurve) -> Self {
        let p = c0.degree();
        let kv = c0.knots().values().to_vec();
        let n = c0.n_points();
        let diff: Vec<DVec3> = c0.points().iter().zip(c.points()).map(|(a, b)| *a - *b).collect();
        let bd = SpanBounds::new(&kv, p, &diff);
        let b0 = SpanBounds::new(&kv, p, c0.points());
        let bc = SpanBounds::new(&kv, p, c.points());
        // rounding of the evaluations: a few ulps of the coordinates' magnitude
        let scale = b0.m0.iter().chain(&bc.m0).fold(0.0f64, |a, &x| a.max(x));
        let slack = 64.0 * f64::EPSILON * scale;
        let (d0, d1) = c0.domain();
        let closed = c.points()[0].distance(c.points()[n - 1]) <= slack;
        let periodic = closed && {
            let (ta, tb) = (c.derivs(d0).d1, c.derivs(d1).d1);
            (ta - tb).length() <= 1e-9 * ta.length().max(tb.length())
        };
        // the faired curve's interior C0 breakpoints (its corners): a closest point there is not a
        // stationary point of the distance, so Newton cannot find it; they are tried directly
        let corners: Vec<f64> = {
            let kn = c.knots();
            let bp = kn.breakpoints();
            bp[1..bp.len().saturating_sub(1)]
                .iter()
                .copied()
                .filter(|&k| kn.multiplicity(k) >= p)
                .collect()
        };
        Self {
            c0,
            c,
            p,
            kv,
            bd,
            b0,
            bc,
            slack,
            d0,
            d1,
            closed,
            periodic,
            corners,
            projector: None,
            globals: 0,
        }
    }

    /// Seeding: one piece per nonempty span where the curves differ, bounded by the control
    /// polygon of the difference.
    fn initial_pieces(&self) -> BinaryHeap<Piece> {
        let mut heap = BinaryHeap::new();
        for s in self.p..self.c0.n_points() {
            if self.kv[s + 1] > self.kv[s] && self.bd.m0[s] > 0.0 {
                heap.push(Piece {
                    bound: self.bd.m0[s] + self.slack,
                    span: s,
                    depth: 0,
                    ends: None,
                });
            }
        }
        heap
    }

    /// The spans of c covering [t_a, t_b]: max |c''| there.
    fn m2_faired(&self, ta: f64, tb: f64) -> f64 {
        let (lo, hi) = (ta.min(tb), ta.max(tb));
        let s0 = self.c.knots().find_span(lo);
        let s1 = self.c.knots().find_span_from(hi, s0);
        (s0..=s1).fold(0.0f64, |a, s| a.max(self.bc.m2[s]))
    }

    /// The corner of the faired curve in [lo, hi] nearest to `q` (ties: nearest to `t`), as
    /// (parameter, distance).
    fn nearest_corner(&self, q: DVec3, t: f64, lo: f64, hi: f64) -> Option<(f64, f64)> {
        let i = self.corners.partition_point(|&k| k < lo);
        self.corners[i..]
            .iter()
            .take_while(|&&k| k <= hi)
            .map(|&k| (k, self.c.point(k).distance(q)))
            .min_by(|a, b| a.1.total_cmp(&b.1).then((a.0 - t).abs().total_cmp(&(b.0 - t).abs())))
    }

    /// Sampling one point c₀(u): its foot on the faired curve by Newton from `t_guess` (across
    /// the seam of a closed curve, or at a corner), and how far that foot is trusted.
    fn sample(&self, u: f64, t_guess: f64, level: u8, span: usize, evals: &mut usize) -> Sample {
        let (c0, c, p, d0, d1) = (self.c0, self.c, self.p, self.d0, self.d1);
        *evals += 1;
        let e0 = c0.derivs2_from(u, span).0;
        let q = e0.p;
        let pdist = (q - c.point_from(u, span)).length();
        let ((mut t, mut dist, mut speed), mut converged) = closest_near(c, q, t_guess, d0, d1, span);
        // a closed curve: a foot stopped at one end of the domain may continue past the seam
        if self.closed && (t == d0 || t == d1) {
            let other = if t == d0 { d1 } else { d0 };
            let ((t2, dist2, speed2), conv2) = closest_near(c, q, other, d0, d1, 0);
            if dist2 < dist {
                (t, dist, speed, converged) = (t2, dist2, speed2, conv2);
            }
        }
        let (mut t, mut dist) = if pdist <= dist { (u, pdist) } else { (t, dist) };
        // a foot Newton reached near the guess is trusted locally (level 1); one it did not
        // converge to, that slid more than a span from u, or where the faired curve nearly stops
        // (a cusp: Newton settles there without a minimum) is searched around first (level 0)
        let sk = c.knots().find_span(t);
        let kvc = c.knots().values();
        let width = kvc[sk + 1] - kvc[sk];
        let mut trusted = converged && (t - u).abs() <= width && speed >= 0.05 * e0.d1.length();
        // a corner of the faired curve in the spans around the foot may be nearer
        let (lo, hi) = (kvc[sk.saturating_sub(1).max(p)], kvc[(sk + 2).min(kvc.len() - p - 1)]);
        if let Some((k, dk)) = self.nearest_corner(q, t, lo, hi)
            && dk < dist
        {
            (t, dist) = (k, dk);
            trusted = (t - u).abs() <= 2.0 * width;
        }
        Sample {
            u,
            t,
            dist,
            pdist,
            level: if trusted { level.max(1) } else { level },
        }
    }

    /// A foot searched one level further (see `Sample::level`); the whole-curve search at most
    /// GLOBAL_SEARCHES times (each costs a pass over the curve).
    fn sharpen(&mut self, x: &mut Sample, global: bool) {
        let (c0, c, p) = (self.c0, self.c, self.p);
        let q = c0.point(x.u);
        let proj = self.projector.get_or_insert_with(|| CurveProjector::new(c, 16));
        let found = if x.level == 0 {
            let kv = c.knots().values();
            let s = c.knots().find_span(x.t);
            let (lo, hi) = (kv[s.saturating_sub(8).max(p)], kv[(s + 9).min(kv.len() - p - 1)]);
            Some(proj.project_between(q, lo, hi))
        } else if global && self.globals < GLOBAL_SEARCHES {
            self.globals += 1;
            Some(proj.project(q))
        } else {
            None
        };
        if let Some(f) = found
            && f.distance < x.dist
        {
            x.t = f.param;
            x.dist = f.distance;
        }
        x.level += 1;
    }

    /// Bounding an interval between two samples: the smaller of the parametric bound and the
    /// projection bound (piecewise where the feet cross corners of the faired curve).
    fn bound_of(&self, a: &Sample, b: &Sample, span: usize) -> f64 {
        let (c0, c, d0, d1) = (self.c0, self.c, self.d0, self.d1);
        let (bd, b0, corners) = (&self.bd, &self.b0, &self.corners);
        let h = b.u - a.u;
        let e = h * h / 8.0;
        let param = a.pdist.max(b.pdist) + e * bd.m2[span];
        // feet on either side of the seam of a C1-closed curve: φ runs across it (c is C1 there,
        // so g' is continuous and the interpolation bound holds with c'' from both ends)
        let (dt, m2c) = if self.periodic && (b.t - a.t).abs() > 0.5 * (d1 - d0) {
            let (lo, hi) = if a.t > b.t { (a.t, b.t) } else { (b.t, a.t) };
            let l = d1 - d0;
            let dt = if b.t < a.t { b.t + l - a.t } else { b.t - l - a.t };
            (dt, self.m2_faired(lo, d1).max(self.m2_faired(d0, hi)))
        } else {
            (b.t - a.t, self.m2_faired(a.t, b.t))
        };
        let s = dt / h;
        let (lo, hi) = (a.t.min(b.t), a.t.max(b.t));
        let i0 = corners.partition_point(|&k| k <= lo);
        let crossed = &corners[i0..i0 + corners[i0..].partition_point(|&k| k < hi)];
        let proj = if crossed.is_empty() || (b.t - a.t).abs() > 0.5 * (d1 - d0) {
            a.dist.max(b.dist) + e * (b0.m2[span] + s * s * m2c)
        } else {
            // φ crosses C0 knots of c (c' jumps there, so g is not C1): φ piecewise linear instead,
            // through each crossed knot k at the proportional u, where |g| is evaluated; the
            // interpolation bound on each piece (the slope s is the same on all)
            let mut nodes = a.dist.max(b.dist);
            let mut curv = 0.0f64;
            let mut prev = a.t;
            let ordered: Vec<f64> = if dt > 0.0 {
                crossed.to_vec()
            } else {
                crossed.iter().rev().copied().collect()
            };
            for &k in ordered.iter().chain(std::iter::once(&b.t)) {
                let hk = h * (k - prev) / dt;
                curv = curv.max(hk * hk / 8.0 * (b0.m2[span] + s * s * self.m2_faired(prev, k)));
                if k != b.t {
                    let uk = a.u + h * (k - a.t) / dt;
                    nodes = nodes.max(c0.point(uk).distance(c.point(k)));
                }
                prev = k;
            }
            nodes + curv
        };
        param.min(proj) + self.slack
    }

    /// First refinement of a whole span: PIECES + 1 equally spaced samples, each foot guessed
    /// from the previous one. `None` when that would exceed `budget` (the search stops).
    fn sample_span(&self, s: usize, budget: usize, out: &mut BandBound) -> Option<Vec<Sample>> {
        let (a, b) = (self.kv[s], self.kv[s + 1]);
        if out.evaluations + PIECES + 1 > budget {
            return None;
        }
        let mut v: Vec<Sample> = Vec::with_capacity(PIECES + 1);
        for k in 0..=PIECES {
            let u = if k == PIECES {
                b
            } else {
                a + (b - a) * k as f64 / PIECES as f64
            };
            let guess = v.last().map_or(u, |x| x.t + (u - x.u));
            v.push(self.sample(u, guess, 0, s, &mut out.evaluations));
        }
        Some(v)
    }

    /// Refinement of an interval between two samples: sharpen its ends' feet first where they make
    /// its bound, else settle it at the depth or budget limit, else bisect it (the midpoint's
    /// samples returned). `None` when the piece was requeued or settled instead.
    #[allow(clippy::too_many_arguments)]
    fn refine_ends(
        &mut self,
        piece: Piece,
        mut l: Sample,
        mut r: Sample,
        level: f64,
        budget: usize,
        out: &mut BandBound,
        heap: &mut BinaryHeap<Piece>,
    ) -> Option<Vec<Sample>> {
        let s = piece.span;
        // an interval whose bound the ends' distances make: search their feet further first
        // (Newton may have stopped at a local minimum, on another branch, at a cusp)
        // (over the whole curve only for a foot that seems outside the band: there a
        // nearer pass of the curve decides the certificate; elsewhere bisection does)
        let global = l.dist.max(r.dist) > level;
        let wants = |x: &Sample| x.level == 0 || (x.level == 1 && global);
        if (wants(&l) || wants(&r)) && l.dist.max(r.dist) >= 0.5 * piece.bound {
            for x in [&mut l, &mut r] {
                if wants(x) {
                    self.sharpen(x, global);
                }
            }
            out.evaluations += 2;
            out.sampled = out.sampled.max(searched(&l).max(searched(&r)));
            heap.push(Piece {
                bound: self.bound_of(&l, &r, s),
                ends: Some((l, r)),
                ..piece
            });
            return None;
        }
        if piece.depth >= MAX_DEPTH || out.evaluations + 1 > budget {
            // cannot refine further: it stays as it is (an upper bound)
            if piece.bound > out.bound {
                out.bound = piece.bound;
                out.at = 0.5 * (l.u + r.u);
            }
            return None;
        }
        // the midpoint's foot from each end's shift t − u: where the ends' feet are on
        // different branches (a curve passing q twice, points slid along a line that doubles
        // back), each half keeps its own end's branch
        let um = 0.5 * (l.u + r.u);
        let (shift_l, shift_r) = (l.t - l.u, r.t - r.u);
        let ml = self.sample(um, um + shift_l, 0, s, &mut out.evaluations);
        let mr = if (shift_l - shift_r).abs() <= 1e-9 * (self.d1 - self.d0) || out.evaluations + 1 > budget {
            ml
        } else {
            self.sample(um, um + shift_r, 0, s, &mut out.evaluations)
        };
        Some(vec![l, ml, mr, r])
    }

    /// Requeueing: the new samples' trusted distances raise the sampled maximum, and each
    /// consecutive pair (the two halves, for a bisection) becomes a piece one level deeper.
    fn push_halves(&self, new_samples: &[Sample], piece: Piece, out: &mut BandBound, heap: &mut BinaryHeap<Piece>) {
        let s = piece.span;
        let pairs: Vec<(Sample, Sample)> = if new_samples.len() == 4 {
            vec![(new_samples[0], new_samples[1]), (new_samples[2], new_samples[3])]
        } else {
            new_samples.windows(2).map(|w| (w[0], w[1])).collect()
        };
        // the distance found at each new point whose foot is trusted (the smaller of a midpoint's two
        // feet)
        let found = match new_samples.len() {
            4 => searched(&new_samples[1]).min(searched(&new_samples[2])),
            _ => new_samples.iter().fold(0.0f64, |a, x| a.max(searched(x))),
        };
        out.sampled = out.sampled.max(found);
        for (a, b) in pairs {
            let w = [a, b];
            heap.push(Piece {
                bound: self.bound_of(&w[0], &w[1], s),
                span: s,
                depth: piece.depth + 1,
                ends: Some((w[0], w[1])),
            });
        }
    }

    /// Finish: the largest bound left in the queue (if above the settled ones) and the sampled
    /// maximum make the result.
    fn finish(&self, heap: &BinaryHeap<Piece>, out: &mut BandBound) {
        if let Some(top) = heap.peek()
            && top.bound > out.bound
        {
            out.bound = top.bound;
            out.at = match top.ends {
                Some((l, r)) => 0.5 * (l.u + r.u),
                None => 0.5 * (self.kv[top.span] + self.kv[top.span + 1]),
            };
        }
        out.bound = out.bound.max(out.sampled);
    }
}

/// The distance at a sample whose foot is trusted (a lower estimate of the true maximum).
fn searched(x: &Sample) -> f64 {
    if x.level >= 1 { x.dist } else { 0.0 }
}

/// The closest point of `c` to `q` near the parameter `t`: Newton from `t`, and where it does not
/// converge (a concave stretch, a point of zero speed, a step that leaves the domain), Newton again
/// from the best point of a polyline over the knot spans around `t`. The best point met, as
/// (parameter, distance), and whether a Newton iteration converged to it. Any parameter gives an upper bound of the distance, so a start that leads
/// nowhere costs sharpness, not soundness.
fn closest_near(c: &BSplineCurve, q: DVec3, t: f64, d0: f64, d1: f64, hint: usize) -> ((f64, f64, f64), bool) {
    let (best, converged) = newton(c, q, t, d0, d1, hint);
    if converged {
        return (best, true);
    }
    let kv = c.knots().values();
    let p = c.degree();
    let s = c.knots().find_span(t.clamp(d0, d1));
    let (lo, hi) = (kv[s.saturating_sub(2).max(p)], kv[(s + 3).min(kv.len() - p - 1)]);
    let mut scan = (best.0, best.1);
    for k in 0..=32 {
        let x = lo + (hi - lo) * k as f64 / 32.0;
        let d = c.point(x).distance(q);
        if d < scan.1 {
            scan = (x, d);
        }
    }
    let (again, converged) = newton(c, q, scan.0, d0, d1, hint);
    if again.1 < scan.1 {
        (again, converged)
    } else {
        ((scan.0, scan.1, c.d1(scan.0).length()), false)
    }
}

/// [`band_bound`] with the engine's budget ([`EVALUATIONS_PER_SPAN`] per knot span): the bound the
/// fairing routes report as `max_deviation`.
pub(crate) fn certify(original: &BSplineCurve, faired: &BSplineCurve, m: f64) -> Option<BandBound> {
    band_bound(
        original,
        faired,
        m,
        EVALUATIONS_PER_SPAN * original.knots().n_spans() + 4096,
    )
}

/// Newton iteration for the closest point of `c` to `q` from `t` (clamped to [d0, d1]): the best
/// point met as (parameter, distance, speed |c'| there), and whether the steps converged.
fn newton(c: &BSplineCurve, q: DVec3, t: f64, d0: f64, d1: f64, hint: usize) -> ((f64, f64, f64), bool) {
    let mut t = t.clamp(d0, d1);
    let mut best = (t, f64::INFINITY, 0.0);
    let mut span = hint;
    for _ in 0..10 {
        let d;
        (d, span) = c.derivs2_from(t, span);
        let r = d.p - q;
        let dist = r.length();
        if dist < best.1 {
            best = (t, dist, d.d1.length());
        }
        if dist == 0.0 {
            return (best, true);
        }
        let g = d.d1.dot(r);
        let h = d.d1.length_squared() + d.d2.dot(r);
        if !(h > 0.0) {
            return (best, false);
        }
        let next = (t - g / h).clamp(d0, d1);
        if (next - t).abs() <= 1e-14 * (d1 - d0) {
            // converged, or stopped at a domain end where the distance still falls outward
            return (best, true);
        }
        t = next;
    }
    (best, false)
}

/// Rounds of midpoint knot insertion at most in [`surface_band_bound`].
const SURFACE_ROUNDS: usize = 5;
/// Control points of the refined difference net at most (the bound stays coarser beyond, still sound).
const SURFACE_NET_LIMIT: usize = 1 << 21;

/// Upper bound of max over the domain of the parametric deviation |S₀(u, v) − S(u, v)| of two
/// surfaces on the same degrees, knots and weights (polynomial, or rational with equal weight nets) —
/// hence of the distance from every point of `original` to `faired`. The difference is itself a
/// (rational) B-spline surface on those knots and weights, with the control point differences as its
/// points, so each patch lies in the convex hull of its (p + 1)(q + 1) difference points and is bounded
/// by the largest (the rational basis is non-negative and sums to one, as the polynomial one); the
/// patches above `level` are refined by inserting their spans' midpoints (in homogeneous form: the
/// weighted differences and the weights, each a polynomial net; the net converges to the surface
/// quadratically), for a few rounds. `None` where the bound does not apply (other degrees, knots or
/// weights). A bound above `level` certifies nothing about the closest-point distance, which can be
/// smaller where the fair slid the surface along itself.
pub fn surface_band_bound(
    original: &crate::surface::BSplineSurface,
    faired: &crate::surface::BSplineSurface,
    level: f64,
) -> Option<f64> {
    if original.weights() != faired.weights()
        || original.degree_u() != faired.degree_u()
        || original.degree_v() != faired.degree_v()
        || original.knots_u() != faired.knots_u()
        || original.knots_v() != faired.knots_v()
    {
        return None;
    }
    let mut net = DifferenceNet::new(original, faired);
    let mut bound = 0.0;
    for round in 0..=SURFACE_ROUNDS {
        let (b, hot_u, hot_v) = net.patch_bounds(level);
        bound = b;
        if bound <= level || round == SURFACE_ROUNDS || !net.refine(&hot_u, &hot_v)? {
            break;
        }
    }
    Some(bound)
}

/// The control net of the difference of two surfaces on the same knots and weights, in homogeneous
/// form: `d = w · (P₀ − P)` and the weights `w` (all 1 for polynomial surfaces), row-major (point (i, j)
/// at i·nv + j, i along u).
struct DifferenceNet {
    p: usize,
    q: usize,
    ku: Vec<f64>,
    kv: Vec<f64>,
    nu: usize,
    nv: usize,
    d: Vec<DVec3>,
    /// The weights as the x of points (refined as a polynomial net, like `d`); `None`: all 1.
    w: Option<Vec<DVec3>>,
    /// Rounding allowance added to each patch's bound.
    slack: f64,
}

impl DifferenceNet {
    fn new(original: &crate::surface::BSplineSurface, faired: &crate::surface::BSplineSurface) -> Self {
        let w: Option<Vec<DVec3>> = original
            .weights()
            .map(|w| w.iter().map(|&x| DVec3::new(x, 0.0, 0.0)).collect());
        let weight = |k: usize| w.as_ref().map_or(1.0, |w| w[k].x);
        let d = (original.points().iter().zip(faired.points()).enumerate())
            .map(|(k, (a, b))| (*a - *b) * weight(k))
            .collect();
        let scale = original
            .points()
            .iter()
            .chain(faired.points())
            .fold(0.0f64, |a, x| a.max(x.length()));
        // the weighted differences and their division by the refined weights round relative to the
        // largest over the smallest weight
        let (wmin, wmax) = original.weights().map_or((1.0, 1.0), |w| {
            w.iter().fold((f64::MAX, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)))
        });
        Self {
            p: original.degree_u(),
            q: original.degree_v(),
            ku: original.knots_u().values().to_vec(),
            kv: original.knots_v().values().to_vec(),
            nu: original.nu(),
            nv: original.nv(),
            d,
            w,
            slack: 64.0 * f64::EPSILON * scale * (wmax / wmin),
        }
    }

    /// The largest patch bound (each patch: its largest difference point, plus the slack) and the spans
    /// (u, v) of the patches above `level`.
    fn patch_bounds(&self, level: f64) -> (f64, Vec<bool>, Vec<bool>) {
        let (p, q, nv) = (self.p, self.q, self.nv);
        let (mut hot_u, mut hot_v) = (vec![false; self.nu], vec![false; nv]);
        let mut bound = 0.0f64;
        let point = |k: usize| self.d[k].length() / self.w.as_ref().map_or(1.0, |w| w[k].x);
        for su in (p..self.nu).filter(|&s| self.ku[s + 1] > self.ku[s]) {
            for sv in (q..nv).filter(|&s| self.kv[s + 1] > self.kv[s]) {
                let b = (su - p..=su)
                    .flat_map(|i| (sv - q..=sv).map(move |j| i * nv + j))
                    .map(point)
                    .fold(0.0f64, f64::max)
                    + self.slack;
                bound = bound.max(b);
                if b > level {
                    hot_u[su] = true;
                    hot_v[sv] = true;
                }
            }
        }
        (bound, hot_u, hot_v)
    }

    /// Insert the midpoints of the hot spans, along u then along v; `Some(false)` when the refined net
    /// would pass [`SURFACE_NET_LIMIT`] (nothing done), `None` if a refinement fails.
    fn refine(&mut self, hot_u: &[bool], hot_v: &[bool]) -> Option<bool> {
        let mids = |k: &[f64], hot: &[bool]| -> Vec<f64> {
            (0..hot.len())
                .filter(|&s| hot[s])
                .map(|s| 0.5 * (k[s] + k[s + 1]))
                .collect()
        };
        let (mu, mv) = (mids(&self.ku, hot_u), mids(&self.kv, hot_v));
        if (self.nu + mu.len()) * (self.nv + mv.len()) > SURFACE_NET_LIMIT {
            return Some(false);
        }
        let (ku, kv) = (self.ku.clone(), self.kv.clone());
        let along_u = |net: &[DVec3]| refine_rows(&ku, self.p, self.nu, self.nv, net, &mu);
        let along_v = |net: &[DVec3], nu: usize| {
            let (k, nv, t) = refine_rows(&kv, self.q, self.nv, nu, &transpose(net, nu, self.nv), &mv)?;
            Some((k, nv, transpose(&t, nv, nu)))
        };
        let (ku, nu, d) = along_u(&self.d)?;
        let (kv, nv, d) = along_v(&d, nu)?;
        if let Some(w) = &self.w {
            let (_, _, w) = along_u(w)?;
            self.w = Some(along_v(&w, nu)?.2);
        }
        (self.ku, self.kv, self.nu, self.nv, self.d) = (ku, kv, nu, nv, d);
        Some(true)
    }
}

/// A row-major `rows × cols` net transposed (`cols × rows`).
fn transpose(net: &[DVec3], rows: usize, cols: usize) -> Vec<DVec3> {
    (0..cols)
        .flat_map(|j| (0..rows).map(move |i| net[i * cols + j]))
        .collect()
}

/// The knots `ins` inserted along the first index of a row-major `n × cols` net of degree `deg` on the
/// knots `k` (each column a curve), one at a time in the order given, as
/// [`BSplineCurve::insert_knot`] inserts them into each column (the same arithmetic: the result is that
/// of refining the columns one by one, bit for bit; test `net_refinement_is_the_columns_refinement`),
/// with each knot's coefficients computed once for all columns: the new knots, the new n and the new
/// net. `None` where a knot is not inside the domain or already of multiplicity `deg`.
fn refine_rows(
    k: &[f64],
    deg: usize,
    n: usize,
    cols: usize,
    net: &[DVec3],
    ins: &[f64],
) -> Option<(Vec<f64>, usize, Vec<DVec3>)> {
    let (mut knots, mut n) = (k.to_vec(), n);
    let mut cur = net.to_vec();
    let mut next = Vec::with_capacity((n + ins.len()) * cols);
    for &u in ins {
        if !(u > knots[deg] && u < knots[n]) {
            return None;
        }
        let span = crate::knots::find_span(&knots, deg, n, u);
        let (lo, hi) = (knots.partition_point(|&v| v < u), knots.partition_point(|&v| v <= u));
        if hi - lo >= deg {
            return None;
        }
        next.clear();
        next.extend_from_slice(&cur[..(span + 1 - deg) * cols]);
        for i in span + 1 - deg..=span {
            let alpha = (u - knots[i]) / (knots[i + deg] - knots[i]);
            let (a, b) = (&cur[i * cols..(i + 1) * cols], &cur[(i - 1) * cols..i * cols]);
            next.extend(a.iter().zip(b).map(|(x, y)| *x * alpha + *y * (1.0 - alpha)));
        }
        next.extend_from_slice(&cur[span * cols..]);
        knots.insert(hi, u);
        n += 1;
        std::mem::swap(&mut cur, &mut next);
    }
    Some((knots, n, cur))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wavy(n: usize, amp: f64, phase: f64) -> BSplineCurve {
        let pts: Vec<glam::DVec2> = (0..n)
            .map(|i| {
                let x = i as f64 / (n - 1) as f64;
                glam::DVec2::new(x, 0.2 * (3.0 * x).sin() + amp * (i as f64 * 1.7 + phase).sin())
            })
            .collect();
        let mut knots = vec![0.0; 4];
        knots.extend((1..n - 3).map(|i| i as f64 / (n - 3) as f64));
        knots.extend([1.0; 4]);
        BSplineCurve::new_2d(3, knots, &pts).unwrap()
    }

    /// Dense independent check: the true max over 50 000 points of the original of the distance to
    /// the faired curve (closest points by the projector's polyline search) never exceeds the bound,
    /// and the bound is within a few per cent of it.
    #[test]
    fn the_bound_holds_and_is_sharp() {
        for (n, amp) in [(12, 0.01), (40, 0.003), (200, 0.001)] {
            let a = wavy(n, amp, 0.0);
            let b = wavy(n, amp, 1.3);
            let bb = band_bound(&a, &b, 0.0, usize::MAX).unwrap();
            let proj = CurveProjector::new(&b, 64);
            let truth = (0..=50_000)
                .map(|k| proj.project(a.point(k as f64 / 50_000.0)).distance)
                .fold(0.0f64, f64::max);
            assert!(bb.bound >= truth, "n {n}: bound {} < dense {truth}", bb.bound);
            assert!(bb.bound <= truth * 1.01, "n {n}: bound {} ≫ dense {truth}", bb.bound);
            assert!(bb.sampled <= bb.bound);
        }
    }

    /// The net refinement inserts each knot into every column exactly as [`BSplineCurve::refine`] does
    /// column by column (bit for bit), refuses knots outside the domain or of full multiplicity as it
    /// does, and the refined columns are the same curves (evaluated).
    #[test]
    fn net_refinement_is_the_columns_refinement() {
        let (deg, n, cols) = (3, 9, 4);
        let k = vec![0.0, 0.0, 0.0, 0.0, 0.1, 0.35, 0.5, 0.5, 0.8, 1.0, 1.0, 1.0, 1.0];
        let net: Vec<DVec3> = (0..n * cols)
            .map(|i| DVec3::new((i as f64 * 0.37).sin(), (i as f64 * 1.3).cos(), i as f64 * 0.01))
            .collect();
        let ins = [0.05, 0.5, 0.9, 0.225, 0.05, 0.65];
        let (k2, n2, net2) = refine_rows(&k, deg, n, cols, &net, &ins).unwrap();
        assert_eq!(n2, n + ins.len());
        for c in 0..cols {
            let col: Vec<DVec3> = (0..n).map(|r| net[r * cols + c]).collect();
            let curve = BSplineCurve::new_3d(deg, k.clone(), col).unwrap();
            let refined = curve.refine(&ins).unwrap();
            assert_eq!(refined.knots().values(), &k2[..]);
            let got: Vec<DVec3> = (0..n2).map(|r| net2[r * cols + c]).collect();
            assert_eq!(refined.points(), &got[..], "column {c}");
            let again = BSplineCurve::new_3d(deg, k2.clone(), got).unwrap();
            for t in 0..=40 {
                let u = t as f64 / 40.0;
                assert!(again.point(u).distance(curve.point(u)) < 1e-14);
            }
        }
        // 0.5 has multiplicity 2: one more insertion makes it 3 = deg, a second is refused (as by the curve)
        let col0 = BSplineCurve::new_3d(deg, k.clone(), (0..n).map(|r| net[r * cols]).collect()).unwrap();
        assert!(col0.refine(&[0.5, 0.5]).is_err() && col0.refine(&[0.5]).is_ok());
        assert!(refine_rows(&k, deg, n, cols, &net, &[0.5, 0.5]).is_none());
        assert!(refine_rows(&k, deg, n, cols, &net, &[0.5]).is_some());
        assert!(refine_rows(&k, deg, n, cols, &net, &[1.0]).is_none());
        assert!(refine_rows(&k, deg, n, cols, &net, &[-0.1]).is_none());
    }

    #[test]
    fn identical_curves_cost_nothing() {
        let a = wavy(30, 0.01, 0.0);
        let bb = band_bound(&a, &a, 0.0, usize::MAX).unwrap();
        assert_eq!(bb.evaluations, 0);
        assert_eq!(bb.bound, 0.0);
    }

    /// Inserted knots in one curve (a G0 region end): the common refinement gives the same bound as
    /// the curves themselves.
    #[test]
    fn different_knots_are_refined_to_common_ones() {
        let a = wavy(20, 0.01, 0.0);
        let b = wavy(20, 0.01, 0.4);
        let plain = band_bound(&a, &b, 0.0, usize::MAX).unwrap();
        let b2 = b.insert_knot(0.37, 3).unwrap();
        let refined = band_bound(&a, &b2, 0.0, usize::MAX).unwrap();
        assert!((plain.sampled - refined.sampled).abs() <= 2e-3 * plain.sampled);
        assert!(refined.bound >= plain.sampled);
    }

    /// A tiny budget leaves the bound coarse but still above the truth.
    #[test]
    fn a_spent_budget_still_bounds() {
        let a = wavy(60, 0.01, 0.0);
        let b = wavy(60, 0.01, 2.0);
        let full = band_bound(&a, &b, 0.0, usize::MAX).unwrap();
        let coarse = band_bound(&a, &b, 0.0, 10).unwrap();
        assert!(coarse.evaluations <= 10);
        assert!(coarse.bound >= full.sampled);
    }

    fn bumpy(n: usize, amp: f64, phase: f64) -> crate::surface::BSplineSurface {
        let k = crate::KnotVector::uniform(3, n).unwrap().values().to_vec();
        let mut pts = vec![];
        for i in 0..n {
            for j in 0..n {
                let (x, y) = (i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64);
                pts.push(DVec3::new(
                    x,
                    y,
                    0.3 * (2.0 * x).sin() * y + amp * ((i * 3 + j * 7) as f64 + phase).sin(),
                ));
            }
        }
        crate::surface::BSplineSurface::try_new(3, 3, k.clone(), k, n, n, pts, None).unwrap()
    }

    /// The surface bound: exact for a constant offset; above the parametric deviation sampled densely
    /// (41 × 41 points a patch pair … 4000 × 4000 in all would be slow: 201 × 201 over the domain) and,
    /// refined towards 0, within 2 % of it; `None` for other knots.
    /// The bound of `c` against `a` is above their distance on an `n × n` grid, refined (tolerance 0) no
    /// larger than the coarse one and within 2 % of the grid's.
    fn assert_bound_holds_and_sharpens(
        a: &crate::surface::BSplineSurface,
        c: &crate::surface::BSplineSurface,
        n: usize,
    ) {
        let t = |i: usize| i as f64 / n as f64;
        let dense = (0..=n)
            .flat_map(|i| (0..=n).map(move |j| (t(i), t(j))))
            .map(|(u, v)| (a.point(u, v) - c.point(u, v)).length())
            .fold(0.0f64, f64::max);
        let coarse = surface_band_bound(a, c, f64::INFINITY).unwrap();
        let sharp = surface_band_bound(a, c, 0.0).unwrap();
        assert!(
            coarse >= sharp && sharp >= dense,
            "coarse {coarse} sharp {sharp} dense {dense}"
        );
        assert!(sharp <= dense * 1.02, "sharp {sharp} vs dense {dense}");
    }

    #[test]
    fn the_surface_bound_holds_and_sharpens() {
        let a = bumpy(12, 0.01, 0.0);
        let up = a
            .with_points(a.points().iter().map(|p| *p + DVec3::new(0.0, 0.0, 0.004)).collect())
            .unwrap();
        let b = surface_band_bound(&a, &up, 1.0).unwrap();
        assert!((b - 0.004).abs() <= 1e-12, "offset: {b}");
        assert_bound_holds_and_sharpens(&a, &bumpy(12, 0.01, 1.1), 200);
        let other = bumpy(13, 0.01, 0.0);
        assert!(surface_band_bound(&a, &other, 1.0).is_none());
    }

    /// A rational surface: weights in [0.3, 3] (unequal, as a CAD system's NURBS face), the same
    /// weights on both sides.
    fn weighted(s: &crate::surface::BSplineSurface) -> crate::surface::BSplineSurface {
        let w: Vec<f64> = (0..s.points().len())
            .map(|k| 10f64.powf(0.5 * ((k as f64) * 0.9).sin()))
            .collect();
        let (ku, kv) = (s.knots_u().values().to_vec(), s.knots_v().values().to_vec());
        crate::surface::BSplineSurface::try_new(3, 3, ku, kv, s.nu(), s.nv(), s.points().to_vec(), Some(w)).unwrap()
    }

    /// The surface bound of two rational surfaces with the same weights: exact for a constant offset
    /// (the rational basis sums to one), above the deviation sampled densely and, refined towards 0,
    /// within 2 % of it; `None` where the weights differ (the difference is then no surface on them).
    #[test]
    fn the_surface_bound_holds_for_rational_surfaces_with_the_same_weights() {
        let a = weighted(&bumpy(12, 0.01, 0.0));
        assert!(!a.is_polynomial());
        let up = a
            .with_points(a.points().iter().map(|p| *p + DVec3::new(0.0, 0.003, 0.004)).collect())
            .unwrap();
        let b = surface_band_bound(&a, &up, 1.0).unwrap();
        assert!((b - 0.005).abs() <= 1e-12, "offset: {b}");
        let c = a.with_points(bumpy(12, 0.01, 1.1).points().to_vec()).unwrap();
        assert_bound_holds_and_sharpens(&a, &c, 300);
        let reweighted = crate::surface::BSplineSurface::try_new(
            3,
            3,
            a.knots_u().values().to_vec(),
            a.knots_v().values().to_vec(),
            12,
            12,
            a.points().to_vec(),
            Some(vec![1.0; 144]),
        )
        .unwrap();
        assert!(surface_band_bound(&a, &reweighted, 1.0).is_none());
    }
}
