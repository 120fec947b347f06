//! An independent dense check of the band: its own B-spline evaluation (Cox–de Boor recursion, not
//! the crate's), `per_span` samples in every knot span of the query curve, each projected onto the
//! other curve by a polyline search in a window of spans around the last foot followed by a
//! golden-section refinement. Shares no code path with the engine's check or `measure`.
#![allow(dead_code)]

use fairway::{BSplineCurve, DVec3};

/// Cox–de Boor: N_{i,p}(u) by the recursion, with the right end of the domain in the last span.
fn basis(k: &[f64], i: usize, p: usize, u: f64) -> f64 {
    if p == 0 {
        let last = *k.last().unwrap();
        let (a, b) = (k[i], k[i + 1]);
        return if (a <= u && u < b) || (u == last && b == last && a < b) {
            1.0
        } else {
            0.0
        };
    }
    let mut v = 0.0;
    let d1 = k[i + p] - k[i];
    if d1 > 0.0 {
        v += (u - k[i]) / d1 * basis(k, i, p - 1, u);
    }
    let d2 = k[i + p + 1] - k[i + 1];
    if d2 > 0.0 {
        v += (k[i + p + 1] - u) / d2 * basis(k, i + 1, p - 1, u);
    }
    v
}

/// A curve evaluated by [`basis`] (non-rational).
pub struct Plain<'a> {
    k: &'a [f64],
    pts: &'a [DVec3],
    p: usize,
}

impl<'a> Plain<'a> {
    pub fn new(c: &'a BSplineCurve) -> Self {
        assert!(!c.is_rational());
        Self {
            k: c.knots().values(),
            pts: c.points(),
            p: c.degree(),
        }
    }

    /// The non-empty spans [a, b].
    pub fn spans(&self) -> Vec<(f64, f64)> {
        let n = self.pts.len();
        (self.p..n)
            .filter(|&s| self.k[s + 1] > self.k[s])
            .map(|s| (self.k[s], self.k[s + 1]))
            .collect()
    }

    pub fn point(&self, u: f64) -> DVec3 {
        // the span's p + 1 functions only (the others vanish): find it by bisection
        let n = self.pts.len();
        let (lo, hi) = (self.k[self.p], self.k[n]);
        let u = u.clamp(lo, hi);
        let s = if u >= hi {
            (self.p..n).rev().find(|&s| self.k[s + 1] > self.k[s]).unwrap()
        } else {
            self.k.partition_point(|&x| x <= u) - 1
        };
        (s - self.p..=s)
            .map(|i| self.pts[i] * basis(self.k, i, self.p, u))
            .sum()
    }
}

/// Max over `per_span` points per knot span of `a` (and its knots) of the distance to `b` (same
/// domain), by a search of `b` in a window of `window` spans either side of the previous foot; the
/// five largest local maxima found are then sharpened by a golden-section search between their
/// neighbouring samples (a deviation peak at a join can be narrower than the sample spacing).
pub fn dense_deviation(a: &BSplineCurve, b: &BSplineCurve, per_span: usize, window: usize) -> (f64, f64) {
    let (pa, pb) = (Plain::new(a), Plain::new(b));
    let bs = pb.spans();
    let closed = b.points()[0].distance(*b.points().last().unwrap()) <= 1e-12 * (1.0 + b.points()[0].length());
    let domain = (bs[0].0, bs[bs.len() - 1].1);
    let project = |u: f64, foot: usize| -> (f64, usize) {
        let q = pa.point(u);
        // b's span holding u (the curves share their domain and nearly their parametrization)
        let at = bs.partition_point(|s| s.1 <= u).min(bs.len() - 1);
        let centre = if foot.abs_diff(at) > window { at } else { foot };
        let (i0, i1) = (centre.saturating_sub(window), (centre + window).min(bs.len() - 1));
        let mut spans: Vec<usize> = (i0..=i1).collect();
        // a closed curve: a window at one end continues past the seam at the other
        if closed {
            let last = bs.len() - 1;
            if centre < window {
                spans.extend(last.saturating_sub(window - centre)..=last);
            }
            if centre + window > last {
                spans.extend(0..=(centre + window - last).min(last));
            }
        }
        // the polyline's vertices, the nearest of each span; those of the three nearest spans are
        // refined (a closed curve's seam point is a vertex twice, once per end, and only one side of
        // it may hold the foot; a very short span next to a long one crowds its vertices together,
        // which must not hide the long span's)
        let mut verts: Vec<(f64, f64, usize)> = vec![];
        for j in spans {
            let (x0, x1) = bs[j];
            let nearest = (0..=16)
                .map(|m| {
                    let t = x0 + (x1 - x0) * m as f64 / 16.0;
                    (pb.point(t).distance(q), t, j)
                })
                .min_by(|x, y| x.0.total_cmp(&y.0))
                .expect("17 vertices");
            verts.push(nearest);
        }
        verts.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut best = verts[0];
        let mut dist = best.0;
        for &v in verts.iter().take(3) {
            // golden section on the two polyline segments around the vertex
            let (x0, x1) = bs[v.2];
            let h = (x1 - x0) / 16.0;
            let f = |t: f64| pb.point(t).distance(q);
            // inside the domain: past its end the clamped evaluation is flat, and the ties it makes send
            // the golden section away from a foot just inside the end (a closed curve's seam)
            let here = golden((v.1 - h).max(domain.0), (v.1 + h).min(domain.1), f, false).1;
            if here < dist {
                dist = here;
                best = v;
            }
        }
        (dist, best.2)
    };
    let mut samples: Vec<(f64, f64, usize)> = vec![]; // (u, distance, foot span)
    let mut foot = 0usize; // index into bs
    for (sa, sb) in pa.spans() {
        for k in 0..=per_span + 1 {
            // the span's ends and per_span points inside
            let u = match k {
                0 => sa,
                k if k == per_span + 1 => sb,
                k => sa + (sb - sa) * (k as f64 - 0.5) / per_span as f64,
            };
            let (d, f) = project(u, foot);
            foot = f;
            samples.push((u, d, f));
        }
    }
    let mut worst = samples
        .iter()
        .fold((0.0f64, 0.0), |w, s| if s.1 > w.0 { (s.1, s.0) } else { w });
    let mut peaks: Vec<usize> = (1..samples.len().saturating_sub(1))
        .filter(|&i| samples[i].1 >= samples[i - 1].1 && samples[i].1 >= samples[i + 1].1)
        .collect();
    peaks.sort_by(|&i, &j| samples[j].1.total_cmp(&samples[i].1));
    for &i in peaks.iter().take(5) {
        let (lo, hi, f0) = (samples[i - 1].0, samples[i + 1].0, samples[i].2);
        let (u, d) = golden(lo, hi, |u| project(u, f0).0, true);
        if d > worst.0 {
            worst = (d, u);
        }
    }
    worst
}

/// Golden-section search of `f` on [lo, hi] (40 steps) for its minimum, or its maximum with `max`:
/// (argument, value).
fn golden(mut lo: f64, mut hi: f64, f: impl Fn(f64) -> f64, max: bool) -> (f64, f64) {
    let sign = if max { -1.0 } else { 1.0 };
    let g = |t: f64| sign * f(t);
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (hi - r * (hi - lo), lo + r * (hi - lo));
    let (mut fc, mut fd) = (g(c), g(d));
    for _ in 0..40 {
        if fc < fd {
            hi = d;
            d = c;
            fd = fc;
            c = hi - r * (hi - lo);
            fc = g(c);
        } else {
            lo = c;
            c = d;
            fc = fd;
            d = lo + r * (hi - lo);
            fd = g(d);
        }
    }
    if fc < fd { (c, sign * fc) } else { (d, sign * fd) }
}
