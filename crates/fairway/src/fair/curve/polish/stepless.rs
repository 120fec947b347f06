//! The polish's run without the curvature-step prices at knots below C2 (`polish_without_steps`), for
//! results that lose to the reference smoother on ∫(dκ/ds)² over the spans.

use glam::DVec3;

use super::super::FairingSetup;
use super::{Objective, STEP_BLEND_MARGIN};

impl FairingSetup {
    /// At knots below C2 the polish prices the curvature steps, which ∫(dκ/ds)² over the spans (what
    /// `measure` and the reference smoother are judged by) does not see, so its result can trade a larger
    /// E_var inside the spans for smaller steps. Where the result in `self.best` (deviation and paper's E
    /// `at`) has more curvature extrema or a larger E_var over the spans than the `reference` (the rank, in
    /// those terms, of what the reference smoother delivers), the polish runs on without the step prices,
    /// from the result and from the smoother's result `smooth`; each run's iterates never have more
    /// extrema or a larger E_var than its start. Of the runs at least as fair as the reference on both
    /// counts, the fairer (fewer extrema, then the lower E_var) is the goal, and the update taken is the
    /// least move from the step-priced result towards it that is at least as fair as the reference (a
    /// bisection on the segment between the two; the band, convex in the update, holds along it): the
    /// steps grow only as far as that needs. `Some((dev, e))` of it in `self.best`; `None` (and
    /// `self.best` as it was) if the result already was as fair as the reference, or no run is.
    pub(super) fn polish_without_steps(
        &mut self,
        accept: f64,
        at: (f64, f64),
        (smooth, sdev): (&[DVec3], f64),
        reference: (usize, f64),
        solves: &mut usize,
        obj: Objective,
    ) -> Option<(f64, f64)> {
        let rank = |s: &Self, d: &[DVec3]| (s.node_extrema(d), s.variation_in_spans(d));
        let beats = |r: (usize, f64)| r.0 <= reference.0 && r.1 <= reference.1;
        if beats(rank(self, &self.best)) {
            return None;
        }
        let first = self.best.clone();
        let jumps = std::mem::take(&mut self.var.jumps);
        // the starts' ranks without the step prices (the interior point's iterates are ranked against them)
        let start_rank = |s: &Self| (s.node_extrema(&s.best), s.variation_parts(&s.best).0);
        let r = start_rank(self);
        self.polish_variation_torsion(accept, at, solves, obj, r);
        let from_result = std::mem::replace(&mut self.best, smooth.to_vec());
        let e_smooth = self.energy_of_update(&self.best);
        let r = start_rank(self);
        self.polish_variation_torsion(accept, (sdev, e_smooth), solves, obj, r);
        let from_smoother = std::mem::replace(&mut self.best, first);
        self.var.jumps = jumps;
        let (r1, r2) = (rank(self, &from_result), rank(self, &from_smoother));
        let goal = match (beats(r1), beats(r2)) {
            (true, b2) if !b2 || r1 <= r2 => from_result,
            (_, true) => from_smoother,
            _ => return None,
        };
        // a blend must beat the reference with a margin: `measure` integrates E_var with its own nodes
        let clear = |r: (usize, f64)| r.0 <= reference.0 && r.1 <= reference.1 * (1.0 - STEP_BLEND_MARGIN);
        Some(self.least_move_towards(goal, |s, d| clear(rank(s, d))))
    }
}
