//! Helpers shared by the subcommands: loading files with clear messages,
//! uniform parameters, JSON output.

use std::io::Write;
use std::path::Path;

use anyhow::{Result, anyhow, bail};
use fairway::{DVec3, Geometry};

/// Load the geometry of a JSON or RON file. Errors name the file and the problem.
pub fn load_geometry(path: &Path) -> Result<Geometry> {
    Ok(load_document(path)?.geometry)
}

/// `n ≥ 2` uniform parameters over `[a, b]`, first and last included:
/// `a + i·(b − a)/(n − 1)`, the last set to `b` exactly (the same values as
/// NumPy's `linspace`, so outputs compare bit for bit with references made
/// with it).
pub fn uniform_params(a: f64, b: f64, n: usize) -> Vec<f64> {
    let n = n.max(2);
    let step = (b - a) / (n - 1) as f64;
    let mut v: Vec<f64> = (0..n).map(|i| i as f64 * step + a).collect();
    v[n - 1] = b;
    v
}

/// A point or vector as `[x, y]` (2D) or `[x, y, z]`.
pub fn coords(p: DVec3, dim: usize) -> Vec<f64> {
    p.to_array()[..dim].to_vec()
}

/// Write a serializable value as one line of JSON to stdout (exact floats;
/// NaN and infinities become `null`).
pub fn print_json<T: serde::Serialize>(value: &T) -> Result<()> {
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    serde_json::to_writer(&mut out, value)?;
    writeln!(out)?;
    out.flush()?;
    Ok(())
}

/// Load a whole document (geometry and saved settings). Errors name the file and the problem.
pub fn load_document(path: &Path) -> Result<fairway::io::Document> {
    fairway::io::load(path).map_err(|e| match e {
        // I/O errors already start with the path
        e @ fairway::Error::Io { .. } => anyhow!("{e}"),
        e => anyhow!("{}: {e}", path.display()),
    })
}

/// An input read by a subcommand, and what the file says about it when it is IGES or STEP.
pub struct Input {
    /// The document (an IGES or STEP object as a new document).
    pub doc: fairway::io::Document,
    /// IGES / STEP: the file's length unit, if it declares one Fairway knows.
    pub unit: Option<fairway::io::Unit>,
    /// IGES / STEP: which object was taken (0-based) of how many.
    pub object: Option<(usize, usize)>,
    /// IGES / STEP: the bounds of a trimmed face (in its surface's (u, v)).
    pub trim: Option<fairway::FaceTrim>,
}

/// Write `doc` to `path` (the format from its extension; an IGES or STEP file declaring `unit`), a
/// trimmed face with its bounds `trim` where the format holds them (IGES, STEP, a `.ron` document of
/// version 2); a JSON output holds the surface only, said on stderr.
pub fn save_document(
    path: &Path,
    doc: fairway::io::Document,
    trim: Option<fairway::FaceTrim>,
    unit: Option<fairway::io::Unit>,
) -> fairway::Result<()> {
    use fairway::io::Format;
    let Some(trim) = trim else {
        return fairway::io::save_in(path, &doc, unit);
    };
    if matches!(Format::from_path(path), Ok(Format::Json)) {
        eprintln!(
            "fairway: {}: a JSON geometry file holds no trim: the face's bounds ({}) are not kept (write .ron, .igs \
             or .stp to keep them)",
            path.display(),
            trim.summary()
        );
        return fairway::io::save_in(path, &doc, unit);
    }
    let scene = fairway::io::Scene {
        objects: vec![fairway::io::SceneObject {
            name: String::new(),
            trim: Some(trim),
            geometry: doc.geometry,
            settings: doc.settings,
        }],
        unit,
        ..Default::default()
    };
    fairway::io::save_scene(path, &scene)
}

/// Load an input file. IGES, STEP and RON documents with several objects: object `index` (default the
/// first), the file's notices (skipped entities, trims not applied) and, when it holds several objects,
/// which one was taken, on stderr.
/// `index` on another format is refused. Errors name the file and the problem.
pub fn load_input(path: &Path, index: Option<usize>) -> Result<Input> {
    let name = path.display();
    let with_path = |e: fairway::Error| match e {
        e @ fairway::Error::Io { .. } => anyhow!("{e}"),
        e => anyhow!("{name}: {e}"),
    };
    let ron = matches!(fairway::io::Format::from_path(path), Ok(fairway::io::Format::Ron));
    if let Some((scene, _)) = if ron { load_scene_input(path)? } else { None }
        .filter(|(s, _)| s.objects.len() > 1 || s.objects.iter().any(|o| o.trim.is_some()))
    {
        // a document with several objects, or a trimmed face (RON version 2): picked like an object of an
        // IGES or STEP file
        let count = scene.objects.len();
        let k = pick(path, index, count)?;
        let o = scene.objects.into_iter().nth(k).expect("k < count");
        return Ok(Input {
            doc: fairway::io::Document {
                geometry: o.geometry,
                settings: o.settings,
            },
            unit: scene.unit,
            object: Some((k, count)),
            trim: o.trim,
        });
    }
    let Some(f) = fairway::io::read_interchange(path).map_err(with_path)? else {
        if let Some(k) = index {
            bail!("--index {k}: {name} holds one document; --index picks an object of an IGES or STEP file");
        }
        return Ok(Input {
            doc: load_document(path)?,
            unit: None,
            object: None,
            trim: None,
        });
    };
    for n in &f.notices {
        eprintln!("fairway: {name}: {n}");
    }
    let count = f.objects.len();
    if count == 0 {
        bail!("{name}: no B-spline curve or surface in the file");
    }
    let k = pick(path, index, count)?;
    let trim = f.trims.get(k).cloned().flatten();
    let g = f.objects.into_iter().nth(k).expect("k < count");
    Ok(Input {
        doc: fairway::io::Document::new(g),
        unit: f.unit,
        object: Some((k, count)),
        trim,
    })
}

/// The object `index` picks of `count` (default the first; when there are several, which one was taken
/// on stderr), or the error naming the file and the count.
fn pick(path: &Path, index: Option<usize>, count: usize) -> Result<usize> {
    let name = path.display();
    let k = index.unwrap_or(0);
    if count > 1 && index.is_none() {
        eprintln!(
            "fairway: {name}: {count} objects, using number {k} (choose with --index, 0 to {})",
            count - 1
        );
    }
    if k >= count {
        bail!(
            "{name}: --index {k} but the file holds {count} objects (0 to {})",
            count - 1
        );
    }
    Ok(k)
}

/// Every object of an IGES, STEP or RON file (`None` for another format) and the reader's notices.
/// Errors name the file and the problem.
pub fn load_scene_input(path: &Path) -> Result<Option<(fairway::io::Scene, Vec<String>)>> {
    use fairway::io::Format;
    if !matches!(Format::from_path(path), Ok(Format::Ron | Format::Iges | Format::Step)) {
        return Ok(None);
    }
    fairway::io::load_scene(path).map(Some).map_err(|e| match e {
        e @ fairway::Error::Io { .. } => anyhow!("{e}"),
        e => anyhow!("{}: {e}", path.display()),
    })
}

/// The file a path names, links resolved: the path itself if it exists, else its folder resolved and its
/// name (a file still to be written).
pub fn resolved(path: &Path) -> std::path::PathBuf {
    if let Ok(p) = path.canonicalize() {
        return p;
    }
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    match (dir.canonicalize(), path.file_name()) {
        (Ok(d), Some(name)) => d.join(name),
        _ => path.to_path_buf(),
    }
}

/// Refuse an output or report that is the input, or a report that is the output (compared after
/// resolving links), before any work.
pub fn refuse_same_files(input: &Path, output: &Path, report: Option<&Path>) -> Result<()> {
    let (i, o) = (resolved(input), resolved(output));
    if i == o {
        bail!(
            "the output {} is the input file: write the result to another file",
            output.display()
        );
    }
    if let Some(r) = report.map(resolved) {
        if r == i {
            bail!(
                "the report {} is the input file: write the report to another file",
                report.unwrap().display()
            );
        }
        if r == o {
            bail!(
                "the report {} is the output file: give the report its own file",
                report.unwrap().display()
            );
        }
    }
    Ok(())
}

/// Refuse `value` if it holds a NaN or an infinity (which JSON would write as `null`): `what`'s field
/// `a.b[3]` is not a finite number (`inf`). Nothing is written then.
pub fn refuse_non_finite<T: serde::Serialize>(what: &str, value: &T) -> Result<()> {
    let mut f = finite::Finder::default();
    let _ = value.serialize(&mut f);
    match f.found {
        None => Ok(()),
        Some((path, x)) => bail!(
            "{what}: {path} is not a finite number ({x}): nothing was written (the input is outside what \
             Fairway evaluates, see docs/DEGENERATE_INPUTS.md)"
        ),
    }
}

/// A serializer that only looks for the first non-finite float and its path.
mod finite {
    use serde::ser::{self, Serialize};

    #[derive(Debug)]
    pub struct Stop;
    impl std::fmt::Display for Stop {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("stop")
        }
    }
    impl std::error::Error for Stop {}
    impl ser::Error for Stop {
        fn custom<T: std::fmt::Display>(_: T) -> Self {
            Stop
        }
    }

    #[derive(Default)]
    pub struct Finder {
        path: Vec<String>,
        index: Vec<usize>,
        pub found: Option<(String, f64)>,
    }

    impl Finder {
        fn float(&mut self, x: f64) -> Result<(), Stop> {
            if x.is_finite() {
                return Ok(());
            }
            let mut p = String::new();
            for s in &self.path {
                if !s.starts_with('[') && !p.is_empty() {
                    p.push('.');
                }
                p.push_str(s);
            }
            self.found = Some((if p.is_empty() { "the value".into() } else { p }, x));
            Err(Stop)
        }
        fn field<T: ?Sized + Serialize>(&mut self, name: String, v: &T) -> Result<(), Stop> {
            self.path.push(name);
            v.serialize(&mut *self)?;
            self.path.pop();
            Ok(())
        }
        fn element<T: ?Sized + Serialize>(&mut self, v: &T) -> Result<(), Stop> {
            let i = self.index.last_mut().expect("in a sequence");
            let name = format!("[{i}]");
            *i += 1;
            self.field(name, v)
        }
    }

    macro_rules! ok_scalars {
        ($($f:ident: $t:ty),*) => {
            $(fn $f(self, _: $t) -> Result<(), Stop> { Ok(()) })*
        };
    }

    impl ser::Serializer for &mut Finder {
        type Ok = ();
        type Error = Stop;
        type SerializeSeq = Self;
        type SerializeTuple = Self;
        type SerializeTupleStruct = Self;
        type SerializeTupleVariant = Self;
        type SerializeMap = Self;
        type SerializeStruct = Self;
        type SerializeStructVariant = Self;
        ok_scalars!(serialize_bool: bool, serialize_i8: i8, serialize_i16: i16, serialize_i32: i32,
            serialize_i64: i64, serialize_u8: u8, serialize_u16: u16, serialize_u32: u32, serialize_u64: u64,
            serialize_char: char, serialize_str: &str, serialize_bytes: &[u8]);
        fn serialize_f32(self, v: f32) -> Result<(), Stop> {
            self.float(v as f64)
        }
        fn serialize_f64(self, v: f64) -> Result<(), Stop> {
            self.float(v)
        }
        fn serialize_none(self) -> Result<(), Stop> {
            Ok(())
        }
        fn serialize_some<T: ?Sized + Serialize>(self, v: &T) -> Result<(), Stop> {
            v.serialize(self)
        }
        fn serialize_unit(self) -> Result<(), Stop> {
            Ok(())
        }
        fn serialize_unit_struct(self, _: &'static str) -> Result<(), Stop> {
            Ok(())
        }
        fn serialize_unit_variant(self, _: &'static str, _: u32, _: &'static str) -> Result<(), Stop> {
            Ok(())
        }
        fn serialize_newtype_struct<T: ?Sized + Serialize>(self, _: &'static str, v: &T) -> Result<(), Stop> {
            v.serialize(self)
        }
        fn serialize_newtype_variant<T: ?Sized + Serialize>(
            self,
            _: &'static str,
            _: u32,
            variant: &'static str,
            v: &T,
        ) -> Result<(), Stop> {
            self.field(variant.into(), v)
        }
        fn serialize_seq(self, _: Option<usize>) -> Result<Self, Stop> {
            self.index.push(0);
            Ok(self)
        }
        fn serialize_tuple(self, _: usize) -> Result<Self, Stop> {
            self.index.push(0);
            Ok(self)
        }
        fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Self, Stop> {
            self.index.push(0);
            Ok(self)
        }
        fn serialize_tuple_variant(self, _: &'static str, _: u32, _: &'static str, _: usize) -> Result<Self, Stop> {
            self.index.push(0);
            Ok(self)
        }
        fn serialize_map(self, _: Option<usize>) -> Result<Self, Stop> {
            self.index.push(0);
            Ok(self)
        }
        fn serialize_struct(self, _: &'static str, _: usize) -> Result<Self, Stop> {
            Ok(self)
        }
        fn serialize_struct_variant(self, _: &'static str, _: u32, _: &'static str, _: usize) -> Result<Self, Stop> {
            Ok(self)
        }
    }

    macro_rules! seq_like {
        ($($tr:ident: $m:ident),*) => {
            $(impl ser::$tr for &mut Finder {
                type Ok = ();
                type Error = Stop;
                fn $m<T: ?Sized + Serialize>(&mut self, v: &T) -> Result<(), Stop> {
                    self.element(v)
                }
                fn end(self) -> Result<(), Stop> {
                    self.index.pop();
                    Ok(())
                }
            })*
        };
    }
    seq_like!(SerializeSeq: serialize_element, SerializeTuple: serialize_element,
        SerializeTupleStruct: serialize_field, SerializeTupleVariant: serialize_field);

    impl ser::SerializeMap for &mut Finder {
        type Ok = ();
        type Error = Stop;
        fn serialize_key<T: ?Sized + Serialize>(&mut self, _: &T) -> Result<(), Stop> {
            Ok(())
        }
        fn serialize_value<T: ?Sized + Serialize>(&mut self, v: &T) -> Result<(), Stop> {
            self.element(v)
        }
        fn end(self) -> Result<(), Stop> {
            self.index.pop();
            Ok(())
        }
    }

    impl ser::SerializeStruct for &mut Finder {
        type Ok = ();
        type Error = Stop;
        fn serialize_field<T: ?Sized + Serialize>(&mut self, key: &'static str, v: &T) -> Result<(), Stop> {
            self.field(key.into(), v)
        }
        fn end(self) -> Result<(), Stop> {
            Ok(())
        }
    }

    impl ser::SerializeStructVariant for &mut Finder {
        type Ok = ();
        type Error = Stop;
        fn serialize_field<T: ?Sized + Serialize>(&mut self, key: &'static str, v: &T) -> Result<(), Stop> {
            self.field(key.into(), v)
        }
        fn end(self) -> Result<(), Stop> {
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Serialize)]
    struct Inner {
        a: f64,
        list: Vec<[f64; 2]>,
    }
    #[derive(serde::Serialize)]
    struct Outer {
        name: &'static str,
        maybe: Option<f64>,
        inner: Inner,
    }

    #[test]
    fn non_finite_values_are_found_with_their_path() {
        let mut v = Outer {
            name: "x",
            maybe: None,
            inner: Inner {
                a: 1.0,
                list: vec![[0.0, 1.0], [2.0, 3.0]],
            },
        };
        refuse_non_finite("the report", &v).unwrap();
        v.inner.list[1][0] = f64::INFINITY;
        let e = refuse_non_finite("the report", &v).unwrap_err().to_string();
        assert!(
            e.starts_with("the report: inner.list[1][0] is not a finite number (inf): nothing was written"),
            "{e}"
        );
        v.maybe = Some(f64::NAN);
        let e = refuse_non_finite("the report", &v).unwrap_err().to_string();
        assert!(e.starts_with("the report: maybe is not a finite number (NaN)"), "{e}");
        let e = refuse_non_finite("the output", &f64::NEG_INFINITY)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("the output: the value is not a finite number (-inf)"),
            "{e}"
        );
    }
}
