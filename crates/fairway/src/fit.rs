//! Least-squares B-spline fitting with a given knot vector and parameters,
//! an optional smoothing term and fixed control points.
//!
//! Minimises `Σ_k w_k |c(t_k) − x_k|² + λ ∫ |c^{(r)}(u)|² du` over the free
//! control points (The NURBS Book §9.4.1 for the least squares; the
//! smoothing Gram matrix `G_ij = ∫ N_i^{(r)} N_j^{(r)} du` is computed
//! exactly by Gauss–Legendre with p + 1 nodes per span). Fixed control points
//! are eliminated: their contribution moves to the right-hand side. The
//! normal equations are banded (bandwidth p) and solved by banded Cholesky
//! in O(n p²).

use glam::DVec3;

use crate::basis::{MAX_ORDER, basis_funs, ders_basis_funs};
use crate::error::{Error, Result};
use crate::knots::KnotVector;
use crate::linalg::BandedSpd;
use crate::quadrature::GaussLegendre;

/// Smoothing term of a fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Smoothing {
    /// Weight λ of the term (0 = none).
    pub lambda: f64,
    /// Derivative order r (1 = length-like, 2 = bending, 3 = curvature variation).
    pub order: usize,
}

impl Smoothing {
    /// No smoothing.
    pub const NONE: Self = Self { lambda: 0.0, order: 2 };
}

/// Banded Gram matrix `G_ij = ∫ N_i^{(r)}(u) N_j^{(r)}(u) du` over the whole domain.
pub fn derivative_gram(knots: &KnotVector, order: usize) -> BandedSpd {
    let p = knots.degree();
    let n = knots.n_points();
    let mut g = BandedSpd::zeros(n, p);
    if order > p {
        return g;
    }
    let gl = GaussLegendre::new(p + 1);
    let kv = knots.values();
    for span in p..n {
        let (a, b) = (kv[span], kv[span + 1]);
        if b <= a {
            continue;
        }
        let h = 0.5 * (b - a);
        for (x, w) in gl.nodes.iter().zip(&gl.weights) {
            let u = 0.5 * (a + b) + h * x;
            let mut d = [[0.0; MAX_ORDER]; 4];
            ders_basis_funs(kv, span, u, p, &mut d);
            for i in 0..=p {
                for j in 0..=i {
                    g.add(span - p + i, span - p + j, w * h * d[order][i] * d[order][j]);
                }
            }
        }
    }
    g
}

/// Fit control points to data `(params[k], targets[k])`.
///
/// * `weights`: per-sample weights `w_k` (all 1 if `None`).
/// * `fixed[i] = Some(p)` keeps control point i at p; `fixed` may be empty (all free).
/// * `smoothing`: the λ-term; λ is scaled by nothing — choose it relative to
///   the data (e.g. the number of samples over the domain length).
///
/// Fails with a clear message when a free control point is not determined
/// (no data in its support and no smoothing).
pub fn fit_curve_points(
    knots: &KnotVector,
    params: &[f64],
    targets: &[DVec3],
    weights: Option<&[f64]>,
    smoothing: Smoothing,
    fixed: &[Option<DVec3>],
) -> Result<Vec<DVec3>> {
    let p = knots.degree();
    let n = knots.n_points();
    if params.len() != targets.len() {
        return Err(Error::LengthMismatch {
            field: "fit targets".into(),
            count: targets.len(),
            expected: params.len(),
        });
    }
    if !fixed.is_empty() && fixed.len() != n {
        return Err(Error::LengthMismatch {
            field: "fit fixed points".into(),
            count: fixed.len(),
            expected: n,
        });
    }
    let is_fixed = |i: usize| !fixed.is_empty() && fixed[i].is_some();
    // compact index of free control points
    let mut map = vec![usize::MAX; n];
    let mut nf = 0;
    for (i, m) in map.iter_mut().enumerate() {
        if !is_fixed(i) {
            *m = nf;
            nf += 1;
        }
    }
    let mut out: Vec<DVec3> = (0..n)
        .map(|i| if is_fixed(i) { fixed[i].unwrap() } else { DVec3::ZERO })
        .collect();
    if nf == 0 {
        return Ok(out);
    }
    let mut a = BandedSpd::zeros(nf, p);
    let mut rhs = vec![DVec3::ZERO; nf];
    let kv = knots.values();
    let mut nb = [0.0; MAX_ORDER];
    for (k, (&t, &x)) in params.iter().zip(targets).enumerate() {
        let w = weights.map_or(1.0, |w| w[k]);
        let span = knots.find_span(t);
        basis_funs(kv, span, knots.clamp(t), p, &mut nb);
        let mut r = x * w;
        for j in 0..=p {
            let gj = span - p + j;
            if is_fixed(gj) {
                r -= out[gj] * (w * nb[j]);
            }
        }
        for i in 0..=p {
            let gi = span - p + i;
            if is_fixed(gi) {
                continue;
            }
            rhs[map[gi]] += r * nb[i];
            for j in 0..=i {
                let gj = span - p + j;
                if !is_fixed(gj) {
                    a.add(map[gi], map[gj], w * nb[i] * nb[j]);
                }
            }
        }
    }
    if smoothing.lambda > 0.0 {
        let g = derivative_gram(knots, smoothing.order);
        for i in 0..n {
            for j in i.saturating_sub(p)..=i {
                let v = smoothing.lambda * g.get(i, j);
                if v == 0.0 {
                    continue;
                }
                match (is_fixed(i), is_fixed(j)) {
                    (false, false) => a.add(map[i], map[j], v),
                    (false, true) => rhs[map[i]] -= out[j] * v,
                    (true, false) => rhs[map[j]] -= out[i] * v,
                    (true, true) => {}
                }
            }
        }
    }
    a.factor().map_err(|_| {
        Error::Solve(format!(
            "the fit is under-determined: some of the {nf} free control points have too few samples in their support; \
             use more samples or a smoothing term"
        ))
    })?;
    a.solve_in_place(&mut rhs);
    for i in 0..n {
        if !is_fixed(i) {
            out[i] = rhs[map[i]];
        }
    }
    Ok(out)
}
