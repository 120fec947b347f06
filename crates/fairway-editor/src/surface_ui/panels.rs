//! The surface workspace's side panel: display, region (with the uv-domain view), tolerance,
//! compare and measures.

use eframe::egui;
use egui::{Color32, Pos2, Rect, RichText, Sense, Stroke};
use fairway::DVec2;

use super::{SurfaceCx, band_certificate};
use crate::Command;
use crate::view3d::scene::{effective_range, mode_values};
use crate::view3d::{self, ShadeMode};

/// The colour of the marks of a draft preview.
pub(super) const DRAFT_COLOR: Color32 = Color32::from_rgb(240, 200, 60);

/// A background draft running this long (s) shows a busy indicator.
const DRAFT_BUSY_AFTER_S: f64 = 0.1;

impl SurfaceCx<'_> {
    pub(super) fn controls_ui(&mut self, ui: &mut egui::Ui) {
        self.display_ui(ui);
        ui.separator();
        self.region_ui(ui);
        ui.separator();
        self.tolerance_section_ui(ui);
        ui.separator();
        self.compare_ui(ui);
        ui.separator();
        self.measures_ui(ui);
    }

    /// The "Display" section: shading mode, stripes, light, curvature range, overlays, mesh density.
    fn display_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Display");
        ui.horizontal_wrapped(|ui| {
            for m in ShadeMode::ALL {
                ui.selectable_value(&mut self.ws.shading.mode, m, m.label())
                    .on_hover_text(match m {
                        ShadeMode::Shaded => "Lit surface",
                        ShadeMode::Isophotes => "Stripes of equal angle between the normal and the light",
                        ShadeMode::Zebra => "Reflection lines of parallel light tubes",
                        ShadeMode::Mean => "Mean curvature H = (κ1+κ2)/2, exact per vertex",
                        ShadeMode::Gauss => "Gaussian curvature K = κ1κ2, exact per vertex",
                        ShadeMode::KMax => "Maximum principal curvature κ1",
                        ShadeMode::KMin => "Minimum principal curvature κ2",
                    });
            }
        });
        if matches!(self.ws.shading.mode, ShadeMode::Isophotes | ShadeMode::Zebra) {
            ui.add(egui::Slider::new(&mut self.ws.shading.stripe_deg, view3d::STRIPE_RANGE).text("Stripe width °"))
                .on_hover_text("Angular width of one stripe (degrees)");
        }
        self.ws.shading.light_ui(ui);
        if self.ws.shading.mode.is_curvature() {
            let values = mode_values(&self.ws.mesh, self.ws.shading.mode).unwrap_or(&[]);
            let mut r = effective_range(&self.ws.shading, values);
            let auto = self.ws.shading.range.is_none();
            ui.horizontal(|ui| {
                let resp = ui
                    .add(
                        egui::Slider::new(&mut r, 1e-4..=1e3)
                            .logarithmic(true)
                            .text("Range ±")
                            .custom_formatter(|v, _| format!("{v:.3e}")),
                    )
                    .on_hover_text("Colour map range: ±range; neutral grey at zero");
                if resp.changed() {
                    self.ws.shading.range = Some(r);
                }
                if ui
                    .selectable_label(auto, "auto")
                    .on_hover_text("95th percentile of |value| on the original surface")
                    .clicked()
                {
                    self.ws.shading.range = None;
                }
            });
        }
        ui.checkbox(&mut self.ws.shading.show_iso, "Isoparametric lines")
            .on_hover_text("u and v isocurves at the knots");
        ui.checkbox(&mut self.ws.shading.show_net, "Control net")
            .on_hover_text("Show the control net");
        let mut d = self.ws.shading.density;
        if ui
            .add(egui::Slider::new(&mut d, view3d::DENSITY_RANGE).text("Mesh density"))
            .on_hover_text("Tessellation vertices per direction (curvature is exact at each vertex)")
            .changed()
        {
            self.ws.shading.density = d;
            if let Err(e) = self.ws.set_surface_changed(self.surface()) {
                *self.error = Some(e.to_string());
            }
        }
    }

    /// The "Region" section: uv view, whole / clear, and the region's parameter bounds.
    fn region_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Region");
        self.uv_view_ui(ui);
        let ((du0, du1), (dv0, dv1)) = self.surface().domain();
        ui.horizontal(|ui| {
            if ui
                .button("Whole surface")
                .on_hover_text("Fair the whole surface")
                .clicked()
            {
                self.push(Command::SetRegionUv(Some(((du0, du1), (dv0, dv1)))));
            }
            if ui
                .add_enabled(self.region().is_some(), egui::Button::new("Clear"))
                .on_hover_text("Clear the region")
                .clicked()
            {
                self.push(Command::SetRegionUv(None));
            }
        });
        if let Some(((mut a, mut b), (mut c, mut d))) = self.region() {
            let mut changed = false;
            for row in [
                [(&mut a, du0, du1, "u1"), (&mut b, du0, du1, "u2")],
                [(&mut c, dv0, dv1, "v1"), (&mut d, dv0, dv1, "v2")],
            ] {
                ui.horizontal(|ui| {
                    for (v, lo, hi, name) in row {
                        let l = ui.label(name);
                        changed |= ui
                            .add(
                                egui::DragValue::new(v)
                                    .range(lo..=hi)
                                    .speed((hi - lo) * 1e-3)
                                    .max_decimals(5),
                            )
                            .labelled_by(l.id)
                            .changed();
                    }
                });
            }
            if changed && a < b && c < d {
                self.push(Command::SetRegionUv(Some(((a, b), (c, d)))));
            }
        } else {
            ui.weak("No region: drag in the uv view, or Ctrl+drag on the surface.");
        }
    }

    /// The "Tolerance" section: max deviation and live preview.
    fn tolerance_section_ui(&mut self, ui: &mut egui::Ui) {
        self.tolerance_ui(
            ui,
            self.tolerance(),
            self.ws.diag(),
            "Max deviation m of the faired surface from the original (in the model's units)",
        );
        ui.checkbox(&mut self.ws.live, "Live preview")
            .on_hover_text("Re-fair whenever region or tolerance change");
    }

    /// The "Compare" section: before / after, blend, side by side, preview error and Accept.
    fn compare_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Compare");
        ui.horizontal(|ui| {
            ui.selectable_value(&mut self.ws.compare.show_after, false, "Before")
                .on_hover_text("Show the original (Space toggles)");
            ui.selectable_value(&mut self.ws.compare.show_after, true, "After")
                .on_hover_text("Show the faired preview (Space toggles)");
        });
        ui.add(egui::Slider::new(&mut self.ws.compare.blend, 0.0..=1.0).text("Blend"))
            .on_hover_text("Blend the control points original (0) -> faired (1)");
        ui.checkbox(&mut self.ws.compare.side_by_side, "Side by side")
            .on_hover_text("Before and after in two views with one camera");
        if let Some(t) = self.ws.fairing_time() {
            let meanwhile = if self.ws.preview.as_ref().is_some_and(|p| p.draft) {
                "the draft shows meanwhile, marked provisional"
            } else {
                "the original shows meanwhile"
            };
            crate::widgets::busy_ui(ui, format!("Fairing… {:.1} s", t.as_secs_f64())).on_hover_text(format!(
                "The full fair runs in the background ({meanwhile}); the editor stays usable and a new edit \
                 restarts it. Untick Live preview to stop it."
            ));
        }
        // a draft that takes long enough to be seen (a large surface or region; a small one's draft
        // arrives within a frame or two and shows no indicator, so the panel does not flicker)
        if let Some(t) = self
            .ws
            .drafting_time()
            .filter(|t| t.as_secs_f64() >= DRAFT_BUSY_AFTER_S)
        {
            let shown = if self.ws.preview.is_some() {
                "the last draft shows meanwhile"
            } else {
                "the original shows meanwhile"
            };
            crate::widgets::busy_ui(ui, format!("Draft… {:.1} s", t.as_secs_f64())).on_hover_text(format!(
                "The draft of the dragged setting runs in the background ({shown}); one at a time: when it \
                 ends, the next starts for where the drag is then. Releasing starts the full fair."
            ));
        }
        if let Some(e) = &self.ws.preview_error {
            ui.label(RichText::new(format!("! {e}")).color(Color32::from_rgb(230, 80, 60)));
        }
        let why_not = if self.ws.is_fairing() {
            "Accept takes the full fair: wait until it has finished"
        } else {
            "Select a region to fair first"
        };
        if ui
            .add_enabled(self.ws.can_accept(self.doc), egui::Button::new("Accept"))
            .on_hover_text("Replace the surface by the faired preview (one undo step)")
            .on_disabled_hover_text(why_not)
            .clicked()
        {
            self.push(Command::AcceptSurface);
        }
    }

    fn measures_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Measures");
        let Some(p) = &self.ws.preview else {
            if self.ws.is_fairing() {
                ui.weak("The measures follow with the full fair.");
            } else {
                ui.weak("Select a region to see the faired preview's measures.");
            }
            return;
        };
        if p.draft {
            ui.label(RichText::new("Draft (provisional): one isocurve level, isocurves alone").color(DRAFT_COLOR))
                .on_hover_text("Computed during the drag; the full fair replaces it when it has finished");
        }
        // the tolerance the preview was computed for: during a drag the draft shown may be that of an
        // earlier point of it, while the next one is computed
        let tol = f64::from_bits(p.key().2);
        ui.label(format!(
            "fair: {:.1} ms, rounds {}, α = {:.2}, verified max deviation {:.3e} (tolerance {:.3e})",
            p.fair_ms, p.rounds, p.alpha, p.max_deviation, tol
        ));
        ui.label(band_certificate(p.band_bound, tol));
        for n in &p.notes {
            ui.label(egui::RichText::new(n).small());
        }
        let (Some(a), Some((_, b))) = (&p.measures, &self.ws.measures_before) else {
            ui.weak("(the measures follow with the full fair)");
            return;
        };
        egui::Grid::new("surf_measures").striped(true).show(ui, |ui| {
            ui.strong("");
            ui.strong("before");
            ui.strong("after");
            ui.strong("change");
            ui.end_row();
            let rows: [(&str, f64, f64, &str); 4] = [
                (
                    "curvature extrema",
                    b.n_curv_extrema as f64,
                    a.n_curv_extrema as f64,
                    "isocurve κ extrema (20 per direction)",
                ),
                (
                    "E = sum int (dκ/ds)^2 ds",
                    b.e_var,
                    a.e_var,
                    "curvature variation along the isocurves",
                ),
                (
                    "int |grad H|^2 dA",
                    b.mean_curv_var,
                    a.mean_curv_var,
                    "mean curvature variation over the surface",
                ),
                (
                    "max deviation",
                    0.0,
                    a.dev_max,
                    "closest-point deviation on a 101×101 grid",
                ),
            ];
            for (name, x, y, tip) in rows {
                ui.label(name).on_hover_text(tip);
                ui.label(format!("{x:.4e}"));
                ui.label(format!("{y:.4e}"));
                if x != 0.0 {
                    ui.label(format!("{:+.0}%", (y / x - 1.0) * 100.0));
                } else {
                    ui.label("");
                }
                ui.end_row();
            }
            ui.label("RMS deviation");
            ui.label("0");
            ui.label(format!("{:.3e}", a.dev_rms));
            ui.end_row();
        });
    }

    /// The uv-domain mini view: knot lines, the region; drag to select.
    fn uv_view_ui(&mut self, ui: &mut egui::Ui) {
        let ((u0, u1), (v0, v1)) = self.surface().domain();
        let w = ui.available_width().clamp(120.0, 280.0);
        let (rect, resp) = ui.allocate_exact_size(egui::vec2(w, w * 0.75), Sense::click_and_drag());
        resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "uv domain"));
        let resp = resp.on_hover_text("uv domain: drag to select the fairing region (u -> right, v up)");
        let to_screen = |uv: DVec2| {
            Pos2::new(
                rect.left() + ((uv.x - u0) / (u1 - u0)) as f32 * rect.width(),
                rect.bottom() - ((uv.y - v0) / (v1 - v0)) as f32 * rect.height(),
            )
        };
        let to_uv = |p: Pos2| {
            DVec2::new(
                u0 + ((p.x - rect.left()) / rect.width()).clamp(0.0, 1.0) as f64 * (u1 - u0),
                v0 + ((rect.bottom() - p.y) / rect.height()).clamp(0.0, 1.0) as f64 * (v1 - v0),
            )
        };
        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 2.0, Color32::from_gray(30));
        let faint = Stroke::new(1.0, Color32::from_gray(60));
        for u in self.surface().knots_u().breakpoints() {
            painter.line_segment([to_screen(DVec2::new(u, v0)), to_screen(DVec2::new(u, v1))], faint);
        }
        for v in self.surface().knots_v().breakpoints() {
            painter.line_segment([to_screen(DVec2::new(u0, v)), to_screen(DVec2::new(u1, v))], faint);
        }
        if resp.drag_started()
            && let Some(p) = ui.input(|i| i.pointer.press_origin())
        {
            self.ws.uv_drag = Some(to_uv(p));
        }
        if let (Some(a), Some(p)) = (self.ws.uv_drag, resp.interact_pointer_pos())
            && resp.dragged()
        {
            let b = to_uv(p);
            if (b.x - a.x).abs() > 1e-9 && (b.y - a.y).abs() > 1e-9 {
                self.push(Command::SetRegionUv(Some(((a.x, b.x), (a.y, b.y)))));
            }
        }
        if resp.drag_stopped() {
            self.ws.uv_drag = None;
        }
        if let Some(((a, b), (c, d))) = self.region() {
            let r = Rect::from_two_pos(to_screen(DVec2::new(a, c)), to_screen(DVec2::new(b, d)));
            painter.rect_filled(r, 0.0, Color32::from_rgba_unmultiplied(255, 140, 25, 50));
            painter.rect_stroke(
                r,
                0.0,
                Stroke::new(1.5, Color32::from_rgb(255, 140, 25)),
                egui::StrokeKind::Inside,
            );
        }
        if let Some((uv, _)) = self.ws.hover {
            painter.circle_filled(to_screen(uv), 3.0, Color32::WHITE);
        }
        painter.text(
            rect.left_bottom() + egui::vec2(4.0, -4.0),
            egui::Align2::LEFT_BOTTOM,
            "u ->",
            egui::FontId::proportional(11.0),
            Color32::GRAY,
        );
        painter.text(
            rect.left_top() + egui::vec2(4.0, 4.0),
            egui::Align2::LEFT_TOP,
            "v up",
            egui::FontId::proportional(11.0),
            Color32::GRAY,
        );
    }
}
