//! Step 8 (module docs of `fair::surface`): the reference smoother's search on the verified band, and the
//! ranking of the candidates by fairness.

use super::{CHECK_PER_SPAN, CheckGrid};
use crate::error::{Error, Result};
use crate::fit_surface::{GridFit, PlateFactor, PlateFit};
use crate::measure_surface::{iso_extrema_in, mean_curvature_variation_adaptive};
use crate::quadrature::GaussLegendre;
use crate::surface::BSplineSurface;
use glam::DVec3;
use std::ops::Range;
use std::sync::{Arc, Mutex, OnceLock};

/// Check samples per knot span and direction of the step-8 candidates (module docs, step 8).
pub(crate) const FINE_CHECK_PER_SPAN: usize = 4 * CHECK_PER_SPAN;

/// Band-holding strengths of each smoother search that step 8 ranks, the strongest first (1: the search's answer).
pub(crate) const SEARCH_CANDIDATES: usize = 1;

/// Blend weights of the isocurve result tried against the smoother's (step 8).
pub(crate) const BLENDS: [f64; 3] = [0.25, 0.5, 0.75];

/// Gauss–Legendre nodes per cell and direction of the step-8 ranking's `∫∫|∇H|²`.
pub(crate) const RANK_GAUSS: usize = 10;

/// A span cell of the ranking's `∫∫|∇H|²` takes the 5-point rule where the 4- and 5-point rules agree to
/// this fraction of the cell's value, [`RANK_GAUSS`] points elsewhere
/// ([`crate::measure_surface::mean_curvature_variation_adaptive`]; within 1.4e-10 of the 10-point rule on
/// its test, where 1e-6 gave 2e-9 and 1e-8 1.5e-12).
pub(crate) const RANK_CELL_AGREEMENT: f64 = 1e-7;

/// Order of the reference smoother's energy: 3, the curvature-variation energy (module docs, step 8; the
/// thin plate, order 2, was measured as the weaker peer).
pub(crate) const REFERENCE_ORDER: usize = 3;

/// Smallest and largest strength (log10) of the reference smoother's search.
pub const REFERENCE_LOG_STRENGTH: (f64, f64) = (-6.0, 8.0);

/// Bisection steps on log10 of the strength (resolution 14 / 2¹² decades, under 1 % in λ).
pub(crate) const REFERENCE_STEPS: usize = 12;

/// Isocurves per direction of the step-8 ranking (as `measure`'s [`crate::measure_surface::N_ISO`]).
pub(crate) const RANK_ISO: usize = 20;

/// The reference smoother's energy for `s` on its grid: [`PlateFit`] of [`REFERENCE_ORDER`] with the mean
/// speeds `|S_u|`, `|S_v|` of the original over the grid as length scales.
pub(super) fn plate_fit<'g, 'a>(
    s: &BSplineSurface,
    grid: &'g GridFit<'a>,
    us: &[f64],
    vs: &[f64],
    order: usize,
) -> Result<PlateFit<'g, 'a>> {
    let (mut lu, mut lv, mut n) = (0.0, 0.0, 0usize);
    let step_u = (us.len() / 16).max(1);
    let step_v = (vs.len() / 16).max(1);
    for &u in us.iter().step_by(step_u) {
        for &v in vs.iter().step_by(step_v) {
            let d = s.derivs(u, v);
            lu += d.su.length();
            lv += d.sv.length();
            n += 1;
        }
    }
    PlateFit::new(grid, order, lu / n as f64, lv / n as f64)
}

/// The band as [`fair_surface`](super::fair_surface) verifies it: the coarse check, then the full one.
pub(super) struct Bands<'a> {
    pub(super) coarse: &'a CheckGrid,
    pub(super) full: &'a CheckGrid,
    /// [`FINE_CHECK_PER_SPAN`] samples per span: the smoother's nets bulge between the full grid's nodes
    /// (by up to 1 % of m, measured by dense projection), so its candidates are accepted on this grid, by
    /// their parametric change.
    pub(super) fine: &'a CheckGrid,
    pub(super) free_u: &'a Range<usize>,
    pub(super) free_v: &'a Range<usize>,
    pub(super) m: f64,
}

impl Bands<'_> {
    /// Whether `f` is within the band of `s`, with a deviation bound that is **not** the one to report:
    /// the fine grid's nodes far from m are skipped ([`CheckGrid::change_peaks`]), so where no node comes
    /// near m the bound is at most m but not the fine grid's maximum. The verdict is [`Self::holds`]'s, bit
    /// for bit; the candidate that is kept takes its figure from [`Self::holds`].
    pub(super) fn holds_quick(&self, s: &BSplineSurface, f: &BSplineSurface) -> Option<f64> {
        self.check(s, f, false)
    }

    /// The verified deviation bound of `f` from `s` if it is within the band.
    pub(super) fn holds(&self, s: &BSplineSurface, f: &BSplineSurface) -> Option<f64> {
        self.check(s, f, true)
    }

    fn check(&self, s: &BSplineSurface, f: &BSplineSurface, every_node: bool) -> Option<f64> {
        if self.coarse.deviation(s, f, self.free_u, self.free_v, self.m, true) > self.m {
            return None;
        }
        if self.full.deviation(s, f, self.free_u, self.free_v, self.m, true) > self.m {
            return None;
        }
        // on the fine grid the parametric change |S_f − S| itself (no projection sharpening): it bounds both
        // one-sided distances at every sample, and it varies little between samples this dense, where a
        // projected distance can exceed m between nodes at which it did not
        let (mut dev, mut peaks) = (self.fine).change_peaks(
            s,
            f,
            self.free_u,
            self.free_v,
            PEAK_FRACTION * self.m,
            self.m,
            every_node,
        );
        if dev > self.m {
            return None;
        }
        // between the nodes: the change's local maxima, from the grid's peaks near m
        peaks.sort_by(|x, y| y.0.total_cmp(&x.0));
        for &(_, u, v) in peaks.iter().take(MAX_PEAKS) {
            dev = dev.max(local_max_change(s, f, (u, v)));
            if dev > self.m {
                return None;
            }
        }
        Some(dev)
    }
}

/// Grid peaks of the change above this fraction of m are followed to their local maximum (the band check of step 8).
pub(crate) const PEAK_FRACTION: f64 = 0.99;

/// At most this many grid peaks (the largest) are followed.
pub(crate) const MAX_PEAKS: usize = 16;

/// The local maximum of the parametric change `|S_b − S_a|` near `uv`: Newton ascent on `|Δ|²/2` (gradient
/// `Δ·Δ_u, Δ·Δ_v`, Hessian `Δ_u·Δ_u + Δ·Δ_uu, …`; a gradient step where that is not negative definite),
/// steps clamped to the domain and halved until the change grows; a coordinate held at the domain boundary
/// by the clamp is left out of the next step.
fn local_max_change(a: &BSplineSurface, b: &BSplineSurface, uv: (f64, f64)) -> f64 {
    let ((u0, u1), (v0, v1)) = a.domain();
    let change = |u: f64, v: f64| (b.point(u, v) - a.point(u, v)).length();
    let (mut u, mut v) = uv;
    let mut best = change(u, v);
    let scale = ((u1 - u0).powi(2) + (v1 - v0).powi(2)).sqrt();
    for _ in 0..15 {
        let (da, db) = (a.derivs(u, v), b.derivs(u, v));
        let (d, du, dv) = (db.p - da.p, db.su - da.su, db.sv - da.sv);
        let (duu, duv, dvv) = (db.suu - da.suu, db.suv - da.suv, db.svv - da.svv);
        let mut g = [d.dot(du), d.dot(dv)];
        let mut h = [
            du.dot(du) + d.dot(duu),
            du.dot(dv) + d.dot(duv),
            dv.dot(dv) + d.dot(dvv),
        ];
        // a coordinate at its bound whose gradient points outwards stays
        let held_u = (u <= u0 && g[0] < 0.0) || (u >= u1 && g[0] > 0.0);
        let held_v = (v <= v0 && g[1] < 0.0) || (v >= v1 && g[1] > 0.0);
        if held_u {
            g[0] = 0.0;
            h[1] = 0.0;
            h[0] = -1.0;
        }
        if held_v {
            g[1] = 0.0;
            h[1] = 0.0;
            h[2] = -1.0;
        }
        let det = h[0] * h[2] - h[1] * h[1];
        let (mut su, mut sv) = if h[0] < 0.0 && det > 0.0 {
            // Newton: s = −H⁻¹ g
            (-(h[2] * g[0] - h[1] * g[1]) / det, -(h[0] * g[1] - h[1] * g[0]) / det)
        } else {
            // gradient ascent, scaled to a step of at most 1 % of the domain
            let n = (g[0] * g[0] + g[1] * g[1]).sqrt();
            if n == 0.0 {
                break;
            }
            (0.01 * scale * g[0] / n, 0.01 * scale * g[1] / n)
        };
        let mut moved = false;
        for _ in 0..20 {
            let (nu, nv) = ((u + su).clamp(u0, u1), (v + sv).clamp(v0, v1));
            let c = change(nu, nv);
            if c > best {
                best = c;
                moved = (nu - u).abs() + (nv - v).abs() > 1e-15 * scale;
                (u, v) = (nu, nv);
                break;
            }
            su *= 0.5;
            sv *= 0.5;
        }
        if !moved {
            break;
        }
    }
    best
}

/// The smoother's search: bisection on the log of the strength over [`REFERENCE_LOG_STRENGTH`]
/// ([`REFERENCE_STEPS`] steps) for the largest strength whose result holds the band. Returns every
/// band-holding result visited as `(net, deviation bound, strength)`, by increasing strength: the last is
/// the smoother's answer. Empty when not even the smallest strength holds the band.
pub(super) fn plate_search(
    s: &BSplineSurface,
    plate: &PlateFit<'_, '_>,
    factors: &PlateFactors<'_, '_, '_>,
    rhs: &[DVec3],
    bands: &Bands<'_>,
) -> Result<Vec<(Vec<DVec3>, f64, f64)>> {
    let attempt = |log_st: f64| -> Result<Option<(Vec<DVec3>, f64, f64)>> {
        crate::cancel::check()?;
        let st = 10f64.powf(log_st);
        let pts = match factors.get(st).and_then(|k| plate.solve_factored(&k, rhs)) {
            Ok(p) => p,
            // a strength too large for the factorization's pivots counts as not holding
            Err(Error::Solve(_)) => return Ok(None),
            Err(e) => return Err(e),
        };
        let f = s.with_points(pts)?;
        Ok(bands.holds_quick(s, &f).map(|dev| (f.points().to_vec(), dev, st)))
    };
    let (mut lo, mut hi) = REFERENCE_LOG_STRENGTH;
    if let Some(r) = attempt(hi)? {
        return Ok(vec![r]);
    }
    let Some(first) = attempt(lo)? else {
        return Ok(Vec::new());
    };
    let mut found = vec![first];
    for _ in 0..REFERENCE_STEPS {
        let mid = 0.5 * (lo + hi);
        match attempt(mid)? {
            Some(r) => {
                found.push(r);
                lo = mid;
            }
            None => hi = mid,
        }
    }
    Ok(found)
}

/// The factored systems of one [`PlateFit`] by strength, shared by the searches on different data (they
/// visit the same strengths until their answers part): each factored once, the second search waiting for
/// a factorization under way rather than repeating it. [`PlateFit::solve`] is `factor` then
/// `solve_factored`, so the searches' results are those of separate solves, bit for bit.
pub(super) struct PlateFactors<'p, 'g, 'a> {
    plate: &'p PlateFit<'g, 'a>,
    #[allow(clippy::type_complexity)]
    done: Mutex<Vec<(u64, Arc<OnceLock<Result<Arc<PlateFactor>>>>)>>,
}

impl<'p, 'g, 'a> PlateFactors<'p, 'g, 'a> {
    pub(super) fn new(plate: &'p PlateFit<'g, 'a>) -> Self {
        Self {
            plate,
            done: Mutex::new(Vec::new()),
        }
    }

    /// The system at `strength`, factored on first use.
    fn get(&self, strength: f64) -> Result<Arc<PlateFactor>> {
        let cell = {
            let mut done = self.done.lock().unwrap_or_else(|e| e.into_inner());
            let key = strength.to_bits();
            match done.iter().find(|(k, _)| *k == key) {
                Some((_, c)) => Arc::clone(c),
                None => {
                    let c = Arc::new(OnceLock::new());
                    done.push((key, Arc::clone(&c)));
                    c
                }
            }
        };
        cell.get_or_init(|| self.plate.factor(strength).map(Arc::new)).clone()
    }
}

/// The step-8 ranking over the moving rectangle: (isocurve curvature extrema with the 1 % dead band of
/// the original's max |κ_n|, `∫∫|∇H|² dA`), compared lexicographically — the measures of
/// [`crate::measure_surface`].
pub(super) struct Ranker {
    rect: ((f64, f64), (f64, f64)),
    delta: f64,
    gl: GaussLegendre,
}

#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
pub(super) struct Rank(pub(super) usize, pub(super) f64);

impl Ranker {
    pub(super) fn new(s: &BSplineSurface, rect: ((f64, f64), (f64, f64))) -> Self {
        let delta = 0.01 * iso_extrema_in(s, rect, RANK_ISO, 0.0).max_abs_kappa;
        Self {
            rect,
            delta,
            gl: GaussLegendre::new(RANK_GAUSS),
        }
    }

    pub(super) fn rank(&self, f: &BSplineSurface) -> Rank {
        let st = iso_extrema_in(f, self.rect, RANK_ISO, self.delta);
        let e = mean_curvature_variation_adaptive(f, self.rect, &self.gl, RANK_CELL_AGREEMENT);
        Rank(
            st.extrema_u + st.extrema_v,
            if e.is_finite() { e } else { f64::INFINITY },
        )
    }
}
