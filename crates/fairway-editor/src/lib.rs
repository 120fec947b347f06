//! Fairway's editor: an eframe app for fairing B-spline curves.
//!
//! [`App`] owns the [`Document`] (geometry + region + tolerance + target),
//! the UI state and the undo [`History`]. Each panel is a `fn xxx_ui(&mut
//! self, ui)`; user actions become [`Command`]s queued during the frame and
//! applied after the panels, so one drag is one undo step. No fairing maths
//! lives here: the editor calls the core.

pub mod autosave;
pub mod bench;
pub mod canvas;
pub mod curve3d;
pub mod fair_ui;
pub mod fairing;
pub mod guard;
pub mod history;
pub mod interchange;
pub mod plot;
pub mod region;
pub mod sampled;
pub mod suggest;
pub mod surface_ui;
pub mod view3d;

use std::path::{Path, PathBuf};

use eframe::egui;
use egui::{Color32, RichText};
use fairway::io::Document;
use fairway::{BSplineCurve, DVec2, Geometry};
use serde::{Deserialize, Serialize};

pub use bench::Bench;
pub use fair_ui::{Compare, TargetDrag, TargetTool};
pub use fairing::{FairOptions, Fairing};
pub use history::{Gesture, History};
pub use sampled::Sampled;

/// How comb tooth length grows with |κ|.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum CombScaling {
    /// Proportional to |κ|.
    Linear,
    /// Proportional to √|κ| (tames large peaks).
    Sqrt,
    /// Proportional to ln(1 + |κ|/κ̄).
    Log,
}

/// Settings kept between sessions (eframe storage), not in documents.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(default)]
pub struct Prefs {
    /// Comb length multiplier.
    pub comb_scale: f64,
    /// Comb scaling law.
    pub comb_scaling: CombScaling,
    /// Draw the curvature comb.
    pub show_comb: bool,
    /// Draw the control polygon.
    pub show_polygon: bool,
    /// Draw inflection and curvature-extremum markers.
    pub show_markers: bool,
    /// Recently opened files, newest first.
    pub recent: Vec<PathBuf>,
    /// Fairing options.
    pub fair: FairOptions,
}

impl Default for Prefs {
    fn default() -> Self {
        Self {
            comb_scale: 1.0,
            comb_scaling: CombScaling::Linear,
            show_comb: true,
            show_polygon: true,
            show_markers: true,
            recent: vec![],
            fair: FairOptions::default(),
        }
    }
}

/// A user action, applied after the panels have been drawn.
#[derive(Debug, Clone)]
pub enum Command {
    /// Set (or clear) the fairing region `[u1, u2]`; on a closed curve `u1 > u2` is the region
    /// across the seam (see [`region`]), on an open curve the ends are put in order.
    SetRegion(Option<(f64, f64)>),
    /// Set the tolerance band width.
    SetTolerance(f64),
    /// Open a file (after the unsaved-work check).
    Open(PathBuf),
    /// Save to a file.
    SaveTo(PathBuf),
    /// Undo one step.
    Undo,
    /// Redo one step.
    Redo,
    /// Replace the curve (accepting a faired result); one undo step.
    ReplaceCurve(Box<BSplineCurve>),
    /// Set the hand-edited target (`None`: automatic) and the pinned samples.
    SetTarget {
        /// Target values g_k over the region's samples.
        values: Option<Vec<f64>>,
        /// Pinned sample indices.
        pinned: Vec<usize>,
    },
    /// Set the end conditions of the curve region (start, end) in the document; one undo step.
    SetEnds([fairway::fair::EndCondition; 2]),
    /// Write what the canvas shows as SVG.
    ExportSvg(PathBuf),
    /// Write the current view (canvas or 3D view) as PNG (a screenshot, taken a frame later).
    ExportPng(PathBuf),
    /// Open object `k` of the IGES or STEP file in the picker.
    OpenPickedObject(usize),
    /// Load the autosave found at start-up as an unsaved document.
    RestoreAutosave,
    /// Delete the autosave found at start-up.
    DiscardAutosave,
}

/// An action waiting for the user to confirm discarding unsaved work.
#[derive(Debug, Clone)]
pub enum Pending {
    /// Open this file.
    Open(PathBuf),
    /// Show the open dialog.
    OpenDialog,
    /// Quit the app.
    Quit,
}

/// Data derived from the document's curve, rebuilt when the curve changes.
#[derive(Debug, Clone, Default)]
pub struct CurveView {
    /// Dense samples of the curve.
    pub sampled: Sampled,
    /// Control points projected onto the view plane.
    pub control: Vec<DVec2>,
    /// Diagonal of the bounding box (model units).
    pub diag: f64,
    /// The curve is closed (first point = last point): its parameter is circular and a region may
    /// run across the seam ([`region`]).
    pub closed: bool,
    /// The curve's parameter domain `(a, b)`.
    pub domain: (f64, f64),
}

impl CurveView {
    fn new(curve: &BSplineCurve) -> Self {
        let spans = curve.knots().breakpoints().len().saturating_sub(1).max(1);
        let sampled = Sampled::new(curve, (spans * 24).clamp(400, 4000));
        let control: Vec<DVec2> = curve.points().iter().map(|p| p.truncate()).collect();
        let (a, b) = sampled.bbox;
        let diag = (b - a).length().max(1e-12);
        Self {
            sampled,
            control,
            diag,
            closed: fairway::fair::closed::is_closed_curve(curve),
            domain: curve.domain(),
        }
    }
}

/// The editor.
pub struct App {
    /// The open document.
    pub doc: Document,
    /// Where the document lives on disk.
    pub path: Option<PathBuf>,
    /// The document as last saved or opened (for the unsaved marker);
    /// `None`: never saved (a restored autosave).
    saved: Option<Document>,
    /// Undo history.
    pub history: History,
    /// Persisted settings.
    pub prefs: Prefs,
    /// Derived drawing data of the document's curve.
    pub view: CurveView,
    /// Commands queued this frame.
    commands: Vec<Command>,
    /// Canvas camera and interaction state.
    pub canvas: canvas::CanvasState,
    /// κ plot interaction state.
    pub plot: plot::PlotState,
    /// Arc length under the pointer (canvas or κ plot), shared by both.
    pub hover_s: Option<f64>,
    next_hover_s: Option<f64>,
    /// Last error, shown until dismissed.
    pub error: Option<String>,
    /// Status line message.
    pub status: String,
    /// The path field (fallback when no file dialog is available).
    pub path_input: String,
    /// Waiting for the user to confirm discarding unsaved work.
    pub confirm: Option<Pending>,
    allow_close: bool,
    last_title: String,
    /// Live fairing preview.
    pub fairing: Fairing,
    /// Bumped whenever the document's curve changes.
    pub curve_rev: u64,
    /// Compare settings.
    pub compare: Compare,
    /// Target tool on the κ plot.
    pub tool: TargetTool,
    /// Falloff radius of a target drag (fraction of the region length).
    pub falloff: f64,
    /// Target drag in progress.
    pub target_drag: Option<TargetDrag>,
    /// A drag (slider, canvas, κ plot) is in progress: the preview is a draft.
    pub drag_in_progress: bool,
    /// CPU time of the last frames' `show` (ms), for the status bar.
    pub frame_ms: f64,
    /// Benchmark mode: sweep the tolerance every frame and report timings.
    pub bench: Option<Bench>,
    /// "Suggest regions" results.
    pub suggest: suggest::Suggestions,
    /// The surface workspace, when a surface is open (replaces the curve screens).
    pub surface: Option<Box<surface_ui::SurfaceEditor>>,
    /// The curve's 3D view (3D comb, extrusion isophotes).
    pub curve3d: curve3d::Curve3dState,
    /// Periodic autosave (`None`: off, as in tests that do not ask for it).
    pub autosave: Option<crate::autosave::Autosave>,
    /// This session wrote the autosave that is on disk.
    autosaved: bool,
    /// An autosave found at start-up, waiting for Restore / Discard.
    pub recovery: Option<crate::autosave::Recovery>,
    /// An IGES or STEP file with several objects, waiting for the user's choice.
    pub object_pick: Option<interchange::ObjectPick>,
    /// The length unit of the open curve's file (IGES / STEP), shown beside lengths and declared when
    /// saving as IGES or STEP; `None`: unitless (saved as mm).
    pub unit: Option<fairway::io::Unit>,
    /// A PNG export in progress (waiting for the screenshot).
    pub png_export: Option<interchange::PngExport>,
    /// The central panel's content area (canvas or 3D view) of the last frame, in points.
    pub view_rect: egui::Rect,
    /// `--export-png`: export the view, then quit.
    export_then_quit: Option<interchange::ExportThenQuit>,
}

impl Default for App {
    fn default() -> Self {
        Self::with_document(Document::new(Geometry::Curve(demo_curve())), None)
    }
}

impl App {
    /// An editor showing `doc`, loaded from `path`.
    pub fn with_document(doc: Document, path: Option<PathBuf>) -> Self {
        let curve = doc_curve(&doc).cloned().unwrap_or_else(demo_curve);
        let saved = if doc_curve(&doc).is_some() {
            doc
        } else {
            Document::new(Geometry::Curve(curve.clone()))
        };
        // settings that do not fit the curve are dropped and said; the document then shows as changed
        let mut doc = saved.clone();
        let error = settings_notes(doc.sanitize_settings());
        Self {
            view: CurveView::new(&curve),
            saved: Some(saved),
            doc,
            path: path.clone(),
            history: History::default(),
            prefs: Prefs::default(),
            commands: vec![],
            canvas: Default::default(),
            plot: Default::default(),
            hover_s: None,
            next_hover_s: None,
            error,
            status: String::new(),
            path_input: path.map(|p| p.display().to_string()).unwrap_or_default(),
            confirm: None,
            allow_close: false,
            last_title: String::new(),
            fairing: Fairing::default(),
            curve_rev: 0,
            compare: Compare::default(),
            tool: TargetTool::default(),
            falloff: 0.08,
            target_drag: None,
            frame_ms: 0.0,
            drag_in_progress: false,
            bench: None,
            suggest: Default::default(),
            surface: None,
            curve3d: Default::default(),
            autosave: None,
            autosaved: false,
            recovery: None,
            object_pick: None,
            unit: None,
            png_export: None,
            view_rect: egui::Rect::NOTHING,
            export_then_quit: None,
        }
    }

    /// Open `path` in a new editor; on error, the demo curve and the error
    /// message.
    pub fn open_or_demo(path: Option<&Path>) -> Self {
        match path {
            None => Self::default(),
            Some(p) => {
                let mut app = Self::default();
                app.open_now(p);
                app
            }
        }
    }

    /// The editor for eframe: settings restored from storage, `path` opened.
    pub fn new(cc: &eframe::CreationContext<'_>, path: Option<&Path>) -> Self {
        view3d::install(cc);
        let mut app = Self::open_or_demo(path).with_default_autosave();
        if let Some(storage) = cc.storage {
            app.load_view3d_prefs(storage);
        }
        if let Some(storage) = cc.storage {
            app.load_prefs(storage);
        }
        app
    }

    /// Restore the curve editor's settings (comb, toggles, recent files,
    /// fairing options) saved by [`eframe::App::save`]; the file opened at
    /// start stays first in the recent list. Unreadable settings change
    /// nothing; out-of-range values (a hand-edited store) are clamped.
    pub fn load_prefs(&mut self, storage: &dyn eframe::Storage) {
        let Some(mut prefs) = eframe::get_value::<Prefs>(storage, "prefs") else {
            return;
        };
        prefs.comb_scale = if prefs.comb_scale.is_finite() {
            prefs.comb_scale.clamp(0.02, 50.0)
        } else {
            Prefs::default().comb_scale
        };
        // the slider's range is 0..=4n; a huge stored strength would stall the Average method
        prefs.fair.strength = prefs.fair.strength.map(|n| n.min(100_000));
        prefs.fair.polish_iterations = prefs.fair.polish_iterations.min(fairing::MAX_POLISH);
        let recent = std::mem::take(&mut self.prefs.recent);
        self.prefs = prefs;
        for r in recent.into_iter().rev() {
            self.push_recent(r);
        }
    }

    /// The document's curve.
    pub fn curve(&self) -> &BSplineCurve {
        doc_curve(&self.doc).expect("the editor only holds curve documents")
    }

    /// Whether the document differs from the saved file.
    pub fn is_dirty(&self) -> bool {
        self.saved.as_ref() != Some(&self.doc) || self.surface.as_ref().is_some_and(|s| s.is_dirty())
    }

    /// The tolerance in effect (document value or a default from the size).
    pub fn tolerance(&self) -> f64 {
        self.doc.settings.tolerance.unwrap_or(self.view.diag * 1e-3)
    }

    /// The region `[u1, u2]`, if one is selected (`u1 > u2`: across the seam of a closed curve).
    pub fn region(&self) -> Option<(f64, f64)> {
        self.doc.settings.region
    }

    /// Queue a command for the end of the frame.
    pub fn push(&mut self, c: Command) {
        self.commands.push(c);
    }

    /// Load `path` now, replacing the document (no unsaved check). Errors go
    /// to [`App::error`] and leave the open document untouched.
    pub fn open_now(&mut self, path: &Path) {
        if interchange::is_interchange(path) {
            self.open_interchange(path);
            return;
        }
        match fairway::io::load(path) {
            Ok(doc) => {
                self.set_document(doc.clone(), Some(path.to_path_buf()), Some(doc));
                self.report_status(format!("Opened {}", path.display()));
                self.push_recent(path.to_path_buf());
            }
            Err(e) => self.report_error(format!("Could not open {}: {e}", path.display())),
        }
    }

    /// Replace the open document by `doc` (a curve goes to the curve editor,
    /// a surface to the surface workspace); `saved` is its state on disk
    /// (`None`: never saved, so it shows as unsaved).
    pub fn set_document(&mut self, mut doc: Document, path: Option<PathBuf>, saved: Option<Document>) {
        // absolute, so an autosave's source still names the file after a restart elsewhere
        let path = path.map(|p| std::path::absolute(&p).unwrap_or(p));
        // a new document is unitless until its opener says otherwise (open_interchange)
        self.unit = None;
        if doc_curve(&doc).is_none() {
            match surface_ui::SurfaceEditor::new(doc, path) {
                Ok(mut s) => {
                    // (SurfaceEditor::new has checked the settings and says what it dropped)
                    s.set_saved(saved);
                    s.set_shading(self.curve3d.surface_shading);
                    self.surface = Some(Box::new(s));
                    // the curve editor's document is hidden while a surface is open
                    self.saved = Some(self.doc.clone());
                }
                Err(e) => self.report_error(format!("Could not open the surface: {e}")),
            }
            return;
        }
        self.surface = None;
        let notes = doc.sanitize_settings();
        let curve = doc_curve(&doc).unwrap().clone();
        self.view = CurveView::new(&curve);
        self.curve_rev += 1;
        self.saved = saved;
        self.doc = doc;
        self.path_input = path.as_ref().map(|p| p.display().to_string()).unwrap_or_default();
        self.path = path;
        self.history.clear();
        self.canvas.needs_fit = true;
        self.error = settings_notes(notes);
    }

    /// Show an error where the user looks: the surface workspace's status
    /// bar when a surface is open, else the curve editor's.
    pub fn report_error(&mut self, msg: String) {
        match self.surface.as_mut() {
            Some(s) => s.error = Some(msg),
            None => self.error = Some(msg),
        }
    }

    /// Show a status message (see [`App::report_error`]).
    pub fn report_status(&mut self, msg: String) {
        match self.surface.as_mut() {
            Some(s) => s.status = msg,
            None => self.status = msg,
        }
    }

    fn push_recent(&mut self, p: PathBuf) {
        let p = std::fs::canonicalize(&p).unwrap_or(p);
        self.prefs.recent.retain(|q| q != &p);
        self.prefs.recent.insert(0, p);
        self.prefs.recent.truncate(10);
    }

    fn save_now(&mut self, path: &Path) {
        match fairway::io::save_in(path, &self.doc, self.unit) {
            Ok(()) => {
                self.saved = Some(self.doc.clone());
                self.path = Some(std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf()));
                self.path_input = path.display().to_string();
                self.status = format!("Saved {}", path.display());
                self.push_recent(path.to_path_buf());
            }
            Err(e) => self.error = Some(format!("Could not save {}: {e}", path.display())),
        }
    }

    /// Ask before `p` if there is unsaved work, else do it.
    fn request(&mut self, p: Pending) {
        if self.is_dirty() {
            self.confirm = Some(p);
        } else {
            self.do_pending(p);
        }
    }

    fn do_pending(&mut self, p: Pending) {
        match p {
            Pending::Open(path) => self.push(Command::Open(path)),
            Pending::OpenDialog => {
                if let Some(path) = self.pick_file(false) {
                    self.push(Command::Open(path));
                }
            }
            Pending::Quit => self.allow_close = true,
        }
    }

    /// A native file dialog for documents, or `None` with a message when none can run.
    fn pick_file(&mut self, save: bool) -> Option<PathBuf> {
        let default_name = self
            .path
            .as_ref()
            .and_then(|p| p.file_name())
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "curve.ron".into());
        let filter: &[&str] = if save {
            &["ron", "fairway", "json", "igs", "iges", "stp", "step"]
        } else {
            &[
                "ron", "fairway", "json", "igs", "iges", "stp", "step", "csv", "txt", "xyz",
            ]
        };
        self.pick_path(
            save.then_some(default_name.as_str()),
            "Fairway document or geometry",
            filter,
        )
    }

    /// A native file dialog: a save dialog proposing `save_name`, or an open
    /// dialog when `None`; `None` with a message when no dialog can run.
    fn pick_path(&mut self, save_name: Option<&str>, what: &str, extensions: &[&str]) -> Option<PathBuf> {
        if !dialog_available() {
            self.error = Some(
                "No file dialog is available here (no desktop portal on the session bus). \
                 Type a path in the File menu's path field, drag a file onto the window, \
                 or pass it on the command line."
                    .into(),
            );
            return None;
        }
        let mut d = rfd::FileDialog::new().add_filter(what, extensions);
        if let Some(dir) = self.path.as_ref().and_then(|p| p.parent()) {
            d = d.set_directory(dir);
        }
        match save_name {
            Some(name) => d.set_file_name(name).save_file(),
            None => d.pick_file(),
        }
    }

    /// Apply the queued commands (after the panels).
    pub fn apply_commands(&mut self) {
        for c in std::mem::take(&mut self.commands) {
            self.apply(c);
        }
    }

    /// Apply one command now.
    pub fn apply(&mut self, c: Command) {
        match c {
            Command::SetRegion(r) => {
                let (dom, closed) = (self.view.domain, self.view.closed);
                let r = r.map(|r| region::canonical(r, dom, closed));
                if self.doc.settings.region != r {
                    self.history.record(&self.doc, Gesture::Region);
                    self.doc.settings.region = r;
                    // a hand-edited target belongs to the old region's samples
                    self.doc.settings.target = None;
                    self.doc.settings.pinned.clear();
                    self.doc.settings.target_params = None;
                }
            }
            Command::SetTolerance(t) => {
                if t.is_finite() && t > 0.0 && self.doc.settings.tolerance != Some(t) {
                    self.history.record(&self.doc, Gesture::Tolerance);
                    self.doc.settings.tolerance = Some(t);
                }
            }
            Command::Open(p) => self.open_now(&p),
            Command::SaveTo(p) => self.save_now(&p),
            Command::Undo => {
                if let Some(d) = self.history.undo(&self.doc) {
                    self.set_doc(d);
                    self.status = "Undone".into();
                }
            }
            Command::Redo => {
                if let Some(d) = self.history.redo(&self.doc) {
                    self.set_doc(d);
                    self.status = "Redone".into();
                }
            }
            Command::ReplaceCurve(c) => {
                self.history.record(&self.doc, Gesture::Single);
                self.doc.geometry = Geometry::Curve(*c);
                self.doc.settings.region = None;
                self.doc.settings.target = None;
                self.doc.settings.pinned.clear();
                self.doc.settings.target_params = None;
                self.view = CurveView::new(self.curve());
                self.curve_rev += 1;
                self.status = "Accepted the faired region (Ctrl+Z to undo)".into();
            }
            Command::SetTarget { values, pinned } => {
                let s = &self.doc.settings;
                if s.target != values || s.pinned != pinned {
                    self.history.record(&self.doc, Gesture::Target);
                    // the edit was made on the preview's samples: their curve parameters go with it, so
                    // that it survives other samples (other end conditions, a reopened file)
                    let params = match (&values, &self.fairing.preview) {
                        (Some(v), Some(Ok(p))) if p.params.len() == v.len() => Some(p.params.clone()),
                        _ => None,
                    };
                    self.doc.settings.target = values;
                    self.doc.settings.pinned = pinned;
                    self.doc.settings.target_params = params;
                }
            }
            Command::SetEnds(ends) => {
                if ends != self.ends() {
                    self.history.record(&self.doc, Gesture::Options);
                    self.doc.settings.ends = Some(ends);
                }
            }
            Command::ExportSvg(p) => self.export_svg(&p),
            Command::ExportPng(p) => self.start_png_export(p),
            Command::OpenPickedObject(k) => self.open_picked_object(k),
            Command::RestoreAutosave => self.restore_autosave(),
            Command::DiscardAutosave => self.discard_autosave(),
        }
    }

    fn set_doc(&mut self, d: Document) {
        let geometry_changed = d.geometry != self.doc.geometry;
        self.doc = d;
        if geometry_changed {
            self.view = CurveView::new(self.curve());
            self.curve_rev += 1;
        }
    }

    /// Draw the whole editor into `ui` and apply the frame's commands.
    pub fn show(&mut self, ui: &mut egui::Ui) {
        self.recovery_ui(ui);
        self.object_picker_ui(ui);
        if self.surface_show(ui) {
            self.apply_commands();
            self.after_frame(ui);
            return;
        }
        self.next_hover_s = None;
        self.shortcuts(ui);
        self.dropped_files(ui);
        egui::Panel::top("menu").show(ui, |ui| self.menu_ui(ui));
        egui::Panel::bottom("status").show(ui, |ui| self.status_ui(ui));
        egui::Panel::right("controls")
            .resizable(true)
            .default_size(270.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.controls_ui(ui));
            });
        egui::Panel::bottom("kappa")
            .resizable(true)
            .default_size(210.0)
            .show(ui, |ui| self.plot_ui(ui));
        egui::CentralPanel::default().show(ui, |ui| {
            self.view_rect = ui.max_rect();
            if self.curve3d.enabled {
                self.curve3d_ui(ui)
            } else {
                self.canvas_ui(ui)
            }
        });
        self.trio_ui(&ui.ctx().clone());
        self.confirm_ui(ui);
        self.apply_commands();
        // a drag on a slider, the canvas or the κ plot: fair a draft (no E
        // polish) until it ends (buttons are clicks, not drags: Accept never
        // starts a draft); the bench counts as a drag
        self.drag_in_progress = self.bench.is_some()
            || ui.ctx().dragged_id().is_some()
            || self.canvas.drag != canvas::CanvasDrag::None
            || self.plot.drag != plot::PlotDrag::None
            || self.target_drag.is_some();
        if self.update_fairing() {
            ui.ctx().request_repaint();
        }
        if let Some(e) = self.fairing.internal_error.take() {
            self.error = Some(e);
        }
        if !ui.input(|i| i.pointer.any_down()) {
            self.history.end_gesture();
        }
        if self.hover_s != self.next_hover_s {
            self.hover_s = self.next_hover_s;
            ui.ctx().request_repaint();
        }
        let title = self.title();
        if title != self.last_title {
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.last_title = title;
        }
        self.after_frame(ui);
    }

    /// Bring the fairing preview up to date with the document; true if it
    /// was recomputed.
    pub fn update_fairing(&mut self) -> bool {
        let tol = self.tolerance();
        let draft = self.drag_in_progress;
        let curve = doc_curve(&self.doc).expect("curve document");
        let opts = FairOptions {
            ends: self.ends(),
            ..self.prefs.fair
        };
        self.fairing.update(
            curve,
            self.curve_rev,
            &self.doc.settings,
            tol,
            opts,
            self.compare.trio,
            draft,
        )
    }

    /// The end conditions of the curve region: the document's, else the default of the preferences.
    pub fn ends(&self) -> [fairway::fair::EndCondition; 2] {
        self.doc.settings.ends.unwrap_or(self.prefs.fair.ends)
    }

    /// Window title: file name and an unsaved marker.
    pub fn title(&self) -> String {
        let name = self
            .path
            .as_ref()
            .and_then(|p| p.file_name())
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "untitled".into());
        format!("{}{name} — Fairway", if self.is_dirty() { "* " } else { "" })
    }

    fn shortcuts(&mut self, ui: &egui::Ui) {
        use egui::{Key, KeyboardShortcut, Modifiers};
        let sc = |m, k| KeyboardShortcut::new(m, k);
        let (redo, undo, open, save_as, save) = ui.input_mut(|i| {
            let redo = i.consume_shortcut(&sc(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z))
                || i.consume_shortcut(&sc(Modifiers::COMMAND, Key::Y));
            let undo = i.consume_shortcut(&sc(Modifiers::COMMAND, Key::Z));
            let open = i.consume_shortcut(&sc(Modifiers::COMMAND, Key::O));
            let save_as = i.consume_shortcut(&sc(Modifiers::COMMAND | Modifiers::SHIFT, Key::S));
            let save = i.consume_shortcut(&sc(Modifiers::COMMAND, Key::S));
            (redo, undo, open, save_as, save)
        });
        if redo {
            self.push(Command::Redo);
        } else if undo {
            self.push(Command::Undo);
        }
        if open {
            self.request(Pending::OpenDialog);
        }
        if save_as {
            self.save_as();
        } else if save {
            self.save();
        }
        if !ui.ctx().egui_wants_keyboard_input() {
            if ui.input(|i| i.key_pressed(Key::F)) {
                self.canvas.needs_fit = true;
            }
            if ui.input(|i| i.key_pressed(Key::Space)) {
                self.compare.show_after = !self.compare.show_after;
            }
        }
    }

    fn dropped_files(&mut self, ui: &egui::Ui) {
        let dropped: Vec<PathBuf> = ui.input(|i| i.raw.dropped_files.iter().map(|f| f.path().to_path_buf()).collect());
        if let Some(p) = dropped.into_iter().next() {
            self.request(Pending::Open(p));
        }
    }

    fn save(&mut self) {
        match self.path.clone() {
            Some(p) => self.push(Command::SaveTo(p)),
            None => self.save_as(),
        }
    }

    fn save_as(&mut self) {
        if let Some(p) = self.pick_file(true) {
            self.push(Command::SaveTo(p));
        }
    }

    fn menu_ui(&mut self, ui: &mut egui::Ui) {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
                if ui
                    .button("Open…")
                    .on_hover_text(
                        "Open a .ron document, a .json curve or surface, an IGES or STEP file or a point list (Ctrl+O)",
                    )
                    .clicked()
                {
                    self.request(Pending::OpenDialog);
                    ui.close();
                }
                if ui.button("Save").on_hover_text("Save the document (Ctrl+S)").clicked() {
                    self.save();
                    ui.close();
                }
                if ui
                    .button("Save As…")
                    .on_hover_text("Save under a new name (Ctrl+Shift+S)")
                    .clicked()
                {
                    self.save_as();
                    ui.close();
                }
                ui.separator();
                self.export_menu_ui(ui);
                ui.separator();
                match typed_path_ui(
                    ui,
                    &mut self.path_input,
                    "/path/to/curve.ron",
                    "Type a file path when no file dialog is available",
                ) {
                    Some(TypedPath::Open(p)) => self.request(Pending::Open(p)),
                    Some(TypedPath::SaveTo(p)) => self.push(Command::SaveTo(p)),
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
            });
            ui.menu_button("Edit", |ui| {
                if ui
                    .add_enabled(self.history.can_undo(), egui::Button::new("Undo"))
                    .on_hover_text("Ctrl+Z")
                    .clicked()
                {
                    self.push(Command::Undo);
                }
                if ui
                    .add_enabled(self.history.can_redo(), egui::Button::new("Redo"))
                    .on_hover_text("Ctrl+Shift+Z or Ctrl+Y")
                    .clicked()
                {
                    self.push(Command::Redo);
                }
            });
            ui.menu_button("View", |ui| {
                if ui.button("Fit to view").on_hover_text("F").clicked() {
                    self.canvas.needs_fit = true;
                }
                ui.checkbox(&mut self.prefs.show_polygon, "Control polygon")
                    .on_hover_text("Show the control points and polygon");
                ui.checkbox(&mut self.prefs.show_comb, "Curvature comb")
                    .on_hover_text("Curvature comb on the canvas");
                ui.checkbox(&mut self.prefs.show_markers, "Inflections and extrema")
                    .on_hover_text("Green diamonds: inflections; orange dots: curvature extrema");
            });
            ui.separator();
            match undo_redo_ui(ui, self.history.can_undo(), self.history.can_redo()) {
                Some(true) => self.push(Command::Undo),
                Some(false) => self.push(Command::Redo),
                None => {}
            }
            if ui
                .button("Fit")
                .on_hover_text("Fit the curve to the view (F)")
                .clicked()
            {
                self.canvas.needs_fit = true;
            }
            ui.toggle_value(&mut self.curve3d.enabled, "3D view")
                .on_hover_text("The curve and its comb in 3D; extrusion isophotes for planar curves");
        });
    }

    fn status_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            if let Some(e) = self.error.clone() {
                ui.label(RichText::new(format!("Error: {e}")).color(Color32::from_rgb(230, 80, 60)));
                if ui.small_button("x").on_hover_text("Dismiss").clicked() {
                    self.error = None;
                }
                return;
            }
            let dirty = if self.is_dirty() { "* unsaved" } else { "saved" };
            ui.label(dirty);
            if self.frame_ms > 0.0 {
                ui.weak(format!("frame {:.1} ms", self.frame_ms))
                    .on_hover_text("CPU time of the last frame's UI code (including any re-fair)");
            }
            ui.separator();
            if let Some(s) = self.hover_s {
                let k = self.view.sampled.kappa_at_s(s);
                ui.label(format!("s = {s:.4}  κ = {k:.5}"));
                ui.separator();
            }
            let c = self.curve();
            ui.label(format!(
                "{}D, degree {}, {} control points, length {:.4}{}",
                c.dim(),
                c.degree(),
                c.n_points(),
                self.view.sampled.length,
                self.unit.map_or(String::new(), |u| format!(" {}", u.symbol()))
            ));
            if let Some(u) = self.unit {
                ui.label(format!("unit {}", u.symbol()))
                    .on_hover_text("The length unit of the file this curve came from (IGES / STEP)");
            }
            ui.separator();
            if self.status.is_empty() {
                ui.weak(
                    "Drag along the curve or the κ plot to select a region · wheel: zoom · right-drag: pan · F: fit",
                );
            } else {
                ui.label(self.status.as_str());
            }
        });
    }

    fn controls_ui(&mut self, ui: &mut egui::Ui) {
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
            let closed = self.view.closed;
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
            ui.weak(if self.view.closed {
                "No region: drag along the curve (past the seam to go across it) or across the κ plot."
            } else {
                "No region: drag along the curve or across the κ plot."
            });
        }
        ui.separator();
        ui.heading(crate::tolerance_heading(self.unit));
        let mut tol = self.tolerance();
        if tolerance_ui(
            ui,
            &mut tol,
            self.view.diag,
            "Tolerance band width m, in the model's units (log scale). The faired curve stays within m.",
        ) {
            self.push(Command::SetTolerance(tol));
        }
        ui.separator();
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
        let s = &self.view.sampled;
        ui.weak(format!(
            "{} inflections, {} curvature extrema, κ in [{:.4}, {:.4}]",
            s.inflections.len(),
            s.extrema.len(),
            s.kappa_range.0,
            s.kappa_range.1
        ));
        ui.separator();
        self.fairing_ui(ui);
        ui.separator();
        self.measures_ui(ui);
    }

    fn confirm_ui(&mut self, ui: &mut egui::Ui) {
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

    /// Let the next close request through without asking about unsaved work.
    fn allow_close(&mut self) {
        self.allow_close = true;
    }

    /// Handle a window close request (ask when there is unsaved work).
    fn handle_close(&mut self, ctx: &egui::Context) {
        if ctx.input(|i| i.viewport().close_requested()) && self.is_dirty() && !self.allow_close {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            self.confirm = Some(Pending::Quit);
        }
    }
}

impl eframe::App for App {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        self.handle_close(&ui.ctx().clone());
        if self.bench.is_some() {
            self.bench_frame(ui, frame.info().cpu_usage);
            return;
        }
        let t0 = std::time::Instant::now();
        self.show(ui);
        self.frame_ms = t0.elapsed().as_secs_f64() * 1e3;
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, "prefs", &self.prefs);
        eframe::set_value(storage, view3d::View3dPrefs::KEY, &self.view3d_prefs());
    }

    /// A clean exit (unsaved work was confirmed lost) removes the autosave.
    fn on_exit(&mut self) {
        self.clear_autosave();
    }
}

/// The message for saved settings that [`Document::sanitize_settings`] had to drop or change (`None`:
/// everything fitted).
pub(crate) fn settings_notes(notes: Vec<String>) -> Option<String> {
    (!notes.is_empty()).then(|| format!("Some saved settings did not fit: {}", notes.join("; ")))
}

fn doc_curve(doc: &Document) -> Option<&BSplineCurve> {
    match &doc.geometry {
        Geometry::Curve(c) => Some(c),
        Geometry::Surface(_) => None,
    }
}

/// Load a document that holds a curve.
pub fn load_curve_doc(path: &Path) -> anyhow::Result<Document> {
    let doc = fairway::io::load(path)?;
    if doc_curve(&doc).is_none() {
        anyhow::bail!("this file holds a surface; the editor fairs curves only (for now)");
    }
    Ok(doc)
}

/// Whether a native file dialog can run: rfd's portal backend needs a
/// session bus.
fn dialog_available() -> bool {
    std::env::var_os("DBUS_SESSION_BUS_ADDRESS").is_some()
}

/// A noisy car-roof-like cubic curve (used when no file is given and no
/// sample is found): 40 control points on a flat arc with a deterministic
/// ripple.
pub fn demo_curve() -> BSplineCurve {
    demo_curve_n(40)
}

/// The demo curve with `n` (≥ 4) control points.
pub fn demo_curve_n(n: usize) -> BSplineCurve {
    let n = n.max(4);
    let p = 3;
    let pts: Vec<DVec2> = (0..n)
        .map(|i| {
            let t = i as f64 / (n - 1) as f64;
            let x = 2.0 * t;
            let y = 0.35 * (std::f64::consts::PI * t).sin() + 0.004 * ((i * 7919 % 13) as f64 / 6.0 - 1.0);
            DVec2::new(x, y)
        })
        .collect();
    let inner = n - p - 1;
    let mut knots = vec![0.0; p + 1];
    knots.extend((1..=inner).map(|k| k as f64 / (inner + 1) as f64));
    knots.extend(vec![1.0; p + 1]);
    BSplineCurve::new_2d(p, knots, &pts).expect("valid demo curve")
}

/// The toolbar's Undo / Redo buttons, shared by the curve and surface screens:
/// `Some(true)` for Undo, `Some(false)` for Redo.
pub fn undo_redo_ui(ui: &mut egui::Ui, can_undo: bool, can_redo: bool) -> Option<bool> {
    let mut out = None;
    if ui
        .add_enabled(can_undo, egui::Button::new("Undo"))
        .on_hover_text("Undo (Ctrl+Z)")
        .clicked()
    {
        out = Some(true);
    }
    if ui
        .add_enabled(can_redo, egui::Button::new("Redo"))
        .on_hover_text("Redo (Ctrl+Shift+Z / Ctrl+Y)")
        .clicked()
    {
        out = Some(false);
    }
    out
}

/// What the File menu's typed-path row asks for.
pub enum TypedPath {
    /// "Open path".
    Open(PathBuf),
    /// "Save to path".
    SaveTo(PathBuf),
}

/// The File menu's typed-path row (for sessions without a file dialog), shared by the curve and the
/// surface screens: a path field with "Open path" and "Save to path"; closes the menu on a click.
pub fn typed_path_ui(ui: &mut egui::Ui, path_input: &mut String, hint: &str, tip: &str) -> Option<TypedPath> {
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
            out = Some(TypedPath::SaveTo(p));
            ui.close();
        }
    });
    out
}

/// The tolerance panel's heading: `Tolerance (mm)` when the file's unit is known.
pub fn tolerance_heading(unit: Option<fairway::io::Unit>) -> String {
    match unit {
        Some(u) => format!("Tolerance ({})", u.symbol()),
        None => "Tolerance".into(),
    }
}

/// The tolerance controls shared by the curve and surface screens: a log
/// slider over [1e-6, 0.05] × the model diagonal `diag` and an exact field
/// (both labelled "Tolerance…" for accessibility). Returns whether `tol` changed.
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
