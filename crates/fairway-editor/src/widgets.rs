//! Small widgets shared by the workspaces.

use std::cell::RefCell;

use eframe::egui;
use fairway::io::{Length, Unit};

use crate::Command;
use crate::workspace::Cx;

/// The tolerance panel's heading: `Tolerance (mm)` when the file's unit is known.
pub fn tolerance_heading(unit: Option<Unit>) -> String {
    match unit {
        Some(u) => format!("Tolerance ({})", u.symbol()),
        None => "Tolerance".into(),
    }
}

/// A typed tolerance (`0.05`, `0.05mm`, `0.002 in`: [`Length::parse`]) in the document's unit `unit`,
/// converted exactly; a plain number is in the document's unit. `Err`: why not, in the user's terms.
pub fn parse_tolerance(text: &str, unit: Option<Unit>) -> Result<f64, String> {
    let length = Length::parse(text).map_err(|e| e.to_string())?;
    let t = length.in_unit(unit).map_err(|e| e.to_string())?;
    if t > 0.0 {
        Ok(t)
    } else {
        Err(format!("{length} is not a tolerance: it must be more than 0"))
    }
}

/// A busy indicator for a background job: a turning arc and `text` ("Fairing… 1.2 s"). It repaints ten
/// times a second (not every frame as egui's `Spinner` does), so a long fair keeps its CPU.
pub fn busy_ui(ui: &mut egui::Ui, text: impl Into<egui::WidgetText>) -> egui::Response {
    ui.horizontal(|ui| {
        let size = ui.style().spacing.interact_size.y;
        let (rect, resp) = ui.allocate_exact_size(egui::vec2(size, size), egui::Sense::hover());
        resp.widget_info(|| egui::WidgetInfo::new(egui::Role::ProgressIndicator));
        let (c, r) = (rect.center(), 0.5 * size - 3.0);
        let start = ui.input(|i| i.time) * std::f64::consts::TAU;
        let arc: Vec<egui::Pos2> = (0..=20)
            .map(|k| {
                let a = start + k as f64 / 20.0 * 1.5 * std::f64::consts::PI;
                c + r * egui::vec2(a.cos() as f32, a.sin() as f32)
            })
            .collect();
        let color = ui.visuals().strong_text_color();
        ui.painter().add(egui::Shape::line(arc, egui::Stroke::new(2.5, color)));
        ui.ctx().request_repaint_after(std::time::Duration::from_millis(100));
        ui.label(text)
    })
    .inner
}

impl<W> Cx<'_, W> {
    /// The "Tolerance" heading and controls of a workspace: a log slider over [1e-6, 0.05] × the model
    /// diagonal `diag` and an exact field taking typed units (both labelled "Tolerance…" for
    /// accessibility), the document's unit beside it. A change pushes [`Command::SetTolerance`]; a typed
    /// entry that is not a tolerance keeps the old value and says why on the error line.
    pub(crate) fn tolerance_ui(&mut self, ui: &mut egui::Ui, mut tol: f64, diag: f64, hint: &str) {
        ui.heading(tolerance_heading(self.unit));
        let old = tol;
        let r1 = ui
            .add(
                egui::Slider::new(&mut tol, diag * 1e-6..=diag * 0.05)
                    .logarithmic(true)
                    .text("Tolerance")
                    .custom_formatter(|v, _| format!("{v:.3e}")),
            )
            .on_hover_text(hint);
        let (unit, rejected) = (self.unit, RefCell::new(None));
        let r2 = ui
            .horizontal(|ui| {
                let l = ui.label("Tolerance (exact)");
                let speed = tol * 0.01;
                let r = ui
                    .add(
                        egui::DragValue::new(&mut tol)
                            .range(1e-12..=f64::MAX)
                            .speed(speed)
                            .max_decimals(12)
                            // parsed on Enter or leaving the field: "0.05m" on the way to "0.05mm" is not applied
                            .update_while_editing(false)
                            .custom_parser(|s| {
                                parse_tolerance(s, unit)
                                    .map_err(|e| *rejected.borrow_mut() = Some(format!("Tolerance {s:?}: {e}")))
                                    .ok()
                            }),
                    )
                    .labelled_by(l.id)
                    .on_hover_text(match unit {
                        Some(u) => format!(
                            "Type a tolerance in {u}, or with a unit (0.05mm, 0.002in, 20um): converted to {u}",
                            u = u.symbol()
                        ),
                        None => "Type a tolerance in the model's units (the document declares no unit)".into(),
                    });
                ui.label(unit.map_or("model units", Unit::symbol));
                r
            })
            .inner;
        if let Some(e) = rejected.into_inner() {
            let stays = format!("{old}{}", unit.map_or(String::new(), |u| format!(" {}", u.symbol())));
            *self.error = Some(format!("{e}; the tolerance stays {stays}"));
        } else if (r1.changed() || r2.changed()) && tol != old {
            self.push(Command::SetTolerance(tol));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typed_tolerances_are_converted_into_the_documents_unit_or_refused() {
        assert_eq!(parse_tolerance("0.05mm", Some(Unit::Inch)), Ok(1.0 / 508.0));
        assert_eq!(parse_tolerance("0.05", Some(Unit::Inch)), Ok(0.05));
        assert_eq!(
            parse_tolerance("2 um", None).unwrap_err(),
            Length::parse("2um").unwrap().in_unit(None).unwrap_err().to_string()
        );
        assert_eq!(
            parse_tolerance("-1 mm", Some(Unit::Millimeter)).unwrap_err(),
            "-1 mm is not a tolerance: it must be more than 0"
        );
        assert_eq!(
            parse_tolerance("0", None).unwrap_err(),
            "0 is not a tolerance: it must be more than 0"
        );
    }
}
