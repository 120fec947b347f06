//! The error type of the core library.

use thiserror::Error;

/// Everything that can go wrong in the core: invalid geometry, bad files,
/// impossible fairing requests. Each variant names the problem and, where it
/// applies, the field of the input that caused it.
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
}

/// Result alias of the core library.
pub type Result<T, E = Error> = std::result::Result<T, E>;
