//! Arc length: adaptive Gauss–Legendre per knot span, and its inverse.
//!
//! The length of `[u_a, u_b]` is `∫ |c'(u)| du`. [`ArcLengthTable`] splits
//! every knot span adaptively until the 5-point Gauss–Legendre value of a
//! piece agrees with the sum over its two halves to `accuracy` (relative to
//! the piece's length); it stores the cumulative lengths at the piece ends.
//! [`ArcLengthTable::param_at`] inverts `s(u)`: binary search for the piece,
//! a cubic Hermite guess from the end speeds, then Newton on
//! `s(u) − s = 0` (derivative `|c'(u)|`) with bisection as a fallback.

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
}

fn speed(c: &BSplineCurve, u: f64) -> f64 {
    c.d1(u).length()
}

fn piece(c: &BSplineCurve, a: f64, b: f64) -> f64 {
    gl5().integrate(a, b, |u| speed(c, u))
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
        };
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
                t.refine(curve, w[0], m, piece(curve, w[0], m), 0);
                t.refine(curve, m, w[1], piece(curve, m, w[1]), 0);
            }
        }
        t
    }

    fn refine(&mut self, c: &BSplineCurve, a: f64, b: f64, whole: f64, depth: u32) {
        let m = 0.5 * (a + b);
        let l = piece(c, a, m);
        let r = piece(c, m, b);
        self.budget = self.budget.saturating_sub(1);
        if depth >= 40
            || self.budget == 0
            || (whole - (l + r)).abs() <= self.accuracy * (l + r) + self.noise * (b - a)
            || b - a <= 1e-14 * (1.0 + b.abs())
        {
            let s0 = *self.s.last().unwrap();
            self.u.push(m);
            self.s.push(s0 + l);
            self.speed.push(speed(c, m));
            self.u.push(b);
            self.s.push(s0 + l + r);
            self.speed.push(speed(c, b));
        } else {
            self.refine(c, a, m, l, depth + 1);
            self.refine(c, m, b, r, depth + 1);
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
        self.s[j] + piece(curve, self.u[j], u)
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
        // Hermite guess for u(s): du/ds = 1/speed at the ends.
        let t = (s - sa) / ds;
        let du = ub - ua;
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
        let (t2, t3) = (t * t, t * t * t);
        let h = (t3 - 2.0 * t2 + t) * m0 + (-2.0 * t3 + 3.0 * t2) + (t3 - t2) * m1;
        let mut u = ua + du * h.clamp(0.0, 1.0);
        let (mut lo, mut hi) = (ua, ub);
        let tol = self.accuracy * ds.max(1e-300) * 0.5;
        for _ in 0..60 {
            let f = sa + piece(curve, ua, u) - s;
            if f.abs() <= tol {
                return u;
            }
            if f > 0.0 {
                hi = u
            } else {
                lo = u
            }
            let v = speed(curve, u);
            let mut next = if v > 0.0 { u - f / v } else { f64::NAN };
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
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
        out.clear();
        let n = n.max(2);
        let total = self.length();
        let mut j = 0;
        out.push(self.u[0]);
        for k in 1..n - 1 {
            let s = total * k as f64 / (n - 1) as f64;
            while j + 2 < self.s.len() && self.s[j + 1] <= s {
                j += 1;
            }
            out.push(self.invert_in(curve, j, s));
        }
        out.push(*self.u.last().unwrap());
    }

    /// `n` parameters at equal arc length (see [`Self::equal_arc_params_into`]).
    pub fn equal_arc_params(&self, curve: &BSplineCurve, n: usize) -> Vec<f64> {
        let mut v = Vec::with_capacity(n);
        self.equal_arc_params_into(curve, n, &mut v);
        v
    }
}

impl BSplineCurve {
    /// Arc length of the whole curve to relative `accuracy`.
    pub fn length(&self, accuracy: f64) -> f64 {
        ArcLengthTable::new(self, accuracy).length()
    }

    /// Arc length of `[u0, u1]` to relative `accuracy`.
    pub fn length_between(&self, u0: f64, u1: f64, accuracy: f64) -> f64 {
        ArcLengthTable::new_range(self, u0.min(u1), u0.max(u1), accuracy).length()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

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
}
