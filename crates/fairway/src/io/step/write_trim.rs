//! Trimmed faces written: a surface with its [`FaceTrim`] as an `ADVANCED_FACE` whose bounds
//! (`FACE_OUTER_BOUND` / `FACE_BOUND` → `EDGE_LOOP` → `ORIENTED_EDGE` → `EDGE_CURVE`) carry each edge
//! twice, as a `SURFACE_CURVE`: its uv curve exactly as stored (a `PCURVE` on the face's surface, in a
//! 2D parametric context) and its 3D curve recomputed on the surface as it is now — the faired one — by
//! [`crate::trim::edge_on_surface`] within [`crate::trim::fit_tolerance`] (10⁻⁶ × the diagonal of the
//! surface's control box). Vertices are the surface's points at the edges' uv starts. Each face is an
//! `OPEN_SHELL` of a `SHELL_BASED_SURFACE_MODEL` in one `MANIFOLD_SURFACE_SHAPE_REPRESENTATION`.

use glam::DVec3;

use super::WriteOptions;
use super::write::{Data, refs, string};
use crate::surface::BSplineSurface;
use crate::trim::{FaceTrim, edge_on_surface, fit_tolerance, polyline_on_surface};

/// The face `s` bounded by `trim`, named `name`: the `ADVANCED_FACE`'s number.
pub(super) fn face(d: &mut Data, s: &BSplineSurface, trim: &FaceTrim, name: &str) -> u64 {
    let sid = d.surface(s, name);
    let ctx2 = d.add(
        "(GEOMETRIC_REPRESENTATION_CONTEXT(2)PARAMETRIC_REPRESENTATION_CONTEXT()REPRESENTATION_CONTEXT('2D SPACE',''))",
    );
    let tol = fit_tolerance(s);
    let mut bounds = vec![];
    for l in &trim.loops {
        let on = |q: DVec3| s.point(q.x, q.y);
        let vertices: Vec<u64> = (l.edges.iter())
            .map(|e| {
                let p = d.point(on(e.point(e.domain().0)));
                d.add(&format!("VERTEX_POINT('',#{p})"))
            })
            .collect();
        let n = l.edges.len();
        let mut oriented = Vec::with_capacity(n);
        for (k, e) in l.edges.iter().enumerate() {
            let c3 = edge_on_surface(s, e, tol)
                .map(|(c, _)| c)
                .or_else(|_| polyline_on_surface(s, e));
            let c3 = match c3 {
                Ok(c) => d.curve_in(&c, "", 3),
                // not reachable for a valid uv curve: the p-curve alone still carries the edge
                Err(_) => d.curve_in(e, "", 2),
            };
            let c2 = d.curve_in(e, "", 2);
            let dr = d.add(&format!("DEFINITIONAL_REPRESENTATION('',(#{c2}),#{ctx2})"));
            let pc = d.add(&format!("PCURVE('',#{sid},#{dr})"));
            let sc = d.add(&format!("SURFACE_CURVE('',#{c3},(#{pc}),.PCURVE_S1.)"));
            let ec = d.add(&format!(
                "EDGE_CURVE('',#{},#{},#{sc},.T.)",
                vertices[k],
                vertices[(k + 1) % n]
            ));
            oriented.push(d.add(&format!("ORIENTED_EDGE('',*,*,#{ec},.T.)")));
        }
        let el = d.add(&format!("EDGE_LOOP('',{})", refs(&oriented)));
        let kind = if l.outer { "FACE_OUTER_BOUND" } else { "FACE_BOUND" };
        bounds.push(d.add(&format!("{kind}('',#{el},.T.)")));
    }
    d.add(&format!("ADVANCED_FACE({},{},#{sid},.T.)", string(name), refs(&bounds)))
}

/// The trimmed faces' representation of the product's shape `shape`: one open shell per face.
pub(super) fn faces_representation(d: &mut Data, opts: &WriteOptions, shape: u64, faces: &[u64]) {
    let ctx = d.context(opts);
    let models: Vec<u64> = (faces.iter())
        .map(|f| {
            let shell = d.add(&format!("OPEN_SHELL('',(#{f}))"));
            d.add(&format!("SHELL_BASED_SURFACE_MODEL('',(#{shell}))"))
        })
        .collect();
    let rep = d.add(&format!(
        "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',{},#{ctx})",
        refs(&models)
    ));
    d.add(&format!("SHAPE_DEFINITION_REPRESENTATION(#{shape},#{rep})"));
}
