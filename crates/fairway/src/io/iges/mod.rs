//! IGES 5.3 interchange: rational B-spline curves (entity 126) and surfaces
//! (entity 128), read and written in the fixed 80-column ASCII form.
//!
//! A file is a sequence of 80-column records in five sections, each record
//! ending with its section letter (column 73) and a sequence number
//! (columns 74–80):
//!
//! * **S** start: free text.
//! * **G** global: free-format parameters (delimiter `,`, record end `;`,
//!   strings as Hollerith `nH...`), among them the model-space scale (G13:
//!   model size over real size) and the unit flag (G14).
//! * **D** directory: two records per entity, twenty 8-column fields (entity
//!   type, pointer to its first **P** record, transformation matrix, status,
//!   number of **P** records, form, ...).
//! * **P** parameter data: the entity's parameters in columns 1–64, the
//!   back pointer to its directory entry in columns 66–72.
//! * **T** terminate: the number of records of each section.
//!
//! Entity 126 (IGES 5.3 §4.23): `126, K, M, PROP1..4, T(−M..N+M), W(0..K),
//! X,Y,Z (0..K), V0, V1, XN, YN, ZN` with `N = 1 + K − M`; entity 128
//! (§4.24): `128, K1, K2, M1, M2, PROP1..5, S(..), T(..), W(i,j), X,Y,Z(i,j),
//! U0, U1, V0, V1`, where the **first index varies fastest** (u inner).
//!
//! Reading ([`read_all`]) returns every 126/128 entity as a Fairway
//! [`Geometry`], applies transformation matrices (entity 124), converts
//! non-clamped or periodic B-splines (and B-splines whose parameter range
//! `[V0, V1]` is narrower than the knot domain) to clamped ones by knot
//! insertion (The NURBS Book A5.1 on homogeneous points: the curve is
//! unchanged), and lists the skipped entities in [`IgesFile::notices`].
//! Curves in the plane z = 0 flagged planar become 2D curves. Units: the
//! coordinates are returned at real size (divided by the model-space scale
//! G13, the ratio of model space to real-world size; a notice when it is not
//! one) in the file's unit, reported in [`IgesFile::unit`], unless
//! [`ReadOptions::unit`] asks for a conversion. The writer writes G13 = 1.
//!
//! A trimmed surface (144) gives its surface the loops of its boundaries
//! ([`IgesFile::trims`], module `trim`); [`write_trimmed`] writes a surface
//! with its loops as a 144 (module `write_trim`).
//!
//! Writing ([`write()`], [`to_string`]) emits each float as its shortest
//! round-trip decimal with a `D` exponent, so Fairway → IGES → Fairway is
//! exact. The parser never panics and never sizes an allocation from a
//! count in the file (counts are checked against the number of parameters
//! actually present).

use glam::{DVec3, DVec4};

use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::geometry::Geometry;
use crate::knots::MAX_DEGREE;
use crate::surface::BSplineSurface;

pub use super::interchange::{EntityInfo, ReadOptions, Timestamp, Unit, WriteOptions};

/// Everything read from an IGES file: the shared [`InterchangeFile`](super::interchange::InterchangeFile).
pub type IgesFile = super::interchange::InterchangeFile;

/// The native system ID (global field 5) Fairway writes: a file that names it was written by Fairway, whose
/// trimmed surfaces' model-space curves are derived from their parameter-space curves (module
/// `write_trim`) and are not read as objects of their own.
pub(super) const FAIRWAY_SYSTEM: &str = "Fairway";

fn perr(message: impl Into<String>) -> Error {
    Error::Parse {
        format: "IGES".into(),
        message: message.into(),
    }
}

mod clamp;
mod entities;
mod lex;
mod read;
#[cfg(test)]
mod tests;
mod trim;
mod write;
mod write_trim;

use clamp::*;
use entities::*;
use lex::*;

pub use clamp::read_first;
pub use read::{read_all, read_all_with};
pub use write::{format_real, to_string, write, write_labeled, write_trimmed};
