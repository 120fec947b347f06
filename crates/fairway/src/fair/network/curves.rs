//! The curves of a network: which joins are concatenated and which held ([`plan`]), the chains that
//! result, and their fair ([`fair_chain`]).

use super::{
    Link, Net, ObjectFair, Route, at, concatenate, concatenate_as, fair_one_curve, hold_condition, is_corner,
    on_knots_of, oriented,
};
use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::fair::curve::{EndCondition, FairingOptions};
use crate::geometry::Geometry;
use crate::network::{CurveEnd, CurveJoin, End, Joins};

/// Curves concatenated into one, in order along it.
#[derive(Debug, Clone)]
pub(crate) struct Chain {
    /// The objects and whether each runs backwards along the chain.
    pub(crate) pieces: Vec<(usize, bool)>,
    /// How consecutive pieces join (`pieces.len() − 1` links; a closed chain's closing join is its seam).
    pub(crate) links: Vec<Link>,
    /// The last piece joins the first.
    pub(crate) closed: bool,
    /// The end conditions held at the chain's start and end (joins not concatenated).
    pub(crate) needs: [Option<EndCondition>; 2],
}

/// How each join is kept: concatenated (`Ok(link)`, and how far a control point moves to make it C2:
/// `moved`, 0 where it already is) or held (`Err(why)`).
fn decide(
    objects: &[Geometry],
    joins: &Joins,
    net: &Net<'_>,
    moved: &mut Vec<f64>,
) -> Vec<std::result::Result<Link, String>> {
    moved.resize(joins.curves.len(), 0.0);
    let chosen = &net.chosen;
    let count = |e: CurveEnd| joins.curves.iter().filter(|j| j.a == e || j.b == e).count();
    joins
        .curves
        .iter()
        .zip(moved.iter_mut())
        .map(|(j, moved)| {
            let (ca, cb) = (curve(objects, j.a.object), curve(objects, j.b.object));
            if net.opts.hold_all {
                return Err("every join held (one by one)".into());
            }
            if !(chosen[j.a.object] && chosen[j.b.object]) {
                return Err("a curve not being faired meets it".into());
            }
            if count(j.a) > 1 || count(j.b) > 1 {
                return Err("three or more curve ends meet there".into());
            }
            if !(ca.is_polynomial() && cb.is_polynomial()) {
                return Err("a rational curve (unequal weights) meets it".into());
            }
            if ca.dim() != cb.dim() || ca.degree() < 2 || cb.degree() < 2 {
                return Err("the curves differ in dimension, or one is of degree < 2".into());
            }
            let angle = j.continuity.angle;
            if angle.to_degrees() > 179.0 {
                return Err("the curves fold back over each other there (a duplicate or overlapping curve)".into());
            }
            if is_corner(angle) {
                return Ok(Link::Corner);
            }
            let link = match j.continuity.class {
                crate::network::Continuity::G0 => {
                    return Err(format!(
                        "a tangent break of {:.3}° is below the corner angle ({}°) the engine keeps",
                        angle.to_degrees(),
                        crate::corners::CORNER_ANGLE_DEG
                    ));
                }
                crate::network::Continuity::G1 => Link::Smooth(1),
                crate::network::Continuity::G2 => Link::Smooth(2),
            };
            let (first, second) = oriented_pair(objects, j).map_err(|e| e.to_string())?;
            let err = match concatenate_as(&first, &second, link, false) {
                Ok(_) => return Ok(link),
                Err(e) if link == Link::Smooth(2) => {
                    concatenate_as(&first, &second, link, true)
                        .map_err(|_| e.to_string())?
                        .2
                }
                Err(e) => return Err(e.to_string()),
            };
            // a control point moved to make a G2 join C2: at most a quarter of the band, else held
            let band = net.tolerance[j.a.object].min(net.tolerance[j.b.object]);
            if err > 0.25 * band {
                return Err(format!(
                    "making it C2 moves a control point next to it by {}, over a quarter of the band",
                    crate::range::short(err)
                ));
            }
            *moved = err;
            Ok(link)
        })
        .collect()
}

/// The curve of object `i`.
fn curve(objects: &[Geometry], i: usize) -> &BSplineCurve {
    objects[i].as_curve().expect("a curve")
}

/// The two curves of a join, the first ending and the second starting at it, raised to one degree.
fn oriented_pair(objects: &[Geometry], j: &CurveJoin) -> Result<(BSplineCurve, BSplineCurve)> {
    let p = curve(objects, j.a.object)
        .degree()
        .max(curve(objects, j.b.object).degree());
    let first = curve(objects, j.a.object).elevate_degree(p)?;
    let second = curve(objects, j.b.object).elevate_degree(p)?;
    let first = if j.a.end == End::End { first } else { first.reversed() };
    let second = if j.b.end == End::Start {
        second
    } else {
        second.reversed()
    };
    Ok((first, second))
}

/// The other end.
fn other(e: End) -> End {
    match e {
        End::Start => End::End,
        End::End => End::Start,
    }
}

/// The chains of the chosen curves, and a note per join (module docs of [`super`]).
pub(crate) fn plan(objects: &[Geometry], joins: &Joins, net: &Net<'_>, notes: &mut Vec<String>) -> Vec<Chain> {
    let chosen = &net.chosen;
    let mut moved = vec![];
    let decided = decide(objects, joins, net, &mut moved);
    // the concatenated join at each curve end: (join, the end on the other side)
    let link_at = |e: CurveEnd| -> Option<(usize, CurveEnd)> {
        joins.curves.iter().enumerate().find_map(|(k, j)| match &decided[k] {
            Ok(_) if j.a == e => Some((k, j.b)),
            Ok(_) if j.b == e => Some((k, j.a)),
            _ => None,
        })
    };
    for (k, j) in joins.curves.iter().enumerate() {
        if !(chosen[j.a.object] || chosen[j.b.object]) {
            continue;
        }
        let what = format!(
            "join of object {} ({:?}) and object {} ({:?}) at {}, {}",
            j.a.object,
            j.a.end,
            j.b.object,
            j.b.end,
            at(j.point),
            j.continuity.class.name()
        );
        notes.push(match &decided[k] {
            Ok(Link::Corner) => format!("{what}: concatenated as a corner (kept exactly, the curves faired as one)"),
            Ok(Link::Smooth(c)) if moved[k] > 0.0 => format!(
                "{what}: concatenated (C1 after a linear rescale, made C{c} by moving a control point next to it \
                 {} along the tangent, which keeps the joint's curvature; the joint moves within the band)",
                crate::range::short(moved[k])
            ),
            Ok(Link::Smooth(c)) => {
                format!("{what}: concatenated (C{c} after a linear rescale; the joint moves within the band)")
            }
            Err(why) => format!(
                "{what}: held ({:?} kept at each end): {why}",
                hold_condition(j.continuity.class)
            ),
        });
    }
    let mut visited = vec![false; objects.len()];
    let mut chains = vec![];
    for i in 0..objects.len() {
        if visited[i] || !chosen[i] || objects[i].as_curve().is_none() {
            continue;
        }
        let mut chain = walk(i, &link_at, &decided);
        for &(o, _) in &chain.pieces {
            visited[o] = true;
        }
        chain.needs = held_needs(joins, &decided, &chain);
        chains.push(chain);
    }
    chains
}

/// The chain through object `i`: back to its start (or round a loop), then forward.
fn walk(
    i: usize,
    link_at: &dyn Fn(CurveEnd) -> Option<(usize, CurveEnd)>,
    decided: &[std::result::Result<Link, String>],
) -> Chain {
    let end = |object, end| CurveEnd { object, end };
    // back: leave each curve by the end the chain enters it
    let (mut cur, mut back, mut cycle) = (i, End::Start, false);
    for _ in 0..decided.len() + 1 {
        match link_at(end(cur, back)) {
            None => break,
            Some((_, e)) if e.object == i => {
                cycle = true;
                break;
            }
            Some((_, e)) => (cur, back) = (e.object, other(e.end)),
        }
    }
    let (start, mut reversed) = if cycle { (i, false) } else { (cur, back == End::End) };
    let (mut pieces, mut links) = (vec![(start, reversed)], vec![]);
    let mut cur = start;
    for _ in 0..decided.len() + 1 {
        let leave = oriented(End::End, reversed);
        let Some((k, e)) = link_at(end(cur, leave)) else { break };
        let link = decided[k].clone().expect("a concatenated join");
        links.push(link);
        if e.object == start {
            break;
        }
        (cur, reversed) = (e.object, e.end == End::End);
        pieces.push((cur, reversed));
    }
    let closed = cycle && links.len() == pieces.len();
    if closed && let Some(c) = links.iter().position(|l| *l == Link::Corner) {
        // the seam at a corner: start after it
        let n = pieces.len();
        pieces.rotate_left((c + 1) % n);
        links.rotate_left((c + 1) % n);
    }
    if closed {
        links.pop();
    }
    Chain {
        pieces,
        links,
        closed,
        needs: [None, None],
    }
}

/// The end conditions the held joins at a chain's two ends ask for (the strongest at each).
fn held_needs(
    joins: &Joins,
    decided: &[std::result::Result<Link, String>],
    chain: &Chain,
) -> [Option<EndCondition>; 2] {
    if chain.closed {
        return [None, None];
    }
    let (first, last) = (chain.pieces[0], chain.pieces[chain.pieces.len() - 1]);
    let ends = [
        CurveEnd {
            object: first.0,
            end: oriented(End::Start, first.1),
        },
        CurveEnd {
            object: last.0,
            end: oriented(End::End, last.1),
        },
    ];
    ends.map(|e| {
        joins
            .curves
            .iter()
            .enumerate()
            .filter(|(k, j)| decided[*k].is_err() && (j.a == e || j.b == e))
            .map(|(_, j)| hold_condition(j.continuity.class))
            .max_by_key(|c| c.order())
    })
}

/// The options and end conditions that hold `needs` (a held join's continuity) at the ends of an open
/// curve faired whole: such an end keeps the join's condition (or the caller's `curve_ends` there, if
/// stronger), while a free end keeps the caller's options (by default at most G1).
pub(crate) fn end_setup(
    mut opts: FairingOptions,
    needs: [Option<EndCondition>; 2],
) -> (FairingOptions, [EndCondition; 2]) {
    opts.region = None;
    for (own, need) in opts.curve_ends.iter_mut().zip(needs) {
        if let Some(n) = need {
            *own = Some(own.map_or(n, |o| if o.order() > n.order() { o } else { n }));
        }
    }
    let ends = [0, 1].map(|i| needs[i].unwrap_or(opts.ends));
    (opts, ends)
}

/// One chain faired (module docs of [`super`]): its objects, the band's note, and the faired pieces or
/// the error. Reads only the originals, so the chains of a network are faired in parallel
/// ([`super::fair_network_at`]) and written back in order by [`apply_chain`].
pub(crate) struct ChainFair {
    group: Vec<usize>,
    band_note: Option<String>,
    result: Result<Vec<Piece>>,
}

/// Fair one chain (module docs of [`super`]).
pub(crate) fn fair_chain(objects: &[Geometry], chain: &Chain, net: &Net<'_>) -> ChainFair {
    let group: Vec<usize> = chain.pieces.iter().map(|p| p.0).collect();
    let (opts, band_note) = net.curve_options(&group);
    let result = if chain.pieces.len() == 1 && !chain.closed {
        let i = group[0];
        fair_one_curve(curve(objects, i), opts, chain.needs).map(|r| vec![(r.curve, r.max_deviation, r.notes)])
    } else {
        fair_concatenated(objects, chain, opts)
    };
    ChainFair {
        group,
        band_note,
        result,
    }
}

/// Write a faired chain's pieces into `out` and their outcome; an error leaves them as they were, with
/// the reason in their notes.
pub(crate) fn apply_chain(chain: &Chain, faired: ChainFair, out: &mut [Geometry], outcome: &mut [ObjectFair]) {
    let ChainFair {
        group,
        band_note,
        result,
    } = faired;
    match result {
        Ok(pieces) => {
            for (&i, (c, bound, mut notes)) in group.iter().zip(pieces) {
                notes.extend(band_note.clone());
                out[i] = c.into();
                outcome[i] = ObjectFair {
                    faired: true,
                    group: group.clone(),
                    max_deviation: bound,
                    notes,
                    route: if group.len() > 1 || chain.closed {
                        Route::Chain
                    } else {
                        Route::Alone
                    },
                };
            }
        }
        Err(e) => {
            for &i in &group {
                outcome[i].group = group.clone();
                outcome[i].notes.push(format!("left as it was: {e}"));
            }
        }
    }
}

/// A faired piece: the curve, its deviation bound, its notes.
type Piece = (BSplineCurve, f64, Vec<String>);

/// Concatenate a chain, fair it as one curve, split it back (module docs of [`super`]).
fn fair_concatenated(objects: &[Geometry], chain: &Chain, opts: FairingOptions) -> Result<Vec<Piece>> {
    let p = chain
        .pieces
        .iter()
        .map(|&(i, _)| curve(objects, i).degree())
        .max()
        .unwrap_or(3);
    // each piece raised to p (the reference for its knots), then turned along the chain
    let raised: Vec<BSplineCurve> = chain
        .pieces
        .iter()
        .map(|&(i, _)| curve(objects, i).elevate_degree(p))
        .collect::<Result<_>>()?;
    let along: Vec<BSplineCurve> = raised
        .iter()
        .zip(&chain.pieces)
        .map(|(c, &(_, rev))| if rev { c.reversed() } else { c.clone() })
        .collect();
    let (mut whole, mut err, mut at_joins) = (along[0].clone(), 0.0, vec![]);
    for (k, next) in along.iter().enumerate().skip(1) {
        let (c, y, e) = concatenate(&whole, next, chain.links[k - 1])?;
        (whole, err) = (c, err + e);
        at_joins.push(y);
    }
    if chain.closed {
        let mut pts = whole.points().to_vec();
        let n = pts.len() - 1;
        let mid = (pts[0] + pts[n]) * 0.5;
        err += 0.5 * pts[0].distance(pts[n]);
        (pts[0], pts[n]) = (mid, mid);
        whole = whole.with_points(pts)?;
    }
    let m = opts.tolerance - err;
    if !(m > 0.0) {
        return Err(Error::InvalidInput(format!(
            "the joins' gaps ({err}) take the whole band ({})",
            opts.tolerance
        )));
    }
    let needs = if chain.closed { [None, None] } else { chain.needs };
    let r = fair_one_curve(&whole, FairingOptions { tolerance: m, ..opts }, needs)?;
    let mut rest = r.curve.clone();
    let mut split = vec![];
    for &y in &at_joins {
        let (l, right) = crate::fair::closed::split(&rest, y)?;
        split.push(l);
        rest = right;
    }
    split.push(rest);
    let mut notes = r.notes.clone();
    notes.push(format!(
        "faired as one curve with objects {:?} (their joins kept by construction; the band narrowed by {} for the \
         joins' gaps and knot removal)",
        chain.pieces.iter().map(|p| p.0).collect::<Vec<_>>(),
        crate::range::short(err)
    ));
    split
        .iter()
        .zip(&along)
        .zip(raised.iter().zip(&chain.pieces))
        .map(|((s, al), (ra, &(i, rev)))| {
            let s = on_knots_of(s, al)?;
            let back = on_knots_of(&if rev { s.reversed() } else { s }, ra)?;
            let mut n = notes.clone();
            if ra.degree() > curve(objects, i).degree() {
                n.push(format!(
                    "degree raised from {} to {} to join the others (exact)",
                    curve(objects, i).degree(),
                    ra.degree()
                ));
            }
            Ok((back, r.max_deviation + err, n))
        })
        .collect()
}
