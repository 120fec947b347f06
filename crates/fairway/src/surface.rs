//! Tensor-product B-spline surfaces (optionally rational): evaluation,
//! partial derivatives up to second order, normals, principal curvatures,
//! isocurves.
//!
//! Control points `d_ij` are stored row-major: `points[i * nv + j]`, `i`
//! over u (rows), `j` over v. Conventions (PRODUCT.md): the normal is
//! `Su × Sv` normalized; a normal curvature is positive where the surface
//! bends towards the normal; `k_max ≥ k_min`, mean = (k_max + k_min)/2,
//! gauss = k_max·k_min. Fundamental forms as in do Carmo §3.3:
//! `E = Su·Su, F = Su·Sv, G = Sv·Sv`, `L = Suu·n, M = Suv·n, N = Svv·n`,
//! `K = (LN − M²)/(EG − F²)`, `H = (EN − 2FM + GL) / (2(EG − F²))`.

use glam::{DVec3, DVec4};

use crate::basis::{MAX_ORDER, basis_funs, ders_basis_funs};
use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::knots::KnotVector;

/// A clamped tensor-product B-spline surface in 3D.
#[derive(Debug, Clone, PartialEq)]
pub struct BSplineSurface {
    knots_u: KnotVector,
    knots_v: KnotVector,
    nu: usize,
    nv: usize,
    points: Vec<DVec3>,
    weights: Option<Vec<f64>>,
}

/// Point and partial derivatives up to second order.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SurfaceDerivs {
    /// S(u, v)
    pub p: DVec3,
    /// ∂S/∂u
    pub su: DVec3,
    /// ∂S/∂v
    pub sv: DVec3,
    /// ∂²S/∂u²
    pub suu: DVec3,
    /// ∂²S/∂u∂v
    pub suv: DVec3,
    /// ∂²S/∂v²
    pub svv: DVec3,
}

/// Curvatures at a point of a surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceCurvature {
    /// Unit normal `Su × Sv / |Su × Sv|`.
    pub normal: DVec3,
    /// Larger principal curvature.
    pub k_max: f64,
    /// Smaller principal curvature.
    pub k_min: f64,
    /// Mean curvature.
    pub mean: f64,
    /// Gaussian curvature.
    pub gauss: f64,
    /// Unit principal direction of `k_max` (in 3D).
    pub dir_max: DVec3,
    /// Unit principal direction of `k_min`.
    pub dir_min: DVec3,
}

impl SurfaceDerivs {
    /// The mean curvature alone, by the same operations as [`Self::curvature`]'s `mean` (bit-identical),
    /// without the principal directions. NaN where the surface is singular.
    pub fn mean_curvature(&self) -> f64 {
        let nn = self.su.cross(self.sv);
        let n = nn / nn.length();
        let (e, f, g) = (self.su.dot(self.su), self.su.dot(self.sv), self.sv.dot(self.sv));
        let (l, m, nc) = (self.suu.dot(n), self.suv.dot(n), self.svv.dot(n));
        let det = e * g - f * f;
        (e * nc - 2.0 * f * m + g * l) / (2.0 * det)
    }

    /// Normal and curvatures from the derivatives. NaN fields where the
    /// surface is singular (`Su × Sv = 0`).
    pub fn curvature(&self) -> SurfaceCurvature {
        let nn = self.su.cross(self.sv);
        let n = nn / nn.length();
        let (e, f, g) = (self.su.dot(self.su), self.su.dot(self.sv), self.sv.dot(self.sv));
        let (l, m, nc) = (self.suu.dot(n), self.suv.dot(n), self.svv.dot(n));
        let det = e * g - f * f;
        let gauss = (l * nc - m * m) / det;
        let mean = (e * nc - 2.0 * f * m + g * l) / (2.0 * det);
        // Half the difference of the principal curvatures from the shape
        // operator S = I⁻¹ II: ((S11 − S22)/2)² + S12·S21 = H² − K. Computing
        // it this way (not as H² − K) keeps full relative accuracy near
        // umbilics, where H² − K cancels and its square root would lose half
        // the digits.
        let s11 = (g * l - f * m) / det;
        let s22 = (e * nc - f * m) / det;
        let s12 = (g * m - f * nc) / det;
        let s21 = (e * m - f * l) / det;
        let half = 0.5 * (s11 - s22);
        let disc = (half * half + s12 * s21).max(0.0).sqrt();
        let (k_max, k_min) = (mean + disc, mean - disc);
        let dir = |k: f64| {
            // (II − k I) a = 0 for a = (a, b) in the (Su, Sv) basis
            let r1 = (m - k * f, -(l - k * e));
            let r2 = (nc - k * g, -(m - k * f));
            let (a, b) = if r1.0.hypot(r1.1) >= r2.0.hypot(r2.1) { r1 } else { r2 };
            let d = self.su * a + self.sv * b;
            d.try_normalize()
        };
        let su_n = self.su.normalize_or_zero();
        let (dir_max, dir_min) = match (dir(k_max), dir(k_min)) {
            (Some(a), _) if disc > 1e-12 * (mean.abs() + disc) => (a, n.cross(a)),
            _ => (su_n, n.cross(su_n)), // umbilic: any orthonormal pair
        };
        SurfaceCurvature {
            normal: n,
            k_max,
            k_min,
            mean,
            gauss,
            dir_max,
            dir_min,
        }
    }
}

impl BSplineSurface {
    /// Build and validate a surface from `nu × nv` row-major points.
    pub fn try_new(
        degree_u: usize,
        degree_v: usize,
        knots_u: Vec<f64>,
        knots_v: Vec<f64>,
        nu: usize,
        nv: usize,
        points: Vec<DVec3>,
        weights: Option<Vec<f64>>,
    ) -> Result<Self> {
        if points.len() != nu * nv {
            return Err(Error::LengthMismatch {
                field: "points".into(),
                count: points.len(),
                expected: nu * nv,
            });
        }
        let knots_u = KnotVector::try_new(knots_u, degree_u, nu, "knots_u")?;
        let knots_v = KnotVector::try_new(knots_v, degree_v, nv, "knots_v")?;
        if let Some(index) = points.iter().position(|p| !p.is_finite()) {
            return Err(Error::NotFinite {
                field: "points".into(),
                index,
            });
        }
        if let Some(w) = &weights {
            crate::curve::validate_weights(w, points.len())?;
        }
        Ok(Self {
            knots_u,
            knots_v,
            nu,
            nv,
            points,
            weights,
        })
    }

    /// The same knots and weights with new control points.
    pub fn with_points(&self, points: Vec<DVec3>) -> Result<Self> {
        Self::try_new(
            self.degree_u(),
            self.degree_v(),
            self.knots_u.values().to_vec(),
            self.knots_v.values().to_vec(),
            self.nu,
            self.nv,
            points,
            self.weights.clone(),
        )
    }

    /// Degree in u.
    pub fn degree_u(&self) -> usize {
        self.knots_u.degree()
    }
    /// Degree in v.
    pub fn degree_v(&self) -> usize {
        self.knots_v.degree()
    }
    /// Knot vector in u.
    pub fn knots_u(&self) -> &KnotVector {
        &self.knots_u
    }
    /// Knot vector in v.
    pub fn knots_v(&self) -> &KnotVector {
        &self.knots_v
    }
    /// Control points in u.
    pub fn nu(&self) -> usize {
        self.nu
    }
    /// Control points in v.
    pub fn nv(&self) -> usize {
        self.nv
    }
    /// Row-major control points.
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }
    /// Axis-aligned bounding box of the control points (contains the surface), as
    /// [`crate::BSplineCurve::control_bounds`].
    pub fn control_bounds(&self) -> (DVec3, DVec3) {
        crate::curve::point_bounds(&self.points)
    }
    /// Control point `d_ij`.
    pub fn point_at(&self, i: usize, j: usize) -> DVec3 {
        self.points[i * self.nv + j]
    }
    /// The same surface with u and v swapped: `S'(v, u) = S(u, v)` (control points and weights
    /// transposed).
    pub fn transposed(&self) -> Self {
        let swap = |k: usize| (k % self.nu) * self.nv + k / self.nu;
        let points = (0..self.points.len()).map(|k| self.points[swap(k)]).collect();
        let weights = self
            .weights
            .as_ref()
            .map(|w| (0..w.len()).map(|k| w[swap(k)]).collect());
        Self::try_new(
            self.degree_v(),
            self.degree_u(),
            self.knots_v().values().to_vec(),
            self.knots_u().values().to_vec(),
            self.nv,
            self.nu,
            points,
            weights,
        )
        .expect("the transpose of a valid surface is valid")
    }
    /// Weights, if rational.
    pub fn weights(&self) -> Option<&[f64]> {
        self.weights.as_deref()
    }
    /// Has weights.
    pub fn is_rational(&self) -> bool {
        self.weights.is_some()
    }
    /// Whether the weights, if any, are all equal.
    pub fn is_polynomial(&self) -> bool {
        self.weights.as_ref().is_none_or(|w| w.iter().all(|&x| x == w[0]))
    }
    /// The surface without weights if they are all equal; an error otherwise.
    pub fn to_polynomial(&self) -> Result<Self> {
        if !self.is_polynomial() {
            return Err(Error::InvalidInput(
                "rational surface (unequal weights): fairing needs a non-rational B-spline surface".into(),
            ));
        }
        Ok(Self {
            weights: None,
            ..self.clone()
        })
    }
    /// Domain `((u0, u1), (v0, v1))`.
    pub fn domain(&self) -> ((f64, f64), (f64, f64)) {
        (self.knots_u.domain(), self.knots_v.domain())
    }

    fn hom(&self, i: usize, j: usize) -> DVec4 {
        let k = i * self.nv + j;
        match &self.weights {
            None => self.points[k].extend(1.0),
            Some(w) => (self.points[k] * w[k]).extend(w[k]),
        }
    }

    /// S(u, v), clamped to the domain.
    pub fn point(&self, u: f64, v: f64) -> DVec3 {
        let (pu, pv) = (self.degree_u(), self.degree_v());
        let su = self.knots_u.find_span(u);
        let sv = self.knots_v.find_span(v);
        let (mut nu, mut nv) = ([0.0; MAX_ORDER], [0.0; MAX_ORDER]);
        basis_funs(self.knots_u.values(), su, self.knots_u.clamp(u), pu, &mut nu);
        basis_funs(self.knots_v.values(), sv, self.knots_v.clamp(v), pv, &mut nv);
        let mut s = DVec4::ZERO;
        for a in 0..=pu {
            let mut row = DVec4::ZERO;
            for b in 0..=pv {
                row += self.hom(su - pu + a, sv - pv + b) * nv[b];
            }
            s += row * nu[a];
        }
        s.truncate() / s.w
    }

    /// Point and partials up to second order (The NURBS Book A3.6 and, for
    /// rational surfaces, A4.4).
    pub fn derivs(&self, u: f64, v: f64) -> SurfaceDerivs {
        let (pu, pv) = (self.degree_u(), self.degree_v());
        let su = self.knots_u.find_span(u);
        let sv = self.knots_v.find_span(v);
        let mut du = [[0.0; MAX_ORDER]; 3];
        let mut dv = [[0.0; MAX_ORDER]; 3];
        ders_basis_funs(self.knots_u.values(), su, self.knots_u.clamp(u), pu, &mut du);
        ders_basis_funs(self.knots_v.values(), sv, self.knots_v.clamp(v), pv, &mut dv);
        // a[k][l] = ∂^{k+l} Aw / ∂u^k ∂v^l
        let mut a = [[DVec4::ZERO; 3]; 3];
        for ia in 0..=pu {
            let mut tmp = [DVec4::ZERO; 3];
            for jb in 0..=pv {
                let h = self.hom(su - pu + ia, sv - pv + jb);
                for l in 0..3 {
                    tmp[l] += h * dv[l][jb];
                }
            }
            for k in 0..3 {
                for l in 0..3 - k {
                    a[k][l] += tmp[l] * du[k][ia];
                }
            }
        }
        let s = if self.weights.is_none() {
            let t = |x: DVec4| x.truncate();
            [
                [t(a[0][0]), t(a[0][1]), t(a[0][2])],
                [t(a[1][0]), t(a[1][1]), DVec3::ZERO],
                [t(a[2][0]), DVec3::ZERO, DVec3::ZERO],
            ]
        } else {
            rational_surface_derivs(&a)
        };
        SurfaceDerivs {
            p: s[0][0],
            su: s[1][0],
            sv: s[0][1],
            suu: s[2][0],
            suv: s[1][1],
            svv: s[0][2],
        }
    }

    /// Unit normal `Su × Sv / |Su × Sv|`.
    pub fn normal(&self, u: f64, v: f64) -> DVec3 {
        let d = self.derivs(u, v);
        d.su.cross(d.sv).normalize_or(DVec3::NAN)
    }

    /// Normal and curvatures at (u, v).
    pub fn curvature(&self, u: f64, v: f64) -> SurfaceCurvature {
        self.derivs(u, v).curvature()
    }

    /// The u-isocurve at fixed `v`: a curve over u with knot vector U and
    /// control points `Σ_j N_j(v) d_ij` (rational: in homogeneous form).
    pub fn iso_u(&self, v: f64) -> BSplineCurve {
        let pv = self.degree_v();
        let sv = self.knots_v.find_span(v);
        let mut nv = [0.0; MAX_ORDER];
        basis_funs(self.knots_v.values(), sv, self.knots_v.clamp(v), pv, &mut nv);
        let h: Vec<DVec4> = (0..self.nu)
            .map(|i| (0..=pv).map(|b| self.hom(i, sv - pv + b) * nv[b]).sum())
            .collect();
        self.curve_from_hom(self.knots_u.clone(), h)
    }

    /// The v-isocurve at fixed `u`: a curve over v with knot vector V.
    pub fn iso_v(&self, u: f64) -> BSplineCurve {
        let pu = self.degree_u();
        let su = self.knots_u.find_span(u);
        let mut nu = [0.0; MAX_ORDER];
        basis_funs(self.knots_u.values(), su, self.knots_u.clamp(u), pu, &mut nu);
        let h: Vec<DVec4> = (0..self.nv)
            .map(|j| (0..=pu).map(|a| self.hom(su - pu + a, j) * nu[a]).sum())
            .collect();
        self.curve_from_hom(self.knots_v.clone(), h)
    }

    fn curve_from_hom(&self, knots: KnotVector, h: Vec<DVec4>) -> BSplineCurve {
        let (points, weights) = if self.weights.is_some() {
            (
                h.iter().map(|x| x.truncate() / x.w).collect(),
                Some(h.iter().map(|x| x.w).collect()),
            )
        } else {
            (h.iter().map(|x| x.truncate()).collect(), None)
        };
        BSplineCurve::try_new(knots.degree(), knots.values().to_vec(), points, weights, 3)
            .expect("an isocurve of a valid surface is valid")
    }
}

/// Rational surface derivatives (The NURBS Book eq. 4.20 / A4.4) up to order 2.
fn rational_surface_derivs(a: &[[DVec4; 3]; 3]) -> [[DVec3; 3]; 3] {
    const BIN: [[f64; 3]; 3] = [[1., 0., 0.], [1., 1., 0.], [1., 2., 1.]];
    let w = |k: usize, l: usize| a[k][l].w;
    let mut s = [[DVec3::ZERO; 3]; 3];
    for k in 0..3 {
        for l in 0..3 - k {
            let mut v = a[k][l].truncate();
            for j in 1..=l {
                v -= s[k][l - j] * (BIN[l][j] * w(0, j));
            }
            for i in 1..=k {
                v -= s[k - i][l] * (BIN[k][i] * w(i, 0));
                let mut v2 = DVec3::ZERO;
                for j in 1..=l {
                    v2 += s[k - i][l - j] * (BIN[l][j] * w(i, j));
                }
                v -= v2 * BIN[k][i];
            }
            s[k][l] = v / w(0, 0);
        }
    }
    s
}
