//! Fairing a curve with corners: the stretches between its corners ([`crate::corners`]) one by one.
//!
//! A [`FairingSetup`] refuses a moving stretch that crosses a corner (it would round the corner off
//! into a curvature spike). [`fair_between_corners`] — which [`super::fair_curve`] and `fairway fair`
//! call when the region holds corners — fairs each stretch between corners as a region of its own,
//! with the caller's end conditions at the region's own ends, G1 at a kink (the kink's point and the
//! tangent direction on each side stay, so its angle is kept exactly; the curvature on each side is
//! faired, not pinned to its noisy value there), and G2 at the knots a stretch ends on next to a stop
//! (smooth points; the spans touching the stop stay as they are). The stretches do not interact:
//! each moves only control points whose support lies inside it, so each is faired on the original and
//! the results are merged (refined to all their knots, exact); each verifies its band on the original's arc-length samples
//! inside it, the ones `measure` projects, so the reported bound is the measured deviation.
//!
//! A closed curve is set up re-seamed (exactly: [`super::closed::reseam`]) so that no stretch runs
//! across its seam, and the merged result is rotated back onto the original knots: a whole loop at its
//! first kink (the old seam is then faired like any other point, C2 as before, and the kink ends the
//! first and last stretch; on a noisy closed circle with a 30° kink the curvature error within 10 % of
//! the length of the seam dropped 3.2× instead of 1.5× with the seam held, `tests/corners.rs`), a
//! region across the seam (`u1 > u2`) in the middle of the untouched rest, as
//! [`super::closed::setup_across_seam`] does. A seam that is itself a kink (a sharp
//! trailing edge, [`crate::corners::seam_corner`]) is a corner like the others: it ends the first and
//! the last stretch with G1 (`fair_closed` would hold such a seam G2: the first and last three control
//! points fixed), and a region across it is faired as its two sides `[u1, b]` and `[a, u2]` (it cannot
//! be re-seamed). If the seam cannot be re-seamed otherwise (not
//! parametrically C2), a whole loop's seam ends two stretches like G2 region ends, and a region across
//! it is left to `setup_across_seam`, which says why. A stretch whose setup is refused (too short
//! to have a free control point, say) is left as it is and said so in [`FairingResult::notes`]; if
//! every stretch is refused, the error names the corners and each stretch's refusal.

use super::closed::{Seam, is_closed_curve, removal_tolerance, reseam, unrotate};
use super::curve::{EndCondition, FairingOptions, FairingResult, FairingSetup};
use super::target::Target;
use crate::arclength::ArcLengthTable;
use crate::corners::{Corner, corners, counted, seam_corner, stretches_between};
use crate::curve::BSplineCurve;
use crate::error::{Error, Result};

/// One stretch between corners as [`fair_between_corners`] faired it.
#[derive(Clone, Debug)]
pub struct Stretch {
    /// Its region.
    pub region: (f64, f64),
    /// Its free control points; empty if it was left as it is.
    pub free_points: std::ops::Range<usize>,
    /// The paper's E of the original on the stretch's samples, against its target (0 if the stretch
    /// was left as it is).
    pub energy_before: f64,
    /// The same after (0 if left as it is).
    pub energy: f64,
    /// Its verified deviation bound (0 if left as it is).
    pub max_deviation: f64,
    /// Its fairness weight μ, update scale α and linear solves (0 if left as it is).
    pub mu: f64,
    /// See `mu`.
    pub alpha: f64,
    /// See `mu`.
    pub solves: usize,
    /// Why it was left as it is (its setup's error), if it was.
    pub left: Option<String>,
}

/// The knots of `c` that `original` lacks (multiset difference of the two sorted knot vectors).
fn extra_knots(c: &BSplineCurve, original: &BSplineCurve) -> Vec<f64> {
    let (a, b) = (c.knots().values(), original.knots().values());
    let (mut out, mut j) = (vec![], 0);
    for &k in a {
        if j < b.len() && b[j] == k {
            j += 1;
        } else {
            out.push(k);
        }
    }
    out
}

/// The results `faired` of stretches faired on `original` (each moving its own control points, maybe
/// with knots inserted at its region ends) in one curve: every result refined to all their knots
/// (exact), then each one's moved control points. Each stretch is faired on the original, not on the
/// result of the one before, so that its band is verified on the original's own arc-length samples, the
/// ones `measure` projects (a stretch faired after another saw that one's new arc length).
fn merged(original: &BSplineCurve, faired: &[BSplineCurve]) -> Result<BSplineCurve> {
    let extras: Vec<Vec<f64>> = faired.iter().map(|c| extra_knots(c, original)).collect();
    let all: Vec<f64> = extras.iter().flatten().copied().collect();
    let base = original.refine(&all)?;
    let mut pts = base.points().to_vec();
    for (i, c) in faired.iter().enumerate() {
        let others: Vec<f64> = extras
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != i)
            .flat_map(|(_, e)| e)
            .copied()
            .collect();
        let c = c.refine(&others)?;
        if c.knots().values() != base.knots().values() {
            return Err(Error::Solve(
                "fairing between corners: the stretches' knot vectors could not be merged".into(),
            ));
        }
        for (k, q) in c.points().iter().enumerate() {
            if *q != base.points()[k] {
                pts[k] = *q;
            }
        }
    }
    base.with_points(pts)
}

/// The outcome of [`fair_between_corners`].
#[derive(Clone, Debug)]
pub struct CornerFair {
    /// The whole result: the curve with every stretch faired; `max_deviation` the largest of the
    /// stretches', `energy` and `solves` their sums, `mu` and `alpha` the smallest, `notes` one line
    /// per stretch left as it is.
    pub result: FairingResult,
    /// The corners kept (inside the region).
    pub corners: Vec<Corner>,
    /// The stretches, in order along the region.
    pub stretches: Vec<Stretch>,
}

/// The setups of the stretches between the corners inside a region ([`crate::corners`]), prepared
/// once and faired together as often as wanted: what [`fair_between_corners`] runs once, and what the
/// editor keeps for its live preview of a region with corners (set each stretch's target or the
/// tolerance, fair again). A stretch whose setup is refused (too short to have a free control point,
/// say) is kept with its reason and left as it is.
#[derive(Clone, Debug)]
pub struct CornerSetups {
    input: BSplineCurve,
    /// The curve the stretches are set up on: `input`, or a closed `input` re-seamed ([`Rotation`]).
    work: BSplineCurve,
    rotation: Option<Rotation>,
    /// The corners kept, on `input`'s parameter.
    corners: Vec<Corner>,
    /// Each stretch's region (on `work`'s parameter) and its setup, or why it has none.
    stretches: Vec<((f64, f64), std::result::Result<FairingSetup, String>)>,
    seam: Seam,
    /// Each faired stretch's last [`FairingSetup::fair`] and what it was run with (options, target):
    /// [`Self::fair`] reuses it while they are unchanged, so a re-fair after an edit of one stretch's
    /// target leaves the other stretches bit for bit (a fresh fair would warm-start its band search
    /// at the last μ and could land elsewhere within the search's resolution).
    last: Vec<Option<(FairingOptions, Target, FairingResult)>>,
}

/// A closed curve's stretches set up on the curve re-seamed at `at` ([`reseam`]: the same points on
/// `[at, at + L]`), so that no stretch runs across the seam: at a kink for a whole loop (the seam is then
/// faired like any other point, and the kink ends the first and last stretch), in the middle of the
/// untouched rest for a region across the seam. The merged result is rotated back ([`unrotate`]).
#[derive(Clone, Copy, Debug)]
struct Rotation {
    /// The domain length L: a parameter `u > b` of the re-seamed curve is the input's `u − L`.
    length: f64,
    /// The region's ends on the re-seamed curve and on the input (`u1`, `u2` for a region across the seam;
    /// the kink for a whole loop): reported as the input's own values, not `(u2 + L) − L`.
    ends: [(f64, f64); 2],
    /// The removal tolerance of the re-seaming and of the rotation back.
    tol: f64,
}

impl Rotation {
    /// A parameter `u` of the re-seamed curve as the input's (domain end `b`): a region end as the
    /// input's own value, past `b` it is `u − L`, else unchanged (the same point on both curves).
    fn to_input(self, u: f64, b: f64) -> f64 {
        match self.ends.iter().find(|e| e.0 == u) {
            Some(e) => e.1,
            None if u > b => u - self.length,
            None => u,
        }
    }
}

impl CornerSetups {
    /// The setups of the stretches between the corners inside `opts.region` (the whole curve if
    /// none) of `curve`, with `ends` at the region's own ends (module docs for the ends between
    /// stretches). A whole loop whose seam is a kink keeps it as a corner (G1 at the curve ends). A
    /// closed curve is set up re-seamed where that keeps every stretch off the seam
    /// (exactly, `closed::reseam`): a whole loop at its first kink (if its seam can be re-seamed exactly; else the
    /// seam ends two stretches like G2 region ends), a region across the seam (`u1 > u2`) in the
    /// middle of the untouched rest. `Ok(None)` if the region holds no corner (for a whole loop
    /// re-seamed at its only kink: one stretch, the kink its ends), or runs across the seam of a curve
    /// that cannot be re-seamed (then `setup_across_seam` says why), or the curve is of degree 1: the
    /// caller fairs as usual.
    pub fn new(curve: &BSplineCurve, opts: FairingOptions, ends: [EndCondition; 2]) -> Result<Option<Self>> {
        let input = curve.to_polynomial()?;
        if input.degree() < 2 {
            return Ok(None);
        }
        let (d0, d1) = input.domain();
        let len = d1 - d0;
        let eps = 1e-12 * len;
        let (u1, u2) = opts.region.unwrap_or((d0, d1));
        let closed = is_closed_curve(&input);
        let tol = removal_tolerance(&input);
        let whole_loop = closed && u1 <= d0 + eps && u2 >= d1 - eps;
        let seam_kink = if whole_loop || (closed && u1 > u2) {
            seam_corner(&input)
        } else {
            None
        };
        let Some(WorkingForm {
            work,
            region,
            at,
            region_ends,
            loop_kink,
        }) = working_form(&input, (u1, u2), ends, whole_loop, seam_kink.is_some(), tol)
        else {
            return Ok(None);
        };
        // the stretches of `work` to cut at corners: the region, or its two sides of a seam that is a kink
        let segments = if region.0 > region.1 {
            vec![(region.0, d1), (d0, region.1)]
        } else {
            vec![region]
        };
        let found: Vec<Corner> = segments.iter().flat_map(|&(a, b)| corners(&work, a, b)).collect();
        if found.is_empty() && loop_kink.is_none() && seam_kink.is_none() {
            return Ok(None);
        }
        // end conditions: the region's own at its ends (a loop re-seamed at a kink: G1, the kink); G1 at a
        // kink (its point and both tangent directions stay, so the kink keeps its angle exactly, and
        // the curvature on each side is faired: on the kinked_profile asset ∫(dκ/ds)² 53.9 with G2
        // there, 36.5 with G1); G2 at the knots next to a stop (smooth points of the curve)
        let end_at = |u: f64| {
            if (u - region.0).abs() <= eps {
                region_ends[0]
            } else if (u - region.1).abs() <= eps {
                region_ends[1]
            } else if found.iter().any(|c| !c.stops && c.u == u) || (seam_kink.is_some() && (u == d0 || u == d1)) {
                EndCondition::G1
            } else {
                EndCondition::G2
            }
        };
        // on a re-seamed curve the band is verified on the input's arc-length samples (measure's): they
        // sit at −s(at) modulo their spacing
        let phase = at.map_or(0.0, |at| -ArcLengthTable::new(&input, 1e-12).length_at(&input, at));
        let stretches = segments
            .iter()
            .flat_map(|&(a, b)| {
                let inside: Vec<Corner> = found.iter().filter(|c| c.u > a && c.u < b).cloned().collect();
                stretches_between(&work, a, b, &inside)
            })
            .map(|r| {
                let o = FairingOptions {
                    region: Some(r),
                    ..opts
                };
                let setup = FairingSetup::new_with_ends_phase(&work, o, [end_at(r.0), end_at(r.1)], phase)
                    .map_err(|e| e.to_string());
                (r, setup)
            })
            .collect();
        let rotation = at.map(|at| Rotation {
            length: len,
            ends: if u1 > u2 {
                [(region.0, u1), (region.1, u2)]
            } else {
                [(region.0, at), (region.1, at)]
            },
            tol,
        });
        let mut kept: Vec<Corner> = found
            .into_iter()
            .map(|c| Corner {
                u: rotation.map_or(c.u, |r| r.to_input(c.u, d1)),
                ..c
            })
            .collect();
        kept.extend(loop_kink);
        kept.extend(seam_kink);
        kept.sort_by(|x, y| x.u.total_cmp(&y.u));
        let seam = seam_state(
            seam_kink,
            rotation.is_some(),
            closed,
            whole_loop || u1 <= d0 + eps || u2 >= d1 - eps,
        );
        Ok(Some(Self {
            input,
            work,
            rotation,
            corners: kept,
            stretches,
            seam,
            last: vec![],
        }))
    }

    /// A parameter of the curve the stretches are set up on ([`Self::stretches`], the setups'
    /// samples) as the input's: past the input's domain end `b` (a re-seamed closed curve) it is
    /// `u − L`, else unchanged (the same point on both curves).
    pub fn to_original(&self, u: f64) -> f64 {
        self.rotation.map_or(u, |r| r.to_input(u, self.input.domain().1))
    }

    /// The curve being faired (polynomial).
    pub fn original(&self) -> &BSplineCurve {
        &self.input
    }

    /// The corners kept (inside the region).
    pub fn corners(&self) -> &[Corner] {
        &self.corners
    }

    /// The stretches in order along the region: each one's region and its setup, or why it has none
    /// (it is then left as it is). Regions and setups are on the re-seamed curve if the input was
    /// re-seamed ([`Self::to_original`] maps its parameters back).
    pub fn stretches(&self) -> impl Iterator<Item = ((f64, f64), std::result::Result<&FairingSetup, &str>)> {
        self.stretches
            .iter()
            .map(|(r, s)| (*r, s.as_ref().map_err(String::as_str)))
    }

    /// The stretches' setups (the ones that have one), in order, to change their targets or options.
    pub fn setups_mut(&mut self) -> impl Iterator<Item = &mut FairingSetup> {
        self.stretches.iter_mut().filter_map(|(_, s)| s.as_mut().ok())
    }

    /// The stretches' setups (the ones that have one), in order.
    pub fn setups(&self) -> impl Iterator<Item = &FairingSetup> {
        self.stretches.iter().filter_map(|(_, s)| s.as_ref().ok())
    }

    /// Set every stretch's tolerance.
    pub fn set_tolerance(&mut self, m: f64) -> Result<()> {
        self.setups_mut().try_for_each(|s| s.set_tolerance(m))
    }

    /// Fair every stretch with [`FairingSetup::fair`] and merge the results; a stretch whose options
    /// and target are those of its last fair keeps that fair's result.
    pub fn fair(&mut self) -> Result<CornerFair> {
        let mut last = std::mem::take(&mut self.last);
        let mut k = 0;
        let out = self.fair_with(|s| {
            if last.len() <= k {
                last.push(None);
            }
            let slot = &mut last[k];
            k += 1;
            if let Some((o, t, r)) = slot.as_ref()
                && o == s.options()
                && t == s.target()
            {
                return Ok(r.clone());
            }
            *slot = None;
            let r = s.fair()?;
            *slot = Some((*s.options(), s.target().clone(), r.clone()));
            Ok(r)
        });
        self.last = last;
        out
    }

    /// Fair every stretch by `pass` on its setup (`FairingSetup::fair`, or the iterative baseline) and
    /// merge the results (module docs).
    pub fn fair_with(
        &mut self,
        mut pass: impl FnMut(&mut FairingSetup) -> Result<FairingResult>,
    ) -> Result<CornerFair> {
        let (rotation, b) = (self.rotation, self.input.domain().1);
        let back = |u: f64| rotation.map_or(u, |r| r.to_input(u, b));
        let mut stretches = vec![];
        let mut curves = vec![];
        for (region, setup) in &mut self.stretches {
            let setup = match setup {
                Ok(s) => s,
                Err(msg) => {
                    stretches.push(Stretch {
                        region: (back(region.0), back(region.1)),
                        free_points: 0..0,
                        energy_before: 0.0,
                        energy: 0.0,
                        max_deviation: 0.0,
                        mu: 0.0,
                        alpha: 0.0,
                        solves: 0,
                        left: Some(msg.clone()),
                    });
                    continue;
                }
            };
            let energy_before = setup.original_energy();
            let r = pass(setup)?;
            stretches.push(Stretch {
                region: (back(region.0), back(region.1)),
                free_points: setup.free_points(),
                energy_before,
                energy: r.energy,
                max_deviation: r.max_deviation,
                mu: r.mu,
                alpha: r.alpha,
                solves: r.solves,
                left: None,
            });
            curves.push(r.curve);
        }
        let faired: Vec<&Stretch> = stretches.iter().filter(|s| s.left.is_none()).collect();
        if faired.is_empty() {
            let list: Vec<String> = self.corners.iter().map(Corner::describe).collect();
            let why: Vec<String> = stretches
                .iter()
                .map(|s| format!("[{}, {}]: {}", s.region.0, s.region.1, s.left.as_deref().unwrap_or("")))
                .collect();
            return Err(Error::InvalidInput(format!(
                "the curve has {} {}, which fairing keeps (across it the band would round it off into a \
                 curvature spike), and no stretch between corners can be faired: {}",
                counted(&self.corners),
                list.join(", "),
                why.join("; ")
            )));
        }
        let cur = merged(&self.work, &curves)?;
        let max_deviation = faired.iter().map(|s| s.max_deviation).fold(0.0, f64::max);
        let cur = match &self.rotation {
            // back onto the input's domain and knots, plus the knots the stretches inserted (G1 / G0
            // region ends), mapped back; where nothing moved (every bound 0), the input itself on those
            // knots, not its rotation there and back (which differs from it by rounding)
            Some(rot) => {
                let mut extra: Vec<f64> = extra_knots(&cur, &self.work).into_iter().map(back).collect();
                extra.sort_by(f64::total_cmp);
                let form = self.input.refine(&extra)?;
                if max_deviation == 0.0 {
                    form
                } else {
                    unrotate(&cur, &form, rot.tol)?
                }
            }
            None => cur,
        };
        let notes = stretches
            .iter()
            .filter_map(|s| {
                s.left.as_ref().map(|why| {
                    format!(
                        "the stretch [{}, {}] between corners was left as it is: {why}",
                        s.region.0, s.region.1
                    )
                })
            })
            .collect();
        let result = FairingResult {
            curve: cur,
            max_deviation,
            mu: faired.iter().map(|s| s.mu).fold(f64::INFINITY, f64::min),
            alpha: faired.iter().map(|s| s.alpha).fold(f64::INFINITY, f64::min),
            solves: faired.iter().map(|s| s.solves).sum(),
            energy: stretches.iter().map(|s| s.energy).sum(),
            seam: self.seam.clone(),
            notes,
        };
        Ok(CornerFair {
            result,
            corners: self.corners.clone(),
            stretches,
        })
    }
}

/// Fair `curve` with `opts` stretch by stretch between the corners inside its region (module docs),
/// each stretch by `pass` on its setup (`FairingSetup::fair`, or the iterative baseline). `Ok(None)`
/// if the region holds no corner (or runs across the seam: then the setup says which corner it
/// crosses), so the caller fairs as usual.
pub fn fair_between_corners(
    curve: &BSplineCurve,
    opts: FairingOptions,
    pass: impl FnMut(&mut FairingSetup) -> Result<FairingResult>,
) -> Result<Option<CornerFair>> {
    match CornerSetups::new(curve, opts, [opts.ends; 2])? {
        Some(mut s) => s.fair_with(pass).map(Some),
        None => Ok(None),
    }
}

/// The curve a corner split is set up on, the region on it, where it was re-seamed, the region's own
/// end conditions, and the kink a whole loop was re-seamed at (kept as a corner: it ends the first and
/// last stretch).
struct WorkingForm {
    work: BSplineCurve,
    region: (f64, f64),
    at: Option<f64>,
    region_ends: [EndCondition; 2],
    loop_kink: Option<Corner>,
}

/// [`WorkingForm`] of `input` for the region `(u1, u2)`; `None` where the split does not apply (an
/// empty region, a region across the seam of an open curve or of a seam that cannot be re-seamed).
fn working_form(
    input: &BSplineCurve,
    (u1, u2): (f64, f64),
    ends: [EndCondition; 2],
    whole_loop: bool,
    seam_is_kink: bool,
    tol: f64,
) -> Option<WorkingForm> {
    let (d0, d1) = input.domain();
    let len = d1 - d0;
    let form = |work: BSplineCurve, region, at, region_ends, loop_kink| WorkingForm {
        work,
        region,
        at,
        region_ends,
        loop_kink,
    };
    if u1 > u2 {
        if !is_closed_curve(input) {
            return None;
        }
        if seam_is_kink {
            // across a seam that is a kink: [u1, b] and [a, u2] (the segments), G1 at the seam
            return Some(form(input.clone(), (u1, u2), None, ends, None));
        }
        let at = 0.5 * (u1 + u2);
        let (r, _) = reseam(input, at, tol).ok()?;
        return Some(form(r, (u1, u2 + len), Some(at), ends, None));
    }
    if !(u1 < u2) {
        return None;
    }
    if whole_loop && seam_is_kink {
        // the seam is a kink (a sharp trailing edge): it ends the first and the last stretch, G1
        return Some(form(input.clone(), (u1, u2), None, [EndCondition::G1; 2], None));
    }
    if whole_loop {
        // a loop has no ends: G2 where the seam ends two stretches
        let kink = corners(input, d0, d1).into_iter().find(|c| !c.stops);
        return Some(
            match kink.and_then(|k| reseam(input, k.u, tol).ok().map(|r| (k, r.0))) {
                Some((k, r)) => form(r, (k.u, k.u + len), Some(k.u), [EndCondition::G1; 2], Some(k)),
                None => form(input.clone(), (u1, u2), None, [EndCondition::G2; 2], None),
            },
        );
    }
    Some(form(input.clone(), (u1, u2), None, ends, None))
}

/// What happens to the seam of a corner split: kept as a corner (`seam_kink`), faired (re-seamed),
/// open, held (a closed curve whose region reaches the seam), or untouched.
fn seam_state(seam_kink: Option<Corner>, rotated: bool, closed: bool, reaches_seam: bool) -> Seam {
    if let Some(k) = seam_kink {
        Seam::Held(format!(
            "the seam is a corner ({}): kept as a corner, G1 on both sides (its point and both tangent \
             directions stay, the curvature next to it is faired)",
            k.describe()
        ))
    } else if rotated {
        Seam::Faired
    } else if !closed {
        Seam::Open
    } else if reaches_seam {
        Seam::Held(
            "the curve has corners and its seam could not be re-seamed at one: the stretches between \
             them were faired one by one, and the seam ends two of them like G2 region ends"
                .into(),
        )
    } else {
        Seam::Untouched
    }
}
