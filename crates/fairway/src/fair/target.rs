//! Target curvature g over arc length (paper §2.1, "Determining the Target
//! Curvature"), editable point by point.
//!
//! A [`Target`] holds, for the n arc-length samples of a fairing region, the
//! original curvature κ_k, the target g_k and a pin flag per sample. Pinned
//! samples are never changed by smoothing; the two end samples are pinned
//! at construction to the original curvature, so that the faired stretch
//! meets its untouched neighbours with the same curvature (G2). An end whose
//! curvature is not kept (a G1 or G0 end) is released ([`Target::release_end`]):
//! smoothing then treats it as a free end (no flux across it: the mirrored
//! stencil), so a noisy end curvature is smoothed like the interior. At a G0
//! curve end (tangent free as well) the end knot span is first filled from the
//! interior ([`Target::extrapolate_end`]): the no-flux flow conserves the mean,
//! so it would keep the end span's noise excess instead of removing it.
//!
//! Smoothing methods ([`TargetMethod`]):
//! * `Average` — the paper's repeated neighbour averaging
//!   `g_k ← (g_{k−1} + g_k + g_{k+1}) / 3`, `strength` passes;
//! * `Binomial` — the (1, 2, 1)/4 kernel, `strength` passes. Unlike the
//!   three-point average, its frequency response `cos²(ω/2)` is zero at the
//!   Nyquist frequency, so a sample-to-sample zig-zag is removed in one pass;
//! * `Heat` (default) — the same heat flow that `Average` integrates with
//!   explicit steps (one three-point pass is a forward-Euler step of
//!   `∂g/∂t = Δg` with `Δt = 1/3` sample²), integrated instead with
//!   `HEAT_STEPS` backward-Euler steps, each one tridiagonal solve
//!   (Thomas). `strength` is the flow time in passes, so `Heat` with
//!   strength P smooths like P averaging passes (same Gaussian variance
//!   2P/3 samples² at low frequencies) but costs O(n) whatever P, where the
//!   passes cost O(n·P) — and the default P grows like n²;
//! * `Fit` — the curvature-minimizing fit of the paper's eq. 3: a cubic
//!   B-spline g(s) over arc length minimizing `Σ (g(s_k) − κ_k)² + λ ∫ g''² ds`
//!   (the integral of the fitted function's bending stands in for the
//!   paper's `∫ κ̂`), with `λ` growing with `strength`; pinned samples are
//!   then restored and blended in over a few samples.

use crate::error::{Error, Result};
use crate::fit::{Smoothing, fit_curve_points};
use crate::knots::KnotVector;
use glam::DVec3;

/// How a target is smoothed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum TargetMethod {
    /// Heat flow of the averaging, integrated implicitly: O(n) for any strength (default).
    #[default]
    Heat,
    /// Repeated three-point neighbour averaging (the paper's).
    Average,
    /// Repeated (1, 2, 1)/4 binomial kernel (damps zig-zag).
    Binomial,
    /// Smoothing-spline fit to the curvature samples (paper eq. 3).
    Fit,
}

impl std::str::FromStr for TargetMethod {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "heat" => Ok(Self::Heat),
            "average" | "avg" => Ok(Self::Average),
            "binomial" => Ok(Self::Binomial),
            "fit" => Ok(Self::Fit),
            _ => Err(Error::InvalidInput(format!(
                "unknown target method {s:?}: expected heat, average, binomial or fit"
            ))),
        }
    }
}

/// Target curvature over the n samples of a region (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Target {
    original: Vec<f64>,
    values: Vec<f64>,
    pinned: Vec<bool>,
    /// Ends released by [`Self::release_end`] (start, end).
    free_ends: [bool; 2],
    /// Samples at each end that [`Self::smooth`] fills from the interior first ([`Self::extrapolate_end`]).
    extrapolated: [usize; 2],
    /// Samples at each end over which [`Self::smooth`] eases into the kept end value ([`Self::ease_end`]).
    eased: [usize; 2],
}

impl Target {
    /// A target equal to the original curvature `kappa` (n ≥ 3 samples),
    /// with both end samples pinned.
    pub fn new(kappa: &[f64]) -> Result<Self> {
        if kappa.len() < 3 {
            return Err(Error::InvalidInput(format!(
                "a target needs at least 3 samples, got {}",
                kappa.len()
            )));
        }
        if let Some(i) = kappa.iter().position(|k| !k.is_finite()) {
            return Err(Error::NotFinite {
                field: "curvature samples".into(),
                index: i,
            });
        }
        let n = kappa.len();
        let mut pinned = vec![false; n];
        pinned[0] = true;
        pinned[n - 1] = true;
        Ok(Self {
            original: kappa.to_vec(),
            values: kappa.to_vec(),
            pinned,
            free_ends: [false; 2],
            extrapolated: [0; 2],
            eased: [0; 2],
        })
    }

    /// The targets `parts` end to end (the stretches between the corners of a region,
    /// [`super::CornerSetups`]): values, original curvature and pins as they are; the first part's
    /// start and the last part's end stay released if they were. Empty for no parts.
    pub fn concat(parts: &[&Target]) -> Self {
        Self {
            original: parts.iter().flat_map(|t| t.original.iter().copied()).collect(),
            values: parts.iter().flat_map(|t| t.values.iter().copied()).collect(),
            pinned: parts.iter().flat_map(|t| t.pinned.iter().copied()).collect(),
            free_ends: [
                parts.first().is_some_and(|t| t.free_ends[0]),
                parts.last().is_some_and(|t| t.free_ends[1]),
            ],
            extrapolated: [0; 2],
            eased: [0; 2],
        }
    }

    /// Release the first (`last = false`) or the last end sample: its curvature is not a join
    /// condition (G1 or G0 end), so it is unpinned and smoothing treats it as a free end.
    pub fn release_end(&mut self, last: bool) {
        let k = if last { self.len() - 1 } else { 0 };
        self.free_ends[last as usize] = true;
        self.pinned[k] = false;
    }

    /// Treat the first (`last = false`) or the last `span` samples as missing data: [`Self::smooth`]
    /// first fills them (those not pinned) with the mean of the next `2·span` samples — a constant
    /// extrapolation from the interior — and then smooths. For a curve end whose tangent and curvature
    /// are free (G0): the end knot span of a curve fitted to noisy points carries its largest curvature
    /// error (the fewest points constrain it; on the noisy circle arc of the tests κ ramps from 0.03 to
    /// 3.9 there, true 1), and the heat flow, which conserves the mean, would spread that excess over
    /// the end instead of removing it. Ignored unless `3·span < n`.
    pub fn extrapolate_end(&mut self, last: bool, span: usize) {
        self.extrapolated[last as usize] = span;
    }

    /// Ease the first (`last = false`) or the last end into its kept curvature over `span` samples.
    /// For a G2 curve end: it has no neighbour, so the curvature it keeps is the original's own, which on
    /// a curve fitted to noisy points carries the end knot span's large error (3.9 where the true value
    /// is 1 on the noisy circle arc of the tests). A pinned end makes the smoothed target climb to that
    /// value from far inside, and the faired curve follows. With an eased end, [`Self::smooth`] smooths
    /// the target as if the end were free (released, its end span filled from the interior as at a G0
    /// curve end), then blends back from that value to the kept end value over the last `span` samples
    /// with the quintic weight: the excess stays in the end span, where the original has it. The end
    /// sample keeps its value and stays pinned; the fit still holds the end's curvature (G2). Ignored
    /// for a released end and unless `3·span < n`.
    pub fn ease_end(&mut self, last: bool, span: usize) {
        self.eased[last as usize] = span;
    }

    /// The samples over which each end is eased ([`Self::ease_end`]; 0: not eased).
    pub fn eased_ends(&self) -> [usize; 2] {
        self.eased
    }

    /// Fill the ends marked by [`Self::extrapolate_end`].
    fn fill_extrapolated_ends(&mut self) {
        let n = self.len();
        for (last, span) in [(false, self.extrapolated[0]), (true, self.extrapolated[1])] {
            if span == 0 || 3 * span >= n {
                continue;
            }
            let idx = |i: usize| if last { n - 1 - i } else { i };
            let mean = (span..3 * span).map(|i| self.values[idx(i)]).sum::<f64>() / (2 * span) as f64;
            for i in 0..span {
                if !self.pinned[idx(i)] {
                    self.values[idx(i)] = mean;
                }
            }
        }
    }

    /// Whether the first / last end sample was released ([`Self::release_end`]).
    pub fn free_ends(&self) -> [bool; 2] {
        self.free_ends
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Always false (a target has at least 3 samples).
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The target values g_k.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The original curvature κ_k.
    pub fn original(&self) -> &[f64] {
        &self.original
    }

    /// Pin flags.
    pub fn pinned(&self) -> &[bool] {
        &self.pinned
    }

    /// Set g_k (ignored for a non-finite value or an index out of range; returns whether it was set).
    /// Setting a value does not pin it; call [`Self::pin`] to keep it through smoothing.
    pub fn set(&mut self, k: usize, value: f64) -> bool {
        if k < self.len() && value.is_finite() {
            self.values[k] = value;
            true
        } else {
            false
        }
    }

    /// Pin sample k: smoothing leaves it unchanged.
    pub fn pin(&mut self, k: usize) {
        if k < self.len() {
            self.pinned[k] = true;
        }
    }

    /// Unpin sample k. The two end samples stay pinned (they carry the G2 join) unless released.
    pub fn unpin(&mut self, k: usize) {
        let n = self.len();
        if (k > 0 && k + 1 < n) || (k == 0 && self.free_ends[0]) || (k + 1 == n && self.free_ends[1]) {
            self.pinned[k] = false;
        }
    }

    /// Back to the original curvature; only the ends that were not released stay pinned.
    pub fn reset(&mut self) {
        self.values.copy_from_slice(&self.original);
        self.pinned.fill(false);
        let n = self.len();
        self.pinned[0] = !self.free_ends[0];
        self.pinned[n - 1] = !self.free_ends[1];
    }

    /// The smoothed index range of `a..=b`: the end samples only when free (not pinned), else the
    /// samples around the range are fixed boundary values.
    fn smoothed(&self, a: usize, b: usize) -> (usize, usize) {
        let n = self.len();
        let lo = if a == 0 && !self.pinned[0] { 0 } else { a.max(1) };
        let hi = if b == n - 1 && !self.pinned[n - 1] {
            n - 1
        } else {
            b.min(n - 2)
        };
        (lo, hi)
    }

    /// Smooth the whole target (after filling the ends marked by [`Self::extrapolate_end`]; ends marked
    /// by [`Self::ease_end`] are smoothed as free ends and then eased into their kept value).
    pub fn smooth(&mut self, method: TargetMethod, strength: usize) {
        let n = self.len();
        let end = |e: usize| if e == 1 { n - 1 } else { 0 };
        let eased = [0, 1].map(|e| {
            let span = self.eased[e];
            (span > 0 && 3 * span < n && !self.free_ends[e]).then_some(span)
        });
        let (free_ends, extrapolated) = (self.free_ends, self.extrapolated);
        let mut kept = [0.0; 2];
        for (e, span) in eased.iter().enumerate() {
            if let Some(span) = *span {
                kept[e] = self.values[end(e)];
                self.free_ends[e] = true;
                self.pinned[end(e)] = false;
                self.extrapolated[e] = self.extrapolated[e].max(span);
            }
        }
        self.fill_extrapolated_ends();
        self.smooth_range(0, n - 1, method, strength);
        (self.free_ends, self.extrapolated) = (free_ends, extrapolated);
        for (e, span) in eased.iter().enumerate() {
            let Some(span) = *span else { continue };
            // i samples from the end: weight 0 at the end (the kept value), 1 from `span` samples in
            for i in 0..span {
                let k = if e == 1 { n - 1 - i } else { i };
                if i > 0 && self.pinned[k] {
                    continue;
                }
                let w = quintic(i as f64 / span as f64);
                self.values[k] = w * self.values[k] + (1.0 - w) * kept[e];
            }
            self.pinned[end(e)] = true;
        }
    }

    /// Smooth the samples `a..=b` (clamped) with `strength` passes / weight;
    /// samples outside and pinned samples act as fixed boundary values.
    pub fn smooth_range(&mut self, a: usize, b: usize, method: TargetMethod, strength: usize) {
        let n = self.len();
        let b = b.min(n - 1);
        if a >= b || strength == 0 {
            return;
        }
        match method {
            TargetMethod::Heat => self.heat(a, b, strength),
            TargetMethod::Average => self.passes(a, b, strength, [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0]),
            TargetMethod::Binomial => self.passes(a, b, strength, [0.25, 0.5, 0.25]),
            TargetMethod::Fit => self.fit_range(a, b, strength),
        }
    }

    fn passes(&mut self, a: usize, b: usize, strength: usize, w: [f64; 3]) {
        // Jacobi sweeps in place: `prev` carries the old value of k − 1, and k + 1 is not yet updated
        let n = self.len();
        let (lo, hi) = self.smoothed(a, b);
        if lo > hi {
            return;
        }
        for _ in 0..strength {
            // a free end mirrors onto itself (no flux across it)
            let mut prev = self.values[lo.max(1) - 1];
            if lo == 0 {
                prev = self.values[0];
            }
            for k in lo..=hi {
                let cur = self.values[k];
                let next = if k + 1 < n { self.values[k + 1] } else { cur };
                if !self.pinned[k] {
                    self.values[k] = w[0] * prev + w[1] * cur + w[2] * next;
                }
                prev = cur;
            }
        }
    }

    /// Backward-Euler heat flow over `a..=b` for a time of `strength` averaging passes
    /// (`strength / 3` in sample² units), in `min(strength, HEAT_STEPS)` steps. Each step solves
    /// `(1 + 2τ) g_k − τ (g_{k−1} + g_{k+1}) = g_k^old` for the free samples (pinned samples and the
    /// samples around the stretch are Dirichlet values), a diagonally dominant tridiagonal system.
    fn heat(&mut self, a: usize, b: usize, strength: usize) {
        let n = self.len();
        let (lo, hi) = self.smoothed(a, b);
        if lo > hi {
            return;
        }
        let steps = strength.min(HEAT_STEPS);
        let tau = strength as f64 / 3.0 / steps as f64;
        let m = hi - lo + 1;
        let mut cp = vec![0.0; m];
        let mut dp = vec![0.0; m];
        for _ in 0..steps {
            // forward sweep of the Thomas algorithm; row i is sample lo + i
            for i in 0..m {
                let k = lo + i;
                // a free end sample (k = 0 or n − 1, not pinned) has one neighbour: no flux across the end
                let (diag, off, mut rhs) = if self.pinned[k] {
                    (1.0, 0.0, self.values[k])
                } else if k == 0 || k + 1 == n {
                    (1.0 + tau, -tau, self.values[k])
                } else {
                    (1.0 + 2.0 * tau, -tau, self.values[k])
                };
                // lower neighbour: known value outside the unknowns, else eliminated
                let lower = if i == 0 {
                    if k > 0 {
                        rhs -= off * self.values[k - 1];
                    }
                    0.0
                } else {
                    off
                };
                let upper = if i + 1 == m {
                    if k + 1 < n {
                        rhs -= off * self.values[k + 1];
                    }
                    0.0
                } else {
                    off
                };
                let denom = if i == 0 { diag } else { diag - lower * cp[i - 1] };
                cp[i] = upper / denom;
                dp[i] = if i == 0 {
                    rhs / denom
                } else {
                    (rhs - lower * dp[i - 1]) / denom
                };
            }
            // back substitution
            let mut next = dp[m - 1];
            self.values[hi] = next;
            for i in (0..m - 1).rev() {
                next = dp[i] - cp[i] * next;
                self.values[lo + i] = next;
            }
        }
    }

    fn fit_range(&mut self, a: usize, b: usize, strength: usize) {
        let m = b - a + 1;
        if m < 5 {
            return self.passes(a, b, strength, [0.25, 0.5, 0.25]);
        }
        // cubic spline over [0, 1] with about one span per 4 samples
        let spans = (m / 4).clamp(1, 400);
        let Ok(knots) = KnotVector::uniform(3, spans + 3) else {
            return;
        };
        let params: Vec<f64> = (0..m).map(|k| k as f64 / (m - 1) as f64).collect();
        let data: Vec<DVec3> = (a..=b).map(|k| DVec3::new(self.values[k], 0.0, 0.0)).collect();
        let weights: Vec<f64> = (a..=b).map(|k| if self.pinned[k] { 1e6 } else { 1.0 }).collect();
        // λ relative to the data: strength² · m · (1/m)^4 · scale, so strength ~ passes
        let s = strength as f64;
        let lambda = (s * s) * (m as f64) / (m as f64).powi(4) * 0.5;
        let Ok(cp) = fit_curve_points(
            &knots,
            &params,
            &data,
            Some(&weights),
            Smoothing { lambda, order: 2 },
            &[],
        ) else {
            return;
        };
        let Ok(spline) = crate::curve::BSplineCurve::try_new(3, knots.values().to_vec(), cp, None, 3) else {
            return;
        };
        for (j, k) in (a..=b).enumerate() {
            // pinned samples (the ends unless released) keep their value
            if self.pinned[k] {
                continue;
            }
            self.values[k] = spline.point(params[j]).x;
        }
    }

    /// Flatten samples `a..=b` (clamped) to their mean (constant curvature);
    /// pinned samples keep their value.
    pub fn flatten_range(&mut self, a: usize, b: usize) {
        let b = b.min(self.len() - 1);
        if a > b {
            return;
        }
        let mean = self.values[a..=b].iter().sum::<f64>() / (b - a + 1) as f64;
        for k in a..=b {
            if !self.pinned[k] {
                self.values[k] = mean;
            }
        }
    }
}

/// Number of backward-Euler steps of [`TargetMethod::Heat`]: with k steps a
/// frequency ω is damped by `(1 + τ_tot ω²/k)^−k` instead of the exact flow's
/// `exp(−τ_tot ω²)`; four steps damp a wiggle the flow reduces to e⁻¹⁰ to
/// 0.7 %, enough for a target that is followed only within the tolerance band.
pub(crate) const HEAT_STEPS: usize = 4;

/// The paper's quintic blending weight λ(t) = 6t⁵ − 15t⁴ + 10t³ (paper §3.1).
#[inline]
pub fn quintic(t: f64) -> f64 {
    let t = t.clamp(0.0, 1.0);
    t * t * t * (t * (6.0 * t - 15.0) + 10.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn released_ends_are_smoothed_like_the_interior() {
        // a constant signal with noisy ends: pinned ends keep their values, released ones are smoothed
        // towards the interior; the heat flow with two free ends conserves the sum (no flux out)
        let mut k = vec![1.0; 41];
        (k[0], k[1], k[39], k[40]) = (3.9, 1.6, 1.4, 2.2);
        for method in [
            TargetMethod::Heat,
            TargetMethod::Average,
            TargetMethod::Binomial,
            TargetMethod::Fit,
        ] {
            let mut pinned = Target::new(&k).unwrap();
            pinned.smooth(method, 30);
            assert_eq!((pinned.values()[0], pinned.values()[40]), (3.9, 2.2), "{method:?}");
            let mut free = Target::new(&k).unwrap();
            free.release_end(false);
            free.release_end(true);
            assert_eq!(free.free_ends(), [true, true]);
            assert!(!free.pinned()[0] && !free.pinned()[40]);
            free.smooth(method, 30);
            let (a, b) = (free.values()[0], free.values()[40]);
            assert!(a < 2.0 && b < 1.6, "{method:?}: ends {a}, {b}");
            assert!(free.values().iter().all(|v| v.is_finite()));
            if method == TargetMethod::Heat {
                let (s0, s1): (f64, f64) = (k.iter().sum(), free.values().iter().sum());
                assert!((s0 - s1).abs() < 1e-12 * s0, "{s0} vs {s1}");
            }
            // reset keeps the released ends free; unpin works on them
            free.reset();
            assert!(!free.pinned()[0] && !free.pinned()[40]);
            free.pin(0);
            free.unpin(0);
            assert!(!free.pinned()[0]);
        }
    }

    #[test]
    fn binomial_kills_zigzag_and_keeps_ends() {
        let k: Vec<f64> = (0..21).map(|i| 1.0 + if i % 2 == 0 { 0.1 } else { -0.1 }).collect();
        let mut t = Target::new(&k).unwrap();
        t.smooth(TargetMethod::Binomial, 1);
        for i in 2..19 {
            assert!((t.values()[i] - 1.0).abs() < 1e-12, "{i} {}", t.values()[i]);
        }
        assert_eq!(t.values()[0], k[0]);
        assert_eq!(t.values()[20], k[20]);
    }

    #[test]
    fn average_preserves_linear_and_pins() {
        let k: Vec<f64> = (0..30).map(|i| 0.5 + 0.01 * i as f64).collect();
        let mut t = Target::new(&k).unwrap();
        t.set(10, 5.0);
        t.pin(10);
        t.smooth(TargetMethod::Average, 20);
        assert_eq!(t.values()[10], 5.0);
        // far from the pin, a linear function is a fixed point of the average
        assert!((t.values()[25] - k[25]).abs() < 0.05);
        t.reset();
        assert_eq!(t.values(), &k[..]);
        assert!(!t.pinned()[10]);
    }

    #[test]
    fn fit_smooths_noise() {
        let k: Vec<f64> = (0..200)
            .map(|i| (i as f64 * 0.03).sin() + 0.05 * ((i * 7919 % 13) as f64 / 6.0 - 1.0))
            .collect();
        let mut t = Target::new(&k).unwrap();
        t.smooth(TargetMethod::Fit, 10);
        let err: f64 = (5..195)
            .map(|i| (t.values()[i] - (i as f64 * 0.03).sin()).abs())
            .fold(0.0, f64::max);
        let before: f64 = (5..195)
            .map(|i| (k[i] - (i as f64 * 0.03).sin()).abs())
            .fold(0.0, f64::max);
        assert!(err < 0.5 * before, "{err} {before}");
    }

    #[test]
    fn heat_follows_the_averaging_flow_in_a_few_solves() {
        // smooth signal + zig-zag noise; P passes of the average vs the implicit flow of the same time
        let n = 400;
        let k: Vec<f64> = (0..n)
            .map(|i| {
                (i as f64 * 0.01).sin()
                    + if i % 2 == 0 { 0.05 } else { -0.05 }
                    + 0.02 * ((i * 37 % 11) as f64 - 5.0) / 5.0
            })
            .collect();
        let p = 600; // σ = 20 samples
        let mut avg = Target::new(&k).unwrap();
        avg.smooth(TargetMethod::Average, p);
        let mut heat = Target::new(&k).unwrap();
        heat.smooth(TargetMethod::Heat, p);
        let smooth = |i: usize| (i as f64 * 0.01).sin();
        let err = |t: &Target| {
            (40..n - 40)
                .map(|i| (t.values()[i] - smooth(i)).abs())
                .fold(0.0, f64::max)
        };
        let noise = (40..n - 40).map(|i| (k[i] - smooth(i)).abs()).fold(0.0, f64::max);
        // σ = 20 samples also flattens the sine by ~2 % (exp(−σ²ω²/2)), so compare with the average's error:
        // both remove the noise, and they agree with each other far better than with the input
        assert!(err(&heat) < 0.4 * noise, "heat {} noise {noise}", err(&heat));
        assert!(
            err(&heat) < 1.2 * err(&avg),
            "heat {} average {}",
            err(&heat),
            err(&avg)
        );
        let diff = (0..n)
            .map(|i| (heat.values()[i] - avg.values()[i]).abs())
            .fold(0.0, f64::max);
        assert!(diff < 0.1 * noise, "heat vs average {diff}, noise {noise}");
        // ends stay pinned, and a pinned interior value stays
        assert_eq!(heat.values()[0], k[0]);
        assert_eq!(heat.values()[n - 1], k[n - 1]);
        let mut pinned = Target::new(&k).unwrap();
        pinned.set(200, 3.0);
        pinned.pin(200);
        pinned.smooth(TargetMethod::Heat, p);
        assert_eq!(pinned.values()[200], 3.0);
        assert!(
            pinned.values()[199] > 1.5,
            "the pin pulls its neighbours: {}",
            pinned.values()[199]
        );
    }

    /// A marked end is filled with the mean of the next two spans before smoothing (the other end and
    /// pinned samples are not), `reset` + `smooth` gives the same target again (the editor's path), and
    /// `smooth_range` alone does not fill.
    #[test]
    fn extrapolated_end_is_filled_from_the_interior() {
        let n = 60;
        // a noisy end ramp on the first 5 samples, 1.0 elsewhere
        let k: Vec<f64> = (0..n).map(|i| if i < 5 { 4.0 - 0.6 * i as f64 } else { 1.0 }).collect();
        let mut t = Target::new(&k).unwrap();
        t.release_end(false);
        t.release_end(true);
        let mut plain = t.clone();
        plain.smooth(TargetMethod::Heat, 30);
        t.extrapolate_end(false, 5);
        t.smooth(TargetMethod::Heat, 30);
        // the excess is gone: flat at 1 (the flow of a constant is the constant)
        for (i, g) in t.values().iter().enumerate() {
            assert!((g - 1.0).abs() < 1e-12, "{i}: {g}");
        }
        // without the fill the heat flow conserves the excess and spreads it over the end
        assert!(plain.values()[0] > 1.1, "{}", plain.values()[0]);
        let first = t.values().to_vec();
        t.reset();
        assert_eq!(t.values(), &k[..]);
        t.smooth(TargetMethod::Heat, 30);
        assert_eq!(t.values(), &first[..]);
        // a pinned sample keeps its value through the fill; smooth_range does not fill
        let mut u = Target::new(&k).unwrap();
        u.release_end(false);
        u.extrapolate_end(false, 5);
        u.pin(2);
        u.smooth(TargetMethod::Heat, 0);
        assert_eq!(u.values()[2], k[2]);
        assert_eq!(u.values()[1], 1.0);
        let mut v = Target::new(&k).unwrap();
        v.release_end(false);
        v.extrapolate_end(false, 5);
        v.smooth_range(0, n - 1, TargetMethod::Heat, 0);
        assert_eq!(v.values()[1], k[1]);
        // a span too long for the target (3·span ≥ n) is ignored
        let mut w = Target::new(&k).unwrap();
        w.extrapolate_end(false, 20);
        w.smooth(TargetMethod::Heat, 0);
        assert_eq!(w.values()[1], k[1]);
    }

    /// An eased end keeps its value and its pin, follows the free-end target (filled from the interior)
    /// from `span` samples in, and blends between the two with the quintic weight in between; an end
    /// that is released, or a span too long, is not eased.
    #[test]
    fn eased_end_joins_the_kept_value_within_its_span() {
        let n = 60;
        let span = 5;
        // the noisy end ramp of the test above at the start, a smooth slope elsewhere
        let k: Vec<f64> = (0..n)
            .map(|i| {
                if i < 5 {
                    4.0 - 0.6 * i as f64
                } else {
                    1.0 + 0.001 * i as f64
                }
            })
            .collect();
        for method in [TargetMethod::Heat, TargetMethod::Binomial, TargetMethod::Fit] {
            let mut free = Target::new(&k).unwrap();
            free.release_end(false);
            free.extrapolate_end(false, span);
            free.smooth(method, 30);
            let mut t = Target::new(&k).unwrap();
            t.ease_end(false, span);
            assert_eq!(t.eased_ends(), [span, 0]);
            t.smooth(method, 30);
            let g = t.values();
            assert_eq!(g[0], k[0], "{method:?}: the end keeps its curvature");
            assert!(t.pinned()[0] && !t.pinned()[1], "{method:?}");
            assert_eq!(t.free_ends(), [false, false], "{method:?}: not released");
            assert_eq!(g[n - 1], k[n - 1], "{method:?}: the other end is untouched");
            for i in 1..span {
                let w = quintic(i as f64 / span as f64);
                let want = w * free.values()[i] + (1.0 - w) * k[0];
                assert!((g[i] - want).abs() < 1e-12, "{method:?} {i}: {} vs {want}", g[i]);
            }
            // from the span on, the free end's target itself
            assert_eq!(&g[span..], &free.values()[span..], "{method:?}");
            // where a pinned end spreads its excess far inside
            let mut pinned = Target::new(&k).unwrap();
            pinned.smooth(method, 30);
            assert!(pinned.values()[2 * span] > g[2 * span] + 0.05, "{method:?}");
            // reset + smooth: the same target (the editor's path)
            let first = g.to_vec();
            t.reset();
            t.smooth(method, 30);
            assert_eq!(t.values(), &first[..], "{method:?}");
        }
        // a released end is not eased; nor is a span with 3·span ≥ n
        let mut released = Target::new(&k).unwrap();
        released.release_end(false);
        let mut plain = released.clone();
        released.ease_end(false, span);
        released.smooth(TargetMethod::Heat, 30);
        plain.smooth(TargetMethod::Heat, 30);
        assert_eq!(released.values(), plain.values());
        let mut long = Target::new(&k).unwrap();
        long.ease_end(false, 20);
        long.smooth(TargetMethod::Heat, 30);
        let mut pinned = Target::new(&k).unwrap();
        pinned.smooth(TargetMethod::Heat, 30);
        assert_eq!(long.values(), pinned.values());
    }

    #[test]
    fn heat_keeps_linear_and_outside_of_range() {
        let k: Vec<f64> = (0..50).map(|i| 0.3 + 0.02 * i as f64).collect();
        let mut t = Target::new(&k).unwrap();
        t.smooth(TargetMethod::Heat, 10_000);
        for i in 0..50 {
            assert!((t.values()[i] - k[i]).abs() < 1e-12, "{i}");
        }
        let mut bump = k.clone();
        bump[25] += 1.0;
        let mut t = Target::new(&bump).unwrap();
        t.smooth_range(20, 30, TargetMethod::Heat, 50);
        assert_eq!(&t.values()[..20], &bump[..20]);
        assert_eq!(&t.values()[31..], &bump[31..]);
        assert!(t.values()[25] < bump[25] - 0.5);
        assert_eq!("heat".parse::<TargetMethod>().unwrap(), TargetMethod::Heat);
    }

    #[test]
    fn flatten_and_quintic() {
        let k: Vec<f64> = (0..10).map(|i| i as f64).collect();
        let mut t = Target::new(&k).unwrap();
        t.flatten_range(2, 5);
        assert_eq!(&t.values()[2..=5], &[3.5, 3.5, 3.5, 3.5]);
        assert_eq!(quintic(0.0), 0.0);
        assert_eq!(quintic(1.0), 1.0);
        assert!((quintic(0.5) - 0.5).abs() < 1e-15);
        assert!(Target::new(&[1.0, 2.0]).is_err());
    }
}
