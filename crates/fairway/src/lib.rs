//! # Fairway core
//!
//! Geometry and fairing of B-spline curves and surfaces, with no GUI
//! dependencies: knot vectors and basis functions ([`knots`], [`basis`]),
//! curves and surfaces ([`curve`], [`surface`]), arc length
//! ([`arclength`]), closest points ([`closest`]), corners ([`corners`]), least-squares fitting
//! ([`fit`]), the fairing engine ([`fair`]) and file formats ([`io`]), suggested
//! fairing regions ([`suggest`]).
//!
//! f64 throughout; points are [`glam::DVec3`] (2D curves keep z = 0).
#![deny(missing_docs)]

pub mod arclength;
pub mod basis;
pub mod closest;
pub mod corners;
pub mod curve;
pub mod error;
pub mod fair;
pub mod fit;
pub mod fit_surface;
pub mod geometry;
pub mod io;
pub mod knots;
pub mod linalg;
pub mod measure;
pub mod measure_surface;
pub mod mesh;
pub mod quadrature;
pub mod range;
pub mod suggest;
pub mod surface;

pub use arclength::ArcLengthTable;
pub use closest::{ClosestPoint, CurveProjector};
pub use curve::{BSplineCurve, CurveDerivs};
pub use error::{Error, Result};
pub use geometry::Geometry;
pub use glam::{DVec2, DVec3};
pub use knots::KnotVector;
pub use mesh::{SurfaceMesh, curve_comb_3d, extrude_curve, pick_uv};
pub use surface::{BSplineSurface, SurfaceCurvature, SurfaceDerivs};
