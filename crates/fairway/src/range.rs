//! The numeric range Fairway computes in: input whose evaluation would
//! overflow or underflow `f64` is refused when it is read, with one message in
//! the user's terms, instead of giving NaN, infinities or zeros later (a
//! length of NaN, a deviation of 1 against a true 1e308, an SVG with
//! `height="inf"`).
//!
//! The limits, all far from any real model:
//! - every control point coordinate is at most [`MAX_COORDINATE`] (1e100) in
//!   magnitude, so squared distances (1e200) and cubed speeds stay finite;
//! - the control points' extent (the diagonal of their bounding box) is 0 (a
//!   point: degenerate, refused by the operations that need a shape) or at
//!   least [`MIN_EXTENT`] (1e-100);
//! - the derivatives' scale: with the extent `D`, the domain length `L` and
//!   the shortest non-empty knot span `h` of each knot vector, `D / h^k` is
//!   at most [`MAX_DERIVATIVE_SCALE`] (1e100) and `D / L^k` at least its
//!   inverse, for `k` = 1 to min(degree, 3) (the derivatives that curvature
//!   and its variation use): knots scaled by 1e300 (derivatives of 1e-300,
//!   whose squares underflow) or by 1e-300 (derivatives of 1e300, whose cubes
//!   overflow) are refused;
//! - weights of rational geometry are within [1e-100, 1e100].
//!
//! [`check_tolerance`] refuses a tolerance below the precision of the
//! coordinates: [`MIN_RELATIVE_TOLERANCE`] (1e-13, about 450 units in the last
//! place) times the largest coordinate magnitude.
//!
//! Numbers in these messages are printed short by [`short`].

use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::geometry::Geometry;
use crate::knots::KnotVector;
use crate::surface::BSplineSurface;
use glam::DVec3;

/// Largest magnitude of a control point coordinate.
pub const MAX_COORDINATE: f64 = 1e100;
/// Smallest non-zero extent (bounding-box diagonal) of the control points.
pub const MIN_EXTENT: f64 = 1e-100;
/// Largest scale of the derivatives (extent / span^k), and the inverse of the smallest.
pub const MAX_DERIVATIVE_SCALE: f64 = 1e100;
/// Smallest and largest weight of rational geometry.
pub const WEIGHT_RANGE: (f64, f64) = (1e-100, 1e100);
/// Smallest tolerance, relative to the largest coordinate magnitude.
pub const MIN_RELATIVE_TOLERANCE: f64 = 1e-13;

/// A number printed short for messages: the shortest exact form if it is short (`0.25`, `1e-7`,
/// `1200`), else 5 significant digits (`0.33333`, `1.2346e300`).
pub fn short(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let exact = format!("{x}");
    if exact.len() <= 8 {
        return exact;
    }
    let e = format!("{x:e}");
    if e.len() <= 8 {
        return e;
    }
    let a = x.abs();
    if (1e-3..1e6).contains(&a) {
        // 5 significant digits, trailing zeros dropped
        let decimals = (4 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{x:.decimals$}");
        let s = if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        };
        return s;
    }
    let s = format!("{x:.4e}");
    let (m, exp) = s.split_once('e').unwrap_or((&s, "0"));
    let m = if m.contains('.') {
        m.trim_end_matches('0').trim_end_matches('.')
    } else {
        m
    };
    format!("{m}e{exp}")
}

/// Refuse geometry outside the numeric range (see the module documentation).
pub fn check_geometry(g: &Geometry) -> Result<()> {
    match g {
        Geometry::Curve(c) => check_curve(c),
        Geometry::Surface(s) => check_surface(s),
    }
}

/// [`check_geometry`] for a curve.
pub fn check_curve(c: &BSplineCurve) -> Result<()> {
    let d = check_points(c.points(), "points", |i| format!("control point {i}"))?;
    check_weights(c.weights(), "weights")?;
    check_knots(c.knots(), c.degree(), d, "knots")
}

/// [`check_geometry`] for a surface.
pub fn check_surface(s: &BSplineSurface) -> Result<()> {
    let nv = s.nv();
    let d = check_points(s.points(), "points", |k| {
        format!("control point [{}][{}]", k / nv, k % nv)
    })?;
    check_weights(s.weights(), "weights")?;
    check_knots(s.knots_u(), s.degree_u(), d, "knots_u")?;
    check_knots(s.knots_v(), s.degree_v(), d, "knots_v")
}

/// The largest coordinate magnitude of the control points: the scale of their precision.
pub fn coordinate_size(g: &Geometry) -> f64 {
    let pts = match g {
        Geometry::Curve(c) => c.points(),
        Geometry::Surface(s) => s.points(),
    };
    pts.iter().map(|p| p.abs().max_element()).fold(0.0, f64::max)
}

/// Refuse a tolerance that is not a positive finite number, or that is below the precision of the
/// coordinates ([`MIN_RELATIVE_TOLERANCE`] × the largest coordinate magnitude). The same message for
/// curves and surfaces.
pub fn check_tolerance(tolerance: f64, g: &Geometry) -> Result<()> {
    check_tolerance_at(tolerance, coordinate_size(g))
}

/// [`check_tolerance`] for coordinates whose largest magnitude is `size` (what the fairing engines
/// call on their input).
pub fn check_tolerance_at(tolerance: f64, size: f64) -> Result<()> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(Error::InvalidInput(format!(
            "tolerance must be a positive finite number, got {}",
            short(tolerance)
        )));
    }
    let min = MIN_RELATIVE_TOLERANCE * size;
    if tolerance < min {
        return Err(Error::InvalidInput(format!(
            "tolerance {} is below the precision of the coordinates: they reach {} in magnitude, where a double \
             resolves about {}, so the smallest tolerance is {} ({} × {})",
            short(tolerance),
            short(size),
            short(size * f64::EPSILON),
            short(min),
            short(MIN_RELATIVE_TOLERANCE),
            short(size)
        )));
    }
    Ok(())
}

/// Check the coordinates and return the extent (bounding-box diagonal).
pub(crate) fn check_points(pts: &[DVec3], field: &str, name: impl Fn(usize) -> String) -> Result<f64> {
    for (i, p) in pts.iter().enumerate() {
        let m = p.abs().max_element();
        if !(m <= MAX_COORDINATE) {
            return Err(Error::InvalidInput(format!(
                "{field}: {} has a coordinate of {}, beyond the {} Fairway computes with (squared distances and \
                 curvatures would overflow): rescale the model",
                name(i),
                short(
                    p.to_array()
                        .into_iter()
                        .fold(0.0, |a: f64, x| if x.abs() > a.abs() { x } else { a })
                ),
                short(MAX_COORDINATE)
            )));
        }
    }
    let (lo, hi) = pts.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let d = if pts.is_empty() { 0.0 } else { (hi - lo).length() };
    if d > 0.0 && d < MIN_EXTENT {
        return Err(Error::InvalidInput(format!(
            "{field}: the control points span only {}, below the {} Fairway computes with (squared distances would \
             underflow to 0): rescale the model",
            short(d),
            short(MIN_EXTENT)
        )));
    }
    Ok(d)
}

fn check_weights(w: Option<&[f64]>, field: &str) -> Result<()> {
    let Some(w) = w else { return Ok(()) };
    if let Some((i, &x)) = w
        .iter()
        .enumerate()
        .find(|(_, x)| !(WEIGHT_RANGE.0..=WEIGHT_RANGE.1).contains(*x))
    {
        return Err(Error::InvalidInput(format!(
            "{field}: weight {} at index {i} is outside [{}, {}], the range Fairway computes with",
            short(x),
            short(WEIGHT_RANGE.0),
            short(WEIGHT_RANGE.1)
        )));
    }
    Ok(())
}

/// Check the derivatives' scale of one knot vector against the control points' extent `d`.
fn check_knots(k: &KnotVector, degree: usize, d: f64, field: &str) -> Result<()> {
    if d == 0.0 {
        return Ok(());
    }
    let (a, b) = k.domain();
    let len = b - a;
    let bp = k.breakpoints();
    let (h, at) = bp
        .windows(2)
        .map(|w| (w[1] - w[0], w[0]))
        .filter(|(h, _)| *h > 0.0)
        .fold((f64::INFINITY, a), |m, x| if x.0 < m.0 { x } else { m });
    let max_log = MAX_DERIVATIVE_SCALE.log10();
    let (ld, lh, ll) = (d.log10(), h.log10(), len.log10());
    for order in 1..=degree.clamp(1, 3) {
        let kf = order as f64;
        let which = match order {
            1 => "first derivatives (speeds)",
            2 => "second derivatives",
            _ => "third derivatives",
        };
        // the smallest scale: over the whole domain
        let low = ld - kf * ll;
        if !(low >= -max_log) {
            return Err(Error::InvalidInput(format!(
                "{field}: the domain [{}, {}] is too long for control points spanning {}: {which} of about 1e{:.0} \
                 would underflow (Fairway computes with derivatives between 1e-{max_log:.0} and 1e{max_log:.0}): \
                 rescale the knots, e.g. to [0, 1]",
                short(a),
                short(b),
                short(d),
                low
            )));
        }
        // the largest: over the shortest knot span
        let high = ld - kf * lh;
        if !(high <= max_log) {
            return Err(Error::InvalidInput(format!(
                "{field}: the knot span [{}, {}] (length {}) is too short for control points spanning {}: {which} of \
                 about 1e{:.0} would overflow (Fairway computes with derivatives between 1e-{max_log:.0} and \
                 1e{max_log:.0}): rescale the knots, e.g. to [0, 1], or remove the near-duplicate knot",
                short(at),
                short(at + h),
                short(h),
                short(d),
                high
            )));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_numbers() {
        assert_eq!(short(0.0), "0");
        assert_eq!(short(0.25), "0.25");
        assert_eq!(short(1e-7), "1e-7");
        assert_eq!(short(1e308), "1e308");
        assert_eq!(short(1.0 / 3.0), "0.33333");
        assert_eq!(short(2.0 / 3.0 * 1e300), "6.6667e299");
        assert_eq!(short(123456.789), "123457");
        assert_eq!(short(-1.5e-300), "-1.5e-300");
        assert_eq!(short(f64::NAN), "NaN");
    }

    fn line(knots: Vec<f64>, x: f64) -> BSplineCurve {
        BSplineCurve::new_2d(
            3,
            knots,
            &[
                glam::DVec2::new(0.0, 0.0),
                glam::DVec2::new(x, 1.0),
                glam::DVec2::new(2.0, -1.0),
                glam::DVec2::new(3.0, 0.0),
            ],
        )
        .unwrap()
    }

    #[test]
    fn ordinary_curves_pass_and_extreme_ones_are_refused() {
        let k = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        check_curve(&line(k.clone(), 1.0)).unwrap();
        let e = check_curve(&line(k.clone(), 1e308)).unwrap_err().to_string();
        assert!(
            e.starts_with("points: control point 1 has a coordinate of 1e308"),
            "{e}"
        );
        let big: Vec<f64> = k.iter().map(|u| u * 1e300).collect();
        let e = check_curve(&line(big, 1.0)).unwrap_err().to_string();
        assert!(
            e.contains("the domain [0, 1e300] is too long") && e.contains("underflow"),
            "{e}"
        );
        let small: Vec<f64> = k.iter().map(|u| u * 1e-300).collect();
        let e = check_curve(&line(small, 1.0)).unwrap_err().to_string();
        assert!(e.contains("knot span [0, 1e-300]") && e.contains("overflow"), "{e}");
    }
}
