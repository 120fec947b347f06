//! Lengths as people type them: `0.05`, `0.05mm`, `0.002 in`, `1e-3m`, `5um`, `5 µm`. One parser for
//! the command line (`fairway fair --tolerance`) and the editor's tolerance field, and an exact
//! conversion into a document's unit.

use std::fmt;
use std::str::FromStr;

use super::interchange::Unit;

/// A length as typed: a finite number and, if one was written after it, its unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Length {
    /// The number.
    pub value: f64,
    /// The unit written after it; `None`: a plain number, in the document's own unit.
    pub unit: Option<Unit>,
}

/// Why a typed length was refused; the message says it in the user's terms.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LengthError {
    /// Nothing was typed.
    #[error("no length given: type a number, optionally with a unit ({EXAMPLES})")]
    Empty,
    /// The text before the unit is not a number.
    #[error("{0:?} is not a number: type a number, optionally with a unit ({EXAMPLES})")]
    NotANumber(String),
    /// The letters after the number are not a unit Fairway knows.
    #[error("{0:?} is not a length unit; known units: {units}", units = known_units())]
    UnknownUnit(String),
    /// The number is infinite or NaN (also a number too large for a double, such as `1e999`).
    #[error("{0:?} is not a finite length")]
    NotFinite(String),
    /// A length with a unit, for a document that declares none: there is nothing to convert to.
    #[error("{0} cannot be converted: the document declares no length unit; type a plain number, in the model's units")]
    NoDocumentUnit(Length),
    /// The converted length does not fit in a double.
    #[error("{0} is too large to express in {unit}", unit = .1.symbol())]
    Overflow(Length, Unit),
}

/// Examples of typed lengths, quoted in the messages.
const EXAMPLES: &str = "0.05, 0.05mm, 0.002 in";

/// The units' symbols, as a message lists them.
fn known_units() -> String {
    Unit::ALL.map(Unit::symbol).join(", ")
}

impl Length {
    /// Parse a typed length: a number (Rust's syntax: `0.05`, `.5`, `1e-3`; a leading `−` as egui
    /// types it is a minus), then optionally a unit symbol or name, with or without a space between
    /// (`mm`, `cm`, `m`, `km`, `in`/`inch`, `ft`, `mi`, `mil`, `um`/`µm`, `uin`/`µin`; any case).
    /// The sign is the caller's to check (a tolerance must be positive).
    pub fn parse(text: &str) -> Result<Length, LengthError> {
        let t = text.trim().replace('−', "-");
        if t.is_empty() {
            return Err(LengthError::Empty);
        }
        // the unit: the letters at the end (a number never ends in a letter, "1e3" ends in a digit)
        let split = t
            .char_indices()
            .rev()
            .take_while(|(_, c)| c.is_alphabetic())
            .last()
            .map_or(t.len(), |(i, _)| i);
        let (number, unit) = (t[..split].trim_end(), &t[split..]);
        // "inf", "NaN" are numbers to Rust: whole-text numbers are tried first, then refused as infinite
        let (number, unit) = match t.parse::<f64>() {
            Ok(_) => (t.as_str(), ""),
            Err(_) => (number, unit),
        };
        let value = number.parse::<f64>().map_err(|_| {
            // only letters ("mm", "abc"): the whole text is what is not a number
            LengthError::NotANumber(if number.is_empty() {
                t.clone()
            } else {
                number.to_string()
            })
        })?;
        if !value.is_finite() {
            return Err(LengthError::NotFinite(t.to_string()));
        }
        let unit = match unit {
            "" => None,
            u => Some(Unit::parse(u).ok_or_else(|| LengthError::UnknownUnit(u.to_string()))?),
        };
        Ok(Length { value, unit })
    }

    /// The length in the document's unit `to`: a plain number as it is; a number with a unit
    /// converted exactly ([`Unit::convert`]: rounded once). Refused when the length has a unit and the
    /// document none, or when the result overflows.
    pub fn in_unit(self, to: Option<Unit>) -> Result<f64, LengthError> {
        match (self.unit, to) {
            (None, _) => Ok(self.value),
            (Some(_), None) => Err(LengthError::NoDocumentUnit(self)),
            (Some(from), Some(to)) => {
                let v = from.convert(self.value, to);
                if v.is_finite() {
                    Ok(v)
                } else {
                    Err(LengthError::Overflow(self, to))
                }
            }
        }
    }
}

impl FromStr for Length {
    type Err = LengthError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Length::parse(s)
    }
}

/// The number as typed back: the shorter of the plain and the exponent forms (both exact).
impl fmt::Display for Length {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (plain, exp) = (format!("{}", self.value), format!("{:e}", self.value));
        let number = if exp.len() < plain.len() { exp } else { plain };
        match self.unit {
            Some(u) => write!(f, "{number} {}", u.symbol()),
            None => f.write_str(&number),
        }
    }
}

/// `v · a / b`, rounded once to the nearest double (ties to even). `v = m · 2^e` exactly with
/// `m < 2^53`; `m · a` (below 2^97 for the units' sizes, `a`, `b` < 2^54) is shifted to the top of a
/// u128 and divided by `b`, the remainder kept as a sticky bit, so rounding the 80-odd-bit quotient to
/// 53 bits is the rounding of the exact value. Only a result in the subnormal range is rounded twice.
pub(crate) fn scale_exact(v: f64, a: u64, b: u64) -> f64 {
    assert!(a > 0 && b > 0 && a < 1 << 54 && b < 1 << 54, "unit sizes {a}, {b}");
    if !v.is_finite() || v == 0.0 || a == b {
        return v;
    }
    let bits = v.abs().to_bits();
    let (exp, frac) = ((bits >> 52) as i32, bits & ((1 << 52) - 1));
    let (m, e) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | 1 << 52, exp - 1075)
    };
    let n = u128::from(m) * u128::from(a);
    let shift = n.leading_zeros();
    let n = n << shift;
    let (q, r) = (n / u128::from(b), n % u128::from(b));
    let q = q | u128::from(r != 0);
    // `as` rounds a u128 to the nearest double, ties to even
    v.signum() * times_pow2(q as f64, e - shift as i32)
}

/// `x · 2^k`, exact while the result is a normal double.
fn times_pow2(mut x: f64, mut k: i32) -> f64 {
    let pow2 = |k: i32| f64::from_bits(((k + 1023) as u64) << 52);
    while k > 1000 {
        x *= pow2(1000);
        k -= 1000;
    }
    while k < -1000 {
        x *= pow2(-1000);
        k += 1000;
    }
    x * pow2(k)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn l(s: &str) -> Result<Length, LengthError> {
        Length::parse(s)
    }

    #[test]
    fn typed_lengths_parse_with_and_without_units() {
        let len = |value, unit| Length { value, unit };
        assert_eq!(l("0.05"), Ok(len(0.05, None)));
        assert_eq!(l("0.05mm"), Ok(len(0.05, Some(Unit::Millimeter))));
        assert_eq!(l(" 0.002 in "), Ok(len(0.002, Some(Unit::Inch))));
        assert_eq!(l("0.002 INCH"), Ok(len(0.002, Some(Unit::Inch))));
        assert_eq!(l("1e-3m"), Ok(len(1e-3, Some(Unit::Meter))));
        assert_eq!(l("1E3mm"), Ok(len(1e3, Some(Unit::Millimeter))));
        assert_eq!(l("5um"), Ok(len(5.0, Some(Unit::Micron))));
        assert_eq!(l("5 µm"), Ok(len(5.0, Some(Unit::Micron))));
        assert_eq!(l("2mil"), Ok(len(2.0, Some(Unit::Mil))));
        assert_eq!(l("3 uin"), Ok(len(3.0, Some(Unit::Microinch))));
        assert_eq!(l("−0.5 cm"), Ok(len(-0.5, Some(Unit::Centimeter))));
        assert_eq!(l(".5"), Ok(len(0.5, None)));
        assert_eq!("0.05mm".parse::<Length>(), l("0.05mm"));
        assert_eq!(l("0.05mm").unwrap().to_string(), "0.05 mm");
        assert_eq!(l("0.05").unwrap().to_string(), "0.05");
    }

    #[test]
    fn bad_lengths_are_refused_with_a_message_in_the_users_terms() {
        let msg = |s: &str| l(s).unwrap_err().to_string();
        assert_eq!(l("  "), Err(LengthError::Empty));
        assert_eq!(
            msg(""),
            "no length given: type a number, optionally with a unit (0.05, 0.05mm, 0.002 in)"
        );
        assert_eq!(l("mm"), Err(LengthError::NotANumber("mm".into())));
        assert_eq!(
            msg("abc"),
            "\"abc\" is not a number: type a number, optionally with a unit (0.05, 0.05mm, 0.002 in)"
        );
        assert_eq!(l("1,5mm"), Err(LengthError::NotANumber("1,5".into())));
        assert_eq!(
            msg("0.05 parsec"),
            "\"parsec\" is not a length unit; known units: in, mm, ft, mi, m, km, mil, µm, cm, µin"
        );
        // "5e" is not a number with the unit "m"; the letters at the end are the unit
        assert_eq!(l("5em"), Err(LengthError::UnknownUnit("em".into())));
        assert_eq!(l("1mm2"), Err(LengthError::NotANumber("1mm2".into())));
        for s in ["nan", "inf", "-inf", "1e999", "NaN mm", "inf in"] {
            assert!(matches!(l(s), Err(LengthError::NotFinite(_))), "{s}: {:?}", l(s));
        }
        assert_eq!(msg("1e999"), "\"1e999\" is not a finite length");
    }

    #[test]
    fn conversions_into_the_documents_unit_are_exact() {
        let to = |s: &str, u: Unit| l(s).unwrap().in_unit(Some(u)).unwrap();
        // 0.05 mm is 1/508 in: the nearest double, which the naive 0.05 / 25.4 misses by one ulp
        assert_eq!(to("0.05mm", Unit::Inch), 1.0 / 508.0);
        assert_ne!(0.05 / 25.4, 1.0 / 508.0);
        assert_eq!(to("1mm", Unit::Inch), 5.0 / 127.0);
        // 7 in = 177.8 mm and 0.3 in = 7.62 mm exactly (7 * 25.4 = 177.79999999999998)
        assert_eq!(to("7in", Unit::Millimeter), 177.8);
        assert_eq!(to("0.3 in", Unit::Millimeter), 7.62);
        assert_ne!(7.0 * 25.4, 177.8);
        assert_eq!(to("0.254mm", Unit::Inch), 0.01);
        assert_eq!(to("2 ft", Unit::Inch), 24.0);
        assert_eq!(to("1 mi", Unit::Foot), 5280.0);
        assert_eq!(to("5um", Unit::Millimeter), 0.005);
        assert_eq!(to("1e-3m", Unit::Millimeter), 1.0);
        assert_eq!(to("-2cm", Unit::Millimeter), -20.0);
        // a plain number is already in the document's unit, with or without one
        assert_eq!(to("0.05", Unit::Inch), 0.05);
        assert_eq!(l("0.05").unwrap().in_unit(None), Ok(0.05));
        // the same unit: unchanged
        assert_eq!(to("0.1mm", Unit::Millimeter), 0.1);
    }

    #[test]
    fn conversion_by_a_power_of_ten_or_an_integer_ratio_is_the_ieee_operation() {
        // where the ratio is an exact double, one IEEE multiply or divide is correctly rounded too:
        // the u128 path must agree with it bit for bit, over many magnitudes and mantissas
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        for _ in 0..20_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let v = f64::from_bits((x >> 2) % (0x7fe << 52)); // positive, finite, subnormals too
            let v = if (1e-290..=1e300).contains(&v) { v } else { v.sqrt() };
            assert_eq!(Unit::Inch.convert(v, Unit::Mil), v * 1000.0, "{v:e}");
            assert_eq!(Unit::Kilometer.convert(v, Unit::Millimeter), v * 1e6, "{v:e}");
            assert_eq!(Unit::Micron.convert(v, Unit::Meter), v / 1e6, "{v:e}");
            assert_eq!(Unit::Foot.convert(-v, Unit::Inch), -v * 12.0, "{v:e}");
        }
    }

    #[test]
    fn lengths_with_a_unit_need_a_document_unit_and_a_finite_result() {
        let e = l("0.1mm").unwrap().in_unit(None).unwrap_err();
        assert_eq!(
            e.to_string(),
            "0.1 mm cannot be converted: the document declares no length unit; type a plain number, in the \
             model's units"
        );
        let e = l("1e300 mi").unwrap().in_unit(Some(Unit::Microinch)).unwrap_err();
        assert_eq!(e.to_string(), "1e300 mi is too large to express in µin");
    }

    #[test]
    fn unit_sizes_agree_with_their_millimetres() {
        let mm = [
            25.4,
            1.0,
            304.8,
            1_609_344.0,
            1000.0,
            1.0e6,
            0.0254,
            0.001,
            10.0,
            2.54e-5,
        ];
        for (u, want) in Unit::ALL.into_iter().zip(mm) {
            assert_eq!(u.in_mm(), want, "{u:?}");
            assert_eq!(u.convert(1.0, Unit::Millimeter), want, "{u:?}");
        }
    }
}
