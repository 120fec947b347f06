//! The options of a curve fairing: end conditions, fit modes, polish methods, and their defaults.

use crate::error::{Error, Result};
use crate::fair::integrate::Integrator;
use crate::fair::target::TargetMethod;

/// Continuity at the region ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum EndCondition {
    /// Position only.
    G0,
    /// Position and tangent.
    G1,
    /// Position, tangent and curvature (default).
    #[default]
    G2,
}

impl EndCondition {
    /// The weaker (lower order) of `self` and `other`.
    pub fn min_by_order(self, other: Self) -> Self {
        if other.order() < self.order() { other } else { self }
    }

    /// The order of geometric continuity: 0, 1 or 2.
    pub fn order(self) -> usize {
        match self {
            Self::G0 => 0,
            Self::G1 => 1,
            Self::G2 => 2,
        }
    }
}

impl std::str::FromStr for EndCondition {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "g0" => Ok(Self::G0),
            "g1" => Ok(Self::G1),
            "g2" => Ok(Self::G2),
            _ => Err(Error::InvalidInput(format!(
                "unknown end condition {s:?}: expected g0, g1 or g2"
            ))),
        }
    }
}

impl PolishMethod {
    /// The name `fairway fair --polish-method` takes and its report writes.
    pub fn name(self) -> &'static str {
        match self {
            Self::LineSearch => "line-search",
            Self::InteriorPoint => "interior-point",
            Self::Variation => "variation",
        }
    }
}

impl std::str::FromStr for PolishMethod {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "line-search" | "ls" => Ok(Self::LineSearch),
            "interior-point" | "ip" => Ok(Self::InteriorPoint),
            "variation" => Ok(Self::Variation),
            _ => Err(Error::InvalidInput(format!(
                "unknown polish method {s:?}: expected variation, line-search or interior-point"
            ))),
        }
    }
}

/// Which fit follows the integration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum FitMode {
    /// Tangent pull-back, fairness term, hard band (default).
    #[default]
    Fairway,
    /// The paper as published: position pull-back, plain least squares, soft band.
    Paper,
    /// The reference smoother: knot-keeping penalized least squares, no target and no integration —
    /// `Σ_k |c(p_k) − c₀(p_k)|² + λ ∫ |c'''|² du` over the free points (the data the original's
    /// equal-arc samples), with the largest λ whose result holds the verified band. What a SciPy user
    /// does by hand (a smoothing spline with a search on its weight); the peer every fair is judged
    /// against, and a method of its own (`fairway fair --method smoothing`).
    Smoothing,
}

/// Options of a curve fairing. Built from the defaults with one setter a field (the struct is
/// `#[non_exhaustive]`, so that a new option is not a breaking change):
///
/// ```
/// use fairway::fair::{EndCondition, FairingOptions};
/// let opts = FairingOptions::default().tolerance(0.01).region(Some((0.2, 0.8))).ends(EndCondition::G1);
/// assert_eq!((opts.tolerance, opts.ends), (0.01, EndCondition::G1));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct FairingOptions {
    /// Region `[u1, u2]` in the curve's parameter (`None`: the whole curve).
    pub region: Option<(f64, f64)>,
    /// Tolerance m (> 0): max deviation from the original.
    pub tolerance: f64,
    /// Continuity at the region ends.
    pub ends: EndCondition,
    /// Target smoothing method.
    pub target: TargetMethod,
    /// Smoothing strength (passes, or the flow time in passes for `Heat`; `None`: [`default_passes`] for
    /// heat, average and binomial, 20 for the fit).
    pub strength: Option<usize>,
    /// Integration scheme.
    pub integrator: Integrator,
    /// Number of samples (`None`: 10 per knot span of the moving stretch, at least 41).
    pub samples: Option<usize>,
    /// Fit mode.
    pub mode: FitMode,
    /// After the band search, polish the paper's E by Gauss–Newton steps inside the band
    /// (Fairway mode; default on; the surface engine's isocurves turn it off).
    pub polish: bool,
    /// Gauss–Newton iterations of that polish at most ([`POLISH_ITERS`] by default; it stops earlier
    /// when a step gains < 0.02 % of E). More lower E further inside the band at more cost: on the
    /// benchmark curve (100 control points, 1000 samples) 8 / 24 give E 537 / 259 (the iterative
    /// baseline 265) at about three times the cost (docs/PERFORMANCE.md).
    /// 0 is the same as `polish: false`.
    pub polish_iterations: usize,
    /// Ease the target into a G2 *curve* end over the end knot span (default off). A curve end has no
    /// neighbour, so G2 keeps the original's own end curvature, which on a curve fitted to noisy points
    /// is often far off (the end knot span has the fewest points to fix it). By default the smoothed
    /// target climbs to that value from deep inside and the faired curve dips to compensate; eased, the
    /// target is smoothed as at a free end and joins the kept value within the end knot span
    /// ([`Target::ease_end`](crate::fair::target::Target::ease_end)). For ends whose curvature is noise: on noisy circle and clothoid arcs
    /// (8 seeds each) it halves the curvature error and the extra extrema (circle Σ extrema 74 → 36),
    /// on the ellipse arc it removes a few extrema at about the same error. Where the end curvature is
    /// real it can add wiggles near the ends, since the held end points leave little freedom to follow
    /// a steep target there: on the sample car roof and spatial curve at m = 5e-3, extrema 12 → 18 and
    /// 8 → 22 (at m = 2e-3 10 → 10 and 10 → 8). An option to compare, not a default. No effect on
    /// region ends inside the curve (they join real neighbours), on G0/G1 ends, or on closed curves.
    pub ease_curve_ends: bool,
    /// How the polish minimizes E inside the band (default [`PolishMethod::LineSearch`]).
    pub polish_method: PolishMethod,
    /// Continuity kept at the start (`[0]`) and at the end (`[1]`) of an *open* curve's domain where the
    /// region reaches it (`None`, the default: the weaker of the region end's condition and G1 — position
    /// and tangent, not the curvature). A free curve end has no neighbour, and on a curve fitted to noisy
    /// points its end curvature is mostly noise: kept, the fair has to bend towards it and adds curvature
    /// extrema there. `Some(G2)` keeps it: a curve end that joins another curve with G2, while its other,
    /// free end keeps the default. Region ends inside the curve and closed curves always take `ends`.
    pub curve_ends: [Option<EndCondition>; 2],
    /// Non-planar 3D curves, [`PolishMethod::Variation`]: weight of the torsion variation
    /// `∫ (d(κ²τ)/ds)² ds / κ_max⁴` in the objective, next to E_var, which does not see the torsion and
    /// leaves it to the noise (`curve/torsion.rs`; 0 turns it off). Default [`TORSION_WEIGHT`] (1). On the
    /// quality suite's five 3D curves (Σ over their 15 rows, `examples/quality_table.rs` with
    /// `QT_TORSION`): torsion extrema 712 without it, 417 with it, the reference smoother 451; curvature
    /// extrema no more than the smoother's in every row. Where the result is not fairer in curvature than
    /// the polish's start, the polish runs again without it and keeps the fairer curvature.
    pub torsion_weight: f64,
    /// β of [`PolishMethod::Variation`]: how strongly the curvature follows the target against the
    /// curvature variation.
    pub target_weight: f64,
}

/// The optimizer of the E polish ([`FairingOptions::polish_method`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum PolishMethod {
    /// Levenberg–Marquardt steps on the paper's E with the band-edge samples frozen and a backtracking band
    /// check (the default before [`PolishMethod::Variation`]). It stops well short of E's minimum in the
    /// band, on purpose: the automatic target is smoothed from noisy curvature and flattens sharp
    /// features, and a result that follows it closely is not a more accurate curve (on the noisy closed
    /// ellipses of the closed-curve tests the curvature error against the noise-free curve rises above
    /// the input's).
    LineSearch,
    /// Primal–dual interior point on the parametric band, the iterative baseline's band
    /// (`FairingSetup::polish_interior`): every iterate holds the band, and a few iterations reach a
    /// lower E than the baseline (bench curve: E 242 after 3 iterations, the baseline 265, the line
    /// search 537 after its 8). For a target that is right — typed in, pinned, or hand-shaped — it
    /// follows it as closely as the band allows.
    InteriorPoint,
    /// Interior point on `∫ (dκ/ds)² ds + β ∫ (κ − g)² ds / ℓ²` inside the parametric band: the curvature
    /// variation of the whole stretch (quadrature over every knot span, so ripples between samples
    /// count) plus the distance from the target g, with ℓ the mean arc length of a knot span and β
    /// [`FairingOptions::target_weight`]. Started from the fairest of the band-holding fit, the reference
    /// smoother's result ([`FitMode::Smoothing`]) and the original; iterates ranked by curvature extrema,
    /// then E_var; the original is returned unless the result is fairer.
    /// The default.
    #[default]
    Variation,
}

impl Default for FairingOptions {
    fn default() -> Self {
        Self {
            region: None,
            tolerance: 1e-3,
            ends: EndCondition::G2,
            target: TargetMethod::Heat,
            strength: None,
            integrator: Integrator::Arc,
            samples: None,
            mode: FitMode::Fairway,
            polish: true,
            polish_iterations: POLISH_ITERS,
            ease_curve_ends: false,
            polish_method: PolishMethod::Variation,
            target_weight: 0.1,
            curve_ends: [None; 2],
            torsion_weight: TORSION_WEIGHT,
        }
    }
}

/// One setter a field, `fn field(self, value) -> Self`, for the options structs that are
/// `#[non_exhaustive]`.
macro_rules! setters_for {
    ($t:ty { $($field:ident: $ty:ty),* $(,)? }) => {
        impl $t {
            $(
                #[doc = concat!("These options with `", stringify!($field), "` set to `value`.")]
                #[must_use]
                pub fn $field(mut self, value: $ty) -> Self {
                    self.$field = value;
                    self
                }
            )*
        }
    };
}
pub(crate) use setters_for;

setters_for!(FairingOptions {
    region: Option<(f64, f64)>,
    tolerance: f64,
    ends: EndCondition,
    target: TargetMethod,
    strength: Option<usize>,
    integrator: Integrator,
    samples: Option<usize>,
    mode: FitMode,
    polish: bool,
    polish_iterations: usize,
    ease_curve_ends: bool,
    polish_method: PolishMethod,
    curve_ends: [Option<EndCondition>; 2],
    torsion_weight: f64,
    target_weight: f64,
});

/// Gauss–Newton iterations of the E polish after the band search.
pub const POLISH_ITERS: usize = 8;

/// The default [`FairingOptions::torsion_weight`].
pub const TORSION_WEIGHT: f64 = 1.0;

/// Default number of smoothing passes for `n` samples: a three-point average
/// repeated P times is close to a Gaussian of variance 2P/3 samples²; the
/// default aims at σ ≈ 6 % of the stretch (the reference measures' moving
/// average spans 10 %), capped at 10000 passes.
pub fn default_passes(n: usize) -> usize {
    let sigma = 0.06 * n as f64;
    ((1.5 * sigma * sigma).round() as usize).clamp(1, 10000)
}
