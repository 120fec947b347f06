//! The surface workspace: a 3D view of the document's surface with the
//! interrogation modes, a uv-domain mini view to pick the fairing region
//! (or Ctrl+drag on the surface), a tolerance slider with live preview by the
//! core's `fair_surface`, compare (toggle, blend, side by side), measures,
//! accept / undo / redo and open / save. Same app model as the curve
//! editor: panels queue [`SurfCommand`]s, applied after the panels, one undo
//! step per gesture.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use eframe::egui;
use egui::{Color32, Pos2, Rect, RichText, Sense, Stroke};
use fairway::fair::surface::{SurfaceFairingOptions, SurfaceMethod, fair_surface};
use fairway::io::Document;
use fairway::measure_surface::{SurfaceMeasures, surface_measures};
use fairway::{BSplineSurface, DVec2, DVec3, Geometry};

use crate::history::{Gesture, History};
use crate::view3d::scene::{effective_range, mode_values, surface_scene};
use crate::view3d::{self, ShadeMode, Shading, View3d};
use fairway::mesh::{SurfaceMesh, pick_uv};

/// A uv rectangle `((u1, u2), (v1, v2))`.
pub type UvRect = ((f64, f64), (f64, f64));

/// A user action of the surface workspace.
#[derive(Debug, Clone)]
pub enum SurfCommand {
    /// Set or clear the uv region.
    SetRegion(Option<UvRect>),
    /// Set the tolerance.
    SetTolerance(f64),
    /// Replace the surface by the preview (one undo step).
    Accept,
    /// Undo.
    Undo,
    /// Redo.
    Redo,
    /// Open a file (surface here; a curve switches to the curve editor).
    Open(PathBuf),
    /// Save to a file.
    SaveTo(PathBuf),
}

/// Compare settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfCompare {
    /// Show the faired preview (Space toggles); else the original.
    pub show_after: bool,
    /// Blend original (0) → faired (1) when showing the preview.
    pub blend: f64,
    /// Before and after side by side.
    pub side_by_side: bool,
}

impl Default for SurfCompare {
    fn default() -> Self {
        Self {
            show_after: true,
            blend: 1.0,
            side_by_side: false,
        }
    }
}

/// The live fairing result.
#[derive(Debug, Clone)]
pub struct SurfacePreview {
    /// The faired surface.
    pub surface: BSplineSurface,
    /// Its tessellation.
    pub mesh: SurfaceMesh,
    /// Verified max deviation from the original.
    pub max_deviation: f64,
    /// The sound bound of the deviation everywhere (`SurfaceFairingResult::band_bound`).
    pub band_bound: Option<f64>,
    /// Tightening rounds used.
    pub rounds: usize,
    /// Partial step factor.
    pub alpha: f64,
    /// Wall time of `fair_surface` (ms).
    pub fair_ms: f64,
    /// What the fair did besides the plain method (`SurfaceFairingResult::notes`: C0 knot lines kept,
    /// tiles held).
    pub notes: Vec<String>,
    /// Measures against the original (computed when the pointer is up).
    pub measures: Option<SurfaceMeasures>,
    /// Computed while a drag was in progress with one isocurve tolerance level (`iso_levels: 1`,
    /// about 3× faster); recomputed with the default levels when the pointer is released.
    pub draft: bool,
    key: PreviewKey,
}

type PreviewKey = (u64, Option<UvRect>, u64, usize);

/// Cached scene of one view.
struct SceneCache {
    key: (u64, u64, Shading, u64, Option<UvRect>),
    scene: Arc<view3d::Scene>,
}

/// The surface workspace.
pub struct SurfaceEditor {
    /// The document (its geometry is a surface).
    pub doc: Document,
    /// Where it lives on disk.
    pub path: Option<PathBuf>,
    /// The length unit of its file (IGES / STEP), shown beside lengths and declared when saving as IGES
    /// or STEP; `None`: unitless (saved as mm).
    pub unit: Option<fairway::io::Unit>,
    saved: Option<Document>,
    /// Undo history.
    pub history: History,
    /// Bumped when the surface changes.
    pub rev: u64,
    /// Tessellation of the document's surface.
    pub mesh: SurfaceMesh,
    /// Shading settings.
    pub shading: Shading,
    /// Camera.
    pub view: View3d,
    /// Live preview on/off.
    pub live: bool,
    /// The current preview.
    pub preview: Option<SurfacePreview>,
    /// Why the last preview failed.
    pub preview_error: Option<String>,
    /// Compare settings.
    pub compare: SurfCompare,
    /// Measures of the original (against itself), per `rev`.
    pub measures_before: Option<(u64, SurfaceMeasures)>,
    /// Last error.
    pub error: Option<String>,
    /// Status message.
    pub status: String,
    /// Path field.
    pub path_input: String,
    /// A file for the app to open: a curve (the app switches back to the
    /// curve editor) or an IGES or STEP file (which may need the object picker).
    pub open_curve: Option<PathBuf>,
    commands: Vec<SurfCommand>,
    uv_drag: Option<DVec2>,
    pick_drag: Option<DVec2>,
    blend_cache: Option<((u64, u64), BSplineSurface, SurfaceMesh)>,
    scenes: [Option<SceneCache>; 2],
    hover: Option<(DVec2, f64)>,
    last_title: String,
}

fn surface_of(doc: &Document) -> Option<&BSplineSurface> {
    match &doc.geometry {
        Geometry::Surface(s) => Some(s),
        Geometry::Curve(_) => None,
    }
}

fn points_hash(s: &BSplineSurface) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for p in s.points() {
        p.x.to_bits().hash(&mut h);
        p.y.to_bits().hash(&mut h);
        p.z.to_bits().hash(&mut h);
    }
    h.finish()
}

impl SurfaceEditor {
    /// A workspace for `doc`, which must hold a surface.
    pub fn new(doc: Document, path: Option<PathBuf>) -> anyhow::Result<Self> {
        let s = surface_of(&doc).ok_or_else(|| anyhow::anyhow!("the document holds a curve, not a surface"))?;
        let shading = Shading::default();
        let mesh = SurfaceMesh::tessellate(s, shading.density, shading.density)?;
        let mut view = View3d::default();
        view.set_bbox(bbox_of(&mesh), true);
        // settings that do not fit the surface are dropped and said; the document then shows as changed
        let saved = doc.clone();
        let mut doc = doc;
        let error = crate::settings_notes(doc.sanitize_settings());
        Ok(Self {
            saved: Some(saved),
            path_input: path.as_ref().map(|p| p.display().to_string()).unwrap_or_default(),
            path,
            unit: None,
            doc,
            history: History::default(),
            rev: 1,
            mesh,
            shading,
            view,
            live: true,
            preview: None,
            preview_error: None,
            compare: SurfCompare::default(),
            measures_before: None,
            error,
            status: String::new(),
            open_curve: None,
            commands: vec![],
            uv_drag: None,
            pick_drag: None,
            blend_cache: None,
            scenes: [None, None],
            hover: None,
            last_title: String::new(),
        })
    }

    /// Replace the shading settings ([`Shading::sanitized`]); a new mesh
    /// density re-tessellates the surface.
    pub fn set_shading(&mut self, shading: Shading) {
        let shading = shading.sanitized();
        let retessellate = shading.density != self.shading.density;
        self.shading = shading;
        if retessellate {
            self.set_surface_changed();
        }
    }

    /// Load a surface document from `path`.
    pub fn open(path: &Path) -> anyhow::Result<Self> {
        let doc = fairway::io::load(path)?;
        Self::new(doc, Some(path.to_path_buf()))
    }

    /// The document's surface.
    pub fn surface(&self) -> &BSplineSurface {
        surface_of(&self.doc).expect("the surface workspace holds a surface")
    }

    /// The uv region, if any.
    pub fn region(&self) -> Option<UvRect> {
        self.doc.settings.region_uv
    }

    /// Diagonal of the surface's bounding box.
    pub fn diag(&self) -> f64 {
        let (a, b) = self.view.bbox;
        (b - a).length().max(1e-12)
    }

    /// The tolerance in effect.
    pub fn tolerance(&self) -> f64 {
        self.doc.settings.tolerance.unwrap_or(self.diag() * 1e-3)
    }

    /// Whether the document differs from the saved file.
    pub fn is_dirty(&self) -> bool {
        self.saved.as_ref() != Some(&self.doc)
    }

    /// Set the document's state on disk (`None`: never saved, shows as unsaved).
    pub fn set_saved(&mut self, saved: Option<Document>) {
        self.saved = saved;
    }

    /// Queue a command.
    pub fn push(&mut self, c: SurfCommand) {
        self.commands.push(c);
    }

    fn set_surface_changed(&mut self) {
        self.rev += 1;
        let s = self.surface().clone();
        match SurfaceMesh::tessellate(&s, self.shading.density, self.shading.density) {
            Ok(m) => self.mesh = m,
            Err(e) => self.error = Some(format!("tessellation failed: {e}")),
        }
        self.view.set_bbox(bbox_of(&self.mesh), false);
        self.preview = None;
    }

    /// Apply one command now.
    pub fn apply(&mut self, c: SurfCommand) {
        match c {
            SurfCommand::SetRegion(r) => {
                let r = r.map(|((a, b), (c, d))| ((a.min(b), a.max(b)), (c.min(d), c.max(d))));
                if self.doc.settings.region_uv != r {
                    self.history.record(&self.doc, Gesture::Region);
                    self.doc.settings.region_uv = r;
                }
            }
            SurfCommand::SetTolerance(t) => {
                if t.is_finite() && t > 0.0 && self.doc.settings.tolerance != Some(t) {
                    self.history.record(&self.doc, Gesture::Tolerance);
                    self.doc.settings.tolerance = Some(t);
                }
            }
            SurfCommand::Accept => {
                if let Some(p) = self.preview.take() {
                    self.history.record(&self.doc, Gesture::Single);
                    self.doc.geometry = Geometry::Surface(p.surface);
                    self.doc.settings.region_uv = None;
                    self.set_surface_changed();
                    self.status = format!("Accepted (max deviation {:.3e})", p.max_deviation);
                }
            }
            SurfCommand::Undo => {
                if let Some(d) = self.history.undo(&self.doc) {
                    self.set_doc(d);
                    self.status = "Undone".into();
                }
            }
            SurfCommand::Redo => {
                if let Some(d) = self.history.redo(&self.doc) {
                    self.set_doc(d);
                    self.status = "Redone".into();
                }
            }
            SurfCommand::Open(p) => self.open_now(&p),
            SurfCommand::SaveTo(p) => match fairway::io::save_in(&p, &self.doc, self.unit) {
                Ok(()) => {
                    self.saved = Some(self.doc.clone());
                    self.path_input = p.display().to_string();
                    self.status = format!("Saved {}", p.display());
                    self.path = Some(p);
                }
                Err(e) => self.error = Some(format!("Could not save {}: {e}", p.display())),
            },
        }
    }

    fn set_doc(&mut self, d: Document) {
        let changed = surface_of(&d).map(points_hash) != Some(points_hash(self.surface()));
        self.doc = d;
        if changed {
            self.set_surface_changed();
        }
    }

    fn open_now(&mut self, p: &Path) {
        if crate::interchange::is_interchange(p) {
            self.open_curve = Some(p.to_path_buf());
            return;
        }
        match fairway::io::load(p) {
            Ok(doc) if surface_of(&doc).is_some() => match Self::new(doc, Some(p.to_path_buf())) {
                Ok(mut s) => {
                    s.set_shading(self.shading);
                    s.status = format!("Opened {}", p.display());
                    *self = s;
                }
                Err(e) => self.error = Some(format!("Could not open {}: {e}", p.display())),
            },
            Ok(_) => self.open_curve = Some(p.to_path_buf()),
            Err(e) => self.error = Some(format!("Could not open {}: {e}", p.display())),
        }
    }

    /// Apply the queued commands.
    pub fn apply_commands(&mut self) {
        for c in std::mem::take(&mut self.commands) {
            self.apply(c);
        }
    }

    /// Bring the preview up to date; true if it was recomputed.
    pub fn update_preview(&mut self, pointer_down: bool) -> bool {
        let Some(region) = self.region() else {
            self.preview = None;
            self.preview_error = None;
            return false;
        };
        if !self.live {
            return false;
        }
        let tol = self.tolerance();
        let key = (self.rev, Some(region), tol.to_bits(), self.shading.density);
        let mut changed = false;
        let stale = match self.preview.as_ref() {
            Some(p) => p.key != key || (p.draft && !pointer_down),
            None => true,
        };
        if stale {
            changed = true;
            let draft = pointer_down;
            let opts = SurfaceFairingOptions {
                region: Some(region),
                tolerance: tol,
                // while dragging: one isocurve tolerance level, the live-preview setting of the core
                iso_levels: if draft {
                    1
                } else {
                    SurfaceFairingOptions::default().iso_levels
                },
                // while dragging: the isocurve fairing alone (the step-8 choice among the reference smoother's
                // candidates costs 8-15 × as much); on release the default
                method: if draft {
                    SurfaceMethod::Isocurves
                } else {
                    SurfaceMethod::default()
                },
                ..Default::default()
            };
            let t0 = Instant::now();
            // a panic in the engine becomes an error message; the document is untouched
            let res = crate::guard::catch_panic("surface fairing", || fair_surface(self.surface(), opts));
            let fair_ms = t0.elapsed().as_secs_f64() * 1e3;
            match res.and_then(|r| {
                let n = self.shading.density;
                SurfaceMesh::tessellate(&r.surface, n, n).map(|m| (r, m))
            }) {
                Ok((r, mesh)) => {
                    self.preview = Some(SurfacePreview {
                        surface: r.surface,
                        mesh,
                        max_deviation: r.max_deviation,
                        band_bound: r.band_bound,
                        rounds: r.rounds,
                        alpha: r.alpha,
                        fair_ms,
                        notes: r.notes,
                        measures: None,
                        key,
                        draft,
                    });
                    self.preview_error = None;
                }
                Err(e) => {
                    self.preview = None;
                    self.preview_error = Some(e.to_string());
                }
            }
        }
        if !pointer_down {
            if let Some(p) = self.preview.as_mut()
                && p.measures.is_none()
            {
                p.measures = Some(surface_measures(surface_of(&self.doc).unwrap(), &p.surface));
                changed = true;
            }
            if self.measures_before.as_ref().map(|m| m.0) != Some(self.rev) {
                let m = surface_measures(self.surface(), self.surface());
                self.measures_before = Some((self.rev, m));
                changed = true;
            }
        }
        changed
    }

    /// Window title.
    pub fn title(&self) -> String {
        let name = self
            .path
            .as_ref()
            .and_then(|p| p.file_name())
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "untitled".into());
        format!("{}{name} — Fairway (surface)", if self.is_dirty() { "* " } else { "" })
    }

    /// Draw the workspace and apply the frame's commands.
    pub fn show(&mut self, ui: &mut egui::Ui) {
        self.shortcuts(ui);
        egui::Panel::top("surf_menu").show(ui, |ui| self.menu_ui(ui));
        egui::Panel::bottom("surf_status").show(ui, |ui| self.status_ui(ui));
        egui::Panel::right("surf_controls")
            .resizable(true)
            .default_size(300.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.controls_ui(ui));
            });
        egui::CentralPanel::default().show(ui, |ui| self.views_ui(ui));
        self.apply_commands();
        let down = ui.input(|i| i.pointer.any_down());
        if self.update_preview(down) {
            ui.ctx().request_repaint();
        }
        if !down {
            self.history.end_gesture();
        }
        let title = self.title();
        if title != self.last_title {
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.last_title = title;
        }
    }

    fn shortcuts(&mut self, ui: &egui::Ui) {
        use egui::{Key, KeyboardShortcut, Modifiers};
        let sc = |m, k| KeyboardShortcut::new(m, k);
        let (redo, undo, save) = ui.input_mut(|i| {
            let redo = i.consume_shortcut(&sc(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z))
                || i.consume_shortcut(&sc(Modifiers::COMMAND, Key::Y));
            let undo = i.consume_shortcut(&sc(Modifiers::COMMAND, Key::Z));
            let save = i.consume_shortcut(&sc(Modifiers::COMMAND, Key::S));
            (redo, undo, save)
        });
        if redo {
            self.push(SurfCommand::Redo);
        } else if undo {
            self.push(SurfCommand::Undo);
        }
        if save && let Some(p) = self.path.clone() {
            self.push(SurfCommand::SaveTo(p));
        }
        if !ui.ctx().egui_wants_keyboard_input() && ui.input(|i| i.key_pressed(Key::Space)) {
            self.compare.show_after = !self.compare.show_after;
        }
    }

    fn menu_ui(&mut self, ui: &mut egui::Ui) {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
                match crate::typed_path_ui(
                    ui,
                    &mut self.path_input,
                    "/path/to/surface.json",
                    "A .ron document or .json surface (a curve file returns to the curve editor)",
                ) {
                    Some(crate::TypedPath::Open(p)) => self.push(SurfCommand::Open(p)),
                    Some(crate::TypedPath::SaveTo(p)) => self.push(SurfCommand::SaveTo(p)),
                    None => {}
                }
                if ui
                    .add_enabled(self.path.is_some(), egui::Button::new("Save"))
                    .on_hover_text("Save to the open file (Ctrl+S)")
                    .clicked()
                {
                    if let Some(p) = self.path.clone() {
                        self.push(SurfCommand::SaveTo(p));
                    }
                    ui.close();
                }
            });
            ui.separator();
            match crate::undo_redo_ui(ui, self.history.can_undo(), self.history.can_redo()) {
                Some(true) => self.push(SurfCommand::Undo),
                Some(false) => self.push(SurfCommand::Redo),
                None => {}
            }
            ui.separator();
            self.view.toolbar_ui(ui);
        });
    }

    fn status_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            if let Some(e) = self.error.clone() {
                ui.label(RichText::new(format!("! {e}")).color(Color32::from_rgb(230, 80, 60)));
                if ui.small_button("x").on_hover_text("Dismiss").clicked() {
                    self.error = None;
                }
                return;
            }
            ui.label(if self.is_dirty() { "* unsaved" } else { "saved" });
            ui.separator();
            match view3d::gpu(ui.ctx()) {
                Some(a) => ui.weak(format!("wgpu: {a}")),
                None => ui.weak("no wgpu renderer"),
            };
            ui.separator();
            let s = self.surface();
            ui.label(format!(
                "surface {}×{} control points, degree {}×{}",
                s.nu(),
                s.nv(),
                s.degree_u(),
                s.degree_v()
            ));
            if let Some(u) = self.unit {
                ui.separator();
                ui.label(format!("unit {}", u.symbol()))
                    .on_hover_text("The length unit of the file this surface came from (IGES / STEP)");
            }
            if let Some((uv, val)) = self.hover {
                ui.separator();
                ui.label(format!("u = {:.4}, v = {:.4}, {} = {val:.4e}", uv.x, uv.y, self.value_name()));
            }
            ui.separator();
            if self.status.is_empty() {
                ui.weak("drag: orbit · right-drag: pan · wheel: zoom · Ctrl+drag: region on the surface · Space: before/after");
            } else {
                ui.label(self.status.as_str());
            }
        });
    }

    fn value_name(&self) -> &'static str {
        match self.shading.mode {
            ShadeMode::Gauss => "K",
            ShadeMode::KMax => "κ1",
            ShadeMode::KMin => "κ2",
            _ => "H",
        }
    }

    fn controls_ui(&mut self, ui: &mut egui::Ui) {
        self.display_ui(ui);
        ui.separator();
        self.region_ui(ui);
        ui.separator();
        self.tolerance_section_ui(ui);
        ui.separator();
        self.compare_ui(ui);
        ui.separator();
        self.measures_ui(ui);
    }

    /// The "Display" section: shading mode, stripes, light, curvature range, overlays, mesh density.
    fn display_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Display");
        ui.horizontal_wrapped(|ui| {
            for m in ShadeMode::ALL {
                ui.selectable_value(&mut self.shading.mode, m, m.label())
                    .on_hover_text(match m {
                        ShadeMode::Shaded => "Lit surface",
                        ShadeMode::Isophotes => "Stripes of equal angle between the normal and the light",
                        ShadeMode::Zebra => "Reflection lines of parallel light tubes",
                        ShadeMode::Mean => "Mean curvature H = (κ1+κ2)/2, exact per vertex",
                        ShadeMode::Gauss => "Gaussian curvature K = κ1κ2, exact per vertex",
                        ShadeMode::KMax => "Maximum principal curvature κ1",
                        ShadeMode::KMin => "Minimum principal curvature κ2",
                    });
            }
        });
        if matches!(self.shading.mode, ShadeMode::Isophotes | ShadeMode::Zebra) {
            ui.add(egui::Slider::new(&mut self.shading.stripe_deg, view3d::STRIPE_RANGE).text("Stripe width °"))
                .on_hover_text("Angular width of one stripe (degrees)");
        }
        self.shading.light_ui(ui);
        if self.shading.mode.is_curvature() {
            let values = mode_values(&self.mesh, self.shading.mode).unwrap_or(&[]);
            let mut r = effective_range(&self.shading, values);
            let auto = self.shading.range.is_none();
            ui.horizontal(|ui| {
                let resp = ui
                    .add(
                        egui::Slider::new(&mut r, 1e-4..=1e3)
                            .logarithmic(true)
                            .text("Range ±")
                            .custom_formatter(|v, _| format!("{v:.3e}")),
                    )
                    .on_hover_text("Colour map range: ±range; neutral grey at zero");
                if resp.changed() {
                    self.shading.range = Some(r);
                }
                if ui
                    .selectable_label(auto, "auto")
                    .on_hover_text("95th percentile of |value| on the original surface")
                    .clicked()
                {
                    self.shading.range = None;
                }
            });
        }
        ui.checkbox(&mut self.shading.show_iso, "Isoparametric lines")
            .on_hover_text("u and v isocurves at the knots");
        ui.checkbox(&mut self.shading.show_net, "Control net")
            .on_hover_text("Show the control net");
        let mut d = self.shading.density;
        if ui
            .add(egui::Slider::new(&mut d, view3d::DENSITY_RANGE).text("Mesh density"))
            .on_hover_text("Tessellation vertices per direction (curvature is exact at each vertex)")
            .changed()
        {
            self.shading.density = d;
            self.set_surface_changed();
        }
    }

    /// The "Region" section: uv view, whole / clear, and the region's parameter bounds.
    fn region_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Region");
        self.uv_view_ui(ui);
        let ((du0, du1), (dv0, dv1)) = self.surface().domain();
        ui.horizontal(|ui| {
            if ui
                .button("Whole surface")
                .on_hover_text("Fair the whole surface")
                .clicked()
            {
                self.push(SurfCommand::SetRegion(Some(((du0, du1), (dv0, dv1)))));
            }
            if ui
                .add_enabled(self.region().is_some(), egui::Button::new("Clear"))
                .on_hover_text("Clear the region")
                .clicked()
            {
                self.push(SurfCommand::SetRegion(None));
            }
        });
        if let Some(((mut a, mut b), (mut c, mut d))) = self.region() {
            let mut changed = false;
            for row in [
                [(&mut a, du0, du1, "u1"), (&mut b, du0, du1, "u2")],
                [(&mut c, dv0, dv1, "v1"), (&mut d, dv0, dv1, "v2")],
            ] {
                ui.horizontal(|ui| {
                    for (v, lo, hi, name) in row {
                        let l = ui.label(name);
                        changed |= ui
                            .add(
                                egui::DragValue::new(v)
                                    .range(lo..=hi)
                                    .speed((hi - lo) * 1e-3)
                                    .max_decimals(5),
                            )
                            .labelled_by(l.id)
                            .changed();
                    }
                });
            }
            if changed && a < b && c < d {
                self.push(SurfCommand::SetRegion(Some(((a, b), (c, d)))));
            }
        } else {
            ui.weak("No region: drag in the uv view, or Ctrl+drag on the surface.");
        }
    }

    /// The "Tolerance" section: max deviation and live preview.
    fn tolerance_section_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading(crate::tolerance_heading(self.unit));
        let mut tol = self.tolerance();
        if crate::tolerance_ui(
            ui,
            &mut tol,
            self.diag(),
            "Max deviation m of the faired surface from the original (in the model's units)",
        ) {
            self.push(SurfCommand::SetTolerance(tol));
        }
        ui.checkbox(&mut self.live, "Live preview")
            .on_hover_text("Re-fair whenever region or tolerance change");
    }

    /// The "Compare" section: before / after, blend, side by side, preview error and Accept.
    fn compare_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Compare");
        ui.horizontal(|ui| {
            ui.selectable_value(&mut self.compare.show_after, false, "Before")
                .on_hover_text("Show the original (Space toggles)");
            ui.selectable_value(&mut self.compare.show_after, true, "After")
                .on_hover_text("Show the faired preview (Space toggles)");
        });
        ui.add(egui::Slider::new(&mut self.compare.blend, 0.0..=1.0).text("Blend"))
            .on_hover_text("Blend the control points original (0) -> faired (1)");
        ui.checkbox(&mut self.compare.side_by_side, "Side by side")
            .on_hover_text("Before and after in two views with one camera");
        if let Some(e) = &self.preview_error {
            ui.label(RichText::new(format!("! {e}")).color(Color32::from_rgb(230, 80, 60)));
        }
        if ui
            .add_enabled(self.preview.is_some(), egui::Button::new("Accept"))
            .on_hover_text("Replace the surface by the faired preview (one undo step)")
            .clicked()
        {
            self.push(SurfCommand::Accept);
        }
    }

    fn measures_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Measures");
        let Some(p) = &self.preview else {
            ui.weak("Select a region to see the faired preview's measures.");
            return;
        };
        ui.label(format!(
            "fair: {:.1} ms, rounds {}, α = {:.2}, verified max deviation {:.3e} (tolerance {:.3e})",
            p.fair_ms,
            p.rounds,
            p.alpha,
            p.max_deviation,
            self.tolerance()
        ));
        ui.label(band_certificate(p.band_bound, self.tolerance()));
        for n in &p.notes {
            ui.label(egui::RichText::new(n).small());
        }
        let (Some(a), Some((_, b))) = (&p.measures, &self.measures_before) else {
            ui.weak("(measures follow when the pointer is released)");
            return;
        };
        egui::Grid::new("surf_measures").striped(true).show(ui, |ui| {
            ui.strong("");
            ui.strong("before");
            ui.strong("after");
            ui.strong("change");
            ui.end_row();
            let rows: [(&str, f64, f64, &str); 4] = [
                (
                    "curvature extrema",
                    b.n_curv_extrema as f64,
                    a.n_curv_extrema as f64,
                    "isocurve κ extrema (20 per direction)",
                ),
                (
                    "E = sum int (dκ/ds)^2 ds",
                    b.e_var,
                    a.e_var,
                    "curvature variation along the isocurves",
                ),
                (
                    "int |grad H|^2 dA",
                    b.mean_curv_var,
                    a.mean_curv_var,
                    "mean curvature variation over the surface",
                ),
                (
                    "max deviation",
                    0.0,
                    a.dev_max,
                    "closest-point deviation on a 101×101 grid",
                ),
            ];
            for (name, x, y, tip) in rows {
                ui.label(name).on_hover_text(tip);
                ui.label(format!("{x:.4e}"));
                ui.label(format!("{y:.4e}"));
                if x != 0.0 {
                    ui.label(format!("{:+.0}%", (y / x - 1.0) * 100.0));
                } else {
                    ui.label("");
                }
                ui.end_row();
            }
            ui.label("RMS deviation");
            ui.label("0");
            ui.label(format!("{:.3e}", a.dev_rms));
            ui.end_row();
        });
    }

    /// The uv-domain mini view: knot lines, the region; drag to select.
    fn uv_view_ui(&mut self, ui: &mut egui::Ui) {
        let ((u0, u1), (v0, v1)) = self.surface().domain();
        let w = ui.available_width().clamp(120.0, 280.0);
        let (rect, resp) = ui.allocate_exact_size(egui::vec2(w, w * 0.75), Sense::click_and_drag());
        resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "uv domain"));
        let resp = resp.on_hover_text("uv domain: drag to select the fairing region (u -> right, v up)");
        let to_screen = |uv: DVec2| {
            Pos2::new(
                rect.left() + ((uv.x - u0) / (u1 - u0)) as f32 * rect.width(),
                rect.bottom() - ((uv.y - v0) / (v1 - v0)) as f32 * rect.height(),
            )
        };
        let to_uv = |p: Pos2| {
            DVec2::new(
                u0 + ((p.x - rect.left()) / rect.width()).clamp(0.0, 1.0) as f64 * (u1 - u0),
                v0 + ((rect.bottom() - p.y) / rect.height()).clamp(0.0, 1.0) as f64 * (v1 - v0),
            )
        };
        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 2.0, Color32::from_gray(30));
        let faint = Stroke::new(1.0, Color32::from_gray(60));
        for u in self.surface().knots_u().breakpoints() {
            painter.line_segment([to_screen(DVec2::new(u, v0)), to_screen(DVec2::new(u, v1))], faint);
        }
        for v in self.surface().knots_v().breakpoints() {
            painter.line_segment([to_screen(DVec2::new(u0, v)), to_screen(DVec2::new(u1, v))], faint);
        }
        if resp.drag_started()
            && let Some(p) = ui.input(|i| i.pointer.press_origin())
        {
            self.uv_drag = Some(to_uv(p));
        }
        if let (Some(a), Some(p)) = (self.uv_drag, resp.interact_pointer_pos())
            && resp.dragged()
        {
            let b = to_uv(p);
            if (b.x - a.x).abs() > 1e-9 && (b.y - a.y).abs() > 1e-9 {
                self.push(SurfCommand::SetRegion(Some(((a.x, b.x), (a.y, b.y)))));
            }
        }
        if resp.drag_stopped() {
            self.uv_drag = None;
        }
        if let Some(((a, b), (c, d))) = self.region() {
            let r = Rect::from_two_pos(to_screen(DVec2::new(a, c)), to_screen(DVec2::new(b, d)));
            painter.rect_filled(r, 0.0, Color32::from_rgba_unmultiplied(255, 140, 25, 50));
            painter.rect_stroke(
                r,
                0.0,
                Stroke::new(1.5, Color32::from_rgb(255, 140, 25)),
                egui::StrokeKind::Inside,
            );
        }
        if let Some((uv, _)) = self.hover {
            painter.circle_filled(to_screen(uv), 3.0, Color32::WHITE);
        }
        painter.text(
            rect.left_bottom() + egui::vec2(4.0, -4.0),
            egui::Align2::LEFT_BOTTOM,
            "u ->",
            egui::FontId::proportional(11.0),
            Color32::GRAY,
        );
        painter.text(
            rect.left_top() + egui::vec2(4.0, 4.0),
            egui::Align2::LEFT_TOP,
            "v up",
            egui::FontId::proportional(11.0),
            Color32::GRAY,
        );
    }

    /// The surface shown as "after": the preview blended with the original.
    fn after_surface(&mut self) -> Option<(u64, BSplineSurface, SurfaceMesh)> {
        let p = self.preview.as_ref()?;
        let t = self.compare.blend.clamp(0.0, 1.0);
        let id = points_hash(&p.surface) ^ t.to_bits().rotate_left(17);
        if t == 1.0 {
            return Some((id, p.surface.clone(), p.mesh.clone()));
        }
        if let Some((k, s, m)) = &self.blend_cache
            && *k == (self.rev, id)
        {
            return Some((id, s.clone(), m.clone()));
        }
        let orig = self.surface();
        let pts: Vec<DVec3> = orig
            .points()
            .iter()
            .zip(p.surface.points())
            .map(|(a, b)| a.lerp(*b, t))
            .collect();
        let s = p.surface.with_points(pts).ok()?;
        let n = self.shading.density;
        let m = SurfaceMesh::tessellate(&s, n, n).ok()?;
        self.blend_cache = Some(((self.rev, id), s.clone(), m.clone()));
        Some((id, s, m))
    }

    fn scene(&mut self, slot: usize, id: u64, s: &BSplineSurface, mesh: &SurfaceMesh) -> Arc<view3d::Scene> {
        let values = mode_values(&self.mesh, self.shading.mode).unwrap_or(&[]);
        let range = effective_range(&self.shading, values);
        // stripe width and light are uniforms of the paint callback, not part of the scene
        let baked = Shading {
            stripe_deg: 0.0,
            light_azimuth: 0.0,
            light_elevation: 0.0,
            ..self.shading
        };
        let key = (self.rev, id, baked, range.to_bits(), self.region());
        if let Some(c) = &self.scenes[slot]
            && c.key == key
        {
            return c.scene.clone();
        }
        let origin = 0.5 * (self.view.bbox.0 + self.view.bbox.1);
        let scene = Arc::new(surface_scene(s, mesh, &self.shading, range, self.region(), origin));
        self.scenes[slot] = Some(SceneCache {
            key,
            scene: scene.clone(),
        });
        scene
    }

    fn views_ui(&mut self, ui: &mut egui::Ui) {
        let full = ui.available_rect_before_wrap();
        let orig = self.surface().clone();
        let orig_mesh = self.mesh.clone();
        let after = if self.compare.show_after || self.compare.side_by_side {
            self.after_surface()
        } else {
            None
        };
        let mut panes: Vec<(Rect, &str, u64, BSplineSurface, SurfaceMesh, usize)> = vec![];
        if self.compare.side_by_side {
            let (l, r) = full.split_left_right_at_fraction(0.5);
            panes.push((l.shrink(1.0), "Before", 0, orig.clone(), orig_mesh.clone(), 0));
            match after {
                Some((id, s, m)) => panes.push((r.shrink(1.0), "After", id, s, m, 1)),
                None => panes.push((r.shrink(1.0), "After (no preview)", 0, orig, orig_mesh, 1)),
            }
        } else {
            match after {
                Some((id, s, m)) => panes.push((full, "After", id, s, m, 1)),
                None => panes.push((full, "Before", 0, orig, orig_mesh, 0)),
            }
        }
        let origin = 0.5 * (self.view.bbox.0 + self.view.bbox.1);
        for (k, (rect, name, id, s, mesh, slot)) in panes.into_iter().enumerate() {
            let resp = ui.interact(rect, ui.scope_id().with(("surf3d", k)), Sense::click_and_drag());
            resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "3D view"));
            self.view.fit_if_needed(rect);
            let ctrl = ui.input(|i| i.modifiers.command);
            // Ctrl+drag: region by ray picking on the surface
            if ctrl || self.pick_drag.is_some() {
                if resp.drag_started()
                    && let Some(p) = ui.input(|i| i.pointer.press_origin())
                {
                    let (o, d) = self.view.ray(p, rect);
                    self.pick_drag = pick_uv(&s, &mesh, o, d);
                }
                if let (Some(a), Some(p)) = (self.pick_drag, resp.interact_pointer_pos())
                    && resp.dragged()
                {
                    let (o, d) = self.view.ray(p, rect);
                    if let Some(b) = pick_uv(&s, &mesh, o, d)
                        && (b.x - a.x).abs() > 1e-9
                        && (b.y - a.y).abs() > 1e-9
                    {
                        self.push(SurfCommand::SetRegion(Some(((a.x, b.x), (a.y, b.y)))));
                    }
                }
                if resp.drag_stopped() {
                    self.pick_drag = None;
                }
                self.view.interact(ui, &resp, false);
            } else {
                self.view.interact(ui, &resp, true);
            }
            if let Some(p) = resp.hover_pos() {
                let (o, d) = self.view.ray(p, rect);
                let hv = pick_uv(&s, &mesh, o, d).map(|uv| {
                    let c = s.curvature(uv.x, uv.y);
                    let v = match self.shading.mode {
                        ShadeMode::Gauss => c.gauss,
                        ShadeMode::KMax => c.k_max,
                        ShadeMode::KMin => c.k_min,
                        _ => c.mean,
                    };
                    (uv, v)
                });
                if hv != self.hover {
                    self.hover = hv;
                }
            }
            let scene = self.scene(slot, id, &s, &mesh);
            self.view.paint(
                ui,
                rect,
                ui.scope_id().with(("surf3d_paint", k)),
                &scene,
                origin,
                &self.shading,
            );
            let painter = ui.painter_at(rect);
            painter.text(
                rect.left_top() + egui::vec2(8.0, 6.0),
                egui::Align2::LEFT_TOP,
                name,
                egui::FontId::proportional(15.0),
                Color32::WHITE,
            );
            if self.shading.mode.is_curvature() {
                let values = mode_values(&self.mesh, self.shading.mode).unwrap_or(&[]);
                let range = effective_range(&self.shading, values);
                view3d::legend(&painter, rect, self.shading.mode.label(), range);
            }
        }
    }
}

/// Bounding box of a mesh's vertices.
pub fn bbox_of(mesh: &SurfaceMesh) -> (DVec3, DVec3) {
    view3d::camera::bbox(mesh.positions.iter().copied()).unwrap_or((DVec3::splat(-1.0), DVec3::splat(1.0)))
}

impl crate::App {
    /// Show the surface workspace if one is open (true), switching back to
    /// the curve editor when the user opened a curve from it.
    pub(crate) fn surface_show(&mut self, ui: &mut egui::Ui) -> bool {
        let Some(s) = self.surface.as_mut() else { return false };
        s.show(ui);
        // remembered for the next surface and for eframe storage
        self.curve3d.surface_shading = s.shading;
        if let Some(p) = s.open_curve.take() {
            self.open_now(&p);
        }
        true
    }
}

/// What the sound bound says of the band, in the user's terms: certified everywhere (not only at the
/// check grid), or only at the grid where the bound is above the tolerance.
pub fn band_certificate(bound: Option<f64>, tolerance: f64) -> String {
    match bound {
        Some(b) if b <= tolerance => format!("band certified everywhere: deviation ≤ {b:.3e}"),
        Some(b) => format!(
            "band verified on the check grid; the bound everywhere is {b:.3e}, above the tolerance (the surface slid \
             along itself)"
        ),
        None => "band verified on the check grid (no bound everywhere for this surface)".into(),
    }
}
