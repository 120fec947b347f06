//! The fast, local fairing of one B-spline curve (paper §3.1), with a hard
//! tolerance band.
//!
//! # Algorithm
//!
//! [`FairingSetup::new`] prepares everything that does not depend on the
//! target or the tolerance; [`FairingSetup::fair`] runs the cheap part and
//! can be called again after the [`Target`] or the tolerance changed.
//!
//! 1. **Free control points.** Only control points whose support
//!    `[t_i, t_{i+p+1}]` lies inside the region `[u1, u2]` move. They are
//!    exactly the points whose change leaves the curve outside the region
//!    unchanged, and since the knot vector is kept, the faired stretch meets
//!    its neighbours with the curve's own continuity at `u1`, `u2` (C2 for a
//!    cubic with simple knots, hence **G2**). Where the knots give less (a
//!    quadratic's simple knots, a cubic's double knot: C1; a p-fold knot: C0)
//!    the first / last free points are constrained instead: the first moves
//!    along the join's tangent only (C1 knot at G2, C0 knot at G1), or stays
//!    and the next one moves along the tangent (C0 knot at G2). That keeps the
//!    faired side's tangent and curvature at the join equal to the original's
//!    (G2 wherever the original is G2 there). End options:
//!    * `G1` / `G0` at an interior region end: the end is first inserted as a
//!      knot up to multiplicity `p − 1` / `p` (Boehm, the curve is unchanged),
//!      which frees one / two more control points and leaves C1 / C0 at the
//!      join; the result then has those extra knots.
//!    * At an end of the curve's domain the first / last 3 (G2), 2 (G1) or 1
//!      (G0) control points are kept, so end point, end tangent and end
//!      curvature stay. One pass treats the seam of a closed curve (first
//!      point = last point) the same way: the seam keeps its original G2
//!      state and shape, unfaired ([`FairingResult::seam`] is
//!      [`Seam::Held`]). [`fair_curve`](crate::fair::fair_curve) (and `fairway fair`) fairs a whole
//!      closed curve across the seam instead, by re-seaming and a second
//!      pass ([`super::closed::fair_closed`]).
//!
//!    The moving stretch `[a, b]` is the union of the free points' supports.
//! 2. **Samples.** n points at equal arc length over `[a, b]`
//!    ([`ArcLengthTable`](crate::arclength::ArcLengthTable)): parameters `p_k`, points `f_k`, unit tangents,
//!    normals, curvature κ_k, speed `v = |c'|` and `v' = c'·c''/v`. In 3D the
//!    curvature is signed along a sign-consistent principal normal: the
//!    normal is flipped whenever it would turn by more than 90° from the
//!    previous sample, and carried over (projected on the normal plane)
//!    where κ ≈ 0, so the target does not fold at inflections. The paper's
//!    E = Σ (κ_k − g_k)² then reads Σ (κN·n_k − g_k)² + (κN·b_k)² in 3D
//!    (b = t × n): the curvature that leaves the osculating plane counts too
//!    (`FairingSetup::residual_sq`).
//! 3. **Target** g ([`Target`]), ends pinned to the original κ at G2 ends and
//!    free (smoothed like the interior) at G1 / G0 ends, whose curvature is not kept.
//! 4. **Integration** from both ends, blended ([`super::integrate`]), with
//!    the pull-back term; in [`FitMode::Fairway`] the tangent is pulled back too.
//! 5. **Fit** with the original knots and the original parameters `p_k`.
//!    Writing the result as `c = c_orig + Σ_{i free} N_i ΔP_i`, Fairway
//!    minimizes
//!
//!    `Σ_k |c(p_k) − y_k|² + λ Σ_k |c''(p_k) − a_k|²`,
//!    `a_k = v'_k T̃_k + v_k² g_k Ñ_k`,
//!
//!    where y_k are the integrated points and T̃, Ñ their tangent / normal:
//!    `a_k` is the second parametric derivative a curve with the original
//!    speed profile and curvature exactly g would have, so the second term is
//!    the paper's E linearized — a fairness term that is zero for a curve
//!    already on target (a circle stays a circle) and damps the wiggles the
//!    plain fit of integrated points re-injects. Both terms are banded
//!    (bandwidth p) and are assembled once; for a given λ the system costs
//!    one banded Cholesky, O(n_free p²).
//! 6. **Hard band.** λ = μ·Δu⁴ (Δu the mean parameter step of the samples,
//!    so μ = 1 weighs a position error like its second difference). The
//!    largest μ ∈ [1e-6, 1e10] whose result holds the band is taken (bisection
//!    in log μ); if even the smallest fails, the update is scaled,
//!    `ΔP ← α ΔP` with α bisected in [0, 1] (α = 0 is the original, so a
//!    positive tolerance can always be met; the result reports α). The band
//!    is verified on the 2000 arc-length samples of the original that
//!    `measure` uses: `|c(u_j) − c_orig(u_j)|` bounds the closest-point
//!    distance from above; where it exceeds m, a Newton projection near u_j
//!    gives a sharper (still upper) bound. So the reported
//!    `max_deviation ≥` the measured `dev_max`, and it is `≤ m`. The band
//!    checks stop each projection as soon as it is inside the band; the
//!    reported value is sharpened once at the end (the sample with the
//!    largest bound is projected further — Newton, then `measure`'s search
//!    near u_j, then over the whole curve — until a fully searched sample is
//!    the largest): it equals the measured `dev_max` to rounding.
//! 7. **Polish** inside the band ([`FairingOptions::polish`], up to
//!    [`FairingOptions::polish_iterations`] steps). The default, [`PolishMethod::Variation`]
//!    (`fair/curve/variation.rs`), minimizes the curvature variation ∫(dκ/ds)² ds plus a mild target term by an
//!    interior point from the fairest of the fit, the reference smoother ([`FitMode::Smoothing`]) and
//!    the original, inside the convex hull of the difference curve (`fair/curve/hull.rs`: the band held
//!    everywhere, not only at the check samples). The paper's E can be polished instead, by one of two optimizers
//!    ([`PolishMethod`]): Levenberg–Marquardt steps with a backtracking band
//!    check (which stops well short of E's minimum), or a
//!    primal–dual interior point on the parametric band at the check samples
//!    (every iterate holds the band; it follows the target as closely as the
//!    band allows: on the bench curve a lower E than the iterative baseline's
//!    after 3 iterations).
//!
//! [`FitMode::Paper`] is the faithful reproduction for comparisons:
//! position-only pull-back, plain least squares (λ = 0), no verification
//! (its `max_deviation` is the band check's bound, not sharpened).

use glam::DVec3;

use super::integrate::{IntegrationScratch, Integrator, PullBack, Track, integrate_blended};
use super::target::Target;
use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::linalg::BandedSpd;

mod check;
mod energy;
mod fit;
mod hull;
mod options;
pub(crate) use options::setters_for;
mod polish;
mod region;
mod setup;
mod torsion;
mod variation;
use check::ChkDeriv;
pub(crate) use check::{band_accept, project_near};
pub use options::{EndCondition, FairingOptions, FitMode, POLISH_ITERS, PolishMethod, TORSION_WEIGHT, default_passes};
pub use setup::MAX_SAMPLES;
pub(crate) use setup::{CHECK_SAMPLES, CHECK_SAMPLES_PER_SPAN, MAX_PASS_WORK};
pub(crate) use setup::{SLIVER_SNAP, snap_to_knot};
use variation::VarRows;

/// What happened at the seam of a closed curve.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Seam {
    /// The curve is not closed (first and last points differ by more than [`closed_tolerance`](crate::curve::closed_tolerance)).
    #[default]
    Open,
    /// A closed curve whose moving stretch does not reach the seam.
    Untouched,
    /// A closed curve whose seam control points were held (the first and last three for G2): the seam
    /// keeps the original's shape there. The text says why.
    Held(String),
    /// A closed curve faired across the seam by re-seaming (module docs): every control point
    /// moved as needed, C^{p−1} across the seam like the original (C2 for a cubic, C1 for a quadratic).
    Faired,
}

/// The outcome of [`FairingSetup::fair`].
#[derive(Debug, Clone, PartialEq)]
pub struct FairingResult {
    /// The faired curve (original knots; with G0/G1 ends the inserted knots too).
    pub curve: BSplineCurve,
    /// Sound upper bound of the distance from every point of the original to the result
    /// ([`super::verify::band_bound`]: the check samples, and an interpolation bound between points
    /// sampled per knot span), sharp to about 0.1 % of the largest distance found; never below
    /// `measure`'s `dev_max`. With `check_samples = 0` (surface isocurves, which the surface verifies
    /// itself) it is the band checks' bound at the samples.
    pub max_deviation: f64,
    /// Fairness weight μ chosen (0 in paper mode).
    pub mu: f64,
    /// Scale α of the update (1 unless the band forced a partial step).
    pub alpha: f64,
    /// Number of linear solves.
    pub solves: usize,
    /// The paper's E = Σ (κ(p_k) − g_k)² at the sample parameters.
    pub energy: f64,
    /// What happened at the seam of a closed curve (see [`Seam`]): a single pass of
    /// [`FairingSetup`] holds it; [`fair_curve`](crate::fair::fair_curve) on a whole closed curve fairs across it, or says
    /// why it could not.
    pub seam: Seam,
    /// What the fair left as it was, and why: one line per stretch between corners whose setup was
    /// refused (see [`super::split`]). Empty otherwise.
    pub notes: Vec<String>,
}

/// Fairs run again with a narrowed band when the result left the band between the check samples.
pub(crate) const BAND_RETRIES: usize = 3;

/// Prepared state of a curve fairing (see the module docs).
#[derive(Debug, Clone)]
pub struct FairingSetup {
    input: BSplineCurve,
    work: BSplineCurve,
    opts: FairingOptions,
    i0: usize,
    nf: usize,
    range: (f64, f64),
    // samples
    params: Vec<f64>,
    pts: Vec<DVec3>,
    tangents: Vec<DVec3>,
    normals: Vec<DVec3>,
    d1: Vec<DVec3>,
    d2: Vec<DVec3>,
    speed: Vec<f64>,
    dspeed: Vec<f64>,
    h: f64,
    du: f64,
    // basis of the free points at the samples: first free-local index, values, second derivatives
    first: Vec<isize>,
    b0: Vec<f64>,
    b1: Vec<f64>,
    b2: Vec<f64>,
    a0: BandedSpd,
    a2: BandedSpd,
    /// `∫ |N_i'''|·|N_j'''| du` of the free points and `−∫ c₀''' N_i'''`: the reference smoother's penalty.
    a3: BandedSpd,
    rhs3: Vec<DVec3>,
    /// The quadrature rows of the variation energy `∫ (dκ/ds)² ds` ([`variation`]).
    var: VarRows,
    /// Rows at the curvature probes of the extrema count ([`variation::PROBES`] a span).
    probes: VarRows,
    /// The μ search solves the smoother's system (`A0 + λ A3`, data term the original) instead of the fit's.
    smoothing_system: bool,
    /// After the band's largest μ, step μ down while the fit's E falls (`fit::finish_mu_fairest`); on
    /// unless [`Self::set_fairest_mu`] turned it off.
    fairest_mu: bool,
    /// λ / μ of the smoother ([`Self::lambda_scale`]).
    a3_scale: f64,
    /// `var`, `probes`, `a3`, `rhs3` and `a3_scale` are built (`setup::variation_rows`: only for a fair
    /// that reads them).
    var_rows_built: bool,
    /// μ of the last smoother search (its warm start).
    last_mu_smooth: Option<f64>,
    /// The variation polish's start candidates that do not depend on the target, kept for the next fair
    /// ([`polish::PolishCache`]).
    polish_cache: polish::PolishCache,
    // check samples
    chk_u: Vec<f64>,
    chk_q: Vec<DVec3>,
    chk_first: Vec<isize>,
    chk_b: Vec<f64>,
    /// Per check sample, filled when its band-edge projection first needs it (degree ≤ 3): see
    /// [`ChkDeriv`]. The polish and the μ search project the same few band-edge samples many times.
    chk_d: Vec<Option<ChkDeriv>>,
    chk_h: f64,
    /// Arc length of the original between consecutive check samples.
    chk_step: f64,
    /// Whether [`Self::fair`] bounds the band everywhere ([`super::verify::band_bound`]): with the
    /// measure's check samples; not with `check_samples = 0` (surface isocurves, which the surface
    /// verifies itself).
    sharp_report: bool,
    target: Target,
    // scratch
    scratch: IntegrationScratch,
    ys: Vec<DVec3>,
    ts: Vec<DVec3>,
    rhs0: Vec<DVec3>,
    rhs2: Vec<DVec3>,
    sol: Vec<DVec3>,
    best: Vec<DVec3>,
    m: BandedSpd,
    /// The paper's E of the update in `best` where the band search's last step computed it
    /// (`fit::finish_mu_fairest`), for the fit's E right after it (`fair_pass`); `None` otherwise.
    best_energy: Option<f64>,
    // μ of the last fair (warm start of the next)
    last_mu: Option<f64>,
    pad: Vec<DVec3>,
    seam: Seam,
    /// The check sample of the last band violation: the next scan starts there (a violated band is
    /// usually violated at the same place again, and a check stops at the first violation it finds).
    scan_from: usize,
    /// The band as the hull rows of the difference curve ([`hull::HullRows`]): the variation polish's
    /// constraints (built on its first run).
    hull_rows: hull::HullRows,
    /// Set while the interior point runs on the hull rows ([`Self::on_hull_rows`]).
    hull_band: bool,
    /// Free points (local index) constrained at a join whose knot is too multiple for the requested
    /// continuity to come by itself: `Some(T)` moves only along the join's tangent T, `None` not at
    /// all ([`Self::constrain_update`]).
    join_fix: Vec<(usize, Option<DVec3>)>,
    /// The unit normal of the plane of a planar 3D curve (control points within 1e-12 of its size of
    /// one plane): the update stays in that plane ([`Self::constrain_update`]).
    plane: Option<DVec3>,
    /// The original's signed curvature at the samples ([`Self::original_energy`]).
    kappa0: Vec<f64>,
    /// 3D: the binormal t × n of the setup's frame per sample, and the original's squared curvature along
    /// it (0 up to rounding: the frame's normal is the original's own curvature direction, except
    /// where it is transported). Empty in 2D. See [`Self::residual_sq`].
    binormals: Vec<DVec3>,
    perp0: Vec<f64>,
}

pub(crate) fn validate_tolerance(m: f64) -> Result<()> {
    if !(m.is_finite() && m > 0.0) {
        return Err(Error::BadTolerance { value: m });
    }
    Ok(())
}

impl FairingSetup {
    /// The seam state of this pass ([`Seam::Held`] when a closed curve's moving stretch reaches its seam).
    pub fn seam(&self) -> &Seam {
        &self.seam
    }

    /// The curve as given (non-rational).
    pub fn original(&self) -> &BSplineCurve {
        &self.input
    }

    /// The working curve: the input, with the G0/G1 knots inserted (same geometry).
    pub fn working_curve(&self) -> &BSplineCurve {
        &self.work
    }

    /// The (sign-consistent) unit normal at sample k.
    pub fn normal(&self, k: usize) -> DVec3 {
        self.normals[k]
    }

    /// The options.
    pub fn options(&self) -> &FairingOptions {
        &self.opts
    }

    /// Sample parameters p_k (equal arc length over the moving stretch).
    pub fn params(&self) -> &[f64] {
        &self.params
    }

    /// Arc-length step between samples.
    pub fn step(&self) -> f64 {
        self.h
    }

    /// The moving stretch `[a, b]` (union of the free points' supports).
    pub fn moving_range(&self) -> (f64, f64) {
        self.range
    }

    /// Indices of the free control points (in the working curve, which equals
    /// the input unless G0/G1 ends inserted knots).
    pub fn free_points(&self) -> std::ops::Range<usize> {
        self.i0..self.i0 + self.nf
    }

    /// The target curvature.
    pub fn target(&self) -> &Target {
        &self.target
    }

    /// The target, to edit (then call [`Self::fair`] again).
    pub fn target_mut(&mut self) -> &mut Target {
        &mut self.target
    }

    /// Cap the E polish at `n` Gauss–Newton iterations (default [`POLISH_ITERS`]; it stops earlier when
    /// a step gains < 0.02 % of E). More iterations lower E further inside the band at more cost
    /// (the later ones cost more: more samples sit at the band edge), e.g.
    /// to reach the iterative baseline's E on a curve where the default does not; 0 skips the polish.
    pub fn set_polish_iterations(&mut self, n: usize) {
        self.opts.polish_iterations = n;
    }

    /// Turn the E polish on or off ([`FairingOptions::polish`]; then call [`Self::fair`] again): a draft
    /// while a drag is in progress skips it, the release polishes, with the same setup.
    pub fn set_polish(&mut self, on: bool) {
        self.opts.polish = on;
    }

    /// Change how the E polish works ([`FairingOptions::polish_method`]; then call [`Self::fair`] again).
    pub fn set_polish_method(&mut self, method: PolishMethod) {
        self.opts.polish_method = method;
    }

    /// Change the tolerance (then call [`Self::fair`] again).
    pub fn set_tolerance(&mut self, m: f64) -> Result<()> {
        validate_tolerance(m)?;
        let size = self
            .work
            .points()
            .iter()
            .map(|p| p.abs().max_element())
            .fold(0.0, f64::max);
        crate::range::check_tolerance_at(m, size)?;
        self.opts.tolerance = m;
        Ok(())
    }

    /// Whether the fit's μ search, having found the largest band-holding μ, steps μ down while the fit's
    /// E falls (on by default: where the original's speed profile is noisy E has its minimum below the
    /// band's limit, see `fit::finish_mu_fairest`). Off, the fit stops at the band's limit: one band-checked
    /// solve and one E fewer per fair (the surface draft's isocurves,
    /// [`SurfaceFairingOptions::draft`](super::SurfaceFairingOptions::draft)).
    pub fn set_fairest_mu(&mut self, on: bool) {
        self.fairest_mu = on;
    }

    /// Start the next [`Self::fair`]'s band search at fairness weight `mu` (e.g. the μ of a
    /// neighbouring isocurve) instead of the previous fair's; `None` searches from scratch. The
    /// result is the same band-holding μ to `MU_RESOLUTION`, found in fewer solves when the hint is close.
    pub fn set_mu_hint(&mut self, mu: Option<f64>) {
        self.last_mu = mu.filter(|m| m.is_finite() && *m > 0.0);
    }

    /// Forget what earlier fairs left in the setup (the last μ of the band searches, the fit's E, where the
    /// band scan last broke, the polish's start candidates): the next [`Self::fair`] then runs as on a setup just built (the surface
    /// engine's cached isocurve setups, [`super::surface::IsocurveCache`]). The options, the tolerance
    /// and the target stay as they are.
    pub(crate) fn as_new(&mut self) {
        self.last_mu = None;
        self.last_mu_smooth = None;
        self.best_energy = None;
        self.scan_from = 0;
        self.polish_cache = Default::default();
    }

    /// Change the integration scheme.
    pub fn set_integrator(&mut self, integrator: Integrator) {
        self.opts.integrator = integrator;
    }

    /// Change the fit mode.
    pub fn set_mode(&mut self, mode: FitMode) {
        self.opts.mode = mode;
    }

    /// The blended integrated points of the last [`Self::fair`] (preview).
    pub fn integrated_points(&self) -> &[DVec3] {
        &self.ys
    }

    /// Run integration, fit and band control for the current target and
    /// tolerance. Reuses every buffer of the setup.
    ///
    /// The result's `max_deviation` is a sound upper bound of the distance from every point of the
    /// original stretch to the result ([`super::verify::band_bound`]), not only at the check samples.
    /// Where the result left the band between the samples, the fair is run again with the band
    /// narrowed by the excess (at most `BAND_RETRIES` (3) times); if that does not hold it either, the
    /// original is returned, with a note.
    pub fn fair(&mut self) -> Result<FairingResult> {
        self.fair_certified()
    }

    /// [`Self::fair`]: the pass, its band bound, and the passes again with the band narrowed by the excess
    /// where the result left the band between the check samples.
    fn fair_certified(&mut self) -> Result<FairingResult> {
        let m = self.opts.tolerance;
        validate_tolerance(m)?;
        let mut r = self.fair_pass()?;
        if !self.sharp_report {
            return Ok(r);
        }
        let work = self.work.clone();
        let certify = |c: &BSplineCurve| super::verify::certify(&work, c, m);
        let Some(mut bb) = certify(&r.curve) else {
            return Ok(r);
        };
        let mut narrowed = m;
        let mut retries = 0;
        while bb.bound > m && retries < BAND_RETRIES {
            retries += 1;
            narrowed *= (m / bb.bound).powi(2) * (1.0 - 1e-3);
            self.opts.tolerance = narrowed;
            let again = self.fair_pass();
            self.opts.tolerance = m;
            r = again?;
            match certify(&r.curve) {
                Some(b) => bb = b,
                None => break,
            }
        }
        if bb.bound > m {
            let u = bb.at;
            self.best.fill(DVec3::ZERO);
            r.curve = self.work.clone();
            r.alpha = 0.0;
            r.energy = self.original_energy();
            r.max_deviation = 0.0;
            r.notes.push(format!(
                "the fair left the tolerance band between its check samples (near u = {u:.6}) and a narrower \
                 band did not hold either: the curve was kept as it was"
            ));
            return Ok(r);
        }
        r.max_deviation = bb.bound;
        Ok(r)
    }

    /// [`Self::fair`] without the final band bound: one run at the current tolerance.
    fn fair_pass(&mut self) -> Result<FairingResult> {
        self.ensure_variation_rows();
        let m = self.opts.tolerance;
        if self.opts.mode == FitMode::Smoothing {
            return self.fair_smoothing();
        }
        let p = self.work.degree();
        let pull = PullBack {
            tolerance: m,
            correct_tangent: self.opts.mode == FitMode::Fairway,
        };
        let tr = Track {
            points: &self.pts,
            tangents: &self.tangents,
            normals: &self.normals,
            dim: self.work.dim(),
            h: self.h,
        };
        integrate_blended(
            &tr,
            self.target.values(),
            self.opts.integrator,
            pull,
            &mut self.scratch,
            &mut self.ys,
            &mut self.ts,
        );
        // right-hand sides (in ΔP)
        self.rhs0.fill(DVec3::ZERO);
        self.rhs2.fill(DVec3::ZERO);
        let g = self.target.values();
        let dim = self.work.dim();
        for k in 0..self.params.len() {
            let r0 = self.ys[k] - self.pts[k];
            let t = self.ts[k];
            let nn = if dim == 2 {
                DVec3::new(-t.y, t.x, 0.0)
            } else {
                let n = self.normals[k] - t * self.normals[k].dot(t);
                n.normalize_or(self.normals[k])
            };
            let v = self.speed[k];
            let a = t * self.dspeed[k] + nn * (v * v * g[k]);
            let r2 = a - self.d2[k];
            let f = self.first[k];
            for i in 0..=p {
                let li = f + i as isize;
                if li < 0 || li as usize >= self.nf {
                    continue;
                }
                self.rhs0[li as usize] += r0 * self.b0[k * (p + 1) + i];
                self.rhs2[li as usize] += r2 * self.b2[k * (p + 1) + i];
            }
        }
        let mut solves = 0;
        let (mu, alpha, dev, energy) = match self.opts.mode {
            FitMode::Paper => {
                self.solve(0.0)?;
                solves += 1;
                self.best.copy_from_slice(&self.sol);
                let dev = self.deviation(&self.best.clone(), f64::INFINITY);
                (0.0, 1.0, dev, self.energy_of_update(&self.best))
            }
            FitMode::Fairway | FitMode::Smoothing => {
                let accept = band_accept(m, &self.work);
                let (mu, mut alpha, mut dev) = self.search_mu(accept, &mut solves)?;
                // Never less fair than the original: where the band-holding fit has a larger E than the
                // original's (noise larger than the control point spacing, knots crowded at an end), the
                // polish, which only accepts steps that lower E, starts from the original instead
                // (without the polish, the original is the result). Without the check a 5000-point zigzag
                // goes from E 1.5e11 to 2.5e13 (cusps of curvature 2.4e8), a curve with knots crowded
                // at its start from E 6.3 to 27. The check comes before the polish, which then runs once
                // (polishing both, the fit and then the original, would nearly double its cost).
                // (E of a straight stretch is rounding on both sides: a floor of (1e-10 / length)² per
                // sample keeps such ties as they are)
                // (each E is evaluated once: the fit's, the original's — kept while the target stays —, and
                // the polish's last; an isocurve of a surface fair pays 1–2 instead of 3)
                let ns = self.params.len() as f64;
                let floor = ns * (1e-10 / (self.h * (ns - 1.0))).powi(2);
                let mut e = match self.best_energy.take() {
                    Some(e) => e,
                    None => self.energy_of_update(&self.best),
                };
                let e0 = self.original_energy();
                if e > e0 + floor {
                    self.best.fill(DVec3::ZERO);
                    alpha = 0.0;
                    dev = 0.0;
                    e = e0;
                }
                let (dev, e) = match (self.opts.polish, self.opts.polish_method) {
                    (false, _) => (dev, e),
                    (true, PolishMethod::LineSearch) => self.polish(accept, dev, e, &mut solves),
                    (true, PolishMethod::InteriorPoint) => self.polish_interior(accept, dev, e, &mut solves),
                    (true, PolishMethod::Variation) => self.polish_variation(accept, dev, e, &mut solves)?,
                };
                // the band checks stop at the first point within the band: report the sharpest bound
                (mu, alpha, dev, e)
            }
        };
        let curve = self.updated_curve(&self.best)?;
        Ok(FairingResult {
            curve,
            max_deviation: dev,
            mu,
            alpha,
            solves,
            energy,
            seam: self.seam.clone(),
            notes: vec![],
        })
    }

    /// The reference smoother ([`FitMode::Smoothing`]): the μ search on its system, the sharp report.
    fn fair_smoothing(&mut self) -> Result<FairingResult> {
        let accept = band_accept(self.opts.tolerance, &self.work);
        let mut solves = 0;
        let (mu, alpha, dev) = self.search_smoothing(accept, &mut solves)?;
        Ok(FairingResult {
            curve: self.updated_curve(&self.best)?,
            max_deviation: dev,
            mu,
            alpha,
            solves,
            energy: self.energy_of_update(&self.best),
            seam: self.seam.clone(),
            notes: vec![],
        })
    }

    /// The working curve with the free control points moved by the update `d`.
    fn updated_curve(&self, d: &[DVec3]) -> Result<BSplineCurve> {
        let mut pts = self.work.points().to_vec();
        for (k, x) in d.iter().enumerate() {
            pts[self.i0 + k] += *x;
        }
        self.work.with_points(pts)
    }
}
