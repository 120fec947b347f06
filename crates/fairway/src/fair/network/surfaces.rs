//! The patches of a network: patches sharing G1 edges that are parametrically C1 after a linear rescale
//! are concatenated where they form a strip (here), a grid (`grid.rs`) or another layout on a grid of
//! cells (`layout.rs`), faired as one surface and split back; other shared edges are held (module docs
//! of [`super`]).

use glam::DVec3;

use super::{Net, ObjectFair, Route, rescaled};
use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::fair::closed::{join, split};
use crate::fair::surface::{SurfaceFairingOptions, fair_surface};
use crate::geometry::Geometry;
use crate::network::{Continuity, Joins, Side, SurfaceJoin};
use crate::surface::BSplineSurface;

mod grid;
mod layout;
mod ring;

/// The curves along v of `s`, one per control row i (points `P(i, ·)`, knots V).
fn along_v(s: &BSplineSurface) -> Vec<BSplineCurve> {
    (0..s.nu())
        .map(|i| {
            let pts = (0..s.nv()).map(|j| s.point_at(i, j)).collect();
            BSplineCurve::try_new(s.degree_v(), s.knots_v().values().to_vec(), pts, None, 3)
                .expect("a row of a valid net")
        })
        .collect()
}

/// The surface whose rows along v are `rows` (one knot vector), with degree and knots `u` across them.
fn from_along_v(rows: &[BSplineCurve], (pu, ku): (usize, &[f64])) -> Result<BSplineSurface> {
    let pts: Vec<DVec3> = rows.iter().flat_map(|c| c.points().iter().copied()).collect();
    BSplineSurface::try_new(
        pu,
        rows[0].degree(),
        ku.to_vec(),
        rows[0].knots().values().to_vec(),
        rows.len(),
        rows[0].n_points(),
        pts,
        None,
    )
}

/// `s` with its v direction reversed.
fn reverse_v(s: &BSplineSurface) -> BSplineSurface {
    let rows: Vec<BSplineCurve> = along_v(s).iter().map(BSplineCurve::reversed).collect();
    from_along_v(&rows, (s.degree_u(), s.knots_u().values())).expect("a reversed valid net")
}

/// `s` with its u direction reversed.
fn reverse_u(s: &BSplineSurface) -> BSplineSurface {
    reverse_v(&s.transposed()).transposed()
}

/// The steps that turn a patch so that its side `side` is v = v₁ (`last`) or v = v₀, the u direction
/// along the edge kept: (transpose first, then reverse v).
fn turn_to_v(side: Side, last: bool) -> (bool, bool) {
    let (transposed, at_end) = match side {
        Side::V0 => (false, false),
        Side::V1 => (false, true),
        Side::U0 => (true, false),
        Side::U1 => (true, true),
    };
    (transposed, at_end != last)
}

fn apply(s: &BSplineSurface, (t, r): (bool, bool), flip_u: bool) -> BSplineSurface {
    let s = if t { s.transposed() } else { s.clone() };
    let s = if r { reverse_v(&s) } else { s };
    if flip_u { reverse_u(&s) } else { s }
}

fn undo(s: &BSplineSurface, (t, r): (bool, bool), flip_u: bool) -> BSplineSurface {
    let s = if flip_u { reverse_u(s) } else { s.clone() };
    let s = if r { reverse_v(&s) } else { s };
    if t { s.transposed() } else { s }
}

/// `s` raised to the degrees `pu`, `pv` (≥ its own; [`BSplineCurve::elevate_degree`] on its rows, exact).
fn elevate(s: &BSplineSurface, pu: usize, pv: usize) -> Result<BSplineSurface> {
    let s = if s.degree_v() < pv {
        let rows: Vec<BSplineCurve> = along_v(s).iter().map(|c| c.elevate_degree(pv)).collect::<Result<_>>()?;
        from_along_v(&rows, (s.degree_u(), s.knots_u().values()))?
    } else {
        s.clone()
    };
    if s.degree_u() < pu {
        let t = s.transposed();
        let rows: Vec<BSplineCurve> = along_v(&t)
            .iter()
            .map(|c| c.elevate_degree(pu))
            .collect::<Result<_>>()?;
        Ok(from_along_v(&rows, (t.degree_u(), t.knots_u().values()))?.transposed())
    } else {
        Ok(s)
    }
}

/// `s` on the u domain `[a, b]` (a linear map).
fn with_u_domain(s: &BSplineSurface, a: f64, b: f64) -> Result<BSplineSurface> {
    let t = s.transposed();
    let rows: Vec<BSplineCurve> = along_v(&t)
        .iter()
        .map(|c| rescaled(c, a, b - a))
        .collect::<Result<_>>()?;
    Ok(from_along_v(&rows, (t.degree_u(), t.knots_u().values()))?.transposed())
}

/// `s` with the u knots `extra` inserted (exact).
fn refine_u(s: &BSplineSurface, extra: &[f64]) -> Result<BSplineSurface> {
    if extra.is_empty() {
        return Ok(s.clone());
    }
    let t = s.transposed();
    let rows: Vec<BSplineCurve> = along_v(&t).iter().map(|c| c.refine(extra)).collect::<Result<_>>()?;
    Ok(from_along_v(&rows, (t.degree_u(), t.knots_u().values()))?.transposed())
}

/// The knots of `a` missing from `b` (multisets of sorted values, equal within `eps`).
fn missing(a: &[f64], b: &[f64], eps: f64) -> Vec<f64> {
    let (mut out, mut j) = (vec![], 0);
    for &k in a {
        while j < b.len() && b[j] < k - eps {
            j += 1;
        }
        if j < b.len() && (b[j] - k).abs() <= eps {
            j += 1;
        } else {
            out.push(k);
        }
    }
    out
}

/// Two patches turned so that `a` ends (v = v₁) and `b` starts (v = v₀) at the shared edge, on one u
/// knot vector: the turned patches and how each was turned.
struct Pair {
    a: BSplineSurface,
    b: BSplineSurface,
    turn_b: (bool, bool),
    /// The u knots inserted into each (notes).
    inserted: [usize; 2],
    /// `b`'s own u domain (turned), before it was mapped onto `a`'s.
    b_u: (f64, f64),
}

fn pair(sa: &BSplineSurface, sb: &BSplineSurface, j: &SurfaceJoin, tol: f64) -> Result<Pair> {
    let (turn_a, turn_b) = (turn_to_v(j.a.1, true), turn_to_v(j.b.1, false));
    let (a, b) = (apply(sa, turn_a, false), apply(sb, turn_b, j.reversed));
    // different degrees: both raised to the higher ones (exact)
    let (pu, pv) = (a.degree_u().max(b.degree_u()), a.degree_v().max(b.degree_v()));
    let (a, b) = (elevate(&a, pu, pv)?, elevate(&b, pu, pv)?);
    let (ua, ub) = (a.domain().0, b.domain().0);
    let b = with_u_domain(&b, ua.0, ua.1)?;
    let eps = 1e-12 * (ua.1 - ua.0).max(ub.1 - ub.0);
    let (ka, kb) = (a.knots_u().values().to_vec(), b.knots_u().values().to_vec());
    let (to_a, to_b) = (missing(&kb, &ka, eps), missing(&ka, &kb, eps));
    let (a, b) = (refine_u(&a, &to_a)?, refine_u(&b, &to_b)?);
    let b = BSplineSurface::try_new(
        b.degree_u(),
        b.degree_v(),
        a.knots_u().values().to_vec(),
        b.knots_v().values().to_vec(),
        b.nu(),
        b.nv(),
        b.points().to_vec(),
        None,
    )?;
    let nv = a.nv();
    if (0..a.nu()).any(|i| a.point_at(i, nv - 1).distance(b.point_at(i, 0)) > tol) {
        return Err(Error::InvalidInput(
            "the edge is parametrized differently on the two patches (its control points differ)".into(),
        ));
    }
    Ok(Pair {
        a,
        b,
        turn_b,
        inserted: [to_a.len(), to_b.len()],
        b_u: ub,
    })
}

/// The v length `b` of a pair takes in the joined surface: its own, scaled so the mean cross-derivative
/// lengths along the edge are equal on both sides (the linear rescale across it).
fn cross_len(p: &Pair) -> Result<f64> {
    let y = p.a.domain().1.1;
    let (mut da, mut db) = (0.0, 0.0);
    for t in 0..=10 {
        let u = p.a.domain().0.0 + (p.a.domain().0.1 - p.a.domain().0.0) * t as f64 / 10.0;
        da += p.a.derivs(u, y).sv.length();
        db += p.b.derivs(u, p.b.domain().1.0).sv.length();
    }
    let (b0, b1) = p.b.domain().1;
    if !(da > 0.0 && db > 0.0) {
        return Err(Error::InvalidInput("a patch is degenerate across the edge".into()));
    }
    Ok((b1 - b0) * db / da)
}

/// The patches of a pair joined along v into one surface (the rows along v concatenated, the edge's
/// knot removed while every row allows it within 1e-9 × the net's size, at least down to C^k): the
/// surface, the edge's v, the error made.
fn concatenate(p: &Pair, k: usize) -> Result<(BSplineSurface, f64, f64)> {
    concatenate_at(p, k, cross_len(p)?)
}

/// [`concatenate`] with `b`'s v length in the joined surface given (`len`).
fn concatenate_at(p: &Pair, k: usize, len: f64) -> Result<(BSplineSurface, f64, f64)> {
    let (ra, rb) = (along_v(&p.a), along_v(&p.b));
    let y = p.a.domain().1.1;
    let (lo, hi) = crate::curve::point_bounds(p.a.points());
    let tol = 1e-9 * (hi - lo).length();
    let rows: Vec<BSplineCurve> = ra
        .iter()
        .zip(&rb)
        .map(|(x, z)| join(x, &rescaled(z, y, len)?))
        .collect::<Result<_>>()?;
    let gap = (0..p.a.nu())
        .map(|i| p.a.point_at(i, p.a.nv() - 1).distance(p.b.point_at(i, 0)))
        .fold(0.0, f64::max);
    let pv = p.a.degree_v();
    let (rows, mult) = super::remove_knot_rows(rows, y, tol, pv, 0);
    let mut err = 0.5 * gap;
    (mult..pv).for_each(|_| err += tol);
    if mult + k > pv {
        return Err(Error::InvalidInput(format!(
            "not parametrically C{k} across the edge after a linear rescale (C{} at most)",
            pv - mult
        )));
    }
    Ok((from_along_v(&rows, (p.a.degree_u(), p.a.knots_u().values()))?, y, err))
}

/// `s` with the knot values of `reference` where it has as many (a patch split back on its own knots).
fn on_knots_of(s: &BSplineSurface, reference: &BSplineSurface) -> BSplineSurface {
    let same = |a: &[f64], b: &[f64]| a.len() == b.len();
    let ku = if same(s.knots_u().values(), reference.knots_u().values()) {
        reference
    } else {
        s
    };
    let kv = if same(s.knots_v().values(), reference.knots_v().values()) {
        reference
    } else {
        s
    };
    BSplineSurface::try_new(
        s.degree_u(),
        s.degree_v(),
        ku.knots_u().values().to_vec(),
        kv.knots_v().values().to_vec(),
        s.nu(),
        s.nv(),
        s.points().to_vec(),
        None,
    )
    .unwrap_or_else(|_| s.clone())
}

/// A faired patch: the surface, its deviation bound, its notes.
type Patch = (BSplineSurface, f64, Vec<String>);

/// How a patch of a strip sits in the joined surface: turned so (transpose, reverse v, reverse u), its
/// own u domain (turned), its own v knots (turned, raised), and the knots inserted along its edges.
struct Placed {
    turn: (bool, bool),
    flip: bool,
    own_u: (f64, f64),
    own_v: BSplineCurve,
    inserted: usize,
}

/// The continuity order a concatenation must keep: C2 across a G2 edge, else C1.
fn order(j: &SurfaceJoin) -> usize {
    if j.continuity.class == Continuity::G2 { 2 } else { 1 }
}

/// The shared edge of `joined`'s side v = v₁ and side `side` of `next` as a join (`reversed` found from
/// the corner points).
fn edge_to(joined: &BSplineSurface, next: &BSplineSurface, side: Side, j: &SurfaceJoin) -> SurfaceJoin {
    let (ca, cb) = (Side::V1.curve(joined), side.curve(next));
    let (a0, b0, b1) = (
        ca.point(ca.domain().0),
        cb.point(cb.domain().0),
        cb.point(cb.domain().1),
    );
    SurfaceJoin {
        a: (0, Side::V1),
        b: (1, side),
        reversed: a0.distance(b1) < a0.distance(b0),
        continuity: j.continuity,
    }
}

/// A strip of patches joined into one surface along v: the surface, the v of each edge between them,
/// how each patch sits in it, and the error the joining made (the edges' gaps closed, knot removals).
struct Strip {
    joined: BSplineSurface,
    at: Vec<f64>,
    placed: Vec<Placed>,
    err: f64,
}

/// Concatenate a strip of patches (`order[k]` joins `order[k − 1]` by `edges[k − 1]`) into one surface.
fn join_strip(objects: &[Geometry], order_: &[usize], edges: &[&SurfaceJoin], tol: f64) -> Result<Strip> {
    let s = |i: usize| objects[i].as_surface().expect("a surface");
    let side_of = |j: &SurfaceJoin, i: usize| if j.a.0 == i { j.a.1 } else { j.b.1 };
    let turn0 = turn_to_v(side_of(edges[0], order_[0]), true);
    let mut joined = apply(s(order_[0]), turn0, false);
    let mut placed = vec![Placed {
        turn: turn0,
        flip: false,
        own_u: joined.domain().0,
        own_v: along_v(&joined)[0].clone(),
        inserted: 0,
    }];
    let (mut at, mut err) = (vec![], 0.0);
    for (k, j) in edges.iter().enumerate() {
        let next = s(order_[k + 1]);
        let e = edge_to(&joined, next, side_of(j, order_[k + 1]), j);
        let p = pair(&joined, next, &e, tol)?;
        let (c, y, e_err) = concatenate(&p, order(j))?;
        placed[..].iter_mut().for_each(|q| q.inserted += p.inserted[0]);
        placed.push(Placed {
            turn: p.turn_b,
            flip: e.reversed,
            own_u: p.b_u,
            own_v: along_v(&p.b)[0].clone(),
            inserted: p.inserted[1],
        });
        (joined, err) = (c, err + e_err);
        at.push(y);
    }
    Ok(Strip {
        joined,
        at,
        placed,
        err,
    })
}

/// Concatenate a strip of patches ([`join_strip`]), fair it as one surface, split it back (module docs of
/// [`super`]).
fn fair_strip(
    objects: &[Geometry],
    order_: &[usize],
    edges: &[&SurfaceJoin],
    opts: &SurfaceFairingOptions,
    tol: f64,
) -> Result<Vec<Patch>> {
    let st = join_strip(objects, order_, edges, tol)?;
    let (r, bound) = fair_joined(&st.joined, st.err, opts, None)?;
    let what =
        format!("faired as one surface with objects {order_:?} across their shared edges (each keeps its continuity)");
    split_back(objects, order_, &st, &r.surface, bound, &r.notes, &what)
}

/// The faired surface `faired` of a joined strip `st` split back into its patches, each on its own knots
/// with its own deviation bound ([`own_bound`], at most the whole's `bound`) and the fair's `notes`
/// followed by `what`.
fn split_back(
    objects: &[Geometry],
    order_: &[usize],
    st: &Strip,
    faired: &BSplineSurface,
    bound: f64,
    notes: &[String],
    what: &str,
) -> Result<Vec<Patch>> {
    let s = |i: usize| objects[i].as_surface().expect("a surface");
    let pieces = split_strip(faired, &st.at, &st.placed)?;
    Ok(pieces
        .into_iter()
        .zip(order_)
        .zip(&st.placed)
        .map(|((piece, &i), q)| {
            let piece = on_knots_of(&piece, s(i));
            let mut n = notes.to_vec();
            n.push(what.to_string());
            exact_changes_notes(q.inserted, s(i), &piece, &mut n);
            let b = own_bound(s(i), &piece, bound, &mut n);
            (piece, b, n)
        })
        .collect())
}

/// A patch's own deviation bound after a fair with others: the sound bound of its own change
/// ([`surface_band_bound`](crate::fair::verify::surface_band_bound) on its own knots) where that applies
/// and is smaller, else the bound of the whole it was faired in.
/// A note says which.
pub(super) fn own_bound(original: &BSplineSurface, piece: &BSplineSurface, whole: f64, notes: &mut Vec<String>) -> f64 {
    use crate::range::short;
    match crate::fair::verify::surface_band_bound(original, piece, whole) {
        Some(b) => {
            let b = b.min(whole);
            notes.push(format!(
                "its own deviation bound {} (the surface faired as one: {})",
                short(b),
                short(whole)
            ));
            b
        }
        None => {
            notes.push(format!(
                "its deviation bound is the surface faired as one's, {} (its own net differs from the original's in knots or degrees)",
                short(whole)
            ));
            whole
        }
    }
}

/// The faired strip split back along v = `at[k]` into its patches, each on its own v knots and u domain,
/// turned back.
fn split_strip(s: &BSplineSurface, at: &[f64], placed: &[Placed]) -> Result<Vec<BSplineSurface>> {
    let mut rest = along_v(s);
    let mut rows: Vec<Vec<BSplineCurve>> = vec![];
    for &y in at {
        let (l, r): (Vec<_>, Vec<_>) = rest
            .iter()
            .map(|c| split(c, y))
            .collect::<Result<Vec<_>>>()?
            .into_iter()
            .unzip();
        rows.push(l);
        rest = r;
    }
    rows.push(rest);
    let ku = s.knots_u().values();
    rows.iter()
        .zip(placed)
        .map(|(r, q)| {
            let r: Vec<BSplineCurve> = r
                .iter()
                .map(|c| super::on_knots_of(c, &q.own_v))
                .collect::<Result<_>>()?;
            let piece = with_u_domain(&from_along_v(&r, (s.degree_u(), ku))?, q.own_u.0, q.own_u.1)?;
            Ok(undo(&piece, q.turn, q.flip))
        })
        .collect()
}

/// Whether an edge can be concatenated (both patches chosen and polynomial, G1 or better, C1 / C2 after a
/// rescale across it), else why it is held.
fn edge_ok(objects: &[Geometry], j: &SurfaceJoin, net: &Net<'_>, tol: f64) -> std::result::Result<(), String> {
    let s = |i: usize| objects[i].as_surface().expect("a surface");
    if net.opts.hold_all {
        return Err("every edge held (one by one)".into());
    }
    if !(net.chosen[j.a.0] && net.chosen[j.b.0]) {
        return Err("a patch not being faired shares it".into());
    }
    if j.continuity.class == Continuity::G0 {
        return Err("G0 only: a crease, kept".into());
    }
    if !(s(j.a.0).is_polynomial() && s(j.b.0).is_polynomial()) {
        return Err("a rational patch (unequal weights)".into());
    }
    let p = pair(s(j.a.0), s(j.b.0), j, tol).map_err(|e| e.to_string())?;
    concatenate(&p, order(j)).map(|_| ()).map_err(|e| e.to_string())
}

/// A strip of patches found among the concatenable edges: its patches in order, the edges between them,
/// and for a ring the edge that closes it (the last patch's with the first).
type Found = (Vec<usize>, Vec<usize>, Option<usize>);

/// The strips of patches joined by the concatenable edges `ok`: each patch with at most two such
/// edges, on opposite sides (else its edges are held, with the reason in `why`); a ring is a strip
/// opened at one edge, its closing edge.
fn strips(joins: &[SurfaceJoin], ok: &mut [std::result::Result<(), String>], n: usize) -> Vec<Found> {
    let at = |ok: &[std::result::Result<(), String>], i: usize| -> Vec<usize> {
        (0..joins.len())
            .filter(|&k| ok[k].is_ok() && (joins[k].a.0 == i || joins[k].b.0 == i))
            .collect()
    };
    let side = |k: usize, i: usize| if joins[k].a.0 == i { joins[k].a.1 } else { joins[k].b.1 };
    let opposite = |a: Side, b: Side| {
        matches!(
            (a, b),
            (Side::U0, Side::U1) | (Side::U1, Side::U0) | (Side::V0, Side::V1) | (Side::V1, Side::V0)
        )
    };
    for i in 0..n {
        let e = at(ok, i);
        if e.len() > 2 || (e.len() == 2 && !opposite(side(e[0], i), side(e[1], i))) {
            for k in e {
                ok[k] = Err(format!(
                    "patch {i} shares edges on more than two or on adjacent sides (only strips are faired as one)"
                ));
            }
        }
    }
    let (mut out, mut seen) = (vec![], vec![false; n]);
    // a strip starts at a patch with one edge; then a ring (every patch two) is opened at its first edge
    let starts: Vec<usize> = (0..n)
        .filter(|&i| at(ok, i).len() == 1)
        .chain((0..n).filter(|&i| at(ok, i).len() == 2))
        .collect();
    for start in starts {
        let e = at(ok, start);
        if seen[start] || e.is_empty() {
            continue;
        }
        // a ring: walked from its first edge round to the closing one, e[0]
        let closing = (e.len() == 2).then_some(e[0]);
        let (mut order_, mut edges, mut cur, mut prev) = (vec![start], vec![], start, closing.unwrap_or(usize::MAX));
        seen[start] = true;
        while let Some(k) = at(ok, cur).into_iter().find(|&k| k != prev) {
            let next = if joins[k].a.0 == cur {
                joins[k].b.0
            } else {
                joins[k].a.0
            };
            if seen[next] {
                break;
            }
            (prev, cur) = (k, next);
            seen[cur] = true;
            order_.push(cur);
            edges.push(k);
        }
        out.push((order_, edges, closing));
    }
    out
}

/// The region of `s` that leaves one knot span next to each held side as it is (`None`: no span left).
fn held_region(s: &BSplineSurface, held: &[Side]) -> Option<((f64, f64), (f64, f64))> {
    let trim = |bps: Vec<f64>, lo: bool, hi: bool| -> Option<(f64, f64)> {
        let n = bps.len();
        let (i, k) = (usize::from(lo), n - 1 - usize::from(hi));
        (i < k).then(|| (bps[i], bps[k]))
    };
    let u = trim(
        s.knots_u().breakpoints(),
        held.contains(&Side::U0),
        held.contains(&Side::U1),
    )?;
    let v = trim(
        s.knots_v().breakpoints(),
        held.contains(&Side::V0),
        held.contains(&Side::V1),
    )?;
    Some((u, v))
}

/// Fair the grids of patches among the concatenable edges `ok` (`grid.rs`), each as one surface; a
/// grid that cannot be joined has its edges held (`ok` says why). Which edges are a grid's.
fn fair_grids(
    objects: &[Geometry],
    joins: &Joins,
    net: &Net<'_>,
    ok: &mut [std::result::Result<(), String>],
    out: &mut [Geometry],
    outcome: &mut [ObjectFair],
    done: &mut [bool],
) -> Vec<bool> {
    let mut in_grid = vec![false; ok.len()];
    for g in grid::grids(&joins.surfaces, ok, objects.len()) {
        let members = g.objects();
        let (opts, band_note) = net.surface_options(&members);
        g.edges.iter().for_each(|&k| in_grid[k] = true);
        match grid::fair_grid(objects, &g, &joins.surfaces, &opts, joins.tolerance) {
            Ok(patches) => record(patches, &members, band_note.as_ref(), Route::Grid, out, outcome, done),
            Err(e) => g.edges.iter().for_each(|&k| {
                ok[k] = Err(format!(
                    "a {} grid of patches that cannot be joined as one: {e}",
                    g.size()
                ))
            }),
        }
    }
    in_grid
}

/// Record the patches of `group` faired as one by `route`: each one's surface and outcome (the band's note
/// added to its notes), and that it is done.
fn record(
    patches: Vec<(usize, Patch)>,
    group: &[usize],
    band_note: Option<&String>,
    route: Route,
    out: &mut [Geometry],
    outcome: &mut [ObjectFair],
    done: &mut [bool],
) {
    for (i, (s, bound, mut n)) in patches {
        n.extend(band_note.cloned());
        out[i] = s.into();
        outcome[i] = ObjectFair {
            faired: true,
            group: group.to_vec(),
            max_deviation: bound,
            notes: n,
            route,
        };
        done[i] = true;
    }
}

/// Fair the cylinders of patches among the concatenable edges `ok` (R ≥ 2 rows closing on themselves,
/// `grid.rs`, `ring.rs`), each as one closed surface; one that cannot be joined has its edges held (`ok`
/// says why). Which edges are a cylinder's.
fn fair_cylinders(
    objects: &[Geometry],
    joins: &Joins,
    net: &Net<'_>,
    ok: &mut [std::result::Result<(), String>],
    out: &mut [Geometry],
    outcome: &mut [ObjectFair],
    done: &mut [bool],
) -> Vec<bool> {
    let mut in_cylinder = vec![false; ok.len()];
    for cy in grid::cylinders(&joins.surfaces, ok, objects.len()) {
        let members = cy.grid.objects();
        if members.iter().any(|&i| done[i]) {
            continue;
        }
        let (opts, band_note) = net.surface_options(&members);
        let edges: Vec<usize> = cy.grid.edges.iter().chain(&cy.wrap).copied().collect();
        edges.iter().for_each(|&k| in_cylinder[k] = true);
        match grid::fair_cylinder(objects, &cy, &joins.surfaces, &opts, joins.tolerance) {
            Ok(patches) => record(patches, &members, band_note.as_ref(), Route::Ring, out, outcome, done),
            Err(e) => edges
                .iter()
                .for_each(|&k| ok[k] = Err(format!("a cylinder of patches that cannot be joined as one: {e}"))),
        }
    }
    in_cylinder
}

/// Fair the layouts of patches among the concatenable edges `ok` that are neither strips nor grids
/// (`layout.rs`), each as one surface; a layout that cannot be joined leaves its edges to the strips
/// (a note says why). Which edges are a faired layout's.
#[allow(clippy::too_many_arguments)]
fn fair_layouts(
    objects: &[Geometry],
    joins: &Joins,
    net: &Net<'_>,
    ok: &[std::result::Result<(), String>],
    out: &mut [Geometry],
    outcome: &mut [ObjectFair],
    done: &mut [bool],
    notes: &mut Vec<String>,
) -> Vec<bool> {
    let mut in_layout = vec![false; ok.len()];
    for lay in layout::layouts(&joins.surfaces, ok, objects.len()) {
        if lay.members.iter().any(|&i| done[i]) {
            continue;
        }
        let (opts, band_note) = net.surface_options(&lay.members);
        match layout::fair_layout(objects, &lay, &joins.surfaces, &opts, joins.tolerance) {
            Ok(patches) => {
                lay.edges.iter().for_each(|&k| in_layout[k] = true);
                record(
                    patches,
                    &lay.members,
                    band_note.as_ref(),
                    Route::Layout,
                    out,
                    outcome,
                    done,
                );
            }
            Err(e) => notes.push(format!(
                "objects {:?}, {}: not faired as one ({e}); their edges go to the strip route",
                lay.members,
                lay.describe()
            )),
        }
    }
    in_layout
}

/// Fair the chosen surfaces, keeping their shared edges (module docs of [`super`]).
pub(crate) fn fair_surfaces(
    objects: &[Geometry],
    joins: &Joins,
    net: &Net<'_>,
    out: &mut [Geometry],
    outcome: &mut [ObjectFair],
    notes: &mut Vec<String>,
) {
    let mut ok: Vec<std::result::Result<(), String>> = joins
        .surfaces
        .iter()
        .map(|j| edge_ok(objects, j, net, joins.tolerance))
        .collect();
    layout::hold_mixed_lines(&joins.surfaces, &mut ok, objects.len());
    let mut done = vec![false; objects.len()];
    // grids first, then the other layouts; their edges are kept from the strips
    let mut in_grid = fair_grids(objects, joins, net, &mut ok, out, outcome, &mut done);
    let in_layout = fair_layouts(objects, joins, net, &ok, out, outcome, &mut done, notes);
    in_grid.iter_mut().zip(in_layout).for_each(|(g, l)| *g |= l);
    let in_cylinder = fair_cylinders(objects, joins, net, &mut ok, out, outcome, &mut done);
    in_grid.iter_mut().zip(in_cylinder).for_each(|(g, l)| *g |= l);
    let mut free: Vec<std::result::Result<(), String>> = ok
        .iter()
        .zip(&in_grid)
        .map(|(r, &g)| if g { Err(String::new()) } else { r.clone() })
        .collect();
    let found = strips(&joins.surfaces, &mut free, objects.len());
    for (k, r) in free.into_iter().enumerate() {
        if !in_grid[k] {
            ok[k] = r;
        }
    }
    for (order_, edges, closing) in found {
        let all: Vec<usize> = edges.iter().copied().chain(closing).collect();
        if grid::has_held(&order_, &all, &joins.surfaces) {
            // the strip route fairs the whole strip: it cannot keep the span next to a held edge
            let why = "a patch of this strip has a held edge (the strip could not be laid on a frame)";
            all.iter().for_each(|&k| ok[k] = Err(why.into()));
            continue;
        }
        let list: Vec<&SurfaceJoin> = edges.iter().map(|&k| &joins.surfaces[k]).collect();
        let (opts, band_note) = net.surface_options(&order_);
        let (fair, route) = match closing {
            Some(c) => (
                ring::fair_ring(objects, &order_, &list, &joins.surfaces[c], &opts, joins.tolerance),
                Route::Ring,
            ),
            None => (
                fair_strip(objects, &order_, &list, &opts, joins.tolerance),
                Route::Strip,
            ),
        };
        match fair {
            Ok(patches) => record(
                order_.iter().copied().zip(patches).collect(),
                &order_,
                band_note.as_ref(),
                route,
                out,
                outcome,
                &mut done,
            ),
            Err(e) => all.iter().for_each(|&k| ok[k] = Err(e.to_string())),
        }
    }
    let mut held: Vec<Vec<Side>> = vec![vec![]; objects.len()];
    for (j, r) in joins.surfaces.iter().zip(&ok) {
        if !(net.chosen[j.a.0] || net.chosen[j.b.0]) {
            continue;
        }
        let what = format!(
            "edge of object {} ({:?}) and object {} ({:?}), {} (normal angle {:.2e}°)",
            j.a.0,
            j.a.1,
            j.b.0,
            j.b.1,
            j.continuity.class.name(),
            j.continuity.normal_angle.to_degrees()
        );
        match r {
            Ok(()) => notes.push(format!("{what}: concatenated and faired as one surface")),
            Err(e) => {
                held[j.a.0].push(j.a.1);
                held[j.b.0].push(j.b.1);
                notes.push(format!("{what}: held (the span next to it kept on each patch): {e}"));
            }
        }
    }
    fair_alone(objects, net, &done, &held, out, outcome);
}

/// Fair the chosen patches not faired in a strip, each with a region one knot span short of its held
/// edges.
fn fair_alone(
    objects: &[Geometry],
    net: &Net<'_>,
    done: &[bool],
    held: &[Vec<Side>],
    out: &mut [Geometry],
    outcome: &mut [ObjectFair],
) {
    for (i, g) in objects.iter().enumerate() {
        let Some(s) = g.as_surface() else { continue };
        if done[i] || !net.chosen[i] {
            continue;
        }
        let region = if held[i].is_empty() {
            None
        } else {
            held_region(s, &held[i])
        };
        if !held[i].is_empty() && region.is_none() {
            outcome[i]
                .notes
                .push("left as it was: too few knot spans to hold its shared edges".into());
            continue;
        }
        let opts = SurfaceFairingOptions {
            region,
            tolerance: net.tolerance[i],
            ..net.opts.surface
        };
        match fair_surface(s, opts) {
            Ok(r) => {
                out[i] = r.surface.into();
                outcome[i].faired = true;
                outcome[i].route = Route::Alone;
                outcome[i].max_deviation = r.band_bound.unwrap_or(r.max_deviation);
                outcome[i].notes = r.notes;
            }
            Err(e) => outcome[i].notes.push(format!("left as it was: {e}")),
        }
    }
}

/// The notes on what joining changed exactly in a patch faired with its neighbours: `inserted` knots along
/// its edges, its degrees raised from `original`'s to `piece`'s.
pub(super) fn exact_changes_notes(
    inserted: usize,
    original: &BSplineSurface,
    piece: &BSplineSurface,
    n: &mut Vec<String>,
) {
    if inserted > 0 {
        n.push(format!(
            "{inserted} knots inserted along the edges to match the neighbours' (exact)"
        ));
    }
    if (piece.degree_u(), piece.degree_v()) != (original.degree_u(), original.degree_v()) {
        n.push(format!(
            "degrees raised from {} × {} to {} × {} to join the neighbours (exact)",
            original.degree_u(),
            original.degree_v(),
            piece.degree_u(),
            piece.degree_v()
        ));
    }
}

/// Fair patches joined into one surface whose joining moved them by up to `err` (the edges' gaps closed):
/// the whole surface (or `region` of it), within the band that leaves; the fair's result and its bound on
/// the deviation from the original patches (the fair's bound plus `err`).
pub(super) fn fair_joined(
    joined: &BSplineSurface,
    err: f64,
    opts: &SurfaceFairingOptions,
    region: Option<((f64, f64), (f64, f64))>,
) -> Result<(crate::fair::surface::SurfaceFairingResult, f64)> {
    let m = opts.tolerance - err;
    if !(m > 0.0) {
        return Err(Error::InvalidInput("the edges' gaps take the whole band".into()));
    }
    let r = fair_surface(
        joined,
        SurfaceFairingOptions {
            tolerance: m,
            region,
            ..*opts
        },
    )?;
    let bound = r.band_bound.unwrap_or(r.max_deviation) + err;
    Ok((r, bound))
}
