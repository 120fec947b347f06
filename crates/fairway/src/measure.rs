//! Quality measures of a faired curve against its original, with the exact
//! definitions (and key names) of the reference implementation described in
//! `shared/reference/README.md`:
//!
//! * `dev_max`, `dev_rms` — the ORIGINAL sampled at 2000 points uniform in
//!   arc length (ends included), each projected on the FAIRED curve (dense
//!   seeds, then Newton on `c'(t)·(c(t) − q)`); `dev_max_reverse` the same
//!   from FAIRED to ORIGINAL; `hausdorff` the larger;
//! * beyond the reference, so that the measures scale: a curve of more than
//!   100 knot spans is sampled at 20 points per span for the deviation and 40
//!   for the curvature (the counts are reported in `params`), and beyond 200
//!   spans each point is projected near the previous one's foot;
//! * target g — curvature at 200 points uniform in arc length, centred
//!   moving average over 2h+1 = 21 samples (h = round(0.1/2·199) = 10),
//!   truncated at the ends; `threshold_delta` δ = 0.01·max|g| of the
//!   ORIGINAL's target;
//! * `n_curv_extrema` — κ at 4000 arc-length samples of FAIRED, interior
//!   extrema as zig-zag pivots confirmed by a move of more than δ;
//!   `_fine` with δ/10; `_raw` every sign change of dκ/ds between
//!   consecutive samples;
//! * `n_inflections` — 2D: sign changes of κ across the dead band [−δ, δ]
//!   (`_fine` δ/10, `_raw` plain sign changes); 3D: interior runs where
//!   κ < δ (`_raw` is null);
//! * `E_var = ∫(dκ/ds)² ds`, `E_bend = ∫κ² ds` — 10-point Gauss–Legendre on
//!   4 equal pieces of every knot span; `_dimless`: `E_var·L³`, `E_bend·L`;
//! * `E_paper = Σ (κ(t_i) − g_i)²` over the 200 samples of FAIRED, g the
//!   ORIGINAL's target matched by normalized arc length; `E_paper_self` with
//!   FAIRED's own target; `_norm` = `E · L_orig² / 200`.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::arclength::ArcLengthTable;
use crate::closest::CurveProjector;
use crate::curve::BSplineCurve;
use crate::quadrature::gl10;

/// Samples for the deviation (the reference's count; a curve of more than 100 knot spans gets
/// [`DEV_SAMPLES_PER_SPAN`] per span instead, see [`dev_samples`]).
pub const DEV_SAMPLES: usize = 2000;
/// Samples for extrema and inflections (a curve of more than 100 knot spans gets
/// [`CURV_SAMPLES_PER_SPAN`] per span, see [`curv_samples`]).
pub const CURV_SAMPLES: usize = 4000;
/// Deviation samples per knot span at least.
pub const DEV_SAMPLES_PER_SPAN: usize = 20;
/// Curvature samples per knot span at least.
pub const CURV_SAMPLES_PER_SPAN: usize = 40;
/// Curves of more knot spans than this project each sample near the previous one's foot (a window of
/// spans) instead of over the whole curve, so that the measures cost time linear in the curve.
const LOCAL_SEARCH_SPANS: usize = 200;
/// Knot spans either side of the previous foot (and of the sample's own parameter) searched.
const LOCAL_WINDOW: usize = 4;

/// Deviation samples of a measure of `c`: [`DEV_SAMPLES`], or [`DEV_SAMPLES_PER_SPAN`] per knot span
/// where that is more.
pub fn dev_samples(c: &BSplineCurve) -> usize {
    DEV_SAMPLES.max(DEV_SAMPLES_PER_SPAN * c.knots().n_spans())
}

/// Curvature samples of a measure of `c`: [`CURV_SAMPLES`], or [`CURV_SAMPLES_PER_SPAN`] per knot span
/// where that is more.
pub fn curv_samples(c: &BSplineCurve) -> usize {
    CURV_SAMPLES.max(CURV_SAMPLES_PER_SPAN * c.knots().n_spans())
}
/// Samples of the target and E.
pub const PAPER_SAMPLES: usize = 200;
/// Relative threshold δ / max|g|.
pub const REL_THRESHOLD: f64 = 0.01;
/// Moving-average window as a fraction of the samples.
pub const WINDOW_FRAC: f64 = 0.1;

/// The sampling parameters, reported with the measures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeasureParams {
    /// 2000, or 20 per knot span of the original where that is more.
    pub dev_samples: usize,
    /// 4000, or 40 per knot span of the faired curve where that is more.
    pub curv_samples: usize,
    /// 0.01.
    pub rel_threshold: f64,
    /// 200.
    pub paper_samples: usize,
    /// 0.1.
    pub window_frac: f64,
    /// 2h + 1 = 21.
    pub window_samples: usize,
}

/// All measures of a faired curve against the original (see the module docs).
#[allow(non_snake_case)]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Measures {
    /// Max distance ORIGINAL → FAIRED.
    pub dev_max: f64,
    /// RMS distance ORIGINAL → FAIRED.
    pub dev_rms: f64,
    /// Max distance FAIRED → ORIGINAL.
    pub dev_max_reverse: f64,
    /// max(dev_max, dev_max_reverse).
    pub hausdorff: f64,
    /// Length of the original.
    pub length_original: f64,
    /// Length of the faired curve.
    pub length: f64,
    /// δ = 0.01 · max|g| of the original's target.
    pub threshold_delta: f64,
    /// max |κ| over the 4000 samples of the faired curve.
    pub kappa_max_abs: f64,
    /// Curvature extrema (threshold δ).
    pub n_curv_extrema: usize,
    /// Curvature extrema (threshold δ/10).
    pub n_curv_extrema_fine: usize,
    /// Sign changes of dκ/ds.
    pub n_curv_extrema_raw: usize,
    /// Inflections (dead band δ).
    pub n_inflections: usize,
    /// Inflections (dead band δ/10).
    pub n_inflections_fine: usize,
    /// Plain sign changes of κ (2D; null for 3D).
    pub n_inflections_raw: Option<usize>,
    /// 3D: torsion extrema of the faired curve, counted like the curvature extrema (τ at the 4000
    /// arc-length samples where it is defined, zig-zag pivots beyond 1 % of the largest |moving average|
    /// of the ORIGINAL's torsion at 200 samples); null for 2D. Not a reference key.
    pub n_torsion_extrema: Option<usize>,
    /// The largest step of the curvature across an interior knot (where the curve is below C2 in the
    /// parameter: a quadratic's simple knots, a cubic's double knots …), as a fraction of
    /// [`Self::kappa_max_abs`]; 0 where the curvature is continuous. ∫(dκ/ds)² ds does not see such a
    /// step, the comb shows it as a break. Not a reference key.
    pub kappa_step_max: f64,
    /// ∫(dκ/ds)² ds.
    pub E_var: f64,
    /// ∫κ² ds.
    pub E_bend: f64,
    /// E_var · L³.
    pub E_var_dimless: f64,
    /// E_bend · L.
    pub E_bend_dimless: f64,
    /// Paper's E against the original's target.
    pub E_paper: f64,
    /// Paper's E against the faired curve's own target.
    pub E_paper_self: f64,
    /// E_paper · L_orig² / 200.
    pub E_paper_norm: f64,
    /// E_paper_self · L_orig² / 200.
    pub E_paper_self_norm: f64,
    /// Sampling parameters.
    pub params: MeasureParams,
    /// Degree of the faired curve.
    pub degree: usize,
    /// Control points of the faired curve.
    pub n_ctrl: usize,
}

/// `n` parameters at equal arc length over the whole curve (ends included).
pub fn arc_params(c: &BSplineCurve, n: usize) -> Vec<f64> {
    ArcLengthTable::new(c, 1e-12).equal_arc_params(c, n)
}

/// [`kappa`] at the increasing parameters `us`, each knot span found from the previous one (the same
/// values as `kappa`, without a binary search per sample: on a 10,000-span curve that search was a
/// third of the evaluation).
fn curvatures_at(c: &BSplineCurve, us: &[f64]) -> Vec<f64> {
    let mut span = 0;
    us.iter()
        .map(|&u| {
            let (d, sp) = c.derivs2_from(u, span);
            span = sp;
            d.curvature(c.dim())
        })
        .collect()
}

/// Curvature as the reference reports it: 2D signed, 3D unsigned.
#[inline]
fn kappa(c: &BSplineCurve, u: f64) -> f64 {
    c.derivs(u).curvature(c.dim())
}

/// Distances from `n` arc-length samples of `from` to the curve `to` (closest point). On a curve `to` of
/// more than 200 knot spans each sample is projected onto the spans around the previous sample's foot
/// and around its own parameter (when the curves share a domain) — time linear in the curves, where a
/// search of the whole curve per sample is quadratic; a foot found there is a true distance, so a
/// missed nearer pass elsewhere could only make the figure larger.
pub fn deviations(from: &BSplineCurve, to: &BSplineCurve, n: usize) -> Vec<f64> {
    let proj = CurveProjector::new(to, 16);
    let us = arc_params(from, n);
    let spans = to.knots().n_spans();
    if spans <= LOCAL_SEARCH_SPANS {
        return us.into_iter().map(|u| proj.project(from.point(u)).distance).collect();
    }
    let bp = to.knots().breakpoints();
    let (t0, t1) = to.domain();
    let same_domain = from.domain() == (t0, t1);
    let closed = to.points()[0].distance(*to.points().last().expect("points")) == 0.0;
    let span_of = |t: f64| bp.partition_point(|&b| b <= t).saturating_sub(1).min(bp.len() - 2);
    let mut foot: Option<f64> = None;
    us.into_iter()
        .map(|u| {
            let q = from.point(u);
            let hit = match foot {
                None => proj.project(q),
                Some(f) => {
                    let (mut lo, mut hi) = (span_of(f), span_of(f));
                    if same_domain {
                        (lo, hi) = (lo.min(span_of(u)), hi.max(span_of(u)));
                    }
                    let (a, b) = (
                        lo.saturating_sub(LOCAL_WINDOW),
                        (hi + 1 + LOCAL_WINDOW).min(bp.len() - 1),
                    );
                    let mut best = proj.project_between(q, bp[a], bp[b]);
                    // a closed curve: the window continues past the seam
                    if closed && lo < LOCAL_WINDOW {
                        let a = (bp.len() - 1).saturating_sub(LOCAL_WINDOW - lo);
                        let other = proj.project_between(q, bp[a], t1);
                        if other.distance < best.distance {
                            best = other;
                        }
                    }
                    if closed && hi + 1 + LOCAL_WINDOW > bp.len() - 1 {
                        let b = (hi + 1 + LOCAL_WINDOW - (bp.len() - 1)).min(bp.len() - 1);
                        let other = proj.project_between(q, t0, bp[b]);
                        if other.distance < best.distance {
                            best = other;
                        }
                    }
                    best
                }
            };
            foot = Some(hit.param);
            hit.distance
        })
        .collect()
}

/// Centred moving average over `2h + 1` samples, truncated at the ends.
pub fn moving_average(k: &[f64], h: usize) -> Vec<f64> {
    let n = k.len();
    let mut prefix = vec![0.0; n + 1];
    for i in 0..n {
        prefix[i + 1] = prefix[i] + k[i];
    }
    (0..n)
        .map(|i| {
            let a = i.saturating_sub(h);
            let b = (i + h).min(n - 1);
            (prefix[b + 1] - prefix[a]) / (b - a + 1) as f64
        })
        .collect()
}

fn window_h() -> usize {
    (WINDOW_FRAC / 2.0 * (PAPER_SAMPLES - 1) as f64).round() as usize
}

/// The reference's target of a curve: curvature at 200 arc-length samples, moving average.
pub fn reference_target(c: &BSplineCurve) -> (Vec<f64>, Vec<f64>) {
    let k: Vec<f64> = arc_params(c, PAPER_SAMPLES).into_iter().map(|u| kappa(c, u)).collect();
    let g = moving_average(&k, window_h());
    (k, g)
}

/// Interior extrema counted as zig-zag pivots with threshold `delta`.
pub fn zigzag_extrema(k: &[f64], delta: f64) -> usize {
    if k.is_empty() {
        return 0;
    }
    let mut count = 0;
    // dir: 0 undecided, 1 rising (tracking a max), -1 falling (tracking a min)
    let mut dir = 0i32;
    let (mut hi, mut lo) = (k[0], k[0]);
    let mut ext = k[0];
    for &x in &k[1..] {
        match dir {
            0 => {
                hi = hi.max(x);
                lo = lo.min(x);
                if x > lo + delta {
                    dir = 1;
                    ext = x;
                } else if x < hi - delta {
                    dir = -1;
                    ext = x;
                }
            }
            1 => {
                if x > ext {
                    ext = x;
                } else if x < ext - delta {
                    count += 1;
                    dir = -1;
                    ext = x;
                }
            }
            _ => {
                if x < ext {
                    ext = x;
                } else if x > ext + delta {
                    count += 1;
                    dir = 1;
                    ext = x;
                }
            }
        }
    }
    count
}

/// Sign changes of κ across the dead band `[−delta, delta]`.
pub fn dead_band_crossings(k: &[f64], delta: f64) -> usize {
    let mut state = 0i32;
    let mut count = 0;
    for &x in k {
        let s = if x > delta {
            1
        } else if x < -delta {
            -1
        } else {
            0
        };
        if s != 0 {
            if state != 0 && s != state {
                count += 1;
            }
            state = s;
        }
    }
    count
}

/// Plain sign changes between consecutive values (zeros skipped).
pub fn sign_changes(v: &[f64]) -> usize {
    let mut prev = 0.0f64;
    let mut count = 0;
    for &x in v {
        if x == 0.0 || !x.is_finite() {
            continue;
        }
        if prev != 0.0 && (x > 0.0) != (prev > 0.0) {
            count += 1;
        }
        prev = x;
    }
    count
}

/// Interior runs of `k < delta` (not touching the first or the last sample).
pub fn interior_low_runs(k: &[f64], delta: f64) -> usize {
    let n = k.len();
    let mut count = 0;
    let mut i = 0;
    while i < n {
        if k[i] < delta {
            let start = i;
            while i < n && k[i] < delta {
                i += 1;
            }
            if start > 0 && i < n {
                count += 1;
            }
        } else {
            i += 1;
        }
    }
    count
}

/// `(∫(dκ/ds)² ds, ∫κ² ds)` by 10-point Gauss–Legendre on 4 equal pieces of every knot span.
pub fn energies(c: &BSplineCurve) -> (f64, f64) {
    energies_with(c, 4)
}

/// [`energies`] with `pieces` Gauss–Legendre rules of 10 nodes a knot span (`energies` has 4).
pub(crate) fn energies_with(c: &BSplineCurve, pieces: usize) -> (f64, f64) {
    let gl = gl10();
    let dim = c.dim();
    let (mut ev, mut eb) = (0.0, 0.0);
    let pieces = pieces.max(1);
    let mut span = 0;
    for w in c.knots().breakpoints().windows(2) {
        // the Gauss nodes lie inside the span: found once (the same span `derivs` finds at each node)
        span = c.knots().find_span_from(0.5 * (w[0] + w[1]), span);
        for q in 0..pieces {
            let a = w[0] + (w[1] - w[0]) * q as f64 / pieces as f64;
            let b = w[0] + (w[1] - w[0]) * (q + 1) as f64 / pieces as f64;
            let h = 0.5 * (b - a);
            for (x, wt) in gl.nodes.iter().zip(&gl.weights) {
                let u = 0.5 * (a + b) + h * x;
                let d = c.derivs_in_span(span, u);
                let v = d.d1.length();
                let k = d.curvature(dim);
                let dk = d.dkappa_ds(dim);
                ev += wt * h * v * dk * dk;
                eb += wt * h * v * k * k;
            }
        }
    }
    (ev, eb)
}

/// The paper's E of `curve` against a given target: `Σ (κ(t_i) − g(s_i/L))²`
/// over the 200 arc-length samples t_i of `curve` (as `E_paper`), where the
/// target values `target` are taken as uniform in normalized arc length
/// `[0, 1]` (first and last included) and interpolated linearly at `s_i/L`.
/// Returns `None` for fewer than 2 target values or a non-finite one.
pub fn paper_energy(curve: &BSplineCurve, target: &[f64]) -> Option<f64> {
    let m = target.len();
    if m < 2 || target.iter().any(|x| !x.is_finite()) {
        return None;
    }
    let n = PAPER_SAMPLES;
    let e = arc_params(curve, n)
        .into_iter()
        .enumerate()
        .map(|(i, u)| {
            let x = i as f64 / (n - 1) as f64 * (m - 1) as f64;
            let j = (x.floor() as usize).min(m - 2);
            let f = x - j as f64;
            let g = target[j] * (1.0 - f) + target[j + 1] * f;
            let r = kappa(curve, u) - g;
            r * r
        })
        .sum();
    Some(e)
}

/// [`Measures::n_curv_extrema`] of `faired` alone (the dead band from `original`), without the deviation
/// and the other figures: the count the engine's guards compare.
pub fn curvature_extrema(original: &BSplineCurve, faired: &BSplineCurve) -> usize {
    curvature_extrema_at(faired, extrema_threshold(original))
}

/// The dead band of [`Measures::n_curv_extrema`] for curves faired from `original`:
/// [`REL_THRESHOLD`] × the largest |κ| of its reference target.
pub fn extrema_threshold(original: &BSplineCurve) -> f64 {
    let (_, g_orig) = reference_target(original);
    REL_THRESHOLD * g_orig.iter().fold(0.0f64, |m, g| m.max(g.abs()))
}

/// The curvature extrema of `c` with the dead band `delta` ([`extrema_threshold`]), at `measure`'s
/// arc-length samples.
pub fn curvature_extrema_at(c: &BSplineCurve, delta: f64) -> usize {
    let kk = curvatures_at(c, &arc_params(c, curv_samples(c)));
    zigzag_extrema(&kk, delta)
}

/// The curvature extrema of a closed curve counted around the loop, with the dead band `delta`: the
/// samples of [`curvature_extrema_at`] read cyclically from the largest |κ| (itself one extremum), so
/// that where the seam sits does not count. (An open count misses an extremum at the seam and finds it
/// once a fair across the seam moves it inside: the same curve, one more.) 0 for a curve whose
/// curvature varies less than `delta`, such as a circle.
pub fn curvature_extrema_around(c: &BSplineCurve, delta: f64) -> usize {
    let mut kk = curvatures_at(c, &arc_params(c, curv_samples(c)));
    // the last sample is the first point again
    kk.pop();
    let Some(top) = (0..kk.len()).max_by(|&a, &b| kk[a].total_cmp(&kk[b])) else {
        return 0;
    };
    let lo = kk.iter().copied().fold(f64::INFINITY, f64::min);
    if kk[top] - lo <= delta {
        return 0;
    }
    kk.rotate_left(top);
    kk.push(kk[0]);
    zigzag_extrema(&kk, delta) + 1
}

/// All measures of `faired` against `original`.
///
/// A copy shifted by `d` deviates by `d` everywhere and has the original's curvature:
///
/// ```
/// use fairway::{BSplineCurve, DVec2};
/// use fairway::measure::measure;
/// let pts: Vec<DVec2> = (0..8).map(|i| DVec2::new(i as f64, (i as f64 * 0.8).sin())).collect();
/// let knots = [vec![0.0; 4], (1..5).map(|i| i as f64 / 5.0).collect(), vec![1.0; 4]].concat();
/// let c = BSplineCurve::new_2d(3, knots.clone(), &pts)?;
/// let shifted: Vec<DVec2> = pts.iter().map(|&q| q + DVec2::new(0.0, 1e-3)).collect();
/// let m = measure(&c, &BSplineCurve::new_2d(3, knots, &shifted)?);
/// assert!(m.dev_max <= 1e-3 + 1e-12 && m.dev_max > 0.5e-3);
/// assert_eq!(m.n_curv_extrema, measure(&c, &c).n_curv_extrema);
/// # Ok::<(), fairway::Error>(())
/// ```
pub fn measure(original: &BSplineCurve, faired: &BSplineCurve) -> Measures {
    let n_dev = dev_samples(original);
    let fwd = deviations(original, faired, n_dev);
    let rev = deviations(faired, original, n_dev);
    let dev_max = fwd.iter().copied().fold(0.0, f64::max);
    let dev_rms = (fwd.iter().map(|d| d * d).sum::<f64>() / fwd.len() as f64).sqrt();
    let dev_max_reverse = rev.iter().copied().fold(0.0, f64::max);
    let length_original = original.length(1e-12);
    let length = faired.length(1e-12);
    let (_, g_orig) = reference_target(original);
    let (k_f, g_self) = reference_target(faired);
    let delta = REL_THRESHOLD * g_orig.iter().fold(0.0f64, |m, g| m.max(g.abs()));
    let n_curv = curv_samples(faired);
    let us = arc_params(faired, n_curv);
    let mut kk = Vec::with_capacity(us.len());
    let mut dk = Vec::with_capacity(us.len());
    for &u in &us {
        let d = faired.derivs(u);
        kk.push(d.curvature(faired.dim()));
        dk.push(d.dkappa_ds(faired.dim()));
    }
    let kappa_max_abs = kk.iter().fold(0.0f64, |m, k| m.max(k.abs()));
    let n_torsion_extrema = (faired.dim() == 3).then(|| {
        let tau = |c: &BSplineCurve, us: &[f64]| -> Vec<f64> {
            us.iter()
                .map(|&u| c.derivs(u).torsion())
                .filter(|t| t.is_finite())
                .collect()
        };
        let g = moving_average(&tau(original, &arc_params(original, PAPER_SAMPLES)), window_h());
        let delta_tau = REL_THRESHOLD * g.iter().fold(0.0f64, |m, t| m.max(t.abs()));
        zigzag_extrema(&tau(faired, &us), delta_tau)
    });
    let (n_inf, n_inf_fine, n_inf_raw) = if faired.dim() == 2 {
        (
            dead_band_crossings(&kk, delta),
            dead_band_crossings(&kk, delta / 10.0),
            Some(sign_changes(&kk)),
        )
    } else {
        (
            interior_low_runs(&kk, delta),
            interior_low_runs(&kk, delta / 10.0),
            None,
        )
    };
    let (e_var, e_bend) = energies(faired);
    let e_paper: f64 = k_f.iter().zip(&g_orig).map(|(k, g)| (k - g) * (k - g)).sum();
    let e_self: f64 = k_f.iter().zip(&g_self).map(|(k, g)| (k - g) * (k - g)).sum();
    let norm = length_original * length_original / PAPER_SAMPLES as f64;
    Measures {
        dev_max,
        dev_rms,
        dev_max_reverse,
        hausdorff: dev_max.max(dev_max_reverse),
        length_original,
        length,
        threshold_delta: delta,
        kappa_max_abs,
        n_curv_extrema: zigzag_extrema(&kk, delta),
        n_curv_extrema_fine: zigzag_extrema(&kk, delta / 10.0),
        n_curv_extrema_raw: sign_changes(&dk),
        n_inflections: n_inf,
        n_inflections_fine: n_inf_fine,
        n_inflections_raw: n_inf_raw,
        n_torsion_extrema,
        kappa_step_max: curvature_step_max(faired) / kappa_max_abs.max(f64::MIN_POSITIVE),
        E_var: e_var,
        E_bend: e_bend,
        E_var_dimless: e_var * length.powi(3),
        E_bend_dimless: e_bend * length,
        E_paper: e_paper,
        E_paper_self: e_self,
        E_paper_norm: e_paper * norm,
        E_paper_self_norm: e_self * norm,
        params: MeasureParams {
            dev_samples: n_dev,
            curv_samples: n_curv,
            rel_threshold: REL_THRESHOLD,
            paper_samples: PAPER_SAMPLES,
            window_frac: WINDOW_FRAC,
            window_samples: 2 * window_h() + 1,
        },
        degree: faired.degree(),
        n_ctrl: faired.n_points(),
    }
}

/// The largest step |κ⁺ − κ⁻| of the curvature (signed in 2D) across an interior knot of `c` where the curve is
/// below C2 in the parameter (multiplicity above p − 2); one-sided values from each knot span's own
/// polynomial. 0 for a curve without such knots.
pub fn curvature_step_max(c: &BSplineCurve) -> f64 {
    let p = c.degree();
    let kv = c.knots();
    let bps = kv.breakpoints();
    let mut step = 0.0f64;
    for w in bps.windows(3) {
        let u = w[1];
        if kv.multiplicity(u) + 2 <= p {
            continue;
        }
        let eps = 1e-9 * (w[2] - w[0]);
        let (l, r) = (c.derivs(u - eps), c.derivs(u + eps));
        let (kl, kr) = (l.curvature(c.dim()), r.curvature(c.dim()));
        if kl.is_finite() && kr.is_finite() {
            step = step.max((kr - kl).abs());
        }
    }
    step
}

/// Curvature figures of a stretch `[u1, u2]` of `curve` (a region; `u1 > u2` on a closed curve: the
/// stretch across the seam, `[u1, end]` then `[start, u2]`): curvature extrema counted as `measure` does
/// (κ at the stretch's share of [`curv_samples`] arc-length samples, zig-zag pivots beyond `delta` — pass the whole
/// curve's `threshold_delta` so region and curve figures compare), and ∫(dκ/ds)² ds over the stretch
/// (10-point Gauss–Legendre on 4 pieces of every knot span, clipped to the stretch).
pub fn region_curvature(curve: &BSplineCurve, u1: f64, u2: f64, delta: f64) -> (usize, f64) {
    let (d0, d1) = curve.domain();
    let pieces = if u1 <= u2 {
        vec![(u1, u2)]
    } else {
        vec![(u1, d1), (d0, u2)]
    };
    let us = arc_params(curve, curv_samples(curve));
    let mut kk = vec![];
    for &(a, b) in &pieces {
        kk.extend(us.iter().filter(|&&u| u >= a && u <= b).map(|&u| kappa(curve, u)));
    }
    let gl = gl10();
    let dim = curve.dim();
    let mut ev = 0.0;
    for &(lo, hi) in &pieces {
        for w in curve.knots().breakpoints().windows(2) {
            let (a0, b0) = (w[0].max(lo), w[1].min(hi));
            if !(b0 > a0) {
                continue;
            }
            for q in 0..4 {
                let a = a0 + (b0 - a0) * q as f64 / 4.0;
                let b = a0 + (b0 - a0) * (q + 1) as f64 / 4.0;
                let h = 0.5 * (b - a);
                for (x, wt) in gl.nodes.iter().zip(&gl.weights) {
                    let d = curve.derivs(0.5 * (a + b) + h * x);
                    let dk = d.dkappa_ds(dim);
                    ev += wt * h * d.d1.length() * dk * dk;
                }
            }
        }
    }
    (zigzag_extrema(&kk, delta), ev)
}

/// Distance of a point to a polyline (helper for tests and tools).
pub fn polyline_distance(poly: &[DVec3], q: DVec3) -> f64 {
    poly.windows(2)
        .map(|w| {
            let ab = w[1] - w[0];
            let l2 = ab.length_squared();
            let t = if l2 > 0.0 {
                ((q - w[0]).dot(ab) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (w[0] + ab * t).distance(q)
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counters() {
        assert_eq!(zigzag_extrema(&[0.0, 1.0, 0.0, 1.0, 0.0], 0.5), 3);
        assert_eq!(zigzag_extrema(&[0.0, 0.1, 0.0, 0.1, 0.0], 0.5), 0);
        assert_eq!(dead_band_crossings(&[1.0, 0.0, -1.0, 0.05, 1.0], 0.1), 2);
        assert_eq!(sign_changes(&[1.0, 0.0, -1.0, 2.0]), 2);
        assert_eq!(interior_low_runs(&[0.0, 1.0, 0.0, 1.0, 0.0], 0.5), 1);
        assert_eq!(moving_average(&[1.0, 2.0, 3.0, 4.0], 1), vec![1.5, 2.0, 3.0, 3.5]);
    }

    /// An exact rational ellipse (semi-axes 3 and 1) whose seam is at the end of its major axis, a
    /// curvature maximum: around the loop it has four curvature extrema (two maxima, two minima); the open
    /// count misses the one at the seam. The circle has none.
    #[test]
    fn extrema_around_a_closed_curve_count_the_one_at_the_seam() {
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let conic = |a: f64, b: f64| {
            let xy = [
                (1., 0.),
                (1., 1.),
                (0., 1.),
                (-1., 1.),
                (-1., 0.),
                (-1., -1.),
                (0., -1.),
                (1., -1.),
                (1., 0.),
            ];
            BSplineCurve::try_new(
                2,
                vec![0., 0., 0., 1., 1., 2., 2., 3., 3., 4., 4., 4.],
                xy.iter().map(|&(x, y)| DVec3::new(a * x, b * y, 0.0)).collect(),
                Some((0..9).map(|i| if i % 2 == 0 { 1.0 } else { w }).collect()),
                2,
            )
            .unwrap()
        };
        let ellipse = conic(3.0, 1.0);
        let delta = 0.01 * 3.0; // 1 % of the largest curvature, a / b² = 3
        assert_eq!(curvature_extrema_around(&ellipse, delta), 4);
        assert_eq!(curvature_extrema_at(&ellipse, delta), 3);
        assert_eq!(curvature_extrema_around(&conic(2.0, 2.0), 0.005), 0);
    }

    #[test]
    fn paper_energy_of_a_circle_against_its_curvature() {
        // a quarter circle of radius 2 as an exact rational curve, made polynomial by refinement
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let c = BSplineCurve::try_new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(2.0, 2.0, 0.0),
                DVec3::new(0.0, 2.0, 0.0),
            ],
            Some(vec![1.0, w, 1.0]),
            2,
        )
        .unwrap();
        // the exact target 1/r gives E ≈ 0; a target off by 0.1 gives 200 · 0.01
        let e0 = paper_energy(&c, &[0.5, 0.5]).unwrap();
        assert!(e0 < 1e-16, "{e0}");
        let e1 = paper_energy(&c, &[0.6, 0.6, 0.6]).unwrap();
        assert!((e1 - 2.0).abs() < 1e-9, "{e1}");
        assert!(paper_energy(&c, &[0.5]).is_none());
        assert!(paper_energy(&c, &[0.5, f64::NAN]).is_none());
    }
}
