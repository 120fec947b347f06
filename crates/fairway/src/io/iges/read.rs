//! Reading a file: sections, global section (delimiters, units), directory, the entities with
//! their transformation matrices.

use super::*;
use crate::io::interchange::{Conversion, map_points};

/// Read every curve (126) and surface (128) of an IGES file, coordinates in
/// the file's unit. Other entities are skipped and listed in `notices`.
pub fn read_all(bytes: &[u8]) -> Result<IgesFile> {
    read_all_with(bytes, ReadOptions::default())
}

/// [`read_all`] with options (unit conversion).
pub fn read_all_with(bytes: &[u8], opts: ReadOptions) -> Result<IgesFile> {
    if let Some(m) = crate::io::blank_text_message(bytes) {
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
    let (unit, conversion) = global_units(&gtoks, opts, &mut notices)?;
    let entries = directory_entries(&dlines)?;
    let data = DataSections {
        entries: &entries,
        plines: &plines,
        pd,
        rd,
        conversion,
    };
    let mut trim_notices = vec![];
    let face_trims = data.face_trims(&mut trim_notices);
    // in a file Fairway wrote, a trimmed surface's curves in space are derived from its uv loops
    let fairway_edges = matches!(gtoks.get(4), Some(Tok::Str(s)) if s == FAIRWAY_SYSTEM);
    let (objects, infos, first_error) = data.read_entities(&mut notices, &face_trims, fairway_edges);
    notices.append(&mut trim_notices);
    let trims = attach_trims(&objects, &infos, &face_trims.by_surface, &mut notices);
    // nothing readable: the first entity's reason is the file's
    if objects.is_empty()
        && let Some(err) = first_error
    {
        return Err(err);
    }
    Ok(IgesFile {
        objects,
        unit,
        scale: conversion.scale,
        notices,
        entities: infos,
        trims,
    })
}

/// The loops of each surface a 144 trims (one per object; `None` for the others, and for a surface that
/// a break split into pieces or whose loops do not close, said in a notice).
fn attach_trims(
    objects: &[Geometry],
    infos: &[EntityInfo],
    face_trims: &std::collections::HashMap<usize, super::trim::Trim144>,
    notices: &mut Vec<String>,
) -> Vec<Option<crate::trim::FaceTrim>> {
    let pieces = |seq: usize| infos.iter().filter(|i| i.entity == seq).count();
    let mut read = 0;
    let trims = (objects.iter().zip(infos))
        .map(|(g, info)| {
            let (Geometry::Surface(s), Some(t)) = (g, face_trims.get(&info.entity)) else {
                return None;
            };
            let what = format!("entity {} (surface, 128)", info.entity);
            if pieces(info.entity) != 1 {
                notices.push(format!("{what}: split into pieces, its trim is not kept"));
                return None;
            }
            let ((u0, u1), (v0, v1)) = s.domain();
            match t.on(s) {
                Ok(t) if t.largest_gap() <= 1e-4 * (u1 - u0).hypot(v1 - v0) => {
                    read += 1;
                    Some(t)
                }
                Ok(t) => {
                    notices.push(format!(
                        "{what}: a boundary of its 144 does not close (a gap of {:.3e} in its parameters), it opens \
                         untrimmed",
                        t.largest_gap()
                    ));
                    None
                }
                Err(e) => {
                    notices.push(format!("{what}: its 144's boundaries are not kept: {e}"));
                    None
                }
            }
        })
        .collect();
    if read > 0 {
        notices.push(format!("{read} trimmed surfaces (144) read with their boundaries"));
    }
    trims
}

/// Sections: the records sorted into the global text, the directory records and the parameter
/// records' columns 1–64 (start and terminate sections are not read).
pub(super) fn split_sections<'a>(recs: &[(u8, &'a [u8])]) -> (Vec<u8>, Vec<&'a [u8]>, Vec<&'a [u8]>) {
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
pub(super) fn global_delimiters(gtext: &[u8]) -> Result<(u8, u8)> {
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

/// Global section, units: the model-space scale (G13: model size over real size), the file's unit
/// (G14/G15) and the conversion taking coordinates to real size in `opts.unit` (the file's unit when not
/// converting), as (unit, conversion). A scale other than 1 is noted.
pub(super) fn global_units(
    gtoks: &[Tok],
    opts: ReadOptions,
    notices: &mut Vec<String>,
) -> Result<(Option<Unit>, Conversion)> {
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
    if scale != 1.0 {
        notices.push(format!(
            "global section: model-space scale {s} (G13): the model is drawn at {s} times its real size; its \
             coordinates are divided by {s}",
            s = crate::range::short(scale)
        ));
    }
    let units = match opts.unit {
        None => None,
        Some(target) => {
            let Some(from) = unit else {
                return Err(perr(format!(
                    "global section: unit flag {unit_flag:?} / name {:?} not recognised, cannot convert to {}",
                    gstr(14),
                    target.name()
                )));
            };
            Some((from, target))
        }
    };
    Ok((unit, Conversion { units, scale }))
}

/// Directory: the entries, one per pair of `D` records (the fields the reader uses).
pub(super) fn directory_entries(dlines: &[&[u8]]) -> Result<Vec<DirEntry>> {
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
/// delimiters and the unit conversion.
pub(super) struct DataSections<'a> {
    pub(super) entries: &'a [DirEntry],
    pub(super) plines: &'a [&'a [u8]],
    pub(super) pd: u8,
    pub(super) rd: u8,
    pub(super) conversion: Conversion,
}

impl DataSections<'_> {
    /// Entities: each curve and surface read (one bad entity skips that entity, listed in the
    /// notices, not the file), as (objects, their entity infos, the first error met).
    /// The entities a read trimmed surface stands for (`trims.used`) are not reported as skipped; with
    /// `fairway_edges` (a file Fairway wrote), its model-space curves are not read as objects either.
    pub(super) fn read_entities(
        &self,
        notices: &mut Vec<String>,
        trims: &super::trim::FaceTrims,
        fairway_edges: bool,
    ) -> (Vec<Geometry>, Vec<EntityInfo>, Option<Error>) {
        let mut budget = self.plines.len().saturating_mul(4).saturating_add(64);
        let mut objects = Vec::new();
        let mut infos = Vec::new();
        let mut first_error: Option<Error> = None;
        let mut edges_kept = 0;
        for e in self.entries {
            if trims.used.contains(&e.seq) && e.etype != 126 {
                continue; // a 142 or 102 of a trimmed surface's boundary, read as its loops
            }
            if trims.used.contains(&e.seq) && (fairway_edges || !trims.model_curves.contains(&e.seq)) {
                edges_kept += trims.model_curves.contains(&e.seq) as usize;
                continue; // a boundary's parameter-space curve, or a model-space curve Fairway derived
            }
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
        if edges_kept > 0 {
            notices.push(format!(
                "{edges_kept} model-space curves of trimmed surfaces' boundaries kept as their trims (derived from \
                 the uv loops by Fairway), not as objects of their own"
            ));
        }
        (objects, infos, first_error)
    }

    /// One entity: its parameters parsed, its transformation chain and the unit conversion applied,
    /// its coordinates range-checked; several objects where a break (a knot above the degree's
    /// multiplicity) splits it ([`crate::knots::resolve_breaks`]).
    pub(super) fn read_entity(
        &self,
        e: &DirEntry,
        what: &str,
        budget: &mut usize,
        notices: &mut Vec<String>,
    ) -> Result<Vec<Geometry>> {
        let (pd, rd) = (self.pd, self.rd);
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
                geom = map_points(geom, |q| m.apply(q))?;
            }
            geom = self.conversion.apply(geom)?;
            crate::range::check_geometry(&geom).map_err(|e| perr(format!("{what}: {e}")))?;
            out.push(geom);
        }
        Ok(out)
    }
}

/// Entity filter: the name of a curve (126) or surface (128) entry for the messages, or `None`
/// (with a notice, except for transformation matrices, 124) for an entry that is not read.
pub(super) fn entity_what(e: &DirEntry, notices: &mut Vec<String>) -> Option<String> {
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

pub(super) fn entity_params(
    plines: &[&[u8]],
    e: &DirEntry,
    what: &str,
    pd: u8,
    rd: u8,
    budget: &mut usize,
) -> Result<Vec<Tok>> {
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
pub(super) struct Affine {
    pub(super) r: [[f64; 3]; 3],
    pub(super) t: [f64; 3],
}

impl Affine {
    pub(super) fn apply(&self, q: DVec3) -> DVec3 {
        let a = q.to_array();
        let mut o = [0.0; 3];
        for i in 0..3 {
            o[i] = self.r[i][0] * a[0] + self.r[i][1] * a[1] + self.r[i][2] * a[2] + self.t[i];
        }
        DVec3::from_array(o)
    }
    pub(super) fn then(&self, outer: &Affine) -> Affine {
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

pub(super) fn transform_chain(
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
