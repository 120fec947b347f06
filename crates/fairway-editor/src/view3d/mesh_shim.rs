//! TEMPORARY stand-in for `fairway::mesh` (helper "surface" is adding it to
//! the core with exactly this API); delete once it is on main.
#![allow(missing_docs)]

use fairway::{BSplineCurve, BSplineSurface, DVec2, DVec3, Error, Result};

#[derive(Debug, Clone, Default)]
pub struct SurfaceMesh {
    pub nu: usize,
    pub nv: usize,
    pub uv: Vec<DVec2>,
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    pub k_max: Vec<f64>,
    pub k_min: Vec<f64>,
    pub mean: Vec<f64>,
    pub gauss: Vec<f64>,
    pub indices: Vec<u32>,
}

impl SurfaceMesh {
    pub fn tessellate(s: &BSplineSurface, nu: usize, nv: usize) -> Result<SurfaceMesh> {
        if nu < 2 || nv < 2 {
            return Err(Error::InvalidInput("tessellation needs at least 2×2 vertices".into()));
        }
        let ((u0, u1), (v0, v1)) = s.domain();
        let mut m = SurfaceMesh {
            nu,
            nv,
            ..Default::default()
        };
        for i in 0..nu {
            let u = u0 + (u1 - u0) * i as f64 / (nu - 1) as f64;
            for j in 0..nv {
                let v = v0 + (v1 - v0) * j as f64 / (nv - 1) as f64;
                let c = s.curvature(u, v);
                m.uv.push(DVec2::new(u, v));
                m.positions.push(s.point(u, v));
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
                let b = a + nv as u32;
                m.indices.extend_from_slice(&[a, b, b + 1, a, b + 1, a + 1]);
            }
        }
        Ok(m)
    }
}

pub fn pick_uv(_s: &BSplineSurface, mesh: &SurfaceMesh, origin: DVec3, dir: DVec3) -> Option<DVec2> {
    let mut best: Option<(f64, DVec2)> = None;
    for t in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
        let (p0, p1, p2) = (mesh.positions[a], mesh.positions[b], mesh.positions[c]);
        let (e1, e2) = (p1 - p0, p2 - p0);
        let h = dir.cross(e2);
        let det = e1.dot(h);
        if det.abs() < 1e-300 {
            continue;
        }
        let f = 1.0 / det;
        let sv = origin - p0;
        let bu = f * sv.dot(h);
        let q = sv.cross(e1);
        let bv = f * dir.dot(q);
        if !(0.0..=1.0).contains(&bu) || bv < 0.0 || bu + bv > 1.0 {
            continue;
        }
        let tt = f * e2.dot(q);
        if tt > 0.0 && best.is_none_or(|(d, _)| tt < d) {
            best = Some((tt, mesh.uv[a] * (1.0 - bu - bv) + mesh.uv[b] * bu + mesh.uv[c] * bv));
        }
    }
    best.map(|b| b.1)
}

pub fn extrude_curve(c: &BSplineCurve, height: f64) -> Result<BSplineSurface> {
    let mut pts = Vec::with_capacity(c.n_points() * 2);
    for p in c.points() {
        pts.push(*p);
        pts.push(*p + DVec3::Z * height);
    }
    let w = c.weights().map(|w| w.iter().flat_map(|&x| [x, x]).collect());
    BSplineSurface::try_new(
        c.degree(),
        1,
        c.knots().values().to_vec(),
        vec![0.0, 0.0, 1.0, 1.0],
        c.n_points(),
        2,
        pts,
        w,
    )
}

pub fn curve_comb_3d(c: &BSplineCurve, samples: usize, scale: f64) -> Vec<(DVec3, DVec3)> {
    let (a, b) = c.domain();
    let n = samples.max(2);
    (0..n)
        .map(|k| {
            let u = a + (b - a) * k as f64 / (n - 1) as f64;
            let p = c.point(u);
            (p, p + scale * c.curvature_vector(u))
        })
        .collect()
}
