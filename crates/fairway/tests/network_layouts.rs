//! Patch layouts that are neither strips nor full grids (issue 30, item 4): an L of three patches and a T
//! of four, cut from one noisy surface at interior knots (every shared edge exactly G2, or G1 where a
//! patch's control row next to it is lifted), faired together as one surface (the layout route) → every
//! shared edge keeps its continuity (normal angle ≤ 0.01°, G2 where it was), every patch stays in its
//! band (dense closest points both ways), its isocurve extrema go down, and in all fewer than with the
//! patches faired one by one with their edges held.

use fairway::fair::network::{NetworkOptions, Route, fair_network};
use fairway::measure_surface::surface_measures;
use fairway::network::{Continuity, find_joins};
use fairway::{BSplineSurface, Geometry};

mod common;
use common::patches::*;

const M: f64 = 4e-3;

/// The bundled surface cut into 2 × 2 and 2 × 3 grids of patches.
fn two_by_two() -> Vec<Vec<BSplineSurface>> {
    let s = bumpy();
    cut(&s, &[knot(s.knots_u().values(), 9)], &[knot(s.knots_v().values(), 7)])
}

fn two_by_three() -> Vec<Vec<BSplineSurface>> {
    let s = bumpy();
    let (ku, kv) = (s.knots_u().values(), s.knots_v().values());
    cut(&s, &[knot(ku, 8)], &[knot(kv, 4), knot(kv, 9)])
}

/// The classes of the shared edges of `patches`, counted: (G1, G2).
fn classes(patches: &[BSplineSurface]) -> (usize, usize) {
    let objects: Vec<Geometry> = patches.iter().cloned().map(Into::into).collect();
    let j = find_joins(&objects);
    let n = |c| j.surfaces.iter().filter(|x| x.continuity.class == c).count();
    (n(Continuity::G1), n(Continuity::G2))
}

/// Every patch took the layout route, and its notes say so.
fn assert_layout_route(name: &str, r: &Outcome, frame: &str) {
    for (i, o) in r.together.outcome.iter().enumerate() {
        assert_eq!(o.route, Route::Layout, "{name}: patch {i}: {:?}", o.notes);
        assert!(
            o.notes.iter().any(|n| n.contains(frame)),
            "{name}: patch {i}: {:?}",
            o.notes
        );
    }
    assert!(
        r.together.notes.iter().all(|n| n.contains("concatenated")),
        "{:?}",
        r.together.notes
    );
    // one by one: each patch alone, or left as it was where its held edges leave it too few spans
    assert!(
        r.held
            .outcome
            .iter()
            .all(|o| matches!(o.route, Route::Alone | Route::NotFaired)),
        "{:?}",
        r.held.outcome
    );
}

#[test]
fn an_l_of_three_patches_cut_from_one_noisy_surface_is_faired_as_one() {
    let g = two_by_two();
    let patches = vec![g[0][0].clone(), g[0][1].clone(), g[1][0].clone()];
    // FAIRWAY_WRITE_L=path: also write the L there as a document (for the screenshot in the README)
    if let Some(out) = std::env::var_os("FAIRWAY_WRITE_L") {
        let scene = fairway::io::Scene {
            objects: patches
                .iter()
                .zip(["CORNER", "EAST", "NORTH"])
                .map(|(p, n)| fairway::io::SceneObject {
                    name: n.into(),
                    geometry: p.clone().into(),
                    settings: Default::default(),
                    trim: None,
                })
                .collect(),
            ..Default::default()
        };
        fairway::io::save_scene(std::path::Path::new(&out), &scene).unwrap();
    }
    assert_eq!(classes(&patches), (0, 2));
    let r = check_with("L", &patches, 2, M, false);
    assert_layout_route(
        "L",
        &r,
        "a layout of 3 patches (neither a strip nor a full grid) in a 2 × 2 frame",
    );
}

#[test]
fn an_l_with_a_g1_edge_keeps_it_g1_and_its_g2_edge_g2() {
    let g = two_by_two();
    // the third patch's control row next to its edge with the first lifted: that edge G1, the other G2;
    // the third patch turned (transposed) and the list shuffled
    let patches = vec![lift(&g[1][0]).transposed(), g[0][0].clone(), reverse_u(&g[0][1])];
    assert_eq!(classes(&patches), (1, 1));
    let r = check_with("L, one edge G1", &patches, 2, M, false);
    assert_layout_route("L, one edge G1", &r, "2 × 2 frame");
}

#[test]
fn a_t_of_four_patches_is_faired_as_one() {
    let g = two_by_three();
    let patches = vec![g[0][0].clone(), g[0][1].clone(), g[0][2].clone(), g[1][1].clone()];
    assert_eq!(classes(&patches), (0, 3));
    let r = check_with("T", &patches, 3, M, false);
    assert_layout_route(
        "T",
        &r,
        "a layout of 4 patches (neither a strip nor a full grid) in a 2 × 3 frame",
    );
}

#[test]
fn a_t_with_a_g1_stem_keeps_it_g1_and_the_bar_g2() {
    let g = two_by_three();
    let patches = vec![
        lift(&g[1][1]),
        g[0][2].transposed(),
        g[0][0].clone(),
        reverse_u(&g[0][1]),
    ];
    assert_eq!(classes(&patches), (1, 2));
    let r = check_with("T, G1 stem", &patches, 3, M, false);
    assert_layout_route("T, G1 stem", &r, "2 × 3 frame");
}

#[test]
fn a_layout_whose_held_edge_is_on_the_frame_holds_the_span_there() {
    // an L (the first three) next to a fourth patch that is not faired: the L's edge with it lies on its
    // frame's east side, whose span is held; the fourth patch stays bit for bit, its edge keeps G2
    let g = two_by_three();
    let patches = [g[0][0].clone(), g[0][1].clone(), g[1][0].clone(), g[0][2].clone()];
    let objects: Vec<Geometry> = patches.iter().cloned().map(Into::into).collect();
    let mut o = NetworkOptions::default();
    o.surface.tolerance = M;
    let r = fair_network(&objects, &[0, 1, 2], &o).unwrap();
    assert_eq!(r.objects[3], objects[3]);
    for (i, x) in r.outcome[..3].iter().enumerate() {
        assert_eq!(x.route, Route::Layout, "patch {i}: {:?} {:?}", x.notes, r.notes);
        assert!(
            x.notes.iter().any(|n| n.contains("boundary span held on its [E]")),
            "{:?}",
            x.notes
        );
    }
    assert_eq!(r.outcome[3].route, Route::NotFaired);
    for (b, a) in r.joins_before.surfaces.iter().zip(&r.joins_after.surfaces) {
        eprintln!("edge {:?}–{:?}: {:?} → {:?}", b.a, b.b, b.continuity, a.continuity);
        assert!(a.continuity.normal_angle.to_degrees() <= 0.01 && a.continuity.gap <= 1e-9);
        assert_eq!(a.continuity.class, b.continuity.class);
    }
    for (p, f) in patches.iter().zip(&r.objects) {
        let mt = surface_measures(p, f.as_surface().unwrap());
        assert!(mt.hausdorff <= M, "{}", mt.hausdorff);
    }
}

#[test]
fn a_grid_or_a_strip_next_to_patches_not_faired_keeps_its_held_edges() {
    // a 2 × 3 grid of which a 2 × 2 grid or a strip of two is faired: the grid and strip routes fair
    // their whole joined surface (before, the edges with the patches not faired came out G0, at 1.5° to
    // 4°); laid on a frame whose spans along the held edges are held, every edge stays G2
    let g = two_by_three();
    let patches = [
        g[0][0].clone(),
        g[0][1].clone(),
        g[1][0].clone(),
        g[1][1].clone(),
        g[0][2].clone(),
        g[1][2].clone(),
    ];
    let objects: Vec<Geometry> = patches.iter().cloned().map(Into::into).collect();
    let mut o = NetworkOptions::default();
    o.surface.tolerance = M;
    for chosen in [vec![0, 1, 2, 3], vec![0, 1]] {
        let r = fair_network(&objects, &chosen, &o).unwrap();
        for (b, a) in r.joins_before.surfaces.iter().zip(&r.joins_after.surfaces) {
            let (b, a) = (b.continuity, a.continuity);
            assert_eq!(a.class, Continuity::G2, "{chosen:?}: {b:?} → {a:?}");
            assert!(
                a.normal_angle.to_degrees() <= 0.01 && a.gap <= 1e-9,
                "{chosen:?}: {a:?}"
            );
        }
        for (i, (p, f)) in patches.iter().zip(&r.objects).enumerate() {
            if !chosen.contains(&i) {
                assert_eq!(&objects[i], f, "{chosen:?}: patch {i} not faired stays bit for bit");
                continue;
            }
            assert_eq!(
                r.outcome[i].route,
                Route::Layout,
                "{chosen:?}: {:?}",
                r.outcome[i].notes
            );
            let (m0, mt) = (surface_measures(p, p), surface_measures(p, f.as_surface().unwrap()));
            eprintln!(
                "{chosen:?}: patch {i}: isocurve extrema {} → {}, deviation {:.2e}",
                m0.n_curv_extrema, mt.n_curv_extrema, mt.hausdorff
            );
            assert!(
                mt.hausdorff <= M && mt.n_curv_extrema < m0.n_curv_extrema,
                "{chosen:?}: patch {i}"
            );
        }
    }
}

#[test]
fn a_plus_of_five_and_a_row_of_three_with_one_on_its_end_are_faired_as_one() {
    let s = bumpy();
    let (ku, kv) = (s.knots_u().values(), s.knots_v().values());
    let g = cut(&s, &[knot(ku, 6), knot(ku, 12)], &[knot(kv, 4), knot(kv, 9)]);
    let pick =
        |cells: &[(usize, usize)]| -> Vec<BSplineSurface> { cells.iter().map(|&(r, c)| g[r][c].clone()).collect() };
    let plus = pick(&[(1, 1), (0, 1), (2, 1), (1, 0), (1, 2)]);
    let r = check_with("+", &plus, 4, M, false);
    assert_layout_route(
        "+",
        &r,
        "a layout of 5 patches (neither a strip nor a full grid) in a 3 × 3 frame",
    );
    let hook = pick(&[(0, 0), (0, 1), (0, 2), (1, 2)]);
    let r = check_with("row of three and one on its end", &hook, 3, M, false);
    assert_layout_route("row and one", &r, "in a 2 × 3 frame");
}
