//! Steps 1 and 3–5 (module docs of `fair::surface`): the rows held at poles and seams, the isocurves faired
//! by the curve engine and their clouds combined.

use super::setup_cache::with_setup;
use super::{Combine, ISO_SAMPLES_PER_SPAN, ISO_TARGET_SIGMA_SPANS, SurfaceFairingOptions, SurfaceTimings, par_map};
use crate::error::{Error, Result};
use crate::fair::curve::{FairingOptions, FairingSetup};
use crate::fair::target::TargetMethod;
use crate::surface::BSplineSurface;
use glam::DVec3;
use std::ops::Range;
use std::time::Instant;

/// Rows next to a pole that a fair keeps: the pole row and the two after it fix the surface's position,
/// tangent plane and curvature at the pole.
pub(crate) const POLE_ROWS: usize = 3;

/// Diagonal of the control net's bounding box.
pub(super) fn net_size(s: &BSplineSurface) -> f64 {
    let (lo, hi) = s.control_bounds();
    (hi - lo).length()
}

/// Whether the control points `pts` all coincide (within 1e-12 of `size`): a collapsed row or column (a
/// pole, as on a surface of revolution or a triangular patch), whose isocurve is a single point.
pub(super) fn collapsed(pts: impl IntoIterator<Item = DVec3>, size: f64) -> bool {
    let mut it = pts.into_iter();
    let Some(first) = it.next() else { return false };
    it.all(|q| q.distance(first) <= 1e-12 * size)
}

/// Free control rows and columns with the poles and seams held.
/// - A **pole**: a boundary row (or column) whose control points all coincide. If the free range reaches
///   it, that row and the next [`POLE_ROWS`] − 1 stay, so the pole stays one point with its tangent plane
///   and curvature (moving its points apart would tear a hole into the surface, within the tolerance but
///   visible as a crease in the shading).
/// - A **seam**: the first and last rows (or columns) coincide point by point (within 1e-10 of the net's
///   size, as for closed curves), i.e. the surface is closed in that direction (a tube, a full surface of
///   revolution). The isocurves are faired one stretch at a time, not across the seam, so the
///   [`POLE_ROWS`] rows at each side of it stay: the surface stays closed, with its continuity across the
///   seam (fairing both sides independently opened a full paraboloid of revolution by 2.4e-3 at m = 3e-3).
pub(super) fn hold_poles_and_seams(
    s: &BSplineSurface,
    mut fu: Range<usize>,
    mut fv: Range<usize>,
) -> (Range<usize>, Range<usize>) {
    let (nu, nv) = (s.nu(), s.nv());
    let pts = s.points();
    let size = net_size(s);
    let row = |i: usize| collapsed((0..nv).map(|j| pts[i * nv + j]), size);
    let col = |j: usize| collapsed((0..nu).map(|i| pts[i * nv + j]), size);
    let seam_u = (0..nv).all(|j| pts[j].distance(pts[(nu - 1) * nv + j]) <= 1e-10 * size);
    let seam_v = (0..nu).all(|i| pts[i * nv].distance(pts[i * nv + nv - 1]) <= 1e-10 * size);
    let hold = |f: &mut Range<usize>, n: usize, first: bool, last: bool| {
        if f.start < f.end && f.start == 0 && first {
            f.start = POLE_ROWS.min(f.end);
        }
        if f.start < f.end && f.end == n && last {
            f.end = (n - POLE_ROWS.min(n)).max(f.start);
        }
    };
    hold(&mut fu, nu, seam_u || row(0), seam_u || row(nu - 1));
    hold(&mut fv, nv, seam_v || col(0), seam_v || col(nv - 1));
    (fu, fv)
}

/// The curve-engine setup for one isocurve `c` over the region `r` (holding
/// `spans_r` knot spans) with the isocurve tolerance `m_iso`.
///
/// By default (`opts.curve.samples` / `strength` unset) ISO_SAMPLES_PER_SPAN
/// samples per knot span of the region and a target smoothing of
/// ISO_TARGET_SIGMA_SPANS knot spans (σ of the equivalent Gaussian of the
/// averaging passes), so that the work per isocurve is linear in its number
/// of spans (the curve engine's default σ = 0.06·n samples costs O(n²)); the
/// isocurve's band is checked at its own samples only
/// ([`FairingSetup::with_check_samples`] with 0), since the surface verifies
/// its own band.
pub fn isocurve_setup(
    c: &crate::curve::BSplineCurve,
    opts: &SurfaceFairingOptions,
    m_iso: f64,
    r: (f64, f64),
    spans_r: usize,
) -> Result<FairingSetup> {
    FairingSetup::with_check_samples(c, isocurve_options(opts, m_iso, r, spans_r), 0)
}

/// The curve-engine options of [`isocurve_setup`].
pub(super) fn isocurve_options(
    opts: &SurfaceFairingOptions,
    m_iso: f64,
    r: (f64, f64),
    spans_r: usize,
) -> FairingOptions {
    let ns = opts.curve.samples.unwrap_or(ISO_SAMPLES_PER_SPAN * spans_r.max(1) + 1);
    let sigma = ISO_TARGET_SIGMA_SPANS * ISO_SAMPLES_PER_SPAN as f64;
    let strength = opts.curve.strength.or(match opts.curve.target {
        TargetMethod::Heat | TargetMethod::Average => Some((1.5 * sigma * sigma).round() as usize),
        TargetMethod::Binomial => Some((2.0 * sigma * sigma).round() as usize),
        TargetMethod::Fit => None,
    });
    FairingOptions {
        region: Some(r),
        tolerance: m_iso,
        samples: Some(ns),
        strength,
        // the E polish is for curves; the surface combines the isocurve clouds and verifies its own band
        polish: false,
        // an isocurve's ends are the surface's border: they keep the border's G2 state
        curve_ends: [None; 2],
        ..opts.curve
    }
}

/// The knot spans of `[a, b]` as the isocurve sampling counts them: a span next to an interior knot of
/// multiplicity s ≥ 1 counts s times (a C0 knot of a chain of Bézier patches brings p control points where a
/// simple knot brings one), so an isocurve gets enough samples for its control points; with simple knots
/// it is the number of spans.
pub(super) fn equivalent_spans(k: &crate::knots::KnotVector, (a, b): (f64, f64)) -> usize {
    let (lo, hi) = k.domain();
    let mult = |t: f64| if t > lo && t < hi { k.multiplicity(t).max(1) } else { 1 };
    k.breakpoints()
        .windows(2)
        .filter(|w| w[0] >= a && w[1] <= b)
        .map(|w| mult(w[0]).max(mult(w[1])))
        .sum()
}

/// Isocurves per block of neighbours (warm-started band search, one unit of parallel work).
pub(crate) const ISO_BLOCK: usize = 8;

/// Fair the isocurves and combine the clouds: returns the grid data `S + Δ`, one per isocurve tolerance
/// of `levels`. Each isocurve's setup (arc length, samples, basis rows, normal equations) does not depend on
/// the tolerance, so it is built once and re-faired per level (each level warm-starts its band search from
/// the neighbouring isocurve's μ at the same level, exactly as one call per level would).
pub(super) fn combined_cloud(
    s: &BSplineSurface,
    opts: &SurfaceFairingOptions,
    levels: &[f64],
    ru: (f64, f64),
    rv: (f64, f64),
    us: &[f64],
    vs: &[f64],
    orig: &[DVec3],
    tm: &mut SurfaceTimings,
) -> Result<Vec<Vec<DVec3>>> {
    let t0 = Instant::now();
    let grid = IsoGrid {
        s,
        opts,
        us,
        vs,
        orig,
        size: net_size(s),
    };
    let faired = grid.fair_all(levels, ru, rv)?;
    let t1 = Instant::now();
    tm.isocurves += t1 - t0;
    let clouds = (0..levels.len()).map(|lv| grid.combine(&faired, lv)).collect();
    tm.combine += t1.elapsed();
    Ok(clouds)
}

/// The faired isocurves of [`IsoGrid::fair_all`] at the grid parameters: `u[l][level][k]` is the u-isocurve
/// at `vs[l]` at `us[k]`, `v[k][level][l]` the v-isocurve at `us[k]` at `vs[l]`; a direction that is not
/// faired has none (its Δ is 0).
struct FairedIsocurves {
    u: Vec<Vec<Vec<DVec3>>>,
    v: Vec<Vec<Vec<DVec3>>>,
}

/// The surface, its grid `us × vs` and the original's points there, shared by the steps of
/// [`combined_cloud`].
struct IsoGrid<'a> {
    s: &'a BSplineSurface,
    opts: &'a SurfaceFairingOptions,
    us: &'a [f64],
    vs: &'a [f64],
    orig: &'a [DVec3],
    /// [`net_size`] of `s`.
    size: f64,
}

impl IsoGrid<'_> {
    /// Step 3: fair every isocurve through the grid at each tolerance of `levels`, evaluated at the grid
    /// parameters.
    fn fair_all(&self, levels: &[f64], ru: (f64, f64), rv: (f64, f64)) -> Result<FairedIsocurves> {
        let (s, us, vs) = (self.s, self.us, self.vs);
        let (mu, mv) = (us.len(), vs.len());
        let nl = levels.len();
        // A direction whose region holds fewer than p + 1 knot spans (a C0 knot's counting p, see
        // `equivalent_spans`) has no movable isocurve control point for the curve engine (e.g. a cubic
        // direction with one span): its isocurves stay, Δ = 0.
        let (spans_u, spans_v) = (equivalent_spans(s.knots_u(), ru), equivalent_spans(s.knots_v(), rv));
        let fair_u = spans_u > s.degree_u();
        let fair_v = spans_v > s.degree_v();
        // The isocurves are independent: fair them in blocks of ISO_BLOCK neighbours (each block warm-starts
        // the band search of an isocurve from its neighbour's μ), the blocks spread over the available cores.
        // Blocks are fixed by the grid, not by the core count, so the result does not depend on the machine.
        let mut tasks: Vec<(bool, usize)> = Vec::with_capacity(mu + mv);
        if fair_u {
            tasks.extend((0..mv).map(|l| (true, l)));
        }
        if fair_v {
            tasks.extend((0..mu).map(|k| (false, k)));
        }
        let blocks: Vec<&[(bool, usize)]> = tasks
            .chunk_by(|a, b| a.0 == b.0)
            .flat_map(|c| c.chunks(ISO_BLOCK))
            .collect();
        // per isocurve of the block, per level: the faired isocurve at the grid parameters
        type BlockResult = Result<Vec<Vec<Vec<DVec3>>>>;
        let fair_block = |block: &[(bool, usize)]| -> BlockResult {
            crate::cancel::check()?;
            let mut hints = vec![None; nl];
            block
                .iter()
                .map(|&(is_u, i)| {
                    let (r, spans) = if is_u { (ru, spans_u) } else { (rv, spans_v) };
                    self.fair_isocurve(is_u, i, levels, r, spans, &mut hints)
                })
                .collect()
        };
        let results = par_map(&blocks, self.opts.threads, |b| fair_block(b));
        let mut out = FairedIsocurves {
            u: vec![vec![]; if fair_u { mv } else { 0 }],
            v: vec![vec![]; if fair_v { mu } else { 0 }],
        };
        for (block, res) in blocks.iter().zip(results) {
            for (&(is_u, i), per_level) in block.iter().zip(res?) {
                if is_u {
                    out.u[i] = per_level;
                } else {
                    out.v[i] = per_level;
                }
            }
        }
        Ok(out)
    }

    /// One isocurve of step 3: the u-isocurve at `vs[i]` (`is_u`) or the v-isocurve at `us[i]`, over the
    /// region `r` of `spans` knot spans, faired at each tolerance of `levels` (warm-started from `hints`,
    /// the neighbour's μ per level, which it updates) and evaluated at the grid parameters.
    fn fair_isocurve(
        &self,
        is_u: bool,
        i: usize,
        levels: &[f64],
        r: (f64, f64),
        spans: usize,
        hints: &mut [Option<f64>],
    ) -> Result<Vec<Vec<DVec3>>> {
        let (s, us, vs, orig) = (self.s, self.us, self.vs, self.orig);
        let (mu, mv) = (us.len(), vs.len());
        let nl = levels.len();
        let ((du0, du1), (dv0, dv1)) = s.domain();
        let (iso, t, at) = if is_u {
            (s.iso_u(vs[i]), us, ("u", "v", vs[i]))
        } else {
            (s.iso_v(us[i]), vs, ("v", "u", us[i]))
        };
        // the isocurve along a pole (a collapsed boundary row, held by `hold_poles_and_seams`) is a single point:
        // it stays (Δ = 0); a point isocurve inside the domain (a pinch at a p-fold knot) still fails
        let on_edge = if is_u {
            vs[i] == dv0 || vs[i] == dv1
        } else {
            us[i] == du0 || us[i] == du1
        };
        if on_edge && collapsed(iso.points().iter().copied(), self.size) {
            let kept: Vec<DVec3> = if is_u {
                (0..mu).map(|k| orig[k * mv + i]).collect()
            } else {
                (0..mv).map(|l| orig[i * mv + l]).collect()
            };
            return Ok(vec![kept; nl]);
        }
        let err = |e: Error| Error::InvalidInput(format!("fairing the {}-isocurve at {} = {}: {e}", at.0, at.1, at.2));
        let fo = isocurve_options(self.opts, levels[0], r, spans);
        with_setup(&iso, fo, |st| {
            let mut out = Vec::with_capacity(nl);
            for (&m_iso, hint) in levels.iter().zip(hints.iter_mut()) {
                st.set_tolerance(m_iso)?;
                st.set_mu_hint(*hint);
                st.set_fairest_mu(self.opts.fairest_isocurves);
                let res = st.fair()?;
                *hint = Some(res.mu);
                out.push(t.iter().map(|&x| res.curve.point(x)).collect());
            }
            Ok(out)
        })
        .map_err(err)
    }

    /// Step 4 for level `lv`: the grid data `S + Δ` from the displacements `Δ_u = P_u − S`, `Δ_v = P_v − S`
    /// of the two directions' faired isocurves `f`, weighted as `opts.combine` says (then
    /// umbrella-smoothed for [`Combine::Smoothed`]).
    fn combine(&self, f: &FairedIsocurves, lv: usize) -> Vec<DVec3> {
        let (us, vs, orig, opts) = (self.us, self.vs, self.orig, self.opts);
        let (mu, mv) = (us.len(), vs.len());
        let ((du0, du1), (dv0, dv1)) = self.s.domain();
        // normalized distance to the held borders; a side on the domain boundary is no border (its rows are free)
        let border_dist = |t: f64, a: f64, b: f64, lo: f64, hi: f64| {
            let da = if a > lo { t - a } else { f64::INFINITY };
            let db = if b < hi { b - t } else { f64::INFINITY };
            (da.min(db) / (b - a)).clamp(0.0, 0.5)
        };
        let (a0, a1) = (us[0], us[mu - 1]);
        let (b0, b1) = (vs[0], vs[mv - 1]);
        let mut data = vec![DVec3::ZERO; mu * mv];
        for k in 0..mu {
            let d_u = border_dist(us[k], a0, a1, du0, du1);
            for l in 0..mv {
                let d_v = border_dist(vs[l], b0, b1, dv0, dv1);
                let (beta_u, beta_v) = if d_u + d_v > 0.0 {
                    (d_v / (d_u + d_v), d_u / (d_u + d_v))
                } else {
                    (0.5, 0.5)
                };
                let o = orig[k * mv + l];
                let x = f.u.get(l).map_or(DVec3::ZERO, |c| c[lv][k] - o);
                let y = f.v.get(k).map_or(DVec3::ZERO, |c| c[lv][l] - o);
                let (mut a, mut b) = match opts.combine {
                    Combine::Average => (0.5, 0.5),
                    Combine::Border => (beta_u, beta_v),
                    Combine::Weighted | Combine::Smoothed => (beta_u * x.length(), beta_v * y.length()),
                };
                if !(a + b > 0.0) {
                    (a, b) = (beta_u, beta_v);
                }
                data[k * mv + l] = o + (x * a + y * b) / (a + b);
            }
        }
        if opts.combine == Combine::Smoothed {
            umbrella_smooth(&mut data, mu, mv, 3, 0.25);
        }
        data
    }
}

/// Normal umbrella smoothing: `P ← P + τ ((avg of the 4 neighbours − P)·n) n`, n the grid normal,
/// border rows and columns held.
fn umbrella_smooth(p: &mut [DVec3], mu: usize, mv: usize, passes: usize, tau: f64) {
    let mut next = p.to_vec();
    for _ in 0..passes {
        for k in 1..mu.saturating_sub(1) {
            for l in 1..mv.saturating_sub(1) {
                let c = p[k * mv + l];
                let (w, e) = (p[(k - 1) * mv + l], p[(k + 1) * mv + l]);
                let (sth, nth) = (p[k * mv + l - 1], p[k * mv + l + 1]);
                let n = (e - w).cross(nth - sth).normalize_or_zero();
                let lap = (w + e + sth + nth) * 0.25 - c;
                next[k * mv + l] = c + n * (tau * lap.dot(n));
            }
        }
        p.copy_from_slice(&next);
    }
}
