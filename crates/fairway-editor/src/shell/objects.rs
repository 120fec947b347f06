//! Documents with many objects: every curve and surface of a scene (an IGES / STEP file, a RON
//! document of version 2) is one document. One object is active: its workspace shows, edits and fairs
//! it, the others are drawn dimmed on the canvas. Selecting another object, and "Fair all (keep joins)"
//! (the core's [`fair_network`] on every object), are commands with one undo step each; the objects
//! panel lists the objects and the joins the core measured between them.

use std::path::PathBuf;

use eframe::egui;
use egui::{Color32, RichText};
use fairway::Geometry;
use fairway::fair::network::{NetworkFair, NetworkOptions, fair_network_at_with};
use fairway::io::{Document, Scene, SceneObject};
use fairway::network::Continuity;

use super::{doc_curve, settings_notes};
use crate::history::{Gesture, Snapshot};
use crate::jobs::Job;
use crate::scene_view::{SceneView, ViewPlane, object_label};
use crate::surface_ui::SurfaceWorkspace;
use crate::{App, Command};

/// An unnamed object holding `doc`.
pub(crate) fn unnamed(doc: Document) -> SceneObject {
    SceneObject {
        name: String::new(),
        trim: None,
        geometry: doc.geometry,
        settings: doc.settings,
    }
}

/// What a network fair is computed from ([`App::network_input`]): the key of its background job, compared
/// with the document's state when the result arrives.
#[derive(Debug, Clone, PartialEq)]
pub struct NetworkInput {
    /// Every object of the document (the active one as it is now), with its settings.
    pub objects: Vec<SceneObject>,
    /// The objects faired together (the others are held).
    pub which: Vec<usize>,
    /// Each object's tolerance in effect.
    pub tolerances: Vec<Option<f64>>,
    /// The smallest tolerance of the faired objects (the curve and surface options').
    pub tolerance: f64,
    /// The network fair's options.
    pub options: NetworkOptions,
}

impl NetworkInput {
    /// The objects' geometries, in order.
    pub fn geometries(&self) -> Vec<Geometry> {
        self.objects.iter().map(|o| o.geometry.clone()).collect()
    }

    /// The core's network fair of this input (what the background job runs), stopped early when
    /// `cancel` is set (`fairway::Error::Cancelled`).
    pub fn fair(&self, cancel: &fairway::Cancel) -> fairway::Result<NetworkFair> {
        fair_network_at_with(&self.geometries(), &self.which, &self.options, &self.tolerances, cancel)
    }
}

/// A network fair in the background: the command that asked for it and its input.
#[derive(Debug)]
pub(crate) struct NetworkRequest {
    /// "Fair all" or "Fair checked" (the status line's name).
    pub(crate) what: &'static str,
    /// What it is computed from.
    pub(crate) input: NetworkInput,
}

/// The colour of a join's marker and list entry: G2 green, G1 yellow, G0 red.
pub fn continuity_color(c: Continuity) -> Color32 {
    match c {
        Continuity::G2 => Color32::from_rgb(90, 220, 110),
        Continuity::G1 => Color32::from_rgb(240, 200, 60),
        Continuity::G0 => Color32::from_rgb(240, 90, 70),
    }
}

impl App {
    /// Every object of the document, the active one as it is now.
    pub fn objects_now(&self) -> Vec<SceneObject> {
        let mut o = self.objects.clone();
        if let Some(a) = o.get_mut(self.active) {
            a.geometry = self.doc.geometry.clone();
            a.settings = self.doc.settings.clone();
        }
        o
    }

    /// The document as a scene (what is saved): every object in order with its name, and the unit.
    pub fn scene(&self) -> Scene {
        Scene {
            objects: self.objects_now(),
            unit: self.unit,
            view_plane: self.view_plane,
        }
    }

    /// Replace the open document by the objects of `scene` (the first curve active, else the first
    /// object), with its unit and view plane; `saved` is its state on disk (`None`: never saved). False
    /// (with the error shown) if the active object could not be shown. The history is cleared.
    pub fn set_scene(&mut self, scene: Scene, path: Option<PathBuf>, saved: Option<Scene>) -> bool {
        let mut objects = scene.objects;
        if objects.is_empty() {
            self.error = Some("The document holds no curve or surface".into());
            return false;
        }
        // absolute, so an autosave's source still names the file after a restart elsewhere
        let path = path.map(|p| std::path::absolute(&p).unwrap_or(p));
        let many = objects.len() > 1;
        let mut notes = vec![];
        for (k, o) in objects.iter_mut().enumerate() {
            let mut d = Document {
                geometry: o.geometry.clone(),
                settings: std::mem::take(&mut o.settings),
            };
            let label = object_label(k, &o.name, &o.geometry);
            notes.extend(
                d.sanitize_settings()
                    .into_iter()
                    .map(|n| if many { format!("{label}: {n}") } else { n }),
            );
            o.settings = d.settings;
        }
        let active = objects
            .iter()
            .position(|o| o.geometry.as_curve().is_some())
            .unwrap_or(0);
        let doc = Document {
            geometry: objects[active].geometry.clone(),
            settings: objects[active].settings.clone(),
        };
        let old = (
            std::mem::replace(&mut self.objects, objects),
            self.active,
            self.view_plane,
        );
        (self.active, self.view_plane) = (active, scene.view_plane);
        self.fair_set.clear();
        self.curve_ws.scene = self.scene_view_of(&self.objects.clone(), &doc);
        if let Err(e) = self.open_workspace(&doc, true) {
            (self.objects, self.active, self.view_plane) = old;
            self.refresh_scene_view();
            self.error = Some(format!("Could not open the surface: {e}"));
            return false;
        }
        self.saved = saved;
        self.doc = doc;
        self.path_input = path.as_ref().map(|p| p.display().to_string()).unwrap_or_default();
        self.path = path;
        self.history.clear();
        // a network fair of the document that was open is of no use any more
        self.network_job = None;
        self.unit = scene.unit;
        self.error = settings_notes(notes);
        true
    }

    /// The scene view of `objects` with `doc` as the active one, on the document's view plane.
    fn scene_view_of(&self, objects: &[SceneObject], doc: &Document) -> SceneView {
        let geometries: Vec<Geometry> = objects
            .iter()
            .enumerate()
            .map(|(k, o)| {
                if k == self.active {
                    doc.geometry.clone()
                } else {
                    o.geometry.clone()
                }
            })
            .collect();
        let names: Vec<String> = objects.iter().map(|o| o.name.clone()).collect();
        SceneView::new(&geometries, &names, self.view_plane)
    }

    /// Show `doc` in its workspace: a curve in the curve workspace (the view fitted with `fit`), a
    /// surface in a new surface workspace.
    fn open_workspace(&mut self, doc: &Document, fit: bool) -> Result<(), String> {
        // the surface shading is kept for the next surface and for eframe storage
        if let Some(s) = &self.surface {
            self.curve_ws.curve3d.surface_shading = s.shading;
        }
        self.curve_ws.active_object = self.active;
        match doc_curve(doc) {
            Some(curve) => {
                self.surface = None;
                if fit {
                    self.curve_ws.set_curve(curve);
                } else {
                    self.curve_ws.show_curve(curve);
                }
            }
            None => {
                let mut s =
                    SurfaceWorkspace::new(doc, self.curve_ws.curve3d.surface_shading).map_err(|e| e.to_string())?;
                s.marks = self.curve_ws.scene.marks3d.clone();
                s.trim = self.objects.get(self.active).and_then(|o| o.trim.clone());
                s.set_others(self.other_patches());
                s.set_gate(self.job_gate.clone());
                self.surface = Some(Box::new(s));
            }
        }
        Ok(())
    }

    /// Make object `k` the active one (the current one's edits kept in its entry); true if it changed.
    pub(crate) fn select_object(&mut self, k: usize) -> bool {
        if k == self.active || k >= self.objects.len() {
            return false;
        }
        let objects = self.objects_now();
        let doc = Document {
            geometry: objects[k].geometry.clone(),
            settings: objects[k].settings.clone(),
        };
        let old = self.active;
        self.active = k;
        if let Err(e) = self.open_workspace(&doc, false) {
            self.active = old;
            self.error = Some(format!("Could not show {}: {e}", self.object_name(k)));
            return false;
        }
        self.objects = objects;
        self.doc = doc;
        self.refresh_scene_view();
        self.status = format!("Selected {} (Ctrl+Z to go back)", self.object_name(k));
        true
    }

    /// The document's patches but the active one, with their indices (drawn dimmed in the surface views).
    fn other_patches(&self) -> Vec<(usize, fairway::BSplineSurface)> {
        self.objects
            .iter()
            .enumerate()
            .filter(|&(k, _)| k != self.active)
            .filter_map(|(k, o)| o.geometry.as_surface().map(|s| (k, s.clone())))
            .collect()
    }

    /// The label of object `k` ([`object_label`]).
    pub fn object_name(&self, k: usize) -> String {
        self.objects
            .get(k)
            .map_or(String::new(), |o| object_label(k, &o.name, &o.geometry))
    }

    /// Restore an undo / redo step: the objects, the active one and the fairing options.
    pub(crate) fn restore(&mut self, s: Snapshot) {
        let switched = s.active != self.active || doc_curve(&s.doc).is_some() != self.surface.is_none();
        let geometry_changed = s.doc.geometry != self.doc.geometry;
        (self.doc, self.prefs.fair, self.objects, self.active) = (s.doc, s.fair, s.objects, s.active);
        self.view_plane = s.view_plane;
        if switched {
            let doc = self.doc.clone();
            if let Err(e) = self.open_workspace(&doc, false) {
                self.error = Some(format!("Could not show {}: {e}", self.object_name(self.active)));
            }
        } else {
            let (ws, sh) = self.split();
            ws.document_changed(sh.doc, geometry_changed);
        }
        self.refresh_scene_view();
    }

    /// Rebuild the canvas's view of every object and their joins (after a change of geometry, of the
    /// active object or of the view plane); a new plane redraws the active curve on it.
    pub(crate) fn refresh_scene_view(&mut self) {
        let view = self.scene_view_of(&self.objects, &self.doc);
        let new_frame = view.frame != self.curve_ws.scene.frame;
        let others = self.other_patches();
        if let Some(s) = self.surface.as_mut() {
            s.marks = view.marks3d.clone();
            s.set_others(others);
        }
        self.curve_ws.scene = view;
        self.curve_ws.active_object = self.active;
        if new_frame && self.surface.is_none() {
            let doc = self.doc.clone();
            if let Some(c) = doc_curve(&doc) {
                self.curve_ws.set_curve(c);
            }
        }
    }

    /// Draw 3D curves on plane `p` of the canvas (saved with the document); true if it changed.
    pub(crate) fn set_view_plane(&mut self, p: ViewPlane) -> bool {
        if self.view_plane == p {
            return false;
        }
        self.view_plane = p;
        self.refresh_scene_view();
        self.status = format!("Curves drawn on the {} (Ctrl+Z to undo)", p.name());
        true
    }

    /// The tolerance in effect for object `k`: its own, else the active one's default for the active
    /// object and 1e-3 of the control net's diagonal for the others (as the curve workspace's default).
    fn object_tolerance(&self, k: usize, o: &SceneObject) -> f64 {
        if k == self.active {
            return self.tolerance();
        }
        o.settings.tolerance.unwrap_or_else(|| match &o.geometry {
            Geometry::Curve(c) => {
                let (a, b) = c.control_bounds();
                (b - a).length().max(1e-12) * 1e-3
            }
            // as the surface workspace's default: 1e-3 of the patch's diagonal
            Geometry::Surface(s) => {
                let (a, b) = s.control_bounds();
                (b - a).length().max(1e-12) * 1e-3
            }
        })
    }

    /// Fair every object of the document together keeping their joins (the core's network fair, each at
    /// its own tolerance in effect, objects faired as one at the smallest of theirs): curves joined into
    /// chains, patches sharing edges into strips or grids. It runs in the background
    /// ([`App::fair_objects`]).
    pub(crate) fn fair_all(&mut self) {
        let all: Vec<usize> = (0..self.objects.len()).collect();
        self.fair_objects(&all, "Fair all");
    }

    /// What a network fair of the objects `which` is computed from: every object as it is now, the
    /// tolerances in effect and the options (`None` if `which` names no object).
    pub fn network_input(&self, which: &[usize]) -> Option<NetworkInput> {
        let objects = self.objects_now();
        let which: Vec<usize> = which.iter().copied().filter(|&k| k < objects.len()).collect();
        if which.is_empty() {
            return None;
        }
        let tolerances: Vec<Option<f64>> = objects
            .iter()
            .enumerate()
            .map(|(k, o)| Some(self.object_tolerance(k, o)))
            .collect();
        let tolerance = which
            .iter()
            .filter_map(|&k| tolerances[k])
            .fold(f64::INFINITY, f64::min);
        let options = NetworkOptions {
            curve: crate::fairing::curve_options(tolerance, &self.prefs.fair),
            surface: fairway::fair::surface::SurfaceFairingOptions::default().tolerance(tolerance),
            ..Default::default()
        };
        Some(NetworkInput {
            objects,
            which,
            tolerances,
            tolerance,
            options,
        })
    }

    /// Start fairing the objects `which` together in the background, keeping every join (`what` names
    /// the command in the status line); the others stay bit for bit. The command returns at once; the
    /// result is applied as one undo step when it arrives ([`App::poll_network_fair`]), if the objects
    /// did not change meanwhile. Refused while another network fair runs.
    pub(crate) fn fair_objects(&mut self, which: &[usize], what: &'static str) {
        if let Some(job) = &self.network_job {
            self.status = format!(
                "{what}: {} is still running; wait for it or cancel it in the status bar",
                job.key().what
            );
            return;
        }
        let Some(input) = self.network_input(which) else {
            self.status = format!("{what}: no object to fair (check objects in the Objects panel)");
            return;
        };
        self.status = format!("{what}: fairing {} objects…", input.which.len());
        let run = input.clone();
        let key = NetworkRequest { what, input };
        let gate = self.job_gate.clone();
        self.network_job = Some(Job::spawn(
            key,
            "network fairing",
            self.repaint.as_ref(),
            move |cancel| {
                if let Some(g) = gate {
                    g.pass();
                }
                run.fair(cancel)
            },
        ));
    }

    /// Whether a network fair ("Fair all", "Fair checked") runs in the background, and since when.
    pub fn network_fair_running(&self) -> Option<(&'static str, std::time::Duration)> {
        self.network_job.as_ref().map(|j| (j.key().what, j.elapsed()))
    }

    /// Drop the running network fair: dropping the job sets its cancel token, so the core stops at its
    /// next checkpoint (before the next curve chain, isocurve block or smoother attempt), and the document
    /// is unchanged.
    pub fn cancel_network_fair(&mut self) {
        if let Some(job) = self.network_job.take() {
            self.status = format!("{}: cancelled; the document is unchanged", job.key().what);
        }
    }

    /// Take the network fair's result if it has finished: applied as one undo step if the objects
    /// (and the tolerances and options they are faired with) are still those it was started from, else
    /// discarded with a note in the status line. True if it finished.
    pub(crate) fn poll_network_fair(&mut self) -> bool {
        let Some(res) = self.network_job.as_mut().and_then(Job::poll) else {
            return false;
        };
        let Some(job) = self.network_job.take() else {
            return false;
        };
        let NetworkRequest { what, input } = job.into_key();
        match res {
            Err(e) => self.error = Some(format!("{what}: {e}")),
            Ok(_) if self.network_input(&input.which).as_ref() != Some(&input) => {
                self.status = format!("{what}: the objects changed while fairing; run it again");
            }
            Ok(r) => self.apply_network_fair(what, input, &r),
        }
        true
    }

    /// Apply the network fair `r` of `input` (the document's state now) as one undo step. Faired
    /// objects lose their region and hand-edited target (they belong to the old geometry).
    fn apply_network_fair(&mut self, what: &str, input: NetworkInput, r: &NetworkFair) {
        let before = self.snapshot();
        let mut objects = input.objects;
        let mut changed = 0;
        for (k, (o, g)) in objects.iter_mut().zip(r.objects.iter().cloned()).enumerate() {
            if o.geometry != g {
                changed += 1;
                o.geometry = g;
                o.settings.region = None;
                o.settings.target = None;
                o.settings.pinned.clear();
                o.settings.target_params = None;
                if k == self.active {
                    self.doc.geometry = o.geometry.clone();
                    self.doc.settings = o.settings.clone();
                }
            }
        }
        self.status = fair_summary(what, r, changed, input.which.len(), input.tolerance);
        if changed == 0 {
            return;
        }
        self.objects = objects;
        let (ws, sh) = self.split();
        ws.document_changed(sh.doc, true);
        self.refresh_scene_view();
        self.history.record(before, Gesture::Single);
    }

    /// The objects panel (left; documents with several objects): the objects (a click selects), "Fair
    /// all (keep joins)" and the joins with their continuity (hover: the measures).
    pub(crate) fn objects_panel_ui(&mut self, ui: &mut egui::Ui) {
        if self.objects.len() < 2 {
            return;
        }
        egui::Panel::left("objects")
            .resizable(true)
            .default_size(210.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    self.object_list_ui(ui);
                    ui.separator();
                    self.joins_list_ui(ui);
                });
            });
    }

    fn object_list_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Objects");
        for k in 0..self.objects.len() {
            let o = &self.objects[k];
            let text = format!("{}. {}", k + 1, object_label(k, &o.name, &o.geometry));
            let tip = crate::interchange::describe_object(&o.geometry, None);
            let mut checked = self.fair_set.contains(&k);
            let (check, select) = ui
                .horizontal(|ui| {
                    let check = ui
                        .checkbox(&mut checked, "")
                        .on_hover_text("In the set that \"Fair checked\" fairs together");
                    let select = ui
                        .selectable_label(k == self.active, text)
                        .on_hover_text(format!("{tip}; click to edit and fair it"));
                    (check.changed(), select.clicked())
                })
                .inner;
            if check {
                if checked {
                    self.fair_set.insert(k);
                } else {
                    self.fair_set.remove(&k);
                }
            }
            if select {
                self.push(Command::Select(k));
            }
        }
        ui.add_space(4.0);
        let idle = self.network_job.is_none();
        let busy = "A network fair is running: wait for it or cancel it in the status bar";
        if ui
            .add_enabled(idle, egui::Button::new("Fair all (keep joins)"))
            .on_disabled_hover_text(busy)
            .on_hover_text(
                "Fair every object together: curves meeting with G1/G2, and patches sharing G1/G2 edges in a strip \
                 or a grid, are faired as one and split back, so each join keeps its continuity; each object \
                 stays within its own tolerance (one undo step)",
            )
            .clicked()
        {
            self.push(Command::FairAll);
        }
        let set: Vec<usize> = self
            .fair_set
            .iter()
            .copied()
            .filter(|&k| k < self.objects.len())
            .collect();
        if ui
            .add_enabled(
                idle && !set.is_empty(),
                egui::Button::new(format!("Fair checked ({}, keep joins)", set.len())),
            )
            .on_hover_text(
                "Fair the checked objects together, as Fair all does; the others stay as they are and their joins \
                 with the checked ones are held (one undo step)",
            )
            .on_disabled_hover_text(if idle {
                "Check objects in the list to fair them together"
            } else {
                busy
            })
            .clicked()
        {
            self.push(Command::FairSet(set));
        }
    }

    fn joins_list_ui(&mut self, ui: &mut egui::Ui) {
        let view = &self.curve_ws.scene;
        ui.heading(format!("Joins ({})", view.joins.len() + view.measured.surfaces.len()));
        if view.joins.is_empty() && view.measured.surfaces.is_empty() {
            ui.weak("No curve ends meet and no patches share an edge");
        }
        for j in &view.joins {
            ui.label(RichText::new(&j.label).color(continuity_color(j.class)))
                .on_hover_text(&j.detail);
        }
        for s in &view.measured.surfaces {
            let c = &s.continuity;
            let text = format!(
                "{} edge: {} {:?} – {} {:?}",
                c.class.name(),
                self.object_name(s.a.0),
                s.a.1,
                self.object_name(s.b.0),
                s.b.1
            );
            ui.label(RichText::new(text).color(continuity_color(c.class)))
                .on_hover_text(format!(
                    "{}: gap {:.2e}, normal angle {:.4}°, normal curvature jump {:.2e}",
                    c.class.name(),
                    c.gap,
                    c.normal_angle.to_degrees(),
                    c.curvature_jump
                ));
        }
    }
}

/// The status line after "Fair all".
fn fair_summary(
    what: &str,
    r: &fairway::fair::network::NetworkFair,
    changed: usize,
    objects: usize,
    tol: f64,
) -> String {
    let (b, a) = (&r.joins_before, &r.joins_after);
    let kept = b
        .curves
        .iter()
        .zip(&a.curves)
        .filter(|(x, y)| y.continuity.class >= x.continuity.class)
        .count()
        + b.surfaces
            .iter()
            .zip(&a.surfaces)
            .filter(|(x, y)| y.continuity.class >= x.continuity.class)
            .count();
    let dev = r.outcome.iter().map(|o| o.max_deviation).fold(0.0, f64::max);
    // how many objects each route took ("layout ×3, alone ×1")
    let mut routes: Vec<(&str, usize)> = vec![];
    for o in r.outcome.iter().filter(|o| o.faired) {
        match routes.iter_mut().find(|(n, _)| *n == o.route.name()) {
            Some(x) => x.1 += 1,
            None => routes.push((o.route.name(), 1)),
        }
    }
    let routes: Vec<String> = routes.iter().map(|(n, c)| format!("{n} ×{c}")).collect();
    format!(
        "{what}: {changed} of {objects} objects changed (each within its own tolerance, the smallest {tol:.3e}; max \
         deviation {dev:.3e}; routes: {}); {kept} of {} joins keep their continuity (Ctrl+Z to undo)",
        routes.join(", "),
        b.curves.len() + b.surfaces.len()
    )
}
