//! The band as the convex hull of the difference curve (issue 28, `docs/PERFORMANCE.md`).
//!
//! The faired and the original curve share knots and degree, so their difference is the B-spline
//! `D(u) = Σ_{i free} N_i(u) ΔP_i`. On each knot span, split at its midpoint, `D` is two Bézier pieces of
//! degree p whose 2p + 1 control points are linear in the p + 1 displacements of the span's control
//! points (blossoms of the span's B-spline, computed by de Boor's recurrence with one argument a level).
//! A curve lies in the convex hull of its Bézier points, and a ball is convex: `|D_k| ≤ m` at every such
//! point bounds `|D(u)| ≤ m` for every u of the span — everywhere, not only at samples — and the
//! parametric distance `|D(u)|` bounds the closest-point distance from the original point `c₀(u)` to the
//! faired curve from above. So these rows, used as band constraints, need no certificate after the
//! solve: the largest `|D_k|` of the result is a sound bound of its deviation.

use super::FairingSetup;
use crate::basis::MAX_ORDER;
use crate::curve::BSplineCurve;

/// The hull rows of the moving stretch: per row, the local index of its first free point (as the check
/// samples' `chk_first`, possibly negative at the stretch's ends) and p + 1 coefficients (as `chk_b`,
/// zero for points that are not free), and the parameter of the span's point the row belongs to.
#[derive(Debug, Clone, Default)]
pub(crate) struct HullRows {
    pub(crate) first: Vec<isize>,
    pub(crate) b: Vec<f64>,
    pub(crate) at: Vec<f64>,
}

impl HullRows {
    /// The rows of every knot span of `work` inside `range` whose control points include a free one
    /// (`i0 .. i0 + nf`): the Bézier points of the span's two halves, the span's start point once.
    pub(crate) fn new(work: &BSplineCurve, range: (f64, f64), i0: usize, nf: usize) -> Self {
        let p = work.degree();
        let kv = work.knots().values();
        let mut out = Self::default();
        let mut first_point_done = false;
        for s in p..kv.len().saturating_sub(p + 1) {
            let (a, b) = (kv[s], kv[s + 1]);
            if !(b > a) || b <= range.0 || a >= range.1 {
                continue;
            }
            let f = (s - p) as isize - i0 as isize;
            if f + (p as isize) < 0 || f >= nf as isize {
                continue;
            }
            let c = 0.5 * (a + b);
            for (half, (lo, hi)) in [(a, c), (c, b)].into_iter().enumerate() {
                for k in 0..=p {
                    // the shared points: the span's start (k = 0 of the first half, kept once per curve:
                    // it is the previous span's end), the midpoint (k = 0 of the second half)
                    if k == 0 && (half == 1 || first_point_done) {
                        continue;
                    }
                    let row = blossom_row(kv, s, p, lo, hi, k);
                    let mut any = false;
                    for (j, &w) in row.iter().enumerate().take(p + 1) {
                        let li = f + j as isize;
                        let inside = li >= 0 && (li as usize) < nf;
                        any |= inside && w != 0.0;
                        out.b.push(if inside { w } else { 0.0 });
                    }
                    if any {
                        out.first.push(f);
                        out.at.push(lo + (hi - lo) * k as f64 / p as f64);
                    } else {
                        out.b.truncate(out.b.len() - (p + 1));
                    }
                }
            }
            first_point_done = true;
        }
        out
    }
}

/// The coefficients of the span `s` control points `P_{s−p} … P_s` in the blossom
/// `f(lo^{p−k}, hi^k)` of the B-spline on knots `kv`: the k-th Bézier point of its piece on `[lo, hi]`
/// (de Boor's recurrence with argument `lo` on the first p − k levels, `hi` on the others).
fn blossom_row(kv: &[f64], s: usize, p: usize, lo: f64, hi: f64, k: usize) -> [f64; MAX_ORDER] {
    let mut d = [[0.0; MAX_ORDER]; MAX_ORDER];
    for (j, row) in d.iter_mut().enumerate().take(p + 1) {
        row[j] = 1.0;
    }
    for r in 1..=p {
        let x = if r <= p - k { lo } else { hi };
        for j in (r..=p).rev() {
            let (t0, t1) = (kv[s + j - p], kv[s + j + 1 - r]);
            let alpha = if t1 > t0 { (x - t0) / (t1 - t0) } else { 0.0 };
            for q in 0..=p {
                d[j][q] = (1.0 - alpha) * d[j - 1][q] + alpha * d[j][q];
            }
        }
    }
    d[p]
}

impl FairingSetup {
    /// `f` with the interior point's band constraints on the hull rows ([`HullRows`]) instead of the
    /// check samples (`chk_first`, `chk_b`, `chk_u` swapped, and back after; the rows are built on the first
    /// call): every iterate then holds the
    /// band everywhere, so the polish needs no margin for a bulge between samples. Only the interior point
    /// may run inside (it reads nothing else of the check samples); nested calls run `f` as they are.
    pub(super) fn on_hull_rows<T>(&mut self, f: impl FnOnce(&mut Self) -> T) -> T {
        if self.hull_band {
            return f(self);
        }
        // built on first use (a setup whose fairs never run the variation polish does not need them)
        if self.hull_rows.first.is_empty() {
            self.hull_rows = HullRows::new(&self.work, self.range, self.i0, self.nf);
        }
        let rows = std::mem::take(&mut self.hull_rows);
        let saved = (
            std::mem::replace(&mut self.chk_first, rows.first),
            std::mem::replace(&mut self.chk_b, rows.b),
            std::mem::replace(&mut self.chk_u, rows.at),
        );
        self.hull_band = true;
        let out = f(self);
        self.hull_band = false;
        let (first, b, at) = (
            std::mem::replace(&mut self.chk_first, saved.0),
            std::mem::replace(&mut self.chk_b, saved.1),
            std::mem::replace(&mut self.chk_u, saved.2),
        );
        self.hull_rows = HullRows { first, b, at };
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn wavy(n: usize, p: usize) -> BSplineCurve {
        let pts: Vec<DVec3> = (0..n)
            .map(|i| {
                let x = i as f64 / (n - 1) as f64;
                DVec3::new(
                    x,
                    0.1 * (7.0 * x).sin() + 0.01 * ((i * 37 % 11) as f64 - 5.0) / 5.0,
                    0.0,
                )
            })
            .collect();
        let mut kv = vec![0.0; p + 1];
        let inner = n - p - 1;
        for i in 1..=inner {
            // unequal spacing
            let t = i as f64 / (inner + 1) as f64;
            kv.push(t + 0.02 * (t * 13.0).sin() / (inner as f64));
        }
        kv.extend(std::iter::repeat_n(1.0, p + 1));
        BSplineCurve::new_3d(p, kv, pts).unwrap()
    }

    /// The rows applied to the control points reproduce the curve at the span ends and midpoints, and
    /// every curve point of a span lies in the convex hull's bounding ball: |c(u) − q| ≤ max_k |P_k − q|
    /// for any q (here each half's first Bézier point).
    #[test]
    fn rows_are_bezier_points_of_the_pieces() {
        for p in 2..=5 {
            let c = wavy(14, p);
            let nf = c.points().len();
            let rows = HullRows::new(&c, c.knots().domain(), 0, nf);
            let pts = c.points();
            let bez: Vec<DVec3> = (0..rows.first.len())
                .map(|r| {
                    (0..=p)
                        .map(|j| {
                            let li = rows.first[r] + j as isize;
                            if li >= 0 && (li as usize) < nf {
                                pts[li as usize] * rows.b[r * (p + 1) + j]
                            } else {
                                DVec3::ZERO
                            }
                        })
                        .sum()
                })
                .collect();
            // the first row is the curve's start, the last its end, every p-th row a span end / midpoint
            for (r, q) in bez.iter().enumerate() {
                if r % p == 0 {
                    let u = rows.at[r];
                    assert!(
                        (c.point(u) - *q).length() < 1e-12,
                        "p {p} row {r}: {:?} vs {:?}",
                        c.point(u),
                        q
                    );
                }
            }
            assert_eq!(rows.first.len(), 2 * p * (c.knots().values().len() - 2 * p - 1) + 1);
            // the hull: a dense scan of each half stays within the largest distance of its Bézier points
            for h in 0..(rows.first.len() - 1) / p {
                let (u0, u1) = (rows.at[h * p], rows.at[(h + 1) * p]);
                let q = bez[h * p];
                let r = bez[h * p..=(h + 1) * p]
                    .iter()
                    .map(|b| (*b - q).length())
                    .fold(0.0, f64::max);
                for i in 0..=50 {
                    let u = u0 + (u1 - u0) * i as f64 / 50.0;
                    assert!((c.point(u) - q).length() <= r * (1.0 + 1e-12) + 1e-15);
                }
            }
        }
    }
}
