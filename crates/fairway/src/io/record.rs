//! Serde mirror records of the geometry, validated into the real types by
//! `TryFrom` (the same constructors as everywhere else), so no invalid
//! geometry can be read.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::geometry::Geometry;
use crate::surface::BSplineSurface;

/// A curve as written in files: `{"degree", "knots", "points", "weights"?}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CurveRecord {
    /// Degree.
    pub degree: usize,
    /// Full clamped knot vector.
    pub knots: Vec<f64>,
    /// Points `[x, y]` or `[x, y, z]`.
    pub points: Vec<Vec<f64>>,
    /// Optional weights.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights: Option<Vec<f64>>,
}

/// A surface as written in files; `points[i][j]`, i over u.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SurfaceRecord {
    /// Degree in u.
    pub degree_u: usize,
    /// Degree in v.
    pub degree_v: usize,
    /// Knots in u.
    pub knots_u: Vec<f64>,
    /// Knots in v.
    pub knots_v: Vec<f64>,
    /// Points `[i][j] = [x, y, z]`.
    pub points: Vec<Vec<Vec<f64>>>,
    /// Optional weights `[i][j]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights: Option<Vec<Vec<f64>>>,
}

/// Either record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum GeometryRecord {
    /// A curve.
    Curve(CurveRecord),
    /// A surface.
    Surface(SurfaceRecord),
}

fn point3(field: &str, index: usize, c: &[f64], dim: usize) -> Result<DVec3> {
    if c.len() != dim {
        return Err(Error::BadDimension {
            field: field.into(),
            index,
            found: c.len(),
            expected: dim,
        });
    }
    Ok(DVec3::new(c[0], c[1], if dim == 3 { c[2] } else { 0.0 }))
}

impl TryFrom<CurveRecord> for BSplineCurve {
    type Error = Error;
    fn try_from(r: CurveRecord) -> Result<Self> {
        let dim = r.points.first().map_or(2, |p| p.len());
        if dim != 2 && dim != 3 {
            return Err(Error::BadDimension {
                field: "points".into(),
                index: 0,
                found: dim,
                expected: 2,
            });
        }
        let pts = r
            .points
            .iter()
            .enumerate()
            .map(|(i, c)| point3("points", i, c, dim))
            .collect::<Result<Vec<_>>>()?;
        BSplineCurve::try_new(r.degree, r.knots, pts, r.weights, dim)
    }
}

impl From<&BSplineCurve> for CurveRecord {
    fn from(c: &BSplineCurve) -> Self {
        let dim = c.dim();
        CurveRecord {
            degree: c.degree(),
            knots: c.knots().values().to_vec(),
            points: c.points().iter().map(|p| p.to_array()[..dim].to_vec()).collect(),
            weights: c.weights().map(|w| w.to_vec()),
        }
    }
}

impl TryFrom<SurfaceRecord> for BSplineSurface {
    type Error = Error;
    fn try_from(r: SurfaceRecord) -> Result<Self> {
        let nu = r.points.len();
        let nv = r.points.first().map_or(0, |row| row.len());
        let mut pts = Vec::with_capacity(nu * nv);
        for (i, row) in r.points.iter().enumerate() {
            if row.len() != nv {
                return Err(Error::LengthMismatch {
                    field: format!("points[{i}]"),
                    count: row.len(),
                    expected: nv,
                });
            }
            for (j, c) in row.iter().enumerate() {
                pts.push(point3("points", i * nv + j, c, 3)?);
            }
        }
        let weights = match r.weights {
            None => None,
            Some(w) => {
                if w.len() != nu || w.iter().any(|row| row.len() != nv) {
                    return Err(Error::InvalidInput(format!(
                        "weights: expected {nu} rows of {nv} values, like points"
                    )));
                }
                Some(w.into_iter().flatten().collect())
            }
        };
        BSplineSurface::try_new(r.degree_u, r.degree_v, r.knots_u, r.knots_v, nu, nv, pts, weights)
    }
}

impl From<&BSplineSurface> for SurfaceRecord {
    fn from(s: &BSplineSurface) -> Self {
        let (nu, nv) = (s.nu(), s.nv());
        SurfaceRecord {
            degree_u: s.degree_u(),
            degree_v: s.degree_v(),
            knots_u: s.knots_u().values().to_vec(),
            knots_v: s.knots_v().values().to_vec(),
            points: (0..nu)
                .map(|i| (0..nv).map(|j| s.point_at(i, j).to_array().to_vec()).collect())
                .collect(),
            weights: s
                .weights()
                .map(|w| (0..nu).map(|i| w[i * nv..(i + 1) * nv].to_vec()).collect()),
        }
    }
}

impl TryFrom<GeometryRecord> for Geometry {
    type Error = Error;
    fn try_from(r: GeometryRecord) -> Result<Self> {
        Ok(match r {
            GeometryRecord::Curve(c) => Geometry::Curve(c.try_into()?),
            GeometryRecord::Surface(s) => Geometry::Surface(s.try_into()?),
        })
    }
}

impl From<&Geometry> for GeometryRecord {
    fn from(g: &Geometry) -> Self {
        match g {
            Geometry::Curve(c) => GeometryRecord::Curve(c.into()),
            Geometry::Surface(s) => GeometryRecord::Surface(s.into()),
        }
    }
}

/// One loop of a trimmed face as written in documents: outer or a hole, its edges as 2D curves in the
/// surface's (u, v).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrimLoopRecord {
    /// The outer boundary (else a hole).
    pub outer: bool,
    /// The edges, in order, each `[u, v]` points.
    pub edges: Vec<CurveRecord>,
}

/// A face's loops as records.
pub(crate) fn trim_records(t: &crate::trim::FaceTrim) -> Vec<TrimLoopRecord> {
    (t.loops.iter())
        .map(|l| TrimLoopRecord {
            outer: l.outer,
            edges: l.edges.iter().map(CurveRecord::from).collect(),
        })
        .collect()
}

/// A face's loops from records, each edge validated as a 2D curve.
pub(crate) fn trim_from_records(r: Vec<TrimLoopRecord>) -> Result<crate::trim::FaceTrim> {
    let loops = (r.into_iter())
        .map(|l| {
            let edges = (l.edges.into_iter())
                .map(|e| {
                    let c = BSplineCurve::try_from(e)?;
                    if c.dim() != 2 {
                        return Err(Error::InvalidInput("a trim edge must be a 2D curve in (u, v)".into()));
                    }
                    Ok(c)
                })
                .collect::<Result<Vec<_>>>()?;
            if edges.is_empty() {
                return Err(Error::InvalidInput("a trim loop has no edges".into()));
            }
            Ok(crate::trim::TrimLoop { outer: l.outer, edges })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(crate::trim::FaceTrim { loops })
}
