//! SVG export of a curve for reports: the curve, its control polygon, its
//! curvature comb, and optionally the tolerance band and a faired curve.
//!
//! Pure: returns the SVG text. 3D curves are drawn in their xy projection.
//! The comb needle at parameter u is `c(u) − s κ(u) N(u)` (pointing away
//! from the centre of curvature, as CAD systems draw it), with the scale `s`
//! chosen so the longest needle is [`SvgOptions::comb_length`] of the
//! drawing's size unless given. The band is drawn as the two offset curves
//! `c(u) ± m N(u)` (2D curves only; the exact band of a 3D curve is a tube).

use std::fmt::Write;

use glam::{DVec2, DVec3};

use crate::curve::BSplineCurve;
use crate::error::{Error, Result};

/// What to draw, and how large.
#[derive(Debug, Clone, PartialEq)]
pub struct SvgOptions {
    /// Width of the drawing in pixels (the height follows the aspect ratio).
    pub width: f64,
    /// Samples per knot span for the curve, comb and band.
    pub samples_per_span: usize,
    /// Draw the control polygon.
    pub control_polygon: bool,
    /// Draw the curvature comb.
    pub comb: bool,
    /// Comb scale `s` in model units per unit of curvature; `None` = automatic.
    pub comb_scale: Option<f64>,
    /// Longest needle as a fraction of the drawing's diagonal (automatic scale).
    pub comb_length: f64,
    /// Tolerance band half-width m (model units), drawn around the curve.
    pub band: Option<f64>,
}

impl Default for SvgOptions {
    fn default() -> Self {
        Self {
            width: 1000.0,
            samples_per_span: 16,
            control_polygon: true,
            comb: true,
            comb_scale: None,
            comb_length: 0.15,
            band: None,
        }
    }
}

fn samples(c: &BSplineCurve, per_span: usize) -> Vec<f64> {
    let bp = c.knots().breakpoints();
    let per = per_span.clamp(1, 10_000);
    let mut u = Vec::with_capacity(bp.len() * per + 1);
    for w in bp.windows(2) {
        for k in 0..per {
            u.push(w[0] + (w[1] - w[0]) * k as f64 / per as f64);
        }
    }
    if let Some(&l) = bp.last() {
        u.push(l);
    }
    u
}

fn xy(p: DVec3) -> DVec2 {
    DVec2::new(p.x, p.y)
}

/// Unit normal in the xy plane (tangent turned left), zero where undefined.
fn normal_xy(c: &BSplineCurve, u: f64) -> (DVec2, f64) {
    let d = c.derivs(u);
    let t = DVec2::new(d.d1.x, d.d1.y);
    let len = t.length();
    if !(len > 0.0) {
        return (DVec2::ZERO, 0.0);
    }
    let n = DVec2::new(-t.y, t.x) / len;
    let k = (t.x * d.d2.y - t.y * d.d2.x) / (len * len * len);
    (n, if k.is_finite() { k } else { 0.0 })
}

/// [`curve_svg`], refused if the drawing holds a coordinate that is not a finite number (a band or a
/// curve too large for the drawing's arithmetic): an SVG with `height="inf"` or `NaN` points is never
/// returned.
pub fn try_curve_svg(curve: &BSplineCurve, faired: Option<&BSplineCurve>, opts: &SvgOptions) -> Result<String> {
    let text = curve_svg(curve, faired, opts);
    // every number of the drawing is written by `{:.0}` or `{:.3}`: a non-finite one reads NaN, inf or -inf
    if text.contains("NaN") || text.contains("inf") {
        return Err(Error::InvalidInput(format!(
            "the drawing's coordinates overflow (the curve spans {}{}): nothing was written",
            crate::range::short(diagonal(curve)),
            opts.band.map_or(String::new(), |m| format!(
                ", the band is {} wide",
                crate::range::short(2.0 * m)
            ))
        )));
    }
    Ok(text)
}

/// The diagonal of the control points' bounding box in the xy plane.
fn diagonal(c: &BSplineCurve) -> f64 {
    let (lo, hi) = crate::curve::point_bounds(c.points());
    (xy(hi) - xy(lo)).length()
}

/// What an SVG drawing shows, in model xy: the curve's samples, its comb needles and their scale,
/// the band's two sides, the faired curve's samples, the control polygon, and their bounds.
struct Layers {
    pts: Vec<DVec2>,
    needles: Vec<DVec2>,
    scale: f64,
    band: Option<(Vec<DVec2>, Vec<DVec2>)>,
    faired: Option<Vec<DVec2>>,
    polygon: Vec<DVec2>,
    /// The diagonal of the curve and its control points (1 if degenerate).
    diag: f64,
    bounds: (DVec2, DVec2),
}

/// Grow `b` by the finite points of `pts`.
fn grow(b: &mut (DVec2, DVec2), pts: &[DVec2]) {
    for &p in pts.iter().filter(|p| p.is_finite()) {
        b.0 = b.0.min(p);
        b.1 = b.1.max(p);
    }
}

impl Layers {
    fn new(curve: &BSplineCurve, faired: Option<&BSplineCurve>, opts: &SvgOptions) -> Self {
        let us = samples(curve, opts.samples_per_span);
        let pts: Vec<DVec2> = us.iter().map(|&u| xy(curve.point(u))).collect();
        let frames: Vec<(DVec2, f64)> = us.iter().map(|&u| normal_xy(curve, u)).collect();
        let polygon: Vec<DVec2> = curve.points().iter().map(|p| xy(*p)).collect();
        let mut bounds = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        grow(&mut bounds, &pts);
        grow(&mut bounds, &polygon);
        let diag0 = (bounds.1 - bounds.0).length();
        let diag = if diag0 > 0.0 && diag0.is_finite() { diag0 } else { 1.0 };
        let kmax = frames.iter().map(|f| f.1.abs()).fold(0.0, f64::max);
        let scale = opts.comb_scale.unwrap_or(if kmax > 0.0 {
            opts.comb_length * diag / kmax
        } else {
            0.0
        });
        let needles: Vec<DVec2> = pts
            .iter()
            .zip(&frames)
            .map(|(p, (n, k))| *p - *n * (scale * k))
            .collect();
        if opts.comb {
            grow(&mut bounds, &needles);
        }
        let band = opts.band.filter(|m| *m > 0.0 && curve.dim() == 2).map(|m| {
            let side = |sign: f64| -> Vec<DVec2> {
                pts.iter()
                    .zip(&frames)
                    .map(|(p, (n, _))| *p + *n * (sign * m))
                    .collect()
            };
            (side(1.0), side(-1.0))
        });
        if let Some((a, b)) = &band {
            grow(&mut bounds, a);
            grow(&mut bounds, b);
        }
        let faired: Option<Vec<DVec2>> = faired.map(|f| {
            samples(f, opts.samples_per_span)
                .iter()
                .map(|&u| xy(f.point(u)))
                .collect()
        });
        if let Some(f) = &faired {
            grow(&mut bounds, f);
        }
        Self {
            pts,
            needles,
            scale,
            band,
            faired,
            polygon,
            diag,
            bounds,
        }
    }
}

/// The drawing's pixel frame: model xy → pixels (y up), with a 5 % margin around the bounds.
struct Frame {
    origin: DVec2,
    k: f64,
    px: f64,
    py: f64,
}

impl Frame {
    fn new(l: &Layers, width: f64) -> Self {
        let (mut lo, mut hi) = l.bounds;
        if !lo.is_finite() || !hi.is_finite() {
            lo = DVec2::ZERO;
            hi = DVec2::ONE;
        }
        let size = (hi - lo).max(DVec2::splat(l.diag * 1e-3));
        let margin = 0.05 * size.max_element();
        let (w, h) = (size.x + 2.0 * margin, size.y + 2.0 * margin);
        let px = width.max(1.0);
        Self {
            origin: lo - DVec2::splat(margin),
            k: px / w,
            px,
            py: px * h / w,
        }
    }

    fn map(&self, p: DVec2) -> DVec2 {
        DVec2::new((p.x - self.origin.x) * self.k, self.py - (p.y - self.origin.y) * self.k)
    }

    /// An SVG path through `v`.
    fn path(&self, v: &[DVec2]) -> String {
        let mut s = String::new();
        for (i, p) in v.iter().enumerate() {
            let q = self.map(*p);
            let _ = write!(s, "{}{:.3},{:.3}", if i == 0 { "M" } else { " L" }, q.x, q.y);
        }
        s
    }
}

/// The SVG drawing of `curve` (and of `faired`, if given, in another colour).
pub fn curve_svg(curve: &BSplineCurve, faired: Option<&BSplineCurve>, opts: &SvgOptions) -> String {
    let l = Layers::new(curve, faired, opts);
    let f = Frame::new(&l, opts.width);
    let (px, py) = (f.px, f.py);
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{px:.0}" height="{py:.0}" viewBox="0 0 {px:.3} {py:.3}">"#
    );
    let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
    if let Some((a, b)) = &l.band {
        let _ = writeln!(
            out,
            r##"<g id="band" fill="none" stroke="#8fc98f" stroke-width="1" stroke-dasharray="4 3"><path d="{}"/><path d="{}"/></g>"##,
            f.path(a),
            f.path(b)
        );
    }
    if opts.comb && l.scale > 0.0 {
        let mut d = String::new();
        for (p, q) in l.pts.iter().zip(&l.needles) {
            let (a, b) = (f.map(*p), f.map(*q));
            let _ = write!(d, "M{:.3},{:.3} L{:.3},{:.3} ", a.x, a.y, b.x, b.y);
        }
        let _ = writeln!(
            out,
            r##"<g id="comb" fill="none" stroke-width="0.7"><path d="{d}" stroke="#7a9cd6"/><path d="{}" stroke="#3060b0"/></g>"##,
            f.path(&l.needles)
        );
    }
    if opts.control_polygon {
        let mut dots = String::new();
        for p in &l.polygon {
            let q = f.map(*p);
            let _ = write!(dots, r#"<circle cx="{:.3}" cy="{:.3}" r="2.5"/>"#, q.x, q.y);
        }
        let _ = writeln!(
            out,
            r##"<g id="control-polygon" fill="#888" stroke="#888" stroke-width="0.8"><path fill="none" d="{}"/>{dots}</g>"##,
            f.path(&l.polygon)
        );
    }
    let _ = writeln!(
        out,
        r##"<path id="curve" fill="none" stroke="black" stroke-width="1.6" d="{}"/>"##,
        f.path(&l.pts)
    );
    if let Some(fp) = &l.faired {
        let _ = writeln!(
            out,
            r##"<path id="faired" fill="none" stroke="#d03030" stroke-width="1.4" d="{}"/>"##,
            f.path(fp)
        );
    }
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circle_comb_has_constant_needles_and_elements_are_present() {
        // quarter circle as a rational quadratic: κ = 1 everywhere
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let c = BSplineCurve::try_new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(0.0, 1.0, 0.0),
            ],
            Some(vec![1.0, w, 1.0]),
            2,
        )
        .unwrap();
        let opts = SvgOptions {
            comb_scale: Some(0.5),
            band: Some(0.1),
            ..Default::default()
        };
        let s = curve_svg(&c, Some(&c), &opts);
        for id in [
            "id=\"curve\"",
            "id=\"comb\"",
            "id=\"band\"",
            "id=\"control-polygon\"",
            "id=\"faired\"",
        ] {
            assert!(s.contains(id), "{id}");
        }
        assert!(s.starts_with("<svg") && s.trim_end().ends_with("</svg>"));
        // needles of a unit circle with scale 0.5 end on the circle of radius 1.5
        for &u in &samples(&c, 8) {
            let (n, k) = normal_xy(&c, u);
            assert!((k - 1.0).abs() < 1e-12);
            let tip = xy(c.point(u)) - n * (0.5 * k);
            assert!((tip.length() - 1.5).abs() < 1e-12);
        }
        assert!(!s.contains("NaN"));
    }

    #[test]
    fn degenerate_curve_gives_finite_svg() {
        let c = BSplineCurve::bezier(vec![DVec3::ZERO; 4], 2).unwrap();
        let s = curve_svg(&c, None, &SvgOptions::default());
        assert!(!s.contains("NaN") && !s.contains("inf"), "{s}");
    }
}
