//! Live fairing preview: keeps the core's [`CurveFairing`] for the current curve, region and end
//! conditions, and re-runs it when the tolerance, the target or the options change (a drag makes a
//! draft on the same setup, the release the full fair). No fairing maths and no routing here — the
//! core picks the route (corners, a region across the seam, a whole loop) and maps results and sample
//! parameters back onto the original curve.

use std::time::Instant;

use fairway::BSplineCurve;
use fairway::corners::Corner;
use fairway::fair::{
    CurveFairing, EndCondition, FairingOptions, FairingResult, FitMode, Integrator, Pass, PolishMethod, Target,
    TargetMethod,
};
use fairway::io::DocumentSettings;
use fairway::measure::{Measures, arc_params, deviations, measure, region_curvature};
use serde::{Deserialize, Serialize};

use crate::Sampled;
use crate::scene_view::Frame;

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
    /// The condition kept at the start and the end of the open curve where the region reaches them
    /// ([`FairingOptions::curve_ends`]): set for a fair, not stored — a curve end that joins another
    /// curve keeps its join's continuity ([`crate::curve_ws::CurveCx::join_holds`]); `None` (a free
    /// end): the core's default (at most G1), or G2 when easing.
    #[serde(skip)]
    pub curve_ends: [Option<EndCondition>; 2],
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
            curve_ends: [None; 2],
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
    /// Fairway's fair or the reference smoother.
    mode: FitMode,
    /// The condition kept at the curve's own ends (a join's).
    curve_ends: [Option<EndCondition>; 2],
}

#[derive(Debug, Clone, PartialEq)]
struct RunKey {
    tolerance: f64,
    /// A draft while a drag is in progress (no polish, seam held), else the full fair.
    draft: bool,
    opts: FairOptions,
    target: Option<Vec<f64>>,
    /// The curve parameters of the target values (the target is resampled onto the samples).
    target_params: Option<Vec<f64>>,
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

/// Live fairing state.
#[derive(Debug, Default)]
pub struct Fairing {
    /// The view plane's frame the preview is sampled in (as the canvas draws the original).
    pub frame: Frame,
    setup: Option<CurveFairing>,
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
    /// Wall time of the last `CurveFairing` build (a new curve, region or end
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
        let (inject_panic, frame) = (self.inject_panic, self.frame);
        *self = Self {
            internal_error: self.internal_error.take(),
            inject_panic,
            frame,
            ..Self::default()
        };
    }

    /// Run an engine call `f` under [`crate::guard::catch_panic`]: a panic
    /// becomes `Err(message)`, also recorded in `internal_error`.
    fn guarded<T>(&mut self, what: &str, f: impl FnOnce() -> T) -> Result<T, String> {
        let inject = std::mem::take(&mut self.inject_panic);
        crate::guard::catch_panic(what, || {
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
        self.setup.as_ref().map(CurveFairing::target).filter(|t| !t.is_empty())
    }

    /// The setup fairs a region across the seam of a closed curve (on the re-seamed curve; results
    /// are mapped back onto the original).
    pub fn across_seam(&self) -> bool {
        self.setup.as_ref().is_some_and(CurveFairing::across_seam)
    }

    /// Build the setup of `key` (a new curve, region or end conditions); false (the error as the
    /// preview) if the core refused it.
    fn new_setup(&mut self, curve: &BSplineCurve, key: SetupKey, fo: FairingOptions, ends: [EndCondition; 2]) -> bool {
        self.setup_key = Some(key);
        self.run_key = None;
        self.trio_key = None;
        self.trio = None;
        let t0 = Instant::now();
        // u1 > u2: the region runs across the seam (the core says so clearly if the curve is open
        // or its seam cannot be re-seamed)
        let res = self
            .guarded("fairing setup", || CurveFairing::with_ends(curve, fo, ends))
            .and_then(|r| r.map_err(|e| e.to_string()));
        self.setup_ms = t0.elapsed().as_secs_f64() * 1e3;
        match res {
            Ok(s) => {
                self.setup = Some(s);
                true
            }
            Err(e) => {
                self.setup = None;
                self.preview = Some(Err(e));
                false
            }
        }
    }

    /// Bring the preview up to date; does nothing when nothing changed.
    /// With `draft` (a drag in progress) the core's E polish is skipped, so
    /// a live drag stays inside the frame budget; when the drag ends
    /// (`draft` false) the same setup re-fairs at full quality. Returns
    /// whether the preview was recomputed.
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
        let sk = SetupKey {
            curve_rev,
            region,
            ends: opts.ends,
            ease_ends: opts.ease_ends,
            mode: opts.mode,
            curve_ends: opts.curve_ends,
        };
        let fo = fairing_options(region, tolerance, &opts);
        let frame = self.frame;
        if self.setup_key.as_ref() != Some(&sk) && !self.new_setup(curve, sk, fo, opts.ends) {
            return true;
        }
        let rk = RunKey {
            tolerance,
            draft,
            opts,
            target: settings.target.clone(),
            target_params: settings.target_params.clone(),
            pinned: settings.pinned.clone(),
        };
        let mut changed = false;
        if self.run_key.as_ref() != Some(&rk) {
            self.run_key = Some(rk.clone());
            changed = true;
            let Some(mut setup) = self.setup.take() else {
                return true;
            };
            let res = self.guarded("fairing", || {
                setup.set_options(fo).map_err(|e| e.to_string())?;
                let fits = match (&rk.target, &rk.target_params) {
                    (Some(v), Some(at)) => setup.set_target_at(at, v, &rk.pinned),
                    (v, _) => setup.set_target(v.as_deref(), &rk.pinned),
                };
                let mismatch = !fits;
                run(&mut setup, tolerance, draft, &frame).map(|p| (p, mismatch))
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
                let trio = [tolerance / 3.0, tolerance, tolerance * 3.0].map(|m| {
                    (
                        m,
                        self.guarded("fairing", || run(&mut s, m, draft, &frame))
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
        let orig = self.setup.as_ref().map(CurveFairing::original);
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
        let n = fairway::measure::DEV_SAMPLES;
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

/// The core's options for `region` at `tolerance` with the editor's choices.
fn fairing_options(region: (f64, f64), tolerance: f64, opts: &FairOptions) -> FairingOptions {
    // easing keeps the G2 curve end (by default a curve end keeps position and tangent only); a join
    // there keeps its own continuity
    let ease = opts.ease_ends.then_some(EndCondition::G2);
    (curve_options(tolerance, opts))
        .region(Some(region))
        .curve_ends(opts.curve_ends.map(|e| match (e, ease) {
            (Some(a), Some(b)) => Some(if a.order() >= b.order() { a } else { b }),
            (a, b) => a.or(b),
        }))
}

/// The core's options at `tolerance` with the editor's choices, without a region (the whole curve,
/// as the network fair takes them).
pub fn curve_options(tolerance: f64, opts: &FairOptions) -> FairingOptions {
    FairingOptions::default()
        .region(None)
        .tolerance(tolerance)
        .target(opts.method)
        .strength(opts.strength)
        .integrator(opts.integrator)
        .polish_iterations(opts.polish_iterations)
        .polish_method(opts.polish_method)
        .ease_curve_ends(opts.ease_ends)
        .curve_ends([opts.ease_ends.then_some(EndCondition::G2); 2])
        .mode(opts.mode)
}

/// Fair at `tolerance` (a draft, or the full fair: for a whole closed curve with the automatic target
/// that fairs its seam too, about 4× a single pass) and build the preview.
fn run(fairing: &mut CurveFairing, tolerance: f64, draft: bool, frame: &Frame) -> Result<Preview, String> {
    let t0 = Instant::now();
    fairing.set_tolerance(tolerance).map_err(|e| e.to_string())?;
    let pass = if draft { Pass::Draft } else { Pass::Full };
    let fair = fairing.fair(pass).map_err(|e| e.to_string())?;
    let fair_ms = t0.elapsed().as_secs_f64() * 1e3;
    let result = fair.result;
    let spans = result.curve.knots().breakpoints().len().saturating_sub(1).max(1);
    let sampled = Sampled::new(&frame.curve_in(&result.curve), (spans * 24).clamp(400, 4000));
    let target = fairing.target();
    Ok(Preview {
        sampled,
        params: fairing.sample_params(),
        target: target.values().to_vec(),
        original: target.original().to_vec(),
        pinned: target.pinned().to_vec(),
        corners: fair.corners,
        stretches: fair.stretches.iter().map(|s| s.region).collect(),
        breaks: fairing.stretch_starts(),
        result,
        fair_ms,
        draft,
    })
}

/// The indices of the pinned target samples (`pinned[k]` true), as [`crate::Command::SetTarget`] takes them.
pub fn pinned_indices(pinned: &[bool]) -> Vec<usize> {
    pinned.iter().enumerate().filter(|(_, b)| **b).map(|(k, _)| k).collect()
}

/// The default smoothing strength for `n` samples: the core's own default
/// ([`fairway::fair::curve_fairing::default_strength`]), so the editor's automatic target is the CLI's.
pub fn default_strength(method: TargetMethod, n: usize) -> usize {
    fairway::fair::curve_fairing::default_strength(method, n)
}
