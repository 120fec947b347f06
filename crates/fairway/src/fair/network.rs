//! Fairing many objects together, keeping their joins ([`crate::network`]): curve networks and patch
//! layouts.
//!
//! **Curves.** Curves joined end to end are *concatenated* into one B-spline where the join allows it,
//! faired as one curve by [`CurveFairing`], and split back at the join parameters:
//!
//! * a G1 / G2 join that is parametrically C1 / C2 after a linear rescale of the next curve's parameter
//!   (its speed at the join made equal to the previous one's) becomes a knot of multiplicity p − 1 /
//!   p − 2, or lower where knot removal is exact (1e-9 × the control net's size): the fit on those knots
//!   keeps the continuity by construction, and the joint moves freely within the band;
//! * a corner (G0 with a tangent break above [`CORNER_ANGLE_DEG`]) becomes a knot of multiplicity p, which
//!   the engine keeps as a corner (its point and both tangent directions stay: the angle is exact); a
//!   closed loop of curves becomes a closed curve (its seam at a corner if it has one);
//! * curves of different degrees are raised to the higher one first
//!   ([`BSplineCurve::elevate_degree`], exact) and come back raised.
//!
//! Each curve's band is its own: the concatenated curve equals the pieces (but for the knot removal's
//! tolerance and half of the join's gap, both subtracted from the band), so the band around it is the
//! pieces' bands. A G2 join that is only C1 after the rescale is made C2 by moving the next curve's third
//! control point along the tangent (which keeps the joint's curvature; the move, at most a quarter of the
//! band, is subtracted from it). Where a join cannot be concatenated (a G2 join needing a larger move, a
//! G1 join not C1, a tangent break below the corner angle, three or more ends at one point, a neighbour
//! not being faired, a rational curve), each curve *holds* its end there with the join's continuity (at
//! least G1, so an angle stays) through [`FairingOptions::curve_ends`] of that end: a G1 end keeps its
//! point and tangent direction, a G2 end its curvature too, while a free end of the same curve keeps
//! the default (position and tangent); [`NetworkFair::notes`] says which joins were held and why.
//!
//! **Surfaces.** Patches sharing edges with G1 (G2) that are parametrically C1 (C2) after a linear
//! rescale across them are concatenated into one surface where they form a strip (each patch joined on at
//! most two opposite sides): each edge becomes a knot line of multiplicity
//! p − 1 (p − 2), or lower where exact; the strip is faired by [`fair_surface`](crate::fair::fair_surface) and split back, each
//! patch on its own knots across the edges. A strip that closes on itself (a ring of patches around a
//! tube) is joined likewise, closed across its last edge, and faired across that edge too, as a closed
//! curve is across its seam: two passes with their seams half the ring apart, blended (`surfaces/ring.rs`);
//! R ≥ 2 rows of patches around a cylinder are joined as a grid cut open along one column line and faired
//! the same way. Knot vectors along an edge are first merged (knot
//! insertion, exact), and patches of different degrees raised to the higher ones (exact; they come back
//! raised). Patches forming a regular grid of 2 × 2 or more, every shared edge concatenable, are joined
//! likewise into one surface, rows first then the rows together, one rescale per column and per row
//! (`surfaces/grid.rs`). Other patch sets sharing concatenable edges that lie on a grid of cells (an L,
//! a T, a plus, a grid or strip with an edge held) are faired as one surface over the rectangle around
//! them, the empty cells an extension of the patches (`surfaces/layout.rs`). Any other shared edge (a
//! crease, a neighbour not faired, a rational patch, an edge parametrized differently on its two sides,
//! a knot line that is G2 along one edge but only C1-able along another — the patches on each side of
//! it are still faired together —, a held edge facing an empty cell of a layout's frame) is held: each
//! patch is faired with a region
//! stopping one knot span short of it (the span next to the edge stays as it is, so the edge and the
//! cross derivatives there do). [`ObjectFair::route`] says which route each object took.

use glam::DVec3;

use super::curve::{EndCondition, FairingOptions};
use super::curve_fairing::{CurveFairing, Pass};
use super::surface::SurfaceFairingOptions;
use crate::corners::CORNER_ANGLE_DEG;
use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::geometry::Geometry;
use crate::network::{Continuity, CurveEnd, End, Joins, find_joins};

mod surfaces;

/// Options of [`fair_network`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NetworkOptions {
    /// The curve fairing's options (tolerance, end conditions at free curve ends, method…); the region
    /// is ignored (each object is faired whole).
    pub curve: FairingOptions,
    /// The surface fairing's options (the region is ignored).
    pub surface: SurfaceFairingOptions,
    /// Concatenate across joins that allow it (the default, module docs); `false` holds every join:
    /// the objects faired one by one, each end at a join keeping its continuity.
    pub hold_all: bool,
}

/// What happened to one object.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectFair {
    /// Whether it was faired (it may still be unchanged if the fair kept the original).
    pub faired: bool,
    /// The objects faired together with it as one curve or surface (indices, in order along it; itself
    /// alone if it was faired on its own).
    pub group: Vec<usize>,
    /// A sound bound of its deviation from the original (0 if not faired).
    pub max_deviation: f64,
    /// Notes of the fair (the engine's, and what was done to the joins).
    pub notes: Vec<String>,
    /// The route it took.
    pub route: Route,
}

/// The route an object's fair took (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Route {
    /// Not faired (not chosen, or refused: the notes say why).
    #[default]
    NotFaired,
    /// On its own, any join it has held.
    Alone,
    /// Curves concatenated across their joins into one curve.
    Chain,
    /// A strip of patches joined into one surface.
    Strip,
    /// A ring of patches (a strip closing on itself, e.g. around a tube, or R × C patches around a
    /// cylinder) joined into one surface closed across its last edge(s).
    Ring,
    /// A full grid of R × C ≥ 2 × 2 patches joined into one surface.
    Grid,
    /// Patches sharing edges that are neither a strip nor a full grid (an L, a T, …), laid on the cells of
    /// the rectangle around them and faired as one surface (the empty cells an extension of the patches).
    Layout,
}

impl Route {
    /// Its name in reports: "not faired", "alone", "chain", "strip", "ring", "grid", "layout".
    pub fn name(self) -> &'static str {
        match self {
            Route::NotFaired => "not faired",
            Route::Alone => "alone",
            Route::Chain => "chain",
            Route::Strip => "strip",
            Route::Ring => "ring",
            Route::Grid => "grid",
            Route::Layout => "layout",
        }
    }
}

/// The outcome of [`fair_network`].
#[derive(Debug, Clone)]
pub struct NetworkFair {
    /// Every object, faired or as it was, in the input's order.
    pub objects: Vec<Geometry>,
    /// Per object.
    pub outcome: Vec<ObjectFair>,
    /// The joins of the input, measured on the input.
    pub joins_before: Joins,
    /// The same joins measured on the result.
    pub joins_after: Joins,
    /// What was done to each join of an object faired: concatenated, held and why.
    pub notes: Vec<String>,
}

/// How a curve join is kept.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Link {
    /// Concatenated as a corner (knot of multiplicity p).
    Corner,
    /// Concatenated with parametric continuity C^k (k = 1, 2).
    Smooth(usize),
}

/// Fair the objects `selected` of `objects` (all if empty) together, keeping their joins (module docs).
/// Objects not selected stay as they are; a selected object's join with one of them is held.
pub fn fair_network(objects: &[Geometry], selected: &[usize], opts: &NetworkOptions) -> Result<NetworkFair> {
    fair_network_at(objects, selected, opts, &[])
}

/// [`fair_network`] with each object's own tolerance: `tolerances[i]` for object `i` (`None`, or past the
/// slice's end: the options' tolerance for its kind). Objects faired as one curve or one surface share
/// the smallest of their tolerances, so each stays within its own band; their notes say so where the
/// tolerances differ.
pub fn fair_network_at(
    objects: &[Geometry],
    selected: &[usize],
    opts: &NetworkOptions,
    tolerances: &[Option<f64>],
) -> Result<NetworkFair> {
    network_fair(objects, selected, opts, tolerances)
}

/// [`fair_network_at`] that stops when `cancel` is set (from another thread): it then returns
/// [`Error::Cancelled`] — never some objects faired and others not
/// ([`crate::cancel`]). Checkpoints: before each curve chain, between the curves and the surfaces, and
/// every surface fair's own (each route's `fair_surface`); a route whose fair was cancelled falls back to
/// the next as on any error, and the call returns `Cancelled` at its end. A token that is not set changes
/// nothing: the result is [`fair_network_at`]'s.
pub fn fair_network_at_with(
    objects: &[Geometry],
    selected: &[usize],
    opts: &NetworkOptions,
    tolerances: &[Option<f64>],
    cancel: &crate::Cancel,
) -> Result<NetworkFair> {
    cancel.run(|| network_fair(objects, selected, opts, tolerances))
}

/// The body of [`fair_network_at`] (with the caller's cancel token, if any, installed).
fn network_fair(
    objects: &[Geometry],
    selected: &[usize],
    opts: &NetworkOptions,
    tolerances: &[Option<f64>],
) -> Result<NetworkFair> {
    let joins = find_joins(objects);
    // faces on one surface (a trimmed face split in two, read with its surface twice): the surface is
    // faired once, under its first object, and the others take its result; their "joins" with it are
    // the surface's own untrimmed boundaries, not edges between faces
    let twin: Vec<Option<usize>> = (0..objects.len())
        .map(|i| (0..i).find(|&j| matches!(objects[i], Geometry::Surface(_)) && objects[j] == objects[i]))
        .collect();
    let single = |i: usize| twin[i].is_none();
    let mut faired_joins = joins.clone();
    faired_joins.curves.retain(|j| single(j.a.object) && single(j.b.object));
    faired_joins.surfaces.retain(|j| single(j.a.0) && single(j.b.0));
    let net = Net {
        opts,
        chosen: (0..objects.len())
            .map(|i| single(i) && (selected.is_empty() || selected.contains(&i) || twin_chosen(&twin, selected, i)))
            .collect(),
        tolerance: objects
            .iter()
            .enumerate()
            .map(|(i, g)| {
                tolerances.get(i).copied().flatten().unwrap_or(match g {
                    Geometry::Curve(_) => opts.curve.tolerance,
                    Geometry::Surface(_) => opts.surface.tolerance,
                })
            })
            .collect(),
    };
    let mut out = objects.to_vec();
    let mut outcome: Vec<ObjectFair> = (0..objects.len())
        .map(|i| ObjectFair {
            faired: false,
            group: vec![i],
            max_deviation: 0.0,
            notes: vec![],
            route: Route::NotFaired,
        })
        .collect();
    let mut notes = vec![];
    let plan = curves::plan(objects, &faired_joins, &net, &mut notes);
    // the chains read only the originals: faired in parallel (as the surface engine's isocurves, on
    // `threads` workers), written back in order — the same result on any number of threads
    let faired = crate::fair::surface::par_map(&plan, opts.surface.threads, |chain| {
        crate::cancel::check().map(|()| curves::fair_chain(objects, chain, &net))
    });
    for (chain, f) in plan.iter().zip(faired) {
        curves::apply_chain(chain, f?, &mut out, &mut outcome);
    }
    crate::cancel::check()?;
    surfaces::fair_surfaces(objects, &faired_joins, &net, &mut out, &mut outcome, &mut notes);
    for (i, t) in twin.iter().enumerate() {
        let Some(j) = *t else { continue };
        if selected.is_empty() || selected.contains(&i) || selected.contains(&j) {
            out[i] = out[j].clone();
            outcome[i] = ObjectFair {
                group: vec![j, i],
                notes: vec![format!(
                    "the same surface as object {j} (faces on one surface): faired once, with it"
                )],
                ..outcome[j].clone()
            };
        }
    }
    let joins_after = remeasure(&joins, &out);
    Ok(NetworkFair {
        objects: out,
        outcome,
        joins_before: joins,
        joins_after,
        notes,
    })
}

/// Whether the surface object `i` is faired with a twin of it (an earlier object with the same surface,
/// [`fair_network_at`]) that is not itself selected: selecting either face fairs the surface.
fn twin_chosen(twin: &[Option<usize>], selected: &[usize], i: usize) -> bool {
    twin.iter()
        .enumerate()
        .any(|(k, t)| *t == Some(i) && selected.contains(&k))
}

/// What every step of a network fair reads: the options, which objects are faired and each one's band.
pub(crate) struct Net<'a> {
    /// The options.
    pub(crate) opts: &'a NetworkOptions,
    /// Whether each object is faired.
    pub(crate) chosen: Vec<bool>,
    /// Each object's tolerance.
    pub(crate) tolerance: Vec<f64>,
}

impl Net<'_> {
    /// The band of the objects `group` faired as one: the smallest of their tolerances (each stays within
    /// its own), and a note saying so where they differ.
    pub(crate) fn band(&self, group: &[usize]) -> (f64, Option<String>) {
        let tols: Vec<f64> = group.iter().map(|&i| self.tolerance[i]).collect();
        let m = tols.iter().copied().fold(f64::INFINITY, f64::min);
        let differ = tols.iter().any(|&t| t != m);
        let note = differ.then(|| {
            format!(
                "faired at {}, the smallest tolerance of objects {group:?} (faired as one, each within its own)",
                crate::range::short(m)
            )
        });
        (m, note)
    }

    /// The surface options of the objects `group` faired as one, at their [`Self::band`], and its note.
    pub(crate) fn surface_options(&self, group: &[usize]) -> (SurfaceFairingOptions, Option<String>) {
        let (tolerance, note) = self.band(group);
        (
            SurfaceFairingOptions {
                tolerance,
                ..self.opts.surface
            },
            note,
        )
    }

    /// The curve options of the objects `group` faired as one, at their [`Self::band`], and its note.
    pub(crate) fn curve_options(&self, group: &[usize]) -> (FairingOptions, Option<String>) {
        let (tolerance, note) = self.band(group);
        (
            FairingOptions {
                tolerance,
                ..self.opts.curve
            },
            note,
        )
    }
}

/// The joins `before` measured again on `objects` (the same ends and edges).
pub fn remeasure(before: &Joins, objects: &[Geometry]) -> Joins {
    let mut j = before.clone();
    for c in &mut j.curves {
        c.continuity = crate::network::curve_continuity(objects, c.a, c.b);
        let curve = |e: CurveEnd| objects[e.object].as_curve().expect("a curve");
        c.point = (crate::network::end_frame(curve(c.a), c.a.end, true).0
            + crate::network::end_frame(curve(c.b), c.b.end, false).0)
            * 0.5;
    }
    for s in &mut j.surfaces {
        s.continuity = crate::network::surface_join_continuity(objects, s);
    }
    j
}

/// The knot `at` (of multiplicity `mult` in every curve of `rows`) removed from all of them at once, one
/// at a time while every one allows it within `tol` and down to multiplicity `floor`: the rows and the
/// multiplicity left (a curve's join is `rows` of one; a surface's edge or seam, its control rows).
pub(crate) fn remove_knot_rows(
    mut rows: Vec<BSplineCurve>,
    at: f64,
    tol: f64,
    mut mult: usize,
    floor: usize,
) -> (Vec<BSplineCurve>, usize) {
    while mult > floor {
        let Ok(next) = rows
            .iter()
            .map(|c| c.remove_knot(at, 1, tol))
            .collect::<Result<Vec<_>>>()
        else {
            break;
        };
        (rows, mult) = (next, mult - 1);
    }
    (rows, mult)
}

/// The knot-removal tolerance of a concatenation: 1e-9 × the control net's size.
fn removal_tolerance(c: &BSplineCurve) -> f64 {
    let (lo, hi) = c.control_bounds();
    1e-9 * (hi - lo).length()
}

/// `c` on the domain `[t0, t0 + len]` (a linear map of its parameter).
pub(crate) fn rescaled(c: &BSplineCurve, t0: f64, len: f64) -> Result<BSplineCurve> {
    let (a, b) = c.domain();
    let s = len / (b - a);
    let n = c.knots().values().len();
    let p = c.degree();
    let mut k: Vec<f64> = c.knots().values().iter().map(|&u| t0 + (u - a) * s).collect();
    k[..=p].fill(t0);
    k[n - 1 - p..].fill(t0 + len);
    BSplineCurve::try_new(p, k, c.points().to_vec(), None, c.dim())
}

/// `c` with the knot values of `reference` (same count; else its domain mapped linearly onto the
/// reference's): a piece split back from a concatenation on its original knots.
pub(crate) fn on_knots_of(c: &BSplineCurve, reference: &BSplineCurve) -> Result<BSplineCurve> {
    if c.knots().values().len() == reference.knots().values().len() && c.degree() == reference.degree() {
        BSplineCurve::try_new(
            c.degree(),
            reference.knots().values().to_vec(),
            c.points().to_vec(),
            None,
            c.dim(),
        )
    } else {
        let (a, b) = reference.domain();
        rescaled(c, a, b - a)
    }
}

/// Concatenate `first` (ending at the join) and `second` (starting there, its parameter rescaled so its
/// speed at the join is `first`'s) with `link`: the curve, the join's parameter and the error made
/// (half the gap, plus the knot removals' tolerance). A G2 join that is only C1 after the rescale (the
/// second derivatives differ along the tangent) is made C2 by [`matched_second_derivative`], whose move
/// is added to the error. Errors if the join is not C^k after the rescale (and that move).
pub(crate) fn concatenate(first: &BSplineCurve, second: &BSplineCurve, link: Link) -> Result<(BSplineCurve, f64, f64)> {
    match concatenate_as(first, second, link, false) {
        Err(e) if link == Link::Smooth(2) => concatenate_as(first, second, link, true).map_err(|_| e),
        r => r,
    }
}

/// `second` (starting where `first` ends, with its speed there) with its third control point moved so
/// that its second derivative at the join is `first`'s: C2 there. At a G2 join the two differ along the
/// tangent (up to the curvature's tolerance), so the move keeps the joint's position, tangent and
/// curvature; the curve moves by at most the move's length (the basis functions sum to one). The curve
/// and that length. Refused below degree 3, and where the point is among the last three (the far end's
/// tangent and curvature would change).
fn matched_second_derivative(first: &BSplineCurve, second: &BSplineCurve) -> Result<(BSplineCurve, f64)> {
    let (p, t) = (second.degree(), second.knots().values());
    if p < 3 || second.n_points() < 6 {
        return Err(Error::InvalidInput(
            "too few control points (or degree below 3) to make it C2".into(),
        ));
    }
    // c''(t₀) depends on P₂ with the weight p(p−1) / ((t_{p+1} − t₂)(t_{p+2} − t₂)) (NURBS Book, 3.3)
    let w = (p * (p - 1)) as f64 / ((t[p + 1] - t[2]) * (t[p + 2] - t[2]));
    let d2a = first.derivs(first.domain().1).d2;
    let d2b = second.derivs(second.domain().0).d2;
    let delta = (d2a - d2b) / w;
    let mut pts = second.points().to_vec();
    pts[2] += delta;
    Ok((second.with_points(pts)?, delta.length()))
}

/// [`concatenate`], `second` first made C2 with `first` ([`matched_second_derivative`]) if `match_d2`.
pub(crate) fn concatenate_as(
    first: &BSplineCurve,
    second: &BSplineCurve,
    link: Link,
    match_d2: bool,
) -> Result<(BSplineCurve, f64, f64)> {
    let (_, y) = first.domain();
    let (b0, b1) = second.domain();
    let (d_first, d_second) = (first.d1(y).length(), second.d1(b0).length());
    if !(d_first > 0.0 && d_second > 0.0) {
        return Err(Error::InvalidInput("a curve stops at the join".into()));
    }
    let len = (b1 - b0) * d_second / d_first;
    let second = rescaled(second, y, len)?;
    let (second, moved) = if match_d2 {
        matched_second_derivative(first, &second)?
    } else {
        (second, 0.0)
    };
    let gap = first.point(y).distance(second.point(y));
    let mut c = super::closed::join(first, &second)?;
    let p = c.degree();
    let tol = removal_tolerance(&c);
    let mut err = 0.5 * gap + moved;
    if let Link::Smooth(k) = link {
        let (rows, mult) = remove_knot_rows(vec![c], y, tol, p, 0);
        c = rows.into_iter().next().expect("one row");
        // (one tolerance per knot removed, added as the removals were)
        (mult..p).for_each(|_| err += tol);
        if mult + k > p {
            return Err(Error::InvalidInput(format!(
                "not parametrically C{k} after a linear rescale (C{} at most)",
                p - mult
            )));
        }
    }
    Ok((c, y, err))
}

/// The end condition a held join asks of a curve end: the join's continuity, at least G1 (an angle
/// stays).
pub(crate) fn hold_condition(c: Continuity) -> EndCondition {
    match c {
        Continuity::G2 => EndCondition::G2,
        _ => EndCondition::G1,
    }
}

/// Is a join with this tangent break (radians) a corner the engine keeps?
pub(crate) fn is_corner(angle: f64) -> bool {
    angle.to_degrees() > CORNER_ANGLE_DEG
}

/// A point for messages: `(x, y, z)` shortened.
pub(crate) fn at(p: DVec3) -> String {
    use crate::range::short;
    format!("({}, {}, {})", short(p.x), short(p.y), short(p.z))
}

/// The fair of one prepared curve (a chain's concatenation, or a curve alone) with its end conditions.
pub(crate) fn fair_one_curve(
    c: &BSplineCurve,
    opts: FairingOptions,
    needs: [Option<EndCondition>; 2],
) -> Result<super::curve::FairingResult> {
    let (opts, ends) = curves::end_setup(opts, needs);
    Ok(CurveFairing::with_ends(c, opts, ends)?.fair(Pass::Full)?.result)
}

/// The end of a curve seen from a chain running along it reversed or not.
pub(crate) fn oriented(end: End, reversed: bool) -> End {
    match (end, reversed) {
        (e, false) => e,
        (End::Start, true) => End::End,
        (End::End, true) => End::Start,
    }
}

mod curves;
