//! Where a STEP file puts its geometry: the placements of an assembly.
//!
//! A part's B-splines are items (reached through faces, shells, edges …) of a representation in the
//! part's own coordinates. An assembly places a representation in its parent's with a
//! `REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION` whose `ITEM_DEFINED_TRANSFORMATION` maps an axis
//! placement of the child (`transform_item_1`, in `rep_1`) onto one of the parent (`transform_item_2`, in
//! `rep_2`): x ↦ A₂ A₁⁻¹ x. A `MAPPED_ITEM` places a representation (through its `REPRESENTATION_MAP`'s
//! origin) at a target placement in the representation that holds the item. Relationships without a
//! transformation (a part's shape representation and its B-rep) share coordinates. A representation used
//! twice in an assembly has two placements: its B-splines are read once per placement.

use std::collections::{HashMap, HashSet};

use glam::{DAffine3, DMat3, DVec3};

use super::parse::{Exchange, Instance, Param};

/// The most placements one representation may have (an assembly that uses a part more often is read
/// with its first ones, and said so).
const MAX_OCCURRENCES: usize = 4096;
/// The deepest assembly tree followed.
const MAX_LEVELS: usize = 64;

/// The world placements of the file's B-splines.
#[derive(Debug, Default)]
pub(super) struct Placements {
    /// B-spline instance → its placements; absent: in the file's coordinates as written.
    of: HashMap<u64, Vec<DAffine3>>,
    /// Representations placed by a transformation (for the notice).
    pub(super) placed: usize,
    /// Occurrences dropped at [`MAX_OCCURRENCES`].
    pub(super) dropped: usize,
}

impl Placements {
    /// What the reader says of the placements: none for a file without an assembly.
    pub(super) fn notice(&self) -> Option<String> {
        let dropped = if self.dropped > 0 {
            format!(
                " ({} occurrences beyond {MAX_OCCURRENCES} of one part not read)",
                self.dropped
            )
        } else {
            String::new()
        };
        (self.placed > 0).then(|| {
            format!(
                "assembly placements applied: {} representations placed in their parents{dropped}",
                self.placed
            )
        })
    }

    /// The placements of the B-spline `#id`: one identity where the file places it nowhere else.
    pub(super) fn of(&self, id: u64) -> &[DAffine3] {
        self.of.get(&id).map_or(&[DAffine3::IDENTITY], Vec::as_slice)
    }
}

/// A representation: an instance with a record `…REPRESENTATION(name, (items), context)` other than a
/// parameter space's (`DEFINITIONAL_REPRESENTATION`).
fn representation_items(inst: &Instance) -> Option<Vec<u64>> {
    let r = inst
        .records
        .iter()
        .find(|r| r.name.ends_with("REPRESENTATION") && r.name != "DEFINITIONAL_REPRESENTATION")?;
    Some(refs(r.params.get(1)?))
}

fn refs(p: &Param) -> Vec<u64> {
    match p {
        Param::Ref(id) => vec![*id],
        Param::List(v) => v.iter().flat_map(refs).collect(),
        Param::Typed(_, p) => refs(p),
        _ => vec![],
    }
}

fn ref_at(inst: &Instance, record: &str, k: usize) -> Option<u64> {
    match inst.record(record)?.params.get(k)? {
        Param::Ref(id) => Some(*id),
        _ => None,
    }
}

/// A direction or point's three coordinates (`DIRECTION`'s ratios, `CARTESIAN_POINT`'s coordinates).
fn coords(ex: &Exchange, id: u64, record: &str) -> Option<DVec3> {
    let v: Vec<f64> = ex
        .get(id)?
        .record(record)?
        .params
        .get(1)?
        .list()?
        .iter()
        .map(Param::real)
        .collect::<Option<_>>()?;
    match v.as_slice() {
        [x, y, z] => Some(DVec3::new(*x, *y, *z)),
        [x, y] => Some(DVec3::new(*x, *y, 0.0)),
        _ => None,
    }
    .filter(|v| v.is_finite())
}

/// The frame of an `AXIS2_PLACEMENT_3D` (location, axis z, reference direction x; defaults z = (0,0,1),
/// x = (1,0,0), x made orthogonal to z): local coordinates to its representation's.
fn axis_placement(ex: &Exchange, id: u64) -> Option<DAffine3> {
    let inst = ex.get(id)?;
    let r = inst.record("AXIS2_PLACEMENT_3D")?;
    let at = |k: usize| match r.params.get(k) {
        Some(Param::Ref(id)) => Some(*id),
        _ => None,
    };
    let origin = coords(ex, at(1)?, "CARTESIAN_POINT")?;
    let z = at(2)
        .map_or(Some(DVec3::Z), |d| coords(ex, d, "DIRECTION"))?
        .try_normalize()?;
    let x0 = at(3).map_or(Some(DVec3::X), |d| coords(ex, d, "DIRECTION"))?;
    let x = (x0 - z * x0.dot(z))
        .try_normalize()
        .unwrap_or_else(|| z.any_orthonormal_vector());
    Some(DAffine3::from_mat3_translation(
        DMat3::from_cols(x, z.cross(x), z),
        origin,
    ))
}

/// `A₂ A₁⁻¹` of two axis placements.
fn mapping(ex: &Exchange, from: u64, to: u64) -> Option<DAffine3> {
    Some(axis_placement(ex, to)? * axis_placement(ex, from)?.inverse())
}

/// Groups of representations sharing coordinates (union–find over relationships without a
/// transformation).
struct Groups(HashMap<u64, u64>);

impl Groups {
    fn root(&self, mut r: u64) -> u64 {
        while let Some(&p) = self.0.get(&r) {
            if p == r {
                break;
            }
            r = p;
        }
        r
    }

    fn join(&mut self, a: u64, b: u64) {
        let (ra, rb) = (self.root(a), self.root(b));
        if ra != rb {
            self.0.insert(ra, rb);
        }
    }
}

/// The placements of every B-spline in `ex` (`is_bspline` tells them).
pub(super) fn placements(ex: &Exchange, is_bspline: impl Fn(&Instance) -> bool) -> Placements {
    let reps: HashMap<u64, Vec<u64>> = ex
        .instances
        .iter()
        .filter_map(|i| Some((i.id, representation_items(i)?)))
        .collect();
    let mut groups = Groups(HashMap::new());
    // (child, parent, transformation) between representations
    let mut edges: Vec<(u64, u64, DAffine3)> = vec![];
    for inst in &ex.instances {
        let (Some(a), Some(b)) = (
            ref_at(inst, "REPRESENTATION_RELATIONSHIP", 2),
            ref_at(inst, "REPRESENTATION_RELATIONSHIP", 3),
        ) else {
            continue;
        };
        if !(reps.contains_key(&a) && reps.contains_key(&b)) {
            continue;
        }
        let op = ref_at(inst, "REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION", 0).and_then(|t| ex.get(t));
        match op.and_then(|t| t.record("ITEM_DEFINED_TRANSFORMATION")) {
            Some(t) => {
                let item = |k: usize| match t.params.get(k) {
                    Some(Param::Ref(id)) => Some(*id),
                    _ => None,
                };
                if let Some(m) = item(2).zip(item(3)).and_then(|(i1, i2)| mapping(ex, i1, i2)) {
                    edges.push((a, b, m));
                }
            }
            None if op.is_none() => groups.join(a, b),
            None => {} // a transformation Fairway does not read (e.g. a cartesian operator): left as written
        }
    }
    // mapped items: the mapped representation placed in the representation that holds the item
    for (&rep, items) in &reps {
        for inst in items.iter().filter_map(|&i| ex.get(i)) {
            let Some(map) = ref_at(inst, "MAPPED_ITEM", 1).and_then(|m| ex.get(m)) else {
                continue;
            };
            let (Some(origin), Some(mapped), Some(target)) = (
                ref_at(map, "REPRESENTATION_MAP", 0),
                ref_at(map, "REPRESENTATION_MAP", 1),
                ref_at(inst, "MAPPED_ITEM", 2),
            ) else {
                continue;
            };
            if let Some(m) = mapping(ex, origin, target).filter(|_| reps.contains_key(&mapped)) {
                edges.push((mapped, rep, m));
            }
        }
    }
    let mut out = Placements::default();
    if edges.is_empty() {
        return out;
    }
    // the edges between groups, child group → (parent group, transformation)
    let mut up: HashMap<u64, Vec<(u64, DAffine3)>> = HashMap::new();
    for (a, b, m) in edges {
        up.entry(groups.root(a)).or_default().push((groups.root(b), m));
    }
    out.placed = up.len();
    let mut world: HashMap<u64, Vec<DAffine3>> = HashMap::new();
    let group_ids: HashSet<u64> = reps.keys().map(|&r| groups.root(r)).collect();
    for &g in &group_ids {
        world_of(g, &up, &mut world, 0, &mut out.dropped);
    }
    // each B-spline reached from a representation's items gets its group's placements
    for (&rep, items) in &reps {
        let Some(w) = world
            .get(&groups.root(rep))
            .filter(|w| !(w.len() == 1 && w[0] == DAffine3::IDENTITY))
        else {
            continue;
        };
        for id in reachable(ex, items, &reps) {
            if ex.get(id).is_some_and(&is_bspline) {
                out.of.entry(id).or_default().extend_from_slice(w);
            }
        }
    }
    out
}

/// The world placements of the group `g`: identity for a root, otherwise each parent's placements after
/// the transformation into it (memoized in `world`; a cycle or a tree deeper than [`MAX_LEVELS`] ends as
/// a root).
fn world_of(
    g: u64,
    up: &HashMap<u64, Vec<(u64, DAffine3)>>,
    world: &mut HashMap<u64, Vec<DAffine3>>,
    level: usize,
    dropped: &mut usize,
) -> Vec<DAffine3> {
    if let Some(w) = world.get(&g) {
        return w.clone();
    }
    let Some(parents) = up.get(&g).filter(|_| level < MAX_LEVELS) else {
        world.insert(g, vec![DAffine3::IDENTITY]);
        return vec![DAffine3::IDENTITY];
    };
    world.insert(g, vec![DAffine3::IDENTITY]); // a cycle back to g ends here
    let mut w = vec![];
    for &(p, m) in parents {
        for pw in world_of(p, up, world, level + 1, dropped) {
            if w.len() == MAX_OCCURRENCES {
                *dropped += 1;
                continue;
            }
            w.push(pw * m);
        }
    }
    world.insert(g, w.clone());
    w
}

/// Every instance reached from `items` through references, not entering other representations (nor a
/// mapped item's map).
fn reachable(ex: &Exchange, items: &[u64], reps: &HashMap<u64, Vec<u64>>) -> HashSet<u64> {
    let mut seen: HashSet<u64> = HashSet::new();
    let mut stack: Vec<u64> = items.to_vec();
    while let Some(id) = stack.pop() {
        if reps.contains_key(&id) || !seen.insert(id) {
            continue;
        }
        let Some(inst) = ex.get(id) else { continue };
        if inst.record("MAPPED_ITEM").is_some() {
            continue;
        }
        stack.extend(inst.records.iter().flat_map(|r| r.params.iter().flat_map(refs)));
    }
    seen
}
