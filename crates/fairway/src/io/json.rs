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
    if text.trim().is_empty() {
        return Err(parse_err("the file is empty"));
    }
    let v: Value = serde_json::from_str(text).map_err(|e| parse_err(e.to_string()))?;
    from_value(v)
}

/// Validate geometry from an already parsed JSON value.
pub fn from_value(v: Value) -> Result<Geometry> {
    let Value::Object(map) = &v else {
        return Err(parse_err(
            "expected an object with \"degree\" (curve) or \"degree_u\" (surface)",
        ));
    };
    if map.contains_key("degree_u") || map.contains_key("knots_u") {
        let r: SurfaceRecord = serde_json::from_value(v).map_err(|e| parse_err(format!("surface: {e}")))?;
        Ok(Geometry::Surface(r.try_into()?))
    } else if map.contains_key("degree") || map.contains_key("knots") {
        let r: CurveRecord = serde_json::from_value(v).map_err(|e| parse_err(format!("curve: {e}")))?;
        Ok(Geometry::Curve(r.try_into()?))
    } else {
        Err(parse_err(
            "neither a curve (key \"degree\") nor a surface (key \"degree_u\")",
        ))
    }
}

/// Geometry as JSON text (pretty enough to read, exact floats).
pub fn to_string(g: &Geometry) -> String {
    let v = match g {
        Geometry::Curve(c) => serde_json::to_value(CurveRecord::from(c)),
        Geometry::Surface(s) => serde_json::to_value(SurfaceRecord::from(s)),
    }
    .expect("records serialize");
    let mut s = serde_json::to_string(&v).expect("values serialize");
    s.push('\n');
    s
}
