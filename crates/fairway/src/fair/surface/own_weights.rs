//! NURBS faces faired on their own knots and weights: the fallback of [`super::fair_rational_surface`]
//! where the non-rational stand-in's fair adds isocurve curvature extrema (its cubic ripples survive).
//!
//! The stand-in's fair is fitted back into the face's own space — its degrees, knots and weights fixed,
//! the control points of the region's free block by linear least squares in homogeneous form
//! ([`crate::fair::nurbs::fixed_weight_fit`]) — which cannot carry ripples finer than the face's own
//! knots. The difference from the original is then a rational surface with the original's weights, so
//! its control net bounds it everywhere ([`crate::fair::verify::surface_band_bound`], refined in
//! homogeneous form); where the bound exceeds m the change is stepped back until it certifies m. Faces
//! whose region crosses C0 knot lines are not taken — the engine fairs those tile by tile with the rows
//! next to each line held, which one fit over the whole region would move — and stay refused, saying so.

use super::*;

/// Samples per knot span and direction of the fit's grid (at least degree + 2).
const FIT_PER_SPAN: usize = 8;

/// `surface` (rational, unequal weights) faired on its own knots and weights from the fair of its
/// stand-in, `stand_in` (band already against `surface`): the result, rational with `surface`'s weights,
/// its deviation soundly bounded by m; `None` for a region crossing C0 knot lines.
pub(super) fn fair_on_own_weights(
    surface: &BSplineSurface,
    opts: &SurfaceFairingOptions,
    stand_in: &SurfaceFairingResult,
) -> Result<Option<SurfaceFairingResult>> {
    if c0_tiles(surface, opts).is_some() {
        return Ok(None);
    }
    let (ru, rv, free_u, free_v) = free_rows(surface, opts.region)?;
    let grid = |k: &KnotVector, (a, b): UvRange| span_grid(k, a, b, FIT_PER_SPAN.max(k.degree() + 2));
    let (us, vs) = (grid(surface.knots_u(), ru), grid(surface.knots_v(), rv));
    let data = grid_points(&stand_in.surface, &us, &vs);
    let fit = crate::fair::nurbs::fixed_weight_fit(surface, &us, &vs, &data, free_u.clone(), free_v.clone())?;
    let (faired, t, bound) = certified_step(surface, fit, opts.tolerance)?;
    let bound = bound.ok_or_else(|| {
        Error::InvalidInput(
            "rational surface (unequal weights): the deviation of its fair on its own knots and weights could \
             not be bounded (its difference net could not be refined)"
                .into(),
        )
    })?;
    Ok(Some(SurfaceFairingResult {
        surface: faired,
        max_deviation: bound,
        band_bound: Some(bound),
        alpha: stand_in.alpha * t,
        free_u,
        free_v,
        notes: vec![],
        ..stand_in.clone()
    }))
}

/// The fair of a NURBS face whose stand-in's fair, `stand_in`, raised its isocurve curvature extrema
/// (`extrema` counts them: `before` → `after`): [`fair_on_own_weights`] with a note, if it does not raise
/// them; else refused, saying both counts.
pub(super) fn instead_of_the_stand_in(
    surface: &BSplineSurface,
    opts: &SurfaceFairingOptions,
    stand_in: &SurfaceFairingResult,
    extrema: &impl Fn(&BSplineSurface) -> usize,
    (before, after): (usize, usize),
) -> Result<SurfaceFairingResult> {
    let own = fair_on_own_weights(surface, opts, stand_in)?;
    let own_after = own.as_ref().map(|o| extrema(&o.surface));
    match (own, own_after) {
        (Some(mut o), Some(n)) if n <= before => {
            o.notes.insert(
                0,
                format!(
                    "rational surface (unequal weights): faired on its own knots and weights (its non-rational \
                     stand-in's fair added isocurve curvature extrema, {before} -> {after}): the stand-in's fair \
                     fitted back with the weights fixed, the deviation bounded on the rational difference"
                ),
            );
            Ok(o)
        }
        (_, own_after) => Err(Error::InvalidInput(format!(
            "rational surface (unequal weights): it could not be faired without adding isocurve curvature \
             extrema ({before} -> {after} through its non-rational stand-in{}); convert it to a non-rational \
             surface in the CAD system, or fair it at a looser tolerance",
            match own_after {
                Some(n) => format!(", {before} -> {n} on its own knots and weights"),
                None => ", and its region crosses C0 knot lines, which the fit on its own knots does not take".into(),
            }
        ))),
    }
}
