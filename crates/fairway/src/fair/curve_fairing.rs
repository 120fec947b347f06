//! [`CurveFairing`]: the one entry point for fairing a curve. It picks the route itself and keeps what
//! it prepared, so the tolerance, the target and the cheap options can change and the curve be faired
//! again without a new setup (the editor's live preview, the CLI's single run, the tests).
//!
//! The routes, tried in this order:
//!
//! 1. **Corners** — the region holds corners of the curve (kinks, stops: [`crate::corners`]): the
//!    stretches between them are faired one by one and merged ([`super::split::CornerSetups`]);
//! 2. **Across the seam** — a region `(u1, u2)` with `u1 > u2` on a closed curve: one setup on the
//!    curve re-seamed in the middle of the untouched rest, the result rotated back
//!    ([`super::closed::setup_across_seam_with_ends`]);
//! 3. **Whole loop** — a closed curve faired whole: a full fair makes the two passes of
//!    [`super::closed::fair_closed`] that fair across the seam; a draft, or a hand-edited target (which
//!    belongs to the first pass's samples), is that first pass alone, the seam held;
//! 4. **One setup** — everything else: [`FairingSetup`] over the region.
//!
//! Every result is on the input curve's domain and knot vector (plus the knots a G1 / G0 region end
//! inserts), and sample parameters are given on the input's parameter.
//!
//! A rational curve with unequal weights (NURBS: conics, circles) is faired through a non-rational
//! B-spline within a tenth of the band of it ([`super::nurbs`]): the fair runs on that stand-in with the
//! band narrowed by its error, the reported deviation adds the error back (a bound from the rational
//! original), and a note says so. The result is non-rational, of degree max(p, 3).

use super::closed::{self, AcrossSeam};
use super::curve::{EndCondition, FairingOptions, FairingResult, FairingSetup};
use super::iterative::{IterativeOptions, fair_iterative};
use super::split::{CornerSetups, Stretch};
use super::target::{Target, TargetMethod};
use crate::corners::Corner;
use crate::curve::BSplineCurve;
use crate::error::Result;

/// How [`CurveFairing::fair`] fairs.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[non_exhaustive]
pub enum Pass {
    /// The full fair: the band-holding fit and the polish ([`FairingOptions::polish`]), and for a
    /// whole closed curve the seam faired too.
    #[default]
    Full,
    /// A draft while the user drags: the band-holding fit without the polish, a closed curve's seam
    /// held. Cheap enough for a frame; the same setup then makes the full fair.
    Draft,
    /// The iterative baseline of the paper (§2.2) on the same setup(s), for comparison.
    Iterative(IterativeOptions),
}

/// The outcome of [`CurveFairing::fair`].
#[derive(Debug, Clone)]
pub struct CurveFair {
    /// The faired curve and its figures (on the input's domain and knots).
    pub result: FairingResult,
    /// The corners kept inside the region (empty if it has none).
    pub corners: Vec<Corner>,
    /// With corners, the stretches between them, each faired as a region of its own; empty otherwise.
    pub stretches: Vec<Stretch>,
    /// The paper's E of the original on the samples, against the target (summed over the stretches),
    /// the figure to compare with `result.energy`.
    pub energy_before: f64,
}

/// What the fair runs on.
#[derive(Debug, Clone)]
enum Route {
    /// One setup: a region of an open curve, a region of a closed one (`across`: the setup is on the
    /// curve re-seamed, results are rotated back), or a whole loop (`whole_loop`: its first pass).
    One {
        setup: Box<FairingSetup>,
        across: Option<AcrossSeam>,
        whole_loop: bool,
    },
    /// One setup per stretch between corners.
    Corners(Box<CornerSetups>),
}

/// A curve prepared for fairing (module docs): build it once per curve, region and end conditions;
/// change the tolerance, the target and the run options, and fair as often as wanted.
///
/// ```
/// # use fairway::{BSplineCurve, DVec2};
/// # use fairway::fair::{CurveFairing, FairingOptions, Pass};
/// let pts: Vec<DVec2> = (0..12).map(|i| DVec2::new(i as f64, ((i * 7) % 3) as f64 * 0.01)).collect();
/// let mut knots = vec![0.0; 4];
/// knots.extend((1..9).map(|i| i as f64 / 9.0));
/// knots.extend([1.0; 4]);
/// let curve = BSplineCurve::new_2d(3, knots, &pts).unwrap();
/// let mut fairing = CurveFairing::new(&curve, FairingOptions::default().tolerance(0.01)).unwrap();
/// let draft = fairing.fair(Pass::Draft).unwrap();
/// let full = fairing.fair(Pass::Full).unwrap();
/// assert!(draft.result.max_deviation <= 0.01 && full.result.max_deviation <= 0.01);
/// // a tighter band, same setup
/// fairing.set_tolerance(0.005).unwrap();
/// assert!(fairing.fair(Pass::Full).unwrap().result.max_deviation <= 0.005);
/// // a hand-shaped target: flatten the middle third of the samples
/// let mut g = fairing.target().values().to_vec();
/// let n = g.len();
/// g[n / 3..2 * n / 3].fill(0.0);
/// assert!(fairing.set_target(Some(&g), &[]));
/// assert!(fairing.fair(Pass::Full).unwrap().result.max_deviation <= 0.005);
/// ```
#[derive(Debug, Clone)]
pub struct CurveFairing {
    /// The curve faired: as given in polynomial form, or a rational curve's non-rational stand-in.
    input: BSplineCurve,
    /// A rational input (unequal weights) as given, and the bound of its stand-in's error.
    rational: Option<(BSplineCurve, f64)>,
    opts: FairingOptions,
    ends: [EndCondition; 2],
    route: Route,
    /// A hand-edited target or pins are in the setup(s) ([`Self::set_target`]).
    edited: bool,
    /// `measure`'s extrema threshold for the input and its curvature extrema at it (computed on the
    /// first full pass).
    original_extrema: Option<(f64, usize)>,
}

impl CurveFairing {
    /// Prepare `curve` for fairing with `opts` (`opts.ends` at both ends of the region).
    pub fn new(curve: &BSplineCurve, opts: FairingOptions) -> Result<Self> {
        Self::with_ends(curve, opts, [opts.ends; 2])
    }

    /// [`Self::new`] with separate end conditions at the region's start and end (`opts.ends` is ignored).
    pub fn with_ends(curve: &BSplineCurve, opts: FairingOptions, ends: [EndCondition; 2]) -> Result<Self> {
        let (input, rational) = match curve.to_polynomial() {
            Ok(c) => (c, None),
            Err(_) if curve.is_rational() => {
                super::curve::validate_tolerance(opts.tolerance)?;
                let a = super::nurbs::polynomial_approximation(curve, super::nurbs::APPROX_FRACTION * opts.tolerance)?;
                (a.curve, Some((curve.clone(), a.error)))
            }
            Err(e) => return Err(e),
        };
        let approx_error = rational.as_ref().map_or(0.0, |r| r.1);
        let route = Self::route(&input, opts.tolerance(opts.tolerance - approx_error), ends)?;
        Ok(Self {
            input,
            rational,
            opts,
            ends,
            route,
            edited: false,
            original_extrema: None,
        })
    }

    fn route(input: &BSplineCurve, opts: FairingOptions, ends: [EndCondition; 2]) -> Result<Route> {
        if let Some(c) = CornerSetups::new(input, opts, ends)? {
            return Ok(Route::Corners(Box::new(c)));
        }
        // (on an open curve the setup says that u1 > u2 asks for a seam the curve does not have)
        if opts.region.is_some_and(|(u1, u2)| u1 > u2) {
            let (setup, across) = closed::setup_across_seam_with_ends(input, opts, ends)?;
            return Ok(Route::One {
                setup: Box::new(setup),
                across: Some(across),
                whole_loop: false,
            });
        }
        let whole_loop = closed::applies(input, &opts);
        let setup = if whole_loop {
            // the first pass's setup (a loop has no ends: G2 all round): E before and a hand-edited
            // target belong to it
            closed::first_pass_setup(input, opts)?
        } else {
            FairingSetup::new_with_ends(input, opts, ends)?
        };
        Ok(Route::One {
            setup: Box::new(setup),
            across: None,
            whole_loop,
        })
    }

    /// The curve being faired, as given (polynomial form): results and sample parameters are on it.
    pub fn original(&self) -> &BSplineCurve {
        &self.input
    }

    /// The options in force.
    pub fn options(&self) -> &FairingOptions {
        &self.opts
    }

    /// The end conditions at the region's start and end.
    pub fn ends(&self) -> [EndCondition; 2] {
        self.ends
    }

    /// The region runs across the seam of a closed curve (route 2 of the module docs).
    pub fn across_seam(&self) -> bool {
        matches!(&self.route, Route::One { across: Some(_), .. })
    }

    /// A closed curve faired whole (route 3): a full fair fairs its seam too.
    pub fn whole_loop(&self) -> bool {
        matches!(&self.route, Route::One { whole_loop: true, .. })
    }

    /// The corners kept inside the region (empty unless route 1).
    pub fn corners(&self) -> &[Corner] {
        match &self.route {
            Route::Corners(c) => c.corners(),
            Route::One { .. } => &[],
        }
    }

    /// The stretches between corners, on the input's parameter, each with its setup or why it has none
    /// (left as it is); empty unless route 1.
    pub fn stretches(&self) -> Vec<((f64, f64), std::result::Result<(), String>)> {
        match &self.route {
            Route::Corners(c) => c
                .stretches()
                .map(|((a, b), s)| {
                    (
                        (c.to_original(a), c.to_original(b)),
                        s.map(|_| ()).map_err(str::to_owned),
                    )
                })
                .collect(),
            Route::One { .. } => vec![],
        }
    }

    /// The setups, in order along the region (one unless the region holds corners).
    pub fn setups(&self) -> Vec<&FairingSetup> {
        match &self.route {
            Route::One { setup, .. } => vec![setup],
            Route::Corners(c) => c.setups().collect(),
        }
    }

    fn setups_mut(&mut self) -> Vec<&mut FairingSetup> {
        match &mut self.route {
            Route::One { setup, .. } => vec![setup],
            Route::Corners(c) => c.setups_mut().collect(),
        }
    }

    /// The free control points (of the single setup; with corners the span from the first stretch's
    /// first to the last one's last, on the curve the stretches are set up on).
    pub fn free_points(&self) -> std::ops::Range<usize> {
        let setups = self.setups();
        match (setups.first(), setups.last()) {
            (Some(a), Some(b)) => a.free_points().start..b.free_points().end,
            _ => 0..0,
        }
    }

    /// The paper's E of the original against the current target, summed over the setups.
    pub fn energy_before(&self) -> f64 {
        self.setups().iter().map(|s| s.original_energy()).sum()
    }

    /// The target of the whole region: the setups' targets end to end.
    pub fn target(&self) -> Target {
        match &self.route {
            Route::One { setup, .. } => setup.target().clone(),
            Route::Corners(c) => Target::concat(&c.setups().map(FairingSetup::target).collect::<Vec<_>>()),
        }
    }

    /// The target samples' parameters on the input curve, in the order of [`Self::target`] (for a region
    /// across the seam: from `u1` up to the domain end, then from its start up to `u2`).
    pub fn sample_params(&self) -> Vec<f64> {
        let map = |u: f64| match &self.route {
            Route::Corners(c) => c.to_original(u),
            Route::One { across: Some(a), .. } => a.to_original(u),
            Route::One { .. } => u,
        };
        self.setups().iter().flat_map(|s| s.params()).map(|&u| map(u)).collect()
    }

    /// The target samples that start a stretch after the first (with corners; the target jumps there).
    pub fn stretch_starts(&self) -> Vec<usize> {
        self.setups()
            .iter()
            .scan(0, |start, s| {
                let k = *start;
                *start += s.params().len();
                Some(k)
            })
            .skip(1)
            .collect()
    }

    /// The bound of a rational input's stand-in error (0 for a non-rational input).
    fn approx_error(&self) -> f64 {
        self.rational.as_ref().map_or(0.0, |r| r.1)
    }

    /// The options the engine runs with: the band narrowed by a rational input's stand-in error.
    fn engine_opts(&self) -> FairingOptions {
        self.opts.tolerance(self.opts.tolerance - self.approx_error())
    }

    /// Change the tolerance (then [`Self::fair`] again). A rational input whose stand-in would take more
    /// than a tenth of the new band is approximated afresh (which drops a hand-edited target).
    pub fn set_tolerance(&mut self, m: f64) -> Result<()> {
        if let Some((original, e)) = &self.rational
            && !(*e <= super::nurbs::APPROX_FRACTION * m)
        {
            let opts = self.opts.tolerance(m);
            *self = Self::with_ends(&original.clone(), opts, self.ends)?;
            return Ok(());
        }
        let approx_error = self.approx_error();
        for s in self.setups_mut() {
            s.set_tolerance(m - approx_error)?;
        }
        self.opts.tolerance = m;
        Ok(())
    }

    /// Change the options. Those a fair reads (tolerance, integrator, polish and its method and
    /// iterations, the automatic target's method and strength) apply to what is prepared — a new
    /// automatic target is smoothed if its method or strength changed, unless the target is hand-edited;
    /// any other change (region, end conditions, mode, samples, …) prepares afresh, dropping a
    /// hand-edited target. Returns whether it prepared afresh.
    pub fn set_options(&mut self, opts: FairingOptions) -> Result<bool> {
        let run_only = opts
            .tolerance(self.opts.tolerance)
            .integrator(self.opts.integrator)
            .polish(self.opts.polish)
            .polish_iterations(self.opts.polish_iterations)
            .polish_method(self.opts.polish_method)
            .target(self.opts.target)
            .strength(self.opts.strength)
            == self.opts;
        if !run_only {
            // `opts.ends` changed: both ends take it; else the ends given to `with_ends` stay
            let ends = if opts.ends == self.opts.ends {
                self.ends
            } else {
                [opts.ends; 2]
            };
            let source = self.rational.as_ref().map_or(&self.input, |r| &r.0).clone();
            *self = Self::with_ends(&source, opts, ends)?;
            return Ok(true);
        }
        let retarget = (opts.target, opts.strength) != (self.opts.target, self.opts.strength);
        for n in self.setups().iter().map(|s| s.target().len()) {
            check_strength(
                opts.target,
                opts.strength.unwrap_or_else(|| default_strength(opts.target, n)),
                n,
            )?;
        }
        self.set_tolerance(opts.tolerance)?;
        for s in self.setups_mut() {
            s.set_integrator(opts.integrator);
            s.set_polish(opts.polish);
            s.set_polish_iterations(opts.polish_iterations);
            s.set_polish_method(opts.polish_method);
        }
        self.opts = opts;
        if retarget && !self.edited {
            self.set_target(None, &[]);
        }
        Ok(false)
    }

    /// Set the target: `values` the whole region's target (as [`Self::target`] lists it; `None`: the
    /// automatic target, smoothed from the original's curvature with the options' method and strength),
    /// and `pinned` the indices of the samples to pin. Returns false, and sets the automatic target,
    /// if `values` does not have one value per sample.
    pub fn set_target(&mut self, values: Option<&[f64]>, pinned: &[usize]) -> bool {
        let (method, strength) = (self.opts.target, self.opts.strength);
        let mut setups = self.setups_mut();
        let total: usize = setups.iter().map(|s| s.target().len()).sum();
        let fits = values.is_none_or(|v| v.len() == total);
        let mut offset = 0;
        for setup in &mut setups {
            let t = setup.target_mut();
            t.reset();
            let n = t.len();
            for &k in pinned {
                if (offset..offset + n).contains(&k) {
                    t.pin(k - offset);
                }
            }
            match values {
                Some(v) if fits => {
                    for (k, &g) in v[offset..offset + n].iter().enumerate() {
                        t.set(k, g);
                    }
                }
                _ => t.smooth(method, strength.unwrap_or_else(|| default_strength(method, n))),
            }
            offset += n;
        }
        self.edited = (values.is_some() && fits) || !pinned.is_empty();
        fits
    }

    /// Set a hand-edited target saved at curve parameters: `at[i]` (on the input's parameter, in order
    /// along the region, as [`Self::sample_params`] lists them) carries `values[i]`; `pinned` indexes
    /// into `at`. Where `at` is this fairing's own samples it is [`Self::set_target`]; otherwise (the
    /// samples changed with the end conditions, the corners or the sampling) the values are resampled
    /// piecewise linearly in the parameter along the region (a corner's two sides apart), and each pin
    /// goes to the nearest sample; samples beyond the saved ones (a longer moving stretch) take the
    /// automatic target. Returns false, and sets the automatic target, if `at` and `values` differ in
    /// length, or `at` covers less than half of the samples' range (a target of another region).
    pub fn set_target_at(&mut self, at: &[f64], values: &[f64], pinned: &[usize]) -> bool {
        let mine = self.sample_params();
        if at == mine.as_slice() {
            return self.set_target(Some(values), pinned);
        }
        let (a, b) = self.input.domain();
        let len = b - a;
        let (saved, new) = (unwrapped(at, len), unwrapped(&mine, len));
        let tol = 1e-9 * len;
        let ordered = at.len() == values.len() && at.len() >= 2 && saved.windows(2).all(|w| w[1] >= w[0]);
        let (lo, hi) = (saved[0] - tol, saved[saved.len() - 1] + tol);
        let (first, last) = (new[0], new[new.len() - 1]);
        // the saved samples must cover at least half of this fairing's (other end conditions move the
        // ends of the moving stretch, not the region)
        let overlap = (hi.min(last) - lo.max(first)).max(0.0);
        if !ordered || overlap < 0.5 * (last - first) {
            self.set_target(None, &[]);
            return false;
        }
        // outside the saved samples (a longer moving stretch) the automatic target
        self.set_target(None, &[]);
        let auto = self.target().values().to_vec();
        let starts = self.stretch_starts();
        let resampled: Vec<f64> = new
            .iter()
            .enumerate()
            .map(|(k, &t)| {
                if t < lo || t > hi {
                    return auto[k];
                }
                // the first sample of a stretch after a corner takes the value right of it, the others
                // the value left of (or at) their parameter
                let right = starts.contains(&k) || k == 0;
                interpolate(&saved, values, t, right)
            })
            .collect();
        let pins: Vec<usize> = pinned
            .iter()
            .filter_map(|&i| saved.get(i))
            .filter_map(|&t| (0..new.len()).min_by(|&x, &y| (new[x] - t).abs().total_cmp(&(new[y] - t).abs())))
            .collect();
        self.set_target(Some(&resampled), &pins)
    }

    /// Fair (module docs for what each route does; [`Pass`] for how).
    ///
    /// A full pass that follows the automatic target never ends with more curvature extrema than the
    /// input (counted as `measure` counts them, over the whole curve): if its result would, the input is
    /// returned as it was, with a note. A hand-edited target is followed as edited, and a region end
    /// inside the curve given G0 or G1 may add the curvature step (and extrema) it asks for.
    pub fn fair(&mut self, pass: Pass) -> Result<CurveFair> {
        let guarded = pass == Pass::Full && !self.edited && !self.asks_for_curvature_steps();
        let mut f = if guarded && self.original_extrema.is_none() {
            // the input's count does not depend on the fair: on the first full fair it is taken beside it
            // (on a second core; the result is the same)
            let input = self.input.clone();
            let (f, known) = rayon::join(
                || self.fair_routed(pass),
                || {
                    let delta = crate::measure::extrema_threshold(&input);
                    (delta, extrema_count(&input, delta))
                },
            );
            self.original_extrema = Some(known);
            f?
        } else {
            self.fair_routed(pass)?
        };
        if !guarded {
            return Ok(f);
        }
        let Some((delta, before)) = self.original_extrema else {
            return Ok(f);
        };
        // (a count the fair's own judged check made of the result at the same dead band is taken as it is:
        // the same function of the same curve)
        let after = self
            .setups()
            .iter()
            .find_map(|s| s.counted_extrema(&f.result.curve, delta))
            .unwrap_or_else(|| extrema_count(&f.result.curve, delta));
        if after > before {
            let r = &mut f.result;
            r.notes.push(format!(
                "left as it was: the fair ended with more curvature extrema than the input ({before} before, {after} after)"
            ));
            r.curve = self
                .rational
                .as_ref()
                .map_or_else(|| self.input.clone(), |(c, _)| c.clone());
            r.max_deviation = 0.0;
            r.alpha = 0.0;
            r.energy = f.energy_before;
        }
        Ok(f)
    }

    /// A region end inside the curve has an end condition below G2: the fair may leave a curvature step
    /// there by the user's choice.
    fn asks_for_curvature_steps(&self) -> bool {
        let Some((u1, u2)) = self.opts.region else {
            return false;
        };
        let (d0, d1) = self.input.domain();
        let eps = 1e-12 * (d1 - d0);
        let closed = super::closed::is_closed_curve(&self.input);
        let inside = |u: f64| closed || (u > d0 + eps && u < d1 - eps);
        [(u1, self.ends[0]), (u2, self.ends[1])]
            .iter()
            .any(|&(u, e)| e != EndCondition::G2 && inside(u))
    }

    /// [`Self::fair`] along the route, without the final extrema guard.
    fn fair_routed(&mut self, pass: Pass) -> Result<CurveFair> {
        let polish = self.opts.polish && pass != Pass::Draft;
        for s in self.setups_mut() {
            s.set_polish(polish);
        }
        let (input, opts, edited) = (&self.input, self.engine_opts(), self.edited);
        let rational = self.rational.as_ref().map(|r| r.1);
        let run = |s: &mut FairingSetup| match pass {
            Pass::Iterative(o) => fair_iterative(s, o),
            Pass::Full | Pass::Draft => s.fair(),
        };
        match &mut self.route {
            Route::One {
                setup,
                across,
                whole_loop,
            } => {
                let energy_before = setup.original_energy();
                let result = match pass {
                    Pass::Full if *whole_loop && !edited => {
                        // the seam pass has no extrema guard of its own (the single pass's polish has):
                        // a result with more curvature extrema than the input falls back to the single
                        // pass with the seam held
                        let r = closed::fair_closed(input, opts)?;
                        let delta = crate::measure::extrema_threshold(input);
                        let extrema = |c: &BSplineCurve| extrema_count(c, delta);
                        let before = extrema(input);
                        let after = extrema(&r.curve);
                        if after <= before {
                            closed::judged_against_reference(input, opts, r)?
                        } else {
                            let mut held = run(setup)?;
                            let held_after = extrema(&held.curve);
                            if held_after <= before {
                                held.notes.push(format!(
                                    "faired with the seam held: across the seam the fair ended with more \
                                     curvature extrema than the input ({before} before, {after} after)"
                                ));
                            } else {
                                // never less fair than the input: it stays as it is
                                held.notes.push(format!(
                                    "left as it was: the fair ended with more curvature extrema than the \
                                     input ({before} before, {} after)",
                                    after.min(held_after)
                                ));
                                held.curve = input.clone();
                                held.max_deviation = 0.0;
                                held.alpha = 0.0;
                                held.energy = setup.original_energy();
                            }
                            held
                        }
                    }
                    Pass::Iterative(o) if *whole_loop && !edited => closed::fair_closed_iterative(input, opts, o)?,
                    _ => run(setup)?,
                };
                let result = match across {
                    Some(a) => a.back(result)?,
                    None => result,
                };
                let result = with_stand_in(result, rational);
                Ok(CurveFair {
                    result,
                    corners: vec![],
                    stretches: vec![],
                    energy_before,
                })
            }
            Route::Corners(c) => {
                let f = match pass {
                    Pass::Iterative(_) => c.fair_with(run)?,
                    Pass::Full | Pass::Draft => c.fair()?,
                };
                let energy_before = f.stretches.iter().map(|s| s.energy_before).sum();
                Ok(CurveFair {
                    result: with_stand_in(f.result, rational),
                    corners: f.corners,
                    stretches: f.stretches,
                    energy_before,
                })
            }
        }
    }
}

/// A result of a rational input's stand-in: its deviation bound from the rational original (the stand-in's
/// error added) and a note saying what was faired.
fn with_stand_in(mut result: FairingResult, approx_error: Option<f64>) -> FairingResult {
    if let Some(e) = approx_error {
        result.max_deviation += e;
        result.notes.push(format!(
            "rational curve (unequal weights): faired through a non-rational B-spline of degree {} within {} of it; \
             the deviation bound is from the rational original",
            result.curve.degree(),
            crate::range::short(e)
        ));
    }
    result
}

/// Parameters in order along a region, unwrapped across the seam of a closed curve of domain length
/// `len` (a step back by more than half the domain is the wrap: `len` is added from there on).
fn unwrapped(at: &[f64], len: f64) -> Vec<f64> {
    let mut shift = 0.0;
    let mut prev = f64::NEG_INFINITY;
    at.iter()
        .map(|&u| {
            if u + shift < prev - 0.5 * len {
                shift += len;
            }
            prev = u + shift;
            prev
        })
        .collect()
}

/// The piecewise linear function through `(t[i], v[i])` (`t` non-decreasing, a repeated `t` a jump) at
/// `x`, clamped to the end values; at a jump the value right of it if `right`, else the one left of it.
fn interpolate(t: &[f64], v: &[f64], x: f64, right: bool) -> f64 {
    // the segment [t[i], t[i + 1]] holding x: the last one starting at or before x (right), or the first
    // one ending at or after it (left)
    let n = t.len();
    let i = if right {
        t.partition_point(|&s| s <= x).clamp(1, n - 1) - 1
    } else {
        t.partition_point(|&s| s < x).clamp(1, n - 1) - 1
    };
    let (t0, t1) = (t[i], t[i + 1]);
    if t1 <= t0 {
        return if right { v[i + 1] } else { v[i] };
    }
    let f = ((x - t0) / (t1 - t0)).clamp(0.0, 1.0);
    v[i] + f * (v[i + 1] - v[i])
}

/// The default smoothing strength of the automatic target over `n` samples, as a setup uses it: 20 for
/// [`TargetMethod::Fit`], else [`super::curve::default_passes`].
pub fn default_strength(method: TargetMethod, n: usize) -> usize {
    match method {
        TargetMethod::Fit => 20,
        _ => super::curve::default_passes(n),
    }
}

/// Refuse a smoothing `strength` whose passes over `n` samples would cost more than
/// [`super::curve::MAX_PASS_WORK`] (the heat and fit targets cost the same at any strength).
pub(crate) fn check_strength(method: TargetMethod, strength: usize, n: usize) -> Result<()> {
    let name = match method {
        TargetMethod::Average => "average",
        TargetMethod::Binomial => "binomial",
        TargetMethod::Heat | TargetMethod::Fit => return Ok(()),
    };
    if strength.saturating_mul(n) > super::curve::MAX_PASS_WORK {
        return Err(crate::error::Error::TargetTooStrong {
            strength,
            target: name.into(),
            samples: n,
            max_passes: super::curve::MAX_PASS_WORK / n.max(1),
        });
    }
    Ok(())
}

/// Fair `curve` with `opts` in one call: [`CurveFairing::new`], then a full [`CurveFairing::fair`].
pub fn fair_curve(curve: &BSplineCurve, opts: FairingOptions) -> Result<FairingResult> {
    Ok(CurveFairing::new(curve, opts)?.fair(Pass::Full)?.result)
}

/// The curvature extrema the guards compare: `measure`'s count with the dead band `delta`, around the
/// loop on a closed curve ([`crate::measure::curvature_extrema_around`]).
fn extrema_count(c: &BSplineCurve, delta: f64) -> usize {
    if super::closed::is_closed_curve(c) {
        crate::measure::curvature_extrema_around(c, delta)
    } else {
        crate::measure::curvature_extrema_at(c, delta)
    }
}
