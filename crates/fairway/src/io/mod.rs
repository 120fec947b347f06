//! File formats: plain geometry JSON, Fairway's RON document, and file
//! helpers (format by extension, atomic writes).

pub mod document;
pub mod json;
pub mod record;

use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};
use crate::geometry::Geometry;

pub use document::{Document, DocumentSettings};

/// A file format known by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Plain geometry JSON (`.json`).
    Json,
    /// Fairway document (`.ron`, `.fairway`).
    Ron,
}

impl Format {
    /// The format of a path, from its extension.
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase());
        match ext.as_deref() {
            Some("json") => Ok(Format::Json),
            Some("ron") | Some("fairway") => Ok(Format::Ron),
            other => Err(Error::Parse {
                format: "file".into(),
                message: format!(
                    "{}: unknown extension {:?}; expected .json, .ron or .fairway",
                    path.display(),
                    other.unwrap_or("")
                ),
            }),
        }
    }
}

fn io_err(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// Read a text file into a string, with the path in the error.
pub fn read_text(path: &Path) -> Result<String> {
    std::fs::read_to_string(path).map_err(|e| io_err(path, e))
}

/// Read a document (JSON geometry or RON document) from a file.
pub fn load(path: &Path) -> Result<Document> {
    let text = read_text(path)?;
    match Format::from_path(path)? {
        Format::Json => Ok(Document::new(json::from_str(&text)?)),
        Format::Ron => Document::from_ron(&text),
    }
}

/// Read only the geometry of a file.
pub fn load_geometry(path: &Path) -> Result<Geometry> {
    Ok(load(path)?.geometry)
}

/// Write a document in the format of the path's extension, atomically.
pub fn save(path: &Path, doc: &Document) -> Result<()> {
    let text = match Format::from_path(path)? {
        Format::Json => json::to_string(&doc.geometry),
        Format::Ron => doc.to_ron()?,
    };
    write_atomic(path, text.as_bytes())
}

/// Write `bytes` to `path` atomically: a temporary file in the same folder,
/// flushed and synced, then renamed over the target. On failure the old file
/// is untouched and the temporary file removed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = path.file_name().ok_or_else(|| io_err(path, "not a file path"))?;
    let tmp = dir.join(format!(".{}.tmp{}", name.to_string_lossy(), std::process::id()));
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)?;
        if let Ok(d) = std::fs::File::open(&dir) {
            let _ = d.sync_all();
        }
        Ok(())
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(io_err(path, e));
    }
    Ok(())
}
