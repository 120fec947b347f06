//! Rings of patches (issue 30): a layout that closes on itself — four patches around a noisy tube, each
//! sharing an edge with the next and the last with the first, or 2 × 4 around it — is faired as one
//! closed surface, every edge kept, the closing ones too.

use fairway::Geometry;
use fairway::fair::network::{NetworkFair, Route};
use fairway::measure_surface::surface_measures;
use fairway::network::{Continuity, JOIN_TOLERANCE, find_joins};

mod common;
use common::patches::*;

const M: f64 = 4e-3;

#[test]
fn four_patches_around_a_noisy_tube_are_faired_as_one_ring_keeping_the_closing_edge() {
    let patches = noisy_tube(14, 32, 0.003);
    let objects: Vec<Geometry> = patches.iter().cloned().map(Into::into).collect();
    let joins = find_joins(&objects);
    // four G2 edges: 0–1, 1–2, 2–3 and the closing one 3–0
    assert_eq!(joins.surfaces.len(), 4, "{joins:?}");
    assert!(joins.surfaces.iter().all(|j| j.continuity.class == Continuity::G2));
    let closing = joins
        .surfaces
        .iter()
        .position(|j| {
            let mut ab = [j.a.0, j.b.0];
            ab.sort();
            ab == [0, 3]
        })
        .expect("the closing edge");
    let r = check("tube ring", &patches, 4, M);
    let c = r.together.joins_after.surfaces[closing].continuity;
    eprintln!("closing edge after: {c:?}");
    assert_eq!(c.class, Continuity::G2, "{c:?}");
    assert!(
        c.normal_angle.to_degrees() <= 0.01 && c.gap <= 1e-9 * joins.tolerance / JOIN_TOLERANCE,
        "{c:?}"
    );
    assert_ring(&r.together, "a ring of patches");
    // the closing edge was faired across, not held: the patches next to it moved there
    let (f0, f3) = (
        r.together.objects[0].as_surface().unwrap(),
        r.together.objects[3].as_surface().unwrap(),
    );
    let moved = |a: &fairway::BSplineSurface, b: &fairway::BSplineSurface, col: usize| {
        (0..a.nu())
            .map(|i| a.point_at(i, col).distance(b.point_at(i, col)))
            .fold(0.0, f64::max)
    };
    let (m0, m3) = (moved(f0, &patches[0], 1), moved(f3, &patches[3], patches[3].nv() - 2));
    eprintln!("second control column from the closing edge moved by {m0:.2e} (patch 0), {m3:.2e} (patch 3)");
    assert!(m0 > 1e-4 && m3 > 1e-4, "{m0} {m3}");
    for (p, f) in patches.iter().zip(&r.together.objects) {
        assert!(surface_measures(p, f.as_surface().unwrap()).hausdorff <= M);
    }
}

#[test]
fn two_rows_of_four_patches_around_a_noisy_tube_are_faired_as_one_cylinder() {
    // cut across the axis at u = ½ too: 8 patches; 8 edges around (2 of them, one per row, closing the
    // rows) and 4 across the cut, all G2
    let g = noisy_tube_cut(14, 32, 0.003, &[0.5]);
    let patches: Vec<fairway::BSplineSurface> = g.into_iter().flatten().collect();
    let objects: Vec<Geometry> = patches.iter().cloned().map(Into::into).collect();
    let joins = find_joins(&objects);
    assert!(joins.surfaces.iter().all(|j| j.continuity.class == Continuity::G2));
    let r = check("cylinder 2 × 4", &patches, 12, M);
    assert_ring(&r.together, "2 rows of 4 patches around a cylinder");
}

/// Every patch took the ring route, its notes say `what` and no edge was held; each one's own deviation
/// bound printed.
fn assert_ring(r: &NetworkFair, what: &str) {
    for (i, o) in r.outcome.iter().enumerate() {
        assert_eq!(o.route, Route::Ring, "patch {i}: {:?} {:?}", o.notes, r.notes);
        assert!(o.notes.iter().any(|n| n.contains(what)), "patch {i}: {:?}", o.notes);
        assert!(
            !o.notes.iter().any(|n| n.contains("closing edge held")),
            "patch {i}: {:?}",
            o.notes
        );
        eprintln!("patch {i}: own deviation bound {:.3e}", o.max_deviation);
    }
}
