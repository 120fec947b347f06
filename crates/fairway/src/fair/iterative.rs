//! The iterative baseline (paper §2.2, after Salvi & Várady 2005): move one
//! control point at a time, minimizing the paper's fairness measure
//! `E = Σ_k (κ(p_k) − g_k)²` under the deviation bound, with the downhill
//! simplex method (Nelder–Mead, Numerical Recipes §10.4).
//!
//! It works on a prepared [`FairingSetup`] (same samples, target, free
//! control points and check samples as the fast method), so the two are
//! compared on exactly the same problem. For each free control point P_i in
//! turn, a Nelder–Mead search over its displacement (2 or 3 unknowns)
//! minimizes the part of E whose samples lie in P_i's support; a candidate
//! is rejected (E = ∞) when the parametric distance `|c(u_j) − c_orig(u_j)|`
//! — an upper bound of the closest-point deviation — exceeds m at a check
//! sample in the support, so the band holds by construction. Sweeps repeat
//! until E improves by less than 1e-9 relative or `max_sweeps` is reached.

use glam::DVec3;

use super::curve::{CHECK_SAMPLES, FairingResult, FairingSetup, band_accept};
use crate::arclength::ArcLengthTable;
use crate::basis::{MAX_ORDER, basis_funs, ders_basis_funs};
use crate::curve::{BSplineCurve, CurveDerivs};
use crate::error::Result;

/// Options of the iterative baseline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterativeOptions {
    /// Maximum number of sweeps over the free control points.
    pub max_sweeps: usize,
    /// Maximum function evaluations per simplex search.
    pub max_evals: usize,
}

impl Default for IterativeOptions {
    fn default() -> Self {
        Self {
            max_sweeps: 20,
            max_evals: 80,
        }
    }
}

struct Local<'a> {
    setup: &'a FairingSetup,
    p: usize,
    pts: Vec<DVec3>,
    orig: Vec<DVec3>,
    span: Vec<usize>,
    ders: Vec<[[f64; MAX_ORDER]; 3]>,
    chk_span: Vec<usize>,
    chk_b: Vec<[f64; MAX_ORDER]>,
    m: f64,
}

impl Local<'_> {
    /// The setup's E term of sample `k` at the current points: (κ − g)² along the setup's normal, and in 3D
    /// the curvature that leaves the osculating plane too ([`FairingSetup::residual_sq`]), so the baseline
    /// minimizes the E it is compared on.
    fn residual_sq(&self, k: usize, g: f64) -> f64 {
        let s = self.span[k] - self.p;
        let (mut d1, mut d2) = (DVec3::ZERO, DVec3::ZERO);
        for j in 0..=self.p {
            d1 += self.pts[s + j] * self.ders[k][1][j];
            d2 += self.pts[s + j] * self.ders[k][2][j];
        }
        let d = CurveDerivs {
            p: DVec3::ZERO,
            d1,
            d2,
            d3: DVec3::ZERO,
        };
        self.setup.residual_sq(&d, k, g)
    }

    /// E over samples `ks` and the band over check samples `js`, with P_i displaced to `x`.
    fn local_e(&mut self, i: usize, x: DVec3, ks: (usize, usize), js: (usize, usize)) -> f64 {
        let old = self.pts[i];
        self.pts[i] = x;
        let mut ok = true;
        for j in js.0..js.1 {
            let s = self.chk_span[j] - self.p;
            let mut d = DVec3::ZERO;
            for l in 0..=self.p {
                d += (self.pts[s + l] - self.orig[s + l]) * self.chk_b[j][l];
            }
            if d.length() > self.m {
                ok = false;
                break;
            }
        }
        let mut e = 0.0;
        if ok {
            let g = self.setup.target().values();
            for k in ks.0..ks.1 {
                e += self.residual_sq(k, g[k]);
            }
        }
        self.pts[i] = old;
        if ok { e } else { f64::INFINITY }
    }
}

impl<'a> Local<'a> {
    /// The baseline's state on `setup`: the basis at its samples and at its check samples (across the
    /// seam: the original's, not the rotated curve's), and those check samples' parameters.
    fn new(setup: &'a FairingSetup) -> (Self, Vec<f64>) {
        let work = setup.working_curve();
        let p = work.degree();
        let kv = work.knots().values();
        let params = setup.params();
        let mut span = Vec::with_capacity(params.len());
        let mut ders = Vec::with_capacity(params.len());
        for &u in params {
            let s = work.knots().find_span(u);
            let mut d = [[0.0; MAX_ORDER]; 3];
            ders_basis_funs(kv, s, work.knots().clamp(u), p, &mut d);
            span.push(s);
            ders.push(d);
        }
        let (a, b) = setup.moving_range();
        // the setup's own check samples (across the seam: the original's, not the rotated curve's)
        let chk_u: Vec<f64> = if setup.check_params().is_empty() {
            ArcLengthTable::new(work, 1e-12)
                .equal_arc_params(work, CHECK_SAMPLES)
                .into_iter()
                .filter(|&u| u > a && u < b)
                .collect()
        } else {
            setup.check_params().to_vec()
        };
        let mut chk_span = Vec::with_capacity(chk_u.len());
        let mut chk_b = Vec::with_capacity(chk_u.len());
        for &u in &chk_u {
            let s = work.knots().find_span(u);
            let mut nb = [0.0; MAX_ORDER];
            basis_funs(kv, s, work.knots().clamp(u), p, &mut nb);
            chk_span.push(s);
            chk_b.push(nb);
        }
        let m = band_accept(setup.options().tolerance, work);
        let loc = Local {
            setup,
            p,
            pts: work.points().to_vec(),
            orig: work.points().to_vec(),
            span,
            ders,
            chk_span,
            chk_b,
            m,
        };
        (loc, chk_u)
    }
}

/// Run the iterative baseline on `setup` (its target and tolerance).
pub fn fair_iterative(setup: &FairingSetup, opts: IterativeOptions) -> Result<FairingResult> {
    let work = setup.working_curve();
    let dim = work.dim();
    let params = setup.params();
    let (mut loc, chk_u) = Local::new(setup);
    // sample / check ranges touching each control point's support
    let range_of = |us: &[f64], lo: f64, hi: f64| (us.partition_point(|&u| u < lo), us.partition_point(|&u| u <= hi));
    let free = setup.free_points();
    let mut e_total = setup.energy(work);
    let mut sweeps = 0;
    let mut evals = 0usize;
    for _ in 0..opts.max_sweeps {
        sweeps += 1;
        let e_before = e_total;
        for i in free.clone() {
            let (lo, hi) = work.knots().support(i);
            let ks = range_of(params, lo, hi);
            let js = range_of(&chk_u, lo, hi);
            let x0 = loc.pts[i];
            let step = (setup.options().tolerance * 0.5).max(1e-12);
            // the setup's constraints (plane of a planar 3D curve, joins at multiple knots) on the move
            let li = i - free.start;
            let fix = |x: DVec3| x0 + setup.constrain_point(li, x - x0);
            let (x, _e) = nelder_mead(
                |x| loc.local_e(i, fix(x), ks, js),
                x0,
                step,
                dim,
                opts.max_evals,
                &mut evals,
            );
            loc.pts[i] = fix(x);
        }
        let c = work.with_points(loc.pts.clone())?;
        e_total = setup.energy(&c);
        if e_before - e_total <= 1e-9 * e_before.abs() {
            break;
        }
    }
    let mut curve: BSplineCurve = work.with_points(loc.pts.clone())?;
    let tol = setup.options().tolerance;
    // The moves were checked by the parametric distance at the check samples; between them the
    // result may leave the band: the sound bound decides, and the update is scaled back by the
    // excess until it holds (the parametric distance scales with it), else the original is kept.
    let mut alpha = 1.0;
    let mut notes = vec![];
    let mut bb = super::verify::certify(work, &curve, tol);
    for _ in 0..super::curve::BAND_RETRIES {
        let Some(b) = bb.filter(|b| b.bound > tol) else { break };
        alpha *= (tol / b.bound) * (1.0 - 1e-3);
        let pts: Vec<DVec3> = work
            .points()
            .iter()
            .zip(&loc.pts)
            .map(|(o, x)| *o + (*x - *o) * alpha)
            .collect();
        curve = work.with_points(pts)?;
        bb = super::verify::certify(work, &curve, tol);
    }
    let dev = match bb {
        Some(b) if b.bound <= tol => b.bound,
        Some(b) => {
            notes.push(format!(
                "the iterative fair left the tolerance band between its check samples (near u = {:.6}): \
                 the curve was kept as it was",
                b.at
            ));
            alpha = 0.0;
            curve = work.clone();
            0.0
        }
        // a rational curve: the parametric distance at the check samples
        None => chk_u
            .iter()
            .fold(0.0f64, |a, &u| a.max(curve.point(u).distance(work.point(u)))),
    };
    let energy = setup.energy(&curve);
    Ok(FairingResult {
        curve,
        max_deviation: dev,
        mu: 0.0,
        alpha,
        solves: sweeps * free.len(),
        energy,
        seam: setup.seam().clone(),
        notes,
    })
}

/// Nelder–Mead on a 2D or 3D displacement (the other coordinates fixed at 0
/// for 2D curves), started from `x0` with initial simplex size `step`.
fn nelder_mead(
    mut f: impl FnMut(DVec3) -> f64,
    x0: DVec3,
    step: f64,
    dim: usize,
    max_evals: usize,
    evals: &mut usize,
) -> (DVec3, f64) {
    let nv = dim + 1;
    let mut xs = [x0; 4];
    for d in 0..dim {
        let mut e = DVec3::ZERO;
        e[d] = step;
        xs[d + 1] = x0 + e;
    }
    let mut fs = [0.0; 4];
    for v in 0..nv {
        fs[v] = f(xs[v]);
    }
    let mut n = nv;
    while n < max_evals {
        // sort vertices by value
        let mut idx = [0usize, 1, 2, 3];
        idx[..nv].sort_by(|&a, &b| fs[a].total_cmp(&fs[b]));
        let (best, worst, second) = (idx[0], idx[nv - 1], idx[nv - 2]);
        if (fs[worst] - fs[best]).abs() <= 1e-14 * (fs[best].abs() + 1e-300) && fs[worst].is_finite() {
            break;
        }
        let mut c = DVec3::ZERO;
        for &v in &idx[..nv - 1] {
            c += xs[v];
        }
        c /= (nv - 1) as f64;
        let xr = c + (c - xs[worst]);
        let fr = f(xr);
        n += 1;
        if fr < fs[best] {
            let xe = c + (c - xs[worst]) * 2.0;
            let fe = f(xe);
            n += 1;
            if fe < fr {
                xs[worst] = xe;
                fs[worst] = fe;
            } else {
                xs[worst] = xr;
                fs[worst] = fr;
            }
        } else if fr < fs[second] {
            xs[worst] = xr;
            fs[worst] = fr;
        } else {
            let xc = c + (xs[worst] - c) * 0.5;
            let fc = f(xc);
            n += 1;
            if fc < fs[worst] {
                xs[worst] = xc;
                fs[worst] = fc;
            } else {
                for &v in &idx[1..nv] {
                    xs[v] = xs[best] + (xs[v] - xs[best]) * 0.5;
                    fs[v] = f(xs[v]);
                    n += 1;
                }
            }
        }
    }
    *evals += n;
    let mut b = 0;
    for v in 1..nv {
        if fs[v] < fs[b] {
            b = v;
        }
    }
    // never worse than the start
    let f0 = f(x0);
    if f0 <= fs[b] { (x0, f0) } else { (xs[b], fs[b]) }
}
