//! Face bounds read as trim loops ([`crate::trim`]): `ADVANCED_FACE` (or `FACE_SURFACE`) on a B-spline
//! surface → `FACE_OUTER_BOUND` / `FACE_BOUND` → `EDGE_LOOP` → `ORIENTED_EDGE` → `EDGE_CURVE`, whose
//! geometry is a `SURFACE_CURVE` / `SEAM_CURVE` (its `PCURVE` on this face's surface preferred: a 2D
//! B-spline, `LINE` (degree 1) or `POLYLINE` taken exactly between the edge's vertices, a `CIRCLE` or
//! `ELLIPSE` exactly as a rational quadratic, a `TRIMMED_CURVE` as its basis curve) or a 3D curve of those
//! kinds (sampled between the vertices and projected onto the surface: a uv polyline within
//! [`crate::trim::fit_tolerance`]). Orientations are applied (the face bound's, the oriented edge's, the
//! edge curve's sense), so each stored loop runs as the face traverses it. A face whose bounds cannot be
//! read (another edge curve type, an edge off its surface, a loop that does not close) opens untrimmed,
//! with a notice naming the face and the reason.

use std::collections::{HashMap, HashSet};

use glam::DVec3;

use super::parse::{Exchange, Instance, Param};
use super::perr;
use crate::closest::CurveProjector;
use crate::curve::BSplineCurve;
use crate::error::Result;
use crate::measure_surface::SurfaceProjector;
use crate::surface::BSplineSurface;
use crate::trim::{FaceTrim, TrimLoop, fit_tolerance, project_path, sub_curve};

/// The most edges one face's bounds may have.
const MAX_FACE_EDGES: usize = 10_000;

/// How far (× the surface's control-box diagonal) an edge may pass from its face's surface.
const OFF_SURFACE: f64 = 1e-2;

/// What the face pass found.
#[derive(Debug, Default)]
pub(super) struct FaceTrims {
    /// B-spline surface instance → the trim of the face on it.
    pub(super) by_surface: HashMap<u64, FaceTrim>,
    /// Instances that the trims read stand for: the faces, their edges and the edges' 3D curves (not
    /// read again as objects of their own, nor counted as trims not applied).
    pub(super) used: HashSet<u64>,
    /// One per face whose bounds were not read, with the reason.
    pub(super) notices: Vec<String>,
}

/// A reader of the B-spline surface or curve `#id` in the file's own coordinates: `Ok(None)` if it is
/// not a B-spline.
pub(super) type RawSurface<'a> = &'a dyn Fn(u64) -> Result<Option<BSplineSurface>>;
pub(super) type RawCurve<'a> = &'a dyn Fn(u64) -> Result<Option<BSplineCurve>>;

/// What every edge of one face is read against: the file, the face's surface (its instance number and
/// its B-spline in the file's coordinates), a projector onto it and the B-spline readers.
struct Face<'a> {
    ex: &'a Exchange,
    sid: u64,
    s: &'a BSplineSurface,
    proj: SurfaceProjector<'a>,
    curve: RawCurve<'a>,
}

/// The trims of every face on a B-spline surface.
pub(super) fn face_trims(ex: &Exchange, surface: RawSurface<'_>, curve: RawCurve<'_>) -> FaceTrims {
    let mut out = FaceTrims::default();
    for inst in &ex.instances {
        let Some(r) = inst.record("ADVANCED_FACE").or_else(|| inst.record("FACE_SURFACE")) else {
            continue;
        };
        let Some(Param::Ref(sid)) = r.params.get(2) else {
            continue;
        };
        let s = match surface(*sid) {
            Ok(Some(s)) => s,
            Ok(None) => continue, // a plane, a cylinder, ...: not read at all
            Err(_) => continue,   // the surface's own notice says why
        };
        if r.params.get(1).and_then(Param::list).is_some_and(<[Param]>::is_empty) {
            continue; // no bounds: the face is the whole surface
        }
        let what = format!("#{} ({})", inst.id, r.name);
        if out.by_surface.contains_key(sid) {
            out.notices.push(format!(
                "{what}: its surface #{sid} bounds another face too; only the first face's bounds are kept"
            ));
            continue;
        }
        let mut used = vec![inst.id];
        let face = Face {
            ex,
            sid: *sid,
            s: &s,
            proj: SurfaceProjector::new(&s, 4),
            curve,
        };
        match read_face(&face, r, &mut used) {
            Ok(t) => {
                out.by_surface.insert(*sid, t);
                out.used.extend(used);
            }
            Err(e) => out.notices.push(format!(
                "{what} on line {}: its bounds are not read, the surface #{sid} opens untrimmed: {}",
                inst.line,
                super::read::reason(&e)
            )),
        }
    }
    out
}

fn reference(p: Option<&Param>, what: &str) -> Result<u64> {
    match p {
        Some(Param::Ref(id)) => Ok(*id),
        _ => Err(perr(format!("{what} is not a reference"))),
    }
}

fn logical(p: Option<&Param>) -> bool {
    !matches!(p, Some(Param::Enum(e)) if e == "F")
}

fn instance(ex: &Exchange, id: u64) -> Result<&Instance> {
    ex.get(id).ok_or_else(|| perr(format!("#{id} is not in the file")))
}

/// The bounds of one face on the surface `s`.
fn read_face(f: &Face<'_>, r: &super::parse::Record, used: &mut Vec<u64>) -> Result<FaceTrim> {
    let (ex, s) = (f.ex, f.s);
    let bounds = r
        .params
        .get(1)
        .and_then(Param::list)
        .ok_or_else(|| perr("the face has no bounds list"))?;
    let mut loops = vec![];
    let mut edges_seen = 0;
    for b in bounds {
        let bid = reference(Some(b), "a face bound")?;
        let bi = instance(ex, bid)?;
        let (br, outer) = match (bi.record("FACE_OUTER_BOUND"), bi.record("FACE_BOUND")) {
            (Some(r), _) => (r, true),
            (None, Some(r)) => (r, false),
            _ => return Err(perr(format!("bound #{bid} is not a FACE_BOUND"))),
        };
        let lid = reference(br.params.get(1), &format!("bound #{bid}'s loop"))?;
        let li = instance(ex, lid)?;
        let Some(lr) = li.record("EDGE_LOOP") else {
            let name = li.records.first().map_or("?", |r| r.name.as_str());
            return Err(perr(format!("loop #{lid} is a {name}, not an EDGE_LOOP")));
        };
        let oes = lr
            .params
            .get(1)
            .and_then(Param::list)
            .ok_or_else(|| perr(format!("loop #{lid} has no edges")))?;
        if oes.is_empty() {
            return Err(perr(format!("loop #{lid} has no edges")));
        }
        edges_seen += oes.len();
        if edges_seen > MAX_FACE_EDGES {
            return Err(perr(format!("more than {MAX_FACE_EDGES} edges in its bounds")));
        }
        let mut edges = Vec::with_capacity(oes.len());
        for oe in oes {
            edges.push(oriented_edge(f, reference(Some(oe), "an oriented edge")?, used)?);
        }
        if !logical(br.params.get(2)) {
            edges = edges.into_iter().rev().map(|e| e.reversed()).collect();
        }
        used.extend([bid, lid]);
        loops.push(TrimLoop { outer, edges });
    }
    if loops.is_empty() {
        return Err(perr("the face has no bounds"));
    }
    // no loop marked outer (every bound a FACE_BOUND): the one with the largest uv box is
    if !loops.iter().any(|l| l.outer) {
        let area = |l: &TrimLoop| {
            let (lo, hi) = l.edges.iter().flat_map(|e| e.points()).fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(a, b), &q| (a.min(q), b.max(q)),
            );
            (hi.x - lo.x) * (hi.y - lo.y)
        };
        let k = (0..loops.len())
            .max_by(|&a, &b| area(&loops[a]).total_cmp(&area(&loops[b])))
            .unwrap_or(0);
        loops[k].outer = true;
    }
    let trim = FaceTrim { loops };
    let ((u0, u1), (v0, v1)) = s.domain();
    let span = (u1 - u0).hypot(v1 - v0);
    let gap = trim.largest_gap();
    if !(gap <= 1e-4 * span) {
        return Err(perr(format!(
            "a loop does not close in the surface's parameters (a gap of {gap:.3e} between edges)"
        )));
    }
    Ok(trim)
}

/// A vertex's point: `VERTEX_POINT` → `CARTESIAN_POINT`.
fn vertex(ex: &Exchange, id: u64) -> Result<DVec3> {
    let v = instance(ex, id)?;
    let r = v
        .record("VERTEX_POINT")
        .ok_or_else(|| perr(format!("vertex #{id} is not a VERTEX_POINT")))?;
    Ok(super::read::point(ex, r.params.get(1).unwrap_or(&Param::Null), 0)?.0)
}

/// One edge of a loop, in (u, v), oriented as the loop runs.
fn oriented_edge(f: &Face<'_>, id: u64, used: &mut Vec<u64>) -> Result<BSplineCurve> {
    let ex = f.ex;
    let oe = instance(ex, id)?;
    let r = oe
        .record("ORIENTED_EDGE")
        .ok_or_else(|| perr(format!("#{id} is not an ORIENTED_EDGE")))?;
    let eid = reference(r.params.get(3), &format!("oriented edge #{id}'s edge"))?;
    let ei = instance(ex, eid)?;
    let er = ei
        .record("EDGE_CURVE")
        .ok_or_else(|| perr(format!("edge #{eid} is not an EDGE_CURVE")))?;
    let (v1, v2) = (
        reference(er.params.get(1), "an edge's start vertex")?,
        reference(er.params.get(2), "an edge's end vertex")?,
    );
    let (start, end) = (vertex(ex, v1)?, vertex(ex, v2)?);
    let gid = reference(er.params.get(3), &format!("edge #{eid}'s curve"))?;
    let same_sense = logical(er.params.get(4));
    let closed = v1 == v2 || start == end;
    let e = edge_uv(f, gid, (start, end, same_sense, closed), used)
        .map_err(|e| perr(format!("edge #{eid}: {}", super::read::reason(&e))))?;
    used.extend([id, eid]);
    Ok(if logical(r.params.get(4)) { e } else { e.reversed() })
}

/// The geometry of an edge: a curve in the face surface's (u, v) or in space.
enum EdgeGeometry {
    Uv(Path),
    Space(Path),
}

/// A curve an edge runs along: a B-spline (a `POLYLINE` as one of degree 1), a line `p + t·d`, or a
/// circle or ellipse `c + a cos t·x + b sin t·y` (t in radians; `x`, `y` unit and orthogonal; a = b = r
/// for a circle).
enum Path {
    BSpline(BSplineCurve),
    Line(DVec3, DVec3),
    Conic {
        c: DVec3,
        x: DVec3,
        y: DVec3,
        a: f64,
        b: f64,
    },
}

impl Path {
    /// The same curve run the other way.
    fn reversed(self) -> Path {
        match self {
            Path::BSpline(c) => Path::BSpline(c.reversed()),
            Path::Line(p, d) => Path::Line(p, -d),
            Path::Conic { c, x, y, a, b } => Path::Conic { c, x, y: -y, a, b },
        }
    }

    fn point(&self, t: f64) -> DVec3 {
        match self {
            Path::BSpline(c) => c.point(t),
            Path::Line(p, d) => *p + *d * t,
            Path::Conic { c, x, y, a, b } => *c + *a * t.cos() * *x + *b * t.sin() * *y,
        }
    }

    /// The parameter of the point nearest `q` (a circle's in [0, 2π)).
    fn param(&self, q: DVec3) -> f64 {
        match self {
            Path::BSpline(c) => CurveProjector::new(c, 8).project(q).param,
            Path::Line(p, d) => (q - *p).dot(*d) / d.length_squared(),
            // exact for a point on the conic (an edge's vertex); the nearest for a circle
            Path::Conic { c, x, y, a, b } => {
                let t = ((q - *c).dot(*y) / *b).atan2((q - *c).dot(*x) / *a);
                if t < 0.0 { t + std::f64::consts::TAU } else { t }
            }
        }
    }

    /// The parameters of an edge at its start and end vertices (`ends`; `None`: one vertex, the whole
    /// closed curve, run in the curve's direction if `same_sense`, else against it); a circle's unwrapped
    /// so that the way from one to the other runs the edge's way round.
    fn range(&self, ends: Option<(f64, f64)>, same_sense: bool) -> Result<(f64, f64)> {
        use std::f64::consts::TAU;
        let (a, b) = match (self, ends) {
            (Path::BSpline(c), None) => c.domain(),
            (Path::Conic { .. }, None) => (0.0, TAU),
            (Path::Line(..), None) => return Err(perr("a closed edge on a line")),
            (_, Some(ab)) => ab,
        };
        let (a, b) = if same_sense || ends.is_some() { (a, b) } else { (b, a) };
        Ok(match self {
            Path::Conic { .. } if same_sense && b <= a => (a, b + TAU),
            Path::Conic { .. } if !same_sense && a <= b => (a + TAU, b),
            _ => (a, b),
        })
    }
}

/// A direction: `DIRECTION` with 2 or 3 ratios, unit length.
fn direction(ex: &Exchange, p: Option<&Param>, what: &str) -> Result<DVec3> {
    let did = reference(p, what)?;
    let d = instance(ex, did)?
        .record("DIRECTION")
        .ok_or_else(|| perr(format!("#{did} is not a DIRECTION")))?;
    let c = super::read::reals(d.params.get(1).unwrap_or(&Param::Null), "a direction")?;
    let d = match c[..] {
        [x, y] => DVec3::new(x, y, 0.0),
        [x, y, z] => DVec3::new(x, y, z),
        _ => return Err(perr(format!("direction #{did} has {} coordinates", c.len()))),
    };
    let n = d.normalize_or_zero();
    if n == DVec3::ZERO || !n.is_finite() {
        return Err(perr(format!("direction #{did} has no length")));
    }
    Ok(n)
}

/// An optional direction of a placement: `default` where it is unset.
fn direction_or(ex: &Exchange, p: Option<&Param>, what: &str, default: DVec3) -> Result<DVec3> {
    match p {
        Some(Param::Ref(_)) => direction(ex, p, what),
        _ => Ok(default),
    }
}

/// A `CIRCLE` (its `AXIS2_PLACEMENT_3D`, or `_2D` in a parameter space, and radius) or an `ELLIPSE` (the
/// placement and its semi-axes along the placement's x and y).
fn conic(ex: &Exchange, gid: u64, r: &super::parse::Record) -> Result<Path> {
    let aid = reference(r.params.get(1), "a circle's placement")?;
    let a = instance(ex, aid)?;
    let (c, z, x) = if let Some(p) = a.record("AXIS2_PLACEMENT_3D") {
        let c = super::read::point(ex, p.params.get(1).unwrap_or(&Param::Null), 0)?.0;
        let z = direction_or(ex, p.params.get(2), "a placement's axis", DVec3::Z)?;
        let x = direction_or(ex, p.params.get(3), "a placement's reference direction", DVec3::X)?;
        (c, z, x)
    } else if let Some(p) = a.record("AXIS2_PLACEMENT_2D") {
        let c = super::read::point(ex, p.params.get(1).unwrap_or(&Param::Null), 0)?.0;
        let x = direction_or(ex, p.params.get(2), "a placement's reference direction", DVec3::X)?;
        (c, DVec3::Z, x)
    } else {
        return Err(perr(format!(
            "circle #{gid}'s placement #{aid} is not an AXIS2_PLACEMENT"
        )));
    };
    let x = (x - z * x.dot(z)).normalize_or_zero();
    let radius = |k: usize| r.params.get(k).and_then(Param::real).unwrap_or(f64::NAN);
    let (a, b) = match r.name.as_str() {
        "ELLIPSE" => (radius(2), radius(3)),
        _ => (radius(2), radius(2)),
    };
    let kind = r.name.to_ascii_lowercase();
    if x == DVec3::ZERO || !(a > 0.0 && a.is_finite() && b > 0.0 && b.is_finite()) {
        return Err(perr(format!("{kind} #{gid} has no radius or no plane")));
    }
    Ok(Path::Conic {
        c,
        x,
        y: z.cross(x),
        a,
        b,
    })
}

/// How deep `TRIMMED_CURVE`s may nest.
const MAX_TRIMMED: usize = 8;

/// The curve `#gid` as a path: a B-spline (`raw` reads it), a `LINE` (point and `VECTOR`), a `CIRCLE`, an
/// `ELLIPSE`, a `POLYLINE` (of degree 1 on its points' parameters 0, 1, ...), or a `TRIMMED_CURVE` of one
/// of those (its basis curve: an edge's vertices bound the part it runs along).
fn path(ex: &Exchange, gid: u64, curve: RawCurve<'_>) -> Result<Path> {
    path_at(ex, gid, curve, 0)
}

fn path_at(ex: &Exchange, gid: u64, curve: RawCurve<'_>, depth: usize) -> Result<Path> {
    if let Some(c) = curve(gid)? {
        return Ok(Path::BSpline(c));
    }
    let g = instance(ex, gid)?;
    if let Some(r) = g.record("LINE") {
        let p = super::read::point(ex, r.params.get(1).unwrap_or(&Param::Null), 0)?.0;
        let vid = reference(r.params.get(2), "a line's vector")?;
        let v = instance(ex, vid)?
            .record("VECTOR")
            .ok_or_else(|| perr(format!("#{vid} is not a VECTOR")))?;
        let mag = v.params.get(2).and_then(Param::real).unwrap_or(1.0);
        let d = direction(ex, v.params.get(1), "a vector's direction")? * mag;
        if d == DVec3::ZERO || !d.is_finite() {
            return Err(perr(format!("line #{gid} has no direction")));
        }
        return Ok(Path::Line(p, d));
    }
    if let Some(r) = g.record("CIRCLE").or_else(|| g.record("ELLIPSE")) {
        return conic(ex, gid, r);
    }
    if let Some(r) = g.record("POLYLINE") {
        let pts = r
            .params
            .get(1)
            .and_then(Param::list)
            .ok_or_else(|| perr(format!("polyline #{gid} has no points")))?;
        if pts.len() < 2 || pts.len() > MAX_FACE_EDGES {
            return Err(perr(format!("polyline #{gid} has {} points", pts.len())));
        }
        let pts = (pts.iter().enumerate())
            .map(|(k, p)| super::read::point(ex, p, k))
            .collect::<Result<Vec<_>>>()?;
        let dim = pts.iter().map(|p| p.1).max().unwrap_or(3).clamp(2, 3);
        let n = pts.len();
        let mut knots = vec![0.0];
        knots.extend((0..n).map(|k| k as f64));
        knots.push((n - 1) as f64);
        let pts = pts.into_iter().map(|p| p.0).collect();
        return Ok(Path::BSpline(BSplineCurve::try_new(1, knots, pts, None, dim)?));
    }
    if let Some(r) = g.record("TRIMMED_CURVE") {
        if depth >= MAX_TRIMMED {
            return Err(perr(format!(
                "trimmed curve #{gid}: nested more than {MAX_TRIMMED} deep"
            )));
        }
        let basis = reference(r.params.get(1), &format!("trimmed curve #{gid}'s basis curve"))?;
        let p = path_at(ex, basis, curve, depth + 1)?;
        // sense agreement .F.: the trimmed curve runs against its basis curve
        return Ok(if logical(r.params.get(4)) { p } else { p.reversed() });
    }
    let name = g.records.first().map_or("?", |r| r.name.as_str());
    Err(perr(format!(
        "its curve #{gid} is a {name}, which is not read (B-spline, LINE, CIRCLE, ELLIPSE, POLYLINE and \
         TRIMMED_CURVE edge curves are)"
    )))
}

/// The geometry of an edge curve `#gid` on the face surface `s`: its p-curve on `s` where it has one,
/// else its 3D curve.
fn edge_geometry(f: &Face<'_>, gid: u64) -> Result<(EdgeGeometry, Vec<u64>)> {
    let ex = f.ex;
    let g = instance(ex, gid)?;
    let sc = g.record("SURFACE_CURVE").or_else(|| g.record("SEAM_CURVE"));
    let (curve3d, pcurves) = match sc {
        Some(r) => (
            reference(r.params.get(1), "a surface curve's 3D curve")?,
            r.params.get(2).and_then(Param::list).unwrap_or(&[]).to_vec(),
        ),
        None if g.record("PCURVE").is_some() => (gid, vec![Param::Ref(gid)]),
        None => (gid, vec![]),
    };
    for pc in pcurves {
        let Param::Ref(pid) = pc else { continue };
        let Some(pr) = ex.get(pid).and_then(|i| i.record("PCURVE")) else {
            continue;
        };
        // the p-curve on this face's surface
        if pr.params.get(1) != Some(&Param::Ref(f.sid)) {
            continue;
        }
        let did = reference(pr.params.get(2), "a p-curve's representation")?;
        let items = instance(ex, did)?
            .record("DEFINITIONAL_REPRESENTATION")
            .and_then(|r| r.params.get(1))
            .and_then(Param::list)
            .ok_or_else(|| perr(format!("p-curve #{pid}'s #{did} is not a DEFINITIONAL_REPRESENTATION")))?;
        let cid = reference(items.first(), "a p-curve's item")?;
        return Ok((EdgeGeometry::Uv(path(ex, cid, f.curve)?), vec![pid, did, cid, curve3d]));
    }
    if curve3d != gid && ex.get(curve3d).is_some_and(|i| i.record("PCURVE").is_some()) {
        return Err(perr("its only curve is a p-curve on another surface"));
    }
    Ok((EdgeGeometry::Space(path(ex, curve3d, f.curve)?), vec![curve3d]))
}

/// An edge curve `#gid` from `start` to `end` (the edge's vertices; `same_sense`: the curve runs that
/// way; `closed`: one vertex, the whole curve) in `s`'s (u, v), oriented from `start` to `end`.
fn edge_uv(
    f: &Face<'_>,
    gid: u64,
    (start, end, same_sense, closed): (DVec3, DVec3, bool, bool),
    used: &mut Vec<u64>,
) -> Result<BSplineCurve> {
    let s = f.s;
    let (geometry, ids) = edge_geometry(f, gid)?;
    let tol = fit_tolerance(s);
    let uv = |q: DVec3| {
        let sp = f.proj.project(q);
        DVec3::new(sp.uv.0, sp.uv.1, 0.0)
    };
    let path = match &geometry {
        EdgeGeometry::Uv(p) | EdgeGeometry::Space(p) => p,
    };
    let ends = match &geometry {
        _ if closed => None,
        EdgeGeometry::Uv(p) => Some((p.param(uv(start)), p.param(uv(end)))),
        EdgeGeometry::Space(p) => Some((p.param(start), p.param(end))),
    };
    let (ta, tb) = path.range(ends, same_sense)?;
    let (lo, hi) = (ta.min(tb), ta.max(tb));
    let e = match (&geometry, path) {
        (EdgeGeometry::Uv(_), Path::BSpline(c)) => {
            let (a, b) = c.domain();
            let snap = |t: f64| {
                if (t - a).abs() <= 1e-12 * (b - a) {
                    a
                } else if (t - b).abs() <= 1e-12 * (b - a) {
                    b
                } else {
                    t
                }
            };
            sub_curve(c, snap(lo), snap(hi))?
        }
        (EdgeGeometry::Uv(_), Path::Line(..)) => {
            let (p, q) = (path.point(lo), path.point(hi));
            BSplineCurve::try_new(1, vec![lo, lo, hi, hi], vec![p, q], None, 2)?
        }
        // exact: a rational quadratic of arcs of at most a quarter turn
        (EdgeGeometry::Uv(_), Path::Conic { c, x, y, a, b }) => conic_arc(*c, *x * *a, *y * *b, lo, hi)?,
        (EdgeGeometry::Space(_), _) => {
            let (lo_s, hi_s) = s.control_bounds();
            let off = OFF_SURFACE * (hi_s - lo_s).length();
            project_path(s, &|t| path.point(t), (lo, hi), tol, off)?.0
        }
    };
    used.extend(ids);
    Ok(if ta > tb { e.reversed() } else { e })
}

/// The arc of the conic `c + cos t·x + sin t·y` for t from `t0` to `t1` (radians) as a rational quadratic
/// B-spline in (u, v) (The NURBS Book A7.1, mapped by the affine map that takes the unit circle to the
/// conic, which keeps the weights): ⌈(t1 − t0)/(π/2)⌉ arcs, each's middle point where the tangents at its
/// ends meet, weighted cos(Δ/2); its knots on [t0, t1], one double knot between arcs (C1 there).
pub(super) fn conic_arc(c: DVec3, x: DVec3, y: DVec3, t0: f64, t1: f64) -> Result<BSplineCurve> {
    let sweep = t1 - t0;
    if !(sweep > 0.0 && sweep.is_finite()) {
        return Err(perr(format!("an arc from {t0} to {t1} radians is empty")));
    }
    let n = ((sweep / std::f64::consts::FRAC_PI_2 - 1e-12).ceil() as usize).clamp(1, 8);
    let d = sweep / n as f64;
    let w = (d / 2.0).cos();
    let at = |t: f64| c + t.cos() * x + t.sin() * y;
    let mut pts = vec![at(t0)];
    let mut weights = vec![1.0];
    let mut knots = vec![t0; 3];
    for k in 0..n {
        let (a, b) = (t0 + d * k as f64, t0 + d * (k + 1) as f64);
        let m = 0.5 * (a + b);
        pts.push(c + (m.cos() * x + m.sin() * y) / w);
        pts.push(if k + 1 == n { at(t1) } else { at(b) });
        weights.extend([w, 1.0]);
        if k + 1 < n {
            knots.extend([b, b]);
        }
    }
    knots.extend([t1; 3]);
    BSplineCurve::try_new(2, knots, pts, Some(weights), 2)
}
