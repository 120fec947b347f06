//! Knots above the degree's multiplicity in B-splines read from files (a break, "C−1"), resolved the same
//! way for every reader ([`crate::knots::resolve_breaks`]): reduced to a C0 knot where the geometry is
//! continuous there, split into pieces otherwise, one notice per break.

use glam::DVec3;

use crate::curve::BSplineCurve;
use crate::error::Result;
use crate::geometry::Geometry;
use crate::surface::BSplineSurface;

/// A curve read from a file as one or more pieces, its breaks resolved (`what` names the entity in the
/// notices).
pub(crate) fn curve_pieces(
    what: &str,
    notices: &mut Vec<String>,
    degree: usize,
    knots: Vec<f64>,
    pts: Vec<DVec3>,
    weights: Option<Vec<f64>>,
    dim: usize,
) -> Result<Vec<Geometry>> {
    let scale = coordinate_scale(&pts);
    let same =
        |a: usize, b: usize| pts[a].distance(pts[b]) <= 1e-9 * scale && weights.as_ref().is_none_or(|w| w[a] == w[b]);
    let (pieces, breaks) = crate::knots::resolve_breaks(&knots, degree, same);
    note_breaks(notices, what, "", &breaks, pieces.len());
    if pieces.len() == 1 && pieces[0].knots == knots {
        // no break: the values as read
        return Ok(vec![BSplineCurve::try_new(degree, knots, pts, weights, dim)?.into()]);
    }
    pieces
        .into_iter()
        .map(|pc| {
            let w = weights.as_ref().map(|w| pc.points.iter().map(|&i| w[i]).collect());
            let q = pc.points.iter().map(|&i| pts[i]).collect();
            Ok(Geometry::Curve(BSplineCurve::try_new(degree, pc.knots, q, w, dim)?))
        })
        .collect()
}

/// The largest coordinate magnitude of `pts` (at least 1e-300): the scale of "coincide" at a break.
pub(crate) fn coordinate_scale(pts: &[DVec3]) -> f64 {
    pts.iter().map(|q| q.abs().max_element()).fold(1e-300, f64::max)
}

/// One notice per break resolved by [`crate::knots::resolve_breaks`] (`dir` names the direction of a
/// surface, empty for a curve).
pub(crate) fn note_breaks(
    notices: &mut Vec<String>,
    what: &str,
    dir: &str,
    breaks: &[crate::knots::Break],
    pieces: usize,
) {
    for b in breaks {
        notices.push(match b {
            crate::knots::Break::Reduced(u) => format!(
                "{what}: knot {dir}{u} has multiplicity above the degree but the geometry is continuous there: \
                 reduced to a C0 knot (same shape)"
            ),
            crate::knots::Break::Split(u) => format!(
                "{what}: the geometry breaks at knot {dir}{u} (multiplicity above the degree): split there, \
                 {pieces} pieces in all"
            ),
        });
    }
}

/// A surface read from a file, its breaks (knots above the degree's multiplicity) resolved in u, then in
/// v on each u-piece ([`crate::knots::resolve_breaks`]): reduced where the rows coincide, split otherwise.
pub(crate) fn surface_pieces(
    what: &str,
    notices: &mut Vec<String>,
    (pu, pv): (usize, usize),
    (ku, kv): (Vec<f64>, Vec<f64>),
    nv: usize,
    points: Vec<DVec3>,
    weights: Option<Vec<f64>>,
) -> Result<Vec<Geometry>> {
    let scale = coordinate_scale(&points);
    let at = |i: usize, j: usize| i * nv + j;
    let same_pt = |a: usize, b: usize| {
        points[a].distance(points[b]) <= 1e-9 * scale && weights.as_ref().is_none_or(|w| w[a] == w[b])
    };
    let (u_pieces, u_breaks) =
        crate::knots::resolve_breaks(&ku, pu, |a, b| (0..nv).all(|j| same_pt(at(a, j), at(b, j))));
    let mut all = vec![];
    let mut v_notes = vec![];
    for up in &u_pieces {
        let (v_pieces, v_breaks) =
            crate::knots::resolve_breaks(&kv, pv, |a, b| up.points.iter().all(|&i| same_pt(at(i, a), at(i, b))));
        v_notes.extend(v_breaks);
        for vp in v_pieces {
            let idx: Vec<usize> = up
                .points
                .iter()
                .flat_map(|&i| vp.points.iter().map(move |&j| at(i, j)))
                .collect();
            all.push(Geometry::Surface(BSplineSurface::try_new(
                pu,
                pv,
                up.knots.clone(),
                vp.knots,
                up.points.len(),
                vp.points.len(),
                idx.iter().map(|&k| points[k]).collect(),
                weights.as_ref().map(|w| idx.iter().map(|&k| w[k]).collect()),
            )?));
        }
    }
    note_breaks(notices, what, "u = ", &u_breaks, all.len());
    v_notes.dedup();
    note_breaks(notices, what, "v = ", &v_notes, all.len());
    Ok(all)
}
