//! Rational (NURBS) curves and surfaces: faired through a non-rational B-spline close to them.
//!
//! The engine works on polynomial B-splines (its rows, the band bound and the fit are linear in the
//! control points). A rational curve with unequal weights — a circle or conic from Alias or CATIA — is
//! first approximated, in its own parameter, by a non-rational B-spline of degree max(p, 3) on its own
//! breakpoints (interior multiplicities raised with the degree, so the continuity class is kept), refined
//! by halving every span where the approximation is not yet within `APPROX_FRACTION` of the band. The
//! approximation error is bounded per span from 64 samples plus the interpolation margin `h²/8 · max|e''|`
//! (doubled), the fair then runs on the approximation with the band narrowed by that bound, and the
//! reported deviation adds it back: what is reported bounds the distance from the rational original.
//!
//! [`fixed_weight_fit`] goes the other way: a fit in a rational surface's own space (its knots and
//! weights fixed), linear in the control points in homogeneous form — the fallback of the surface engine
//! where a stand-in's fair adds curvature extrema (`fair/surface/own_weights.rs`).

use glam::DVec3;

use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::fit::{Smoothing, fit_curve_points};
use crate::knots::KnotVector;
use crate::surface::BSplineSurface;

/// The share of the tolerance the non-rational approximation of a rational curve may use.
pub(crate) const APPROX_FRACTION: f64 = 0.1;

/// Rounds of span halving before the approximation gives up.
const MAX_ROUNDS: usize = 14;

/// The largest control net the approximation of a rational surface may grow to.
const MAX_SURFACE_POINTS: usize = 250_000;

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

/// A non-rational stand-in for a rational surface.
#[derive(Debug, Clone)]
pub struct SurfaceApprox {
    /// The approximation: degrees max(p, 3), the rational surface's domain and breakpoints (and more).
    pub surface: BSplineSurface,
    /// An upper bound of `|approx(u, v) − original(u, v)|` over the domain.
    pub error: f64,
}

/// The knots of degree `q` on the breakpoints of `kv` (degree p; interior multiplicities raised with the
/// degree, so the continuity class is kept) and the extra simple knots `extra`.
fn raised_knots(kv: &KnotVector, q: usize, extra: &[f64]) -> Vec<f64> {
    let p = kv.degree();
    let bps = kv.breakpoints();
    let (a, b) = (bps[0], bps[bps.len() - 1]);
    let mut interior: Vec<(f64, usize)> = bps[1..bps.len() - 1]
        .iter()
        .map(|&u| (u, (kv.multiplicity(u) + q - p).min(q)))
        .chain(extra.iter().map(|&u| (u, 1)))
        .collect();
    interior.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut knots = vec![a; q + 1];
    for (u, m) in interior {
        knots.extend(std::iter::repeat_n(u, m));
    }
    knots.extend(std::iter::repeat_n(b, q + 1));
    knots
}

/// Parameters of a grid: `per_span` interior points per knot span of `kv`, or `per_span + 1` points per
/// span ends included (`ends`).
fn span_params(kv: &KnotVector, per_span: usize, ends: bool) -> Vec<f64> {
    let bps = kv.breakpoints();
    let mut out = vec![];
    for w in bps.windows(2) {
        if ends {
            out.extend((0..per_span).map(|k| w[0] + (w[1] - w[0]) * k as f64 / per_span as f64));
        } else {
            out.extend((0..per_span).map(|k| w[0] + (w[1] - w[0]) * (k as f64 + 0.5) / per_span as f64));
        }
    }
    if ends {
        out.push(bps[bps.len() - 1]);
    }
    out
}

/// A non-rational B-spline surface within `tol` of the rational `surface` in its own parameters: the
/// least-squares fit on the raised knots (degrees max(p, 3)), refined by halving the spans of each
/// direction where a tile's error is above `tol`. The error per tile is bounded from a 24 × 24 sample grid
/// plus the interpolation margin `h_u²/8 · max|e_uu| + h_v²/8 · max|e_vv|` (doubled).
pub fn surface_polynomial_approximation(surface: &BSplineSurface, tol: f64) -> Result<SurfaceApprox> {
    const SURF_FIT: usize = 8;
    const SURF_CHECK: usize = 24;
    if !(tol > 0.0 && tol.is_finite()) {
        return Err(Error::InvalidInput(format!(
            "the approximation of a rational surface needs a positive tolerance, got {}",
            crate::range::short(tol)
        )));
    }
    let (ku0, kv0) = (surface.knots_u(), surface.knots_v());
    let (qu, qv) = (ku0.degree().max(3), kv0.degree().max(3));
    let (mut extra_u, mut extra_v) = (vec![], vec![]);
    for _ in 0..MAX_ROUNDS {
        // cancel checkpoints per refinement and per row of its check (no-ops outside a fair with a token,
        // `crate::cancel`)
        crate::cancel::check()?;
        let knots_u = raised_knots(ku0, qu, &extra_u);
        let knots_v = raised_knots(kv0, qv, &extra_v);
        let (nu, nv) = (knots_u.len() - qu - 1, knots_v.len() - qv - 1);
        if nu * nv > MAX_SURFACE_POINTS {
            break;
        }
        let base = BSplineSurface::try_new(qu, qv, knots_u, knots_v, nu, nv, vec![DVec3::ZERO; nu * nv], None)?;
        let (us, vs) = (
            span_params(base.knots_u(), SURF_FIT, false),
            span_params(base.knots_v(), SURF_FIT, false),
        );
        let data: Vec<DVec3> = us
            .iter()
            .flat_map(|&u| vs.iter().map(move |&v| surface.point(u, v)))
            .collect();
        let pts = crate::fit_surface::fit_surface_grid(
            &base,
            &us,
            &vs,
            &data,
            0..nu,
            0..nv,
            crate::fit_surface::SurfaceSmoothing::NONE,
        )?;
        let approx = base.with_points(pts)?;
        // the error per tile (span × span)
        let (bu, bv) = (approx.knots_u().breakpoints(), approx.knots_v().breakpoints());
        let mut worst = 0.0f64;
        let (mut split_u, mut split_v) = (vec![false; bu.len() - 1], vec![false; bv.len() - 1]);
        for (iu, wu) in bu.windows(2).enumerate() {
            crate::cancel::check()?;
            for (iv, wv) in bv.windows(2).enumerate() {
                let (hu, hv) = ((wu[1] - wu[0]) / SURF_CHECK as f64, (wv[1] - wv[0]) / SURF_CHECK as f64);
                let (mut e0, mut euu, mut evv) = (0.0f64, 0.0f64, 0.0f64);
                for a in 0..=SURF_CHECK {
                    for b in 0..=SURF_CHECK {
                        let (u, v) = (wu[0] + hu * a as f64, wv[0] + hv * b as f64);
                        let (da, dr) = (approx.derivs(u, v), surface.derivs(u, v));
                        e0 = e0.max((da.p - dr.p).length());
                        euu = euu.max((da.suu - dr.suu).length());
                        evv = evv.max((da.svv - dr.svv).length());
                    }
                }
                let bound = e0 + 2.0 * (hu * hu / 8.0 * euu + hv * hv / 8.0 * evv);
                worst = worst.max(bound);
                if bound > tol {
                    split_u[iu] = true;
                    split_v[iv] = true;
                }
            }
        }
        if !worst.is_finite() {
            break;
        }
        if worst <= tol {
            return Ok(SurfaceApprox {
                surface: approx,
                error: worst,
            });
        }
        extra_u.extend(
            bu.windows(2)
                .zip(&split_u)
                .filter(|(_, s)| **s)
                .map(|(w, _)| 0.5 * (w[0] + w[1])),
        );
        extra_v.extend(
            bv.windows(2)
                .zip(&split_v)
                .filter(|(_, s)| **s)
                .map(|(w, _)| 0.5 * (w[0] + w[1])),
        );
    }
    Err(Error::InvalidInput(format!(
        "rational surface (unequal weights): no non-rational B-spline surface within {} of it was found with at \
         most {MAX_SURFACE_POINTS} control points; loosen the tolerance or convert it in the CAD system",
        crate::range::short(tol)
    )))
}

/// The control points of `surface`'s block `free_u × free_v` fitted to `data` at the grid `us × vs`
/// (row-major, `data[k * vs.len() + l]` at `(us[k], vs[l])`), its knots, degrees and weights fixed. With
/// the weights fixed the surface is linear in its control points in homogeneous form:
/// `S · W = Σ N_ij w_ij P_ij` with `W = Σ N_ij w_ij`, so the polynomial least-squares fit of the
/// numerator to `W · data` on the surface's own knots gives `w_ij P_ij` (the residual weighted by `W`,
/// positive and bounded). Held points are kept bit for bit; a polynomial surface is an ordinary fit.
pub fn fixed_weight_fit(
    surface: &BSplineSurface,
    us: &[f64],
    vs: &[f64],
    data: &[DVec3],
    free_u: std::ops::Range<usize>,
    free_v: std::ops::Range<usize>,
) -> Result<BSplineSurface> {
    let ones = vec![1.0; surface.points().len()];
    let w = surface.weights().unwrap_or(&ones);
    let net = |pts: Vec<DVec3>| {
        BSplineSurface::try_new(
            surface.degree_u(),
            surface.degree_v(),
            surface.knots_u().values().to_vec(),
            surface.knots_v().values().to_vec(),
            surface.nu(),
            surface.nv(),
            pts,
            None,
        )
    };
    let numerator = net(surface.points().iter().zip(w).map(|(&p, &w)| p * w).collect())?;
    // the denominator W as the x of a polynomial surface on the same knots
    let denominator = net(w.iter().map(|&w| DVec3::new(w, 0.0, 0.0)).collect())?;
    if data.len() != us.len() * vs.len() {
        return Err(Error::InvalidInput(format!(
            "fixed-weight fit: {} data points for a {} × {} grid",
            data.len(),
            us.len(),
            vs.len()
        )));
    }
    let homogeneous: Vec<DVec3> = (us.iter().flat_map(|&u| vs.iter().map(move |&v| (u, v))))
        .zip(data)
        .map(|((u, v), &d)| d * denominator.point(u, v).x)
        .collect();
    let q = crate::fit_surface::fit_surface_grid(
        &numerator,
        us,
        vs,
        &homogeneous,
        free_u.clone(),
        free_v.clone(),
        crate::fit_surface::SurfaceSmoothing::NONE,
    )?;
    let nv = surface.nv();
    let free = |k: usize| free_u.contains(&(k / nv)) && free_v.contains(&(k % nv));
    let pts = (surface.points().iter().enumerate())
        .map(|(k, &p)| if free(k) { q[k] / w[k] } else { p })
        .collect();
    surface.with_points(pts)
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

    /// A quarter cylinder (rational quadratic circle × linear): the stand-in is within the asked tolerance
    /// of the exact cylinder (closed form: distance 1 from the axis), densely checked, and of the original
    /// in its parameters within the returned bound.
    #[test]
    fn a_rational_cylinder_is_approximated_within_the_bound() {
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let circle = [
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let pts: Vec<DVec3> = circle.iter().flat_map(|&c| [c, c + DVec3::Z * 2.0]).collect();
        let weights: Vec<f64> = [1.0, w, 1.0].iter().flat_map(|&x| [x, x]).collect();
        let s = BSplineSurface::try_new(
            2,
            1,
            vec![0., 0., 0., 1., 1., 1.],
            vec![0., 0., 1., 1.],
            3,
            2,
            pts,
            Some(weights),
        )
        .unwrap();
        for tol in [1e-3, 1e-6] {
            let a = surface_polynomial_approximation(&s, tol).unwrap();
            assert!(!a.surface.is_rational() && a.error <= tol);
            let mut dense = 0.0f64;
            for i in 0..=200 {
                for j in 0..=10 {
                    let (u, v) = (i as f64 / 200.0, j as f64 / 10.0);
                    let q = a.surface.point(u, v);
                    dense = dense.max(q.distance(s.point(u, v)));
                    assert!((q.truncate().length() - 1.0).abs() <= tol * (1.0 + 1e-9), "{q}");
                }
            }
            assert!(
                dense <= a.error * (1.0 + 1e-9),
                "dense {dense} above the bound {}",
                a.error
            );
        }
    }

    /// A rational bicubic net (weights in [0.3, 3]) and another with the same knots and weights and other
    /// points: the fixed-weight fit of the first's free block to samples of the second reproduces the
    /// second there (to rounding) and keeps the held rows of the first bit for bit.
    #[test]
    fn the_fixed_weight_fit_reproduces_a_surface_of_its_own_space() {
        let n = 8;
        let k = crate::KnotVector::uniform(3, n).unwrap().values().to_vec();
        let net = |phase: f64| -> Vec<DVec3> {
            (0..n * n)
                .map(|i| {
                    let (x, y) = ((i / n) as f64, (i % n) as f64);
                    DVec3::new(x, y, (0.7 * x + phase).sin() * (0.4 * y).cos())
                })
                .collect()
        };
        let w: Vec<f64> = (0..n * n).map(|i| 10f64.powf(0.5 * (i as f64 * 1.3).sin())).collect();
        let surf = |pts| BSplineSurface::try_new(3, 3, k.clone(), k.clone(), n, n, pts, Some(w.clone())).unwrap();
        let (base, target) = (surf(net(0.0)), surf(net(0.9)));
        // the target differs from the base only in the free block: its points elsewhere are the base's
        let (fu, fv) = (2..6, 1..7);
        let free = |i: usize| fu.contains(&(i / n)) && fv.contains(&(i % n));
        let mixed: Vec<DVec3> = (0..n * n)
            .map(|i| if free(i) { target.points()[i] } else { base.points()[i] })
            .collect();
        let target = surf(mixed);
        let g: Vec<f64> = (0..=40).map(|i| i as f64 / 40.0).collect();
        let data: Vec<DVec3> = g
            .iter()
            .flat_map(|&u| g.iter().map(move |&v| (u, v)))
            .map(|(u, v)| target.point(u, v))
            .collect();
        let fit = fixed_weight_fit(&base, &g, &g, &data, fu.clone(), fv.clone()).unwrap();
        assert_eq!(fit.weights(), base.weights());
        for (i, (a, b)) in fit.points().iter().zip(target.points()).enumerate() {
            if free(i) {
                assert!(a.distance(*b) <= 1e-11, "point {i}: {a} vs {b}");
            } else {
                assert_eq!(a, &base.points()[i], "held point {i}");
            }
        }
        // and the surface with it: a dense check of the fitted surface against the target
        let worst = (0..=200)
            .flat_map(|i| (0..=200).map(move |j| (i as f64 / 200.0, j as f64 / 200.0)))
            .map(|(u, v)| fit.point(u, v).distance(target.point(u, v)))
            .fold(0.0f64, f64::max);
        assert!(worst <= 1e-11, "{worst}");
        // a grid of the wrong size is an error, not a panic
        assert!(fixed_weight_fit(&base, &g, &g, &data[1..], fu, fv).is_err());
    }
}
