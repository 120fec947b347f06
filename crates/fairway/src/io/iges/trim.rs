//! Trimmed surfaces (type 144) read as trim loops ([`crate::trim`]): its surface (128) keeps the loops
//! of its boundaries (142, curves on a parametric surface: `142, CRTN, SPTR, BPTR, CPTR, PREF`), each from
//! its parameter-space curve B (a 126, a 110 line, or a 102 composite of them, in the surface's (u, v))
//! or, where the boundary has none (BPTR = 0) or prefers its model-space curve (PREF = 2), from its
//! model-space curve C (the same types, in space) sampled and projected onto the surface as a uv polyline
//! within [`crate::trim::fit_tolerance`] ([`crate::trim::project_path`]; B is the fallback when C does
//! not lie on the surface). An outer boundary that is the surface's own (N1 = 0) is its domain's
//! rectangle; several 144s on one surface give it all their loops. A 144 whose boundaries cannot be read
//! (another curve type, a curve off the surface) leaves its surface untrimmed, with a notice naming the
//! entity and the reason. The entities a read 144 stands for (its 142s and their curves) are listed in
//! `FaceTrims::used`: not reported as skipped, and in a file Fairway wrote, the model-space curves
//! (which it derives from the uv loops) are not read as objects of their own.

use std::collections::{HashMap, HashSet};

use super::read::{DataSections, entity_params, transform_chain};
use super::*;
use crate::trim::{FaceTrim, TrimLoop, fit_tolerance, project_path};

/// The most curves one boundary may hold (a 102's count), and the deepest nesting of 102s.
const MAX_CURVES: usize = 10_000;
const MAX_NESTING: usize = 8;

/// How far (× the surface's control-box diagonal) a model-space boundary may pass from its surface.
const OFF_SURFACE: f64 = 1e-2;

/// One boundary (142) as read: its parameter-space curves and/or its model-space curves (in the
/// objects' coordinates: transformed and converted as the surface is), which one the file prefers.
pub(super) struct Boundary {
    pub(super) outer: bool,
    pub(super) uv: Option<Vec<BSplineCurve>>,
    pub(super) model: Option<Vec<BSplineCurve>>,
    pub(super) model_first: bool,
}

impl Boundary {
    /// Its edges in the (u, v) of `s`: the uv curves, or the model-space ones projected onto `s` where
    /// there are no uv curves or the file prefers the model-space ones (the uv curves then the fallback).
    fn on(&self, s: &BSplineSurface) -> Result<TrimLoop> {
        let projected = || -> Result<Vec<BSplineCurve>> {
            let cs = self.model.as_ref().ok_or_else(|| perr("the boundary has no curve"))?;
            let tol = fit_tolerance(s);
            let off = OFF_SURFACE * tol / crate::trim::FIT_FRACTION;
            cs.iter()
                .map(|c| project_path(s, &|t| c.point(t), c.domain(), tol, off).map(|(uv, _)| uv))
                .collect()
        };
        let edges = match (&self.uv, self.model_first || self.uv.is_none()) {
            (Some(uv), false) => uv.clone(),
            (uv, _) => match (projected(), uv) {
                (Ok(e), _) => e,
                (Err(_), Some(uv)) => uv.clone(),
                (Err(e), None) => {
                    return Err(perr(format!(
                        "its model-space curve (it has no parameter-space curve) cannot be projected onto the \
                         surface: {}",
                        match &e {
                            Error::Parse { message, .. } => message.clone(),
                            other => other.to_string(),
                        }
                    )));
                }
            },
        };
        Ok(TrimLoop {
            outer: self.outer,
            edges,
        })
    }
}

/// A 144's loops, the outer one to be made the surface's domain where the file says so (N1 = 0).
pub(super) struct Trim144 {
    pub(super) outer_is_domain: bool,
    pub(super) loops: Vec<Boundary>,
}

impl Trim144 {
    /// The loops on the surface `s` (the domain's rectangle first where the outer boundary is it).
    pub(super) fn on(&self, s: &BSplineSurface) -> Result<FaceTrim> {
        let mut loops = vec![];
        if self.outer_is_domain {
            let ((u0, u1), (v0, v1)) = s.domain();
            let corners = [(u0, v0), (u1, v0), (u1, v1), (u0, v1)];
            let edges = (0..4)
                .map(|k| {
                    let (a, b) = (corners[k], corners[(k + 1) % 4]);
                    let pts = vec![DVec3::new(a.0, a.1, 0.0), DVec3::new(b.0, b.1, 0.0)];
                    BSplineCurve::try_new(1, vec![0.0, 0.0, 1.0, 1.0], pts, None, 2)
                })
                .collect::<Result<Vec<_>>>()?;
            loops.push(TrimLoop { outer: true, edges });
        }
        for b in &self.loops {
            loops.push(b.on(s)?);
        }
        // outer loops first, as a face keeps them
        loops.sort_by_key(|l| !l.outer);
        Ok(FaceTrim { loops })
    }
}

/// What the 144 pass found.
#[derive(Default)]
pub(super) struct FaceTrims {
    /// The directory number of a trimmed surface → its loops (of every 144 on it).
    pub(super) by_surface: HashMap<usize, Trim144>,
    /// The directory numbers of the entities the read 144s stand for: the 144s, their 142s, and the
    /// 142s' curves (102s and their members).
    pub(super) used: HashSet<usize>,
    /// Of those, the curves in model space.
    pub(super) model_curves: HashSet<usize>,
}

impl DataSections<'_> {
    /// The entry a directory pointer names.
    fn entry_at(&self, de: i64) -> Result<&DirEntry> {
        let k = usize::try_from(de - 1).ok().filter(|k| k % 2 == 0).map(|k| k / 2);
        k.and_then(|k| self.entries.get(k))
            .filter(|e| e.seq as i64 == de)
            .ok_or_else(|| perr(format!("pointer {de} names no directory entry")))
    }

    /// Every 144's loops, by the directory number of its surface; a notice for each that cannot be read.
    pub(super) fn face_trims(&self, notices: &mut Vec<String>) -> FaceTrims {
        let mut budget = self.plines.len().saturating_mul(4).saturating_add(64);
        let mut out = FaceTrims::default();
        for e in self.entries.iter().filter(|e| e.etype == 144) {
            let what = format!("entity {} (trimmed surface, 144)", e.seq);
            let mut used = Used::default();
            match self.read_144(e, &what, &mut budget, &mut used) {
                Ok(Some((surface, t))) => {
                    match out.by_surface.get_mut(&surface) {
                        // another 144 on the same surface (a face with several outer loops): its loops too
                        Some(first) => {
                            first.outer_is_domain |= t.outer_is_domain;
                            first.loops.extend(t.loops);
                        }
                        None => {
                            out.by_surface.insert(surface, t);
                        }
                    }
                    out.used.insert(e.seq);
                    out.used.extend(used.all.iter().copied());
                    out.model_curves.extend(used.model);
                }
                Ok(None) => {} // on a surface that is not read (120, 118, ...): its own notice says so
                Err(err) => notices.push(format!(
                    "{what}: its boundaries are not read, its surface opens untrimmed: {}",
                    match &err {
                        Error::Parse { message, .. } => message.clone(),
                        other => other.to_string(),
                    }
                )),
            }
        }
        out
    }

    fn read_144(
        &self,
        e: &DirEntry,
        what: &str,
        budget: &mut usize,
        used: &mut Used,
    ) -> Result<Option<(usize, Trim144)>> {
        let toks = entity_params(self.plines, e, what, self.pd, self.rd, budget)?;
        let mut p = Params {
            toks: &toks,
            pos: 1,
            what: what.to_string(),
        };
        let pts = p.int()?;
        let surface = self.entry_at(pts)?;
        if surface.etype != 128 {
            return Ok(None);
        }
        let n1 = p.int()?;
        let n2 = p.count("N2 (inner boundaries)", MAX_CURVES as i64)?;
        let pto = p.int()?;
        let mut loops = vec![];
        if n1 != 0 {
            loops.push(self.boundary_142(pto, true, budget, used)?);
        }
        for _ in 0..n2 {
            let pti = p.int()?;
            loops.push(self.boundary_142(pti, false, budget, used)?);
        }
        Ok(Some((
            surface.seq,
            Trim144 {
                outer_is_domain: n1 == 0,
                loops,
            },
        )))
    }

    /// A 142's curves: in parameter space (BPTR) and, where it has none or prefers it (PREF = 2), in
    /// model space (CPTR).
    fn boundary_142(&self, de: i64, outer: bool, budget: &mut usize, used: &mut Used) -> Result<Boundary> {
        let e = self.entry_at(de)?;
        if e.etype != 142 {
            return Err(perr(format!("boundary {de} is a type {}, not a 142", e.etype)));
        }
        used.all.push(e.seq);
        let what = format!("boundary {de} (142)");
        let toks = entity_params(self.plines, e, &what, self.pd, self.rd, budget)?;
        let mut p = Params {
            toks: &toks,
            pos: 1,
            what,
        };
        let (_crtn, _sptr, bptr) = (p.int()?, p.int()?, p.int()?);
        // CPTR and PREF: absent read as 0 (no model-space curve, no preference)
        let cptr = if p.remaining() > 0 { p.int()? } else { 0 };
        let pref = if p.remaining() > 0 { p.int()? } else { 0 };
        let uv = match bptr {
            0 => None,
            _ => Some(self.uv_curves(bptr, budget, 0, used)?),
        };
        let model = match cptr {
            0 => None,
            _ if uv.is_some() && pref != 2 => {
                // not needed; still the boundary's, not an object of its own
                self.mark_curves(cptr, 0, used);
                None
            }
            _ => match self.model_curves(cptr, budget, 0, used) {
                Ok(cs) => Some(cs),
                Err(err) if uv.is_some() => {
                    let _ = err; // the parameter-space curve carries the boundary
                    None
                }
                Err(err) => {
                    return Err(perr(format!(
                        "boundary {de} (142) has no parameter-space curve, and its model-space curve is not read: {}",
                        match &err {
                            Error::Parse { message, .. } => message.clone(),
                            other => other.to_string(),
                        }
                    )));
                }
            },
        };
        if uv.is_none() && model.is_none() {
            return Err(perr(format!("boundary {de} (142) has no curve")));
        }
        if uv.as_ref().is_some_and(Vec::is_empty) || model.as_ref().is_some_and(Vec::is_empty) {
            return Err(perr(format!("boundary {de} (142) has no curve")));
        }
        Ok(Boundary {
            outer,
            uv,
            model,
            model_first: pref == 2,
        })
    }

    /// A curve in a surface's (u, v): a 126 (its pieces), a 110 line, or a 102's curves in order.
    fn uv_curves(&self, de: i64, budget: &mut usize, depth: usize, used: &mut Used) -> Result<Vec<BSplineCurve>> {
        let e = self.entry_at(de)?;
        used.all.push(e.seq);
        let what = format!("parameter-space curve {de} ({})", e.etype);
        let toks = entity_params(self.plines, e, &what, self.pd, self.rd, budget)?;
        let mut p = Params {
            toks: &toks,
            pos: 1,
            what: what.clone(),
        };
        let uv = BSplineCurve::to_2d;
        match e.etype {
            126 => read_126(&mut p, &mut vec![])?
                .iter()
                .filter_map(Geometry::as_curve)
                .map(uv)
                .collect(),
            110 => {
                let a = DVec3::new(p.real()?, p.real()?, 0.0);
                let _ = p.real()?;
                let b = DVec3::new(p.real()?, p.real()?, 0.0);
                Ok(vec![line(a, b, 2)?])
            }
            102 if depth < MAX_NESTING => {
                let n = p.count("N (curves)", MAX_CURVES as i64)?;
                let mut out = vec![];
                for _ in 0..n {
                    let de = p.int()?;
                    out.extend(self.uv_curves(de, budget, depth + 1, used)?);
                }
                Ok(out)
            }
            t => Err(perr(format!(
                "{what}: a type {t} curve in parameter space is not read (126, 110, 102 are)"
            ))),
        }
    }

    /// A curve in model space, in the objects' coordinates (its transformation matrices and the unit
    /// conversion applied, as to the surface): a 126 (its pieces), a 110 line, or a 102's curves in order.
    fn model_curves(&self, de: i64, budget: &mut usize, depth: usize, used: &mut Used) -> Result<Vec<BSplineCurve>> {
        let e = self.entry_at(de)?;
        used.all.push(e.seq);
        used.model.push(e.seq);
        let what = format!("model-space curve {de} ({})", e.etype);
        let placed = |g: Geometry| -> Result<Geometry> {
            let xf = transform_chain(self.entries, self.plines, e.transform, self.pd, self.rd, &mut 64)?;
            let g = match xf {
                Some(m) => crate::io::interchange::map_points(g, |q| m.apply(q))?,
                None => g,
            };
            self.conversion.apply(g)
        };
        let toks = entity_params(self.plines, e, &what, self.pd, self.rd, budget)?;
        let mut p = Params {
            toks: &toks,
            pos: 1,
            what: what.clone(),
        };
        let curves = |gs: Vec<Geometry>| -> Result<Vec<BSplineCurve>> {
            gs.into_iter()
                .map(|g| match placed(g)? {
                    Geometry::Curve(c) => Ok(c),
                    Geometry::Surface(_) => Err(perr(format!("{what}: not a curve"))),
                })
                .collect()
        };
        match e.etype {
            126 => curves(read_126(&mut p, &mut vec![])?),
            110 => {
                let a = DVec3::new(p.real()?, p.real()?, p.real()?);
                let b = DVec3::new(p.real()?, p.real()?, p.real()?);
                curves(vec![Geometry::Curve(line(a, b, 3)?)])
            }
            102 if depth < MAX_NESTING => {
                let n = p.count("N (curves)", MAX_CURVES as i64)?;
                let mut out = vec![];
                for _ in 0..n {
                    let de = p.int()?;
                    out.extend(self.model_curves(de, budget, depth + 1, used)?);
                }
                Ok(out)
            }
            t => Err(perr(format!(
                "{what}: a type {t} curve in model space is not read (126, 110, 102 are)"
            ))),
        }
    }

    /// The model-space curve `de` and a 102's members, marked as a boundary's (not read).
    fn mark_curves(&self, de: i64, depth: usize, used: &mut Used) {
        let Ok(e) = self.entry_at(de) else { return };
        used.all.push(e.seq);
        used.model.push(e.seq);
        if e.etype != 102 || depth >= MAX_NESTING {
            return;
        }
        let mut budget = 64;
        let Ok(toks) = entity_params(self.plines, e, "a composite curve", self.pd, self.rd, &mut budget) else {
            return;
        };
        let mut p = Params {
            toks: &toks,
            pos: 1,
            what: String::new(),
        };
        let Ok(n) = p.count("N (curves)", MAX_CURVES as i64) else {
            return;
        };
        for _ in 0..n {
            match p.int() {
                Ok(de) => self.mark_curves(de, depth + 1, used),
                Err(_) => return,
            }
        }
    }
}

/// The directory numbers one 144's reading went through.
#[derive(Default)]
struct Used {
    all: Vec<usize>,
    model: Vec<usize>,
}

/// The line from `a` to `b` as a degree-1 B-spline on [0, 1] with `dim` coordinates.
fn line(a: DVec3, b: DVec3, dim: usize) -> Result<BSplineCurve> {
    BSplineCurve::try_new(1, vec![0.0, 0.0, 1.0, 1.0], vec![a, b], None, dim)
}
