//! The variation polish's last look (`judged_against_reference`): its result measured as the reference
//! smoother's is judged — `measure`'s curvature extrema and ∫(dκ/ds)² on the whole curve — and moved
//! towards the smoother's result where it is not at least as fair.

use glam::DVec3;

use crate::BSplineCurve;

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

/// A rank as `measure` counts it, each part computed once it is asked for (a curve's judged extrema and
/// E_var are kept between re-fairs where the curve stays: the original, the smoother's result).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Parts {
    extrema: Option<usize>,
    var: Option<f64>,
}

impl Parts {
    fn rank(self) -> Option<Rank> {
        Some((self.extrema?, self.var?))
    }
}

impl FairingSetup {
    /// `parts` of `c₀ + Σ N_i d_i` with the extrema, and E_var where `var` asks for it, filled in
    /// ([`Self::judged`] where both are missing, one measure otherwise).
    fn judged_parts(&self, parts: Parts, d: &[DVec3], var: bool) -> Option<Parts> {
        match (parts.extrema, parts.var) {
            (None, None) if var => {
                let (e, v) = self.judged(d)?;
                Some(Parts {
                    extrema: Some(e),
                    var: Some(v),
                })
            }
            (None, _) => Some(Parts {
                extrema: Some(self.judged_extrema(&self.updated_curve(d).ok()?)),
                ..parts
            }),
            (Some(_), None) if var => Some(Parts {
                var: Some(crate::measure::energies(&self.updated_curve(d).ok()?).0),
                ..parts
            }),
            _ => Some(parts),
        }
    }

    /// The curvature extrema of `c` as `measure` counts them on the whole working curve (around the loop
    /// on a closed one), with `measure`'s dead band of the working curve.
    fn judged_extrema(&self, c: &BSplineCurve) -> usize {
        extrema_of(c, self.judged_delta())
    }

    /// `measure`'s dead band, from the whole curve's reference target (the polish's own, `var.delta`, is
    /// from the stretch's denser samples: on a noisy 300-point wave it is half of this).
    fn judged_delta(&self) -> f64 {
        match self.polish_cache.judged_delta.get() {
            Some(d) => d,
            None => {
                let d = crate::measure::extrema_threshold(&self.work);
                self.polish_cache.judged_delta.set(Some(d));
                d
            }
        }
    }

    /// (curvature extrema, E_var) of `c₀ + Σ N_i d_i` as `measure` counts them on the whole working curve
    /// (around the loop on a closed one), with the polish's dead band.
    fn judged(&self, d: &[DVec3]) -> Option<Rank> {
        let c = self.updated_curve(d).ok()?;
        let delta = self.judged_delta();
        let extrema = || extrema_of(&c, delta);
        let var = || crate::measure::energies(&c).0;
        // on a long curve the two measures (each O(spans), 40 samples a span) run side by side
        let rank = if c.knots().n_spans() >= PARALLEL_SPANS {
            rayon::join(extrema, var)
        } else {
            (extrema(), var())
        };
        // the last curve judged is usually the result: the final guard of `CurveFairing::fair` counts it again
        *self.polish_cache.last_judged.borrow_mut() = Some((c, rank.0));
        Some(rank)
    }

    /// The curvature extrema of `c` with dead band `delta` as `measure` counts them, where this setup has
    /// counted them already (the last curve judged, at `measure`'s dead band of the working curve): the
    /// final guard of [`crate::fair::CurveFairing::fair`] counts the result, which a close call here has
    /// usually just counted.
    pub(crate) fn counted_extrema(&self, c: &BSplineCurve, delta: f64) -> Option<usize> {
        if self.polish_cache.judged_delta.get()?.to_bits() != delta.to_bits() {
            return None;
        }
        match &*self.polish_cache.last_judged.borrow() {
            Some((last, e)) if last == c => Some(*e),
            _ => None,
        }
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
        let best_var = if self.best.as_slice() == smooth {
            smooth_var
        } else {
            measured_var(self, &self.best)
        };
        let close = near(bar) || near(smooth_rank) || !(best_var < CLOSE_VAR * smooth_var);
        if !close {
            return None;
        }
        let zero = vec![DVec3::ZERO; self.nf];
        // the smoother's own result (the polish found nothing fairer: a 10,000-point curve): it is at least as
        // fair as the reference unless the smoother's has more extrema than the original (then the original
        // is the reference), which the extrema alone decide
        let tie = self.best.as_slice() == smooth;
        // (both are kept for the re-fairs of this setup: the original's always, the smoother's at its band)
        let (mut orig, mut smoothed) = (
            self.polish_cache.judged_orig,
            self.polish_cache.smooth.as_ref().map(|s| s.judged).unwrap_or_default(),
        );
        if tie && orig.extrema.is_none() && smoothed.extrema.is_none() && self.work.knots().n_spans() >= PARALLEL_SPANS
        {
            // a long curve: the two counts side by side
            let (c0, cs) = (self.updated_curve(&zero).ok()?, self.updated_curve(smooth).ok()?);
            let delta = self.judged_delta();
            let (e0, es) = rayon::join(|| extrema_of(&c0, delta), || extrema_of(&cs, delta));
            (orig.extrema, smoothed.extrema) = (Some(e0), Some(es));
        }
        let mut orig = self.judged_parts(orig, &zero, !tie)?;
        let mut smoothed = self.judged_parts(smoothed, smooth, !tie)?;
        if tie && smoothed.extrema <= orig.extrema {
            self.keep_judged(orig, smoothed);
            return None;
        }
        orig = self.judged_parts(orig, &zero, true)?;
        smoothed = self.judged_parts(smoothed, smooth, true)?;
        self.keep_judged(orig, smoothed);
        let (orig, smoothed) = (orig.rank()?, smoothed.rank()?);
        let (goal, theirs) = if smoothed.0 > orig.0 {
            (zero, orig)
        } else {
            (smooth.to_vec(), smoothed)
        };
        let fair_enough = |r: Rank| r.0 <= theirs.0 && r.1 <= theirs.1;
        let ours = if tie { smoothed } else { self.judged(&self.best)? };
        if fair_enough(ours) {
            return None;
        }
        Some(self.least_move_towards(goal, |s, d| s.judged(d).is_some_and(fair_enough)))
    }

    /// Keep the judged parts of the original and of the smoother's result for the re-fairs.
    fn keep_judged(&mut self, orig: Parts, smoothed: Parts) {
        self.polish_cache.judged_orig = orig;
        if let Some(s) = self.polish_cache.smooth.as_mut() {
            s.judged = smoothed;
        }
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

/// The curvature extrema of `c` as `measure` counts them (around the loop on a closed curve), dead band `delta`.
fn extrema_of(c: &BSplineCurve, delta: f64) -> usize {
    if crate::curve::is_closed_curve(c) {
        crate::measure::curvature_extrema_around(c, delta)
    } else {
        crate::measure::curvature_extrema_at(c, delta)
    }
}
