//! NURBS faces faired on their own knots and weights: the fallback of [`super::fair_rational_surface`]
//! where the non-rational stand-in's fair adds isocurve curvature extrema (its cubic ripples survive).
//!
//! The stand-in's fair is fitted back into the face's own space — its degrees, knots and weights fixed,
//! the control points of the region's free block by linear least squares in homogeneous form
//! ([`crate::fair::nurbs::fixed_weight_fit`]) — which cannot carry ripples finer than the face's own
//! knots. The difference from the original is then a rational surface with the original's weights, so
//! its control net bounds it everywhere ([`crate::fair::verify::surface_band_bound`], refined in
//! homogeneous form); where the bound exceeds m the change is stepped back until it certifies m. A region
//! crossing C0 knot lines is fitted tile by tile between them (as the engine fairs such faces), the control
//! rows on each side of a line held, so each line keeps its continuity; the fit of each tile reads only the
//! stand-in's fair inside it.

use super::*;

/// Samples per knot span and direction of the fit's grid (at least degree + 2).
const FIT_PER_SPAN: usize = 8;

/// `surface` (rational, unequal weights) faired on its own knots and weights from the fair of its
/// stand-in, `stand_in` (band already against `surface`): the result, rational with `surface`'s weights,
/// its deviation soundly bounded by m; `None` where no control row of `surface` can move (every tile
/// between its C0 knot lines too short once the rows next to the lines are held).
pub(super) fn fair_on_own_weights(
    surface: &BSplineSurface,
    opts: &SurfaceFairingOptions,
    stand_in: &SurfaceFairingResult,
) -> Result<Option<SurfaceFairingResult>> {
    // validation of the region and the net (errors in the user's terms)
    free_rows(surface, opts.region)?;
    let region = opts.region.unwrap_or(surface.domain());
    let tiles = c0_tiles(surface, opts).unwrap_or_else(|| vec![region]);
    let grid = |k: &KnotVector, (a, b): UvRange| span_grid(k, a, b, FIT_PER_SPAN.max(k.degree() + 2));
    let mut fit = surface.clone();
    let mut moved: Option<(Range<usize>, Range<usize>)> = None;
    for &(ru, rv) in &tiles {
        let (ku, kv) = (surface.knots_u(), surface.knots_v());
        let fu = hold_c0_neighbours(ku, free_range(ku, ru.0, ru.1));
        let fv = hold_c0_neighbours(kv, free_range(kv, rv.0, rv.1));
        let (fu, fv) = hold_poles_and_seams(surface, fu, fv);
        if fu.is_empty() || fv.is_empty() {
            continue;
        }
        let (us, vs) = (grid(ku, ru), grid(kv, rv));
        let data = grid_points(&stand_in.surface, &us, &vs);
        fit = crate::fair::nurbs::fixed_weight_fit(&fit, &us, &vs, &data, fu.clone(), fv.clone())?;
        moved = Some(match moved {
            None => (fu, fv),
            Some((u, v)) => (
                u.start.min(fu.start)..u.end.max(fu.end),
                v.start.min(fv.start)..v.end.max(fv.end),
            ),
        });
    }
    let Some((free_u, free_v)) = moved else {
        return Ok(None);
    };
    let (faired, t, bound) = certified_step(surface, fit, opts.tolerance)?;
    let bound = bound.ok_or_else(|| {
        Error::InvalidInput(
            "rational surface (unequal weights): the deviation of its fair on its own knots and weights could \
             not be bounded (its difference net could not be refined)"
                .into(),
        )
    })?;
    let mut notes = vec![];
    if tiles.len() > 1 {
        notes.push(format!(
            "C0 knot lines: fitted on its own knots and weights tile by tile between them ({} tiles), the \
             control rows on each side of a line held, so each line keeps its continuity",
            tiles.len()
        ));
    }
    Ok(Some(SurfaceFairingResult {
        surface: faired,
        max_deviation: bound,
        band_bound: Some(bound),
        alpha: stand_in.alpha * t,
        free_u,
        free_v,
        notes,
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
                None => ", and on its own knots no control row can move between its C0 knot lines".into(),
            }
        ))),
    }
}
