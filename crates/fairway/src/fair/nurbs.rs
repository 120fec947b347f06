//! Rational (NURBS) curves: faired through a non-rational B-spline close to them.
//!
//! The engine works on polynomial B-splines (its rows, the band bound and the fit are linear in the
//! control points). A rational curve with unequal weights — a circle or conic from Alias or CATIA — is
//! first approximated, in its own parameter, by a non-rational B-spline of degree max(p, 3) on its own
//! breakpoints (interior multiplicities raised with the degree, so the continuity class is kept), refined
//! by halving every span where the approximation is not yet within [`APPROX_FRACTION`] of the band. The
//! approximation error is bounded per span from 64 samples plus the interpolation margin `h²/8 · max|e''|`
//! (doubled), the fair then runs on the approximation with the band narrowed by that bound, and the
//! reported deviation adds it back: what is reported bounds the distance from the rational original.

use glam::DVec3;

use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::fit::{Smoothing, fit_curve_points};
use crate::knots::KnotVector;

/// The share of the tolerance the non-rational approximation of a rational curve may use.
pub const APPROX_FRACTION: f64 = 0.1;

/// Rounds of span halving before the approximation gives up.
const MAX_ROUNDS: usize = 14;

/// Samples per span of the fit and of the error check.
const FIT_SAMPLES: usize = 16;
const CHECK_SAMPLES: usize = 64;

/// A non-rational stand-in for a rational curve.
#[derive(Debug, Clone)]
pub struct PolynomialApprox {
    /// The approximation: degree max(p, 3), the rational curve's domain and breakpoints (and more).
    pub curve: BSplineCurve,
    /// An upper bound of `|approx(u) − original(u)|` over the domain (in the parameter, so also of the
    /// distance from each original point to the approximation).
    pub error: f64,
}

/// A non-rational B-spline within `tol` of the rational `curve` in its own parameter, ends interpolated.
pub fn polynomial_approximation(curve: &BSplineCurve, tol: f64) -> Result<PolynomialApprox> {
    if !(tol > 0.0 && tol.is_finite()) {
        return Err(Error::InvalidInput(format!(
            "the approximation of a rational curve needs a positive tolerance, got {}",
            crate::range::short(tol)
        )));
    }
    let p = curve.degree();
    let q = p.max(3);
    let kv = curve.knots();
    let bps = kv.breakpoints();
    let (a, b) = curve.domain();
    // the rational curve's breakpoints, their interior multiplicities raised with the degree
    let mut interior: Vec<(f64, usize)> = bps[1..bps.len() - 1]
        .iter()
        .map(|&u| (u, (kv.multiplicity(u) + q - p).min(q)))
        .collect();
    for _ in 0..MAX_ROUNDS {
        let mut knots = vec![a; q + 1];
        for &(u, m) in &interior {
            knots.extend(std::iter::repeat_n(u, m));
        }
        knots.extend(std::iter::repeat_n(b, q + 1));
        let n_pts = knots.len() - q - 1;
        let kvq = KnotVector::try_new(knots.clone(), q, n_pts, "knots")?;
        let n = kvq.n_points();
        let spans: Vec<(f64, f64)> = kvq.breakpoints().windows(2).map(|w| (w[0], w[1])).collect();
        let mut params = Vec::with_capacity(spans.len() * FIT_SAMPLES);
        for &(s0, s1) in &spans {
            for k in 0..FIT_SAMPLES {
                params.push(s0 + (s1 - s0) * (k as f64 + 0.5) / FIT_SAMPLES as f64);
            }
        }
        let targets: Vec<DVec3> = params.iter().map(|&u| curve.point(u)).collect();
        let mut fixed = vec![None; n];
        fixed[0] = Some(curve.point(a));
        fixed[n - 1] = Some(curve.point(b));
        let pts = fit_curve_points(&kvq, &params, &targets, None, Smoothing::NONE, &fixed)?;
        let approx = BSplineCurve::try_new(q, knots, pts, None, curve.dim())?;
        // the error per span: the sampled maximum and the interpolation margin between samples
        let mut worst = 0.0f64;
        let mut split = vec![];
        for &(s0, s1) in &spans {
            let h = (s1 - s0) / CHECK_SAMPLES as f64;
            let mid = 0.5 * (s0 + s1);
            let (sa, sr) = (approx.knots().find_span(mid), curve.knots().find_span(mid));
            let (mut e0, mut e2) = (0.0f64, 0.0f64);
            for k in 0..=CHECK_SAMPLES {
                let u = s0 + h * k as f64;
                let (da, dr) = (approx.derivs_in_span(sa, u), curve.derivs_in_span(sr, u));
                e0 = e0.max((da.p - dr.p).length());
                e2 = e2.max((da.d2 - dr.d2).length());
            }
            let bound = e0 + 2.0 * h * h / 8.0 * e2;
            worst = worst.max(bound);
            if bound > tol {
                split.push(0.5 * (s0 + s1));
            }
        }
        if !worst.is_finite() {
            break;
        }
        if split.is_empty() {
            return Ok(PolynomialApprox {
                curve: approx,
                error: worst,
            });
        }
        interior.extend(split.into_iter().map(|u| (u, 1)));
        interior.sort_by(|x, y| x.0.total_cmp(&y.0));
    }
    Err(Error::InvalidInput(format!(
        "rational curve (unequal weights): no non-rational B-spline within {} of it was found after {MAX_ROUNDS} \
         rounds of refinement; loosen the tolerance or convert it in the CAD system",
        crate::range::short(tol)
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rational quadratic quarter circle (weights 1, 1/√2, 1): the approximation stays within the asked
    /// tolerance of the exact circle (checked densely by the closed form |c| = 1), the bound is at least
    /// what the dense check finds, the ends are exact, and a tighter tolerance takes more control points.
    #[test]
    fn a_rational_circle_is_approximated_within_the_bound() {
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let c = BSplineCurve::try_new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(0.0, 1.0, 0.0),
            ],
            Some(vec![1.0, w, 1.0]),
            2,
        )
        .unwrap();
        let mut last_n = 0;
        for tol in [1e-3, 1e-5, 1e-7] {
            let a = polynomial_approximation(&c, tol).unwrap();
            assert!(!a.curve.is_rational() && a.curve.degree() == 3);
            assert!(a.error <= tol, "{} > {tol}", a.error);
            let mut dense = 0.0f64;
            for k in 0..=20_000 {
                let u = k as f64 / 20_000.0;
                dense = dense.max((a.curve.point(u) - c.point(u)).length());
                // and the approximation is near the unit circle itself
                assert!((a.curve.point(u).length() - 1.0).abs() <= tol * (1.0 + 1e-9));
            }
            assert!(
                dense <= a.error * (1.0 + 1e-9),
                "dense {dense} above the bound {}",
                a.error
            );
            assert_eq!(a.curve.point(0.0), c.point(0.0));
            assert_eq!(a.curve.point(1.0), c.point(1.0));
            assert!(a.curve.n_points() > last_n);
            last_n = a.curve.n_points();
        }
    }
}
