//! The 2D canvas: curve, control polygon, curvature comb, markers, region
//! and tolerance band; pan (right/middle drag or drag off the curve), zoom
//! (wheel), fit; region selection by dragging along the curve (on a closed
//! curve through the seam too: [`crate::region`]).

use eframe::egui;
use egui::{Color32, Pos2, Rect, Sense, Shape, Stroke, Vec2};
use fairway::DVec2;

use crate::curve_ws::CurveCx;
use crate::region::RegionDrag;
use crate::{CombScaling, Command, Sampled};

/// Pick radius around the curve and handles, in points.
const PICK: f32 = 12.0;

/// Colours shared by the canvas and the κ plot.
pub mod colors {
    use super::Color32;
    /// The original curve.
    pub const CURVE: Color32 = Color32::from_rgb(220, 220, 225);
    /// The region.
    pub const REGION: Color32 = Color32::from_rgb(255, 170, 40);
    /// Positive curvature comb.
    pub const POS: Color32 = Color32::from_rgb(70, 150, 255);
    /// Negative curvature comb.
    pub const NEG: Color32 = Color32::from_rgb(255, 90, 90);
    /// Faired preview.
    pub const FAIRED: Color32 = Color32::from_rgb(80, 220, 120);
    /// Target curvature.
    pub const TARGET: Color32 = Color32::from_rgb(230, 110, 255);
    /// Tolerance band.
    pub const BAND: Color32 = Color32::from_rgb(120, 160, 200);
}

/// What a canvas drag does.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum CanvasDrag {
    /// Nothing.
    #[default]
    None,
    /// Move the view.
    Pan,
    /// Select a region from where the drag started to the pointer.
    Select(RegionDrag),
    /// Move one end of the region (0 = start, 1 = end).
    Handle(usize, RegionDrag),
}

/// Camera and interaction state of the canvas.
#[derive(Debug, Clone)]
pub struct CanvasState {
    /// World point at the centre of the view.
    pub center: DVec2,
    /// Screen points per model unit.
    pub ppu: f64,
    /// Fit the curve on the next frame.
    pub needs_fit: bool,
    /// Current drag.
    pub drag: CanvasDrag,
    /// Screen rectangle of the last frame.
    pub rect: Rect,
}

impl Default for CanvasState {
    fn default() -> Self {
        Self {
            center: DVec2::ZERO,
            ppu: 100.0,
            needs_fit: true,
            drag: CanvasDrag::None,
            rect: Rect::NOTHING,
        }
    }
}

impl CanvasState {
    /// World → screen.
    pub fn to_screen(&self, p: DVec2) -> Pos2 {
        let c = self.rect.center();
        let d = (p - self.center) * self.ppu;
        Pos2::new(c.x + d.x as f32, c.y - d.y as f32)
    }

    /// Screen → world.
    pub fn to_world(&self, q: Pos2) -> DVec2 {
        let c = self.rect.center();
        self.center + DVec2::new((q.x - c.x) as f64, -(q.y - c.y) as f64) / self.ppu
    }

    /// Fit the box `(a, b)` into the view with a margin.
    pub fn fit(&mut self, a: DVec2, b: DVec2) {
        let size = (b - a).max(DVec2::splat(1e-9));
        let w = (self.rect.width() as f64 - 60.0).max(10.0);
        let h = (self.rect.height() as f64 - 60.0).max(10.0);
        self.ppu = (w / size.x).min(h / size.y);
        self.center = 0.5 * (a + b);
    }
}

/// Signed comb tooth length (model units) for curvature `k`.
pub fn comb_length(k: f64, scaling: CombScaling, kmax: f64, kmean: f64, unit: f64) -> f64 {
    let a = k.abs();
    let kmax = kmax.max(1e-300);
    let f = match scaling {
        CombScaling::Linear => a / kmax,
        CombScaling::Sqrt => (a / kmax).sqrt(),
        CombScaling::Log => {
            let r = kmean.max(kmax * 1e-6);
            (1.0 + a / r).ln() / (1.0 + kmax / r).ln()
        }
    };
    k.signum() * f * unit
}

impl CurveCx<'_> {
    /// Index of the sample nearest to screen point `q`, with its distance.
    fn nearest_sample(&self, q: Pos2) -> (usize, f32) {
        let mut best = (0, f32::INFINITY);
        for (i, &p) in self.ws.view.sampled.p.iter().enumerate() {
            let d = self.ws.canvas.to_screen(p).distance(q);
            if d < best.1 {
                best = (i, d);
            }
        }
        best
    }

    /// Comb tip positions for `s` (model units), using the original's
    /// curvature scale so several combs compare.
    pub fn comb_tips(&self, s: &Sampled, kappa: &[f64], out: &mut Vec<DVec2>) {
        let o = &self.ws.view.sampled;
        let kmax = o.kappa_range.0.abs().max(o.kappa_range.1.abs());
        let kmean = o.kappa.iter().map(|k| k.abs()).sum::<f64>() / o.kappa.len().max(1) as f64;
        let unit = 0.15 * self.ws.view.diag * self.prefs.comb_scale;
        out.clear();
        out.extend(
            s.p.iter()
                .zip(&s.n)
                .zip(kappa)
                .map(|((&p, &n), &k)| p + n * comb_length(k, self.prefs.comb_scaling, kmax, kmean, unit)),
        );
    }

    /// The canvas panel.
    pub fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        let (rect, resp) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
        resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "Canvas"));
        self.ws.canvas.rect = rect;
        if self.ws.canvas.needs_fit && rect.width() > 20.0 {
            let (mut a, mut b) = self.ws.view.sampled.bbox;
            if let Some((sa, sb)) = self.ws.scene.bbox {
                (a, b) = (a.min(sa), b.max(sb));
            }
            if self.prefs.show_polygon {
                for &p in &self.ws.view.control {
                    a = a.min(p);
                    b = b.max(p);
                }
            }
            self.ws.canvas.fit(a, b);
            self.ws.canvas.needs_fit = false;
        }
        self.canvas_input(ui, &resp);
        self.click_to_select(&resp);
        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 0.0, Color32::from_gray(24));
        self.draw_canvas(&painter);
        self.join_markers_ui(ui, rect);
        resp.on_hover_text_at_pointer(if self.ws.view.closed {
            "Drag along the curve: select a region (on through the seam point: a region across the seam) · drag a \
             region end: adjust · wheel: zoom · right-drag: pan"
        } else {
            "Drag along the curve: select a region · drag a region end: adjust · wheel: zoom · right-drag: pan"
        });
    }

    fn canvas_input(&mut self, ui: &egui::Ui, resp: &egui::Response) {
        // zoom around the pointer
        if resp.hovered() {
            let (scroll, zoom) = ui.input(|i| (i.smooth_scroll_delta.y, i.zoom_delta()));
            let factor = (scroll as f64 * 0.0025).exp() * zoom as f64;
            if factor != 1.0
                && let Some(q) = resp.hover_pos()
            {
                let w = self.ws.canvas.to_world(q);
                self.ws.canvas.ppu = (self.ws.canvas.ppu * factor).clamp(1e-6, 1e12);
                let w2 = self.ws.canvas.to_world(q);
                self.ws.canvas.center += w - w2;
            }
        }
        // hover cursor shared with the κ plot
        if let Some(q) = resp.hover_pos() {
            let (i, d) = self.nearest_sample(q);
            if d < PICK * 2.0 {
                self.ws.next_hover_s = Some(self.ws.view.sampled.s[i]);
            }
        }
        if resp.drag_started() {
            let origin = ui.input(|i| i.pointer.press_origin()).or(resp.interact_pointer_pos());
            self.ws.canvas.drag = CanvasDrag::Pan;
            if resp.dragged_by(egui::PointerButton::Primary)
                && let Some(q) = origin
            {
                let handle = self.region().and_then(|(u1, u2)| {
                    [u1, u2]
                        .iter()
                        .map(|&u| self.ws.canvas.to_screen(self.ws.view.sampled.point_at_u(u)).distance(q))
                        .enumerate()
                        .filter(|(_, d)| *d < PICK)
                        .min_by(|a, b| a.1.total_cmp(&b.1))
                        .map(|(k, _)| k)
                });
                let (dom, closed) = (self.ws.view.domain, self.ws.view.closed);
                if let (Some(k), Some(r)) = (handle, self.region()) {
                    self.ws.canvas.drag = CanvasDrag::Handle(k, RegionDrag::handle(r, k, dom, closed));
                } else {
                    let (i, d) = self.nearest_sample(q);
                    if d < PICK {
                        self.ws.canvas.drag =
                            CanvasDrag::Select(RegionDrag::select(self.ws.view.sampled.u[i], dom, closed));
                    }
                }
            }
        }
        if resp.dragged() {
            match self.ws.canvas.drag {
                CanvasDrag::Pan => {
                    let d = resp.drag_delta();
                    self.ws.canvas.center -= DVec2::new(d.x as f64, -d.y as f64) / self.ws.canvas.ppu;
                }
                CanvasDrag::Select(mut d) | CanvasDrag::Handle(_, mut d) => {
                    // the nearest sample's parameter; on a closed curve the drag follows it through the
                    // seam (the sample jumps from one end of the domain to the other)
                    if let Some(q) = resp.interact_pointer_pos() {
                        let u = self.ws.view.sampled.u[self.nearest_sample(q).0];
                        let r = d.move_to(u);
                        match &mut self.ws.canvas.drag {
                            CanvasDrag::Select(x) | CanvasDrag::Handle(_, x) => *x = d,
                            _ => {}
                        }
                        if r.0 != r.1 {
                            self.push(Command::SetRegion(Some(r)));
                        }
                    }
                }
                CanvasDrag::None => {}
            }
        }
        if resp.drag_stopped() {
            self.ws.canvas.drag = CanvasDrag::None;
        }
    }

    fn draw_canvas(&self, painter: &egui::Painter) {
        let s = &self.ws.view.sampled;
        let region = self.region();
        // the region's samples in order along it (through the seam for a region across it)
        let in_region = region.map(|r| s.region_indices(r)).unwrap_or_default();

        self.draw_other_curves(painter);
        self.draw_band(painter, &in_region);
        self.draw_control_polygon(painter);

        // the faired preview (blended with the original by the blend slider)
        let preview = self.ws.preview().filter(|_| self.ws.compare.show_after);
        let shown_owned = preview.map(|p| blend(s, &p.sampled, self.ws.compare.blend));
        let shown = shown_owned.as_ref().unwrap_or(s);

        self.draw_comb(painter, shown);
        self.draw_curves(painter, &in_region, shown_owned.as_ref());
        self.draw_max_dev(painter);
        self.draw_markers(painter, shown);
        // the joins over the region's handles (a region often ends at one)
        self.draw_handles_and_cursor(painter, region);
        self.draw_joins(painter);
    }

    /// The tolerance band: offsets of the original inside the region.
    fn draw_band(&self, painter: &egui::Painter, in_region: &[usize]) {
        let s = &self.ws.view.sampled;
        let scr = |p: DVec2| self.ws.canvas.to_screen(p);
        if in_region.len() > 1 {
            let m = self.tolerance();
            for side in [-1.0, 1.0] {
                let pts: Vec<Pos2> = in_region.iter().map(|&i| scr(s.p[i] + s.n[i] * m * side)).collect();
                painter.add(Shape::line(pts, Stroke::new(1.0, colors::BAND)));
            }
        }
    }

    /// The control polygon and its points.
    fn draw_control_polygon(&self, painter: &egui::Painter) {
        let scr = |p: DVec2| self.ws.canvas.to_screen(p);
        if self.prefs.show_polygon {
            let pts: Vec<Pos2> = self.ws.view.control.iter().map(|&p| scr(p)).collect();
            painter.add(Shape::line(pts.clone(), Stroke::new(1.0, Color32::from_gray(90))));
            for p in pts {
                painter.rect_filled(
                    Rect::from_center_size(p, Vec2::splat(4.0)),
                    0.0,
                    Color32::from_gray(130),
                );
            }
        }
    }

    /// The curvature comb of the shown curve, with the target curvature as a second envelope.
    fn draw_comb(&self, painter: &egui::Painter, shown: &Sampled) {
        let scr = |p: DVec2| self.ws.canvas.to_screen(p);
        if self.prefs.show_comb {
            let mut tips = Vec::with_capacity(shown.len());
            self.comb_tips(shown, &shown.kappa, &mut tips);
            let s = shown;
            let stride = (s.len() / 250).max(1);
            for i in (0..s.len()).step_by(stride) {
                let c = if s.kappa[i] >= 0.0 { colors::POS } else { colors::NEG };
                painter.line_segment([scr(s.p[i]), scr(tips[i])], Stroke::new(1.0, c.gamma_multiply(0.45)));
            }
            let env: Vec<Pos2> = tips.iter().map(|&p| scr(p)).collect();
            painter.add(Shape::line(env, Stroke::new(1.2, Color32::from_rgb(150, 190, 255))));
            // target curvature as a second envelope
            if let Some(p) = self.ws.preview() {
                let t: Vec<Pos2> = self.target_envelope(p).into_iter().map(scr).collect();
                painter.add(Shape::line(t, Stroke::new(1.5, colors::TARGET)));
            }
        }
    }

    /// The original curve (dimmed under a preview), the region highlighted, and the shown faired curve.
    fn draw_curves(&self, painter: &egui::Painter, in_region: &[usize], shown_owned: Option<&Sampled>) {
        let s = &self.ws.view.sampled;
        let scr = |p: DVec2| self.ws.canvas.to_screen(p);
        let pts: Vec<Pos2> = s.p.iter().map(|&p| scr(p)).collect();
        let dim = shown_owned.is_some();
        if !dim || self.ws.compare.overlay {
            let c = if dim { Color32::from_gray(110) } else { colors::CURVE };
            painter.add(Shape::line(pts.clone(), Stroke::new(if dim { 1.5 } else { 2.0 }, c)));
        }
        if in_region.len() > 1 {
            painter.add(Shape::line(
                in_region.iter().map(|&i| pts[i]).collect(),
                Stroke::new(3.0, colors::REGION.gamma_multiply(0.8)),
            ));
        }

        if let Some(sh) = shown_owned {
            let fp: Vec<Pos2> = sh.p.iter().map(|&p| scr(p)).collect();
            painter.add(Shape::line(fp, Stroke::new(2.0, colors::FAIRED)));
        }
    }

    /// The cross at the point of maximum deviation.
    fn draw_max_dev(&self, painter: &egui::Painter) {
        let s = &self.ws.view.sampled;
        let scr = |p: DVec2| self.ws.canvas.to_screen(p);
        if let Some(u) = self.ws.fairing.dev_at {
            let c = scr(s.point_at_u(u));
            let st = Stroke::new(2.0, Color32::from_rgb(255, 60, 60));
            painter.line_segment([c + Vec2::splat(-5.0), c + Vec2::splat(5.0)], st);
            painter.line_segment([c + Vec2::new(-5.0, 5.0), c + Vec2::new(5.0, -5.0)], st);
            painter.text(
                c + Vec2::new(8.0, -8.0),
                egui::Align2::LEFT_BOTTOM,
                "max dev",
                egui::FontId::proportional(11.0),
                st.color,
            );
        }
    }

    /// Curvature extrema and inflection markers of the shown curve.
    fn draw_markers(&self, painter: &egui::Painter, shown: &Sampled) {
        let scr = |p: DVec2| self.ws.canvas.to_screen(p);
        if self.prefs.show_markers {
            let s = shown;
            for &i in &s.extrema {
                painter.circle_filled(scr(s.p[i]), 2.5, Color32::from_rgb(255, 150, 40));
            }
            for &u in &s.inflections {
                let c = scr(s.point_at_u(u));
                let r = 5.0;
                painter.add(Shape::convex_polygon(
                    vec![
                        c + Vec2::new(0.0, -r),
                        c + Vec2::new(r, 0.0),
                        c + Vec2::new(0.0, r),
                        c + Vec2::new(-r, 0.0),
                    ],
                    Color32::from_rgb(60, 220, 90),
                    Stroke::NONE,
                ));
            }
        }
    }

    /// The region's end handles and the cursor shared with the κ plot.
    fn draw_handles_and_cursor(&self, painter: &egui::Painter, region: Option<(f64, f64)>) {
        let s = &self.ws.view.sampled;
        let scr = |p: DVec2| self.ws.canvas.to_screen(p);
        if let Some((u1, u2)) = region {
            for u in [u1, u2] {
                let c = scr(s.point_at_u(u));
                painter.circle(c, 6.0, Color32::from_rgb(40, 40, 40), Stroke::new(2.0, colors::REGION));
            }
        }

        // shared cursor
        if let Some(hs) = self.ws.hover_s {
            let i = s.index_at_s(hs).round() as usize;
            painter.circle_stroke(scr(s.p[i]), 5.0, Stroke::new(1.5, Color32::WHITE));
        }
    }
}

/// The curve drawn after fairing: faired samples blended towards the
/// original (same sample fractions) by `t` ∈ [0, 1].
fn blend(orig: &Sampled, faired: &Sampled, t: f64) -> Sampled {
    if t >= 1.0 {
        return faired.clone();
    }
    let mut out = faired.clone();
    let n0 = orig.len().max(2) - 1;
    let n1 = faired.len().max(2) - 1;
    for i in 0..faired.len() {
        let j = ((i * n0) as f64 / n1 as f64).round() as usize;
        out.p[i] = orig.p[j].lerp(faired.p[i], t);
        out.kappa[i] = orig.kappa[j] + (faired.kappa[i] - orig.kappa[j]) * t;
    }
    out.extrema.clear();
    out.inflections.clear();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comb_length_scalings_keep_the_sign_and_meet_at_the_largest_curvature() {
        let (kmax, kmean, unit) = (4.0, 1.0, 0.5);
        for s in [CombScaling::Linear, CombScaling::Sqrt, CombScaling::Log] {
            // the largest |κ| gets the full unit, either sign; κ = 0 gets nothing
            assert!((comb_length(kmax, s, kmax, kmean, unit) - unit).abs() < 1e-15);
            assert!((comb_length(-kmax, s, kmax, kmean, unit) + unit).abs() < 1e-15);
            assert_eq!(comb_length(0.0, s, kmax, kmean, unit), 0.0);
            // monotone in |κ|
            let mut last = 0.0;
            for i in 1..=40 {
                let l = comb_length(kmax * i as f64 / 40.0, s, kmax, kmean, unit);
                assert!(l > last, "{s:?} not increasing at {i}");
                last = l;
            }
        }
        // linear is proportional; sqrt and log lift small curvatures above it
        let k = 0.25;
        let lin = comb_length(k, CombScaling::Linear, kmax, kmean, unit);
        assert!((lin - unit * k / kmax).abs() < 1e-15);
        let sq = comb_length(k, CombScaling::Sqrt, kmax, kmean, unit);
        assert!((sq - unit * (k / kmax).sqrt()).abs() < 1e-15);
        let lg = comb_length(k, CombScaling::Log, kmax, kmean, unit);
        assert!((lg - unit * (1.0 + k / kmean).ln() / (1.0 + kmax / kmean).ln()).abs() < 1e-15);
        assert!(sq > lin && lg > lin);
    }
}
