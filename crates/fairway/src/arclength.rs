//! Arc length: adaptive Gauss–Legendre per knot span, and its inverse.
//!
//! The length of `[u_a, u_b]` is `∫ |c'(u)| du`. [`ArcLengthTable`] splits
//! every knot span adaptively until the 5-point Gauss–Legendre value of a
//! piece agrees with the sum over its two halves to `accuracy` (relative to
//! the piece's length); it stores the cumulative lengths at the piece ends.
//! [`ArcLengthTable::param_at`] inverts `s(u)`: binary search for the piece,
//! a cubic Hermite guess from the end speeds, then Newton on
//! `s(u) − s = 0` (derivative `|c'(u)|`) with bisection as a fallback.
//!
//! Speed: for a non-rational curve of degree ≤ 5, `c'` is a polynomial of
//! degree ≤ 4 on each knot span, so the table stores its exact Taylor
//! expansion about the span's midpoint, `c'(m + h) = c'(m) + c''(m) h +
//! c'''(m) h²/2 + …` (one derivative evaluation per span), and every speed
//! evaluation afterwards is a few multiply-adds instead of a basis
//! evaluation (for a quintic, ~10× cheaper). Other curves evaluate `c'`
//! through the basis.

use glam::DVec3;

use crate::curve::BSplineCurve;
use crate::quadrature::gl5;

/// Cumulative arc-length table over a parameter range of a curve.
#[derive(Debug, Clone, Default)]
pub struct ArcLengthTable {
    u: Vec<f64>,
    s: Vec<f64>,
    speed: Vec<f64>,
    accuracy: f64,
    // absolute rounding floor of the speed per unit parameter in the current span, and the
    // number of refinements left (guarantees termination whatever the input)
    noise: f64,
    budget: usize,
    // exact Taylor form of c' per knot span (empty: evaluate through the basis), and the span of each piece
    polys: Vec<SpanPoly>,
    piece_span: Vec<u32>,
    // with the Taylor form: the quintic Hermite guess's coefficients of each piece (see `invert_in`),
    // computed once (NaN: a zero end speed, the guess is linear)
    herm: Vec<[f64; 4]>,
}

/// Degree of the curves whose speed the table takes from a per-span Taylor form (`c'` of degree ≤ 4).
const TAYLOR_MAX_DEGREE: usize = 5;

/// `c'(m + h) = a + b h + c h² + e₃ h³ + e₄ h⁴` on one knot span (exact for a non-rational curve of degree
/// ≤ 5; `hi` is zero up to degree 3, where the form is the quadratic alone).
#[derive(Debug, Clone, Copy, Default)]
struct SpanPoly {
    m: f64,
    a: DVec3,
    b: DVec3,
    c: DVec3,
    /// `c⁽⁴⁾(m)/6, c⁽⁵⁾(m)/24` (quartic and quintic curves).
    hi: Option<[DVec3; 2]>,
}

impl SpanPoly {
    /// The form on the span of `m` (degree ≤ [`TAYLOR_MAX_DEGREE`], non-rational).
    fn new(curve: &BSplineCurve, m: f64) -> Self {
        if curve.degree() <= 3 {
            let d = curve.derivs(m);
            return Self {
                m,
                a: d.d1,
                b: d.d2,
                c: 0.5 * d.d3,
                hi: None,
            };
        }
        let (kv, p) = (curve.knots().values(), curve.degree());
        let span = curve.knots().find_span(m);
        let mut nd = [[0.0; crate::basis::MAX_ORDER]; TAYLOR_MAX_DEGREE + 1];
        crate::basis::ders_basis_funs(kv, span, curve.knots().clamp(m), p, &mut nd);
        let der = |k: usize| -> DVec3 { (0..=p).map(|j| curve.points()[span - p + j] * nd[k][j]).sum() };
        Self {
            m,
            a: der(1),
            b: der(2),
            c: 0.5 * der(3),
            hi: Some([der(4) / 6.0, der(5) / 24.0]),
        }
    }

    #[inline]
    fn d1(&self, h: f64) -> DVec3 {
        match &self.hi {
            None => self.a + h * (self.b + h * self.c),
            Some([e3, e4]) => self.a + h * (self.b + h * (self.c + h * (*e3 + h * *e4))),
        }
    }

    #[inline]
    fn speed(&self, u: f64) -> f64 {
        self.d1(u - self.m).length()
    }

    /// Speed v and dv/du = c'·c''/v.
    #[inline]
    fn speed_and_slope(&self, u: f64) -> (f64, f64) {
        let h = u - self.m;
        let d1 = self.d1(h);
        let d2 = match &self.hi {
            None => self.b + 2.0 * h * self.c,
            Some([e3, e4]) => self.b + h * (2.0 * self.c + h * (3.0 * *e3 + h * (4.0 * *e4))),
        };
        let v = d1.length();
        (v, if v > 0.0 { d1.dot(d2) / v } else { 0.0 })
    }
}

fn speed(c: &BSplineCurve, u: f64) -> f64 {
    c.d1(u).length()
}

fn piece(c: &BSplineCurve, a: f64, b: f64) -> f64 {
    gl5().integrate(a, b, |u| speed(c, u))
}

/// 5-point Gauss–Legendre nodes and weights on [−1, 1].
const GL5_X: [f64; 5] = [
    -0.906_179_845_938_664,
    -0.538_469_310_105_683,
    0.0,
    0.538_469_310_105_683,
    0.906_179_845_938_664,
];
const GL5_W: [f64; 5] = [
    0.236_926_885_056_189_1,
    0.478_628_670_499_366_5,
    0.568_888_888_888_888_9,
    0.478_628_670_499_366_5,
    0.236_926_885_056_189_1,
];

impl SpanPoly {
    #[inline]
    fn piece(&self, a: f64, b: f64) -> f64 {
        let h = 0.5 * (b - a);
        let c = 0.5 * (a + b);
        let mut s = 0.0;
        for (x, w) in GL5_X.iter().zip(&GL5_W) {
            s += w * self.speed(c + h * x);
        }
        s * h
    }
}

impl ArcLengthTable {
    /// Table over the whole domain. `accuracy` is relative (e.g. `1e-12`).
    pub fn new(curve: &BSplineCurve, accuracy: f64) -> Self {
        let (a, b) = curve.domain();
        Self::new_range(curve, a, b, accuracy)
    }

    /// Table over `[u0, u1]` (clamped to the domain, `u0 ≤ u1`).
    pub fn new_range(curve: &BSplineCurve, u0: f64, u1: f64, accuracy: f64) -> Self {
        let accuracy = accuracy.clamp(1e-15, 1e-2);
        let u0 = curve.knots().clamp(u0);
        let u1 = curve.knots().clamp(u1).max(u0);
        let mut t = Self {
            u: vec![u0],
            s: vec![0.0],
            speed: vec![speed(curve, u0)],
            accuracy,
            noise: 0.0,
            budget: 0,
            polys: Vec::new(),
            piece_span: Vec::new(),
            herm: Vec::new(),
        };
        let fast = curve.weights().is_none() && curve.degree() <= TAYLOR_MAX_DEGREE;
        // Rounding floor: c'(u) = Σ N'_i(u) P_i sums terms of size up to p/Δ·|P|max, so its
        // absolute error is ≈ ε·p/Δ·|P|max (Δ the span width). For a curve far from the
        // origin (coordinates 1e9, size 10) that is far above `accuracy` × length, and
        // halving the pieces would never reach it: accept differences at that floor.
        let pmax = curve.points().iter().map(|q| q.abs().max_element()).fold(0.0, f64::max);
        let wmax = curve.weights().map_or(1.0, |w| {
            let (lo, hi) = w
                .iter()
                .fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
            hi / lo
        });
        let mut bps: Vec<f64> = curve
            .knots()
            .breakpoints()
            .into_iter()
            .filter(|&x| x > u0 && x < u1)
            .collect();
        bps.insert(0, u0);
        bps.push(u1);
        t.budget = 4096 + 512 * bps.len();
        for w in bps.windows(2) {
            if w[1] > w[0] {
                let span = curve.knots().find_span(0.5 * (w[0] + w[1]));
                let kv = curve.knots().values();
                let width = kv[span + 1] - kv[span];
                t.noise = 64.0 * f64::EPSILON * curve.degree() as f64 * pmax * wmax / width;
                // two pieces per span at least: keeps the Hermite guess good
                let m = 0.5 * (w[0] + w[1]);
                if fast {
                    t.polys.push(SpanPoly::new(curve, m));
                }
                let sp = t.polys.len().saturating_sub(1);
                let (l, r) = (t.piece(curve, sp, w[0], m), t.piece(curve, sp, m, w[1]));
                t.refine(curve, sp, w[0], m, l, 0);
                t.refine(curve, sp, m, w[1], r, 0);
            }
        }
        if !t.polys.is_empty() {
            t.herm = (0..t.u.len() - 1).map(|j| t.hermite_coefficients(j)).collect();
        }
        t
    }

    /// The quintic Hermite guess of u(s) on piece `j` (normalized t = (s − s_a)/Δs ↦ (u − u_a)/Δu):
    /// end slopes m = Δs/(v Δu) and second derivatives a = −Δs²/Δu · v'/v³ (du/ds = 1/v,
    /// d²u/ds² = −v'/v³), from the span's Taylor form; NaN where an end speed is zero.
    fn hermite_coefficients(&self, j: usize) -> [f64; 4] {
        let (ua, ub) = (self.u[j], self.u[j + 1]);
        let ds = self.s[j + 1] - self.s[j];
        let du = ub - ua;
        let q = &self.polys[self.span_of(j)];
        let ((va, sla), (vb, slb)) = (q.speed_and_slope(ua), q.speed_and_slope(ub));
        if va > 0.0 && vb > 0.0 {
            [
                ds / va / du,
                ds / vb / du,
                -ds * ds / du * sla / (va * va * va),
                -ds * ds / du * slb / (vb * vb * vb),
            ]
        } else {
            [f64::NAN; 4]
        }
    }

    /// Speed at `u` in span `sp` (the Taylor form when the table has one).
    #[inline]
    fn speed_in(&self, c: &BSplineCurve, sp: usize, u: f64) -> f64 {
        match self.polys.get(sp) {
            Some(q) => q.speed(u),
            None => speed(c, u),
        }
    }

    /// GL5 length of `[a, b]` inside span `sp`.
    #[inline]
    fn piece(&self, c: &BSplineCurve, sp: usize, a: f64, b: f64) -> f64 {
        match self.polys.get(sp) {
            Some(q) => q.piece(a, b),
            None => piece(c, a, b),
        }
    }

    fn refine(&mut self, c: &BSplineCurve, sp: usize, a: f64, b: f64, whole: f64, depth: u32) {
        let m = 0.5 * (a + b);
        let l = self.piece(c, sp, a, m);
        let r = self.piece(c, sp, m, b);
        self.budget = self.budget.saturating_sub(1);
        if depth >= 40
            || self.budget == 0
            || (whole - (l + r)).abs() <= self.accuracy * (l + r) + self.noise * (b - a)
            || b - a <= 1e-14 * (1.0 + b.abs())
        {
            let s0 = *self.s.last().unwrap();
            let (vm, vb) = (self.speed_in(c, sp, m), self.speed_in(c, sp, b));
            self.u.push(m);
            self.s.push(s0 + l);
            self.speed.push(vm);
            self.u.push(b);
            self.s.push(s0 + l + r);
            self.speed.push(vb);
            self.piece_span.extend([sp as u32; 2]);
        } else {
            self.refine(c, sp, a, m, l, depth + 1);
            self.refine(c, sp, m, b, r, depth + 1);
        }
    }

    /// Total length of the range.
    #[inline]
    pub fn length(&self) -> f64 {
        *self.s.last().unwrap()
    }

    /// Parameter range `(u0, u1)` of the table.
    pub fn range(&self) -> (f64, f64) {
        (self.u[0], *self.u.last().unwrap())
    }

    /// Arc length from the start of the range to `u`.
    pub fn length_at(&self, curve: &BSplineCurve, u: f64) -> f64 {
        let (u0, u1) = self.range();
        let u = u.clamp(u0, u1);
        let j = self
            .u
            .partition_point(|&x| x <= u)
            .saturating_sub(1)
            .min(self.u.len() - 2);
        self.s[j] + self.piece(curve, self.span_of(j), self.u[j], u)
    }

    /// The knot span (index into `polys`) of piece `j`.
    #[inline]
    fn span_of(&self, j: usize) -> usize {
        self.piece_span.get(j).map_or(usize::MAX, |&x| x as usize)
    }

    /// The parameter at arc length `s` from the start of the range (clamped
    /// to `[0, length]`), to the table's accuracy.
    pub fn param_at(&self, curve: &BSplineCurve, s: f64) -> f64 {
        let total = self.length();
        if s <= 0.0 {
            return self.u[0];
        }
        if s >= total {
            return *self.u.last().unwrap();
        }
        let j = self
            .s
            .partition_point(|&x| x <= s)
            .saturating_sub(1)
            .min(self.u.len() - 2);
        self.invert_in(curve, j, s)
    }

    fn invert_in(&self, curve: &BSplineCurve, j: usize, s: f64) -> f64 {
        let (ua, ub) = (self.u[j], self.u[j + 1]);
        let (sa, sb) = (self.s[j], self.s[j + 1]);
        let ds = sb - sa;
        if ds <= 0.0 {
            return ua;
        }
        // Hermite guess for u(s): du/ds = 1/v at the ends, and with the Taylor form also
        // d²u/ds² = −v'/v³ (quintic Hermite: the guess is then usually within the tolerance)
        let t = (s - sa) / ds;
        let du = ub - ua;
        let (t2, t3) = (t * t, t * t * t);
        let sp = self.span_of(j);
        let h = match self.herm.get(j) {
            Some(&[m0, m1, a0, a1]) => {
                if !m0.is_nan() {
                    let (t4, t5) = (t3 * t, t3 * t2);
                    (t - 6.0 * t3 + 8.0 * t4 - 3.0 * t5) * m0
                        + 0.5 * (t2 - 3.0 * t3 + 3.0 * t4 - t5) * a0
                        + 0.5 * (t3 - 2.0 * t4 + t5) * a1
                        + (-4.0 * t3 + 7.0 * t4 - 3.0 * t5) * m1
                        + (10.0 * t3 - 15.0 * t4 + 6.0 * t5)
                } else {
                    t
                }
            }
            None => {
                let m0 = if self.speed[j] > 0.0 {
                    ds / self.speed[j] / du
                } else {
                    1.0
                };
                let m1 = if self.speed[j + 1] > 0.0 {
                    ds / self.speed[j + 1] / du
                } else {
                    1.0
                };
                (t3 - 2.0 * t2 + t) * m0 + (-2.0 * t3 + 3.0 * t2) + (t3 - t2) * m1
            }
        };
        let mut u = ua + du * h.clamp(0.0, 1.0);
        let (mut lo, mut hi) = (ua, ub);
        let tol = self.accuracy * ds.max(1e-300) * 0.5;
        for _ in 0..60 {
            let f = sa + self.piece(curve, sp, ua, u) - s;
            if f.abs() <= tol {
                return u;
            }
            if f > 0.0 {
                hi = u
            } else {
                lo = u
            }
            let (v, slope) = match self.polys.get(sp) {
                Some(q) => q.speed_and_slope(u),
                None => (speed(curve, u), f64::INFINITY),
            };
            let mut next = if v > 0.0 { u - f / v } else { f64::NAN };
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            } else if 2.0 * slope.abs() * (f / v) * (f / v) <= tol {
                // Newton on S(u) − s with S' = v, S'' = v': the residual after this step is about
                // |v'|/2 · (f/v)², here below tol/4 — accept it without another quadrature
                return next;
            }
            if (next - u).abs() <= 1e-15 * (1.0 + u.abs()) {
                return next;
            }
            u = next;
        }
        u
    }

    /// `n ≥ 2` parameters at equal arc length over the range, first and last
    /// included, written into `out` (cleared first).
    pub fn equal_arc_params_into(&self, curve: &BSplineCurve, n: usize, out: &mut Vec<f64>) {
        self.equal_arc_params_between(curve, 0.0, self.length(), n, out);
        if let Some(last) = out.last_mut() {
            *last = *self.u.last().unwrap();
        }
    }

    /// `n ≥ 2` parameters at arc lengths `s0 + (s1 − s0)·k/(n − 1)` from the start of the
    /// range (`0 ≤ s0 ≤ s1 ≤ length`), written into `out` (cleared first).
    pub fn equal_arc_params_between(&self, curve: &BSplineCurve, s0: f64, s1: f64, n: usize, out: &mut Vec<f64>) {
        out.clear();
        let n = n.max(2);
        let mut j = 0;
        for k in 0..n {
            let s = s0 + (s1 - s0) * k as f64 / (n - 1) as f64;
            if s <= 0.0 {
                out.push(self.u[0]);
                continue;
            }
            while j + 2 < self.s.len() && self.s[j + 1] <= s {
                j += 1;
            }
            out.push(self.invert_in(curve, j, s.min(self.length())));
        }
    }

    /// `n` parameters at equal arc length (see [`Self::equal_arc_params_into`]).
    pub fn equal_arc_params(&self, curve: &BSplineCurve, n: usize) -> Vec<f64> {
        let mut v = Vec::with_capacity(n);
        self.equal_arc_params_into(curve, n, &mut v);
        v
    }
}

/// Knot spans per stretch of [`BSplineCurve::length`] on a long curve.
pub(crate) const LENGTH_CHUNK_SPANS: usize = 4096;

impl BSplineCurve {
    /// Arc length of the whole curve to relative `accuracy`. A long curve is measured in stretches of
    /// `LENGTH_CHUNK_SPANS` knot spans, each table dropped once summed: memory stays bounded by a
    /// stretch's table, not the curve's (each stretch to relative `accuracy`, so the sum is too).
    pub fn length(&self, accuracy: f64) -> f64 {
        let bp = self.knots().breakpoints();
        if bp.len() <= LENGTH_CHUNK_SPANS + 1 {
            return ArcLengthTable::new(self, accuracy).length();
        }
        (0..bp.len() - 1)
            .step_by(LENGTH_CHUNK_SPANS)
            .map(|k| {
                let b = bp[(k + LENGTH_CHUNK_SPANS).min(bp.len() - 1)];
                ArcLengthTable::new_range(self, bp[k], b, accuracy).length()
            })
            .sum()
    }

    /// Arc length of `[u0, u1]` to relative `accuracy`.
    pub fn length_between(&self, u0: f64, u1: f64, accuracy: f64) -> f64 {
        ArcLengthTable::new_range(self, u0.min(u1), u0.max(u1), accuracy).length()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A curve of more spans than a stretch is measured stretch by stretch: the same length as one table
    /// over the whole curve (to the accuracy asked) and as the sum of the spans' lengths.
    #[test]
    fn a_long_curve_is_measured_in_stretches_to_the_same_length() {
        let n = 2 * LENGTH_CHUNK_SPANS + 700;
        let pts: Vec<glam::DVec2> = (0..n)
            .map(|i| glam::DVec2::new(i as f64 * 0.1, (i as f64 * 0.37).sin() * 0.05))
            .collect();
        let c = BSplineCurve::new_2d(3, crate::KnotVector::uniform(3, n).unwrap().values().to_vec(), &pts).unwrap();
        let whole = ArcLengthTable::new(&c, 1e-12).length();
        let chunked = c.length(1e-12);
        assert!((whole - chunked).abs() <= 1e-11 * whole, "{whole} vs {chunked}");
        let bp = c.knots().breakpoints();
        let by_span: f64 = bp.windows(2).map(|w| c.length_between(w[0], w[1], 1e-12)).sum();
        assert!((by_span - chunked).abs() <= 1e-11 * whole, "{by_span} vs {chunked}");
    }

    #[test]
    fn far_from_origin_the_table_stops_at_the_rounding_floor() {
        // a cubic of size ~10 at 1e9: before the floor, halving never met 1e-12 and ran to depth 40
        let pts: Vec<DVec3> = (0..12)
            .map(|i| DVec3::new(i as f64, ((i * 7) % 3) as f64 * 0.05, 0.0))
            .collect();
        let mut knots = vec![0.0; 4];
        knots.extend((1..9).map(|i| i as f64 / 9.0));
        knots.extend([1.0; 4]);
        let near = BSplineCurve::try_new(3, knots.clone(), pts.clone(), None, 2).unwrap();
        let far_pts = pts.iter().map(|q| *q + DVec3::new(1e9, -1e9, 0.0)).collect();
        let far = BSplineCurve::try_new(3, knots, far_pts, None, 2).unwrap();
        let a = ArcLengthTable::new(&near, 1e-12);
        let b = ArcLengthTable::new(&far, 1e-12);
        assert!(b.u.len() < 2000, "{} pieces", b.u.len());
        assert!((a.length() - b.length()).abs() < 1e-5 * a.length());
        // near the origin the floor is far below the accuracy: same table as before
        assert!(a.u.len() < 200);
        let n = 20000;
        let ref_len: f64 = (0..n)
            .map(|k| gl5().integrate(k as f64 / n as f64, (k + 1) as f64 / n as f64, |x| speed(&near, x)))
            .sum();
        assert!((a.length() - ref_len).abs() < 1e-12 * ref_len);
    }

    #[test]
    fn span_taylor_speed_equals_the_basis_speed() {
        // non-uniform knots, 3D curves of degree 2–5: the per-span Taylor form is c' exactly
        for (p, knots) in [
            (
                3usize,
                vec![0.0, 0.0, 0.0, 0.0, 0.1, 0.35, 0.4, 0.8, 1.0, 1.0, 1.0, 1.0],
            ),
            (2, vec![0.0, 0.0, 0.0, 0.2, 0.5, 0.55, 0.9, 1.0, 1.0, 1.0]),
            (
                4,
                vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.15, 0.3, 0.6, 0.65, 1.0, 1.0, 1.0, 1.0, 1.0],
            ),
            (
                5,
                vec![
                    0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.2, 0.25, 0.7, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0,
                ],
            ),
        ] {
            let n = knots.len() - p - 1;
            let pts: Vec<DVec3> = (0..n)
                .map(|i| DVec3::new(i as f64, ((i * 7) % 3) as f64 * 0.4, ((i * 5) % 4) as f64 * 0.3))
                .collect();
            let c = BSplineCurve::try_new(p, knots, pts, None, 3).unwrap();
            let t = ArcLengthTable::new(&c, 1e-12);
            assert!(!t.polys.is_empty());
            for j in 0..t.u.len() - 1 {
                let u = 0.3 * t.u[j] + 0.7 * t.u[j + 1];
                let (fast, slow) = (t.speed_in(&c, t.span_of(j), u), speed(&c, u));
                assert!(
                    (fast - slow).abs() <= 1e-13 * slow.max(1.0),
                    "p {p} u {u}: {fast} vs {slow}"
                );
                // and its slope dv/du = c'·c''/v, which the inversion's Newton steps use
                let (_, slope) = t.polys[t.span_of(j)].speed_and_slope(u);
                let d = c.derivs(u);
                let exact = d.d1.dot(d.d2) / d.d1.length();
                assert!(
                    (slope - exact).abs() <= 1e-11 * exact.abs().max(1.0),
                    "p {p} u {u}: slope {slope} vs {exact}"
                );
            }
            let m = 20000;
            let ref_len: f64 = (0..m)
                .map(|k| gl5().integrate(k as f64 / m as f64, (k + 1) as f64 / m as f64, |x| speed(&c, x)))
                .sum();
            assert!(
                (t.length() - ref_len).abs() < 1e-12 * ref_len,
                "{} vs {ref_len}",
                t.length()
            );
            // and the inverse lands on the arc length asked for
            for k in 1..10 {
                let s = t.length() * k as f64 / 10.0;
                let u = t.param_at(&c, s);
                // reference: 500 GL5 pieces per knot span piece of [0, u] (never straddling a knot)
                let mut cuts: Vec<f64> = c.knots().breakpoints().into_iter().filter(|&x| x < u).collect();
                cuts.push(u);
                let back: f64 = cuts
                    .windows(2)
                    .map(|w| {
                        (0..500)
                            .map(|i| {
                                let h = (w[1] - w[0]) / 500.0;
                                gl5().integrate(w[0] + h * i as f64, w[0] + h * (i + 1) as f64, |x| speed(&c, x))
                            })
                            .sum::<f64>()
                    })
                    .sum();
                assert!((back - s).abs() < 1e-10 * t.length(), "{back} vs {s}");
            }
        }
    }
}
