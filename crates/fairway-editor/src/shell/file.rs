//! The shell's file operations: open (a curve or a surface, IGES and STEP through the picker), save and save
//! as (atomic, by the core's `io::save_in`, in the file's unit), the unsaved-work check, the file dialogs, dropped files,
//! recent files and the window title.

use std::path::{Path, PathBuf};

use eframe::egui;
use fairway::io::Document;

use crate::{App, Command, Pending, interchange};

/// Whether a native file dialog can run: rfd's portal backend needs a session bus.
pub fn dialog_available() -> bool {
    std::env::var_os("DBUS_SESSION_BUS_ADDRESS").is_some()
}

impl App {
    /// Load `path` now, replacing the document (no unsaved check). Errors go to [`App::error`] and
    /// leave the open document untouched.
    pub fn open_now(&mut self, path: &Path) {
        if interchange::is_interchange(path) {
            self.open_interchange(path);
            return;
        }
        if fairway::io::Format::from_path(path).is_ok_and(|f| f == fairway::io::Format::Ron)
            && self.open_ron_scene(path)
        {
            return;
        }
        match fairway::io::load(path) {
            Ok(doc) => {
                if self.set_document(doc.clone(), Some(path.to_path_buf()), Some(doc)) {
                    self.status = format!("Opened {}", path.display());
                    self.push_recent(path.to_path_buf());
                }
            }
            Err(e) => self.error = Some(format!("Could not open {}: {e}", path.display())),
        }
    }

    /// Replace the open document by `doc` (a curve opens the curve workspace, a surface the surface
    /// workspace); `saved` is its state on disk (`None`: never saved, so it shows as unsaved). False
    /// (with the error shown) if the surface could not be shown.
    pub fn set_document(&mut self, doc: Document, path: Option<PathBuf>, saved: Option<Document>) -> bool {
        self.set_scene(doc.into(), path, saved.map(Into::into))
    }

    /// Open a RON document of version 2 with several objects (or one named object, or a view plane) as
    /// one document; false if `path` is not one (the caller then opens it as one object).
    fn open_ron_scene(&mut self, path: &Path) -> bool {
        let Ok((scene, _)) = fairway::io::load_scene(path) else {
            return false;
        };
        if is_plain_document(&scene) {
            return false;
        }
        let n = scene.objects.len();
        if self.set_scene(scene.clone(), Some(path.to_path_buf()), Some(scene)) {
            self.status = format!("Opened {} ({n} objects)", path.display());
            self.push_recent(path.to_path_buf());
        }
        true
    }

    pub(crate) fn push_recent(&mut self, p: PathBuf) {
        let p = std::fs::canonicalize(&p).unwrap_or(p);
        self.prefs.recent.retain(|q| q != &p);
        self.prefs.recent.insert(0, p);
        self.prefs.recent.truncate(10);
    }

    /// Save to `path`: a document of one unnamed object on the XY plane as before (`io::save_in`), else
    /// every object in order with its name and the view plane (`io::save_scene`), in the file's unit.
    pub(crate) fn save_now(&mut self, path: &Path) {
        let scene = self.scene();
        let res = if is_plain_document(&scene) {
            fairway::io::save_in(path, &self.doc, self.unit)
        } else {
            fairway::io::save_scene(path, &scene)
        };
        match res {
            Ok(()) => {
                self.saved = Some(scene);
                self.path = Some(std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf()));
                self.path_input = path.display().to_string();
                self.status = format!("Saved {}", path.display());
                self.push_recent(path.to_path_buf());
            }
            Err(e) => self.error = Some(format!("Could not save {}: {e}", path.display())),
        }
    }

    /// Ask before `p` if there is unsaved work, else do it.
    pub(crate) fn request(&mut self, p: Pending) {
        if self.is_dirty() {
            self.confirm = Some(p);
        } else {
            self.do_pending(p);
        }
    }

    pub(crate) fn do_pending(&mut self, p: Pending) {
        match p {
            Pending::Open(path) => self.push(Command::Open(path)),
            Pending::OpenDialog => {
                if let Some(path) = self.pick_file(false) {
                    self.push(Command::Open(path));
                }
            }
            Pending::ImportOne(path) => self.push(Command::ImportOne(path)),
            Pending::Quit => self.allow_close(),
        }
    }

    /// A native file dialog for documents, or `None` with a message when none can run.
    fn pick_file(&mut self, save: bool) -> Option<PathBuf> {
        let default_name = self
            .path
            .as_ref()
            .and_then(|p| p.file_name())
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| {
                if self.surface.is_some() {
                    "surface.ron"
                } else {
                    "curve.ron"
                }
                .into()
            });
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

    /// A native file dialog: a save dialog proposing `save_name`, or an open dialog when `None`;
    /// `None` with a message when no dialog can run.
    pub(crate) fn pick_path(&mut self, save_name: Option<&str>, what: &str, extensions: &[&str]) -> Option<PathBuf> {
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

    pub(crate) fn dropped_files(&mut self, ui: &egui::Ui) {
        let dropped: Vec<PathBuf> = ui.input(|i| i.raw.dropped_files.iter().map(|f| f.path().to_path_buf()).collect());
        if let Some(p) = dropped.into_iter().next() {
            self.request(Pending::Open(p));
        }
    }

    /// Save to the open file, or Save As without one.
    pub(crate) fn save(&mut self) {
        match self.path.clone() {
            Some(p) => self.save_now(&p),
            None => self.save_as(),
        }
    }

    /// Save under a name chosen in a dialog.
    pub(crate) fn save_as(&mut self) {
        if let Some(p) = self.pick_file(true) {
            self.save_now(&p);
        }
    }

    /// Window title: file name, an unsaved marker and the workspace.
    pub fn title(&self) -> String {
        let name = self
            .path
            .as_ref()
            .and_then(|p| p.file_name())
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "untitled".into());
        let suffix = match &self.surface {
            Some(s) => crate::Workspace::title_suffix(&**s),
            None => crate::Workspace::title_suffix(&self.curve_ws),
        };
        format!("{}{name} — Fairway{suffix}", if self.is_dirty() { "* " } else { "" })
    }
}

/// Whether `scene` is what a version 1 document holds: one unnamed object without a trim, drawn on the XY
/// plane (the view plane, names and trims need version 2, or IGES / STEP).
pub(crate) fn is_plain_document(scene: &fairway::io::Scene) -> bool {
    scene.objects.len() < 2
        && scene.objects.iter().all(|o| o.name.is_empty() && o.trim.is_none())
        && scene.view_plane == fairway::io::ViewPlane::Xy
}
