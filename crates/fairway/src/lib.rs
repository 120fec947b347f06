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
//!
//! A curve, evaluated, faired inside a tolerance band and judged by the independent measures:
//!
//! ```
//! use fairway::{BSplineCurve, DVec2};
//! use fairway::fair::{FairingOptions, fair_curve};
//! use fairway::measure::measure;
//!
//! // a cubic through a wiggly row of control points, clamped uniform knots
//! let pts: Vec<DVec2> = (0..16)
//!     .map(|i| DVec2::new(i as f64, (0.3 * i as f64).sin() + 0.02 * ((i * 7 % 5) as f64 - 2.0)))
//!     .collect();
//! let mut knots = vec![0.0; 4];
//! knots.extend((1..13).map(|i| i as f64 / 13.0));
//! knots.extend([1.0; 4]);
//! let curve = BSplineCurve::new_2d(3, knots, &pts)?;
//!
//! // evaluation: point, derivatives, signed curvature (2D)
//! let p = curve.point(0.5);
//! let d = curve.derivs(0.5);
//! assert!((d.p - p).length() < 1e-12 && d.d1.length() > 0.0);
//! assert!(curve.curvature(0.5).is_finite());
//!
//! // the default fair: knots and degree kept, the band verified everywhere
//! let m = 0.02;
//! let r = fair_curve(&curve, FairingOptions::default().tolerance(m))?;
//! assert!(r.max_deviation <= m);
//!
//! // judged by measures the engine does not optimize: fewer curvature extrema, lower ∫(dκ/ds)² ds
//! let (before, after) = (measure(&curve, &curve), measure(&curve, &r.curve));
//! assert!(after.dev_max <= m);
//! assert!(after.n_curv_extrema <= before.n_curv_extrema && after.E_var < before.E_var);
//! # Ok::<(), fairway::Error>(())
//! ```
#![deny(missing_docs)]

// the crate by its own name, for code shared with the benches (`fair/curve/polish_tests.rs`)
#[cfg(test)]
extern crate self as fairway;

pub mod arclength;
pub mod basis;
pub mod cancel;
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
pub mod network;
pub mod quadrature;
pub mod range;
pub mod suggest;
pub mod surface;
pub mod trim;

pub use arclength::ArcLengthTable;
pub use cancel::Cancel;
pub use closest::{ClosestPoint, CurveProjector};
pub use curve::{BSplineCurve, CurveDerivs};
pub use error::{Error, Result};
pub use geometry::Geometry;
pub use glam::{DVec2, DVec3};
pub use knots::KnotVector;
pub use mesh::{SurfaceMesh, curve_comb_3d, extrude_curve, pick_uv};
pub use surface::{BSplineSurface, SurfaceCurvature, SurfaceDerivs};
pub use trim::{FaceTrim, TrimLoop};
