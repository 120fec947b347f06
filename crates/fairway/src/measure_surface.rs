//! Measures of a (faired) surface against an original: deviation by
//! closest-point projection, curvature extrema and curvature variation of
//! isocurves, and the mean-curvature variation ∫|∇H|² dA.
//!
//! Definitions (all lengths in model units, curvatures in 1/length):
//!
//! * **dev_max / dev_rms**: the ORIGINAL is sampled on an `n × n` grid
//!   uniform in (u, v) (first and last included); each sample is projected on
//!   the FAIRED surface ([`SurfaceProjector::project_near`], seeded at the same
//!   (u, v), then safeguarded Newton) and the max / RMS of the distances is
//!   taken. Any point of the faired surface bounds the distance from above,
//!   so the figure is an upper bound of the true one-sided deviation, exact
//!   when the Newton minimum is the global one (always so for small
//!   deviations, where the faired surface is a graph over the original).
//!   `dev_max_reverse`: the same from FAIRED to ORIGINAL; `hausdorff`: the
//!   larger.
//! * **isocurve curvature**: along the u-isocurve through (u, v) the signed
//!   normal curvature `κ_n = L/E = (S_uu·n)/(S_u·S_u)` (the curvature of the
//!   isocurve as the surface bends it, sign w.r.t. the surface normal; an
//!   unsigned curve curvature would fold at every inflection line of a flat
//!   patch). For v-isocurves `κ_n = N/G`.
//! * **n_curv_extrema**: on `n_iso` isocurves in each direction (uniform
//!   interior parameters), κ_n sampled at 16 points per knot span; extrema
//!   counted as zig-zag pivots with a dead band δ = 0.01 · max|κ_n| of the
//!   ORIGINAL (the same δ for both surfaces), as the curve measure of
//!   `reference/README.md`.
//! * **e_var** = Σ over those isocurves of `∫ (dκ_n/ds)² ds`, by 5-point
//!   Gauss–Legendre per knot span, `dκ_n/ds = (dκ_n/du)/|S_u|` with
//!   `dκ_n/du` by a central difference of step 1e-5·(span width) inside the
//!   span (κ_n is smooth inside a span; its derivative jumps at knots).
//! * **mean_curv_var** = `∫∫ |∇H|² dA`: the surface gradient of the mean
//!   curvature, `|∇H|² = (G H_u² − 2F H_u H_v + E H_v²)/(EG − F²)` (do Carmo
//!   §3.3, the inverse first fundamental form), `dA = √(EG − F²) du dv`;
//!   H_u, H_v by central differences of H inside each span cell (step
//!   1e-5·cell width; truncation O(h²), rounding ≈ 1e-11 relative), 10×10
//!   Gauss–Legendre per cell (H is rational, so the rule is not exact; 1e-3
//!   relative on the closed-form test). Analytic H_u would need third partials.
//! * **n_isophote_inflections**: isophote waviness ([`isophote_waviness`]): the
//!   isophotes of the light `L = (1, 1, 1)/√3` every 2° (level lines of n·L,
//!   traced by marching squares on a uv grid of 8 nodes per knot span, at
//!   least 240 per direction), resampled at an arc-length step D/80; the sign changes of their
//!   geodesic curvature (turning angle / step, signed by the normal), counted
//!   with a dead band τ = 2/D (D the bounding-box diagonal), summed over all
//!   isophotes. 0 for a plane, a cylinder, a sphere; it counts the wiggles of
//!   the reflection lines a designer sees.

use glam::DVec3;

use crate::basis::MAX_ORDER;
use crate::quadrature::{gl5, gl10};
use crate::surface::{BSplineSurface, SurfaceDerivs};

/// Result of a surface projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// Parameters of the closest point.
    pub uv: (f64, f64),
    /// The closest point.
    pub point: DVec3,
    /// Its distance to the query.
    pub distance: f64,
}

/// Closest points on one surface: seeds on a parameter grid, then Newton on
/// `(S − q)·S_u = 0, (S − q)·S_v = 0` with the Hessian
/// `[[S_u·S_u + r·S_uu, S_u·S_v + r·S_uv], [·, S_v·S_v + r·S_vv]]`, r = S − q
/// (Gauss–Newton when that is not positive definite), steps clamped to the
/// domain and halved until the distance decreases.
#[derive(Debug, Clone)]
pub struct SurfaceProjector<'a> {
    surface: &'a BSplineSurface,
    seeds: Vec<((f64, f64), DVec3)>,
}

fn grid_params(knots: &crate::knots::KnotVector, per_span: usize) -> Vec<f64> {
    let bp = knots.breakpoints();
    let m = per_span.max(1);
    let mut out = Vec::with_capacity((bp.len() - 1) * m + 1);
    for w in bp.windows(2) {
        for k in 0..m {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / m as f64);
        }
    }
    out.push(*bp.last().unwrap());
    out
}

impl<'a> SurfaceProjector<'a> {
    /// Prepare with `per_span` seeds per knot span in each direction (≥ 1; 4 is plenty for cubics).
    pub fn new(surface: &'a BSplineSurface, per_span: usize) -> Self {
        let us = grid_params(surface.knots_u(), per_span);
        let vs = grid_params(surface.knots_v(), per_span);
        let mut seeds = Vec::with_capacity(us.len() * vs.len());
        for &u in &us {
            for &v in &vs {
                seeds.push(((u, v), surface.point(u, v)));
            }
        }
        Self { surface, seeds }
    }

    /// The closest point to `q` (best seed, then Newton).
    pub fn project(&self, q: DVec3) -> SurfacePoint {
        let mut best = (f64::INFINITY, (0.0, 0.0));
        for &(uv, p) in &self.seeds {
            let d = p.distance_squared(q);
            if d < best.0 {
                best = (d, uv);
            }
        }
        self.project_near(q, best.1)
    }

    /// Newton from the guess `uv` (a local closest point).
    pub fn project_near(&self, q: DVec3, uv: (f64, f64)) -> SurfacePoint {
        newton_project(self.surface, q, uv)
    }
}

/// Safeguarded Newton projection from a starting guess (see [`SurfaceProjector`]).
pub fn newton_project(s: &BSplineSurface, q: DVec3, uv: (f64, f64)) -> SurfacePoint {
    let ((u0, u1), (v0, v1)) = s.domain();
    let (mut u, mut v) = (uv.0.clamp(u0, u1), uv.1.clamp(v0, v1));
    let mut d = s.derivs(u, v);
    let mut dist2 = (d.p - q).length_squared();
    let tol_u = 1e-15 * (u1 - u0).max(1.0);
    let tol_v = 1e-15 * (v1 - v0).max(1.0);
    for _ in 0..30 {
        let r = d.p - q;
        let (f1, f2) = (r.dot(d.su), r.dot(d.sv));
        let (e, f, g) = (d.su.dot(d.su), d.su.dot(d.sv), d.sv.dot(d.sv));
        let (mut j11, mut j12, mut j22) = (e + r.dot(d.suu), f + r.dot(d.suv), g + r.dot(d.svv));
        if !(j11 > 0.0 && j11 * j22 - j12 * j12 > 0.0) {
            (j11, j12, j22) = (e, f, g);
        }
        let det = j11 * j22 - j12 * j12;
        if !(det > 0.0) {
            break;
        }
        let mut du = -(j22 * f1 - j12 * f2) / det;
        let mut dv = -(j11 * f2 - j12 * f1) / det;
        let mut improved = false;
        for _ in 0..12 {
            let (nu, nv) = ((u + du).clamp(u0, u1), (v + dv).clamp(v0, v1));
            let nd = s.derivs(nu, nv);
            let nd2 = (nd.p - q).length_squared();
            if nd2 <= dist2 {
                let moved = (nu - u).abs() > tol_u || (nv - v).abs() > tol_v;
                (u, v, d, dist2) = (nu, nv, nd, nd2);
                improved = moved;
                break;
            }
            du *= 0.5;
            dv *= 0.5;
        }
        if !improved {
            break;
        }
    }
    SurfacePoint {
        uv: (u, v),
        point: d.p,
        distance: dist2.sqrt(),
    }
}

/// One-sided deviation of `from` to `onto` on an `n × n` uniform parameter grid
/// of `from`: `(max, rms)` (see the module docs). Both surfaces should share
/// the parameter domain (a faired surface does); otherwise the seeds are the
/// grid of `onto`'s projector.
pub fn deviation(from: &BSplineSurface, onto: &BSplineSurface, n: usize) -> (f64, f64) {
    let n = n.max(2);
    let ((a0, a1), (b0, b1)) = from.domain();
    let same = from.domain() == onto.domain();
    let proj = if same {
        None
    } else {
        Some(SurfaceProjector::new(onto, 4))
    };
    let (mut max, mut sum) = (0.0f64, 0.0);
    for k in 0..n {
        let u = a0 + (a1 - a0) * k as f64 / (n - 1) as f64;
        for l in 0..n {
            let v = b0 + (b1 - b0) * l as f64 / (n - 1) as f64;
            let q = from.point(u, v);
            let d = match &proj {
                None => newton_project(onto, q, (u, v)).distance,
                Some(p) => p.project(q).distance,
            };
            max = max.max(d);
            sum += d * d;
        }
    }
    (max, (sum / (n * n) as f64).sqrt())
}

/// Signed normal curvature of the u-isocurve (`dir_u = true`, L/E) or the v-isocurve (N/G).
fn iso_kappa(d: &SurfaceDerivs, dir_u: bool) -> f64 {
    let n = d.su.cross(d.sv).normalize_or_zero();
    if dir_u {
        d.suu.dot(n) / d.su.length_squared()
    } else {
        d.svv.dot(n) / d.sv.length_squared()
    }
}

/// Count interior extrema of a sampled function as zig-zag pivots with dead band `delta`.
pub fn count_extrema(k: &[f64], delta: f64) -> usize {
    if k.len() < 3 {
        return 0;
    }
    let (mut lo, mut hi) = (k[0], k[0]);
    let mut dir = 0i8;
    let mut ext = k[0];
    let mut count = 0;
    for &x in &k[1..] {
        match dir {
            0 => {
                lo = lo.min(x);
                hi = hi.max(x);
                if x - lo > delta {
                    if k[0] - lo > delta {
                        count += 1;
                    }
                    dir = 1;
                    ext = x;
                } else if hi - x > delta {
                    if hi - k[0] > delta {
                        count += 1;
                    }
                    dir = -1;
                    ext = x;
                }
            }
            1 => {
                if x > ext {
                    ext = x;
                } else if ext - x > delta {
                    count += 1;
                    dir = -1;
                    ext = x;
                }
            }
            _ => {
                if x < ext {
                    ext = x;
                } else if x - ext > delta {
                    count += 1;
                    dir = 1;
                    ext = x;
                }
            }
        }
    }
    count
}

/// Isocurve statistics of one surface.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct IsoStats {
    /// Total curvature extrema over the u-isocurves.
    pub extrema_u: usize,
    /// Total curvature extrema over the v-isocurves.
    pub extrema_v: usize,
    /// Σ ∫ (dκ_n/ds)² ds over the u-isocurves.
    pub e_var_u: f64,
    /// Σ ∫ (dκ_n/ds)² ds over the v-isocurves.
    pub e_var_v: f64,
    /// max |κ_n| seen over all isocurve samples.
    pub max_abs_kappa: f64,
}

fn iso_params(a: f64, b: f64, n: usize) -> impl Iterator<Item = f64> {
    (0..n).map(move |k| a + (b - a) * (k as f64 + 0.5) / n as f64)
}

/// Isocurve statistics: `n_iso` isocurves per direction, extrema with dead band `delta`
/// (see the module docs).
pub fn iso_stats(s: &BSplineSurface, n_iso: usize, delta: f64) -> IsoStats {
    iso_stats_in(s, s.domain(), n_iso, delta)
}

/// Knot spans of `bp` clipped to `[a, b]` (the pieces inside the rectangle).
fn clipped_spans(bp: &[f64], a: f64, b: f64) -> Vec<(f64, f64)> {
    bp.windows(2)
        .map(|w| (w[0].max(a), w[1].min(b)))
        .filter(|(x, y)| y > x)
        .collect()
}

/// [`iso_stats`] restricted to the parameter rectangle `((u0, u1), (v0, v1))`: `n_iso` isocurves per
/// direction at uniform interior parameters of the rectangle, each sampled and integrated over its
/// part inside the rectangle only (knot spans clipped to it). Over the domain it equals [`iso_stats`].
pub fn iso_stats_in(s: &BSplineSurface, rect: ((f64, f64), (f64, f64)), n_iso: usize, delta: f64) -> IsoStats {
    let mut st = IsoStats::default();
    let ((u0, u1), (v0, v1)) = rect;
    let su = clipped_spans(&s.knots_u().breakpoints(), u0, u1);
    let sv = clipped_spans(&s.knots_v().breakpoints(), v0, v1);
    let mut buf = Vec::new();
    for dir_u in [true, false] {
        let (spans, (f0, f1)) = if dir_u { (&su, (v0, v1)) } else { (&sv, (u0, u1)) };
        let Some(&(_, t_end)) = spans.last() else {
            continue;
        };
        for fixed in iso_params(f0, f1, n_iso) {
            let at = |t: f64| if dir_u { s.derivs(t, fixed) } else { s.derivs(fixed, t) };
            buf.clear();
            let mut e = 0.0;
            for &(a, b) in spans.iter() {
                for k in 0..16 {
                    let t = a + (b - a) * k as f64 / 16.0;
                    buf.push(iso_kappa(&at(t), dir_u));
                }
                let h = 1e-5 * (b - a);
                let gl = gl5();
                for (x, wt) in gl.nodes.iter().zip(&gl.weights) {
                    let t = 0.5 * (a + b) + 0.5 * (b - a) * x;
                    let d = at(t);
                    let speed = if dir_u { d.su.length() } else { d.sv.length() };
                    let dk = (iso_kappa(&at(t + h), dir_u) - iso_kappa(&at(t - h), dir_u)) / (2.0 * h);
                    let dks = dk / speed;
                    e += wt * 0.5 * (b - a) * dks * dks * speed;
                }
            }
            buf.push(iso_kappa(&at(t_end), dir_u));
            st.max_abs_kappa = buf.iter().fold(st.max_abs_kappa, |m, k| m.max(k.abs()));
            let c = count_extrema(&buf, delta);
            if dir_u {
                st.extrema_u += c;
                st.e_var_u += e;
            } else {
                st.extrema_v += c;
                st.e_var_v += e;
            }
        }
    }
    st
}

/// Mean curvature H at (u, v) (PRODUCT.md convention), point by point: the tests' direct quadrature.
#[cfg(test)]
fn mean_at(s: &BSplineSurface, u: f64, v: f64) -> f64 {
    s.derivs(u, v).mean_curvature()
}

/// `∫∫ |∇H|² dA` over the whole surface (see the module docs).
pub fn mean_curvature_variation(s: &BSplineSurface) -> f64 {
    mean_curvature_variation_in(s, s.domain())
}

/// `∫∫ |∇H|² dA` over the parameter rectangle `((u0, u1), (v0, v1))` (knot cells clipped to it, the
/// same rule per piece); over the domain it equals [`mean_curvature_variation`].
pub fn mean_curvature_variation_in(s: &BSplineSurface, rect: ((f64, f64), (f64, f64))) -> f64 {
    mean_curvature_variation_rule(s, rect, gl10())
}

/// [`mean_curvature_variation_in`] with the Gauss–Legendre rule `gl` per cell and direction (a cheaper
/// estimate with fewer nodes, e.g. for ranking candidates).
pub fn mean_curvature_variation_rule(
    s: &BSplineSurface,
    rect: ((f64, f64), (f64, f64)),
    gl: &crate::quadrature::GaussLegendre,
) -> f64 {
    let ((u0, u1), (v0, v1)) = rect;
    let su = clipped_spans(&s.knots_u().breakpoints(), u0, u1);
    let sv = clipped_spans(&s.knots_v().breakpoints(), v0, v1);
    let mut total = 0.0;
    let n = gl.nodes.len();
    let mut cell = CellDerivs::default();
    for &(a0, a1) in &su {
        let hu = 1e-5 * (a1 - a0);
        let u_at = |x: f64| 0.5 * (a0 + a1) + 0.5 * (a1 - a0) * x;
        // per node: the node and its two difference points
        let us: Vec<f64> = gl
            .nodes
            .iter()
            .flat_map(|&x| [u_at(x), u_at(x) + hu, u_at(x) - hu])
            .collect();
        for &(b0, b1) in &sv {
            let hv = 1e-5 * (b1 - b0);
            let v_at = |y: f64| 0.5 * (b0 + b1) + 0.5 * (b1 - b0) * y;
            let vs: Vec<f64> = gl
                .nodes
                .iter()
                .flat_map(|&y| [v_at(y), v_at(y) + hv, v_at(y) - hv])
                .collect();
            if !s.is_rational() {
                cell.prepare(s, &us, &vs);
            }
            let d = |a: usize, b: usize| -> SurfaceDerivs {
                if s.is_rational() {
                    s.derivs(us[a], vs[b])
                } else {
                    cell.at(a, b)
                }
            };
            for (i, wx) in gl.weights.iter().enumerate() {
                for (j, wy) in gl.weights.iter().enumerate() {
                    let (a, b) = (3 * i, 3 * j);
                    let c = d(a, b);
                    let (e, f, g) = (c.su.dot(c.su), c.su.dot(c.sv), c.sv.dot(c.sv));
                    let det = e * g - f * f;
                    let h_u = (d(a + 1, b).mean_curvature() - d(a + 2, b).mean_curvature()) / (2.0 * hu);
                    let h_v = (d(a, b + 1).mean_curvature() - d(a, b + 2).mean_curvature()) / (2.0 * hv);
                    let grad2 = (g * h_u * h_u - 2.0 * f * h_u * h_v + e * h_v * h_v) / det;
                    let jac = 0.25 * (a1 - a0) * (b1 - b0) * wx * wy;
                    total += grad2 * det.sqrt() * jac;
                }
            }
            debug_assert_eq!(vs.len(), 3 * n);
        }
    }
    total
}

/// Derivatives of a polynomial surface on a parameter grid `us × vs` inside one knot cell, evaluated
/// separably: per v-parameter and control row of the cell, the v-sums `T_l = Σ_j M_j^{(l)}(v) P_ij`, then
/// per point the u-sums `Σ_i N_i^{(k)}(u) T_l` — the operations of [`BSplineSurface::derivs`] in its order
/// (bit-identical), with the basis functions computed once per parameter instead of per point.
#[derive(Default)]
struct CellDerivs {
    pu: usize,
    /// Per u-parameter: basis derivatives 0..=2.
    du: Vec<[[f64; MAX_ORDER]; 3]>,
    /// Per v-parameter and control row of the cell: `T_0, T_1, T_2`.
    t: Vec<[[DVec3; 3]; MAX_ORDER]>,
}

impl CellDerivs {
    fn prepare(&mut self, s: &BSplineSurface, us: &[f64], vs: &[f64]) {
        let (ku, kv) = (s.knots_u(), s.knots_v());
        let (pu, pv, nv) = (s.degree_u(), s.degree_v(), s.nv());
        self.pu = pu;
        let pts = s.points();
        self.du.clear();
        for &u in us {
            let sp = ku.find_span(u);
            let mut d = [[0.0; MAX_ORDER]; 3];
            crate::basis::ders_basis_funs::<3>(ku.values(), sp, ku.clamp(u), pu, &mut d);
            self.du.push(d);
        }
        // every u-parameter lies in the same knot span (the cell's): the rows of the cell
        let span_u = ku.find_span(us[0]);
        self.t.clear();
        for &v in vs {
            let sp = kv.find_span(v);
            let mut dv = [[0.0; MAX_ORDER]; 3];
            crate::basis::ders_basis_funs::<3>(kv.values(), sp, kv.clamp(v), pv, &mut dv);
            let mut rows = [[DVec3::ZERO; 3]; MAX_ORDER];
            for (ia, row) in rows.iter_mut().enumerate().take(pu + 1) {
                for jb in 0..=pv {
                    let q = pts[(span_u - pu + ia) * nv + sp - pv + jb];
                    for l in 0..3 {
                        row[l] += q * dv[l][jb];
                    }
                }
            }
            self.t.push(rows);
        }
    }

    fn at(&self, a: usize, b: usize) -> SurfaceDerivs {
        let du = &self.du[a];
        let rows = &self.t[b];
        let mut acc = [[DVec3::ZERO; 3]; 3];
        for ia in 0..=self.pu {
            for k in 0..3 {
                for l in 0..3 - k {
                    acc[k][l] += rows[ia][l] * du[k][ia];
                }
            }
        }
        SurfaceDerivs {
            p: acc[0][0],
            su: acc[1][0],
            sv: acc[0][1],
            suu: acc[2][0],
            suv: acc[1][1],
            svv: acc[0][2],
        }
    }
}

/// All surface measures of FAIRED against ORIGINAL (`fairway measure` on surfaces).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SurfaceMeasures {
    /// Max distance ORIGINAL → FAIRED.
    pub dev_max: f64,
    /// RMS distance ORIGINAL → FAIRED.
    pub dev_rms: f64,
    /// Max distance FAIRED → ORIGINAL.
    pub dev_max_reverse: f64,
    /// The larger of the two.
    pub hausdorff: f64,
    /// Curvature extrema of the u-isocurves plus the v-isocurves.
    pub n_curv_extrema: usize,
    /// Of the u-isocurves.
    pub n_curv_extrema_u: usize,
    /// Of the v-isocurves.
    pub n_curv_extrema_v: usize,
    /// Σ ∫ (dκ_n/ds)² ds over all isocurves.
    #[serde(rename = "E_var")]
    pub e_var: f64,
    /// ∫∫ |∇H|² dA.
    pub mean_curv_var: f64,
    /// Isophote waviness of FAIRED: geodesic-curvature sign changes over all its isophotes
    /// ([`isophote_waviness`] with [`ISOPHOTE_LIGHT`], [`ISOPHOTE_STEP_DEG`], [`ISOPHOTE_DEAD_BAND`]).
    pub n_isophote_inflections: usize,
    /// Isophote polylines traced on FAIRED.
    pub n_isophotes: usize,
    /// Number of isocurves per direction.
    pub n_iso: usize,
    /// Dead band δ of the extrema count.
    pub delta: f64,
}

/// Deviation samples per direction of [`surface_measures`].
pub const DEV_SAMPLES: usize = 101;
/// Isocurves per direction of [`surface_measures`].
pub const N_ISO: usize = 20;

/// Measure FAIRED against ORIGINAL (module docs): deviation on a 101×101 grid,
/// 20 isocurves per direction, δ from the original.
pub fn surface_measures(original: &BSplineSurface, faired: &BSplineSurface) -> SurfaceMeasures {
    let (dev_max, dev_rms) = deviation(original, faired, DEV_SAMPLES);
    let (dev_max_reverse, _) = deviation(faired, original, DEV_SAMPLES);
    let so = iso_stats(original, N_ISO, 0.0);
    let delta = 0.01 * so.max_abs_kappa;
    let sf = iso_stats(faired, N_ISO, delta);
    let iso = isophote_waviness(
        faired,
        DVec3::from_array(ISOPHOTE_LIGHT),
        ISOPHOTE_STEP_DEG,
        ISOPHOTE_DEAD_BAND,
    );
    SurfaceMeasures {
        dev_max,
        dev_rms,
        dev_max_reverse,
        hausdorff: dev_max.max(dev_max_reverse),
        n_curv_extrema: sf.extrema_u + sf.extrema_v,
        n_curv_extrema_u: sf.extrema_u,
        n_curv_extrema_v: sf.extrema_v,
        e_var: sf.e_var_u + sf.e_var_v,
        mean_curv_var: mean_curvature_variation(faired),
        n_isophote_inflections: iso.n_inflections,
        n_isophotes: iso.n_isophotes,
        n_iso: N_ISO,
        delta,
    }
}

/// Light direction (normalized on use) of the isophotes in [`surface_measures`].
pub const ISOPHOTE_LIGHT: [f64; 3] = [1.0, 1.0, 1.0];
/// Angle between successive isophotes in [`surface_measures`], degrees.
pub const ISOPHOTE_STEP_DEG: f64 = 2.0;
/// uv grid nodes per knot span (and direction) on which the isophotes are traced (at least
/// [`ISOPHOTE_MIN_NODES`] per direction).
pub const ISOPHOTE_GRID_PER_SPAN: usize = 8;
/// Least number of uv grid nodes per direction of the isophote tracing.
pub const ISOPHOTE_MIN_NODES: usize = 240;
/// Most uv grid nodes per direction of the isophote tracing (memory and time stay bounded for huge nets;
/// beyond 128 spans fewer than 8 nodes per span, still ≥ 12 nodes per resampling step D/80).
pub const ISOPHOTE_MAX_NODES: usize = 1024;
/// Arc-length step of the resampled isophotes relative to D, the bounding-box diagonal.
pub const ISOPHOTE_STEP_REL: f64 = 1.0 / 80.0;
/// Dead band of the isophote inflection count: `ISOPHOTE_DEAD_BAND / D`, D the diagonal of the bounding
/// box of the surface's samples (an isophote must bend both ways with a radius below D / 2 to count).
pub const ISOPHOTE_DEAD_BAND: f64 = 2.0;

/// Isophote waviness of a surface ([`isophote_waviness`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct IsophoteStats {
    /// Isophote polylines traced (open or closed), of any length.
    pub n_isophotes: usize,
    /// Total geodesic-curvature sign changes (with the dead band) over all isophotes.
    pub n_inflections: usize,
    /// The dead band τ used (1/length).
    pub dead_band: f64,
}

/// Isophote waviness: sign changes of the geodesic curvature along the isophotes (module docs).
///
/// Definition. The isophotes of the light direction `light` are the level lines of `n·L` (n the unit
/// normal `S_u × S_v`) at the angles `arccos(n·L) = k · step_deg`, k = 1, 2, …: the reflection lines
/// a designer looks at. They are traced by marching squares on a uv grid of
/// [`ISOPHOTE_GRID_PER_SPAN`] nodes per knot span (at least [`ISOPHOTE_MIN_NODES`] per direction, at
/// most [`ISOPHOTE_MAX_NODES`], then uniform in the parameter;
/// the ambiguous saddle cells resolved by the cell-centre value), linked into polylines, mapped to 3D
/// by linear interpolation of the node positions and normals along the crossed grid edges, and
/// resampled at equal arc length with a step `h = D ·` [`ISOPHOTE_STEP_REL`] (D the bounding-box
/// diagonal of the grid samples; a geometric scale, not the grid's, so refining the grid changes the
/// count only where it was unresolved; the grid's kinks average out). At each inner
/// resampled point the signed geodesic curvature is `κ_g = ∠(a, b) / h` with the turning angle
/// between the chords `a`, `b` before and after it, signed by `(a × b)·n` (intrinsic: it does not
/// depend on the parameterization). Sign changes are counted with hysteresis: a change counts only
/// when κ_g goes from above `τ` to below `−τ` or back, with `τ = dead_band_factor / D`, D the
/// bounding-box diagonal of the grid samples (scale-invariant: the same count for a scaled copy).
/// A plane has no isophotes, a cylinder straight ones and a sphere circles: 0 for all three; a noisy
/// surface's isophotes wiggle and count many. Cost: one `derivs` per grid node plus O(isophote length).
pub fn isophote_waviness(s: &BSplineSurface, light: DVec3, step_deg: f64, dead_band_factor: f64) -> IsophoteStats {
    let l = light.normalize_or_zero();
    let mut out = IsophoteStats::default();
    if l == DVec3::ZERO || !(step_deg > 0.0 && step_deg.is_finite()) {
        return out;
    }
    let grid = |k: &crate::knots::KnotVector| {
        let bp = k.breakpoints();
        let spans = bp.len().saturating_sub(1).max(1);
        let per = ISOPHOTE_GRID_PER_SPAN.max(ISOPHOTE_MIN_NODES.div_ceil(spans));
        if spans * per + 1 > ISOPHOTE_MAX_NODES {
            // uniform in the parameter instead of per span
            let (a, b) = (bp[0], *bp.last().unwrap());
            let n = ISOPHOTE_MAX_NODES - 1;
            return (0..=n).map(|j| a + (b - a) * j as f64 / n as f64).collect::<Vec<f64>>();
        }
        let mut t = Vec::with_capacity(spans * per + 1);
        for w in bp.windows(2) {
            for j in 0..per {
                t.push(w[0] + (w[1] - w[0]) * j as f64 / per as f64);
            }
        }
        t.push(*bp.last().unwrap());
        t
    };
    let (us, vs) = (grid(s.knots_u()), grid(s.knots_v()));
    let (nu, nv) = (us.len(), vs.len());
    let mut pos = Vec::with_capacity(nu * nv);
    let mut nrm = Vec::with_capacity(nu * nv);
    let mut f = Vec::with_capacity(nu * nv);
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for &u in &us {
        for &v in &vs {
            let d = s.derivs(u, v);
            let n = d.su.cross(d.sv).normalize_or_zero();
            pos.push(d.p);
            nrm.push(n);
            f.push(if n == DVec3::ZERO { f64::NAN } else { n.dot(l) });
            lo = lo.min(d.p);
            hi = hi.max(d.p);
        }
    }
    let diag = (hi - lo).length();
    if !(diag > 0.0 && diag.is_finite()) {
        return out;
    }
    let tau = dead_band_factor / diag;
    out.dead_band = tau;
    let h = ISOPHOTE_STEP_REL * diag;
    let (fmin, fmax) = f
        .iter()
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    // edges: u-edges (i,j)-(i+1,j) then v-edges (i,j)-(i,j+1)
    let n_ue = (nu - 1) * nv;
    let ue = |i: usize, j: usize| i * nv + j;
    let ve = |i: usize, j: usize| n_ue + i * (nv - 1) + j;
    let n_edges = n_ue + nu * (nv - 1);
    let ends = |e: usize| -> (usize, usize) {
        if e < n_ue {
            (e, e + nv)
        } else {
            let k = e - n_ue;
            let (i, j) = (k / (nv - 1), k % (nv - 1));
            (i * nv + j, i * nv + j + 1)
        }
    };
    const NONE: u32 = u32::MAX;
    let mut adj = vec![[NONE; 2]; n_edges];
    let mut seen = vec![false; n_edges];
    let mut chain: Vec<usize> = Vec::new();
    let mut pts: Vec<(DVec3, DVec3)> = Vec::new();
    let mut kappa: Vec<f64> = Vec::new();
    let mut k = 1usize;
    loop {
        let theta = (k as f64 * step_deg).to_radians();
        k += 1;
        if theta >= std::f64::consts::PI {
            break;
        }
        let c = theta.cos();
        if c < fmin || c > fmax {
            continue;
        }
        let above = |node: usize| f[node] >= c;
        let crossed = |e: usize| {
            let (a, b) = ends(e);
            f[a].is_finite() && f[b].is_finite() && above(a) != above(b)
        };
        for a in adj.iter_mut() {
            *a = [NONE; 2];
        }
        let link = |adj: &mut [[u32; 2]], a: usize, b: usize| {
            for (x, y) in [(a, b), (b, a)] {
                let s = &mut adj[x];
                if s[0] == NONE {
                    s[0] = y as u32;
                } else if s[1] == NONE {
                    s[1] = y as u32;
                }
            }
        };
        for i in 0..nu - 1 {
            for j in 0..nv - 1 {
                let e = [ue(i, j), ve(i + 1, j), ue(i, j + 1), ve(i, j)];
                let cr = e.map(crossed);
                let n_cr = cr.iter().filter(|&&x| x).count();
                if n_cr == 2 {
                    let mut it = (0..4).filter(|&q| cr[q]);
                    let (p, q) = (it.next().unwrap(), it.next().unwrap());
                    link(&mut adj, e[p], e[q]);
                } else if n_cr == 4 {
                    let corners = [i * nv + j, (i + 1) * nv + j, (i + 1) * nv + j + 1, i * nv + j + 1];
                    let centre = corners.iter().map(|&q| f[q]).sum::<f64>() * 0.25;
                    if (centre >= c) == above(corners[0]) {
                        link(&mut adj, e[0], e[1]);
                        link(&mut adj, e[2], e[3]);
                    } else {
                        link(&mut adj, e[3], e[0]);
                        link(&mut adj, e[1], e[2]);
                    }
                }
            }
        }
        seen.fill(false);
        // open chains first (from an end: one neighbour), then closed loops
        for pass in 0..2 {
            for start in 0..n_edges {
                if seen[start] || adj[start][0] == NONE {
                    continue;
                }
                let is_end = adj[start][1] == NONE;
                if (pass == 0) != is_end {
                    continue;
                }
                chain.clear();
                let (mut prev, mut cur) = (usize::MAX, start);
                loop {
                    seen[cur] = true;
                    chain.push(cur);
                    let nb = adj[cur];
                    let next = if nb[0] != NONE && nb[0] as usize != prev && !seen[nb[0] as usize] {
                        nb[0] as usize
                    } else if nb[1] != NONE && nb[1] as usize != prev && !seen[nb[1] as usize] {
                        nb[1] as usize
                    } else {
                        break;
                    };
                    prev = cur;
                    cur = next;
                }
                let closed = pass == 1;
                if closed {
                    chain.push(start);
                }
                out.n_isophotes += 1;
                // crossing points (bilinear along the edge)
                pts.clear();
                for &e in chain.iter() {
                    let (a, b) = ends(e);
                    let t = (f[a] - c) / (f[a] - f[b]);
                    let p = pos[a] + (pos[b] - pos[a]) * t;
                    let n = (nrm[a] + (nrm[b] - nrm[a]) * t).normalize_or_zero();
                    pts.push((p, n));
                }
                out.n_inflections += sign_changes(&pts, h, tau, &mut kappa, closed);
            }
        }
    }
    out
}

/// Resample the polyline at arc-length step `h` and count the hysteresis sign changes of its turning
/// curvature (see [`isophote_waviness`]).
fn sign_changes(pts: &[(DVec3, DVec3)], h: f64, tau: f64, kappa: &mut Vec<f64>, closed: bool) -> usize {
    // resample
    let mut res: Vec<(DVec3, DVec3)> = Vec::new();
    if pts.len() < 2 {
        return 0;
    }
    res.push(pts[0]);
    let (mut acc, mut next) = (0.0, h); // arc length at the segment start, of the next sample
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = a.0.distance(b.0);
        while len > 0.0 && next <= acc + len {
            let t = (next - acc) / len;
            res.push((a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t));
            next += h;
        }
        acc += len;
    }
    if closed && res.len() > 3 {
        // wrap around: the first two points follow the last
        let (r0, r1) = (res[0], res[1]);
        res.push(r0);
        res.push(r1);
    }
    kappa.clear();
    for w in res.windows(3) {
        let (a, b) = (w[1].0 - w[0].0, w[2].0 - w[1].0);
        let x = a.cross(b);
        let sgn = x.dot(w[1].1).signum();
        let ang = x.length().atan2(a.dot(b));
        kappa.push(sgn * ang / h);
    }
    let mut state = 0i8;
    let mut count = 0;
    for &k in kappa.iter() {
        if k > tau {
            if state < 0 {
                count += 1;
            }
            state = 1;
        } else if k < -tau {
            if state > 0 {
                count += 1;
            }
            state = -1;
        }
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::knots::KnotVector;

    /// z = c x³ over [0,1]×[0,1] as an exact bicubic (Bézier in u, linear data in v).
    fn cubic_cylinder(c: f64) -> BSplineSurface {
        // x(u) = u, z = c u³: Bézier control values of u³ are 0,0,0,1; of u: 0,1/3,2/3,1
        let ku = KnotVector::uniform(3, 4).unwrap();
        let kv = KnotVector::uniform(3, 4).unwrap();
        let zs = [0.0, 0.0, 0.0, c];
        let mut pts = Vec::new();
        for i in 0..4 {
            for j in 0..4 {
                pts.push(DVec3::new(i as f64 / 3.0, j as f64 / 3.0, zs[i]));
            }
        }
        BSplineSurface::try_new(3, 3, ku.values().to_vec(), kv.values().to_vec(), 4, 4, pts, None).unwrap()
    }

    #[test]
    fn mean_curvature_variation_matches_closed_form() {
        let c = 0.7;
        let s = cubic_cylinder(c);
        // H(x) = κ/2 with κ = z''/(1+z'²)^{3/2} (sign by normal Su×Sv = (−z', 0, 1)·…, squared anyway)
        let hh = |x: f64| 0.5 * 6.0 * c * x / (1.0 + 9.0 * c * c * x.powi(4)).powf(1.5);
        // ∫∫|∇H|² dA = ∫ H'(x)² / sqrt(1+z'²) dx (width 1 in y)
        let n = 20000;
        let mut exact = 0.0;
        for k in 0..n {
            let x = (k as f64 + 0.5) / n as f64;
            let h = 1e-6;
            let dh = (hh(x + h) - hh(x - h)) / (2.0 * h);
            exact += dh * dh / (1.0 + 9.0 * c * c * x.powi(4)).sqrt() / n as f64;
        }
        let got = mean_curvature_variation(&s);
        assert!((got - exact).abs() < 1e-3 * exact, "{got} vs {exact}");
        // a plane has none
        let flat = cubic_cylinder(0.0);
        assert!(mean_curvature_variation(&flat).abs() < 1e-12);
    }

    #[test]
    fn cell_derivatives_are_those_of_the_surface_bit_for_bit() {
        let s = crate::fit_surface::fit_graph(7, |u, v| (3.0 * u).sin() * (2.0 * v).cos() + u * v * v).unwrap();
        let bp = s.knots_u().breakpoints();
        let (a0, a1) = (bp[1], bp[2]);
        let us: Vec<f64> = (0..7).map(|k| a0 + (a1 - a0) * (0.05 + 0.9 * k as f64 / 6.0)).collect();
        let vs: Vec<f64> = (0..5).map(|k| a0 + (a1 - a0) * (0.1 + 0.2 * k as f64)).collect();
        let mut cell = CellDerivs::default();
        cell.prepare(&s, &us, &vs);
        for (a, &u) in us.iter().enumerate() {
            for (b, &v) in vs.iter().enumerate() {
                assert_eq!(cell.at(a, b), s.derivs(u, v), "({u}, {v})");
            }
        }
    }

    #[test]
    fn mean_curvature_variation_vanishes_on_a_sphere_and_a_cylinder() {
        // ∇H = 0 where H is constant: rational (exact) patches of a sphere and a cylinder
        for (name, s, r) in [
            ("sphere", sphere_patch(2.0), 2.0),
            ("cylinder", cylinder_patch(1.5, 2.0), 1.5),
        ] {
            // the patch is where it should be and H is the constant ∓1/r (sphere) or ∓1/(2r) (cylinder)
            let p = s.point(0.3, 0.6);
            let k = s.curvature(0.3, 0.6);
            if name == "sphere" {
                assert!(
                    (p.length() - r).abs() < 1e-12 && (k.mean.abs() - 1.0 / r).abs() < 1e-12,
                    "{k:?}"
                );
            } else {
                assert!((p.truncate().length() - r).abs() < 1e-12 && (k.mean.abs() - 0.5 / r).abs() < 1e-12);
            }
            let h = mean_curvature_variation(&s);
            assert!(h.abs() < 1e-12, "{name}: {h}");
        }
    }

    /// A patch of the sphere of radius `r`: longitude 0..90° (a quarter circle as one rational quadratic)
    /// times latitude 0..60° (likewise; it stays away from the pole, where Su × Sv vanishes). Both
    /// arcs' homogeneous forms multiply, so the patch lies on the sphere exactly.
    fn sphere_patch(r: f64) -> BSplineSurface {
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let lon = [(1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        let a = std::f64::consts::FRAC_PI_3;
        let h = 0.5 * a;
        // the middle control point at the end tangents' crossing, weight cos(half angle)
        let lat = [(1.0, 0.0), (1.0, h.tan()), (a.cos(), a.sin())];
        let (w_lon, w_lat) = ([1.0, w, 1.0], [1.0, h.cos(), 1.0]);
        let mut pts = Vec::new();
        let mut ws = Vec::new();
        for (i, &(c, sn)) in lat.iter().enumerate() {
            for (j, &(x, y)) in lon.iter().enumerate() {
                pts.push(DVec3::new(r * c * x, r * c * y, r * sn));
                ws.push(w_lat[i] * w_lon[j]);
            }
        }
        let k = vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
        BSplineSurface::try_new(2, 2, k.clone(), k, 3, 3, pts, Some(ws)).unwrap()
    }

    /// A quarter of the cylinder of radius `r` and height `h`: a rational quadratic arc in u, linear in v.
    fn cylinder_patch(r: f64, h: f64) -> BSplineSurface {
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let arc = [(1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        let mut pts = Vec::new();
        let mut ws = Vec::new();
        for (i, &(x, y)) in arc.iter().enumerate() {
            for z in [0.0, h] {
                pts.push(DVec3::new(r * x, r * y, z));
                ws.push([1.0, w, 1.0][i]);
            }
        }
        BSplineSurface::try_new(
            2,
            1,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![0.0, 0.0, 1.0, 1.0],
            3,
            2,
            pts,
            Some(ws),
        )
        .unwrap()
    }

    #[test]
    fn mean_curvature_variation_of_a_polynomial_graph_matches_a_direct_quadrature() {
        // the separable evaluation against a point-by-point one of the same rule: bit-identical H, so the
        // totals agree to rounding of the sum
        let s = crate::fit_surface::fit_graph(6, |u, v| 0.3 * (2.0 * u).sin() * v + 0.2 * u * u * v);
        let s = s.unwrap();
        let gl = crate::quadrature::GaussLegendre::new(4);
        let mut direct = 0.0;
        let bp = s.knots_u().breakpoints();
        for w in bp.windows(2) {
            for z in bp.windows(2) {
                let (a0, a1, b0, b1) = (w[0], w[1], z[0], z[1]);
                let (hu, hv) = (1e-5 * (a1 - a0), 1e-5 * (b1 - b0));
                for (x, wx) in gl.nodes.iter().zip(&gl.weights) {
                    for (y, wy) in gl.nodes.iter().zip(&gl.weights) {
                        let u = 0.5 * (a0 + a1) + 0.5 * (a1 - a0) * x;
                        let v = 0.5 * (b0 + b1) + 0.5 * (b1 - b0) * y;
                        let d = s.derivs(u, v);
                        let (e, f, g) = (d.su.dot(d.su), d.su.dot(d.sv), d.sv.dot(d.sv));
                        let det = e * g - f * f;
                        let h_u = (mean_at(&s, u + hu, v) - mean_at(&s, u - hu, v)) / (2.0 * hu);
                        let h_v = (mean_at(&s, u, v + hv) - mean_at(&s, u, v - hv)) / (2.0 * hv);
                        let grad2 = (g * h_u * h_u - 2.0 * f * h_u * h_v + e * h_v * h_v) / det;
                        let jac = 0.25 * (a1 - a0) * (b1 - b0) * wx * wy;
                        direct += grad2 * det.sqrt() * jac;
                    }
                }
            }
        }
        let got = mean_curvature_variation_rule(&s, s.domain(), &gl);
        assert!(direct > 0.0);
        assert_eq!(got, direct);
    }

    #[test]
    fn projection_recovers_offset_points() {
        let s = cubic_cylinder(0.5);
        let proj = SurfaceProjector::new(&s, 4);
        for &(u, v) in &[(0.3, 0.4), (0.9, 0.1), (0.5, 0.5)] {
            let d = s.derivs(u, v);
            let n = d.su.cross(d.sv).normalize();
            let q = d.p + n * 0.01;
            let r = proj.project(q);
            assert!((r.distance - 0.01).abs() < 1e-10, "{r:?}");
            assert!((r.uv.0 - u).abs() < 1e-8 && (r.uv.1 - v).abs() < 1e-8);
            let r2 = proj.project_near(q, (u + 0.05, v - 0.05));
            assert!((r2.distance - 0.01).abs() < 1e-10);
        }
        // beyond the boundary: clamps to the border
        let q = s.point(1.0, 0.5) + DVec3::new(0.2, 0.0, 0.0);
        let r = proj.project(q);
        assert!((r.uv.0 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn deviation_of_an_offset_plane() {
        let a = cubic_cylinder(0.0);
        let moved: Vec<DVec3> = a.points().iter().map(|p| *p + DVec3::new(0.0, 0.0, 0.02)).collect();
        let b = a.with_points(moved).unwrap();
        let (max, rms) = deviation(&a, &b, 11);
        assert!((max - 0.02).abs() < 1e-12 && (rms - 0.02).abs() < 1e-12);
    }

    #[test]
    fn isophote_sign_changes_of_a_sine() {
        // y = sin x over [0, 4π] in the plane z = 0 (normal +z): inflections at π, 2π, 3π
        let n = 2000;
        let up = DVec3::Z;
        let pts: Vec<(DVec3, DVec3)> = (0..=n)
            .map(|i| {
                let x = 4.0 * std::f64::consts::PI * i as f64 / n as f64;
                // zig-zag noise at the point spacing: its turning is large, its scale tiny
                let z = if i % 2 == 0 { 2e-5 } else { -2e-5 };
                (DVec3::new(x, x.sin() + z, 0.0), up)
            })
            .collect();
        let mut k = Vec::new();
        assert_eq!(sign_changes(&pts, 0.05, 0.2, &mut k, false), 3);
        // the curvature along it is −sin x (turning left is positive about +z)
        let mid = k.len() / 8; // x ≈ π/2
        assert!((k[mid] + 1.0).abs() < 0.05, "{}", k[mid]);
        // without resampling (step of the point spacing) and dead band the noise counts
        assert!(sign_changes(&pts, 4.0 * std::f64::consts::PI / n as f64, 0.0, &mut k, false) > 100);
    }

    /// Least-squares bicubic graph of `f` over [0,1]² (test helper).
    fn graph(n: usize, f: impl Fn(f64, f64) -> f64) -> BSplineSurface {
        crate::fit_surface::fit_graph(n, f).unwrap()
    }

    fn default_iso(s: &BSplineSurface) -> IsophoteStats {
        isophote_waviness(
            s,
            DVec3::from_array(ISOPHOTE_LIGHT),
            ISOPHOTE_STEP_DEG,
            ISOPHOTE_DEAD_BAND,
        )
    }

    #[test]
    fn isophotes_of_plane_cylinder_and_sphere_do_not_wave() {
        // plane: n·L constant, no isophote
        let plane = graph(8, |u, v| 0.2 * u - 0.1 * v);
        assert_eq!(
            default_iso(&plane),
            IsophoteStats {
                dead_band: default_iso(&plane).dead_band,
                ..Default::default()
            }
        );
        // cylinder: straight isophotes along the rulings
        let cyl = graph(12, |u, _| (1.0 - (u - 0.5).powi(2)).sqrt());
        let c = default_iso(&cyl);
        eprintln!("cylinder {c:?}");
        assert!(c.n_isophotes >= 5 && c.n_inflections == 0, "{c:?}");
        // sphere cap lit from its pole: circles, curvature cot θ / R > 0 everywhere, so even with no dead
        // band no sign change
        let sph = graph(12, |u, v| (4.0 - (u - 0.5).powi(2) - (v - 0.5).powi(2)).sqrt());
        let sp = isophote_waviness(&sph, DVec3::Z, ISOPHOTE_STEP_DEG, 0.0);
        eprintln!("sphere {sp:?}");
        assert!(sp.n_isophotes >= 5 && sp.n_inflections == 0, "{sp:?}");
        let sp = default_iso(&sph);
        assert!(sp.n_isophotes >= 5 && sp.n_inflections == 0, "{sp:?}");
    }

    #[test]
    fn isophote_grid_is_capped_for_long_nets() {
        // 300 × 4 net (297 spans in u: 8 per span would be 2377 nodes): capped, still straight isophotes
        let (n, m) = (300, 4);
        let ku = KnotVector::uniform(3, n).unwrap();
        let kv = KnotVector::uniform(3, m).unwrap();
        let (gu, gv) = (ku.greville(), kv.greville());
        let mut pts = Vec::new();
        for &u in &gu {
            for &v in &gv {
                pts.push(DVec3::new(u, v, (1.0 - (u - 0.5).powi(2)).sqrt()));
            }
        }
        let s = BSplineSurface::try_new(3, 3, ku.values().to_vec(), kv.values().to_vec(), n, m, pts, None).unwrap();
        let st = default_iso(&s);
        assert!(st.n_isophotes >= 5 && st.n_inflections == 0, "{st:?}");
    }

    #[test]
    fn isophotes_of_a_noisy_surface_wave_and_fairing_calms_them() {
        let exact = graph(16, |u, v| 0.15 * (4.0 * u).sin() * (4.8 * v).cos() + 0.05 * u * v);
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let pts: Vec<DVec3> = exact
            .points()
            .iter()
            .map(|p| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                *p + DVec3::new(0.0, 0.0, 2e-3 * ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5))
            })
            .collect();
        let noisy = exact.with_points(pts).unwrap();
        let (c0, c1) = (default_iso(&exact), default_iso(&noisy));
        let faired = crate::fair::fair_surface(
            &noisy,
            crate::fair::SurfaceFairingOptions {
                tolerance: 2e-3,
                ..Default::default()
            },
        )
        .unwrap()
        .surface;
        let c2 = default_iso(&faired);
        eprintln!("exact {c0:?}\nnoisy {c1:?}\nfaired {c2:?}");
        // the clean wave's isophotes meander and have genuine inflections (129 measured; 126 on a grid twice
        // as fine); the noise adds many (204 / 203), the fairing removes most of them (136 / 137)
        let (n0, n1, n2) = (
            c0.n_inflections as i64,
            c1.n_inflections as i64,
            c2.n_inflections as i64,
        );
        assert!(n0 > 0 && 4 * n1 >= 5 * n0, "{c0:?} {c1:?}");
        assert!(4 * (n2 - n0).max(0) <= n1 - n0, "{c0:?} {c1:?} {c2:?}");
    }

    #[test]
    fn extrema_count() {
        let k: Vec<f64> = (0..200).map(|i| (i as f64 * 0.1).sin()).collect(); // x ∈ [0, 19.9]: extrema at π/2 + kπ
        assert_eq!(count_extrema(&k, 0.01), 6);
        let noisy: Vec<f64> = (0..200).map(|i| if i % 2 == 0 { 0.001 } else { 0.0 }).collect();
        assert_eq!(count_extrema(&noisy, 0.01), 0);
    }
}
