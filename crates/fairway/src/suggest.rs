//! Suggested fairing regions: the stretches of a curve where the curvature
//! is wiggly, ranked, so that a designer can pick one with a click.
//!
//! The curvature κ_i is sampled at `n` points uniform in arc length (step
//! Δs = L/(n−1)) and compared with a smoothed target g (centred moving
//! average over 2h+1 samples, h = round(window/2 · (n−1)), as in
//! [`crate::measure`]). The residual r_i = κ_i − g_i is what fairing
//! removes. A local activity a_i (moving average of r² over h+1 samples)
//! marks the samples with a_i > τ = max(2·median(a), δ²) — twice the
//! curve's typical wiggle energy, and at least a residual of δ (below);
//! samples within h of the ends (truncated average) are never marked;
//! consecutive marked samples form a run, widened by h samples on
//! each side (the tails of a wiggle) and merged with neighbours closer than
//! h samples. A run is offered when κ has at least `min_extrema`
//! curvature extrema inside it, counted as zig-zag pivots with threshold
//! δ = 0.01·max|g| (the measures' definition): a single genuine peak
//! (one extremum) is a feature, not a wiggle. Runs are ranked by the
//! residual energy ∫(κ − g)² ds over the run (Σ r_i² Δs).

use crate::arclength::ArcLengthTable;
use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::measure::{REL_THRESHOLD, moving_average, zigzag_extrema};

/// Options of [`suggest_regions`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SuggestOptions {
    /// Curvature samples over the whole curve (≥ 20).
    pub samples: usize,
    /// Moving-average window of the target as a fraction of the samples
    /// (0 < window < 1).
    pub window: f64,
    /// Fewest curvature extrema for a stretch to count as wiggly.
    pub min_extrema: usize,
    /// Most suggestions returned.
    pub max: usize,
}

impl Default for SuggestOptions {
    fn default() -> Self {
        Self {
            samples: 400,
            window: 0.1,
            min_extrema: 3,
            max: 8,
        }
    }
}

/// One suggested region.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Suggestion {
    /// Start parameter.
    pub u1: f64,
    /// End parameter.
    pub u2: f64,
    /// Arc length at the start.
    pub s1: f64,
    /// Arc length at the end.
    pub s2: f64,
    /// Curvature extrema inside (zig-zag pivots beyond δ).
    pub extrema: usize,
    /// RMS of κ − g over the stretch.
    pub rms: f64,
    /// Ranking score: ∫(κ − g)² ds over the stretch.
    pub score: f64,
}

/// The wiggly stretches of `curve`, best (largest residual energy) first.
/// An empty list means no stretch has enough extrema to be called wiggly.
pub fn suggest_regions(curve: &BSplineCurve, opts: &SuggestOptions) -> Result<Vec<Suggestion>> {
    let n = opts.samples;
    if n < 20 {
        return Err(Error::InvalidInput(format!("suggest: samples = {n}, need at least 20")));
    }
    if !(opts.window > 0.0 && opts.window < 1.0) {
        return Err(Error::InvalidInput(format!(
            "suggest: window = {}, expected a fraction in (0, 1)",
            opts.window
        )));
    }
    let table = ArcLengthTable::new(curve, 1e-10);
    let length = table.length();
    if !(length > 0.0) {
        return Err(Error::InvalidInput("suggest: the curve has zero length".into()));
    }
    let params = table.equal_arc_params(curve, n);
    let dim = curve.dim();
    let kappa: Vec<f64> = params.iter().map(|&u| curve.derivs(u).curvature(dim)).collect();
    let h = ((opts.window / 2.0 * (n - 1) as f64).round() as usize).max(1);
    let g = moving_average(&kappa, h);
    let r: Vec<f64> = kappa.iter().zip(&g).map(|(k, g)| k - g).collect();
    let r2: Vec<f64> = r.iter().map(|x| x * x).collect();
    let mut act = moving_average(&r2, h.div_ceil(2));
    // Within h samples of the ends the moving average is truncated, so g
    // lags a curvature gradient and κ − g there is not a wiggle: such
    // samples never start a run (a wiggle near an end is still covered
    // by the widening of a run that starts inside).
    let edge = h.min(n / 2);
    act[..edge].fill(0.0);
    act[n - edge..].fill(0.0);
    let mut sorted = act.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[n / 2];
    let gmax = g.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let delta = REL_THRESHOLD * gmax;
    let tau = (2.0 * median).max(delta * delta);
    let ds = length / (n - 1) as f64;

    // runs of high activity, widened by h and merged
    let mut runs: Vec<(usize, usize)> = vec![];
    let mut i = 0;
    while i < n {
        if act[i] > tau {
            let a = i;
            while i < n && act[i] > tau {
                i += 1;
            }
            let (a, b) = (a.saturating_sub(h), (i - 1 + h).min(n - 1));
            match runs.last_mut() {
                Some(last) if a <= last.1 + h => last.1 = b,
                _ => runs.push((a, b)),
            }
        } else {
            i += 1;
        }
    }

    let mut out: Vec<Suggestion> = runs
        .into_iter()
        .filter_map(|(a, b)| {
            let extrema = zigzag_extrema(&kappa[a..=b], delta);
            if extrema < opts.min_extrema || b <= a {
                return None;
            }
            let e: f64 = r2[a..=b].iter().sum::<f64>() * ds;
            Some(Suggestion {
                u1: params[a],
                u2: params[b],
                s1: a as f64 * ds,
                s2: b as f64 * ds,
                extrema,
                rms: (e / ((b - a + 1) as f64 * ds)).sqrt(),
                score: e,
            })
        })
        .collect();
    out.sort_by(|x, y| y.score.total_cmp(&x.score));
    out.truncate(opts.max);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// Uniform clamped cubic with control points on y = 0.3 sin(x/2) at the
    /// Greville abscissae, x ∈ [0, 6], with alternating bumps of size `amp` on the control
    /// points in `ripples`.
    fn curve(ripples: &[(std::ops::Range<usize>, f64)]) -> BSplineCurve {
        let n = 60;
        let p = 3;
        let inner = n - p - 1;
        let mut knots = vec![0.0; p + 1];
        knots.extend((1..=inner).map(|k| k as f64 / (inner + 1) as f64));
        knots.extend(vec![1.0; p + 1]);
        // control points at the Greville abscissae, so that the unrippled
        // curve is a fair (evenly parameterized) approximation of the sine
        let pts: Vec<DVec2> = (0..n)
            .map(|i| {
                let x = 6.0 * knots[i + 1..=i + p].iter().sum::<f64>() / p as f64;
                let mut y = 0.3 * (x / 2.0).sin();
                for (r, amp) in ripples {
                    if r.contains(&i) {
                        y += if i % 2 == 0 { *amp } else { -*amp };
                    }
                }
                DVec2::new(x, y)
            })
            .collect();
        BSplineCurve::new_2d(p, knots, &pts).unwrap()
    }

    #[test]
    fn a_fair_curve_gets_no_suggestion() {
        let s = suggest_regions(&curve(&[]), &SuggestOptions::default()).unwrap();
        assert!(s.is_empty(), "{s:?}");
    }

    #[test]
    fn a_local_ripple_is_found_and_the_rest_is_left_alone() {
        let c = curve(&[(36..46, 0.004)]);
        let s = suggest_regions(&c, &SuggestOptions::default()).unwrap();
        assert_eq!(s.len(), 1, "{s:?}");
        // control point i influences u in [knot_i, knot_{i+4}] ≈ [(i-3)/57, (i+1)/57]
        let (lo, hi) = (33.0 / 57.0, 46.0 / 57.0);
        let t = s[0];
        assert!(t.u1 < lo + 0.02 && t.u2 > hi - 0.02, "does not cover the ripple: {t:?}");
        assert!(t.u1 > 0.4 && t.u2 < 0.97, "far too wide: {t:?}");
        assert!(t.extrema >= 6, "{t:?}");
        assert!(t.s1 < t.s2 && t.score > 0.0 && t.rms > 0.0);
    }

    #[test]
    fn ranked_by_wiggle_energy() {
        let c = curve(&[(8..16, 0.002), (38..46, 0.006)]);
        let s = suggest_regions(&c, &SuggestOptions::default()).unwrap();
        assert!(s.len() >= 2, "{s:?}");
        assert!(s[0].u1 > 0.5, "the larger ripple (right) should rank first: {s:?}");
        assert!(s[1].u2 < 0.5, "the smaller ripple (left) second: {s:?}");
        assert!(s[0].score > s[1].score);
        let s1 = suggest_regions(
            &c,
            &SuggestOptions {
                max: 1,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(s1, s[..1]);
    }

    #[test]
    fn bad_options_are_errors() {
        let c = curve(&[]);
        assert!(
            suggest_regions(
                &c,
                &SuggestOptions {
                    samples: 5,
                    ..Default::default()
                }
            )
            .is_err()
        );
        assert!(
            suggest_regions(
                &c,
                &SuggestOptions {
                    window: 0.0,
                    ..Default::default()
                }
            )
            .is_err()
        );
    }
}
