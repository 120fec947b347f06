//! Fairway's own document, in RON: the geometry plus the editor state that
//! belongs to the work (region, tolerance, target edits), versioned.
//!
//! ```ron
//! (format: "fairway", version: 1, geometry: Curve((degree: 3, knots: [...], points: [...])),
//!  settings: (tolerance: Some(0.01), region: Some((0.2, 0.6))))
//! ```
//! Unknown fields are rejected; fields missing in older versions take their
//! defaults.

use serde::{Deserialize, Serialize};

use super::record::GeometryRecord;
use crate::error::{Error, Result};
use crate::geometry::Geometry;

/// The current document version.
pub const DOCUMENT_VERSION: u32 = 1;

/// Editor state saved with the geometry. Every field is optional so older
/// files keep loading.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct DocumentSettings {
    /// Tolerance band width m, model units.
    pub tolerance: Option<f64>,
    /// Curve region `[u1, u2]`.
    pub region: Option<(f64, f64)>,
    /// Surface region `[u1, u2] × [v1, v2]`.
    pub region_uv: Option<((f64, f64), (f64, f64))>,
    /// Hand-edited target curvature values over the region (arc-length samples).
    pub target: Option<Vec<f64>>,
    /// Pinned target samples (indices into `target`).
    pub pinned: Vec<usize>,
}

/// A Fairway document.
#[derive(Debug, Clone, PartialEq)]
pub struct Document {
    /// The geometry.
    pub geometry: Geometry,
    /// Saved editor state.
    pub settings: DocumentSettings,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct DocumentFile {
    format: String,
    version: u32,
    geometry: GeometryRecord,
    #[serde(default)]
    settings: DocumentSettings,
}

impl Document {
    /// A document holding `geometry` with default settings.
    pub fn new(geometry: Geometry) -> Self {
        Self {
            geometry,
            settings: DocumentSettings::default(),
        }
    }

    /// Parse and validate a RON document.
    pub fn from_ron(text: &str) -> Result<Self> {
        let perr = |m: String| Error::Parse {
            format: "RON".into(),
            message: m,
        };
        if text.trim().is_empty() {
            return Err(perr("the file is empty".into()));
        }
        let f: DocumentFile = ron::from_str(text).map_err(|e| perr(e.to_string()))?;
        if f.format != "fairway" {
            return Err(perr(format!("format is {:?}, expected \"fairway\"", f.format)));
        }
        if f.version == 0 || f.version > DOCUMENT_VERSION {
            return Err(perr(format!(
                "document version {} is not supported (this Fairway reads 1 to {DOCUMENT_VERSION})",
                f.version
            )));
        }
        if let Some(t) = f.settings.tolerance
            && !(t.is_finite() && t > 0.0)
        {
            return Err(perr(format!("settings.tolerance: {t} must be a positive number")));
        }
        Ok(Self {
            geometry: f.geometry.try_into()?,
            settings: f.settings,
        })
    }

    /// The document as RON text.
    pub fn to_ron(&self) -> Result<String> {
        let f = DocumentFile {
            format: "fairway".into(),
            version: DOCUMENT_VERSION,
            geometry: (&self.geometry).into(),
            settings: self.settings.clone(),
        };
        let cfg = ron::ser::PrettyConfig::new().depth_limit(3).indentor(" ".to_string());
        let mut s = ron::ser::to_string_pretty(&f, cfg).map_err(|e| Error::Parse {
            format: "RON".into(),
            message: e.to_string(),
        })?;
        s.push('\n');
        Ok(s)
    }
}
