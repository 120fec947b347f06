//! The shell's panels: the menu bar (File, Edit, View, Help and the toolbar), the status bar and
//! the "discard unsaved changes?" modal. The workspace adds its View menu items, its toolbar and
//! its part of the status bar.

use std::path::PathBuf;

use eframe::egui;
use egui::{Color32, RichText};

use crate::shortcuts::shortcut_text;
use crate::{App, Command, Pending};

impl App {
    /// A menu entry that pushes `c`, labelled with its shortcut from the table; closes the menu.
    fn menu_item(&mut self, ui: &mut egui::Ui, text: &str, tip: &str, enabled: bool, c: Command) {
        let button = egui::Button::new(text).shortcut_text(shortcut_text(ui.ctx(), &c));
        if ui.add_enabled(enabled, button).on_hover_text(tip).clicked() {
            self.push(c);
            ui.close();
        }
    }

    pub(crate) fn menu_ui(&mut self, ui: &mut egui::Ui) {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| self.file_menu_ui(ui));
            ui.menu_button("Edit", |ui| {
                let (u, r) = (self.history.can_undo(), self.history.can_redo());
                self.menu_item(ui, "Undo", "Undo the last edit", u, Command::Undo);
                self.menu_item(ui, "Redo", "Redo the step undone last", r, Command::Redo);
            });
            ui.menu_button("View", |ui| {
                self.menu_item(
                    ui,
                    "Fit to view",
                    "Fit the view to the geometry",
                    true,
                    Command::FitView,
                );
                let (ws, mut sh) = self.split();
                ws.view_menu_ui(ui, &mut sh);
                if self.surface.is_none() {
                    self.view_plane_menu_ui(ui);
                }
            });
            ui.menu_button("Help", |ui| {
                let tip = "The keyboard shortcuts";
                self.menu_item(ui, "Keyboard shortcuts", tip, true, Command::ToggleHelp);
            });
            ui.separator();
            self.undo_redo_ui(ui);
            let (ws, mut sh) = self.split();
            ws.toolbar_ui(ui, &mut sh);
        });
    }

    /// The View menu's choice of the plane 3D curves are drawn on.
    fn view_plane_menu_ui(&mut self, ui: &mut egui::Ui) {
        ui.separator();
        ui.label("Draw curves on");
        for p in crate::scene_view::ViewPlane::ALL {
            if ui
                .radio(self.view_plane == p, p.name())
                .on_hover_text(crate::scene_view::plane_tip(p))
                .clicked()
            {
                self.push(Command::SetViewPlane(p));
                ui.close();
            }
        }
    }

    /// The toolbar's Undo / Redo buttons.
    fn undo_redo_ui(&mut self, ui: &mut egui::Ui) {
        for (text, enabled, c) in [
            ("Undo", self.history.can_undo(), Command::Undo),
            ("Redo", self.history.can_redo(), Command::Redo),
        ] {
            let tip = format!("{text} ({})", shortcut_text(ui.ctx(), &c));
            if ui
                .add_enabled(enabled, egui::Button::new(text))
                .on_hover_text(tip)
                .clicked()
            {
                self.push(c);
            }
        }
    }

    fn file_menu_ui(&mut self, ui: &mut egui::Ui) {
        let tip = "Open a .ron document, a .json curve or surface, an IGES or STEP file or a point list";
        self.menu_item(ui, "Open…", tip, true, Command::OpenDialog);
        if ui
            .button("Import one object…")
            .on_hover_text("Choose one curve or surface of an IGES or STEP file (Open opens all of them)")
            .clicked()
        {
            ui.close();
            if let Some(p) = self.pick_path(None, "IGES or STEP", &["igs", "iges", "stp", "step"]) {
                self.request(Pending::ImportOne(p));
            }
        }
        self.menu_item(ui, "Save", "Save the document", true, Command::Save);
        self.menu_item(ui, "Save As…", "Save under a new name", true, Command::SaveAs);
        ui.separator();
        self.export_menu_ui(ui);
        ui.separator();
        let hint = if self.surface.is_some() {
            "/path/to/surface.ron"
        } else {
            "/path/to/curve.ron"
        };
        match typed_path_ui(
            ui,
            &mut self.path_input,
            hint,
            "Type a file path when no file dialog is available",
        ) {
            Some(TypedPath::Open(p)) => self.request(Pending::Open(p)),
            Some(TypedPath::SaveTo(p)) => self.push(Command::SaveTo(p)),
            Some(TypedPath::ImportOne(p)) => self.request(Pending::ImportOne(p)),
            None => {}
        }
        self.export_path_ui(ui);
        ui.separator();
        ui.menu_button("Recent", |ui| {
            if self.prefs.recent.is_empty() {
                ui.label("(none)");
            }
            for p in self.prefs.recent.clone() {
                if ui
                    .button(p.display().to_string())
                    .on_hover_text("Open this file")
                    .clicked()
                {
                    self.request(Pending::Open(p));
                    ui.close();
                }
            }
        });
        ui.separator();
        if ui
            .button("Quit")
            .on_hover_text("Close Fairway (asks about unsaved work)")
            .clicked()
        {
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }

    pub(crate) fn status_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            if let Some(e) = self.error.clone() {
                ui.label(RichText::new(format!("Error: {e}")).color(Color32::from_rgb(230, 80, 60)));
                if ui.small_button("x").on_hover_text("Dismiss").clicked() {
                    self.error = None;
                }
                return;
            }
            ui.label(if self.is_dirty() { "* unsaved" } else { "saved" });
            if self.frame_ms > 0.0 {
                ui.weak(format!("frame {:.1} ms", self.frame_ms))
                    .on_hover_text("CPU time of the last frame's UI code (including any re-fair)");
            }
            ui.separator();
            if let Some((what, t)) = self.network_fair_running() {
                crate::widgets::busy_ui(ui, format!("{what}: fairing… {:.1} s", t.as_secs_f64())).on_hover_text(
                    "The network fair runs in the background; the result is applied as one undo step if the \
                     objects are unchanged when it ends (an edit meanwhile discards it)",
                );
                if ui
                    .small_button("Cancel")
                    .on_hover_text("Stop this fair (the document stays as it is)")
                    .clicked()
                {
                    self.cancel_network_fair();
                }
                ui.separator();
            }
            let (ws, mut sh) = self.split();
            ws.status_ui(ui, &mut sh);
            let hint = ws.hint();
            ui.separator();
            if self.status.is_empty() {
                ui.weak(hint);
            } else {
                ui.label(self.status.as_str());
            }
        });
    }

    pub(crate) fn confirm_ui(&mut self, ui: &mut egui::Ui) {
        let Some(p) = self.confirm.clone() else { return };
        let mut close = false;
        egui::Modal::new(egui::Id::unique("discard")).show(ui.ctx(), |ui| {
            ui.heading("Discard unsaved changes?");
            ui.label("The document has changes that are not saved.");
            ui.horizontal(|ui| {
                if ui
                    .button("Discard changes")
                    .on_hover_text("Lose the unsaved changes and go on")
                    .clicked()
                {
                    self.do_pending(p.clone());
                    if matches!(p, Pending::Quit) {
                        ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
                    }
                    close = true;
                }
                if ui.button("Cancel").on_hover_text("Keep the document open").clicked() {
                    close = true;
                }
            });
        });
        if close {
            self.confirm = None;
        }
    }
}

/// What the File menu's typed-path row asks for.
pub enum TypedPath {
    /// "Open path".
    Open(PathBuf),
    /// "Save to path".
    SaveTo(PathBuf),
    /// "Import one object" (of an IGES or STEP file, through the picker).
    ImportOne(PathBuf),
}

/// The File menu's typed-path row (for sessions without a file dialog): a path field with "Open
/// path" and "Save to path"; closes the menu on a click.
fn typed_path_ui(ui: &mut egui::Ui, path_input: &mut String, hint: &str, tip: &str) -> Option<TypedPath> {
    ui.label("Path:");
    ui.add(
        egui::TextEdit::singleline(path_input)
            .hint_text(hint)
            .desired_width(320.0),
    )
    .on_hover_text(tip);
    let mut out = None;
    ui.horizontal(|ui| {
        let p = PathBuf::from(path_input.trim());
        if ui
            .button("Open path")
            .on_hover_text("Open the file at the typed path")
            .clicked()
        {
            out = Some(TypedPath::Open(p.clone()));
            ui.close();
        }
        if ui
            .button("Save to path")
            .on_hover_text("Save the document to the typed path")
            .clicked()
        {
            out = Some(TypedPath::SaveTo(p.clone()));
            ui.close();
        }
        if ui
            .button("Import one object")
            .on_hover_text("Choose one curve or surface of the IGES or STEP file at the typed path")
            .clicked()
        {
            out = Some(TypedPath::ImportOne(p));
            ui.close();
        }
    });
    out
}
