//! The variation polish's last look (`judged_against_reference`): its result measured as the reference
//! smoother's is judged — `measure`'s curvature extrema and ∫(dκ/ds)² on the whole curve — and moved
//! towards the smoother's result where it is not at least as fair.

use glam::DVec3;

use super::super::FairingSetup;
use super::{Rank, STEP_BLEND_BISECTIONS};

/// The polish's own rank (extrema at its probes, E_var at its nodes) is within this many extrema (or a
/// fifth of the reference's, if more) or this fraction of E_var of the reference's: a close call, measured
/// again as `measure` measures.
const CLOSE_EXTREMA: usize = 2;
const CLOSE_VAR: f64 = 0.9;
/// Knot spans from which [`FairingSetup::judged`]'s two measures run in parallel (at 1,000 spans each
/// takes milliseconds; below, a thread's wake-up is not worth it).
const PARALLEL_SPANS: usize = 1000;

impl FairingSetup {
    /// (curvature extrema, E_var) of `c₀ + Σ N_i d_i` as `measure` counts them on the whole working curve
    /// (around the loop on a closed one), with the polish's dead band.
    fn judged(&self, d: &[DVec3]) -> Option<Rank> {
        let c = self.updated_curve(d).ok()?;
        // `measure`'s dead band, from the whole curve's reference target (the polish's own, `var.delta`,
        // is from the stretch's denser samples: on a noisy 300-point wave it is half of this)
        let delta = match self.polish_cache.judged_delta.get() {
            Some(d) => d,
            None => {
                let d = crate::measure::extrema_threshold(&self.work);
                self.polish_cache.judged_delta.set(Some(d));
                d
            }
        };
        let extrema = || {
            if crate::curve::is_closed_curve(&c) {
                crate::measure::curvature_extrema_around(&c, delta)
            } else {
                crate::measure::curvature_extrema_at(&c, delta)
            }
        };
        let var = || crate::measure::energies(&c).0;
        // on a long curve the two measures (each O(spans), 40 samples a span) run side by side
        Some(if c.knots().n_spans() >= PARALLEL_SPANS {
            rayon::join(extrema, var)
        } else {
            (extrema(), var())
        })
    }

    /// The polish ranks its iterates at its own probes and nodes; the reference smoother is judged by
    /// `measure` (4000 arc-length samples, 40 Gauss nodes a span). Where the two ranks of the result in
    /// `self.best` and of the reference as it is delivered (the smoother's update `smooth`, or the original
    /// where that has more extrema) are close (`rank` against `bar`, within [`CLOSE_EXTREMA`] or
    /// [`CLOSE_VAR`]), or the result's E_var on 10 Gauss nodes a span is not [`CLOSE_VAR`] of the
    /// smoother's (checked on every result), both are measured as `measure` does; if the result then has more extrema or a larger
    /// E_var, the update taken is the least move from it towards the reference's that is at least as fair
    /// on both counts (a bisection on the segment; its end is the reference's result itself, a tie).
    /// `Some((dev, e))` of the moved update in `self.best`; `None` where nothing moved.
    pub(super) fn judged_against_reference(
        &mut self,
        rank: Rank,
        (bar, smooth_rank): (Rank, Rank),
        smooth: &[DVec3],
    ) -> Option<(f64, f64)> {
        // (the counts differ more where there are many extrema: a fifth of them is a close call too)
        let near = |r: Rank| rank.0 + CLOSE_EXTREMA.max(r.0 / 5) >= r.0 || rank.1 >= CLOSE_VAR * r.1;
        // E_var on 10 Gauss nodes a span (the polish's 6 can miss a spike between them; `measure` has 40,
        // which costs 4 × more), ours against the smoother's: a result the polish ranks far ahead can still
        // lose there
        let measured_var = |s: &Self, d: &[DVec3]| {
            s.updated_curve(d)
                .map_or(f64::NAN, |c| crate::measure::energies_with(&c, 1).0)
        };
        let smooth_var = match self.polish_cache.smooth.as_ref().and_then(|s| s.measured_var) {
            Some(v) => v,
            None => {
                let v = measured_var(self, smooth);
                if let Some(s) = self.polish_cache.smooth.as_mut() {
                    s.measured_var = Some(v);
                }
                v
            }
        };
        let close = near(bar) || near(smooth_rank) || !(measured_var(self, &self.best) < CLOSE_VAR * smooth_var);
        if !close {
            return None;
        }
        let zero = vec![DVec3::ZERO; self.nf];
        // (both are kept for the re-fairs of this setup: the original's always, the smoother's at its band)
        let orig = match self.polish_cache.judged_orig {
            Some(r) => r,
            None => {
                let r = self.judged(&zero)?;
                self.polish_cache.judged_orig = Some(r);
                r
            }
        };
        let smoothed = match self.polish_cache.smooth.as_ref().and_then(|s| s.judged) {
            Some(r) => r,
            None => {
                let r = self.judged(smooth)?;
                if let Some(s) = self.polish_cache.smooth.as_mut() {
                    s.judged = Some(r);
                }
                r
            }
        };
        let (goal, theirs) = if smoothed.0 > orig.0 {
            (zero, orig)
        } else {
            (smooth.to_vec(), smoothed)
        };
        let fair_enough = |r: Rank| r.0 <= theirs.0 && r.1 <= theirs.1;
        // the smoother's own result (the polish found nothing fairer: a 10,000-point curve) is judged already
        let ours = if self.best.as_slice() == smooth {
            smoothed
        } else {
            self.judged(&self.best)?
        };
        if fair_enough(ours) {
            return None;
        }
        Some(self.least_move_towards(goal, |s, d| s.judged(d).is_some_and(fair_enough)))
    }

    /// The least move from the update in `self.best` towards `goal` that `ok` accepts: a bisection on the
    /// segment between the two ([`STEP_BLEND_BISECTIONS`] halvings; the band, convex in the update, holds
    /// along it), the goal itself (not a + 1·(g − a), a rounding away from it) where no shorter move is
    /// accepted. Leaves it in `self.best`; returns its (deviation at the check samples, paper's E).
    pub(super) fn least_move_towards(&mut self, goal: Vec<DVec3>, ok: impl Fn(&Self, &[DVec3]) -> bool) -> (f64, f64) {
        let blend =
            |t: f64, a: &[DVec3]| -> Vec<DVec3> { a.iter().zip(&goal).map(|(a, g)| *a + t * (*g - *a)).collect() };
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..STEP_BLEND_BISECTIONS {
            let t = 0.5 * (lo + hi);
            if ok(self, &blend(t, &self.best)) {
                hi = t;
            } else {
                lo = t;
            }
        }
        self.best = if hi < 1.0 { blend(hi, &self.best) } else { goal };
        let mut disp = vec![DVec3::ZERO; self.chk_u.len()];
        self.chk_displacements(&self.best.clone(), &mut disp);
        let dev = disp.iter().fold(0.0f64, |a, d| a.max(d.length_squared())).sqrt();
        (dev, self.energy_of_update(&self.best))
    }
}
