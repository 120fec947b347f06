//! What a 3D view needs from the core: tessellation of a surface with exact
//! per-vertex curvature, ray picking to (u, v), extrusion of a planar curve
//! (for the paper's extrusion isophotes) and a curvature comb in 3D.
//!
//! Conventions are those of [`crate::surface`]: the normal is `Su × Sv`
//! normalized, a normal curvature is positive where the surface bends
//! towards the normal, `k_max ≥ k_min`.

use glam::{DMat3, DVec2, DVec3};

use crate::arclength::ArcLengthTable;
use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::surface::BSplineSurface;

/// Largest vertex count of a tessellation (indices are `u32`; this also keeps
/// a careless request from allocating gigabytes).
pub const MAX_MESH_VERTICES: usize = 1 << 24;

/// A triangle mesh of a surface on a uniform grid of the knot domain, with
/// the exact normal and curvatures of the surface at every vertex.
///
/// Vertex `(i, j)` (i along u, j along v) is at index `i * nv + j`; every
/// grid cell gives the triangles `(i,j) (i+1,j) (i+1,j+1)` and
/// `(i,j) (i+1,j+1) (i,j+1)`, counter-clockwise seen from the side the
/// normal `Su × Sv` points to.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SurfaceMesh {
    /// Vertices along u (≥ 2).
    pub nu: usize,
    /// Vertices along v (≥ 2).
    pub nv: usize,
    /// Parameters `(u, v)` of the vertices.
    pub uv: Vec<DVec2>,
    /// `S(u, v)`.
    pub positions: Vec<DVec3>,
    /// Unit normals `Su × Sv / |Su × Sv|` (see [`SurfaceMesh::tessellate`]
    /// for singular points).
    pub normals: Vec<DVec3>,
    /// Larger principal curvature.
    pub k_max: Vec<f64>,
    /// Smaller principal curvature.
    pub k_min: Vec<f64>,
    /// Mean curvature `(k_max + k_min) / 2`.
    pub mean: Vec<f64>,
    /// Gaussian curvature `k_max · k_min`.
    pub gauss: Vec<f64>,
    /// Triangle list, three indices per triangle.
    pub indices: Vec<u32>,
}

impl SurfaceMesh {
    /// Tessellate `s` with `nu × nv` vertices at uniform parameters of the
    /// knot domain (first and last included). Normals and curvatures come
    /// from the exact derivatives of the surface
    /// ([`BSplineSurface::curvature`]), not from the mesh.
    ///
    /// At a singular point (`Su × Sv = 0`, e.g. a collapsed edge) the
    /// normal and curvatures are those at a point moved by 10⁻⁷ of the
    /// domain towards its centre, i.e. the limit along that direction; if
    /// even that is singular, the normal is averaged from the adjacent
    /// triangles and the curvatures are set to 0 (nothing is NaN).
    ///
    /// Errors: `nu < 2`, `nv < 2`, or more than [`MAX_MESH_VERTICES`]
    /// vertices.
    pub fn tessellate(s: &BSplineSurface, nu: usize, nv: usize) -> Result<SurfaceMesh> {
        if nu < 2 || nv < 2 {
            return Err(Error::InvalidInput(format!(
                "tessellation: {nu} x {nv} vertices, at least 2 in each direction are needed"
            )));
        }
        if nu.checked_mul(nv).is_none_or(|n| n > MAX_MESH_VERTICES) {
            return Err(Error::InvalidInput(format!(
                "tessellation: {nu} x {nv} vertices, at most {MAX_MESH_VERTICES} in all"
            )));
        }
        let ((u0, u1), (v0, v1)) = s.domain();
        let (uc, vc) = (0.5 * (u0 + u1), 0.5 * (v0 + v1));
        let n = nu * nv;
        let mut m = SurfaceMesh {
            nu,
            nv,
            uv: Vec::with_capacity(n),
            positions: Vec::with_capacity(n),
            normals: Vec::with_capacity(n),
            k_max: Vec::with_capacity(n),
            k_min: Vec::with_capacity(n),
            mean: Vec::with_capacity(n),
            gauss: Vec::with_capacity(n),
            indices: Vec::with_capacity(6 * (nu - 1) * (nv - 1)),
        };
        let lerp = |a: f64, b: f64, k: usize, n: usize| {
            if k + 1 == n {
                b
            } else {
                a + (b - a) * k as f64 / (n - 1) as f64
            }
        };
        let mut singular = Vec::new();
        for i in 0..nu {
            let u = lerp(u0, u1, i, nu);
            for j in 0..nv {
                let v = lerp(v0, v1, j, nv);
                let d = s.derivs(u, v);
                let mut c = d.curvature();
                if !curv_finite(&c) {
                    let t = 1e-7;
                    c = s.curvature(u + t * (uc - u), v + t * (vc - v));
                }
                if !curv_finite(&c) {
                    singular.push(m.positions.len());
                    c.normal = DVec3::ZERO;
                    c.k_max = 0.0;
                    c.k_min = 0.0;
                    c.mean = 0.0;
                    c.gauss = 0.0;
                }
                m.uv.push(DVec2::new(u, v));
                m.positions.push(d.p);
                m.normals.push(c.normal);
                m.k_max.push(c.k_max);
                m.k_min.push(c.k_min);
                m.mean.push(c.mean);
                m.gauss.push(c.gauss);
            }
        }
        for i in 0..nu - 1 {
            for j in 0..nv - 1 {
                let a = (i * nv + j) as u32;
                let b = ((i + 1) * nv + j) as u32;
                let c = b + 1;
                let d = a + 1;
                m.indices.extend_from_slice(&[a, b, c, a, c, d]);
            }
        }
        if !singular.is_empty() {
            let mut acc = vec![DVec3::ZERO; n];
            for t in m.indices.chunks_exact(3) {
                let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
                let f = (m.positions[b] - m.positions[a]).cross(m.positions[c] - m.positions[a]);
                for k in [a, b, c] {
                    acc[k] += f;
                }
            }
            for k in singular {
                m.normals[k] = acc[k].normalize_or(DVec3::Z);
            }
        }
        Ok(m)
    }

    /// Number of triangles.
    pub fn n_triangles(&self) -> usize {
        self.indices.len() / 3
    }

    /// Axis-aligned bounding box `(min, max)` of the vertices.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        crate::curve::point_bounds(&self.positions)
    }
}

fn curv_finite(c: &crate::surface::SurfaceCurvature) -> bool {
    c.normal.is_finite() && c.k_max.is_finite() && c.k_min.is_finite() && c.mean.is_finite() && c.gauss.is_finite()
}

/// Ray `origin + t·dir, t > 0` against one triangle (Möller–Trumbore, both
/// faces). Returns `(t, b1, b2)` with the hit `a + b1 (b − a) + b2 (c − a)`.
fn ray_triangle(o: DVec3, d: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<(f64, f64, f64)> {
    let e1 = b - a;
    let e2 = c - a;
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - a;
    let b1 = s.dot(p) * inv;
    // a small slack so that a ray through a shared edge is not lost to rounding
    const SLACK: f64 = 1e-12;
    if !(-SLACK..=1.0 + SLACK).contains(&b1) {
        return None;
    }
    let q = s.cross(e1);
    let b2 = d.dot(q) * inv;
    if b2 < -SLACK || b1 + b2 > 1.0 + SLACK {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > 0.0).then_some((t, b1, b2))
}

/// The parameters `(u, v)` of the nearest point where the ray
/// `origin + t·dir, t > 0` meets the surface, or `None` if it misses the
/// mesh.
///
/// First the nearest hit on the triangles of `mesh` (a tessellation of `s`),
/// with `(u, v)` interpolated from the triangle's vertices; then Newton's
/// method on the exact surface, `S(u, v) − (origin + t·dir) = 0` in the
/// unknowns `(u, v, t)` (Jacobian `[Su, Sv, −dir]`), clamped to the domain.
/// If Newton does not converge to the ray (a grazing ray, or a hit just
/// outside the domain that only the mesh has), the mesh estimate is
/// returned. `dir` need not be unit length; a zero or non-finite ray gives
/// `None`.
pub fn pick_uv(s: &BSplineSurface, mesh: &SurfaceMesh, origin: DVec3, dir: DVec3) -> Option<DVec2> {
    if !origin.is_finite() || !dir.is_finite() || dir.length_squared() == 0.0 {
        return None;
    }
    let (lo, hi) = mesh.bounds();
    if !ray_hits_box(origin, dir, lo, hi) {
        return None;
    }
    let mut best: Option<(f64, DVec2)> = None;
    for t in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
        let p = &mesh.positions;
        if let Some((tt, b1, b2)) = ray_triangle(origin, dir, p[a], p[b], p[c])
            && best.is_none_or(|(bt, _)| tt < bt)
        {
            let uv = mesh.uv[a] * (1.0 - b1 - b2) + mesh.uv[b] * b1 + mesh.uv[c] * b2;
            best = Some((tt, uv));
        }
    }
    let (t0, uv0) = best?;
    let scale = (hi - lo).length().max(f64::MIN_POSITIVE);
    Some(refine_hit(s, origin, dir, uv0, t0, scale).unwrap_or(uv0))
}

/// Slab test of the ray against a (slightly enlarged) box.
fn ray_hits_box(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> bool {
    let pad = 1e-9 * (hi - lo).length() + 1e-300;
    let (lo, hi) = (lo - DVec3::splat(pad), hi + DVec3::splat(pad));
    let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
    for k in 0..3 {
        if d[k] == 0.0 {
            if o[k] < lo[k] || o[k] > hi[k] {
                return false;
            }
        } else {
            let (a, b) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
    }
    t0 <= t1
}

/// Newton on `S(u, v) − o − t d = 0`; `None` unless it converges inside the domain.
fn refine_hit(s: &BSplineSurface, o: DVec3, d: DVec3, uv: DVec2, t: f64, scale: f64) -> Option<DVec2> {
    let ((u0, u1), (v0, v1)) = s.domain();
    let (mut u, mut v, mut t) = (uv.x, uv.y, t);
    let tol = 1e-13 * scale;
    for _ in 0..30 {
        let sd = s.derivs(u, v);
        let f = sd.p - (o + d * t);
        let j = DMat3::from_cols(sd.su, sd.sv, -d);
        if j.determinant().abs() <= f64::MIN_POSITIVE {
            return None;
        }
        let step = j.inverse() * f;
        if !step.is_finite() {
            return None;
        }
        let (nu, nv) = ((u - step.x).clamp(u0, u1), (v - step.y).clamp(v0, v1));
        let moved = (nu - u).abs() / (u1 - u0) + (nv - v).abs() / (v1 - v0);
        u = nu;
        v = nv;
        t -= step.z;
        if f.length() <= tol && moved < 1e-15 {
            break;
        }
    }
    let f = s.point(u, v) - (o + d * t);
    (f.length() <= 1e-10 * scale && t > 0.0).then_some(DVec2::new(u, v))
}

/// The planar curve `c` (z = 0) extruded by `height` along +z: the surface
/// `S(u, v) = c(u) + v·height·ẑ`, `v ∈ [0, 1]`, of degree `(p, 1)` with
/// the curve's knots (and weights) in u and knots `[0, 0, 1, 1]` in v.
/// Exact: `S(u, 0) = c(u)`, and every u-isoline is a translate of `c`.
///
/// Its normal `Su × Sv = c' × ẑ` is the curve's **right** normal, so the
/// normal curvature along u is `−κ` for the signed 2D curvature κ
/// (`k_min = min(−κ, 0)`, `k_max = max(−κ, 0)`); this is the surface whose
/// isophotes the paper uses to interrogate a planar curve.
///
/// Errors: a curve with a point off the plane z = 0, or a height that is
/// not finite and positive.
pub fn extrude_curve(c: &BSplineCurve, height: f64) -> Result<BSplineSurface> {
    if !(height.is_finite() && height > 0.0) {
        return Err(Error::InvalidInput(format!(
            "extrusion height must be a positive finite number, got {height}"
        )));
    }
    if let Some(i) = c.points().iter().position(|p| p.z != 0.0) {
        return Err(Error::InvalidInput(format!(
            "extrusion needs a planar curve in z = 0; control point {i} has z = {}",
            c.points()[i].z
        )));
    }
    let n = c.n_points();
    let mut points = Vec::with_capacity(2 * n);
    for p in c.points() {
        points.push(*p);
        points.push(*p + DVec3::Z * height);
    }
    let weights = c.weights().map(|w| w.iter().flat_map(|&x| [x, x]).collect());
    BSplineSurface::try_new(
        c.degree(),
        1,
        c.knots().values().to_vec(),
        vec![0.0, 0.0, 1.0, 1.0],
        n,
        2,
        points,
        weights,
    )
}

/// Sign-consistent unit normal and signed curvature at the parameters `us`
/// (taken in order), the frame of the curve fairing engine
/// ([`crate::fair::curve`], step 2):
/// * 2D: the tangent turned by +90° and the signed curvature;
/// * 3D: the principal normal, flipped whenever it would turn by more than
///   90° from the previous sample, and carried over (projected on the normal
///   plane) where `|κ| ≤ 10⁻⁹ · max κ`, so the frame does not fold at
///   inflections; the curvature is `κN · N` (negative past an inflection).
///
/// `κ·N` is always the curvature vector. Entries are NaN where `c' = 0`.
pub fn signed_frame(c: &BSplineCurve, us: &[f64]) -> Vec<(DVec3, f64)> {
    let dim = c.dim();
    let kmax = if dim == 3 {
        us.iter()
            .map(|&u| c.derivs(u).curvature_vector().length())
            .fold(0.0f64, |a, b| a.max(b))
    } else {
        0.0
    };
    let mut out = Vec::with_capacity(us.len());
    let mut prev: Option<DVec3> = None;
    for &u in us {
        let d = c.derivs(u);
        let v = d.d1.length();
        if !(v > 0.0) || !v.is_finite() {
            out.push((DVec3::NAN, f64::NAN));
            continue;
        }
        let t = d.d1 / v;
        if dim == 2 {
            out.push((DVec3::new(-t.y, t.x, 0.0), d.curvature(2)));
            continue;
        }
        let kv = d.curvature_vector();
        let kl = kv.length();
        let mut nn = if kl > 1e-9 * kmax.max(1e-300) {
            kv / kl
        } else if let Some(pn) = prev {
            (pn - t * pn.dot(t)).normalize_or(t.any_orthonormal_vector())
        } else {
            t.any_orthonormal_vector()
        };
        if prev.is_some_and(|pn| nn.dot(pn) < 0.0) {
            nn = -nn;
        }
        prev = Some(nn);
        out.push((nn, kv.dot(nn)));
    }
    out
}

/// A curvature comb: `samples` points at equal arc length over the whole
/// curve (first and last included; 1 sample gives the start), each with its
/// tooth `(base, tip)`, `tip = base − scale · κ · N` in the sign-consistent
/// frame of [`signed_frame`] — i.e. `−scale` times the curvature vector:
/// teeth of length `scale·|κ|` on the outside of the bend, away from the
/// centre of curvature. 3D curves get their comb in space, 2D curves in
/// their plane (z = 0). Samples where the curve has zero speed (coincident
/// control points) are left out. `samples = 0` gives an empty comb.
pub fn curve_comb_3d(c: &BSplineCurve, samples: usize, scale: f64) -> Vec<(DVec3, DVec3)> {
    let us: Vec<f64> = match samples {
        0 => return Vec::new(),
        1 => vec![c.domain().0],
        n => ArcLengthTable::new(c, 1e-10).equal_arc_params(c, n),
    };
    signed_frame(c, &us)
        .into_iter()
        .zip(&us)
        .filter(|((n, k), _)| n.is_finite() && k.is_finite())
        .map(|((n, k), &u)| {
            let p = c.point(u);
            (p, p - n * (scale * k))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_1_SQRT_2;

    /// Rational biquadratic patch of a sphere of radius r about the origin:
    /// a quarter meridian (latitude 0..90°, polar cap excluded by using
    /// 0..`lat1`) swept by a quarter parallel. Built from exact conics:
    /// meridian arc from angle a0 to a1 (< 90°) as one rational quadratic.
    fn sphere_patch(r: f64, a0: f64, a1: f64) -> BSplineSurface {
        // meridian in the (ρ, z) plane
        let am = 0.5 * (a1 - a0);
        let wm = am.cos();
        let pm0 = (a0.cos(), a0.sin());
        let pm2 = (a1.cos(), a1.sin());
        let mid = 0.5 * (a0 + a1);
        let pm1 = (mid.cos() / wm, mid.sin() / wm);
        let mer = [(pm0, 1.0), (pm1, wm), (pm2, 1.0)];
        // parallel: quarter circle in the xy plane
        let par = [((1.0, 0.0), 1.0), ((1.0, 1.0), FRAC_1_SQRT_2), ((0.0, 1.0), 1.0)];
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for &((rho, z), wi) in &mer {
            for &((x, y), wj) in &par {
                pts.push(DVec3::new(r * rho * x, r * rho * y, r * z));
                w.push(wi * wj);
            }
        }
        let k = vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
        BSplineSurface::try_new(2, 2, k.clone(), k, 3, 3, pts, Some(w)).unwrap()
    }

    fn plane(origin: DVec3, a: DVec3, b: DVec3) -> BSplineSurface {
        // bicubic plane S(u,v) = origin + u a + v b on [0,1]², non-uniform knots
        let ku = vec![0.0, 0.0, 0.0, 0.0, 0.3, 1.0, 1.0, 1.0, 1.0];
        let kv = vec![0.0, 0.0, 0.0, 0.0, 0.6, 1.0, 1.0, 1.0, 1.0];
        // Greville abscissae reproduce the linear function exactly
        let g = |k: &[f64]| {
            (0..5)
                .map(|i| (k[i + 1] + k[i + 2] + k[i + 3]) / 3.0)
                .collect::<Vec<_>>()
        };
        let (gu, gv) = (g(&ku), g(&kv));
        let mut pts = Vec::new();
        for &u in &gu {
            for &v in &gv {
                pts.push(origin + a * u + b * v);
            }
        }
        BSplineSurface::try_new(3, 3, ku, kv, 5, 5, pts, None).unwrap()
    }

    fn cylinder(r: f64, h: f64) -> BSplineSurface {
        // quarter cylinder x² + y² = r², z ∈ [0, h]: u around, v along z
        let par = [((1.0, 0.0), 1.0), ((1.0, 1.0), FRAC_1_SQRT_2), ((0.0, 1.0), 1.0)];
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for &((x, y), wi) in &par {
            for z in [0.0, h] {
                pts.push(DVec3::new(r * x, r * y, z));
                w.push(wi);
            }
        }
        BSplineSurface::try_new(
            2,
            1,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![0.0, 0.0, 1.0, 1.0],
            3,
            2,
            pts,
            Some(w),
        )
        .unwrap()
    }

    #[test]
    fn sphere_patch_curvature_is_one_over_r() {
        let r = 2.5;
        let s = sphere_patch(r, 0.1, 1.2);
        let m = SurfaceMesh::tessellate(&s, 9, 7).unwrap();
        assert_eq!(m.positions.len(), 63);
        assert_eq!(m.indices.len(), 6 * 8 * 6);
        for k in 0..m.positions.len() {
            let p = m.positions[k];
            assert!((p.length() - r).abs() < 1e-12, "on the sphere");
            let n = m.normals[k];
            assert!((n.length() - 1.0).abs() < 1e-12);
            // the normal is radial (either orientation), and the curvature
            // has the sign of bending towards it: −1/r for outward normals
            let radial = p / r;
            let sign = n.dot(radial);
            assert!((sign.abs() - 1.0).abs() < 1e-10, "radial normal");
            let expect = -sign.signum() / r;
            for kk in [m.k_max[k], m.k_min[k], m.mean[k]] {
                assert!((kk - expect).abs() < 1e-9, "{kk} vs {expect}");
            }
            assert!((m.gauss[k] - 1.0 / (r * r)).abs() < 1e-9);
        }
        // the uv grid is uniform in the knot domain, corners included
        assert_eq!(m.uv[0], DVec2::new(0.0, 0.0));
        assert_eq!(m.uv[62], DVec2::new(1.0, 1.0));
        assert!((m.uv[7].x - 0.125).abs() < 1e-15 && m.uv[1].y == 1.0 / 6.0);
    }

    #[test]
    fn plane_and_cylinder_curvatures() {
        let s = plane(
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(2.0, 0.5, 0.0),
            DVec3::new(0.0, 1.0, 1.0),
        );
        let m = SurfaceMesh::tessellate(&s, 5, 4).unwrap();
        let n0 = DVec3::new(2.0, 0.5, 0.0).cross(DVec3::new(0.0, 1.0, 1.0)).normalize();
        for k in 0..m.positions.len() {
            assert!((m.normals[k] - n0).length() < 1e-12);
            for x in [m.k_max[k], m.k_min[k], m.mean[k], m.gauss[k]] {
                assert!(x.abs() < 1e-10);
            }
            let uv = m.uv[k];
            let p = DVec3::new(1.0, 2.0, 3.0) + DVec3::new(2.0, 0.5, 0.0) * uv.x + DVec3::new(0.0, 1.0, 1.0) * uv.y;
            assert!((m.positions[k] - p).length() < 1e-12);
        }
        let r = 0.75;
        let c = cylinder(r, 2.0);
        let m = SurfaceMesh::tessellate(&c, 6, 3).unwrap();
        for k in 0..m.positions.len() {
            let p = m.positions[k];
            let radial = DVec3::new(p.x, p.y, 0.0) / r;
            assert!((radial.length() - 1.0).abs() < 1e-12);
            let sign = m.normals[k].dot(radial);
            assert!((sign.abs() - 1.0).abs() < 1e-10);
            // one principal curvature 0, the other ∓1/r
            let k_round = -sign.signum() / r;
            let (hi, lo) = if k_round > 0.0 { (k_round, 0.0) } else { (0.0, k_round) };
            assert!((m.k_max[k] - hi).abs() < 1e-9 && (m.k_min[k] - lo).abs() < 1e-9);
            assert!((m.mean[k] - k_round / 2.0).abs() < 1e-9 && m.gauss[k].abs() < 1e-9);
        }
    }

    #[test]
    fn winding_agrees_with_normals() {
        for s in [sphere_patch(1.0, 0.0, 1.0), cylinder(1.0, 1.0), {
            let p = plane(DVec3::ZERO, DVec3::X, DVec3::Y);
            p.with_points(p.points().iter().map(|q| DVec3::new(q.y, q.x, 0.3 * q.x)).collect())
                .unwrap()
        }] {
            let m = SurfaceMesh::tessellate(&s, 7, 5).unwrap();
            assert_eq!(m.n_triangles(), 2 * 6 * 4);
            for t in m.indices.chunks_exact(3) {
                let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
                let f = (m.positions[b] - m.positions[a]).cross(m.positions[c] - m.positions[a]);
                let nsum = m.normals[a] + m.normals[b] + m.normals[c];
                assert!(f.dot(nsum) > 0.0, "triangle {t:?} wound against its normals");
            }
            // every index in range
            assert!(m.indices.iter().all(|&i| (i as usize) < m.positions.len()));
        }
    }

    #[test]
    fn bad_tessellation_requests() {
        let s = cylinder(1.0, 1.0);
        assert!(matches!(SurfaceMesh::tessellate(&s, 1, 5), Err(Error::InvalidInput(_))));
        assert!(matches!(SurfaceMesh::tessellate(&s, 5, 0), Err(Error::InvalidInput(_))));
        assert!(SurfaceMesh::tessellate(&s, 1 << 13, 1 << 12).is_err());
    }

    #[test]
    fn collapsed_edge_gives_finite_normals() {
        // a cone-like patch: the row i = 0 collapses to one point (apex)
        let mut pts = Vec::new();
        for i in 0..4 {
            for j in 0..4 {
                let rho = i as f64 / 3.0;
                let a = j as f64 / 3.0;
                pts.push(DVec3::new(rho * a.cos(), rho * a.sin(), 1.0 - rho));
            }
        }
        let k = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let s = BSplineSurface::try_new(3, 3, k.clone(), k, 4, 4, pts, None).unwrap();
        assert!(s.normal(0.0, 0.5).is_nan());
        let m = SurfaceMesh::tessellate(&s, 5, 5).unwrap();
        for k in 0..25 {
            assert!(m.normals[k].is_finite() && (m.normals[k].length() - 1.0).abs() < 1e-9);
            assert!(m.k_max[k].is_finite() && m.gauss[k].is_finite());
        }
        // at the apex the normal is the limit of the nearby normals
        let near = s.normal(1e-4, 0.5);
        assert!(m.normals[2].dot(near) > 0.99, "{:?} vs {near:?}", m.normals[2]);
    }

    #[test]
    fn pick_plane_returns_analytic_uv() {
        let o = DVec3::new(1.0, 2.0, 3.0);
        let (a, b) = (DVec3::new(2.0, 0.5, 0.0), DVec3::new(0.0, 1.0, 1.0));
        let s = plane(o, a, b);
        let m = SurfaceMesh::tessellate(&s, 4, 4).unwrap();
        let n = a.cross(b).normalize();
        for (u, v) in [(0.3, 0.7), (0.01, 0.99), (0.5, 0.5), (0.9, 0.12)] {
            let target = o + a * u + b * v;
            for dir in [-n, -n + a * 0.3, (-n - b * 0.2) * 5.0] {
                let origin = target - dir * 3.0;
                let uv = pick_uv(&s, &m, origin, dir).expect("hit");
                assert!((uv - DVec2::new(u, v)).length() < 1e-9, "{uv:?} vs ({u}, {v})");
            }
        }
    }

    #[test]
    fn pick_sphere_returns_analytic_uv_and_nearest_hit() {
        let r = 2.0;
        let s = sphere_patch(r, 0.1, 1.2);
        let m = SurfaceMesh::tessellate(&s, 6, 6).unwrap();
        for (u, v) in [(0.3, 0.6), (0.5, 0.5), (0.8, 0.15), (0.05, 0.9)] {
            let target = s.point(u, v);
            // from outside, straight at the centre: hits the patch at target
            let origin = target * 3.0;
            let uv = pick_uv(&s, &m, origin, -target).expect("hit");
            assert!((uv - DVec2::new(u, v)).length() < 1e-9, "{uv:?} vs ({u}, {v})");
            // an oblique ray through the same point
            let dir = -target + DVec3::new(0.3, -0.2, 0.1);
            let uv = pick_uv(&s, &m, target - dir * 0.5, dir).expect("hit");
            assert!((uv - DVec2::new(u, v)).length() < 1e-9, "{uv:?} vs ({u}, {v})");
        }
        // a ray straight down onto a plane, and the same ray pointing away
        let near = plane(DVec3::new(0.0, 0.0, 1.0), DVec3::X, DVec3::Y);
        let mn = SurfaceMesh::tessellate(&near, 3, 3).unwrap();
        let uv = pick_uv(&near, &mn, DVec3::new(0.25, 0.5, 5.0), DVec3::NEG_Z).unwrap();
        assert!((uv - DVec2::new(0.25, 0.5)).length() < 1e-12);
        // behind the origin: no hit
        assert!(pick_uv(&near, &mn, DVec3::new(0.25, 0.5, 5.0), DVec3::Z).is_none());
    }

    #[test]
    fn pick_nearest_of_two_hits() {
        // a half cylinder seen side-on: the ray crosses it twice, the nearer wins
        let r = 1.0;
        let k = vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0];
        let ctrl = [
            ((1.0, 0.0), 1.0),
            ((1.0, 1.0), FRAC_1_SQRT_2),
            ((0.0, 1.0), 1.0),
            ((-1.0, 1.0), FRAC_1_SQRT_2),
            ((-1.0, 0.0), 1.0),
        ];
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for &((x, y), wi) in &ctrl {
            for z in [0.0, 1.0] {
                pts.push(DVec3::new(r * x, r * y, z));
                w.push(wi);
            }
        }
        let s = BSplineSurface::try_new(2, 1, k, vec![0.0, 0.0, 1.0, 1.0], 5, 2, pts, Some(w)).unwrap();
        let m = SurfaceMesh::tessellate(&s, 17, 3).unwrap();
        // ray along −x at height y = 0.6, z = 0.4: hits x = +0.8 first
        let uv = pick_uv(&s, &m, DVec3::new(5.0, 0.6, 0.4), DVec3::NEG_X).unwrap();
        let p = s.point(uv.x, uv.y);
        assert!((p - DVec3::new(0.8, 0.6, 0.4)).length() < 1e-9, "{p:?}");
        assert!(uv.x < 0.5 && (uv.y - 0.4).abs() < 1e-9);
        let uv = pick_uv(&s, &m, DVec3::new(-5.0, 0.6, 0.4), DVec3::X).unwrap();
        assert!((s.point(uv.x, uv.y) - DVec3::new(-0.8, 0.6, 0.4)).length() < 1e-9);
    }

    #[test]
    fn pick_miss_returns_none() {
        let s = sphere_patch(1.0, 0.1, 1.2);
        let m = SurfaceMesh::tessellate(&s, 8, 8).unwrap();
        // pointing away, passing beside, parallel to a plane, degenerate
        assert!(pick_uv(&s, &m, DVec3::new(3.0, 3.0, 3.0), DVec3::new(1.0, 1.0, 1.0)).is_none());
        assert!(pick_uv(&s, &m, DVec3::new(-3.0, -3.0, 0.5), DVec3::new(0.0, 0.0, 1.0)).is_none());
        assert!(pick_uv(&s, &m, DVec3::new(0.5, 0.5, 0.5), DVec3::ZERO).is_none());
        assert!(pick_uv(&s, &m, DVec3::new(0.5, 0.5, f64::NAN), DVec3::Z).is_none());
        let p = plane(DVec3::ZERO, DVec3::X, DVec3::Y);
        let mp = SurfaceMesh::tessellate(&p, 3, 3).unwrap();
        assert!(pick_uv(&p, &mp, DVec3::new(0.5, 0.5, 1.0), DVec3::X).is_none());
        assert!(pick_uv(&p, &mp, DVec3::new(1.5, 0.5, 1.0), DVec3::NEG_Z).is_none());
    }

    fn wavy_2d() -> BSplineCurve {
        let pts: Vec<DVec2> = (0..8)
            .map(|i| DVec2::new(i as f64, (i as f64 * 1.3).sin() + 0.1 * i as f64))
            .collect();
        BSplineCurve::new_2d(
            3,
            vec![0.0, 0.0, 0.0, 0.0, 0.2, 0.3, 0.5, 0.8, 1.0, 1.0, 1.0, 1.0],
            &pts,
        )
        .unwrap()
    }

    #[test]
    fn extrusion_is_exact() {
        let c = wavy_2d();
        let h = 2.5;
        let s = extrude_curve(&c, h).unwrap();
        assert_eq!((s.degree_u(), s.degree_v()), (3, 1));
        for k in 0..=40 {
            let u = k as f64 / 40.0;
            for v in [0.0, 0.3, 1.0] {
                let q = c.point(u) + DVec3::Z * (v * h);
                assert!((s.point(u, v) - q).length() < 1e-13);
            }
            // the u-isoline at any height has the curve's curvature, and the
            // surface's normal curvature along u is −κ (normal = right normal)
            let kappa = c.curvature(u);
            let iso = s.iso_u(0.4);
            assert!((iso.curvature(u) - kappa.abs()).abs() < 1e-9 * (1.0 + kappa.abs()));
            let sc = s.curvature(u, 0.4);
            assert!((sc.k_max + sc.k_min + kappa).abs() < 1e-9 * (1.0 + kappa.abs()));
            assert!(sc.gauss.abs() < 1e-9);
            let right = c.normal(u) * -1.0;
            assert!((sc.normal - right).length() < 1e-12);
        }
        // rational curves keep their weights: a quarter circle stays exact
        let circ = BSplineCurve::try_new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y],
            Some(vec![1.0, FRAC_1_SQRT_2, 1.0]),
            2,
        )
        .unwrap();
        let s = extrude_curve(&circ, 1.0).unwrap();
        for k in 0..=10 {
            let p = s.point(k as f64 / 10.0, 0.7);
            assert!((DVec3::new(p.x, p.y, 0.0).length() - 1.0).abs() < 1e-13 && (p.z - 0.7).abs() < 1e-15);
        }
        // bad input
        let c3 = BSplineCurve::new_3d(1, vec![0.0, 0.0, 1.0, 1.0], vec![DVec3::ZERO, DVec3::ONE]).unwrap();
        assert!(matches!(extrude_curve(&c3, 1.0), Err(Error::InvalidInput(_))));
        assert!(extrude_curve(&c, 0.0).is_err() && extrude_curve(&c, f64::NAN).is_err());
        // a 3D curve lying in z = 0 is accepted
        let flat = BSplineCurve::new_3d(1, vec![0.0, 0.0, 1.0, 1.0], vec![DVec3::ZERO, DVec3::X]).unwrap();
        assert!(extrude_curve(&flat, 1.0).is_ok());
    }

    #[test]
    fn comb_of_a_circle() {
        let r = 1.7;
        let scale = 0.4;
        // full circle as four rational quadratic arcs, 2D and 3D (tilted)
        let (s2, c) = (
            FRAC_1_SQRT_2,
            [
                (1.0, 0.0),
                (1.0, 1.0),
                (0.0, 1.0),
                (-1.0, 1.0),
                (-1.0, 0.0),
                (-1.0, -1.0),
                (0.0, -1.0),
                (1.0, -1.0),
                (1.0, 0.0),
            ],
        );
        let w: Vec<f64> = (0..9).map(|i| if i % 2 == 1 { s2 } else { 1.0 }).collect();
        let knots = vec![0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0];
        let pts2: Vec<DVec3> = c.iter().map(|&(x, y)| DVec3::new(r * x, r * y, 0.0)).collect();
        let circle2 = BSplineCurve::try_new(2, knots.clone(), pts2.clone(), Some(w.clone()), 2).unwrap();
        let rot = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.8);
        let centre = DVec3::new(0.3, -1.0, 2.0);
        let pts3: Vec<DVec3> = pts2.iter().map(|&p| centre + rot * p).collect();
        let circle3 = BSplineCurve::try_new(2, knots, pts3, Some(w), 3).unwrap();
        for (curve, ctr) in [(&circle2, DVec3::ZERO), (&circle3, centre)] {
            let comb = curve_comb_3d(curve, 33, scale);
            assert_eq!(comb.len(), 33);
            for &(base, tip) in &comb {
                assert!(((base - ctr).length() - r).abs() < 1e-12);
                let tooth = tip - base;
                assert!((tooth.length() - scale / r).abs() < 1e-9, "{}", tooth.length());
                // outside the circle, radial
                assert!(((tip - ctr).length() - (r + scale / r)).abs() < 1e-9);
            }
            // equal arc length spacing
            let d0 = (comb[1].0 - comb[0].0).length();
            assert!(comb.windows(2).all(|p| ((p[1].0 - p[0].0).length() - d0).abs() < 1e-9));
            // the 2D comb stays in its plane
            if curve.dim() == 2 {
                assert!(comb.iter().all(|(b, t)| b.z == 0.0 && t.z == 0.0));
            }
        }
        assert!(curve_comb_3d(&circle2, 0, 1.0).is_empty());
        assert_eq!(curve_comb_3d(&circle2, 1, 1.0).len(), 1);
    }

    #[test]
    fn signed_frame_does_not_fold_at_a_3d_inflection() {
        // an S-shaped space curve: the principal normal flips at the
        // inflection, the signed frame does not and κ changes sign instead
        let pts = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.1),
            DVec3::new(2.0, 1.0, 0.2),
            DVec3::new(3.0, -1.0, 0.3),
            DVec3::new(4.0, -1.0, 0.4),
            DVec3::new(5.0, 0.0, 0.5),
        ];
        let c = BSplineCurve::new_3d(3, vec![0.0, 0.0, 0.0, 0.0, 0.4, 0.6, 1.0, 1.0, 1.0, 1.0], pts).unwrap();
        let us: Vec<f64> = (0..=200).map(|k| k as f64 / 200.0).collect();
        let f = signed_frame(&c, &us);
        let mut sign_changes = 0;
        for k in 1..f.len() {
            assert!(f[k].0.dot(f[k - 1].0) > 0.0, "frame folds at {}", us[k]);
            if f[k].1.signum() != f[k - 1].1.signum() {
                sign_changes += 1;
            }
        }
        assert!(sign_changes >= 1, "κ must change sign at the inflection");
        for (k, &u) in us.iter().enumerate() {
            // κN is the curvature vector, whatever the sign
            assert!((f[k].0 * f[k].1 - c.curvature_vector(u)).length() < 1e-9);
        }
        // the comb teeth are −scale × the curvature vector
        let comb = curve_comb_3d(&c, 20, 0.5);
        let ua = ArcLengthTable::new(&c, 1e-10).equal_arc_params(&c, 20);
        assert_eq!(comb.len(), 20);
        for (&(b, t), &u) in comb.iter().zip(&ua) {
            assert!((b - c.point(u)).length() < 1e-12);
            assert!((t - b + c.curvature_vector(u) * 0.5).length() < 1e-9);
        }
    }
}
