//! Plain geometry JSON (PRODUCT.md): a curve
//! `{"degree", "knots", "points": [[x, y], ...], "weights"?}` or a surface
//! `{"degree_u", "degree_v", "knots_u", "knots_v", "points": [[[x, y, z]]]}`.
//! Extra keys are ignored. Floats round-trip exactly (shortest
//! representation on output, correctly rounded parsing on input).

use serde_json::Value;

use super::record::{CurveRecord, SurfaceRecord};
use crate::error::{Error, Result};
use crate::geometry::Geometry;

fn parse_err(message: impl Into<String>) -> Error {
    Error::Parse {
        format: "JSON".into(),
        message: message.into(),
    }
}

/// Parse geometry JSON, validating it.
pub fn from_str(text: &str) -> Result<Geometry> {
    if let Some(m) = super::blank_text_message(text.as_bytes()) {
        return Err(parse_err(m));
    }
    // Typed first: the keys alone (their values skipped without allocating), then the record straight
    // from the text, so the memory is that of the geometry (about 3 times the file), not of a tree of
    // JSON values (about 20 times). Only a file that does not deserialize goes through the tree, for its
    // message with the path of the wrong value.
    if let Ok(keys) = serde_json::from_str::<std::collections::BTreeMap<String, serde::de::IgnoredAny>>(text) {
        let has = |k: &str| keys.contains_key(k);
        if has("degree_u") || has("knots_u") {
            if let Ok(r) = serde_json::from_str::<SurfaceRecord>(text) {
                return checked(Geometry::Surface(r.try_into()?));
            }
        } else if (has("degree") || has("knots"))
            && let Ok(r) = serde_json::from_str::<CurveRecord>(text)
        {
            return checked(Geometry::Curve(r.try_into()?));
        }
    }
    let v: Value = serde_json::from_str(text).map_err(|e| parse_err(e.to_string()))?;
    from_value(v)
}

/// Geometry read, refused if outside the numeric range (see [`crate::range`]).
fn checked(g: Geometry) -> Result<Geometry> {
    crate::range::check_geometry(&g)?;
    Ok(g)
}

/// Validate geometry from an already parsed JSON value.
pub fn from_value(v: Value) -> Result<Geometry> {
    let Value::Object(map) = &v else {
        return Err(parse_err(
            "expected an object with \"degree\" (curve) or \"degree_u\" (surface)",
        ));
    };
    if map.contains_key("degree_u") || map.contains_key("knots_u") {
        check_keys(map, SURFACE_KEYS)?;
        let r: SurfaceRecord = serde_json::from_value(v).map_err(|e| parse_err(format!("surface: {e}")))?;
        checked(Geometry::Surface(r.try_into()?))
    } else if map.contains_key("degree") || map.contains_key("knots") {
        check_keys(map, CURVE_KEYS)?;
        let r: CurveRecord = serde_json::from_value(v).map_err(|e| parse_err(format!("curve: {e}")))?;
        checked(Geometry::Curve(r.try_into()?))
    } else {
        Err(parse_err(
            "neither a curve (key \"degree\") nor a surface (key \"degree_u\")",
        ))
    }
}

/// Expected JSON shape of a key: `(name, nesting depth of the number arrays, required)`;
/// depth 0 is an integer (a degree).
type KeySpec = (&'static str, usize, bool);

const CURVE_KEYS: &[KeySpec] = &[
    ("degree", 0, true),
    ("knots", 1, true),
    ("points", 2, true),
    ("weights", 1, false),
];
const SURFACE_KEYS: &[KeySpec] = &[
    ("degree_u", 0, true),
    ("degree_v", 0, true),
    ("knots_u", 1, true),
    ("knots_v", 1, true),
    ("points", 3, true),
    ("weights", 2, false),
];

fn type_name(v: &Value) -> String {
    match v {
        Value::Null => "null".into(),
        Value::Bool(b) => format!("boolean {b}"),
        Value::Number(n) => format!("number {n}"),
        Value::String(s) => format!("string {s:?}"),
        Value::Array(_) => "an array".into(),
        Value::Object(_) => "an object".into(),
    }
}

/// Check that every known key is present (if required) and holds numbers
/// nested `depth` deep, so that a wrong type is reported with its path
/// (`points[3][1]: expected a number, found string "a"`) instead of serde's
/// position-only message.
fn check_keys(map: &serde_json::Map<String, Value>, spec: &[KeySpec]) -> Result<()> {
    fn check(path: &str, v: &Value, depth: usize) -> Result<()> {
        if depth == 0 {
            return match v {
                Value::Number(n) if n.is_f64() || n.is_i64() || n.is_u64() => Ok(()),
                other => Err(parse_err(format!(
                    "{path}: expected a number, found {}",
                    type_name(other)
                ))),
            };
        }
        let Value::Array(items) = v else {
            return Err(parse_err(format!("{path}: expected an array, found {}", type_name(v))));
        };
        for (i, x) in items.iter().enumerate() {
            check(&format!("{path}[{i}]"), x, depth - 1)?;
        }
        Ok(())
    }
    for &(key, depth, required) in spec {
        match map.get(key) {
            None | Some(Value::Null) if !required => {}
            None => return Err(parse_err(format!("missing key \"{key}\""))),
            Some(v) if depth == 0 => {
                if v.as_u64().is_none() {
                    return Err(parse_err(format!(
                        "{key}: expected a non-negative integer, found {}",
                        type_name(v)
                    )));
                }
            }
            Some(v) => check(key, v, depth)?,
        }
    }
    Ok(())
}

/// Geometry as JSON text (pretty enough to read, exact floats).
pub fn to_string(g: &Geometry) -> String {
    // straight from the records (no tree of JSON values: memory about that of the text); their fields are
    // in alphabetical order, so the text is the same as through a (sorted) serde_json::Value
    let mut s = match g {
        Geometry::Curve(c) => serde_json::to_string(&CurveRecord::from(c)),
        Geometry::Surface(s) => serde_json::to_string(&SurfaceRecord::from(s)),
    }
    .expect("records serialize");
    s.push('\n');
    s
}
