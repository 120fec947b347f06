//! STEP (ISO 10303-21 exchange files, AP203/AP214/AP242): B-spline curves
//! and surfaces read and written.
//!
//! **Reading** ([`read_all`]) returns every `B_SPLINE_CURVE_WITH_KNOTS` and
//! `B_SPLINE_SURFACE_WITH_KNOTS`, their rational complex forms
//! (`(BOUNDED_CURVE() B_SPLINE_CURVE(..) B_SPLINE_CURVE_WITH_KNOTS(..) ..
//! RATIONAL_B_SPLINE_CURVE((w..)) REPRESENTATION_ITEM('name'))`, weights kept),
//! and the Bézier, quasi-uniform and uniform forms (their knots implied by
//! ISO 10303-42), in file order, each once however many edges, faces or
//! trimmed curves refer to it, labelled with its instance number and name
//! ([`EntityInfo`]). Knot multiplicities are expanded into a full knot
//! vector. Skipped, each listed in [`InterchangeFile::notices`] with its
//! reason: a malformed instance, a B-spline that fails validation (degree,
//! counts, increasing knots, finite numbers, positive weights), and curves in a surface's
//! parameter space (items of a `DEFINITIONAL_REPRESENTATION`); other curves
//! and surfaces (lines, planes, cylinders, ...) are counted in one notice.
//! Unclamped B-splines (periodic ones such as a full circle, the uniform
//! form) are made clamped by knot insertion at their domain ends (the same
//! shape on the same domain), with a notice.
//! Coordinates stay in the file's length unit (the `LENGTH_UNIT` of the
//! `GLOBAL_UNIT_ASSIGNED_CONTEXT`: `SI_UNIT` with a prefix or a
//! `CONVERSION_BASED_UNIT` such as `'INCH'`), reported in
//! [`InterchangeFile::unit`], unless [`ReadOptions::unit`] asks for a
//! conversion. The bounds of a face on a B-spline surface (`ADVANCED_FACE`)
//! are read as loops in the surface's (u, v) ([`InterchangeFile::trims`],
//! module `trim`), its edges' curves then not objects of their own; other
//! trims (`TRIMMED_CURVE`) are not applied. Each B-spline is returned once per
//! placement of its part in the assembly, in the assembly's coordinates
//! (module `placement`).
//!
//! The Part 21 parser ([`parse`]) is written here rather than taken from a
//! crate: `ruststep` 0.4 (Apache-2.0) parses complex instances but comes
//! with nom, serde and derive macros, builds its schema structs from
//! generated code, and gives no control over error recovery per instance;
//! `truck-stepio` 0.3 pulls in the whole truck modelling kernel. The parser
//! here is small, skips a bad instance up to its `;` (one bad entity skips
//! that entity, not the file), bounds nesting, and allocates only as it
//! reads tokens.
//!
//! **Writing** ([`write()`]) produces an AP214 (`AUTOMOTIVE_DESIGN`) file:
//! a product with one shape, a representation context with the length unit
//! of [`WriteOptions::unit`], the 3D objects in a
//! `GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION` (curves only) or
//! a `GEOMETRICALLY_BOUNDED_SURFACE_SHAPE_REPRESENTATION` (a
//! `GEOMETRIC_SET` of curves and surfaces), 2D curves (points with two
//! coordinates) in a wireframe representation of their own with a 2D
//! context; a surface with bounds ([`write_trimmed`]) as an `ADVANCED_FACE`
//! in an open shell of a `MANIFOLD_SURFACE_SHAPE_REPRESENTATION` (module
//! `write_trim`). Knots are written as distinct values with multiplicities,
//! rational B-splines as complex instances, and every real as its shortest
//! round-trip decimal, so Fairway → STEP → Fairway is exact.

pub mod parse;
mod placement;
mod read;
mod trim;
mod units;
mod write;
mod write_trim;

pub use write::format_real;

use crate::error::{Error, Result};
use crate::geometry::Geometry;
pub use crate::io::interchange::{EntityInfo, InterchangeFile, ReadOptions, Timestamp, Unit, WriteOptions};

/// The name that marks a 2D curve written with z = 0 (`'2D curve 3'`): read back as a 2D curve when
/// all its z coordinates are 0.
pub(crate) const PLANAR_NAME: &str = "2D curve";

fn perr(message: impl Into<String>) -> Error {
    Error::Parse {
        format: "STEP".into(),
        message: message.into(),
    }
}

/// Read every B-spline curve and surface of a STEP file, coordinates in the file's unit. Other
/// entities are skipped; skipped curves and surfaces are listed in `notices`.
pub fn read_all(bytes: &[u8]) -> Result<InterchangeFile> {
    read_all_with(bytes, ReadOptions::default())
}

/// [`read_all`] with options (unit conversion).
pub fn read_all_with(bytes: &[u8], opts: ReadOptions) -> Result<InterchangeFile> {
    if let Some(m) = super::blank_text_message(bytes) {
        return Err(perr(m));
    }
    let ex = parse::parse(bytes).map_err(perr)?;
    read::read_exchange(&ex, opts)
}

/// Read the first curve or surface of a STEP file.
pub fn read_first(bytes: &[u8]) -> Result<Geometry> {
    let f = read_all(bytes)?;
    f.objects.into_iter().next().ok_or_else(|| {
        perr(format!(
            "no B-spline curve or surface in the file{}",
            if f.notices.is_empty() {
                String::new()
            } else {
                format!(" ({})", f.notices.join("; "))
            }
        ))
    })
}

/// Write curves and surfaces as a STEP AP214 file.
pub fn write(objects: &[Geometry], opts: &WriteOptions) -> String {
    write::write(objects, &[], &[], opts)
}

/// [`write()`] with a name per object (`names[k]` for `objects[k]`; missing or empty: `curve k`,
/// `surface k`), written as the entity's name so that [`read_all`] reports it again (a 2D curve's name
/// keeps the prefix that marks it 2D, which the reader strips).
pub fn write_labeled(objects: &[Geometry], names: &[String], opts: &WriteOptions) -> String {
    write::write(objects, names, &[], opts)
}

/// [`write_labeled`] with the bounds of trimmed faces: `trims[k]` (if any) bounds the surface
/// `objects[k]`, written as an `ADVANCED_FACE` whose edges are recomputed on the surface as it is now
/// (module `write_trim`); the others as [`write_labeled`] writes them.
pub fn write_trimmed(
    objects: &[Geometry],
    names: &[String],
    trims: &[Option<crate::trim::FaceTrim>],
    opts: &WriteOptions,
) -> String {
    write::write(objects, names, trims, opts)
}

/// One geometry as STEP text with default options.
pub fn to_string(g: &Geometry) -> String {
    write(std::slice::from_ref(g), &WriteOptions::default())
}
