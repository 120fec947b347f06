//! Scenes of the 3D view built from a surface and its tessellation: the
//! triangles carry the exact normals and (for the curvature modes) colours
//! of the core's per-vertex curvature; lines for isoparametric curves at the
//! knots, the control net and the uv region's outline.

use fairway::{BSplineSurface, DVec3};

use super::colormap::{auto_range, diverging};
use super::render::Scene;
use super::{ShadeMode, Shading};
use fairway::mesh::SurfaceMesh;

/// Grey of the plain surface.
const SURFACE_GREY: [f32; 4] = [0.78, 0.80, 0.84, 1.0];
const ISO_COLOR: [f32; 4] = [0.10, 0.11, 0.14, 0.85];
const NET_COLOR: [f32; 4] = [0.35, 0.65, 1.0, 1.0];
const REGION_COLOR: [f32; 4] = [1.0, 0.55, 0.1, 1.0];
/// The outline of the active patch where the document has others.
const ACTIVE_OUTLINE: [f32; 4] = [1.0, 0.85, 0.2, 1.0];
/// Grey of the other patches of the document (plain shading).
const OTHER_GREY: [f32; 4] = [0.62, 0.66, 0.74, 1.0];
/// The brightness of the other patches relative to the active one (the vertex colour's alpha, which
/// the surface shader multiplies in every mode).
pub const OTHER_DIM: f32 = 0.6;

/// Per-vertex values of a curvature mode (`None` for the other modes).
pub fn mode_values(mesh: &SurfaceMesh, mode: ShadeMode) -> Option<&[f64]> {
    match mode {
        ShadeMode::Mean => Some(&mesh.mean),
        ShadeMode::Gauss => Some(&mesh.gauss),
        ShadeMode::KMax => Some(&mesh.k_max),
        ShadeMode::KMin => Some(&mesh.k_min),
        _ => None,
    }
}

/// The colour-map range in effect: the manual one or [`auto_range`] of `values`.
pub fn effective_range(shading: &Shading, values: &[f64]) -> f64 {
    match shading.range {
        Some(r) if r > 0.0 && r.is_finite() => r,
        _ => auto_range(values),
    }
}

fn f3(p: DVec3) -> [f32; 3] {
    [p.x as f32, p.y as f32, p.z as f32]
}

/// Build the scene of `s` (tessellated as `mesh`) relative to `origin`, with
/// the curvature map range `range`, and the outline of `region` if given.
pub fn surface_scene(
    s: &BSplineSurface,
    mesh: &SurfaceMesh,
    shading: &Shading,
    range: f64,
    region: Option<((f64, f64), (f64, f64))>,
    origin: DVec3,
) -> Scene {
    let mut sc = Scene::new();
    let values = mode_values(mesh, shading.mode);
    sc.tri_vertices
        .reserve(mesh.positions.len() * super::render::VERTEX_FLOATS);
    for k in 0..mesh.positions.len() {
        let c = match values {
            Some(v) => {
                let c = diverging(v[k], range);
                [c[0], c[1], c[2], 1.0]
            }
            None => SURFACE_GREY,
        };
        sc.tri_vertex(f3(mesh.positions[k] - origin), f3(mesh.normals[k]), c);
    }
    sc.tri_indices.extend_from_slice(&mesh.indices);
    let ((u0, u1), (v0, v1)) = s.domain();
    let polyline = |sc: &mut Scene, f: &dyn Fn(f64) -> DVec3, n: usize, color: [f32; 4]| {
        let mut last = f(0.0);
        for k in 1..=n {
            let p = f(k as f64 / n as f64);
            sc.line(f3(last - origin), f3(p - origin), color);
            last = p;
        }
    };
    if shading.show_iso {
        for u in s.knots_u().breakpoints() {
            polyline(&mut sc, &|t| s.point(u, v0 + (v1 - v0) * t), 96, ISO_COLOR);
        }
        for v in s.knots_v().breakpoints() {
            polyline(&mut sc, &|t| s.point(u0 + (u1 - u0) * t, v), 96, ISO_COLOR);
        }
    }
    if shading.show_net {
        let (nu, nv) = (s.nu(), s.nv());
        for i in 0..nu {
            for j in 0..nv {
                let p = s.point_at(i, j);
                if i + 1 < nu {
                    sc.line(f3(p - origin), f3(s.point_at(i + 1, j) - origin), NET_COLOR);
                }
                if j + 1 < nv {
                    sc.line(f3(p - origin), f3(s.point_at(i, j + 1) - origin), NET_COLOR);
                }
            }
        }
    }
    if let Some(((a1, a2), (b1, b2))) = region {
        polyline(&mut sc, &|t| s.point(a1 + (a2 - a1) * t, b1), 64, REGION_COLOR);
        polyline(&mut sc, &|t| s.point(a1 + (a2 - a1) * t, b2), 64, REGION_COLOR);
        polyline(&mut sc, &|t| s.point(a1, b1 + (b2 - b1) * t), 64, REGION_COLOR);
        polyline(&mut sc, &|t| s.point(a2, b1 + (b2 - b1) * t), 64, REGION_COLOR);
    }
    sc
}

/// Append another patch of the document (tessellated as `mesh`) to `sc`, dimmed ([`OTHER_DIM`]): grey in
/// the plain mode, the curvature map on the same range in the curvature modes, the stripes of the active
/// one in the stripe modes (the shader's), so they flow across the shared edges.
pub fn append_other(sc: &mut Scene, mesh: &SurfaceMesh, shading: &Shading, range: f64, origin: DVec3) {
    let first = sc.n_tri_vertices() as u32;
    let values = mode_values(mesh, shading.mode);
    for k in 0..mesh.positions.len() {
        let c = match values {
            Some(v) => diverging(v[k], range),
            None => [OTHER_GREY[0], OTHER_GREY[1], OTHER_GREY[2]],
        };
        sc.tri_vertex(
            f3(mesh.positions[k] - origin),
            f3(mesh.normals[k]),
            [c[0], c[1], c[2], OTHER_DIM],
        );
    }
    sc.tri_indices.extend(mesh.indices.iter().map(|i| i + first));
}

/// Append the boundary of `s` (the active patch) as a highlighted outline.
pub fn append_outline(sc: &mut Scene, s: &BSplineSurface, origin: DVec3) {
    let ((u0, u1), (v0, v1)) = s.domain();
    let n = 96;
    let at = |k: usize, side: usize| {
        let t = k as f64 / n as f64;
        match side {
            0 => s.point(u0 + (u1 - u0) * t, v0),
            1 => s.point(u1, v0 + (v1 - v0) * t),
            2 => s.point(u1 - (u1 - u0) * t, v1),
            _ => s.point(u0, v1 - (v1 - v0) * t),
        }
    };
    for side in 0..4 {
        for k in 0..n {
            sc.line(f3(at(k, side) - origin), f3(at(k + 1, side) - origin), ACTIVE_OUTLINE);
        }
    }
}

/// The colour of a trimmed face's loops.
const TRIM_LOOP: [f32; 4] = [0.2, 0.9, 1.0, 1.0];

/// A trimmed face's loops drawn on its surface `s` (as it is now: the loops are in its (u, v)), as
/// polylines of 48 segments an edge.
pub fn append_trim(sc: &mut Scene, s: &BSplineSurface, trim: &fairway::FaceTrim, origin: DVec3) {
    for l in trim.polylines(48) {
        for w in l.windows(2) {
            let (a, b) = (s.point(w[0].x, w[0].y), s.point(w[1].x, w[1].y));
            sc.line(f3(a - origin), f3(b - origin), TRIM_LOOP);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::view3d::render::VERTEX_FLOATS;

    /// A bicubic patch of the paraboloid-like z = x² − y² (exact: degree 2 in
    /// each variable is representable, elevated here via cubic knots).
    fn saddle() -> BSplineSurface {
        // z = (2u−1)² − (2v−1)² over [0,1]²: Bézier control values of (2t−1)²
        // in degree 2 are 1, −1, 1.
        let zs = [1.0, -1.0, 1.0];
        let mut pts = vec![];
        for i in 0..3 {
            for j in 0..3 {
                pts.push(DVec3::new(i as f64 * 0.5, j as f64 * 0.5, zs[i] - zs[j]));
            }
        }
        let k = vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
        BSplineSurface::try_new(2, 2, k.clone(), k, 3, 3, pts, None).unwrap()
    }

    #[test]
    fn curvature_colours_follow_the_sign_of_the_exact_curvature() {
        let s = saddle();
        let mesh = SurfaceMesh::tessellate(&s, 9, 9).unwrap();
        let sh = Shading {
            mode: ShadeMode::Gauss,
            show_iso: false,
            ..Default::default()
        };
        let range = effective_range(&sh, &mesh.gauss);
        let sc = surface_scene(&s, &mesh, &sh, range, None, DVec3::ZERO);
        assert_eq!(sc.n_tri_vertices(), 81);
        assert_eq!(sc.tri_indices.len(), 8 * 8 * 6);
        // a saddle: K < 0 everywhere → every vertex is on the cool side
        for k in 0..81 {
            assert!(mesh.gauss[k] < 0.0);
            let c = &sc.tri_vertices[k * VERTEX_FLOATS + 6..k * VERTEX_FLOATS + 9];
            assert!(c[2] > c[0], "vertex {k}: {c:?}");
        }
        // lines: none without iso/net/region; a region adds 4×64 segments
        assert!(sc.line_vertices.is_empty());
        let sc = surface_scene(&s, &mesh, &sh, range, Some(((0.2, 0.6), (0.1, 0.9))), DVec3::ZERO);
        assert_eq!(sc.line_vertices.len(), 4 * 64 * 2 * VERTEX_FLOATS);
    }

    #[test]
    fn positions_are_relative_to_the_origin() {
        let s = saddle();
        let mesh = SurfaceMesh::tessellate(&s, 3, 3).unwrap();
        let o = DVec3::new(10.0, -2.0, 0.5);
        let sc = surface_scene(&s, &mesh, &Shading::default(), 1.0, None, o);
        for k in 0..9 {
            let p = &sc.tri_vertices[k * VERTEX_FLOATS..k * VERTEX_FLOATS + 3];
            let q = mesh.positions[k] - o;
            assert!((p[0] as f64 - q.x).abs() < 1e-6 && (p[1] as f64 - q.y).abs() < 1e-6);
        }
    }
}
