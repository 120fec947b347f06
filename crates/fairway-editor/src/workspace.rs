//! The workspace trait: what the shell ([`crate::App`]) needs from the curve and the surface
//! workspaces. The shell owns the document, its file, the history, the status line, the menus and
//! the shortcuts; a workspace owns its views and draws its panels against a [`ShellCx`] (the
//! document read-only, the settings, the command queue). Panels push [`Command`]s; the shell applies
//! them after the panels: a document edit goes to [`Workspace::apply_edit`] and becomes one undo step.

use eframe::egui;
use fairway::io::{Document, Unit};

use crate::fairing::FairOptions;
use crate::{Command, Prefs};

/// What the shell lends a workspace for one frame.
pub struct ShellCx<'a> {
    /// The open document (edited only through commands).
    pub doc: &'a Document,
    /// Settings kept between sessions.
    pub prefs: &'a mut Prefs,
    /// Commands queued this frame.
    pub commands: &'a mut Vec<Command>,
    /// The status line message.
    pub status: &'a mut String,
    /// The error shown in the status bar until dismissed.
    pub error: &'a mut Option<String>,
    /// The length unit of the document's file (IGES / STEP); `None`: unitless.
    pub unit: Option<Unit>,
}

impl<'a> ShellCx<'a> {
    /// The context with workspace `ws`: what its panels are written against.
    pub fn with<'b, W>(&'b mut self, ws: &'b mut W) -> Cx<'b, W> {
        Cx {
            ws,
            doc: self.doc,
            prefs: &mut *self.prefs,
            commands: &mut *self.commands,
            status: &mut *self.status,
            error: &mut *self.error,
            unit: self.unit,
        }
    }
}

/// A workspace `W` with the shell's context for one frame.
pub struct Cx<'a, W> {
    /// The workspace (views, caches, interaction state).
    pub ws: &'a mut W,
    /// The open document.
    pub doc: &'a Document,
    /// Settings kept between sessions.
    pub prefs: &'a mut Prefs,
    commands: &'a mut Vec<Command>,
    /// The status line message.
    pub status: &'a mut String,
    /// The error line.
    pub error: &'a mut Option<String>,
    /// The length unit of the document's file (IGES / STEP); `None`: unitless.
    pub unit: Option<Unit>,
}

impl<W> Cx<'_, W> {
    /// Queue a command for the end of the frame.
    pub fn push(&mut self, c: Command) {
        self.commands.push(c);
    }
}

/// A workspace: the views and panels of one kind of document (curve, surface).
pub trait Workspace {
    /// The window title's suffix after "Fairway" (e.g. " (surface)").
    fn title_suffix(&self) -> &'static str {
        ""
    }
    /// The tolerance used while the document has none (from the model's size).
    fn default_tolerance(&self) -> f64;
    /// Items of the View menu.
    fn view_menu_ui(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>);
    /// The workspace's part of the toolbar (after Undo / Redo).
    fn toolbar_ui(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>);
    /// The workspace's part of the status bar (geometry, pointer readout).
    fn status_ui(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>);
    /// The hint shown in the status bar while there is no message.
    fn hint(&self) -> &'static str;
    /// The side (and bottom) panels.
    fn panels_ui(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>);
    /// The central view (canvas or 3D view).
    fn canvas_ui(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>);
    /// Apply the document edit `c` to `doc` (and the fairing options `fair`); true if it changed
    /// anything (the shell then records the undo step).
    fn apply_edit(&mut self, c: &Command, doc: &mut Document, fair: &mut FairOptions) -> bool;
    /// The document was replaced by undo / redo (`geometry_changed`: its curve or surface too):
    /// bring the derived data up to date.
    fn document_changed(&mut self, doc: &Document, geometry_changed: bool);
    /// After the commands: bring previews up to date (a frame's last work).
    fn after_commands(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>);
    /// Fit the view to the geometry.
    fn fit_view(&mut self);
    /// Toggle between the original and the faired preview.
    fn toggle_before_after(&mut self);
}
