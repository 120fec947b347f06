//! The curvature plot κ(s) over arc length: original curvature, region
//! shading, shared hover cursor; drag across it to select a region, drag a
//! region edge to adjust it. On a closed curve a drag that leaves the plot at
//! one edge goes on from the other (the parameter is circular): the region
//! runs across the seam and is shaded in two parts, at the end and at the
//! start of the plot ([`crate::region`]).

use eframe::egui;
use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Shape, Stroke};

use crate::Command;
use crate::canvas::colors;
use crate::curve_ws::CurveCx;
use crate::region::{self, RegionDrag};

/// What a drag on the plot does.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum PlotDrag {
    /// Nothing.
    #[default]
    None,
    /// Select a region from where the drag started to the pointer.
    Select(RegionDrag),
    /// Move one region end (0 = start, 1 = end).
    Handle(usize, RegionDrag),
}

/// Interaction state of the κ plot.
#[derive(Debug, Clone, Default)]
pub struct PlotState {
    /// Current drag.
    pub drag: PlotDrag,
    /// Plot area of the last frame.
    pub rect: Option<Rect>,
    /// κ range shown (bottom, top).
    pub y_range: (f64, f64),
    /// During a region drag: the pointer's parameter ([`CurveCx::plot_u`]) plus this is the moving end's
    /// unwrapped parameter (a multiple of the domain length: `L` when the grabbed end is the `u2` of a
    /// region across the seam, else 0).
    pub drag_offset: f64,
}

impl PlotState {
    /// Arc length → screen x.
    pub fn x(&self, s: f64, length: f64) -> f32 {
        let r = self.rect.unwrap_or(Rect::NOTHING);
        r.left() + (s / length.max(1e-300)) as f32 * r.width()
    }

    /// Screen x → arc length (clamped).
    pub fn s(&self, x: f32, length: f64) -> f64 {
        let r = self.rect.unwrap_or(Rect::NOTHING);
        (((x - r.left()) / r.width().max(1.0)) as f64).clamp(0.0, 1.0) * length
    }

    /// Screen x → arc length, not clamped: beyond the plot's edges it goes on below 0 or above
    /// `length` (at most one length beyond).
    pub fn s_unclamped(&self, x: f32, length: f64) -> f64 {
        let r = self.rect.unwrap_or(Rect::NOTHING);
        (((x - r.left()) / r.width().max(1.0)) as f64).clamp(-1.0, 2.0) * length
    }

    /// κ → screen y.
    pub fn y(&self, k: f64) -> f32 {
        let r = self.rect.unwrap_or(Rect::NOTHING);
        let (lo, hi) = self.y_range;
        r.bottom() - ((k - lo) / (hi - lo).max(1e-300)) as f32 * r.height()
    }

    /// Screen y → κ.
    pub fn k(&self, y: f32) -> f64 {
        let r = self.rect.unwrap_or(Rect::NOTHING);
        let (lo, hi) = self.y_range;
        lo + ((r.bottom() - y) / r.height().max(1.0)) as f64 * (hi - lo)
    }
}

impl CurveCx<'_> {
    /// The κ(s) plot panel.
    pub fn plot_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.strong("Curvature κ(s)");
            ui.weak(if self.ws.view.closed {
                "— drag across the plot to select a region (past an edge: on through the seam), drag its edges to adjust"
            } else {
                "— drag across the plot to select a region, drag its edges to adjust"
            });
        });
        let (outer, resp) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
        resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "Curvature plot"));
        let rect = Rect::from_min_max(outer.min + egui::vec2(56.0, 6.0), outer.max - egui::vec2(8.0, 18.0));
        self.ws.plot.rect = Some(rect);
        let s = &self.ws.view.sampled;
        let (mut lo, mut hi) = s.kappa_range;
        for k in self.extra_kappa_ranges() {
            lo = lo.min(k.0);
            hi = hi.max(k.1);
        }
        lo = lo.min(0.0);
        hi = hi.max(0.0);
        let pad = 0.08 * (hi - lo).max(1e-12);
        self.ws.plot.y_range = (lo - pad, hi + pad);
        self.plot_input(ui, &resp);
        let painter = ui.painter_at(outer);
        painter.rect_filled(outer, 0.0, Color32::from_gray(20));
        self.draw_plot(&painter, rect);
    }

    /// κ ranges of other drawn curves (target, faired) so the plot fits them.
    fn extra_kappa_ranges(&self) -> Vec<(f64, f64)> {
        let mut out = vec![];
        if let Some(p) = self.ws.preview() {
            let r = |v: &mut dyn Iterator<Item = f64>| {
                v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), k| (a.min(k), b.max(k)))
            };
            out.push(r(&mut p.target.iter().copied()));
            let reg = self.region().unwrap_or((0.0, 0.0));
            out.push(r(&mut p
                .sampled
                .u
                .iter()
                .zip(&p.sampled.kappa)
                .filter(|(u, _)| region::contains(reg, **u))
                .map(|(_, k)| *k)));
        }
        out.retain(|(a, b)| a.is_finite() && b.is_finite());
        out
    }

    /// The curve parameter under screen x on the plot. On a closed curve beyond the plot's edges the
    /// parameter goes on through the seam (above `b` past the right edge, below `a` past the left
    /// one); on an open curve it is clamped to the domain.
    pub fn plot_u(&self, x: f32) -> f64 {
        let s = &self.ws.view.sampled;
        let len = s.length;
        let (a, b) = self.ws.view.domain;
        let t = self.ws.plot.s_unclamped(x, len);
        if !self.ws.view.closed || (0.0..=len).contains(&t) {
            s.u_at_s(t.clamp(0.0, len))
        } else if t > len {
            s.u_at_s(t - len) + (b - a)
        } else {
            s.u_at_s(t + len) - (b - a)
        }
    }

    fn plot_input(&mut self, ui: &egui::Ui, resp: &egui::Response) {
        let len = self.ws.view.sampled.length;
        if let Some(q) = resp.hover_pos() {
            self.ws.next_hover_s = Some(self.ws.plot.s(q.x, len));
        }
        if self.target_plot_input(ui, resp) {
            return;
        }
        if resp.drag_started_by(egui::PointerButton::Primary)
            && let Some(q) = ui.input(|i| i.pointer.press_origin())
        {
            let handle = self.region().and_then(|(u1, u2)| {
                [u1, u2]
                    .iter()
                    .map(|&u| (self.ws.plot.x(self.ws.view.sampled.s_at_u(u), len) - q.x).abs())
                    .enumerate()
                    .filter(|(_, d)| *d < 6.0)
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .map(|(k, _)| k)
            });
            let (dom, closed) = (self.ws.view.domain, self.ws.view.closed);
            let u = self.plot_u(q.x);
            self.ws.plot.drag = match (handle, self.region()) {
                (Some(k), Some(r)) => PlotDrag::Handle(k, RegionDrag::handle(r, k, dom, closed)),
                _ => PlotDrag::Select(RegionDrag::select(u, dom, closed)),
            };
            // the plot's x is absolute: the moving end follows it, shifted by whole periods as grabbed
            self.ws.plot.drag_offset = match self.ws.plot.drag {
                PlotDrag::Handle(_, d) if closed => ((d.moving - u) / (dom.1 - dom.0)).round() * (dom.1 - dom.0),
                _ => 0.0,
            };
        }
        if resp.dragged_by(egui::PointerButton::Primary)
            && let Some(q) = resp.interact_pointer_pos()
            && let PlotDrag::Select(mut d) | PlotDrag::Handle(_, mut d) = self.ws.plot.drag
        {
            let r = d.set_moving(self.plot_u(q.x) + self.ws.plot.drag_offset);
            if let PlotDrag::Select(x) | PlotDrag::Handle(_, x) = &mut self.ws.plot.drag {
                *x = d;
            }
            if r.0 != r.1 {
                self.push(Command::SetRegion(Some(r)));
            }
        }
        if resp.drag_stopped() {
            self.ws.plot.drag = PlotDrag::None;
        }
    }

    fn draw_plot(&self, painter: &egui::Painter, rect: Rect) {
        let s = &self.ws.view.sampled;
        let p = &self.ws.plot;
        let len = s.length;
        let font = FontId::proportional(11.0);
        let axis = Color32::from_gray(110);
        // axes and zero line
        painter.rect_stroke(
            rect,
            0.0,
            Stroke::new(1.0, Color32::from_gray(60)),
            egui::StrokeKind::Inside,
        );
        let y0 = p.y(0.0);
        painter.line_segment(
            [Pos2::new(rect.left(), y0), Pos2::new(rect.right(), y0)],
            Stroke::new(1.0, axis),
        );
        for k in [p.y_range.0, 0.0, p.y_range.1] {
            painter.text(
                Pos2::new(rect.left() - 4.0, p.y(k)),
                Align2::RIGHT_CENTER,
                format!("{k:.3}"),
                font.clone(),
                axis,
            );
        }
        for f in [0.0, 0.25, 0.5, 0.75, 1.0] {
            let x = rect.left() + f as f32 * rect.width();
            painter.text(
                Pos2::new(x, rect.bottom() + 2.0),
                if f == 0.0 {
                    Align2::LEFT_TOP
                } else if f == 1.0 {
                    Align2::RIGHT_TOP
                } else {
                    Align2::CENTER_TOP
                },
                format!("s={:.3}", f * len),
                font.clone(),
                axis,
            );
        }
        // region shading (in two parts, end and start of the plot, for a region across the seam)
        if let Some((u1, u2)) = self.region() {
            for (v1, v2) in region::parts((u1, u2), self.ws.view.domain) {
                let (x1, x2) = (p.x(s.s_at_u(v1), len), p.x(s.s_at_u(v2), len));
                painter.rect_filled(
                    Rect::from_x_y_ranges(x1..=x2, rect.y_range()),
                    0.0,
                    colors::REGION.gamma_multiply(0.15),
                );
            }
            if region::wraps((u1, u2)) {
                painter.text(
                    Pos2::new(rect.right() - 4.0, rect.top() + 2.0),
                    Align2::RIGHT_TOP,
                    "region across the seam: continues at the left edge",
                    font.clone(),
                    colors::REGION,
                );
            }
            let (x1, x2) = (p.x(s.s_at_u(u1), len), p.x(s.s_at_u(u2), len));
            for x in [x1, x2] {
                painter.line_segment(
                    [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
                    Stroke::new(2.0, colors::REGION),
                );
            }
        }
        self.draw_plot_suggestions(painter, rect);
        // original κ
        let pts: Vec<Pos2> =
            s.s.iter()
                .zip(&s.kappa)
                .map(|(&si, &k)| Pos2::new(p.x(si, len), p.y(k)))
                .collect();
        painter.add(Shape::line(pts, Stroke::new(1.5, Color32::from_rgb(150, 190, 255))));
        self.draw_plot_fairing(painter);
        // cursor
        if let Some(hs) = self.ws.hover_s {
            let x = p.x(hs, len);
            painter.line_segment(
                [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
                Stroke::new(1.0, Color32::from_white_alpha(140)),
            );
            let k = s.kappa_at_s(hs);
            painter.circle_stroke(Pos2::new(x, p.y(k)), 4.0, Stroke::new(1.5, Color32::WHITE));
        }
    }
}
