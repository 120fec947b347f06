//! Fairway's own document, in RON: the geometry plus the editor state that
//! belongs to the work (region, tolerance, target edits), versioned.
//!
//! ```ron
//! (format: "fairway", version: 1, geometry: Curve((degree: 3, knots: [...], points: [...])),
//!  settings: (tolerance: Some(0.01), region: Some((0.2, 0.6))))
//! ```
//! Version 2 holds several named objects, each with its own settings, and the length unit of the file
//! they came from ([`super::scene::Scene`]):
//! ```ron
//! (format: "fairway", version: 2, unit: Some("mm"), objects: [
//!   (name: "sheer", geometry: Curve((...)), settings: (tolerance: Some(0.01))),
//!   (name: "deck", geometry: Surface((...))),
//! ])
//! ```
//! A [`Document`] is one object: it reads version 1 and a version 2 file holding one object, and writes
//! version 1 (which every Fairway reads). Unknown fields are rejected; fields missing in older versions
//! take their defaults.

use serde::{Deserialize, Serialize};

use super::record::GeometryRecord;
use crate::error::{Error, Result};
use crate::geometry::Geometry;

/// The newest document version this Fairway reads and writes (2: several named objects).
pub const DOCUMENT_VERSION: u32 = 2;

/// The version of a single-object document ([`Document::to_ron`]).
pub const SINGLE_OBJECT_VERSION: u32 = 1;

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
    /// The curve parameter of each `target` value, in order along the region: with it the target (and its
    /// pins, at these parameters) is resampled onto whatever samples the region has when it is reopened
    /// ([`crate::fair::CurveFairing::set_target_at`]); without it (older files) the values fit only the
    /// samples they were made on.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub target_params: Option<Vec<f64>>,
    /// Continuity at the start and the end of the curve region (`None`: the editor's default, G2).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ends: Option<[crate::fair::EndCondition; 2]>,
}

/// A Fairway document.
#[derive(Debug, Clone, PartialEq)]
pub struct Document {
    /// The geometry.
    pub geometry: Geometry,
    /// Saved editor state.
    pub settings: DocumentSettings,
}

/// A version 1 file: one geometry and its settings.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct DocumentFile {
    pub(crate) format: String,
    pub(crate) version: u32,
    pub(crate) geometry: GeometryRecord,
    #[serde(default)]
    pub(crate) settings: DocumentSettings,
}

/// A version 2 file: named objects and the length unit of the file they came from.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SceneFile {
    pub(crate) format: String,
    pub(crate) version: u32,
    #[serde(default)]
    pub(crate) unit: Option<String>,
    /// The editor's view plane for 3D curves (optional: XY when absent, and not written then).
    #[serde(default, skip_serializing_if = "super::scene::ViewPlane::is_xy")]
    pub(crate) view_plane: super::scene::ViewPlane,
    pub(crate) objects: Vec<ObjectFile>,
}

/// One object of a version 2 file.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ObjectFile {
    #[serde(default)]
    pub(crate) name: String,
    pub(crate) geometry: GeometryRecord,
    #[serde(default)]
    pub(crate) settings: DocumentSettings,
    /// A trimmed face's loops in its surface's (u, v).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) trim: Option<Vec<super::record::TrimLoopRecord>>,
}

/// The header every version has (the rest is read by the version's own struct).
#[derive(Deserialize)]
struct Header {
    format: String,
    version: u32,
}

/// A document file of either version.
pub(crate) enum AnyFile {
    /// Version 1.
    One(Box<DocumentFile>),
    /// Version 2.
    Scene(SceneFile),
}

/// A parse error of a RON document.
pub(crate) fn ron_error(m: impl Into<String>) -> Error {
    Error::Parse {
        format: "RON".into(),
        message: m.into(),
    }
}

/// Check a settings block: a saved tolerance must be a positive number.
pub(crate) fn check_settings(st: &DocumentSettings, what: &str) -> Result<()> {
    match st.tolerance {
        Some(t) if !(t.is_finite() && t > 0.0) => Err(ron_error(format!(
            "{what}settings.tolerance: {t} must be a positive number"
        ))),
        _ => Ok(()),
    }
}

/// Parse the RON text of any version: the header first (format, version in 1..=[`DOCUMENT_VERSION`]),
/// then the fields of its version.
pub(crate) fn parse_file(text: &str) -> Result<AnyFile> {
    if let Some(m) = super::blank_text_message(text.as_bytes()) {
        return Err(ron_error(m));
    }
    let h: Header = ron::from_str(text).map_err(|e| ron_error(e.to_string()))?;
    if h.format != "fairway" {
        return Err(ron_error(format!("format is {:?}, expected \"fairway\"", h.format)));
    }
    match h.version {
        1 => Ok(AnyFile::One(Box::new(
            ron::from_str(text).map_err(|e| ron_error(e.to_string()))?,
        ))),
        2 => Ok(AnyFile::Scene(
            ron::from_str(text).map_err(|e| ron_error(e.to_string()))?,
        )),
        v => Err(ron_error(format!(
            "document version {v} is not supported (this Fairway reads 1 to {DOCUMENT_VERSION})"
        ))),
    }
}

/// A document file as pretty RON text, ending in a newline.
pub(crate) fn write_ron(f: &impl Serialize) -> Result<String> {
    let cfg = ron::ser::PrettyConfig::new().depth_limit(3).indentor(" ".to_string());
    let mut s = ron::ser::to_string_pretty(f, cfg).map_err(|e| ron_error(e.to_string()))?;
    s.push('\n');
    Ok(s)
}

impl Document {
    /// A document holding `geometry` with default settings.
    pub fn new(geometry: Geometry) -> Self {
        Self {
            geometry,
            settings: DocumentSettings::default(),
        }
    }

    /// Parse and validate a RON document: version 1, or a version 2 document holding one object (one
    /// with several is refused with the count: read it as a [`super::scene::Scene`]).
    pub fn from_ron(text: &str) -> Result<Self> {
        let (geometry, settings) = match parse_file(text)? {
            AnyFile::One(f) => (f.geometry, f.settings),
            AnyFile::Scene(mut f) if f.objects.len() == 1 => {
                let o = f.objects.remove(0);
                (o.geometry, o.settings)
            }
            AnyFile::Scene(f) => {
                return Err(ron_error(format!(
                    "the document holds {} objects, not one: open it as a scene (`fairway::io::Scene`; \
                     `fairway info` and `fairway fair` read every object)",
                    f.objects.len()
                )));
            }
        };
        check_settings(&settings, "")?;
        let geometry: Geometry = geometry.try_into()?;
        crate::range::check_geometry(&geometry)?;
        Ok(Self { geometry, settings })
    }

    /// The document as RON text (version [`SINGLE_OBJECT_VERSION`]).
    pub fn to_ron(&self) -> Result<String> {
        let f = DocumentFile {
            format: "fairway".into(),
            version: SINGLE_OBJECT_VERSION,
            geometry: (&self.geometry).into(),
            settings: self.settings.clone(),
        };
        write_ron(&f)
    }

    /// Make the saved settings fit the geometry, and say what had to change: one message per
    /// setting dropped or reordered, empty when everything fits. A hand-edited or corrupted file
    /// keeps its geometry (nothing is lost); only the settings that cannot apply go:
    /// - a curve region with a non-finite end, equal ends or an end outside the curve's domain is
    ///   dropped; `u1 > u2` is kept on a closed curve (a region across the seam) and reordered on an
    ///   open one;
    /// - a surface region likewise per direction (ends reordered when given backwards);
    /// - a region of the other kind (a curve region on a surface, or the reverse) is dropped;
    /// - a target with a non-finite value is dropped, with its pins;
    /// - target parameters that do not match the target (count, finite) are dropped.
    pub fn sanitize_settings(&mut self) -> Vec<String> {
        let mut notes = Vec::new();
        let st = &mut self.settings;
        // ends outside the domain by more than rounding are errors (1e-12 of the domain length)
        let fits = |r: (f64, f64), d: (f64, f64), what: &str| -> std::result::Result<(), String> {
            let eps = 1e-12 * (d.1 - d.0);
            if !(r.0.is_finite() && r.1.is_finite()) {
                Err(format!("the saved {what} ({}, {}) is not finite", r.0, r.1))
            } else if r.0 == r.1 {
                Err(format!("the saved {what} ({}, {}) is empty", r.0, r.1))
            } else if [r.0, r.1].iter().any(|&u| u < d.0 - eps || u > d.1 + eps) {
                Err(format!(
                    "the saved {what} ({}, {}) is outside the domain [{}, {}]",
                    r.0, r.1, d.0, d.1
                ))
            } else {
                Ok(())
            }
        };
        let clamp = |r: (f64, f64), d: (f64, f64)| (r.0.clamp(d.0, d.1), r.1.clamp(d.0, d.1));
        match &self.geometry {
            Geometry::Curve(c) => {
                if let Some(r) = st.region {
                    let d = c.domain();
                    match fits(r, d, "region") {
                        Err(e) => {
                            notes.push(format!("{e}: ignored"));
                            st.region = None;
                        }
                        Ok(()) => {
                            let r = clamp(r, d);
                            st.region = Some(if r.0 > r.1 && !crate::fair::closed::is_closed_curve(c) {
                                notes.push(format!(
                                    "the saved region ({}, {}) runs backwards on an open curve: read as ({}, {})",
                                    r.0, r.1, r.1, r.0
                                ));
                                (r.1, r.0)
                            } else {
                                r
                            });
                        }
                    }
                }
                if st.region_uv.take().is_some() {
                    notes.push("the saved surface region does not apply to a curve: ignored".into());
                }
            }
            Geometry::Surface(s) => {
                if let Some((ru, rv)) = st.region_uv {
                    let (du, dv) = s.domain();
                    let order = |r: (f64, f64)| if r.0 > r.1 { (r.1, r.0) } else { r };
                    match fits(ru, du, "surface region in u").and(fits(rv, dv, "surface region in v")) {
                        Err(e) => {
                            notes.push(format!("{e}: ignored"));
                            st.region_uv = None;
                        }
                        Ok(()) => {
                            let (u, v) = (order(clamp(ru, du)), order(clamp(rv, dv)));
                            if (u, v) != (ru, rv) && (ru.0 > ru.1 || rv.0 > rv.1) {
                                notes.push(format!(
                                    "the saved surface region had its ends backwards: read as u ({}, {}), v ({}, {})",
                                    u.0, u.1, v.0, v.1
                                ));
                            }
                            st.region_uv = Some((u, v));
                        }
                    }
                }
                if st.region.take().is_some() {
                    notes.push("the saved curve region does not apply to a surface: ignored".into());
                }
            }
        }
        if let Some(t) = &st.target
            && let Some(k) = t.iter().position(|g| !g.is_finite())
        {
            notes.push(format!(
                "the saved target curvature has a non-finite value ({}) at sample {k}: the target and its pins are ignored",
                t[k]
            ));
            st.target = None;
            st.pinned.clear();
        }
        if let Some(at) = &st.target_params {
            let why = if st.target.as_ref().is_none_or(|t| t.len() != at.len()) {
                Some("does not have one parameter per target value")
            } else if at.iter().any(|u| !u.is_finite()) {
                Some("has a non-finite value")
            } else {
                None
            };
            if let Some(why) = why {
                notes.push(format!(
                    "the saved target's parameter list {why}: the target applies only to the samples it was made on"
                ));
                st.target_params = None;
            }
        }
        notes
    }
}
