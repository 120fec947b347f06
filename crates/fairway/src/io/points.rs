//! Point import: a CSV or whitespace-separated list of 2D or 3D points
//! (one per line; `#` starts a comment; a header line is tolerated) fitted
//! by a B-spline with a chosen number of control points and degree.
//!
//! The fit (The NURBS Book §9.4.1):
//! 1. parameters ū_k by chord length, `ū_k − ū_{k−1} ∝ |Q_k − Q_{k−1}|`, or
//!    centripetal, `∝ |Q_k − Q_{k−1}|^{1/2}` (Lee 1989), normalised to [0, 1];
//! 2. knots by averaging: for approximation (m + 1 points, n + 1 control
//!    points, m > n) eq. 9.69, `d = (m+1)/(n−p+1)`, `u_{p+j} = (1−α) ū_{i−1}
//!    + α ū_i` with `i = ⌊j d⌋, α = j d − i`, which puts at least one
//!    parameter in every knot span so the normal equations are positive
//!    definite; for interpolation (m = n) eq. 9.8, `u_{j+p} = (1/p) Σ ū_i`;
//! 3. least squares by [`crate::fit::fit_curve_points`] with the first and
//!    last control points fixed at the first and last data points (the ends
//!    are interpolated).
//!
//! Consecutive duplicate points (closer than 1e−12 of the data's size) are
//! dropped before the fit; they would give zero-length parameter steps.

use glam::DVec3;

use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::fit::{Smoothing, fit_curve_points};
use crate::knots::{KnotVector, MAX_DEGREE};

fn perr(message: impl Into<String>) -> Error {
    Error::Parse {
        format: "CSV".into(),
        message: message.into(),
    }
}

/// Points read from a text file.
#[derive(Debug, Clone, PartialEq)]
pub struct PointSet {
    /// The points (z = 0 for 2D).
    pub points: Vec<DVec3>,
    /// 2 or 3.
    pub dim: usize,
    /// The header line skipped, if there was one.
    pub header: Option<String>,
}

/// How parameters are assigned to the data points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Parametrization {
    /// Proportional to the chord lengths (The NURBS Book eq. 9.5).
    #[default]
    ChordLength,
    /// Proportional to the square roots of the chord lengths (eq. 9.6, Lee's centripetal).
    Centripetal,
}

impl std::str::FromStr for Parametrization {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "chord" | "chord-length" | "chordlength" => Ok(Self::ChordLength),
            "centripetal" => Ok(Self::Centripetal),
            _ => Err(Error::InvalidInput(format!(
                "parametrization {s:?}: expected \"chord\" or \"centripetal\""
            ))),
        }
    }
}

/// Options of [`fit_points`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// Number of control points; `None` = half the points, at least
    /// degree + 1 and at most 40.
    pub control_points: Option<usize>,
    /// Degree (default 3).
    pub degree: usize,
    /// Parametrisation (default chord length).
    pub param: Parametrization,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            control_points: None,
            degree: 3,
            param: Parametrization::ChordLength,
        }
    }
}

/// Parse a point list: numbers separated by commas, semicolons, spaces or
/// tabs, two or three per line, `#` comments, blank lines ignored, and the
/// first data line skipped if it is not numeric (a header).
pub fn parse(text: &str) -> Result<PointSet> {
    let mut points = Vec::new();
    let mut dim = 0;
    let mut header = None;
    let mut seen_data = false;
    for (ln, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let nums: Vec<Option<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        if nums.iter().any(Option::is_none) {
            if !seen_data && header.is_none() {
                header = Some(line.to_string());
                continue;
            }
            let bad = fields
                .iter()
                .zip(&nums)
                .find(|(_, n)| n.is_none())
                .map_or("", |(f, _)| *f);
            return Err(perr(format!("line {}: {bad:?} is not a number", ln + 1)));
        }
        seen_data = true;
        let d = nums.len();
        if d != 2 && d != 3 {
            return Err(perr(format!(
                "line {}: {d} values; a point has 2 (x, y) or 3 (x, y, z)",
                ln + 1
            )));
        }
        if dim == 0 {
            dim = d;
        } else if d != dim {
            return Err(perr(format!(
                "line {}: {d} coordinates, but the first point has {dim} (mixed 2D and 3D points)",
                ln + 1
            )));
        }
        let v: Vec<f64> = nums.into_iter().flatten().collect();
        if let Some(k) = v.iter().position(|x| !x.is_finite()) {
            return Err(perr(format!(
                "line {}: coordinate {} is not a finite number ({})",
                ln + 1,
                k + 1,
                fields[k]
            )));
        }
        points.push(DVec3::new(v[0], v[1], if d == 3 { v[2] } else { 0.0 }));
    }
    if points.is_empty() {
        return Err(perr(if let Some(m) = super::blank_text_message(text.as_bytes()) {
            m.to_string()
        } else {
            "no points found (expected lines of 2 or 3 numbers)".to_string()
        }));
    }
    Ok(PointSet { points, dim, header })
}

/// Parameters ū_k in [0, 1] for distinct consecutive points.
pub fn parameters(points: &[DVec3], param: Parametrization) -> Vec<f64> {
    let mut u = Vec::with_capacity(points.len());
    u.push(0.0);
    let mut acc = 0.0;
    for w in points.windows(2) {
        let d = (w[1] - w[0]).length();
        acc += match param {
            Parametrization::ChordLength => d,
            Parametrization::Centripetal => d.sqrt(),
        };
        u.push(acc);
    }
    if acc > 0.0 {
        for x in &mut u {
            *x /= acc;
        }
    }
    if let Some(last) = u.last_mut() {
        *last = 1.0;
    }
    u
}

/// Knots by averaging for `n_ctrl` control points of degree `p` over the
/// parameters `ubar` (eq. 9.69 for approximation, 9.8 for interpolation).
pub fn averaging_knots(ubar: &[f64], n_ctrl: usize, p: usize) -> Vec<f64> {
    let m1 = ubar.len(); // m + 1
    let n = n_ctrl - 1;
    let mut k = vec![0.0; p + 1];
    if m1 == n_ctrl {
        for j in 1..=n - p {
            k.push(ubar[j..j + p].iter().sum::<f64>() / p as f64);
        }
    } else {
        let d = m1 as f64 / (n - p + 1) as f64;
        for j in 1..=n - p {
            let jd = j as f64 * d;
            let i = (jd.floor() as usize).clamp(1, m1 - 1);
            let a = jd - i as f64;
            k.push((1.0 - a) * ubar[i - 1] + a * ubar[i]);
        }
    }
    k.extend(std::iter::repeat_n(1.0, p + 1));
    k
}

/// Fit a B-spline to the points (see the module documentation).
pub fn fit_points(set: &PointSet, opts: &FitOptions) -> Result<BSplineCurve> {
    let p = opts.degree;
    if p == 0 || p > MAX_DEGREE {
        return Err(Error::BadDegree {
            field: "degree".into(),
            degree: p,
            max: MAX_DEGREE,
        });
    }
    if set.dim != 2 && set.dim != 3 {
        return Err(Error::InvalidInput(format!("point dimension {} (2 or 3)", set.dim)));
    }
    if let Some(i) = set.points.iter().position(|q| !q.is_finite()) {
        return Err(Error::NotFinite {
            field: "points".into(),
            index: i,
        });
    }
    crate::range::check_points(&set.points, "points", |i| format!("point {}", i + 1))?;
    let (lo, hi) = crate::curve::point_bounds(&set.points);
    let size = (hi - lo).length();
    if !(size > 0.0) || !size.is_finite() {
        return Err(Error::Degenerate(format!(
            "all {} points coincide (or their extent overflows): no curve can be fitted",
            set.points.len()
        )));
    }
    let eps = 1e-12 * size;
    let mut pts: Vec<DVec3> = Vec::with_capacity(set.points.len());
    for &q in &set.points {
        if pts.last().is_none_or(|l: &DVec3| (q - *l).length() > eps) {
            pts.push(q);
        }
    }
    let n_ctrl = opts
        .control_points
        .unwrap_or_else(|| (pts.len() / 2).clamp(p + 1, 40.max(p + 1)));
    if pts.len() < p + 1 {
        return Err(Error::TooFewPoints {
            field: format!("points ({} distinct of {} read)", pts.len(), set.points.len()),
            count: pts.len(),
            degree: p,
            needed: p + 1,
        });
    }
    if n_ctrl < p + 1 {
        return Err(Error::InvalidInput(format!(
            "{n_ctrl} control points: a curve of degree {p} needs at least {}",
            p + 1
        )));
    }
    if n_ctrl > pts.len() {
        return Err(Error::InvalidInput(format!(
            "{n_ctrl} control points but only {} distinct data points: use at most {} control points",
            pts.len(),
            pts.len()
        )));
    }
    let ubar = parameters(&pts, opts.param);
    let knots = KnotVector::try_new(averaging_knots(&ubar, n_ctrl, p), p, n_ctrl, "knots")?;
    let mut fixed = vec![None; n_ctrl];
    fixed[0] = pts.first().copied();
    fixed[n_ctrl - 1] = pts.last().copied();
    let ctrl = fit_curve_points(&knots, &ubar, &pts, None, Smoothing::NONE, &fixed)?;
    let ctrl = if set.dim == 2 {
        ctrl.into_iter().map(|q| DVec3::new(q.x, q.y, 0.0)).collect()
    } else {
        ctrl
    };
    let curve = BSplineCurve::try_new(p, knots.values().to_vec(), ctrl, None, set.dim)?;
    crate::range::check_curve(&curve)?;
    Ok(curve)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_csv_with_header_comments_and_separators() {
        let s = parse("# scanned section\nx, y\n0,0\n1 2 # trailing\n\n2;3\n3\t4.5e0\n").unwrap();
        assert_eq!(s.dim, 2);
        assert_eq!(s.header.as_deref(), Some("x, y"));
        assert_eq!(s.points.len(), 4);
        assert_eq!(s.points[3], DVec3::new(3.0, 4.5, 0.0));
        let s3 = parse("1 2 3\n4 5 6\n").unwrap();
        assert_eq!(s3.dim, 3);
    }

    #[test]
    fn parse_errors_are_clear() {
        for (text, want) in [
            ("", "empty"),
            ("# only a comment\n", "no points"),
            ("1 2\n3 4 5\n", "mixed"),
            ("1 2\nnan 4\n", "line 2: coordinate 1 is not a finite"),
            ("1 2\n3 inf\n", "not a finite"),
            ("1 2\n3 x\n", "line 2: \"x\" is not a number"),
            ("1 2 3 4\n", "4 values"),
        ] {
            let e = parse(text).unwrap_err().to_string();
            assert!(e.contains(want), "{text:?}: {e}");
        }
    }

    #[test]
    fn cubic_data_is_reproduced_exactly() {
        // Points on a polynomial cubic curve: a cubic B-spline fit reproduces it
        // (the curve is in the spline space for any knots) — up to the
        // parametrisation, so use data whose chord parameters are the curve's own:
        // a straight line traversed uniformly.
        let pts: Vec<DVec3> = (0..30)
            .map(|k| DVec3::new(k as f64 * 0.5, 1.0 + k as f64 * 0.25, 0.0))
            .collect();
        let set = PointSet {
            points: pts.clone(),
            dim: 2,
            header: None,
        };
        let c = fit_points(
            &set,
            &FitOptions {
                control_points: Some(7),
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(c.n_points(), 7);
        assert_eq!(c.dim(), 2);
        let u = parameters(&pts, Parametrization::ChordLength);
        for (t, q) in u.iter().zip(&pts) {
            assert!((c.point(*t) - *q).length() < 1e-12);
        }
    }

    #[test]
    fn circle_fit_is_close_and_ends_interpolated() {
        let pts: Vec<DVec3> = (0..=100)
            .map(|k| {
                let a = k as f64 / 100.0 * 3.0;
                DVec3::new(a.cos(), a.sin(), 0.1 * a)
            })
            .collect();
        let mut with_dups = pts.clone();
        with_dups.insert(10, pts[9]);
        for param in [Parametrization::ChordLength, Parametrization::Centripetal] {
            let set = PointSet {
                points: with_dups.clone(),
                dim: 3,
                header: None,
            };
            let c = fit_points(
                &set,
                &FitOptions {
                    control_points: Some(12),
                    degree: 3,
                    param,
                },
            )
            .unwrap();
            assert_eq!(c.point(0.0), pts[0]);
            assert_eq!(c.point(1.0), pts[100]);
            let u = parameters(&pts, param);
            let err = u
                .iter()
                .zip(&pts)
                .map(|(t, q)| (c.point(*t) - *q).length())
                .fold(0.0, f64::max);
            assert!(err < 1e-4, "{param:?}: {err}");
        }
    }

    #[test]
    fn interpolation_when_as_many_control_points_as_points() {
        let pts: Vec<DVec3> = [(0.0, 0.0), (1.0, 2.0), (3.0, 3.0), (4.0, 0.0), (6.0, 1.0)]
            .iter()
            .map(|&(x, y)| DVec3::new(x, y, 0.0))
            .collect();
        let set = PointSet {
            points: pts.clone(),
            dim: 2,
            header: None,
        };
        let c = fit_points(
            &set,
            &FitOptions {
                control_points: Some(5),
                ..Default::default()
            },
        )
        .unwrap();
        let u = parameters(&pts, Parametrization::ChordLength);
        for (t, q) in u.iter().zip(&pts) {
            assert!((c.point(*t) - *q).length() < 1e-12);
        }
    }

    #[test]
    fn degenerate_inputs_are_rejected() {
        let set = |v: Vec<DVec3>| PointSet {
            points: v,
            dim: 2,
            header: None,
        };
        let same = set(vec![DVec3::new(1.0, 1.0, 0.0); 10]);
        assert!(matches!(
            fit_points(&same, &FitOptions::default()),
            Err(Error::Degenerate(_))
        ));
        let three = set(vec![DVec3::ZERO, DVec3::X, DVec3::Y]);
        assert!(matches!(
            fit_points(&three, &FitOptions::default()),
            Err(Error::TooFewPoints { needed: 4, .. })
        ));
        let ten = set((0..10).map(|k| DVec3::new(k as f64, 0.0, 0.0)).collect());
        let e = fit_points(
            &ten,
            &FitOptions {
                control_points: Some(11),
                ..Default::default()
            },
        )
        .unwrap_err();
        assert!(e.to_string().contains("at most 10"), "{e}");
    }
}
