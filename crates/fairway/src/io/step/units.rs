//! STEP length units: read from the representation contexts
//! (`GLOBAL_UNIT_ASSIGNED_CONTEXT`), written as `SI_UNIT` or
//! `CONVERSION_BASED_UNIT`.

use super::parse::{Exchange, Instance, Param};
use crate::io::interchange::Unit;

/// The SI prefix of a unit that is a prefixed metre, `None` for a conversion-based unit.
pub fn si_prefix(u: Unit) -> Option<&'static str> {
    Some(match u {
        Unit::Millimeter => ".MILLI.",
        Unit::Centimeter => ".CENTI.",
        Unit::Meter => "$",
        Unit::Kilometer => ".KILO.",
        Unit::Micron => ".MICRO.",
        _ => return None,
    })
}

/// The name of a conversion-based unit, as written.
pub fn conversion_name(u: Unit) -> &'static str {
    match u {
        Unit::Inch => "INCH",
        Unit::Foot => "FOOT",
        Unit::Mile => "MILE",
        Unit::Mil => "MIL",
        Unit::Microinch => "MICROINCH",
        Unit::Millimeter => "MILLIMETRE",
        Unit::Centimeter => "CENTIMETRE",
        Unit::Meter => "METRE",
        Unit::Kilometer => "KILOMETRE",
        Unit::Micron => "MICROMETRE",
    }
}

const ALL: [Unit; 10] = Unit::ALL;

fn from_prefix(prefix: &Param) -> Option<Unit> {
    match prefix {
        Param::Null => Some(Unit::Meter),
        Param::Enum(p) => ALL
            .into_iter()
            .find(|&u| si_prefix(u).is_some_and(|s| s.trim_matches('.') == p)),
        _ => None,
    }
}

/// A known unit whose length in mm is `mm` (within 1e-9 relative).
fn from_mm(mm: f64) -> Option<Unit> {
    ALL.into_iter().find(|u| (u.in_mm() - mm).abs() <= 1e-9 * mm.abs())
}

/// The length of a unit instance in mm, following conversion-based units (at most a few levels).
fn unit_mm(ex: &Exchange, inst: &Instance, depth: usize) -> Option<f64> {
    if let Some(si) = inst.record("SI_UNIT") {
        if si.params.get(1) != Some(&Param::Enum("METRE".into())) {
            return None;
        }
        return from_prefix(si.params.first()?).map(Unit::in_mm);
    }
    let conv = inst.record("CONVERSION_BASED_UNIT")?;
    // the conversion factor, a MEASURE_WITH_UNIT(value, unit), says what the unit is; the name only
    // where the factor cannot be followed
    let factor = || -> Option<f64> {
        if depth > 4 {
            return None;
        }
        let Some(Param::Ref(m)) = conv.params.get(1) else {
            return None;
        };
        let rec = ex
            .get(*m)?
            .records
            .iter()
            .find(|r| r.name.ends_with("MEASURE_WITH_UNIT"))?;
        let value = rec.params.first()?.real()?;
        let Some(Param::Ref(base)) = rec.params.get(1) else {
            return None;
        };
        let mm = value * unit_mm(ex, ex.get(*base)?, depth + 1)?;
        (mm.is_finite() && mm > 0.0).then_some(mm)
    };
    factor().or_else(|| {
        let Some(Param::Str(name)) = conv.params.first() else {
            return None;
        };
        let name = name.trim();
        ALL.into_iter()
            .find(|&u| conversion_name(u).eq_ignore_ascii_case(name) || u.name().eq_ignore_ascii_case(name))
            .map(Unit::in_mm)
    })
}

/// The file's length unit: the `LENGTH_UNIT` assigned by the representation contexts. Contexts
/// that disagree, or a unit that is not recognised, are reported in `notices`.
pub fn file_unit(ex: &Exchange, notices: &mut Vec<String>) -> Option<Unit> {
    let mut found: Vec<(u64, Option<Unit>)> = Vec::new();
    for inst in &ex.instances {
        let Some(ctx) = inst.record("GLOBAL_UNIT_ASSIGNED_CONTEXT") else {
            continue;
        };
        let Some(units) = ctx.params.first().and_then(Param::list) else {
            continue;
        };
        for p in units {
            let Param::Ref(id) = p else { continue };
            let Some(u) = ex.get(*id).filter(|u| u.record("LENGTH_UNIT").is_some()) else {
                continue;
            };
            let unit = unit_mm(ex, u, 0).and_then(from_mm);
            if unit.is_none() {
                notices.push(format!(
                    "length unit #{id} is not recognised: coordinates are read as they are"
                ));
            }
            if !found.iter().any(|(_, x)| *x == unit) {
                found.push((inst.id, unit));
            }
        }
    }
    if found.len() > 1 {
        let names: Vec<String> = found
            .iter()
            .map(|(id, u)| format!("#{id}: {}", u.map_or("unknown", |u| u.name())))
            .collect();
        notices.push(format!(
            "the representation contexts use different length units ({}): coordinates are read as they are, the first unit is reported",
            names.join(", ")
        ));
    }
    found.first().and_then(|(_, u)| *u)
}
