//! B-spline curves (2D and 3D, optionally rational): evaluation, derivatives,
//! differential geometry, knot insertion.
//!
//! Points are stored as [`DVec3`]; a 2D curve keeps `z = 0` and reports its
//! curvature *signed* (positive when turning left), a 3D curve unsigned.
//! Evaluation follows The NURBS Book: A3.2 (derivatives of a B-spline curve
//! through basis derivatives), A4.2 (rational derivatives by the quotient
//! rule on homogeneous coordinates), A5.1 (Boehm knot insertion), A5.8 (knot
//! removal).

use glam::{DVec3, DVec4};

use crate::basis::{MAX_ORDER, basis_funs, ders_basis_funs};
use crate::error::{Error, Result};
use crate::knots::KnotVector;

/// A clamped B-spline curve of any degree up to [`MAX_DEGREE`](crate::knots::MAX_DEGREE),
/// in 2D or 3D, with optional weights (NURBS). Always valid: built through
/// [`BSplineCurve::try_new`].
#[derive(Debug, Clone, PartialEq)]
pub struct BSplineCurve {
    knots: KnotVector,
    points: Vec<DVec3>,
    weights: Option<Vec<f64>>,
    dim: usize,
}

/// Point and derivatives with respect to the parameter at one parameter value.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CurveDerivs {
    /// c(u)
    pub p: DVec3,
    /// c'(u)
    pub d1: DVec3,
    /// c''(u)
    pub d2: DVec3,
    /// c'''(u)
    pub d3: DVec3,
}

impl CurveDerivs {
    /// Curvature from the derivatives: 2D signed `(x'y''−y'x'')/|c'|³`, 3D
    /// `|c'×c''|/|c'|³`. NaN where `c' = 0` (a cusp or degenerate stretch).
    #[inline]
    pub fn curvature(&self, dim: usize) -> f64 {
        let s = self.d1.length();
        if dim == 2 {
            (self.d1.x * self.d2.y - self.d1.y * self.d2.x) / (s * s * s)
        } else {
            self.d1.cross(self.d2).length() / (s * s * s)
        }
    }

    /// Curvature vector `κ N = (c'' − (c''·T) T)/|c'|²`.
    #[inline]
    pub fn curvature_vector(&self) -> DVec3 {
        let s2 = self.d1.length_squared();
        let t = self.d1 / s2.sqrt();
        (self.d2 - self.d2.dot(t) * t) / s2
    }

    /// Derivative of curvature with respect to arc length, dκ/ds
    /// (signed in 2D, of the unsigned κ in 3D).
    pub fn dkappa_ds(&self, dim: usize) -> f64 {
        let v = self.d1.length();
        let v3 = v * v * v;
        let dv3 = 3.0 * v * self.d1.dot(self.d2); // d/du |c'|³
        let (num, dnum) = if dim == 2 {
            (
                self.d1.x * self.d2.y - self.d1.y * self.d2.x,
                self.d1.x * self.d3.y - self.d1.y * self.d3.x,
            )
        } else {
            let w = self.d1.cross(self.d2);
            let wl = w.length();
            let dw = self.d1.cross(self.d3);
            (wl, if wl > 0.0 { w.dot(dw) / wl } else { dw.length() })
        };
        (dnum * v3 - num * dv3) / (v3 * v3) / v
    }

    /// Torsion `(c'×c'')·c''' / |c'×c''|²` (0 for 2D curves; NaN where κ = 0).
    pub fn torsion(&self) -> f64 {
        let w = self.d1.cross(self.d2);
        w.dot(self.d3) / w.length_squared()
    }
}

/// Checks of [`BSplineCurve::try_new`] on the control points and weights (their count against the
/// knots is the knot vector's check): finite points, z = 0 in 2D, finite positive weights, one per point.
fn validate_points(points: &[DVec3], weights: Option<&[f64]>, dim: usize) -> Result<()> {
    for (i, p) in points.iter().enumerate() {
        if !p.is_finite() {
            return Err(Error::NotFinite {
                field: "points".into(),
                index: i,
            });
        }
        if dim == 2 && p.z != 0.0 {
            return Err(Error::InvalidInput(format!(
                "points: point {i} of a 2D curve has z = {}",
                p.z
            )));
        }
    }
    if let Some(w) = weights {
        validate_weights(w, points.len())?;
    }
    Ok(())
}

/// Weights of a rational curve or surface: one per control point (`n`), finite and positive.
pub(crate) fn validate_weights(w: &[f64], n: usize) -> Result<()> {
    if w.len() != n {
        return Err(Error::LengthMismatch {
            field: "weights".into(),
            count: w.len(),
            expected: n,
        });
    }
    for (i, &x) in w.iter().enumerate() {
        if !x.is_finite() {
            return Err(Error::NotFinite {
                field: "weights".into(),
                index: i,
            });
        }
        if x <= 0.0 {
            return Err(Error::BadWeight {
                field: "weights".into(),
                index: i,
                value: x,
            });
        }
    }
    Ok(())
}

impl BSplineCurve {
    /// Build and validate a curve. `dim` is 2 or 3; for 2D, the z coordinates
    /// must be 0. `weights`, if given, must be positive, one per point.
    pub fn try_new(
        degree: usize,
        knots: Vec<f64>,
        points: Vec<DVec3>,
        weights: Option<Vec<f64>>,
        dim: usize,
    ) -> Result<Self> {
        if dim != 2 && dim != 3 {
            return Err(Error::InvalidInput(format!(
                "dimension {dim} is not supported (2 or 3)"
            )));
        }
        let knots = KnotVector::try_new(knots, degree, points.len(), "knots")?;
        validate_points(&points, weights.as_deref(), dim)?;
        Ok(Self {
            knots,
            points,
            weights,
            dim,
        })
    }

    /// A non-rational 2D curve from `(x, y)` points.
    ///
    /// A clamped quadratic with one interior knot, evaluated at its ends, its knot and between:
    ///
    /// ```
    /// use fairway::{BSplineCurve, DVec2, DVec3};
    /// let pts = [DVec2::new(0.0, 0.0), DVec2::new(1.0, 2.0), DVec2::new(3.0, 2.0), DVec2::new(4.0, 0.0)];
    /// let c = BSplineCurve::new_2d(2, vec![0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0], &pts)?;
    /// assert_eq!(c.point(0.0), DVec3::ZERO);
    /// assert_eq!(c.point(1.0), DVec3::new(4.0, 0.0, 0.0));
    /// // at the knot: the midpoint of the two middle control points (quadratic, simple knot)
    /// assert!((c.point(0.5) - DVec3::new(2.0, 2.0, 0.0)).length() < 1e-15);
    /// // symmetric control polygon: the tangent at the middle is horizontal, the curvature negative (turns right)
    /// assert!(c.derivs(0.5).d1.y.abs() < 1e-12 && c.curvature(0.5) < 0.0);
    /// // a knot vector of the wrong length is refused with the field and the counts
    /// let e = BSplineCurve::new_2d(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0], &pts).unwrap_err();
    /// assert!(matches!(e, fairway::Error::KnotCount { count: 6, expected: 7, .. }));
    /// # Ok::<(), fairway::Error>(())
    /// ```
    pub fn new_2d(degree: usize, knots: Vec<f64>, points: &[glam::DVec2]) -> Result<Self> {
        Self::try_new(degree, knots, points.iter().map(|p| p.extend(0.0)).collect(), None, 2)
    }

    /// A non-rational 3D curve.
    pub fn new_3d(degree: usize, knots: Vec<f64>, points: Vec<DVec3>) -> Result<Self> {
        Self::try_new(degree, knots, points, None, 3)
    }

    /// Its projection on the XY plane as a 2D curve (z dropped; same degree, knots and weights): a
    /// parameter-space curve or a 2D curve a file stores in 3D with z = 0.
    pub fn to_2d(&self) -> Result<Self> {
        let pts = self.points().iter().map(|q| DVec3::new(q.x, q.y, 0.0)).collect();
        Self::try_new(
            self.degree(),
            self.knots().values().to_vec(),
            pts,
            self.weights().map(<[f64]>::to_vec),
            2,
        )
    }

    /// A Bézier curve (one span on `[0, 1]`) through its control points.
    pub fn bezier(points: Vec<DVec3>, dim: usize) -> Result<Self> {
        let p = points.len().saturating_sub(1);
        let mut k = vec![0.0; p + 1];
        k.extend(std::iter::repeat_n(1.0, p + 1));
        Self::try_new(p, k, points, None, dim)
    }

    /// The same knots and weights with new control points (validated: as many as before, finite,
    /// z = 0 in 2D; the knots are not checked again).
    pub fn with_points(&self, points: Vec<DVec3>) -> Result<Self> {
        if points.len() != self.points.len() {
            return Err(Error::LengthMismatch {
                field: "points".into(),
                count: points.len(),
                expected: self.points.len(),
            });
        }
        validate_points(&points, self.weights.as_deref(), self.dim)?;
        Ok(Self {
            knots: self.knots.clone(),
            points,
            weights: self.weights.clone(),
            dim: self.dim,
        })
    }

    /// Degree p.
    #[inline]
    pub fn degree(&self) -> usize {
        self.knots.degree()
    }
    /// The knot vector.
    #[inline]
    pub fn knots(&self) -> &KnotVector {
        &self.knots
    }
    /// Control points (z = 0 for 2D).
    #[inline]
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }
    /// Weights, if rational.
    #[inline]
    pub fn weights(&self) -> Option<&[f64]> {
        self.weights.as_deref()
    }
    /// 2 or 3.
    #[inline]
    pub fn dim(&self) -> usize {
        self.dim
    }
    /// Has weights.
    #[inline]
    pub fn is_rational(&self) -> bool {
        self.weights.is_some()
    }
    /// Parameter domain.
    #[inline]
    pub fn domain(&self) -> (f64, f64) {
        self.knots.domain()
    }
    /// Number of control points.
    #[inline]
    pub fn n_points(&self) -> usize {
        self.points.len()
    }

    /// Whether the weights, if any, are all equal (then the curve is polynomial).
    pub fn is_polynomial(&self) -> bool {
        match &self.weights {
            None => true,
            Some(w) => w.iter().all(|&x| x == w[0]),
        }
    }

    /// The curve without weights if they are all equal; an error for a true NURBS.
    pub fn to_polynomial(&self) -> Result<Self> {
        if !self.is_polynomial() {
            return Err(Error::InvalidInput(
                "rational curve (unequal weights): fairing needs a non-rational B-spline; \
                 convert it first (e.g. refit) in the CAD system"
                    .into(),
            ));
        }
        Ok(Self {
            weights: None,
            ..self.clone()
        })
    }

    /// First and last points coincide (within `tol`).
    pub fn is_closed(&self, tol: f64) -> bool {
        self.points[0].distance(*self.points.last().unwrap()) <= tol
    }

    /// c(u). `u` is clamped to the domain.
    #[inline]
    pub fn point(&self, u: f64) -> DVec3 {
        let p = self.degree();
        let kv = self.knots.values();
        let span = self.knots.find_span(u);
        let u = self.knots.clamp(u);
        let mut n = [0.0; MAX_ORDER];
        basis_funs(kv, span, u, p, &mut n);
        match &self.weights {
            None => {
                let mut c = DVec3::ZERO;
                for j in 0..=p {
                    c += self.points[span - p + j] * n[j];
                }
                c
            }
            Some(w) => {
                let mut c = DVec4::ZERO;
                for j in 0..=p {
                    let i = span - p + j;
                    c += (self.points[i] * w[i]).extend(w[i]) * n[j];
                }
                c.truncate() / c.w
            }
        }
    }

    /// Point and first three derivatives at `u` (clamped to the domain). At
    /// an interior knot the derivatives are those of the span to the right
    /// (the left one at the domain end).
    #[inline]
    pub fn derivs(&self, u: f64) -> CurveDerivs {
        self.derivs_in_span(self.knots.find_span(u), self.knots.clamp(u))
    }

    /// [`Self::point`] from the knot span found by
    /// [`KnotVector::find_span_from`](crate::knots::KnotVector::find_span_from) with `hint` (the same value).
    #[inline]
    pub(crate) fn point_from(&self, u: f64, hint: usize) -> DVec3 {
        if self.weights.is_some() {
            return self.point(u);
        }
        let p = self.degree();
        let span = self.knots.find_span_from(u, hint);
        let mut n = [0.0; MAX_ORDER];
        basis_funs(self.knots.values(), span, self.knots.clamp(u), p, &mut n);
        let mut c = DVec3::ZERO;
        for j in 0..=p {
            c += self.points[span - p + j] * n[j];
        }
        c
    }

    /// [`Self::derivs`] without the third derivative (`d3` is 0 on a non-rational curve), from the knot span
    /// found by [`KnotVector::find_span_from`](crate::knots::KnotVector::find_span_from) with `hint`: the same
    /// values for c, c', c'' (a closest-point Newton iteration needs no more); returns the span too.
    #[inline]
    pub(crate) fn derivs2_from(&self, u: f64, hint: usize) -> (CurveDerivs, usize) {
        let span = self.knots.find_span_from(u, hint);
        let u = self.knots.clamp(u);
        if self.weights.is_some() {
            return (self.derivs_in_span(span, u), span);
        }
        let p = self.degree();
        let mut d = [[0.0; MAX_ORDER]; 3];
        ders_basis_funs(self.knots.values(), span, u, p, &mut d);
        let mut out = [DVec3::ZERO; 3];
        for j in 0..=p {
            let cp = self.points[span - p + j];
            for k in 0..3 {
                out[k] += cp * d[k][j];
            }
        }
        let derivs = CurveDerivs {
            p: out[0],
            d1: out[1],
            d2: out[2],
            d3: DVec3::ZERO,
        };
        (derivs, span)
    }

    /// [`Self::derivs`] with the polynomial pieces of knot span `span` (`p ≤ span < n`, non-empty):
    /// at a knot, the span that ends there gives the left-hand limits.
    #[inline]
    pub(crate) fn derivs_in_span(&self, span: usize, u: f64) -> CurveDerivs {
        let p = self.degree();
        let kv = self.knots.values();
        let mut d = [[0.0; MAX_ORDER]; 4];
        ders_basis_funs(kv, span, u, p, &mut d);
        match &self.weights {
            None => {
                let mut out = [DVec3::ZERO; 4];
                for j in 0..=p {
                    let cp = self.points[span - p + j];
                    for k in 0..4 {
                        out[k] += cp * d[k][j];
                    }
                }
                CurveDerivs {
                    p: out[0],
                    d1: out[1],
                    d2: out[2],
                    d3: out[3],
                }
            }
            Some(w) => {
                let mut a = [DVec4::ZERO; 4];
                for j in 0..=p {
                    let i = span - p + j;
                    let h = (self.points[i] * w[i]).extend(w[i]);
                    for k in 0..4 {
                        a[k] += h * d[k][j];
                    }
                }
                let c = rational_derivs(&a);
                CurveDerivs {
                    p: c[0],
                    d1: c[1],
                    d2: c[2],
                    d3: c[3],
                }
            }
        }
    }

    /// c'(u). For a polynomial curve only the basis functions and their first
    /// derivatives are computed (A2.3 with n = 1: the first-derivative values are
    /// the same operations as in [`Self::derivs`], hence bit-identical to
    /// `derivs(u).d1`, at about half the cost); rational curves use `derivs`.
    #[inline]
    pub fn d1(&self, u: f64) -> DVec3 {
        if self.weights.is_some() {
            return self.derivs(u).d1;
        }
        let p = self.degree();
        let span = self.knots.find_span(u);
        let mut d = [[0.0; MAX_ORDER]; 2];
        ders_basis_funs(self.knots.values(), span, self.knots.clamp(u), p, &mut d);
        let mut out = DVec3::ZERO;
        for j in 0..=p {
            out += self.points[span - p + j] * d[1][j];
        }
        out
    }

    /// Unit tangent c'/|c'| (NaN at a cusp).
    pub fn tangent(&self, u: f64) -> DVec3 {
        self.derivs(u).d1.normalize_or(DVec3::NAN)
    }

    /// Normal: for 2D the tangent turned +90° (so that κ·N points to the
    /// centre of curvature); for 3D the principal normal (NaN where κ = 0).
    pub fn normal(&self, u: f64) -> DVec3 {
        let d = self.derivs(u);
        if self.dim == 2 {
            let t = d.d1.normalize_or(DVec3::NAN);
            DVec3::new(-t.y, t.x, 0.0)
        } else {
            d.curvature_vector().normalize_or(DVec3::NAN)
        }
    }

    /// Curvature (2D signed, 3D unsigned); NaN where `c' = 0`.
    #[inline]
    pub fn curvature(&self, u: f64) -> f64 {
        self.derivs(u).curvature(self.dim)
    }

    /// Curvature vector κN.
    pub fn curvature_vector(&self, u: f64) -> DVec3 {
        self.derivs(u).curvature_vector()
    }

    /// Torsion (3D); 0 for a 2D curve.
    pub fn torsion(&self, u: f64) -> f64 {
        if self.dim == 2 { 0.0 } else { self.derivs(u).torsion() }
    }

    /// dκ/ds.
    pub fn dkappa_ds(&self, u: f64) -> f64 {
        self.derivs(u).dkappa_ds(self.dim)
    }

    /// Parameters of the inflections of a 2D curve: sign changes of
    /// `f(u) = x'y'' − y'x''`, found on `samples_per_span` samples per knot
    /// span (and the domain end) and refined by bisection to `1e-14` of the
    /// domain. Values with `|f| ≤ 1e-12·|c'|·|c''|` count as zero (rounding
    /// noise on straight stretches), so straight segments have no
    /// inflections; a sign change across such a stretch is reported at its
    /// bisected crossing. An inflection at a knot where the curvature jumps
    /// from one sign to the other is reported at that knot. Empty for 3D
    /// curves.
    pub fn inflections(&self, samples_per_span: usize) -> Vec<f64> {
        if self.dim != 2 {
            return vec![];
        }
        // sign of f, or 0 where it is zero to rounding
        let sign = |u: f64| {
            let d = self.derivs(u);
            let f = d.d1.x * d.d2.y - d.d1.y * d.d2.x;
            if f.abs() <= 1e-12 * d.d1.length() * d.d2.length() {
                0.0
            } else {
                f.signum()
            }
        };
        let bp = self.knots.breakpoints();
        let m = samples_per_span.max(2);
        // the samples, not stored (a curve of a million spans would need 32 million of them)
        let samples = bp
            .windows(2)
            .flat_map(|w| (0..m).map(move |k| w[0] + (w[1] - w[0]) * k as f64 / m as f64))
            .chain(std::iter::once(*bp.last().unwrap()));
        let mut out = vec![];
        let mut prev: Option<(f64, f64)> = None; // last sample with a non-zero sign
        for u in samples {
            let sg = sign(u);
            if sg == 0.0 {
                continue;
            }
            if let Some((pu, ps)) = prev
                && ps != sg
            {
                let (mut a, mut b) = (pu, u);
                while b - a > 1e-14 * (1.0 + b.abs()) {
                    let mid = 0.5 * (a + b);
                    if mid <= a || mid >= b {
                        break;
                    }
                    let sm = sign(mid);
                    if sm == ps {
                        a = mid
                    } else if sm == sg {
                        b = mid
                    } else {
                        // zero to rounding at mid: the crossing is there
                        a = mid;
                        b = mid;
                    }
                }
                out.push(0.5 * (a + b));
            }
            prev = Some((u, sg));
        }
        out
    }

    /// Insert `u` `times` times (Boehm, The NURBS Book A5.1). The curve is unchanged.
    pub fn insert_knot(&self, u: f64, times: usize) -> Result<Self> {
        self.check_interior(u, "knot to insert")?;
        let mut c = self.clone();
        for _ in 0..times {
            c = c.insert_once(u)?;
        }
        Ok(c)
    }

    /// `u` strictly inside the domain, else [`Error::OutOfDomain`] naming `what`.
    fn check_interior(&self, u: f64, what: &str) -> Result<()> {
        let (a, b) = self.domain();
        if u > a && u < b {
            Ok(())
        } else {
            Err(Error::OutOfDomain {
                what: what.into(),
                value: u,
                start: a,
                end: b,
            })
        }
    }

    fn insert_once(&self, u: f64) -> Result<Self> {
        let p = self.degree();
        let kv = self.knots.values();
        let k = self.knots.find_span(u);
        let s = self.knots.multiplicity(u);
        if s >= p {
            return Err(Error::InvalidInput(format!(
                "knot {u} already has multiplicity {s} = degree"
            )));
        }
        let h = self.homogeneous();
        let mut q = Vec::with_capacity(h.len() + 1);
        q.extend_from_slice(&h[..=k - p]);
        for i in k - p + 1..=k {
            let alpha = (u - kv[i]) / (kv[i + p] - kv[i]);
            q.push(h[i] * alpha + h[i - 1] * (1.0 - alpha));
        }
        q.extend_from_slice(&h[k..]);
        let knots = self.knots.with_inserted(u);
        self.rebuild_homogeneous(knots, q)
    }

    /// Remove the interior knot `u` `times` times (The NURBS Book A5.8, one removal at a time),
    /// the inverse of [`Self::insert_knot`]. Each removal solves for the p − s new control points
    /// from both sides of the knot (s its multiplicity) and accepts only if the two solutions meet
    /// within `tol` (a distance in model units; for a rational curve the book's bound
    /// `tol·w_min/(1 + max|P|)` on the homogeneous points), so the curve moves by at most about
    /// `tol`. A knot of multiplicity s can be removed once exactly when the curve is C^(p−s) there.
    ///
    /// Errors: `u` not an interior knot of multiplicity ≥ `times`, a negative or non-finite `tol`,
    /// or [`Error::KnotNotRemovable`] when a removal would move the curve by more than `tol` (a kink
    /// or a derivative jump at `u`); the curve is then left as it was.
    pub fn remove_knot(&self, u: f64, times: usize, tol: f64) -> Result<Self> {
        self.check_interior(u, "knot to remove")?;
        if !(tol.is_finite() && tol >= 0.0) {
            return Err(Error::InvalidInput(format!(
                "knot removal tolerance must be finite and ≥ 0, got {tol}"
            )));
        }
        let s = self.knots.multiplicity(u);
        if s < times {
            return Err(Error::InvalidInput(format!(
                "knot {u} has multiplicity {s}: it cannot be removed {times} time(s)"
            )));
        }
        let mut c = self.clone();
        for t in 0..times {
            c = c.remove_once(u, tol).ok_or(Error::KnotNotRemovable {
                value: u,
                requested: times,
                removed: t,
                tolerance: tol,
            })?;
        }
        Ok(c)
    }

    /// One removal of the interior knot `u` (present), or `None` if it would move the curve by more than `tol`.
    fn remove_once(&self, u: f64, tol: f64) -> Option<Self> {
        let p = self.degree() as isize;
        let kv = self.knots.values();
        let s = self.knots.multiplicity(u) as isize;
        let r = kv.partition_point(|&k| k <= u) as isize - 1; // last index of u
        let mut h = self.homogeneous();
        let tol = match &self.weights {
            None => tol,
            Some(w) => {
                let wmin = w.iter().fold(f64::INFINITY, |m, &x| m.min(x));
                let pmax = self.points.iter().fold(0.0f64, |m, q| m.max(q.length()));
                tol * wmin / (1.0 + pmax)
            }
        };
        let (first, last) = (r - p, r - s);
        let off = first - 1;
        let at = |i: isize| i as usize;
        let mut temp = vec![DVec4::ZERO; at(last - off + 2)];
        temp[0] = h[at(off)];
        temp[at(last + 1 - off)] = h[at(last + 1)];
        let (mut i, mut j, mut ii, mut jj) = (first, last, 1isize, last - off);
        while j - i > 0 {
            let alfi = (u - kv[at(i)]) / (kv[at(i + p + 1)] - kv[at(i)]);
            let alfj = (u - kv[at(j)]) / (kv[at(j + p + 1)] - kv[at(j)]);
            temp[at(ii)] = (h[at(i)] - temp[at(ii - 1)] * (1.0 - alfi)) / alfi;
            temp[at(jj)] = (h[at(j)] - temp[at(jj + 1)] * alfj) / (1.0 - alfj);
            i += 1;
            ii += 1;
            j -= 1;
            jj -= 1;
        }
        let dev = if j - i < 0 {
            temp[at(ii - 1)].distance(temp[at(jj + 1)])
        } else {
            let alfi = (u - kv[at(i)]) / (kv[at(i + p + 1)] - kv[at(i)]);
            h[at(i)].distance(temp[at(ii + 1)] * alfi + temp[at(ii - 1)] * (1.0 - alfi))
        };
        if !(dev <= tol) {
            return None;
        }
        let (mut i, mut j) = (first, last);
        while j - i > 0 {
            h[at(i)] = temp[at(i - off)];
            h[at(j)] = temp[at(j - off)];
            i += 1;
            j -= 1;
        }
        h.remove(at((2 * r - s - p) / 2));
        let mut knots = kv.to_vec();
        knots.remove(at(r));
        self.rebuild_homogeneous(knots, h).ok()
    }

    /// Insert every value of `us` (sorted or not) once: knot refinement.
    pub fn refine(&self, us: &[f64]) -> Result<Self> {
        let mut c = self.clone();
        for &u in us {
            c = c.insert_knot(u, 1)?;
        }
        Ok(c)
    }

    /// The same curve traversed backwards, on the domain reflected as `a + b − u`.
    ///
    /// `a + b − k` rounds, and two distinct knots a few ulps apart (a G0 region end inserted next to an
    /// existing knot) can round to one value, which would merge their multiplicities beyond the degree:
    /// equal knots stay equal, and a distinct knot that would not come out above its predecessor is
    /// moved up to the next representable value (an ulp-sized change of the parameter).
    pub fn reversed(&self) -> Self {
        let (a, b) = self.domain();
        let src = self.knots.values();
        let mut knots: Vec<f64> = Vec::with_capacity(src.len());
        for i in (0..src.len()).rev() {
            let mut r = a + b - src[i];
            if let Some(&prev) = knots.last() {
                if src[i] == src[i + 1] {
                    r = prev;
                } else if r <= prev {
                    r = prev.next_up();
                }
            }
            knots.push(r);
        }
        let mut points = self.points.clone();
        points.reverse();
        let weights = self.weights.clone().map(|mut w| {
            w.reverse();
            w
        });
        Self {
            knots: KnotVector::try_new(knots, self.degree(), points.len(), "knots").expect("reversal keeps validity"),
            points,
            weights,
            dim: self.dim,
        }
    }

    fn homogeneous(&self) -> Vec<DVec4> {
        match &self.weights {
            None => self.points.iter().map(|p| p.extend(1.0)).collect(),
            Some(w) => self.points.iter().zip(w).map(|(p, &w)| (*p * w).extend(w)).collect(),
        }
    }

    fn rebuild_homogeneous(&self, knots: Vec<f64>, h: Vec<DVec4>) -> Result<Self> {
        let (points, weights) = if self.weights.is_some() {
            let w: Vec<f64> = h.iter().map(|x| x.w).collect();
            (h.iter().map(|x| x.truncate() / x.w).collect(), Some(w))
        } else {
            (h.iter().map(|x| x.truncate()).collect(), None)
        };
        let mut points: Vec<DVec3> = points;
        if self.dim == 2 {
            for p in &mut points {
                p.z = 0.0;
            }
        }
        Self::try_new(self.degree(), knots, points, weights, self.dim)
    }

    /// The same curve of degree `degree` (≥ its own; non-rational): each Bézier segment elevated (The
    /// NURBS Book eq. 5.36), every interior breakpoint kept at its multiplicity plus the degrees added.
    /// Exact but for rounding (the knots inserted for the Bézier form are removed again within
    /// 1e-12 × the control net's size).
    pub fn elevate_degree(&self, degree: usize) -> Result<Self> {
        let mut c = self.to_polynomial()?;
        let (lo, hi) = c.control_bounds();
        let tol = 1e-12 * (hi - lo).length().max(f64::MIN_POSITIVE);
        while c.degree() < degree {
            c = c.elevate_once(tol)?;
        }
        Ok(c)
    }

    /// [`Self::elevate_degree`] by one.
    fn elevate_once(&self, tol: f64) -> Result<Self> {
        let p = self.degree();
        let (a, b) = self.domain();
        let inner: Vec<(f64, usize)> = self
            .knots
            .breakpoints()
            .into_iter()
            .filter(|&u| u > a && u < b)
            .map(|u| (u, self.knots.multiplicity(u)))
            .collect();
        let mut bez = self.clone();
        for &(u, s) in &inner {
            if s < p {
                bez = bez.insert_knot(u, p - s)?;
            }
        }
        // the Bézier segments, each elevated: Q_i = i/(p+1) P_{i−1} + (1 − i/(p+1)) P_i
        let pts = bez.points();
        let mut out = vec![pts[0]];
        for seg in 0..=inner.len() {
            let s = &pts[seg * p..=seg * p + p];
            for i in 1..=p + 1 {
                let f = i as f64 / (p + 1) as f64;
                let q = if i == p + 1 {
                    s[p]
                } else {
                    s[i - 1] * f + s[i] * (1.0 - f)
                };
                out.push(q);
            }
        }
        let mut knots = vec![a; p + 2];
        for &(u, _) in &inner {
            knots.extend(std::iter::repeat_n(u, p + 1));
        }
        knots.extend(std::iter::repeat_n(b, p + 2));
        let mut c = Self::try_new(p + 1, knots, out, None, self.dim)?;
        for &(u, s) in &inner {
            if s < p {
                c = c.remove_knot(u, p - s, tol)?;
            }
        }
        Ok(c)
    }

    /// Axis-aligned bounding box of the control points (contains the curve).
    pub fn control_bounds(&self) -> (DVec3, DVec3) {
        point_bounds(&self.points)
    }
}

/// Axis-aligned bounding box `(min, max)` of `pts` (`(+∞, −∞)` when empty).
pub(crate) fn point_bounds(pts: &[DVec3]) -> (DVec3, DVec3) {
    pts.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

/// Derivatives of a rational curve from the derivatives of its homogeneous
/// form `a[k] = (A^(k), w^(k))` (The NURBS Book, eq. 4.8 / A4.2):
/// `C^(k) = (A^(k) − Σ_{i=1..k} C(k,i) w^(i) C^(k−i)) / w`.
pub(crate) fn rational_derivs(a: &[DVec4; 4]) -> [DVec3; 4] {
    const BIN: [[f64; 4]; 4] = [[1., 0., 0., 0.], [1., 1., 0., 0.], [1., 2., 1., 0.], [1., 3., 3., 1.]];
    let w0 = a[0].w;
    let mut c = [DVec3::ZERO; 4];
    for k in 0..4 {
        let mut v = a[k].truncate();
        for i in 1..=k {
            v -= c[k - i] * (BIN[k][i] * a[i].w);
        }
        c[k] = v / w0;
    }
    c
}

/// Distance under which first and last control points count as one: `1e-10 ×` the diagonal of
/// the control points' bounding box.
pub fn closed_tolerance(c: &BSplineCurve) -> f64 {
    let (lo, hi) = c.control_bounds();
    1e-10 * (hi - lo).length()
}

/// First point = last point (within [`closed_tolerance`]).
pub fn is_closed_curve(c: &BSplineCurve) -> bool {
    c.is_closed(closed_tolerance(c))
}
