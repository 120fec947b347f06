//! Least-squares tensor-product B-spline surface fit to grid data with the
//! original knot vectors, a block of free control points (all others held)
//! and an optional separable smoothing term.
//!
//! Data: points `x_kl` at parameters `(u_k, v_l)` on a grid (`k` over u,
//! `l` over v). With the basis matrices `A_ki = N_i(u_k)`, `B_lj = M_j(v_l)`
//! the surface at the data is `A D Bᵀ` (D the `nu × nv` control net), and the
//! fit minimises
//!
//! ```text
//! ‖A D Bᵀ − X‖² + λu⟨Gu D, D BᵀB⟩ + λv⟨AᵀA D, D Gv⟩ + λu λv⟨Gu D, D Gv⟩
//!   = ⟨Pu D Pv, D⟩ − 2⟨AᵀX B, D⟩ + const,   Pu = AᵀA + λu Gu,  Pv = BᵀB + λv Gv,
//! ```
//!
//! with `G_ij = ∫ N_i^{(r)} N_j^{(r)}` the derivative Gram matrices
//! ([`crate::fit::derivative_gram`]). The λu term is `Σ_l ∫ |∂ᵣS/∂uʳ(u, v_l)|² du`
//! (the r-th derivative energy of the data's u-isocurves), the λv term the same in v,
//! and the product term `∫∫ |∂^{2r}S/∂uʳ∂vʳ|²`: a separable (Kronecker) penalty, so
//! the problem stays separable.
//!
//! Only the control points of a rectangular block `D_f` (rows `free_u`, columns
//! `free_v`) move; the others, `D_b`, keep their values. Setting the gradient
//! with respect to `D_f` to zero gives the exact normal equations
//!
//! ```text
//! Pu_ff · D_f · Pv_ff = [AᵀX B − Pu D_b Pv]_ff
//! ```
//!
//! which are solved as two sets of banded 1D systems (Cholesky of the banded
//! `Pu_ff` then `Pv_ff`, bandwidth p): O(data · p) to assemble,
//! O(nu·nv·p) to solve. This is the tensor-product least squares of
//! The NURBS Book §9.4.1 made separable, as in Dierckx, *Curve and Surface
//! Fitting with Splines* (1993), §10.2.

use std::borrow::Cow;
use std::ops::Range;
use std::sync::OnceLock;

use glam::DVec3;

use crate::basis::{MAX_ORDER, basis_funs};
use crate::error::{Error, Result};
use crate::fit::derivative_gram;
use crate::knots::KnotVector;
use crate::linalg::BandedSpd;
use crate::surface::BSplineSurface;

/// Smoothing of a surface fit: dimensionless strengths, scaled internally by
/// `trace(AᵀA) / trace(G)` in each direction so that a strength of 1 weighs
/// the derivative energy like the data term, whatever the parameterization
/// and sample count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceSmoothing {
    /// Strength of the u-derivative term (0 = none).
    pub strength_u: f64,
    /// Strength of the v-derivative term (0 = none).
    pub strength_v: f64,
    /// Derivative order r (2 = bending, 3 = curvature variation).
    pub order: usize,
}

impl SurfaceSmoothing {
    /// No smoothing.
    pub const NONE: Self = Self {
        strength_u: 0.0,
        strength_v: 0.0,
        order: 2,
    };
}

/// The control-point indices, in one direction, whose support lies inside
/// `[a, b]`: basis function `i` is free iff `[t_i, t_{i+p+1}] ⊂ [a, b]`.
///
/// Moving only those keeps the surface outside the region exactly as it was,
/// and, since a basis function is `C^{p−k}` at a knot of multiplicity k, the
/// change joins the untouched part with `C^{p−1}` continuity (G2 for cubics at
/// simple knots). Empty when the region holds fewer than p + 1 knot spans.
pub fn free_range(knots: &KnotVector, a: f64, b: f64) -> Range<usize> {
    let n = knots.n_points();
    let mut lo = n;
    let mut hi = 0;
    for i in 0..n {
        let (s0, s1) = knots.support(i);
        if s0 >= a && s1 <= b {
            lo = lo.min(i);
            hi = hi.max(i + 1);
        }
    }
    if lo >= hi { 0..0 } else { lo..hi }
}

/// Basis values of one direction at the data parameters: span and p + 1 values each.
struct Basis1 {
    spans: Vec<usize>,
    vals: Vec<[f64; MAX_ORDER]>,
    p: usize,
}

impl Basis1 {
    fn new(knots: &KnotVector, params: &[f64]) -> Self {
        let p = knots.degree();
        let mut spans = Vec::with_capacity(params.len());
        let mut vals = Vec::with_capacity(params.len());
        for &t in params {
            let s = knots.find_span(t);
            let mut nb = [0.0; MAX_ORDER];
            basis_funs(knots.values(), s, knots.clamp(t), p, &mut nb);
            spans.push(s);
            vals.push(nb);
        }
        Self { spans, vals, p }
    }

    /// `AᵀA` (full size, banded).
    fn gram(&self, n: usize) -> BandedSpd {
        let p = self.p;
        let mut a = BandedSpd::zeros(n, p);
        for (s, nb) in self.spans.iter().zip(&self.vals) {
            for i in 0..=p {
                for j in 0..=i {
                    a.add(s - p + i, s - p + j, nb[i] * nb[j]);
                }
            }
        }
        a
    }
}

/// `P = AᵀA + λ G` with λ = strength · tr(AᵀA)/tr(G) (`gram`: the derivative Gram matrix G, asked for
/// only when the strength is positive).
fn normal_matrix<'a>(ata: &BandedSpd, strength: f64, gram: impl FnOnce() -> Cow<'a, BandedSpd>) -> BandedSpd {
    let mut a = ata.clone();
    if strength > 0.0 {
        let (n, p) = (a.n(), a.bandwidth());
        let g = gram();
        let tr_a: f64 = (0..n).map(|i| a.get(i, i)).sum();
        let tr_g: f64 = (0..n).map(|i| g.get(i, i)).sum();
        if tr_g > 0.0 {
            let lambda = strength * tr_a / tr_g;
            for i in 0..n {
                for j in i.saturating_sub(p)..=i {
                    a.add(i, j, lambda * g.get(i, j));
                }
            }
        }
    }
    a
}

fn sub_matrix(a: &BandedSpd, r: &Range<usize>) -> BandedSpd {
    let bw = a.bandwidth();
    let mut s = BandedSpd::zeros(r.len(), bw);
    for i in 0..r.len() {
        for j in i.saturating_sub(bw)..=i {
            s.add(i, j, a.get(r.start + i, r.start + j));
        }
    }
    s
}

/// Fit the control net of `base` (its knots, degrees and the held control
/// points) to grid data, moving only the block `free_u × free_v`.
///
/// * `us`, `vs`: the data parameters (any order, inside the domain);
/// * `data`: `us.len() × vs.len()` points, row-major (`data[k * vs.len() + l]` at `(us[k], vs[l])`);
/// * returns the full row-major control net (held points bit-for-bit unchanged).
///
/// Rational surfaces are rejected (convert with [`BSplineSurface::to_polynomial`]).
/// Fails with [`Error::Solve`] when a free control point has too little data in
/// its support and no smoothing determines it.
pub fn fit_surface_grid(
    base: &BSplineSurface,
    us: &[f64],
    vs: &[f64],
    data: &[DVec3],
    free_u: Range<usize>,
    free_v: Range<usize>,
    smoothing: SurfaceSmoothing,
) -> Result<Vec<DVec3>> {
    let fit = GridFit::new(base, us, vs, free_u, free_v)?;
    let rhs = fit.project(data)?;
    fit.solve(&rhs, smoothing)
}

/// The least-squares bicubic graph `z = f(u, v)` over `[0, 1]²` with an `n × n` net (n ≥ 4) and
/// uniform knots, fitted to `4n × 4n` samples: a quick test or demo surface of known shape.
pub fn fit_graph(n: usize, f: impl Fn(f64, f64) -> f64) -> Result<BSplineSurface> {
    let k = KnotVector::uniform(3, n)?;
    let base = BSplineSurface::try_new(
        3,
        3,
        k.values().to_vec(),
        k.values().to_vec(),
        n,
        n,
        vec![DVec3::ZERO; n * n],
        None,
    )?;
    let g: Vec<f64> = (0..4 * n).map(|i| i as f64 / (4 * n - 1) as f64).collect();
    let data: Vec<DVec3> = g
        .iter()
        .flat_map(|&u| g.iter().map(move |&v| (u, v)))
        .map(|(u, v)| DVec3::new(u, v, f(u, v)))
        .collect();
    let pts = fit_surface_grid(&base, &g, &g, &data, 0..n, 0..n, SurfaceSmoothing::NONE)?;
    base.with_points(pts)
}

/// [`fit_surface_grid`] split in its parts, for fitting several data sets or smoothing strengths on the
/// same grid: the bases and `AᵀA` once ([`Self::new`]), the data term `[AᵀX B]_ff` once per data set
/// ([`Self::project`]), then one banded solve per smoothing ([`Self::solve`]). The results are
/// bit-identical to [`fit_surface_grid`].
pub struct GridFit<'a> {
    base: &'a BSplineSurface,
    mu: usize,
    mv: usize,
    bu: Basis1,
    bv: Basis1,
    ata_u: BandedSpd,
    ata_v: BandedSpd,
    /// Derivative Gram matrices (u, v) with their order, computed on the first smoothed solve.
    gram: [OnceLock<(usize, BandedSpd)>; 2],
    free_u: Range<usize>,
    free_v: Range<usize>,
}

impl<'a> GridFit<'a> {
    /// Prepare the fit of `base`'s block `free_u × free_v` to data at the grid `us × vs` (see
    /// [`fit_surface_grid`] for the arguments and the errors).
    pub fn new(
        base: &'a BSplineSurface,
        us: &[f64],
        vs: &[f64],
        free_u: Range<usize>,
        free_v: Range<usize>,
    ) -> Result<Self> {
        if base.is_rational() {
            return Err(Error::InvalidInput(
                "surface fit: the surface is rational; convert it (equal weights) or fair a non-rational surface"
                    .into(),
            ));
        }
        let (nu, nv) = (base.nu(), base.nv());
        if free_u.end > nu || free_v.end > nv {
            return Err(Error::InvalidInput(format!(
                "surface fit: free block {free_u:?} × {free_v:?} outside the {nu} × {nv} control net"
            )));
        }
        if let Some(k) = us.iter().chain(vs).position(|t| !t.is_finite()) {
            return Err(Error::NotFinite {
                field: "surface fit parameters".into(),
                index: k,
            });
        }
        let bu = Basis1::new(base.knots_u(), us);
        let bv = Basis1::new(base.knots_v(), vs);
        let (ata_u, ata_v) = (bu.gram(nu), bv.gram(nv));
        Ok(Self {
            base,
            mu: us.len(),
            mv: vs.len(),
            bu,
            bv,
            ata_u,
            ata_v,
            gram: [OnceLock::new(), OnceLock::new()],
            free_u,
            free_v,
        })
    }

    /// The data term `[AᵀX B]_ff` of `data` (`us.len() × vs.len()` points, row-major), row-major over
    /// the free block.
    pub fn project(&self, data: &[DVec3]) -> Result<Vec<DVec3>> {
        let (mu, mv) = (self.mu, self.mv);
        let nv = self.base.nv();
        if data.len() != mu * mv {
            return Err(Error::LengthMismatch {
                field: "surface fit data".into(),
                count: data.len(),
                expected: mu * mv,
            });
        }
        if let Some(k) = data.iter().position(|p| !p.is_finite()) {
            return Err(Error::NotFinite {
                field: "surface fit data".into(),
                index: k,
            });
        }
        let (free_u, free_v) = (&self.free_u, &self.free_v);
        let (nfu, nfv) = (free_u.len(), free_v.len());
        if nfu == 0 || nfv == 0 {
            return Ok(Vec::new());
        }
        let (pu, pv) = (self.bu.p, self.bv.p);
        let (bu, bv) = (&self.bu, &self.bv);
        // T = X B (mu × nv), then C = Aᵀ T restricted to the free block.
        let mut t = vec![DVec3::ZERO; mu * nv];
        for k in 0..mu {
            let row = &data[k * mv..(k + 1) * mv];
            let trow = &mut t[k * nv..(k + 1) * nv];
            for (l, x) in row.iter().enumerate() {
                let (s, nb) = (bv.spans[l], &bv.vals[l]);
                for b in 0..=pv {
                    trow[s - pv + b] += *x * nb[b];
                }
            }
        }
        let mut rhs = vec![DVec3::ZERO; nfu * nfv]; // row-major over the free block
        for k in 0..mu {
            let (s, nb) = (bu.spans[k], &bu.vals[k]);
            for a in 0..=pu {
                let i = s - pu + a;
                if !free_u.contains(&i) {
                    continue;
                }
                let r = &mut rhs[(i - free_u.start) * nfv..(i - free_u.start + 1) * nfv];
                for (jj, x) in r.iter_mut().enumerate() {
                    *x += t[k * nv + free_v.start + jj] * nb[a];
                }
            }
        }
        Ok(rhs)
    }

    /// The derivative Gram matrix of direction `dir` (0 = u) and `order`: cached for the first order asked.
    fn gram(&self, dir: usize, order: usize) -> Cow<'_, BandedSpd> {
        let knots = if dir == 0 {
            self.base.knots_u()
        } else {
            self.base.knots_v()
        };
        let (o, g) = self.gram[dir].get_or_init(|| (order, derivative_gram(knots, order)));
        if *o == order {
            Cow::Borrowed(g)
        } else {
            Cow::Owned(derivative_gram(knots, order))
        }
    }

    /// The free block's size (rows, columns), `None` if it is empty (nothing to solve); an error if the
    /// data term `rhs` (named `what` in the message) does not have one entry per free point.
    fn free_block(&self, rhs: &[DVec3], what: &str) -> Result<Option<(usize, usize)>> {
        let (nfu, nfv) = (self.free_u.len(), self.free_v.len());
        if nfu == 0 || nfv == 0 {
            return Ok(None);
        }
        if rhs.len() != nfu * nfv {
            return Err(Error::LengthMismatch {
                field: what.into(),
                count: rhs.len(),
                expected: nfu * nfv,
            });
        }
        Ok(Some((nfu, nfv)))
    }

    /// Solve for the free block with `smoothing`, given the data term `rhs` of [`Self::project`];
    /// returns the full row-major control net (held points bit-for-bit unchanged).
    pub fn solve(&self, rhs: &[DVec3], smoothing: SurfaceSmoothing) -> Result<Vec<DVec3>> {
        let base = self.base;
        let (nu, nv) = (base.nu(), base.nv());
        let (free_u, free_v) = (&self.free_u, &self.free_v);
        let mut out = base.points().to_vec();
        let Some((nfu, nfv)) = self.free_block(rhs, "surface fit data term")? else {
            return Ok(out);
        };
        let (pu, pv) = (self.bu.p, self.bv.p);
        let full_u = normal_matrix(&self.ata_u, smoothing.strength_u, || self.gram(0, smoothing.order));
        let full_v = normal_matrix(&self.ata_v, smoothing.strength_v, || self.gram(1, smoothing.order));
        let mut rhs = rhs.to_vec();
        // subtract [Pu D_b Pv]_ff, D_b = net with the free block zeroed: W = D_b Pv (only
        // free columns needed), then Pu W (only free rows).
        let mut db = base.points().to_vec();
        for i in free_u.clone() {
            for j in free_v.clone() {
                db[i * nv + j] = DVec3::ZERO;
            }
        }
        let mut w = vec![DVec3::ZERO; nu * nfv];
        for i in 0..nu {
            for (jj, j) in free_v.clone().enumerate() {
                let mut s = DVec3::ZERO;
                for jb in j.saturating_sub(pv)..(j + pv + 1).min(nv) {
                    s += db[i * nv + jb] * full_v.get(jb, j);
                }
                w[i * nfv + jj] = s;
            }
        }
        for (ii, i) in free_u.clone().enumerate() {
            for ib in i.saturating_sub(pu)..(i + pu + 1).min(nu) {
                let c = full_u.get(i, ib);
                if c == 0.0 {
                    continue;
                }
                for jj in 0..nfv {
                    rhs[ii * nfv + jj] -= w[ib * nfv + jj] * c;
                }
            }
        }
        // solve Pu_ff Y = RHS (columns), then Pv_ff Dᵀ = Yᵀ (rows)
        let underdetermined = |dir: &str| {
            Error::Solve(format!(
                "surface fit: too few data points in the support of some free control points in {dir}; \
                 use more samples per knot span or a smoothing term"
            ))
        };
        let mut su = sub_matrix(&full_u, free_u);
        su.factor().map_err(|_| underdetermined("u"))?;
        let mut sv = sub_matrix(&full_v, free_v);
        sv.factor().map_err(|_| underdetermined("v"))?;
        let mut col = vec![DVec3::ZERO; nfu];
        for jj in 0..nfv {
            for ii in 0..nfu {
                col[ii] = rhs[ii * nfv + jj];
            }
            su.solve_in_place(&mut col);
            for ii in 0..nfu {
                rhs[ii * nfv + jj] = col[ii];
            }
        }
        for ii in 0..nfu {
            sv.solve_in_place(&mut rhs[ii * nfv..(ii + 1) * nfv]);
            for jj in 0..nfv {
                out[(free_u.start + ii) * nv + free_v.start + jj] = rhs[ii * nfv + jj];
            }
        }
        Ok(out)
    }
}

/// `[X D_b Y]_ff`: the symmetric banded `X` (u) and `Y` (v) applied to the net `db` (row-major,
/// `nu × nv`), restricted to the free block (row-major over it).
fn kron_apply(
    x: &BandedSpd,
    y: &BandedSpd,
    db: &[DVec3],
    nv: usize,
    free_u: &Range<usize>,
    free_v: &Range<usize>,
) -> Vec<DVec3> {
    let nu = db.len() / nv.max(1);
    let (pu, pv) = (x.bandwidth(), y.bandwidth());
    let nfv = free_v.len();
    let mut w = vec![DVec3::ZERO; nu * nfv];
    for i in 0..nu {
        for (jj, j) in free_v.clone().enumerate() {
            let mut s = DVec3::ZERO;
            for jb in j.saturating_sub(pv)..(j + pv + 1).min(nv) {
                s += db[i * nv + jb] * y.get(jb, j);
            }
            w[i * nfv + jj] = s;
        }
    }
    let mut out = vec![DVec3::ZERO; free_u.len() * nfv];
    for (ii, i) in free_u.clone().enumerate() {
        for ib in i.saturating_sub(pu)..(i + pu + 1).min(nu) {
            let c = x.get(i, ib);
            if c == 0.0 {
                continue;
            }
            for jj in 0..nfv {
                out[ii * nfv + jj] += w[ib * nfv + jj] * c;
            }
        }
    }
    out
}

/// Tensor-product penalized least squares with a rotation-invariant derivative energy: the surface
/// counterpart of the curve reference smoother. On the data grid of a [`GridFit`] it minimises
///
/// ```text
/// ‖A D Bᵀ − X‖² + λ Σ_{k=0..r} C(r, k) ∫∫ |∂ʳS/∂xʳ⁻ᵏ∂yᵏ|² dx dy
/// ```
///
/// with `x = L_u u`, `y = L_v v` (`L_u`, `L_v` the mean speeds `|S_u|`, `|S_v|`, so that the energy is
/// that of the surface's shape, not of its parameterization): for r = 2 the thin-plate energy
/// `∫∫ S_xx² + 2 S_xy² + S_yy²`, for r = 3 the curvature-variation energy
/// `∫∫ S_xxx² + 3 S_xxy² + 3 S_xyy² + S_yyy²`. Each term is a Kronecker product of 1D derivative
/// Gram matrices (`G_{r−k} ⊗ G_k`), but their sum is not separable, so the free block is solved as one
/// banded system (unknowns ordered along the shorter side of the block, bandwidth `p·(short side) + p`):
/// O(n · bw²) per strength. λ = `strength · tr(AᵀA ⊗ BᵀB) / tr(energy)` (dimensionless, as
/// [`SurfaceSmoothing`]).
pub struct PlateFit<'g, 'a> {
    grid: &'g GridFit<'a>,
    /// Energy terms: weight and the u and v Gram matrices.
    terms: Vec<(f64, BandedSpd, BandedSpd)>,
    /// `tr(data) / tr(energy)`.
    norm: f64,
    /// A large system's pattern and its symbolic sparse Cholesky (ordering, elimination tree, supernodes),
    /// made on the first factorization and shared by all strengths ([`SPARSE_PLATE_MIN`]); `None` if the
    /// analysis failed (the banded factor is used then).
    sparse: OnceLock<Option<SparsePattern>>,
}

/// Free control points from which a plate system is factored as a sparse matrix (supernodal Cholesky
/// after an approximate-minimum-degree ordering, `faer`) instead of a banded one. The banded factor costs
/// O(n · bw²) with the bandwidth bw ≈ p · √n of a square block; the sparse one about O(n^1.5), plus an
/// analysis of the pattern once per fit. Measured on this project's 2-core host (whole bicubic nets, one
/// thread, per factorization after the first; the first, with the analysis, 2–10 ms): 400 / 529 unknowns
/// banded 0.36 / 0.57 ms against sparse 0.62 / 1.28 ms; 676 / 900: 0.87–1.5 / 1.4–2.4 against 0.53 / 0.85–1.2;
/// 1,225 / 1,600 / 2,500: 2.5–4.0 / 4.1 / 9.3 against 1.3–1.7 / 1.9 / 3.8; 9,409 (a 100 × 100 net): 112–130
/// against 26–37 ms. Below this size (the quality suite's 16 × 16 nets, the 30 × 30 bench net, the tests'
/// nets) the gain would not pay for the analysis, and the banded factor stays.
pub const SPARSE_PLATE_MIN: usize = 1024;

/// The sparsity pattern of a large plate system (upper triangle by columns = lower by rows) with the
/// control-point pairs of its entries, and its symbolic factorization.
struct SparsePattern {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Per entry: the u pair and the v pair of control points (i, i2, j, j2) whose coupling it holds.
    pairs: Vec<[u32; 4]>,
    symbolic: faer::sparse::linalg::solvers::SymbolicLlt<usize>,
}

impl<'g, 'a> PlateFit<'g, 'a> {
    /// The energy of order `order` (2 or 3) with the length scales `lu`, `lv` (> 0, finite) of u and v.
    pub fn new(grid: &'g GridFit<'a>, order: usize, lu: f64, lv: f64) -> Result<Self> {
        if !(order == 2 || order == 3) {
            return Err(Error::InvalidInput(format!(
                "surface smoothing: energy order {order} (expected 2, thin plate, or 3, curvature variation)"
            )));
        }
        if !(lu.is_finite() && lv.is_finite() && lu > 0.0 && lv > 0.0) {
            return Err(Error::Degenerate(format!(
                "surface smoothing: the surface has no extent along u or v (mean speeds {lu}, {lv})"
            )));
        }
        let (ku, kv) = (grid.base.knots_u(), grid.base.knots_v());
        let binom = |n: usize, k: usize| (0..k).fold(1.0, |c, i| c * (n - i) as f64 / (i + 1) as f64);
        let trace = |g: &BandedSpd| (0..g.n()).map(|i| g.get(i, i)).sum::<f64>();
        let mut terms = Vec::with_capacity(order + 1);
        let mut tr_e = 0.0;
        for k in 0..=order {
            let w = binom(order, k) / (lu.powi(2 * (order - k) as i32) * lv.powi(2 * k as i32));
            let (gu, gv) = (derivative_gram(ku, order - k), derivative_gram(kv, k));
            tr_e += w * trace(&gu) * trace(&gv);
            terms.push((w, gu, gv));
        }
        let tr_d = trace(&grid.ata_u) * trace(&grid.ata_v);
        let norm = if tr_e > 0.0 { tr_d / tr_e } else { 0.0 };
        Ok(Self {
            grid,
            terms,
            norm,
            sparse: OnceLock::new(),
        })
    }

    /// Solve for the free block with the dimensionless `strength` (≥ 0), given the data term `rhs` of
    /// [`GridFit::project`]; returns the full row-major control net (held points bit-for-bit unchanged).
    pub fn solve(&self, rhs: &[DVec3], strength: f64) -> Result<Vec<DVec3>> {
        self.check_strength(strength)?;
        if self.grid.free_block(rhs, "surface smoothing data term")?.is_none() {
            return Ok(self.grid.base.points().to_vec());
        }
        self.solve_factored(&self.factor(strength)?, rhs)
    }

    fn check_strength(&self, strength: f64) -> Result<()> {
        if !(strength.is_finite() && strength >= 0.0) {
            return Err(Error::InvalidInput(format!(
                "surface smoothing: strength {strength} (expected a finite value ≥ 0)"
            )));
        }
        Ok(())
    }

    /// The weighted terms of the system at `strength`: the data term, then the energy's if λ > 0.
    fn weighted_terms(&self, strength: f64) -> Vec<(f64, &BandedSpd, &BandedSpd)> {
        let g = self.grid;
        let lambda = strength * self.norm;
        let mut terms: Vec<(f64, &BandedSpd, &BandedSpd)> = vec![(1.0, &g.ata_u, &g.ata_v)];
        if lambda > 0.0 {
            terms.extend(self.terms.iter().map(|(w, a, b)| (lambda * w, a, b)));
        }
        terms
    }

    /// The factored system of the free block at the dimensionless `strength` (≥ 0), for
    /// [`Self::solve_factored`]: the matrix does not depend on the data, so one factorization serves every
    /// data set at that strength ([`Self::solve`] = `factor` then `solve_factored`, bit for bit).
    pub fn factor(&self, strength: f64) -> Result<PlateFactor> {
        self.check_strength(strength)?;
        let n = self.grid.free_u.len() * self.grid.free_v.len();
        // the banded factor also where the sparse analysis failed (it allocates the symbolic factor: out of
        // memory is its only failure on a valid pattern)
        if n >= SPARSE_PLATE_MIN
            && let Some(pat) = self.sparse.get_or_init(|| self.sparse_pattern())
        {
            return self.factor_sparse(pat, strength, n);
        }
        self.factor_banded(strength)
    }

    /// [`Self::factor`] as one banded system (unknowns along the shorter side of the block).
    fn factor_banded(&self, strength: f64) -> Result<PlateFactor> {
        let g = self.grid;
        let (free_u, free_v) = (&g.free_u, &g.free_v);
        let (nfu, nfv) = (free_u.len(), free_v.len());
        let (pu, pv) = (g.bu.p, g.bv.p);
        let terms = self.weighted_terms(strength);
        // unknown index of free point (ii, jj): along the shorter side, for the smaller bandwidth
        let u_major = nfv <= nfu;
        let idx = |ii: usize, jj: usize| if u_major { ii * nfv + jj } else { jj * nfu + ii };
        let bw = if u_major { pu * nfv + pv } else { pv * nfu + pu };
        let n = nfu * nfv;
        let mut k = BandedSpd::zeros(n, bw.min(n.saturating_sub(1)));
        for ii in 0..nfu {
            let i = free_u.start + ii;
            for ii2 in ii.saturating_sub(pu)..(ii + pu + 1).min(nfu) {
                let i2 = free_u.start + ii2;
                for jj in 0..nfv {
                    let j = free_v.start + jj;
                    let (r, c0) = (idx(ii, jj), jj.saturating_sub(pv));
                    for jj2 in c0..(jj + pv + 1).min(nfv) {
                        let c = idx(ii2, jj2);
                        if c > r {
                            continue;
                        }
                        let j2 = free_v.start + jj2;
                        let v: f64 = terms.iter().map(|(w, x, y)| w * x.get(i, i2) * y.get(j, j2)).sum();
                        if v != 0.0 {
                            k.add(r, c, v);
                        }
                    }
                }
            }
        }
        k.factor().map_err(|_| {
            Error::Solve(
                "surface smoothing: the system is singular (too few data points in the support of some free \
                 control points and no smoothing)"
                    .into(),
            )
        })?;
        Ok(PlateFactor {
            strength,
            k: PlateSystem::Banded(k),
        })
    }

    /// The pattern of the free block's system (entries (r, c), c ≤ r, by r then c, in the unknown order
    /// of [`Self::factor`]) with its symbolic factorization; `None` if that fails.
    fn sparse_pattern(&self) -> Option<SparsePattern> {
        let g = self.grid;
        let (free_u, free_v) = (&g.free_u, &g.free_v);
        let (nfu, nfv) = (free_u.len(), free_v.len());
        let (pu, pv) = (g.bu.p, g.bv.p);
        let u_major = nfv <= nfu;
        let idx = |ii: usize, jj: usize| if u_major { ii * nfv + jj } else { jj * nfu + ii };
        let n = nfu * nfv;
        let mut rows: Vec<Vec<(usize, [u32; 4])>> = vec![Vec::new(); n];
        for ii in 0..nfu {
            for ii2 in ii.saturating_sub(pu)..(ii + pu + 1).min(nfu) {
                for jj in 0..nfv {
                    let r = idx(ii, jj);
                    for jj2 in jj.saturating_sub(pv)..(jj + pv + 1).min(nfv) {
                        let c = idx(ii2, jj2);
                        if c <= r {
                            let at = |x: usize, o: usize| (o + x) as u32;
                            let pair = [
                                at(ii, free_u.start),
                                at(ii2, free_u.start),
                                at(jj, free_v.start),
                                at(jj2, free_v.start),
                            ];
                            rows[r].push((c, pair));
                        }
                    }
                }
            }
        }
        let (mut col_ptr, mut row_idx, mut pairs) = (vec![0usize], Vec::new(), Vec::new());
        for mut row in rows {
            row.sort_unstable_by_key(|e| e.0);
            row_idx.extend(row.iter().map(|e| e.0));
            pairs.extend(row.iter().map(|e| e.1));
            col_ptr.push(row_idx.len());
        }
        let symbolic = {
            let pattern = faer::sparse::SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
            faer::sparse::linalg::solvers::SymbolicLlt::try_new(pattern, faer::Side::Upper).ok()?
        };
        Some(SparsePattern {
            col_ptr,
            row_idx,
            pairs,
            symbolic,
        })
    }

    /// [`Self::factor`] of a large block ([`SPARSE_PLATE_MIN`]): the same matrix, factored sparse.
    fn factor_sparse(&self, pat: &SparsePattern, strength: f64, n: usize) -> Result<PlateFactor> {
        let terms = self.weighted_terms(strength);
        let values: Vec<f64> = (pat.pairs.iter())
            .map(|&[i, i2, j, j2]| {
                let (i, i2, j, j2) = (i as usize, i2 as usize, j as usize, j2 as usize);
                terms.iter().map(|(w, x, y)| w * x.get(i, i2) * y.get(j, j2)).sum()
            })
            .collect();
        let pattern = faer::sparse::SymbolicSparseColMatRef::new_checked(n, n, &pat.col_ptr, None, &pat.row_idx);
        let mat = faer::sparse::SparseColMatRef::new(pattern, &values);
        let llt =
            faer::sparse::linalg::solvers::Llt::try_new_with_symbolic(pat.symbolic.clone(), mat, faer::Side::Upper)
                .map_err(|_| {
                    Error::Solve(
                        "surface smoothing: the system is not positive definite at this strength (rounding at a very \
                     large strength, or too few data points in the support of some free control points)"
                            .into(),
                    )
                })?;
        Ok(PlateFactor {
            strength,
            k: PlateSystem::Sparse(Box::new(llt), n),
        })
    }

    /// [`Self::solve`] with the system `f` of [`Self::factor`] (of this fit).
    pub fn solve_factored(&self, f: &PlateFactor, rhs: &[DVec3]) -> Result<Vec<DVec3>> {
        let g = self.grid;
        let base = g.base;
        let (nu, nv) = (base.nu(), base.nv());
        let (free_u, free_v) = (&g.free_u, &g.free_v);
        let mut out = base.points().to_vec();
        let Some((nfu, nfv)) = g.free_block(rhs, "surface smoothing data term")? else {
            return Ok(out);
        };
        let terms = self.weighted_terms(f.strength);
        let u_major = nfv <= nfu;
        let idx = |ii: usize, jj: usize| if u_major { ii * nfv + jj } else { jj * nfu + ii };
        let n = nfu * nfv;
        if f.k.n() != n {
            return Err(Error::LengthMismatch {
                field: "surface smoothing factor".into(),
                count: f.k.n(),
                expected: n,
            });
        }
        // right-hand side: the data term minus the held points' part, Σ w [X D_b Y]_ff
        let mut db = base.points().to_vec();
        for i in free_u.clone() {
            for j in free_v.clone() {
                db[i * nv + j] = DVec3::ZERO;
            }
        }
        let mut b = vec![DVec3::ZERO; n];
        for (ii, jj) in (0..nfu).flat_map(|ii| (0..nfv).map(move |jj| (ii, jj))) {
            b[idx(ii, jj)] = rhs[ii * nfv + jj];
        }
        for (w, x, y) in &terms {
            let held = kron_apply(x, y, &db, nv, free_u, free_v);
            for (ii, jj) in (0..nfu).flat_map(|ii| (0..nfv).map(move |jj| (ii, jj))) {
                b[idx(ii, jj)] -= held[ii * nfv + jj] * *w;
            }
        }
        f.k.solve_in_place(&mut b);
        debug_assert_eq!(out.len(), nu * nv);
        for (ii, jj) in (0..nfu).flat_map(|ii| (0..nfv).map(move |jj| (ii, jj))) {
            out[(free_u.start + ii) * nv + free_v.start + jj] = b[idx(ii, jj)];
        }
        Ok(out)
    }
}

/// The factored system of a [`PlateFit`] at one strength ([`PlateFit::factor`]).
#[derive(Debug, Clone)]
pub struct PlateFactor {
    strength: f64,
    k: PlateSystem,
}

/// A factored plate system: banded, or sparse for a large block ([`SPARSE_PLATE_MIN`]).
#[derive(Debug, Clone)]
enum PlateSystem {
    Banded(BandedSpd),
    Sparse(Box<faer::sparse::linalg::solvers::Llt<usize, f64>>, usize),
}

impl PlateSystem {
    fn n(&self) -> usize {
        match self {
            Self::Banded(k) => k.n(),
            Self::Sparse(_, n) => *n,
        }
    }

    /// Solve in place for the three coordinates.
    fn solve_in_place(&self, b: &mut [DVec3]) {
        match self {
            Self::Banded(k) => k.solve_in_place(b),
            Self::Sparse(llt, n) => {
                use faer::linalg::solvers::SolveCore;
                let mut m = faer::Mat::<f64>::from_fn(*n, 3, |i, c| b[i][c]);
                llt.solve_in_place_with_conj(faer::Conj::No, m.as_mut());
                for (i, x) in b.iter_mut().enumerate() {
                    *x = DVec3::new(m[(i, 0)], m[(i, 1)], m[(i, 2)]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_graph_reproduces_a_quadratic_graph() {
        // a bicubic spline space holds every polynomial of degree ≤ 3 in each variable: exact fit
        let f = |u: f64, v: f64| 0.3 + 0.2 * u - 0.1 * v + 0.5 * u * v - 0.4 * v * v;
        let s = fit_graph(7, f).unwrap();
        for (u, v) in [(0.0, 0.0), (0.13, 0.77), (0.5, 0.5), (0.91, 0.08), (1.0, 1.0)] {
            let p = s.point(u, v);
            assert!((p - DVec3::new(u, v, f(u, v))).length() < 1e-12, "({u}, {v}): {p}");
        }
        assert!(fit_graph(3, f).is_err());
    }

    fn surface(nu: usize, nv: usize, f: impl Fn(f64, f64) -> f64) -> BSplineSurface {
        let ku = KnotVector::uniform(3, nu).unwrap();
        let kv = KnotVector::uniform(3, nv).unwrap();
        let (gu, gv) = (ku.greville(), kv.greville());
        let mut pts = Vec::new();
        for &u in &gu {
            for &v in &gv {
                pts.push(DVec3::new(u, v, f(u, v)));
            }
        }
        BSplineSurface::try_new(3, 3, ku.values().to_vec(), kv.values().to_vec(), nu, nv, pts, None).unwrap()
    }

    fn grid(n: usize) -> Vec<f64> {
        (0..n).map(|k| k as f64 / (n - 1) as f64).collect()
    }

    #[test]
    fn reproduces_a_surface_in_the_space() {
        let s = surface(9, 7, |u, v| (3.0 * u).sin() * v + u * u);
        let (us, vs) = (grid(40), grid(31));
        let data: Vec<DVec3> = us
            .iter()
            .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
            .map(|(u, v)| s.point(u, v))
            .collect();
        // perturb the start net: the fit must recover it exactly
        let moved: Vec<DVec3> = s.points().iter().map(|p| *p + DVec3::new(0.1, -0.2, 0.3)).collect();
        let base = s.with_points(moved).unwrap();
        let out = fit_surface_grid(&base, &us, &vs, &data, 0..9, 0..7, SurfaceSmoothing::NONE).unwrap();
        for (a, b) in out.iter().zip(s.points()) {
            assert!((*a - *b).length() < 1e-10, "{a} {b}");
        }
    }

    #[test]
    fn held_points_unchanged_and_normal_equations_hold() {
        let s = surface(10, 8, |u, v| u * v);
        let (us, vs) = (grid(33), grid(29));
        let data: Vec<DVec3> = us
            .iter()
            .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
            .map(|(u, v)| DVec3::new(u, v, (5.0 * u).cos() * (4.0 * v).sin()))
            .collect();
        let (fu, fv) = (3..7, 2..6);
        let out = fit_surface_grid(&s, &us, &vs, &data, fu.clone(), fv.clone(), SurfaceSmoothing::NONE).unwrap();
        for i in 0..10 {
            for j in 0..8 {
                if !(fu.contains(&i) && fv.contains(&j)) {
                    assert_eq!(out[i * 8 + j], s.points()[i * 8 + j]);
                }
            }
        }
        // gradient of the residual w.r.t. each free point vanishes: Σ N_i M_j (S − x) = 0
        let fitted = s.with_points(out).unwrap();
        let ku = fitted.knots_u().clone();
        let kv = fitted.knots_v().clone();
        for i in fu {
            for j in fv.clone() {
                let mut g = DVec3::ZERO;
                for (k, &u) in us.iter().enumerate() {
                    for (l, &v) in vs.iter().enumerate() {
                        let ni = basis_value(&ku, i, u);
                        let mj = basis_value(&kv, j, v);
                        g += (fitted.point(u, v) - data[k * vs.len() + l]) * ni * mj;
                    }
                }
                assert!(g.length() < 1e-10, "gradient at ({i},{j}) = {g}");
            }
        }
    }

    fn basis_value(k: &KnotVector, i: usize, t: f64) -> f64 {
        let s = k.find_span(t);
        let p = k.degree();
        if i + p < s || i > s {
            return 0.0;
        }
        let mut nb = [0.0; MAX_ORDER];
        basis_funs(k.values(), s, k.clamp(t), p, &mut nb);
        nb[i + p - s]
    }

    #[test]
    fn smoothing_reduces_bending_and_keeps_planes() {
        // plane data with smoothing: a plane has zero second derivative, the fit stays exact
        let s = surface(8, 8, |u, v| 0.3 * u - 0.2 * v);
        let (us, vs) = (grid(25), grid(25));
        let data: Vec<DVec3> = us
            .iter()
            .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
            .map(|(u, v)| s.point(u, v))
            .collect();
        let sm = SurfaceSmoothing {
            strength_u: 0.1,
            strength_v: 0.1,
            order: 2,
        };
        let flat = s.with_points(vec![DVec3::ZERO; 64]).unwrap();
        let out = fit_surface_grid(&flat, &us, &vs, &data, 0..8, 0..8, sm).unwrap();
        for (a, b) in out.iter().zip(s.points()) {
            assert!((*a - *b).length() < 1e-9);
        }
    }

    /// A block of at least [`SPARSE_PLATE_MIN`] free points is factored sparse: its solutions are the
    /// banded factorization's to rounding (1e-10 of the data's size, which is ≈ 1: measured ≤ 5e-12 at
    /// strength 1e6, the conditioning growing with the strength) at strengths from none to large, for
    /// both unknown orders (u- and v-major), with the held points bit for bit kept; data in the energy's
    /// null space is still reproduced at a large strength.
    #[test]
    fn sparse_plate_factor_solves_as_the_banded_one() {
        let s = surface(37, 41, |u, v| 0.2 * (3.0 * u).sin() * (2.0 * v).cos());
        let (us, vs) = (grid(110), grid(124));
        for (fu, fv) in [(2..35, 3..37), (1..36, 2..33)] {
            assert!(fu.len() * fv.len() >= SPARSE_PLATE_MIN);
            let g = GridFit::new(&s, &us, &vs, fu.clone(), fv.clone()).unwrap();
            let data: Vec<DVec3> = us
                .iter()
                .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
                .map(|(u, v)| {
                    DVec3::new(
                        u,
                        v,
                        0.2 * (3.0 * u).sin() * (2.0 * v).cos() + 1e-3 * (37.0 * u * v).sin(),
                    )
                })
                .collect();
            let rhs = g.project(&data).unwrap();
            let plate = PlateFit::new(&g, 3, 1.0, 1.2).unwrap();
            for st in [0.0, 1e-3, 1.0, 1e3, 1e6] {
                let sparse = plate.factor(st).unwrap();
                assert!(matches!(sparse.k, PlateSystem::Sparse(..)));
                let banded = plate.factor_banded(st).unwrap();
                let (a, b) = (
                    plate.solve_factored(&sparse, &rhs).unwrap(),
                    plate.solve_factored(&banded, &rhs).unwrap(),
                );
                let worst = a.iter().zip(&b).map(|(x, y)| x.distance(*y)).fold(0.0, f64::max);
                assert!(worst < 1e-10, "strength {st}: sparse and banded differ by {worst:e}");
                for i in 0..37 {
                    for j in 0..41 {
                        if !(fu.contains(&i) && fv.contains(&j)) {
                            assert_eq!(a[i * 41 + j], s.points()[i * 41 + j]);
                        }
                    }
                }
            }
        }
        let whole = GridFit::new(&s, &us, &vs, 0..37, 0..41).unwrap();
        let f = |u: f64, v: f64| 0.3 * u * u - 0.2 * u * v + 0.4 * v * v - u;
        let quadric: Vec<DVec3> = us
            .iter()
            .flat_map(|&u| vs.iter().map(move |&v| DVec3::new(u, v, f(u, v))))
            .collect();
        let plate = PlateFit::new(&whole, 3, 1.0, 1.0).unwrap();
        let fitted = s
            .with_points(plate.solve(&whole.project(&quadric).unwrap(), 1e4).unwrap())
            .unwrap();
        for (u, v) in [(0.1, 0.2), (0.5, 0.5), (0.9, 0.7)] {
            assert!(
                (fitted.point(u, v) - DVec3::new(u, v, f(u, v))).length() < 1e-8,
                "({u}, {v})"
            );
        }
    }

    #[test]
    fn plate_fit_reduces_to_least_squares_keeps_its_null_space_and_held_points() {
        let s = surface(9, 8, |u, v| u * v);
        let (us, vs) = (grid(30), grid(27));
        let data_of = |f: &dyn Fn(f64, f64) -> f64| -> Vec<DVec3> {
            us.iter()
                .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
                .map(|(u, v)| DVec3::new(u, v, f(u, v)))
                .collect()
        };
        let (fu, fv) = (2..7, 1..6);
        let g = GridFit::new(&s, &us, &vs, fu.clone(), fv.clone()).unwrap();
        let wavy = data_of(&|u, v| (5.0 * u).cos() * (4.0 * v).sin());
        let rhs = g.project(&wavy).unwrap();
        let ls = g.solve(&rhs, SurfaceSmoothing::NONE).unwrap();
        for order in [2, 3] {
            let plate = PlateFit::new(&g, order, 1.0, 1.3).unwrap();
            // strength 0: the plain least-squares fit
            let p0 = plate.solve(&rhs, 0.0).unwrap();
            for (a, b) in p0.iter().zip(&ls) {
                assert!((*a - *b).length() < 1e-10, "order {order}: {a} vs {b}");
            }
            // held points bit for bit, and smoothing lowers the data fit's wiggle: the fitted z varies less
            let p = plate.solve(&rhs, 10.0).unwrap();
            // one factorization serves other data at the same strength, bit for bit as separate solves
            let k = plate.factor(10.0).unwrap();
            let rhs2 = g.project(&data_of(&|u, v| u * u - v)).unwrap();
            assert_eq!(plate.solve_factored(&k, &rhs).unwrap(), p);
            assert_eq!(
                plate.solve_factored(&k, &rhs2).unwrap(),
                plate.solve(&rhs2, 10.0).unwrap()
            );
            assert!(plate.factor(-1.0).is_err() && plate.solve_factored(&k, &rhs2[1..]).is_err());
            for i in 0..9 {
                for j in 0..8 {
                    if !(fu.contains(&i) && fv.contains(&j)) {
                        assert_eq!(p[i * 8 + j], s.points()[i * 8 + j]);
                    }
                }
            }
            let spread = |pts: &[DVec3]| {
                let z: Vec<f64> = fu
                    .clone()
                    .flat_map(|i| fv.clone().map(move |j| pts[i * 8 + j].z))
                    .collect();
                z.iter().fold(f64::MIN, |a, &b| a.max(b)) - z.iter().fold(f64::MAX, |a, &b| a.min(b))
            };
            assert!(spread(&p) < spread(&p0), "order {order}");
        }
        // data in the energy's null space (a plane for the thin plate, a quadric for order 3) on the whole net
        // is reproduced at any strength
        let whole = GridFit::new(&s, &us, &vs, 0..9, 0..8).unwrap();
        for (order, f) in [
            (
                2,
                &(|u: f64, v: f64| 0.3 * u - 0.2 * v + 0.1) as &dyn Fn(f64, f64) -> f64,
            ),
            (3, &|u: f64, v: f64| 0.3 * u * u - 0.2 * u * v + 0.4 * v * v - u),
        ] {
            let data = data_of(f);
            let plate = PlateFit::new(&whole, order, 1.0, 1.0).unwrap();
            let pts = plate.solve(&whole.project(&data).unwrap(), 1e4).unwrap();
            let fitted = s.with_points(pts).unwrap();
            for (u, v) in [(0.1, 0.2), (0.5, 0.5), (0.9, 0.7)] {
                let want = DVec3::new(u, v, f(u, v));
                assert!(
                    (fitted.point(u, v) - want).length() < 1e-8,
                    "order {order} at ({u}, {v})"
                );
            }
        }
        // bad input
        assert!(PlateFit::new(&g, 1, 1.0, 1.0).is_err());
        assert!(PlateFit::new(&g, 3, 0.0, 1.0).is_err());
        assert!(PlateFit::new(&g, 3, f64::NAN, 1.0).is_err());
        let plate = PlateFit::new(&g, 3, 1.0, 1.0).unwrap();
        assert!(plate.solve(&rhs, -1.0).is_err());
        assert!(plate.solve(&rhs, f64::INFINITY).is_err());
        assert!(matches!(plate.solve(&rhs[1..], 1.0), Err(Error::LengthMismatch { .. })));
    }

    #[test]
    fn free_range_of_a_region() {
        let k = KnotVector::uniform(3, 10).unwrap(); // spans of 1/7
        let r = free_range(&k, 1.0 / 7.0, 6.0 / 7.0);
        assert_eq!(r, 4..6); // t_4 = 1/7, t_{5+4} = t_9 = 6/7
        // every free index has support inside, the neighbours not
        for i in r.clone() {
            let (a, b) = k.support(i);
            assert!(a >= 1.0 / 7.0 - 1e-15 && b <= 6.0 / 7.0 + 1e-15);
        }
    }

    #[test]
    fn rejects_bad_input() {
        let s = surface(6, 6, |_, _| 0.0);
        let us = grid(3);
        let e = fit_surface_grid(&s, &us, &us, &[DVec3::ZERO; 9], 0..6, 0..6, SurfaceSmoothing::NONE);
        assert!(matches!(e, Err(Error::Solve(_))), "{e:?}");
        let e = fit_surface_grid(&s, &us, &us, &[DVec3::ZERO; 8], 0..6, 0..6, SurfaceSmoothing::NONE);
        assert!(matches!(e, Err(Error::LengthMismatch { .. })));
    }
}
