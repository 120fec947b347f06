//! A curve sampled densely at equal arc length, for drawing (curve, comb,
//! κ plot) and for mapping between parameter, arc length and screen.
//!
//! This is display data only: the fairing itself is done by the core.

use fairway::{ArcLengthTable, BSplineCurve, DVec2};

/// Samples of a curve at equal arc length, projected onto the view plane
/// (x, y; a 3D curve drops z).
#[derive(Debug, Clone, Default)]
pub struct Sampled {
    /// Parameters of the samples (increasing).
    pub u: Vec<f64>,
    /// Arc length at each sample (from the curve's start).
    pub s: Vec<f64>,
    /// Points.
    pub p: Vec<DVec2>,
    /// Unit direction in which the comb is drawn at each sample (away from
    /// the centre of curvature for positive κ in 2D).
    pub n: Vec<DVec2>,
    /// Curvature (signed in 2D, unsigned in 3D).
    pub kappa: Vec<f64>,
    /// Total length.
    pub length: f64,
    /// Parameters of the inflections (2D).
    pub inflections: Vec<f64>,
    /// Sample indices of local curvature extrema.
    pub extrema: Vec<usize>,
    /// Smallest and largest κ.
    pub kappa_range: (f64, f64),
    /// Bounding box (min, max) of the samples.
    pub bbox: (DVec2, DVec2),
}

impl Sampled {
    /// Sample `curve` at `n` (≥ 2) points of equal arc length.
    pub fn new(curve: &BSplineCurve, n: usize) -> Self {
        let n = n.max(2);
        let table = ArcLengthTable::new(curve, 1e-10);
        let length = table.length();
        let mut u = Vec::with_capacity(n);
        table.equal_arc_params_into(curve, n, &mut u);
        let dim = curve.dim();
        let mut out = Self {
            s: (0..n).map(|k| length * k as f64 / (n - 1) as f64).collect(),
            p: Vec::with_capacity(n),
            n: Vec::with_capacity(n),
            kappa: Vec::with_capacity(n),
            length,
            ..Default::default()
        };
        for &ui in &u {
            let d = curve.derivs(ui);
            out.p.push(d.p.truncate());
            let k = d.curvature(dim);
            out.kappa.push(k);
            let t = d.d1.truncate().normalize_or_zero();
            let dir = if dim == 2 {
                // left normal is towards the centre for κ > 0; comb points away
                DVec2::new(t.y, -t.x)
            } else {
                -d.curvature_vector().truncate().normalize_or_zero()
            };
            out.n.push(dir);
        }
        out.u = u;
        out.inflections = curve.inflections(16);
        out.extrema = local_extrema(&out.kappa);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &k in &out.kappa {
            lo = lo.min(k);
            hi = hi.max(k);
        }
        out.kappa_range = (lo, hi);
        let (mut a, mut b) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for &p in &out.p {
            a = a.min(p);
            b = b.max(p);
        }
        out.bbox = (a, b);
        out
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.u.len()
    }

    /// True when there are no samples.
    pub fn is_empty(&self) -> bool {
        self.u.is_empty()
    }

    /// Fractional sample index of parameter `u` (clamped).
    pub fn index_at_u(&self, u: f64) -> f64 {
        frac_index(&self.u, u)
    }

    /// Fractional sample index of arc length `s` (clamped).
    pub fn index_at_s(&self, s: f64) -> f64 {
        if self.length <= 0.0 {
            return 0.0;
        }
        (s / self.length * (self.len() - 1) as f64).clamp(0.0, (self.len() - 1) as f64)
    }

    /// Arc length at parameter `u` (linear between samples).
    pub fn s_at_u(&self, u: f64) -> f64 {
        lerp_at(&self.s, self.index_at_u(u))
    }

    /// Parameter at arc length `s` (linear between samples).
    pub fn u_at_s(&self, s: f64) -> f64 {
        lerp_at(&self.u, self.index_at_s(s))
    }

    /// Curvature at arc length `s` (linear between samples).
    pub fn kappa_at_s(&self, s: f64) -> f64 {
        lerp_at(&self.kappa, self.index_at_s(s))
    }

    /// Indices of the samples covering the region `r` in order along it: from the sample at or before
    /// `u1` to the one at or after `u2`; for a region across the seam of a closed curve (`u1 > u2`,
    /// [`crate::region`]) the samples from `u1` to the end, then from the start to `u2` (the first
    /// and last samples are the same point there, so the polyline is continuous).
    pub fn region_indices(&self, r: (f64, f64)) -> Vec<usize> {
        let n = self.len();
        if n == 0 {
            return vec![];
        }
        let i1 = self.index_at_u(r.0).floor() as usize;
        let i2 = (self.index_at_u(r.1).ceil() as usize).min(n - 1);
        if crate::region::wraps(r) {
            (i1..n).chain(0..=i2).collect()
        } else {
            (i1..=i2.max(i1)).collect()
        }
    }

    /// Point at parameter `u` (linear between samples).
    pub fn point_at_u(&self, u: f64) -> DVec2 {
        let i = self.index_at_u(u);
        let k = (i.floor() as usize).min(self.len().saturating_sub(2));
        let t = i - k as f64;
        self.p[k].lerp(self.p[(k + 1).min(self.len() - 1)], t)
    }
}

/// Fractional index of `x` in the increasing sequence `xs`.
fn frac_index(xs: &[f64], x: f64) -> f64 {
    let n = xs.len();
    if n < 2 || x <= xs[0] {
        return 0.0;
    }
    if x >= xs[n - 1] {
        return (n - 1) as f64;
    }
    let k = xs.partition_point(|&v| v <= x).clamp(1, n - 1) - 1;
    let w = xs[k + 1] - xs[k];
    k as f64 + if w > 0.0 { (x - xs[k]) / w } else { 0.0 }
}

fn lerp_at(v: &[f64], i: f64) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    let k = (i.floor().max(0.0) as usize).min(v.len().saturating_sub(2));
    let t = i - k as f64;
    let b = v[(k + 1).min(v.len() - 1)];
    v[k] + (b - v[k]) * t
}

/// Indices where the discrete derivative of `k` changes sign (interior
/// samples only; flat stretches count once).
fn local_extrema(k: &[f64]) -> Vec<usize> {
    let mut out = vec![];
    let mut prev_sign = 0.0;
    let mut prev_i = 0;
    for i in 1..k.len() {
        let d = k[i] - k[i - 1];
        if d == 0.0 {
            continue;
        }
        let sg = d.signum();
        if prev_sign != 0.0 && sg != prev_sign {
            out.push(prev_i);
        }
        prev_sign = sg;
        prev_i = i;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frac_index_interpolates_and_clamps() {
        let xs = [0.0, 1.0, 3.0];
        assert_eq!(frac_index(&xs, -1.0), 0.0);
        assert_eq!(frac_index(&xs, 0.5), 0.5);
        assert_eq!(frac_index(&xs, 2.0), 1.5);
        assert_eq!(frac_index(&xs, 9.0), 2.0);
    }

    #[test]
    fn region_indices_run_through_the_seam() {
        let s = Sampled {
            u: (0..=10).map(|i| i as f64 / 10.0).collect(),
            ..Default::default()
        };
        assert_eq!(s.region_indices((0.2, 0.45)), vec![2, 3, 4, 5]);
        assert_eq!(s.region_indices((0.8, 0.15)), vec![8, 9, 10, 0, 1, 2]);
    }

    #[test]
    fn extrema_of_a_zigzag() {
        assert_eq!(local_extrema(&[0.0, 1.0, 0.0, 1.0, 1.0, 0.0]), vec![1, 2, 3]);
    }
}
