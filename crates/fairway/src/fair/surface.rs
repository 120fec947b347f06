//! Fast, local fairing of a tensor-product B-spline surface (paper §3.2):
//! the isocurves through the region are faired with the curve engine
//! ([`super::curve`]), the two point clouds combined and a surface fitted
//! with the original knots ([`crate::fit_surface`]), under a verified
//! tolerance; then the fairest of that result, the reference smoother's and
//! their combinations is returned (step 8).
//!
//! # Algorithm
//!
//! 1. **Free control points.** In each direction only the control points
//!    whose support `[t_i, t_{i+p+1}]` lies inside the region move
//!    ([`free_range`]); all others keep their exact values, so the surface
//!    outside the *moving rectangle* (the union of the free supports) is
//!    unchanged and, since the knots are kept, the change joins it with
//!    `C^{p−1}` continuity across the border (G2 for bicubics with simple
//!    knots: position, normal and normal curvature). For degree 3 this holds
//!    the three control rows/columns next to the region border. A **pole** —
//!    a boundary row or column whose control points coincide (a surface of
//!    revolution, a triangular patch) — holds its row and the next two
//!    ([`POLE_ROWS`]), so it stays one point with its tangent plane and
//!    curvature; the isocurve through it is a point and is left as it is
//!    (test `a_pole_stays_one_point_and_the_rest_is_faired`). A **seam** —
//!    a closed direction, first and last rows equal — holds [`POLE_ROWS`]
//!    rows at each side of it: the isocurves are faired one stretch each, not
//!    across the seam, and fairing the two sides independently would open the
//!    surface there (test `a_closed_surface_stays_closed_at_its_seam`). Fairing
//!    across a surface's seam, as [`super::closed`] does for curves, is not
//!    done.
//! 2. **Grid.** Parameters `u_k`, `v_l`: `samples_per_span` per knot span of
//!    the moving rectangle (ends included).
//! 3. **Isocurves.** For each `v_l` the u-isocurve `S(·, v_l)` (a B-spline
//!    curve with knots U, [`BSplineSurface::iso_u`]) is faired by
//!    the curve engine ([`FairingSetup`], set up by [`isocurve_setup`]:
//!    4 samples per knot span, a target smoothing of 1.6 spans, the band
//!    checked at the samples) over `[u1, u2]` with the isocurve tolerance —
//!    target, integration, band, fit and G2 ends are the curve engine's — and
//!    evaluated at the `u_k`: the cloud `P_u`. Likewise the v-isocurves give
//!    `P_v`. A direction whose region holds fewer than p + 1 knot spans
//!    (e.g. a single-span cubic direction) has no movable isocurve control
//!    point; its isocurves are left as they are (Δ = 0).
//! 4. **Combine** (see [`Combine`]). With the displacements
//!    `Δ_u = P_u − S`, `Δ_v = P_v − S` at each grid point, the default
//!    [`Combine::Weighted`] takes `Δ = (a Δ_u + b Δ_v)/(a + b)` with
//!    `a = β_u |Δ_u|`, `b = β_v |Δ_v|` (the β alone when both vanish), where
//!    `β_u = d_v/(d_u + d_v)`, `d_u`, `d_v` the normalized parameter
//!    distances (≤ 1/2) to the held u- and v-borders of the moving rectangle
//!    (a side on the domain boundary is free, hence no border). Why: (i) near a u-border the
//!    u-isocurve is pinned G2 by the curve engine while a v-isocurve there
//!    still moves although the held control points cannot follow — so trust
//!    the direction whose border is near; (ii) a wiggle running along v (a
//!    ridge across u) is seen only by the u-isocurves, the v-isocurves see a
//!    fair line and leave it — their "no change" is no evidence against the
//!    change, so the larger correction wins. An extruded curve is thus faired
//!    exactly like the curve, where the paper's 0.5/0.5 average would do
//!    half of it. [`Combine::Average`] is the paper's;
//!    [`Combine::Smoothed`] adds passes of normal umbrella smoothing
//!    (a discrete mean-curvature flow) on the combined grid, border rows held
//!    — the "modified" variant that smooths curvature in 2D.
//!
//!    **Measured** (`cargo run --release -p fairway --example surface_combine`:
//!    20×20 bicubic graphs, noise σ = 1e-3 on z, m = 3e-3; RMS principal
//!    curvature error against the noise-free surface, original → result;
//!    with the fairness-energy choice of step 6):
//!
//!    | surface, region | original | Average | Border | Weighted | Smoothed |
//!    |---|---|---|---|---|---|
//!    | cylinder, whole | 0.437 | 0.065 | 0.065 | **0.064** | **0.064** |
//!    | bump, whole | 0.369 | **0.119** | **0.119** | 0.141 | 0.148 |
//!    | saddle, whole | 0.456 | **0.0035** | **0.0035** | 0.0036 | 0.0036 |
//!    | wave, whole | 0.439 | 0.045 | 0.045 | 0.045 | 0.045 |
//!    | cylinder, local | 0.479 | **0.311** | 0.315 | 0.335 | 0.335 |
//!    | bump, local | 0.280 | 0.290 | 0.303 | **0.238** | 0.239 |
//!    | saddle, local | 0.465 | **0.311** | 0.313 | 0.349 | 0.339 |
//!    | wave, local | 0.451 | **0.306** | 0.309 | 0.337 | 0.324 |
//!
//!    No variant wins everywhere. In local regions `Weighted` is 8–12 %
//!    behind the average on the cylinder, saddle and wave, but it is the only
//!    one that improves the bump (the average makes it worse than the
//!    original there), and where one direction carries the correction (an
//!    extrusion) it reproduces the curve engine exactly — test
//!    `extruded_curve_matches_the_curve_engine` — while the average does
//!    half the correction; so it is the default. (Before step 6 chose by
//!    fairness, the same table had e.g. bump whole 0.289 / 0.258, wave local
//!    0.419 / 0.336 for Average / Weighted.) `Smoothed` (umbrella smoothing
//!    also shrinks curved regions) is offered, not default.
//! 5. **Fit** the control block to `S + Δ` on the grid with the original
//!    knots and parameters ([`GridFit`], separable, O(n)).
//! 6. **Choice of the isocurve tolerance and the fit smoothing** (with
//!    `auto_smoothing`, the default). For the isocurve tolerances
//!    `m_iso = m, m/3, m/9, …` ([`ISO_LEVEL_FACTOR`], at most
//!    `iso_levels`, greedy: stop at the first level that is no fairer), each
//!    smoothing strength of [`AUTO_STRENGTHS`] is fitted (after the first
//!    level only those next to the pick, see below); among the
//!    candidates that hold the band (step 7) the one with the least
//!    *fairness energy* is taken: the Dirichlet energy of the mean curvature
//!    H on a grid of [`ENERGY_PER_SPAN`] samples per knot span of the moving
//!    rectangle, `Σ_edges (H_a − H_b)² w_⊥/|P_a − P_b|` (a discrete
//!    `∫∫|∇H|² dA`). **Why** (measured, `cargo run --release -p fairway
//!    --example surface_region_quality`, assets/bumpy_surface.json, region
//!    [0.1, 0.9]²): the former rule — m_iso = m and the *largest* strength
//!    that holds the band — made interior regions *less* fair at larger m
//!    (Σ∫(dκ/ds)² over the region ×1.08 at m = 4e-3, ×3.8 at m = 2e-2;
//!    ∫∫|∇H|² ×0.92 / ×2.3). Two causes: (i) each isocurve is faired on its
//!    own with its own band-limited μ; with a band of m the corrections are of
//!    size m but differ from one isocurve to the next, so the combined cloud
//!    is wavy *across* the isocurves (with no fit smoothing the region's
//!    Σ∫(dκ/ds)² grows ×0.93 → ×5.7 from m = 2e-3 to 2e-2, the whole
//!    surface's ×1 → ×60); (ii) a strong separable derivative penalty next
//!    to held border rows pulls the free block towards a stiff interpolant of
//!    the border (strength 1e2 held the band at m = 2e-2 and gave ×3.8), while
//!    with no held border (whole surface) the same strength is what makes the
//!    result fair. Measuring the candidates instead of trusting "more
//!    smoothing is fairer" fixes both: the region's Σ∫(dκ/ds)² is now ×0.72–0.75
//!    and ∫∫|∇H|² ×0.73–0.74 for m = 2e-3…2e-2, the whole surface ×0.94 / ×0.93
//!    (it is not fairer outside; the held G2 strip next to the border keeps its
//!    noise). The whole-surface fairing also gains at small m (bumpy surface,
//!    m = 2e-3: Σ∫(dκ/ds)² ×0.99 → ×0.041).
//!
//!    **How the levels are made.** By default the isocurves are faired once,
//!    at m, and level k's cloud is the original plus the combined correction
//!    scaled by 3⁻ᵏ; with `refair_levels` every isocurve is faired again at
//!    m/3, m/9, … (its setup is reused, so a level costs the band search and
//!    integration only). Scaling is what a smaller band mostly does to the
//!    correction's size; what it does not reproduce is the isocurve's own
//!    re-balancing at the smaller band. Measured (`cargo run --release -p
//!    fairway --example surface_combine`, curvature error against the exact
//!    surface, default `Weighted`, refair → scaled): cylinder whole 0.0643 →
//!    0.0643, local 0.3220 → 0.3119; bump 0.1410 → 0.1410, local 0.2379 →
//!    0.2406; saddle 0.0036 → 0.0040, local 0.3493 → 0.3493; wave 0.0453 →
//!    0.0455, local 0.3365 → 0.3365. Interior regions of the bumpy sample
//!    (`surface_region_quality`): region Σ∫(dκ/ds)² ×0.721–0.753 refaired,
//!    ×0.722–0.738 scaled. Cost of the isocurves: one pass instead of up to
//!    `iso_levels` (100 × 100: 118 ms instead of 220 ms wall on 2 threads), so
//!    scaling is the default. After the first level, only the picked strength
//!    and its two neighbours on [`AUTO_STRENGTHS`] are fitted (3 fits and
//!    energies instead of 8 per level; `surface_combine` and
//!    `surface_region_quality` give the same or lower curvature errors).
//! 7. **Hard tolerance.** The result is checked on a grid of
//!    `CHECK_PER_SPAN` samples per knot span of the moving rectangle (outside
//!    it nothing moved): `|S_f(u,v) − S(u,v)|` bounds both one-sided
//!    closest-point distances from above; where it exceeds m, a Newton
//!    projection in both directions gives a sharper (still upper) bound. If
//!    the bound exceeds m, the isocurve tolerance is tightened
//!    (`m_iso ← 0.8 · m_iso · m / dev`) and all is redone (up to
//!    [`MAX_ROUNDS`]); if still above, the change of the control points is
//!    scaled, `ΔD ← α ΔD`, α bisected in [0, 1] (α = 0 is the original, so a
//!    positive tolerance is always met; the result reports α).
//! 8. **The fairest candidate** (default [`SurfaceMethod::Fairway`]; [`SurfaceMethod::Isocurves`] stops
//!    after step 7). The **reference smoother** ([`SurfaceMethod::Smoothing`], `fairway fair --method
//!    smoothing`) is the surface counterpart of the curve engine's `FitMode::Smoothing`: on the same
//!    free block and grid as step 5, with the original's samples as data, [`PlateFit`] minimises
//!    `‖S − S₀‖² + λ ∫∫ S_xxx² + 3 S_xxy² + 3 S_xyy² + S_yyy²` (order [`REFERENCE_ORDER`] = 3, the
//!    rotation-invariant curvature-variation energy, x, y the parameters scaled by the mean speeds), the
//!    largest λ on a log bisection whose result holds the band. Candidates: the original, step 7's
//!    result, the smoother's answer on the original's samples and on step 7's result (data = the isocurve
//!    result's samples, band still against the original; ranking the weaker strengths the searches visited
//!    as well changed no row of the table), and blends
//!    `a + (b − a)(1 − w)` of pairs of the isocurve result, the smoother's answer and the fairest
//!    smoother-on-isocurves net ([`BLENDS`]). A smoother or blend candidate holds the band when the
//!    step-7 checks pass and, on a grid of [`FINE_CHECK_PER_SPAN`] samples per span, the parametric
//!    change `|S_f − S|` stays ≤ m, its grid peaks followed to their local maxima by Newton ascent
//!    (projected distances are never larger; without the peaks the smoother's nets exceeded m by up to
//!    0.1 % between nodes, measured by dense projection). Each candidate is ranked by
//!    (isocurve curvature extrema with the 1 % dead band, `∫∫|∇H|²`), the measures of
//!    [`crate::measure_surface`] over the moving rectangle ([`RANK_ISO`] isocurves; for a whole-surface
//!    fair exactly `measure`'s numbers). Returned: the lexicographically fairest candidate that is no
//!    less fair on either measure than the reference and than step 7's result and has no more extrema
//!    than the original; if none, the fairest no less fair than the reference with no more extrema than
//!    the original; if none, the fairest of all. The result's `pick` says which.
//!
//!    **Why** (measured, `cargo run --release -p fairway --example surface_quality_table`, 5 noisy
//!    surfaces × 3 tolerances, docs/QUALITY.md): step 7 alone was less fair than the reference in 13 of
//!    15 rows (Σ extrema 1329 against the reference's 1040; on a nearly quadratic car roof at 1σ 232
//!    against 35 extrema), the reference alone less fair than step 7 in others (the bumpy asset at 3σ:
//!    41 against 37). Step 8 is at least as fair as both on both measures in 13 of 15 rows (Σ extrema
//!    938); the two others are the apex dome, where the reference has more extrema than the original and
//!    the original's count comes first. The thin-plate energy (order 2) was the weaker peer: Σ extrema
//!    1987, and on the car roof at 1σ it leaves ∫∫|∇H|² at 0.60 where order 3 reaches 1.5·10⁻³ (on a
//!    10 × 10 net it raised it above the original's: a thin plate penalizes the crown's curvature itself
//!    and flattens it unevenly within the band). **Cost**: the two searches and the ranking (≈ 5 ms per
//!    candidate on a 20 × 16 net, 13 candidates on 2 threads) make the default 8–15 × step 7's time (≈ 90 ms instead of 5–12 on the bumpy
//!    asset; 0.8 s instead of 20–70 ms on 40 × 40 nets).
//!
//! Rational surfaces with equal weights are converted; others are rejected.
//! Degree 2 gives C1 (G1) joins only; any degree ≥ 1 and any clamped knot
//! vectors work otherwise.

use std::ops::Range;
use std::time::{Duration, Instant};

use glam::DVec3;

use super::curve::{FairingOptions, FairingSetup};
use super::target::TargetMethod;
use crate::basis::{MAX_ORDER, basis_funs};
use crate::error::{Error, Result};
use crate::fit_surface::{GridFit, PlateFit, SurfaceSmoothing, free_range};
use crate::knots::KnotVector;
use crate::measure_surface::{iso_stats_in, mean_curvature_variation_rule, newton_project};
use crate::quadrature::GaussLegendre;
use crate::surface::BSplineSurface;

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

/// What [`fair_surface`] does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum SurfaceMethod {
    /// The isocurve fairing (steps 1-7), then the fairest of it, the reference smoother and the smoother
    /// run on its result (step 8).
    #[default]
    Fairway,
    /// The reference smoother alone: tensor-product penalized least squares on the original's grid
    /// samples with the curvature-variation energy ([`PlateFit`], order [`REFERENCE_ORDER`]), the largest strength
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

/// Which candidate [`fair_surface`] returned (module docs, step 8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum SurfacePick {
    /// The isocurve fairing's result (steps 1-7).
    Isocurves,
    /// The reference smoother's result on the original's samples.
    Reference,
    /// The reference smoother run on the isocurve fairing's result (band still against the original).
    Combined,
    /// A blend of the isocurve result's net with the fairer smoother net ([`BLENDS`]).
    Blend,
    /// The original: no candidate was fairer.
    Original,
}

/// Options of a surface fairing.
#[derive(Debug, Clone, Copy, PartialEq)]
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
    /// Choose the smoothing strength (of [`AUTO_STRENGTHS`]) and the isocurve tolerance (see
    /// `iso_levels`) by the fairness energy among the results that hold the tolerance (module docs,
    /// step 6). Without it: `smoothing` as given, the isocurve tolerance m (tightened only when the
    /// band is broken).
    pub auto_smoothing: bool,
    /// Threads fairing the isocurves (`None`: rayon's global pool, `RAYON_NUM_THREADS` if set; `Some(1)`: this
    /// thread only). The result does not depend on it.
    pub threads: Option<usize>,
    /// With `auto_smoothing`: at most this many isocurve tolerances `m, m/3, m/9, …` ([`ISO_LEVEL_FACTOR`]) are tried
    /// (greedy: stop at the first level that does not lower the fairness energy), ≥ 1 (module docs, step 6).
    pub iso_levels: usize,
    /// How the levels below m are made: `false` (default) scales the combined correction of the one
    /// isocurve pass at m by 1/3, 1/9, … (no further isocurve work); `true` fairs every isocurve again at
    /// each level's tolerance m/3, m/9, … (one setup per isocurve, re-faired per level: about 2× the
    /// isocurve time). Measured in the module docs (step 6): the same fairness within a few per cent.
    pub refair_levels: bool,
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
            method: SurfaceMethod::Fairway,
        }
    }
}

/// The outcome of [`fair_surface`].
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceFairingResult {
    /// The faired surface (original knots and degrees, non-rational).
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
    /// [`super::verify::surface_band_bound`], the control net of the parametric difference refined
    /// where it comes near m. `Some(b)` with b ≤ tolerance certifies the band: where the first bound came
    /// out above m (the grid held the band, but the fair slid the surface along itself between its
    /// points), the change is scaled back until it certifies m (`alpha` says by how much). `None` for a
    /// rational input, where only the check grid holds.
    pub band_bound: Option<f64>,
}

/// Wall-clock time of the phases of one [`fair_surface`] call (summed over
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

/// Smoothing strengths tried, largest first, with `auto_smoothing` (see [`SurfaceSmoothing`]).
pub const AUTO_STRENGTHS: [f64; 8] = [1e5, 1e4, 1e3, 1e2, 1e1, 1.0, 1e-1, 0.0];

/// Ratio of successive isocurve tolerances tried with `auto_smoothing` (module docs, step 6).
pub const ISO_LEVEL_FACTOR: f64 = 1.0 / 3.0;

/// Rounds of isocurve-tolerance tightening before the α fallback.
pub const MAX_ROUNDS: usize = 4;
/// Check samples per knot span and direction of the hard tolerance.
pub const CHECK_PER_SPAN: usize = 6;
/// Curve-engine samples per knot span of an isocurve (unless `curve.samples` is set).
pub const ISO_SAMPLES_PER_SPAN: usize = 4;
/// Width of the isocurves' default target smoothing, in knot spans (unless `curve.strength` is set).
pub const ISO_TARGET_SIGMA_SPANS: f64 = 1.6;

fn span_grid(knots: &KnotVector, a: f64, b: f64, per_span: usize) -> Vec<f64> {
    let bp: Vec<f64> = knots.breakpoints().into_iter().filter(|&t| t >= a && t <= b).collect();
    let mut out = Vec::with_capacity(bp.len() * per_span + 1);
    for w in bp.windows(2) {
        for k in 0..per_span {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / per_span as f64);
        }
    }
    out.push(b);
    out
}

/// Fair `surface` (see the module docs).
pub fn fair_surface(surface: &BSplineSurface, opts: SurfaceFairingOptions) -> Result<SurfaceFairingResult> {
    let m = opts.tolerance;
    let mut r = fair_surface_unbounded(surface, opts)?;
    r.band_bound = super::verify::surface_band_bound(surface, &r.surface, m);
    if let Some(b) = r.band_bound
        && b > m
    {
        // The grid held the band but nothing sound says so between its points: step back towards the
        // original until the bound certifies m. The difference is linear in the step, so is its bound.
        let t = m / b * (1.0 - 1e-9);
        let pts: Vec<_> = surface
            .points()
            .iter()
            .zip(r.surface.points())
            .map(|(&a, &f)| a + t * (f - a))
            .collect();
        r.surface = r.surface.with_points(pts)?;
        r.alpha *= t;
        r.band_bound = super::verify::surface_band_bound(surface, &r.surface, m);
        // the grid's figure was the old surface's; the bound is this one's (and sound)
        r.max_deviation = r.band_bound.unwrap_or(m);
    }
    Ok(r)
}

fn fair_surface_unbounded(surface: &BSplineSurface, opts: SurfaceFairingOptions) -> Result<SurfaceFairingResult> {
    let m = opts.tolerance;
    let size = surface
        .points()
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f64::max);
    crate::range::check_tolerance_at(m, size)?;
    if opts.samples_per_span < 2 {
        return Err(Error::InvalidInput("samples_per_span must be at least 2".into()));
    }
    let s = if surface.is_rational() {
        surface.to_polynomial()?
    } else {
        surface.clone()
    };
    if !(net_size(&s) > 0.0) {
        return Err(Error::Degenerate(
            "all control points of the surface coincide (a single point): there is no shape to fair".into(),
        ));
    }
    let ((du0, du1), (dv0, dv1)) = s.domain();
    let ((u1, u2), (v1, v2)) = opts.region.unwrap_or(((du0, du1), (dv0, dv1)));
    for (name, a, b, lo, hi) in [("u", u1, u2, du0, du1), ("v", v1, v2, dv0, dv1)] {
        if !(a.is_finite() && b.is_finite() && a < b) {
            return Err(Error::InvalidInput(format!(
                "region in {name}: [{a}, {b}] is empty or not finite"
            )));
        }
        if a < lo || b > hi {
            return Err(Error::OutOfDomain {
                what: format!("region in {name}"),
                value: if a < lo { a } else { b },
                start: lo,
                end: hi,
            });
        }
    }
    let (ku, kv) = (s.knots_u().clone(), s.knots_v().clone());
    let free_u = free_range(&ku, u1, u2);
    let free_v = free_range(&kv, v1, v2);
    let had = !free_u.is_empty() && !free_v.is_empty();
    let (free_u, free_v) = hold_poles_and_seams(&s, free_u, free_v);
    if had && (free_u.is_empty() || free_v.is_empty()) {
        return Err(Error::InvalidInput(format!(
            "region [{u1}, {u2}] × [{v1}, {v2}] holds no movable control point: its control rows are all among \
             the {POLE_ROWS} held next to a pole or the seam of a closed surface (widen the region away from it)"
        )));
    }
    if free_u.is_empty() || free_v.is_empty() {
        return Err(Error::InvalidInput(format!(
            "region [{u1}, {u2}] × [{v1}, {v2}] holds no movable control point: it must contain at least \
             degree + 1 knot spans in each direction ({} in u, {} in v)",
            ku.degree() + 1,
            kv.degree() + 1
        )));
    }
    let (pu, pv) = (ku.degree(), kv.degree());
    // moving rectangle: union of free supports
    let (au, bu) = (ku.values()[free_u.start], ku.values()[free_u.end - 1 + pu + 1]);
    let (av, bv) = (kv.values()[free_v.start], kv.values()[free_v.end - 1 + pv + 1]);
    let us = span_grid(&ku, au, bu, opts.samples_per_span);
    let vs = span_grid(&kv, av, bv, opts.samples_per_span);
    let t_orig = Instant::now();
    let orig = grid_points(&s, &us, &vs);
    let threads = opts.threads;
    let full_check = CheckGrid::new(
        &s,
        &span_grid(&ku, au, bu, CHECK_PER_SPAN),
        &span_grid(&kv, av, bv, CHECK_PER_SPAN),
        threads,
    );
    let coarse_check = CheckGrid::new(&s, &span_grid(&ku, au, bu, 3), &span_grid(&kv, av, bv, 3), threads);

    let mut tm = SurfaceTimings {
        isocurves: t_orig.elapsed(),
        ..Default::default()
    };
    let rect = ((au, bu), (av, bv));
    let fine_check = || {
        CheckGrid::new(
            &s,
            &span_grid(&ku, au, bu, FINE_CHECK_PER_SPAN),
            &span_grid(&kv, av, bv, FINE_CHECK_PER_SPAN),
            threads,
        )
    };
    if opts.method == SurfaceMethod::Smoothing {
        let fine = fine_check();
        let t0 = Instant::now();
        let grid_fit = GridFit::new(&s, &us, &vs, free_u.clone(), free_v.clone())?;
        let plate = plate_fit(&s, &grid_fit, &us, &vs, REFERENCE_ORDER)?;
        let rhs = grid_fit.project(&orig)?;
        let bands = Bands {
            coarse: &coarse_check,
            full: &full_check,
            fine: &fine,
            free_u: &free_u,
            free_v: &free_v,
            m,
        };
        let (pts, dev, strength) = plate_search(&s, &plate, &rhs, &bands)?
            .pop()
            .unwrap_or_else(|| (s.points().to_vec(), 0.0, 0.0));
        tm.reference += t0.elapsed();
        return Ok(SurfaceFairingResult {
            surface: s.with_points(pts)?,
            max_deviation: dev,
            iso_tolerance: 0.0,
            rounds: 0,
            alpha: 1.0,
            smoothing: SurfaceSmoothing {
                strength_u: strength,
                strength_v: strength,
                order: REFERENCE_ORDER,
            },
            free_u,
            free_v,
            timings: tm,
            pick: SurfacePick::Reference,
            band_bound: None,
        });
    }
    // today's isocurve fairing (module docs, steps 3-7)
    let iso_result = (|| -> Result<SurfaceFairingResult> {
        let mut m_iso = m;
        let mut best: Option<(Vec<DVec3>, f64)> = None;
        let mut rounds = 0;
        let ladder: &[f64] = if opts.auto_smoothing {
            &AUTO_STRENGTHS
        } else {
            &[f64::NAN]
        };
        // fairness energy over the moving rectangle (auto-smoothing selection, module docs step 6)
        let energy = opts.auto_smoothing.then(|| FairnessGrid::new(&s, (au, bu), (av, bv)));
        let grid_fit = GridFit::new(&s, &us, &vs, free_u.clone(), free_v.clone())?;
        // the fairest candidate holding the band so far: (points, dev, m_iso, smoothing, round, energy)
        type Pick = (Vec<DVec3>, f64, f64, SurfaceSmoothing, usize, f64);
        let mut pick: Option<Pick> = None;
        let max_rounds = if opts.auto_smoothing {
            MAX_ROUNDS.max(opts.iso_levels.max(1))
        } else {
            MAX_ROUNDS
        };
        // With auto smoothing the clouds of all `iso_levels` levels m, m/3, m/9, … are made in the first round:
        // the correction of the pass at m scaled by 1/3, 1/9, … or, with `refair_levels`, the isocurves faired at
        // each tolerance (one setup per isocurve, re-faired per level). The rounds that step down a level take
        // their cloud from here; a tightening round (no level held the band) fairs the isocurves at its own m_iso.
        let mut level_clouds: Vec<(f64, Vec<DVec3>)> = Vec::new();
        if opts.auto_smoothing && opts.iso_levels > 1 {
            let mut levels = vec![m_iso];
            for _ in 1..opts.iso_levels {
                levels.push(levels[levels.len() - 1] * ISO_LEVEL_FACTOR);
            }
            let clouds = if opts.refair_levels {
                combined_cloud(&s, &opts, &levels, (u1, u2), (v1, v2), &us, &vs, &orig, &mut tm)?
            } else {
                let first = combined_cloud(&s, &opts, &levels[..1], (u1, u2), (v1, v2), &us, &vs, &orig, &mut tm)?;
                let first = first.into_iter().next().expect("one level");
                let t0 = Instant::now();
                let scaled = levels
                    .iter()
                    .map(|l| {
                        let a = l / levels[0];
                        first.iter().zip(&orig).map(|(c, o)| *o + (*c - *o) * a).collect()
                    })
                    .collect();
                tm.combine += t0.elapsed();
                scaled
            };
            level_clouds = levels.into_iter().zip(clouds).collect();
        }
        for _ in 0..max_rounds {
            rounds += 1;
            let data = match level_clouds.iter().position(|(l, _)| *l == m_iso) {
                Some(i) => level_clouds.swap_remove(i).1,
                None => combined_cloud(&s, &opts, &[m_iso], (u1, u2), (v1, v2), &us, &vs, &orig, &mut tm)?
                    .pop()
                    .expect("one level"),
            };
            let mut level_best: Option<Pick> = None;
            // the fits and their fairness energies are independent: computed in parallel, then checked in order
            let t0 = Instant::now();
            // After the first level only the pick's strength and its two neighbours on the ladder are fitted
            // (module docs, step 6): the fairest strength moves little from one level to the next.
            let near: Vec<f64> = match &pick {
                Some(pk) => {
                    let i = ladder.iter().position(|&x| x == pk.3.strength_u).unwrap_or(0);
                    ladder[i.saturating_sub(1)..(i + 2).min(ladder.len())].to_vec()
                }
                _ => ladder.to_vec(),
            };
            // the data term is the same for every strength: projected once per level
            let rhs = grid_fit.project(&data)?;
            let cands = par_map(&near, threads, |&st| {
                let sm = if st.is_nan() {
                    opts.smoothing
                } else {
                    SurfaceSmoothing {
                        strength_u: st,
                        strength_v: st,
                        order: opts.smoothing.order,
                    }
                };
                let pts = grid_fit.solve(&rhs, sm)?;
                let faired = s.with_points(pts.clone())?;
                let e = energy.as_ref().map(|eg| eg.energy(&faired));
                Ok::<_, Error>((sm, pts, faired, e))
            });
            tm.fit += t0.elapsed();
            for cand in cands {
                let (sm, pts, faired, e) = cand?;
                let t1 = Instant::now();
                // with auto smoothing: a candidate no fairer than the level's best is not checked
                if let (Some(e), Some(lb)) = (e, level_best.as_ref())
                    && e >= lb.5
                {
                    tm.verify += t1.elapsed();
                    continue;
                }
                // coarse check first (cheap), the full check only for a candidate that passes it
                if coarse_check.deviation(&s, &faired, &free_u, &free_v, m, true) > m {
                    tm.verify += t1.elapsed();
                    continue;
                }
                let dev = full_check.deviation(&s, &faired, &free_u, &free_v, m, false);
                if dev <= m {
                    match e {
                        None => {
                            tm.verify += t1.elapsed();
                            return Ok(SurfaceFairingResult {
                                surface: faired,
                                max_deviation: dev,
                                iso_tolerance: m_iso,
                                rounds,
                                alpha: 1.0,
                                smoothing: sm,
                                free_u: free_u.clone(),
                                free_v: free_v.clone(),
                                timings: tm,
                                pick: SurfacePick::Isocurves,
                                band_bound: None,
                            });
                        }
                        Some(e) => level_best = Some((pts.clone(), dev, m_iso, sm, rounds, e)),
                    }
                }
                tm.verify += t1.elapsed();
                if best.as_ref().is_none_or(|b| dev < b.1) {
                    best = Some((pts, dev));
                }
            }
            if let Some(lb) = level_best {
                let improved = pick.as_ref().is_none_or(|p| lb.5 < p.5);
                if improved {
                    pick = Some(lb);
                }
                if !improved || rounds >= opts.iso_levels.max(1) {
                    break;
                }
                m_iso *= ISO_LEVEL_FACTOR;
                continue;
            }
            if pick.is_some() {
                m_iso *= ISO_LEVEL_FACTOR;
                continue;
            }
            if best.is_none() {
                let t0 = Instant::now();
                let pts = grid_fit.solve(&rhs, opts.smoothing)?;
                let t1 = Instant::now();
                tm.fit += t1 - t0;
                let dev = full_check.deviation(&s, &s.with_points(pts.clone())?, &free_u, &free_v, m, false);
                tm.verify += t1.elapsed();
                best = Some((pts, dev));
            }
            let dev = best.as_ref().unwrap().1;
            m_iso *= 0.8 * m / dev;
        }
        if let Some((pts, dev, m_iso, sm, round, _)) = pick {
            return Ok(SurfaceFairingResult {
                surface: s.with_points(pts)?,
                max_deviation: dev,
                iso_tolerance: m_iso,
                rounds: round,
                alpha: 1.0,
                smoothing: sm,
                free_u: free_u.clone(),
                free_v: free_v.clone(),
                timings: tm,
                pick: SurfacePick::Isocurves,
                band_bound: None,
            });
        }
        // α fallback: bisect the largest α ∈ [0, 1] whose blend holds the band
        let (pts, _) = best.expect("at least one round");
        let blend = |alpha: f64| -> Vec<DVec3> {
            s.points()
                .iter()
                .zip(&pts)
                .map(|(a, b)| *a + (*b - *a) * alpha)
                .collect()
        };
        let t0 = Instant::now();
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        let mut lo_dev = 0.0;
        for _ in 0..20 {
            let mid = 0.5 * (lo + hi);
            let f = s.with_points(blend(mid))?;
            let d = full_check.deviation(&s, &f, &free_u, &free_v, m, true);
            if d <= m {
                lo = mid;
                lo_dev = d;
            } else {
                hi = mid;
            }
            if hi - lo < 1e-4 {
                break;
            }
        }
        tm.verify += t0.elapsed();
        Ok(SurfaceFairingResult {
            surface: s.with_points(blend(lo))?,
            max_deviation: lo_dev,
            iso_tolerance: m_iso,
            rounds,
            alpha: lo,
            smoothing: opts.smoothing,
            free_u: free_u.clone(),
            free_v: free_v.clone(),
            timings: tm,
            pick: SurfacePick::Isocurves,
            band_bound: None,
        })
    })()?;
    if opts.method == SurfaceMethod::Isocurves {
        return Ok(iso_result);
    }
    let mut result = iso_result;
    // step 8 (module docs)
    let t0 = Instant::now();
    let grid_fit = GridFit::new(&s, &us, &vs, free_u.clone(), free_v.clone())?;
    let plate = plate_fit(&s, &grid_fit, &us, &vs, REFERENCE_ORDER)?;
    let fine = fine_check();
    let bands = Bands {
        coarse: &coarse_check,
        full: &full_check,
        fine: &fine,
        free_u: &free_u,
        free_v: &free_v,
        m,
    };
    let ranker = Ranker::new(&s, rect);
    // (rank, pick, surface, deviation bound, strength)
    type Cand = (Rank, SurfacePick, BSplineSurface, f64, f64);
    let mut cands: Vec<Cand> = vec![
        (ranker.rank(&s), SurfacePick::Original, s.clone(), 0.0, 0.0),
        (
            ranker.rank(&result.surface),
            SurfacePick::Isocurves,
            result.surface.clone(),
            result.max_deviation,
            result.smoothing.strength_u,
        ),
    ];
    let today = cands[1].0;
    // the smoother on the original's samples (the reference; its answer is the largest band-holding
    // strength) and on the isocurve result's: independent searches
    let iso_grid = grid_points(&result.surface, &us, &vs);
    let rhs = [grid_fit.project(&orig)?, grid_fit.project(&iso_grid)?];
    let searches = par_map(&rhs, threads, |r| plate_search(&s, &plate, r, &bands));
    let [reference, combined]: [_; 2] = (searches.into_iter().collect::<Result<Vec<_>>>()?)
        .try_into()
        .map_err(|_| Error::Solve("surface smoothing: one search per data set".into()))?;
    // the searches' strongest band-holding strengths, ranked in parallel (the ranking is most of step 8's cost)
    let mut found = Vec::new();
    for (pick, all) in [(SurfacePick::Reference, reference), (SurfacePick::Combined, combined)] {
        let keep = all.len().saturating_sub(SEARCH_CANDIDATES);
        for (pts, dev, st) in all.into_iter().skip(keep) {
            found.push((pick, s.with_points(pts)?, dev, st));
        }
    }
    let ranks = par_map(&found, threads, |c| ranker.rank(&c.1));
    cands.extend(
        found
            .into_iter()
            .zip(ranks)
            .map(|((pick, f, dev, st), r)| (r, pick, f, dev, st)),
    );
    // the reference's rank: that of its answer (the original's when no strength held the band)
    let ref_rank = (cands.iter().rev())
        .find(|c| c.1 == SurfacePick::Reference)
        .map_or(cands[0].0, |c| c.0);
    // blends of pairs of anchors — the isocurve result, the reference's answer and the fairest net of the
    // smoother run on the isocurve result: |S_blend − S| is at most the larger of the two nets' changes at
    // every point; each blend is checked on the fine grid again
    let mut anchors: Vec<usize> = vec![1];
    if let Some(i) = cands.iter().rposition(|c| c.1 == SurfacePick::Reference) {
        anchors.push(i);
    }
    let best_combined = (cands.iter().enumerate())
        .filter(|(_, c)| c.1 == SurfacePick::Combined)
        .min_by(|a, b| a.1.0.partial_cmp(&b.1.0).unwrap_or(std::cmp::Ordering::Equal))
        .map(|(i, _)| i);
    anchors.extend(best_combined);
    let mut blends = Vec::new();
    for (k, &i) in anchors.iter().enumerate() {
        for &j in &anchors[k + 1..] {
            for w in BLENDS {
                let pts: Vec<DVec3> = (cands[i].2.points().iter().zip(cands[j].2.points()))
                    // a + (b − a)(1 − w): a held point (a = b) stays bit for bit
                    .map(|(a, b)| *a + (*b - *a) * (1.0 - w))
                    .collect();
                let f = s.with_points(pts)?;
                if let Some(dev) = bands.holds(&s, &f) {
                    blends.push((f, dev));
                }
            }
        }
    }
    let ranks = par_map(&blends, threads, |b| ranker.rank(&b.0));
    cands.extend(
        blends
            .into_iter()
            .zip(ranks)
            .map(|((f, dev), r)| (r, SurfacePick::Blend, f, dev, 0.0)),
    );
    // the lexicographically fairest of the candidates that are no less fair than the reference and the
    // isocurve result on either measure and have no more extrema than the original; if none, of those no
    // less fair than the reference with no more extrema than the original; if none, of all
    let dominates = |r: &Rank, o: &Rank| r.0 <= o.0 && r.1 <= o.1;
    let best_of = |keep: &dyn Fn(&Rank) -> bool| {
        cands
            .iter()
            .enumerate()
            .filter(|(_, c)| keep(&c.0))
            .min_by(|a, b| a.1.0.partial_cmp(&b.1.0).unwrap_or(std::cmp::Ordering::Equal))
            .map(|(i, _)| i)
    };
    let orig_ext = cands[0].0.0;
    let pick = best_of(&|r| dominates(r, &ref_rank) && dominates(r, &today) && r.0 <= orig_ext)
        .or_else(|| best_of(&|r| dominates(r, &ref_rank) && r.0 <= orig_ext))
        .or_else(|| best_of(&|_| true))
        .unwrap_or(1);
    let (_, kind, f, dev, st) = cands.swap_remove(pick);
    if kind != SurfacePick::Isocurves {
        result.surface = f;
        result.max_deviation = dev;
        result.alpha = if kind == SurfacePick::Original { 0.0 } else { 1.0 };
        result.smoothing = SurfaceSmoothing {
            strength_u: st,
            strength_v: st,
            order: REFERENCE_ORDER,
        };
        result.pick = kind;
    }
    result.timings.reference += t0.elapsed();
    Ok(result)
}

/// Check samples per knot span and direction of the step-8 candidates (module docs, step 8).
pub const FINE_CHECK_PER_SPAN: usize = 4 * CHECK_PER_SPAN;
/// Band-holding strengths of each smoother search that step 8 ranks, the strongest first (1: the search's answer).
pub const SEARCH_CANDIDATES: usize = 1;
/// Blend weights of the isocurve result tried against the smoother's (step 8).
pub const BLENDS: [f64; 3] = [0.25, 0.5, 0.75];
/// Gauss–Legendre nodes per cell and direction of the step-8 ranking's `∫∫|∇H|²`.
pub const RANK_GAUSS: usize = 10;

/// Order of the reference smoother's energy: 3, the curvature-variation energy (module docs, step 8; the
/// thin plate, order 2, was measured as the weaker peer).
pub const REFERENCE_ORDER: usize = 3;
/// Smallest and largest strength (log10) of the reference smoother's search.
pub const REFERENCE_LOG_STRENGTH: (f64, f64) = (-6.0, 8.0);
/// Bisection steps on log10 of the strength (resolution 14 / 2¹² decades, under 1 % in λ).
pub const REFERENCE_STEPS: usize = 12;
/// Isocurves per direction of the step-8 ranking (as `measure`'s [`crate::measure_surface::N_ISO`]).
pub const RANK_ISO: usize = 20;

/// The reference smoother's energy for `s` on its grid: [`PlateFit`] of [`REFERENCE_ORDER`] with the mean
/// speeds `|S_u|`, `|S_v|` of the original over the grid as length scales.
fn plate_fit<'g, 'a>(
    s: &BSplineSurface,
    grid: &'g GridFit<'a>,
    us: &[f64],
    vs: &[f64],
    order: usize,
) -> Result<PlateFit<'g, 'a>> {
    let (mut lu, mut lv, mut n) = (0.0, 0.0, 0usize);
    let step_u = (us.len() / 16).max(1);
    let step_v = (vs.len() / 16).max(1);
    for &u in us.iter().step_by(step_u) {
        for &v in vs.iter().step_by(step_v) {
            let d = s.derivs(u, v);
            lu += d.su.length();
            lv += d.sv.length();
            n += 1;
        }
    }
    PlateFit::new(grid, order, lu / n as f64, lv / n as f64)
}

/// The band as [`fair_surface`] verifies it: the coarse check, then the full one.
struct Bands<'a> {
    coarse: &'a CheckGrid,
    full: &'a CheckGrid,
    /// [`FINE_CHECK_PER_SPAN`] samples per span: the smoother's nets bulge between the full grid's nodes
    /// (by up to 1 % of m, measured by dense projection), so its candidates are accepted on this grid, by
    /// their parametric change.
    fine: &'a CheckGrid,
    free_u: &'a Range<usize>,
    free_v: &'a Range<usize>,
    m: f64,
}

impl Bands<'_> {
    /// The verified deviation bound of `f` from `s` if it is within the band.
    fn holds(&self, s: &BSplineSurface, f: &BSplineSurface) -> Option<f64> {
        if self.coarse.deviation(s, f, self.free_u, self.free_v, self.m, true) > self.m {
            return None;
        }
        if self.full.deviation(s, f, self.free_u, self.free_v, self.m, true) > self.m {
            return None;
        }
        // on the fine grid the parametric change |S_f − S| itself (no projection sharpening): it bounds both
        // one-sided distances at every sample, and it varies little between samples this dense, where a
        // projected distance can exceed m between nodes at which it did not
        let (mut dev, mut peaks) = (self.fine).change_peaks(s, f, self.free_u, self.free_v, PEAK_FRACTION * self.m);
        if dev > self.m {
            return None;
        }
        // between the nodes: the change's local maxima, from the grid's peaks near m
        peaks.sort_by(|x, y| y.0.total_cmp(&x.0));
        for &(_, u, v) in peaks.iter().take(MAX_PEAKS) {
            dev = dev.max(local_max_change(s, f, (u, v)));
            if dev > self.m {
                return None;
            }
        }
        Some(dev)
    }
}

/// Grid peaks of the change above this fraction of m are followed to their local maximum (the band check of step 8).
pub const PEAK_FRACTION: f64 = 0.99;
/// At most this many grid peaks (the largest) are followed.
pub const MAX_PEAKS: usize = 16;

/// The local maximum of the parametric change `|S_b − S_a|` near `uv`: Newton ascent on `|Δ|²/2` (gradient
/// `Δ·Δ_u, Δ·Δ_v`, Hessian `Δ_u·Δ_u + Δ·Δ_uu, …`; a gradient step where that is not negative definite),
/// steps clamped to the domain and halved until the change grows; a coordinate held at the domain boundary
/// by the clamp is left out of the next step.
fn local_max_change(a: &BSplineSurface, b: &BSplineSurface, uv: (f64, f64)) -> f64 {
    let ((u0, u1), (v0, v1)) = a.domain();
    let change = |u: f64, v: f64| (b.point(u, v) - a.point(u, v)).length();
    let (mut u, mut v) = uv;
    let mut best = change(u, v);
    let scale = ((u1 - u0).powi(2) + (v1 - v0).powi(2)).sqrt();
    for _ in 0..15 {
        let (da, db) = (a.derivs(u, v), b.derivs(u, v));
        let (d, du, dv) = (db.p - da.p, db.su - da.su, db.sv - da.sv);
        let (duu, duv, dvv) = (db.suu - da.suu, db.suv - da.suv, db.svv - da.svv);
        let mut g = [d.dot(du), d.dot(dv)];
        let mut h = [
            du.dot(du) + d.dot(duu),
            du.dot(dv) + d.dot(duv),
            dv.dot(dv) + d.dot(dvv),
        ];
        // a coordinate at its bound whose gradient points outwards stays
        let held_u = (u <= u0 && g[0] < 0.0) || (u >= u1 && g[0] > 0.0);
        let held_v = (v <= v0 && g[1] < 0.0) || (v >= v1 && g[1] > 0.0);
        if held_u {
            g[0] = 0.0;
            h[1] = 0.0;
            h[0] = -1.0;
        }
        if held_v {
            g[1] = 0.0;
            h[1] = 0.0;
            h[2] = -1.0;
        }
        let det = h[0] * h[2] - h[1] * h[1];
        let (mut su, mut sv) = if h[0] < 0.0 && det > 0.0 {
            // Newton: s = −H⁻¹ g
            (-(h[2] * g[0] - h[1] * g[1]) / det, -(h[0] * g[1] - h[1] * g[0]) / det)
        } else {
            // gradient ascent, scaled to a step of at most 1 % of the domain
            let n = (g[0] * g[0] + g[1] * g[1]).sqrt();
            if n == 0.0 {
                break;
            }
            (0.01 * scale * g[0] / n, 0.01 * scale * g[1] / n)
        };
        let mut moved = false;
        for _ in 0..20 {
            let (nu, nv) = ((u + su).clamp(u0, u1), (v + sv).clamp(v0, v1));
            let c = change(nu, nv);
            if c > best {
                best = c;
                moved = (nu - u).abs() + (nv - v).abs() > 1e-15 * scale;
                (u, v) = (nu, nv);
                break;
            }
            su *= 0.5;
            sv *= 0.5;
        }
        if !moved {
            break;
        }
    }
    best
}

/// The smoother's search: bisection on the log of the strength over [`REFERENCE_LOG_STRENGTH`]
/// ([`REFERENCE_STEPS`] steps) for the largest strength whose result holds the band. Returns every
/// band-holding result visited as `(net, deviation bound, strength)`, by increasing strength: the last is
/// the smoother's answer. Empty when not even the smallest strength holds the band.
fn plate_search(
    s: &BSplineSurface,
    plate: &PlateFit<'_, '_>,
    rhs: &[DVec3],
    bands: &Bands<'_>,
) -> Result<Vec<(Vec<DVec3>, f64, f64)>> {
    let attempt = |log_st: f64| -> Result<Option<(Vec<DVec3>, f64, f64)>> {
        let st = 10f64.powf(log_st);
        let pts = match plate.solve(rhs, st) {
            Ok(p) => p,
            // a strength too large for the factorization's pivots counts as not holding
            Err(Error::Solve(_)) => return Ok(None),
            Err(e) => return Err(e),
        };
        let f = s.with_points(pts)?;
        Ok(bands.holds(s, &f).map(|dev| (f.points().to_vec(), dev, st)))
    };
    let (mut lo, mut hi) = REFERENCE_LOG_STRENGTH;
    if let Some(r) = attempt(hi)? {
        return Ok(vec![r]);
    }
    let Some(first) = attempt(lo)? else {
        return Ok(Vec::new());
    };
    let mut found = vec![first];
    for _ in 0..REFERENCE_STEPS {
        let mid = 0.5 * (lo + hi);
        match attempt(mid)? {
            Some(r) => {
                found.push(r);
                lo = mid;
            }
            None => hi = mid,
        }
    }
    Ok(found)
}

/// The step-8 ranking over the moving rectangle: (isocurve curvature extrema with the 1 % dead band of
/// the original's max |κ_n|, `∫∫|∇H|² dA`), compared lexicographically — the measures of
/// [`crate::measure_surface`].
struct Ranker {
    rect: ((f64, f64), (f64, f64)),
    delta: f64,
    gl: GaussLegendre,
}

#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
struct Rank(usize, f64);

impl Ranker {
    fn new(s: &BSplineSurface, rect: ((f64, f64), (f64, f64))) -> Self {
        let delta = 0.01 * iso_stats_in(s, rect, RANK_ISO, 0.0).max_abs_kappa;
        Self {
            rect,
            delta,
            gl: GaussLegendre::new(RANK_GAUSS),
        }
    }

    fn rank(&self, f: &BSplineSurface) -> Rank {
        let st = iso_stats_in(f, self.rect, RANK_ISO, self.delta);
        let e = mean_curvature_variation_rule(f, self.rect, &self.gl);
        Rank(
            st.extrema_u + st.extrema_v,
            if e.is_finite() { e } else { f64::INFINITY },
        )
    }
}

/// Rows next to a pole that a fair keeps: the pole row and the two after it fix the surface's position,
/// tangent plane and curvature at the pole.
pub const POLE_ROWS: usize = 3;

/// Diagonal of the control net's bounding box.
fn net_size(s: &BSplineSurface) -> f64 {
    let (lo, hi) = s.control_bounds();
    (hi - lo).length()
}

/// Whether the control points `pts` all coincide (within 1e-12 of `size`): a collapsed row or column (a
/// pole, as on a surface of revolution or a triangular patch), whose isocurve is a single point.
fn collapsed(pts: impl IntoIterator<Item = DVec3>, size: f64) -> bool {
    let mut it = pts.into_iter();
    let Some(first) = it.next() else { return false };
    it.all(|q| q.distance(first) <= 1e-12 * size)
}

/// Free control rows and columns with the poles and seams held.
/// - A **pole**: a boundary row (or column) whose control points all coincide. If the free range reaches
///   it, that row and the next [`POLE_ROWS`] − 1 stay, so the pole stays one point with its tangent plane
///   and curvature (moving its points apart would tear a hole into the surface, within the tolerance but
///   visible as a crease in the shading).
/// - A **seam**: the first and last rows (or columns) coincide point by point (within 1e-10 of the net's
///   size, as for closed curves), i.e. the surface is closed in that direction (a tube, a full surface of
///   revolution). The isocurves are faired one stretch at a time, not across the seam, so the
///   [`POLE_ROWS`] rows at each side of it stay: the surface stays closed, with its continuity across the
///   seam (fairing both sides independently opened a full paraboloid of revolution by 2.4e-3 at m = 3e-3).
fn hold_poles_and_seams(
    s: &BSplineSurface,
    mut fu: Range<usize>,
    mut fv: Range<usize>,
) -> (Range<usize>, Range<usize>) {
    let (nu, nv) = (s.nu(), s.nv());
    let pts = s.points();
    let size = net_size(s);
    let row = |i: usize| collapsed((0..nv).map(|j| pts[i * nv + j]), size);
    let col = |j: usize| collapsed((0..nu).map(|i| pts[i * nv + j]), size);
    let seam_u = (0..nv).all(|j| pts[j].distance(pts[(nu - 1) * nv + j]) <= 1e-10 * size);
    let seam_v = (0..nu).all(|i| pts[i * nv].distance(pts[i * nv + nv - 1]) <= 1e-10 * size);
    let hold = |f: &mut Range<usize>, n: usize, first: bool, last: bool| {
        if f.start < f.end && f.start == 0 && first {
            f.start = POLE_ROWS.min(f.end);
        }
        if f.start < f.end && f.end == n && last {
            f.end = (n - POLE_ROWS.min(n)).max(f.start);
        }
    };
    hold(&mut fu, nu, seam_u || row(0), seam_u || row(nu - 1));
    hold(&mut fv, nv, seam_v || col(0), seam_v || col(nv - 1));
    (fu, fv)
}

/// The curve-engine setup for one isocurve `c` over the region `r` (holding
/// `spans_r` knot spans) with the isocurve tolerance `m_iso`.
///
/// By default (`opts.curve.samples` / `strength` unset) ISO_SAMPLES_PER_SPAN
/// samples per knot span of the region and a target smoothing of
/// ISO_TARGET_SIGMA_SPANS knot spans (σ of the equivalent Gaussian of the
/// averaging passes), so that the work per isocurve is linear in its number
/// of spans (the curve engine's default σ = 0.06·n samples costs O(n²)); the
/// isocurve's band is checked at its own samples only
/// ([`FairingSetup::with_check_samples`] with 0), since the surface verifies
/// its own band.
pub fn isocurve_setup(
    c: &crate::curve::BSplineCurve,
    opts: &SurfaceFairingOptions,
    m_iso: f64,
    r: (f64, f64),
    spans_r: usize,
) -> Result<FairingSetup> {
    let ns = opts.curve.samples.unwrap_or(ISO_SAMPLES_PER_SPAN * spans_r.max(1) + 1);
    let sigma = ISO_TARGET_SIGMA_SPANS * ISO_SAMPLES_PER_SPAN as f64;
    let strength = opts.curve.strength.or(match opts.curve.target {
        TargetMethod::Heat | TargetMethod::Average => Some((1.5 * sigma * sigma).round() as usize),
        TargetMethod::Binomial => Some((2.0 * sigma * sigma).round() as usize),
        TargetMethod::Fit => None,
    });
    let fo = FairingOptions {
        region: Some(r),
        tolerance: m_iso,
        samples: Some(ns),
        strength,
        // the E polish is for curves; the surface combines the isocurve clouds and verifies its own band
        polish: false,
        // an isocurve's ends are the surface's border: they keep the border's G2 state
        curve_ends: None,
        ..opts.curve
    };
    FairingSetup::with_check_samples(c, fo, 0)
}

/// `f` over `items`, results in the order of `items`, on rayon's global pool (`threads` `None`; its size
/// is rayon's choice, `RAYON_NUM_THREADS` if set), on a pool of `threads` workers, or here in this thread
/// (`Some(1)`). The result of each item does not depend on the thread count. A panic in a worker is
/// re-raised here (the editor's frame guard reports it).
fn par_map<T: Sync, R: Send>(items: &[T], threads: Option<usize>, f: impl Fn(&T) -> R + Sync + Send) -> Vec<R> {
    use rayon::prelude::*;
    match threads {
        Some(0 | 1) => items.iter().map(f).collect(),
        None => items.par_iter().map(f).collect(),
        Some(n) => match rayon::ThreadPoolBuilder::new().num_threads(n).build() {
            Ok(pool) => pool.install(|| items.par_iter().map(&f).collect()),
            Err(_) => items.iter().map(f).collect(),
        },
    }
}

/// Isocurves per block of neighbours (warm-started band search, one unit of parallel work).
pub const ISO_BLOCK: usize = 8;

/// Fair the isocurves and combine the clouds: returns the grid data `S + Δ`, one per isocurve tolerance
/// of `levels`. Each isocurve's setup (arc length, samples, basis rows, normal equations) does not depend on
/// the tolerance, so it is built once and re-faired per level (each level warm-starts its band search from
/// the neighbouring isocurve's μ at the same level, exactly as one call per level would).
fn combined_cloud(
    s: &BSplineSurface,
    opts: &SurfaceFairingOptions,
    levels: &[f64],
    ru: (f64, f64),
    rv: (f64, f64),
    us: &[f64],
    vs: &[f64],
    orig: &[DVec3],
    tm: &mut SurfaceTimings,
) -> Result<Vec<Vec<DVec3>>> {
    let t0 = Instant::now();
    let (mu, mv) = (us.len(), vs.len());
    let nl = levels.len();
    let mut du = vec![vec![DVec3::ZERO; mu * mv]; nl];
    let mut dv = vec![vec![DVec3::ZERO; mu * mv]; nl];
    // A direction whose region holds fewer than p + 1 knot spans has no movable isocurve control point for
    // the curve engine (e.g. a cubic direction with one span): its isocurves stay, Δ = 0.
    let spans_in = |k: &crate::knots::KnotVector, (a, b): (f64, f64)| {
        k.breakpoints().windows(2).filter(|w| w[0] >= a && w[1] <= b).count()
    };
    let (spans_u, spans_v) = (spans_in(s.knots_u(), ru), spans_in(s.knots_v(), rv));
    let fair_u = spans_u > s.degree_u();
    let fair_v = spans_v > s.degree_v();
    // The isocurves are independent: fair them in blocks of ISO_BLOCK neighbours (each block warm-starts
    // the band search of an isocurve from its neighbour's μ), the blocks spread over the available cores.
    // Blocks are fixed by the grid, not by the core count, so the result does not depend on the machine.
    let mut tasks: Vec<(bool, usize)> = Vec::with_capacity(mu + mv);
    if fair_u {
        tasks.extend((0..mv).map(|l| (true, l)));
    }
    if fair_v {
        tasks.extend((0..mu).map(|k| (false, k)));
    }
    let blocks: Vec<&[(bool, usize)]> = tasks
        .chunk_by(|a, b| a.0 == b.0)
        .flat_map(|c| c.chunks(ISO_BLOCK))
        .collect();
    // per isocurve of the block, per level: the faired isocurve at the grid parameters
    type BlockResult = Result<Vec<Vec<Vec<DVec3>>>>;
    let size = net_size(s);
    let ((du0, du1), (dv0, dv1)) = s.domain();
    let fair_block = |block: &[(bool, usize)]| -> BlockResult {
        let mut hints = vec![None; nl];
        block
            .iter()
            .map(|&(is_u, i)| {
                let (iso, r, spans, t, at) = if is_u {
                    (s.iso_u(vs[i]), ru, spans_u, us, ("u", "v", vs[i]))
                } else {
                    (s.iso_v(us[i]), rv, spans_v, vs, ("v", "u", us[i]))
                };
                // the isocurve along a pole (a collapsed boundary row, held by `hold_poles_and_seams`) is a single point:
                // it stays (Δ = 0); a point isocurve inside the domain (a pinch at a p-fold knot) still fails
                let on_edge = if is_u {
                    vs[i] == dv0 || vs[i] == dv1
                } else {
                    us[i] == du0 || us[i] == du1
                };
                if on_edge && collapsed(iso.points().iter().copied(), size) {
                    let kept: Vec<DVec3> = if is_u {
                        (0..mu).map(|k| orig[k * mv + i]).collect()
                    } else {
                        (0..mv).map(|l| orig[i * mv + l]).collect()
                    };
                    return Ok(vec![kept; nl]);
                }
                let err = |e: Error| {
                    Error::InvalidInput(format!("fairing the {}-isocurve at {} = {}: {e}", at.0, at.1, at.2))
                };
                let mut st = isocurve_setup(&iso, opts, levels[0], r, spans).map_err(err)?;
                let mut out = Vec::with_capacity(nl);
                for (&m_iso, hint) in levels.iter().zip(hints.iter_mut()) {
                    st.set_tolerance(m_iso).map_err(err)?;
                    st.set_mu_hint(*hint);
                    let res = st.fair().map_err(err)?;
                    *hint = Some(res.mu);
                    out.push(t.iter().map(|&x| res.curve.point(x)).collect());
                }
                Ok(out)
            })
            .collect()
    };
    let results = par_map(&blocks, opts.threads, |b| fair_block(b));
    for (block, res) in blocks.iter().zip(results) {
        let pts = res?;
        for (&(is_u, i), per_level) in block.iter().zip(pts) {
            for (lv, p) in per_level.into_iter().enumerate() {
                if is_u {
                    for k in 0..mu {
                        du[lv][k * mv + i] = p[k] - orig[k * mv + i];
                    }
                } else {
                    for l in 0..mv {
                        dv[lv][i * mv + l] = p[l] - orig[i * mv + l];
                    }
                }
            }
        }
    }
    let t1 = Instant::now();
    tm.isocurves += t1 - t0;
    // normalized distance to the held borders; a side on the domain boundary is no border (its rows are free)
    let border_dist = |t: f64, a: f64, b: f64, lo: f64, hi: f64| {
        let da = if a > lo { t - a } else { f64::INFINITY };
        let db = if b < hi { b - t } else { f64::INFINITY };
        (da.min(db) / (b - a)).clamp(0.0, 0.5)
    };
    let (a0, a1) = (us[0], us[mu - 1]);
    let (b0, b1) = (vs[0], vs[mv - 1]);
    let clouds = du
        .iter()
        .zip(&dv)
        .map(|(du, dv)| {
            let mut data = vec![DVec3::ZERO; mu * mv];
            for k in 0..mu {
                let d_u = border_dist(us[k], a0, a1, du0, du1);
                for l in 0..mv {
                    let d_v = border_dist(vs[l], b0, b1, dv0, dv1);
                    let (beta_u, beta_v) = if d_u + d_v > 0.0 {
                        (d_v / (d_u + d_v), d_u / (d_u + d_v))
                    } else {
                        (0.5, 0.5)
                    };
                    let (x, y) = (du[k * mv + l], dv[k * mv + l]);
                    let (mut a, mut b) = match opts.combine {
                        Combine::Average => (0.5, 0.5),
                        Combine::Border => (beta_u, beta_v),
                        Combine::Weighted | Combine::Smoothed => (beta_u * x.length(), beta_v * y.length()),
                    };
                    if !(a + b > 0.0) {
                        (a, b) = (beta_u, beta_v);
                    }
                    data[k * mv + l] = orig[k * mv + l] + (x * a + y * b) / (a + b);
                }
            }
            if opts.combine == Combine::Smoothed {
                umbrella_smooth(&mut data, mu, mv, 3, 0.25);
            }
            data
        })
        .collect();
    tm.combine += t1.elapsed();
    Ok(clouds)
}

/// Normal umbrella smoothing: `P ← P + τ ((avg of the 4 neighbours − P)·n) n`, n the grid normal,
/// border rows and columns held.
fn umbrella_smooth(p: &mut [DVec3], mu: usize, mv: usize, passes: usize, tau: f64) {
    let mut next = p.to_vec();
    for _ in 0..passes {
        for k in 1..mu.saturating_sub(1) {
            for l in 1..mv.saturating_sub(1) {
                let c = p[k * mv + l];
                let (w, e) = (p[(k - 1) * mv + l], p[(k + 1) * mv + l]);
                let (sth, nth) = (p[k * mv + l - 1], p[k * mv + l + 1]);
                let n = (e - w).cross(nth - sth).normalize_or_zero();
                let lap = (w + e + sth + nth) * 0.25 - c;
                next[k * mv + l] = c + n * (tau * lap.dot(n));
            }
        }
        p.copy_from_slice(&next);
    }
}

/// Discrete fairness energy used to choose among tolerance-holding candidates (module docs, step 6):
/// the mean curvature H at [`ENERGY_PER_SPAN`] samples per knot span of the moving rectangle and the
/// Dirichlet energy of H on that grid, `Σ_edges (H_a − H_b)² · w_⊥ / |P_a − P_b|` (`w_⊥` the
/// length of the grid cell across the edge), a first-order discretization of `∫∫ |∇H|² dA`.
/// Evaluated separably from basis-derivative tables (O(grid · p)).
struct FairnessGrid {
    /// Per u-sample: span and the values, 1st and 2nd derivatives of the p + 1 basis functions.
    bu: Vec<(usize, [[f64; MAX_ORDER]; 3])>,
    bv: Vec<(usize, [[f64; MAX_ORDER]; 3])>,
}

/// Samples per knot span of the fairness energy grid.
pub const ENERGY_PER_SPAN: usize = 2;

fn basis_table(k: &KnotVector, ts: &[f64]) -> Vec<(usize, [[f64; MAX_ORDER]; 3])> {
    ts.iter()
        .map(|&t| {
            let sp = k.find_span(t);
            let mut d = [[0.0; MAX_ORDER]; 3];
            crate::basis::ders_basis_funs::<3>(k.values(), sp, k.clamp(t), k.degree(), &mut d);
            (sp, d)
        })
        .collect()
}

impl FairnessGrid {
    fn new(s: &BSplineSurface, (au, bu): (f64, f64), (av, bv): (f64, f64)) -> Self {
        Self {
            bu: basis_table(s.knots_u(), &span_grid(s.knots_u(), au, bu, ENERGY_PER_SPAN)),
            bv: basis_table(s.knots_v(), &span_grid(s.knots_v(), av, bv, ENERGY_PER_SPAN)),
        }
    }

    fn energy(&self, s: &BSplineSurface) -> f64 {
        let (mu, mv) = (self.bu.len(), self.bv.len());
        let (pu, pv, nv) = (s.degree_u(), s.degree_v(), s.nv());
        let pts = s.points();
        // Σ_i N_i^{(r)}(u_k) D_ij for r = 0, 1, 2, per (k, j)
        let mut tab = vec![[DVec3::ZERO; 3]; mu * nv];
        let mut hs = Vec::with_capacity(mu * mv);
        let mut ps = Vec::with_capacity(mu * mv);
        for (k, (sp, d)) in self.bu.iter().enumerate() {
            for a in 0..=pu {
                let i = sp - pu + a;
                for j in 0..nv {
                    let q = pts[i * nv + j];
                    let t = &mut tab[k * nv + j];
                    for r in 0..3 {
                        t[r] += q * d[r][a];
                    }
                }
            }
        }
        for k in 0..mu {
            for (sp, d) in &self.bv {
                let (mut p, mut su, mut sv, mut suu, mut suv, mut svv) = (
                    DVec3::ZERO,
                    DVec3::ZERO,
                    DVec3::ZERO,
                    DVec3::ZERO,
                    DVec3::ZERO,
                    DVec3::ZERO,
                );
                for b in 0..=pv {
                    let t = tab[k * nv + sp - pv + b];
                    p += t[0] * d[0][b];
                    sv += t[0] * d[1][b];
                    svv += t[0] * d[2][b];
                    su += t[1] * d[0][b];
                    suv += t[1] * d[1][b];
                    suu += t[2] * d[0][b];
                }
                let n = su.cross(sv).normalize_or_zero();
                let (e, f, g) = (su.dot(su), su.dot(sv), sv.dot(sv));
                let det = e * g - f * f;
                let h = (e * svv.dot(n) - 2.0 * f * suv.dot(n) + g * suu.dot(n)) / (2.0 * det);
                hs.push(if h.is_finite() { h } else { 0.0 });
                ps.push(p);
            }
        }
        let (h, p) = (&hs, &ps);
        let mut e = 0.0;
        let len = |a: usize, b: usize| (p[a] - p[b]).length();
        for k in 0..mu.saturating_sub(1) {
            for l in 0..mv.saturating_sub(1) {
                // the two edges leaving (k, l), each weighted by the width of its cell across it
                let i = k * mv + l;
                let (a, b) = (i + mv, i + 1);
                let (lu, lv) = (len(i, a), len(i, b));
                if lu > 0.0 && lv > 0.0 {
                    e += (h[a] - h[i]).powi(2) * lv / lu + (h[b] - h[i]).powi(2) * lu / lv;
                }
            }
        }
        e
    }
}

/// Basis values of one direction at the parameters of a check grid.
struct GridBasis {
    spans: Vec<usize>,
    vals: Vec<[f64; MAX_ORDER]>,
    params: Vec<f64>,
}

impl GridBasis {
    fn new(k: &KnotVector, ts: &[f64]) -> Self {
        let p = k.degree();
        let mut spans = Vec::with_capacity(ts.len());
        let mut vals = Vec::with_capacity(ts.len());
        for &t in ts {
            let sp = k.find_span(t);
            let mut n = [0.0; MAX_ORDER];
            basis_funs(k.values(), sp, k.clamp(t), p, &mut n);
            spans.push(sp);
            vals.push(n);
        }
        Self {
            spans,
            vals,
            params: ts.to_vec(),
        }
    }
}

/// A check grid (module docs, step 7) with its basis values, so that the
/// change `S_f − S = Σ ΔD_ij N_i(u) M_j(v)` is evaluated separably
/// (O(grid · p)) instead of by two point evaluations per sample.
struct CheckGrid {
    u: GridBasis,
    v: GridBasis,
    pu: usize,
    pv: usize,
    threads: Option<usize>,
}

/// Rows of a check grid per unit of parallel work (fixed, so the result does not depend on the threads).
const CHECK_ROWS_PER_TASK: usize = 16;

/// The surface at every grid node `(us[k], vs[l])` (row-major over k), evaluated separably:
/// `T[k][j] = Σ_i N_i(u_k) P_ij`, then `S = Σ_j M_j(v_l) T[k][j]` (O(grid · p) instead of a point
/// evaluation per node).
fn grid_points(s: &BSplineSurface, us: &[f64], vs: &[f64]) -> Vec<DVec3> {
    let (bu, bv) = (GridBasis::new(s.knots_u(), us), GridBasis::new(s.knots_v(), vs));
    let (pu, pv, nv) = (s.degree_u(), s.degree_v(), s.nv());
    let pts = s.points();
    let mut out = Vec::with_capacity(us.len() * vs.len());
    let mut row = vec![DVec3::ZERO; nv];
    for k in 0..us.len() {
        row.fill(DVec3::ZERO);
        let sp = bu.spans[k];
        for a in 0..=pu {
            let w = bu.vals[k][a];
            let src = &pts[(sp - pu + a) * nv..(sp - pu + a + 1) * nv];
            for (r, q) in row.iter_mut().zip(src) {
                *r += *q * w;
            }
        }
        for l in 0..vs.len() {
            let sp = bv.spans[l];
            out.push((0..=pv).map(|b| row[sp - pv + b] * bv.vals[l][b]).sum());
        }
    }
    out
}

impl CheckGrid {
    /// The parametric change `|S_b − S_a|` on the grid (`b` differing from `a` only in the control block
    /// `fu × fv`, evaluated separably from the change of that block): its maximum and the nodes where it
    /// exceeds `thresh` and is no smaller than at its four grid neighbours, as `(change, u, v)`.
    fn change_peaks(
        &self,
        a: &BSplineSurface,
        b: &BSplineSurface,
        fu: &Range<usize>,
        fv: &Range<usize>,
        thresh: f64,
    ) -> (f64, Vec<(f64, f64, f64)>) {
        let nv = a.nv();
        let nfv = fv.len();
        let (mu, mv) = (self.u.params.len(), self.v.params.len());
        let (pa, pb) = (a.points(), b.points());
        let mut tmp = vec![DVec3::ZERO; mu * nfv];
        for k in 0..mu {
            let sp = self.u.spans[k];
            for ia in 0..=self.pu {
                let i = sp - self.pu + ia;
                if !fu.contains(&i) {
                    continue;
                }
                let w = self.u.vals[k][ia];
                for (jj, t) in tmp[k * nfv..(k + 1) * nfv].iter_mut().enumerate() {
                    let idx = i * nv + fv.start + jj;
                    *t += (pb[idx] - pa[idx]) * w;
                }
            }
        }
        let mut d = vec![0.0f64; mu * mv];
        for k in 0..mu {
            for l in 0..mv {
                let sp = self.v.spans[l];
                let mut x = DVec3::ZERO;
                for jb in 0..=self.pv {
                    let j = sp - self.pv + jb;
                    if fv.contains(&j) {
                        x += tmp[k * nfv + j - fv.start] * self.v.vals[l][jb];
                    }
                }
                d[k * mv + l] = x.length();
            }
        }
        let max = d.iter().fold(0.0f64, |m, &x| m.max(x));
        let mut out = Vec::new();
        for k in 0..mu {
            for l in 0..mv {
                let x = d[k * mv + l];
                if !(x > thresh) {
                    continue;
                }
                let nb = [
                    (k > 0).then(|| d[(k - 1) * mv + l]),
                    (k + 1 < mu).then(|| d[(k + 1) * mv + l]),
                    (l > 0).then(|| d[k * mv + l - 1]),
                    (l + 1 < mv).then(|| d[k * mv + l + 1]),
                ];
                if nb.iter().flatten().all(|&y| y <= x) {
                    out.push((x, self.u.params[k], self.v.params[l]));
                }
            }
        }
        (max, out)
    }

    fn new(s: &BSplineSurface, cu: &[f64], cv: &[f64], threads: Option<usize>) -> Self {
        Self {
            u: GridBasis::new(s.knots_u(), cu),
            v: GridBasis::new(s.knots_v(), cv),
            pu: s.degree_u(),
            pv: s.degree_v(),
            threads,
        }
    }

    /// Upper bound of the deviation between `a` (the original) and `b` (same
    /// knots, control points differing only in the block `fu × fv`) on the
    /// grid: `|S_b − S_a|` at every sample, sharpened by Newton projections
    /// in both directions where it exceeds `m`. With `stop_early`, returns
    /// the first sharpened value above `m` (a proof that the band is broken,
    /// not the maximum).
    fn deviation(
        &self,
        a: &BSplineSurface,
        b: &BSplineSurface,
        fu: &Range<usize>,
        fv: &Range<usize>,
        m: f64,
        stop_early: bool,
    ) -> f64 {
        let nv = a.nv();
        let nfv = fv.len();
        let (mu, mv) = (self.u.params.len(), self.v.params.len());
        // T[k][jj] = Σ_a N_a(u_k) ΔD[i][fv.start + jj]
        let mut tmp = vec![DVec3::ZERO; mu * nfv];
        let (pa, pb) = (a.points(), b.points());
        for k in 0..mu {
            let sp = self.u.spans[k];
            for ia in 0..=self.pu {
                let i = sp - self.pu + ia;
                if !fu.contains(&i) {
                    continue;
                }
                let w = self.u.vals[k][ia];
                let row = &mut tmp[k * nfv..(k + 1) * nfv];
                for (jj, t) in row.iter_mut().enumerate() {
                    let idx = i * nv + fv.start + jj;
                    *t += (pb[idx] - pa[idx]) * w;
                }
            }
        }
        // rows in fixed chunks, in parallel; each chunk returns (its max, whether it stopped at a violation)
        let chunks: Vec<(usize, Range<usize>)> = (0..mu)
            .step_by(CHECK_ROWS_PER_TASK)
            .map(|k0| k0..(k0 + CHECK_ROWS_PER_TASK).min(mu))
            .enumerate()
            .collect();
        // with stop_early, chunks after one that proved a violation need not finish (the result is the
        // violation of the first such chunk in grid order, as a sequential scan would return)
        let first_violation = std::sync::atomic::AtomicUsize::new(usize::MAX);
        let per_chunk = par_map(&chunks, self.threads, |(c, rows)| {
            let mut max = 0.0f64;
            for k in rows.clone() {
                if stop_early && first_violation.load(std::sync::atomic::Ordering::Relaxed) < *c {
                    return (max, false);
                }
                for l in 0..mv {
                    let sp = self.v.spans[l];
                    let mut d = DVec3::ZERO;
                    for jb in 0..=self.pv {
                        let j = sp - self.pv + jb;
                        if fv.contains(&j) {
                            d += tmp[k * nfv + j - fv.start] * self.v.vals[l][jb];
                        }
                    }
                    let mut dist = d.length();
                    if dist > m {
                        let (u, v) = (self.u.params[k], self.v.params[l]);
                        let (qa, qb) = (a.point(u, v), b.point(u, v));
                        let d1 = newton_project(b, qa, (u, v)).distance;
                        let d2 = newton_project(a, qb, (u, v)).distance;
                        dist = dist.min(d1.max(d2));
                        if stop_early && dist > m {
                            first_violation.fetch_min(*c, std::sync::atomic::Ordering::Relaxed);
                            return (dist, true);
                        }
                    }
                    max = max.max(dist);
                }
            }
            (max, false)
        });
        // with stop_early: the first chunk (in grid order) that proved a violation
        if let Some(&(d, _)) = per_chunk.iter().find(|c| c.1) {
            return d;
        }
        per_chunk.iter().fold(0.0f64, |acc, c| acc.max(c.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::knots::KnotVector;
    use crate::measure_surface::deviation;
    use proptest::{prop_assert, prop_assert_eq};

    /// xorshift64* with a Box–Muller normal: a fixed, dependency-free noise source.
    pub(crate) struct Rng(u64);
    impl Rng {
        pub(crate) fn uniform(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
        }
        pub(crate) fn normal(&mut self) -> f64 {
            let (a, b) = (self.uniform().max(1e-300), self.uniform());
            (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
        }
    }

    /// Least-squares bicubic graph of `f` over [0,1]² with an `n × n` net and uniform knots.
    pub(crate) fn graph(n: usize, f: impl Fn(f64, f64) -> f64) -> BSplineSurface {
        crate::fit_surface::fit_graph(n, f).unwrap()
    }

    pub(crate) fn noisy(s: &BSplineSurface, sigma: f64, seed: u64) -> BSplineSurface {
        let mut r = Rng(seed);
        let pts = s
            .points()
            .iter()
            .map(|p| *p + DVec3::new(0.0, 0.0, sigma * r.normal()))
            .collect();
        s.with_points(pts).unwrap()
    }

    /// RMS over an interior grid of the mean-curvature and Gauss-curvature-root errors against `exact`.
    fn curvature_error(s: &BSplineSurface, exact: &BSplineSurface) -> f64 {
        curvature_error_on(s, exact, |k, l| {
            (0.1 + 0.8 * k as f64 / 29.0, 0.1 + 0.8 * l as f64 / 29.0)
        })
    }

    /// RMS of the principal-curvature errors against `exact` at the 30 × 30 parameters `uv(k, l)`.
    fn curvature_error_on(s: &BSplineSurface, exact: &BSplineSurface, uv: impl Fn(usize, usize) -> (f64, f64)) -> f64 {
        let mut sum = 0.0;
        let n = 30;
        for k in 0..n {
            for l in 0..n {
                let (u, v) = uv(k, l);
                let (a, b) = (s.curvature(u, v), exact.curvature(u, v));
                sum += (a.k_max - b.k_max).powi(2) + (a.k_min - b.k_min).powi(2);
            }
        }
        (sum / (n * n) as f64).sqrt()
    }

    fn fair(s: &BSplineSurface, m: f64, combine: Combine) -> SurfaceFairingResult {
        fair_surface(
            s,
            SurfaceFairingOptions {
                tolerance: m,
                combine,
                ..Default::default()
            },
        )
        .unwrap()
    }

    /// Interior-region fairing must make the region fairer at every tolerance (it once got worse at
    /// large m: the largest band-holding fit smoothing and isocurve corrections of size m, incoherent
    /// from one isocurve to the next, were taken; module docs step 6). Noisy wave, fixed seed; the
    /// measures over the region drop by at least the quoted factor (measured x0.74..0.78 for Σ∫(dκ/ds)², x0.86..0.87
    /// for ∫∫|∇H|²; before the fix x1.14 / x1.08 at m = 2e-3), the whole surface gets no worse.
    #[test]
    fn interior_region_gets_fairer_at_every_tolerance() {
        use crate::measure_surface::{iso_stats_in, mean_curvature_variation_in};
        let exact = graph(16, |u, v| 0.15 * (4.0 * u).sin() * (4.8 * v).cos() + 0.05 * u * v);
        let s = noisy(&exact, 1e-3, 11);
        let region = ((0.15, 0.85), (0.15, 0.85));
        let whole = s.domain();
        let e = |x: &BSplineSurface, r| {
            let st = iso_stats_in(x, r, 12, 0.0);
            st.e_var_u + st.e_var_v
        };
        let (e_in0, h_in0) = (e(&s, region), mean_curvature_variation_in(&s, region));
        let (e_all0, h_all0) = (e(&s, whole), mean_curvature_variation_in(&s, whole));
        for m in [2e-3, 5e-3, 1e-2, 2e-2] {
            let r = fair_surface(
                &s,
                SurfaceFairingOptions {
                    region: Some(region),
                    tolerance: m,
                    ..Default::default()
                },
            )
            .unwrap();
            let f = &r.surface;
            let (e_in, h_in) = (e(f, region) / e_in0, mean_curvature_variation_in(f, region) / h_in0);
            let (e_all, h_all) = (e(f, whole) / e_all0, mean_curvature_variation_in(f, whole) / h_all0);
            eprintln!(
                "m {m:.0e}: region E x{e_in:.3}, |grad H|^2 x{h_in:.3}; whole E x{e_all:.3}, |grad H|^2 x{h_all:.3} \
                 (m_iso {:.1e}, strength {}, dev {:.2e})",
                r.iso_tolerance, r.smoothing.strength_u, r.max_deviation
            );
            assert!(r.max_deviation <= m);
            assert!(
                e_in < 0.85 && h_in < 0.92,
                "m = {m}: region E x{e_in}, |grad H|^2 x{h_in}"
            );
            assert!(
                e_all < 1.0 && h_all < 1.0,
                "m = {m}: whole E x{e_all}, |grad H|^2 x{h_all}"
            );
        }
    }

    /// The default levels (the pass at m scaled) against the isocurves re-faired per level
    /// (`refair_levels`): both hold the band, and the scaled levels are as fair to within 10 %.
    #[test]
    fn scaled_levels_are_as_fair_as_refaired_levels() {
        use crate::measure_surface::iso_stats_in;
        let exact = graph(16, |u, v| 0.15 * (4.0 * u).sin() * (4.8 * v).cos() + 0.05 * u * v);
        let s = noisy(&exact, 1e-3, 11);
        let e = |x: &BSplineSurface, r| {
            let st = iso_stats_in(x, r, 12, 0.0);
            st.e_var_u + st.e_var_v
        };
        for (region, m) in [(((0.15, 0.85), (0.15, 0.85)), 1e-2), (s.domain(), 3e-3)] {
            let run = |refair_levels| {
                fair_surface(
                    &s,
                    SurfaceFairingOptions {
                        region: Some(region),
                        tolerance: m,
                        refair_levels,
                        ..Default::default()
                    },
                )
                .unwrap()
            };
            let (scaled, refaired) = (run(false), run(true));
            let e0 = e(&s, region);
            let (es, er) = (e(&scaled.surface, region) / e0, e(&refaired.surface, region) / e0);
            eprintln!(
                "region {region:?}, m {m:.0e}: E x{es:.3} scaled (m_iso {:.1e}), x{er:.3} refaired (m_iso {:.1e})",
                scaled.iso_tolerance, refaired.iso_tolerance
            );
            assert!(scaled.max_deviation <= m && refaired.max_deviation <= m);
            assert!(es < 1.0 && es <= 1.1 * er, "scaled x{es} vs refaired x{er}");
        }
    }

    #[test]
    fn noisy_plane_cylinder_bump_curvature_error_drops() {
        let sigma = 1e-3;
        type Case = (&'static str, Box<dyn Fn(f64, f64) -> f64>, f64);
        let cases: [Case; 3] = [
            ("plane", Box::new(|u, v| 0.2 * u - 0.1 * v), 10.0),
            ("cylinder", Box::new(|u, _| (1.0 - (u - 0.5).powi(2)).sqrt()), 2.0),
            // the bump: measured 0.21 -> 0.13 (x1.6) since the fairness-energy choice (was 0.21 -> 0.27, worse,
            // when the largest band-holding smoothing was taken)
            (
                "bump",
                Box::new(|u, v| 0.3 * (-((u - 0.5).powi(2) + (v - 0.5).powi(2)) / 0.05).exp()),
                1.3,
            ),
        ];
        for (name, f, factor) in cases {
            let exact = graph(14, f);
            let s = noisy(&exact, sigma, 7);
            let m = 3.0 * sigma;
            let r = fair(&s, m, Combine::Weighted);
            let (e0, e1) = (curvature_error(&s, &exact), curvature_error(&r.surface, &exact));
            eprintln!(
                "{name}: curvature error {e0:.4} -> {e1:.4} (x{:.1}), dev {:.2e}, rounds {}, alpha {}",
                e0 / e1,
                r.max_deviation,
                r.rounds,
                r.alpha
            );
            assert!(r.max_deviation <= m);
            assert!(e1 * factor < e0, "{name}: {e0} -> {e1}");
            // outside nothing moved (whole-surface region here: the boundary rows are free too, so only check the band)
            let (dev, _) = deviation(&s, &r.surface, 41);
            assert!(dev <= m * (1.0 + 1e-9), "{name}: measured deviation {dev} > {m}");
        }
    }

    fn border_g2(a: &BSplineSurface, b: &BSplineSurface, along_u: bool, t: f64) {
        // G2 across the border line u = t (along_u) or v = t: position, normal and the second fundamental form
        // of the faired surface (evaluated on the region side) equal the original's (unchanged side).
        for k in 0..=20 {
            let w = 0.02 + 0.96 * k as f64 / 20.0;
            let (u, v) = if along_u { (t, w) } else { (w, t) };
            let (da, db) = (a.derivs(u, v), b.derivs(u, v));
            let (ca, cb) = (da.curvature(), db.curvature());
            assert!((da.p - db.p).length() < 1e-12, "position at {u},{v}");
            assert!((ca.normal - cb.normal).length() < 1e-9, "normal at {u},{v}");
            let ii = |d: &crate::surface::SurfaceDerivs, n: DVec3| [d.suu.dot(n), d.suv.dot(n), d.svv.dot(n)];
            let (ia, ib) = (ii(&da, ca.normal), ii(&db, cb.normal));
            for c in 0..3 {
                assert!(
                    (ia[c] - ib[c]).abs() < 1e-7 * (1.0 + ia[c].abs()),
                    "II at {u},{v}: {ia:?} {ib:?}"
                );
            }
        }
    }

    #[test]
    fn local_region_keeps_outside_and_joins_g2() {
        for seed in [1u64, 2, 3] {
            let exact = graph(16, |u, v| 0.2 * (3.0 * u).sin() * v);
            let s = noisy(&exact, 1e-3, seed);
            let mut r = Rng(seed * 77);
            let u1 = 0.1 + 0.2 * r.uniform();
            let v1 = 0.05 + 0.2 * r.uniform();
            let region = ((u1, u1 + 0.55), (v1, v1 + 0.6));
            let m = 2e-3 + 3e-3 * r.uniform();
            let out = fair_surface(
                &s,
                SurfaceFairingOptions {
                    region: Some(region),
                    tolerance: m,
                    ..Default::default()
                },
            )
            .unwrap();
            let f = &out.surface;
            // control points outside the free block: bit-for-bit
            for i in 0..16 {
                for j in 0..16 {
                    if !(out.free_u.contains(&i) && out.free_v.contains(&j)) {
                        assert_eq!(f.point_at(i, j), s.point_at(i, j));
                    }
                }
            }
            // something moved
            assert!(f.points() != s.points());
            // every free point's support is inside the region
            for i in out.free_u.clone() {
                let (a, b) = s.knots_u().support(i);
                assert!(a >= region.0.0 && b <= region.0.1);
            }
            // band, measured independently on a dense grid
            let (dev, _) = deviation(&s, f, 81);
            let (rev, _) = deviation(f, &s, 81);
            assert!(dev.max(rev) <= m * (1.0 + 1e-9), "deviation {dev} / {rev} > {m}");
            // G2 across the four border lines of the moving rectangle
            let ku = s.knots_u().values();
            let kv = s.knots_v().values();
            let (au, bu) = (ku[out.free_u.start], ku[out.free_u.end + 3]);
            let (av, bv) = (kv[out.free_v.start], kv[out.free_v.end + 3]);
            border_g2(&s, f, true, au);
            border_g2(&s, f, false, av);
            // at the far borders evaluate from the region side: just below the knot
            border_g2(&s, f, true, bu - 1e-13);
            border_g2(&s, f, false, bv - 1e-13);
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(8))]
        /// Random region, tolerance, combination and noise: the band holds (measured independently in both
        /// directions), control points outside the free block are bit-identical, and the faired patch joins
        /// the untouched surface G2 across every border line of the moving rectangle inside the domain.
        #[test]
        fn band_outside_and_g2_hold(
            seed in 1u64..1000,
            u1 in 0.0f64..0.3,
            du in 0.5f64..0.7,
            v1 in 0.0f64..0.3,
            dv in 0.5f64..0.7,
            m in 1e-3f64..1e-2,
            c in 0usize..4,
        ) {
            let combine = [Combine::Average, Combine::Border, Combine::Weighted, Combine::Smoothed][c];
            let exact = graph(14, |u, v| 0.2 * (2.0 * u).sin() * (1.0 + v * v));
            let s = noisy(&exact, 1e-3, seed);
            let (u2, v2) = ((u1 + du).min(1.0), (v1 + dv).min(1.0));
            let out = fair_surface(
                &s,
                SurfaceFairingOptions { region: Some(((u1, u2), (v1, v2))), tolerance: m, combine, ..Default::default() },
            )
            .unwrap();
            let f = &out.surface;
            prop_assert!(out.max_deviation <= m);
            let (dev, _) = deviation(&s, f, 41);
            let (rev, _) = deviation(f, &s, 41);
            prop_assert!(dev.max(rev) <= m * (1.0 + 1e-9), "deviation {} / {} > {}", dev, rev, m);
            for i in 0..14 {
                for j in 0..14 {
                    if !(out.free_u.contains(&i) && out.free_v.contains(&j)) {
                        prop_assert_eq!(f.point_at(i, j), s.point_at(i, j));
                    }
                }
            }
            let (ku, kv) = (s.knots_u().values(), s.knots_v().values());
            let (au, bu) = (ku[out.free_u.start], ku[out.free_u.end + 3]);
            let (av, bv) = (kv[out.free_v.start], kv[out.free_v.end + 3]);
            // border lines strictly inside the domain (a side on the domain boundary has no neighbour)
            if au > 0.0 { border_g2(&s, f, true, au); }
            if av > 0.0 { border_g2(&s, f, false, av); }
            if bu < 1.0 { border_g2(&s, f, true, bu - 1e-13); }
            if bv < 1.0 { border_g2(&s, f, false, bv - 1e-13); }
        }
    }

    #[test]
    fn extruded_curve_matches_the_curve_engine() {
        // a noisy 3D curve in the xz plane, extruded along y with a cubic (collinear) v direction
        let n = 20;
        let k = KnotVector::uniform(3, n).unwrap();
        let mut r = Rng(11);
        let cpts: Vec<DVec3> = k
            .greville()
            .iter()
            .map(|&u| DVec3::new(u, 0.0, 0.2 * (2.0 * u).sin() + 1e-3 * r.normal()))
            .collect();
        let curve = crate::curve::BSplineCurve::new_3d(3, k.values().to_vec(), cpts.clone()).unwrap();
        let kv = KnotVector::uniform(3, 4).unwrap();
        let mut pts = Vec::new();
        for p in &cpts {
            for j in 0..4 {
                pts.push(*p + DVec3::new(0.0, j as f64 / 3.0, 0.0));
            }
        }
        let s = BSplineSurface::try_new(3, 3, k.values().to_vec(), kv.values().to_vec(), n, 4, pts, None).unwrap();
        let m = 3e-3;
        let out = fair_surface(
            &s,
            SurfaceFairingOptions {
                tolerance: m,
                combine: Combine::Weighted,
                auto_smoothing: false,
                // the isocurve fairing (steps 1-7) is what reproduces the curve engine; step 8 may return a
                // fairer candidate
                method: SurfaceMethod::Isocurves,
                ..Default::default()
            },
        )
        .unwrap();
        // the same curve-engine setup the surface engine uses for its u-isocurves (17 spans)
        let fr = isocurve_setup(
            &curve,
            &SurfaceFairingOptions::default(),
            out.iso_tolerance,
            (0.0, 1.0),
            n - 3,
        )
        .unwrap()
        .fair()
        .unwrap();
        let fc = fr.curve;
        // the v-isocurves are straight: the curve engine leaves them (|Δ_v| ~ rounding), so Weighted takes Δ_u,
        // the faired extrusion lies in the spline space and the fit reproduces it up to rounding of the solves
        let mut worst = 0.0f64;
        for i in 0..=50 {
            let u = i as f64 / 50.0;
            for j in 0..=4 {
                let v = j as f64 / 4.0;
                let want = fc.point(u) + DVec3::new(0.0, v, 0.0);
                worst = worst.max((out.surface.point(u, v) - want).length());
            }
        }
        assert!(worst < 1e-9, "extrusion differs by {worst}");
        // the paper's 0.5/0.5 average does about half of that correction (Δ_v ≈ 0 is averaged in)
        let avg = fair_surface(
            &s,
            SurfaceFairingOptions {
                tolerance: m,
                combine: Combine::Average,
                auto_smoothing: false,
                method: SurfaceMethod::Isocurves,
                ..Default::default()
            },
        )
        .unwrap();
        let change = |f: &BSplineSurface| {
            (0..=50)
                .map(|i| (f.point(i as f64 / 50.0, 0.5) - s.point(i as f64 / 50.0, 0.5)).length())
                .fold(0.0f64, f64::max)
        };
        let ratio = change(&avg.surface) / change(&out.surface);
        assert!((0.35..0.65).contains(&ratio), "average / weighted change = {ratio}");
    }

    #[test]
    fn rectangular_nonuniform_other_degrees_and_rational() {
        // 26 × 10 net, degrees 4 × 2, non-uniform knots in u
        let (nu, nv) = (26, 10);
        let mut ku = vec![0.0; 5];
        for i in 1..nu - 4 {
            let t = i as f64 / (nu - 4) as f64;
            ku.push(t * t * (3.0 - 2.0 * t));
        }
        ku.extend([1.0; 5]);
        let kv = KnotVector::uniform(2, nv).unwrap();
        let mut r = Rng(5);
        let gu = KnotVector::try_new(ku.clone(), 4, nu, "u").unwrap().greville();
        let gv = kv.greville();
        let mut pts = Vec::new();
        for &u in &gu {
            for &v in &gv {
                pts.push(DVec3::new(2.0 * u, v, 0.3 * u * v + 1e-3 * r.normal()));
            }
        }
        let s = BSplineSurface::try_new(4, 2, ku, kv.values().to_vec(), nu, nv, pts, None).unwrap();
        let m = 2e-3;
        let out = fair_surface(
            &s,
            SurfaceFairingOptions {
                region: Some(((0.2, 0.8), (0.1, 0.9))),
                tolerance: m,
                ..Default::default()
            },
        )
        .unwrap();
        let (dev, _) = deviation(&s, &out.surface, 61);
        assert!(dev <= m * (1.0 + 1e-9));
        assert!(!out.free_u.is_empty() && !out.free_v.is_empty());
        // rational with unequal weights: a clear error
        let mut w = vec![1.0; nu * nv];
        w[7] = 2.0;
        let rs = BSplineSurface::try_new(
            4,
            2,
            s.knots_u().values().to_vec(),
            s.knots_v().values().to_vec(),
            nu,
            nv,
            s.points().to_vec(),
            Some(w),
        )
        .unwrap();
        let e = fair_surface(&rs, SurfaceFairingOptions::default()).unwrap_err();
        assert!(e.to_string().contains("rational"), "{e}");
        // equal weights: converted, and faired exactly like the non-rational surface
        let rs = BSplineSurface::try_new(
            4,
            2,
            s.knots_u().values().to_vec(),
            s.knots_v().values().to_vec(),
            nu,
            nv,
            s.points().to_vec(),
            Some(vec![2.5; nu * nv]),
        )
        .unwrap();
        assert!(rs.is_rational());
        let opts = SurfaceFairingOptions {
            region: Some(((0.2, 0.8), (0.1, 0.9))),
            tolerance: m,
            ..Default::default()
        };
        let fr = fair_surface(&rs, opts).unwrap();
        assert!(!fr.surface.is_rational());
        assert_eq!(fr.surface.points(), out.surface.points());
        // bad requests
        assert!(
            fair_surface(
                &s,
                SurfaceFairingOptions {
                    tolerance: -1.0,
                    ..Default::default()
                }
            )
            .is_err()
        );
        let tiny = SurfaceFairingOptions {
            region: Some(((0.5, 0.52), (0.1, 0.9))),
            ..Default::default()
        };
        assert!(matches!(fair_surface(&s, tiny), Err(Error::InvalidInput(_))));
    }

    #[test]
    fn the_result_does_not_depend_on_the_thread_count() {
        let exact = graph(12, |u, v| 0.2 * (3.0 * u).sin() * (2.0 * v).cos());
        let s = noisy(&exact, 1e-3, 11);
        let run = |threads| {
            fair_surface(
                &s,
                SurfaceFairingOptions {
                    tolerance: 3e-3,
                    region: Some(((0.1, 0.95), (0.0, 0.8))),
                    threads: Some(threads),
                    ..Default::default()
                },
            )
            .unwrap()
        };
        let one = run(1);
        assert!(one.surface.points() != s.points(), "the fairing moved nothing");
        for t in [2, 3, 7] {
            assert_eq!(run(t).surface.points(), one.surface.points(), "{t} threads");
        }
    }

    /// An `n × n` bicubic net with uniform knots over `pts` (row-major in u).
    fn uniform_net(n: usize, pts: Vec<DVec3>) -> BSplineSurface {
        let k = KnotVector::uniform(3, n).unwrap();
        BSplineSurface::try_new(3, 3, k.values().to_vec(), k.values().to_vec(), n, n, pts, None).unwrap()
    }

    /// The points of an `n × n` net with u and v swapped.
    fn transposed(pts: &[DVec3], n: usize) -> Vec<DVec3> {
        (0..n).flat_map(|j| (0..n).map(move |i| pts[i * n + j])).collect()
    }

    /// Fair the whole of `s` at `m` (default options); the reported and the measured deviation hold the band.
    fn fair_whole_checked(s: &BSplineSurface, m: f64, name: &str) -> SurfaceFairingResult {
        let r = fair_surface(
            s,
            SurfaceFairingOptions {
                tolerance: m,
                ..Default::default()
            },
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        let (dev, _) = deviation(s, &r.surface, 41);
        assert!(
            r.max_deviation <= m && dev <= m * (1.0 + 1e-9),
            "{name}: {} / {dev} > {m}",
            r.max_deviation
        );
        r
    }

    /// A surface of revolution (a paraboloid over 0.8 of a turn) with its pole at u = 0: every control point
    /// of row 0 is the apex. The pole row and the two after it stay (bit for bit, so the pole stays one point
    /// with its tangent plane), the isocurve through the pole is left as it is instead of failing, the band
    /// holds, and the rest is faired. (Before: "fairing the v-isocurve at u = 0: degenerate geometry: the
    /// region [0, 1] has zero length".) The same with the pole at u = 1, and at v = 0 (transposed net).
    #[test]
    fn a_pole_stays_one_point_and_the_rest_is_faired() {
        let n = 16;
        let k = KnotVector::uniform(3, n).unwrap();
        let g = k.greville();
        let mut rng = Rng(29);
        let mut exact_pts = Vec::new();
        let mut noisy_pts = Vec::new();
        for &r in &g {
            for &t in &g {
                let a = 0.8 * std::f64::consts::TAU * t;
                let p = DVec3::new(r * a.cos(), r * a.sin(), 0.5 * r * r);
                exact_pts.push(p);
                let z = if r > 0.0 { 1.5e-3 * rng.normal() } else { 0.0 };
                noisy_pts.push(p + DVec3::new(0.0, 0.0, z));
            }
        }
        let (exact, s) = (uniform_net(n, exact_pts), uniform_net(n, noisy_pts));
        // the pole at u = 0, at u = 1 (rows reversed) and at v = 0 (transposed)
        let flip_u = |pts: &[DVec3]| {
            (0..n)
                .rev()
                .flat_map(|i| pts[i * n..(i + 1) * n].to_vec())
                .collect::<Vec<_>>()
        };
        let net = |pts: Vec<DVec3>| uniform_net(n, pts);
        let cases = [
            ("pole at u = 0", exact.clone(), s.clone()),
            ("pole at u = 1", net(flip_u(exact.points())), net(flip_u(s.points()))),
            (
                "pole at v = 0",
                net(transposed(exact.points(), n)),
                net(transposed(s.points(), n)),
            ),
        ];
        let m = 4.5e-3;
        for (name, exact, s) in cases {
            let r = fair_whole_checked(&s, m, name);
            // the held rows (or columns) next to the pole: bit for bit
            let held = |i: usize, j: usize| match name {
                "pole at u = 0" => i < POLE_ROWS,
                "pole at u = 1" => i >= n - POLE_ROWS,
                _ => j < POLE_ROWS,
            };
            let (a, b) = (s.points(), r.surface.points());
            for i in 0..n {
                for j in 0..n {
                    if held(i, j) {
                        assert_eq!(a[i * n + j], b[i * n + j], "{name}: control point ({i}, {j}) moved");
                    }
                }
            }
            assert!(a != b, "{name}: nothing was faired");
            // a region of 3 spans at the pole: its 3 movable rows are the held ones
            if name == "pole at u = 0" {
                let small = SurfaceFairingOptions {
                    tolerance: m,
                    region: Some(((0.0, 3.0 / 13.0), (0.0, 1.0))),
                    ..Default::default()
                };
                assert_eq!(
                    fair_surface(&s, small).unwrap_err().to_string(),
                    format!(
                        "region [0, {}] × [0, 1] holds no movable control point: its control rows are \
                         all among the 3 held next to a pole or the seam of a closed surface (widen the region away \
                         from it)",
                        3.0 / 13.0
                    )
                );
            }
            // RMS principal-curvature error against the noise-free net, 30 × 30 samples with the distance from
            // the pole (as a parameter of the pole's direction) in [d0, 0.9]: the held rows keep their noise
            // up to t_6 ≈ 0.23 (like the held strip along a region border), the rest is free
            let err = |x: &BSplineSurface, d0: f64| {
                curvature_error_on(x, &exact, |k, l| {
                    let (d, w) = (d0 + (0.9 - d0) * k as f64 / 29.0, 0.1 + 0.8 * l as f64 / 29.0);
                    match name {
                        "pole at u = 0" => (d, w),
                        "pole at u = 1" => (1.0 - d, w),
                        _ => (w, d),
                    }
                })
            };
            let (e0, e1) = (err(&s, 0.1), err(&r.surface, 0.1));
            let (f0, f1) = (err(&s, 0.3), err(&r.surface, 0.3));
            eprintln!("{name}: curvature error {e0:.4} -> {e1:.4}, away from the pole {f0:.4} -> {f1:.4}");
            assert!(e1 < e0, "{name}: curvature error {e0} -> {e1}");
            assert!(f1 < 0.6 * f0, "{name}: curvature error away from the pole {f0} -> {f1}");
        }
    }

    #[test]
    fn a_surface_that_is_one_point_is_refused() {
        let k = KnotVector::uniform(3, 8).unwrap();
        let s = BSplineSurface::try_new(
            3,
            3,
            k.values().to_vec(),
            k.values().to_vec(),
            8,
            8,
            vec![DVec3::ONE; 64],
            None,
        )
        .unwrap();
        let e = fair_surface(&s, SurfaceFairingOptions::default()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "degenerate geometry: all control points of the surface coincide (a single point): there is no shape to fair"
        );
    }

    /// The ridge's tangent break on the u-isocurve of `s` at v (degrees; 0 if none at u = 0.5).
    fn ridge_angle(s: &BSplineSurface, v: f64) -> f64 {
        crate::corners::corners(&s.iso_u(v), 0.0, 1.0)
            .iter()
            .find(|k| k.u == 0.5)
            .map_or(0.0, |k| k.angle_deg)
    }

    /// A crease (a character line: the u-knot 0.5 triple, the tangent plane breaking by ≈ 53° across it) is
    /// kept by the fit on the original knots: the faired surface still breaks there, by the same angle to
    /// within 1° all along the line (measured ≤ 0.71° over seeds 3–6, 11 samples along the line), and both
    /// sides are faired. Rows next to the crease carry no noise here (a modelled crease); with noise on them
    /// too, the angle changes by up to 4.1° (that noise wiggles the crease angle along the line by 4.5–5.9°;
    /// the fair evens it out to 0.4–1.3°).
    ///
    /// Measured and not kept (session 13): fairing the two sides as separate regions, the crease row held and
    /// the isocurves ending G1 there (as the curve engine does at a kink), changed the angle by up to 2.8°
    /// on these clean-neighbour roofs, evened it out less (spread 1.5–3.6°) and left ∫∫|∇H|² within 0.1 of the
    /// crease 1.8–7× higher; also holding the rows next to the crease kept the angle exactly but left the sides
    /// 3–7× less fair (their noise stays).
    #[test]
    fn a_crease_is_kept_by_the_fit_on_the_original_knots() {
        let m = 3e-3;
        for seed in [3, 6] {
            let ku = vec![
                0.0, 0.0, 0.0, 0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.5, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.0, 1.0, 1.0,
            ];
            let kv = KnotVector::uniform(3, 12).unwrap();
            let gu = KnotVector::try_new(ku.clone(), 3, ku.len() - 4, "u")
                .unwrap()
                .greville();
            let gv = kv.greville();
            let k = gu.iter().position(|&x| x == 0.5).unwrap();
            let mut rng = Rng(seed);
            let mut pts = vec![];
            for (i, &x) in gu.iter().enumerate() {
                for &y in &gv {
                    // a ridge along u = 0.5 on a gently curved roof; noise off the crease and its neighbours
                    let z = 0.25 * (1.0 - (2.0 * x - 1.0).abs()) + 0.1 * (std::f64::consts::PI * y).sin();
                    let noise = if i + 1 >= k && i <= k + 1 {
                        0.0
                    } else {
                        1e-3 * rng.normal()
                    };
                    pts.push(DVec3::new(x, y, z + noise));
                }
            }
            let s = BSplineSurface::try_new(3, 3, ku, kv.values().to_vec(), gu.len(), gv.len(), pts, None).unwrap();
            let r = fair_surface(
                &s,
                SurfaceFairingOptions {
                    tolerance: m,
                    ..Default::default()
                },
            )
            .unwrap();
            let (dev, _) = deviation(&s, &r.surface, 60);
            assert!(dev <= m * (1.0 + 1e-6), "seed {seed}: {dev}");
            for i in 0..=10 {
                let v = i as f64 / 10.0;
                let (a0, a1) = (ridge_angle(&s, v), ridge_angle(&r.surface, v));
                assert!(
                    a0 > 45.0 && (a1 - a0).abs() < 1.0,
                    "seed {seed}, v = {v}: crease angle {a0}° -> {a1}°"
                );
            }
            for side in [(0.0, 0.5), (0.5, 1.0)] {
                let rect = (side, (0.0, 1.0));
                let e = |x: &BSplineSurface| crate::measure_surface::mean_curvature_variation_in(x, rect);
                let (before, after) = (e(&s), e(&r.surface));
                assert!(
                    after < 0.5 * before,
                    "seed {seed}, u in {side:?}: ∫∫|∇H|² {before} -> {after}"
                );
            }
        }
    }

    /// A pinch inside the domain (a collapsed control row at a triple knot: the isocurve there is a point, but
    /// its neighbours are free) is refused as before, not faired: only boundary poles are held.
    #[test]
    fn a_pinch_inside_the_domain_is_refused() {
        let ku = vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0];
        let kv = KnotVector::uniform(3, 10).unwrap();
        let mut rng = Rng(5);
        let mut pts = Vec::new();
        for i in 0..7 {
            let r = (i as f64 - 3.0).abs() / 3.0;
            for j in 0..10 {
                let a = 1.5 * j as f64 / 9.0;
                let z = if i == 3 { 0.0 } else { 1e-3 * rng.normal() };
                pts.push(DVec3::new(r * a.cos(), r * a.sin(), (i as f64 - 3.0) / 3.0 + z));
            }
        }
        let s = BSplineSurface::try_new(3, 3, ku, kv.values().to_vec(), 7, 10, pts, None).unwrap();
        let e = fair_surface(&s, SurfaceFairingOptions::default())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "fairing the v-isocurve at u = 0.5: degenerate geometry: the region [0, 1] has zero length (coincident \
             control points)"
        );
    }

    /// A closed surface (a full turn of a paraboloid of revolution, r ∈ [0.3, 1]: the first and last control
    /// columns coincide) stays closed: the three columns at each side of the seam stay bit for bit, the band
    /// holds, and away from the seam the curvature error against the noise-free surface drops. (Before, the
    /// two sides were faired independently and the seam opened by 2.4e-3 at m = 3e-3.) Also with the seam in u
    /// (transposed net).
    #[test]
    fn a_closed_surface_stays_closed_at_its_seam() {
        let n = 16;
        let k = KnotVector::uniform(3, n).unwrap();
        let g = k.greville();
        let mut rng = Rng(31);
        let (mut exact_pts, mut noisy_pts) = (Vec::new(), Vec::new());
        for &t in &g {
            let r = 0.3 + 0.7 * t;
            let mut first = DVec3::ZERO;
            for (j, &w) in g.iter().enumerate() {
                let a = std::f64::consts::TAU * w;
                let p = DVec3::new(r * a.cos(), r * a.sin(), 0.5 * r * r);
                exact_pts.push(p);
                // the same noise on both sides of the seam: the input is closed
                let q = if j + 1 < n {
                    p + DVec3::new(0.0, 0.0, 1.5e-3 * rng.normal())
                } else {
                    first
                };
                if j == 0 {
                    first = q;
                }
                noisy_pts.push(q);
            }
        }
        let (exact, s) = (uniform_net(n, exact_pts), uniform_net(n, noisy_pts));
        let net = |pts: Vec<DVec3>| uniform_net(n, pts);
        let cases = [
            ("seam in v", exact.clone(), s.clone()),
            (
                "seam in u",
                net(transposed(exact.points(), n)),
                net(transposed(s.points(), n)),
            ),
        ];
        let m = 4.5e-3;
        for (name, exact, s) in cases {
            let r = fair_whole_checked(&s, m, name);
            let (a, b) = (s.points(), r.surface.points());
            // (i, j) of the net with the seam direction second
            let at = |i: usize, j: usize| if name == "seam in v" { i * n + j } else { j * n + i };
            for i in 0..n {
                assert_eq!(b[at(i, 0)], b[at(i, n - 1)], "{name}: the seam opened at row {i}");
                for j in (0..POLE_ROWS).chain(n - POLE_ROWS..n) {
                    assert_eq!(
                        a[at(i, j)],
                        b[at(i, j)],
                        "{name}: control point ({i}, {j}) next to the seam moved"
                    );
                }
            }
            assert!(a != b, "{name}: nothing was faired");
            // curvature error on the half turn opposite the seam (the seam direction's parameter in [0.25, 0.75])
            let err = |x: &BSplineSurface| {
                curvature_error_on(x, &exact, |k, l| {
                    let (d, w) = (0.1 + 0.8 * k as f64 / 29.0, 0.25 + 0.5 * l as f64 / 29.0);
                    if name == "seam in v" { (d, w) } else { (w, d) }
                })
            };
            let (e0, e1) = (err(&s), err(&r.surface));
            eprintln!("{name}: curvature error away from the seam {e0:.4} -> {e1:.4}");
            assert!(e1 < 0.6 * e0, "{name}: curvature error {e0} -> {e1}");
        }
    }
}
