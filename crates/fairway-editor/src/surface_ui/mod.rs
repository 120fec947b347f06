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
use fairway::fair::surface::{IsocurveCache, SurfaceFairingOptions, SurfaceFairingResult, fair_surface_cached};
use fairway::io::Document;
use fairway::measure_surface::{SurfaceMeasures, surface_measures};
use fairway::mesh::SurfaceMesh;
use fairway::{BSplineSurface, DVec2, DVec3, Geometry};

use crate::Command;
use crate::commands::set_tolerance;
use crate::fairing::FairOptions;
use crate::jobs::{Gate, Job, JobWatch};
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
    /// Measures against the original (computed with the full fair, in the background; none for a draft).
    pub measures: Option<SurfaceMeasures>,
    /// Computed while a drag was in progress with the draft options (`SurfaceFairingOptions::draft`: one
    /// isocurve tolerance level, the isocurves alone, each at the band's largest μ; in the background, one
    /// draft at a time); the full fair runs when the pointer is released (in the background; the draft is
    /// shown meanwhile, marked provisional).
    pub draft: bool,
    key: PreviewKey,
}

/// What a preview was computed for: (the surface's revision, the region, the tolerance's bits, the mesh
/// density).
pub type PreviewKey = (u64, Option<UvRect>, u64, usize);

impl SurfacePreview {
    /// The preview of the fair `r` of `key` (tessellated at the key's density), `fair_ms` its time.
    fn new(r: SurfaceFairingResult, fair_ms: f64, key: PreviewKey, draft: bool) -> fairway::Result<Self> {
        let n = key.3;
        let mesh = SurfaceMesh::tessellate(&r.surface, n, n)?;
        Ok(Self {
            surface: r.surface,
            mesh,
            max_deviation: r.max_deviation,
            band_bound: r.band_bound,
            rounds: r.rounds,
            alpha: r.alpha,
            fair_ms,
            notes: r.notes,
            measures: None,
            draft,
            key,
        })
    }

    /// The key it was computed for.
    pub fn key(&self) -> PreviewKey {
        self.key
    }
}

/// The fairing options of a preview of `key`: a draft while dragging (`SurfaceFairingOptions::draft`), else
/// the defaults.
fn preview_options(key: PreviewKey, draft: bool) -> SurfaceFairingOptions {
    let opts = SurfaceFairingOptions::default()
        .region(key.1)
        .tolerance(f64::from_bits(key.2));
    if draft { opts.draft() } else { opts }
}

/// What the background full fair hands back.
struct FullFair {
    preview: SurfacePreview,
    /// The original measured against itself, if it was not yet for this revision.
    measures_before: Option<SurfaceMeasures>,
}

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
    /// The full fair of the preview, running in the background (keyed like the preview).
    job: Option<Job<PreviewKey, FullFair>>,
    /// The draft of the preview during a drag, running in the background: at most one at a time; the
    /// next starts, for the latest key, when it has finished (keys in between are skipped).
    draft_job: Option<Job<PreviewKey, SurfacePreview>>,
    /// Draft jobs started so far (tests: one at a time, intermediate keys skipped).
    pub drafts_started: usize,
    /// The isocurve setups of the last fairs of this surface, shared by the draft and full-fair jobs: a
    /// draft at another tolerance (a tolerance drag) and the full fair after it skip the setups
    /// ([`IsocurveCache`]; cleared when the surface changes).
    pub iso_cache: IsocurveCache,
    /// Whether the pointer was down at the last [`Self::update_preview`] (a drag in progress).
    pointer_down: bool,
    /// Tests: every job this workspace starts waits at this gate before it computes.
    gate: Option<Gate>,
    /// The key of the last fair that failed and whether it was a draft: not tried again until the key
    /// changes (a failed draft still lets the full fair run on release).
    failed: Option<(PreviewKey, bool)>,
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
            job: None,
            draft_job: None,
            drafts_started: 0,
            iso_cache: IsocurveCache::new(),
            pointer_down: false,
            gate: None,
            failed: None,
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
        self.job = None;
        self.draft_job = None;
        self.iso_cache.clear();
        self.mesh = SurfaceMesh::tessellate(surface, self.shading.density, self.shading.density)
            .map_err(|e| anyhow::anyhow!("tessellation failed: {e}"))?;
        let b = self.scene_bbox();
        self.view.set_bbox(b, false);
        Ok(())
    }

    /// The key of the preview the document asks for: the surface's revision, the region, the
    /// tolerance in effect and the mesh density (`None` without a region).
    pub fn preview_key(&self, doc: &Document) -> Option<PreviewKey> {
        surface_of(doc)?;
        let region = doc.settings.region_uv?;
        let tol = doc.settings.tolerance.unwrap_or(self.default_tolerance());
        Some((self.rev, Some(region), tol.to_bits(), self.shading.density))
    }

    /// Bring the preview up to date; true if it changed (the caller repaints). While the pointer is
    /// down (a drag) a missing preview is computed as a draft in the background, coalesced: while a draft
    /// job runs no other starts, the last draft (or the original) staying on screen; when it ends, the
    /// next starts for the key of that moment. With the pointer up the full fair runs in the background,
    /// the draft of this key (shown, or still coming — started beside the full fair where there was none)
    /// staying as the provisional preview, and a later call takes its result if its key still matches. A new key supersedes a running full fair: the job is
    /// dropped, which cancels it (the core stops at its next checkpoint). `repaint` is asked for a frame
    /// when a background fair ends.
    pub fn update_preview(&mut self, doc: &Document, pointer_down: bool, repaint: Option<&egui::Context>) -> bool {
        self.pointer_down = pointer_down;
        let Some(surface) = surface_of(doc) else { return false };
        let Some(key) = self.preview_key(doc) else {
            let changed = self.preview.is_some()
                || self.preview_error.is_some()
                || self.job.is_some()
                || self.draft_job.is_some();
            (self.preview, self.preview_error, self.job, self.draft_job) = (None, None, None, None);
            return changed;
        };
        if !self.live {
            (self.job, self.draft_job) = (None, None);
            return false;
        }
        let mut changed = self.take_job_result(key);
        changed |= self.take_draft_result(key);
        let current = self.preview.as_ref().filter(|p| p.key == key);
        if current.is_some_and(|p| !p.draft) || self.job.is_some() || self.failed == Some((key, false)) {
            return changed;
        }
        if pointer_down {
            // one draft job at a time: the next starts when it has ended, for the key of that moment
            if current.is_none() && self.failed != Some((key, true)) && self.draft_job.is_none() {
                self.draft_job = Some(self.draft_job(surface, key, repaint));
                self.drafts_started += 1;
                changed = true;
            }
        } else {
            // released: a draft of another key is outdated (its job is dropped, so cancelled); the draft
            // of this key stays as the provisional preview, or is still coming
            if self.draft_job.as_ref().is_some_and(|j| *j.key() != key) {
                self.draft_job = None;
            }
            if current.is_none() {
                self.preview = None;
                // no draft of this key (a typed tolerance, a button, a release after a draft of an earlier
                // point of the drag): one runs beside the full fair, so a provisional result shows in a
                // fraction of the full fair's time (it is dropped if the full fair comes first)
                if self.draft_job.is_none() && self.failed != Some((key, true)) {
                    self.draft_job = Some(self.draft_job(surface, key, repaint));
                    self.drafts_started += 1;
                }
            }
            self.job = Some(self.full_fair_job(surface, key, repaint));
            changed = true;
        }
        changed
    }

    /// Whether the full fair of the preview runs in the background.
    pub fn is_fairing(&self) -> bool {
        self.job.is_some()
    }

    /// How long the background fair has been running.
    pub fn fairing_time(&self) -> Option<std::time::Duration> {
        self.job.as_ref().map(Job::elapsed)
    }

    /// The key the background fair was started for.
    pub fn fairing_key(&self) -> Option<PreviewKey> {
        self.job.as_ref().map(|j| *j.key())
    }

    /// Whether a draft runs in the background (during a drag).
    pub fn is_drafting(&self) -> bool {
        self.draft_job.is_some()
    }

    /// How long the background draft has been running.
    pub fn drafting_time(&self) -> Option<std::time::Duration> {
        self.draft_job.as_ref().map(Job::elapsed)
    }

    /// The key the background draft was started for.
    pub fn drafting_key(&self) -> Option<PreviewKey> {
        self.draft_job.as_ref().map(|j| *j.key())
    }

    /// A watch on the background full fair's thread (tests: a superseded fair ends `Cancelled`).
    pub fn watch_fair(&self) -> Option<JobWatch> {
        self.job.as_ref().map(Job::watch)
    }

    /// A watch on the background draft's thread.
    pub fn watch_draft(&self) -> Option<JobWatch> {
        self.draft_job.as_ref().map(Job::watch)
    }

    /// Tests: every job started from now on waits at `gate` before it computes (`None`: no gate), so a
    /// test can hold a job deterministically while it runs. Open the gate before waiting for the jobs.
    pub fn set_gate(&mut self, gate: Option<Gate>) {
        self.gate = gate;
    }

    /// Block until the background fair and draft (if any) have their results, which the next
    /// [`SurfaceWorkspace::update_preview`] takes (tests and scripts; the UI never waits).
    pub fn wait_for_job(&mut self) {
        if let Some(j) = self.job.as_mut() {
            j.wait();
        }
        if let Some(j) = self.draft_job.as_mut() {
            j.wait();
        }
    }

    /// [`SurfaceWorkspace::wait_for_job`], then take the results as the next frame would (used only
    /// if their keys match `doc`); true if the preview changed.
    pub fn finish_job(&mut self, doc: &Document) -> bool {
        self.wait_for_job();
        self.preview_key(doc)
            .is_some_and(|key| self.take_job_result(key) | self.take_draft_result(key))
    }

    /// The background fair's result, if it has finished: used if it was started for `key`, else
    /// dropped (a job for another key is dropped even while it runs, which cancels it). True if the
    /// preview changed.
    fn take_job_result(&mut self, key: PreviewKey) -> bool {
        let Some(job) = self.job.as_mut() else { return false };
        if *job.key() != key {
            // superseded by an edit: dropping the job cancels it, and its result is never taken
            self.job = None;
            return false;
        }
        let Some(res) = job.poll() else { return false };
        self.job = None;
        match res {
            Ok(full) => {
                if let Some(m) = full.measures_before {
                    self.measures_before = Some((key.0, m));
                }
                self.preview = Some(full.preview);
                self.preview_error = None;
                self.failed = None;
            }
            Err(e) => {
                self.preview = None;
                self.preview_error = Some(e.to_string());
                self.failed = Some((key, false));
            }
        }
        true
    }

    /// The background draft's result, if it has finished. During a drag it is shown whatever its key
    /// (the latest draft there is; [`Self::update_preview`] then starts the next for `key` if the key
    /// moved meanwhile); after the release only the draft of `key`, and only until the full fair is
    /// there. True if the preview changed.
    fn take_draft_result(&mut self, key: PreviewKey) -> bool {
        let Some(res) = self.draft_job.as_mut().and_then(Job::poll) else {
            return false;
        };
        let Some(dkey) = self.draft_job.take().map(|j| *j.key()) else {
            return false;
        };
        // the full fair of this key has ended (its result shown, or its error): the draft is not wanted
        let full_there =
            self.preview.as_ref().is_some_and(|p| !p.draft && p.key == key) || self.failed == Some((key, false));
        if full_there || dkey.0 != self.rev || (!self.pointer_down && dkey != key) {
            return false;
        }
        match res {
            Ok(p) => {
                self.preview = Some(p);
                self.preview_error = None;
            }
            // a draft job is cancelled only when dropped, and then never polled
            Err(fairway::Error::Cancelled) => return false,
            Err(e) => {
                self.preview = None;
                self.preview_error = Some(e.to_string());
                self.failed = Some((dkey, true));
            }
        }
        true
    }

    /// The draft preview of `key` as a background job (`SurfaceFairingOptions::draft`: one isocurve
    /// tolerance level, the isocurve fairing alone — the step-8 choice among the reference smoother's
    /// candidates costs 8-15 × as much — and each isocurve's fit at the band's largest μ), and its
    /// tessellation.
    fn draft_job(
        &self,
        surface: &BSplineSurface,
        key: PreviewKey,
        repaint: Option<&egui::Context>,
    ) -> Job<PreviewKey, SurfacePreview> {
        let surface = surface.clone();
        let (gate, cache) = (self.gate.clone(), self.iso_cache.clone());
        Job::spawn(key, "surface fairing", repaint, move |cancel| {
            if let Some(g) = gate {
                g.pass();
            }
            let t0 = Instant::now();
            let r = fair_surface_cached(&surface, preview_options(key, true), cancel, &cache)?;
            let fair_ms = t0.elapsed().as_secs_f64() * 1e3;
            SurfacePreview::new(r, fair_ms, key, true)
        })
    }

    /// The full fair of `key` as a background job: the fair, its tessellation and its measures against
    /// the original (and the original's own, if not yet measured for this revision).
    fn full_fair_job(
        &self,
        surface: &BSplineSurface,
        key: PreviewKey,
        repaint: Option<&egui::Context>,
    ) -> Job<PreviewKey, FullFair> {
        let surface = surface.clone();
        let measure_before = self.measures_before.as_ref().map(|m| m.0) != Some(key.0);
        let (gate, cache) = (self.gate.clone(), self.iso_cache.clone());
        Job::spawn(key, "surface fairing", repaint, move |cancel| {
            if let Some(g) = gate {
                g.pass();
            }
            let t0 = Instant::now();
            let r = fair_surface_cached(&surface, preview_options(key, false), cancel, &cache)?;
            let fair_ms = t0.elapsed().as_secs_f64() * 1e3;
            let mut preview = SurfacePreview::new(r, fair_ms, key, false)?;
            // the measures are not the core's fair: a job superseded meanwhile skips them
            let stop = || cancel.is_cancelled().then_some(fairway::Error::Cancelled);
            if let Some(e) = stop() {
                return Err(e);
            }
            preview.measures = Some(surface_measures(&surface, &preview.surface));
            if let Some(e) = stop() {
                return Err(e);
            }
            let measures_before = measure_before.then(|| surface_measures(&surface, &surface));
            Ok(FullFair {
                preview,
                measures_before,
            })
        })
    }

    /// Whether Accept may take the preview: the full fair (not a draft) of the document's current key.
    pub fn can_accept(&self, doc: &Document) -> bool {
        let key = self.preview_key(doc);
        self.preview.as_ref().is_some_and(|p| !p.draft && Some(p.key) == key)
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
                // the full fair of the current key only: not a draft, not a preview of an older state
                if !self.can_accept(doc) {
                    return false;
                }
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
        if self.update_preview(sh.doc, down, Some(ui.ctx())) {
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
