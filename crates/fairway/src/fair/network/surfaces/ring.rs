//! Rings of patches: a strip that closes on itself (4 patches around a tube, each sharing an edge with the
//! next and the last with the first) faired as one surface with every edge kept, the closing one too.
//!
//! The ring is joined as a strip opened at its closing edge (`join_strip`: the surface `J`, v around the
//! ring), its first and last control rows — the two sides of the closing edge, equal within the joins'
//! tolerance — set to their mean (half the gap counted against the band), so `J` is closed in v. Like a
//! closed curve ([`crate::fair::closed`]) it is faired twice and the two blended:
//!
//! 1. **Pass A** fairs `J` as it is: the surface engine holds the rows next to a seam
//!    (`POLE_ROWS` on each side), so the closing edge stays exactly as it was, every other edge is an
//!    interior knot line (C1/C2 by construction).
//! 2. **Re-seaming.** Each row of `J` is rotated at the edge nearest the middle of the ring
//!    ([`rotate`]) and the old seam's knot removed (tolerance 1e-9 × the net's size) down to the closing
//!    edge's multiplicity p − k (k = 2 across a G2 edge, else 1): this succeeds when the closing edge is
//!    parametrically C^k with the rescales the other edges gave the patches (else the ring is refused
//!    and its edges held, with that reason). **Pass B** fairs the rotated surface: its seam (held) is the
//!    middle edge, the closing edge an interior knot line; it is rotated back ([`unrotate`]: exact, the
//!    rows next to the middle edge did not move).
//! 3. **Blend** control row by control row on `J`'s knots, `P = A + φ (B − A)`, φ = 1 within 15 % of the
//!    ring's length from the closing edge (where A held), 0 beyond 35 % (B held around the middle
//!    edge), the quintic step between: one surface on `J`'s knots, so every interior edge keeps its
//!    continuity, and the closing edge is B's (φ = 1 on the rows next to it, checked), C^k as an interior
//!    line of B. Its deviation from `J` is bounded soundly
//!    ([`surface_band_bound`](crate::fair::verify::surface_band_bound)); where it exceeds the band (the two passes
//!    moved a spot to opposite sides), pass A alone is taken — the closing edge held as it was — and the
//!    notes say so.
//!
//! The ring is then split back into its patches as a strip is (each on its own knots).

use super::{Patch, along_v, fair_joined, from_along_v, join_strip, split_back};
use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::fair::closed::{rotate, unrotate};
use crate::fair::surface::SurfaceFairingOptions;
use crate::fair::target::quintic;
use crate::geometry::Geometry;
use crate::network::SurfaceJoin;
use crate::surface::BSplineSurface;

/// The blend weight φ is 1 up to this fraction of the ring's length from the closing edge…
const BLEND_INNER: f64 = 0.15;
/// …and 0 from this one on.
const BLEND_OUTER: f64 = 0.35;

/// Fair a ring of patches (`order_[k]` joins `order_[k + 1]` by `edges[k]`, the last patch joins the first
/// by `closing`) as one closed surface (module docs): each member's patch.
pub(super) fn fair_ring(
    objects: &[Geometry],
    order_: &[usize],
    edges: &[&SurfaceJoin],
    closing: &SurfaceJoin,
    opts: &SurfaceFairingOptions,
    tol: f64,
) -> Result<Vec<Patch>> {
    let mut st = join_strip(objects, order_, edges, tol)?;
    let what = format!(
        "faired as one closed surface with objects {order_:?}, a ring of patches, across all their shared edges, the closing one too (each keeps its continuity)"
    );
    let (surface, bound, notes) = fair_closed_v(&mut st.joined, st.err, super::order(closing), &st.at, opts, tol)?;
    split_back(objects, order_, &st, &surface, bound, &notes, &what)
}

/// Fair a joined ring `j` (v around it, its edges at the v values `at`, closing across its v ends with
/// continuity order `k`; joining it moved it by up to `err`) as one closed surface (module docs):
/// `j` closed (its first and last rows set to their mean), then the faired surface on its knots, a bound of
/// its deviation from the patches, the fair's notes.
pub(super) fn fair_closed_v(
    j: &mut BSplineSurface,
    err: f64,
    k: usize,
    at: &[f64],
    opts: &SurfaceFairingOptions,
    tol: f64,
) -> Result<(BSplineSurface, f64, Vec<String>)> {
    let err = err + 0.5 * close(j, tol)?;
    let j = &*j;
    // pass A: the closing edge is the seam, held
    let (a, bound_a) = fair_joined(j, err, opts, None)?;
    let mid = middle_edge(j, at);
    let blended = (|| -> Result<(BSplineSurface, f64, Vec<String>)> {
        let rows = along_v(j);
        let rot = reseam(&rows, j, mid, k)?;
        let (b, _) = fair_joined(&rot, err, opts, None)?;
        let tol_rm = removal_tolerance(j);
        let back: Vec<BSplineCurve> = along_v(&b.surface)
            .iter()
            .zip(&rows)
            .map(|(r, o)| unrotate(r, o, tol_rm))
            .collect::<Result<_>>()?;
        let b = from_along_v(&back, (j.degree_u(), j.knots_u().values()))?;
        let s = blend(&a.surface, &b, j, mid, k)?;
        let m = opts.tolerance - err;
        let bound = crate::fair::verify::surface_band_bound(j, &s, m)
            .ok_or_else(|| Error::InvalidInput("the blend is not on the ring's knots".into()))?;
        if bound > m {
            return Err(Error::InvalidInput(format!(
                "the blend of the two passes leaves the band (by a bound of {})",
                crate::range::short(bound)
            )));
        }
        Ok((s, bound + err, a.notes.clone()))
    })();
    Ok(match blended {
        Ok(x) => x,
        Err(e) => {
            let mut n = a.notes.clone();
            n.push(format!(
                "the ring's closing edge held as it was (faired across the other edges only): {e}"
            ));
            (a.surface.clone(), bound_a, n)
        }
    })
}

/// Close a joined ring: its first and last control rows (v = v₀, v₁), equal within `tol` point by point,
/// set to their mean. The largest gap between them; an error where they differ by more (a ring that
/// meets itself turned, or with its edge parametrized differently).
fn close(s: &mut BSplineSurface, tol: f64) -> Result<f64> {
    let nv = s.nv();
    let mut pts = s.points().to_vec();
    let mut gap = 0.0f64;
    for i in 0..s.nu() {
        let (x, y) = (pts[i * nv], pts[i * nv + nv - 1]);
        gap = gap.max(x.distance(y));
        pts[i * nv] = (x + y) * 0.5;
        pts[i * nv + nv - 1] = pts[i * nv];
    }
    if gap > tol {
        return Err(Error::InvalidInput(
            "the ring does not close point for point across its closing edge (a twisted ring, or that edge parametrized differently on its two patches)".into(),
        ));
    }
    *s = s.with_points(pts)?;
    Ok(gap)
}

/// The knot-removal tolerance: 1e-9 × the net's size.
fn removal_tolerance(s: &BSplineSurface) -> f64 {
    let (lo, hi) = crate::curve::point_bounds(s.points());
    1e-9 * (hi - lo).length()
}

/// The v of the edge (among `at`) nearest the middle of the joined ring `j`.
fn middle_edge(j: &BSplineSurface, at: &[f64]) -> f64 {
    let (a, b) = j.domain().1;
    let half = 0.5 * (a + b);
    at.iter()
        .copied()
        .min_by(|x, y| (x - half).abs().total_cmp(&(y - half).abs()))
        .unwrap_or(half)
}

/// The ring's rows rotated at `mid`, the old seam's knot removed down to multiplicity p − k in every row
/// (the closing edge C^k) or lower where exact, as a surface.
fn reseam(rows: &[BSplineCurve], j: &BSplineSurface, mid: f64, k: usize) -> Result<BSplineSurface> {
    let seam = j.domain().1.1;
    let p = j.degree_v();
    let tol = removal_tolerance(j);
    let rot: Vec<BSplineCurve> = rows.iter().map(|r| rotate(r, mid)).collect::<Result<_>>()?;
    let (rot, mult) = crate::fair::network::remove_knot_rows(rot, seam, tol, p, 1);
    if mult + k > p {
        return Err(Error::InvalidInput(format!(
            "the closing edge is not parametrically C{k} with the rescales of the other edges (C{} at most)",
            p - mult
        )));
    }
    from_along_v(&rot, (j.degree_u(), j.knots_u().values()))
}

/// Pass A and pass B (rotated back) blended control row by control row on the ring's knots (module docs).
/// Errors where the rows next to the closing edge would not all be B's or those next to the middle edge
/// not all A's (too few knot spans around the ring).
fn blend(a: &BSplineSurface, b: &BSplineSurface, j: &BSplineSurface, mid: f64, k: usize) -> Result<BSplineSurface> {
    let (p, kv, nv) = (j.degree_v(), j.knots_v().values(), j.nv());
    let (v0, v1) = j.domain().1;
    let len = v1 - v0;
    let phi: Vec<f64> = (0..nv)
        .map(|c| {
            let g = kv[c + 1..=c + p].iter().sum::<f64>() / p as f64;
            let d = (g - v0).min(v1 - g) / len;
            1.0 - quintic((d - BLEND_INNER) / (BLEND_OUTER - BLEND_INNER))
        })
        .collect();
    // the closing edge's continuity lives on the k + 1 rows next to it; B held the rows whose support
    // reaches the middle edge's neighbourhood (its seam rows)
    let ends_b = (0..=k).all(|c| phi[c] == 1.0 && phi[nv - 1 - c] == 1.0);
    let mid_a = (0..nv)
        .filter(|&c| (kv[c] - mid).abs() < 1e-12 * len || (kv[c] < mid && kv[c + p + 1] > mid))
        .all(|c| phi[c] == 0.0);
    if !(ends_b && mid_a) {
        return Err(Error::InvalidInput(
            "too few knot spans around the ring to blend the two passes".into(),
        ));
    }
    let (pa, pb) = (a.points(), b.points());
    let pts = (0..j.nu() * nv)
        .map(|x| pa[x] + (pb[x] - pa[x]) * phi[x % nv])
        .collect();
    j.with_points(pts)
}
