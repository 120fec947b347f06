//! Colour maps of the curvature modes: a diverging map (Moreland's
//! "cool to warm", K. Moreland, *Diverging Color Maps for Scientific
//! Visualization*, ISVC 2009) with its neutral grey at zero, so that the sign
//! of a signed curvature is read off the hue and its size off the saturation.

/// Control colours of the diverging map at t = −1, −½, 0, ½, 1 (sRGB).
const STOPS: [[f32; 3]; 5] = [
    [59.0, 76.0, 192.0],
    [141.0, 176.0, 254.0],
    [221.0, 221.0, 221.0],
    [244.0, 154.0, 123.0],
    [180.0, 4.0, 38.0],
];

/// Colour (sRGB, 0..1) of `value` on the symmetric range `[−range, range]`:
/// neutral grey at 0, blue for negative, red for positive, clamped outside
/// the range. A non-finite value is magenta (visible, never silently mapped).
pub fn diverging(value: f64, range: f64) -> [f32; 3] {
    if !value.is_finite() {
        return [1.0, 0.0, 1.0];
    }
    let r = if range > 0.0 && range.is_finite() { range } else { 1.0 };
    let t = (value / r).clamp(-1.0, 1.0) as f32;
    let x = (t + 1.0) * 2.0; // 0..4
    let i = (x.floor() as usize).min(3);
    let f = x - i as f32;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    [0, 1, 2].map(|k| (a[k] + (b[k] - a[k]) * f) / 255.0)
}

/// A default symmetric range for `values`: the 95th percentile of |value|
/// (robust against the spikes of a noisy surface), or 1 if all are zero.
pub fn auto_range(values: &[f64]) -> f64 {
    let mut a: Vec<f64> = values.iter().filter(|v| v.is_finite()).map(|v| v.abs()).collect();
    if a.is_empty() {
        return 1.0;
    }
    a.sort_by(f64::total_cmp);
    let r = a[((a.len() - 1) as f64 * 0.95).round() as usize];
    if r > 0.0 { r } else { a[a.len() - 1].max(1.0) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_is_neutral_and_the_sign_sets_the_hue() {
        let z = diverging(0.0, 2.0);
        assert!((z[0] - z[1]).abs() < 1e-6 && (z[1] - z[2]).abs() < 1e-6, "{z:?}");
        for v in [0.1, 0.7, 1.9, 5.0] {
            let p = diverging(v, 2.0);
            let n = diverging(-v, 2.0);
            assert!(p[0] > p[2], "positive is warm: {p:?}");
            assert!(n[2] > n[0], "negative is cool: {n:?}");
        }
    }

    #[test]
    fn saturation_grows_with_size_and_clamps_outside_the_range() {
        let sat = |c: [f32; 3]| c.iter().cloned().fold(f32::MIN, f32::max) - c.iter().cloned().fold(f32::MAX, f32::min);
        let mut last = 0.0;
        for k in 0..=10 {
            let s = sat(diverging(k as f64 * 0.1, 1.0));
            assert!(s >= last - 1e-6, "{k}: {s} < {last}");
            last = s;
        }
        assert_eq!(diverging(1.0, 1.0), diverging(3.0, 1.0));
        assert_eq!(diverging(-1.0, 1.0), diverging(-30.0, 1.0));
        assert_eq!(diverging(f64::NAN, 1.0), [1.0, 0.0, 1.0]);
    }

    #[test]
    fn auto_range_ignores_rare_spikes() {
        let mut v: Vec<f64> = (0..100).map(|i| (i as f64 * 0.01) - 0.5).collect();
        v[3] = 1e6;
        let r = auto_range(&v);
        assert!(r > 0.4 && r < 0.5, "{r}");
        assert_eq!(auto_range(&[0.0, 0.0]), 1.0);
        assert_eq!(auto_range(&[]), 1.0);
    }
}
