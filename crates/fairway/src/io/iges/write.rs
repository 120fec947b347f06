//! Writing: fixed-format records, each float as its shortest round-trip decimal.

use super::*;
use crate::trim::FaceTrim;

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

pub(super) fn hollerith(s: &str) -> String {
    format!("{}H{s}", s.len())
}

/// Wrap tokens (each followed by its delimiter) into lines of at most `width` columns.
pub(super) fn wrap(tokens: &[String], width: usize) -> Vec<String> {
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

pub(super) fn curve_params(c: &BSplineCurve) -> Vec<String> {
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

pub(super) fn surface_params(s: &BSplineSurface) -> Vec<String> {
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

pub(super) fn record(body: &str, letter: char, seq: usize) -> String {
    format!("{body:<72}{letter}{seq:>7}\n")
}

/// Write curves and surfaces as an IGES 5.3 fixed-format file.
pub fn write(objects: &[Geometry], opts: &WriteOptions) -> String {
    write_labeled(objects, &[], opts)
}

/// An object's label as IGES directory fields 18 and 19: `NAME(k)` (as [`read_all`] reports a label with
/// a subscript) gives `NAME` and `k`; the name is cut to 8 characters, anything but printable ASCII
/// replaced by `_`.
pub(super) fn label_fields(label: &str) -> (String, i64) {
    let (name, sub) = match label.strip_suffix(')').and_then(|l| l.rsplit_once('(')) {
        Some((n, k)) if k.parse::<i64>().is_ok_and(|k| (1..=99_999_999).contains(&k)) => (n, k.parse().unwrap_or(0)),
        _ => (label, 0),
    };
    let name: String = name
        .trim()
        .chars()
        .map(|c| if c.is_ascii_graphic() || c == ' ' { c } else { '_' })
        .take(8)
        .collect();
    (name, sub)
}

/// [`write()`] with a label per object (`labels[k]` for `objects[k]`; missing or empty: none), written to
/// directory fields 18–19 (`label_fields`), so that [`read_all`] reports them again.
pub fn write_labeled(objects: &[Geometry], labels: &[String], opts: &WriteOptions) -> String {
    write_trimmed(objects, labels, &[], opts)
}

/// [`write_labeled`] with the bounds of trimmed faces: `trims[k]` (if any) bounds the surface
/// `objects[k]`, written as a trimmed surface (144) whose boundaries (142) carry each loop twice, as its
/// curves in the surface's (u, v) exactly as stored and as curves in space recomputed on the surface as
/// it is now (module `write_trim`); the others as [`write_labeled`] writes them.
pub fn write_trimmed(
    objects: &[Geometry],
    labels: &[String],
    trims: &[Option<FaceTrim>],
    opts: &WriteOptions,
) -> String {
    write_with(objects, labels, trims, opts, super::write_trim::Boundaries::Both)
}

/// One entity to write: its type, form, status digits (blank, subordinate, use, hierarchy), label and
/// parameters (the type first).
pub(super) struct Entity {
    pub(super) etype: u32,
    pub(super) form: u32,
    pub(super) status: &'static str,
    pub(super) label: (String, i64),
    pub(super) params: Vec<String>,
}

/// The entities of a file in directory order.
#[derive(Default)]
pub(super) struct Entities(pub(super) Vec<Entity>);

impl Entities {
    /// Add an independent entity (status `00000000`); returns its directory number.
    pub(super) fn add(&mut self, etype: u32, params: Vec<String>, label: (String, i64)) -> i64 {
        self.add_with(etype, "00000000", params, label)
    }

    /// Add an entity with its status digits; returns its directory number.
    pub(super) fn add_with(
        &mut self,
        etype: u32,
        status: &'static str,
        params: Vec<String>,
        label: (String, i64),
    ) -> i64 {
        self.0.push(Entity {
            etype,
            form: 0,
            status,
            label,
            params,
        });
        2 * self.0.len() as i64 - 1
    }
}

/// The whole file; `boundaries` says which curves a trimmed face's boundaries carry (both but in tests).
pub(super) fn write_with(
    objects: &[Geometry],
    labels: &[String],
    trims: &[Option<FaceTrim>],
    opts: &WriteOptions,
    boundaries: super::write_trim::Boundaries,
) -> String {
    let date = opts.date_or_now().to_iges();
    let mut out = String::new();
    // S
    let trimmed = trims.iter().flatten().next().is_some();
    let s_lines = [if trimmed {
        "Fairway IGES export: B-spline curves (126), surfaces (128), trims (144)."
    } else {
        "Fairway IGES export: rational B-spline curves (126) and surfaces (128)."
    }];
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
        hollerith(opts.file_name_or("fairway.igs")),
        hollerith(super::FAIRWAY_SYSTEM),
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
    let mut ents = Entities::default();
    for (k, gm) in objects.iter().enumerate() {
        let label = label_fields(labels.get(k).map_or("", String::as_str));
        match (gm, trims.get(k)) {
            (Geometry::Surface(s), Some(Some(t))) => super::write_trim::face(&mut ents, s, t, label, boundaries),
            (Geometry::Curve(c), _) => {
                ents.add(126, curve_params(c), label);
            }
            (Geometry::Surface(s), _) => {
                ents.add(128, surface_params(s), label);
            }
        }
    }
    // P data first (to know the pointers), then D.
    let mut d_out = String::new();
    let mut p_out = String::new();
    let mut p_seq = 1;
    for (k, e) in ents.0.iter().enumerate() {
        let de = 2 * k + 1;
        let etype = e.etype;
        let lines = wrap(&e.params, 64);
        let start = p_seq;
        for l in &lines {
            p_out.push_str(&format!("{l:<64} {de:>7}P{p_seq:>7}\n"));
            p_seq += 1;
        }
        let d1 = format!(
            "{etype:>8}{start:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
            0, 0, 0, 0, 0, 0, e.status
        );
        let (label, subscript) = (&e.label.0, e.label.1);
        let d2 = format!(
            "{etype:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{label:>8}{subscript:>8}",
            0,
            0,
            lines.len(),
            e.form,
            "",
            "",
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
        2 * ents.0.len(),
        p_seq - 1
    );
    out.push_str(&record(&t, 'T', 1));
    out
}

/// One geometry as IGES text with default options.
pub fn to_string(g: &Geometry) -> String {
    write(std::slice::from_ref(g), &WriteOptions::default())
}
