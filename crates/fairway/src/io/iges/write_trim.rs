//! Trimmed faces written: a surface with its [`FaceTrim`] as a trimmed parametric surface (144, IGES 5.3
//! §4.34): `144, PTS, N1, N2, PTO, PTI(1..N2)` → its surface (128) and one curve on a parametric surface
//! (142, §4.32: `142, CRTN, SPTR, BPTR, CPTR, PREF`) per loop. Each boundary carries the loop twice: its
//! parameter-space curve B (BPTR: the uv edges exactly as stored, each a planar 126 in (u, v, 0) with the
//! use flag 05, joined by a composite curve 102 where the loop has more than one edge) and its model-space
//! curve C (CPTR: each edge recomputed on the surface as it is now — the faired one — by
//! [`crate::trim::edge_on_surface`] within [`crate::trim::fit_tolerance`], a 126 in space, joined by a
//! 102 likewise), PREF = 1 (B on the surface is the definition, C follows it). The surface, the boundaries
//! and their curves are physically dependent (status digits 3–4 = 01) on the 144.
//!
//! A face with more than one outer loop is written as one 144 per outer loop on the same surface, each
//! with the holes that lie inside its outer loop (by the holes' first points); a face with holes but no
//! outer loop as one 144 with N1 = 0 (the outer boundary is the surface's domain).

use super::write::{Entities, curve_params, surface_params};
use super::*;
use crate::trim::{FaceTrim, TrimLoop, edge_on_surface, fit_tolerance, polyline_on_surface};

/// Which curves a boundary (142) carries: both (what the writer writes) or, to test a reader on
/// files from other systems, only the model-space curve (BPTR = 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Boundaries {
    Both,
    #[cfg_attr(not(test), allow(dead_code))]
    ModelOnly,
}

/// Status digits: physically dependent geometry, and physically dependent 2D parametric geometry.
const DEPENDENT: &str = "00010000";
const DEPENDENT_UV: &str = "00010500";

/// The face `s` bounded by `trim`, labelled `label`: its surface, boundaries and 144(s) added to `ents`.
pub(super) fn face(ents: &mut Entities, s: &BSplineSurface, trim: &FaceTrim, label: (String, i64), mode: Boundaries) {
    let sid = ents.add_with(128, DEPENDENT, surface_params(s), label.clone());
    let outers: Vec<&TrimLoop> = trim.loops.iter().filter(|l| l.outer).collect();
    let holes: Vec<&TrimLoop> = trim.loops.iter().filter(|l| !l.outer).collect();
    // each hole to the outer loop that holds its first point (the first outer loop if none does)
    let polygons: Vec<Vec<glam::DVec2>> = outers
        .iter()
        .map(|l| {
            FaceTrim {
                loops: vec![(*l).clone()],
            }
            .polylines(32)
            .remove(0)
        })
        .collect();
    let mut holes_of: Vec<Vec<&TrimLoop>> = vec![vec![]; outers.len().max(1)];
    for h in holes {
        let e = &h.edges[0];
        let q = e.point(e.domain().0);
        let k = polygons
            .iter()
            .position(|p| inside(p, glam::DVec2::new(q.x, q.y)))
            .unwrap_or(0);
        holes_of[k].push(h);
    }
    for (k, hs) in holes_of.iter().enumerate() {
        let pto = outers.get(k).map_or(0, |l| boundary(ents, s, sid, l, mode));
        let ptis: Vec<i64> = hs.iter().map(|h| boundary(ents, s, sid, h, mode)).collect();
        let mut p = vec![
            "144".to_string(),
            sid.to_string(),
            i64::from(pto != 0).to_string(),
            ptis.len().to_string(),
            pto.to_string(),
        ];
        p.extend(ptis.iter().map(i64::to_string));
        ents.add(144, p, label.clone());
    }
}

/// One loop as a 142 on the surface `sid`; returns its directory number.
fn boundary(ents: &mut Entities, s: &BSplineSurface, sid: i64, l: &TrimLoop, mode: Boundaries) -> i64 {
    let none = || (String::new(), 0);
    let bptr = match mode {
        Boundaries::Both => {
            let uv: Vec<i64> = (l.edges.iter())
                .map(|e| ents.add_with(126, DEPENDENT_UV, curve_params(e), none()))
                .collect();
            composite(ents, &uv, DEPENDENT_UV)
        }
        Boundaries::ModelOnly => 0,
    };
    let tol = fit_tolerance(s);
    let model: Option<Vec<BSplineCurve>> = (l.edges.iter())
        .map(|e| {
            edge_on_surface(s, e, tol)
                .map(|(c, _)| c)
                .or_else(|_| polyline_on_surface(s, e))
                .ok()
        })
        .collect();
    // not reachable for a valid uv curve: the parameter-space curve alone still carries the loop
    let cptr = match model {
        Some(cs) => {
            let des: Vec<i64> = (cs.iter())
                .map(|c| ents.add_with(126, DEPENDENT, curve_params(c), none()))
                .collect();
            composite(ents, &des, DEPENDENT)
        }
        None => 0,
    };
    let p = [
        "142".to_string(),
        "0".into(),
        sid.to_string(),
        bptr.to_string(),
        cptr.to_string(),
        "1".into(),
    ];
    ents.add_with(142, DEPENDENT_UV, p.to_vec(), none())
}

/// One curve as it is, several as a composite curve (102) of them in order.
fn composite(ents: &mut Entities, des: &[i64], status: &'static str) -> i64 {
    match des {
        [one] => *one,
        _ => {
            let mut p = vec!["102".to_string(), des.len().to_string()];
            p.extend(des.iter().map(i64::to_string));
            ents.add_with(102, status, p, (String::new(), 0))
        }
    }
}

/// Whether `q` lies inside the closed polygon `p` (even-odd rule).
fn inside(p: &[glam::DVec2], q: glam::DVec2) -> bool {
    let mut c = false;
    for w in p.windows(2) {
        let (a, b) = (w[0], w[1]);
        if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y) {
            c = !c;
        }
    }
    c
}
