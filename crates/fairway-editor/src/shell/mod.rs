//! The shell: one [`App`] owns the document, its file, the undo history, the status line, the
//! title, the menus and the shortcuts, with the workspace of the open document behind
//! [`Workspace`]: the curve workspace ([`CurveWorkspace`]) or the surface workspace
//! ([`SurfaceWorkspace`]). One frame: shortcuts, menu bar, status bar, the workspace's panels and
//! view, then the queued commands ([`crate::commands`]), then the workspace's previews.

mod file;
mod objects;
mod ui;

use std::path::{Path, PathBuf};

use eframe::egui;
use fairway::fair::network::NetworkFair;
use fairway::io::{Document, SceneObject};
use fairway::{BSplineCurve, Geometry};

use crate::curve_ws::CurveWorkspace;
use crate::history::History;
use crate::jobs::Job;
use crate::scene_view::ViewPlane;
use crate::surface_ui::SurfaceWorkspace;
use crate::workspace::{ShellCx, Workspace};
use crate::{Bench, Command, Pending, Prefs, interchange, view3d};

pub use file::dialog_available;
pub(crate) use file::is_plain_document;
pub use objects::{NetworkInput, continuity_color};

/// The editor.
pub struct App {
    /// The active object of the open document (a curve or a surface): the one its workspace shows,
    /// edits and fairs.
    pub doc: Document,
    /// Every object of the document in file order, with its name and own settings; the active one's
    /// entry is brought up to date from `doc` when another is selected ([`App::objects_now`] is
    /// always current).
    pub objects: Vec<SceneObject>,
    /// The index of the active object in `objects`.
    pub active: usize,
    /// The objects checked in the objects panel, which "Fair checked" fairs together (cleared when
    /// another document opens).
    pub fair_set: std::collections::BTreeSet<usize>,
    /// The plane 3D curves are drawn on in the 2D canvas (saved with the document; XY if it saves none).
    pub view_plane: ViewPlane,
    /// Where the document lives on disk.
    pub path: Option<PathBuf>,
    /// The document (its objects and view plane) as last saved or opened (for the unsaved marker);
    /// `None`: never saved (a restored autosave).
    saved: Option<fairway::io::Scene>,
    /// Undo history (of both workspaces).
    pub history: History,
    /// Persisted settings.
    pub prefs: Prefs,
    /// The curve workspace (shown while the document holds a curve).
    pub curve_ws: CurveWorkspace,
    /// The surface workspace, while the document holds a surface.
    pub surface: Option<Box<SurfaceWorkspace>>,
    /// Commands queued this frame.
    pub(crate) commands: Vec<Command>,
    /// Last error, shown until dismissed.
    pub error: Option<String>,
    /// Status line message.
    pub status: String,
    /// The path field (fallback when no file dialog is available).
    pub path_input: String,
    /// Waiting for the user to confirm discarding unsaved work.
    pub confirm: Option<Pending>,
    /// The keyboard shortcuts overlay is open.
    pub show_help: bool,
    allow_close: bool,
    last_title: String,
    /// CPU time of the last frames' `show` (ms), for the status bar.
    pub frame_ms: f64,
    /// Benchmark mode: sweep the tolerance every frame and report timings.
    pub bench: Option<Bench>,
    /// Periodic autosave (`None`: off, as in tests that do not ask for it).
    pub autosave: Option<crate::autosave::Autosave>,
    /// This session wrote the autosave that is on disk.
    pub(crate) autosaved: bool,
    /// An autosave found at start-up, waiting for Restore / Discard.
    pub recovery: Option<crate::autosave::Recovery>,
    /// An IGES or STEP file with several objects, waiting for the user's choice.
    pub object_pick: Option<interchange::ObjectPick>,
    /// The length unit of the document's file (IGES / STEP), shown in the status bar and the
    /// tolerance heading and declared when saving as IGES or STEP; `None`: unitless (saved as mm).
    pub unit: Option<fairway::io::Unit>,
    /// A PNG export in progress (waiting for the screenshot).
    pub png_export: Option<interchange::PngExport>,
    /// The central panel's content area (canvas or 3D view) of the last frame, in points.
    pub view_rect: egui::Rect,
    /// `--export-png`: export the view, then quit.
    pub(crate) export_then_quit: Option<interchange::ExportThenQuit>,
    /// "Fair all" / "Fair checked" running in the background ([`App::fair_objects`]).
    pub(crate) network_job: Option<Job<objects::NetworkRequest, NetworkFair>>,
    /// The egui context of the last frame: background jobs ask it for a repaint when they finish.
    pub(crate) repaint: Option<egui::Context>,
    /// Tests: the gate every background job waits at before it computes ([`App::set_job_gate`]).
    pub(crate) job_gate: Option<crate::jobs::Gate>,
}

impl Default for App {
    fn default() -> Self {
        Self::with_document(Document::new(Geometry::Curve(crate::demo_curve())), None)
    }
}

impl App {
    /// An editor showing `doc` (a curve; a surface document opens the demo curve), loaded from
    /// `path`.
    pub fn with_document(doc: Document, path: Option<PathBuf>) -> Self {
        let saved = match &doc.geometry {
            Geometry::Curve(_) => doc,
            Geometry::Surface(_) => Document::new(Geometry::Curve(crate::demo_curve())),
        };
        // settings that do not fit the curve are dropped and said; the document then shows as changed
        let mut doc = saved.clone();
        let error = settings_notes(doc.sanitize_settings());
        let mut app = Self {
            curve_ws: CurveWorkspace::new(doc_curve(&doc).expect("a curve document")),
            saved: Some(saved.into()),
            objects: vec![objects::unnamed(doc.clone())],
            active: 0,
            fair_set: Default::default(),
            view_plane: ViewPlane::Xy,
            doc,
            path: path.clone(),
            history: History::default(),
            prefs: Prefs::default(),
            surface: None,
            commands: vec![],
            error,
            status: String::new(),
            path_input: path.map(|p| p.display().to_string()).unwrap_or_default(),
            confirm: None,
            show_help: false,
            allow_close: false,
            last_title: String::new(),
            frame_ms: 0.0,
            bench: None,
            autosave: None,
            autosaved: false,
            recovery: None,
            object_pick: None,
            unit: None,
            png_export: None,
            view_rect: egui::Rect::NOTHING,
            export_then_quit: None,
            network_job: None,
            repaint: None,
            job_gate: None,
        };
        app.refresh_scene_view();
        app
    }

    /// Open `path` in a new editor; on error, the demo curve and the error message.
    pub fn open_or_demo(path: Option<&Path>) -> Self {
        let mut app = Self::default();
        if let Some(p) = path {
            app.open_now(p);
        }
        app
    }

    /// The editor for eframe: settings restored from storage, `path` opened.
    pub fn new(cc: &eframe::CreationContext<'_>, path: Option<&Path>) -> Self {
        view3d::install(cc);
        let mut app = Self::open_or_demo(path).with_default_autosave();
        if let Some(storage) = cc.storage {
            app.load_view3d_prefs(storage);
            app.load_prefs(storage);
        }
        app
    }

    /// Restore the settings (comb, toggles, recent files, fairing options) saved by
    /// [`eframe::App::save`]; the file opened at start stays first in the recent list. Unreadable
    /// settings change nothing; out-of-range values (a hand-edited store) are clamped.
    pub fn load_prefs(&mut self, storage: &dyn eframe::Storage) {
        let Some(prefs) = eframe::get_value::<Prefs>(storage, "prefs") else {
            return;
        };
        let recent = std::mem::take(&mut self.prefs.recent);
        self.prefs = prefs.sanitized();
        for r in recent.into_iter().rev() {
            self.push_recent(r);
        }
    }

    /// The document's curve (panics while a surface is open).
    pub fn curve(&self) -> &BSplineCurve {
        doc_curve(&self.doc).expect("the document holds a curve")
    }

    /// The open workspace.
    pub fn workspace(&mut self) -> &mut dyn Workspace {
        match self.surface.as_deref_mut() {
            Some(s) => s,
            None => &mut self.curve_ws,
        }
    }

    /// The open workspace and what the shell lends it for a frame.
    pub(crate) fn split(&mut self) -> (&mut dyn Workspace, ShellCx<'_>) {
        let ws: &mut dyn Workspace = match self.surface.as_deref_mut() {
            Some(s) => s,
            None => &mut self.curve_ws,
        };
        let sh = ShellCx {
            doc: &self.doc,
            prefs: &mut self.prefs,
            commands: &mut self.commands,
            status: &mut self.status,
            error: &mut self.error,
            unit: self.unit,
        };
        (ws, sh)
    }

    /// Whether the document differs from the saved file.
    pub fn is_dirty(&self) -> bool {
        let Some(saved) = &self.saved else { return true };
        saved.view_plane != self.view_plane
            || saved.objects.len() != self.objects.len()
            || saved.objects.iter().zip(&self.objects).enumerate().any(|(k, (s, o))| {
                if k == self.active {
                    s.geometry != self.doc.geometry || s.settings != self.doc.settings
                } else {
                    s != o
                }
            })
    }

    /// The tolerance in effect (document value or a default from the size).
    pub fn tolerance(&self) -> f64 {
        let default = match &self.surface {
            Some(s) => s.default_tolerance(),
            None => self.curve_ws.default_tolerance(),
        };
        self.doc.settings.tolerance.unwrap_or(default)
    }

    /// The curve region `[u1, u2]`, if one is selected (`u1 > u2`: across the seam of a closed curve).
    pub fn region(&self) -> Option<(f64, f64)> {
        self.doc.settings.region
    }

    /// The end conditions of the curve region: the document's, else the default of the preferences.
    pub fn ends(&self) -> [fairway::fair::EndCondition; 2] {
        self.doc.settings.ends.unwrap_or(self.prefs.fair.ends)
    }

    /// Draw the whole editor into `ui` and apply the frame's commands.
    pub fn show(&mut self, ui: &mut egui::Ui) {
        self.repaint = Some(ui.ctx().clone());
        if self.poll_network_fair() {
            ui.ctx().request_repaint();
        }
        self.recovery_ui(ui);
        self.object_picker_ui(ui);
        self.shortcuts(ui);
        self.dropped_files(ui);
        egui::Panel::top("menu").show(ui, |ui| self.menu_ui(ui));
        egui::Panel::bottom("status").show(ui, |ui| self.status_ui(ui));
        self.objects_panel_ui(ui);
        let (ws, mut sh) = self.split();
        ws.panels_ui(ui, &mut sh);
        let mut rect = egui::Rect::NOTHING;
        egui::CentralPanel::default().show(ui, |ui| {
            rect = ui.max_rect();
            ws.canvas_ui(ui, &mut sh);
        });
        self.view_rect = rect;
        self.help_ui(ui);
        self.confirm_ui(ui);
        self.apply_commands();
        let (ws, mut sh) = self.split();
        ws.after_commands(ui, &mut sh);
        // commands pushed by the previews (none today) wait for the next frame
        if !ui.input(|i| i.pointer.any_down()) {
            self.history.end_gesture();
        }
        let title = self.title();
        if title != self.last_title {
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.last_title = title;
        }
        self.after_frame(ui);
    }

    /// Whether a background job runs: a network fair, or the surface preview's full fair or draft.
    pub fn is_computing(&self) -> bool {
        self.network_job.is_some() || (self.surface.as_ref()).is_some_and(|s| s.is_fairing() || s.is_drafting())
    }

    /// Tests: every background job started from now on (network fair, surface fair and draft, also in a
    /// surface workspace opened later) waits at `gate` before it computes, so a test holds a job running
    /// deterministically; `None` removes the gate. Open the gate before waiting for the jobs.
    pub fn set_job_gate(&mut self, gate: Option<crate::jobs::Gate>) {
        if let Some(s) = self.surface.as_mut() {
            s.set_gate(gate.clone());
        }
        self.job_gate = gate;
    }

    /// A watch on the running network fair's thread (tests: a cancelled fair ends `Cancelled`).
    pub fn watch_network_fair(&self) -> Option<crate::jobs::JobWatch> {
        self.network_job.as_ref().map(Job::watch)
    }

    /// Block until every background job has its result; the next frame takes it (as when the job
    /// ends on its own). For tests and scripts that need a deterministic point: the UI never waits.
    pub fn wait_for_jobs(&mut self) {
        if let Some(j) = self.network_job.as_mut() {
            j.wait();
        }
        if let Some(s) = self.surface.as_mut() {
            s.wait_for_job();
        }
    }

    /// [`App::wait_for_jobs`], then take the results now, as the next frame would: after a frame, the
    /// state is then what the synchronous computation gave (the test harness calls it after each
    /// frame).
    pub fn finish_jobs(&mut self) {
        if let Some(j) = self.network_job.as_mut() {
            j.wait();
        }
        self.poll_network_fair();
        if let Some(s) = self.surface.as_mut() {
            s.finish_job(&self.doc);
        }
    }

    /// Show an error in the status bar (until dismissed).
    pub fn report_error(&mut self, msg: String) {
        self.error = Some(msg);
    }

    /// Show a status message.
    pub fn report_status(&mut self, msg: String) {
        self.status = msg;
    }

    /// Let the next close request through without asking about unsaved work.
    pub(crate) fn allow_close(&mut self) {
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

/// The curve of a curve document.
pub(crate) fn doc_curve(doc: &Document) -> Option<&BSplineCurve> {
    match &doc.geometry {
        Geometry::Curve(c) => Some(c),
        Geometry::Surface(_) => None,
    }
}
