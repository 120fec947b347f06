//! The curve workspace's measures (before / after, the whole curve and the region) and the
//! tight / medium / loose trio window.

use eframe::egui;
use egui::{Color32, Pos2, Rect, Sense, Shape, Stroke};
use fairway::DVec2;

use crate::canvas::colors;
use crate::curve_ws::CurveCx;
use crate::fairing::Preview;
use crate::region;

impl CurveCx<'_> {
    /// Measures before / after.
    pub fn measures_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Measures");
        let Some(p) = self.ws.preview() else {
            ui.weak("(no preview)");
            return;
        };
        let max_dev = p.result.max_deviation;
        // the bench simulates drags (tolerance sweep, target drag) without a pointer
        let dragging = ui.input(|i| i.pointer.any_down()) || self.ws.benchmarking || p.draft;
        self.ws.fairing.update_measures(dragging);
        if self.ws.fairing.measures_stale() {
            ui.weak("(updated when the drag ends)");
        }
        let Some((b, a)) = self.ws.fairing.measures.as_ref() else {
            return;
        };
        let region = self.ws.fairing.region_measures;
        egui::Grid::new("measures").striped(true).show(ui, |ui| {
            ui.strong("");
            ui.strong("before");
            ui.strong("after");
            ui.strong("change");
            ui.end_row();
            let deviation_tip = format!(
                "Largest distance from the original, by closest-point projection of {} arc-length samples \
                 (at least {} a knot span)",
                fairway::measure::DEV_SAMPLES,
                fairway::measure::DEV_SAMPLES_PER_SPAN
            );
            let raw_tip = format!(
                "Every sign change of dκ/ds between {} samples of the whole curve (at least {} a knot span)",
                fairway::measure::CURV_SAMPLES,
                fairway::measure::CURV_SAMPLES_PER_SPAN
            );
            // (name, tooltip, before, after, is a count)
            let rows = [
                ("max deviation", deviation_tip.as_str(), b.dev_max, a.dev_max, false),
                (
                    "κ extrema",
                    "Curvature extrema of the whole curve (zig-zag pivots beyond δ = 1% of max|g|)",
                    b.n_curv_extrema as f64,
                    a.n_curv_extrema as f64,
                    true,
                ),
                (
                    "κ extrema (raw)",
                    raw_tip.as_str(),
                    b.n_curv_extrema_raw as f64,
                    a.n_curv_extrema_raw as f64,
                    true,
                ),
                (
                    "inflections",
                    "Sign changes of κ across the dead band ±δ (whole curve)",
                    b.n_inflections as f64,
                    a.n_inflections as f64,
                    true,
                ),
                (
                    "E (paper)",
                    "Σ (κ − g)² over 200 samples, g the original's smoothed curvature",
                    b.E_paper,
                    a.E_paper,
                    false,
                ),
                ("∫(dκ/ds)² ds", "Variation of curvature energy", b.E_var, a.E_var, false),
                ("∫κ² ds", "Bending energy", b.E_bend, a.E_bend, false),
            ];
            // the region's own figures beside the whole curve's (same δ)
            let region_rows = region.map(|((eb, vb), (ea, va))| {
                [
                    (
                        "κ extrema (region)",
                        "Curvature extrema inside the region (the whole curve's δ)",
                        eb as f64,
                        ea as f64,
                        true,
                    ),
                    (
                        "∫(dκ/ds)² (region)",
                        "Variation of curvature energy over the region",
                        vb,
                        va,
                        false,
                    ),
                ]
            });
            let rows = rows.into_iter().chain(region_rows.into_iter().flatten());
            // the original's distance to itself is 0 up to closest-point round-off (~1e-14)
            let zero = 1e-12 * self.ws.view.diag.max(1e-300);
            for row in rows {
                measure_row(ui, row, zero);
            }
        });
        ui.weak(format!("core's verified bound on the deviation: {}", fmt_num(max_dev)))
            .on_hover_text("An upper bound: the measured max deviation above is at most this");
    }

    /// The tight / medium / loose trio window.
    pub fn trio_ui(&mut self, ctx: &egui::Context) {
        if !self.ws.compare.trio {
            return;
        }
        let mut open = true;
        egui::Window::new("Tight / medium / loose")
            .open(&mut open)
            .default_size([900.0, 260.0])
            .show(ctx, |ui| {
                let Some(trio) = self.ws.fairing.trio.clone() else {
                    ui.weak("Select a region first.");
                    return;
                };
                ui.columns(3, |cols| {
                    for (col, (m, res)) in cols.iter_mut().zip(trio.iter()) {
                        col.strong(format!("m = {m:.2e}"));
                        match res {
                            Err(e) => {
                                col.colored_label(Color32::from_rgb(230, 80, 60), e.as_str());
                            }
                            Ok(p) => {
                                let (ex, inf) = region_counts(&p.sampled, self.region());
                                col.label(format!(
                                    "dev {:.2e} · κ extrema {ex} · inflections {inf} (in region)",
                                    p.result.max_deviation
                                ));
                                let (rect, _) =
                                    col.allocate_exact_size(egui::vec2(col.available_width(), 180.0), Sense::hover());
                                self.draw_mini(col.painter_at(rect), rect, p);
                            }
                        }
                    }
                });
            });
        if !open {
            self.ws.compare.trio = false;
        }
    }

    fn draw_mini(&self, painter: egui::Painter, rect: Rect, p: &Preview) {
        painter.rect_filled(rect, 0.0, Color32::from_gray(24));
        let s = &p.sampled;
        let idx = s.region_indices(self.region().unwrap_or(self.ws.view.domain));
        let mut tips = vec![];
        self.comb_tips(s, &s.kappa, &mut tips);
        let (mut a, mut b) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for &i in &idx {
            for q in [s.p[i], tips[i]] {
                a = a.min(q);
                b = b.max(q);
            }
        }
        let size = (b - a).max(DVec2::splat(1e-12));
        let k = ((rect.width() as f64 - 10.0) / size.x).min((rect.height() as f64 - 10.0) / size.y);
        let c = 0.5 * (a + b);
        let scr = |q: DVec2| {
            let d = (q - c) * k;
            Pos2::new(rect.center().x + d.x as f32, rect.center().y - d.y as f32)
        };
        for &i in idx.iter().step_by((idx.len() / 80).max(1)) {
            let col = if s.kappa[i] >= 0.0 { colors::POS } else { colors::NEG };
            painter.line_segment([scr(s.p[i]), scr(tips[i])], Stroke::new(1.0, col.gamma_multiply(0.5)));
        }
        painter.add(Shape::line(
            idx.iter().map(|&i| scr(tips[i])).collect(),
            Stroke::new(1.0, colors::POS),
        ));
        painter.add(Shape::line(
            idx.iter().map(|&i| scr(s.p[i])).collect(),
            Stroke::new(2.0, colors::FAIRED),
        ));
    }
}

fn fmt_num(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.abs() >= 1e4 || v.abs() < 1e-3 {
        format!("{v:.3e}")
    } else {
        format!("{v:.4}")
    }
}

/// Curvature extrema and inflections of a sampled curve inside the region.
fn region_counts(s: &crate::Sampled, region: Option<(f64, f64)>) -> (usize, usize) {
    let r = region.unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
    let ex = s.extrema.iter().filter(|&&i| region::contains(r, s.u[i])).count();
    let inf = s.inflections.iter().filter(|&&u| region::contains(r, u)).count();
    (ex, inf)
}

/// One row of the measures grid: name (with `tip`), before, after and the relative change; a
/// "max deviation" below `zero` shows as 0.
fn measure_row(ui: &mut egui::Ui, (name, tip, bv, av, count): (&str, &str, f64, f64, bool), zero: f64) {
    let (bv, av) = if name == "max deviation" {
        (if bv < zero { 0.0 } else { bv }, if av < zero { 0.0 } else { av })
    } else {
        (bv, av)
    };
    let f = |v: f64| if count { format!("{v:.0}") } else { fmt_num(v) };
    ui.label(name).on_hover_text(tip);
    ui.label(f(bv));
    ui.label(f(av));
    // a relative change from a round-off "before" (e.g. deviation 1e-14) means nothing
    let ch = if bv.abs() > 1e-6 * av.abs() {
        format!("{:+.0}%", (av / bv - 1.0) * 100.0)
    } else {
        "—".into()
    };
    ui.label(ch);
    ui.end_row();
}
