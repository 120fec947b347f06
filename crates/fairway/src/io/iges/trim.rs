//! Trimmed surfaces (type 144) read as trim loops ([`crate::trim`]): its surface (128) keeps the loops
//! of its boundaries (142, curves on a parametric surface), each from its parameter-space curve (a 126,
//! a 110 line, or a 102 composite of them, in the surface's (u, v)); an outer boundary that is the
//! surface's own (N1 = 0) is its domain's rectangle. A 144 whose boundaries cannot be read (only a
//! model-space curve, another curve type) leaves its surface untrimmed, with a notice naming the entity
//! and the reason.

use std::collections::HashMap;

use super::read::{DataSections, entity_params};
use super::*;
use crate::trim::{FaceTrim, TrimLoop};

/// The most curves one boundary may hold (a 102's count), and the deepest nesting of 102s.
const MAX_CURVES: usize = 10_000;
const MAX_NESTING: usize = 8;

/// A 144's loops, the outer one to be made the surface's domain where the file says so (N1 = 0).
pub(super) struct Trim144 {
    pub(super) outer_is_domain: bool,
    pub(super) loops: Vec<TrimLoop>,
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
        loops.extend(self.loops.iter().cloned());
        Ok(FaceTrim { loops })
    }
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
    pub(super) fn face_trims(&self, notices: &mut Vec<String>) -> HashMap<usize, Trim144> {
        let mut budget = self.plines.len().saturating_mul(4).saturating_add(64);
        let mut out = HashMap::new();
        for e in self.entries.iter().filter(|e| e.etype == 144) {
            let what = format!("entity {} (trimmed surface, 144)", e.seq);
            match self.read_144(e, &what, &mut budget) {
                Ok(Some((surface, t))) => {
                    out.insert(surface, t);
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

    fn read_144(&self, e: &DirEntry, what: &str, budget: &mut usize) -> Result<Option<(usize, Trim144)>> {
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
            loops.push(TrimLoop {
                outer: true,
                edges: self.boundary_142(pto, budget)?,
            });
        }
        for _ in 0..n2 {
            let pti = p.int()?;
            loops.push(TrimLoop {
                outer: false,
                edges: self.boundary_142(pti, budget)?,
            });
        }
        Ok(Some((
            surface.seq,
            Trim144 {
                outer_is_domain: n1 == 0,
                loops,
            },
        )))
    }

    /// A 142's parameter-space curve as uv edges.
    fn boundary_142(&self, de: i64, budget: &mut usize) -> Result<Vec<BSplineCurve>> {
        let e = self.entry_at(de)?;
        if e.etype != 142 {
            return Err(perr(format!("boundary {de} is a type {}, not a 142", e.etype)));
        }
        let what = format!("boundary {de} (142)");
        let toks = entity_params(self.plines, e, &what, self.pd, self.rd, budget)?;
        let mut p = Params {
            toks: &toks,
            pos: 1,
            what,
        };
        let (_crtn, _sptr, bptr) = (p.int()?, p.int()?, p.int()?);
        if bptr == 0 {
            return Err(perr(format!(
                "boundary {de} (142) has only its model-space curve; curves in space are not projected onto IGES \
                 surfaces yet"
            )));
        }
        let edges = self.uv_curves(bptr, budget, 0)?;
        if edges.is_empty() {
            return Err(perr(format!("boundary {de} (142) has no curve")));
        }
        Ok(edges)
    }

    /// A curve in a surface's (u, v): a 126 (its pieces), a 110 line, or a 102's curves in order.
    fn uv_curves(&self, de: i64, budget: &mut usize, depth: usize) -> Result<Vec<BSplineCurve>> {
        let e = self.entry_at(de)?;
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
                Ok(vec![BSplineCurve::try_new(
                    1,
                    vec![0.0, 0.0, 1.0, 1.0],
                    vec![a, b],
                    None,
                    2,
                )?])
            }
            102 if depth < MAX_NESTING => {
                let n = p.count("N (curves)", MAX_CURVES as i64)?;
                let mut out = vec![];
                for _ in 0..n {
                    let de = p.int()?;
                    out.extend(self.uv_curves(de, budget, depth + 1)?);
                }
                Ok(out)
            }
            t => Err(perr(format!(
                "{what}: a type {t} curve in parameter space is not read (126, 110, 102 are)"
            ))),
        }
    }
}
