//! The error type of the core library.

use thiserror::Error;

/// Everything that can go wrong in the core: invalid geometry, bad files,
/// impossible fairing requests. Each variant names the problem and, where it
/// applies, the field of the input that caused it; its message says it in the user's terms.
///
/// Refusals are matched as variants:
///
/// ```
/// use fairway::{BSplineCurve, DVec2, Error};
/// use fairway::fair::{FairingOptions, fair_curve};
/// let pts: Vec<DVec2> = (0..10).map(|i| DVec2::new(i as f64, (i % 2) as f64)).collect();
/// let knots = [vec![0.0; 4], (1..7).map(|i| i as f64 / 7.0).collect(), vec![1.0; 4]].concat();
/// let c = BSplineCurve::new_2d(3, knots, &pts)?;
/// let narrow = FairingOptions::default().tolerance(0.01).region(Some((0.5, 0.5001)));
/// match fair_curve(&c, narrow) {
///     Err(Error::RegionTooSmall { u1, u2, .. }) => assert_eq!((u1, u2), (0.5, 0.5001)),
///     other => panic!("{other:?}"),
/// }
/// # Ok::<(), fairway::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum Error {
    /// The degree is outside `1..=MAX_DEGREE`.
    #[error("{field}: degree {degree} is not supported (1 to {max})")]
    BadDegree {
        /// The field that holds the degree (`degree`, `degree_u`, ...).
        field: String,
        /// The degree found.
        degree: usize,
        /// The largest supported degree.
        max: usize,
    },
    /// Fewer control points than degree + 1.
    #[error("{field}: {count} control points, a curve of degree {degree} needs at least {needed}")]
    TooFewPoints {
        /// The field that holds the points.
        field: String,
        /// How many points there are.
        count: usize,
        /// The degree.
        degree: usize,
        /// How many are needed.
        needed: usize,
    },
    /// The knot vector has the wrong length.
    #[error("{field}: {count} values, expected {expected} for {points} points of degree {degree}")]
    KnotCount {
        /// The field.
        field: String,
        /// How many knots there are.
        count: usize,
        /// How many are expected (points + degree + 1).
        expected: usize,
        /// How many control points.
        points: usize,
        /// The degree.
        degree: usize,
    },
    /// A knot is smaller than its predecessor.
    #[error("{field}: knots decrease at index {index} ({prev} > {next})")]
    KnotsDecreasing {
        /// The field.
        field: String,
        /// Index of the offending knot.
        index: usize,
        /// The previous value.
        prev: f64,
        /// The smaller value that follows.
        next: f64,
    },
    /// The knot vector is not clamped (first and last values repeated degree + 1 times).
    #[error("{field}: not clamped: the first and the last value must each appear {needed} times (degree + 1)")]
    KnotsNotClamped {
        /// The field.
        field: String,
        /// The needed multiplicity.
        needed: usize,
    },
    /// An interior knot has multiplicity larger than the degree.
    #[error("{field}: interior knot {value} has multiplicity {multiplicity}, at most {degree} (the degree) is allowed")]
    KnotMultiplicity {
        /// The field.
        field: String,
        /// The knot value.
        value: f64,
        /// Its multiplicity.
        multiplicity: usize,
        /// The degree.
        degree: usize,
    },
    /// The parameter domain has zero length.
    #[error("{field}: the parameter domain [{start}, {end}] is empty")]
    EmptyDomain {
        /// The field.
        field: String,
        /// Domain start.
        start: f64,
        /// Domain end.
        end: f64,
    },
    /// A NaN or infinite number.
    #[error("{field}: value at index {index} is not a finite number")]
    NotFinite {
        /// The field.
        field: String,
        /// The flat index of the value.
        index: usize,
    },
    /// A weight is zero or negative.
    #[error("{field}: weight {value} at index {index} must be positive")]
    BadWeight {
        /// The field.
        field: String,
        /// Index of the weight.
        index: usize,
        /// The value.
        value: f64,
    },
    /// Two arrays that must agree in length do not.
    #[error("{field}: {count} values, expected {expected}")]
    LengthMismatch {
        /// The field.
        field: String,
        /// Found.
        count: usize,
        /// Expected.
        expected: usize,
    },
    /// Points of a wrong or mixed dimension.
    #[error("{field}: point {index} has {found} coordinates, expected {expected}")]
    BadDimension {
        /// The field.
        field: String,
        /// The point index.
        index: usize,
        /// Coordinates found.
        found: usize,
        /// Coordinates expected (2 or 3).
        expected: usize,
    },
    /// A file could not be parsed, or has the wrong shape.
    #[error("{format}: {message}")]
    Parse {
        /// The format (`JSON`, `RON`, `IGES`, `CSV`).
        format: String,
        /// What is wrong, with the location if known.
        message: String,
    },
    /// A file could not be read or written.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// The operating system's message.
        message: String,
    },
    /// A parameter outside the domain of the geometry.
    #[error("{what}: {value} is outside the domain [{start}, {end}]")]
    OutOfDomain {
        /// What the parameter is.
        what: String,
        /// The value.
        value: f64,
        /// Domain start.
        start: f64,
        /// Domain end.
        end: f64,
    },
    /// The geometry is degenerate for the requested operation.
    #[error("degenerate geometry: {0}")]
    Degenerate(String),
    /// A request that cannot be carried out as asked (bad tolerance, empty region, ...).
    #[error("{0}")]
    InvalidInput(String),
    /// A tolerance (the band's half width) that is not a positive finite number.
    #[error("tolerance must be a positive finite number, got {value}")]
    BadTolerance {
        /// The value given.
        value: f64,
    },
    /// Fairing works on curvature: the curve must be of degree 2 or more.
    #[error("fairing needs a curve of degree ≥ 2 (curvature), got degree {degree}")]
    DegreeTooLowToFair {
        /// The curve's degree.
        degree: usize,
    },
    /// A region whose ends are not finite numbers.
    #[error("region [{u1}, {u2}] is not finite")]
    RegionNotFinite {
        /// Region start.
        u1: f64,
        /// Region end.
        u2: f64,
    },
    /// A region of an open curve with `u2 <= u1`.
    #[error("region [{u1}, {u2}] is empty (u1 must be < u2)")]
    EmptyRegion {
        /// Region start.
        u1: f64,
        /// Region end.
        u2: f64,
    },
    /// A region too small to move any control point.
    #[error("region [{u1}, {u2}] is too small: {reason}")]
    RegionTooSmall {
        /// Region start.
        u1: f64,
        /// Region end.
        u2: f64,
        /// Why, in the user's terms, and what to do.
        reason: String,
    },
    /// A region whose moving stretch crosses corners of the curve (fairing would round them off).
    #[error("region [{u1}, {u2}] crosses {description}")]
    RegionCrossesCorner {
        /// Region start.
        u1: f64,
        /// Region end.
        u2: f64,
        /// The corners' knots.
        corners: Vec<f64>,
        /// The stretches between corners to fair instead.
        stretches: Vec<(f64, f64)>,
        /// The corners, why they stay and what to do, for the message.
        description: String,
    },
    /// A whole-curve fair of a curve with too few control points for its end conditions.
    #[error(
        "the curve has only {points} control points: with {ends} ends the first and last {held} are held, so \
         fairing needs at least {needed} (insert knots to refine the curve)"
    )]
    TooFewControlPoints {
        /// Control points of the curve.
        points: usize,
        /// The end condition (`G0`, `G1`, `G2`).
        ends: String,
        /// Points held at each end.
        held: usize,
        /// Points needed.
        needed: usize,
    },
    /// More fairing samples than memory allows.
    #[error(
        "{samples} samples are too many: at most {max} (each million takes about 0.4 GB of memory); ask for \
         fewer samples, or fair a region of the curve"
    )]
    TooManySamples {
        /// Samples asked for.
        samples: usize,
        /// The limit.
        max: usize,
    },
    /// Fewer fairing samples than free control points (the fit would be underdetermined).
    #[error("{samples} samples are too few for {free} free control points (need more than {free})")]
    TooFewSamples {
        /// Samples asked for.
        samples: usize,
        /// Free control points.
        free: usize,
    },
    /// A pass-based target smoothing whose cost (strength × samples) is beyond the limit.
    #[error(
        "target strength {strength} is too much work for the {target} target: its passes cost strength × \
         samples, and {samples} samples allow at most {max_passes} passes; use the heat target (the implicit \
         heat flow of the averaging), whose cost stays bounded at any strength"
    )]
    TargetTooStrong {
        /// The strength (passes) asked for.
        strength: usize,
        /// The target method's name.
        target: String,
        /// Samples of the target.
        samples: usize,
        /// The most passes allowed at this sample count.
        max_passes: usize,
    },
    /// A region across the seam of a closed curve that could not be faired.
    #[error(
        "region [{u1}, {u2}] across the seam (the stretch [{u1}, {end}] then [{start}, {u2}], fairing region \
         [{u1}, {reseamed_end}] of the re-seamed curve): {source}"
    )]
    AcrossSeam {
        /// Region start (before the seam).
        u1: f64,
        /// Region end (past the seam).
        u2: f64,
        /// The domain's start.
        start: f64,
        /// The domain's end.
        end: f64,
        /// The region's end on the re-seamed curve.
        reseamed_end: f64,
        /// Why the re-seamed region could not be faired.
        source: Box<Error>,
    },
    /// A tolerance that cannot be met.
    #[error("tolerance {tolerance} cannot be met: {reason}")]
    ToleranceNotMet {
        /// The requested tolerance.
        tolerance: f64,
        /// Why (best deviation reached, ...).
        reason: String,
    },
    /// A linear system could not be solved.
    #[error("linear solve failed: {0}")]
    Solve(String),
    /// Knot removal (The NURBS Book A5.8) would change the curve by more than the tolerance:
    /// the curve is not smooth enough at that knot (a kink, or a derivative jump).
    #[error(
        "knot {value} cannot be removed {requested} time(s) within {tolerance}: only {removed} removal(s) keep \
         the curve (it is not smooth enough there)"
    )]
    KnotNotRemovable {
        /// The knot.
        value: f64,
        /// Removals asked for.
        requested: usize,
        /// Removals that stayed within the tolerance.
        removed: usize,
        /// The tolerance (a distance).
        tolerance: f64,
    },
    /// The caller set the fair's [`Cancel`](crate::Cancel) token: the fair stopped at a checkpoint and
    /// returns no result (not a partial one).
    #[error("cancelled before the fair finished (nothing was changed)")]
    Cancelled,
}

/// Result alias of the core library.
pub type Result<T, E = Error> = std::result::Result<T, E>;
