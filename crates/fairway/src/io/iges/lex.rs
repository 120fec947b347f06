//! Lexing: 80-column records, directory fields, free-format parameter tokens and their reader.

use super::*;

/// One parameter token.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Tok {
    Empty,
    Str(String),
    Num(String),
}

/// Split free-format parameter text into tokens, honouring Hollerith strings.
/// Stops at the record delimiter.
pub(super) fn tokenize(s: &[u8], pd: u8, rd: u8) -> Vec<Tok> {
    let mut out = Vec::new();
    let mut i = 0;
    let n = s.len();
    loop {
        while i < n && s[i] == b' ' {
            i += 1;
        }
        let start = i;
        // Hollerith: digits then 'H'.
        let mut j = i;
        while j < n && s[j].is_ascii_digit() {
            j += 1;
        }
        if j > i && j < n && (s[j] == b'H' || s[j] == b'h') {
            let count: usize = std::str::from_utf8(&s[i..j])
                .ok()
                .and_then(|t| t.parse().ok())
                .unwrap_or(usize::MAX);
            let body_start = j + 1;
            let body_end = body_start.saturating_add(count).min(n);
            out.push(Tok::Str(String::from_utf8_lossy(&s[body_start..body_end]).into_owned()));
            i = body_end;
            // skip to the delimiter
            while i < n && s[i] != pd && s[i] != rd {
                i += 1;
            }
        } else {
            while i < n && s[i] != pd && s[i] != rd {
                i += 1;
            }
            let t: String = String::from_utf8_lossy(&s[start..i])
                .chars()
                .filter(|c| *c != ' ')
                .collect();
            out.push(if t.is_empty() { Tok::Empty } else { Tok::Num(t) });
        }
        if i >= n || s[i] == rd {
            break;
        }
        i += 1; // parameter delimiter
    }
    out
}

/// Parse an IGES real: `1.5`, `1.`, `.5`, `1.5D3`, `1.5E-3`, `-2`, `+2D0`.
pub(super) fn parse_real(t: &str) -> Option<f64> {
    let t = t.replace(['D', 'd'], "E");
    let (mant, exp) = match t.find(['E', 'e']) {
        Some(k) => (&t[..k], Some(&t[k + 1..])),
        None => (t.as_str(), None),
    };
    let mut m = mant.to_string();
    if m.ends_with('.') {
        m.push('0');
    }
    if m.is_empty() || m == "+" || m == "-" {
        return None;
    }
    let full = match exp {
        Some(e) => format!("{m}e{e}"),
        None => m,
    };
    // Rust's parser also accepts "inf"/"nan": reject anything but digits, signs, '.', 'e'.
    if !full
        .bytes()
        .all(|b| b.is_ascii_digit() || matches!(b, b'+' | b'-' | b'.' | b'e'))
    {
        return None;
    }
    full.parse().ok()
}

pub(super) struct Params<'a> {
    pub(super) toks: &'a [Tok],
    pub(super) pos: usize,
    pub(super) what: String,
}

impl<'a> Params<'a> {
    pub(super) fn remaining(&self) -> usize {
        self.toks.len().saturating_sub(self.pos)
    }
    pub(super) fn next_tok(&mut self) -> Result<&'a Tok> {
        let toks: &'a [Tok] = self.toks;
        let t = toks
            .get(self.pos)
            .ok_or_else(|| perr(format!("{}: too few parameters ({} read)", self.what, self.pos)))?;
        self.pos += 1;
        Ok(t)
    }
    pub(super) fn real(&mut self) -> Result<f64> {
        let pos = self.pos;
        match self.next_tok()? {
            Tok::Num(s) => match parse_real(s) {
                Some(v) if v.is_finite() => Ok(v),
                _ => Err(perr(format!(
                    "{}: parameter {} ({s:?}) is not a finite number",
                    self.what,
                    pos + 1
                ))),
            },
            Tok::Empty => Ok(0.0),
            Tok::Str(_) => Err(perr(format!(
                "{}: parameter {} is a string, expected a number",
                self.what,
                pos + 1
            ))),
        }
    }
    pub(super) fn int(&mut self) -> Result<i64> {
        let pos = self.pos;
        let v = self.real()?;
        if v.fract() != 0.0 || v.abs() > 1e15 {
            return Err(perr(format!(
                "{}: parameter {} ({v}) is not an integer",
                self.what,
                pos + 1
            )));
        }
        Ok(v as i64)
    }
    pub(super) fn count(&mut self, name: &str, max: i64) -> Result<usize> {
        let v = self.int()?;
        if v < 0 || v > max {
            return Err(perr(format!(
                "{}: {name} = {v} is out of range (0 to {max})",
                self.what
            )));
        }
        Ok(v as usize)
    }
}

/// Split text into 80-column records: (section letter, content of columns 1–72).
pub(super) fn records(bytes: &[u8]) -> Result<Vec<(u8, &[u8])>> {
    let mut out = Vec::new();
    for (ln, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let line = raw.strip_suffix(b"\r").unwrap_or(raw);
        if line.iter().all(|b| b.is_ascii_whitespace()) {
            continue;
        }
        if line.len() < 73 {
            return Err(perr(format!(
                "line {}: {} columns; fixed-format IGES records have 80 (section letter in column 73)",
                ln + 1,
                line.len()
            )));
        }
        let letter = line[72];
        if !matches!(letter, b'S' | b'G' | b'D' | b'P' | b'T') {
            if ln == 0 && (letter == b'C' || line[72] == 0) {
                return Err(perr(
                    "compressed or binary IGES is not supported; save as fixed-format ASCII",
                ));
            }
            return Err(perr(format!(
                "line {}: column 73 is {:?}, expected a section letter S, G, D, P or T",
                ln + 1,
                letter as char
            )));
        }
        out.push((letter, &line[..72]));
    }
    Ok(out)
}

pub(super) fn field8(line: &[u8], k: usize) -> &[u8] {
    let a = (k * 8).min(line.len());
    let b = (k * 8 + 8).min(line.len());
    &line[a..b]
}

pub(super) fn int8(line: &[u8], k: usize, what: &str) -> Result<i64> {
    let s: String = String::from_utf8_lossy(field8(line, k)).trim().to_string();
    if s.is_empty() {
        return Ok(0);
    }
    s.parse::<i64>()
        .map_err(|_| perr(format!("{what}: directory field {} ({s:?}) is not an integer", k + 1)))
}

pub(super) struct DirEntry {
    pub(super) seq: usize,
    pub(super) etype: i64,
    pub(super) pstart: i64,
    pub(super) transform: i64,
    pub(super) status: String,
    pub(super) plines: i64,
    pub(super) form: i64,
    pub(super) label: String,
}
