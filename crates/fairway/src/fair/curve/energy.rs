//! The paper's E at the samples, from the stored basis rows, and its Gauss–Newton system.

use glam::DVec3;

use super::FairingSetup;
use crate::curve::{BSplineCurve, CurveDerivs};
use crate::linalg::BandedSpd;

impl FairingSetup {
    /// The term of E at sample k for a curve with derivatives `d` there and target g_k. 2D: (κ − g)², κ the
    /// signed curvature. 3D: |κN − g n|² without its tangential part, i.e. (κN·n − g)² + (κN·b)², with n
    /// the setup's sign-consistent normal and b = t × n: the signed curvature along n, and the curvature
    /// that turns out of the osculating plane. (With the first term alone the polish can
    /// turn the curvature vector out of n for free: on `assets/spatial_curve.json` at m = 0.02 it
    /// matches g along n to E = 3e-4 while ∫(dκ/ds)² goes from 9.1 to 33 and the curvature extrema
    /// from 36 to 50.) A planar 3D curve (its update stays in the plane) has no second term: it fairs as in 2D.
    pub(crate) fn residual_sq(&self, d: &CurveDerivs, k: usize, g: f64) -> f64 {
        if self.work.dim() == 2 {
            let e = d.curvature(2) - g;
            e * e
        } else if self.binormals.is_empty() {
            let e = d.curvature_vector().dot(self.normals[k]) - g;
            e * e
        } else {
            let cv = d.curvature_vector();
            let e = cv.dot(self.normals[k]) - g;
            let q = cv.dot(self.binormals[k]);
            e * e + q * q
        }
    }

    /// The paper's E = Σ_k (κ(p_k) − g_k)² of a curve on the same parameter
    /// domain (the original or a faired one), with the setup's target.
    pub fn energy(&self, curve: &BSplineCurve) -> f64 {
        let g = self.target.values();
        self.params
            .iter()
            .enumerate()
            .map(|(k, &u)| self.residual_sq(&curve.derivs(u), k, g[k]))
            .sum()
    }

    /// [`Self::energy`] of `c_orig + Σ N_i d_i` from the stored basis rows: the
    /// same numbers without evaluating the new curve (two fused sums per sample).
    pub(super) fn energy_of_update(&self, d: &[DVec3]) -> f64 {
        self.energy_and_roughness::<false>(d).0
    }

    /// [`Self::energy_of_update`] and, with `ROUGH`, the roughness of the curvature at the samples,
    /// Σ_k (κ_{k+1} − κ_k)² / h — the discrete ∫(dκ/ds)² ds (κ signed in 2D, along the setup's normal in
    /// 3D) — from the same pass.
    pub(super) fn energy_and_roughness<const ROUGH: bool>(&self, d: &[DVec3]) -> (f64, f64) {
        match self.work.degree() {
            2 => self.energy_rows::<3, ROUGH>(d),
            3 => self.energy_rows::<4, ROUGH>(d),
            4 => self.energy_rows::<5, ROUGH>(d),
            5 => self.energy_rows::<6, ROUGH>(d),
            _ => self.energy_rows::<0, ROUGH>(d),
        }
    }

    /// The paper's E of the original against the current target: Σ (κ_k − g_k)² from the original's
    /// signed curvature at the samples, which the setup keeps (no curve evaluation; [`Self::energy`] of
    /// the original to rounding, and bit for bit the E of the zero update the E guard compares with).
    pub fn original_energy(&self) -> f64 {
        let g = self.target.values();
        self.kappa0
            .iter()
            .zip(g)
            .enumerate()
            .map(|(k, (kap, g))| {
                let e = kap - g;
                if self.perp0.is_empty() {
                    e * e
                } else {
                    e * e + self.perp0[k]
                }
            })
            .sum()
    }

    /// [`Self::energy_and_roughness`] with `N` = p + 1 known at compile time (0: read p from the curve):
    /// samples whose p + 1 rows are all free take an unrolled path (the same sums in the same order).
    fn energy_rows<const N: usize, const ROUGH: bool>(&self, d: &[DVec3]) -> (f64, f64) {
        let p = self.work.degree();
        let g = self.target.values();
        let (mut e_sum, mut r_sum) = (0.0, 0.0);
        let mut prev = f64::NAN;
        for k in 0..self.params.len() {
            let f = self.first[k];
            let (mut d1, mut d2) = (self.d1[k], self.d2[k]);
            let (kap, e2) = 'term: {
                if N > 0 && f >= 0 && f as usize + N <= self.nf {
                    let base = f as usize;
                    let rows = &d[base..base + N];
                    let (b1, b2) = (&self.b1[k * N..(k + 1) * N], &self.b2[k * N..(k + 1) * N]);
                    if self.work.dim() == 2 {
                        // z is 0 in 2D: κ = (x'y'' − y'x'') / |c'|³ from x and y alone (the same value)
                        let (mut x1, mut y1, mut x2, mut y2) = (d1.x, d1.y, d2.x, d2.y);
                        for i in 0..N {
                            x1 += rows[i].x * b1[i];
                            y1 += rows[i].y * b1[i];
                            x2 += rows[i].x * b2[i];
                            y2 += rows[i].y * b2[i];
                        }
                        let v = (x1 * x1 + y1 * y1).sqrt();
                        let kap = (x1 * y2 - y1 * x2) / (v * v * v);
                        let e = kap - g[k];
                        break 'term (kap, e * e);
                    }
                    for i in 0..N {
                        d1 += rows[i] * b1[i];
                        d2 += rows[i] * b2[i];
                    }
                } else {
                    for i in 0..=p {
                        let li = f + i as isize;
                        if li >= 0 && (li as usize) < self.nf {
                            d1 += d[li as usize] * self.b1[k * (p + 1) + i];
                            d2 += d[li as usize] * self.b2[k * (p + 1) + i];
                        }
                    }
                }
                let cd = CurveDerivs {
                    p: DVec3::ZERO,
                    d1,
                    d2,
                    d3: DVec3::ZERO,
                };
                // Self::residual_sq, with the curvature along n kept for the roughness
                if self.work.dim() == 2 {
                    let kap = cd.curvature(2);
                    let e = kap - g[k];
                    (kap, e * e)
                } else {
                    let cv = cd.curvature_vector();
                    let kap = cv.dot(self.normals[k]);
                    let e = kap - g[k];
                    match self.binormals.get(k) {
                        Some(b) => {
                            let q = cv.dot(*b);
                            (kap, e * e + q * q)
                        }
                        None => (kap, e * e),
                    }
                }
            };
            e_sum += e2;
            if ROUGH {
                if k > 0 {
                    r_sum += (kap - prev) * (kap - prev);
                }
                prev = kap;
            }
        }
        (e_sum, r_sum / self.h)
    }

    /// [`Self::gn_system`] with the row widths of the common degrees and dimensions known at compile time.
    pub(super) fn gauss_newton(&self, g: &[f64], h: &mut BandedSpd, rhs: &mut [DVec3]) {
        match (self.work.degree(), self.work.dim()) {
            (2, 2) => self.gn_system::<3, 6>(g, h, rhs),
            (2, 3) => self.gn_system::<3, 9>(g, h, rhs),
            (3, 2) => self.gn_system::<4, 8>(g, h, rhs),
            (3, 3) => self.gn_system::<4, 12>(g, h, rhs),
            (4, 2) => self.gn_system::<5, 10>(g, h, rhs),
            (5, 2) => self.gn_system::<6, 12>(g, h, rhs),
            _ => self.gn_system::<0, 0>(g, h, rhs),
        }
    }

    /// The polish's Gauss–Newton system at the update `self.best`: `h += JᵀJ`, `rhs −= Jᵀr` with
    /// r_k = κ_k − g_k and J_k's row ∂κ_k/∂P_{li, c} = ∂κ/∂c'_c N'_i(p_k) + ∂κ/∂c''_c N''_i(p_k)
    /// (unknown index li·dim + c). `N` = p + 1 and `W` = dim·(p + 1) for the common cases (samples
    /// whose p + 1 rows are all free take an unrolled path), 0 for "read them from the curve".
    fn gn_system<const N: usize, const W: usize>(&self, g: &[f64], h: &mut BandedSpd, rhs: &mut [DVec3]) {
        let p = self.work.degree();
        let dim = self.work.dim();
        let np1 = p + 1;
        if N > 0 && W == 2 * N && dim == 2 {
            return self.gn_system_2d::<N, W>(g, h, rhs);
        }
        let mut jrow = vec![0.0; dim * np1];
        for k in 0..self.params.len() {
            let f = self.first[k];
            if N > 0 && f >= 0 && f as usize + N <= self.nf {
                let base = f as usize;
                let (b1, b2) = (&self.b1[k * N..(k + 1) * N], &self.b2[k * N..(k + 1) * N]);
                let rows = &self.best[base..base + N];
                let (mut d1, mut d2) = (self.d1[k], self.d2[k]);
                for i in 0..N {
                    d1 += rows[i] * b1[i];
                    d2 += rows[i] * b2[i];
                }
                // one residual row along n (target g), in 3D a second along b (target 0): Self::residual_sq
                for (w, gk) in self.residual_dirs(k, g[k]) {
                    let (kap, g1, g2) = kappa_and_gradients(dim, w, d1, d2);
                    let r = kap - gk;
                    let d = W / N;
                    let mut jr = [0.0; W];
                    for i in 0..N {
                        let gi = g1 * b1[i] + g2 * b2[i];
                        for c in 0..d {
                            jr[i * d + c] = gi[c];
                        }
                    }
                    let block: &mut [DVec3; W] = (&mut rhs[base * d..base * d + W]).try_into().expect("W rows");
                    for (y, x) in block.iter_mut().zip(&jr) {
                        y.x -= x * r;
                    }
                    h.add_outer_fixed(base * d, &jr);
                }
                continue;
            }
            let (mut d1, mut d2) = (self.d1[k], self.d2[k]);
            for i in 0..=p {
                let li = f + i as isize;
                if li >= 0 && (li as usize) < self.nf {
                    d1 += self.best[li as usize] * self.b1[k * np1 + i];
                    d2 += self.best[li as usize] * self.b2[k * np1 + i];
                }
            }
            for (w, gk) in self.residual_dirs(k, g[k]) {
                let (kap, g1, g2) = kappa_and_gradients(dim, w, d1, d2);
                let r = kap - gk;
                let base = f.max(0) as usize;
                jrow.fill(0.0);
                for i in 0..=p {
                    let li = f + i as isize;
                    if li < 0 || li as usize >= self.nf {
                        continue;
                    }
                    let gi = g1 * self.b1[k * np1 + i] + g2 * self.b2[k * np1 + i];
                    for c in 0..dim {
                        jrow[(li as usize - base) * dim + c] = gi[c];
                    }
                }
                let width = ((f + np1 as isize).min(self.nf as isize) - f.max(0)).max(0) as usize * dim;
                for a in 0..width {
                    rhs[base * dim + a].x -= jrow[a] * r;
                }
                h.add_outer(base * dim, &jrow[..width]);
            }
        }
    }

    /// [`Self::gn_system`] of a 2D curve (`W` = 2 `N`, `N` > 0) in three passes: c', c'' at every sample,
    /// then the curvature and its gradients ([`kappa_and_gradients`]'s operations, whose divisions then
    /// run on independent lanes), then the assembly (the same sums in the same order).
    fn gn_system_2d<const N: usize, const W: usize>(&self, g: &[f64], h: &mut BandedSpd, rhs: &mut [DVec3]) {
        let p = self.work.degree();
        let np1 = p + 1;
        let ns = self.params.len();
        let mut ders = Vec::with_capacity(ns);
        for k in 0..ns {
            let f = self.first[k];
            let (mut d1, mut d2) = (self.d1[k], self.d2[k]);
            if f >= 0 && f as usize + N <= self.nf {
                let base = f as usize;
                let (b1, b2) = (&self.b1[k * N..(k + 1) * N], &self.b2[k * N..(k + 1) * N]);
                let rows = &self.best[base..base + N];
                for i in 0..N {
                    d1 += rows[i] * b1[i];
                    d2 += rows[i] * b2[i];
                }
            } else {
                for i in 0..=p {
                    let li = f + i as isize;
                    if li >= 0 && (li as usize) < self.nf {
                        d1 += self.best[li as usize] * self.b1[k * np1 + i];
                        d2 += self.best[li as usize] * self.b2[k * np1 + i];
                    }
                }
            }
            ders.push([d1.x, d1.y, d2.x, d2.y]);
        }
        // kappa_and_gradients(2, ..): κ, ∂κ/∂c' and ∂κ/∂c'' (x, y)
        let grads: Vec<[f64; 5]> = ders
            .iter()
            .map(|&[x1, y1, x2, y2]| {
                let s2 = x1 * x1 + y1 * y1;
                let v3 = s2 * s2.sqrt();
                let cr = x1 * y2 - y1 * x2;
                let t = 3.0 * cr / (v3 * s2);
                [cr / v3, y2 / v3 - x1 * t, -x2 / v3 - y1 * t, -y1 / v3, x1 / v3]
            })
            .collect();
        for k in 0..ns {
            let f = self.first[k];
            let [kap, g1x, g1y, g2x, g2y] = grads[k];
            let r = kap - g[k];
            if f >= 0 && f as usize + N <= self.nf {
                let base = f as usize;
                let (b1, b2) = (&self.b1[k * N..(k + 1) * N], &self.b2[k * N..(k + 1) * N]);
                let mut jr = [0.0; W];
                for i in 0..N {
                    jr[2 * i] = g1x * b1[i] + g2x * b2[i];
                    jr[2 * i + 1] = g1y * b1[i] + g2y * b2[i];
                }
                let block: &mut [DVec3; W] = (&mut rhs[base * 2..base * 2 + W]).try_into().expect("W rows");
                for (y, x) in block.iter_mut().zip(&jr) {
                    y.x -= x * r;
                }
                h.add_outer_fixed(base * 2, &jr);
                continue;
            }
            let base = f.max(0) as usize;
            let mut jrow = [0.0; W];
            for i in 0..=p {
                let li = f + i as isize;
                if li < 0 || li as usize >= self.nf {
                    continue;
                }
                let (b1, b2) = (self.b1[k * np1 + i], self.b2[k * np1 + i]);
                let off = (li as usize - base) * 2;
                jrow[off] = g1x * b1 + g2x * b2;
                jrow[off + 1] = g1y * b1 + g2y * b2;
            }
            let width = ((f + np1 as isize).min(self.nf as isize) - f.max(0)).max(0) as usize * 2;
            for a in 0..width {
                rhs[base * 2 + a].x -= jrow[a] * r;
            }
            h.add_outer(base * 2, &jrow[..width]);
        }
    }

    /// The directions and targets of E's residuals at sample k ([`Self::residual_sq`]): (n, g_k), and in
    /// 3D also (b, 0). In 2D the direction is unused ([`kappa_and_gradients`] takes the signed curvature).
    fn residual_dirs(&self, k: usize, g: f64) -> impl Iterator<Item = (DVec3, f64)> + use<> {
        let b = self.binormals.get(k).map(|&b| (b, 0.0));
        std::iter::once((self.normals[k], g)).chain(b)
    }
}

/// Signed curvature from (c', c'') and its gradients with respect to c' and c''.
/// 2D: `κ = (c' × c'')_z / v³`; 3D: `κ = κN·N = (c''·N − (c''·c')(c'·N)/v²)/v²` along the unit
/// normal `nn` (the setup's sign-consistent normal, the quantity E uses).
fn kappa_and_gradients(dim: usize, nn: DVec3, d1: DVec3, d2: DVec3) -> (f64, DVec3, DVec3) {
    let s2 = d1.length_squared();
    if dim == 2 {
        let v3 = s2 * s2.sqrt();
        let cr = d1.x * d2.y - d1.y * d2.x;
        let g1 = DVec3::new(d2.y, -d2.x, 0.0) / v3 - d1 * (3.0 * cr / (v3 * s2));
        let g2 = DVec3::new(-d1.y, d1.x, 0.0) / v3;
        (cr / v3, g1, g2)
    } else {
        let (a, b, c) = (d2.dot(nn), d2.dot(d1), d1.dot(nn));
        let s4 = s2 * s2;
        let kap = a / s2 - b * c / s4;
        let g2 = nn / s2 - d1 * (c / s4);
        let g1 = -(d2 * c + nn * b) / s4 - d1 * (2.0 * a / s4) + d1 * (4.0 * b * c / (s4 * s2));
        (kap, g1, g2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fair::curve::FairingOptions;

    #[test]
    fn curvature_gradients_match_finite_differences() {
        let d1 = DVec3::new(0.8, -0.3, 0.25);
        let d2 = DVec3::new(-0.4, 1.1, 0.6);
        let nn = DVec3::new(0.1, 0.9, -0.2).normalize();
        for dim in [2usize, 3] {
            let (d1, d2) = if dim == 2 {
                (DVec3::new(d1.x, d1.y, 0.0), DVec3::new(d2.x, d2.y, 0.0))
            } else {
                (d1, d2)
            };
            let (k, g1, g2) = kappa_and_gradients(dim, nn, d1, d2);
            if dim == 2 {
                let v = d1.length();
                assert!((k - (d1.x * d2.y - d1.y * d2.x) / (v * v * v)).abs() < 1e-14);
            } else {
                let kv = (d2 - d1 * (d2.dot(d1) / d1.length_squared())) / d1.length_squared();
                assert!((k - kv.dot(nn)).abs() < 1e-14);
            }
            let h = 1e-6;
            for c in 0..dim {
                let mut e = DVec3::ZERO;
                e[c] = h;
                let f1 = (kappa_and_gradients(dim, nn, d1 + e, d2).0 - kappa_and_gradients(dim, nn, d1 - e, d2).0)
                    / (2.0 * h);
                let f2 = (kappa_and_gradients(dim, nn, d1, d2 + e).0 - kappa_and_gradients(dim, nn, d1, d2 - e).0)
                    / (2.0 * h);
                assert!((f1 - g1[c]).abs() < 1e-7, "dim {dim} d1[{c}]: {f1} vs {}", g1[c]);
                assert!((f2 - g2[c]).abs() < 1e-7, "dim {dim} d2[{c}]: {f2} vs {}", g2[c]);
            }
        }
    }

    /// The E guard compares the fit's E with the original's, which the setup sums from the original's
    /// curvature at the samples instead of evaluating the zero update's rows: the same number bit for bit
    /// (2D and a twisted 3D curve, cubic and quartic, whole and over a region, default and edited
    /// target), and E of the original curve evaluated afresh agrees to rounding.
    #[test]
    fn original_energy_is_the_zero_updates_energy_bit_for_bit() {
        for (p, dim) in [(3usize, 2usize), (3, 3), (4, 2), (4, 3)] {
            let n = 14;
            let knots = crate::knots::KnotVector::uniform(p, n).unwrap().values().to_vec();
            let pts: Vec<DVec3> = (0..n)
                .map(|i| {
                    let t = i as f64 / (n - 1) as f64;
                    let z = if dim == 3 { 0.3 * (5.0 * t).cos() } else { 0.0 };
                    DVec3::new(2.0 * t, (4.0 * t).sin() + 0.02 * ((i * 7 % 5) as f64 - 2.0), z)
                })
                .collect();
            let c = BSplineCurve::try_new(p, knots, pts, None, dim).unwrap();
            for region in [None, Some((0.2, 0.75))] {
                let o = FairingOptions {
                    tolerance: 1e-2,
                    region,
                    ..Default::default()
                };
                let mut s = FairingSetup::new(&c, o).unwrap();
                for edit in [false, true] {
                    if edit {
                        let k = s.target().len() / 2;
                        s.target_mut().set(k, 3.0);
                        s.target_mut().flatten_range(k + 2, k + 9);
                    }
                    let zero = vec![DVec3::ZERO; s.nf];
                    let (a, b) = (s.original_energy(), s.energy_of_update(&zero));
                    assert_eq!(
                        a.to_bits(),
                        b.to_bits(),
                        "p {p} dim {dim} {region:?} edit {edit}: {a} vs {b}"
                    );
                    let fresh = s.energy(&c);
                    assert!((a - fresh).abs() <= 1e-9 * fresh.max(1.0), "{a} vs {fresh}");
                    assert!(a > 0.0);
                }
            }
        }
    }
}
