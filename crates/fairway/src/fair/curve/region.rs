//! The region of a fairing resolved on the curve, its free control points and its samples (module docs
//! of `fair::curve`, steps 1–2): the first steps of [`super::FairingSetup::build`].

use super::{
    CHECK_SAMPLES_PER_SPAN, EndCondition, FairingOptions, MAX_SAMPLES, SLIVER_SNAP, snap_to_knot, validate_tolerance,
};
use crate::arclength::ArcLengthTable;
use crate::corners::{Corner, corners, counted, stretches_between};
use crate::curve::BSplineCurve;
use crate::error::{Error, Result};

/// The error of a region whose moving stretch crosses `found` (not empty): which corners, why they
/// stay, and the regions to fair instead.
fn crossed_corners(curve: &BSplineCurve, u1: f64, u2: f64, found: &[Corner]) -> Error {
    let list: Vec<String> = found.iter().map(Corner::describe).collect();
    let stretches = stretches_between(curve, u1, u2, found);
    let pieces: Vec<String> = stretches.iter().map(|(a, b)| format!("[{a}, {b}]")).collect();
    Error::RegionCrossesCorner {
        u1,
        u2,
        corners: found.iter().map(|c| c.u).collect(),
        stretches,
        description: format!(
            "{} of the curve {}: fairing across a corner would round it off inside the band, a curvature spike; \
             fair the stretches between corners as regions of their own ({}), as fair_curve and `fairway fair` \
             do by themselves",
            counted(found),
            list.join(", "),
            pieces.join(", ")
        ),
    }
}

/// The knots that cut off a sliver knot span at the start and at the end of `curve`: a span whose control
/// polygon (an upper bound of its arc length) is below [`SLIVER_SNAP`] of the mean span's.
fn end_slivers(curve: &BSplineCurve) -> (Option<f64>, Option<f64>) {
    let bps = curve.knots().breakpoints();
    let p = curve.degree();
    let pts = curve.points();
    let polygon = |a: usize, b: usize| -> f64 { pts[a..=b].windows(2).map(|w| w[0].distance(w[1])).sum() };
    let n_spans = bps.len().saturating_sub(1);
    if n_spans < 3 {
        return (None, None);
    }
    let mean = polygon(0, pts.len() - 1) / n_spans as f64;
    let first = (polygon(0, p) < SLIVER_SNAP * mean).then(|| bps[1]);
    let last = (polygon(pts.len() - 1 - p, pts.len() - 1) < SLIVER_SNAP * mean).then(|| bps[n_spans - 1]);
    (first, last)
}

/// The region of a fairing resolved on the curve: the first steps of [`super::FairingSetup::build`].
pub(super) struct Region {
    /// The curve as given (non-rational).
    pub(super) input: BSplineCurve,
    /// The check samples: as asked, at least [`CHECK_SAMPLES_PER_SPAN`] a knot span (0 stays 0).
    pub(super) check_samples: usize,
    /// The curve's domain.
    pub(super) domain: (f64, f64),
    /// The region `[u1, u2]` within the domain (a G1 / G0 end a sliver from a knot moved onto it by
    /// [`Self::working_curve`]).
    pub(super) u1: f64,
    pub(super) u2: f64,
    /// Parameters this close (1e-12 of the domain) are the same.
    pub(super) eps: f64,
    /// Whether the region reaches the start / end of the domain.
    pub(super) at_start: bool,
    pub(super) at_end: bool,
    /// The end conditions at `u1`, `u2` (at the ends of an open curve: `curve_ends`).
    pub(super) ends: [EndCondition; 2],
}

impl Region {
    /// Validate the tolerance, the curve and the region; the end conditions that apply.
    pub(super) fn resolve(
        curve: &BSplineCurve,
        opts: &FairingOptions,
        check_samples: usize,
        ends: [EndCondition; 2],
    ) -> Result<Self> {
        validate_tolerance(opts.tolerance)?;
        let input = curve.to_polynomial()?;
        let size = input.points().iter().map(|p| p.abs().max_element()).fold(0.0, f64::max);
        crate::range::check_tolerance_at(opts.tolerance, size)?;
        let check_samples = if check_samples == 0 {
            0
        } else {
            check_samples
                .max(2)
                .max(CHECK_SAMPLES_PER_SPAN * input.knots().n_spans() + 1)
        };
        let p = input.degree();
        if p < 2 {
            return Err(Error::DegreeTooLowToFair { degree: p });
        }
        let (d0, d1) = input.domain();
        let (u1, u2) = opts.region.unwrap_or((d0, d1));
        if !(u1.is_finite() && u2.is_finite()) {
            return Err(Error::RegionNotFinite { u1, u2 });
        }
        let eps = 1e-12 * (d1 - d0);
        for u in [u1, u2] {
            if u < d0 - eps || u > d1 + eps {
                return Err(Error::OutOfDomain {
                    what: "region end".into(),
                    value: u,
                    start: d0,
                    end: d1,
                });
            }
        }
        if u2 <= u1 {
            return Err(Error::EmptyRegion { u1, u2 });
        }
        let (mut u1, mut u2) = (u1.max(d0), u2.min(d1));
        let (mut at_start, mut at_end) = (u1 <= d0 + eps, u2 >= d1 - eps);
        // the region reaches an end of the curve (also where a sliver span there is left out)
        let (curve_start, curve_end) = (at_start, at_end);
        // a sliver knot span at an end of an open curve (a Bézier chain's last patch a hundredth of the
        // others') stays as it is: moving its joint a few band widths bends the curve inside it without
        // limit (measured on a public impeller model's edge: ∫(dκ/ds)² 1.1e4 → 1.5e14 with the band held).
        // The region then ends at the sliver's knot, with the curve end's condition.
        if !crate::curve::is_closed_curve(&input) {
            let slivers = end_slivers(&input);
            if at_start && let Some(k) = slivers.0.filter(|&k| k < u2) {
                (u1, at_start) = (k, false);
            }
            if at_end && let Some(k) = slivers.1.filter(|&k| k > u1) {
                (u2, at_end) = (k, false);
            }
        }
        // an end of an open curve has no neighbour in it: it takes its `curve_ends`, by default at most G1
        let ends = if crate::curve::is_closed_curve(&input) {
            ends
        } else {
            let reaches = [curve_start, curve_end];
            [0, 1].map(|i| match reaches[i] {
                true => opts.curve_ends[i].unwrap_or(ends[i].min_by_order(EndCondition::G1)),
                false => ends[i],
            })
        };
        Ok(Self {
            input,
            check_samples,
            domain: (d0, d1),
            u1,
            u2,
            eps,
            at_start,
            at_end,
            ends,
        })
    }

    /// The working curve: the input with a G1 / G0 region end inside the curve inserted as a knot of
    /// multiplicity p − 1 / p (the curve is unchanged), after moving such an end a sliver from a knot onto it.
    pub(super) fn working_curve(&mut self) -> Result<BSplineCurve> {
        let (input, p, (d0, d1), eps) = (&self.input, self.input.degree(), self.domain, self.eps);
        let (at_start, at_end, ends) = (self.at_start, self.at_end, self.ends);
        let (mut u1, mut u2) = (self.u1, self.u2);
        // G1/G0 freedom at interior ends: knot insertion (curve unchanged)
        let mut work = input.clone();
        let want = |e: EndCondition| match e {
            EndCondition::G2 => 0,
            EndCondition::G1 => p - 1,
            EndCondition::G0 => p,
        };
        // a G1 / G0 end within 1 % of its knot span of a knot inside the region is moved in onto it:
        // inserted beside it, it would make a moving sliver span whose few control points bend the
        // curve within it (measured: a G0 end 1.1e-5 from a knot, 2e-4 of the span, gave ∫(dκ/ds)²
        // 5.6e15 for 7.6). Only inward: what is outside the region stays as it is.
        let kv0 = input.knots().values();
        let sliver = |u: f64| {
            let s = input.knots().find_span(u.clamp(d0, d1));
            (SLIVER_SNAP * (kv0[s + 1] - kv0[s])).max(eps)
        };
        if !at_start && want(ends[0]) > 0 {
            let i = kv0.partition_point(|&k| k < u1);
            if let Some(&k) = kv0.get(i).filter(|&&k| k - u1 <= sliver(u1) && k < u2) {
                u1 = k;
            }
        }
        if !at_end && want(ends[1]) > 0 {
            let i = kv0.partition_point(|&k| k <= u2);
            if let Some(&k) = i
                .checked_sub(1)
                .and_then(|j| kv0.get(j))
                .filter(|&&k| u2 - k <= sliver(u2) && k > u1)
            {
                u2 = k;
            }
        }
        for (u, interior, e) in [(u1, !at_start, ends[0]), (u2, !at_end, ends[1])] {
            let want = want(e);
            if interior && want > 0 {
                let u = snap_to_knot(work.knots().values(), u, eps);
                let have = work.knots().multiplicity(u);
                if have < want {
                    work = work.insert_knot(u, want - have)?;
                }
            }
        }
        (self.u1, self.u2) = (u1, u2);
        Ok(work)
    }

    /// The free control points of `work` (those whose support lies inside the region, less the `hold`
    /// or more a curve end holds): the first one, their number, and the moving stretch, the union of
    /// their supports. With `keep_corners`, a stretch across a corner is refused.
    pub(super) fn free_points(
        &self,
        work: &BSplineCurve,
        hold: usize,
        keep_corners: bool,
    ) -> Result<(usize, usize, (f64, f64))> {
        let (p, eps, u1, u2) = (work.degree(), self.eps, self.u1, self.u2);
        let (at_start, at_end, ends) = (self.at_start, self.at_end, self.ends);
        let n = work.n_points();
        let kv = work.knots().values();
        // the points a curve end holds: position, and one more per order of continuity
        let keep = |e: EndCondition| (e.order() + 1).max(hold).min(n);
        let (keep_start, keep_end) = (keep(ends[0]), keep(ends[1]));
        let inside = (0..n).filter(|&i| kv[i] >= u1 - eps && kv[i + p + 1] <= u2 + eps);
        let n_inside = inside.clone().count();
        let mut free: Vec<usize> = inside
            .filter(|&i| !((at_start && i < keep_start) || (at_end && i >= n - keep_end)))
            .collect();
        free.sort_unstable();
        if free.is_empty() && at_start && at_end {
            return Err(Error::TooFewControlPoints {
                points: n,
                ends: format!("{:?}", ends[1]),
                held: keep_end,
                needed: keep_start + keep_end + 1,
            });
        }
        if free.is_empty() && n_inside > 0 {
            // the region has control points of its own, but all are held at the curve end it reaches
            let (which, k, e) = if at_start {
                ("start", keep_start, ends[0])
            } else {
                ("end", keep_end, ends[1])
            };
            let side = if at_start { "first" } else { "last" };
            return Err(Error::RegionTooSmall {
                u1,
                u2,
                reason: format!(
                    "it reaches the curve's {which}, where the {side} {k} control points are held ({e:?} end), and \
                     its {n_inside} control point(s) are among them (widen the region, or insert knots to refine \
                     the curve)"
                ),
            });
        }
        if free.is_empty() {
            return Err(Error::RegionTooSmall {
                u1,
                u2,
                reason: format!(
                    "no control point of this degree-{p} curve has its support inside it (a region must span at \
                     least {} knot spans)",
                    p + 1
                ),
            });
        }
        let i0 = free[0];
        let nf = free.len();
        let range = (kv[i0], kv[free[nf - 1] + p + 1]);
        if keep_corners {
            let found = corners(work, range.0 + eps, range.1 - eps);
            if !found.is_empty() {
                return Err(crossed_corners(work, u1, u2, &found));
            }
        }
        Ok((i0, nf, range))
    }
}

/// The fairing samples of the moving stretch (module docs of `fair::curve`, step 2).
pub(super) struct Samples {
    /// The arc-length table: over the whole curve, or with `check_samples = 0` over the stretch only.
    pub(super) table: ArcLengthTable,
    /// Knot spans of the stretch.
    pub(super) spans: usize,
    /// Arc length at the stretch's start and end in the table, and their difference.
    pub(super) s_a: f64,
    pub(super) s_b: f64,
    pub(super) length: f64,
    /// Sample parameters p_k at equal arc length, the ends exactly.
    pub(super) params: Vec<f64>,
}

impl Samples {
    /// The samples of the stretch `range` of `work` (`nf` free points): as many as `opts` asks, or 10 a
    /// knot span (at least 41 and 4 a free point); too many, too few, or a stretch of zero length is refused.
    pub(super) fn new(
        work: &BSplineCurve,
        range: (f64, f64),
        nf: usize,
        opts: &FairingOptions,
        check_samples: usize,
        arc_accuracy: f64,
    ) -> Result<Self> {
        let spans = work
            .knots()
            .breakpoints()
            .iter()
            .filter(|&&x| x > range.0 && x < range.1)
            .count()
            + 1;
        let ns = opts.samples.unwrap_or((10 * spans + 1).max(41).max(4 * nf + 1));
        if ns > MAX_SAMPLES {
            return Err(Error::TooManySamples {
                samples: ns,
                max: MAX_SAMPLES,
            });
        }
        if ns < 3 || ns < nf + 1 {
            return Err(Error::TooFewSamples { samples: ns, free: nf });
        }
        // One table over the whole curve serves the fairing samples of the stretch and the check samples
        // (with check_samples = 0, a table over the stretch only).
        let table = if check_samples == 0 {
            ArcLengthTable::new_range(work, range.0, range.1, arc_accuracy)
        } else {
            ArcLengthTable::new(work, arc_accuracy)
        };
        let (s_a, s_b) = if check_samples == 0 {
            (0.0, table.length())
        } else {
            (table.length_at(work, range.0), table.length_at(work, range.1))
        };
        let length = s_b - s_a;
        let size = {
            let (lo, hi) = work.control_bounds();
            (hi - lo).length()
        };
        if size == 0.0 || !(length > 1e-12 * size) {
            return Err(Error::Degenerate(format!(
                "the region [{}, {}] has zero length (coincident control points)",
                range.0, range.1
            )));
        }
        let mut params = Vec::with_capacity(ns);
        table.equal_arc_params_between(work, s_a, s_b, ns, &mut params);
        // the ends exactly: the first and last samples carry the pinned end curvature
        params[0] = range.0;
        params[ns - 1] = range.1;
        Ok(Self {
            table,
            spans,
            s_a,
            s_b,
            length,
            params,
        })
    }
}
