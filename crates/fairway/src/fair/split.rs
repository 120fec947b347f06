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
//! On a whole closed curve with corners the seam ends two stretches like G2 region ends (it is not
//! faired across, as a closed curve without corners is). A stretch whose setup is refused (too short
//! to have a free control point, say) is left as it is and said so in [`FairingResult::notes`]; if
//! every stretch is refused, the error names the corners and each stretch's refusal.

use super::closed::{Seam, is_closed_curve};
use super::curve::{EndCondition, FairingOptions, FairingResult, FairingSetup};
use super::target::Target;
use crate::corners::{Corner, corners, counted, stretches_between};
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

/// The results `faired` of stretches faired on `original` (each moving its own control points, maybe
/// with knots inserted at its region ends) in one curve: every result refined to all their knots
/// (exact), then each one's moved control points. Each stretch is faired on the original, not on the
/// result of the one before, so that its band is verified on the original's own arc-length samples, the
/// ones `measure` projects (a stretch faired after another saw that one's new arc length).
fn merged(original: &BSplineCurve, faired: &[BSplineCurve]) -> Result<BSplineCurve> {
    // knots of a result that the original lacks (multiset difference of two sorted vectors)
    let extra = |c: &BSplineCurve| {
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
    };
    let extras: Vec<Vec<f64>> = faired.iter().map(extra).collect();
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
    corners: Vec<Corner>,
    /// Each stretch's region and its setup, or why it has none.
    stretches: Vec<((f64, f64), std::result::Result<FairingSetup, String>)>,
    seam: Seam,
    /// Each faired stretch's last [`FairingSetup::fair`] and what it was run with (options, target):
    /// [`Self::fair`] reuses it while they are unchanged, so a re-fair after an edit of one stretch's
    /// target leaves the other stretches bit for bit (a fresh fair would warm-start its band search
    /// at the last μ and could land elsewhere within the search's resolution).
    last: Vec<Option<(FairingOptions, Target, FairingResult)>>,
}

impl CornerSetups {
    /// The setups of the stretches between the corners inside `opts.region` (the whole curve if
    /// none) of `curve`, with `ends` at the region's own ends (module docs for the ends between
    /// stretches). `Ok(None)` if the region holds no corner, runs across the seam (`u1 > u2`: then
    /// the setup says which corner it crosses) or the curve is of degree 1, so the caller fairs as
    /// usual.
    pub fn new(curve: &BSplineCurve, opts: FairingOptions, ends: [EndCondition; 2]) -> Result<Option<Self>> {
        let input = curve.to_polynomial()?;
        let (d0, d1) = input.domain();
        let (u1, u2) = opts.region.unwrap_or((d0, d1));
        if !(u1 < u2) || input.degree() < 2 {
            return Ok(None);
        }
        let found = corners(&input, u1, u2);
        if found.is_empty() {
            return Ok(None);
        }
        let eps = 1e-12 * (d1 - d0);
        let whole_loop = is_closed_curve(&input) && u1 <= d0 + eps && u2 >= d1 - eps;
        // end conditions: the caller's at the region's own ends (a whole loop has none: G2); G1 at a
        // kink (its point and both tangent directions stay, so the kink keeps its angle exactly, and
        // the curvature on each side is faired: on the kinked_profile asset ∫(dκ/ds)² 53.9 with G2
        // there, 36.5 with G1); G2 at the knots next to a stop (smooth points of the curve)
        let end_at = |u: f64| {
            if !whole_loop && (u - u1).abs() <= eps {
                ends[0]
            } else if !whole_loop && (u - u2).abs() <= eps {
                ends[1]
            } else if found.iter().any(|c| !c.stops && c.u == u) {
                EndCondition::G1
            } else {
                EndCondition::G2
            }
        };
        let stretches = stretches_between(&input, u1, u2, &found)
            .into_iter()
            .map(|region| {
                let o = FairingOptions {
                    region: Some(region),
                    ..opts
                };
                let setup = FairingSetup::new_with_ends(&input, o, [end_at(region.0), end_at(region.1)])
                    .map_err(|e| e.to_string());
                (region, setup)
            })
            .collect();
        let seam = if !is_closed_curve(&input) {
            Seam::Open
        } else if whole_loop || u1 <= d0 + eps || u2 >= d1 - eps {
            Seam::Held(
                "the curve has corners: its stretches between them were faired one by one, and the seam \
                 ends two of them like G2 region ends"
                    .into(),
            )
        } else {
            Seam::Untouched
        };
        Ok(Some(Self {
            input,
            corners: found,
            stretches,
            seam,
            last: vec![],
        }))
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
    /// (it is then left as it is).
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
        let mut stretches = vec![];
        let mut curves = vec![];
        for (region, setup) in &mut self.stretches {
            let setup = match setup {
                Ok(s) => s,
                Err(msg) => {
                    stretches.push(Stretch {
                        region: *region,
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
            let energy_before = setup.energy(setup.working_curve());
            let r = pass(setup)?;
            stretches.push(Stretch {
                region: *region,
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
        let cur = merged(&self.input, &curves)?;
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
            max_deviation: faired.iter().map(|s| s.max_deviation).fold(0.0, f64::max),
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
