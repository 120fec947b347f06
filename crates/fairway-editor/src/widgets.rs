//! Small widgets shared by the workspaces.

use eframe::egui;

/// The tolerance panel's heading: `Tolerance (mm)` when the file's unit is known.
pub fn tolerance_heading(unit: Option<fairway::io::Unit>) -> String {
    match unit {
        Some(u) => format!("Tolerance ({})", u.symbol()),
        None => "Tolerance".into(),
    }
}

/// The tolerance controls shared by the curve and surface workspaces: a log slider over
/// [1e-6, 0.05] × the model diagonal `diag` and an exact field (both labelled "Tolerance…" for
/// accessibility). Returns whether `tol` changed.
///
/// The heading above it is [`tolerance_heading`].
pub fn tolerance_ui(ui: &mut egui::Ui, tol: &mut f64, diag: f64, hint: &str) -> bool {
    let r1 = ui
        .add(
            egui::Slider::new(tol, diag * 1e-6..=diag * 0.05)
                .logarithmic(true)
                .text("Tolerance")
                .custom_formatter(|v, _| format!("{v:.3e}")),
        )
        .on_hover_text(hint);
    let r2 = ui
        .horizontal(|ui| {
            let l = ui.label("Tolerance (exact)");
            let speed = *tol * 0.01;
            ui.add(
                egui::DragValue::new(tol)
                    .range(1e-12..=f64::MAX)
                    .speed(speed)
                    .max_decimals(12),
            )
            .labelled_by(l.id)
            .on_hover_text("Type an exact tolerance in model units")
        })
        .inner;
    r1.changed() || r2.changed()
}
