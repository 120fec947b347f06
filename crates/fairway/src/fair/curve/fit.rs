//! The fit and its band search (module docs of `fair::curve`, steps 5–6): the banded system for a fairness
//! weight, the search for the largest μ whose fit holds the band, the scaled update.

use glam::DVec3;

use super::FairingSetup;
use crate::error::{Error, Result};
use crate::linalg::BandedSpd;

/// Smallest fairness weight μ tried (see the module docs, step 6).
pub(crate) const MU_MIN: f64 = 1e-6;

/// Largest fairness weight μ tried.
pub(crate) const MU_MAX: f64 = 1e10;

/// The band search stops when the largest good μ is known to within this factor.
pub(crate) const MU_RESOLUTION: f64 = 1.05;

/// Step factor of the warm-started search around the previous μ.
pub(crate) const MU_WARM_STEP: f64 = 16.0;

impl FairingSetup {
    /// The μ search of the reference smoother: `(A0 + λ A3) ΔP = λ rhs3` (data term the original), the
    /// largest λ whose result holds the band. Leaves the update in `self.best`; returns (μ, α, deviation).
    pub(super) fn search_smoothing(&mut self, accept: f64, solves: &mut usize) -> Result<(f64, f64, f64)> {
        let rhs0 = std::mem::replace(&mut self.rhs0, vec![DVec3::ZERO; self.nf]);
        let rhs2 = std::mem::replace(&mut self.rhs2, self.rhs3.clone());
        std::mem::swap(&mut self.last_mu, &mut self.last_mu_smooth);
        self.smoothing_system = true;
        let r = self.search_mu(accept, solves);
        self.smoothing_system = false;
        std::mem::swap(&mut self.last_mu, &mut self.last_mu_smooth);
        self.rhs0 = rhs0;
        self.rhs2 = rhs2;
        r
    }

    /// Deviation of the fit with fairness weight `mu` (∞ if the solve failed); the solution stays in `self.sol`.
    fn try_mu(&mut self, mu: f64, accept: f64, solves: &mut usize) -> f64 {
        *solves += 1;
        // a failed solve at a large fairness weight (ill-conditioned A2, e.g. next to a multiple knot of
        // G0/G1 ends) counts as "band not held": smaller μ are tried
        if self.solve(mu * self.lambda_scale()).is_err() {
            return f64::INFINITY;
        }
        let sol = std::mem::take(&mut self.sol);
        let d = self.deviation(&sol, accept);
        self.sol = sol;
        d
    }

    /// The largest μ ∈ [[`MU_MIN`], [`MU_MAX`]] (to a factor [`MU_RESOLUTION`]) whose fit holds the band,
    /// found by bisection in log μ; started from the previous fair's μ when there is one (a re-fair
    /// after a target or tolerance edit usually needs a handful of solves). If even `MU_MIN` fails,
    /// the update of `MU_MIN` is scaled by α ∈ [0, 1] (α = 0 is the original). Leaves the accepted
    /// update in `self.best`; returns (μ, α, deviation).
    pub(super) fn search_mu(&mut self, accept: f64, solves: &mut usize) -> Result<(f64, f64, f64)> {
        self.best_energy = None;
        let (lo, hi) = (MU_MIN.ln(), MU_MAX.ln());
        let step = MU_WARM_STEP.ln();
        // bracket [a, b]: ok at a (with its deviation), not ok at b
        let (mut a, mut da, mut b);
        match self.last_mu.map(|x| x.ln().clamp(lo, hi)) {
            Some(x0) => {
                let d0 = self.try_mu(x0.exp(), accept, solves);
                if d0 <= accept {
                    (a, da) = (x0, d0);
                    self.best.copy_from_slice(&self.sol);
                    loop {
                        if a >= hi {
                            return Ok(self.finish_mu_fairest(a, da, accept, solves));
                        }
                        let x = (a + step).min(hi);
                        let d = self.try_mu(x.exp(), accept, solves);
                        if d <= accept {
                            (a, da) = (x, d);
                            self.best.copy_from_slice(&self.sol);
                        } else {
                            b = x;
                            break;
                        }
                    }
                } else {
                    b = x0;
                    loop {
                        if b <= lo {
                            return self.scale_update(accept, solves);
                        }
                        let x = (b - step).max(lo);
                        let d = self.try_mu(x.exp(), accept, solves);
                        if d <= accept {
                            (a, da) = (x, d);
                            self.best.copy_from_slice(&self.sol);
                            break;
                        }
                        b = x;
                    }
                }
            }
            None => {
                let d_hi = self.try_mu(MU_MAX, accept, solves);
                if d_hi <= accept {
                    self.best.copy_from_slice(&self.sol);
                    return Ok(self.finish_mu_fairest(hi, d_hi, accept, solves));
                }
                let d_lo = self.try_mu(MU_MIN, accept, solves);
                // NaN-safe (an update from a target out of range can be NaN): not within the band
                if !(d_lo <= accept) {
                    return self.scale_update(accept, solves);
                }
                self.best.copy_from_slice(&self.sol);
                (a, da, b) = (lo, d_lo, hi);
            }
        }
        while b - a > MU_RESOLUTION.ln() {
            let c = 0.5 * (a + b);
            let d = self.try_mu(c.exp(), accept, solves);
            if d <= accept {
                (a, da) = (c, d);
                self.best.copy_from_slice(&self.sol);
            } else {
                b = c;
            }
        }
        Ok(self.finish_mu_fairest(a, da, accept, solves))
    }

    /// From the largest band-holding μ found (ln μ = `a`, its update in `self.best`), step μ down by
    /// [`MU_WARM_STEP`] while the band holds and E drops, then finish there. The fairness term is E
    /// linearized about the *original* speed profile: where that profile is noisy (a zig-zag stretch) its
    /// largest weights pin the fit to the noise, and E(μ) has its minimum below the largest μ the band
    /// allows. Where the band binds, E still falls as μ rises to the band's limit, and the first step
    /// down (one solve) leaves the result as it was. Stopping at the band's limit instead, the second
    /// stretch of `assets/kinked_profile.json` faired at m = 0.03 stops at μ = 1e10 with E 9.5, where
    /// μ = 1e6 gives 2.2: a looser tolerance would give a less fair curve than m = 0.01 (∫(dκ/ds)² 58
    /// against 25).
    fn finish_mu_fairest(&mut self, a: f64, da: f64, accept: f64, solves: &mut usize) -> (f64, f64, f64) {
        if self.smoothing_system || !self.fairest_mu {
            // the smoother's weight is the largest the band allows, as a smoothing-factor search gives
            // (and the fit's where the step down is turned off)
            return self.finish_mu(a, da);
        }
        let lo = MU_MIN.ln();
        let step = MU_WARM_STEP.ln();
        let (mut a, mut da) = (a, da);
        let mut e_a = self.energy_of_update(&self.best);
        while a - step >= lo {
            let x = a - step;
            let d = self.try_mu(x.exp(), accept, solves);
            if !(d <= accept) {
                break;
            }
            let e = self.energy_of_update(&self.sol);
            if !(e < e_a) {
                break;
            }
            (a, da, e_a) = (x, d, e);
            self.best.copy_from_slice(&self.sol);
        }
        self.best_energy = Some(e_a);
        self.finish_mu(a, da)
    }

    fn finish_mu(&mut self, ln_mu: f64, dev: f64) -> (f64, f64, f64) {
        let mu = ln_mu.exp();
        self.last_mu = Some(mu);
        (mu, 1.0, dev)
    }

    /// Even `MU_MIN` breaks the band: scale its update down until the band holds (α = 0 is the original).
    fn scale_update(&mut self, accept: f64, solves: &mut usize) -> Result<(f64, f64, f64)> {
        self.solve(MU_MIN * self.lambda_scale())?;
        *solves += 1;
        let full = self.sol.clone();
        let (mut a, mut b) = (0.0f64, 1.0f64);
        let mut best_d = 0.0;
        let mut scaled = full.clone();
        self.best.fill(DVec3::ZERO);
        for _ in 0..20 {
            let c = 0.5 * (a + b);
            for (s, f) in scaled.iter_mut().zip(&full) {
                *s = *f * c;
            }
            let d = self.deviation(&scaled, accept);
            if d <= accept {
                a = c;
                best_d = d;
                self.best.copy_from_slice(&scaled);
            } else {
                b = c;
            }
        }
        self.last_mu = Some(MU_MIN);
        Ok((MU_MIN, a, best_d))
    }

    /// Solve `(A0 + λ A2) ΔP = rhs0 + λ rhs2` into `self.sol`.
    pub(super) fn solve(&mut self, lambda: f64) -> Result<()> {
        self.assemble(lambda, 0.0);
        for i in 0..self.nf {
            self.sol[i] = self.rhs0[i] + self.rhs2[i] * lambda;
        }
        if self.m.factor().is_err() {
            // A free point whose support no sample reaches (a short span between multiple knots, which
            // equal arc-length samples can skip) has an empty row: a small ridge keeps such points where
            // they are (their right-hand side is zero) and leaves the others as good as unchanged.
            let dmax = (0..self.nf)
                .map(|i| self.a0.get(i, i) + lambda * self.penalty().get(i, i))
                .fold(0.0, f64::max);
            self.assemble(lambda, 1e-9 * dmax);
            self.m.factor().map_err(|e| {
                Error::Solve(format!(
                    "fairing fit: {e}; the region has too few samples per free control point (raise --samples)"
                ))
            })?;
        }
        self.m.solve_in_place(&mut self.sol);
        let mut sol = std::mem::take(&mut self.sol);
        self.constrain_update(&mut sol);
        self.sol = sol;
        Ok(())
    }

    /// The penalty matrix of the μ search: the fit's `A2`, or the smoother's `A3`.
    fn penalty(&self) -> &BandedSpd {
        if self.smoothing_system { &self.a3 } else { &self.a2 }
    }

    /// λ = μ · this: `Δu⁴` for the fit's second-derivative term at the samples (μ = 1 weighs a position
    /// error like its second difference), `tr A0 / tr A3` for the smoother (μ = 1 weighs both terms alike,
    /// whatever the parameter's scale and the knot spacing).
    fn lambda_scale(&self) -> f64 {
        if self.smoothing_system {
            self.a3_scale
        } else {
            self.du.powi(4)
        }
    }

    /// `self.m = A0 + λ A2 + ridge·I` (lower band; `A3` for the smoother).
    fn assemble(&mut self, lambda: f64, ridge: f64) {
        let p = self.work.degree();
        self.m.reset(self.nf, p);
        for i in 0..self.nf {
            for j in i.saturating_sub(p)..=i {
                let mut v = self.a0.get(i, j) + lambda * self.penalty().get(i, j);
                if i == j {
                    v += ridge;
                }
                if v != 0.0 {
                    self.m.add(i, j, v);
                }
            }
        }
    }
}
