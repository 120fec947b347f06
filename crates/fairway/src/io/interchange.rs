//! What the interchange readers (IGES, STEP) return: the objects read, where
//! each came from, the notices (skipped entities, conversions), and the
//! file's length unit.

use crate::geometry::Geometry;

/// A length unit: the IGES global section's (field G14) or a STEP file's length unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Unit {
    /// Inch (flag 1).
    Inch,
    /// Millimetre (flag 2), the unit files are written in unless told otherwise.
    #[default]
    Millimeter,
    /// Foot (flag 4).
    Foot,
    /// Mile (flag 5).
    Mile,
    /// Metre (flag 6).
    Meter,
    /// Kilometre (flag 7).
    Kilometer,
    /// Mil, 0.001 inch (flag 8).
    Mil,
    /// Micron (flag 9).
    Micron,
    /// Centimetre (flag 10).
    Centimeter,
    /// Microinch (flag 11).
    Microinch,
}

impl Unit {
    /// Every unit, in IGES flag order.
    pub const ALL: [Unit; 10] = [
        Unit::Inch,
        Unit::Millimeter,
        Unit::Foot,
        Unit::Mile,
        Unit::Meter,
        Unit::Kilometer,
        Unit::Mil,
        Unit::Micron,
        Unit::Centimeter,
        Unit::Microinch,
    ];

    /// The IGES unit flag (G14).
    pub fn flag(self) -> i64 {
        match self {
            Unit::Inch => 1,
            Unit::Millimeter => 2,
            Unit::Foot => 4,
            Unit::Mile => 5,
            Unit::Meter => 6,
            Unit::Kilometer => 7,
            Unit::Mil => 8,
            Unit::Micron => 9,
            Unit::Centimeter => 10,
            Unit::Microinch => 11,
        }
    }

    /// The IGES unit name (G15).
    pub fn name(self) -> &'static str {
        match self {
            Unit::Inch => "INCH",
            Unit::Millimeter => "MM",
            Unit::Foot => "FT",
            Unit::Mile => "MI",
            Unit::Meter => "M",
            Unit::Kilometer => "KM",
            Unit::Mil => "MIL",
            Unit::Micron => "UM",
            Unit::Centimeter => "CM",
            Unit::Microinch => "UIN",
        }
    }

    /// The unit's symbol, as shown next to a length: `mm`, `in`, `µm`, ...
    pub fn symbol(self) -> &'static str {
        match self {
            Unit::Inch => "in",
            Unit::Millimeter => "mm",
            Unit::Foot => "ft",
            Unit::Mile => "mi",
            Unit::Meter => "m",
            Unit::Kilometer => "km",
            Unit::Mil => "mil",
            Unit::Micron => "µm",
            Unit::Centimeter => "cm",
            Unit::Microinch => "µin",
        }
    }

    /// The unit of a symbol or name (`mm`, `in`, `inch`, `um`, `µm`, `MM`, ...), case-insensitive.
    pub fn parse(s: &str) -> Option<Unit> {
        let t = s.trim();
        Unit::from_name(t).or_else(|| {
            let l = t.to_lowercase().replace('µ', "u");
            Unit::ALL.into_iter().find(|u| u.symbol().replace('µ', "u") == l)
        })
    }

    /// Length of one unit in tenths of a nanometre (10⁻¹⁰ m): an integer for every unit, so ratios of
    /// units are exact ([`Unit::convert`]).
    pub fn in_tenth_nm(self) -> u64 {
        match self {
            Unit::Inch => 254_000_000,
            Unit::Millimeter => 10_000_000,
            Unit::Foot => 3_048_000_000,
            Unit::Mile => 16_093_440_000_000,
            Unit::Meter => 10_000_000_000,
            Unit::Kilometer => 10_000_000_000_000,
            Unit::Mil => 254_000,
            Unit::Micron => 10_000,
            Unit::Centimeter => 100_000_000,
            Unit::Microinch => 254,
        }
    }

    /// Length of one unit in millimetres (the nearest double).
    pub fn in_mm(self) -> f64 {
        self.in_tenth_nm() as f64 / 1e7
    }

    /// `value` in this unit, expressed in `to`: `value` times the exact ratio of the two units' sizes,
    /// rounded once (the nearest double; 0.05 mm in inches is the double nearest 1/508, which
    /// `0.05 / 25.4` misses by one unit in the last place). Infinite if the result overflows.
    pub fn convert(self, value: f64, to: Unit) -> f64 {
        super::length::scale_exact(value, self.in_tenth_nm(), to.in_tenth_nm())
    }

    /// The unit of a flag, or (flag 3) of a name.
    pub fn from_flag(flag: i64, name: &str) -> Option<Unit> {
        Some(match flag {
            1 => Unit::Inch,
            2 => Unit::Millimeter,
            4 => Unit::Foot,
            5 => Unit::Mile,
            6 => Unit::Meter,
            7 => Unit::Kilometer,
            8 => Unit::Mil,
            9 => Unit::Micron,
            10 => Unit::Centimeter,
            11 => Unit::Microinch,
            3 => return Unit::from_name(name),
            _ => return None,
        })
    }

    /// The unit of a G15 name (`MM`, `IN`, `INCH`, `M`, ...), case-insensitive.
    pub fn from_name(name: &str) -> Option<Unit> {
        let n = name.trim().to_ascii_uppercase();
        Some(match n.as_str() {
            "IN" | "INCH" => Unit::Inch,
            "MM" => Unit::Millimeter,
            "FT" => Unit::Foot,
            "MI" => Unit::Mile,
            "M" => Unit::Meter,
            "KM" => Unit::Kilometer,
            "MIL" => Unit::Mil,
            "UM" => Unit::Micron,
            "CM" => Unit::Centimeter,
            "UIN" => Unit::Microinch,
            _ => return None,
        })
    }
}

/// Options of [`iges::read_all_with`](super::iges::read_all_with) and
/// [`step::read_all_with`](super::step::read_all_with).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ReadOptions {
    /// Convert coordinates to this unit (times the unit ratio). `None` keeps
    /// the file's unit. Either way an IGES file's coordinates are divided by
    /// its model-space scale G13 (real size).
    pub unit: Option<Unit>,
}

/// How a reader takes a file's coordinates to real size in the unit asked for: each coordinate times the
/// exact ratio of the two units, rounded once ([`Unit::convert`]), then divided by the IGES model-space
/// scale (1 for STEP).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Conversion {
    /// (the file's unit, the unit asked for); `None`: keep the file's unit.
    pub(crate) units: Option<(Unit, Unit)>,
    /// The model-space scale the coordinates are divided by.
    pub(crate) scale: f64,
}

impl Conversion {
    /// Coordinates kept as they are.
    pub(crate) fn is_identity(&self) -> bool {
        self.scale == 1.0 && self.units.is_none_or(|(from, to)| from == to)
    }

    /// One coordinate converted.
    pub(crate) fn value(&self, x: f64) -> f64 {
        let y = match self.units {
            Some((from, to)) if from != to => from.convert(x, to),
            _ => x,
        };
        if self.scale == 1.0 { y } else { y / self.scale }
    }

    /// `g` with every control point converted (knots and weights kept).
    pub(crate) fn apply(&self, g: Geometry) -> crate::error::Result<Geometry> {
        if self.is_identity() {
            return Ok(g);
        }
        map_points(g, |q| {
            glam::DVec3::new(self.value(q.x), self.value(q.y), self.value(q.z))
        })
    }
}

/// `g` with every control point mapped by `f` (knots and weights kept: B-splines, rational ones too, are
/// invariant under affine maps). A 2D curve stays 2D while its points stay in z = 0.
pub(crate) fn map_points(g: Geometry, f: impl Fn(glam::DVec3) -> glam::DVec3) -> crate::error::Result<Geometry> {
    Ok(match g {
        Geometry::Curve(c) => {
            let pts: Vec<glam::DVec3> = c.points().iter().map(|&q| f(q)).collect();
            let dim = if c.dim() == 2 && pts.iter().all(|q| q.z == 0.0) {
                2
            } else {
                3
            };
            Geometry::Curve(crate::curve::BSplineCurve::try_new(
                c.degree(),
                c.knots().values().to_vec(),
                pts,
                c.weights().map(<[f64]>::to_vec),
                dim,
            )?)
        }
        Geometry::Surface(s) => Geometry::Surface(s.with_points(s.points().iter().map(|&q| f(q)).collect())?),
    })
}

/// Everything read from an interchange file (IGES or STEP).
#[derive(Debug, Clone, PartialEq)]
pub struct InterchangeFile {
    /// The curves and surfaces (IGES 126 and 128, STEP B-spline entities), in file order.
    pub objects: Vec<Geometry>,
    /// The file's length unit (IGES G14/G15, STEP `LENGTH_UNIT` of the representation context), if
    /// recognised.
    pub unit: Option<Unit>,
    /// The IGES model-space scale (G13: model size over real size), 1 if absent (always 1 for STEP);
    /// `objects` are already divided by it.
    pub scale: f64,
    /// Skipped entities and conversions made, one message each.
    pub notices: Vec<String>,
    /// Where each of `objects` came from (same order and length).
    pub entities: Vec<EntityInfo>,
    /// The bounds of each of `objects` that is a trimmed face's surface, in its (u, v) (same order and
    /// length; `None` for the others). May be shorter (older callers): missing entries are `None`.
    pub trims: Vec<Option<crate::trim::FaceTrim>>,
}

/// The entity an object of [`InterchangeFile::objects`] was read from.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EntityInfo {
    /// IGES: sequence number of the entry's first `D` record (odd, 1-based);
    /// STEP: the instance number (`#n`); as the notices refer to it.
    pub entity: usize,
    /// IGES: the entity label (directory field 18, 8 characters, trimmed)
    /// and, when non-zero, its subscript (field 19) in parentheses; STEP: the
    /// entity's name; empty if none.
    pub label: String,
}

/// How an IGES or STEP file is written ([`super::iges::write`], [`super::step::write`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct WriteOptions {
    /// The unit the coordinates are in, declared in the file (IGES G14/G15, STEP's unit context).
    /// Fairway documents are unitless: millimetres unless the objects came from a file in another unit.
    pub unit: Unit,
    /// The file name written into the header (IGES G4, STEP `FILE_NAME`, whose stem also names the
    /// product); `None`: `fairway.igs` / `fairway.stp`.
    pub file_name: Option<String>,
    /// The time stamp written into the header; `None`: now.
    pub date: Option<Timestamp>,
}

impl WriteOptions {
    /// The options of a file written to `path` in `unit`: the header names the file as it is saved.
    pub fn for_path(path: &std::path::Path, unit: Unit) -> Self {
        Self {
            unit,
            file_name: path.file_name().map(|n| n.to_string_lossy().into_owned()),
            date: None,
        }
    }

    /// The file name to write, `default` if none was given.
    pub(crate) fn file_name_or<'a>(&'a self, default: &'a str) -> &'a str {
        self.file_name.as_deref().unwrap_or(default)
    }

    /// The time stamp to write: the one given, or now.
    pub(crate) fn date_or_now(&self) -> Timestamp {
        self.date.unwrap_or_else(Timestamp::now)
    }
}

/// A date and time (UTC) as written into a file header.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Timestamp {
    /// Year, e.g. 2026.
    pub year: i64,
    /// Month, 1–12.
    pub month: u8,
    /// Day of the month, 1–31.
    pub day: u8,
    /// Hour, 0–23.
    pub hour: u8,
    /// Minute, 0–59.
    pub minute: u8,
    /// Second, 0–59.
    pub second: u8,
}

impl Timestamp {
    /// The time now, UTC (the Unix epoch if the clock is before it).
    pub fn now() -> Self {
        let secs = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        Self::from_unix(secs)
    }

    /// `YYYYMMDD.HHNNSS`, the IGES form (global fields G18, G25).
    pub fn to_iges(&self) -> String {
        let Self {
            year,
            month,
            day,
            hour,
            minute,
            second,
        } = *self;
        format!("{year:04}{month:02}{day:02}.{hour:02}{minute:02}{second:02}")
    }

    /// `YYYY-MM-DDTHH:MM:SS`, ISO 8601 as STEP's `FILE_NAME` has it.
    pub fn to_iso8601(&self) -> String {
        let Self {
            year,
            month,
            day,
            hour,
            minute,
            second,
        } = *self;
        format!("{year:04}-{month:02}-{day:02}T{hour:02}:{minute:02}:{second:02}")
    }

    /// The UTC date and time `secs` seconds after 1970-01-01T00:00:00 (civil from days, H. Hinnant).
    pub fn from_unix(secs: u64) -> Self {
        let days = (secs / 86_400) as i64;
        let rem = secs % 86_400;
        let z = days + 719_468;
        let era = z.div_euclid(146_097);
        let doe = z - era * 146_097;
        let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
        let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
        let mp = (5 * doy + 2) / 153;
        let day = doy - (153 * mp + 2) / 5 + 1;
        let month = if mp < 10 { mp + 3 } else { mp - 9 };
        let year = yoe + era * 400 + i64::from(month <= 2);
        Self {
            year,
            month: month as u8,
            day: day as u8,
            hour: (rem / 3600) as u8,
            minute: (rem / 60 % 60) as u8,
            second: (rem % 60) as u8,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Timestamp, Unit, WriteOptions};
    use crate::curve::BSplineCurve;
    use crate::geometry::Geometry;
    use crate::io::{iges, step};
    use glam::DVec3;

    #[test]
    fn both_writers_put_the_same_options_into_their_headers() {
        let pts = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(2.0, 1.0, 0.5),
            DVec3::new(3.0, 0.0, 1.0),
        ];
        let c = BSplineCurve::new_3d(3, vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0], pts).unwrap();
        let objects = [Geometry::Curve(c)];
        let opts = |name: &str| WriteOptions {
            unit: Unit::Inch,
            file_name: Some(name.into()),
            date: Some(Timestamp::from_unix(951_827_696)), // 2000-02-29T12:34:56
        };
        let igs = iges::write(&objects, &opts("wing.igs"));
        assert!(igs.contains("8Hwing.igs"), "{igs}");
        assert!(igs.contains("15H20000229.123456"), "{igs}");
        let stp = step::write(&objects, &opts("wing.stp"));
        assert!(stp.contains("FILE_NAME('wing.stp','2000-02-29T12:34:56'"), "{stp}");
        assert!(stp.contains("PRODUCT('wing','wing'"), "{stp}");
        assert_eq!(iges::read_all(igs.as_bytes()).unwrap().unit, Some(Unit::Inch));
        assert_eq!(step::read_all(stp.as_bytes()).unwrap().unit, Some(Unit::Inch));
        // the defaults: millimetres, the format's own file name
        let igs = iges::write(&objects, &WriteOptions::default());
        assert!(igs.contains("11Hfairway.igs"), "{igs}");
        assert_eq!(iges::read_all(igs.as_bytes()).unwrap().unit, Some(Unit::Millimeter));
        let stp = step::write(&objects, &WriteOptions::default());
        assert!(stp.contains("FILE_NAME('fairway.stp'"), "{stp}");
        assert_eq!(step::read_all(stp.as_bytes()).unwrap().unit, Some(Unit::Millimeter));
    }

    #[test]
    fn both_readers_convert_units_exactly() {
        use crate::io::ReadOptions;
        // 7 in is 177.8 mm and 0.3 in is 7.62 mm; 7 × 25.4 is 177.79999999999998
        let pts = vec![
            DVec3::new(7.0, 0.3, 0.0),
            DVec3::X,
            DVec3::new(2.0, 1.0, 0.5),
            DVec3::new(3.0, 0.0, 1.0),
        ];
        let c = BSplineCurve::new_3d(3, vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0], pts).unwrap();
        let objects = [Geometry::Curve(c)];
        let inch = WriteOptions {
            unit: Unit::Inch,
            ..Default::default()
        };
        let to_mm = ReadOptions {
            unit: Some(Unit::Millimeter),
        };
        let igs = iges::read_all_with(iges::write(&objects, &inch).as_bytes(), to_mm).unwrap();
        let stp = step::read_all_with(step::write(&objects, &inch).as_bytes(), to_mm).unwrap();
        for f in [igs, stp] {
            let Geometry::Curve(c) = &f.objects[0] else {
                panic!("a curve")
            };
            assert_eq!(c.points()[0], DVec3::new(177.8, 7.62, 0.0));
            assert_eq!(c.points()[3], DVec3::new(76.2, 0.0, 25.4));
        }
    }

    #[test]
    fn unix_times_convert_to_civil_dates() {
        let t = |y, mo, d, h, mi, s| Timestamp {
            year: y,
            month: mo,
            day: d,
            hour: h,
            minute: mi,
            second: s,
        };
        assert_eq!(Timestamp::from_unix(0), t(1970, 1, 1, 0, 0, 0));
        // 2000-02-29 (a leap day of a century leap year) 12:34:56
        assert_eq!(Timestamp::from_unix(951_827_696), t(2000, 2, 29, 12, 34, 56));
        // the last second of 2026
        assert_eq!(Timestamp::from_unix(1_798_761_599), t(2026, 12, 31, 23, 59, 59));
    }
}
