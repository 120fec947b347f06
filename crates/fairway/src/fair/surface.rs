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
//!    (`POLE_ROWS`), so it stays one point with its tangent plane and
//!    curvature; the isocurve through it is a point and is left as it is
//!    (test `a_pole_stays_one_point_and_the_rest_is_faired`). Before that,
//!    the default method makes a noisy pole smooth (**step 0**, `poles.rs`:
//!    its first ring into the tangent plane, the second onto a quadratic
//!    height, within half the band; a tip rising more than 5° is kept) and
//!    fairs the result with the rest of the band, keeping that route where it
//!    is no less fair on both measures of step 8 (test
//!    `a_noisy_pole_is_made_smooth_and_a_tip_is_kept`). A **seam** —
//!    a closed direction, first and last rows equal — holds `POLE_ROWS`
//!    rows at each side of it: the isocurves are faired one stretch each, not
//!    across the seam, and fairing the two sides independently would open the
//!    surface there (test `a_closed_surface_stays_closed_at_its_seam`). Fairing
//!    across a surface's seam, as [`super::closed`] does for curves, is not
//!    done.
//! 2. **Grid.** Parameters `u_k`, `v_l`: `samples_per_span` per knot span of
//!    the moving rectangle (ends included).
//! 3. **Isocurves.** For each `v_l` the u-isocurve `S(·, v_l)` (a B-spline
//!    curve with knots U, [`BSplineSurface::iso_u`]) is faired by
//!    the curve engine ([`FairingSetup`](super::curve::FairingSetup), set up by [`isocurve_setup`]:
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
//!    No variant wins everywhere (docs/QUALITY.md, `cargo run --release -p
//!    fairway --example surface_combine`). `Weighted` is the default: it is
//!    the only one that improves a bump in a local region, and where one
//!    direction carries the correction (an extrusion) it reproduces the curve
//!    engine exactly (test `extruded_curve_matches_the_curve_engine`), while the
//!    average does half the correction. `Smoothed` (umbrella smoothing also
//!    shrinks curved regions) is offered, not default.
//! 5. **Fit** the control block to `S + Δ` on the grid with the original
//!    knots and parameters ([`GridFit`], separable, O(n)).
//! 6. **Choice of the isocurve tolerance and the fit smoothing** (with
//!    `auto_smoothing`, the default). For the isocurve tolerances
//!    `m_iso = m, m/3, m/9, …` (`ISO_LEVEL_FACTOR`, at most
//!    `iso_levels`, greedy: stop at the first level that is no fairer), each
//!    smoothing strength of `AUTO_STRENGTHS` is fitted (after the first
//!    level only those next to the pick, see below); among the
//!    candidates that hold the band (step 7) the one with the least
//!    *fairness energy* is taken: the Dirichlet energy of the mean curvature
//!    H on a grid of `ENERGY_PER_SPAN` samples per knot span of the moving
//!    rectangle, `Σ_edges (H_a − H_b)² w_⊥/|P_a − P_b|` (a discrete
//!    `∫∫|∇H|²`). **Why**: taking the *largest* strength that holds the band
//!    made interior regions less fair at larger m: each isocurve's own
//!    band-limited correction differs from its neighbour's, so the combined
//!    cloud is wavy across the isocurves, and a strong penalty next to held
//!    border rows pulls the block towards a stiff interpolant of the border.
//!    Measuring the candidates instead of trusting "more smoothing is fairer"
//!    fixes both (docs/QUALITY.md).
//!
//!    **How the levels are made.** By default the isocurves are faired once,
//!    at m, and level k's cloud is the original plus the combined correction
//!    scaled by 3⁻ᵏ; with `refair_levels` every isocurve is faired again at
//!    m/3, m/9, … (its setup is reused, so a level costs the band search and
//!    integration only). Scaling is what a smaller band mostly does to the
//!    correction's size; what it does not reproduce is the isocurve's own
//!    re-balancing at the smaller band, which changes the curvature errors
//!    little on the measured cases (docs/QUALITY.md), at up to `iso_levels` times the isocurve
//!    cost: so scaling is the default. After the first level, only the picked
//!    strength and its two neighbours on `AUTO_STRENGTHS` are fitted.
//! 7. **Hard tolerance.** The result is checked on a grid of
//!    `CHECK_PER_SPAN` samples per knot span of the moving rectangle (outside
//!    it nothing moved): `|S_f(u,v) − S(u,v)|` bounds both one-sided
//!    closest-point distances from above; where it exceeds m, a Newton
//!    projection in both directions gives a sharper (still upper) bound. If
//!    the bound exceeds m, the isocurve tolerance is tightened
//!    (`m_iso ← 0.8 · m_iso · m / dev`) and all is redone (up to
//!    `MAX_ROUNDS`); if still above, the change of the control points is
//!    scaled, `ΔD ← α ΔD`, α bisected in [0, 1] (α = 0 is the original, so a
//!    positive tolerance is always met; the result reports α).
//! 8. **The fairest candidate** (default [`SurfaceMethod::Fairway`]; [`SurfaceMethod::Isocurves`] stops
//!    after step 7). The **reference smoother** ([`SurfaceMethod::Smoothing`], `fairway fair --method
//!    smoothing`) is the surface counterpart of the curve engine's `FitMode::Smoothing`: on the same
//!    free block and grid as step 5, with the original's samples as data, [`PlateFit`] minimises
//!    `‖S − S₀‖² + λ ∫∫ S_xxx² + 3 S_xxy² + 3 S_xyy² + S_yyy²` (order `REFERENCE_ORDER` = 3, the
//!    rotation-invariant curvature-variation energy, x, y the parameters scaled by the mean speeds), the
//!    largest λ on a log bisection whose result holds the band. Candidates: the original, step 7's
//!    result, the smoother's answer on the original's samples and on step 7's result (data = the isocurve
//!    result's samples, band still against the original; ranking the weaker strengths the searches visited
//!    as well changed no row of the table), and blends
//!    `a + (b − a)(1 − w)` of pairs of the isocurve result, the smoother's answer and the fairest
//!    smoother-on-isocurves net (`BLENDS`). A smoother or blend candidate holds the band when the
//!    step-7 checks pass and, on a grid of `FINE_CHECK_PER_SPAN` samples per span, the parametric
//!    change `|S_f − S|` stays ≤ m, its grid peaks followed to their local maxima by Newton ascent
//!    (projected distances are never larger; without the peaks the smoother's nets exceeded m by up to
//!    0.1 % between nodes, measured by dense projection; the cells whose control points all moved by less
//!    than the peaks' threshold are skipped, as no node there can reach it). Each candidate is ranked by
//!    (isocurve curvature extrema with the 1 % dead band, `∫∫|∇H|²`), the measures of
//!    [`crate::measure_surface`] over the moving rectangle (`RANK_ISO` isocurves; for a whole-surface
//!    fair exactly `measure`'s extrema, and its `∫∫|∇H|²` with ∇H from the third partials, within 1e-8
//!    relative of `measure`'s difference quotients at a fifth of the evaluations, by the adaptive rule of
//!    [`crate::measure_surface::mean_curvature_variation_adaptive`]: 4 and 5 Gauss points a direction
//!    where they agree, `measure`'s 10 elsewhere). Returned: the lexicographically fairest candidate that is no
//!    less fair on either measure than the reference and than step 7's result and has no more extrema
//!    than the original; if none, the fairest no less fair than the reference with no more extrema than
//!    the original; if none, the fairest of all. The result's `pick` says which.
//!
//!    **Why**: step 7 alone is less fair than the reference on most rows of the surface quality table,
//!    the reference alone less fair than step 7 on others; ranking both (and their blends) by the
//!    independent measures takes the better of each. Order 3 (not the thin plate, order 2, which
//!    penalizes the crown's curvature itself). The ranking costs several times step 7's time.
//!    Measurements: docs/QUALITY.md, "Surface engine".
//!
//! Rational surfaces with equal weights are converted; others are faired through a close non-rational
//! stand-in (`fair::nurbs`, [`fair_surface`]'s notes say so), or, where the stand-in's fair adds isocurve
//! curvature extrema, on their own knots and weights (`own_weights.rs`).
//! Degree 2 gives C1 (G1) joins only; any degree ≥ 1 and any clamped knot
//! vectors work otherwise.

use std::ops::Range;
use std::time::Instant;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::fit_surface::{GridFit, PlateFit, SurfaceSmoothing, free_range};
use crate::knots::KnotVector;
use crate::surface::BSplineSurface;

mod candidates;
mod check;
mod fairness;
mod isocurves;
mod options;
mod own_weights;
mod parallel;
mod poles;
mod reference;
mod rounds;
mod setup_cache;
#[cfg(test)]
mod tests;

use candidates::fairest_candidate;
use check::{CheckGrid, grid_points};
use fairness::FairnessGrid;
use isocurves::POLE_ROWS;
pub use isocurves::isocurve_setup;
use isocurves::{combined_cloud, hold_poles_and_seams, net_size};
pub use options::{Combine, SurfaceFairingOptions, SurfaceFairingResult, SurfaceMethod, SurfacePick, SurfaceTimings};
pub(crate) use parallel::par_map;
pub use reference::REFERENCE_LOG_STRENGTH;
use reference::{BLENDS, FINE_CHECK_PER_SPAN, REFERENCE_ORDER, SEARCH_CANDIDATES};
use reference::{Bands, PlateFactors, Rank, Ranker, plate_fit, plate_search};
use rounds::isocurve_rounds;
pub use setup_cache::{CACHE_SAMPLES, CacheCounts, IsocurveCache};

/// Smoothing strengths tried, largest first, with `auto_smoothing` (see [`SurfaceSmoothing`]).
pub(crate) const AUTO_STRENGTHS: [f64; 8] = [1e5, 1e4, 1e3, 1e2, 1e1, 1.0, 1e-1, 0.0];

/// Ratio of successive isocurve tolerances tried with `auto_smoothing` (module docs, step 6).
pub(crate) const ISO_LEVEL_FACTOR: f64 = 1.0 / 3.0;

/// Rounds of isocurve-tolerance tightening before the α fallback.
pub(crate) const MAX_ROUNDS: usize = 4;

/// Check samples per knot span and direction of the hard tolerance.
pub(crate) const CHECK_PER_SPAN: usize = 6;

/// Curve-engine samples per knot span of an isocurve (unless `curve.samples` is set).
pub(crate) const ISO_SAMPLES_PER_SPAN: usize = 4;

/// Width of the isocurves' default target smoothing, in knot spans (unless `curve.strength` is set).
pub(crate) const ISO_TARGET_SIGMA_SPANS: f64 = 1.6;

fn span_grid(knots: &KnotVector, a: f64, b: f64, per_span: usize) -> Vec<f64> {
    let bp: Vec<f64> = knots.breakpoints().into_iter().filter(|&t| t >= a && t <= b).collect();
    let (lo, hi) = knots.domain();
    // a span next to an interior knot of multiplicity s carries s new control points where a simple knot
    // brings one (a chain of Bézier patches): it gets s times the samples, so the fit has data for each
    let mult = |t: f64| {
        if t > lo && t < hi {
            knots.multiplicity(t).max(1)
        } else {
            1
        }
    };
    let mut out = Vec::with_capacity(bp.len() * per_span + 1);
    for w in bp.windows(2) {
        let n = per_span * mult(w[0]).max(mult(w[1]));
        for k in 0..n {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / n as f64);
        }
    }
    out.push(b);
    out
}

/// [`fair_surface`] that stops when `cancel` is set (from another thread): it then returns
/// [`Error::Cancelled`] at its next checkpoint — before each block of isocurves, each round, step 8, each
/// attempt of step 8's smoother searches, each tile — and never a partial result ([`crate::cancel`]). A
/// token that is not set changes nothing: the result is [`fair_surface`]'s, bit for bit.
pub fn fair_surface_with(
    surface: &BSplineSurface,
    opts: SurfaceFairingOptions,
    cancel: &crate::Cancel,
) -> Result<SurfaceFairingResult> {
    cancel.run(|| fair_surface(surface, opts))
}

/// [`fair_surface_with`] taking the isocurves' setups from `cache` where it holds them and keeping the new
/// ones there ([`IsocurveCache`]): a surface faired again at another tolerance (the editor's drafts
/// while the tolerance is dragged, the full fair after them) skips the isocurve setups. The result is
/// [`fair_surface`]'s, bit for bit.
pub fn fair_surface_cached(
    surface: &BSplineSurface,
    opts: SurfaceFairingOptions,
    cancel: &crate::Cancel,
    cache: &IsocurveCache,
) -> Result<SurfaceFairingResult> {
    cache.run(|| fair_surface_with(surface, opts, cancel))
}

/// Fair `surface` (see the module docs). Inside [`fair_surface_with`] (or a network fair with a token)
/// it stops at the caller's token; on its own it has none and runs to its end.
pub fn fair_surface(surface: &BSplineSurface, opts: SurfaceFairingOptions) -> Result<SurfaceFairingResult> {
    if !surface.is_polynomial() {
        return fair_rational_surface(surface, opts);
    }
    let m = opts.tolerance;
    let mut r = fair_polynomial(surface, opts)?;
    if opts.method == SurfaceMethod::Fairway {
        r = with_smooth_poles(surface, opts, r)?;
    }
    // a rational input with equal weights (the only kind the engine takes) is its polynomial form exactly
    let (faired, t, bound) = certified_step(&surface.to_polynomial()?, r.surface.to_polynomial()?, m)?;
    (r.surface, r.band_bound) = (faired, bound);
    if t < 1.0 {
        r.alpha *= t;
        // the grid's figure was the old surface's; the bound is this one's (and sound)
        r.max_deviation = bound.unwrap_or(m);
    }
    Ok(r)
}

/// Steps 1–8 on a polynomial surface: tile by tile across C0 knot lines, else in one piece.
fn fair_polynomial(surface: &BSplineSurface, opts: SurfaceFairingOptions) -> Result<SurfaceFairingResult> {
    match c0_tiles(surface, &opts) {
        Some(tiles) => fair_tiles(surface, opts, &tiles),
        None => fair_surface_unbounded(surface, opts),
    }
}

/// Step 0 (`poles.rs`): where `surface` has a pole with a noisy ring inside the region, the pole is made
/// smooth within part of the band and the result faired with the rest; that route replaces `plain` (the
/// fair of the surface as it is) where it is no less fair on both measures — isocurve curvature extrema
/// (with the hysteresis of the original's) and `∫∫|∇H|²` — and has no more extrema than the original.
fn with_smooth_poles(
    surface: &BSplineSurface,
    opts: SurfaceFairingOptions,
    mut plain: SurfaceFairingResult,
) -> Result<SurfaceFairingResult> {
    let m = opts.tolerance;
    let mut tips = Vec::new();
    let step = poles::smoothed_poles(surface, opts.region, m, &mut tips)?;
    plain.notes.extend(tips);
    let Some(step) = step else { return Ok(plain) };
    let Ok(mut r) = fair_polynomial(&step.surface, opts.tolerance(m - step.bound)) else {
        return Ok(plain);
    };
    let extrema = iso_extrema_counter(surface);
    let energy = crate::measure_surface::mean_curvature_variation;
    let (e0, ep, er) = (extrema(surface), extrema(&plain.surface), extrema(&r.surface));
    if er > e0 || er > ep || energy(&r.surface) > energy(&plain.surface) {
        return Ok(plain);
    }
    r.max_deviation += step.bound;
    if step.moved_u {
        r.free_u = r.free_u.start.min(1)..r.free_u.end.max(surface.nu() - 1);
    }
    if step.moved_v {
        r.free_v = r.free_v.start.min(1)..r.free_v.end.max(surface.nv() - 1);
    }
    r.timings = r.timings + plain.timings;
    r.smoothed_poles = step.notes.len();
    r.notes.splice(0..0, step.notes);
    Ok(r)
}

/// `faired` (on `original`'s knots and weights) with the sound bound of its deviation
/// ([`super::verify::surface_band_bound`]), stepped back towards `original` where the grid held the
/// band but the bound exceeds `m` (the fair slid the surface along itself between the grid's points),
/// until the bound certifies m: the difference is linear in the step, so is its bound. Returns the
/// surface, the step t ∈ (0, 1] and its bound (`None`: other knots or weights).
fn certified_step(
    original: &BSplineSurface,
    faired: BSplineSurface,
    m: f64,
) -> Result<(BSplineSurface, f64, Option<f64>)> {
    match super::verify::surface_band_bound(original, &faired, m) {
        Some(b) if b > m => {
            let t = m / b * (1.0 - 1e-9);
            let pts: Vec<_> = (original.points().iter().zip(faired.points()))
                .map(|(&a, &f)| a + t * (f - a))
                .collect();
            let stepped = faired.with_points(pts)?;
            let bound = super::verify::surface_band_bound(original, &stepped, m);
            Ok((stepped, t, bound))
        }
        bound => Ok((faired, 1.0, bound)),
    }
}

/// A rational surface with unequal weights (NURBS from Alias, CATIA: surfaces of revolution, fillets),
/// faired through a non-rational stand-in ([`super::nurbs::surface_polynomial_approximation`]) within
/// `APPROX_FRACTION`(super::nurbs::APPROX_FRACTION) of the band: the stand-in is faired with the band
/// narrowed by its error, and the reported deviation and bound add that error back, so they bound the
/// distance from the rational original. The result is non-rational, of degrees max(p, 3), on the
/// stand-in's knots (the original's breakpoints and more).
fn fair_rational_surface(surface: &BSplineSurface, opts: SurfaceFairingOptions) -> Result<SurfaceFairingResult> {
    let m = opts.tolerance;
    check_tolerance(surface, m)?;
    let a = super::nurbs::surface_polynomial_approximation(surface, RATIONAL_APPROX_FRACTION * m)?;
    let mut r = fair_surface(
        &a.surface,
        SurfaceFairingOptions {
            tolerance: m - a.error,
            ..opts
        },
    )?;
    r.max_deviation += a.error;
    r.band_bound = r.band_bound.map(|b| b + a.error);
    // never less fair than the input: the stand-in's curvature ripples must not survive the fair
    let extrema = iso_extrema_counter(surface);
    let (before, after) = (extrema(surface), extrema(&r.surface));
    if after > before {
        return own_weights::instead_of_the_stand_in(surface, &opts, &r, &extrema, (before, after));
    }
    r.notes.insert(
        0,
        format!(
            "rational surface (unequal weights): faired through a non-rational B-spline surface of degrees {} × {} \
             ({} × {} control points) within {:.3e} of it; the deviation reported includes that",
            a.surface.degree_u(),
            a.surface.degree_v(),
            a.surface.nu(),
            a.surface.nv(),
            a.error
        ),
    );
    Ok(r)
}

/// The isocurve curvature extrema of a surface (16 isocurves each way), with the hysteresis of 1 % of
/// `original`'s largest |κ|: the count fairing a NURBS face must not raise.
fn iso_extrema_counter(original: &BSplineSurface) -> impl Fn(&BSplineSurface) -> usize {
    let delta = 0.01 * crate::measure_surface::iso_stats(original, 16, 0.0).max_abs_kappa;
    move |x| {
        let st = crate::measure_surface::iso_stats(x, 16, delta);
        st.extrema_u + st.extrema_v
    }
}

/// The share of the band the non-rational stand-in of a rational surface may use: tighter than a curve's
/// (a tenth), because a cubic stand-in's curvature ripples grow as its error over h², and the isocurve
/// fair does not remove them all (impeller corpus, full: 189 of 212 NURBS faces with more curvature
/// extrema at m/10, 33 at m/1000; at m/10⁵ two faces found no stand-in).
const RATIONAL_APPROX_FRACTION: f64 = 1e-3;

/// A parameter interval `(a, b)`.
type UvRange = (f64, f64);

/// A parameter rectangle `((u1, u2), (v1, v2))`.
type UvRect = (UvRange, UvRange);

/// The interior C0 knot lines of a direction (knots of multiplicity ≥ p, p ≥ 2: the joints of a chain of
/// Bézier patches, a crease or a G1 joint) strictly inside `(a, b)`.
fn c0_lines(k: &KnotVector, a: f64, b: f64) -> Vec<f64> {
    let p = k.degree();
    if p < 2 {
        return vec![];
    }
    k.breakpoints()
        .into_iter()
        .filter(|&t| t > a && t < b && k.multiplicity(t) >= p)
        .collect()
}

/// Where the region crosses C0 knot lines: the tiles between them (u-stretches × v-stretches), each faired
/// on its own by [`fair_tiles`]; `None` when it crosses none.
fn c0_tiles(s: &BSplineSurface, opts: &SurfaceFairingOptions) -> Option<Vec<UvRect>> {
    let ((u1, u2), (v1, v2)) = opts.region.unwrap_or(s.domain());
    let (lu, lv) = (c0_lines(s.knots_u(), u1, u2), c0_lines(s.knots_v(), v1, v2));
    if lu.is_empty() && lv.is_empty() {
        return None;
    }
    let stretches = |a: f64, b: f64, lines: &[f64]| -> Vec<(f64, f64)> {
        let cuts: Vec<f64> = std::iter::once(a).chain(lines.iter().copied()).chain([b]).collect();
        cuts.windows(2).map(|w| (w[0], w[1])).collect()
    };
    let (su, sv) = (stretches(u1, u2, &lu), stretches(v1, v2, &lv));
    Some(su.iter().flat_map(|&ru| sv.iter().map(move |&rv| (ru, rv))).collect())
}

/// A free range next to an interior C0 knot (multiplicity ≥ p, p ≥ 2) loses the row next to it: the
/// joint row is held already (its support crosses the knot), and with its neighbour on this side held
/// too, the cross-boundary derivative along the line stays as it was — a G1 joint stays G1, a crease
/// keeps its angle.
fn hold_c0_neighbours(k: &KnotVector, mut f: Range<usize>) -> Range<usize> {
    let (p, t) = (k.degree(), k.values());
    let (lo, hi) = k.domain();
    let c0 = |u: f64| p >= 2 && u > lo && u < hi && k.multiplicity(u) >= p;
    if f.start < f.end && c0(t[f.start]) {
        f.start += 1;
    }
    if f.start < f.end && c0(t[f.end + p]) {
        f.end -= 1;
    }
    f
}

/// A surface whose region crosses C0 knot lines, faired tile by tile (module docs, step 1): each tile is
/// a region of its own, the rows next to the lines held, so the lines keep their continuity; a tile with
/// no movable control row is left as it is and named in the notes. The tiles' free rows have their
/// supports inside their tiles, so each tile's change is independent of the others'.
fn fair_tiles(surface: &BSplineSurface, opts: SurfaceFairingOptions, tiles: &[UvRect]) -> Result<SurfaceFairingResult> {
    let mut work = if surface.is_rational() {
        surface.to_polynomial()?
    } else {
        surface.clone()
    };
    let mut out: Option<SurfaceFairingResult> = None;
    let mut held = vec![];
    for &(ru, rv) in tiles {
        let fu = hold_c0_neighbours(work.knots_u(), free_range(work.knots_u(), ru.0, ru.1));
        let fv = hold_c0_neighbours(work.knots_v(), free_range(work.knots_v(), rv.0, rv.1));
        let (fu, fv) = hold_poles_and_seams(&work, fu, fv);
        if fu.is_empty() || fv.is_empty() {
            held.push(format!(
                "u ∈ [{:.6}, {:.6}] × v ∈ [{:.6}, {:.6}]",
                ru.0, ru.1, rv.0, rv.1
            ));
            continue;
        }
        let r = fair_surface_unbounded(
            &work,
            SurfaceFairingOptions {
                region: Some((ru, rv)),
                ..opts
            },
        )?;
        work = r.surface.clone();
        out = Some(match out {
            None => r,
            Some(mut acc) => {
                acc.max_deviation = acc.max_deviation.max(r.max_deviation);
                acc.iso_tolerance = acc.iso_tolerance.max(r.iso_tolerance);
                acc.rounds += r.rounds;
                acc.alpha = acc.alpha.min(r.alpha);
                acc.free_u = acc.free_u.start.min(r.free_u.start)..acc.free_u.end.max(r.free_u.end);
                acc.free_v = acc.free_v.start.min(r.free_v.start)..acc.free_v.end.max(r.free_v.end);
                acc.timings = acc.timings + r.timings;
                acc.surface = r.surface;
                acc
            }
        });
    }
    let Some(mut r) = out else {
        return Err(Error::InvalidInput(format!(
            "the region holds no movable control point: the surface's C0 knot lines (creases or joints of \
             Bézier patches) cut it into {} tile(s), and each is too short to move once the rows next to the \
             lines are held (a tile needs more than 2 control rows between its lines in each direction)",
            tiles.len()
        )));
    };
    let lines = |k: &KnotVector, (a, b): (f64, f64)| {
        c0_lines(k, a, b)
            .iter()
            .map(|t| format!("{t:.6}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let region = opts.region.unwrap_or(surface.domain());
    r.notes.push(format!(
        "C0 knot lines (u = [{}], v = [{}]): faired tile by tile between them, the control rows on each \
         side of a line held, so each line keeps its continuity (G1 stays G1, a crease keeps its angle)",
        lines(surface.knots_u(), region.0),
        lines(surface.knots_v(), region.1)
    ));
    if !held.is_empty() {
        r.notes.push(format!(
            "{} of {} tile(s) too short to move (no free control row once the rows next to the lines are \
             held), left as they were: {}",
            held.len(),
            tiles.len(),
            held.join("; ")
        ));
    }
    Ok(r)
}

/// [`fair_surface`] before the sound band bound (a cancel checkpoint at its start and before step 8):
/// validation and grids ([`free_block`], [`Grids::new`]),
/// then the reference smoother alone ([`smoothing_only`]) or the isocurve rounds ([`isocurve_rounds`],
/// steps 3–7) followed by step 8's pick of the fairest candidate ([`fairest_candidate`]).
fn fair_surface_unbounded(surface: &BSplineSurface, opts: SurfaceFairingOptions) -> Result<SurfaceFairingResult> {
    crate::cancel::check()?;
    let (s, ru, rv, free_u, free_v) = free_block(surface, &opts)?;
    let (g, tm) = Grids::new(&s, &opts, ru, rv, free_u, free_v);
    if opts.method == SurfaceMethod::Smoothing {
        return smoothing_only(&g, tm);
    }
    // today's isocurve fairing (module docs, steps 3-7)
    let iso_result = isocurve_rounds(&g, &opts, tm)?;
    if opts.method == SurfaceMethod::Isocurves {
        return Ok(iso_result);
    }
    crate::cancel::check()?;
    fairest_candidate(&g, iso_result)
}

/// The tolerance `m` is usable on `surface`: positive, finite, and not below what f64 resolves at the
/// size of its control points.
fn check_tolerance(surface: &BSplineSurface, m: f64) -> Result<()> {
    let size = surface
        .points()
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f64::max);
    crate::range::check_tolerance_at(m, size)
}

/// What [`free_block`] returns: (surface, region in u, region in v, free rows, free columns).
type FreeBlock = (BSplineSurface, (f64, f64), (f64, f64), Range<usize>, Range<usize>);

/// Validation and step 1: the tolerance, the grid density and the region are checked, the surface taken
/// in its polynomial form, and the free control rows and columns found (poles and seams held).
fn free_block(surface: &BSplineSurface, opts: &SurfaceFairingOptions) -> Result<FreeBlock> {
    let m = opts.tolerance;
    check_tolerance(surface, m)?;
    if opts.samples_per_span < 2 {
        return Err(Error::InvalidInput("samples_per_span must be at least 2".into()));
    }
    let s = if surface.is_rational() {
        surface.to_polynomial()?
    } else {
        surface.clone()
    };
    let (ru, rv, free_u, free_v) = free_rows(&s, opts.region)?;
    Ok((s, ru, rv, free_u, free_v))
}

/// What [`free_rows`] returns: (region in u, region in v, free rows, free columns).
type FreeRows = (UvRange, UvRange, Range<usize>, Range<usize>);

/// The region (the whole domain if `None`) checked on `s`, and its free control rows and columns: those
/// whose supports lie inside it, less the rows next to C0 knot lines, poles and seams (step 1). Only
/// knots and control points are read, so `s` may be rational.
fn free_rows(s: &BSplineSurface, region: Option<UvRect>) -> Result<FreeRows> {
    if !(net_size(s) > 0.0) {
        return Err(Error::Degenerate(
            "all control points of the surface coincide (a single point): there is no shape to fair".into(),
        ));
    }
    let ((du0, du1), (dv0, dv1)) = s.domain();
    let ((u1, u2), (v1, v2)) = region.unwrap_or(((du0, du1), (dv0, dv1)));
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
    let (ku, kv) = (s.knots_u(), s.knots_v());
    let free_u = hold_c0_neighbours(ku, free_range(ku, u1, u2));
    let free_v = hold_c0_neighbours(kv, free_range(kv, v1, v2));
    let had = !free_u.is_empty() && !free_v.is_empty();
    let (free_u, free_v) = hold_poles_and_seams(s, free_u, free_v);
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
    Ok(((u1, u2), (v1, v2), free_u, free_v))
}

/// The surface to fair with its free block, the moving rectangle and the grids on it (module docs,
/// steps 1, 2 and 7), shared by the steps of [`fair_surface_unbounded`].
struct Grids<'a> {
    /// The surface (polynomial) and the options' region.
    s: &'a BSplineSurface,
    ru: (f64, f64),
    rv: (f64, f64),
    free_u: Range<usize>,
    free_v: Range<usize>,
    /// The moving rectangle: the union of the free control points' supports.
    rect: ((f64, f64), (f64, f64)),
    /// The fit grid (`samples_per_span` per knot span) and the original's points there.
    us: Vec<f64>,
    vs: Vec<f64>,
    orig: Vec<DVec3>,
    /// The band checks of step 7: [`CHECK_PER_SPAN`] and 3 samples per knot span.
    full_check: CheckGrid,
    coarse_check: CheckGrid,
    threads: Option<usize>,
    m: f64,
}

impl<'a> Grids<'a> {
    /// Step 2 and the check grids of step 7 for `s` with the region `ru × rv` and the free block; returns
    /// them with the timings so far (the original's sampling counts as the isocurves').
    fn new(
        s: &'a BSplineSurface,
        opts: &SurfaceFairingOptions,
        ru: (f64, f64),
        rv: (f64, f64),
        free_u: Range<usize>,
        free_v: Range<usize>,
    ) -> (Self, SurfaceTimings) {
        let (ku, kv) = (s.knots_u(), s.knots_v());
        let (pu, pv) = (ku.degree(), kv.degree());
        // moving rectangle: union of free supports
        let (au, bu) = (ku.values()[free_u.start], ku.values()[free_u.end - 1 + pu + 1]);
        let (av, bv) = (kv.values()[free_v.start], kv.values()[free_v.end - 1 + pv + 1]);
        let us = span_grid(ku, au, bu, opts.samples_per_span);
        let vs = span_grid(kv, av, bv, opts.samples_per_span);
        let t_orig = Instant::now();
        let orig = grid_points(s, &us, &vs);
        let threads = opts.threads;
        let full_check = CheckGrid::new(
            s,
            &span_grid(ku, au, bu, CHECK_PER_SPAN),
            &span_grid(kv, av, bv, CHECK_PER_SPAN),
            threads,
        );
        let coarse_check = CheckGrid::new(s, &span_grid(ku, au, bu, 3), &span_grid(kv, av, bv, 3), threads);
        let tm = SurfaceTimings {
            isocurves: t_orig.elapsed(),
            ..Default::default()
        };
        let g = Self {
            s,
            ru,
            rv,
            free_u,
            free_v,
            rect: ((au, bu), (av, bv)),
            us,
            vs,
            orig,
            full_check,
            coarse_check,
            threads,
            m: opts.tolerance,
        };
        (g, tm)
    }

    /// The check grid of `FINE_CHECK_PER_SPAN` samples per knot span of the moving rectangle (step 8).
    fn fine_check(&self) -> CheckGrid {
        let ((au, bu), (av, bv)) = self.rect;
        CheckGrid::new(
            self.s,
            &span_grid(self.s.knots_u(), au, bu, FINE_CHECK_PER_SPAN),
            &span_grid(self.s.knots_v(), av, bv, FINE_CHECK_PER_SPAN),
            self.threads,
        )
    }

    /// The band as step 8 verifies it, with `fine` from [`Self::fine_check`].
    fn bands<'b>(&'b self, fine: &'b CheckGrid) -> Bands<'b> {
        Bands {
            coarse: &self.coarse_check,
            full: &self.full_check,
            fine,
            free_u: &self.free_u,
            free_v: &self.free_v,
            m: self.m,
        }
    }

    /// A result of the isocurve rounds on this free block (`pick` [`SurfacePick::Isocurves`]).
    fn iso_result(
        &self,
        surface: BSplineSurface,
        max_deviation: f64,
        (iso_tolerance, rounds, alpha): (f64, usize, f64),
        smoothing: SurfaceSmoothing,
        timings: SurfaceTimings,
    ) -> SurfaceFairingResult {
        SurfaceFairingResult {
            surface,
            max_deviation,
            iso_tolerance,
            rounds,
            alpha,
            smoothing,
            free_u: self.free_u.clone(),
            free_v: self.free_v.clone(),
            timings,
            pick: SurfacePick::Isocurves,
            band_bound: None,
            notes: vec![],
            smoothed_poles: 0,
        }
    }
}

/// [`SurfaceMethod::Smoothing`]: the reference smoother of step 8 alone, on the original's samples (the
/// original itself when no strength holds the band).
fn smoothing_only(g: &Grids<'_>, mut tm: SurfaceTimings) -> Result<SurfaceFairingResult> {
    let s = g.s;
    let fine = g.fine_check();
    let t0 = Instant::now();
    let grid_fit = GridFit::new(s, &g.us, &g.vs, g.free_u.clone(), g.free_v.clone())?;
    let plate = plate_fit(s, &grid_fit, &g.us, &g.vs, REFERENCE_ORDER)?;
    let rhs = grid_fit.project(&g.orig)?;
    let bands = g.bands(&fine);
    let (pts, dev, strength) = plate_search(s, &plate, &PlateFactors::new(&plate), &rhs, &bands)?
        .pop()
        .unwrap_or_else(|| (s.points().to_vec(), 0.0, 0.0));
    tm.reference += t0.elapsed();
    Ok(SurfaceFairingResult {
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
        free_u: g.free_u.clone(),
        free_v: g.free_v.clone(),
        timings: tm,
        pick: SurfacePick::Reference,
        band_bound: None,
        notes: vec![],
        smoothed_poles: 0,
    })
}
