//! Surfaces with C0 knot lines (interior knots of multiplicity p: chains of Bézier patches, as CATIA
//! writes them): every one fairs, the lines keep their continuity (a G1 joint stays G1, a crease keeps
//! its angle), the band holds, and a tile too short to move is held and named.

use fairway::fair::{SurfaceFairingOptions, fair_surface};
use fairway::measure_surface::iso_stats;
use fairway::surface::BSplineSurface;
use glam::DVec3;

/// Knots of a chain of `pieces` Bézier pieces of degree p on [0, 1]: interior knots of multiplicity p.
fn chain(p: usize, pieces: &[f64]) -> (Vec<f64>, usize) {
    let mut k = vec![0.0; p + 1];
    for &t in pieces {
        k.extend(std::iter::repeat_n(t, p));
    }
    k.extend(std::iter::repeat_n(1.0, p + 1));
    let n = k.len() - p - 1;
    (k, n)
}

/// A noisy graph surface of degree p on Bézier-chain knots; with `g1`, each joint row is the mean of its
/// neighbours (G1 across the joint, here even C1), else the joints are creases.
fn noisy_chain(p: usize, cuts_u: &[f64], cuts_v: &[f64], g1: bool) -> BSplineSurface {
    let ((ku, nu), (kv, nv)) = (chain(p, cuts_u), chain(p, cuts_v));
    let mut seed = 7u64;
    let mut rnd = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    };
    let grev = |k: &[f64], i: usize| k[i + 1..i + 1 + p].iter().sum::<f64>() / p as f64;
    let mut pts = vec![];
    for i in 0..nu {
        for j in 0..nv {
            let (x, y) = (grev(&ku, i), grev(&kv, j));
            pts.push(DVec3::new(x, y, 0.2 * (3.0 * x).sin() * (2.0 * y).cos() + 2e-3 * rnd()));
        }
    }
    if g1 {
        for i in (p..nu - 1).step_by(p) {
            for j in 0..nv {
                pts[i * nv + j] = (pts[(i - 1) * nv + j] + pts[(i + 1) * nv + j]) / 2.0;
            }
        }
        for j in (p..nv - 1).step_by(p) {
            for i in 0..nu {
                pts[i * nv + j] = (pts[i * nv + j - 1] + pts[i * nv + j + 1]) / 2.0;
            }
        }
    }
    BSplineSurface::try_new(p, p, ku, kv, nu, nv, pts, None).unwrap()
}

/// The largest angle (degrees) between the normals on the two sides of each line, 101 points along it.
fn normal_jumps(s: &BSplineSurface, lines_u: &[f64], lines_v: &[f64]) -> Vec<f64> {
    let mut out = vec![];
    for &u in lines_u {
        out.push((0..=100).map(|k| k as f64 / 100.0).fold(0.0, |m: f64, v| {
            m.max(s.normal(u - 1e-9, v).angle_between(s.normal(u + 1e-9, v)).to_degrees())
        }));
    }
    for &v in lines_v {
        out.push((0..=100).map(|k| k as f64 / 100.0).fold(0.0, |m: f64, u| {
            m.max(s.normal(u, v - 1e-9).angle_between(s.normal(u, v + 1e-9)).to_degrees())
        }));
    }
    out
}

fn fair(s: &BSplineSurface, m: f64) -> fairway::fair::SurfaceFairingResult {
    fair_surface(s, SurfaceFairingOptions::default().tolerance(m)).unwrap()
}

#[test]
fn quintic_bezier_chains_fair_and_keep_their_joints() {
    let (lu, lv) = ([1.0 / 3.0, 2.0 / 3.0], [0.5]);
    for g1 in [true, false] {
        let s = noisy_chain(5, &lu, &lv, g1);
        let m = 3e-3;
        let r = fair(&s, m);
        let bound = r.band_bound.expect("a sound bound");
        assert!(bound <= m, "g1 {g1}: bound {bound} > m {m}");
        let (before, after) = (normal_jumps(&s, &lu, &lv), normal_jumps(&r.surface, &lu, &lv));
        for (b, a) in before.iter().zip(&after) {
            assert!(
                (a - b).abs() <= 1e-6,
                "g1 {g1}: a joint's normal jump went {b}° -> {a}°"
            );
            if g1 {
                assert!(*b < 1e-6);
            } else {
                assert!(*b > 1.0, "the crease test surface has creases ({b}°)");
            }
        }
        let (sb, sa) = (iso_stats(&s, 20, 0.01), iso_stats(&r.surface, 20, 0.01));
        assert!(
            sa.extrema_u + sa.extrema_v < sb.extrema_u + sb.extrema_v,
            "g1 {g1}: isocurve curvature extrema {} -> {}",
            sb.extrema_u + sb.extrema_v,
            sa.extrema_u + sa.extrema_v
        );
        assert!(
            sa.e_var_u + sa.e_var_v < sb.e_var_u + sb.e_var_v,
            "g1 {g1}: {sb:?} -> {sa:?}"
        );
        assert!(r.notes.iter().any(|n| n.contains("C0 knot lines")), "{:?}", r.notes);
        // the joint rows and their neighbours did not move
        let nv = s.nv();
        for i in [4, 5, 6, 9, 10, 11] {
            for j in 0..nv {
                assert_eq!(s.point_at(i, j), r.surface.point_at(i, j), "row {i}");
            }
        }
    }
}

#[test]
fn a_tile_too_short_to_move_is_held_and_named() {
    // cubic: a C0 line at 0.2 and 0.3 leaves the middle u-stretch one Bézier span (4 rows: the two joint
    // rows and their two neighbours, all held); the others move
    let s = noisy_chain(3, &[0.2, 0.3, 0.6], &[0.5], false);
    let m = 3e-3;
    let r = fair(&s, m);
    assert!(r.band_bound.unwrap() <= m);
    let held = r
        .notes
        .iter()
        .find(|n| n.contains("too short to move"))
        .expect("a held-tile note");
    assert!(held.contains("u ∈ [0.200000, 0.300000]"), "{held}");
    assert_ne!(s.points(), r.surface.points(), "the other tiles moved");
    // the held tile's rows: joint at 0.2 (row 3) .. joint at 0.3 (row 6)
    for i in 3..=6 {
        for j in 0..s.nv() {
            assert_eq!(s.point_at(i, j), r.surface.point_at(i, j), "row {i}");
        }
    }
}

#[test]
fn a_surface_of_single_bezier_tiles_gets_a_clear_refusal() {
    // inside the region every stretch is a single cubic Bézier span: nothing can move without breaking a
    // joint (the outer spans, on the domain boundary, are outside the region)
    let s = noisy_chain(3, &[0.25, 0.5, 0.75], &[0.25, 0.5, 0.75], false);
    let opts = SurfaceFairingOptions::default()
        .tolerance(3e-3)
        .region(Some(((0.25, 0.75), (0.25, 0.75))));
    let e = fair_surface(&s, opts).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("C0 knot lines") && msg.contains("too short to move"),
        "{msg}"
    );
}
