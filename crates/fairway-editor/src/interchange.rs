//! The editor's side of interchange and hardening: autosave and crash
//! recovery, SVG / PNG export, and the object picker for IGES and STEP files
//! that hold several curves or surfaces. The file formats and the autosave
//! bookkeeping live in the core (`fairway::io::{autosave, svg, iges, step}`); this
//! module only wires them into the app (commands, a modal, a window, the
//! File menu's export entries).

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant, SystemTime};

use crate::autosave::{self, Autosave};
use eframe::egui;
use egui::ColorImage;
use fairway::Geometry;
use fairway::io::interchange::EntityInfo;
use fairway::io::svg::{SvgOptions, try_curve_svg};
use fairway::io::{Document, Format, InterchangeFile, Unit};

use crate::{App, Command};

/// How often a dirty document is autosaved. 30 s bounds the work lost in a
/// crash to half a minute while writing (a few kB, atomically) rarely enough
/// to be invisible.
pub const AUTOSAVE_INTERVAL: Duration = Duration::from_secs(30);

/// Environment variable naming the autosave folder (overrides the platform's
/// application data folder, [`autosave::default_dir`]).
pub const AUTOSAVE_DIR_ENV: &str = "FAIRWAY_AUTOSAVE_DIR";

/// The autosave folder: `$FAIRWAY_AUTOSAVE_DIR` if set, else the platform's
/// application data folder.
pub fn autosave_dir() -> Option<PathBuf> {
    std::env::var_os(AUTOSAVE_DIR_ENV)
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(autosave::default_dir)
}

/// Whether `path` names an IGES or STEP file (by its extension).
pub fn is_interchange(path: &Path) -> bool {
    Format::from_path(path).is_ok_and(|f| matches!(f, Format::Iges | Format::Step))
}

/// Object `k` of an IGES or STEP file as a document of its own: unnamed (saved as the file it came from
/// was, a version 1 document when it is a plain curve or surface) with its trim, if it is a trimmed face.
fn one_object(file: &InterchangeFile, k: usize) -> fairway::io::Scene {
    let doc = Document::new(file.objects[k].clone());
    fairway::io::Scene {
        objects: vec![fairway::io::SceneObject {
            name: String::new(),
            trim: file.trims.get(k).cloned().flatten(),
            geometry: doc.geometry,
            settings: doc.settings,
        }],
        ..Default::default()
    }
}

/// An IGES or STEP file with several objects, shown in the picker.
#[derive(Debug, Clone)]
pub struct ObjectPick {
    /// The file.
    pub path: PathBuf,
    /// What the core read from it.
    pub file: InterchangeFile,
}

/// ` (unit mm)`, or nothing when the file declares no unit Fairway knows.
fn unit_note(unit: Option<Unit>) -> String {
    unit.map_or(String::new(), |u| format!(" (unit {})", u.symbol()))
}

/// One line describing object `k` of an IGES or STEP file: kind, degree, control
/// points, weights, entity (IGES directory entry, STEP instance `#n`) and label.
pub fn describe_object(g: &Geometry, info: Option<&EntityInfo>) -> String {
    let mut s = match g {
        Geometry::Curve(c) => format!(
            "curve {}D, degree {}, {} control points{}",
            c.dim(),
            c.degree(),
            c.n_points(),
            if c.weights().is_some() { ", rational" } else { "" }
        ),
        Geometry::Surface(sf) => format!(
            "surface, degree {}x{}, {}x{} control points{}",
            sf.degree_u(),
            sf.degree_v(),
            sf.nu(),
            sf.nv(),
            if sf.weights().is_some() { ", rational" } else { "" }
        ),
    };
    if let Some(i) = info {
        s.push_str(&format!(", entity {}", i.entity));
        if !i.label.is_empty() {
            s.push_str(&format!(", label {}", i.label));
        }
    }
    s
}

/// Frames drawn before `--export-png` takes its screenshot (first layout, view fit, preview).
const EXPORT_SETTLE_FRAMES: u32 = 5;

/// State of `--export-png PATH` (export once laid out, then quit).
#[derive(Debug, Clone)]
pub struct ExportThenQuit {
    path: PathBuf,
    frames: u32,
    started: bool,
}

/// A PNG export waiting for its screenshot.
#[derive(Debug)]
pub struct PngExport {
    /// Where to write.
    pub path: PathBuf,
    /// Frames to wait before asking for the screenshot (so the menu that
    /// started the export has closed).
    wait: u8,
    /// Filled by the screenshot callback.
    shot: Option<Arc<Mutex<Option<Arc<ColorImage>>>>>,
    /// The view's rectangle (points) and the scale at the time of the request.
    crop: egui::Rect,
    pixels_per_point: f32,
}

/// The pixels of `img` inside `rect` (points, scaled by `pixels_per_point`
/// and clamped to the image) as straight-alpha RGBA8 rows; the whole image
/// if the rectangle misses it. Returns (width, height, bytes).
pub fn crop_rgba(img: &ColorImage, rect: egui::Rect, pixels_per_point: f32) -> (u32, u32, Vec<u8>) {
    let [w, h] = img.size;
    let px = |v: f32, max: usize| ((v * pixels_per_point).round().max(0.0) as usize).min(max);
    let (mut x0, mut x1) = (px(rect.min.x, w), px(rect.max.x, w));
    let (mut y0, mut y1) = (px(rect.min.y, h), px(rect.max.y, h));
    if !rect.is_finite() || x1 <= x0 || y1 <= y0 {
        (x0, x1, y0, y1) = (0, w, 0, h);
    }
    let mut bytes = Vec::with_capacity((x1 - x0) * (y1 - y0) * 4);
    for row in y0..y1 {
        for c in &img.pixels[row * w + x0..row * w + x1] {
            bytes.extend_from_slice(&c.to_srgba_unmultiplied());
        }
    }
    ((x1 - x0) as u32, (y1 - y0) as u32, bytes)
}

/// Encode RGBA8 pixels as PNG and write them atomically to `path`.
pub fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> anyhow::Result<()> {
    use image::ImageEncoder;
    let mut buf = Vec::new();
    image::codecs::png::PngEncoder::new(&mut buf).write_image(rgba, width, height, image::ExtendedColorType::Rgba8)?;
    fairway::io::write_atomic(path, &buf)?;
    Ok(())
}

fn has_ext(path: &Path, ext: &str) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

impl App {
    /// Autosave into `dir` every [`AUTOSAVE_INTERVAL`] while the document is
    /// dirty; an autosave left there by a crashed session is offered for
    /// recovery (the "Restore unsaved work?" prompt).
    pub fn with_autosave(mut self, dir: impl Into<PathBuf>) -> Self {
        let a = Autosave::new(dir, AUTOSAVE_INTERVAL);
        match autosave::pending(a.dir()) {
            Ok(r) => self.recovery = r,
            Err(e) => {
                self.error = Some(format!(
                    "An autosave in {} could not be read ({e}); it will be replaced by the next autosave",
                    a.dir().display()
                ))
            }
        }
        self.autosave = Some(a);
        self
    }

    /// [`App::with_autosave`] in [`autosave_dir`], if one is known.
    pub fn with_default_autosave(self) -> Self {
        match autosave_dir() {
            Some(d) => self.with_autosave(d),
            None => self,
        }
    }

    /// Autosave the document if it is dirty and the interval has passed; remove
    /// this session's autosave once the document is clean again (saved, or
    /// back to its saved state). Called every frame with the current time.
    pub fn autosave_tick(&mut self, now: Instant) {
        if self.recovery.is_some() {
            return; // the previous session's autosave waits for the user's choice
        }
        let Some(mut a) = self.autosave.take() else { return };
        let (source, dirty) = (self.path.clone(), self.is_dirty());
        let result = if dirty {
            a.tick_scene(|| self.scene(), source.as_deref(), true, now)
                .map(|wrote| self.autosaved |= wrote)
        } else if self.autosaved {
            self.autosaved = false;
            a.clear()
        } else {
            Ok(())
        };
        self.autosave = Some(a);
        if let Err(e) = result {
            self.report_error(format!("Autosave failed: {e}"));
        }
    }

    /// Remove the autosave (clean exit, discard).
    pub fn clear_autosave(&mut self) {
        self.autosaved = false;
        if let Some(a) = self.autosave.as_mut()
            && let Err(e) = a.clear()
        {
            self.report_error(format!("Could not remove the autosave: {e}"));
        }
    }

    pub(crate) fn restore_autosave(&mut self) {
        let Some(r) = self.recovery.take() else { return };
        // the file as it is on disk, if any: the restored document is dirty against it
        let scene = fairway::io::Scene {
            objects: r.objects,
            unit: r.unit,
            view_plane: r.view_plane,
        };
        if scene.unit.is_some() || !crate::shell::is_plain_document(&scene) {
            let saved = r.source.as_deref().and_then(|p| fairway::io::load_scene(p).ok());
            if self.set_scene(scene, r.source, saved.map(|(s, _)| s)) {
                self.status = "Restored the autosaved document (not saved yet)".into();
            }
            return;
        }
        let saved = r.source.as_deref().and_then(|p| fairway::io::load(p).ok());
        if self.set_document(r.document, r.source, saved) {
            self.status = "Restored the autosaved document (not saved yet)".into();
        }
    }

    pub(crate) fn discard_autosave(&mut self) {
        self.recovery = None;
        self.clear_autosave();
        self.status = "Discarded the autosaved document".into();
    }

    /// The "Restore unsaved work?" prompt, while an autosave from a previous
    /// session waits.
    pub(crate) fn recovery_ui(&mut self, ui: &mut egui::Ui) {
        let Some(r) = &self.recovery else { return };
        let from = r
            .source
            .as_ref()
            .map_or("an untitled document".to_string(), |p| p.display().to_string());
        let ago = SystemTime::now()
            .duration_since(r.saved_at)
            .map_or(String::new(), |d| format!(" {} min ago", d.as_secs() / 60));
        egui::Modal::new(egui::Id::unique("recovery")).show(ui.ctx(), |ui| {
            ui.heading("Restore unsaved work?");
            ui.label(format!(
                "Fairway did not close normally. Unsaved work on {from} was autosaved{ago}."
            ));
            ui.horizontal(|ui| {
                if ui
                    .button("Restore")
                    .on_hover_text("Open the autosaved document (it stays unsaved until you save it)")
                    .clicked()
                {
                    self.push(Command::RestoreAutosave);
                }
                if ui
                    .button("Discard")
                    .on_hover_text("Delete the autosave and go on")
                    .clicked()
                {
                    self.push(Command::DiscardAutosave);
                }
            });
        });
    }

    /// Read an IGES or STEP file for opening (errors reported).
    fn read_interchange_for_open(&mut self, path: &Path) -> Option<InterchangeFile> {
        match fairway::io::read_interchange(path) {
            Ok(Some(f)) => Some(f),
            Ok(None) => {
                self.report_error(format!("Could not open {}: not an IGES or STEP file", path.display()));
                None
            }
            Err(e) => {
                self.report_error(format!("Could not open {}: {e}", path.display()));
                None
            }
        }
    }

    /// Show the picker of an IGES or STEP file, to import one of its objects as an untitled document.
    pub(crate) fn pick_one_object(&mut self, path: &Path) {
        if !is_interchange(path) {
            return self.report_error(format!(
                "{}: import one object reads IGES (.igs, .iges) and STEP (.stp, .step) files",
                path.display()
            ));
        }
        if let Some(file) = self.read_interchange_for_open(path) {
            if file.objects.is_empty() {
                return self.report_error(format!(
                    "Could not open {}: no B-spline curve or surface in it",
                    path.display()
                ));
            }
            self.object_pick = Some(ObjectPick {
                path: path.to_path_buf(),
                file,
            });
        }
    }

    /// Open an IGES or STEP file: all its objects as one document (the picker imports one of them:
    /// [`Command::ImportOne`]).
    pub(crate) fn open_interchange(&mut self, path: &Path) {
        let Some(file) = self.read_interchange_for_open(path) else {
            return;
        };
        match file.objects.len() {
            0 => self.report_error(format!(
                "Could not open {}: no B-spline curve or surface in it{}",
                path.display(),
                if file.notices.is_empty() {
                    String::new()
                } else {
                    format!(" ({})", file.notices.join("; "))
                }
            )),
            1 => {
                // a trimmed face keeps its bounds
                let scene = one_object(&file, 0);
                // keep the path only if saving back loses nothing else of the file
                let keep = file.notices.is_empty();
                if !self.set_scene(scene.clone(), keep.then(|| path.to_path_buf()), Some(scene)) {
                    return;
                }
                self.unit = file.unit;
                let mut msg = format!("Opened {}{}", path.display(), unit_note(file.unit));
                if !keep {
                    msg.push_str(&format!(
                        " ({} notices, e.g. {}; Save As to keep it)",
                        file.notices.len(),
                        file.notices[0]
                    ));
                }
                self.report_status(msg);
                self.push_recent(path.to_path_buf());
            }
            n => {
                // keep the path only if saving back loses nothing else of the file
                let keep = file.notices.is_empty();
                let notices = file.notices.clone();
                let unit = file.unit;
                let scene = fairway::io::Scene::from_interchange(file);
                if !self.set_scene(scene.clone(), keep.then(|| path.to_path_buf()), Some(scene)) {
                    return;
                }
                let mut msg = format!("Opened {}: {n} objects{}", path.display(), unit_note(unit));
                if !keep {
                    msg.push_str(&format!(
                        " ({} notices, e.g. {}; Save As to keep it)",
                        notices.len(),
                        notices[0]
                    ));
                }
                self.report_status(msg);
                self.push_recent(path.to_path_buf());
            }
        }
    }

    pub(crate) fn open_picked_object(&mut self, k: usize) {
        let Some(pick) = self.object_pick.take() else { return };
        if k >= pick.file.objects.len() {
            return;
        }
        // a trimmed face keeps its bounds
        let scene = one_object(&pick.file, k);
        // untitled: saving over the file would drop its other objects
        if !self.set_scene(scene.clone(), None, Some(scene)) {
            return;
        }
        self.unit = pick.file.unit;
        self.report_status(format!(
            "Imported object {} of {} from {}{} (untitled: Save As to keep it)",
            k + 1,
            pick.file.objects.len(),
            pick.path.display(),
            unit_note(pick.file.unit)
        ));
        self.push_recent(pick.path);
    }

    /// The object picker window of an IGES or STEP file.
    pub(crate) fn object_picker_ui(&mut self, ui: &mut egui::Ui) {
        let Some(pick) = &self.object_pick else { return };
        let mut chosen = None;
        let mut cancel = false;
        let name = pick
            .path
            .file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into_owned());
        egui::Window::new("Choose an object")
            .id(egui::Id::unique("iges_picker"))
            .collapsible(false)
            .show(ui.ctx(), |ui| {
                let f = &pick.file;
                ui.label(format!(
                    "{name} holds {} curves and surfaces{}:",
                    f.objects.len(),
                    unit_note(f.unit)
                ));
                egui::Grid::new("iges_objects").striped(true).show(ui, |ui| {
                    for (k, g) in f.objects.iter().enumerate() {
                        ui.label(format!("{}.", k + 1));
                        ui.label(describe_object(g, f.entities.get(k)));
                        if ui
                            .button(format!("Open object {}", k + 1))
                            .on_hover_text("Open this curve or surface (as an untitled document)")
                            .clicked()
                        {
                            chosen = Some(k);
                        }
                        ui.end_row();
                    }
                });
                if !f.notices.is_empty() {
                    ui.separator();
                    ui.label(format!("{} notices (skipped entities, conversions):", f.notices.len()));
                    egui::ScrollArea::vertical().max_height(120.0).show(ui, |ui| {
                        for n in &f.notices {
                            ui.weak(n.as_str());
                        }
                    });
                }
                ui.separator();
                if ui
                    .button("Cancel import")
                    .on_hover_text("Keep the open document")
                    .clicked()
                {
                    cancel = true;
                }
            });
        if let Some(k) = chosen {
            self.push(Command::OpenPickedObject(k));
        } else if cancel {
            self.object_pick = None;
        }
    }

    /// The SVG drawing of what the canvas shows: the curve, and as the
    /// canvas draws them the control polygon, the comb, the tolerance band
    /// (when a region is selected) and the faired preview (when shown).
    /// The comb is the original's, scaled automatically. Refused (nothing to write) if a coordinate of
    /// the drawing is not a finite number.
    pub fn svg_text(&self) -> Result<String, String> {
        let opts = SvgOptions {
            control_polygon: self.prefs.show_polygon,
            comb: self.prefs.show_comb,
            band: self.region().map(|_| self.tolerance()),
            ..SvgOptions::default()
        };
        let faired = self
            .curve_ws
            .preview()
            .filter(|_| self.curve_ws.compare.show_after)
            .map(|p| &p.result.curve);
        try_curve_svg(self.curve(), faired, &opts).map_err(|e| e.to_string())
    }

    /// Write [`App::svg_text`] to `path` (which must end in `.svg`).
    pub fn export_svg(&mut self, path: &Path) {
        let res = if self.surface.is_some() {
            Err("SVG export draws curves; a surface is open".to_string())
        } else if !has_ext(path, "svg") {
            Err("the file name must end in .svg".to_string())
        } else {
            self.svg_text()
                .and_then(|text| fairway::io::write_atomic(path, text.as_bytes()).map_err(|e| e.to_string()))
        };
        match res {
            Ok(()) => self.report_status(format!("Exported {}", path.display())),
            Err(e) => self.report_error(format!("Could not export {}: {e}", path.display())),
        }
    }

    /// Start a PNG export of the current view to `path` (written a couple of
    /// frames later, when the screenshot arrives).
    pub(crate) fn start_png_export(&mut self, path: PathBuf) {
        if !has_ext(&path, "png") {
            return self.report_error(format!(
                "Could not export {}: the file name must end in .png",
                path.display()
            ));
        }
        self.report_status(format!("Exporting {}...", path.display()));
        self.png_export = Some(PngExport {
            path,
            wait: 1,
            shot: None,
            crop: egui::Rect::NOTHING,
            pixels_per_point: 1.0,
        });
    }

    /// Drive a PNG export: ask for the screenshot once the menu has closed,
    /// then crop it to the view and write it.
    fn poll_png_export(&mut self, ctx: &egui::Context) {
        let view = self.view_rect;
        let Some(x) = self.png_export.as_mut() else { return };
        let image = match &x.shot {
            None if x.wait > 0 => {
                x.wait -= 1;
                ctx.request_repaint();
                return;
            }
            None => {
                let slot = Arc::new(Mutex::new(None));
                let (s2, c2) = (slot.clone(), ctx.clone());
                ctx.request_screenshot(move |img| {
                    *s2.lock().unwrap_or_else(|p| p.into_inner()) = Some(img);
                    c2.request_repaint();
                });
                x.shot = Some(slot);
                x.crop = view;
                x.pixels_per_point = ctx.pixels_per_point();
                return;
            }
            Some(slot) => slot.lock().unwrap_or_else(|p| p.into_inner()).take(),
        };
        let Some(img) = image else { return };
        let Some(x) = self.png_export.take() else { return };
        let (w, h, rgba) = crop_rgba(&img, x.crop, x.pixels_per_point);
        match write_png(&x.path, w, h, &rgba) {
            Ok(()) => self.report_status(format!("Exported {} ({w}x{h})", x.path.display())),
            Err(e) => self.report_error(format!("Could not export {}: {e}", x.path.display())),
        }
    }

    /// Work at the end of every frame: PNG export and autosave.
    pub(crate) fn after_frame(&mut self, ui: &egui::Ui) {
        self.poll_png_export(ui.ctx());
        self.drive_export_then_quit(ui.ctx());
        self.autosave_tick(Instant::now());
    }

    /// `--export-png PATH`: write the view to `PATH` once the first frames are
    /// laid out, then close (the curve's view is cropped to the canvas; the
    /// surface workspace is written whole).
    pub fn export_png_then_quit(&mut self, path: PathBuf) {
        self.export_then_quit = Some(ExportThenQuit {
            path,
            frames: 0,
            started: false,
        });
    }

    fn drive_export_then_quit(&mut self, ctx: &egui::Context) {
        let computing = self.is_computing();
        let Some(x) = self.export_then_quit.as_mut() else {
            return;
        };
        if !x.started {
            if computing {
                // the preview's full fair (or a network fair) runs in the background: the export waits
                // for it (its end asks for a frame), without spinning frames that take its CPU, then
                // lets the layout settle again (the measures change the side panel's width)
                x.frames = 0;
                ctx.request_repaint_after(std::time::Duration::from_millis(200));
                return;
            }
            x.frames += 1;
            ctx.request_repaint();
            if x.frames >= EXPORT_SETTLE_FRAMES {
                x.started = true;
                let p = x.path.clone();
                self.start_png_export(p);
            }
        } else if self.png_export.is_none() {
            self.export_then_quit = None;
            match &self.error {
                Some(e) => eprintln!("fairway-editor: {e}"),
                None => eprintln!("fairway-editor: {}", self.status),
            }
            self.allow_close();
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }

    fn export_name(&self, ext: &str) -> String {
        let stem = self
            .path
            .as_ref()
            .and_then(|p| p.file_stem())
            .map_or("curve".into(), |s| s.to_string_lossy().into_owned());
        format!("{stem}.{ext}")
    }

    /// File menu: export through a file dialog.
    pub(crate) fn export_menu_ui(&mut self, ui: &mut egui::Ui) {
        if ui
            .button("Export SVG…")
            .on_hover_text("Write what the canvas shows (curve, polygon, comb, band, faired curve) as SVG")
            .clicked()
        {
            ui.close();
            let name = self.export_name("svg");
            if let Some(p) = self.pick_path(Some(&name), "SVG drawing", &["svg"]) {
                self.push(Command::ExportSvg(p));
            }
        }
        if ui
            .button("Export PNG…")
            .on_hover_text("Write the current view (canvas or 3D view) as a PNG image")
            .clicked()
        {
            ui.close();
            let name = self.export_name("png");
            if let Some(p) = self.pick_path(Some(&name), "PNG image", &["png"]) {
                self.push(Command::ExportPng(p));
            }
        }
    }

    /// File menu: export to the typed path (when no dialog is available).
    pub(crate) fn export_path_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            let p = PathBuf::from(self.path_input.trim());
            if ui
                .button("Export SVG to path")
                .on_hover_text("Export the canvas as SVG to the typed path (.svg)")
                .clicked()
            {
                self.push(Command::ExportSvg(p.clone()));
                ui.close();
            }
            if ui
                .button("Export PNG to path")
                .on_hover_text("Export the current view as PNG to the typed path (.png)")
                .clicked()
            {
                self.push(Command::ExportPng(p));
                ui.close();
            }
        });
    }
}
