//! Live fairing preview: keeps a [`FairingSetup`] of the core for the
//! current curve and region, and re-runs it when the tolerance, the target
//! or the options change. No fairing maths here — it all lives in
//! `fairway::fair`.
//!
//! A region across the seam of a closed curve (`u1 > u2`, [`crate::region`])
//! is set up with the core's `setup_across_seam_with_ends` (the curve re-seamed
//! in the middle of the untouched rest, where the region is an ordinary
//! stretch) and every fair's result is mapped back onto the original knot
//! vector with [`AcrossSeam::back`]; the setup is kept and re-faired cheaply
//! like any other. Its sample parameters are the re-seamed curve's: past the
//! old seam `b` they are the original's `u − L`, and [`Preview::params`] holds
//! them so mapped.
//!
//! A region that holds corners of the curve (tangent breaks, stops: [`fairway::corners`]) is set up with
//! the core's [`CornerSetups`], one setup per stretch between corners, faired together and merged
//! exactly as `fairway fair` does (a closed curve re-seamed at a kink or, for a region across the
//! seam, in the untouched rest; [`CornerSetups::to_original`] maps its sample parameters back); the
//! preview's target, samples and pins are the stretches' ones end to end, and a hand-edited target is
//! split back among them.

use std::time::Instant;

use fairway::BSplineCurve;
use fairway::corners::Corner;
use fairway::fair::closed::{AcrossSeam, setup_across_seam_with_ends};
use fairway::fair::{
    CornerSetups, EndCondition, FairingOptions, FairingResult, FairingSetup, FitMode, Integrator, PolishMethod, Target,
    TargetMethod, fair_closed,
};
use fairway::io::DocumentSettings;
use fairway::measure::{Measures, arc_params, deviations, measure, region_curvature};
use serde::{Deserialize, Serialize};

use crate::Sampled;

/// The largest E polish iteration count the editor offers (and accepts from stored settings).
pub const MAX_POLISH: usize = 64;

/// Fairing options chosen in the editor (persisted with the settings).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct FairOptions {
    /// Continuity at the region's start and end.
    pub ends: [EndCondition; 2],
    /// Target smoothing method.
    pub method: TargetMethod,
    /// Smoothing strength (`None`: the core's default).
    pub strength: Option<usize>,
    /// Integration scheme.
    pub integrator: Integrator,
    /// Gauss–Newton iterations of the core's E polish in a full fair (drafts skip the polish).
    pub polish_iterations: usize,
    /// How the core's E polish works ([`FairingOptions::polish_method`]).
    pub polish_method: PolishMethod,
    /// Ease the automatic target into G2 ends that are ends of an open curve
    /// ([`FairingOptions::ease_curve_ends`]).
    pub ease_ends: bool,
    /// Fairway's fair or the reference smoother ([`FairingOptions::mode`]).
    pub mode: FitMode,
}

impl Default for FairOptions {
    fn default() -> Self {
        let d = FairingOptions::default();
        Self {
            ends: [d.ends; 2],
            method: d.target,
            strength: None,
            integrator: d.integrator,
            polish_iterations: d.polish_iterations,
            polish_method: d.polish_method,
            ease_ends: d.ease_curve_ends,
            mode: d.mode,
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
struct SetupKey {
    curve_rev: u64,
    region: (f64, f64),
    ends: [EndCondition; 2],
    /// Eased G2 curve ends (they shape the automatic target, built with the setup).
    ease_ends: bool,
    /// The core's E polish (off for a draft while a drag is in progress).
    polish: bool,
    /// Fairway's fair or the reference smoother.
    mode: FitMode,
}

#[derive(Debug, Clone, PartialEq)]
struct RunKey {
    tolerance: f64,
    opts: FairOptions,
    target: Option<Vec<f64>>,
    pinned: Vec<usize>,
}

/// The current faired preview.
#[derive(Debug, Clone)]
pub struct Preview {
    /// The core's result (faired curve, max deviation, energy, ...).
    pub result: FairingResult,
    /// The faired curve sampled for drawing.
    pub sampled: Sampled,
    /// Sample parameters of the target (the setup's p_k) on the original curve. For a region across
    /// the seam they run from `u1` up to `b`, then from `a` up to `u2` (the re-seamed setup's `u > b`
    /// mapped to `u − L`: the same points).
    pub params: Vec<f64>,
    /// Target values g_k.
    pub target: Vec<f64>,
    /// Original curvature κ_k at the samples.
    pub original: Vec<f64>,
    /// Pin flags.
    pub pinned: Vec<bool>,
    /// The corners kept inside the region (empty if it has none) and the stretches between them,
    /// each faired as a region of its own.
    pub corners: Vec<Corner>,
    /// See `corners`.
    pub stretches: Vec<(f64, f64)>,
    /// The target samples that start a stretch after the first (the κ plot draws each stretch's target
    /// as a line of its own, not one line through the jump at a corner).
    pub breaks: Vec<usize>,
    /// Wall time of the last re-fair, milliseconds.
    pub fair_ms: f64,
    /// A draft made while a drag is in progress: the band-holding fit without
    /// the core's E polish ([`FairingOptions::polish`]); the release re-fairs
    /// with it. Accept waits for the full fair.
    pub draft: bool,
}

/// What the preview re-fairs: one setup, or one per stretch between the corners in the region.
#[derive(Debug, Clone)]
enum Prepared {
    One(Box<FairingSetup>),
    Corners(Box<CornerSetups>),
}

impl Prepared {
    /// The curve being faired (for a region across the seam: the re-seamed one).
    fn original(&self) -> &BSplineCurve {
        match self {
            Self::One(s) => s.original(),
            Self::Corners(c) => c.original(),
        }
    }

    /// The setups, in order along the region.
    fn setups(&self) -> Vec<&FairingSetup> {
        match self {
            Self::One(s) => vec![s],
            Self::Corners(c) => c.setups().collect(),
        }
    }

    /// The target of the whole region: the stretches' targets end to end.
    fn target(&self) -> Target {
        match self {
            Self::One(s) => s.target().clone(),
            Self::Corners(c) => Target::concat(&c.setups().map(FairingSetup::target).collect::<Vec<_>>()),
        }
    }
}

/// Live fairing state.
#[derive(Debug, Default)]
pub struct Fairing {
    setup: Option<Prepared>,
    /// For a region across the seam: the rotation that maps the setup's results back.
    across: Option<AcrossSeam>,
    setup_key: Option<SetupKey>,
    run_key: Option<RunKey>,
    /// The preview, or the core's error message.
    pub preview: Option<Result<Preview, String>>,
    /// Tight / medium / loose results (tolerance m/3, m, 3m), when asked for.
    pub trio: Option<[(f64, Result<Preview, String>); 3]>,
    trio_key: Option<RunKey>,
    /// A hand-edited target did not match the setup's samples and was ignored.
    pub target_mismatch: bool,
    /// Measures of the original (against itself) and of the preview.
    pub measures: Option<(Measures, Measures)>,
    /// The region's own curvature figures, before and after: (curvature extrema, ∫(dκ/ds)² ds) over the
    /// region with the whole curve's δ (`fairway::measure::region_curvature`); `None` for the whole curve.
    pub region_measures: Option<((usize, f64), (usize, f64))>,
    /// Parameter (on the original) where the preview deviates most.
    pub dev_at: Option<f64>,
    /// What the measures describe: the setup (curve, region, ends) and the run (tolerance, options,
    /// target); a new region with the same tolerance and target is a new preview too.
    measures_key: Option<(Option<SetupKey>, Option<RunKey>)>,
    before: Option<(SetupKey, Measures)>,
    /// A panic caught in the engine since the app last looked (the app moves
    /// it to its error line).
    pub internal_error: Option<String>,
    /// Wall time of the last `FairingSetup` build (a new curve, region or end
    /// conditions), milliseconds.
    pub setup_ms: f64,
    /// Test seam: the next engine call panics (inside the guard), to check
    /// that a panic in the engine is reported and changes nothing.
    #[doc(hidden)]
    pub inject_panic: bool,
}

impl Fairing {
    /// Forget everything (no region).
    pub fn clear(&mut self) {
        let inject_panic = self.inject_panic;
        *self = Self {
            internal_error: self.internal_error.take(),
            inject_panic,
            ..Self::default()
        };
    }

    /// Run an engine call `f` under [`fairway::guard::catch_panic`]: a panic
    /// becomes `Err(message)`, also recorded in `internal_error`.
    fn guarded<T>(&mut self, what: &str, f: impl FnOnce() -> T) -> Result<T, String> {
        let inject = std::mem::take(&mut self.inject_panic);
        fairway::guard::catch_panic(what, || {
            if inject {
                panic!("injected panic (test seam)");
            }
            Ok(f())
        })
        .map_err(|e| {
            let msg = e.to_string();
            self.internal_error = Some(msg.clone());
            msg
        })
    }

    /// The prepared target of the region (for target edits: a copy to change and push back): the
    /// setup's, or the stretches' between corners end to end. For a region across the seam it is the
    /// re-seamed curve's setup's ([`Fairing::across_seam`]).
    pub fn target(&self) -> Option<Target> {
        self.setup.as_ref().map(Prepared::target).filter(|t| !t.is_empty())
    }

    /// The setup fairs a region across the seam of a closed curve (on the re-seamed curve; results
    /// are mapped back onto the original).
    pub fn across_seam(&self) -> bool {
        self.across.is_some()
    }

    /// Bring the preview up to date; does nothing when nothing changed.
    /// With `draft` (a drag in progress) the core's E polish is skipped, so
    /// a live drag stays inside the frame budget; when the drag ends
    /// (`draft` false) the setup is rebuilt with the polish and the preview
    /// re-faired at full quality. Returns whether the preview was recomputed.
    pub fn update(
        &mut self,
        curve: &BSplineCurve,
        curve_rev: u64,
        settings: &DocumentSettings,
        tolerance: f64,
        opts: FairOptions,
        want_trio: bool,
        draft: bool,
    ) -> bool {
        let Some(region) = settings.region else {
            if self.setup.is_some() || self.preview.is_some() {
                self.clear();
            }
            return false;
        };
        let polish = !draft && FairingOptions::default().polish;
        let sk = SetupKey {
            curve_rev,
            region,
            ends: opts.ends,
            ease_ends: opts.ease_ends,
            polish,
            mode: opts.mode,
        };
        if self.setup_key.as_ref() != Some(&sk) {
            self.setup_key = Some(sk);
            self.run_key = None;
            self.trio_key = None;
            self.trio = None;
            let fo = FairingOptions {
                region: Some(region),
                tolerance,
                target: opts.method,
                strength: opts.strength,
                integrator: opts.integrator,
                polish,
                ease_curve_ends: opts.ease_ends,
                // easing keeps the G2 curve end (by default a curve end keeps position and tangent only)
                curve_ends: opts.ease_ends.then_some(EndCondition::G2),
                mode: opts.mode,
                ..FairingOptions::default()
            };
            let t0 = Instant::now();
            // u1 > u2: the region runs across the seam (the core says so clearly if the curve is open
            // or its seam cannot be re-seamed)
            let res = self
                .guarded("fairing setup", || match CornerSetups::new(curve, fo, opts.ends) {
                    Ok(Some(c)) => Ok((Prepared::Corners(Box::new(c)), None)),
                    Ok(None) if region.0 > region.1 => setup_across_seam_with_ends(curve, fo, opts.ends)
                        .map(|(s, a)| (Prepared::One(Box::new(s)), Some(a))),
                    Ok(None) => {
                        FairingSetup::new_with_ends(curve, fo, opts.ends).map(|s| (Prepared::One(Box::new(s)), None))
                    }
                    Err(e) => Err(e),
                })
                .and_then(|r| r.map_err(|e| e.to_string()));
            self.setup_ms = t0.elapsed().as_secs_f64() * 1e3;
            match res {
                Ok((s, a)) => {
                    self.setup = Some(s);
                    self.across = a;
                }
                Err(e) => {
                    self.setup = None;
                    self.across = None;
                    self.preview = Some(Err(e));
                    return true;
                }
            }
        }
        let rk = RunKey {
            tolerance,
            opts,
            target: settings.target.clone(),
            pinned: settings.pinned.clone(),
        };
        let mut changed = false;
        if self.run_key.as_ref() != Some(&rk) {
            self.run_key = Some(rk.clone());
            changed = true;
            let Some(mut setup) = self.setup.take() else {
                return true;
            };
            let across = self.across.clone();
            let res = self.guarded("fairing", || {
                let mismatch = !prepare(&mut setup, &rk);
                let seam = across.is_none() && across_the_seam(&setup, &rk, !polish);
                run(&mut setup, tolerance, !polish, seam, across.as_ref()).map(|p| (p, mismatch))
            });
            match res {
                Ok(Ok((p, mismatch))) => {
                    self.target_mismatch = mismatch;
                    self.preview = Some(Ok(p));
                    self.setup = Some(setup);
                }
                Ok(Err(e)) => {
                    self.preview = Some(Err(e));
                    self.setup = Some(setup);
                }
                // a panic may have left the setup half-updated: drop it (a new
                // region or curve builds a fresh one)
                Err(e) => self.preview = Some(Err(e)),
            }
        }
        if want_trio && self.trio_key.as_ref() != Some(&rk) {
            if let Some(mut s) = self.setup.clone() {
                let across = self.across.clone();
                let trio = [tolerance / 3.0, tolerance, tolerance * 3.0].map(|m| {
                    (
                        m,
                        self.guarded("fairing", || run(&mut s, m, !polish, false, across.as_ref()))
                            .and_then(|r| r),
                    )
                });
                self.trio = Some(trio);
                self.trio_key = Some(rk);
                changed = true;
            }
        } else if !want_trio {
            self.trio = None;
            self.trio_key = None;
        }
        changed
    }

    /// Whether the measures belong to an older preview.
    pub fn measures_stale(&self) -> bool {
        self.measures_key.as_ref() != Some(&(self.setup_key.clone(), self.run_key.clone()))
    }

    /// Measure the preview (before / after) if it changed since the last
    /// call; cheap to call every frame. With `defer` (a drag in progress)
    /// existing measures are kept stale: the full measures (4000 curvature
    /// samples, 2 × 2000 closest points) cost more than the frame budget.
    pub fn update_measures(&mut self, defer: bool) {
        if !self.measures_stale() || (defer && self.measures.is_some()) {
            return;
        }
        self.measures_key = Some((self.setup_key.clone(), self.run_key.clone()));
        self.measures = None;
        self.region_measures = None;
        self.dev_at = None;
        // the curve being faired: the original, also for a region across the seam (not the re-seamed one)
        let orig = match &self.across {
            Some(a) => Some(a.original()),
            None => self.setup.as_ref().map(Prepared::original),
        };
        let (Some(orig), Some(Ok(p))) = (orig, self.preview.as_ref()) else {
            return;
        };
        let before = match &self.before {
            Some((k, m)) if Some(k) == self.setup_key.as_ref() => m.clone(),
            _ => measure(orig, orig),
        };
        if let Some(k) = self.setup_key.clone() {
            self.before = Some((k, before.clone()));
        }
        let n = 2000;
        let dev = deviations(orig, &p.result.curve, n);
        let at = arc_params(orig, n);
        if let Some((i, _)) = dev.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)) {
            self.dev_at = Some(at[i]);
        }
        let after = measure(orig, &p.result.curve);
        if let Some(k) = &self.setup_key {
            let (d0, d1) = orig.domain();
            let (u1, u2) = k.region;
            let whole = u1 <= u2 && u1 <= d0 + 1e-12 * (d1 - d0) && u2 >= d1 - 1e-12 * (d1 - d0);
            if !whole {
                let delta = before.threshold_delta;
                self.region_measures = Some((
                    region_curvature(orig, u1, u2, delta),
                    region_curvature(&p.result.curve, u1, u2, delta),
                ));
            }
        }
        self.measures = Some((before, after));
    }
}

/// Put the automatic or hand-edited target into the setup(s) (a hand-edited target of a region with
/// corners is the stretches' targets end to end: split back among them); false if the hand-edited
/// target does not fit the samples (then it is ignored).
fn prepare(prepared: &mut Prepared, rk: &RunKey) -> bool {
    let mut setups: Vec<&mut FairingSetup> = match prepared {
        Prepared::One(s) => vec![s],
        Prepared::Corners(c) => c.setups_mut().collect(),
    };
    let total: usize = setups.iter().map(|s| s.target().len()).sum();
    let fits = rk.target.as_ref().is_none_or(|v| v.len() == total);
    let mut offset = 0;
    for setup in &mut setups {
        setup.set_integrator(rk.opts.integrator);
        setup.set_polish_iterations(rk.opts.polish_iterations);
        setup.set_polish_method(rk.opts.polish_method);
        let t: &mut Target = setup.target_mut();
        t.reset();
        let n = t.len();
        let strength = rk.opts.strength.unwrap_or(default_strength(rk.opts.method, n));
        for &k in &rk.pinned {
            if (offset..offset + n).contains(&k) {
                t.pin(k - offset);
            }
        }
        match &rk.target {
            Some(v) if fits => {
                for (k, &g) in v[offset..offset + n].iter().enumerate() {
                    t.set(k, g);
                }
            }
            _ => t.smooth(rk.opts.method, strength),
        }
        offset += n;
    }
    fits
}

/// Fair with the setup (or, with `seam`, the whole closed curve across its seam: [`across_the_seam`];
/// a region with corners: every stretch between them, merged); with `across` (a region across the
/// seam) the result is mapped back onto the original.
fn run(
    prepared: &mut Prepared,
    tolerance: f64,
    draft: bool,
    seam: bool,
    across: Option<&AcrossSeam>,
) -> Result<Preview, String> {
    let t0 = Instant::now();
    let (result, corners, stretches) = match prepared {
        Prepared::One(setup) => {
            setup.set_tolerance(tolerance).map_err(|e| e.to_string())?;
            let r = if seam {
                fair_closed(setup.original(), *setup.options())
            } else {
                setup.fair()
            }
            .map_err(|e| e.to_string())?;
            (r, vec![], vec![])
        }
        Prepared::Corners(c) => {
            c.set_tolerance(tolerance).map_err(|e| e.to_string())?;
            let f = c.fair().map_err(|e| e.to_string())?;
            (f.result, f.corners, f.stretches.iter().map(|s| s.region).collect())
        }
    };
    let result = match across {
        Some(a) => a.back(result).map_err(|e| e.to_string())?,
        None => result,
    };
    let fair_ms = t0.elapsed().as_secs_f64() * 1e3;
    let spans = result.curve.knots().breakpoints().len().saturating_sub(1).max(1);
    let sampled = Sampled::new(&result.curve, (spans * 24).clamp(400, 4000));
    // the setups' samples end to end (one setup unless the region has corners)
    let setups = prepared.setups();
    let breaks = setups
        .iter()
        .scan(0, |start, s| {
            let k = *start;
            *start += s.params().len();
            Some(k)
        })
        .skip(1)
        .collect();
    // a re-seamed setup's parameters past the old seam b, back on the original (u − L)
    let params = setups
        .iter()
        .flat_map(|s| s.params())
        .map(|&u| match (&*prepared, across) {
            (Prepared::Corners(c), _) => c.to_original(u),
            (_, Some(a)) => a.to_original(u),
            _ => u,
        })
        .collect();
    let cat = |f: fn(&Target) -> &[f64]| setups.iter().flat_map(|s| f(s.target())).copied().collect();
    Ok(Preview {
        sampled,
        params,
        target: cat(Target::values),
        original: cat(Target::original),
        pinned: setups.iter().flat_map(|s| s.target().pinned()).copied().collect(),
        corners,
        stretches,
        breaks,
        result,
        fair_ms,
        draft,
    })
}

/// Whether the full preview fairs a whole closed curve across its seam with the core's
/// [`fair_closed`] (two passes, about 4× a single fair) instead of the setup's single pass, which
/// holds the seam: not for a draft, and not with a hand-edited target or pins (they belong to the
/// setup's samples). The target plot keeps showing the setup's samples.
fn across_the_seam(prepared: &Prepared, rk: &RunKey, draft: bool) -> bool {
    let Prepared::One(setup) = prepared else {
        // with corners the core's CornerSetups handles the seam (re-seamed at a kink, or kept as one)
        return false;
    };
    !draft
        && rk.target.is_none()
        && rk.pinned.is_empty()
        && fairway::fair::closed::applies(setup.original(), setup.options())
}

/// The indices of the pinned target samples (`pinned[k]` true), as [`crate::Command::SetTarget`] takes them.
pub fn pinned_indices(pinned: &[bool]) -> Vec<usize> {
    pinned.iter().enumerate().filter(|(_, b)| **b).map(|(k, _)| k).collect()
}

/// The default smoothing strength for `n` samples: the core's own default
/// (20 for `Fit`, else [`fairway::fair::curve::default_passes`]), so the
/// editor's automatic target is the CLI's.
pub fn default_strength(method: TargetMethod, n: usize) -> usize {
    if method == TargetMethod::Fit {
        20
    } else {
        fairway::fair::curve::default_passes(n)
    }
}
