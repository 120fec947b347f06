//! A scene: several named curves and surfaces in one document (RON version 2), as an IGES or STEP file
//! with many objects holds them. Read from any format ([`load_scene`]: RON of either version, JSON, IGES,
//! STEP, points) and written back ([`save_scene`]) in the same order with the same names: IGES labels
//! (directory field 18, 8 characters, and the subscript of field 19), STEP entity names.

use std::path::Path;

use super::document::{AnyFile, ObjectFile, SceneFile, check_settings, parse_file, ron_error, write_ron};
use super::interchange::{InterchangeFile, Unit};
use super::{Document, DocumentSettings, Format};
use crate::error::{Error, Result};
use crate::geometry::Geometry;

/// One object of a [`Scene`].
#[derive(Debug, Clone, PartialEq)]
pub struct SceneObject {
    /// Its name: an IGES label (with its subscript in parentheses), a STEP entity name, or given by
    /// hand; empty if none.
    pub name: String,
    /// The curve or surface.
    pub geometry: Geometry,
    /// Its own fairing settings (tolerance, region, target edits).
    pub settings: DocumentSettings,
    /// A trimmed face's bounds, in its surface's (u, v) (read from STEP or IGES, written back there).
    pub trim: Option<crate::trim::FaceTrim>,
}

/// The plane the editor draws 3D curves on in its 2D canvas, saved with a document (version 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum ViewPlane {
    /// x to the right, y up (2D curves live here); the default.
    #[default]
    #[serde(rename = "XY")]
    Xy,
    /// y to the right, z up.
    #[serde(rename = "YZ")]
    Yz,
    /// z to the right, x up.
    #[serde(rename = "ZX")]
    Zx,
    /// The plane that fits the curves' control points best (least squares), its longest extent to
    /// the right.
    BestFit,
}

impl ViewPlane {
    /// Every choice, in menu order.
    pub const ALL: [ViewPlane; 4] = [ViewPlane::Xy, ViewPlane::Yz, ViewPlane::Zx, ViewPlane::BestFit];

    /// Its name for people: "XY plane", ..., "Best-fit plane".
    pub fn name(self) -> &'static str {
        match self {
            ViewPlane::Xy => "XY plane",
            ViewPlane::Yz => "YZ plane",
            ViewPlane::Zx => "ZX plane",
            ViewPlane::BestFit => "Best-fit plane",
        }
    }

    /// Whether it is XY (the default, not written).
    pub(crate) fn is_xy(&self) -> bool {
        *self == ViewPlane::Xy
    }
}

/// Several named curves and surfaces, in order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Scene {
    /// The objects, in file order.
    pub objects: Vec<SceneObject>,
    /// The length unit of the file the objects came from (declared again when written as IGES/STEP).
    pub unit: Option<Unit>,
    /// The editor's view plane for 3D curves (RON only; XY when the file has none).
    pub view_plane: ViewPlane,
}

impl From<Document> for Scene {
    fn from(d: Document) -> Self {
        Scene {
            objects: vec![SceneObject {
                name: String::new(),
                trim: None,
                geometry: d.geometry,
                settings: d.settings,
            }],
            ..Default::default()
        }
    }
}

impl Scene {
    /// The objects of an IGES or STEP file, named by their labels, with the file's unit.
    pub fn from_interchange(f: InterchangeFile) -> Self {
        let mut trims = f.trims.into_iter();
        let objects = f
            .objects
            .into_iter()
            .zip(
                f.entities
                    .into_iter()
                    .map(|e| e.label)
                    .chain(std::iter::repeat(String::new())),
            )
            .map(|(geometry, name)| SceneObject {
                name,
                trim: trims.next().flatten(),
                geometry,
                settings: DocumentSettings::default(),
            })
            .collect();
        Scene {
            objects,
            unit: f.unit,
            ..Default::default()
        }
    }

    /// The geometries, in order.
    pub fn geometries(&self) -> Vec<Geometry> {
        self.objects.iter().map(|o| o.geometry.clone()).collect()
    }

    /// The names, in order.
    pub fn names(&self) -> Vec<String> {
        self.objects.iter().map(|o| o.name.clone()).collect()
    }

    /// The index of the object `key` names: its 0-based index, or its name (exact; an index wins).
    pub fn find(&self, key: &str) -> Option<usize> {
        match key.trim().parse::<usize>() {
            Ok(i) if i < self.objects.len() => Some(i),
            _ => self.objects.iter().position(|o| o.name == key),
        }
    }

    /// Parse and validate a RON document of either version (version 1: one unnamed object).
    pub fn from_ron(text: &str) -> Result<Self> {
        match parse_file(text)? {
            AnyFile::One(_) => Ok(Document::from_ron(text)?.into()),
            AnyFile::Scene(f) => {
                let unit = match &f.unit {
                    None => None,
                    Some(u) => Some(Unit::parse(u).ok_or_else(|| ron_error(format!("unknown unit {u:?}")))?),
                };
                let objects = f
                    .objects
                    .into_iter()
                    .enumerate()
                    .map(|(k, o)| {
                        check_settings(&o.settings, &format!("objects[{k}]."))?;
                        let geometry: Geometry = o.geometry.try_into()?;
                        crate::range::check_geometry(&geometry)?;
                        let trim = match (o.trim, &geometry) {
                            (None, _) => None,
                            (Some(t), Geometry::Surface(_)) => Some(
                                super::record::trim_from_records(t)
                                    .map_err(|e| ron_error(format!("objects[{k}].trim: {e}")))?,
                            ),
                            (Some(_), Geometry::Curve(_)) => {
                                return Err(ron_error(format!("objects[{k}].trim: a curve has no trim")));
                            }
                        };
                        Ok(SceneObject {
                            name: o.name,
                            trim,
                            geometry,
                            settings: o.settings,
                        })
                    })
                    .collect::<Result<Vec<_>>>()?;
                Ok(Scene {
                    objects,
                    unit,
                    view_plane: f.view_plane,
                })
            }
        }
    }

    /// The scene as RON text (version 2).
    pub fn to_ron(&self) -> Result<String> {
        let f = SceneFile {
            format: "fairway".into(),
            version: super::document::DOCUMENT_VERSION,
            unit: self.unit.map(|u| u.symbol().to_string()),
            view_plane: self.view_plane,
            objects: self
                .objects
                .iter()
                .map(|o| ObjectFile {
                    trim: o.trim.as_ref().map(super::record::trim_records),
                    name: o.name.clone(),
                    geometry: (&o.geometry).into(),
                    settings: o.settings.clone(),
                })
                .collect(),
        };
        write_ron(&f)
    }
}

/// Read every object of a file (the format from the extension) and the notices of an IGES or STEP
/// reader (skipped entities, conversions); RON of either version, JSON and point files give their one
/// object (a version 1 document unnamed).
pub fn load_scene(path: &Path) -> Result<(Scene, Vec<String>)> {
    match Format::from_path(path)? {
        Format::Ron => Ok((Scene::from_ron(&super::read_text(path)?)?, vec![])),
        Format::Iges | Format::Step => {
            let f =
                super::read_interchange(path)?.ok_or_else(|| Error::InvalidInput("not an interchange file".into()))?;
            if f.objects.is_empty() {
                return Err(Error::InvalidInput(format!(
                    "no B-spline curve or surface in the file{}",
                    if f.notices.is_empty() {
                        String::new()
                    } else {
                        format!(" ({})", f.notices.join("; "))
                    }
                )));
            }
            let notices = f.notices.clone();
            Ok((Scene::from_interchange(f), notices))
        }
        Format::Json | Format::Points => Ok((super::load(path)?.into(), vec![])),
    }
}

/// Write every object of `scene` in the format of the path's extension, atomically, in order: RON
/// version 2; IGES and STEP with the names as labels, the scene's unit (millimetres if it has none) and
/// each trimmed face with its bounds (IGES 144, STEP `ADVANCED_FACE`);
/// JSON holds one object only (refused with more).
pub fn save_scene(path: &Path, scene: &Scene) -> Result<()> {
    let unit = scene.unit.unwrap_or(Unit::Millimeter);
    let opts = super::WriteOptions::for_path(path, unit);
    let (objects, names) = (scene.geometries(), scene.names());
    let trims: Vec<Option<crate::trim::FaceTrim>> = scene.objects.iter().map(|o| o.trim.clone()).collect();
    let text = match Format::from_path(path)? {
        Format::Ron => scene.to_ron()?,
        Format::Json => match scene.objects.as_slice() {
            [one] => super::json::to_string(&one.geometry),
            _ => {
                return Err(Error::InvalidInput(format!(
                    "{}: a JSON geometry file holds one object and the scene has {}; save as .ron, .igs or .stp",
                    path.display(),
                    scene.objects.len()
                )));
            }
        },
        Format::Iges => super::iges::write_trimmed(&objects, &names, &trims, &opts),
        Format::Step => super::step::write_trimmed(&objects, &names, &trims, &opts),
        Format::Points => {
            return Err(Error::InvalidInput(format!(
                "{}: point files (.csv, .txt, .xyz) are import only; save as .ron, .igs or .stp",
                path.display()
            )));
        }
    };
    super::write_atomic(path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_indices_find_objects() {
        let c = crate::BSplineCurve::new_2d(1, vec![0.0, 0.0, 1.0, 1.0], &[glam::DVec2::ZERO, glam::DVec2::X]).unwrap();
        let obj = |n: &str| SceneObject {
            name: n.into(),
            trim: None,
            geometry: c.clone().into(),
            settings: DocumentSettings::default(),
        };
        let s = Scene {
            objects: vec![obj("a"), obj("7"), obj("b")],
            ..Default::default()
        };
        assert_eq!(s.find("1"), Some(1));
        assert_eq!(s.find("b"), Some(2));
        assert_eq!(s.find("7"), Some(1), "an index wins over a name");
        assert_eq!(s.find("x"), None);
    }
}
