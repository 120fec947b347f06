//! Patch layouts faired together (issue 30, item 4): grids of 2 × 2 and larger cut from one noisy surface
//! at interior knots, faired as one surface and split back; every shared edge keeps its continuity, each
//! patch its band, and the isocurves lose curvature extrema, more than with the patches faired one by one
//! with their edges held.

use fairway::fair::network::{NetworkFair, NetworkOptions, fair_network};
use fairway::measure_surface::surface_measures;
use fairway::network::{Continuity, find_joins};
use fairway::{BSplineSurface, Geometry};

mod common;
use common::patches::*;

#[test]
fn a_two_by_two_grid_cut_from_one_noisy_surface_is_faired_as_one() {
    let s = bumpy();
    let g = cut(&s, &[knot(s.knots_u().values(), 9)], &[knot(s.knots_v().values(), 7)]);
    let patches: Vec<BSplineSurface> = g.into_iter().flatten().collect();
    let r = check("2 × 2", &patches, 4, 4e-3);
    assert!(
        r.together.outcome[0].notes.iter().any(|n| n.contains("a 2 × 2 grid")),
        "{:?}",
        r.together.outcome[0].notes
    );
    assert!(
        r.together.notes.iter().all(|n| n.contains("concatenated")),
        "{:?}",
        r.together.notes
    );
    assert!(r.held.notes.iter().all(|n| n.contains("held")), "{:?}", r.held.notes);
}

#[test]
fn a_two_by_three_grid_turned_every_way_and_listed_out_of_order_is_faired_as_one() {
    let s = bumpy();
    let (ku, kv) = (s.knots_u().values(), s.knots_v().values());
    let g = cut(&s, &[knot(ku, 8)], &[knot(kv, 4), knot(kv, 9)]);
    // some patches transposed, some run backwards in u, the list shuffled
    let patches = vec![
        g[1][2].clone(),
        g[0][1].transposed(),
        reverse_u(&g[1][0]),
        g[0][0].clone(),
        reverse_u(&g[0][2]).transposed(),
        g[1][1].clone(),
    ];
    check("2 × 3", &patches, 7, 4e-3);
}

#[test]
fn a_strip_of_three_cut_across_one_direction_is_faired_as_one() {
    let s = bumpy();
    let ku = s.knots_u().values();
    let patches = cut_u(&s, &[knot(ku, 6), knot(ku, 12)]);
    let r = check("3 × 1", &patches, 2, 4e-3);
    assert!(
        r.together.outcome[1].notes.iter().all(|n| !n.contains("grid")),
        "a strip, not a grid"
    );
}

#[test]
fn a_grid_with_a_g1_knot_line_keeps_it_g1_and_the_g2_line_g2() {
    let s = bumpy();
    let g = cut(&s, &[knot(s.knots_u().values(), 9)], &[knot(s.knots_v().values(), 7)]);
    // the second row's patches: their third control row from the shared u edge lifted by a smooth bump
    // that vanishes three columns short of their v sides, so the u line is G1, not G2, and the v line
    // stays G2
    let patches = vec![g[0][0].clone(), g[0][1].clone(), lift(&g[1][0]), lift(&g[1][1])];
    let objects: Vec<Geometry> = patches.iter().cloned().map(Into::into).collect();
    let classes: Vec<Continuity> = find_joins(&objects)
        .surfaces
        .iter()
        .map(|j| j.continuity.class)
        .collect();
    assert_eq!(
        classes.iter().filter(|&&c| c == Continuity::G1).count(),
        2,
        "{classes:?}"
    );
    assert_eq!(
        classes.iter().filter(|&&c| c == Continuity::G2).count(),
        2,
        "{classes:?}"
    );
    check("2 × 2, G1 across u", &patches, 4, 4e-3);
}

#[test]
fn a_grid_with_a_patch_left_out_holds_its_edges_and_says_why() {
    let s = bumpy();
    let g = cut(&s, &[knot(s.knots_u().values(), 9)], &[knot(s.knots_v().values(), 7)]);
    let patches: Vec<BSplineSurface> = g.into_iter().flatten().collect();
    let objects: Vec<Geometry> = patches.iter().cloned().map(Into::into).collect();
    let mut o = NetworkOptions::default();
    o.surface.tolerance = 4e-3;
    // the last patch is not faired: its two edges are held; the other three patches form an L whose held
    // edges face the empty cell of its frame, which the layout route refuses (a note says so): the L's
    // edges go to the strips, which hold them too, each patch faired on its own
    let r = fair_network(&objects, &[0, 1, 2], &o).unwrap();
    assert_eq!(r.objects[3], objects[3]);
    assert!(r.outcome[..3].iter().all(|x| x.faired), "{:?}", r.outcome);
    assert!(
        r.notes.iter().any(|n| n.contains("a patch not being faired shares it")),
        "{:?}",
        r.notes
    );
    assert!(
        r.notes
            .iter()
            .any(|n| n.contains("faces a cell inside the layout's frame")),
        "{:?}",
        r.notes
    );
    for (b, a) in find_joins(&objects).surfaces.iter().zip(&r.joins_after.surfaces) {
        eprintln!("held edge: {:?} → {:?}", b.continuity, a.continuity);
        assert!(a.continuity.normal_angle.to_degrees() <= 0.01 && a.continuity.gap <= 1e-9);
    }
}

#[test]
fn a_grid_whose_knot_line_mixes_g2_and_g1_holds_that_line_and_fairs_each_side_together() {
    // the u line G1 along one edge (the third patch's control row next to it lifted) and G2 along the
    // other: a knot line of one surface has one continuity, so that line's edges are held and the two
    // rows faired each as one strip with their spans along the line held; before, the whole grid was held
    let s = bumpy();
    let g = cut(&s, &[knot(s.knots_u().values(), 9)], &[knot(s.knots_v().values(), 7)]);
    let patches = [g[0][0].clone(), g[0][1].clone(), lift(&g[1][0]), g[1][1].clone()];
    let objects: Vec<Geometry> = patches.iter().cloned().map(Into::into).collect();
    let joins = find_joins(&objects);
    let classes: Vec<Continuity> = joins.surfaces.iter().map(|j| j.continuity.class).collect();
    assert_eq!(
        classes.iter().filter(|&&c| c == Continuity::G1).count(),
        1,
        "{classes:?}"
    );
    let mut o = NetworkOptions::default();
    o.surface.tolerance = 4e-3;
    let r = fair_network(&objects, &[], &o).unwrap();
    assert!(
        r.notes
            .iter()
            .any(|n| n.contains("G2 along one edge and only G1 along another")),
        "{:?}",
        r.notes
    );
    for (i, x) in r.outcome.iter().enumerate() {
        assert_eq!(x.group.len(), 2, "patch {i}: faired with its row: {:?}", x.notes);
    }
    against_one_by_one("mixed", &patches, &r, o);
    for (b, a) in joins.surfaces.iter().zip(&r.joins_after.surfaces) {
        assert_eq!(a.continuity.class, b.continuity.class, "{a:?}");
        assert!(a.continuity.normal_angle.to_degrees() <= 0.01 && a.continuity.gap <= 1e-9);
    }
}

#[test]
fn a_grid_line_g2_along_one_edge_and_a_crease_along_the_other_holds_that_line_and_fairs_each_side() {
    // the v line between the columns: G2 along row 0's edge, a crease (G0, not concatenable, held) along
    // row 1's (the fourth patch's second control column from it lifted); a knot line cannot be joined
    // along one edge and held along another, so the G2 edge on it is held too and each column faired as
    // one, keeping every edge's class (before, the held edge faced a cell inside the grid's frame, the
    // layout route stopped, and every edge was held: each patch faired alone)
    let s = bumpy();
    let g = cut(&s, &[knot(s.knots_u().values(), 9)], &[knot(s.knots_v().values(), 7)]);
    let patches = [g[0][0].clone(), g[0][1].clone(), g[1][0].clone(), crease(&g[1][1])];
    let objects: Vec<Geometry> = patches.iter().cloned().map(Into::into).collect();
    let joins = find_joins(&objects);
    let classes: Vec<Continuity> = joins.surfaces.iter().map(|j| j.continuity.class).collect();
    assert_eq!(
        classes.iter().filter(|&&c| c == Continuity::G0).count(),
        1,
        "{classes:?}"
    );
    assert_eq!(
        classes.iter().filter(|&&c| c == Continuity::G2).count(),
        3,
        "{classes:?}"
    );
    let mut o = NetworkOptions::default();
    o.surface.tolerance = 4e-3;
    let r = fair_network(&objects, &[], &o).unwrap();
    for n in &r.notes {
        eprintln!("note: {n}");
    }
    assert!(r.notes.iter().any(|n| n.contains("a crease, kept")), "{:?}", r.notes);
    assert!(
        r.notes
            .iter()
            .any(|n| n.contains("held too, the patches on each side faired together")),
        "{:?}",
        r.notes
    );
    for (i, x) in r.outcome.iter().enumerate() {
        // each faired with its column: objects 0 and 2, 1 and 3
        assert_eq!(x.group, vec![i % 2, i % 2 + 2], "patch {i}: {:?}", x.notes);
        assert!(x.faired && x.max_deviation <= 4e-3, "patch {i}: {x:?}");
    }
    against_one_by_one("G2/crease line", &patches, &r, o);
    for (b, a) in joins.surfaces.iter().zip(&r.joins_after.surfaces) {
        eprintln!("edge {:?}–{:?}: {:?} → {:?}", b.a, b.b, b.continuity, a.continuity);
        assert_eq!(a.continuity.class, b.continuity.class, "{a:?}");
        assert!(a.continuity.gap <= 1e-9, "{a:?}");
        if b.continuity.class == Continuity::G0 {
            // the crease kept: its angle along the edge as it was
            let d = (a.continuity.normal_angle - b.continuity.normal_angle).abs();
            assert!(d <= 1e-9, "crease angle changed by {d:e}");
        } else {
            assert!(a.continuity.normal_angle.to_degrees() <= 0.01, "{a:?}");
        }
    }
}

/// Every patch of `r` (the fair of `patches` with options `o`) within the band with fewer isocurve
/// extrema than it had, and fewer in all than the patches faired one by one with their edges held.
fn against_one_by_one(name: &str, patches: &[BSplineSurface], r: &NetworkFair, o: NetworkOptions) {
    let objects: Vec<Geometry> = patches.iter().cloned().map(Into::into).collect();
    let held = fair_network(&objects, &[], &NetworkOptions { hold_all: true, ..o }).unwrap();
    let (mut sum, mut sum_held) = (0, 0);
    for (k, ((p, f), h)) in patches.iter().zip(&r.objects).zip(&held.objects).enumerate() {
        let (m0, mt, mh) = (
            surface_measures(p, p),
            surface_measures(p, f.as_surface().unwrap()),
            surface_measures(p, h.as_surface().unwrap()),
        );
        eprintln!(
            "{name}: patch {k}: isocurve extrema {} → {} ({} one by one), deviation {:.2e}",
            m0.n_curv_extrema, mt.n_curv_extrema, mh.n_curv_extrema, mt.hausdorff
        );
        assert!(
            mt.hausdorff <= o.surface.tolerance && mt.n_curv_extrema < m0.n_curv_extrema,
            "{name}: patch {k}"
        );
        (sum, sum_held) = (sum + mt.n_curv_extrema, sum_held + mh.n_curv_extrema);
    }
    eprintln!("{name}: isocurve extrema in all: {sum} vs {sum_held} one by one");
    assert!(sum < sum_held, "{name}");
}
