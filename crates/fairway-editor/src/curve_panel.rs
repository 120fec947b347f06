//! The curve workspace's side panel: region, tolerance and comb sections, then the fairing
//! controls ([`crate::fair_ui`]) and the measures.

use eframe::egui;

use crate::curve_ws::CurveCx;
use crate::{CombScaling, Command, region};

impl CurveCx<'_> {
    pub(crate) fn controls_ui(&mut self, ui: &mut egui::Ui) {
        self.region_section_ui(ui);
        ui.separator();
        self.tolerance_ui(
            ui,
            self.tolerance(),
            self.ws.view.diag,
            "Tolerance band width m, in the model's units (log scale). The faired curve stays within m.",
        );
        ui.separator();
        self.comb_section_ui(ui);
        ui.separator();
        self.fairing_ui(ui);
        ui.separator();
        self.measures_ui(ui);
    }

    /// The "Region" section: whole / clear, suggestions, the region's parameter bounds.
    fn region_section_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Region");
        let (a, b) = self.curve().domain();
        ui.horizontal(|ui| {
            if ui
                .button("Whole curve")
                .on_hover_text("Select the whole curve as the region")
                .clicked()
            {
                self.push(Command::SetRegion(Some((a, b))));
            }
            if ui
                .add_enabled(self.region().is_some(), egui::Button::new("Clear"))
                .on_hover_text("Clear the region")
                .clicked()
            {
                self.push(Command::SetRegion(None));
            }
        });
        self.suggest_ui(ui);
        if let Some((mut u1, mut u2)) = self.region() {
            // on a closed curve either end may pass the other: u₁ > u₂ runs across the seam
            let closed = self.ws.view.closed;
            let (range1, range2) = if closed { (a..=b, a..=b) } else { (a..=u2, u1..=b) };
            let text = region::describe((u1, u2));
            ui.label(text).on_hover_text(if closed {
                "Closed curve: the parameter is circular; u₁ > u₂ is the stretch from u₁ through the seam to u₂"
            } else {
                "The region's parameter range"
            });
            let (r1, r2) = ui
                .horizontal(|ui| {
                    let l1 = ui.label("u₁");
                    let r1 = ui
                        .add(
                            egui::DragValue::new(&mut u1)
                                .range(range1)
                                .speed((b - a) * 1e-3)
                                .max_decimals(6),
                        )
                        .labelled_by(l1.id)
                        .on_hover_text("Start parameter of the region");
                    let l2 = ui.label("u₂");
                    let r2 = ui
                        .add(
                            egui::DragValue::new(&mut u2)
                                .range(range2)
                                .speed((b - a) * 1e-3)
                                .max_decimals(6),
                        )
                        .labelled_by(l2.id)
                        .on_hover_text("End parameter of the region");
                    (r1, r2)
                })
                .inner;
            if r1.changed() || r2.changed() {
                self.push(Command::SetRegion(Some((u1, u2))));
            }
        } else {
            ui.weak(if self.ws.view.closed {
                "No region: drag along the curve (past the seam to go across it) or across the κ plot."
            } else {
                "No region: drag along the curve or across the κ plot."
            });
        }
    }

    /// The "Comb" section: comb and display toggles, curvature figures.
    fn comb_section_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Comb");
        ui.checkbox(&mut self.prefs.show_comb, "Show comb")
            .on_hover_text("Curvature comb on the canvas");
        ui.add(
            egui::Slider::new(&mut self.prefs.comb_scale, 0.02..=50.0)
                .logarithmic(true)
                .text("Comb scale"),
        )
        .on_hover_text("Length of the comb teeth");
        ui.horizontal(|ui| {
            ui.label("Scaling:");
            for (m, name, tip) in [
                (CombScaling::Linear, "linear", "Tooth length ~ |κ|"),
                (CombScaling::Sqrt, "sqrt", "Tooth length ~ sqrt|κ|"),
                (CombScaling::Log, "log", "Tooth length ~ ln(1 + |κ|/mean|κ|)"),
            ] {
                ui.selectable_value(&mut self.prefs.comb_scaling, m, name)
                    .on_hover_text(tip);
            }
        });
        ui.checkbox(&mut self.prefs.show_polygon, "Control polygon")
            .on_hover_text("Show the control points and polygon");
        ui.checkbox(&mut self.prefs.show_markers, "Inflections and extrema")
            .on_hover_text("Green diamonds: inflections; orange dots: curvature extrema");
        let s = &self.ws.view.sampled;
        ui.weak(format!(
            "{} inflections, {} curvature extrema, κ in [{:.4}, {:.4}]",
            s.inflections.len(),
            s.extrema.len(),
            s.kappa_range.0,
            s.kappa_range.1
        ));
    }
}
