//! The band checks at the check samples and the Newton projection that sharpens them (module docs of
//! `fair::curve`, step 6).

use glam::DVec3;

use super::FairingSetup;
use crate::basis::{MAX_ORDER, ders_basis_funs};
use crate::curve::BSplineCurve;

/// The deviation the band check accepts for tolerance `m` on `curve`: `m (1 − 1e-9)`, less 16 units of
/// rounding of the coordinates (`16 ε max|P|`). Distances between points of that magnitude are only known
/// to a few ulps, and `measure` computes them by another path: far from the origin (coordinates 1e7,
/// ulp 4e-9) a result verified against m itself measured up to 2e-5·m above it (probe campaign). Below
/// that rounding (m ≲ 1e-14 max|P|) nothing moves (α = 0: the original).
pub(crate) fn band_accept(m: f64, curve: &BSplineCurve) -> f64 {
    let (lo, hi) = curve.control_bounds();
    let scale = lo.abs().max(hi.abs()).max_element();
    m * (1.0 - 1e-9) - 16.0 * f64::EPSILON * scale
}

impl FairingSetup {
    /// The band's check parameters inside the moving stretch (the original's arc-length samples, see
    /// [`Self::new_with_ends_phase`]); empty with `check_samples = 0`.
    pub(crate) fn check_params(&self) -> &[f64] {
        &self.chk_u
    }

    /// Check samples whose distance to the curve `c_orig + Σ N_i d_i` exceeds `level`: those whose
    /// parametric displacement is above it, confirmed by a Newton projection (started one Newton step
    /// from u_j with the cached derivative rows, stopped as soon as a point within `level` is found:
    /// the displacement at equal u overestimates where the curve slid along itself).
    pub(super) fn band_samples(&mut self, d: &[DVec3], level: f64) -> Vec<usize> {
        let np1 = self.work.degree() + 1;
        let mut pad = std::mem::take(&mut self.pad);
        pad.clear();
        pad.resize(self.nf + 2 * np1, DVec3::ZERO);
        pad[np1..np1 + self.nf].copy_from_slice(d);
        let mut cache = std::mem::take(&mut self.chk_d);
        let mut cand: Option<BSplineCurve> = None;
        let mut out = vec![];
        for j in 0..self.chk_u.len() {
            let (rows, delta) = self.chk_rows(&pad, j);
            if delta.length() <= level {
                continue;
            }
            if cand.is_none() {
                cand = self.updated_curve(d).ok();
            }
            let far = cand.as_ref().is_none_or(|c| {
                let start = self.first_newton_step(j, rows, delta, &mut cache);
                project_near(c, self.chk_q[j], self.chk_u[j], self.chk_h, start, level) > level
            });
            if far {
                out.push(j);
            }
        }
        self.chk_d = cache;
        self.pad = pad;
        out
    }

    /// Upper bound of the max over the check samples of the distance from the
    /// original sample to the curve `c_orig + Σ N_i d_i`. Samples whose
    /// parametric distance exceeds `sharpen` are projected (Newton near u_j).
    pub(super) fn deviation(&mut self, d: &[DVec3], sharpen: f64) -> f64 {
        let p = self.work.degree();
        // d padded with p + 1 zeros on both sides: every check sample's p + 1 rows are in bounds
        // (its first row f ≥ −p, f + p < nf + p + 1), so the inner loop has no branch
        let off = p + 1;
        let mut pad = std::mem::take(&mut self.pad);
        pad.clear();
        pad.resize(self.nf + 2 * off, DVec3::ZERO);
        pad[off..off + self.nf].copy_from_slice(d);
        let mut cache = std::mem::take(&mut self.chk_d);
        // the common degrees with the row count known at compile time (an unrolled inner loop)
        let (worst, broken_at) = match self.work.degree() {
            3 if self.work.dim() == 2 => self.scan::<4, true>(&pad, d, sharpen, &mut cache),
            2 => self.scan::<3, false>(&pad, d, sharpen, &mut cache),
            3 => self.scan::<4, false>(&pad, d, sharpen, &mut cache),
            4 => self.scan::<5, false>(&pad, d, sharpen, &mut cache),
            5 => self.scan::<6, false>(&pad, d, sharpen, &mut cache),
            _ => self.scan::<0, false>(&pad, d, sharpen, &mut cache),
        };
        if let Some(j) = broken_at {
            self.scan_from = j;
        }
        self.chk_d = cache;
        self.pad = pad;
        worst
    }

    /// Check sample j's p + 1 rows of the padded update `pad` (see [`Self::deviation`]) and the
    /// displacement `Σ N_i(u_j) d_i` they give.
    #[inline]
    pub(super) fn chk_rows<'a>(&self, pad: &'a [DVec3], j: usize) -> (&'a [DVec3], DVec3) {
        let np1 = self.work.degree() + 1;
        let base = (self.chk_first[j] + np1 as isize) as usize;
        let rows = &pad[base..base + np1];
        let mut delta = DVec3::ZERO;
        for (x, b) in rows.iter().zip(&self.chk_b[j * np1..(j + 1) * np1]) {
            delta += *x * *b;
        }
        (rows, delta)
    }

    /// The parameter after one Newton step of the projection of check sample j's original point q onto
    /// the updated curve, started at u_j where the update (its p + 1 padded rows `rows`) moved the
    /// curve by `delta`: c(u_j) − q = delta, and c', c'' there come from the sample's cached
    /// derivative rows (computed on first use), so the step needs no curve evaluation.
    fn first_newton_step(&self, j: usize, rows: &[DVec3], delta: DVec3, cache: &mut Vec<Option<ChkDeriv>>) -> f64 {
        let p = self.work.degree();
        let u = self.chk_u[j];
        if p > 3 {
            return u;
        }
        if cache.len() != self.chk_u.len() {
            cache.clear();
            cache.resize(self.chk_u.len(), None);
        }
        let e = *cache[j].get_or_insert_with(|| {
            let f = self.chk_first[j];
            let span = (f + (p + self.i0) as isize) as usize;
            let mut nd = [[0.0; MAX_ORDER]; 3];
            ders_basis_funs(self.work.knots().values(), span, self.work.knots().clamp(u), p, &mut nd);
            let mut e = ChkDeriv::default();
            for i in 0..=p {
                let q = self.work.points()[span - p + i];
                e.d1 += q * nd[1][i];
                e.d2 += q * nd[2][i];
                let li = f + i as isize;
                if li >= 0 && (li as usize) < self.nf {
                    e.b1[i] = nd[1][i];
                    e.b2[i] = nd[2][i];
                }
            }
            e
        });
        let (mut d1, mut d2) = (e.d1, e.d2);
        for (i, x) in rows.iter().enumerate() {
            d1 += *x * e.b1[i];
            d2 += *x * e.b2[i];
        }
        let (f, df) = (d1.dot(delta), d2.dot(delta) + d1.length_squared());
        if df > 0.0 { u - f / df } else { u }
    }

    /// The band check's scan over the check samples; `N` = p + 1, or 0 for "read it from the curve".
    /// Samples below the band are compared by squared length (the square root only of the maximum:
    /// the same value, since the root is monotone and correctly rounded). The scan starts at
    /// `self.scan_from` and wraps around: the maximum is the same in any order, and a broken band
    /// returns the first violation found (callers only compare it with `sharpen`) and where.
    fn scan<const N: usize, const PLANE: bool>(
        &self,
        pad: &[DVec3],
        d: &[DVec3],
        sharpen: f64,
        cache: &mut Vec<Option<ChkDeriv>>,
    ) -> (f64, Option<usize>) {
        let np1 = if N > 0 { N } else { self.work.degree() + 1 };
        let off = np1;
        let sharpen2 = sharpen * sharpen;
        let (mut worst2, mut worst_sharp) = (0.0f64, 0.0f64);
        let mut cand: Option<BSplineCurve> = None;
        let n = self.chk_u.len();
        let from = if self.scan_from < n { self.scan_from } else { 0 };
        for j in (from..n).chain(0..from) {
            let base = (self.chk_first[j] + off as isize) as usize;
            let w = &self.chk_b[j * np1..(j + 1) * np1];
            let rows = &pad[base..base + np1];
            // 2D (`PLANE`): z is 0 in every row, so only x and y are summed (the same value)
            let delta = if PLANE {
                let (mut x, mut y) = (0.0, 0.0);
                for (r, b) in rows.iter().zip(w) {
                    x += r.x * *b;
                    y += r.y * *b;
                }
                DVec3::new(x, y, 0.0)
            } else {
                let mut delta = DVec3::ZERO;
                for (x, b) in rows.iter().zip(w) {
                    delta += *x * *b;
                }
                delta
            };
            let len2 = delta.length_squared();
            // NaN-safe: a NaN update is "above the band"
            if !(len2 <= sharpen2) {
                let mut dist = len2.sqrt();
                if cand.is_none() {
                    cand = self.updated_curve(d).ok();
                }
                if let Some(c) = &cand {
                    let start = self.first_newton_step(j, rows, delta, cache);
                    dist = dist.min(project_near(
                        c,
                        self.chk_q[j],
                        self.chk_u[j],
                        self.chk_h,
                        start,
                        sharpen,
                    ));
                }
                if !(dist <= sharpen) {
                    // the band is broken: callers only compare with `sharpen`, so stop here
                    return (dist, Some(j));
                }
                worst_sharp = worst_sharp.max(dist);
            } else {
                worst2 = worst2.max(len2);
            }
        }
        (worst2.sqrt().max(worst_sharp), None)
    }
}

/// Cached derivative data of one check sample (degree ≤ 3): the first and second derivatives of the
/// free rows' basis functions at u_j (zero for held rows) and the original's c'(u_j), c''(u_j).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct ChkDeriv {
    b1: [f64; 4],
    b2: [f64; 4],
    d1: DVec3,
    d2: DVec3,
}

/// Distance from `q` to the best point of `c` found by safeguarded Newton on
/// `c'(t)·(c(t) − q)` in `[u − w, u + w]`, started at `start` (clamped to it). Every evaluated
/// point is on the curve, so the result bounds the true distance from above.
/// Stops as soon as a point within `enough` is found (the band check only
/// needs to know that the distance is below the band).
pub(crate) fn project_near(c: &BSplineCurve, q: DVec3, u: f64, w: f64, start: f64, enough: f64) -> f64 {
    newton_distance(c, q, u, w, start, enough, false)
}

/// The Newton search of [`project_near`] (`widen` false: 12 steps in a fixed window; `widen` true:
/// 40 steps, the window doubling up to the whole domain when Newton wants to leave it).
#[inline(always)]
fn newton_distance(c: &BSplineCurve, q: DVec3, u: f64, w: f64, start: f64, enough: f64, widen: bool) -> f64 {
    let (d0, d1) = c.domain();
    let window = |w: f64| ((u - w).max(d0), (u + w).min(d1));
    let mut w = w;
    let (mut lo, mut hi) = window(w);
    let mut t = match (start.is_finite(), widen) {
        (false, _) => u,
        (true, false) => start.clamp(lo, hi),
        (true, true) => start.clamp(d0, d1),
    };
    // the point alone first: near the band edge one Newton step from u_j usually lands within `enough`
    let mut best = c.point(t).distance(q);
    if best <= enough {
        return best;
    }
    let mut span = 0;
    for _ in 0..if widen { 40 } else { 12 } {
        let d;
        (d, span) = c.derivs2_from(t, span);
        let r = d.p - q;
        best = best.min(r.length());
        if best <= enough {
            return best;
        }
        let f = d.d1.dot(r);
        let mut df = d.d2.dot(r) + d.d1.length_squared();
        if !(df > 0.0) {
            if !widen {
                return best;
            }
            // where the curve bends away from q, Newton has no minimum to aim at: a Gauss–Newton step
            // (the curve's tangent line's foot) still moves towards one
            df = d.d1.length_squared();
            if !(df > 0.0) {
                return best;
            }
        }
        let want = t - f / df;
        if widen && ((want < lo && lo > d0) || (want > hi && hi < d1)) {
            w = (2.0 * w).max(f64::MIN_POSITIVE);
            (lo, hi) = window(w);
        }
        let nt = want.clamp(lo, hi);
        if (nt - t).abs() <= 1e-15 * (1.0 + t.abs()) {
            return best;
        }
        t = nt;
    }
    // the last step's point (not evaluated in the loop)
    best.min(c.point(t).distance(q))
}
