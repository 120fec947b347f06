//! The curvature-variation energy `E_var = ∫ (dκ/ds)² ds` of an update, its Gauss–Newton system, and the
//! third-derivative Gram matrix of the reference smoother.
//!
//! `E_var` is evaluated by Gauss–Legendre quadrature in the parameter over every knot span of the moving
//! stretch ([`VAR_GAUSS`] nodes a span), so it sees the whole curve, not only the fairing samples: a
//! ripple between two samples costs as much as one on them. With `v = |c'|` and `κ_u = dκ/du`,
//! `(dκ/ds)² ds = (κ_u / √v)² du`, so each node contributes one residual `r_q = √w_q · κ_u / √v`, a
//! function of `c'`, `c''`, `c'''` there, which are linear in the free control points.

use glam::DVec3;

use super::FairingSetup;
use super::torsion::TwistRows;
use crate::basis::{MAX_ORDER, ders_basis_funs};
use crate::curve::BSplineCurve;
use crate::linalg::BandedSpd;
use crate::quadrature::GaussLegendre;

/// Gauss–Legendre nodes per knot span of the variation energy.
pub(crate) const VAR_GAUSS: usize = 6;
/// Weight of a curvature step at a knot below C2, per 1/(arc length of the span): 1 would price a step like
/// the same change spread over one span and leave the optimizer indifferent between a staircase and a
/// ramp; above 1 a ramp is cheaper. Measured on the quality suite's quadratic (tests/common/suite.rs):
/// 1 leaves a staircase with one extremum more than the reference smoother at m = 10σ, 10 trades so much
/// slope inside the spans for smaller steps that ∫(dκ/ds)² over the spans (which does not see the steps)
/// rises above the smoother's; 2 and 3 beat it on both.
pub(crate) const JUMP_WEIGHT: f64 = 2.0;
/// Curvature probes per knot span of the extrema count ([`FairingSetup::node_extrema`]).
pub(crate) const PROBES: usize = 16;

/// Quadrature rows of the variation energy over the moving stretch (see the module docs).
#[derive(Debug, Clone, Default)]
pub(crate) struct VarRows {
    /// Quadrature weight of each node (in the parameter).
    pub(crate) w: Vec<f64>,
    /// First free-local index of each node's p + 1 basis functions.
    pub(crate) first: Vec<isize>,
    /// Per node, 3 (p + 1) values: the basis functions' 1st, 2nd, 3rd derivatives (0 for held points).
    pub(crate) b: Vec<f64>,
    /// The original's c', c'', c''' at each node.
    pub(crate) c: Vec<[DVec3; 3]>,
    /// 3D only: curvature below which |κ| is rounded off (`√(κ² + ε²)`): the unsigned curvature has a
    /// kink where it vanishes, and its derivative a jump.
    pub(crate) eps: f64,
    /// Knots inside the stretch where the curvature may jump (a quadratic's simple knots, a cubic's double
    /// knots: parametric continuity below C2): the curvature on each side enters as a residual
    /// `√w (κ⁺ − κ⁻)`, since the quadrature inside the spans cannot see a step.
    pub(crate) jumps: Vec<Jump>,
    /// The hysteresis of the curvature-extrema count ([`FairingSetup::node_extrema`]): 1 % of the largest
    /// |g| of the original's moving-average target, as `measure`'s δ.
    pub(crate) delta: f64,
    /// The torsion-variation rows of a non-planar 3D curve, whose torsion E_var does not see (empty
    /// otherwise; [`super::FairingOptions::torsion_weight`]).
    pub(crate) twist: TwistRows,
}

/// One knot of [`VarRows::jumps`]: the two one-sided rows (first free-local index, 1st and 2nd basis
/// derivatives, the original's c' and c''), and the weight `1 / (v Δu)`.
#[derive(Debug, Clone)]
pub(crate) struct Jump {
    pub(crate) w: f64,
    pub(crate) first: [isize; 2],
    pub(crate) b: [[[f64; MAX_ORDER]; 2]; 2],
    pub(crate) c: [[DVec3; 2]; 2],
}

impl VarRows {
    /// The rows of the free points `i0 .. i0 + nf` over the knot spans inside `range`, at the
    /// [`VAR_GAUSS`] Gauss–Legendre nodes of every span.
    pub(crate) fn new(work: &BSplineCurve, range: (f64, f64), i0: usize, nf: usize) -> Self {
        let gl = GaussLegendre::new(VAR_GAUSS);
        Self::at_nodes::<4>(work, range, i0, nf, &gl.nodes, &gl.weights)
    }

    /// The rows at [`PROBES`] + 1 points of every span, equally spaced in the parameter with both ends (the
    /// curvature-extrema count, which reads c' and c'' only: the third derivative's rows are 0; weights and
    /// `eps` unused). Both ends, because at a knot below C2 the curvature steps and `measure` sees both
    /// sides of the step: a count without the side before the knot misses extrema there.
    pub(crate) fn probes(work: &BSplineCurve, range: (f64, f64), i0: usize, nf: usize) -> Self {
        let x: Vec<f64> = (0..=PROBES).map(|k| -1.0 + 2.0 * k as f64 / PROBES as f64).collect();
        Self::at_nodes::<3>(work, range, i0, nf, &x, &[0.0; PROBES + 1])
    }

    /// The rows at `nodes` (on [−1, 1]) of every knot span inside `range`, with the basis derivatives up to
    /// order `D − 1` (3: all the rows; 2: the third derivative's rows 0, and no curvature threshold).
    fn at_nodes<const D: usize>(
        work: &BSplineCurve,
        range: (f64, f64),
        i0: usize,
        nf: usize,
        nodes: &[f64],
        weights: &[f64],
    ) -> Self {
        let p = work.degree();
        let kv = work.knots().values();
        let cp = work.points();
        let mut rows = Self::default();
        let mut kmax = 0.0f64;
        let bps: Vec<f64> = work
            .knots()
            .breakpoints()
            .iter()
            .copied()
            .filter(|&x| x >= range.0 && x <= range.1)
            .collect();
        let mut ders = [[0.0; MAX_ORDER]; D];
        let nodes_total = bps.len().saturating_sub(1) * nodes.len();
        rows.w.reserve(nodes_total);
        rows.first.reserve(nodes_total);
        rows.c.reserve(nodes_total);
        rows.b.reserve(nodes_total * 3 * (p + 1));
        for w in bps.windows(2) {
            let (a, b) = (w[0], w[1]);
            let half = 0.5 * (b - a);
            let span = work.knots().find_span(0.5 * (a + b));
            for (x, wt) in nodes.iter().zip(weights) {
                let u = 0.5 * (a + b) + half * x;
                ders_basis_funs(kv, span, u, p, &mut ders);
                let mut c = [DVec3::ZERO; 3];
                for j in 0..=p {
                    for (o, co) in c.iter_mut().enumerate().take(D - 1) {
                        *co += cp[span - p + j] * ders[o + 1][j];
                    }
                }
                let f = (span - p) as isize - i0 as isize;
                for o in 1..=3 {
                    for j in 0..=p {
                        let li = f + j as isize;
                        let inside = li >= 0 && (li as usize) < nf;
                        rows.b.push(if inside && o < D { ders[o][j] } else { 0.0 });
                    }
                }
                let v2 = c[0].length_squared();
                if D == 4 && v2 > 0.0 {
                    kmax = kmax.max(c[0].cross(c[1]).length() / (v2 * v2.sqrt()));
                }
                rows.w.push(wt * half);
                rows.first.push(f);
                rows.c.push(c);
            }
        }
        rows.eps = 1e-3 * kmax.max(1e-300);
        for w in bps.windows(3) {
            let u = w[1];
            if p - work.knots().multiplicity(u).min(p) >= 2 {
                continue;
            }
            let mut jump = Jump {
                w: 0.0,
                first: [0; 2],
                b: [[[0.0; MAX_ORDER]; 2]; 2],
                c: [[DVec3::ZERO; 2]; 2],
            };
            let mut speed = 0.0;
            for side in 0..2 {
                let span = if side == 0 {
                    work.knots().find_span(0.5 * (w[0] + u))
                } else {
                    work.knots().find_span(0.5 * (u + w[2]))
                };
                let mut d = [[0.0; MAX_ORDER]; 3];
                ders_basis_funs(kv, span, u, p, &mut d);
                let f = (span - p) as isize - i0 as isize;
                jump.first[side] = f;
                for j in 0..=p {
                    let li = f + j as isize;
                    let inside = li >= 0 && (li as usize) < nf;
                    for o in 0..2 {
                        jump.b[side][o][j] = if inside { d[o + 1][j] } else { 0.0 };
                        jump.c[side][o] += cp[span - p + j] * d[o + 1][j];
                    }
                }
                speed += 0.5 * jump.c[side][0].length();
            }
            let du = 0.5 * (w[2] - w[0]);
            if speed > 0.0 && du > 0.0 {
                jump.w = JUMP_WEIGHT / (speed * du);
                rows.jumps.push(jump);
            }
        }
        rows
    }

    /// `(∫ |c'''|² du` Gram matrix of the free points, right-hand side `−∫ c₀''' N_i'''`): the penalty of the
    /// reference smoother on `c₀ + Σ N_i ΔP_i`. A quadratic (c''' = 0) takes `∫ |c''|² du` instead.
    pub(crate) fn penalty_gram(&self, p: usize, nf: usize) -> (BandedSpd, Vec<DVec3>) {
        let np1 = p + 1;
        let order = p.min(3);
        let mut a = BandedSpd::zeros(nf, p);
        let mut rhs = vec![DVec3::ZERO; nf];
        for q in 0..self.w.len() {
            let f = self.first[q];
            let b3 = &self.b[q * 3 * np1 + (order - 1) * np1..q * 3 * np1 + order * np1];
            for i in 0..np1 {
                let li = f + i as isize;
                if li < 0 || li as usize >= nf {
                    continue;
                }
                rhs[li as usize] -= self.c[q][order - 1] * (self.w[q] * b3[i]);
                for j in 0..=i {
                    let lj = f + j as isize;
                    if lj < 0 {
                        continue;
                    }
                    let v = self.w[q] * b3[i] * b3[j];
                    if v != 0.0 {
                        a.add(li as usize, lj as usize, v);
                    }
                }
            }
        }
        (a, rhs)
    }

    /// [`Self::derivs`] with `N` = p + 1 known at compile time (0: read `np1`): a node whose p + 1 rows are
    /// all free takes an unrolled path without index checks (the same sums in the same order); the third
    /// derivative is updated only with `THIRD` (else it is the original's).
    #[inline(always)]
    fn derivs_n<const N: usize, const THIRD: bool>(&self, q: usize, np1: usize, d: &[DVec3]) -> [DVec3; 3] {
        let f = self.first[q];
        if N > 0 && f >= 0 && f as usize + N <= d.len() {
            let base = f as usize;
            let mut c = self.c[q];
            let b = &self.b[q * 3 * N..(q + 1) * 3 * N];
            let rows = &d[base..base + N];
            for i in 0..N {
                let x = rows[i];
                c[0] += x * b[i];
                c[1] += x * b[N + i];
                if THIRD {
                    c[2] += x * b[2 * N + i];
                }
            }
            return c;
        }
        self.derivs(q, np1, d)
    }

    /// c', c'', c''' of `c₀ + Σ N_i d_i` at node q.
    #[inline]
    fn derivs(&self, q: usize, np1: usize, d: &[DVec3]) -> [DVec3; 3] {
        let mut c = self.c[q];
        let f = self.first[q];
        let b = &self.b[q * 3 * np1..(q + 1) * 3 * np1];
        for i in 0..np1 {
            let li = f + i as isize;
            if li < 0 || li as usize >= d.len() {
                continue;
            }
            let x = d[li as usize];
            c[0] += x * b[i];
            c[1] += x * b[np1 + i];
            c[2] += x * b[2 * np1 + i];
        }
        c
    }
}

/// `κ_u / |c'|^{1/2}` from c', c'', c''' (so that its square is `(dκ/ds)² |c'|`), and its gradients with
/// respect to c', c'', c'''. With a plane normal `n` (2D: z; a planar 3D curve: its plane's) the curvature
/// signed about n; otherwise the unsigned one, rounded off below `eps`.
#[inline(always)]
pub(crate) fn dkds_residual(plane: Option<DVec3>, c1: DVec3, c2: DVec3, c3: DVec3, eps: f64) -> (f64, [DVec3; 3]) {
    let s = c1.length_squared();
    if !(s > 0.0) {
        return (0.0, [DVec3::ZERO; 3]);
    }
    let d12 = c1.dot(c2);
    // s^{-7/4} by square roots (powf was a tenth of a fair's time)
    let (r2, r4) = (s.sqrt(), s.sqrt().sqrt());
    let sm74 = 1.0 / (s * r2 * r4);
    let sm114 = sm74 / s;
    if let Some(n) = plane {
        // r = cr3 s^{-7/4} − 3 cr d12 s^{-11/4}, cr = n·(c1 × c2), cr3 = n·(c1 × c3)
        let cr = n.dot(c1.cross(c2));
        let cr3 = n.dot(c1.cross(c3));
        let r = cr3 * sm74 - 3.0 * cr * d12 * sm114;
        let perp = |a: DVec3| a.cross(n); // ∂ n·(c1 × a)/∂c1
        let g1 = perp(c3) * sm74 - c1 * (3.5 * cr3 * sm114) - (perp(c2) * d12 + c2 * cr) * (3.0 * sm114)
            + c1 * (16.5 * cr * d12 * sm114 / s);
        let rot = n.cross(c1); // ∂ n·(c1 × a)/∂a
        let g2 = -(rot * d12 + c1 * cr) * (3.0 * sm114);
        let g3 = rot * sm74;
        return (r, [g1, g2, g3]);
    }
    // 3D, from dot products: K² = s d22 − d12², P = (c1×c2)·(c1×c3) = s d23 − d12 d13,
    // r = P / K s^{-7/4} − 3 K d12 s^{-11/4}, K rounded off: √(K² + (eps s^{3/2})²)
    let (d13, d22, d23) = (c1.dot(c3), c2.dot(c2), c2.dot(c3));
    let k2 = (s * d22 - d12 * d12).max(0.0);
    let e = eps * s * s.sqrt();
    let kk = (k2 + e * e).sqrt();
    // K K' with the round-off: (c1×c2)·(c1×c3) + e e', e e' = 3 eps² s² d12
    let pp = s * d23 - d12 * d13 + 3.0 * eps * eps * s * s * d12;
    let r = pp / kk * sm74 - 3.0 * kk * d12 * sm114;
    let r_p = sm74 / kk;
    let r_k = -pp / (kk * kk) * sm74 - 3.0 * d12 * sm114;
    // explicit s dependence, including that of the round-off e² = eps² s³ inside K
    let r_s = -1.75 * pp / kk * sm114 + 8.25 * kk * d12 * sm114 / s + r_k * 1.5 * e * e / (s * kk);
    let r_d12 = -3.0 * kk * sm114;
    let (rs, rd12, rd13, rd22, rd23) = (
        r_s + r_p * (d23 + 6.0 * eps * eps * s * d12) + r_k * d22 / (2.0 * kk),
        r_d12 - r_p * (d13 - 3.0 * eps * eps * s * s) - r_k * d12 / kk,
        -r_p * d12,
        r_k * s / (2.0 * kk),
        r_p * s,
    );
    let g1 = c1 * (2.0 * rs) + c2 * rd12 + c3 * rd13;
    let g2 = c1 * rd12 + c2 * (2.0 * rd22) + c3 * rd23;
    let g3 = c1 * rd13 + c2 * rd23;
    (r, [g1, g2, g3])
}

/// [`dkds_residual`] of a 2D curve (signed about z, every z component 0): the same operations on x and y
/// alone, so the same values (the gradients' z is 0).
#[inline(always)]
pub(crate) fn dkds_residual_2d(c1: DVec3, c2: DVec3, c3: DVec3) -> (f64, [DVec3; 3]) {
    let s = c1.x * c1.x + c1.y * c1.y;
    if !(s > 0.0) {
        return (0.0, [DVec3::ZERO; 3]);
    }
    let d12 = c1.x * c2.x + c1.y * c2.y;
    let (r2, r4) = (s.sqrt(), s.sqrt().sqrt());
    let sm74 = 1.0 / (s * r2 * r4);
    let sm114 = sm74 / s;
    let cr = c1.x * c2.y - c2.x * c1.y;
    let cr3 = c1.x * c3.y - c3.x * c1.y;
    let r = cr3 * sm74 - 3.0 * cr * d12 * sm114;
    // perp(a) = a × z = (a.y, −a.x), rot = z × c1 = (−c1.y, c1.x)
    let (k1, k2, k3) = (3.5 * cr3 * sm114, 3.0 * sm114, 16.5 * cr * d12 * sm114 / s);
    let g1 = DVec3::new(
        c3.y * sm74 - c1.x * k1 - (c2.y * d12 + c2.x * cr) * k2 + c1.x * k3,
        -c3.x * sm74 - c1.y * k1 - (-c2.x * d12 + c2.y * cr) * k2 + c1.y * k3,
        0.0,
    );
    let g2 = DVec3::new(-(-c1.y * d12 + c1.x * cr) * k2, -(c1.x * d12 + c1.y * cr) * k2, 0.0);
    let g3 = DVec3::new(-c1.y * sm74, c1.x * sm74, 0.0);
    (r, [g1, g2, g3])
}

/// The curvature (signed about a plane normal, as [`dkds_residual`]; else unsigned and rounded off below
/// `eps`) from c', c'', and its gradients with respect to them.
pub(crate) fn kappa_residual(plane: Option<DVec3>, c1: DVec3, c2: DVec3, eps: f64) -> (f64, [DVec3; 2]) {
    let s = c1.length_squared();
    if !(s > 0.0) {
        return (0.0, [DVec3::ZERO; 2]);
    }
    let sm15 = 1.0 / (s * s.sqrt());
    if let Some(n) = plane {
        let cr = n.dot(c1.cross(c2));
        let g1 = c2.cross(n) * sm15 - c1 * (3.0 * cr * sm15 / s);
        let g2 = n.cross(c1) * sm15;
        return (cr * sm15, [g1, g2]);
    }
    let (d12, d22) = (c1.dot(c2), c2.dot(c2));
    let e2 = eps * eps * s * s * s;
    let kk = ((s * d22 - d12 * d12).max(0.0) + e2).sqrt();
    let g1 =
        (c1 * (2.0 * d22) - c2 * (2.0 * d12) + c1 * (6.0 * e2 / s)) * (0.5 / kk * sm15) - c1 * (3.0 * kk * sm15 / s);
    let g2 = (c2 * (2.0 * s) - c1 * (2.0 * d12)) * (0.5 / kk * sm15);
    (kk * sm15, [g1, g2])
}

impl VarRows {
    /// How many more points than p + 1 a curvature step's row spans (0 without steps).
    pub(crate) fn jump_reach(&self) -> usize {
        self.jumps
            .iter()
            .map(|j| (j.first[1] - j.first[0]).unsigned_abs())
            .max()
            .unwrap_or(0)
            .max(self.twist.reach())
    }
}

impl Jump {
    /// c', c'' of `c₀ + Σ N_i d_i` on `side` of the knot.
    fn derivs(&self, side: usize, np1: usize, d: &[DVec3]) -> [DVec3; 2] {
        let mut c = self.c[side];
        for i in 0..np1 {
            let li = self.first[side] + i as isize;
            if li < 0 || li as usize >= d.len() {
                continue;
            }
            c[0] += d[li as usize] * self.b[side][0][i];
            c[1] += d[li as usize] * self.b[side][1][i];
        }
        c
    }
}

impl FairingSetup {
    /// The normal the curvature is signed about: z in 2D, a planar 3D curve's plane normal, else none.
    fn signed_plane(&self) -> Option<DVec3> {
        if self.work.dim() == 2 {
            Some(DVec3::Z)
        } else {
            self.plane
        }
    }

    /// Curvature extrema of `c₀ + Σ N_i d_i` at the probes ([`PROBES`] a span), zig-zag pivots with the
    /// hysteresis [`VarRows::delta`] (`measure`'s count, at the probes instead of 4000 arc-length samples).
    pub(crate) fn node_extrema(&self, d: &[DVec3]) -> usize {
        match self.work.degree() {
            2 => self.node_extrema_n::<3>(d),
            3 => self.node_extrema_n::<4>(d),
            4 => self.node_extrema_n::<5>(d),
            5 => self.node_extrema_n::<6>(d),
            _ => self.node_extrema_n::<0>(d),
        }
    }

    /// [`Self::node_extrema`] with `N` = p + 1 known at compile time (0: read p from the curve).
    fn node_extrema_n<const N: usize>(&self, d: &[DVec3]) -> usize {
        let np1 = self.work.degree() + 1;
        let plane = self.signed_plane();
        let v = &self.probes;
        let n = v.w.len();
        let k: Vec<f64> = if self.work.dim() == 2 {
            // z is 0: the plane's formula below on x and y alone (the same values), in two passes so that
            // the square roots and divisions of the second run on independent lanes
            let mut num = Vec::with_capacity(n);
            let mut den = Vec::with_capacity(n);
            for q in 0..n {
                let c = v.derivs_n::<N, false>(q, np1, d);
                num.push(c[0].x * c[1].y - c[1].x * c[0].y);
                den.push(c[0].x * c[0].x + c[0].y * c[0].y);
            }
            num.iter().zip(&den).map(|(a, s)| a / (s * s.sqrt())).collect()
        } else {
            (0..n)
                .map(|q| {
                    let c = v.derivs_n::<N, false>(q, np1, d);
                    match plane {
                        Some(n) => n.dot(c[0].cross(c[1])) / (c[0].length_squared() * c[0].length()),
                        None => c[0].cross(c[1]).length() / (c[0].length_squared() * c[0].length()),
                    }
                })
                .collect()
        };
        crate::measure::zigzag_extrema(&k, self.var.delta)
    }

    /// `E_var` of `c₀ + Σ N_i d_i` over the moving stretch (module docs) with the curvature steps, and the
    /// torsion-variation energy of a non-planar 3D curve ([`TwistRows`]).
    pub(crate) fn variation_parts(&self, d: &[DVec3]) -> (f64, f64) {
        let [inner, steps, third] = self.variation_terms(d);
        (inner + steps, third)
    }

    /// `E_var` over the knot spans only, as `measure` integrates it: without the curvature steps at knots
    /// below C2 that [`Self::variation_parts`] prices.
    pub(crate) fn variation_in_spans(&self, d: &[DVec3]) -> f64 {
        self.variation_terms(d)[0]
    }

    /// (∫(dκ/ds)² over the spans, the priced curvature steps, the torsion-variation energy) at `d`.
    fn variation_terms(&self, d: &[DVec3]) -> [f64; 3] {
        match self.work.degree() {
            2 => self.variation_terms_n::<3>(d),
            3 => self.variation_terms_n::<4>(d),
            4 => self.variation_terms_n::<5>(d),
            5 => self.variation_terms_n::<6>(d),
            _ => self.variation_terms_n::<0>(d),
        }
    }

    /// [`Self::variation_terms`] with `N` = p + 1 known at compile time (0: read p from the curve).
    fn variation_terms_n<const N: usize>(&self, d: &[DVec3]) -> [f64; 3] {
        let np1 = self.work.degree() + 1;
        let plane = self.signed_plane();
        let v = &self.var;
        let inner: f64 = if self.work.dim() == 2 {
            // dkds_residual_2d's value in two passes: the products first, then the roots and divisions on
            // independent lanes (the same operations, the same values and sum)
            let n = v.w.len();
            let mut parts = Vec::with_capacity(n);
            for q in 0..n {
                let [c1, c2, c3] = v.derivs_n::<N, true>(q, np1, d);
                let s = c1.x * c1.x + c1.y * c1.y;
                let d12 = c1.x * c2.x + c1.y * c2.y;
                let cr = c1.x * c2.y - c2.x * c1.y;
                let cr3 = c1.x * c3.y - c3.x * c1.y;
                parts.push([s, d12, cr, cr3]);
            }
            parts
                .iter()
                .zip(&v.w)
                .map(|(&[s, d12, cr, cr3], w)| {
                    let r = if s > 0.0 {
                        let (r2, r4) = (s.sqrt(), s.sqrt().sqrt());
                        let sm74 = 1.0 / (s * r2 * r4);
                        let sm114 = sm74 / s;
                        cr3 * sm74 - 3.0 * cr * d12 * sm114
                    } else {
                        0.0
                    };
                    w * r * r
                })
                .sum()
        } else {
            (0..v.w.len())
                .map(|q| {
                    let c = v.derivs_n::<N, true>(q, np1, d);
                    let r = dkds_residual(plane, c[0], c[1], c[2], v.eps).0;
                    v.w[q] * r * r
                })
                .sum()
        };
        let steps: f64 = v
            .jumps
            .iter()
            .map(|j| {
                let [a, b] = [0, 1].map(|side| {
                    let c = j.derivs(side, np1, d);
                    kappa_residual(plane, c[0], c[1], v.eps).0
                });
                j.w * (b - a) * (b - a)
            })
            .sum();
        let third = v.twist.energy(np1, d);
        [inner, steps, third]
    }

    /// Adds `weight · JᵀJ` to `h` and `−weight · Jᵀr` to `rhs` for `E_var` at the update `d` (unknown
    /// `li · dim + c`, as the polish's systems).
    pub(crate) fn variation_system(&self, d: &[DVec3], weight: f64, h: &mut BandedSpd, rhs: &mut [DVec3]) {
        match (self.work.degree(), self.work.dim()) {
            (2, 2) => self.variation_system_n::<3, 2, 6>(d, weight, h, rhs),
            (2, 3) => self.variation_system_n::<3, 3, 9>(d, weight, h, rhs),
            (3, 2) => self.variation_system_n::<4, 2, 8>(d, weight, h, rhs),
            (3, 3) => self.variation_system_n::<4, 3, 12>(d, weight, h, rhs),
            (4, 2) => self.variation_system_n::<5, 2, 10>(d, weight, h, rhs),
            (5, 2) => self.variation_system_n::<6, 2, 12>(d, weight, h, rhs),
            _ => self.variation_system_n::<0, 0, 0>(d, weight, h, rhs),
        }
    }

    /// [`Self::variation_system`] with `N` = p + 1, `D` = dim and `W` = N·D known at compile time (0: read
    /// them from the curve): a node whose p + 1 rows are all free takes an unrolled path (the same sums in
    /// the same order).
    fn variation_system_n<const N: usize, const D: usize, const W: usize>(
        &self,
        d: &[DVec3],
        weight: f64,
        h: &mut BandedSpd,
        rhs: &mut [DVec3],
    ) {
        let np1 = self.work.degree() + 1;
        let dim = self.work.dim();
        let plane = self.signed_plane();
        let v = &self.var;
        let nf = self.nf;
        let mut jrow = vec![0.0; dim * np1];
        for q in 0..v.w.len() {
            let c = v.derivs_n::<N, true>(q, np1, d);
            let (r, g) = if D == 2 {
                dkds_residual_2d(c[0], c[1], c[2])
            } else {
                dkds_residual(plane, c[0], c[1], c[2], v.eps)
            };
            let sw = (weight * v.w[q]).sqrt();
            let f = v.first[q];
            if N > 0 && f >= 0 && f as usize + N <= nf {
                let base = f as usize;
                let b = &v.b[q * 3 * N..(q + 1) * 3 * N];
                let mut jr = [0.0; W];
                for i in 0..N {
                    let gi = g[0] * b[i] + g[1] * b[N + i] + g[2] * b[2 * N + i];
                    for cc in 0..D {
                        jr[i * D + cc] = sw * gi[cc];
                    }
                }
                let block: &mut [DVec3; W] = (&mut rhs[base * D..base * D + W]).try_into().expect("W rows");
                for (y, x) in block.iter_mut().zip(&jr) {
                    y.x -= x * sw * r;
                }
                h.add_outer_fixed(base * D, &jr);
                continue;
            }
            let base = f.max(0) as usize;
            let b = &v.b[q * 3 * np1..(q + 1) * 3 * np1];
            jrow.fill(0.0);
            let mut width = 0;
            for i in 0..np1 {
                let li = f + i as isize;
                if li < 0 || li as usize >= nf {
                    continue;
                }
                let gi = g[0] * b[i] + g[1] * b[np1 + i] + g[2] * b[2 * np1 + i];
                let off = (li as usize - base) * dim;
                for cc in 0..dim {
                    jrow[off + cc] = sw * gi[cc];
                }
                width = off + dim;
            }
            if width == 0 {
                continue;
            }
            for a in 0..width {
                rhs[base * dim + a].x -= jrow[a] * sw * r;
            }
            h.add_outer(base * dim, &jrow[..width]);
        }
        // the curvature steps at knots below C2: r = √w (κ⁺ − κ⁻), rows over both sides' points
        for j in &v.jumps {
            let f0 = j.first[0].min(j.first[1]);
            let base = f0.max(0) as usize;
            let width_pts = (j.first[1].max(j.first[0]) + np1 as isize).min(nf as isize) - f0.max(0);
            if width_pts <= 0 {
                continue;
            }
            let width = width_pts as usize * dim;
            let mut row = vec![0.0; width];
            let sw = (weight * j.w).sqrt();
            let mut r = 0.0;
            for (side, sign) in [(0, -1.0), (1, 1.0)] {
                let c = j.derivs(side, np1, d);
                let (k, g) = kappa_residual(plane, c[0], c[1], v.eps);
                r += sign * k;
                for i in 0..np1 {
                    let li = j.first[side] + i as isize;
                    if li < 0 || li as usize >= nf {
                        continue;
                    }
                    let gi = g[0] * j.b[side][0][i] + g[1] * j.b[side][1][i];
                    let off = (li as usize - base) * dim;
                    for cc in 0..dim {
                        row[off + cc] += sign * sw * gi[cc];
                    }
                }
            }
            for a in 0..width {
                rhs[base * dim + a].x -= row[a] * sw * r;
            }
            h.add_outer(base * dim, &row);
        }
        if !v.twist.is_empty() {
            v.twist.system(np1, nf, d, weight, h, rhs);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curvature_gradients_match_finite_differences() {
        for (dim, c1, c2) in [
            (2, DVec3::new(1.3, 0.4, 0.0), DVec3::new(-0.7, 2.1, 0.0)),
            (3, DVec3::new(1.3, 0.4, -0.2), DVec3::new(-0.7, 2.1, 0.5)),
        ] {
            let eps = 0.05;
            let plane = (dim == 2).then_some(DVec3::Z);
            let (k, g) = kappa_residual(plane, c1, c2, eps);
            let d = crate::curve::CurveDerivs {
                p: DVec3::ZERO,
                d1: c1,
                d2: c2,
                d3: DVec3::ZERO,
            };
            let want = if dim == 2 {
                d.curvature(2)
            } else {
                d.curvature(3).hypot(eps)
            };
            assert!((k - want).abs() <= 1e-12 * want.abs(), "{k} vs {want}");
            for o in 0..2 {
                for c in 0..dim {
                    let mut cs = [c1, c2];
                    let h = 1e-6;
                    cs[o][c] += h;
                    let kp = kappa_residual(plane, cs[0], cs[1], eps).0;
                    cs[o][c] -= 2.0 * h;
                    let km = kappa_residual(plane, cs[0], cs[1], eps).0;
                    let fd = (kp - km) / (2.0 * h);
                    assert!((g[o][c] - fd).abs() <= 1e-6 * fd.abs().max(1.0), "{} vs {fd}", g[o][c]);
                }
            }
        }
    }

    #[test]
    fn residual_gradients_match_finite_differences() {
        let cases = [
            (
                2,
                DVec3::new(1.3, 0.4, 0.0),
                DVec3::new(-0.7, 2.1, 0.0),
                DVec3::new(0.9, -1.4, 0.0),
            ),
            (
                3,
                DVec3::new(1.3, 0.4, -0.2),
                DVec3::new(-0.7, 2.1, 0.5),
                DVec3::new(0.9, -1.4, 0.3),
            ),
            (
                3,
                DVec3::new(0.2, 1.1, 0.7),
                DVec3::new(0.01, 0.02, -0.03),
                DVec3::new(4.0, 0.0, 1.0),
            ),
        ];
        for (dim, c1, c2, c3) in cases {
            let eps = 0.05;
            let plane = (dim == 2).then_some(DVec3::Z);
            let (r, g) = dkds_residual(plane, c1, c2, c3, eps);
            // the value: κ_u / √v against a finite difference of κ along u (c(u) = c1 u + c2 u²/2 + c3 u³/6)
            let kap = |u: f64| {
                let d1 = c1 + c2 * u + c3 * (u * u / 2.0);
                let d2 = c2 + c3 * u;
                if dim == 2 {
                    (d1.x * d2.y - d1.y * d2.x) / d1.length().powi(3)
                } else {
                    let kk = d1.cross(d2).length() / d1.length().powi(3);
                    (kk * kk + eps * eps).sqrt()
                }
            };
            let hu = 1e-5;
            let ku = (kap(hu) - kap(-hu)) / (2.0 * hu);
            let want = ku / c1.length().sqrt();
            assert!((r - want).abs() <= 1e-6 * want.abs().max(1.0), "value {r} vs {want}");
            for o in 0..3 {
                for c in 0..dim {
                    let mut cs = [c1, c2, c3];
                    let h = 1e-6;
                    cs[o][c] += h;
                    let rp = dkds_residual(plane, cs[0], cs[1], cs[2], eps).0;
                    cs[o][c] -= 2.0 * h;
                    let rm = dkds_residual(plane, cs[0], cs[1], cs[2], eps).0;
                    let fd = (rp - rm) / (2.0 * h);
                    assert!(
                        (g[o][c] - fd).abs() <= 1e-6 * fd.abs().max(1.0),
                        "dim {dim}, derivative {o}, coordinate {c}: {} vs {fd}",
                        g[o][c]
                    );
                }
            }
        }
    }

    /// Cubics with double knots (C1: the curvature steps at every knot), their steps from small to large
    /// against the dead band (control points off a parabola by up to a third of their spacing; beyond,
    /// 16 probes a span miss extrema inside the spans): the polish's count at the probes agrees with
    /// `measure`'s count on 4000 arc-length samples on every one.
    #[test]
    fn the_probe_count_sees_both_sides_of_a_curvature_step() {
        use crate::fair::{FairingOptions, FairingSetup};
        let knots = [vec![0.0; 4], vec![0.2, 0.2, 0.4, 0.4, 0.6, 0.6, 0.8, 0.8], vec![1.0; 4]].concat();
        let n = knots.len() - 4;
        let mut stepped = 0;
        for k in 0..50 {
            let a = 1e-4 * 1.15f64.powi(k);
            let pts: Vec<DVec3> = (0..n)
                .map(|i| {
                    let t = i as f64 / (n - 1) as f64;
                    DVec3::new(3.0 * t, t * t + a * ((i * 5 % 3) as f64 - 1.0), 0.0)
                })
                .collect();
            let c = BSplineCurve::try_new(3, knots.clone(), pts, None, 2).unwrap();
            let opts = FairingOptions {
                tolerance: 1e-3,
                ..Default::default()
            };
            let s = FairingSetup::new(&c, opts).unwrap();
            let probed = s.node_extrema(&vec![DVec3::ZERO; s.nf]);
            let measured = crate::measure::curvature_extrema_at(&c, s.var.delta);
            assert_eq!(probed, measured, "amplitude {a}");
            stepped += usize::from(measured > 0);
        }
        assert!(stepped > 10, "curves with extrema at their steps: {stepped}");
    }
}
