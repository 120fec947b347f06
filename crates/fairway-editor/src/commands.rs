//! The editor's commands: what panels, menus and shortcuts ask for, applied by the shell after the
//! panels ([`crate::App::apply_commands`]). A document edit (its [`Command::edit_kind`] is `Some`)
//! goes to the open workspace and becomes one undo step; consecutive edits of one kind during one
//! pointer press (a drag, a slider move) merge into one step.

use std::path::PathBuf;

use fairway::BSplineCurve;
use fairway::fair::EndCondition;
use fairway::io::Document;

use crate::App;
use crate::fairing::FairOptions;
use crate::history::{Gesture, Snapshot};
use crate::scene_view::ViewPlane;
use crate::surface_ui::UvRect;

/// A user action, applied after the panels have been drawn.
#[derive(Debug, Clone)]
pub enum Command {
    // ---- document edits (one undo step each)
    /// Set (or clear) the fairing region `[u1, u2]`; on a closed curve `u1 > u2` is the region
    /// across the seam (see [`crate::region`]), on an open curve the ends are put in order.
    SetRegion(Option<(f64, f64)>),
    /// Set (or clear) the surface region `[u1, u2] × [v1, v2]` (the ends are put in order).
    SetRegionUv(Option<UvRect>),
    /// Set the tolerance band width.
    SetTolerance(f64),
    /// Set the fairing options (method, strength, integrator, polish, ...).
    SetFairOptions(FairOptions),
    /// Set the end conditions of the curve region (start, end) in the document.
    SetEnds([EndCondition; 2]),
    /// Set the hand-edited target (`None`: automatic) and the pinned samples.
    SetTarget {
        /// Target values g_k over the region's samples.
        values: Option<Vec<f64>>,
        /// Pinned sample indices.
        pinned: Vec<usize>,
    },
    /// Replace the curve (accepting a faired result).
    ReplaceCurve(Box<BSplineCurve>),
    /// Replace the surface by the faired preview.
    AcceptSurface,
    /// Make object `k` of the document the active one (the one edited and faired).
    Select(usize),
    /// Fair every object of the document together, keeping their joins (the core's network fair). It
    /// runs in the background; its result is one undo step when it arrives ([`App::fair_objects`]).
    FairAll,
    /// Fair these objects of the document together (the others stay as they are; their joins with the
    /// faired ones are held), keeping the joins; in the background, as [`Command::FairAll`].
    FairSet(Vec<usize>),
    /// Draw 3D curves on this plane of the 2D canvas (saved with the document).
    SetViewPlane(ViewPlane),
    // ---- files
    /// Show the open dialog (after the unsaved-work check).
    OpenDialog,
    /// Open a file (after the unsaved-work check).
    Open(PathBuf),
    /// Save to the open file (Save As without one).
    Save,
    /// Save under a name chosen in a dialog.
    SaveAs,
    /// Save to a file.
    SaveTo(PathBuf),
    /// Write what the canvas shows as SVG.
    ExportSvg(PathBuf),
    /// Write the current view (canvas or 3D view) as PNG (a screenshot, taken a frame later).
    ExportPng(PathBuf),
    /// Open object `k` of the IGES or STEP file in the picker.
    OpenPickedObject(usize),
    /// Show the picker of an IGES or STEP file, to import one of its objects.
    ImportOne(PathBuf),
    /// Load the autosave found at start-up as an unsaved document.
    RestoreAutosave,
    /// Delete the autosave found at start-up.
    DiscardAutosave,
    // ---- history and view
    /// Undo one step.
    Undo,
    /// Redo one step.
    Redo,
    /// Fit the view to the geometry.
    FitView,
    /// Toggle between the original and the faired preview.
    ToggleBeforeAfter,
    /// Show or hide the keyboard shortcuts.
    ToggleHelp,
}

impl Command {
    /// For a document edit, the kind of undo step it makes (edits of one kind during one gesture
    /// merge); `None` for every other command.
    pub fn edit_kind(&self) -> Option<Gesture> {
        Some(match self {
            Command::SetRegion(_) | Command::SetRegionUv(_) => Gesture::Region,
            Command::SetTolerance(_) => Gesture::Tolerance,
            Command::SetTarget { .. } => Gesture::Target,
            Command::SetFairOptions(_) | Command::SetEnds(_) => Gesture::Options,
            Command::ReplaceCurve(_) | Command::AcceptSurface | Command::Select(_) | Command::SetViewPlane(_) => {
                Gesture::Single
            }
            _ => return None,
        })
    }
}

/// Set the document's tolerance to `t` (a finite positive value); true if it changed.
pub fn set_tolerance(doc: &mut Document, t: f64) -> bool {
    let ok = t.is_finite() && t > 0.0 && doc.settings.tolerance != Some(t);
    if ok {
        doc.settings.tolerance = Some(t);
    }
    ok
}

/// Set the fairing options; true if they changed.
pub fn set_fair_options(fair: &mut FairOptions, o: FairOptions) -> bool {
    let changed = *fair != o;
    *fair = o;
    changed
}

/// An action waiting for the user to confirm discarding unsaved work.
#[derive(Debug, Clone)]
pub enum Pending {
    /// Open this file.
    Open(PathBuf),
    /// Show the open dialog.
    OpenDialog,
    /// Show the object picker of an IGES or STEP file.
    ImportOne(PathBuf),
    /// Quit the app.
    Quit,
}

impl App {
    /// Queue a command for the end of the frame.
    pub fn push(&mut self, c: Command) {
        self.commands.push(c);
    }

    /// Apply the queued commands (after the panels).
    pub fn apply_commands(&mut self) {
        for c in std::mem::take(&mut self.commands) {
            self.apply(c);
        }
    }

    /// Apply one command now.
    pub fn apply(&mut self, c: Command) {
        if let Some(g) = c.edit_kind() {
            return self.apply_edit(&c, g);
        }
        match c {
            Command::OpenDialog => self.request(Pending::OpenDialog),
            Command::Open(p) => self.open_now(&p),
            Command::Save => self.save(),
            Command::SaveAs => self.save_as(),
            Command::SaveTo(p) => self.save_now(&p),
            Command::ExportSvg(p) => self.export_svg(&p),
            Command::ExportPng(p) => self.start_png_export(p),
            Command::OpenPickedObject(k) => self.open_picked_object(k),
            Command::ImportOne(p) => self.pick_one_object(&p),
            Command::RestoreAutosave => self.restore_autosave(),
            Command::DiscardAutosave => self.discard_autosave(),
            Command::Undo => self.step_history(true),
            Command::Redo => self.step_history(false),
            Command::FitView => self.workspace().fit_view(),
            Command::ToggleBeforeAfter => self.workspace().toggle_before_after(),
            Command::ToggleHelp => self.show_help = !self.show_help,
            Command::FairAll => self.fair_all(),
            Command::FairSet(ks) => self.fair_objects(&ks, "Fair checked"),
            _ => unreachable!("document edits are applied above"),
        }
    }

    /// The document and fairing options, as one undo step restores them.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            doc: self.doc.clone(),
            fair: self.prefs.fair,
            objects: self.objects_now(),
            active: self.active,
            view_plane: self.view_plane,
        }
    }

    /// A document edit: the open workspace applies it, the history records the state before it.
    fn apply_edit(&mut self, c: &Command, g: Gesture) {
        let before = self.snapshot();
        let note = match c {
            Command::ReplaceCurve(_) => Some("Accepted the faired region (Ctrl+Z to undo)".to_string()),
            Command::AcceptSurface => self
                .surface
                .as_ref()
                .and_then(|s| s.preview.as_ref())
                .map(|p| format!("Accepted (max deviation {:.3e}; Ctrl+Z to undo)", p.max_deviation)),
            _ => None,
        };
        let changed = match c {
            Command::Select(k) => self.select_object(*k),
            Command::SetViewPlane(p) => self.set_view_plane(*p),
            _ => {
                let ws: &mut dyn crate::Workspace = match self.surface.as_deref_mut() {
                    Some(s) => s,
                    None => &mut self.curve_ws,
                };
                ws.apply_edit(c, &mut self.doc, &mut self.prefs.fair)
            }
        };
        if changed {
            if before.doc.geometry != self.doc.geometry {
                self.refresh_scene_view();
            }
            self.history.record(before, g);
            if let Some(note) = note {
                self.status = note;
            }
        }
    }

    /// Undo (`back`) or redo one step.
    fn step_history(&mut self, back: bool) {
        let now = self.snapshot();
        let step = if back {
            self.history.undo(now)
        } else {
            self.history.redo(now)
        };
        let Some(s) = step else { return };
        self.restore(s);
        self.status = if back { "Undone" } else { "Redone" }.into();
    }
}
