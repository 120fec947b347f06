//! The discrete fairness energy of the auto-smoothing selection (module docs of `fair::surface`, step 6).

use super::span_grid;
use crate::basis::MAX_ORDER;
use crate::knots::KnotVector;
use crate::surface::BSplineSurface;
use glam::DVec3;

/// Discrete fairness energy used to choose among tolerance-holding candidates (module docs, step 6):
/// the mean curvature H at [`ENERGY_PER_SPAN`] samples per knot span of the moving rectangle and the
/// Dirichlet energy of H on that grid, `Σ_edges (H_a − H_b)² · w_⊥ / |P_a − P_b|` (`w_⊥` the
/// length of the grid cell across the edge), a first-order discretization of `∫∫ |∇H|² dA`.
/// Evaluated separably from basis-derivative tables (O(grid · p)).
pub(super) struct FairnessGrid {
    /// Per u-sample: span and the values, 1st and 2nd derivatives of the p + 1 basis functions.
    bu: Vec<(usize, [[f64; MAX_ORDER]; 3])>,
    bv: Vec<(usize, [[f64; MAX_ORDER]; 3])>,
}

/// Samples per knot span of the fairness energy grid.
pub(crate) const ENERGY_PER_SPAN: usize = 2;

fn basis_table(k: &KnotVector, ts: &[f64]) -> Vec<(usize, [[f64; MAX_ORDER]; 3])> {
    ts.iter()
        .map(|&t| {
            let sp = k.find_span(t);
            let mut d = [[0.0; MAX_ORDER]; 3];
            crate::basis::ders_basis_funs::<3>(k.values(), sp, k.clamp(t), k.degree(), &mut d);
            (sp, d)
        })
        .collect()
}

impl FairnessGrid {
    pub(super) fn new(s: &BSplineSurface, (au, bu): (f64, f64), (av, bv): (f64, f64)) -> Self {
        Self {
            bu: basis_table(s.knots_u(), &span_grid(s.knots_u(), au, bu, ENERGY_PER_SPAN)),
            bv: basis_table(s.knots_v(), &span_grid(s.knots_v(), av, bv, ENERGY_PER_SPAN)),
        }
    }

    pub(super) fn energy(&self, s: &BSplineSurface) -> f64 {
        let mv = self.bv.len();
        let (pu, pv, nv) = (s.degree_u(), s.degree_v(), s.nv());
        let pts = s.points();
        // Row by row of the u samples, with two rows of H and of the points kept: a few kB instead of
        // tables over the grid (freshly allocated per candidate, their page faults were 5 % of a draft)
        let mut tab = vec![[DVec3::ZERO; 3]; nv];
        let (mut h0, mut h1) = (vec![0.0; mv], vec![0.0; mv]);
        let (mut p0, mut p1) = (vec![DVec3::ZERO; mv], vec![DVec3::ZERO; mv]);
        let mut e = 0.0;
        for (k, (sp, d)) in self.bu.iter().enumerate() {
            // Σ_i N_i^{(r)}(u_k) D_ij for r = 0, 1, 2, per j
            tab.fill([DVec3::ZERO; 3]);
            for a in 0..=pu {
                let i = sp - pu + a;
                for (t, &q) in tab.iter_mut().zip(&pts[i * nv..(i + 1) * nv]) {
                    for r in 0..3 {
                        t[r] += q * d[r][a];
                    }
                }
            }
            for (l, (sp, d)) in self.bv.iter().enumerate() {
                let (mut p, mut su, mut sv, mut suu, mut suv, mut svv) = (
                    DVec3::ZERO,
                    DVec3::ZERO,
                    DVec3::ZERO,
                    DVec3::ZERO,
                    DVec3::ZERO,
                    DVec3::ZERO,
                );
                for b in 0..=pv {
                    let t = tab[sp - pv + b];
                    p += t[0] * d[0][b];
                    sv += t[0] * d[1][b];
                    svv += t[0] * d[2][b];
                    su += t[1] * d[0][b];
                    suv += t[1] * d[1][b];
                    suu += t[2] * d[0][b];
                }
                // H = (e L − 2 f M + g N) / (2 det) with L, M, N against the unit normal n / |n|:
                // one square root and one division
                let n = su.cross(sv);
                let (e, f, g) = (su.dot(su), su.dot(sv), sv.dot(sv));
                let det = e * g - f * f;
                let h = (e * svv.dot(n) - 2.0 * f * suv.dot(n) + g * suu.dot(n)) / (2.0 * det * n.length());
                h1[l] = if h.is_finite() { h } else { 0.0 };
                p1[l] = p;
            }
            if k > 0 {
                // the two edges leaving each (k − 1, l), each weighted by the width of its cell across it:
                // lv / lu = lv² / (lu lv), lu / lv = lu² / (lu lv) (one square root, one division)
                for l in 0..mv.saturating_sub(1) {
                    let (lu2, lv2) = ((p0[l] - p1[l]).length_squared(), (p0[l] - p0[l + 1]).length_squared());
                    if lu2 > 0.0 && lv2 > 0.0 {
                        let r = 1.0 / (lu2 * lv2).sqrt();
                        e += (h1[l] - h0[l]).powi(2) * (lv2 * r) + (h0[l + 1] - h0[l]).powi(2) * (lu2 * r);
                    }
                }
            }
            std::mem::swap(&mut h0, &mut h1);
            std::mem::swap(&mut p0, &mut p1);
        }
        e
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fair::surface::span_grid;

    /// The energy by its definition, point by point: H from `BSplineSurface::derivs` at the grid of
    /// [`ENERGY_PER_SPAN`] samples a span, the grid points, then the edge sum over the whole grid.
    fn direct(s: &BSplineSurface, ru: (f64, f64), rv: (f64, f64)) -> f64 {
        let us = span_grid(s.knots_u(), ru.0, ru.1, ENERGY_PER_SPAN);
        let vs = span_grid(s.knots_v(), rv.0, rv.1, ENERGY_PER_SPAN);
        let mut h = vec![];
        let mut p = vec![];
        for &u in &us {
            for &v in &vs {
                let m = s.derivs(u, v).mean_curvature();
                h.push(if m.is_finite() { m } else { 0.0 });
                p.push(s.point(u, v));
            }
        }
        let mv = vs.len();
        let mut e = 0.0;
        for k in 0..us.len() - 1 {
            for l in 0..mv - 1 {
                let i = k * mv + l;
                let (a, b) = (i + mv, i + 1);
                let (lu, lv) = (p[i].distance(p[a]), p[i].distance(p[b]));
                e += (h[a] - h[i]).powi(2) * lv / lu + (h[b] - h[i]).powi(2) * lu / lv;
            }
        }
        e
    }

    /// The separable, row-by-row evaluation (two rows of H and points kept) is the energy of its
    /// definition: a wavy biquadratic × bicubic net with unequal knots and more u than v points, over the
    /// whole domain and over a sub-rectangle.
    #[test]
    fn row_by_row_energy_is_the_direct_sum() {
        let (nu, nv) = (9, 7);
        let ku = vec![0.0, 0.0, 0.0, 0.1, 0.25, 0.3, 0.5, 0.7, 0.85, 1.0, 1.0, 1.0];
        let kv = vec![0.0, 0.0, 0.0, 0.0, 0.2, 0.45, 0.6, 1.0, 1.0, 1.0, 1.0];
        let mut pts = vec![];
        for i in 0..nu {
            for j in 0..nv {
                let (x, y) = (i as f64 / 8.0, j as f64 / 6.0);
                let z = 0.2 * (5.0 * x).sin() * (3.0 * y + 0.3).cos() + 0.01 * ((i * 7 + j * 3) % 5) as f64;
                pts.push(DVec3::new(x + 0.02 * y, y, z));
            }
        }
        let s = BSplineSurface::try_new(2, 3, ku, kv, nu, nv, pts, None).unwrap();
        for (ru, rv) in [((0.0, 1.0), (0.0, 1.0)), ((0.25, 0.85), (0.2, 0.6))] {
            let e = FairnessGrid::new(&s, ru, rv).energy(&s);
            let d = direct(&s, ru, rv);
            assert!(d > 0.0 && (e - d).abs() <= 1e-10 * d, "{ru:?} {rv:?}: {e} against {d}");
        }
    }
}
