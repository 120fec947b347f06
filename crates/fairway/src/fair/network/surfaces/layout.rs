//! Patch layouts that are neither a strip nor a full grid (an L, a T, a plus, a row with a patch on its
//! side, any set of patches sharing whole edges that lies on a grid of cells): the patches are laid on
//! the cells of the rectangle around them (their *frame*), turned so that v runs east and u north, raised
//! to common degrees, each column given one v length and each row one u length (the linear rescales that
//! make the cross derivatives meet, the mean over the row's or column's edges) and one merged knot
//! vector (knot insertion, exact). The frame is one B-spline surface on those knots, its knot lines C1
//! (C2 where the edges along them are G2): each filled cell's block of its net is found from the patch
//! (`layout/net.rs`: the restriction to the cell inverted), the empty cells' points are the smoothest
//! extension of the patches (least second differences of the net). The frame equals every patch on its
//! cell up to the edges' gaps (measured on the nets, a sound bound, subtracted from the band), is faired
//! as one surface by [`fair_surface`](crate::fair::fair_surface) — the empty cells come along within the
//! band of their extension — and each patch is cut back out of it onto its own knots. A knot line
//! carries one continuity, so a line whose edges are G2 along one and only G1 along another is not
//! joined (the layout's edges go to the strips, held where those cannot take them). A patch's edge
//! held (a neighbour not faired, a crease) on the frame's outer boundary holds the frame's span along
//! that side; one facing a cell inside the frame stops the route.

use std::collections::BTreeMap;

use glam::DVec3;

use super::grid::{Dir, Embedding, components, embed, has_held, index, turn, with_v_domain};
use super::{Patch, apply, elevate, exact_changes_notes, missing, on_knots_of, order, refine_u, undo, with_u_domain};
use crate::error::{Error, Result};
use crate::fair::surface::SurfaceFairingOptions;
use crate::geometry::Geometry;
use crate::network::SurfaceJoin;
use crate::surface::BSplineSurface;

mod net;

/// A layout of patches: a component of the concatenable edges that lies on a grid of cells but does not
/// fill its frame.
pub(super) struct Layout {
    /// Its objects (sorted).
    pub(super) members: Vec<usize>,
    /// Its shared edges (indices into the joins).
    pub(super) edges: Vec<usize>,
    emb: Embedding,
}

impl Layout {
    /// "a layout of N patches (neither a strip nor a full grid) in an R × C frame", or for a full one
    /// "N patches filling an R × C frame, an edge held".
    pub(super) fn describe(&self) -> String {
        let (r, c) = self.emb.size;
        if self.empty() > 0 {
            format!(
                "a layout of {} patches (neither a strip nor a full grid) in a {r} × {c} frame",
                self.members.len()
            )
        } else {
            format!("{} patches filling a {r} × {c} frame, an edge held", self.members.len())
        }
    }

    /// The number of empty cells of its frame.
    fn empty(&self) -> usize {
        self.emb.size.0 * self.emb.size.1 - self.members.len()
    }

    /// The object in cell (r, c), if any.
    fn at(&self, r: usize, c: usize) -> Option<usize> {
        self.emb.pos.iter().find(|&(_, &p)| p == (r, c)).map(|(&i, _)| i)
    }
}

/// The layouts among the patches joined by the concatenable edges `ok`: components that lie on a grid
/// of cells and leave some of its cells empty, or fill it but have a held edge (the grid and strip
/// routes fair the whole joined surface, so they take only full rectangles with no edge held).
pub(super) fn layouts(joins: &[SurfaceJoin], ok: &[std::result::Result<(), String>], n: usize) -> Vec<Layout> {
    components(joins, ok, n)
        .into_iter()
        .filter_map(|(members, edges)| {
            let emb = embed(&members, &edges, joins)?;
            let full = emb.size.0 * emb.size.1 == members.len();
            (!full || has_held(&members, &edges, joins)).then_some(Layout { members, edges, emb })
        })
        .collect()
}

/// The edges along each of the frame's knot lines between columns (`vertical`) or rows, by their
/// continuity order.
fn line_edges(lay: &Layout, joins: &[SurfaceJoin], vertical: bool) -> Vec<BTreeMap<usize, Vec<usize>>> {
    let n = if vertical { lay.emb.size.1 } else { lay.emb.size.0 };
    let mut seen: Vec<BTreeMap<usize, Vec<usize>>> = vec![BTreeMap::new(); n.saturating_sub(1)];
    for &k in &lay.edges {
        let (a, b) = (lay.emb.pos[&joins[k].a.0], lay.emb.pos[&joins[k].b.0]);
        let (same, x, y) = if vertical {
            (a.0 == b.0, a.1, b.1)
        } else {
            (a.1 == b.1, a.0, b.0)
        };
        if same {
            seen[x.min(y)].entry(order(&joins[k])).or_default().push(k);
        }
    }
    seen
}

/// The continuity orders of the frame's knot lines between columns (`vertical`) or rows: the edges
/// along each must agree (a mixed line is refused).
fn line_orders(lay: &Layout, joins: &[SurfaceJoin], vertical: bool) -> Result<Vec<usize>> {
    line_edges(lay, joins, vertical)
        .iter()
        .enumerate()
        .map(|(l, s)| match s.len() {
            1 => Ok(*s.keys().next().expect("one")),
            0 => Err(Error::InvalidInput(format!("no shared edge crosses knot line {l}"))),
            _ => Err(Error::InvalidInput(format!(
                "the knot line between {} {l} and {} is G2 along one edge and only G1 along another (a mixed line is not joined)",
                if vertical { "columns" } else { "rows" },
                l + 1
            ))),
        })
        .collect()
}

/// Hold the edges along every knot line of a laid-out component that is G2 along one edge and only G1
/// along another (a knot line of one surface has one continuity): the component falls apart at that
/// line into parts that are faired each as one, their spans along the line held, so every edge keeps
/// its class. The edges held say why in `ok`.
pub(super) fn hold_mixed_lines(joins: &[SurfaceJoin], ok: &mut [std::result::Result<(), String>], n: usize) {
    for (members, edges) in components(joins, ok, n) {
        let Some(emb) = embed(&members, &edges, joins) else {
            continue;
        };
        let lay = Layout { members, edges, emb };
        for vertical in [true, false] {
            for (l, by_order) in line_edges(&lay, joins, vertical).iter().enumerate() {
                if by_order.len() < 2 {
                    continue;
                }
                let why = format!(
                    "on a knot line of objects {:?} that is G2 along one edge and only G1 along another (between {} {l} and {}): held, the patches on each side faired together",
                    lay.members,
                    if vertical { "columns" } else { "rows" },
                    l + 1
                );
                by_order.values().flatten().for_each(|&k| ok[k] = Err(why.clone()));
            }
        }
        held_lines(&lay, joins, ok);
    }
}

/// Hold the edges along every knot line of a laid-out component that an edge between two of its
/// patches, held itself (e.g. a G2 edge only C1 after the rescale, a crease), crosses: one knot line
/// cannot be joined along some edges and held along another, so the component falls apart at that line
/// into parts faired each as one, their spans along the line held — each edge keeps its own continuity.
/// The edges held say why in `ok`.
fn held_lines(lay: &Layout, joins: &[SurfaceJoin], ok: &mut [std::result::Result<(), String>]) {
    let mut lines: Vec<(bool, usize, String)> = vec![];
    for (k, j) in joins.iter().enumerate() {
        let (Some(&a), Some(&b)) = (lay.emb.pos.get(&j.a.0), lay.emb.pos.get(&j.b.0)) else {
            continue;
        };
        let Err(e) = &ok[k] else { continue };
        let line = match (a.0 == b.0, a.1 == b.1) {
            (true, _) if a.1.abs_diff(b.1) == 1 => (true, a.1.min(b.1)),
            (_, true) if a.0.abs_diff(b.0) == 1 => (false, a.0.min(b.0)),
            _ => continue,
        };
        if !lines.iter().any(|(v, l, _)| (*v, *l) == line) {
            lines.push((
                line.0,
                line.1,
                format!("edge of objects {} and {} held ({e})", j.a.0, j.b.0),
            ));
        }
    }
    for (vertical, l, what) in lines {
        let why = format!(
            "on a knot line of objects {:?} (between {} {l} and {}) along which the {what}: held too, the patches on each side faired together",
            lay.members,
            if vertical { "columns" } else { "rows" },
            l + 1
        );
        for (_, ks) in line_edges(lay, joins, vertical).get(l).into_iter().flatten() {
            ks.iter().for_each(|&k| ok[k] = Err(why.clone()));
        }
    }
}

/// The sides of the frame whose boundary span is held (a patch's edge not joined there), or why the
/// layout cannot be joined: two patches side by side without a concatenable edge, or a held edge facing
/// a cell inside the frame.
fn held_sides(lay: &Layout, joins: &[SurfaceJoin]) -> Result<Vec<Dir>> {
    let (rows, cols) = lay.emb.size;
    for (&i, &(r, c)) in &lay.emb.pos {
        for (rr, cc) in [(r + 1, c), (r, c + 1)] {
            let Some(o) = lay.at(rr, cc) else { continue };
            let joined = lay.edges.iter().any(|&k| {
                let j = &joins[k];
                (j.a.0, j.b.0) == (i, o) || (j.a.0, j.b.0) == (o, i)
            });
            if !joined {
                return Err(Error::InvalidInput(format!(
                    "objects {i} and {o} sit side by side in the layout without a concatenable edge between them"
                )));
            }
        }
    }
    let mut held = vec![];
    for (k, j) in joins.iter().enumerate() {
        if lay.edges.contains(&k) {
            continue;
        }
        for (i, side) in [j.a, j.b] {
            let Some(&(r, c)) = lay.emb.pos.get(&i) else { continue };
            let d = lay.emb.dirs[&i][index(side)];
            let (dr, dc) = d.step();
            let (nr, nc) = (r as i64 + dr, c as i64 + dc);
            if (0..rows as i64).contains(&nr) && (0..cols as i64).contains(&nc) {
                return Err(Error::InvalidInput(format!(
                    "object {i}'s edge {side:?} is held and faces a cell inside the layout's frame"
                )));
            }
            if !held.contains(&d) {
                held.push(d);
            }
        }
    }
    Ok(held)
}

/// The lengths of the frame's columns along v: column 0 the v length of a patch in it, each next one
/// scaled by the mean over its rows of the rescale that makes the cross derivatives across the line
/// meet. (The rows' lengths along u: the same on the patches transposed, `pos` swapped.)
fn lengths(
    pos: &BTreeMap<usize, (usize, usize)>,
    patches: &BTreeMap<usize, BSplineSurface>,
    n: usize,
) -> Result<Vec<f64>> {
    let len_v = |s: &BSplineSurface| s.domain().1.1 - s.domain().1.0;
    let cross = |s: &BSplineSurface, v: f64| {
        let (u0, u1) = s.domain().0;
        (0..=10)
            .map(|t| s.derivs(u0 + (u1 - u0) * t as f64 / 10.0, v).sv.length())
            .sum::<f64>()
    };
    let first = pos
        .iter()
        .filter(|(_, p)| p.1 == 0)
        .map(|(&i, _)| i)
        .min()
        .ok_or_else(|| Error::InvalidInput("an empty first column".into()))?;
    let mut out = vec![len_v(&patches[&first])];
    for c in 0..n - 1 {
        let ratios: Vec<f64> = pos
            .iter()
            .filter(|(_, p)| p.1 == c)
            .filter_map(|(&a, &(r, _))| {
                let b = pos.iter().find(|(_, q)| **q == (r, c + 1)).map(|(&b, _)| b)?;
                let (sa, sb) = (&patches[&a], &patches[&b]);
                let (da, db) = (cross(sa, sa.domain().1.1), cross(sb, sb.domain().1.0));
                Some(db * len_v(sb) / (da * len_v(sa)))
            })
            .collect();
        let ratio = ratios.iter().sum::<f64>() / ratios.len() as f64;
        if !(ratio.is_finite() && ratio > 0.0) {
            return Err(Error::InvalidInput(format!(
                "no usable edge between columns {c} and {} (degenerate across it)",
                c + 1
            )));
        }
        out.push(out[c] * ratio);
    }
    Ok(out)
}

/// The sorted union (as multisets, values equal within `eps`) of knot vectors.
fn union(all: &[&[f64]], eps: f64) -> Vec<f64> {
    let mut out: Vec<f64> = all[0].to_vec();
    for k in &all[1..] {
        out.extend(missing(k, &out, eps));
        out.sort_by(f64::total_cmp);
    }
    out
}

/// The knot vector of the whole frame along one direction: the cells' clamped vectors `cells` joined,
/// each line between two of them of multiplicity p − k (k its continuity order).
fn frame_knots(cells: &[Vec<f64>], p: usize, orders: &[usize]) -> Vec<f64> {
    let mut out: Vec<f64> = cells[0][..cells[0].len() - p - 1].to_vec();
    for (k, c) in cells.iter().enumerate().skip(1) {
        out.extend(std::iter::repeat_n(c[0], p.saturating_sub(orders[k - 1])));
        out.extend(&c[p + 1..c.len() - p - 1]);
    }
    let last = cells.last().expect("a cell");
    out.extend(std::iter::repeat_n(last[last.len() - 1], p + 1));
    out
}

/// A patch placed on its cell: turned so, its own domains (turned), its net on the cell's knots, the
/// knots inserted into it.
struct Cell {
    turn: ((bool, bool), bool),
    own: ((f64, f64), (f64, f64)),
    net: BSplineSurface,
    inserted: usize,
}

/// The layout's frame, before its net is assembled: each member on its cell, the cells' knots along u
/// (rows) and v (columns), the frame's knots and degrees.
struct Frame {
    cells: BTreeMap<usize, Cell>,
    rows: Vec<Vec<f64>>,
    cols: Vec<Vec<f64>>,
    ku: Vec<f64>,
    kv: Vec<f64>,
    degrees: (usize, usize),
}

/// `s`'s u knots on the cumulative bounds of `lens` starting at 0: `[Σ_{<k}, Σ_{≤k}]` for each k.
fn bounds(lens: &[f64]) -> Vec<f64> {
    std::iter::once(0.0)
        .chain(lens.iter().scan(0.0, |s, l| {
            *s += l;
            Some(*s)
        }))
        .collect()
}

/// `v` with its first and last `p + 1` values set to `a` and `b` exactly.
fn clamped(mut v: Vec<f64>, p: usize, (a, b): (f64, f64)) -> Vec<f64> {
    let n = v.len();
    v[..=p].fill(a);
    v[n - p - 1..].fill(b);
    v
}

/// Lay the members on their cells (module docs): turned, raised, rescaled, on merged knots.
fn frame(objects: &[Geometry], lay: &Layout, joins: &[SurfaceJoin]) -> Result<Frame> {
    let s = |i: usize| objects[i].as_surface().expect("a surface");
    let turns: BTreeMap<usize, ((bool, bool), bool)> =
        lay.members.iter().map(|&i| (i, turn(lay.emb.dirs[&i]))).collect();
    let turned: BTreeMap<usize, BSplineSurface> = lay
        .members
        .iter()
        .map(|&i| (i, apply(s(i), turns[&i].0, turns[&i].1)))
        .collect();
    let pu = turned.values().map(BSplineSurface::degree_u).max().unwrap_or(3);
    let pv = turned.values().map(BSplineSurface::degree_v).max().unwrap_or(3);
    let turned: BTreeMap<usize, BSplineSurface> = turned
        .iter()
        .map(|(&i, t)| Ok((i, elevate(t, pu, pv)?)))
        .collect::<Result<_>>()?;
    let (rows, cols) = lay.emb.size;
    let lv = lengths(&lay.emb.pos, &turned, cols)?;
    let swapped: BTreeMap<usize, (usize, usize)> = lay.emb.pos.iter().map(|(&i, &(r, c))| (i, (c, r))).collect();
    let transposed: BTreeMap<usize, BSplineSurface> = turned.iter().map(|(&i, t)| (i, t.transposed())).collect();
    let lu = lengths(&swapped, &transposed, rows)?;
    let (bu, bv) = (bounds(&lu), bounds(&lv));
    let eps = 1e-12 * (bu[rows] + bv[cols]);
    let mapped: BTreeMap<usize, BSplineSurface> = turned
        .iter()
        .map(|(&i, t)| {
            let (r, c) = lay.emb.pos[&i];
            let t = with_u_domain(t, bu[r], bu[r + 1])?;
            Ok((i, with_v_domain(&t, (bv[c], bv[c + 1]))?))
        })
        .collect::<Result<_>>()?;
    let merged =
        |n: usize, pick: &dyn Fn(usize) -> usize, knots: &dyn Fn(&BSplineSurface) -> Vec<f64>, b: &[f64], p| {
            (0..n)
                .map(|x| {
                    let all: Vec<Vec<f64>> = mapped
                        .iter()
                        .filter(|(i, _)| pick(**i) == x)
                        .map(|(_, t)| knots(t))
                        .collect();
                    let refs: Vec<&[f64]> = all.iter().map(Vec::as_slice).collect();
                    clamped(union(&refs, eps), p, (b[x], b[x + 1]))
                })
                .collect::<Vec<_>>()
        };
    let row_knots = merged(
        rows,
        &|i| lay.emb.pos[&i].0,
        &|t| t.knots_u().values().to_vec(),
        &bu,
        pu,
    );
    let col_knots = merged(
        cols,
        &|i| lay.emb.pos[&i].1,
        &|t| t.knots_v().values().to_vec(),
        &bv,
        pv,
    );
    let mut cells = BTreeMap::new();
    for (&i, t) in &mapped {
        let (r, c) = lay.emb.pos[&i];
        let (ku, kv) = (&row_knots[r], &col_knots[c]);
        let add_u = missing(ku, t.knots_u().values(), eps);
        let add_v = missing(kv, t.knots_v().values(), eps);
        let net = refine_u(&refine_u(t, &add_u)?.transposed(), &add_v)?.transposed();
        let net = BSplineSurface::try_new(
            pu,
            pv,
            ku.clone(),
            kv.clone(),
            net.nu(),
            net.nv(),
            net.points().to_vec(),
            None,
        )?;
        let own = turned[&i].domain();
        let inserted = add_u.len() + add_v.len();
        cells.insert(
            i,
            Cell {
                turn: turns[&i],
                own,
                net,
                inserted,
            },
        );
    }
    let ku = frame_knots(&row_knots, pu, &line_orders(lay, joins, false)?);
    let kv = frame_knots(&col_knots, pv, &line_orders(lay, joins, true)?);
    Ok(Frame {
        cells,
        rows: row_knots,
        cols: col_knots,
        ku,
        kv,
        degrees: (pu, pv),
    })
}

/// Each row's and column's restriction of the frame's basis (first index, matrix).
type Restrictions = (Vec<(usize, Vec<Vec<f64>>)>, Vec<(usize, Vec<Vec<f64>>)>);

fn restrictions(f: &Frame) -> Result<Restrictions> {
    let (pu, pv) = f.degrees;
    let one = |k: &[f64], p: usize, knots: &[f64]| {
        net::restriction(k, p, (knots[0], knots[knots.len() - 1]), knots.len() - p - 1)
    };
    let rows = f.rows.iter().map(|r| one(&f.ku, pu, r)).collect::<Result<_>>()?;
    let cols = f.cols.iter().map(|c| one(&f.kv, pv, c)).collect::<Result<_>>()?;
    Ok((rows, cols))
}

/// The block of `net` (`nv` wide) at `(fr, fc)`, `nu × nv_b`.
fn block(net: &[DVec3], nv: usize, (fr, fc): (usize, usize), (nu_b, nv_b): (usize, usize)) -> Vec<DVec3> {
    (0..nu_b)
        .flat_map(|a| (0..nv_b).map(move |b| net[(fr + a) * nv + fc + b]))
        .collect()
}

/// The frame as one surface (module docs) and how far it is from the patches on their cells (a sound
/// bound: the largest distance between the cells' nets on the same knots).
fn assemble(lay: &Layout, f: &Frame, (rs, cs): &Restrictions) -> Result<(BSplineSurface, Vec<bool>, f64)> {
    let (pu, pv) = f.degrees;
    let (nu, nv) = (f.ku.len() - pu - 1, f.kv.len() - pv - 1);
    let (mut sum, mut count) = (vec![DVec3::ZERO; nu * nv], vec![0u32; nu * nv]);
    for (&i, cell) in &f.cells {
        let (r, c) = lay.emb.pos[&i];
        let ((fr, mu), (fc, mv)) = (&rs[r], &cs[c]);
        let b = net::unrestrict(cell.net.points(), mu, mv)?;
        for (k, q) in b.iter().enumerate() {
            let at = (fr + k / mv.len()) * nv + fc + k % mv.len();
            sum[at] += *q;
            count[at] += 1;
        }
    }
    let mut pts: Vec<DVec3> = sum
        .iter()
        .zip(&count)
        .map(|(&s, &n)| if n > 0 { s / n as f64 } else { s })
        .collect();
    let known: Vec<bool> = count.iter().map(|&n| n > 0).collect();
    let (lo, hi) = crate::curve::point_bounds(&pts);
    net::fill(&mut pts, &known, (nu, nv), 1e-12 * (hi - lo).length());
    let mut err = 0.0f64;
    for (&i, cell) in &f.cells {
        let (r, c) = lay.emb.pos[&i];
        let ((fr, mu), (fc, mv)) = (&rs[r], &cs[c]);
        let back = net::restrict(&block(&pts, nv, (*fr, *fc), (mu.len(), mv.len())), mu, mv);
        err = back
            .iter()
            .zip(cell.net.points())
            .map(|(a, b)| a.distance(*b))
            .fold(err, f64::max);
    }
    let whole = BSplineSurface::try_new(pu, pv, f.ku.clone(), f.kv.clone(), nu, nv, pts, None)?;
    Ok((whole, known, err))
}

/// How many times the frame is faired: the first time with its empty cells as [`assemble`] fills them,
/// then again from the patches as they were with the empty cells' points taken from the last fair.
/// The fill is only a start (the fair holds it within the band of where it starts); a fill that carries
/// the patches' noise on into the empty cells keeps the isocurves through them from getting fair.
/// Measured on an L of three noisy patches (`tests/network_layouts.rs`, m = 4e-3), isocurve extrema of
/// the frame after each fair: 224, 187, 111, 73.
pub(super) const FILL_ROUNDS: usize = 4;

/// Fair the frame `whole` ([`super::fair_joined`]) [`FILL_ROUNDS`] times, each time from the patches'
/// points as they are in `whole` (`known`) and the empty cells' as the last fair left them; the last
/// fair (stopping early where the empty cells no longer change).
fn fair_rounds(
    whole: &BSplineSurface,
    known: &[bool],
    err: f64,
    opts: &SurfaceFairingOptions,
    region: Option<Region>,
) -> Result<(crate::fair::surface::SurfaceFairingResult, f64)> {
    let mut start = whole.clone();
    let mut last = super::fair_joined(&start, err, opts, region)?;
    for _ in 1..FILL_ROUNDS {
        let pts: Vec<DVec3> = known
            .iter()
            .zip(whole.points().iter().zip(last.0.surface.points()))
            .map(|(&k, (&a, &b))| if k { a } else { b })
            .collect();
        if pts == start.points() {
            break;
        }
        start = whole.with_points(pts)?;
        last = super::fair_joined(&start, err, opts, region)?;
    }
    Ok(last)
}

/// A region of a surface: (u range, v range).
type Region = ((f64, f64), (f64, f64));

/// The region of the frame that leaves the boundary span of each `held` side as it is.
fn region(s: &BSplineSurface, held: &[Dir]) -> Result<Option<Region>> {
    if held.is_empty() {
        return Ok(None);
    }
    let trim = |bp: Vec<f64>, lo: bool, hi: bool| {
        let n = bp.len();
        let (i, k) = (usize::from(lo), n - 1 - usize::from(hi));
        (i < k)
            .then(|| (bp[i], bp[k]))
            .ok_or_else(|| Error::InvalidInput("too few knot spans to hold its edges".into()))
    };
    let u = trim(
        s.knots_u().breakpoints(),
        held.contains(&Dir::S),
        held.contains(&Dir::N),
    )?;
    let v = trim(
        s.knots_v().breakpoints(),
        held.contains(&Dir::W),
        held.contains(&Dir::E),
    )?;
    Ok(Some((u, v)))
}

/// Fair a layout as one surface (module docs): each member with its patch.
pub(super) fn fair_layout(
    objects: &[Geometry],
    lay: &Layout,
    joins: &[SurfaceJoin],
    opts: &SurfaceFairingOptions,
    tol: f64,
) -> Result<Vec<(usize, Patch)>> {
    let held = held_sides(lay, joins)?;
    let f = frame(objects, lay, joins)?;
    let rs = restrictions(&f)?;
    let (whole, known, err) = assemble(lay, &f, &rs)?;
    if err > tol {
        return Err(Error::InvalidInput(format!(
            "the patches are not one surface across their edges after the rescales (off by {})",
            crate::range::short(err)
        )));
    }
    let (r, bound) = fair_rounds(&whole, &known, err, opts, region(&whole, &held)?)?;
    let nv = r.surface.nv();
    let mut out = vec![];
    for &i in &lay.members {
        let cell = &f.cells[&i];
        let (rr, cc) = lay.emb.pos[&i];
        let ((fr, mu), (fc, mv)) = (&rs.0[rr], &rs.1[cc]);
        let pts = net::restrict(&block(r.surface.points(), nv, (*fr, *fc), (mu.len(), mv.len())), mu, mv);
        let piece = cell.net.with_points(pts)?;
        let piece = with_u_domain(&piece, cell.own.0.0, cell.own.0.1)?;
        let piece = with_v_domain(&piece, cell.own.1)?;
        let original = objects[i].as_surface().expect("a surface");
        let piece = on_knots_of(&undo(&piece, cell.turn.0, cell.turn.1), original);
        let mut n = r.notes.clone();
        n.push(format!(
            "faired as one surface with objects {:?}, {}, across their shared edges (each keeps its continuity)",
            lay.members,
            lay.describe()
        ));
        if lay.empty() > 0 {
            n.push(format!(
                "the frame's {} empty cells filled by the smoothest extension of the patches, refilled from the fair ({FILL_ROUNDS} fairs)",
                lay.empty()
            ));
        }
        if !held.is_empty() {
            n.push(format!(
                "the frame's boundary span held on its {held:?} side(s) (held edges there)"
            ));
        }
        exact_changes_notes(cell.inserted, original, &piece, &mut n);
        let own = super::own_bound(original, &piece, bound, &mut n);
        out.push((i, (piece, own, n)));
    }
    Ok(out)
}
