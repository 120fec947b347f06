//! Fairing of B-spline curves: the fast, local method of Salvi & Várady,
//! *Fast and Local Fairing of B-Spline Curves and Surfaces* (§3), made to
//! hold a hard tolerance band, and the iterative baseline of its §2.2.
//!
//! * [`target`] — the target curvature g (smoothing, hand edits, pins);
//! * [`integrate`] — twofold integration of g from both ends, quintic blend,
//!   pull-back (Euler, RK2, exact arc steps);
//! * [`curve`] — [`FairingSetup`]: sampling, free control points of the
//!   region, the constrained fit with a fairness term, the band control;
//! * [`closed`] — closed curves faired across the seam (re-seaming, two passes);
//! * [`split`] — curves with corners: the stretches between corners faired one by one;
//! * [`iterative`] — the downhill-simplex baseline;
//! * [`verify`] — a sound bound of the band between the samples;
//! * [`surface`] — surfaces (paper §3.2): isocurves faired by the curve engine, combined, fitted.
//!
//! Typical use (the editor keeps the setup and re-runs `fair` while the
//! user edits the target or drags the tolerance slider):
//!
//! ```
//! # use fairway::{BSplineCurve, DVec2};
//! # use fairway::fair::{FairingOptions, FairingSetup};
//! let pts: Vec<DVec2> = (0..12).map(|i| DVec2::new(i as f64, ((i * 7) % 3) as f64 * 0.01)).collect();
//! let mut knots = vec![0.0; 4];
//! knots.extend((1..9).map(|i| i as f64 / 9.0));
//! knots.extend([1.0; 4]);
//! let curve = BSplineCurve::new_2d(3, knots, &pts).unwrap();
//! let mut setup = FairingSetup::new(&curve, FairingOptions::default().tolerance(0.01)).unwrap();
//! let first = setup.fair().unwrap();
//! assert!(first.max_deviation <= 0.01);
//! setup.target_mut().flatten_range(10, 40);
//! setup.set_tolerance(0.005).unwrap();
//! let second = setup.fair().unwrap();
//! assert!(second.max_deviation <= 0.005);
//! ```

pub mod closed;
pub mod curve;
pub mod curve_fairing;
pub mod integrate;
pub mod iterative;
pub mod network;
pub mod nurbs;
pub mod split;
pub mod surface;
pub mod target;
pub mod verify;

pub use closed::{fair_closed, fair_closed_iterative};
pub use curve::{
    EndCondition, FairingOptions, FairingResult, FairingSetup, FitMode, PolishMethod, Seam, TORSION_WEIGHT,
};
pub use curve_fairing::{CurveFair, CurveFairing, Pass, fair_curve};
pub use integrate::Integrator;
pub use iterative::{IterativeOptions, fair_iterative};
pub use split::{CornerFair, CornerSetups, Stretch, fair_between_corners};
pub use surface::{
    Combine, IsocurveCache, SurfaceFairingOptions, SurfaceFairingResult, SurfaceMethod, SurfacePick, SurfaceTimings,
    fair_surface, fair_surface_cached, fair_surface_with,
};
pub use target::{Target, TargetMethod};
pub use verify::{BandBound, band_bound};
