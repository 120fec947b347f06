//! The surface workspace: a 3D view of the document's surface with the interrogation modes, a
//! uv-domain mini view to pick the fairing region (or Ctrl+drag on the surface), the tolerance with a
//! live preview by the core's `fair_surface`, compare (toggle, blend, side by side), measures and
//! accept. The shell owns the document, its file and the history; edits are [`Command`]s like the
//! curve workspace's.

mod panels;
mod views;

use std::sync::Arc;
use std::time::Instant;

use eframe::egui;
use fairway::fair::surface::{SurfaceFairingOptions, SurfaceMethod, fair_surface};
use fairway::io::Document;
use fairway::measure_surface::{SurfaceMeasures, surface_measures};
use fairway::mesh::SurfaceMesh;
use fairway::{BSplineSurface, DVec2, DVec3, Geometry};

use crate::Command;
use crate::commands::set_tolerance;
use crate::fairing::FairOptions;
use crate::view3d::{self, ShadeMode, Shading, View3d};
use crate::workspace::{Cx, ShellCx, Workspace};

pub use views::bbox_of;

/// A uv rectangle `((u1, u2), (v1, v2))`.
pub type UvRect = ((f64, f64), (f64, f64));

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
pub(crate) struct SceneCache {
    /// (revision, the shown surface, shading, colour range, region, the other patches' revision)
    pub(crate) key: (u64, u64, Shading, u64, Option<UvRect>, u64),
    pub(crate) scene: Arc<view3d::Scene>,
}

/// The surface workspace's state: tessellation, camera, shading, preview and caches.
pub struct SurfaceWorkspace {
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
    uv_drag: Option<DVec2>,
    pick_drag: Option<DVec2>,
    blend_cache: Option<((u64, u64), BSplineSurface, SurfaceMesh)>,
    scenes: [Option<SceneCache>; 2],
    hover: Option<(DVec2, f64)>,
    /// An error of an edit (a failed tessellation), shown by the shell after the commands.
    edit_error: Option<String>,
    /// The document's joins and shared patch edges, drawn over the views (set by the shell).
    pub marks: Vec<crate::scene_view::Mark3d>,
    /// The document's other patches, drawn dimmed in the views (set by the shell, [`Self::set_others`]).
    pub others: Vec<OtherPatch>,
    /// The active face's bounds (a trimmed face from STEP), drawn on it in the 3D views.
    pub trim: Option<fairway::FaceTrim>,
    /// Counts changes of `others` (the scene caches' key).
    others_rev: u64,
}

/// Another patch of the document, drawn dimmed in the 3D views; a click on it selects it.
pub struct OtherPatch {
    /// Its index among the document's objects.
    pub object: usize,
    /// The patch.
    pub surface: BSplineSurface,
    /// Its tessellation.
    pub mesh: SurfaceMesh,
}

/// The surface workspace with the shell's context: what its panels are written against.
pub type SurfaceCx<'a> = Cx<'a, SurfaceWorkspace>;

fn surface_of(doc: &Document) -> Option<&BSplineSurface> {
    match &doc.geometry {
        Geometry::Surface(s) => Some(s),
        Geometry::Curve(_) => None,
    }
}

pub(crate) fn points_hash(s: &BSplineSurface) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for p in s.points() {
        p.x.to_bits().hash(&mut h);
        p.y.to_bits().hash(&mut h);
        p.z.to_bits().hash(&mut h);
    }
    h.finish()
}

impl SurfaceWorkspace {
    /// A workspace for `doc`, which must hold a surface, shown with `shading`.
    pub fn new(doc: &Document, shading: Shading) -> anyhow::Result<Self> {
        let s = surface_of(doc).ok_or_else(|| anyhow::anyhow!("the document holds a curve, not a surface"))?;
        let shading = shading.sanitized();
        let mesh = SurfaceMesh::tessellate(s, shading.density, shading.density)?;
        let mut view = View3d::default();
        view.set_bbox(bbox_of(&mesh), true);
        Ok(Self {
            rev: 1,
            mesh,
            shading,
            view,
            live: true,
            preview: None,
            preview_error: None,
            compare: SurfCompare::default(),
            measures_before: None,
            uv_drag: None,
            pick_drag: None,
            blend_cache: None,
            scenes: [None, None],
            hover: None,
            edit_error: None,
            marks: vec![],
            others: vec![],
            trim: None,
            others_rev: 0,
        })
    }

    /// Replace the shading settings ([`Shading::sanitized`]); a new mesh density re-tessellates
    /// `surface` (the document's).
    pub fn set_shading(&mut self, shading: Shading, surface: &BSplineSurface) -> anyhow::Result<()> {
        let shading = shading.sanitized();
        let retessellate = shading.density != self.shading.density;
        self.shading = shading;
        if retessellate {
            self.set_surface_changed(surface)?;
        }
        Ok(())
    }

    /// Diagonal of the surface's bounding box.
    pub fn diag(&self) -> f64 {
        let (a, b) = bbox_of(&self.mesh);
        (b - a).length().max(1e-12)
    }

    /// The box of the active patch and the others: what the views show.
    fn scene_bbox(&self) -> (DVec3, DVec3) {
        self.others.iter().fold(bbox_of(&self.mesh), |(lo, hi), o| {
            let (a, b) = bbox_of(&o.mesh);
            (lo.min(a), hi.max(b))
        })
    }

    /// Show the document's other patches (`object`, surface) dimmed beside the active one; unchanged
    /// patches keep their tessellation. A patch that cannot be tessellated is left out.
    pub fn set_others(&mut self, others: Vec<(usize, BSplineSurface)>) {
        let same = others.len() == self.others.len()
            && others
                .iter()
                .zip(&self.others)
                .all(|((k, s), o)| *k == o.object && *s == o.surface);
        if same {
            return;
        }
        let n = self.shading.density;
        self.others = others
            .into_iter()
            .filter_map(|(object, surface)| {
                let mesh = SurfaceMesh::tessellate(&surface, n, n).ok()?;
                Some(OtherPatch { object, surface, mesh })
            })
            .collect();
        self.others_rev += 1;
        let b = self.scene_bbox();
        self.view.set_bbox(b, false);
    }

    /// The document's surface changed (or the mesh density): re-tessellate, drop the preview.
    fn set_surface_changed(&mut self, surface: &BSplineSurface) -> anyhow::Result<()> {
        self.rev += 1;
        self.preview = None;
        self.mesh = SurfaceMesh::tessellate(surface, self.shading.density, self.shading.density)
            .map_err(|e| anyhow::anyhow!("tessellation failed: {e}"))?;
        let b = self.scene_bbox();
        self.view.set_bbox(b, false);
        Ok(())
    }

    /// Bring the preview up to date; true if it was recomputed.
    pub fn update_preview(&mut self, doc: &Document, pointer_down: bool) -> bool {
        let Some(surface) = surface_of(doc) else { return false };
        let Some(region) = doc.settings.region_uv else {
            self.preview = None;
            self.preview_error = None;
            return false;
        };
        if !self.live {
            return false;
        }
        let tol = doc.settings.tolerance.unwrap_or(self.default_tolerance());
        let key = (self.rev, Some(region), tol.to_bits(), self.shading.density);
        let mut changed = false;
        let stale = match self.preview.as_ref() {
            Some(p) => p.key != key || (p.draft && !pointer_down),
            None => true,
        };
        if stale {
            changed = true;
            let draft = pointer_down;
            // while dragging: one isocurve tolerance level (the live-preview setting of the core) and the
            // isocurve fairing alone (the step-8 choice among the reference smoother's candidates costs
            // 8-15 × as much); on release the defaults
            let defaults = SurfaceFairingOptions::default();
            let opts = defaults
                .region(Some(region))
                .tolerance(tol)
                .iso_levels(if draft { 1 } else { defaults.iso_levels })
                .method(if draft {
                    SurfaceMethod::Isocurves
                } else {
                    defaults.method
                });
            let t0 = Instant::now();
            // a panic in the engine becomes an error message; the document is untouched
            let res = crate::guard::catch_panic("surface fairing", || fair_surface(surface, opts));
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
                p.measures = Some(surface_measures(surface, &p.surface));
                changed = true;
            }
            if self.measures_before.as_ref().map(|m| m.0) != Some(self.rev) {
                let m = surface_measures(surface, surface);
                self.measures_before = Some((self.rev, m));
                changed = true;
            }
        }
        changed
    }

    fn value_name(&self) -> &'static str {
        match self.shading.mode {
            ShadeMode::Gauss => "K",
            ShadeMode::KMax => "κ1",
            ShadeMode::KMin => "κ2",
            _ => "H",
        }
    }
}

impl<'a> SurfaceCx<'a> {
    /// The document's surface.
    pub fn surface(&self) -> &'a BSplineSurface {
        surface_of(self.doc).expect("the surface workspace shows a surface document")
    }

    /// The uv region, if any.
    pub fn region(&self) -> Option<UvRect> {
        self.doc.settings.region_uv
    }

    /// The tolerance in effect.
    pub fn tolerance(&self) -> f64 {
        self.doc.settings.tolerance.unwrap_or(self.ws.default_tolerance())
    }

    /// The status bar: renderer, surface description, pointer readout.
    fn status_ui(&mut self, ui: &mut egui::Ui) {
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
        if let Some((uv, val)) = self.ws.hover {
            ui.separator();
            ui.label(format!(
                "u = {:.4}, v = {:.4}, {} = {val:.4e}",
                uv.x,
                uv.y,
                self.ws.value_name()
            ));
        }
    }
}

impl Workspace for SurfaceWorkspace {
    fn title_suffix(&self) -> &'static str {
        " (surface)"
    }

    fn default_tolerance(&self) -> f64 {
        self.diag() * 1e-3
    }

    fn view_menu_ui(&mut self, ui: &mut egui::Ui, _sh: &mut ShellCx<'_>) {
        ui.checkbox(&mut self.compare.side_by_side, "Side by side")
            .on_hover_text("Before and after in two views with one camera");
    }

    fn toolbar_ui(&mut self, ui: &mut egui::Ui, _sh: &mut ShellCx<'_>) {
        ui.separator();
        self.view.toolbar_ui(ui);
    }

    fn status_ui(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>) {
        sh.with(self).status_ui(ui);
    }

    fn hint(&self) -> &'static str {
        "drag: orbit · right-drag: pan · wheel: zoom · Ctrl+drag: region on the surface · Space: before/after · F1: keys"
    }

    fn panels_ui(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>) {
        let mut cx = sh.with(self);
        egui::Panel::right("surf_controls")
            .resizable(true)
            .default_size(300.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| cx.controls_ui(ui));
            });
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>) {
        sh.with(self).views_ui(ui);
    }

    fn apply_edit(&mut self, c: &Command, doc: &mut Document, _fair: &mut FairOptions) -> bool {
        match c {
            Command::SetRegionUv(r) => {
                let r = r.map(|((a, b), (c, d))| ((a.min(b), a.max(b)), (c.min(d), c.max(d))));
                let changed = doc.settings.region_uv != r;
                doc.settings.region_uv = r;
                changed
            }
            Command::SetTolerance(t) => set_tolerance(doc, *t),
            Command::AcceptSurface => {
                let Some(p) = self.preview.take() else { return false };
                doc.geometry = Geometry::Surface(p.surface);
                doc.settings.region_uv = None;
                if let Some(s) = surface_of(doc)
                    && let Err(e) = self.set_surface_changed(s)
                {
                    self.edit_error = Some(e.to_string());
                }
                true
            }
            _ => false,
        }
    }

    fn document_changed(&mut self, doc: &Document, geometry_changed: bool) {
        if geometry_changed
            && let Some(s) = surface_of(doc)
            && let Err(e) = self.set_surface_changed(s)
        {
            self.edit_error = Some(e.to_string());
        }
    }

    fn after_commands(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>) {
        if let Some(e) = self.edit_error.take() {
            *sh.error = Some(e);
        }
        let down = ui.input(|i| i.pointer.any_down());
        if self.update_preview(sh.doc, down) {
            ui.ctx().request_repaint();
        }
    }

    fn fit_view(&mut self) {
        self.view.set_bbox(self.view.bbox, true);
    }

    fn toggle_before_after(&mut self) {
        self.compare.show_after = !self.compare.show_after;
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
