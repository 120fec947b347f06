//! `fairway eval FILE --samples N [--json]`: evaluate at N uniform parameters.
//!
//! Curves: `{"parameters", "points", "d1", "d2", "curvature"}` at N uniform
//! parameters over the knot domain, first and last included; d1 and d2 are
//! derivatives with respect to the parameter; 2D curvature is signed
//! `(x'y'' − y'x'')/|c'|³`, 3D unsigned. 2D vectors are written `[x, y]`.
//!
//! Surfaces: `{"u", "v", "points", "normals", "k_max", "k_min", "mean",
//! "gauss"}` on the N×N grid of uniform u and v, nested `[i over u][j over v]`;
//! normal = Su × Sv normalized, a curvature is positive where the surface
//! bends towards the normal, k_max ≥ k_min (PRODUCT.md). Undefined values
//! (a cusp, a singular point) are written as `null`.

use std::path::PathBuf;

use anyhow::{Result, bail};
use fairway::{BSplineCurve, BSplineSurface, Geometry};
use serde::Serialize;

use crate::common::{coords, load_geometry, print_json, uniform_params};

/// Largest grid side for surfaces (N×N evaluations).
const MAX_SURFACE_SAMPLES: usize = 4000;

/// Arguments of `fairway eval`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Geometry file (.json geometry or .ron/.fairway document).
    pub file: PathBuf,
    /// Number of uniform parameters (per direction for surfaces), at least 2.
    #[arg(long, short = 'n', default_value_t = 101, value_parser = clap::value_parser!(u32).range(2..=10_000_000))]
    pub samples: u32,
    /// Print JSON (the schema of PRODUCT.md) instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Evaluation of a curve (the JSON schema).
#[derive(Serialize, Debug)]
pub struct CurveEval {
    /// Parameters.
    pub parameters: Vec<f64>,
    /// c(u).
    pub points: Vec<Vec<f64>>,
    /// c'(u).
    pub d1: Vec<Vec<f64>>,
    /// c''(u).
    pub d2: Vec<Vec<f64>>,
    /// κ(u).
    pub curvature: Vec<f64>,
}

/// Evaluation of a surface (the JSON schema).
#[derive(Serialize, Debug)]
pub struct SurfaceEval {
    /// u values.
    pub u: Vec<f64>,
    /// v values.
    pub v: Vec<f64>,
    /// S(u_i, v_j).
    pub points: Vec<Vec<Vec<f64>>>,
    /// Unit normals.
    pub normals: Vec<Vec<Vec<f64>>>,
    /// Larger principal curvature.
    pub k_max: Vec<Vec<f64>>,
    /// Smaller principal curvature.
    pub k_min: Vec<Vec<f64>>,
    /// Mean curvature.
    pub mean: Vec<Vec<f64>>,
    /// Gaussian curvature.
    pub gauss: Vec<Vec<f64>>,
}

/// Evaluate a curve at `n` uniform parameters.
pub fn eval_curve(c: &BSplineCurve, n: usize) -> CurveEval {
    let (a, b) = c.domain();
    let parameters = uniform_params(a, b, n);
    let dim = c.dim();
    let mut e = CurveEval {
        points: Vec::with_capacity(n),
        d1: Vec::with_capacity(n),
        d2: Vec::with_capacity(n),
        curvature: Vec::with_capacity(n),
        parameters,
    };
    for &u in &e.parameters {
        let d = c.derivs(u);
        e.points.push(coords(d.p, dim));
        e.d1.push(coords(d.d1, dim));
        e.d2.push(coords(d.d2, dim));
        e.curvature.push(d.curvature(dim));
    }
    e
}

/// Evaluate a surface on the `n × n` uniform grid.
pub fn eval_surface(s: &BSplineSurface, n: usize) -> SurfaceEval {
    let ((u0, u1), (v0, v1)) = s.domain();
    let u = uniform_params(u0, u1, n);
    let v = uniform_params(v0, v1, n);
    let mut e = SurfaceEval {
        points: Vec::with_capacity(n),
        normals: Vec::with_capacity(n),
        k_max: Vec::with_capacity(n),
        k_min: Vec::with_capacity(n),
        mean: Vec::with_capacity(n),
        gauss: Vec::with_capacity(n),
        u,
        v,
    };
    for &ui in &e.u {
        let mut row = (vec![], vec![], vec![], vec![], vec![], vec![]);
        for &vj in &e.v {
            let d = s.derivs(ui, vj);
            let k = d.curvature();
            row.0.push(d.p.to_array().to_vec());
            row.1.push(k.normal.to_array().to_vec());
            row.2.push(k.k_max);
            row.3.push(k.k_min);
            row.4.push(k.mean);
            row.5.push(k.gauss);
        }
        e.points.push(row.0);
        e.normals.push(row.1);
        e.k_max.push(row.2);
        e.k_min.push(row.3);
        e.mean.push(row.4);
        e.gauss.push(row.5);
    }
    e
}

fn fmt_vec(v: &[f64]) -> String {
    v.iter().map(|x| format!("{x:>15.8e}")).collect::<Vec<_>>().join(" ")
}

/// Run `fairway eval`.
pub fn run(args: &Args) -> Result<()> {
    let n = args.samples as usize;
    match load_geometry(&args.file)? {
        Geometry::Curve(c) => {
            let e = eval_curve(&c, n);
            if args.json {
                return print_json(&e);
            }
            println!(
                "# {}: curve, {} samples: u, point, d1, d2, curvature",
                args.file.display(),
                n
            );
            for i in 0..n {
                println!(
                    "{:>12.9} {} {} {} {:>15.8e}",
                    e.parameters[i],
                    fmt_vec(&e.points[i]),
                    fmt_vec(&e.d1[i]),
                    fmt_vec(&e.d2[i]),
                    e.curvature[i]
                );
            }
        }
        Geometry::Surface(s) => {
            if n > MAX_SURFACE_SAMPLES {
                bail!(
                    "--samples {n} is too large for a surface ({n}×{n} grid); at most {MAX_SURFACE_SAMPLES} per direction"
                );
            }
            let e = eval_surface(&s, n);
            if args.json {
                return print_json(&e);
            }
            println!(
                "# {}: surface, {n}×{n} grid: u, v, point, normal, k_max, k_min, mean, gauss",
                args.file.display()
            );
            for i in 0..n {
                for j in 0..n {
                    println!(
                        "{:>12.9} {:>12.9} {} {} {:>15.8e} {:>15.8e} {:>15.8e} {:>15.8e}",
                        e.u[i],
                        e.v[j],
                        fmt_vec(&e.points[i][j]),
                        fmt_vec(&e.normals[i][j]),
                        e.k_max[i][j],
                        e.k_min[i][j],
                        e.mean[i][j],
                        e.gauss[i][j]
                    );
                }
            }
        }
    }
    Ok(())
}
