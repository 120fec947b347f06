//! The options and the outcome of a surface fairing.

use crate::error::{Error, Result};
use crate::fair::curve::FairingOptions;
use crate::fit_surface::SurfaceSmoothing;
use crate::surface::BSplineSurface;
use std::ops::Range;
use std::time::Duration;

/// How the u- and v-isocurve point clouds are combined (module docs, step 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Combine {
    /// The paper: 0.5/0.5.
    Average,
    /// By distance to the region border only (equal to `Average` for a
    /// whole-surface fairing, which has no held border).
    Border,
    /// By distance to the border and size of the correction (default).
    #[default]
    Weighted,
    /// `Weighted`, then normal umbrella smoothing on the grid (border held).
    Smoothed,
}

impl std::str::FromStr for Combine {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "average" => Ok(Self::Average),
            "border" => Ok(Self::Border),
            "weighted" => Ok(Self::Weighted),
            "smoothed" => Ok(Self::Smoothed),
            _ => Err(Error::InvalidInput(format!(
                "unknown combination {s:?}: expected average, border, weighted or smoothed"
            ))),
        }
    }
}

/// What [`fair_surface`](super::fair_surface) does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum SurfaceMethod {
    /// The isocurve fairing (steps 1-7), then the fairest of it, the reference smoother and the smoother
    /// run on its result (step 8).
    #[default]
    Fairway,
    /// The reference smoother alone: tensor-product penalized least squares on the original's grid
    /// samples with the curvature-variation energy ([`PlateFit`](crate::fit_surface::PlateFit), order `REFERENCE_ORDER`(super::REFERENCE_ORDER)), the largest strength
    /// whose result holds the verified band (module docs, step 8).
    Smoothing,
    /// The isocurve fairing alone (steps 1-7, without the step-8 choice): for comparisons.
    Isocurves,
}

impl std::str::FromStr for SurfaceMethod {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "fairway" | "fast" => Ok(Self::Fairway),
            "smoothing" => Ok(Self::Smoothing),
            "isocurves" => Ok(Self::Isocurves),
            _ => Err(Error::InvalidInput(format!(
                "unknown surface method {s:?}: expected fast (fairway), smoothing or isocurves"
            ))),
        }
    }
}

/// Which candidate [`fair_surface`](super::fair_surface) returned (module docs, step 8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum SurfacePick {
    /// The isocurve fairing's result (steps 1-7).
    Isocurves,
    /// The reference smoother's result on the original's samples.
    Reference,
    /// The reference smoother run on the isocurve fairing's result (band still against the original).
    Combined,
    /// A blend of the isocurve result's net with the fairer smoother net (`BLENDS`(super::BLENDS)).
    Blend,
    /// The original: no candidate was fairer.
    Original,
}

/// Options of a surface fairing, built from the defaults with one setter a field (`#[non_exhaustive]`):
/// `SurfaceFairingOptions::default().tolerance(0.01).region(Some(((0.2, 0.8), (0.1, 0.9))))`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct SurfaceFairingOptions {
    /// Region `((u1, u2), (v1, v2))` (`None`: the whole surface).
    pub region: Option<((f64, f64), (f64, f64))>,
    /// Tolerance m (> 0): max deviation from the original.
    pub tolerance: f64,
    /// Options for the isocurves (`region` and `tolerance` are set per isocurve).
    pub curve: FairingOptions,
    /// Combination of the two clouds.
    pub combine: Combine,
    /// Grid samples (isocurves) per knot span, ≥ 2.
    pub samples_per_span: usize,
    /// Smoothing of the surface fit (with `auto_smoothing`, only its order is used).
    pub smoothing: SurfaceSmoothing,
    /// Choose the smoothing strength (of `AUTO_STRENGTHS`(super::AUTO_STRENGTHS)) and the isocurve tolerance (see
    /// `iso_levels`) by the fairness energy among the results that hold the tolerance (module docs,
    /// step 6). Without it: `smoothing` as given, the isocurve tolerance m (tightened only when the
    /// band is broken).
    pub auto_smoothing: bool,
    /// Threads fairing the isocurves (`None`: rayon's global pool, `RAYON_NUM_THREADS` if set; `Some(1)`: this
    /// thread only). The result does not depend on it.
    pub threads: Option<usize>,
    /// With `auto_smoothing`: at most this many isocurve tolerances `m, m/3, m/9, …` (`ISO_LEVEL_FACTOR`(super::ISO_LEVEL_FACTOR)) are tried
    /// (greedy: stop at the first level that does not lower the fairness energy), ≥ 1 (module docs, step 6).
    pub iso_levels: usize,
    /// How the levels below m are made: `false` (default) scales the combined correction of the one
    /// isocurve pass at m by 1/3, 1/9, … (no further isocurve work); `true` fairs every isocurve again at
    /// each level's tolerance m/3, m/9, … (one setup per isocurve, re-faired per level: about 2× the
    /// isocurve time). Measured in the module docs (step 6): the same fairness within a few per cent.
    pub refair_levels: bool,
    /// Each isocurve's fit steps its fairness weight μ below the band's largest while its E falls, as a
    /// curve fair does (default `true`; [`FairingSetup::set_fairest_mu`](crate::fair::FairingSetup::set_fairest_mu)).
    /// Off in [`Self::draft`]: one band-checked solve and one E fewer per isocurve.
    pub fairest_isocurves: bool,
    /// The isocurve fairing with the step-8 choice (default), the reference smoother alone, or the isocurve
    /// fairing alone. Step 8 runs with or without `auto_smoothing`: for exactly the given `smoothing`, use
    /// [`SurfaceMethod::Isocurves`].
    pub method: SurfaceMethod,
}

impl Default for SurfaceFairingOptions {
    fn default() -> Self {
        Self {
            region: None,
            tolerance: 1e-3,
            curve: FairingOptions::default(),
            combine: Combine::Weighted,
            samples_per_span: 3,
            smoothing: SurfaceSmoothing {
                strength_u: 0.0,
                strength_v: 0.0,
                order: 3,
            },
            auto_smoothing: true,
            threads: None,
            iso_levels: 3,
            refair_levels: false,
            fairest_isocurves: true,
            method: SurfaceMethod::Fairway,
        }
    }
}

/// The outcome of [`fair_surface`](super::fair_surface).
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceFairingResult {
    /// The faired surface: the original's knots and degrees, non-rational; a NURBS face (unequal weights)
    /// faired through its stand-in is on the stand-in's knots (degrees max(p, 3)), one faired on its own
    /// knots and weights is rational with the original's weights (the notes say which).
    pub surface: BSplineSurface,
    /// Verified upper bound of the deviation on the check grid (≤ tolerance).
    pub max_deviation: f64,
    /// Isocurve tolerance of the picked level (m, m/3, m/9, … or a tightened one; 0 for
    /// [`SurfaceMethod::Smoothing`], which fairs no isocurve). With the default
    /// scaled levels (`refair_levels` off), level k's isocurve corrections are those of the pass at m
    /// scaled by 3⁻ᵏ, so this bounds their size the same way.
    pub iso_tolerance: f64,
    /// Rounds of isocurve fairing done.
    pub rounds: usize,
    /// Scale of the control point change (1 unless the band forced a partial step).
    pub alpha: f64,
    /// Smoothing of the fit that was used.
    pub smoothing: SurfaceSmoothing,
    /// Free control rows (u).
    pub free_u: Range<usize>,
    /// Free control columns (v).
    pub free_v: Range<usize>,
    /// Where the time went.
    pub timings: SurfaceTimings,
    /// Which candidate was returned (module docs, step 8).
    pub pick: SurfacePick,
    /// A sound upper bound of the deviation everywhere (not only on the check grid):
    /// [`crate::fair::verify::surface_band_bound`], the control net of the parametric difference refined
    /// where it comes near m. `Some(b)` with b ≤ tolerance certifies the band: where the first bound came
    /// out above m (the grid held the band, but the fair slid the surface along itself between its
    /// points), the change is scaled back until it certifies m (`alpha` says by how much). A rational
    /// input with equal weights is bounded in its polynomial form, the same surface; a NURBS face faired
    /// on its own knots and weights on the rational difference (same weights). `None` only where the
    /// bound cannot apply (different knots: never for this engine's result).
    pub band_bound: Option<f64>,
    /// What the fair did besides the plain method, in the user's terms: C0 knot lines faired tile by
    /// tile with the rows next to them held, tiles too short to move left as they were.
    pub notes: Vec<String>,
    /// Poles made smooth before the fair (step 0, `poles.rs`; the notes say which and how far): 0 where
    /// the surface has none, or the route through them was not the fairer. `pick` then names the
    /// candidate of the pole-smoothed surface's fair.
    pub smoothed_poles: usize,
}

/// Wall-clock time of the phases of one [`fair_surface`](super::fair_surface) call (summed over
/// rounds and smoothing candidates).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SurfaceTimings {
    /// Sampling the original on the grid, extracting and fairing the isocurves (curve engine).
    pub isocurves: Duration,
    /// Combining the two clouds (including `Combine::Smoothed`'s smoothing).
    pub combine: Duration,
    /// Surface least-squares fits.
    pub fit: Duration,
    /// Hard-tolerance verification (coarse and full check grids, α bisection).
    pub verify: Duration,
    /// The reference smoother's searches and the ranking of the candidates (step 8).
    pub reference: Duration,
}

impl SurfaceTimings {
    /// Sum of the phases.
    pub fn total(&self) -> Duration {
        self.isocurves + self.combine + self.fit + self.verify + self.reference
    }
}

impl std::ops::Add for SurfaceTimings {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            isocurves: self.isocurves + o.isocurves,
            combine: self.combine + o.combine,
            fit: self.fit + o.fit,
            verify: self.verify + o.verify,
            reference: self.reference + o.reference,
        }
    }
}

impl SurfaceFairingOptions {
    /// These options made a draft: the quick preview the editor shows while the tolerance (or the region)
    /// is dragged, replaced by the full fair when the pointer is released. One isocurve tolerance level
    /// (`iso_levels` 1), the isocurve fairing alone (no step-8 ranking: [`SurfaceMethod::Isocurves`]) and
    /// each isocurve's fit at the band's largest μ (`fairest_isocurves` off). The band is checked and
    /// bounded as in every fair. Measured on the surface suite at 30 × 30 and 1, 3, 10 σ (PERFORMANCE.md,
    /// session 29): the same isocurve curvature extrema as with `fairest_isocurves` on, `∫∫|∇H|²` within
    /// 0.3 %, 12 % less time a draft.
    pub fn draft(self) -> Self {
        Self {
            iso_levels: 1,
            method: SurfaceMethod::Isocurves,
            fairest_isocurves: false,
            ..self
        }
    }
}

crate::fair::curve::setters_for!(SurfaceFairingOptions {
    region: Option<((f64, f64), (f64, f64))>,
    tolerance: f64,
    curve: FairingOptions,
    combine: Combine,
    samples_per_span: usize,
    smoothing: SurfaceSmoothing,
    auto_smoothing: bool,
    threads: Option<usize>,
    iso_levels: usize,
    refair_levels: bool,
    fairest_isocurves: bool,
    method: SurfaceMethod,
});
