//! The torsion-variation energy of a non-planar 3D curve, which `E_var` does not see: fairing κ alone
//! leaves the torsion to the noise (a noisy helix keeps τ ripples at every knot).
//!
//! What is faired is `t = κ² τ / κ_max² = (c'×c'')·c''' / (|c'|⁶ κ_max²)` (κ_max the original's largest
//! curvature on the stretch): the torsion weighted by how much the curve bends there. τ alone is
//! meaningless where the curve is nearly straight (it divides by |c'×c''|²) and would pull such stretches
//! about for nothing; `t` is a polynomial over |c'|⁶, vanishes there, and is τ itself on a helix.
//! `t` is sampled at [`TWIST_PROBES`] points of every knot span, both span ends included as one-sided
//! limits, and the energy is the sum over consecutive samples of `(Δt)² / Δs` ≈ `∫ (dt/ds)² ds`: inside a
//! span a difference quotient, across a knot the step there (a cubic's c''' jumps at every simple knot,
//! and that is where the noise sits) priced as [`super::variation::JUMP_WEIGHT`] prices a curvature step.

use glam::DVec3;

use super::variation::JUMP_WEIGHT;
use crate::basis::{MAX_ORDER, ders_basis_funs};
use crate::curve::BSplineCurve;
use crate::linalg::BandedSpd;

/// Torsion samples per knot span, both ends included.
pub(crate) const TWIST_PROBES: usize = 4;

/// The original's torsion energy is scaled down to at most this many times its E_var
/// ([`TwistRows::cap_to`]). Measured (`examples/real_curves.rs` on the 66 distinct curves of a public
/// impeller model, `examples/quality_table.rs` on the suite's 15 3D rows): 1 keeps too little of the
/// term (a noisy helix keeps 14 of its 33 torsion extrema); no cap lets it dominate curves that twist
/// more than they bend (3 fewer curves as fair as the reference smoother); 10 gives 52 of 66 as fair
/// (52 without the term), torsion extrema 270 (361 without the term, the smoother 117) and 417 on the
/// suite (712 without, the smoother 451).
pub(crate) const TWIST_CAP: f64 = 10.0;

/// One torsion sample: the first free-local index of its p + 1 basis functions, their 1st–3rd
/// derivatives (0 for held points) and the original's c', c'', c''' there.
#[derive(Debug, Clone)]
struct Sample {
    first: isize,
    b: [[f64; MAX_ORDER]; 3],
    c: [DVec3; 3],
}

/// The rows of `E_tor` over the moving stretch, scaled by the torsion weight.
#[derive(Debug, Clone, Default)]
pub(crate) struct TwistRows {
    samples: Vec<Sample>,
    /// Consecutive samples `(a, b, w)`: the residual is `√w (τ_b − τ_a)`.
    pairs: Vec<(usize, usize, f64)>,
    kmax: f64,
}

impl TwistRows {
    /// The rows of the free points `i0 .. i0 + nf` over the knot spans inside `range`, with `weight` (the
    /// torsion weight) folded in; empty below degree 3 (c''' = 0: no torsion).
    pub(crate) fn new(work: &BSplineCurve, range: (f64, f64), i0: usize, nf: usize, weight: f64, kmax: f64) -> Self {
        let p = work.degree();
        let mut rows = Self {
            kmax,
            ..Self::default()
        };
        if p < 3 || !(weight > 0.0 && kmax > 0.0) {
            return rows;
        }
        let kv = work.knots().values();
        let cp = work.points();
        let bps: Vec<f64> = work
            .knots()
            .breakpoints()
            .iter()
            .copied()
            .filter(|&x| x >= range.0 && x <= range.1)
            .collect();
        let mut ders = [[0.0; MAX_ORDER]; 4];
        for (k, w) in bps.windows(2).enumerate() {
            let (a, b) = (w[0], w[1]);
            let span = work.knots().find_span(0.5 * (a + b));
            let first_here = rows.samples.len();
            for j in 0..TWIST_PROBES {
                let u = a + (b - a) * j as f64 / (TWIST_PROBES - 1) as f64;
                ders_basis_funs(kv, span, u, p, &mut ders);
                let f = (span - p) as isize - i0 as isize;
                let mut s = Sample {
                    first: f,
                    b: [[0.0; MAX_ORDER]; 3],
                    c: [DVec3::ZERO; 3],
                };
                for i in 0..=p {
                    let li = f + i as isize;
                    let inside = li >= 0 && (li as usize) < nf;
                    for o in 0..3 {
                        s.b[o][i] = if inside { ders[o + 1][i] } else { 0.0 };
                        s.c[o] += cp[span - p + i] * ders[o + 1][i];
                    }
                }
                rows.samples.push(s);
            }
            // inside the span: (Δτ)² / Δs with Δs ≈ the mean speed × Δu
            for j in first_here..first_here + TWIST_PROBES - 1 {
                let speed = 0.5 * (rows.samples[j].c[0].length() + rows.samples[j + 1].c[0].length());
                let ds = speed * (b - a) / (TWIST_PROBES - 1) as f64;
                if ds > 0.0 {
                    rows.pairs.push((j, j + 1, weight / ds));
                }
            }
            // across the knot before this span: its step, priced like a curvature step
            if k > 0 {
                let (l, r) = (first_here - 1, first_here);
                let speed = 0.5 * (rows.samples[l].c[0].length() + rows.samples[r].c[0].length());
                let du = 0.5 * (b - bps[k - 1]);
                if speed > 0.0 && du > 0.0 {
                    rows.pairs.push((l, r, weight * JUMP_WEIGHT / (speed * du)));
                }
            }
        }
        rows
    }

    /// Scales the rows down so that the original's torsion energy is at most `e_var` (a multiple of the
    /// original's E_var, [`TWIST_CAP`]): the term is there to fair the torsion alongside the curvature,
    /// not to outweigh it on a curve that twists much more than it bends (τ ≫ κ) or whose curvature is
    /// already fair.
    pub(crate) fn cap_to(&mut self, np1: usize, e_var: f64) {
        let e_tor = self.energy(np1, &[]);
        if e_tor > e_var && e_tor > 0.0 {
            let f = e_var.max(0.0) / e_tor;
            for pair in &mut self.pairs {
                pair.2 *= f;
            }
        }
    }

    /// Multiplies the rows' weights by `f`.
    pub(crate) fn scale(&mut self, f: f64) {
        for pair in &mut self.pairs {
            pair.2 *= f;
        }
    }

    /// Whether there is anything to fair.
    pub(crate) fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// How many more points than p + 1 a residual's row spans.
    pub(crate) fn reach(&self) -> usize {
        self.pairs
            .iter()
            .map(|&(a, b, _)| (self.samples[b].first - self.samples[a].first).unsigned_abs())
            .max()
            .unwrap_or(0)
    }

    fn derivs(&self, k: usize, np1: usize, d: &[DVec3]) -> [DVec3; 3] {
        let s = &self.samples[k];
        let mut c = s.c;
        for i in 0..np1 {
            let li = s.first + i as isize;
            if li < 0 || li as usize >= d.len() {
                continue;
            }
            for (o, co) in c.iter_mut().enumerate() {
                *co += d[li as usize] * s.b[o][i];
            }
        }
        c
    }

    /// `E_tor` (weighted) of `c₀ + Σ N_i d_i`.
    pub(crate) fn energy(&self, np1: usize, d: &[DVec3]) -> f64 {
        let tau: Vec<f64> = (0..self.samples.len())
            .map(|k| {
                let c = self.derivs(k, np1, d);
                twist(c[0], c[1], c[2], self.kmax).0
            })
            .collect();
        self.pairs.iter().map(|&(a, b, w)| w * (tau[b] - tau[a]).powi(2)).sum()
    }

    /// Adds `JᵀJ` to `h` and `−Jᵀr` to `rhs` for `weight · E_tor` at the update `d` (unknown
    /// `li · 3 + c`, as [`super::variation::VarRows::variation_system`]).
    pub(crate) fn system(&self, np1: usize, nf: usize, d: &[DVec3], weight: f64, h: &mut BandedSpd, rhs: &mut [DVec3]) {
        let grads: Vec<(f64, [DVec3; 3])> = (0..self.samples.len())
            .map(|k| {
                let c = self.derivs(k, np1, d);
                twist(c[0], c[1], c[2], self.kmax)
            })
            .collect();
        let mut row = Vec::new();
        for &(a, b, w) in &self.pairs {
            let (sa, sb) = (&self.samples[a], &self.samples[b]);
            let f0 = sa.first.min(sb.first);
            let base = f0.max(0) as usize;
            let end = (sa.first.max(sb.first) + np1 as isize).min(nf as isize);
            if end <= f0.max(0) {
                continue;
            }
            let width = (end - f0.max(0)) as usize * 3;
            row.clear();
            row.resize(width, 0.0);
            let sw = (weight * w).sqrt();
            let r = sw * (grads[b].0 - grads[a].0);
            for (s, g, sign) in [(sa, &grads[a].1, -1.0), (sb, &grads[b].1, 1.0)] {
                for i in 0..np1 {
                    let li = s.first + i as isize;
                    if li < 0 || li as usize >= nf {
                        continue;
                    }
                    let gi = g[0] * s.b[0][i] + g[1] * s.b[1][i] + g[2] * s.b[2][i];
                    let off = (li as usize - base) * 3;
                    for cc in 0..3 {
                        row[off + cc] += sign * sw * gi[cc];
                    }
                }
            }
            for (k, x) in row.iter().enumerate() {
                rhs[base * 3 + k].x -= x * r;
            }
            h.add_outer(base * 3, &row);
        }
    }
}

/// `κ² τ / κ_max² = (c1×c2)·c3 / (|c1|⁶ κ_max²)` and its gradients with respect to c1, c2, c3.
pub(crate) fn twist(c1: DVec3, c2: DVec3, c3: DVec3, kmax: f64) -> (f64, [DVec3; 3]) {
    let s = c1.length_squared();
    let scale = 1.0 / (s * s * s * kmax * kmax);
    if !(scale.is_finite() && scale > 0.0) {
        return (0.0, [DVec3::ZERO; 3]);
    }
    let x = c1.cross(c2);
    let pv = x.dot(c3);
    let g1 = (c2.cross(c3) - c1 * (6.0 * pv / s)) * scale;
    let g2 = c3.cross(c1) * scale;
    let g3 = x * scale;
    (pv * scale, [g1, g2, g3])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a helix `t` is its torsion (closed form) when κ_max is its curvature, and the gradients match
    /// finite differences.
    #[test]
    fn twist_matches_a_helix_and_finite_differences() {
        // c(t) = (r cos t, r sin t, h t): κ = r / (r² + h²), τ = h / (r² + h²)
        let (r, hh, t) = (1.7, 0.6, 0.4f64);
        let c1 = DVec3::new(-r * t.sin(), r * t.cos(), hh);
        let c2 = DVec3::new(-r * t.cos(), -r * t.sin(), 0.0);
        let c3 = DVec3::new(r * t.sin(), -r * t.cos(), 0.0);
        let kappa = r / (r * r + hh * hh);
        let (tau, _) = twist(c1, c2, c3, kappa);
        let want = hh / (r * r + hh * hh);
        assert!((tau - want).abs() < 1e-12, "{tau} vs {want}");
        for (c1, c2, c3) in [(c1, c2, c3), (c1 * 0.7, c2 * 0.01 + c3 * 0.2, c3 * 3.0)] {
            let (_, g) = twist(c1, c2, c3, kappa);
            for o in 0..3 {
                for c in 0..3 {
                    let mut cs = [c1, c2, c3];
                    let h = 1e-6;
                    cs[o][c] += h;
                    let tp = twist(cs[0], cs[1], cs[2], kappa).0;
                    cs[o][c] -= 2.0 * h;
                    let tm = twist(cs[0], cs[1], cs[2], kappa).0;
                    let fd = (tp - tm) / (2.0 * h);
                    assert!(
                        (g[o][c] - fd).abs() <= 1e-6 * fd.abs().max(1.0),
                        "derivative {o}, coordinate {c}: {} vs {fd}",
                        g[o][c]
                    );
                }
            }
        }
    }
}
