//! Patch layouts that form a regular grid of R × C patches (R, C ≥ 2) whose every shared edge can be
//! concatenated: each patch is turned so that its v runs along the grid's rows (east) and its u along its
//! columns (north); the patches of each row are joined along v with one v scale per column, the same in
//! every row (the mean of the rows' rescales, so the rows' knots match), then the rows are joined along
//! u; the whole is faired by [`fair_surface`] as one surface and split back (into rows, then each row
//! into its patches), each patch turned back onto its own knots. A knot line across the whole grid
//! carries one continuity: the highest of the edges along it (C2 where one of them is G2).

use std::collections::{BTreeMap, HashMap};

use super::{
    Pair, Patch, Placed, along_v, apply, concatenate_at, cross_len, elevate, on_knots_of, order, pair, split_strip,
    undo, with_u_domain,
};
use crate::error::Result;
use crate::fair::surface::SurfaceFairingOptions;
use crate::geometry::Geometry;
use crate::network::{Continuity, Side, SurfaceContinuity, SurfaceJoin};
use crate::surface::BSplineSurface;

/// A direction in the grid: east (the next column), west, north (the next row), south.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Dir {
    E,
    W,
    N,
    S,
}

impl Dir {
    pub(super) fn opposite(self) -> Dir {
        match self {
            Dir::E => Dir::W,
            Dir::W => Dir::E,
            Dir::N => Dir::S,
            Dir::S => Dir::N,
        }
    }

    /// The step to the neighbour that way: (row, column).
    pub(super) fn step(self) -> (i64, i64) {
        match self {
            Dir::E => (0, 1),
            Dir::W => (0, -1),
            Dir::N => (1, 0),
            Dir::S => (-1, 0),
        }
    }
}

/// The index of a side in a patch's `[Dir; 4]` (U0, U1, V0, V1).
pub(super) fn index(s: Side) -> usize {
    match s {
        Side::U0 => 0,
        Side::U1 => 1,
        Side::V0 => 2,
        Side::V1 => 3,
    }
}

fn opposite_side(s: Side) -> Side {
    match s {
        Side::U0 => Side::U1,
        Side::U1 => Side::U0,
        Side::V0 => Side::V1,
        Side::V1 => Side::V0,
    }
}

/// The sides through the start and the end of side `s`'s curve ([`Side::curve`]: a U side runs along v
/// from v₀, a V side along u from u₀).
fn ends_of(s: Side) -> (Side, Side) {
    match s {
        Side::U0 | Side::U1 => (Side::V0, Side::V1),
        Side::V0 | Side::V1 => (Side::U0, Side::U1),
    }
}

/// A grid layout of patches.
pub(super) struct Grid {
    /// The object at row r, column c: `cells[r][c]`.
    pub(super) cells: Vec<Vec<usize>>,
    /// Where each side of each object faces (indexed by [`index`]).
    dirs: HashMap<usize, [Dir; 4]>,
    /// The shared edges inside the grid (indices into the joins).
    pub(super) edges: Vec<usize>,
}

/// The components of the patches joined by the concatenable edges `ok` (union–find): each one's objects
/// (sorted) and its edges (indices into the joins).
pub(super) fn components(
    joins: &[SurfaceJoin],
    ok: &[std::result::Result<(), String>],
    n: usize,
) -> Vec<(Vec<usize>, Vec<usize>)> {
    let mut root: Vec<usize> = (0..n).collect();
    fn find(root: &mut [usize], mut i: usize) -> usize {
        while root[i] != i {
            root[i] = root[root[i]];
            i = root[i];
        }
        i
    }
    let usable: Vec<usize> = (0..joins.len()).filter(|&k| ok[k].is_ok()).collect();
    for &k in &usable {
        let (a, b) = (find(&mut root, joins[k].a.0), find(&mut root, joins[k].b.0));
        root[a] = b;
    }
    let mut members: HashMap<usize, Vec<usize>> = HashMap::new();
    for &k in &usable {
        for i in [joins[k].a.0, joins[k].b.0] {
            let r = find(&mut root, i);
            let m = members.entry(r).or_default();
            if !m.contains(&i) {
                m.push(i);
            }
        }
    }
    let mut roots: Vec<usize> = members.keys().copied().collect();
    roots.sort_unstable();
    roots
        .into_iter()
        .filter_map(|r| {
            let mut m = members.remove(&r)?;
            m.sort_unstable();
            let edges: Vec<usize> = usable.iter().copied().filter(|&k| m.contains(&joins[k].a.0)).collect();
            Some((m, edges))
        })
        .collect()
}

/// The grids among the patches joined by the concatenable edges `ok` (components of R × C ≥ 2 × 2 whose
/// edges are exactly a grid's and none of whose patches has a held edge; other components are left to
/// the layouts and the strips).
pub(super) fn grids(joins: &[SurfaceJoin], ok: &[std::result::Result<(), String>], n: usize) -> Vec<Grid> {
    components(joins, ok, n)
        .into_iter()
        .filter(|(m, edges)| !has_held(m, edges, joins))
        .filter_map(|(m, edges)| layout(&m, &edges, joins))
        .collect()
}

/// Whether a patch of `members` has a shared edge that is not among `edges` (held: the route that fairs
/// them must keep the span next to it).
pub(super) fn has_held(members: &[usize], edges: &[usize], joins: &[SurfaceJoin]) -> bool {
    joins
        .iter()
        .enumerate()
        .any(|(k, j)| !edges.contains(&k) && (members.contains(&j.a.0) || members.contains(&j.b.0)))
}

/// Where the patches of a component sit: each object's cell (row, column; the lowest 0, 0) and where
/// each of its sides faces.
pub(super) struct Embedding {
    /// Each object's cell.
    pub(super) pos: BTreeMap<usize, (usize, usize)>,
    /// Where each side of each object faces (indexed by [`index`]).
    pub(super) dirs: HashMap<usize, [Dir; 4]>,
    /// Rows and columns of the frame around them.
    pub(super) size: (usize, usize),
}

/// The patches `members` joined by `edges` laid out on a grid of cells (module docs), if they fit one:
/// each edge between two neighbouring cells, the patches turned consistently, no cell taken twice.
pub(super) fn embed(members: &[usize], edges: &[usize], joins: &[SurfaceJoin]) -> Option<Embedding> {
    let first = *members.first()?;
    let mut dirs: HashMap<usize, [Dir; 4]> = HashMap::from([(first, [Dir::S, Dir::N, Dir::W, Dir::E])]);
    let mut pos: HashMap<usize, (i64, i64)> = HashMap::from([(first, (0, 0))]);
    let mut queue = vec![first];
    while let Some(i) = queue.pop() {
        for &k in edges {
            let Some((o, p, dn)) = neighbour(&joins[k], i, pos[&i], dirs[&i]) else {
                continue;
            };
            match (pos.get(&o), dirs.get(&o)) {
                (Some(&q), Some(e)) => {
                    if q != p || *e != dn {
                        return None;
                    }
                }
                _ => {
                    pos.insert(o, p);
                    dirs.insert(o, dn);
                    queue.push(o);
                }
            }
        }
    }
    let (r0, c0) = pos
        .values()
        .fold((i64::MAX, i64::MAX), |(a, b), &(r, c)| (a.min(r), b.min(c)));
    let (r1, c1) = pos
        .values()
        .fold((i64::MIN, i64::MIN), |(a, b), &(r, c)| (a.max(r), b.max(c)));
    let pos: BTreeMap<usize, (usize, usize)> = pos
        .into_iter()
        .map(|(i, (r, c))| (i, ((r - r0) as usize, (c - c0) as usize)))
        .collect();
    let mut cells: Vec<(usize, usize)> = pos.values().copied().collect();
    cells.sort_unstable();
    cells.dedup();
    (cells.len() == pos.len() && pos.len() == members.len()).then_some(Embedding {
        pos,
        dirs,
        size: ((r1 - r0 + 1) as usize, (c1 - c0 + 1) as usize),
    })
}

/// The patch across the edge `j` from patch `i` (in cell `at`, its sides facing `di`), if `j` is one of
/// `i`'s: that patch, its cell and where its sides face — back across the edge, and its sides through
/// the edge's ends as ours do.
fn neighbour(j: &SurfaceJoin, i: usize, at: (i64, i64), di: [Dir; 4]) -> Option<(usize, (i64, i64), [Dir; 4])> {
    let (si, o, so) = match (j.a.0 == i, j.b.0 == i) {
        (true, _) => (j.a.1, j.b.0, j.b.1),
        (_, true) => (j.b.1, j.a.0, j.a.1),
        _ => return None,
    };
    let d = di[index(si)];
    let (dr, dc) = d.step();
    let mut dn = [d; 4];
    dn[index(so)] = d.opposite();
    dn[index(opposite_side(so))] = d;
    let (start_i, _) = ends_of(si);
    let (start_o, end_o) = ends_of(so);
    let (first, second) = if j.reversed { (end_o, start_o) } else { (start_o, end_o) };
    dn[index(first)] = di[index(start_i)];
    dn[index(second)] = di[index(start_i)].opposite();
    Some((o, (at.0 + dr, at.1 + dc), dn))
}

/// The grid that the patches `members` joined by `edges` form, if they form one of at least 2 × 2.
fn layout(members: &[usize], edges: &[usize], joins: &[SurfaceJoin]) -> Option<Grid> {
    if members.len() < 4 {
        return None;
    }
    let e = embed(members, edges, joins)?;
    let (rows, cols) = e.size;
    let inner_edges = rows * (cols - 1) + cols * (rows - 1);
    if rows < 2 || cols < 2 || rows * cols != members.len() || edges.len() != inner_edges {
        return None;
    }
    let mut cells = vec![vec![usize::MAX; cols]; rows];
    for (&i, &(r, c)) in &e.pos {
        cells[r][c] = i;
    }
    Some(Grid {
        cells,
        dirs: e.dirs,
        edges: edges.to_vec(),
    })
}

/// How to turn a patch whose sides face `d` so that its v₁ side faces east and its u₁ side north
/// (transpose, reverse v; reverse u), as [`apply`] takes it.
pub(super) fn turn(d: [Dir; 4]) -> ((bool, bool), bool) {
    let (u1, v1) = (d[index(Side::U1)], d[index(Side::V1)]);
    if matches!(v1, Dir::E | Dir::W) {
        ((false, v1 == Dir::W), u1 == Dir::S)
    } else {
        // transposed: u₁ becomes v₁, v₁ becomes u₁
        ((true, u1 == Dir::W), v1 == Dir::S)
    }
}

/// `s` on the v domain `[a, b]` (a linear map).
pub(super) fn with_v_domain(s: &BSplineSurface, (a, b): (f64, f64)) -> Result<BSplineSurface> {
    Ok(with_u_domain(&s.transposed(), a, b)?.transposed())
}

/// A row of patches joined along v: the surface, the v of each edge, how each patch sits in it, the
/// error made.
struct Joined {
    surface: BSplineSurface,
    at: Vec<f64>,
    placed: Vec<Placed>,
    err: f64,
}

/// Each row of `rows` (patches turned, of one degree pair) joined along v, the rows in lockstep: column
/// c + 1 is joined with continuity order `orders[c]` and one v length in every row (the mean of the
/// rows' rescales; column 0 mapped onto row 0's v domain first), so the rows' v knots match.
fn join_rows(rows: &[Vec<BSplineSurface>], orders: &[usize], tol: f64) -> Result<Vec<Joined>> {
    let v0 = rows[0][0].domain().1;
    let mut out: Vec<Joined> = rows
        .iter()
        .map(|r| {
            Ok(Joined {
                surface: with_v_domain(&r[0], v0)?,
                at: vec![],
                placed: vec![Placed {
                    turn: (false, false),
                    flip: false,
                    own_u: r[0].domain().0,
                    own_v: along_v(&r[0])[0].clone(),
                    inserted: 0,
                }],
                err: 0.0,
            })
        })
        .collect::<Result<_>>()?;
    let edge = SurfaceJoin {
        a: (0, Side::V1),
        b: (1, Side::V0),
        reversed: false,
        continuity: SurfaceContinuity {
            gap: 0.0,
            normal_angle: 0.0,
            curvature_jump: 0.0,
            class: Continuity::G1,
        },
    };
    for c in 1..rows[0].len() {
        let pairs: Vec<Pair> = out
            .iter()
            .zip(rows)
            .map(|(j, r)| pair(&j.surface, &r[c], &edge, tol))
            .collect::<Result<_>>()?;
        let lens: Vec<f64> = pairs.iter().map(cross_len).collect::<Result<_>>()?;
        let len = lens.iter().sum::<f64>() / lens.len() as f64;
        for (j, p) in out.iter_mut().zip(&pairs) {
            let (s, y, err) = concatenate_at(p, orders[c - 1], len)?;
            j.placed.iter_mut().for_each(|q| q.inserted += p.inserted[0]);
            j.placed.push(Placed {
                turn: (false, false),
                flip: false,
                own_u: p.b_u,
                own_v: along_v(&p.b)[0].clone(),
                inserted: p.inserted[1],
            });
            (j.surface, j.err) = (s, j.err + err);
            j.at.push(y);
        }
    }
    Ok(out)
}

impl Grid {
    /// The continuity order of the edge between objects `x` and `y` (0 if none).
    fn order_between(&self, joins: &[SurfaceJoin], x: usize, y: usize) -> usize {
        self.edges
            .iter()
            .map(|&k| &joins[k])
            .filter(|j| (j.a.0, j.b.0) == (x, y) || (j.a.0, j.b.0) == (y, x))
            .map(order)
            .max()
            .unwrap_or(0)
    }

    /// "R × C".
    pub(super) fn size(&self) -> String {
        format!("{} × {}", self.cells.len(), self.cells[0].len())
    }

    /// The objects, row by row.
    pub(super) fn objects(&self) -> Vec<usize> {
        self.cells.iter().flatten().copied().collect()
    }
}

/// Concatenate the grid's patches into one surface, fair it, split it back (module docs): each object
/// with its patch.
pub(super) fn fair_grid(
    objects: &[Geometry],
    g: &Grid,
    joins: &[SurfaceJoin],
    opts: &SurfaceFairingOptions,
    tol: f64,
) -> Result<Vec<(usize, Patch)>> {
    let jg = join_grid(objects, g, joins, tol)?;
    let (r, bound) = super::fair_joined(&jg.outer.surface, jg.err, opts, None)?;
    let what = format!(
        "faired as one surface with objects {:?}, a {} grid of patches, across their shared edges (each keeps its continuity)",
        g.objects(),
        g.size()
    );
    split_grid(objects, g, &jg, &r.surface, bound, &r.notes, &what)
}

/// A grid joined into one surface: each row along v (`inner`), then the rows together (`outer`, its u
/// along the rows' v, its v across the rows), the error made.
struct JoinedGrid {
    inner: Vec<Joined>,
    outer: Joined,
    err: f64,
}

/// Concatenate the grid's patches into one surface (module docs).
fn join_grid(objects: &[Geometry], g: &Grid, joins: &[SurfaceJoin], tol: f64) -> Result<JoinedGrid> {
    let s = |i: usize| objects[i].as_surface().expect("a surface");
    let (rows, cols) = (g.cells.len(), g.cells[0].len());
    let turned: Vec<Vec<BSplineSurface>> = g
        .cells
        .iter()
        .map(|row| {
            row.iter()
                .map(|&i| {
                    let (t, f) = turn(g.dirs[&i]);
                    apply(s(i), t, f)
                })
                .collect()
        })
        .collect();
    // one degree pair for all (raised, exact)
    let pu = turned.iter().flatten().map(BSplineSurface::degree_u).max().unwrap_or(3);
    let pv = turned.iter().flatten().map(BSplineSurface::degree_v).max().unwrap_or(3);
    let turned: Vec<Vec<BSplineSurface>> = turned
        .iter()
        .map(|row| row.iter().map(|p| elevate(p, pu, pv)).collect::<Result<_>>())
        .collect::<Result<_>>()?;
    // one order per knot line: the highest of its edges'
    let col_orders: Vec<usize> = (0..cols - 1)
        .map(|c| {
            (0..rows)
                .map(|r| g.order_between(joins, g.cells[r][c], g.cells[r][c + 1]))
                .max()
                .unwrap_or(1)
        })
        .collect();
    let row_orders: Vec<usize> = (0..rows - 1)
        .map(|r| {
            (0..cols)
                .map(|c| g.order_between(joins, g.cells[r][c], g.cells[r + 1][c]))
                .max()
                .unwrap_or(1)
        })
        .collect();
    let inner = join_rows(&turned, &col_orders, tol)?;
    let stacked: Vec<BSplineSurface> = inner.iter().map(|j| j.surface.transposed()).collect();
    let outer = join_rows(&[stacked], &row_orders, tol)?.remove(0);
    let err = outer.err + inner.iter().map(|j| j.err).fold(0.0, f64::max);
    Ok(JoinedGrid { inner, outer, err })
}

/// The faired surface `faired` of a joined grid split back into its patches (rows first), each on its
/// own knots with its own deviation bound (at most `bound`), the fair's `notes` followed by `what`.
fn split_grid(
    objects: &[Geometry],
    g: &Grid,
    jg: &JoinedGrid,
    faired: &BSplineSurface,
    bound: f64,
    notes: &[String],
    what: &str,
) -> Result<Vec<(usize, Patch)>> {
    let s = |i: usize| objects[i].as_surface().expect("a surface");
    let mut out = vec![];
    let rows_back = split_strip(faired, &jg.outer.at, &jg.outer.placed)?;
    for ((row_t, (joined, cells)), row_q) in rows_back
        .iter()
        .zip(jg.inner.iter().zip(&g.cells))
        .zip(&jg.outer.placed)
    {
        let pieces = split_strip(&row_t.transposed(), &joined.at, &joined.placed)?;
        for ((piece, &i), q) in pieces.iter().zip(cells).zip(&joined.placed) {
            let (t, f) = turn(g.dirs[&i]);
            let piece = on_knots_of(&undo(piece, t, f), s(i));
            let mut n = notes.to_vec();
            n.push(what.to_string());
            super::exact_changes_notes(q.inserted + row_q.inserted, s(i), &piece, &mut n);
            let own = super::own_bound(s(i), &piece, bound, &mut n);
            out.push((i, (piece, own, n)));
        }
    }
    Ok(out)
}

/// A grid of patches closing on itself around one direction (R ≥ 2 rows of C ≥ 2 patches around a
/// cylinder): the grid cut open along one column line, and the edges along that line (each joining
/// column C − 1 to column 0 of its row).
pub(super) struct Cylinder {
    pub(super) grid: Grid,
    pub(super) wrap: Vec<usize>,
}

/// The cylinders among the patches joined by the concatenable edges `ok` (components none of whose
/// patches has a held edge that [`embed`] cannot lay on a grid because they close on themselves).
pub(super) fn cylinders(joins: &[SurfaceJoin], ok: &[std::result::Result<(), String>], n: usize) -> Vec<Cylinder> {
    components(joins, ok, n)
        .into_iter()
        .filter(|(m, edges)| !has_held(m, edges, joins) && embed(m, edges, joins).is_none())
        .filter_map(|(m, edges)| cylinder(&m, &edges, joins))
        .collect()
}

/// The patches `members` joined by `edges` laid on a grid of cells whose columns close on themselves
/// (as [`embed`], the column taken modulo the period that the walk around finds): R ≥ 2 rows (one row is
/// a ring of the strip route), every cell taken once, every edge between neighbours.
fn cylinder(members: &[usize], edges: &[usize], joins: &[SurfaceJoin]) -> Option<Cylinder> {
    let first = *members.first()?;
    let mut dirs: HashMap<usize, [Dir; 4]> = HashMap::from([(first, [Dir::S, Dir::N, Dir::W, Dir::E])]);
    let mut pos: HashMap<usize, (i64, i64)> = HashMap::from([(first, (0, 0))]);
    let mut period: Option<i64> = None;
    let mut queue = vec![first];
    while let Some(i) = queue.pop() {
        for &k in edges {
            let Some((o, p, dn)) = neighbour(&joins[k], i, pos[&i], dirs[&i]) else {
                continue;
            };
            match (pos.get(&o), dirs.get(&o)) {
                (Some(&q), Some(e)) => {
                    // met again around the columns: the same row and turn, the column off by the period
                    if *e != dn || q.0 != p.0 {
                        return None;
                    }
                    let off = (q.1 - p.1).abs();
                    if off != 0 {
                        if period.is_some_and(|x| x != off) {
                            return None;
                        }
                        period = Some(off);
                    }
                }
                _ => {
                    pos.insert(o, p);
                    dirs.insert(o, dn);
                    queue.push(o);
                }
            }
        }
    }
    let cols = period?;
    let r0 = pos.values().map(|p| p.0).min()?;
    let rows = pos.values().map(|p| p.0).max()? - r0 + 1;
    let (rows, cols_u) = (usize::try_from(rows).ok()?, usize::try_from(cols).ok()?);
    if rows < 2 || cols_u < 2 || rows * cols_u != members.len() || edges.len() != rows * cols_u + cols_u * (rows - 1) {
        return None;
    }
    let mut cells = vec![vec![usize::MAX; cols_u]; rows];
    let mut at: HashMap<usize, (usize, usize)> = HashMap::new();
    for (&i, &(r, c)) in &pos {
        let (r, c) = ((r - r0) as usize, c.rem_euclid(cols) as usize);
        if cells[r][c] != usize::MAX {
            return None;
        }
        cells[r][c] = i;
        at.insert(i, (r, c));
    }
    // the line cut open: the edges leaving column C − 1 eastwards
    let wrap: Vec<usize> = edges
        .iter()
        .copied()
        .filter(|&k| {
            let j = &joins[k];
            [j.a, j.b]
                .iter()
                .any(|&(i, side)| at[&i].1 == cols_u - 1 && dirs[&i][index(side)] == Dir::E)
        })
        .collect();
    if wrap.len() != rows {
        return None;
    }
    let inner: Vec<usize> = edges.iter().copied().filter(|k| !wrap.contains(k)).collect();
    Some(Cylinder {
        grid: Grid {
            cells,
            dirs,
            edges: inner,
        },
        wrap,
    })
}

/// Fair a cylinder of patches as one surface closed around it (the grid joined as [`fair_grid`] does, cut
/// open along one column line, then faired as a ring, `ring.rs`): each object with its patch.
pub(super) fn fair_cylinder(
    objects: &[Geometry],
    cy: &Cylinder,
    joins: &[SurfaceJoin],
    opts: &SurfaceFairingOptions,
    tol: f64,
) -> Result<Vec<(usize, Patch)>> {
    let g = &cy.grid;
    let jg = join_grid(objects, g, joins, tol)?;
    // the joined grid's u runs around (the rows' v): turned so that v does
    let mut j = jg.outer.surface.transposed();
    let k = cy.wrap.iter().map(|&e| order(&joins[e])).max().unwrap_or(1);
    let (faired, bound, notes) = super::ring::fair_closed_v(&mut j, jg.err, k, &jg.inner[0].at, opts, tol)?;
    let what = format!(
        "faired as one closed surface with objects {:?}, {} rows of {} patches around a cylinder, across all their shared edges, the closing ones too (each keeps its continuity)",
        g.objects(),
        g.cells.len(),
        g.cells[0].len()
    );
    split_grid(objects, g, &jg, &faired.transposed(), bound, &notes, &what)
}
