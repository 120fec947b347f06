//! File formats: plain geometry JSON, Fairway's RON document, IGES 5.3
//! (curves 126, surfaces 128), point lists (CSV / text, import only), SVG
//! (export only), and file helpers (format by extension, atomic writes).
//!
//! [`load`] and [`save`] pick the format from the extension. An IGES file
//! may hold several objects: [`load`] returns the first one, and
//! [`iges::read_all`] returns all of them with the list of skipped
//! entities. A point file is fitted by [`points::fit_points`] with
//! [`points::FitOptions::default`]; call it directly to choose the number of
//! control points, the degree and the parametrisation.

pub mod document;
pub mod iges;
pub mod json;
pub mod points;
pub mod record;
pub mod svg;

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
    /// IGES 5.3 fixed format (`.igs`, `.iges`).
    Iges,
    /// Points, one per line (`.csv`, `.txt`, `.xyz`); import only.
    Points,
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
            Some("igs") | Some("iges") => Ok(Format::Iges),
            Some("csv") | Some("txt") | Some("xyz") => Ok(Format::Points),
            other => Err(Error::Parse {
                format: "file".into(),
                message: format!(
                    "{}: unknown extension {:?}; expected .json, .ron, .fairway, .igs, .iges, .csv, .txt or .xyz",
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

/// Read a document from a file, the format from the extension: JSON
/// geometry, RON document, IGES (the first curve or surface; see
/// [`iges::read_all`] for all), or a point list (fitted with
/// [`points::FitOptions::default`]).
pub fn load(path: &Path) -> Result<Document> {
    let geometry = match Format::from_path(path)? {
        Format::Iges => {
            let bytes = std::fs::read(path).map_err(|e| io_err(path, e))?;
            iges::read_first(&bytes)?
        }
        Format::Json => json::from_str(&read_text(path)?)?,
        Format::Ron => return Document::from_ron(&read_text(path)?),
        Format::Points => {
            points::fit_points(&points::parse(&read_text(path)?)?, &points::FitOptions::default())?.into()
        }
    };
    Ok(Document::new(geometry))
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
        Format::Iges => iges::write(
            std::slice::from_ref(&doc.geometry),
            &iges::WriteOptions {
                file_name: path
                    .file_name()
                    .map_or("fairway.igs".into(), |n| n.to_string_lossy().into_owned()),
                ..Default::default()
            },
        ),
        Format::Points => {
            return Err(Error::InvalidInput(format!(
                "{}: point files (.csv, .txt, .xyz) are import only; save as .json, .ron or .igs",
                path.display()
            )));
        }
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
