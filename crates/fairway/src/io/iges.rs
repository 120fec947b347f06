//! IGES 5.3 interchange: rational B-spline curves (entity 126) and surfaces
//! (entity 128), read and written in the fixed 80-column ASCII form.
//!
//! A file is a sequence of 80-column records in five sections, each record
//! ending with its section letter (column 73) and a sequence number
//! (columns 74–80):
//!
//! * **S** start: free text.
//! * **G** global: free-format parameters (delimiter `,`, record end `;`,
//!   strings as Hollerith `nH...`), among them the model-space scale (G13)
//!   and the unit flag (G14).
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
//! coordinates are returned in the file's unit, reported in
//! [`IgesFile::unit`], unless [`ReadOptions::unit`] asks for a conversion
//! (which also divides by the model-space scale).
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

pub use super::interchange::{EntityInfo, ReadOptions, Unit};

/// Everything read from an IGES file: the shared [`InterchangeFile`](super::interchange::InterchangeFile).
pub type IgesFile = super::interchange::InterchangeFile;

fn perr(message: impl Into<String>) -> Error {
    Error::Parse {
        format: "IGES".into(),
        message: message.into(),
    }
}

/// Options of [`write()`].
#[derive(Debug, Clone, PartialEq)]
pub struct WriteOptions {
    /// Unit written to G14/G15 (Fairway documents are unitless; default mm).
    pub unit: Unit,
    /// File name written to G4.
    pub file_name: String,
    /// Date written to G18/G25 as `YYYYMMDD.HHNNSS`; `None` = now (UTC).
    pub date: Option<String>,
}

impl Default for WriteOptions {
    fn default() -> Self {
        Self {
            unit: Unit::Millimeter,
            file_name: "fairway.igs".into(),
            date: None,
        }
    }
}

// ---------------------------------------------------------------- reading

/// One parameter token.
#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Empty,
    Str(String),
    Num(String),
}

/// Split free-format parameter text into tokens, honouring Hollerith strings.
/// Stops at the record delimiter.
fn tokenize(s: &[u8], pd: u8, rd: u8) -> Vec<Tok> {
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
fn parse_real(t: &str) -> Option<f64> {
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

struct Params<'a> {
    toks: &'a [Tok],
    pos: usize,
    what: String,
}

impl<'a> Params<'a> {
    fn remaining(&self) -> usize {
        self.toks.len().saturating_sub(self.pos)
    }
    fn next_tok(&mut self) -> Result<&'a Tok> {
        let toks: &'a [Tok] = self.toks;
        let t = toks
            .get(self.pos)
            .ok_or_else(|| perr(format!("{}: too few parameters ({} read)", self.what, self.pos)))?;
        self.pos += 1;
        Ok(t)
    }
    fn real(&mut self) -> Result<f64> {
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
    fn int(&mut self) -> Result<i64> {
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
    fn count(&mut self, name: &str, max: i64) -> Result<usize> {
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
fn records(bytes: &[u8]) -> Result<Vec<(u8, &[u8])>> {
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

fn field8(line: &[u8], k: usize) -> &[u8] {
    let a = (k * 8).min(line.len());
    let b = (k * 8 + 8).min(line.len());
    &line[a..b]
}

fn int8(line: &[u8], k: usize, what: &str) -> Result<i64> {
    let s: String = String::from_utf8_lossy(field8(line, k)).trim().to_string();
    if s.is_empty() {
        return Ok(0);
    }
    s.parse::<i64>()
        .map_err(|_| perr(format!("{what}: directory field {} ({s:?}) is not an integer", k + 1)))
}

struct DirEntry {
    seq: usize,
    etype: i64,
    pstart: i64,
    transform: i64,
    status: String,
    plines: i64,
    form: i64,
    label: String,
}

/// Read every curve (126) and surface (128) of an IGES file, coordinates in
/// the file's unit. Other entities are skipped and listed in `notices`.
pub fn read_all(bytes: &[u8]) -> Result<IgesFile> {
    read_all_with(bytes, ReadOptions::default())
}

/// [`read_all`] with options (unit conversion).
pub fn read_all_with(bytes: &[u8], opts: ReadOptions) -> Result<IgesFile> {
    if let Some(m) = super::blank_text_message(bytes) {
        return Err(perr(m));
    }
    let recs = records(bytes)?;
    let (gtext, dlines, plines) = split_sections(&recs);
    if gtext.is_empty() {
        return Err(perr("no global (G) section"));
    }
    let (pd, rd) = global_delimiters(&gtext)?;
    let gtoks = tokenize(&gtext, pd, rd);
    let mut notices = Vec::new();
    let (scale, unit, factor) = global_units(&gtoks, opts, &mut notices)?;
    let entries = directory_entries(&dlines)?;
    let data = DataSections {
        entries: &entries,
        plines: &plines,
        pd,
        rd,
        factor,
    };
    let (objects, infos, first_error) = data.read_entities(&mut notices);
    // nothing readable: the first entity's reason is the file's
    if objects.is_empty()
        && let Some(err) = first_error
    {
        return Err(err);
    }
    Ok(IgesFile {
        objects,
        unit,
        scale,
        notices,
        entities: infos,
    })
}

/// Sections: the records sorted into the global text, the directory records and the parameter
/// records' columns 1–64 (start and terminate sections are not read).
fn split_sections<'a>(recs: &[(u8, &'a [u8])]) -> (Vec<u8>, Vec<&'a [u8]>, Vec<&'a [u8]>) {
    let mut gtext: Vec<u8> = Vec::new();
    let mut dlines: Vec<&[u8]> = Vec::new();
    let mut plines: Vec<&[u8]> = Vec::new();
    for (letter, body) in recs {
        match letter {
            b'G' => gtext.extend_from_slice(body),
            b'D' => dlines.push(body),
            b'P' => plines.push(&body[..64]),
            _ => {}
        }
    }
    (gtext, dlines, plines)
}

/// Global section, delimiters first: the parameter and record delimiters (fields 1–2, default
/// `,` and `;`), which every later field's tokenizing needs.
fn global_delimiters(gtext: &[u8]) -> Result<(u8, u8)> {
    let mut pd = b',';
    let mut rd = b';';
    let g = gtext;
    let mut k = 0;
    while k < g.len() && g[k] == b' ' {
        k += 1;
    }
    if g.len() >= k + 3 && g[k] == b'1' && (g[k + 1] == b'H' || g[k + 1] == b'h') {
        pd = g[k + 2];
        k += 3;
    }
    // after field 1 comes pd, then field 2
    if k < g.len() && g[k] == pd {
        k += 1;
        while k < g.len() && g[k] == b' ' {
            k += 1;
        }
        if g.len() >= k + 3 && g[k] == b'1' && (g[k + 1] == b'H' || g[k + 1] == b'h') {
            rd = g[k + 2];
        }
    }
    if pd == rd || pd == b' ' || rd == b' ' || pd.is_ascii_digit() || rd.is_ascii_digit() {
        return Err(perr("global section: invalid delimiters"));
    }
    Ok((pd, rd))
}

/// Global section, units: the model-space scale (G13), the file's unit (G14/G15) and the factor
/// converting coordinates to `opts.unit` (1 when not converting), as (scale, unit, factor).
fn global_units(gtoks: &[Tok], opts: ReadOptions, notices: &mut Vec<String>) -> Result<(f64, Option<Unit>, f64)> {
    let greal = |i: usize| -> Option<f64> {
        match gtoks.get(i) {
            Some(Tok::Num(s)) => parse_real(s),
            _ => None,
        }
    };
    let gstr = |i: usize| -> String {
        match gtoks.get(i) {
            Some(Tok::Str(s)) => s.clone(),
            _ => String::new(),
        }
    };
    let scale = match greal(12) {
        Some(s) if s.is_finite() && s > 0.0 => s,
        None => 1.0,
        Some(s) => {
            notices.push(format!("global section: model-space scale {s} is invalid; 1 is used"));
            1.0
        }
    };
    let unit_flag = greal(13)
        .filter(|f| f.fract() == 0.0 && f.abs() < 1e6)
        .map(|f| f as i64);
    let unit = match unit_flag {
        Some(f) => Unit::from_flag(f, &gstr(14)),
        None => Unit::from_name(&gstr(14)),
    };
    let factor = match opts.unit {
        None => 1.0,
        Some(target) => {
            let Some(from) = unit else {
                return Err(perr(format!(
                    "global section: unit flag {unit_flag:?} / name {:?} not recognised, cannot convert to {}",
                    gstr(14),
                    target.name()
                )));
            };
            from.in_mm() / target.in_mm() / scale
        }
    };
    Ok((scale, unit, factor))
}

/// Directory: the entries, one per pair of `D` records (the fields the reader uses).
fn directory_entries(dlines: &[&[u8]]) -> Result<Vec<DirEntry>> {
    if !dlines.len().is_multiple_of(2) {
        return Err(perr(format!(
            "directory section has {} records; entries are pairs of records",
            dlines.len()
        )));
    }
    let mut entries = Vec::with_capacity(dlines.len() / 2);
    for (k, pair) in dlines.chunks_exact(2).enumerate() {
        let seq = 2 * k + 1;
        let what = format!("directory entry {seq}");
        let (a, b) = (pair[0], pair[1]);
        entries.push(DirEntry {
            seq,
            etype: int8(a, 0, &what)?,
            pstart: int8(a, 1, &what)?,
            transform: int8(a, 6, &what)?,
            status: String::from_utf8_lossy(field8(a, 8)).replace(' ', "0"),
            plines: int8(b, 3, &what)?,
            form: int8(b, 4, &what)?,
            label: {
                // fields 18-19 are informative only: a malformed subscript is ignored
                let name = String::from_utf8_lossy(field8(b, 7)).trim().to_string();
                match int8(b, 8, &what) {
                    Ok(sub) if sub != 0 => format!("{name}({sub})"),
                    _ => name,
                }
            },
        });
    }
    Ok(entries)
}

/// What reading the entities needs of the file: the directory, the parameter records, the
/// delimiters and the unit conversion factor.
struct DataSections<'a> {
    entries: &'a [DirEntry],
    plines: &'a [&'a [u8]],
    pd: u8,
    rd: u8,
    factor: f64,
}

impl DataSections<'_> {
    /// Entities: each curve and surface read (one bad entity skips that entity, listed in the
    /// notices, not the file), as (objects, their entity infos, the first error met).
    fn read_entities(&self, notices: &mut Vec<String>) -> (Vec<Geometry>, Vec<EntityInfo>, Option<Error>) {
        let mut budget = self.plines.len().saturating_mul(4).saturating_add(64);
        let mut objects = Vec::new();
        let mut infos = Vec::new();
        let mut first_error: Option<Error> = None;
        for e in self.entries {
            let Some(what) = entity_what(e, notices) else {
                continue;
            };
            let pieces = match self.read_entity(e, &what, &mut budget, notices) {
                Ok(g) => g,
                Err(err) => {
                    let reason = match &err {
                        Error::Parse { message, .. } => message
                            .strip_prefix(&format!("{what}: "))
                            .unwrap_or(message)
                            .to_string(),
                        other => other.to_string(),
                    };
                    notices.push(format!("{what} skipped: {reason}"));
                    first_error.get_or_insert(err);
                    continue;
                }
            };
            let count = pieces.len();
            for (k, geom) in pieces.into_iter().enumerate() {
                objects.push(geom);
                let piece = if count > 1 {
                    format!("piece {} of {count}", k + 1)
                } else {
                    String::new()
                };
                infos.push(EntityInfo {
                    entity: e.seq,
                    label: [e.label.as_str(), piece.as_str()]
                        .iter()
                        .filter(|t| !t.is_empty())
                        .copied()
                        .collect::<Vec<_>>()
                        .join(", "),
                });
            }
        }
        (objects, infos, first_error)
    }

    /// One entity: its parameters parsed, its transformation chain and the unit factor applied,
    /// its coordinates range-checked; several objects where a break (a knot above the degree's
    /// multiplicity) splits it ([`crate::knots::resolve_breaks`]).
    fn read_entity(
        &self,
        e: &DirEntry,
        what: &str,
        budget: &mut usize,
        notices: &mut Vec<String>,
    ) -> Result<Vec<Geometry>> {
        let (pd, rd, factor) = (self.pd, self.rd, self.factor);
        let toks = entity_params(self.plines, e, what, pd, rd, budget)?;
        let mut p = Params {
            toks: &toks,
            pos: 1,
            what: what.to_string(),
        };
        let xf = transform_chain(self.entries, self.plines, e.transform, pd, rd, budget)?;
        let pieces = if e.etype == 126 {
            read_126(&mut p, notices)?
        } else {
            read_128(&mut p, notices)?
        };
        let mut out = Vec::with_capacity(pieces.len());
        for mut geom in pieces {
            if let Some(m) = xf {
                geom = apply(geom, |q| m.apply(q))?;
            }
            if factor != 1.0 {
                geom = apply(geom, |q| q * factor)?;
            }
            crate::range::check_geometry(&geom).map_err(|e| perr(format!("{what}: {e}")))?;
            out.push(geom);
        }
        Ok(out)
    }
}

/// Entity filter: the name of a curve (126) or surface (128) entry for the messages, or `None`
/// (with a notice, except for transformation matrices, 124) for an entry that is not read.
fn entity_what(e: &DirEntry, notices: &mut Vec<String>) -> Option<String> {
    let kind = match e.etype {
        126 => "curve",
        128 => "surface",
        _ => {
            if e.etype != 124 {
                notices.push(format!(
                    "entity {} (type {}, form {}) skipped: only B-spline curves (126) and surfaces (128) are read",
                    e.seq, e.etype, e.form
                ));
            }
            return None;
        }
    };
    // use flag (status digits 5-6) 05 = 2D parametric: a curve on a surface
    if e.etype == 126 && e.status.get(4..6) == Some("05") {
        notices.push(format!(
            "entity {} (126) skipped: a curve in a surface's parameter space",
            e.seq
        ));
        return None;
    }
    let what = format!("entity {} ({kind} 126/128)", e.seq).replace("(curve 126/128)", "(curve, 126)");
    Some(what.replace("(surface 126/128)", "(surface, 128)"))
}

fn entity_params(plines: &[&[u8]], e: &DirEntry, what: &str, pd: u8, rd: u8, budget: &mut usize) -> Result<Vec<Tok>> {
    if e.pstart < 1 || e.plines < 1 {
        return Err(perr(format!(
            "{what}: parameter pointer {} / line count {} invalid",
            e.pstart, e.plines
        )));
    }
    let start = (e.pstart - 1) as usize;
    let count = e.plines as usize;
    if start >= plines.len() || count > plines.len() - start {
        return Err(perr(format!(
            "{what}: parameter lines {}..{} outside the P section ({} lines)",
            e.pstart,
            e.pstart.saturating_add(e.plines),
            plines.len()
        )));
    }
    if count > *budget {
        return Err(perr(format!("{what}: parameter data pointers overlap too much")));
    }
    *budget -= count;
    let mut text = Vec::with_capacity(count * 64);
    for l in &plines[start..start + count] {
        text.extend_from_slice(l);
    }
    let toks = tokenize(&text, pd, rd);
    match toks.first() {
        Some(Tok::Num(s)) if parse_real(s) == Some(e.etype as f64) => Ok(toks),
        _ => Err(perr(format!(
            "{what}: parameter data does not start with the entity type {}",
            e.etype
        ))),
    }
}

/// An affine map x ↦ R x + t (entity 124).
#[derive(Clone, Copy)]
struct Affine {
    r: [[f64; 3]; 3],
    t: [f64; 3],
}

impl Affine {
    fn apply(&self, q: DVec3) -> DVec3 {
        let a = q.to_array();
        let mut o = [0.0; 3];
        for i in 0..3 {
            o[i] = self.r[i][0] * a[0] + self.r[i][1] * a[1] + self.r[i][2] * a[2] + self.t[i];
        }
        DVec3::from_array(o)
    }
    fn then(&self, outer: &Affine) -> Affine {
        // outer ∘ self
        let mut r = [[0.0; 3]; 3];
        let mut t = [0.0; 3];
        for i in 0..3 {
            for j in 0..3 {
                r[i][j] = (0..3).map(|k| outer.r[i][k] * self.r[k][j]).sum();
            }
            t[i] = (0..3).map(|k| outer.r[i][k] * self.t[k]).sum::<f64>() + outer.t[i];
        }
        Affine { r, t }
    }
}

fn transform_chain(
    entries: &[DirEntry],
    plines: &[&[u8]],
    mut ptr: i64,
    pd: u8,
    rd: u8,
    budget: &mut usize,
) -> Result<Option<Affine>> {
    let mut acc: Option<Affine> = None;
    let mut depth = 0;
    while ptr != 0 {
        depth += 1;
        if depth > 16 {
            return Err(perr("transformation matrices chained more than 16 deep (a cycle?)"));
        }
        let what = format!("transformation matrix {ptr}");
        if ptr < 1 || ptr % 2 == 0 || ((ptr - 1) / 2) as usize >= entries.len() {
            return Err(perr(format!("{what}: not a directory entry")));
        }
        let e = &entries[((ptr - 1) / 2) as usize];
        if e.etype != 124 {
            return Err(perr(format!("{what}: entity type {}, expected 124", e.etype)));
        }
        let toks = entity_params(plines, e, &what, pd, rd, budget)?;
        let mut p = Params {
            toks: &toks,
            pos: 1,
            what,
        };
        let mut m = Affine {
            r: [[0.0; 3]; 3],
            t: [0.0; 3],
        };
        for i in 0..3 {
            for j in 0..3 {
                m.r[i][j] = p.real()?;
            }
            m.t[i] = p.real()?;
        }
        acc = Some(match acc {
            None => m,
            Some(a) => a.then(&m),
        });
        ptr = e.transform;
    }
    Ok(acc)
}

fn apply(g: Geometry, f: impl Fn(DVec3) -> DVec3) -> Result<Geometry> {
    Ok(match g {
        Geometry::Curve(c) => {
            let pts: Vec<DVec3> = c.points().iter().map(|&q| f(q)).collect();
            let planar_z0 = pts.iter().all(|q| q.z == 0.0);
            let dim = if c.dim() == 2 && planar_z0 { 2 } else { 3 };
            Geometry::Curve(BSplineCurve::try_new(
                c.degree(),
                c.knots().values().to_vec(),
                pts,
                c.weights().map(|w| w.to_vec()),
                dim,
            )?)
        }
        Geometry::Surface(s) => {
            let pts = s.points().iter().map(|&q| f(q)).collect();
            Geometry::Surface(s.with_points(pts)?)
        }
    })
}

/// Check `needed` parameters are present before allocating anything for them.
fn need(p: &Params<'_>, needed: Option<usize>) -> Result<()> {
    match needed {
        Some(n) if n <= p.remaining() => Ok(()),
        _ => Err(perr(format!(
            "{}: the counts in the parameters need {} more values, only {} present",
            p.what,
            needed.map_or("too many".to_string(), |n| n.to_string()),
            p.remaining()
        ))),
    }
}

fn read_126(p: &mut Params<'_>, notices: &mut Vec<String>) -> Result<Vec<Geometry>> {
    let k = p.count("K (number of control points − 1)", i64::from(u32::MAX))?;
    let m = p.count("M (degree)", MAX_DEGREE as i64)?;
    if m == 0 {
        return Err(perr(format!(
            "{}: degree 0 is not supported (1 to {MAX_DEGREE})",
            p.what
        )));
    }
    let planar = p.int()?;
    let _closed = p.int()?;
    let polynomial = p.int()?;
    let periodic = p.int()?;
    let n_pts = k.checked_add(1);
    let n_knots = k.checked_add(m).and_then(|v| v.checked_add(2));
    need(
        p,
        n_knots.and_then(|a| {
            n_pts
                .and_then(|b| b.checked_mul(4))
                .and_then(|b| b.checked_add(a))
                .map(|x| x + 2)
        }),
    )?;
    let (n_pts, n_knots) = (k + 1, k + m + 2);
    if n_pts < m + 1 {
        return Err(Error::TooFewPoints {
            field: format!("{} points", p.what),
            count: n_pts,
            degree: m,
            needed: m + 1,
        });
    }
    let mut knots = Vec::with_capacity(n_knots);
    for _ in 0..n_knots {
        knots.push(p.real()?);
    }
    let mut w = Vec::with_capacity(n_pts);
    for _ in 0..n_pts {
        w.push(p.real()?);
    }
    let mut pts = Vec::with_capacity(n_pts);
    for _ in 0..n_pts {
        pts.push(DVec3::new(p.real()?, p.real()?, p.real()?));
    }
    let v0 = p.real()?;
    let v1 = p.real()?;
    let rational = polynomial == 0;
    check_weights(&w, rational, &p.what)?;
    let hom: Vec<DVec4> = pts
        .iter()
        .zip(&w)
        .map(|(q, &wi)| if rational { (*q * wi).extend(wi) } else { q.extend(1.0) })
        .collect();
    // Already clamped: the values as read (bit-exact); otherwise converted.
    let (knots, pts, weights) = match clamp_to(knots.clone(), hom, m, v0, v1, periodic != 0, &p.what, notices)? {
        None => (knots, pts, rational.then_some(w)),
        Some((k, hom)) => (
            k,
            hom.iter().map(|h| h.truncate() / h.w).collect(),
            rational.then(|| hom.iter().map(|h| h.w).collect()),
        ),
    };
    let dim = if planar == 1 && pts.iter().all(|q| q.z == 0.0) {
        2
    } else {
        3
    };
    let scale = coordinate_scale(&pts);
    let same =
        |a: usize, b: usize| pts[a].distance(pts[b]) <= 1e-9 * scale && weights.as_ref().is_none_or(|w| w[a] == w[b]);
    let (pieces, breaks) = crate::knots::resolve_breaks(&knots, m, same);
    note_breaks(notices, &p.what, "", &breaks, pieces.len());
    pieces
        .into_iter()
        .map(|pc| {
            let w = weights.as_ref().map(|w| pc.points.iter().map(|&i| w[i]).collect());
            let q = pc.points.iter().map(|&i| pts[i]).collect();
            Ok(Geometry::Curve(BSplineCurve::try_new(m, pc.knots, q, w, dim)?))
        })
        .collect()
}

/// The largest coordinate magnitude of `pts` (at least 1e-300): the scale of "coincide" at a break.
fn coordinate_scale(pts: &[DVec3]) -> f64 {
    pts.iter().map(|q| q.abs().max_element()).fold(1e-300, f64::max)
}

/// One notice per break resolved by [`crate::knots::resolve_breaks`] (`dir` names the direction of a
/// surface, empty for a curve).
fn note_breaks(notices: &mut Vec<String>, what: &str, dir: &str, breaks: &[crate::knots::Break], pieces: usize) {
    for b in breaks {
        notices.push(match b {
            crate::knots::Break::Reduced(u) => format!(
                "{what}: knot {dir}{u} has multiplicity above the degree but the geometry is continuous there: \
                 reduced to a C0 knot (same shape)"
            ),
            crate::knots::Break::Split(u) => format!(
                "{what}: the geometry breaks at knot {dir}{u} (multiplicity above the degree): split there, \
                 {pieces} pieces in all"
            ),
        });
    }
}

fn check_weights(w: &[f64], rational: bool, what: &str) -> Result<()> {
    if rational && let Some((i, &x)) = w.iter().enumerate().find(|(_, x)| **x <= 0.0) {
        return Err(Error::BadWeight {
            field: format!("{what} weights"),
            index: i,
            value: x,
        });
    }
    Ok(())
}

fn read_128(p: &mut Params<'_>, notices: &mut Vec<String>) -> Result<Vec<Geometry>> {
    let h = read_128_header(p)?;
    let (nu, nv, total, rational) = (h.nu, h.nv, h.nu * h.nv, h.polynomial == 0);
    let (ku, kv, w, pts, (u0, u1, v0, v1)) = read_128_values(p, &h)?;
    check_weights(&w, rational, &p.what)?;
    // IGES order: index (i, j) at i + j*nu (u fastest); Fairway's is row-major i*nv + j.
    let hom_at = |i: usize, j: usize| {
        let q = pts[i + j * nu];
        let wi = w[i + j * nu];
        if rational { (q * wi).extend(wi) } else { q.extend(1.0) }
    };
    // clamp in u: for each j, the row over i
    let rows: Vec<Vec<DVec4>> = (0..nv).map(|j| (0..nu).map(|i| hom_at(i, j)).collect()).collect();
    let (new_ku, cols) = clamp_lines(&ku, rows, h.m1, (u0, u1), h.periodic_u != 0, &p.what, "u", notices)?;
    let nu2 = cols.first().map_or(0, |c| c.len());
    // clamp in v: for each i, the column over j
    let by_i: Vec<Vec<DVec4>> = (0..nu2).map(|i| cols.iter().map(|c| c[i]).collect()).collect();
    let (new_kv, grid) = clamp_lines(&kv, by_i, h.m2, (v0, v1), h.periodic_v != 0, &p.what, "v", notices)?;
    let nv2 = grid.first().map_or(0, |c| c.len());
    let (points, weights) = if new_ku.is_none() && new_kv.is_none() {
        // Already clamped: the values as read (bit-exact).
        let mut points = Vec::with_capacity(total);
        let mut ws = Vec::with_capacity(total);
        for i in 0..nu {
            for j in 0..nv {
                points.push(pts[i + j * nu]);
                ws.push(w[i + j * nu]);
            }
        }
        (points, rational.then_some(ws))
    } else {
        let flat: Vec<DVec4> = grid.into_iter().flatten().collect();
        (
            flat.iter().map(|h| h.truncate() / h.w).collect(),
            rational.then(|| flat.iter().map(|h| h.w).collect()),
        )
    };
    let (ku, kv) = (new_ku.unwrap_or(ku), new_kv.unwrap_or(kv));
    if points.len() != nu2 * nv2 {
        return Ok(vec![Geometry::Surface(BSplineSurface::try_new(
            h.m1, h.m2, ku, kv, nu2, nv2, points, weights,
        )?)]);
    }
    surface_pieces(&p.what, notices, (h.m1, h.m2), (ku, kv), nv2, points, weights)
}

/// A surface read from a file, its breaks (knots above the degree's multiplicity) resolved in u, then in
/// v on each u-piece ([`crate::knots::resolve_breaks`]): reduced where the rows coincide, split otherwise.
fn surface_pieces(
    what: &str,
    notices: &mut Vec<String>,
    (pu, pv): (usize, usize),
    (ku, kv): (Vec<f64>, Vec<f64>),
    nv: usize,
    points: Vec<DVec3>,
    weights: Option<Vec<f64>>,
) -> Result<Vec<Geometry>> {
    let scale = coordinate_scale(&points);
    let at = |i: usize, j: usize| i * nv + j;
    let same_pt = |a: usize, b: usize| {
        points[a].distance(points[b]) <= 1e-9 * scale && weights.as_ref().is_none_or(|w| w[a] == w[b])
    };
    let (u_pieces, u_breaks) =
        crate::knots::resolve_breaks(&ku, pu, |a, b| (0..nv).all(|j| same_pt(at(a, j), at(b, j))));
    let mut all = vec![];
    let mut v_notes = vec![];
    for up in &u_pieces {
        let (v_pieces, v_breaks) =
            crate::knots::resolve_breaks(&kv, pv, |a, b| up.points.iter().all(|&i| same_pt(at(i, a), at(i, b))));
        v_notes.extend(v_breaks);
        for vp in v_pieces {
            let idx: Vec<usize> = up
                .points
                .iter()
                .flat_map(|&i| vp.points.iter().map(move |&j| at(i, j)))
                .collect();
            all.push(Geometry::Surface(BSplineSurface::try_new(
                pu,
                pv,
                up.knots.clone(),
                vp.knots,
                up.points.len(),
                vp.points.len(),
                idx.iter().map(|&k| points[k]).collect(),
                weights.as_ref().map(|w| idx.iter().map(|&k| w[k]).collect()),
            )?));
        }
    }
    note_breaks(notices, what, "u = ", &u_breaks, all.len());
    v_notes.dedup();
    note_breaks(notices, what, "v = ", &v_notes, all.len());
    Ok(all)
}

/// The counts and flags heading an entity 128's parameters.
struct Header128 {
    nu: usize,
    nv: usize,
    m1: usize,
    m2: usize,
    polynomial: i64,
    periodic_u: i64,
    periodic_v: i64,
}

/// Entity 128 header: counts, degrees and flags read and checked (degrees, enough values
/// present before anything is allocated, enough points per direction).
fn read_128_header(p: &mut Params<'_>) -> Result<Header128> {
    let k1 = p.count("K1", i64::from(u32::MAX))?;
    let k2 = p.count("K2", i64::from(u32::MAX))?;
    let m1 = p.count("M1 (degree in u)", MAX_DEGREE as i64)?;
    let m2 = p.count("M2 (degree in v)", MAX_DEGREE as i64)?;
    if m1 == 0 || m2 == 0 {
        return Err(perr(format!(
            "{}: degree 0 is not supported (1 to {MAX_DEGREE})",
            p.what
        )));
    }
    let _closed_u = p.int()?;
    let _closed_v = p.int()?;
    let polynomial = p.int()?;
    let periodic_u = p.int()?;
    let periodic_v = p.int()?;
    let nu = k1.checked_add(1);
    let nv = k2.checked_add(1);
    let nk_u = k1.checked_add(m1 + 2);
    let nk_v = k2.checked_add(m2 + 2);
    let total = nu.zip(nv).and_then(|(a, b)| a.checked_mul(b));
    let needed = total
        .and_then(|t| t.checked_mul(4))
        .zip(nk_u.zip(nk_v))
        .and_then(|(a, (b, c))| a.checked_add(b)?.checked_add(c)?.checked_add(4));
    need(p, needed)?;
    let (nu, nv) = (k1 + 1, k2 + 1);
    for (n, m, f) in [(nu, m1, "u"), (nv, m2, "v")] {
        if n < m + 1 {
            return Err(Error::TooFewPoints {
                field: format!("{} points in {f}", p.what),
                count: n,
                degree: m,
                needed: m + 1,
            });
        }
    }
    Ok(Header128 {
        nu,
        nv,
        m1,
        m2,
        polynomial,
        periodic_u,
        periodic_v,
    })
}

/// The values of an entity 128: knots in u and v, weights, points and the (u0, u1, v0, v1)
/// parameter range.
type Values128 = (Vec<f64>, Vec<f64>, Vec<f64>, Vec<DVec3>, (f64, f64, f64, f64));

/// Entity 128 values: knots, weights, points (IGES order) and parameter range, as read.
fn read_128_values(p: &mut Params<'_>, h: &Header128) -> Result<Values128> {
    let (nk_u, nk_v, total) = (h.nu + h.m1 + 1, h.nv + h.m2 + 1, h.nu * h.nv);
    let mut ku = Vec::with_capacity(nk_u);
    for _ in 0..nk_u {
        ku.push(p.real()?);
    }
    let mut kv = Vec::with_capacity(nk_v);
    for _ in 0..nk_v {
        kv.push(p.real()?);
    }
    let mut w = Vec::with_capacity(total);
    for _ in 0..total {
        w.push(p.real()?);
    }
    let mut pts = Vec::with_capacity(total);
    for _ in 0..total {
        pts.push(DVec3::new(p.real()?, p.real()?, p.real()?));
    }
    let range = (p.real()?, p.real()?, p.real()?, p.real()?);
    Ok((ku, kv, w, pts, range))
}

/// The new knots (if any line was converted) and the lines of homogeneous points.
type ClampedLines = (Option<Vec<f64>>, Vec<Vec<DVec4>>);

/// Entity 128 clamping in one direction: each line of homogeneous points clamped to the
/// parameter range `(t0, t1)` (the first line's notices kept, tagged with `dir`), as (the new
/// knots if any line was converted, the lines).
#[allow(clippy::too_many_arguments)]
fn clamp_lines(
    knots: &[f64],
    lines: Vec<Vec<DVec4>>,
    degree: usize,
    (t0, t1): (f64, f64),
    periodic: bool,
    what: &str,
    dir: &str,
    notices: &mut Vec<String>,
) -> Result<ClampedLines> {
    let mut new_knots = None;
    let mut out: Vec<Vec<DVec4>> = Vec::with_capacity(lines.len());
    for (j, line) in lines.into_iter().enumerate() {
        let mut sink = Vec::new();
        match clamp_to(knots.to_vec(), line.clone(), degree, t0, t1, periodic, what, &mut sink)? {
            None => out.push(line),
            Some((k, r)) => {
                new_knots = Some(k);
                out.push(r);
            }
        }
        if j == 0 {
            notices.extend(sink.into_iter().map(|s| format!("{s} ({dir} direction)")));
        }
    }
    Ok((new_knots, out))
}

/// Boehm insertion (The NURBS Book A5.1) of `u` once into an arbitrary
/// (possibly unclamped) knot vector, on homogeneous points.
fn insert_once(knots: &[f64], pts: &[DVec4], p: usize, u: f64) -> (Vec<f64>, Vec<DVec4>) {
    let n = pts.len();
    // span k: knots[k] <= u < knots[k+1], with p <= k <= n-1
    let mut k = p;
    while k + 1 < n && knots[k + 1] <= u {
        k += 1;
    }
    let s = knots[..=k].iter().filter(|&&t| t == u).count();
    let mut q = Vec::with_capacity(n + 1);
    for i in 0..=n {
        if i + p <= k {
            q.push(pts[i]);
        } else if i > k.saturating_sub(s) {
            q.push(pts[i - 1]);
        } else {
            let a = (u - knots[i]) / (knots[i + p] - knots[i]);
            q.push(pts[i] * a + pts[i - 1] * (1.0 - a));
        }
    }
    let mut kn = Vec::with_capacity(knots.len() + 1);
    kn.extend_from_slice(&knots[..=k]);
    kn.push(u);
    kn.extend_from_slice(&knots[k + 1..]);
    (kn, q)
}

/// Make a B-spline clamped on `[v0, v1] ∩ [t_p, t_n]` by inserting the ends
/// until their multiplicity is p, then dropping the knots and points outside.
/// The curve over the kept range is unchanged.
#[allow(clippy::too_many_arguments)]
fn clamp_to(
    mut knots: Vec<f64>,
    mut pts: Vec<DVec4>,
    p: usize,
    v0: f64,
    v1: f64,
    periodic: bool,
    what: &str,
    notices: &mut Vec<String>,
) -> Result<Option<(Vec<f64>, Vec<DVec4>)>> {
    let n = pts.len();
    if knots.len() != n + p + 1 {
        return Err(perr(format!("{what}: knot count does not match")));
    }
    if let Some(i) = (1..knots.len()).find(|&i| knots[i] < knots[i - 1]) {
        return Err(Error::KnotsDecreasing {
            field: format!("{what} knots"),
            index: i,
            prev: knots[i - 1],
            next: knots[i],
        });
    }
    let (ta, tb) = (knots[p], knots[n]);
    if tb <= ta {
        return Err(Error::EmptyDomain {
            field: format!("{what} knots"),
            start: ta,
            end: tb,
        });
    }
    // A parameter range outside the knot domain (or not given) means the whole domain.
    let (mut a, mut b) = (v0.max(ta), v1.min(tb));
    if !(a < b) {
        a = ta;
        b = tb;
    }
    let clamped = knots[..=p].iter().all(|&t| t == knots[0])
        && knots[n..].iter().all(|&t| t == knots[n + p])
        && a == knots[0]
        && b == knots[n + p];
    if clamped {
        return Ok(None);
    }
    for u in [a, b] {
        let mut guard = 0;
        loop {
            let k = knots.iter().filter(|&&t| t == u).count();
            if k >= p || guard > p {
                break;
            }
            (knots, pts) = insert_once(&knots, &pts, p, u);
            guard += 1;
        }
    }
    // Now a and b have multiplicity >= p. With the run of a starting at
    // index s: C(a) = P[s-1] when the run has exactly p knots (the basis
    // functions before it vanish on [a, b]), P[s + mult - p - 1] when longer.
    let first_a = knots.iter().position(|&t| t == a).unwrap_or(0);
    let mult_a = knots.iter().filter(|&&t| t == a).count();
    let i0 = if mult_a > p {
        first_a + mult_a - p - 1
    } else {
        first_a.saturating_sub(1)
    };
    // The kept knots: a (p + 1 times), the interior ones, b (p + 1 times).
    let mut new_knots = vec![a; p + 1];
    new_knots.extend(knots.iter().copied().filter(|&t| t > a && t < b));
    new_knots.extend(std::iter::repeat_n(b, p + 1));
    let n_new = new_knots.len() - p - 1;
    if i0 + n_new > pts.len() {
        return Err(perr(format!("{what}: cannot clamp the knot vector")));
    }
    let new_pts = pts[i0..i0 + n_new].to_vec();
    notices.push(format!(
        "{what}: {} knot vector converted to a clamped one on [{a}, {b}] by knot insertion",
        if periodic { "periodic" } else { "non-clamped" }
    ));
    Ok(Some((new_knots, new_pts)))
}

/// Read the first curve or surface of an IGES file.
pub fn read_first(bytes: &[u8]) -> Result<Geometry> {
    let f = read_all(bytes)?;
    f.objects.into_iter().next().ok_or_else(|| {
        perr(format!(
            "no B-spline curve (126) or surface (128) in the file{}",
            if f.notices.is_empty() {
                String::new()
            } else {
                format!(" ({})", f.notices.join("; "))
            }
        ))
    })
}

// ---------------------------------------------------------------- writing

/// A float as an IGES real: the shortest decimal that parses back to the
/// same f64, with a decimal point and a `D` exponent (`1.5`, `1.0D-7`).
pub fn format_real(x: f64) -> String {
    let s = format!("{x:e}");
    let (mant, exp) = s.split_once('e').unwrap_or((&s, "0"));
    let mut m = mant.to_string();
    if !m.contains('.') {
        m.push_str(".0");
    }
    if exp == "0" { m } else { format!("{m}D{exp}") }
}

fn hollerith(s: &str) -> String {
    format!("{}H{s}", s.len())
}

/// Wrap tokens (each followed by its delimiter) into lines of at most `width` columns.
fn wrap(tokens: &[String], width: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut cur = String::new();
    let last = tokens.len().saturating_sub(1);
    for (i, t) in tokens.iter().enumerate() {
        let piece = format!("{t}{}", if i == last { ';' } else { ',' });
        if !cur.is_empty() && cur.len() + piece.len() > width {
            lines.push(std::mem::take(&mut cur));
        }
        if piece.len() > width {
            // a long string: split it across lines (only Hollerith can be this long)
            let bytes = piece.as_bytes();
            for chunk in bytes.chunks(width) {
                lines.push(String::from_utf8_lossy(chunk).into_owned());
            }
            continue;
        }
        cur.push_str(&piece);
    }
    if !cur.is_empty() {
        lines.push(cur);
    }
    lines
}

pub(crate) fn now_stamp() -> String {
    let [y, m, d, h, n, s] = now_utc();
    format!("{y:04}{m:02}{d:02}.{h:02}{n:02}{s:02}")
}

/// The time now (UTC) as [year, month, day, hour, minute, second].
pub(crate) fn now_utc() -> [i64; 6] {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs()) as i64;
    let days = secs.div_euclid(86_400);
    let rem = secs.rem_euclid(86_400);
    // civil from days (H. Hinnant)
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + if m <= 2 { 1 } else { 0 };
    [y, m, d, rem / 3600, (rem / 60) % 60, rem % 60]
}

fn curve_params(c: &BSplineCurve) -> Vec<String> {
    let p = c.degree();
    let n = c.n_points();
    let planar = c.dim() == 2;
    let closed = c.points().first() == c.points().last();
    let mut t = vec![
        "126".to_string(),
        (n - 1).to_string(),
        p.to_string(),
        (planar as u8).to_string(),
        (closed as u8).to_string(),
        (!c.is_rational() as u8).to_string(),
        "0".to_string(),
    ];
    t.extend(c.knots().values().iter().map(|&v| format_real(v)));
    match c.weights() {
        Some(w) => t.extend(w.iter().map(|&v| format_real(v))),
        None => t.extend(std::iter::repeat_n(format_real(1.0), n)),
    }
    for q in c.points() {
        t.extend([q.x, q.y, q.z].map(format_real));
    }
    let (a, b) = c.domain();
    t.push(format_real(a));
    t.push(format_real(b));
    let nrm = if planar { [0.0, 0.0, 1.0] } else { [0.0, 0.0, 0.0] };
    t.extend(nrm.map(format_real));
    t
}

fn surface_params(s: &BSplineSurface) -> Vec<String> {
    let (nu, nv) = (s.nu(), s.nv());
    let mut t = vec![
        "128".to_string(),
        (nu - 1).to_string(),
        (nv - 1).to_string(),
        s.degree_u().to_string(),
        s.degree_v().to_string(),
        "0".into(),
        "0".into(),
        (!s.is_rational() as u8).to_string(),
        "0".into(),
        "0".into(),
    ];
    t.extend(s.knots_u().values().iter().map(|&v| format_real(v)));
    t.extend(s.knots_v().values().iter().map(|&v| format_real(v)));
    for j in 0..nv {
        for i in 0..nu {
            t.push(format_real(s.weights().map_or(1.0, |w| w[i * nv + j])));
        }
    }
    for j in 0..nv {
        for i in 0..nu {
            let q = s.point_at(i, j);
            t.extend([q.x, q.y, q.z].map(format_real));
        }
    }
    let ((u0, u1), (v0, v1)) = s.domain();
    t.extend([u0, u1, v0, v1].map(format_real));
    t
}

fn record(body: &str, letter: char, seq: usize) -> String {
    format!("{body:<72}{letter}{seq:>7}\n")
}

/// Write curves and surfaces as an IGES 5.3 fixed-format file.
pub fn write(objects: &[Geometry], opts: &WriteOptions) -> String {
    let date = opts.date.clone().unwrap_or_else(now_stamp);
    let mut out = String::new();
    // S
    let s_lines = ["Fairway IGES export: rational B-spline curves (126) and surfaces (128)."];
    for (i, l) in s_lines.iter().enumerate() {
        out.push_str(&record(l, 'S', i + 1));
    }
    // G
    let max_coord = objects
        .iter()
        .flat_map(|g| match g {
            Geometry::Curve(c) => c.points().to_vec(),
            Geometry::Surface(s) => s.points().to_vec(),
        })
        .map(|q| q.abs().max_element())
        .fold(0.0, f64::max);
    let g = vec![
        hollerith(","),
        hollerith(";"),
        hollerith("Fairway"),
        hollerith(&opts.file_name),
        hollerith("Fairway"),
        hollerith(env!("CARGO_PKG_VERSION")),
        "32".into(),
        "38".into(),
        "6".into(),
        "308".into(),
        "15".into(),
        hollerith("Fairway"),
        format_real(1.0),
        opts.unit.flag().to_string(),
        hollerith(opts.unit.name()),
        "1".into(),
        format_real(0.0),
        hollerith(&date),
        format_real(1e-10),
        format_real(max_coord),
        hollerith(""),
        hollerith(""),
        "11".into(),
        "0".into(),
        hollerith(&date),
    ];
    let g_lines = wrap(&g, 72);
    for (i, l) in g_lines.iter().enumerate() {
        out.push_str(&record(l, 'G', i + 1));
    }
    // P data first (to know the pointers), then D.
    let mut d_out = String::new();
    let mut p_out = String::new();
    let mut p_seq = 1;
    for (k, gm) in objects.iter().enumerate() {
        let de = 2 * k + 1;
        let (etype, toks) = match gm {
            Geometry::Curve(c) => (126, curve_params(c)),
            Geometry::Surface(s) => (128, surface_params(s)),
        };
        let lines = wrap(&toks, 64);
        let start = p_seq;
        for l in &lines {
            p_out.push_str(&format!("{l:<64} {de:>7}P{p_seq:>7}\n"));
            p_seq += 1;
        }
        let d1 = format!(
            "{etype:>8}{start:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
            0, 0, 0, 0, 0, 0, "00000000"
        );
        let d2 = format!(
            "{etype:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
            0,
            0,
            lines.len(),
            0,
            "",
            "",
            "",
            0
        );
        d_out.push_str(&record(&d1, 'D', de));
        d_out.push_str(&record(&d2, 'D', de + 1));
    }
    out.push_str(&d_out);
    out.push_str(&p_out);
    let t = format!(
        "S{:>7}G{:>7}D{:>7}P{:>7}",
        s_lines.len(),
        g_lines.len(),
        2 * objects.len(),
        p_seq - 1
    );
    out.push_str(&record(&t, 'T', 1));
    out
}

/// One geometry as IGES text with default options.
pub fn to_string(g: &Geometry) -> String {
    write(std::slice::from_ref(g), &WriteOptions::default())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    fn sample_curve_2d() -> BSplineCurve {
        let pts = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0 / 3.0, 0.7),
            DVec2::new(1.1, -0.2),
            DVec2::new(2.0, std::f64::consts::PI),
            DVec2::new(3.0, 1e-9),
        ];
        BSplineCurve::new_2d(3, vec![0.0, 0.0, 0.0, 0.0, 0.1234567890123, 1.0, 1.0, 1.0, 1.0], &pts).unwrap()
    }

    fn sample_surface(rational: bool) -> BSplineSurface {
        let (nu, nv) = (4, 3);
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for i in 0..nu {
            for j in 0..nv {
                pts.push(DVec3::new(i as f64 * 0.7, j as f64 / 3.0, ((i * j) as f64).sin()));
                w.push(1.0 + 0.1 * (i + 2 * j) as f64);
            }
        }
        BSplineSurface::try_new(
            2,
            2,
            vec![0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0],
            vec![0.0, 0.0, 0.0, 2.0, 2.0, 2.0],
            nu,
            nv,
            pts,
            rational.then_some(w),
        )
        .unwrap()
    }

    #[test]
    fn records_are_80_columns_and_t_counts_match() {
        let text = write(
            &[sample_curve_2d().into(), sample_surface(true).into()],
            &WriteOptions::default(),
        );
        let mut counts = std::collections::BTreeMap::new();
        for l in text.lines() {
            assert_eq!(l.len(), 80, "{l:?}");
            *counts.entry(l.as_bytes()[72]).or_insert(0usize) += 1;
        }
        let t = text.lines().last().unwrap();
        let expect = format!(
            "S{:>7}G{:>7}D{:>7}P{:>7}",
            counts[&b'S'], counts[&b'G'], counts[&b'D'], counts[&b'P']
        );
        assert_eq!(&t[..32], expect);
        assert_eq!(counts[&b'D'], 4);
        // P back pointers point at the D entries, P pointers at the first P line.
        let plines: Vec<&str> = text.lines().filter(|l| l.as_bytes()[72] == b'P').collect();
        assert_eq!(plines[0][64..72].trim(), "1");
        assert_eq!(plines.last().unwrap()[64..72].trim(), "3");
        let d3 = text.lines().filter(|l| l.as_bytes()[72] == b'D').nth(2).unwrap();
        let pstart: usize = d3[8..16].trim().parse().unwrap();
        assert!(plines[pstart - 1].starts_with("128,"));
        assert_eq!(plines[pstart - 2][64..72].trim(), "1");
    }

    #[test]
    fn round_trip_is_exact() {
        let c2 = sample_curve_2d();
        let c3 = BSplineCurve::try_new(
            2,
            vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0],
            vec![
                DVec3::new(1.0, 2.0, 3.0),
                DVec3::new(-1e9, 0.1, 0.2),
                DVec3::new(1e-300, 5.5, -7.25),
                DVec3::new(0.1 + 0.2, 0.0, 1.0),
                DVec3::new(4.0, 4.0, 0.0),
            ],
            Some(vec![1.0, 0.5, 2.0, 0.3, 1.0]),
            3,
        )
        .unwrap();
        let objs: Vec<Geometry> = vec![
            c2.into(),
            c3.into(),
            sample_surface(true).into(),
            sample_surface(false).into(),
        ];
        let text = write(&objs, &WriteOptions::default());
        let back = read_all(text.as_bytes()).unwrap();
        assert_eq!(back.objects, objs, "bit-exact round trip");
        assert!(back.notices.is_empty(), "{:?}", back.notices);
        assert_eq!(back.unit, Some(Unit::Millimeter));
    }

    #[test]
    fn entity_numbers_and_labels_are_reported() {
        let text = write(
            &[sample_curve_2d().into(), sample_surface(false).into()],
            &WriteOptions::default(),
        );
        assert_eq!(
            read_all(text.as_bytes()).unwrap().entities,
            vec![
                EntityInfo {
                    entity: 1,
                    label: String::new()
                },
                EntityInfo {
                    entity: 3,
                    label: String::new()
                }
            ]
        );
        // label "HULL" (field 18) with subscript 2 (field 19) on the surface's second D record
        let lines: Vec<String> = text
            .lines()
            .map(|l| {
                if &l[72..] == "D      4" {
                    format!("{}{:>8}{:>8}{}", &l[..56], "HULL", 2, &l[72..])
                } else {
                    l.to_string()
                }
            })
            .collect();
        let f = read_all(lines.join("\n").as_bytes()).unwrap();
        assert_eq!(f.entities[0].label, "");
        assert_eq!(f.entities[1].label, "HULL(2)");
        assert_eq!(f.entities[1].entity, 3);
    }

    #[test]
    fn reals_parse_in_all_spellings() {
        for (s, v) in [
            ("1.", 1.0),
            (".5", 0.5),
            ("1.5D3", 1500.0),
            ("1.5E-3", 0.0015),
            ("-2", -2.0),
            ("+2.D0", 2.0),
            ("1D2", 100.0),
        ] {
            assert_eq!(parse_real(s), Some(v), "{s}");
        }
        for s in ["inf", "NaN", "", "-", "1.2.3", "D5", "1e", "0x10"] {
            assert_eq!(parse_real(s), None, "{s}");
        }
        for x in [0.1, -1e-300, 1.7976931348623157e308, 5e-324, 123456.789] {
            assert_eq!(parse_real(&format_real(x)), Some(x));
        }
    }

    /// Hand-written header with an unclamped uniform cubic (other CAD style)
    /// in inches, and a line entity (110) that is skipped.
    fn foreign_file(unit_flag: &str, scale: &str) -> String {
        let mut s = String::new();
        s.push_str(&record("foreign test", 'S', 1));
        let g = format!(
            "1H,,1H;,4HTEST,8Htest.igs,4HTEST,4HTEST,32,38,6,308,15,4HTEST,{scale},{unit_flag},2HIN,1,0.,15H20240101.000000,1.E-6,10.,,,11,0,;"
        );
        for (i, c) in g.as_bytes().chunks(72).enumerate() {
            s.push_str(&record(std::str::from_utf8(c).unwrap(), 'G', i + 1));
        }
        let line = "110,0.,0.,0.,1.,1.,1.;";
        // uniform knots 0..7 with 4 control points, degree 3 (unclamped)
        let bs =
            "126,3,3,0,0,1,0,0.,1.,2.,3.,4.,5.,6.,7.,1.,1.,1.,1.,0.,0.,0.,1.,2.,0.,2.,-1.,0.,3.,0.,1.,3.,4.,0.,0.,0.;";
        let d = |t: i64, p: usize, n: usize| {
            (
                format!(
                    "{t:>8}{p:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
                    0, 0, 0, 0, 0, 0, "00000000"
                ),
                format!("{t:>8}{:>8}{:>8}{n:>8}{:>8}", 0, 0, 0),
            )
        };
        let cut = bs[..64].rfind(',').unwrap() + 1;
        let bs_lines: Vec<&str> = vec![&bs[..cut], &bs[cut..]];
        let (a1, a2) = d(110, 1, 1);
        let (b1, b2) = d(126, 2, bs_lines.len());
        s.push_str(&record(&a1, 'D', 1));
        s.push_str(&record(&a2, 'D', 2));
        s.push_str(&record(&b1, 'D', 3));
        s.push_str(&record(&b2, 'D', 4));
        s.push_str(&format!("{line:<64} {:>7}P{:>7}\n", 1, 1));
        for (i, l) in bs_lines.iter().enumerate() {
            s.push_str(&format!("{l:<64} {:>7}P{:>7}\n", 3, i + 2));
        }
        s.push_str(&record("S      1G      2D      4P      3", 'T', 1));
        s
    }

    #[test]
    fn foreign_unclamped_curve_is_clamped_exactly_and_units_converted() {
        let text = foreign_file("1", "1.0");
        let f = read_all(text.as_bytes()).unwrap();
        assert_eq!(f.unit, Some(Unit::Inch));
        assert_eq!(f.objects.len(), 1);
        assert_eq!(f.notices.len(), 2, "{:?}", f.notices);
        assert!(f.notices[0].contains("type 110"));
        assert!(f.notices[1].contains("clamped"));
        let c = f.objects[0].as_curve().unwrap();
        assert_eq!(c.domain(), (3.0, 4.0));
        assert_eq!(c.dim(), 3);
        // the uniform cubic B-spline on span [3,4]: C(u) = Σ N_i(u) P_i with
        // the uniform blending (1−t)³/6, (3t³−6t²+4)/6, (−3t³+3t²+3t+1)/6, t³/6
        let p = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(2.0, -1.0, 0.0),
            DVec3::new(3.0, 0.0, 1.0),
        ];
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            let b = [
                (1.0 - t).powi(3) / 6.0,
                (3.0 * t.powi(3) - 6.0 * t * t + 4.0) / 6.0,
                (-3.0 * t.powi(3) + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
                t.powi(3) / 6.0,
            ];
            let want = p[0] * b[0] + p[1] * b[1] + p[2] * b[2] + p[3] * b[3];
            assert!((c.point(3.0 + t) - want).length() < 1e-13, "t={t}");
        }
        // converting inches to mm multiplies by 25.4 / scale
        let f2 = read_all_with(
            foreign_file("1", "2.0").as_bytes(),
            ReadOptions {
                unit: Some(Unit::Millimeter),
            },
        )
        .unwrap();
        let c2 = f2.objects[0].as_curve().unwrap();
        for (a, b) in c.points().iter().zip(c2.points()) {
            assert!((*a * 12.7 - *b).length() < 1e-12);
        }
    }

    #[test]
    fn transformation_matrix_is_applied() {
        let c = sample_curve_2d();
        let text = write(&[c.clone().into()], &WriteOptions::default());
        // Append a 124 entity (translation by (1,2,3), rotation z by 90°) and point the curve at it.
        let mut lines: Vec<String> = text.lines().map(String::from).collect();
        let d_idx = lines.iter().position(|l| l.as_bytes()[72] == b'D').unwrap();
        let p_count = lines.iter().filter(|l| l.as_bytes()[72] == b'P').count();
        let mut d1 = lines[d_idx].clone();
        d1.replace_range(48..56, &format!("{:>8}", 3));
        lines[d_idx] = d1;
        let m1 = format!(
            "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
            124,
            p_count + 1,
            0,
            0,
            0,
            0,
            0,
            0,
            "00000000"
        );
        let m2 = format!("{:>8}{:>8}{:>8}{:>8}{:>8}", 124, 0, 0, 1, 0);
        lines.insert(d_idx + 2, record(&m1, 'D', 3).trim_end_matches('\n').to_string());
        lines.insert(d_idx + 3, record(&m2, 'D', 4).trim_end_matches('\n').to_string());
        let t_idx = lines.len() - 1;
        let pbody = "124,0.,-1.,0.,1.,1.,0.,0.,2.,0.,0.,1.,3.;";
        lines.insert(t_idx, format!("{pbody:<64} {:>7}P{:>7}", 3, p_count + 1));
        let f = read_all(lines.join("\n").as_bytes()).unwrap();
        let g = f.objects[0].as_curve().unwrap();
        assert_eq!(g.dim(), 3);
        for (a, b) in c.points().iter().zip(g.points()) {
            let want = DVec3::new(-a.y + 1.0, a.x + 2.0, a.z + 3.0);
            assert!((want - *b).length() < 1e-15);
        }
    }

    #[test]
    fn bad_files_give_clear_errors() {
        let good = to_string(&sample_curve_2d().into());
        // edit the parameter data, keeping the 64-column field
        let edit = |from: &str, to: &str| -> String {
            good.lines()
                .map(|l| {
                    if l.as_bytes()[72] == b'P' && l[..64].contains(from) {
                        // make room: "1.0," and "0.0," have shorter spellings
                        let d = l[..64]
                            .replacen(from, to, 1)
                            .replace("1.0,", "1.,")
                            .replace("0.0,", "0.,");
                        let d = d.trim_end();
                        assert!(d.len() <= 64);
                        format!("{d:<64}{}\n", &l[64..])
                    } else {
                        format!("{l}\n")
                    }
                })
                .collect()
        };
        let cases: Vec<(String, &str)> = vec![
            (String::new(), "empty"),
            ("hello\n".into(), "80"),
            (edit("126,4,3", "126,900000000,3"), "more values"),
            (edit("126,4,3", "126,4,30"), "out of range"),
            (edit("126,4,3", "126,4,0"), "degree 0"),
            (edit("1.234567890123D-1", "1.234567890123D1"), "decrease"),
        ];
        for (text, want) in cases {
            let e = read_all(text.as_bytes()).unwrap_err().to_string();
            assert!(e.contains(want), "{want}: {e}");
        }
    }
}
