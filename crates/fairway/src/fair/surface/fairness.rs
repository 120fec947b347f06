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
        let (mu, mv) = (self.bu.len(), self.bv.len());
        let (pu, pv, nv) = (s.degree_u(), s.degree_v(), s.nv());
        let pts = s.points();
        // Σ_i N_i^{(r)}(u_k) D_ij for r = 0, 1, 2, per (k, j)
        let mut tab = vec![[DVec3::ZERO; 3]; mu * nv];
        let mut hs = Vec::with_capacity(mu * mv);
        let mut ps = Vec::with_capacity(mu * mv);
        for (k, (sp, d)) in self.bu.iter().enumerate() {
            for a in 0..=pu {
                let i = sp - pu + a;
                for j in 0..nv {
                    let q = pts[i * nv + j];
                    let t = &mut tab[k * nv + j];
                    for r in 0..3 {
                        t[r] += q * d[r][a];
                    }
                }
            }
        }
        for k in 0..mu {
            for (sp, d) in &self.bv {
                let (mut p, mut su, mut sv, mut suu, mut suv, mut svv) = (
                    DVec3::ZERO,
                    DVec3::ZERO,
                    DVec3::ZERO,
                    DVec3::ZERO,
                    DVec3::ZERO,
                    DVec3::ZERO,
                );
                for b in 0..=pv {
                    let t = tab[k * nv + sp - pv + b];
                    p += t[0] * d[0][b];
                    sv += t[0] * d[1][b];
                    svv += t[0] * d[2][b];
                    su += t[1] * d[0][b];
                    suv += t[1] * d[1][b];
                    suu += t[2] * d[0][b];
                }
                let n = su.cross(sv).normalize_or_zero();
                let (e, f, g) = (su.dot(su), su.dot(sv), sv.dot(sv));
                let det = e * g - f * f;
                let h = (e * svv.dot(n) - 2.0 * f * suv.dot(n) + g * suu.dot(n)) / (2.0 * det);
                hs.push(if h.is_finite() { h } else { 0.0 });
                ps.push(p);
            }
        }
        let (h, p) = (&hs, &ps);
        let mut e = 0.0;
        let len = |a: usize, b: usize| (p[a] - p[b]).length();
        for k in 0..mu.saturating_sub(1) {
            for l in 0..mv.saturating_sub(1) {
                // the two edges leaving (k, l), each weighted by the width of its cell across it
                let i = k * mv + l;
                let (a, b) = (i + mv, i + 1);
                let (lu, lv) = (len(i, a), len(i, b));
                if lu > 0.0 && lv > 0.0 {
                    e += (h[a] - h[i]).powi(2) * lv / lu + (h[b] - h[i]).powi(2) * lu / lv;
                }
            }
        }
        e
    }
}
