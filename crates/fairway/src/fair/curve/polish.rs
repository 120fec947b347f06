//! The polish inside the band (module docs of `fair::curve`, step 7): Levenberg–Marquardt steps on E, the
//! interior point on E or on the curvature variation.

use glam::DVec3;

use super::FairingSetup;
use super::variation;
use crate::error::Result;
use crate::linalg::BandedSpd;

mod judged;
mod stepless;

/// The interior point's objective: `paper · E + var · E_var`, with `paper` 1 or 0 (the Gauss–Newton
/// system of E is added with weight 1, the barrier is scaled to the objective).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Objective {
    paper: f64,
    var: f64,
    /// The variation objective's torsion pass ([`FairingSetup::polish_torsion_within`]): iterates are
    /// taken by the objective's value (E_var and the torsion term) among those with at most these
    /// curvature extrema and this E_var, instead of by their curvature rank.
    ceiling: Option<Rank>,
}

impl Objective {
    const PAPER: Self = Self {
        paper: 1.0,
        var: 0.0,
        ceiling: None,
    };
}

/// A polish step is accepted only if the roughness of the curvature at the samples (Σ (Δκ)² / h) stays
/// within this factor of the larger of the polish's start and the target's (`FairingSetup::polish`).
pub(crate) const POLISH_ROUGHNESS_CAP: f64 = 1.0;

/// The interior-point polish starts at most this fraction of the band from the original (the fit is
/// scaled back if its parametric displacement reaches further).
pub(crate) const IP_START: f64 = 0.95;

/// Bisections on the segment from the step-priced result to the polish without step prices
/// (`FairingSetup::polish_without_steps`): the move is found to 2⁻⁸ of the segment.
pub(crate) const STEP_BLEND_BISECTIONS: usize = 8;

/// The blend of `FairingSetup::polish_without_steps` has an E_var over the spans at least this fraction
/// below the reference's (the end of the segment is taken where it is not).
pub(crate) const STEP_BLEND_MARGIN: f64 = 0.01;

/// Centring parameter of the interior-point polish: τ ← σ · mean(z_j c_j) after each step.
pub(crate) const IP_SIGMA: f64 = 0.2;

/// The interior point's iterate and its work arrays ([`FairingSetup::interior_point`]).
struct IpState {
    /// The update (the free control points' displacements) and its parametric displacements `D_j`.
    x: Vec<DVec3>,
    disp: Vec<DVec3>,
    /// The duals of the band constraints and the barrier parameter τ.
    z: Vec<f64>,
    tau: f64,
    /// The objective at `x` and its barrier `−Σ ln(c_j / m²)`.
    e_x: f64,
    log_b: f64,
    /// Marquardt damping of the system (raised while the factorization or the line search fail).
    damping: f64,
    /// Size and half bandwidth of the system.
    nu: usize,
    bw: usize,
    /// The system, its damped factorization, right-hand side and solution.
    h: BandedSpd,
    m: BandedSpd,
    rhs: Vec<DVec3>,
    sol: Vec<DVec3>,
    /// The step and a candidate iterate with their displacements, the duals' step, the per-point traces.
    step: Vec<DVec3>,
    cand: Vec<DVec3>,
    sdisp: Vec<DVec3>,
    cdisp: Vec<DVec3>,
    dz: Vec<f64>,
    traces: Vec<f64>,
}

impl IpState {
    /// The longest step along `step` (at most 1) that stays 1 % inside every constraint, and the duals'
    /// step `dz` (from `z_j c_j = τ` linearized) with its longest length that keeps z positive.
    fn step_bounds(&mut self, m2: f64) -> (f64, f64) {
        let (mut a_max, mut a_dual) = (1.0f64, 1.0f64);
        for j in 0..self.disp.len() {
            let (d, ds) = (self.disp[j], self.sdisp[j]);
            let c = m2 - d.length_squared();
            let (qa, qb) = (ds.length_squared(), 2.0 * d.dot(ds));
            // |d + α ds|² ≤ |d|² + |qb| + qa for α ≤ 1: where that stays 1 % inside, no root is needed
            if qa > 0.0 && c - qb.abs() - qa < 0.02 * c {
                // the positive root of |d + α ds|² = m²
                let disc = (qb * qb + 4.0 * qa * c).sqrt();
                let root = if qb > 0.0 {
                    2.0 * c / (qb + disc)
                } else {
                    (disc - qb) / (2.0 * qa)
                };
                a_max = a_max.min(0.99 * root);
            }
        }
        // the duals' step in a loop of its own (its divisions on independent lanes)
        for ((dz, (d, ds)), z) in self.dz.iter_mut().zip(self.disp.iter().zip(&self.sdisp)).zip(&self.z) {
            let c = m2 - d.length_squared();
            let qb = 2.0 * d.dot(*ds);
            *dz = (self.tau - z * c + z * qb) / c;
        }
        for (dz, z) in self.dz.iter().zip(&self.z) {
            if *dz < 0.0 {
                a_dual = a_dual.min(-0.99 * z / dz);
            }
        }
        (a_max, a_dual)
    }

    /// Take the accepted candidate (objective `e_c`, barrier `lb`) as the iterate, the duals' step of length
    /// `a_z`, and τ ← [`IP_SIGMA`] · mean(z_j c_j).
    fn advance(&mut self, a_z: f64, e_c: f64, lb: f64, m2: f64) {
        std::mem::swap(&mut self.x, &mut self.cand);
        std::mem::swap(&mut self.disp, &mut self.cdisp);
        (self.e_x, self.log_b) = (e_c, lb);
        let nc = self.z.len();
        let mut zc = 0.0;
        for j in 0..nc {
            self.z[j] = (self.z[j] + a_z * self.dz[j]).max(1e-300);
            zc += self.z[j] * (m2 - self.disp[j].length_squared());
        }
        self.tau = IP_SIGMA * zc / nc as f64;
    }
}

/// What the variation polish ([`FairingSetup::polish_variation`]) computes that depends only on the setup
/// and the band, not on the target: the original's rank (curvature extrema, E_var), and the reference
/// smoother's result at the last band with its deviation and rank. A re-fair after a target edit reuses
/// them; a re-fair at another band searches the smoother again.
#[derive(Debug, Clone, Default)]
pub(super) struct PolishCache {
    pub(super) orig_rank: Option<Rank>,
    smooth: Option<SmoothStart>,
    /// `measure`'s dead band of the curvature extrema of the working curve (`judged_against_reference`).
    judged_delta: std::cell::Cell<Option<f64>>,
    /// The original's rank as `measure` counts it, its parts as asked (`judged_against_reference`): the same
    /// for every re-fair.
    judged_orig: judged::Parts,
    /// The last curve `judged` measured and its extrema ([`FairingSetup::counted_extrema`]).
    last_judged: std::cell::RefCell<Option<(crate::BSplineCurve, usize)>>,
}

/// How fair an update is: (curvature extrema at the probes, E_var).
pub(super) type Rank = (usize, f64);

/// The torsion pass ([`FairingSetup::polish_torsion_within`]) keeps the curvature's E_var this fraction
/// below the reference smoother's.
pub(crate) const TWIST_BAR_MARGIN: f64 = 0.01;

/// The reference smoother's result at one band ([`PolishCache`]).
#[derive(Debug, Clone)]
struct SmoothStart {
    /// The band's bits (`accept`).
    band: u64,
    upd: Vec<DVec3>,
    dev: f64,
    rank: Rank,
    /// Its E_var on 10 Gauss nodes a span, once asked for (`judged_against_reference`).
    measured_var: Option<f64>,
    /// Its rank as `measure` counts it, its parts once asked for (`judged_against_reference`).
    judged: judged::Parts,
}

/// The fairest iterate of the interior point so far and what ranks it ([`FairingSetup::ip_consider`]).
struct IpBest {
    /// Its objective, deviation bound and update.
    value: f64,
    dev: f64,
    upd: Vec<DVec3>,
    /// The paper's E: the roughness an iterate may not exceed (∞ for the variation objective).
    rough_cap: f64,
    /// The variation objective: the start's E_var, and the best's E_var and curvature extrema.
    start_var: f64,
    var: f64,
    extrema: usize,
}

impl FairingSetup {
    /// Gauss–Newton polish of the paper's E = Σ (κ(p_k) − g_k)² from the band-holding fit in
    /// `self.best`, inside the band: Levenberg–Marquardt steps on the free control points (the
    /// Jacobian of κ_k is banded: sample k depends on p + 1 points), each accepted only if E drops
    /// and the band check still holds. The fairness-weighted fit is the linearized E with the
    /// original speed profile; this removes what that linearization leaves (the fast result's E
    /// was ≈ 11 % above the iterative baseline's). Returns the deviation of the accepted update.
    pub(super) fn polish(&mut self, accept: f64, dev: f64, e: f64, solves: &mut usize) -> (f64, f64) {
        let p = self.work.degree();
        let dim = self.work.dim();
        let nu = dim * self.nf;
        let bw = dim * (p + 1) - 1;
        let g = self.target.values().to_vec();
        let mut e = e;
        let mut dev = dev;
        let mut lambda = 1e-3;
        // a step may lower E only without roughening the curvature (see `roughness_cap`)
        let rough_cap = self.roughness_cap(&g);
        let mut h = BandedSpd::zeros(nu, bw);
        let mut rhs = vec![DVec3::ZERO; nu];
        for _ in 0..self.opts.polish_iterations {
            let e_start = e;
            h.reset(nu, bw);
            rhs.fill(DVec3::ZERO);
            self.gauss_newton(&g, &mut h, &mut rhs);
            // The band is usually active at a few check samples: the step minimizes Σ (r + J s)² + ρ Σ_{j∈A}
            // |Δs(u_j)|² where A holds the check samples within 3 % of the band edge (their displacement is
            // frozen; a rank-1 penalty on the outward component only was tried and did worse), then a
            // backtracking line search keeps the band.
            let diag: Vec<f64> = (0..nu).map(|i| h.get(i, i)).collect();
            // per-point traces of the diagonal blocks: rotation invariant scales for ρ and the damping
            let traces: Vec<f64> = (0..self.nf)
                .map(|i| diag[i * dim..(i + 1) * dim].iter().sum())
                .collect();
            let tmax = traces.iter().fold(0.0f64, |a, &b| a.max(b));
            let rho = 1e3 * tmax;
            let best = std::mem::take(&mut self.best);
            let active: Vec<usize> = self.band_samples(&best, 0.97 * accept);
            self.best = best;
            let mut accepted = false;
            for _ in 0..12 {
                let Some(full) = self.lm_step(&h, &rhs, &active, rho, &traces, tmax, lambda, solves) else {
                    lambda *= 10.0;
                    continue;
                };
                let Some((cand, e_new, d_new)) = self.lm_backtrack(&full, accept, e, rough_cap) else {
                    lambda *= 10.0;
                    continue;
                };
                self.best.copy_from_slice(&cand);
                (e, dev) = (e_new, d_new);
                lambda = (lambda / 3.0).max(1e-9);
                accepted = true;
                break;
            }
            // converged: the last step gained less than 0.02 % of E
            if !accepted || e_start - e < 2e-4 * e_start {
                break;
            }
        }
        (dev, e)
    }

    /// The roughness cap of the E polishes ([`Self::polish`], [`Self::polish_interior`]): a step may lower E
    /// only without roughening the curvature beyond the polish's start (the update in `self.best`) and the
    /// target `g`, times [`POLISH_ROUGHNESS_CAP`].
    ///
    /// Why: E compares κ with g at fixed parameters, and where the band leaves room the cheapest way to lower
    /// it is to let κ zig-zag about g from knot span to knot span, sliding samples along the curve. Without
    /// the cap, on `assets/car_roof.json` at m = 0.1 the polish takes E 7.6 → 4.9 while ∫(dκ/ds)² goes
    /// 5.3 → 14.3 and the curvature extrema 2 → 32: a looser tolerance would give a less fair curve. Where the
    /// polish smooths the curvature (the bench curve, the known-answer arcs) the cap does not bind.
    fn roughness_cap(&self, g: &[f64]) -> f64 {
        let r0 = self.energy_and_roughness::<true>(&self.best).1;
        let rg = g.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>() / self.h;
        r0.max(rg) * POLISH_ROUGHNESS_CAP
    }

    /// One damped solve of [`Self::polish`]: the Gauss–Newton system `h`, `rhs` plus the penalty `rho` that
    /// freezes the displacement at the `active` check samples and Marquardt damping `lambda` by the
    /// per-point `traces`, factored and solved. Returns the step projected onto the directions the setup
    /// allows, or `None` when the factorization fails (the caller raises the damping).
    fn lm_step(
        &self,
        h: &BandedSpd,
        rhs: &[DVec3],
        active: &[usize],
        rho: f64,
        traces: &[f64],
        tmax: f64,
        lambda: f64,
        solves: &mut usize,
    ) -> Option<Vec<DVec3>> {
        let p = self.work.degree();
        let dim = self.work.dim();
        let mut m = h.clone();
        let b = rhs.to_vec();
        for &j in active {
            let f = self.chk_first[j];
            let w = &self.chk_b[j * (p + 1)..(j + 1) * (p + 1)];
            for x in 0..=p {
                let lx = f + x as isize;
                if lx < 0 || lx as usize >= self.nf {
                    continue;
                }
                for y in 0..=x {
                    let ly = f + y as isize;
                    if ly < 0 {
                        continue;
                    }
                    for c in 0..dim {
                        m.add(lx as usize * dim + c, ly as usize * dim + c, rho * w[x] * w[y]);
                    }
                }
            }
        }
        // unknowns κ does not depend on (e.g. out of the plane of a planar 3D curve) get a floor
        // of damping, so they stay at zero instead of making the system singular
        // Marquardt damping by the trace of each point's diagonal block: invariant under rotations
        // (a planar curve fairs the same in 2D and rotated into 3D)
        for (i, tr) in traces.iter().enumerate() {
            for c in 0..dim {
                m.add(i * dim + c, i * dim + c, lambda * tr.max(1e-9 * tmax).max(1e-300));
            }
        }
        *solves += 1;
        if m.factor().is_err() {
            return None;
        }
        let mut step = b;
        m.solve_in_place(&mut step);
        let mut full: Vec<DVec3> = (0..self.nf)
            .map(|j| {
                let mut d = DVec3::ZERO;
                for c in 0..dim {
                    d[c] = step[j * dim + c].x;
                }
                d
            })
            .collect();
        self.constrain_update(&mut full);
        Some(full)
    }

    /// The line search of [`Self::polish`]: backtracking on the step length, the longest of 1, 1/2, … (8
    /// tries) whose update `self.best + α full` holds the band and lowers E below `e` within `rough_cap`.
    /// Returns that update with its E and deviation, or `None` (the caller raises the damping).
    fn lm_backtrack(&mut self, full: &[DVec3], accept: f64, e: f64, rough_cap: f64) -> Option<(Vec<DVec3>, f64, f64)> {
        let mut alpha = 1.0;
        for _ in 0..8 {
            let cand: Vec<DVec3> = self.best.iter().zip(full).map(|(b, s)| *b + *s * alpha).collect();
            // band first: a violated band stops the check at the first proven violation
            let d_new = self.deviation(&cand, accept);
            if d_new <= accept {
                let (e_new, rough) = self.energy_and_roughness::<true>(&cand);
                if e_new < e && rough <= rough_cap {
                    return Some((cand, e_new, d_new));
                }
            }
            alpha *= 0.5;
        }
        None
    }

    /// Interior-point polish of the paper's E inside the band ([`PolishMethod::InteriorPoint`](super::PolishMethod::InteriorPoint)): a
    /// primal–dual barrier method on
    ///
    /// `min E(ΔP)  subject to  c_j = m² − |D_j|² > 0` for every check sample j,
    ///
    /// where `D_j = Σ_i N_i(u_j) ΔP_i` is the parametric displacement at u_j — an upper bound of the
    /// closest-point distance (the iterative baseline's band), so every iterate holds the band by
    /// construction and no step needs a band check (the constraints are convex: the segment between
    /// two feasible updates is feasible). Each iteration is one Gauss–Newton linearization of E (the
    /// banded `JᵀJ` of [`Self::gn_system`]) plus the constraints' terms ([`Self::barrier_terms`]), one
    /// banded Cholesky, a step that stays 1 % inside every constraint, and a backtracking search on
    /// `E − τ Σ ln c_j`. The duals follow `z_j c_j = τ`, and τ falls to [`IP_SIGMA`] times the mean
    /// complementarity after each step. The start is the band-holding fit, scaled towards the
    /// original until its parametric displacement is within [`IP_START`] of the band. Returns the
    /// deviation bound and E of the fairest iterate that keeps the roughness cap (see [`Self::polish`];
    /// the start when none does).
    pub(super) fn polish_interior(&mut self, accept: f64, dev: f64, e: f64, solves: &mut usize) -> (f64, f64) {
        let (dev, e, _) = self.interior_point(accept, dev, e, solves, Objective::PAPER, None);
        (dev, e)
    }

    /// The interior-point minimization of `obj` (the paper's E, or the variation objective) inside the
    /// parametric band at the check samples, from the band-holding update in `self.best` whose paper's E is
    /// `e`, deviation `dev` and (variation objective) rank `start_rank` when the caller has it. Leaves the
    /// fairest iterate in `self.best`; returns its (deviation, E) and, for the variation objective, its rank
    /// (the ranking computed it already; `None` where the polish did not run).
    ///
    /// Each iteration: the damped system ([`Self::ip_factor`]), the step ([`Self::ip_direction`]), its
    /// longest feasible length and the duals' ([`IpState::step_bounds`]), the line search
    /// ([`Self::ip_backtrack`]), the update of the iterate and duals ([`IpState::advance`]) and its ranking
    /// ([`Self::ip_consider`]).
    fn interior_point(
        &mut self,
        accept: f64,
        dev: f64,
        e: f64,
        solves: &mut usize,
        obj: Objective,
        start_rank: Option<Rank>,
    ) -> (f64, f64, Option<Rank>) {
        let nf = self.nf;
        let nc = self.chk_u.len();
        if nc == 0 || nf == 0 || !(accept > 0.0) {
            return (dev, e, None);
        }
        let g = self.target.values().to_vec();
        // (the variation objective rides the band: it runs on the hull rows, `polish_variation_torsion`, which
        // bound the band between them too; on check samples such a curve bulged past the band between them)
        let m2 = accept * accept;
        let mut best = self.ip_ranking(obj, &g, e, dev, start_rank.map(|r| r.0));
        let mut st = self.ip_start(obj, accept, m2);
        for _ in 0..self.opts.polish_iterations {
            if !self.ip_factor(&mut st, obj, &g, m2, solves) {
                break;
            }
            self.ip_direction(&mut st);
            let (a_max, a_dual) = st.step_bounds(m2);
            let Some((alpha, e_c, rough, lb)) = self.ip_backtrack(&mut st, obj, m2, a_max) else {
                st.damping *= 100.0;
                continue;
            };
            st.damping = (st.damping / 10.0).max(1e-12);
            let e_prev = st.e_x;
            st.advance(alpha.min(a_dual), e_c, lb, m2);
            self.ip_consider(&mut best, obj, &st, rough);
            // converged: E moved by less than 0.02 % and the barrier is negligible against E
            if (e_prev - st.e_x).abs() < 2e-4 * e_prev && st.tau * (nc as f64) < 1e-3 * st.e_x {
                break;
            }
        }
        let IpBest {
            value: e,
            dev,
            upd,
            var,
            extrema,
            ..
        } = best;
        self.best = upd;
        if obj.var > 0.0 {
            // the best's extrema and E_var are those of its update (`ip_ranking`, `ip_consider`)
            (dev, self.energy_of_update(&self.best), Some((extrema, var)))
        } else {
            (dev, e, None)
        }
    }

    /// The interior point's ranking at its start (the update in `self.best`, of paper's E `e` and deviation
    /// `dev`, of curvature extrema `start_extrema` when known): the iterate to beat and, for the paper's E, the
    /// roughness cap ([`Self::roughness_cap`]) an iterate must keep to be taken.
    fn ip_ranking(&self, obj: Objective, g: &[f64], e: f64, dev: f64, start_extrema: Option<usize>) -> IpBest {
        let rough_cap = if obj.var > 0.0 {
            f64::INFINITY
        } else {
            self.roughness_cap(g)
        };
        let (start_value, start_var) = if obj.var > 0.0 {
            self.objective_value(obj, &self.best)
        } else {
            (e, 0.0)
        };
        // the variation objective ranks iterates by their curvature extrema first (never more than the
        // start's), then by E_var, among those whose E_var is not above the start's
        let extrema = if obj.var > 0.0 {
            start_extrema.unwrap_or_else(|| self.node_extrema(&self.best))
        } else {
            0
        };
        IpBest {
            value: start_value,
            dev,
            upd: self.best.clone(),
            rough_cap,
            start_var,
            var: start_var,
            extrema,
        }
    }

    /// The interior point's start: strictly inside the parametric band (the fit holds the band in the
    /// closest-point sense: where the curve slid along itself its parametric displacement can reach m), the
    /// update in `self.best` scaled towards the original until its displacement is within [`IP_START`] of
    /// the band; τ = objective / samples with the duals on `z_j c_j = τ`; the work arrays of the system.
    fn ip_start(&mut self, obj: Objective, accept: f64, m2: f64) -> IpState {
        let p = self.work.degree();
        let dim = self.work.dim();
        let nf = self.nf;
        let nc = self.chk_u.len();
        let nu = dim * nf;
        // a curvature step at a knot below C2 couples the points of the spans on both sides
        let reach = if obj.var > 0.0 { self.var.jump_reach() } else { 0 };
        let bw = dim * (p + 1 + reach) - 1;
        let mut x = self.best.clone();
        let mut disp = vec![DVec3::ZERO; nc];
        self.chk_displacements(&x, &mut disp);
        let dmax2 = disp.iter().fold(0.0f64, |a, d| a.max(d.length_squared()));
        if !(dmax2 <= (IP_START * accept).powi(2)) {
            let s = if dmax2.is_finite() {
                IP_START * accept / dmax2.sqrt()
            } else {
                0.0
            };
            for v in x.iter_mut() {
                *v *= s;
            }
            for d in disp.iter_mut() {
                *d *= s;
            }
        }
        let e_x = self.objective_value(obj, &x).0;
        let tau = (e_x / nc as f64).max(1e-300);
        let z: Vec<f64> = disp.iter().map(|d| tau / (m2 - d.length_squared())).collect();
        let log_b = barrier_log_sum(&disp, m2);
        IpState {
            x,
            disp,
            z,
            tau,
            e_x,
            log_b,
            damping: 1e-9,
            nu,
            bw,
            h: BandedSpd::zeros(nu, bw),
            m: BandedSpd::zeros(nu, bw),
            rhs: vec![DVec3::ZERO; nu],
            sol: vec![DVec3::ZERO; nu],
            step: vec![DVec3::ZERO; nf],
            cand: vec![DVec3::ZERO; nf],
            sdisp: vec![DVec3::ZERO; nc],
            cdisp: vec![DVec3::ZERO; nc],
            dz: vec![0.0; nc],
            traces: vec![0.0; nf],
        }
    }

    /// The interior point's system at the iterate: the Gauss–Newton system of E and/or the variation's,
    /// plus the constraints' terms ([`Self::barrier_terms`]), damped and factored into `st.m` (the damping
    /// raised ×100 up to 6 times until the factorization succeeds). Returns whether it did.
    fn ip_factor(&mut self, st: &mut IpState, obj: Objective, g: &[f64], m2: f64, solves: &mut usize) -> bool {
        let p = self.work.degree();
        let dim = self.work.dim();
        // Gauss–Newton system of E at x
        st.h.reset(st.nu, st.bw);
        st.rhs.fill(DVec3::ZERO);
        if obj.paper > 0.0 {
            std::mem::swap(&mut self.best, &mut st.x);
            self.gauss_newton(g, &mut st.h, &mut st.rhs);
            std::mem::swap(&mut self.best, &mut st.x);
        }
        if obj.var > 0.0 {
            self.variation_system(&st.x, obj.var, &mut st.h, &mut st.rhs);
        }
        // the constraints' terms
        let (disp, z, tau, h, rhs) = (&st.disp, &st.z, st.tau, &mut st.h, &mut st.rhs);
        match (p, dim) {
            (2, 2) => self.barrier_terms::<3, 2>(disp, z, tau, m2, h, rhs),
            (2, 3) => self.barrier_terms::<3, 3>(disp, z, tau, m2, h, rhs),
            (3, 2) => self.barrier_terms::<4, 2>(disp, z, tau, m2, h, rhs),
            (3, 3) => self.barrier_terms::<4, 3>(disp, z, tau, m2, h, rhs),
            (4, 2) => self.barrier_terms::<5, 2>(disp, z, tau, m2, h, rhs),
            (5, 2) => self.barrier_terms::<6, 2>(disp, z, tau, m2, h, rhs),
            _ => self.barrier_terms::<0, 0>(disp, z, tau, m2, h, rhs),
        }
        // Marquardt damping by each point's diagonal block (rotation invariant, with a floor for
        // unknowns E does not see), and a stiff penalty on the directions the setup's constraints
        // forbid (the plane of a planar 3D curve, joins at multiple knots), which the projection of
        // the step then removes exactly
        for (i, t) in st.traces.iter_mut().enumerate() {
            *t = (0..dim).map(|c| st.h.get(i * dim + c, i * dim + c)).sum();
        }
        let tmax = st.traces.iter().fold(0.0f64, |a, &b| a.max(b));
        for _ in 0..6 {
            st.m.clone_from(&st.h);
            for (i, tr) in st.traces.iter().enumerate() {
                for c in 0..dim {
                    st.m.add(i * dim + c, i * dim + c, st.damping * tr.max(1e-9 * tmax).max(1e-300));
                }
            }
            self.penalize_constrained(&mut st.m, 1e6 * tmax.max(1e-300));
            *solves += 1;
            if st.m.factor().is_ok() {
                return true;
            }
            st.damping *= 100.0;
        }
        false
    }

    /// The interior point's step from the factored system: solved, projected onto the directions the
    /// setup allows, and its parametric displacements at the check samples (`st.step`, `st.sdisp`).
    fn ip_direction(&mut self, st: &mut IpState) {
        let dim = self.work.dim();
        st.sol.copy_from_slice(&st.rhs);
        st.m.solve_in_place(&mut st.sol);
        for (i, s) in st.step.iter_mut().enumerate() {
            let mut v = DVec3::ZERO;
            for c in 0..dim {
                v[c] = st.sol[i * dim + c].x;
            }
            *s = v;
        }
        self.constrain_update(&mut st.step);
        self.chk_displacements(&st.step, &mut st.sdisp);
    }

    /// The interior point's line search: backtracking on the barrier function `E + τ (−Σ ln(c_j/m²))` from
    /// the longest feasible step `a_max`, halved up to 12 times until it does not rise. Leaves the accepted
    /// candidate in `st.cand`, `st.cdisp`; returns (α, objective, roughness, barrier) there, or `None`.
    fn ip_backtrack(&self, st: &mut IpState, obj: Objective, m2: f64, a_max: f64) -> Option<(f64, f64, f64, f64)> {
        let phi0 = st.e_x + st.tau * st.log_b;
        let mut alpha = a_max;
        for _ in 0..12 {
            for ((c, x0), s) in st.cand.iter_mut().zip(&st.x).zip(&st.step) {
                *c = *x0 + *s * alpha;
            }
            for ((c, d0), s) in st.cdisp.iter_mut().zip(&st.disp).zip(&st.sdisp) {
                *c = *d0 + *s * alpha;
            }
            let lb = barrier_log_sum(&st.cdisp, m2);
            if lb.is_finite() {
                let (e_c, rough) = self.objective_value(obj, &st.cand);
                // NaN-safe: a NaN energy is not a decrease
                if e_c + st.tau * lb <= phi0 {
                    return Some((alpha, e_c, rough, lb));
                }
            }
            alpha *= 0.5;
        }
        None
    }

    /// The interior point's ranking of an accepted iterate (`st.x`, of roughness or E_var `rough`): kept in
    /// `best` if it is fairer than the best so far.
    fn ip_consider(&self, best: &mut IpBest, obj: Objective, st: &IpState, rough: f64) {
        let better = if let Some((max_extrema, max_var)) = obj.ceiling {
            let take = st.e_x < best.value && rough <= max_var && {
                let ext = self.node_extrema(&st.x);
                ext <= max_extrema && {
                    best.extrema = ext;
                    true
                }
            };
            if take {
                best.var = rough;
            }
            take
        } else if obj.var > 0.0 {
            // the objective steers the descent; E_var (the curvature's own variation) picks among equals
            // (the extrema are probed only for an iterate whose E_var is not above the start's)
            let take = rough <= best.start_var && {
                let ext = self.node_extrema(&st.x);
                let take = ext < best.extrema || (ext == best.extrema && rough < best.var);
                if take {
                    best.extrema = ext;
                }
                take
            };
            if take {
                best.var = rough;
            }
            take
        } else {
            st.e_x < best.value && rough <= best.rough_cap
        };
        if better {
            let dev = st.disp.iter().fold(0.0f64, |a, d| a.max(d.length_squared())).sqrt();
            (best.value, best.dev, best.upd) = (st.e_x, dev, st.x.clone());
        }
    }

    /// The interior point's objective at the update `d` and, for the paper's E, the roughness its steps
    /// are capped by (for the variation objective: E_var).
    fn objective_value(&self, obj: Objective, d: &[DVec3]) -> (f64, f64) {
        let (mut v, mut rough) = (0.0, 0.0);
        if obj.paper > 0.0 {
            let (e, r) = self.energy_and_roughness::<true>(d);
            v += obj.paper * e;
            rough = r;
        }
        if obj.var > 0.0 {
            let (ev, third) = self.variation_parts(d);
            v += obj.var * (ev + third);
            rough = ev;
        }
        (v, rough)
    }

    /// [`PolishMethod::Variation`](super::PolishMethod::Variation): from the reference smoother's result or the fit's, whichever is fairer
    /// (fewer curvature extrema at the quadrature nodes, then the lower E_var), the interior point on
    /// `E_var + β ∫ (κ − g)² ds / ℓ²`.
    pub(super) fn polish_variation(&mut self, accept: f64, dev: f64, e: f64, solves: &mut usize) -> Result<(f64, f64)> {
        let obj = self.variation_objective();
        // how fair an update is: (curvature extrema, E_var), as the interior point ranks its iterates
        let rank_of = |s: &Self, d: &[DVec3]| (s.node_extrema(d), s.variation_parts(d).0);
        let fit = (self.best.clone(), dev, e);
        let fit_rank = rank_of(self, &fit.0);
        let (smooth, sdev, smooth_rank) = match &self.polish_cache.smooth {
            Some(s) if s.band == accept.to_bits() && s.upd.len() == self.nf => {
                self.best.copy_from_slice(&s.upd);
                (s.upd.clone(), s.dev, s.rank)
            }
            _ => {
                let (_, _, sdev) = self.search_smoothing(accept, solves)?;
                let smooth = self.best.clone();
                let rank = rank_of(self, &smooth);
                self.polish_cache.smooth = Some(SmoothStart {
                    band: accept.to_bits(),
                    upd: smooth.clone(),
                    dev: sdev,
                    rank,
                    measured_var: None,
                    judged: Default::default(),
                });
                (smooth, sdev, rank)
            }
        };
        let zero = vec![DVec3::ZERO; self.nf];
        let orig_rank = match self.polish_cache.orig_rank {
            Some(r) => r,
            None => {
                let r = rank_of(self, &zero);
                self.polish_cache.orig_rank = Some(r);
                r
            }
        };
        // the start: the fairest of the smoother's result, the fit's and the original
        let from_smoother = smooth_rank <= fit_rank && smooth_rank <= orig_rank;
        let (dev, e, start_rank) = if from_smoother {
            (sdev, self.energy_of_update(&self.best), smooth_rank)
        } else if fit_rank <= orig_rank {
            self.best = fit.0;
            (fit.1, fit.2, fit_rank)
        } else {
            self.best.fill(DVec3::ZERO);
            (0.0, self.original_energy(), orig_rank)
        };
        // the reference as it is delivered: the original where the smoother's result has more extrema
        let bar = if smooth_rank.0 > orig_rank.0 {
            orig_rank
        } else {
            smooth_rank
        };
        let (mut dev, mut e, rank) = self.polish_variation_torsion(accept, (dev, e), solves, obj, start_rank);
        let mut rank = rank.unwrap_or_else(|| rank_of(self, &self.best));
        // at least as fair as the smoother on both counts: where the result has fewer extrema but a larger
        // E_var than the smoother's (or more extrema), the polish also runs from the smoother's result, whose
        // iterates never have more extrema or a larger E_var than it; that result is taken unless it has
        // more extrema than the original
        if !(from_smoother || (rank.0 <= smooth_rank.0 && rank.1 <= smooth_rank.1)) {
            let first = (std::mem::replace(&mut self.best, smooth.clone()), dev, e);
            let e_smooth = self.energy_of_update(&self.best);
            let (dev2, e2, rank2) = self.polish_variation_torsion(accept, (sdev, e_smooth), solves, obj, smooth_rank);
            let rank2 = rank2.unwrap_or_else(|| rank_of(self, &self.best));
            if rank2.0 <= orig_rank.0 {
                (dev, e, rank) = (dev2, e2, rank2);
            } else {
                (self.best, dev, e) = first;
            }
        }
        if !self.var.jumps.is_empty() {
            // the reference as it is delivered: the original where the smoother's result has more extrema
            let reference = if smooth_rank.0 > orig_rank.0 { &zero } else { &smooth };
            let reference = (self.node_extrema(reference), self.variation_in_spans(reference));
            if let Some(taken) = self.polish_without_steps(accept, (dev, e), (&smooth, sdev), reference, solves, obj) {
                (dev, e) = taken;
                // judged as the smoother was: E_var over the spans
                rank = (self.node_extrema(&self.best), self.variation_in_spans(&self.best));
                let orig = (orig_rank.0, self.variation_in_spans(&zero));
                if rank.0 <= orig.0 && rank.1 < orig.1 {
                    return Ok((dev, e));
                }
                // judged by the same measure, not fairer than the input: the input is kept
                self.best = zero;
                return Ok((0.0, self.original_energy()));
            }
        }
        if !self.var.twist.is_empty() && rank.0 <= bar.0 && rank.1 < bar.1 * (1.0 - TWIST_BAR_MARGIN) {
            let ceiling = (rank.0, bar.1 * (1.0 - TWIST_BAR_MARGIN));
            (dev, e, rank) = self.polish_torsion_within(accept, (dev, e, rank), solves, obj, ceiling);
        }
        // judged as the reference is judged where the two come close: at least as fair as it by `measure`
        if let Some(moved) = self.judged_against_reference(rank, (bar, smooth_rank), &smooth) {
            return Ok(moved);
        }
        // never less fair than the input: a result without fewer curvature extrema or a lower E_var than the
        // original's (a straight line, which the smoother would only re-parametrize) leaves it as it is
        if rank.0 > orig_rank.0 || (rank.0 == orig_rank.0 && !(rank.1 < orig_rank.1 * (1.0 - 1e-9))) {
            self.best = zero;
            return Ok((0.0, self.original_energy()));
        }
        Ok((dev, e))
    }

    /// The variation polish's objective `E_var + β ∫ (κ − g)² ds / ℓ²`, scaled by `β h / ℓ²` to
    /// `E + (ℓ² / (β h)) E_var` (E_var alone where β = 0).
    pub(super) fn variation_objective(&self) -> Objective {
        let beta = self.opts.target_weight.max(0.0);
        let spans = self.var.w.len() / variation::VAR_GAUSS;
        let ell = self.h * (self.params.len() - 1) as f64 / spans.max(1) as f64;
        if beta > 0.0 {
            Objective {
                paper: 1.0,
                var: ell * ell / (beta * self.h),
                ceiling: None,
            }
        } else {
            Objective {
                paper: 0.0,
                var: 1.0,
                ceiling: None,
            }
        }
    }

    /// The interior point of the variation polish. On a non-planar 3D curve it carries the torsion term
    /// ([`FairingOptions::torsion_weight`](super::FairingOptions::torsion_weight)), which fairs τ as well
    /// as κ; where that result has more curvature extrema or no lower E_var than the polish started from,
    /// the polish runs again from the same start without the term and keeps whichever has fewer curvature
    /// extrema (then the lower E_var): the torsion is faired only where the curvature does not pay for it.
    /// [`Self::polish_torsion_within`] then spends what the curvature has to spare.
    pub(super) fn polish_variation_torsion(
        &mut self,
        accept: f64,
        (dev, e): (f64, f64),
        solves: &mut usize,
        obj: Objective,
        start_rank: Rank,
    ) -> (f64, f64, Option<Rank>) {
        // the band as the hull of the difference curve (`hull.rs`): held everywhere, not only at the samples
        if !self.hull_band {
            return self.on_hull_rows(|s| s.polish_variation_torsion(accept, (dev, e), solves, obj, start_rank));
        }
        if self.var.twist.is_empty() {
            return self.interior_point(accept, dev, e, solves, obj, Some(start_rank));
        }
        let rank_of =
            |s: &Self, r: Option<Rank>| r.unwrap_or_else(|| (s.node_extrema(&s.best), s.variation_parts(&s.best).0));
        let start = self.best.clone();
        let (tdev, te, trank) = self.interior_point(accept, dev, e, solves, obj, Some(start_rank));
        let rank = rank_of(self, trank);
        if rank.0 <= start_rank.0 && rank.1 < start_rank.1 * (1.0 - 1e-9) {
            return (tdev, te, Some(rank));
        }
        let twisted_best = std::mem::replace(&mut self.best, start);
        let twist = std::mem::take(&mut self.var.twist);
        let (pdev, pe, prank) = self.interior_point(accept, dev, e, solves, obj, Some(start_rank));
        self.var.twist = twist;
        let plain_rank = rank_of(self, prank);
        if rank < plain_rank {
            self.best = twisted_best;
            (tdev, te, Some(rank))
        } else {
            (pdev, pe, Some(plain_rank))
        }
    }

    /// The torsion pass of a non-planar 3D curve whose curvature came out fairer than the reference
    /// smoother's with room to spare (`ceiling`: its curvature extrema, and the reference's E_var less
    /// [`TWIST_BAR_MARGIN`]): the interior point again from `self.best`, on the objective with the
    /// torsion term scaled to E_var's size there, each iterate taken if it lowers that objective and
    /// stays within the ceiling. Why: where the polish kept the run without the term (the term's run did
    /// not improve the curvature rank), its result can twist — on a real impeller edge (20 points,
    /// 5·10⁻⁴ of its diagonal) τ ran to −3 over a span where the input had −0.1, the torsion energy 50 ×
    /// the input's — and the term at its own weight then outweighs E_var ten-thousandfold, its run giving
    /// up the curvature (12 extrema from 8). Balanced, the pass lowers both: that edge's torsion energy
    /// 164 → 23 and E_var 6.3·10⁻³ → 1.3·10⁻³ (measured over the 66 real curves of
    /// `examples/real_curves.rs`: Σ curvature extrema 383 → 317, E_var ×0.65 (geometric mean), Σ torsion
    /// extrema 283 → 290; the term at 3 × E_var: 343 and 283; without the term: 306 but two curves above
    /// the reference's E_var and torsion extrema 375).
    fn polish_torsion_within(
        &mut self,
        accept: f64,
        (dev, e, rank): (f64, f64, Rank),
        solves: &mut usize,
        obj: Objective,
        ceiling: Rank,
    ) -> (f64, f64, Rank) {
        let obj = Objective {
            ceiling: Some(ceiling),
            ..obj
        };
        // the torsion term balanced against E_var at the start (never raised above its own weight)
        let (ev, third) = self.variation_parts(&self.best);
        if !(ev > 0.0 && third > 0.0) {
            // nothing twists, or no curvature variation to spend
            return (dev, e, rank);
        }
        let own = self.var.twist.clone();
        self.var.twist.scale((ev / third).min(1.0));
        // on the hull band, as every run of the variation polish (`hull.rs`)
        let (tdev, te, trank) = self.on_hull_rows(|s| s.interior_point(accept, dev, e, solves, obj, Some(rank)));
        self.var.twist = own;
        match trank {
            Some(r) => (tdev, te, r),
            None => (dev, e, rank),
        }
    }

    /// `m += ρ P_i` on each free point's diagonal block, `P_i` the projector onto the directions its
    /// update may not take ([`Self::constrain_point`]): the normal of a planar 3D curve's plane, and at a
    /// constrained join everything but the join's tangent (or every direction for a held point).
    fn penalize_constrained(&self, m: &mut BandedSpd, rho: f64) {
        if self.plane.is_none() && self.join_fix.is_empty() {
            return;
        }
        let dim = self.work.dim();
        for i in 0..self.nf {
            let fix = self.join_fix.iter().find(|(k, _)| *k == i).map(|&(_, t)| t);
            for r in 0..dim {
                for q in 0..=r {
                    let id = if r == q { 1.0 } else { 0.0 };
                    let mut v = 0.0;
                    if let Some(n) = self.plane {
                        v += n[r] * n[q];
                    }
                    match fix {
                        Some(Some(t)) => v += id - t[r] * t[q],
                        Some(None) => v += id,
                        None => {}
                    }
                    if v != 0.0 {
                        m.add(i * dim + r, i * dim + q, rho * v);
                    }
                }
            }
        }
    }

    /// The band constraints' part of the interior-point system ([`Self::polish_interior`]) at the
    /// displacements `disp` with duals `z`: `h += Σ_j (b bᵀ) ⊗ (z_j I + 2 z_j/c_j D_j D_jᵀ)` and
    /// `rhs −= Σ_j (τ / c_j) b ⊗ D_j` (the halved barrier of E/2). `N` = p + 1 and `D` = dim for the
    /// common cases (check samples whose rows are all free take a fixed-size path), 0 for any.
    fn barrier_terms<const N: usize, const D: usize>(
        &self,
        disp: &[DVec3],
        z: &[f64],
        tau: f64,
        m2: f64,
        h: &mut BandedSpd,
        rhs: &mut [DVec3],
    ) {
        let np1 = self.work.degree() + 1;
        let dim = self.work.dim();
        let nf = self.nf;
        // the divisions first, in a loop of their own (independent lanes), then the assembly
        let coef: Vec<[f64; 2]> = disp
            .iter()
            .zip(z)
            .map(|(d, &zj)| {
                let c = m2 - d.length_squared();
                [2.0 * zj / c, tau / c]
            })
            .collect();
        for (j, d) in disp.iter().enumerate() {
            let (zi, [zd, gj]) = (z[j], coef[j]);
            let f = self.chk_first[j];
            let b = &self.chk_b[j * np1..(j + 1) * np1];
            if N > 0 && f >= 0 && f as usize + N <= nf {
                let base = f as usize;
                let bf: &[f64; N] = b.try_into().expect("N rows");
                let mut m = [[0.0; D]; D];
                for r in 0..D {
                    for q in 0..D {
                        m[r][q] = zd * d[r] * d[q];
                    }
                    m[r][r] += zi;
                }
                let block: &mut [DVec3] = &mut rhs[base * D..base * D + N * D];
                for a in 0..N {
                    let ga = gj * bf[a];
                    for r in 0..D {
                        block[a * D + r].x -= ga * d[r];
                    }
                }
                h.add_kron_fixed::<N, D>(base * D, bf, &m);
                continue;
            }
            for a in 0..np1 {
                let la = f + a as isize;
                if la < 0 || la as usize >= nf {
                    continue;
                }
                let la = la as usize;
                for r in 0..dim {
                    rhs[la * dim + r].x -= gj * b[a] * d[r];
                }
                for bb in 0..=a {
                    let lb = f + bb as isize;
                    if lb < 0 {
                        continue;
                    }
                    let lb = lb as usize;
                    let w = b[a] * b[bb];
                    for r in 0..dim {
                        for q in 0..dim {
                            if bb == a && q > r {
                                continue;
                            }
                            let mut v = zd * d[r] * d[q];
                            if r == q {
                                v += zi;
                            }
                            h.add(la * dim + r, lb * dim + q, w * v);
                        }
                    }
                }
            }
        }
    }

    /// Parametric displacements `D_j = Σ_i N_i(u_j) d_i` of the update `d` at every check sample.
    fn chk_displacements(&mut self, d: &[DVec3], out: &mut [DVec3]) {
        let np1 = self.work.degree() + 1;
        let mut pad = std::mem::take(&mut self.pad);
        pad.clear();
        pad.resize(self.nf + 2 * np1, DVec3::ZERO);
        pad[np1..np1 + self.nf].copy_from_slice(d);
        for (j, o) in out.iter_mut().enumerate() {
            *o = self.chk_rows(&pad, j).1;
        }
        self.pad = pad;
    }
}

/// `−Σ_j ln(c_j / m²)`, `c_j = m² − |D_j|²`, of the interior-point polish's barrier (∞ outside the band):
/// the logarithm of products of eight terms at a time (each in (0, 1]), one `ln` per eight samples
/// unless a product underflows.
fn barrier_log_sum(disp: &[DVec3], m2: f64) -> f64 {
    let inv = 1.0 / m2;
    let mut s = 0.0;
    for chunk in disp.chunks(8) {
        let mut prod = 1.0;
        for d in chunk {
            let c = 1.0 - d.length_squared() * inv;
            if !(c > 0.0) {
                return f64::INFINITY;
            }
            prod *= c;
        }
        if prod > 1e-280 {
            s -= prod.ln();
        } else {
            for d in chunk {
                s -= (1.0 - d.length_squared() * inv).ln();
            }
        }
    }
    s
}

#[cfg(test)]
#[path = "polish_tests.rs"]
mod tests;
