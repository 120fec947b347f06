//! Corners of a curve: interior knots where the direction of travel jumps.
//!
//! A B-spline curve can only break its tangent at a knot: at a knot of multiplicity p (the curve is
//! C0 there, a designer's kink), or where it stops (zero speed: p coincident control points of a
//! degree-p curve, or fewer next to a multiple knot). Fairing across such a point cannot keep it
//! inside the band except by rounding it off with a radius of about 8m/θ² (θ the break, m the
//! tolerance): a curvature spike of θ²/(8m), e.g. 37 for a 54° break at m = 3e-3, where the
//! curvature comb had none. A stop is worse still: the curvature is unbounded next to it (it grows
//! like 1/t at a distance t in parameter), and the fit's basis functions there cover almost no arc
//! length, so a fair across a stop that turns by 40° can put a loop of size 1e-4 with curvature 3400
//! into it (test `degenerate.rs`). The fairing engine therefore keeps corners: the
//! setup refuses a moving stretch across one, and [`crate::fair::fair_curve`] fairs the stretches
//! between corners one by one, each a region of its own ([`crate::fair::split`]).

use crate::curve::BSplineCurve;
use glam::DVec3;

/// The smallest tangent break that makes a knot a corner: 1°, the usual angle tolerance of CAD
/// systems (below it a join counts as tangent-continuous). A smaller break is faired through: the
/// band rounds it off with a radius of about 8m/θ² (26 000 m at 1°), which the target's smoothing
/// cannot tell from the rest of the curve.
pub const CORNER_ANGLE_DEG: f64 = 1.0;

/// A corner at an interior knot ([`corners`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Corner {
    /// The knot.
    pub u: f64,
    /// Angle between the directions of travel arriving at and leaving the knot, in degrees (0 to
    /// 180; 180 is a cusp that turns straight back). 0 for a stop whose direction is undefined.
    pub angle_deg: f64,
    /// The curve stops at the knot (zero speed on at least one side, relative to the control net's
    /// size): its curvature is unbounded next to it.
    pub stops: bool,
}

impl Corner {
    /// What the corner is, for messages: `at u = 0.5 (tangent break 54.2°)`, or `at u = 0.5 (the
    /// curve stops there: coincident control points; it turns by 4.6°)`.
    pub fn describe(&self) -> String {
        if self.stops {
            format!(
                "at u = {} (the curve stops there: coincident control points; it turns by {:.1}°)",
                self.u, self.angle_deg
            )
        } else {
            format!("at u = {} (tangent break {:.1}°)", self.u, self.angle_deg)
        }
    }
}

/// "a corner" or "N corners", for messages about `found`.
pub fn counted(found: &[Corner]) -> String {
    if found.len() == 1 {
        "a corner".to_string()
    } else {
        format!("{} corners", found.len())
    }
}

/// The corners of `curve` strictly inside `(u1, u2)`: interior knots where the directions of travel
/// arriving and leaving differ by more than [`CORNER_ANGLE_DEG`], or where the curve stops. The
/// directions are the first one-sided derivative that is not zero (relative to the control net's
/// size): c′, else the second derivative (a stop: arriving along −c″ of the span before, leaving
/// along c″ of the span after), else the third. Sorted by `u`.
pub fn corners(curve: &BSplineCurve, u1: f64, u2: f64) -> Vec<Corner> {
    let p = curve.degree();
    let kv = curve.knots().values();
    let (lo, hi) = curve.control_bounds();
    let size = (hi - lo).length();
    let mut out = vec![];
    if size == 0.0 || p < 1 {
        return out;
    }
    let (d0, d1) = curve.domain();
    for &c in curve.knots().breakpoints().iter() {
        if c <= u1 || c >= u2 || c <= d0 || c >= d1 {
            continue;
        }
        // the non-empty spans that end and start at c
        let left = kv.partition_point(|&k| k < c) - 1;
        let right = kv.partition_point(|&k| k <= c) - 1;
        let (wl, wr) = (c - kv[left], kv[right + 1] - c);
        // below multiplicity p the curve is C1 at c: c′ is continuous, so only a stop can be a corner
        if right - left < p && (curve.d1(c) * wr).length() > 1e-9 * size {
            continue;
        }
        if let Some(corner) = turn(curve, (left, c, wl), (right, c, wr), c, size) {
            out.push(corner);
        }
    }
    out
}

/// The corner at the seam of a closed curve (first point = last point): the direction it arrives by at
/// its end `b` against the one it leaves by at its start `a` (as [`corners`] compares the two sides of a
/// knot), reported at `u = a`; `None` if the curve is smooth there to [`CORNER_ANGLE_DEG`] (or stops
/// at an end: an end is never a stop here).
pub fn seam_corner(curve: &BSplineCurve) -> Option<Corner> {
    let (lo, hi) = curve.control_bounds();
    let size = (hi - lo).length();
    let kv = curve.knots().values();
    let p = curve.degree();
    let (a, b) = curve.domain();
    if size == 0.0 || p < 1 {
        return None;
    }
    // the last and the first non-empty span
    let last = kv.partition_point(|&k| k < b) - 1;
    let first = kv.partition_point(|&k| k <= a) - 1;
    let c = turn(curve, (last, b, b - kv[last]), (first, a, kv[first + 1] - a), a, size)?;
    (!c.stops).then_some(c)
}

/// The corner at `u` between the span `left = (span, u_end, width)` that the curve arrives by and the
/// span `right = (span, u_start, width)` it leaves by, if the turn is one ([`corners`]).
fn turn(curve: &BSplineCurve, left: (usize, f64, f64), right: (usize, f64, f64), u: f64, size: f64) -> Option<Corner> {
    let dl = curve.derivs_in_span(left.0, left.1);
    let dr = curve.derivs_in_span(right.0, right.1);
    // d^k c / du^k scaled by w^k: the displacement over the span it predicts, comparable to `size`
    let lead = |ds: [DVec3; 3], w: f64| -> Option<(usize, DVec3)> {
        let mut s = 1.0;
        for (k, d) in ds.into_iter().enumerate() {
            s *= w;
            if (d * s).length() > 1e-9 * size {
                return Some((k + 1, d));
            }
        }
        None
    };
    let arriving = lead([dl.d1, dl.d2, dl.d3], left.2).map(|(k, d)| (k, if k % 2 == 0 { -d } else { d }));
    let leaving = lead([dr.d1, dr.d2, dr.d3], right.2);
    let stops = arriving.is_none_or(|(k, _)| k > 1) || leaving.is_none_or(|(k, _)| k > 1);
    let angle_deg = match (arriving, leaving) {
        (Some((_, a)), Some((_, b))) => a.cross(b).length().atan2(a.dot(b)).to_degrees(),
        _ => 0.0,
    };
    (stops || angle_deg > CORNER_ANGLE_DEG).then_some(Corner { u, angle_deg, stops })
}

/// The stretches of `[u1, u2]` between the corners `found` (sorted, strictly inside, as [`corners`]
/// gives them), to be faired one by one: each ends at a corner, or next to a stop at the knot before
/// (after) it, since a stretch cannot end where the curve stops (no curvature there: the span next to
/// a stop stays as it is). Empty stretches are dropped.
pub fn stretches_between(curve: &BSplineCurve, u1: f64, u2: f64, found: &[Corner]) -> Vec<(f64, f64)> {
    let bp = curve.knots().breakpoints();
    let mut out = vec![];
    let mut a = u1;
    for c in found {
        let (end, next) = if c.stops {
            let before = bp.iter().rev().find(|&&b| b < c.u).copied().unwrap_or(c.u);
            let after = bp.iter().find(|&&b| b > c.u).copied().unwrap_or(c.u);
            (before, after)
        } else {
            (c.u, c.u)
        };
        if end > a {
            out.push((a, end));
        }
        a = a.max(next);
    }
    if u2 > a {
        out.push((a, u2));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    fn tent(knots: Vec<f64>, n: usize) -> BSplineCurve {
        let pts: Vec<DVec2> = (0..n)
            .map(|i| {
                let t = i as f64 / (n - 1) as f64;
                DVec2::new(4.0 * t, 1.0 - (2.0 * t - 1.0).abs())
            })
            .collect();
        BSplineCurve::new_2d(3, knots, &pts).unwrap()
    }

    #[test]
    fn a_triple_knot_between_two_lines_is_a_corner_of_their_angle() {
        // control points on two lines of slope ±1/2 meeting at (2, 1), the middle one at a triple knot
        let k = vec![0., 0., 0., 0., 0.25, 0.5, 0.5, 0.5, 0.75, 1., 1., 1., 1.];
        let c = tent(k, 9);
        let found = corners(&c, 0.0, 1.0);
        let want = 2.0 * 0.5f64.atan().to_degrees();
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].u, 0.5);
        assert!(!found[0].stops);
        assert!(
            (found[0].angle_deg - want).abs() < 1e-9,
            "{} vs {want}",
            found[0].angle_deg
        );
        // outside (u1, u2), or at its ends: not reported
        assert!(corners(&c, 0.0, 0.5).is_empty() && corners(&c, 0.5, 1.0).is_empty());
        // a kink: the stretches end at it
        assert_eq!(stretches_between(&c, 0.1, 0.9, &found), vec![(0.1, 0.5), (0.5, 0.9)]);
    }

    #[test]
    fn smooth_curves_and_small_breaks_have_no_corners() {
        // uniform cubic: C2 everywhere
        let c = tent(crate::KnotVector::uniform(3, 9).unwrap().values().to_vec(), 9);
        assert!(corners(&c, 0.0, 1.0).is_empty());
        // a triple knot whose two sides meet at 0.5°: below the threshold
        let s = (0.25f64).to_radians().tan();
        let pts: Vec<DVec2> = (0..9)
            .map(|i| DVec2::new(i as f64, s * (i as f64 - 4.0).abs()))
            .collect();
        let k = vec![0., 0., 0., 0., 0.25, 0.5, 0.5, 0.5, 0.75, 1., 1., 1., 1.];
        let c = BSplineCurve::new_2d(3, k, &pts).unwrap();
        assert!(corners(&c, 0.0, 1.0).is_empty());
    }

    #[test]
    fn coincident_control_points_make_a_stop_with_the_turn_of_the_polygon() {
        // three coincident points of a cubic at simple knots: c' = 0 at the knot between them; the
        // curve arrives along the polygon leg before the triple point and leaves along the leg after
        let mut pts: Vec<DVec2> = (0..10).map(|i| DVec2::new(i as f64, 0.0)).collect();
        for q in pts.iter_mut().skip(7) {
            q.y = q.x - 6.0;
        }
        pts[4] = pts[5];
        pts[6] = pts[5];
        let c = BSplineCurve::new_2d(3, crate::KnotVector::uniform(3, 10).unwrap().values().to_vec(), &pts).unwrap();
        let found = corners(&c, 0.0, 1.0);
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(found[0].stops);
        assert!((found[0].u - 4.0 / 7.0).abs() < 1e-15);
        assert!(c.derivs(found[0].u).d1.length() < 1e-12);
        // next to the triple point P the curve is P + (P3 − P) N3(u), then P + (P7 − P) N7(u): it arrives
        // along P − P3 = (2, 0) and leaves along P7 − P = (2, 1)
        let want = 0.5f64.atan().to_degrees();
        assert!(
            (found[0].angle_deg - want).abs() < 1e-6,
            "{} vs {want}",
            found[0].angle_deg
        );
        // the stretches to fair leave out the span on each side of the stop
        let st = stretches_between(&c, 0.0, 1.0, &found);
        assert_eq!(st, vec![(0.0, 3.0 / 7.0), (5.0 / 7.0, 1.0)]);
    }
}
