//! A curve or a surface: what a file holds.

use crate::curve::BSplineCurve;
use crate::surface::BSplineSurface;

/// The geometry of a document or a file.
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    /// A 2D or 3D curve.
    Curve(BSplineCurve),
    /// A tensor-product surface.
    Surface(BSplineSurface),
}

impl Geometry {
    /// "curve" or "surface".
    pub fn kind(&self) -> &'static str {
        match self {
            Geometry::Curve(_) => "curve",
            Geometry::Surface(_) => "surface",
        }
    }

    /// The curve, if this is one.
    pub fn as_curve(&self) -> Option<&BSplineCurve> {
        match self {
            Geometry::Curve(c) => Some(c),
            Geometry::Surface(_) => None,
        }
    }

    /// The surface, if this is one.
    pub fn as_surface(&self) -> Option<&BSplineSurface> {
        match self {
            Geometry::Surface(s) => Some(s),
            Geometry::Curve(_) => None,
        }
    }
}

impl From<BSplineCurve> for Geometry {
    fn from(c: BSplineCurve) -> Self {
        Geometry::Curve(c)
    }
}

impl From<BSplineSurface> for Geometry {
    fn from(s: BSplineSurface) -> Self {
        Geometry::Surface(s)
    }
}
