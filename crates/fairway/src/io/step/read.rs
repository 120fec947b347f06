//! From Part 21 instances to Fairway geometry: the B-spline curves and
//! surfaces, their points and weights, and the file's length unit.

use crate::io::breaks::{curve_pieces, surface_pieces};
use std::collections::{BTreeMap, HashSet};

use glam::{DAffine3, DVec3, DVec4};

use super::parse::{Exchange, Instance, Param, Record};
use super::perr;
use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::geometry::Geometry;
use crate::io::interchange::{Conversion, EntityInfo, InterchangeFile, ReadOptions, map_points};
use crate::knots::MAX_DEGREE;
use crate::surface::BSplineSurface;

/// Curve and surface entities that are not B-splines: skipped, counted in one notice.
const OTHER_GEOMETRY: &[&str] = &[
    "LINE",
    "CIRCLE",
    "ELLIPSE",
    "HYPERBOLA",
    "PARABOLA",
    "POLYLINE",
    "OFFSET_CURVE_3D",
    "CLOTHOID",
    "PLANE",
    "CYLINDRICAL_SURFACE",
    "CONICAL_SURFACE",
    "SPHERICAL_SURFACE",
    "TOROIDAL_SURFACE",
    "DEGENERATE_TOROIDAL_SURFACE",
    "SURFACE_OF_LINEAR_EXTRUSION",
    "SURFACE_OF_REVOLUTION",
    "OFFSET_SURFACE",
];

/// Entities that trim the B-splines: not applied (the B-splines are read whole), counted in one notice.
const NOT_APPLIED: &[&str] = &["ADVANCED_FACE", "FACE_SURFACE", "EDGE_CURVE", "TRIMMED_CURVE"];

/// What a B-spline instance is, from its record names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Curve,
    Surface,
}

/// How the knots of a B-spline instance are given.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum KnotForm {
    WithKnots,
    Bezier,
    QuasiUniform,
    Uniform,
}

const CURVE_FORMS: [(&str, KnotForm); 4] = [
    ("B_SPLINE_CURVE_WITH_KNOTS", KnotForm::WithKnots),
    ("BEZIER_CURVE", KnotForm::Bezier),
    ("QUASI_UNIFORM_CURVE", KnotForm::QuasiUniform),
    ("UNIFORM_CURVE", KnotForm::Uniform),
];
const SURFACE_FORMS: [(&str, KnotForm); 4] = [
    ("B_SPLINE_SURFACE_WITH_KNOTS", KnotForm::WithKnots),
    ("BEZIER_SURFACE", KnotForm::Bezier),
    ("QUASI_UNIFORM_SURFACE", KnotForm::QuasiUniform),
    ("UNIFORM_SURFACE", KnotForm::Uniform),
];

/// The parameters of a B-spline instance, simple or complex, gathered by role.
struct Parts<'a> {
    kind: Kind,
    form: KnotForm,
    name: String,
    /// The `B_SPLINE_CURVE` (5) or `B_SPLINE_SURFACE` (7) attributes.
    base: &'a [Param],
    /// The knot attributes of `..._WITH_KNOTS` (curve 3, surface 5), empty otherwise.
    knots: &'a [Param],
    /// The weights list, for a rational B-spline.
    weights: Option<&'a Param>,
}

/// The B-spline form of an instance, if it is one: (kind, form, entity name).
fn bspline_form(inst: &Instance) -> Option<(Kind, KnotForm, &'static str)> {
    for (kind, forms) in [(Kind::Curve, CURVE_FORMS), (Kind::Surface, SURFACE_FORMS)] {
        for (name, form) in forms {
            if inst.record(name).is_some() {
                return Some((kind, form, name));
            }
        }
    }
    None
}

fn parts<'a>(inst: &'a Instance, kind: Kind, form: KnotForm, entity: &'static str) -> Result<Parts<'a>> {
    let (nb, nk) = match kind {
        Kind::Curve => (5, 3),
        Kind::Surface => (7, 5),
    };
    let nk = if form == KnotForm::WithKnots { nk } else { 0 };
    let name_of = |p: Option<&Param>| match p {
        Some(Param::Str(s)) => s.clone(),
        _ => String::new(),
    };
    let count = |r: &Record, n: usize| -> Result<()> {
        if r.params.len() == n {
            Ok(())
        } else {
            Err(perr(format!(
                "{} has {} parameters, expected {n}",
                r.name,
                r.params.len()
            )))
        }
    };
    if !inst.complex {
        let r = &inst.records[0];
        count(r, 1 + nb + nk)?;
        return Ok(Parts {
            kind,
            form,
            name: name_of(r.params.first()),
            base: &r.params[1..1 + nb],
            knots: &r.params[1 + nb..],
            weights: None,
        });
    }
    let (base_name, rational_name) = match kind {
        Kind::Curve => ("B_SPLINE_CURVE", "RATIONAL_B_SPLINE_CURVE"),
        Kind::Surface => ("B_SPLINE_SURFACE", "RATIONAL_B_SPLINE_SURFACE"),
    };
    let base = inst
        .record(base_name)
        .ok_or_else(|| perr(format!("the complex instance has no {base_name} part")))?;
    count(base, nb)?;
    let knots = inst.record(entity).expect("found by bspline_form");
    count(knots, nk)?;
    let weights = match inst.record(rational_name) {
        None => None,
        Some(r) => {
            count(r, 1)?;
            Some(&r.params[0])
        }
    };
    Ok(Parts {
        kind,
        form,
        name: name_of(inst.record("REPRESENTATION_ITEM").and_then(|r| r.params.first())),
        base: &base.params,
        knots: &knots.params,
        weights,
    })
}

fn int(p: &Param, what: &str) -> Result<i64> {
    match p {
        Param::Int(i) => Ok(*i),
        _ => Err(perr(format!("{what} is not an integer"))),
    }
}

fn degree(p: &Param, what: &str) -> Result<usize> {
    let d = int(p, what)?;
    if (1..=MAX_DEGREE as i64).contains(&d) {
        Ok(d as usize)
    } else {
        Err(perr(format!("{what} {d} is not supported (1 to {MAX_DEGREE})")))
    }
}

fn list<'a>(p: &'a Param, what: &str) -> Result<&'a [Param]> {
    p.list().ok_or_else(|| perr(format!("{what} is not a list")))
}

pub(super) fn reals(p: &Param, what: &str) -> Result<Vec<f64>> {
    let l = list(p, what)?;
    let mut v = Vec::with_capacity(l.len());
    for (i, x) in l.iter().enumerate() {
        match x.real() {
            Some(x) if x.is_finite() => v.push(x),
            _ => return Err(perr(format!("{what}: value {} is not a finite number", i + 1))),
        }
    }
    Ok(v)
}

/// A control point: `#n` naming a `CARTESIAN_POINT` with 2 or 3 coordinates.
pub(super) fn point(ex: &Exchange, p: &Param, k: usize) -> Result<(DVec3, usize)> {
    let Param::Ref(id) = p else {
        return Err(perr(format!("control point {} is not a reference to a point", k + 1)));
    };
    let inst = ex.get(*id).ok_or_else(|| {
        perr(format!(
            "control point {} refers to #{id}, which is not in the file",
            k + 1
        ))
    })?;
    let rec = inst.record("CARTESIAN_POINT").ok_or_else(|| {
        perr(format!(
            "control point {} refers to #{id}, which is not a CARTESIAN_POINT",
            k + 1
        ))
    })?;
    let c = rec
        .params
        .get(1)
        .ok_or_else(|| perr(format!("#{id} (CARTESIAN_POINT) has no coordinates")))?;
    let c = reals(c, &format!("#{id} (CARTESIAN_POINT) coordinates"))?;
    match c[..] {
        [x, y] => Ok((DVec3::new(x, y, 0.0), 2)),
        [x, y, z] => Ok((DVec3::new(x, y, z), 3)),
        _ => Err(perr(format!(
            "#{id} (CARTESIAN_POINT) has {} coordinates, not 2 or 3",
            c.len()
        ))),
    }
}

/// The control points of a list of references, all of one dimension: (points, dimension).
fn points(ex: &Exchange, refs: &[Param], start: usize, dim: &mut usize) -> Result<Vec<DVec3>> {
    let mut v = Vec::with_capacity(refs.len());
    for (k, r) in refs.iter().enumerate() {
        let (q, d) = point(ex, r, start + k)?;
        if *dim == 0 {
            *dim = d;
        } else if *dim != d {
            return Err(perr(format!(
                "control point {} has {d} coordinates, the first has {}",
                start + k + 1,
                *dim
            )));
        }
        v.push(q);
    }
    Ok(v)
}

/// A full knot vector from multiplicities and distinct knots; the total checked against
/// `points + degree + 1` before anything is allocated.
fn expand_knots(mults: &Param, knots: &Param, degree: usize, n_points: usize, dir: &str) -> Result<Vec<f64>> {
    let m = list(mults, &format!("{dir}knot multiplicities"))?;
    let k = reals(knots, &format!("{dir}knots"))?;
    if m.len() != k.len() {
        return Err(perr(format!(
            "{} {dir}knot multiplicities for {} {dir}knots",
            m.len(),
            k.len()
        )));
    }
    let expected = n_points + degree + 1;
    let mut total: i64 = 0;
    for (i, x) in m.iter().enumerate() {
        let x = int(x, &format!("{dir}knot multiplicity {}", i + 1))?;
        if x < 1 {
            return Err(perr(format!(
                "{dir}knot multiplicity {} is {x}, must be at least 1",
                i + 1
            )));
        }
        total = total.saturating_add(x);
    }
    if total != expected as i64 {
        return Err(perr(format!(
            "{dir}knot multiplicities add up to {total}, expected {expected} for {n_points} control points of degree {degree}"
        )));
    }
    if let Some(i) = k.windows(2).position(|w| w[1] <= w[0]) {
        return Err(perr(format!(
            "{dir}knots must increase: knot {} ({}) is not above knot {} ({})",
            i + 2,
            k[i + 1],
            i + 1,
            k[i]
        )));
    }
    let mut out = Vec::with_capacity(expected);
    for (x, &u) in m.iter().zip(&k) {
        let times = x.real().unwrap_or(0.0) as usize;
        out.extend(std::iter::repeat_n(u, times));
    }
    Ok(out)
}

/// The knot vector implied by a form without explicit knots (ISO 10303-42 §4.3.4).
fn implied_knots(form: KnotForm, degree: usize, n_points: usize, dir: &str) -> Result<Vec<f64>> {
    let mut out = vec![0.0; degree + 1];
    match form {
        KnotForm::Bezier => {
            if !(n_points - 1).is_multiple_of(degree) {
                return Err(perr(format!(
                    "{dir}a Bézier form with {n_points} control points of degree {degree}: {} is not a multiple of the degree",
                    n_points - 1
                )));
            }
            let spans = (n_points - 1) / degree;
            for s in 1..spans {
                out.extend(std::iter::repeat_n(s as f64, degree));
            }
            out.extend(std::iter::repeat_n(spans as f64, degree + 1));
        }
        KnotForm::QuasiUniform => {
            let spans = n_points - degree;
            out.extend((1..spans).map(|s| s as f64));
            out.extend(std::iter::repeat_n(spans as f64, degree + 1));
        }
        KnotForm::Uniform => {
            // -p, ..., n: the domain [0, n - p]; clamped by the caller
            return Ok((0..n_points + degree + 1).map(|i| i as f64 - degree as f64).collect());
        }
        KnotForm::WithKnots => unreachable!("explicit knots are not implied"),
    }
    Ok(out)
}

fn knots_of(p: &Parts<'_>, mults: usize, knots: usize, degree: usize, n: usize, dir: &str) -> Result<Vec<f64>> {
    let k = if p.form == KnotForm::WithKnots {
        expand_knots(&p.knots[mults], &p.knots[knots], degree, n, dir)?
    } else {
        implied_knots(p.form, degree, n, dir)?
    };
    Ok(k)
}

/// The weights of a rational B-spline: a list for a curve, for a surface a list of `rows` rows of
/// `expected / rows` weights each (as its control points).
fn weights(p: &Parts<'_>, expected: usize, rows: Option<usize>) -> Result<Option<Vec<f64>>> {
    let Some(w) = p.weights else { return Ok(None) };
    let w = if let Some(nu) = rows {
        let nv = expected / nu.max(1);
        let rows = list(w, "weights")?;
        if rows.len() != nu {
            return Err(perr(format!(
                "{} rows of weights for {nu} rows of control points",
                rows.len()
            )));
        }
        let mut v = Vec::with_capacity(expected);
        for (i, r) in rows.iter().enumerate() {
            let r = reals(r, &format!("weights row {}", i + 1))?;
            if r.len() != nv {
                return Err(perr(format!(
                    "weights row {} has {} weights for {nv} control points",
                    i + 1,
                    r.len()
                )));
            }
            v.extend(r);
        }
        v
    } else {
        reals(w, "weights")?
    };
    if w.len() != expected {
        return Err(perr(format!("{} weights for {expected} control points", w.len())));
    }
    if let Some(i) = w.iter().position(|&x| x <= 0.0) {
        return Err(perr(format!("weight {} is {}, weights must be positive", i + 1, w[i])));
    }
    Ok(Some(w))
}

/// Whether the end knots are each repeated degree + 1 times.
fn is_clamped(knots: &[f64], p: usize) -> bool {
    let same = |ends: &[f64]| ends.iter().all(|&u| u == ends[0]);
    same(&knots[..=p]) && same(&knots[knots.len() - p - 1..])
}

/// An unclamped B-spline (periodic, uniform) made clamped by knot insertion (Boehm, The NURBS Book
/// A5.1) at both ends of its domain [U[p], U[n]]: the same curve on the same domain, its end knots
/// repeated p + 1 times. `pts` are homogeneous (x·w, y·w, z·w, w).
fn clamp(p: usize, knots: &[f64], pts: &[DVec4]) -> Result<(Vec<f64>, Vec<DVec4>)> {
    let (k, q) = clamp_start(p, knots.to_vec(), pts.to_vec())?;
    // the end: the start of the reversed curve
    let rk = k.iter().rev().map(|u| -u).collect();
    let (rk, rq) = clamp_start(p, rk, q.into_iter().rev().collect())?;
    Ok((rk.iter().rev().map(|u| -u).collect(), rq.into_iter().rev().collect()))
}

/// [`clamp`] at the start of the domain only.
fn clamp_start(p: usize, mut u: Vec<f64>, mut pts: Vec<DVec4>) -> Result<(Vec<f64>, Vec<DVec4>)> {
    let a = u[p];
    if u[..=p].iter().all(|&x| x == a) {
        return Ok((u, pts));
    }
    if u[pts.len()] <= a {
        return Err(perr(format!("knots: the domain [{a}, {}] is empty", u[pts.len()])));
    }
    // insert a until its multiplicity is p: the curve then passes through a control point there
    while u.iter().filter(|&&x| x == a).count() < p {
        // the last knot equal to a: k ≥ p, and u[k + 1] > a as the domain is not empty
        let k = u.iter().rposition(|&x| x == a).expect("u[p] = a");
        let mut q = Vec::with_capacity(pts.len() + 1);
        q.extend_from_slice(&pts[..=k - p]);
        for i in k - p + 1..=k {
            let alpha = (a - u[i]) / (u[i + p] - u[i]);
            q.push(pts[i] * alpha + pts[i - 1] * (1.0 - alpha));
        }
        q.extend_from_slice(&pts[k..]);
        u.insert(k + 1, a);
        pts = q;
    }
    // the basis functions on [a, ..) do not depend on the knots before the run of a: drop them and
    // the control points that only they weigh
    let last = u.iter().rposition(|&x| x == a).expect("u[p] = a");
    let after = u.len() - last - 1;
    let mut k = vec![a; p + 1];
    k.extend_from_slice(&u[last + 1..]);
    Ok((k, pts[pts.len() - after..].to_vec()))
}

fn homogeneous(pts: &[DVec3], w: Option<&[f64]>) -> Vec<DVec4> {
    pts.iter()
        .enumerate()
        .map(|(i, q)| {
            let w = w.map_or(1.0, |w| w[i]);
            (*q * w).extend(w)
        })
        .collect()
}

/// Points and (for a rational B-spline) weights from homogeneous points.
fn cartesian(h: &[DVec4], rational: bool) -> (Vec<DVec3>, Option<Vec<f64>>) {
    if rational {
        (
            h.iter().map(|q| q.truncate() / q.w).collect(),
            Some(h.iter().map(|q| q.w).collect()),
        )
    } else {
        (h.iter().map(|q| q.truncate()).collect(), None)
    }
}

/// Why an object was converted on reading, if it was (unclamped knots clamped).
const CLAMPED: &str = "unclamped knots (a periodic or uniform B-spline) made clamped by knot insertion: the same \
                       shape on the same domain";

/// A B-spline curve entity: one curve, or its pieces where it breaks (a knot above the degree's
/// multiplicity, [`crate::io::breaks`]); and whether its knots were clamped.
fn read_curve(ex: &Exchange, p: &Parts<'_>, what: &str, notices: &mut Vec<String>) -> Result<(Vec<Geometry>, bool)> {
    let degree = degree(&p.base[0], "degree")?;
    let refs = list(&p.base[1], "control points")?;
    if refs.len() < degree + 1 {
        return Err(perr(format!(
            "{} control points, a curve of degree {degree} needs at least {}",
            refs.len(),
            degree + 1
        )));
    }
    let mut dim = 0;
    let pts = points(ex, refs, 0, &mut dim)?;
    let knots = knots_of(p, 0, 1, degree, pts.len(), "")?;
    let w = weights(p, pts.len(), None)?;
    if is_clamped(&knots, degree) {
        return Ok((curve_pieces(what, notices, degree, knots, pts, w, dim)?, false));
    }
    let (knots, h) = clamp(degree, &knots, &homogeneous(&pts, w.as_deref()))?;
    let (pts, w) = cartesian(&h, w.is_some());
    Ok((curve_pieces(what, notices, degree, knots, pts, w, dim)?, true))
}

/// A B-spline surface entity: one surface, or its pieces where it breaks; and whether its knots were
/// clamped.
fn read_surface(ex: &Exchange, p: &Parts<'_>, what: &str, notices: &mut Vec<String>) -> Result<(Vec<Geometry>, bool)> {
    let du = degree(&p.base[0], "u degree")?;
    let dv = degree(&p.base[1], "v degree")?;
    let rows = list(&p.base[2], "control points")?;
    let nu = rows.len();
    let nv = rows.first().and_then(Param::list).map_or(0, <[Param]>::len);
    if nu < du + 1 || nv < dv + 1 {
        return Err(perr(format!(
            "{nu}×{nv} control points, a surface of degree {du}×{dv} needs at least {}×{}",
            du + 1,
            dv + 1
        )));
    }
    let mut dim = 0;
    let mut pts = Vec::new();
    for (i, r) in rows.iter().enumerate() {
        let r = list(r, &format!("control point row {}", i + 1))?;
        if r.len() != nv {
            return Err(perr(format!(
                "control point row {} has {} points, the first has {nv}",
                i + 1,
                r.len()
            )));
        }
        pts.extend(points(ex, r, i * nv, &mut dim)?);
    }
    if dim != 3 {
        return Err(perr("the control points have 2 coordinates; a surface needs 3"));
    }
    let ku = knots_of(p, 0, 2, du, nu, "u ")?;
    let kv = knots_of(p, 1, 3, dv, nv, "v ")?;
    let w = weights(p, nu * nv, Some(nu))?;
    if is_clamped(&ku, du) && is_clamped(&kv, dv) {
        return Ok((surface_pieces(what, notices, (du, dv), (ku, kv), nv, pts, w)?, false));
    }
    // rows (fixed i) in v, then columns (fixed j) in u
    let h = homogeneous(&pts, w.as_deref());
    let (mut kv2, mut rows) = (kv.clone(), Vec::with_capacity(nu));
    for i in 0..nu {
        let (k, r) = clamp(dv, &kv, &h[i * nv..(i + 1) * nv])?;
        kv2 = k;
        rows.push(r);
    }
    let nv2 = rows[0].len();
    let (mut ku2, mut cols) = (ku.clone(), Vec::with_capacity(nv2));
    for j in 0..nv2 {
        let col: Vec<DVec4> = rows.iter().map(|r| r[j]).collect();
        let (k, c) = clamp(du, &ku, &col)?;
        ku2 = k;
        cols.push(c);
    }
    let nu2 = cols[0].len();
    let h: Vec<DVec4> = (0..nu2).flat_map(|i| cols.iter().map(move |c| c[i])).collect();
    let (pts, w) = cartesian(&h, w.is_some());
    if pts.len() != nu2 * nv2 {
        return Ok((
            vec![BSplineSurface::try_new(du, dv, ku2, kv2, nu2, nv2, pts, w)?.into()],
            true,
        ));
    }
    Ok((surface_pieces(what, notices, (du, dv), (ku2, kv2), nv2, pts, w)?, true))
}

/// The B-spline surface `#id` in the file's coordinates (for its faces' bounds): `None` if it is not a
/// B-spline surface; an error if it cannot be read or breaks into pieces.
fn raw_surface(ex: &Exchange, id: u64) -> Result<Option<BSplineSurface>> {
    let Some(inst) = ex.get(id) else { return Ok(None) };
    let Some((Kind::Surface, form, entity)) = bspline_form(inst) else {
        return Ok(None);
    };
    let p = parts(inst, Kind::Surface, form, entity)?;
    match read_surface(ex, &p, "", &mut vec![])?.0.as_slice() {
        [Geometry::Surface(s)] => Ok(Some(s.clone())),
        _ => Err(perr(format!(
            "surface #{id} breaks into pieces (a knot above the degree)"
        ))),
    }
}

/// The B-spline curve `#id` in the file's coordinates (an edge's 3D curve or a p-curve's 2D one): `None`
/// if it is not a B-spline curve; an error if it cannot be read or breaks into pieces.
fn raw_curve(ex: &Exchange, id: u64) -> Result<Option<BSplineCurve>> {
    let Some(inst) = ex.get(id) else { return Ok(None) };
    let Some((Kind::Curve, form, entity)) = bspline_form(inst) else {
        return Ok(None);
    };
    let p = parts(inst, Kind::Curve, form, entity)?;
    match read_curve(ex, &p, "", &mut vec![])?.0.as_slice() {
        [Geometry::Curve(c)] => Ok(Some(c.clone())),
        _ => Err(perr(format!(
            "curve #{id} breaks into pieces (a knot above the degree)"
        ))),
    }
}

/// The instances that are items of a `DEFINITIONAL_REPRESENTATION`: curves in a surface's parameter
/// space (p-curves), not objects of their own.
fn parameter_space_items(ex: &Exchange) -> HashSet<u64> {
    let mut set = HashSet::new();
    for inst in &ex.instances {
        if let Some(r) = inst.record("DEFINITIONAL_REPRESENTATION")
            && let Some(items) = r.params.get(1).and_then(Param::list)
        {
            set.extend(items.iter().filter_map(|p| match p {
                Param::Ref(id) => Some(*id),
                _ => None,
            }));
        }
    }
    set
}

/// One B-spline instance as geometry, once per placement (each the pieces of its breaks), placed,
/// converted to the unit asked for and the coordinates range-checked.
fn read_instance(
    ex: &Exchange,
    p: &Parts<'_>,
    (placements, conversion): (&[DAffine3], Conversion),
    what: &str,
    notices: &mut Vec<String>,
) -> Result<(Vec<Vec<Geometry>>, bool)> {
    let (pieces, clamped) = match p.kind {
        Kind::Curve => read_curve(ex, p, what, notices)?,
        Kind::Surface => read_surface(ex, p, what, notices)?,
    };
    let occurrences = placements
        .iter()
        .map(|a| {
            (pieces.iter().cloned())
                .map(|g| {
                    let g = if *a == DAffine3::IDENTITY {
                        g
                    } else {
                        map_points(g, |q| a.transform_point3(q))?
                    };
                    instance_geometry(g, p, conversion)
                })
                .collect::<Result<Vec<_>>>()
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((occurrences, clamped))
}

/// A piece of an instance as Fairway holds it: a 2D curve as Fairway writes it (named so, z = 0) made
/// 2D, converted to the requested unit, and checked against the range Fairway computes in.
fn instance_geometry(g: Geometry, p: &Parts<'_>, conversion: Conversion) -> Result<Geometry> {
    // a 2D curve as Fairway writes it: named so, z = 0
    let g = match g {
        Geometry::Curve(c)
            if c.dim() == 3 && p.name.starts_with(super::PLANAR_NAME) && c.points().iter().all(|q| q.z == 0.0) =>
        {
            c.to_2d()?.into()
        }
        g => g,
    };
    let g = conversion.apply(g)?;
    crate::range::check_geometry(&g)?;
    Ok(g)
}

pub(super) fn reason(e: &Error) -> String {
    match e {
        Error::Parse { message, .. } => message.clone(),
        other => other.to_string(),
    }
}

/// The objects of one occurrence of a B-spline instance `#id` named `name`: its pieces (more than one
/// where a break split it), labelled.
fn push_pieces(
    pieces: Vec<Geometry>,
    name: &str,
    id: u64,
    objects: &mut Vec<Geometry>,
    entities: &mut Vec<EntityInfo>,
) {
    let count = pieces.len();
    for (k, g) in pieces.into_iter().enumerate() {
        // a named 2D curve as Fairway writes it: "2D curve: NAME" (`step::write_labeled`)
        let base = match (
            &g,
            name.strip_prefix(super::PLANAR_NAME).and_then(|n| n.strip_prefix(": ")),
        ) {
            (Geometry::Curve(c), Some(n)) if c.dim() == 2 => n.to_string(),
            _ => name.to_string(),
        };
        let label = match (count, base.is_empty()) {
            (1, _) => base,
            (_, true) => format!("piece {} of {count}", k + 1),
            (_, false) => format!("{base}, piece {} of {count}", k + 1),
        };
        objects.push(g);
        entities.push(EntityInfo {
            entity: id as usize,
            label,
        });
    }
}

/// Read every B-spline curve and surface of a parsed file (see [`super::read_all_with`]).
pub fn read_exchange(ex: &Exchange, opts: ReadOptions) -> Result<InterchangeFile> {
    let mut notices: Vec<String> = ex.errors.iter().map(|e| format!("{e} (skipped)")).collect();
    let unit = super::units::file_unit(ex, &mut notices);
    let units = match (opts.unit, unit) {
        (None, _) => None,
        (Some(to), Some(from)) => Some((from, to)),
        (Some(to), None) => {
            return Err(perr(format!(
                "the file's length unit is not recognised, cannot convert to {}",
                to.name()
            )));
        }
    };
    let conversion = Conversion { units, scale: 1.0 };
    let pcurves = parameter_space_items(ex);
    let faces = super::trim::face_trims(ex, &|id| raw_surface(ex, id), &|id| raw_curve(ex, id));
    let placements = super::placement::placements(ex, |i| bspline_form(i).is_some());
    let (mut objects, mut entities, mut trims) = (Vec::new(), Vec::new(), Vec::new());
    let mut first_error = None;
    let mut others: BTreeMap<&str, usize> = BTreeMap::new();
    let mut not_applied: BTreeMap<&str, usize> = BTreeMap::new();
    for inst in &ex.instances {
        let Some((kind, form, entity)) = bspline_form(inst) else {
            if pcurves.contains(&inst.id) {
                continue; // a p-curve that is a line, a circle, ...: part of a face's trim, not an object
            }
            if let Some(r) = inst.records.iter().find(|r| OTHER_GEOMETRY.contains(&r.name.as_str())) {
                *others.entry(r.name.as_str()).or_default() += 1;
            }
            if let Some(r) = (inst.records.iter())
                .find(|r| NOT_APPLIED.contains(&r.name.as_str()))
                .filter(|_| !faces.used.contains(&inst.id))
            {
                *not_applied.entry(r.name.as_str()).or_default() += 1;
            }
            continue;
        };
        let what = format!("#{} ({entity})", inst.id);
        if faces.used.contains(&inst.id) {
            continue; // an edge (or p-curve) of a face whose bounds were read: part of its trim
        }
        if pcurves.contains(&inst.id) {
            notices.push(format!("{what} skipped: a curve in a surface's parameter space"));
            continue;
        }
        let mut piece_notes = vec![];
        let placed = (placements.of(inst.id), conversion);
        let read = parts(inst, kind, form, entity)
            .and_then(|p| Ok((read_instance(ex, &p, placed, &what, &mut piece_notes)?, p.name)));
        match read {
            Ok(((occurrences, clamped), name)) => {
                if clamped {
                    notices.push(format!("{what}: {CLAMPED}"));
                }
                notices.append(&mut piece_notes);
                let n = occurrences.len();
                for (j, pieces) in occurrences.into_iter().enumerate() {
                    // a part used more than once in an assembly: one object per placement
                    let name = match (n, name.is_empty()) {
                        (1, _) => name.clone(),
                        (_, true) => format!("occurrence {} of {n}", j + 1),
                        (_, false) => format!("{name} (occurrence {} of {n})", j + 1),
                    };
                    let trim = faces.by_surface.get(&inst.id).filter(|_| pieces.len() == 1);
                    trims.extend(std::iter::repeat_n(trim.cloned(), pieces.len()));
                    push_pieces(pieces, &name, inst.id, &mut objects, &mut entities);
                }
            }
            Err(e) => {
                notices.push(format!("{what} on line {} skipped: {}", inst.line, reason(&e)));
                first_error.get_or_insert(perr(format!("{what}: {}", reason(&e))));
            }
        }
    }
    notices.extend(faces.notices);
    let consumed = faces
        .used
        .iter()
        .filter(|id| ex.get(**id).is_some_and(|i| bspline_form(i).is_some()))
        .count();
    if !faces.by_surface.is_empty() {
        notices.push(format!(
            "{} trimmed faces read with their bounds ({consumed} B-spline edge curves kept as their trims, not as \
             objects of their own)",
            faces.by_surface.len()
        ));
    }
    notices.extend(placements.notice());
    if !others.is_empty() {
        let list: Vec<String> = others.iter().map(|(k, n)| format!("{n} {k}")).collect();
        notices.push(format!(
            "{} other curves and surfaces skipped (only B-splines are read): {}",
            others.values().sum::<usize>(),
            list.join(", ")
        ));
    }
    if !not_applied.is_empty() && !objects.is_empty() {
        let list: Vec<String> = not_applied.iter().map(|(k, n)| format!("{n} {k}")).collect();
        notices.push(format!(
            "trims not applied ({}): the B-splines are read whole",
            list.join(", ")
        ));
    }
    if objects.is_empty()
        && let Some(e) = first_error
    {
        return Err(e);
    }
    Ok(InterchangeFile {
        objects,
        unit,
        scale: 1.0,
        notices,
        entities,
        trims,
    })
}
