//! The keyboard shortcuts: one table that dispatches them ([`App::shortcuts`]), labels the menu
//! entries ([`shortcut_text`]) and fills the help overlay ([`App::help_ui`]).

use eframe::egui;
use egui::{Key, KeyboardShortcut, Modifiers};

use crate::{App, Command};

/// One keyboard shortcut.
pub struct Shortcut {
    /// The key.
    pub key: Key,
    /// The modifiers (Ctrl, or Cmd on macOS, is `command`). A shortcut without modifiers does
    /// nothing while a text field has the keyboard.
    pub modifiers: Modifiers,
    /// What it does.
    pub command: Command,
    /// What it does, for the help overlay.
    pub description: &'static str,
}

impl Shortcut {
    /// As egui's shortcut.
    pub fn shortcut(&self) -> KeyboardShortcut {
        KeyboardShortcut::new(self.modifiers, self.key)
    }
}

const CTRL: Modifiers = Modifiers::COMMAND;
const CTRL_SHIFT: Modifiers = Modifiers {
    shift: true,
    ..Modifiers::COMMAND
};
const NONE: Modifiers = Modifiers::NONE;

/// Every shortcut of the editor. A shortcut with more modifiers comes before the one it extends
/// (Ctrl+Shift+Z before Ctrl+Z): egui lets extra Shift through.
pub static SHORTCUTS: [Shortcut; 9] = [
    Shortcut {
        key: Key::O,
        modifiers: CTRL,
        command: Command::OpenDialog,
        description: "Open a document, a curve or surface file, an IGES or STEP file or a point list",
    },
    Shortcut {
        key: Key::S,
        modifiers: CTRL_SHIFT,
        command: Command::SaveAs,
        description: "Save the document under a new name",
    },
    Shortcut {
        key: Key::S,
        modifiers: CTRL,
        command: Command::Save,
        description: "Save the document",
    },
    Shortcut {
        key: Key::Z,
        modifiers: CTRL_SHIFT,
        command: Command::Redo,
        description: "Redo the step undone last",
    },
    Shortcut {
        key: Key::Y,
        modifiers: CTRL,
        command: Command::Redo,
        description: "Redo the step undone last",
    },
    Shortcut {
        key: Key::Z,
        modifiers: CTRL,
        command: Command::Undo,
        description: "Undo the last edit (a whole drag is one step)",
    },
    Shortcut {
        key: Key::F,
        modifiers: NONE,
        command: Command::FitView,
        description: "Fit the view to the curve or surface",
    },
    Shortcut {
        key: Key::Space,
        modifiers: NONE,
        command: Command::ToggleBeforeAfter,
        description: "Show the original or the faired preview",
    },
    Shortcut {
        key: Key::F1,
        modifiers: NONE,
        command: Command::ToggleHelp,
        description: "Show or hide this list of shortcuts",
    },
];

/// The shortcut text of the first shortcut that runs `c` ("Ctrl+Z"), or "".
pub fn shortcut_text(ctx: &egui::Context, c: &Command) -> String {
    let want = std::mem::discriminant(c);
    SHORTCUTS
        .iter()
        .find(|s| std::mem::discriminant(&s.command) == want)
        .map_or(String::new(), |s| ctx.format_shortcut(&s.shortcut()))
}

impl App {
    /// Queue the commands of the shortcuts pressed this frame.
    pub(crate) fn shortcuts(&mut self, ui: &egui::Ui) {
        let typing = ui.ctx().egui_wants_keyboard_input();
        let hits: Vec<Command> = ui.input_mut(|i| {
            SHORTCUTS
                .iter()
                .filter(|s| !(typing && s.modifiers.is_none()) && i.consume_shortcut(&s.shortcut()))
                .map(|s| s.command.clone())
                .collect()
        });
        for c in hits {
            self.push(c);
        }
    }

    /// The keyboard shortcuts overlay (F1 or Help ▸ Keyboard shortcuts).
    pub(crate) fn help_ui(&mut self, ui: &egui::Ui) {
        let ctx = ui.ctx().clone();
        egui::Window::new("Keyboard shortcuts")
            .open(&mut self.show_help)
            .collapsible(false)
            .resizable(false)
            .show(&ctx, |ui| {
                egui::Grid::new("shortcuts").striped(true).show(ui, |ui| {
                    for s in &SHORTCUTS {
                        ui.strong(ctx.format_shortcut(&s.shortcut()));
                        ui.label(s.description);
                        ui.end_row();
                    }
                });
                ui.separator();
                ui.weak("Mouse: wheel zooms, right-drag pans; drag along the curve or the κ plot to select a region.");
            });
    }
}
