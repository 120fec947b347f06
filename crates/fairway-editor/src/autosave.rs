//! Autosave and crash recovery of the open document, for the editor (kept
//! here, free of any UI, so it can be tested without a window).
//!
//! While a document is dirty, [`Autosave::tick`] writes it every
//! `interval` to `<dir>/autosave.ron` (atomically, with [`fairway::io::write_atomic`])
//! next to `<dir>/autosave.meta` (one line per field: the process id, the
//! document's own path if it has one, the time in seconds since 1970). A
//! successful save, a deliberate discard, or a clean exit calls
//! [`Autosave::clear`], which removes both. So an autosave found at start-up
//! ([`pending`]) means the previous session ended without clearing it — a
//! crash or `kill -9` — and the editor offers to restore it. An autosave
//! whose process is still running (another open editor, checked on Linux via
//! `/proc/<pid>`) is not offered.
//!
//! The folder is injectable (tests use a temporary one); [`default_dir`]
//! gives the platform's application data folder.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

use fairway::io::{Document, Scene, SceneObject, Unit};
use fairway::{Error, Result};

const DOC: &str = "autosave.ron";
const META: &str = "autosave.meta";

/// The platform's application data folder for Fairway: `$XDG_DATA_HOME/fairway`
/// or `~/.local/share/fairway` (Linux), `%APPDATA%\Fairway` (Windows),
/// `~/Library/Application Support/Fairway` (macOS). `None` if no home is known.
pub fn default_dir() -> Option<PathBuf> {
    let env = |k: &str| std::env::var_os(k).filter(|v| !v.is_empty()).map(PathBuf::from);
    if cfg!(windows) {
        return env("APPDATA").map(|d| d.join("Fairway"));
    }
    if cfg!(target_os = "macos") {
        return env("HOME").map(|h| h.join("Library/Application Support/Fairway"));
    }
    env("XDG_DATA_HOME")
        .map(|d| d.join("fairway"))
        .or_else(|| env("HOME").map(|h| h.join(".local/share/fairway")))
}

/// A document found at start-up that a previous session autosaved and never cleared.
#[derive(Debug, Clone, PartialEq)]
pub struct Recovery {
    /// The autosaved document (its first curve, else its first object, of several).
    pub document: Document,
    /// Every object of the autosaved document, with its name and settings.
    pub objects: Vec<SceneObject>,
    /// The length unit of the document's file, if it had one.
    pub unit: Option<Unit>,
    /// The plane 3D curves were drawn on.
    pub view_plane: fairway::io::ViewPlane,
    /// The file the document was opened from or saved to, if any.
    pub source: Option<PathBuf>,
    /// When it was autosaved.
    pub saved_at: SystemTime,
}

/// Periodic autosave of one open document into a folder.
#[derive(Debug, Clone)]
pub struct Autosave {
    dir: PathBuf,
    interval: Duration,
    last: Option<Instant>,
}

impl Autosave {
    /// Autosave into `dir` (created when first needed) every `interval` while dirty.
    pub fn new(dir: impl Into<PathBuf>, interval: Duration) -> Self {
        Self {
            dir: dir.into(),
            interval,
            last: None,
        }
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Call every frame (cheap when nothing is due): writes the document if
    /// it is dirty and `interval` has passed since the last autosave (or
    /// none was written yet). Returns whether it wrote.
    pub fn tick(&mut self, doc: &Document, source: Option<&Path>, dirty: bool, now: Instant) -> Result<bool> {
        self.tick_scene(|| Scene::from(doc.clone()), source, dirty, now)
    }

    /// [`Autosave::tick`] for a document of several objects (`scene` is called only when writing).
    pub fn tick_scene(
        &mut self,
        scene: impl FnOnce() -> Scene,
        source: Option<&Path>,
        dirty: bool,
        now: Instant,
    ) -> Result<bool> {
        if !dirty
            || self
                .last
                .is_some_and(|t| now.saturating_duration_since(t) < self.interval)
        {
            return Ok(false);
        }
        // count the attempt even if it fails, so a broken folder is not retried every frame
        self.last = Some(now);
        self.write_scene(&scene(), source)?;
        Ok(true)
    }

    /// Write the autosave now.
    pub fn write(&self, doc: &Document, source: Option<&Path>) -> Result<()> {
        self.write_scene(&Scene::from(doc.clone()), source)
    }

    /// Write the autosave of a document of several objects now: a RON document of version 1 for one
    /// unnamed object without a unit or a trim on the XY plane (as before), else of version 2 (every object,
    /// named, the unit, the view plane).
    pub fn write_scene(&self, scene: &Scene, source: Option<&Path>) -> Result<()> {
        std::fs::create_dir_all(&self.dir).map_err(|e| Error::Io {
            path: self.dir.display().to_string(),
            message: e.to_string(),
        })?;
        let text = match scene.objects.as_slice() {
            [one]
                if one.name.is_empty()
                    && one.trim.is_none()
                    && scene.unit.is_none()
                    && scene.view_plane == Default::default() =>
            {
                Document {
                    geometry: one.geometry.clone(),
                    settings: one.settings.clone(),
                }
                .to_ron()?
            }
            _ => scene.to_ron()?,
        };
        fairway::io::write_atomic(&self.dir.join(DOC), text.as_bytes())?;
        let secs = SystemTime::now()
            .duration_since(SystemTime::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        let meta = format!(
            "pid {}\nsource {}\ntime {secs}\n",
            std::process::id(),
            source.map_or(String::new(), |p| p.display().to_string())
        );
        fairway::io::write_atomic(&self.dir.join(META), meta.as_bytes())
    }

    /// Remove the autosave (after a save, a discard, or on a clean exit).
    pub fn clear(&mut self) -> Result<()> {
        self.last = None;
        for f in [DOC, META] {
            match std::fs::remove_file(self.dir.join(f)) {
                Ok(()) => {}
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                Err(e) => {
                    return Err(Error::Io {
                        path: self.dir.join(f).display().to_string(),
                        message: e.to_string(),
                    });
                }
            }
        }
        Ok(())
    }
}

fn process_alive(pid: u32) -> bool {
    pid == std::process::id() || (cfg!(target_os = "linux") && Path::new(&format!("/proc/{pid}")).exists())
}

/// At start-up: the autosave a crashed session left in `dir`, if any. An
/// autosave of a process that is still running is not returned; an
/// unreadable one is an error (the editor reports it and can discard it
/// with [`Autosave::clear`]).
pub fn pending(dir: &Path) -> Result<Option<Recovery>> {
    let doc_path = dir.join(DOC);
    if !doc_path.exists() {
        return Ok(None);
    }
    let meta = std::fs::read_to_string(dir.join(META)).unwrap_or_default();
    let field = |k: &str| {
        meta.lines()
            .find_map(|l| l.strip_prefix(k).and_then(|r| r.strip_prefix(' ')))
            .map(str::to_string)
    };
    if let Some(pid) = field("pid").and_then(|p| p.parse::<u32>().ok())
        && pid != std::process::id()
        && process_alive(pid)
    {
        return Ok(None);
    }
    let scene = Scene::from_ron(&fairway::io::read_text(&doc_path)?)?;
    let first = scene
        .objects
        .iter()
        .find(|o| o.geometry.as_curve().is_some())
        .or(scene.objects.first())
        .ok_or_else(|| Error::InvalidInput("the autosave holds no object".into()))?;
    let document = Document {
        geometry: first.geometry.clone(),
        settings: first.settings.clone(),
    };
    let source = field("source").filter(|s| !s.is_empty()).map(PathBuf::from);
    let saved_at = field("time")
        .and_then(|t| t.parse::<u64>().ok())
        .map_or(SystemTime::UNIX_EPOCH, |s| {
            SystemTime::UNIX_EPOCH + Duration::from_secs(s)
        });
    Ok(Some(Recovery {
        document,
        objects: scene.objects,
        unit: scene.unit,
        view_plane: scene.view_plane,
        source,
        saved_at,
    }))
}
