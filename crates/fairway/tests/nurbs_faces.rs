//! NURBS faces whose non-rational stand-in cannot be faired without adding isocurve curvature extrema:
//! faired on their own knots and weights instead (`fair/surface/own_weights.rs`), on a real face of the
//! corpus (`tests/data/corpus/impeller.igs`, a blade face the stand-in route refused before).

use fairway::fair::{SurfaceFairingOptions, fair_surface};
use fairway::measure_surface::{deviation, iso_stats};
use fairway::{BSplineCurve, BSplineSurface, Geometry};

/// Object `k` of the corpus file `name`, a surface.
fn corpus_surface(name: &str, k: usize) -> BSplineSurface {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/corpus")
        .join(name);
    let f = fairway::io::iges::read_all(&std::fs::read(&path).unwrap()).unwrap();
    match &f.objects[k] {
        Geometry::Surface(s) => s.clone(),
        _ => panic!("{name} object {k} is not a surface"),
    }
}

/// The face keeps its degrees, knots and weights (the result is rational, on the face's own space), moves
/// (by more than a hundredth of the band), stays within the band — the sound bound, and an independent
/// dense parametric check and projection below it — and has no more isocurve curvature extrema and less
/// isocurve curvature variation than it had; the note says which route was taken and why.
#[test]
fn rational_faces_whose_stand_in_gains_extrema_are_faired_on_their_own_knots_and_weights() {
    let s = corpus_surface("impeller.igs", 738);
    assert!(!s.is_polynomial(), "a NURBS face with unequal weights");
    let (lo, hi) = s.control_bounds();
    let m = 5e-4 * (hi - lo).length();
    let r = fair_surface(&s, SurfaceFairingOptions::default().tolerance(m)).unwrap();
    assert!(
        r.notes[0].starts_with("rational surface (unequal weights): faired on its own knots and weights")
            && r.notes[0].contains("stand-in's fair added isocurve curvature extrema"),
        "{:?}",
        r.notes
    );
    let f = &r.surface;
    assert_eq!((f.degree_u(), f.degree_v()), (s.degree_u(), s.degree_v()));
    assert_eq!((f.knots_u(), f.knots_v()), (s.knots_u(), s.knots_v()));
    assert_eq!(f.weights(), s.weights());
    // the band: the sound bound, above the dense parametric difference and the projected deviation
    let bound = r.band_bound.expect("a bound on the face's own knots and weights");
    assert!(bound <= m, "bound {bound} > m {m}");
    assert_eq!(r.max_deviation, bound);
    let ((u0, u1), (v0, v1)) = s.domain();
    let n = 200;
    let dense = (0..=n)
        .flat_map(|i| (0..=n).map(move |j| (i as f64 / n as f64, j as f64 / n as f64)))
        .map(|(a, b)| (u0 + a * (u1 - u0), v0 + b * (v1 - v0)))
        .map(|(u, v)| f.point(u, v).distance(s.point(u, v)))
        .fold(0.0f64, f64::max);
    assert!(
        dense <= bound && dense > 0.01 * m,
        "dense {dense}, bound {bound}, m {m}"
    );
    let (projected, _) = deviation(&s, f, 61);
    assert!(projected <= bound, "projected {projected} > bound {bound}");
    // fairer: no more extrema (the reference's 1 % hysteresis), less curvature variation
    let delta = 0.01 * iso_stats(&s, 16, 0.0).max_abs_kappa;
    let (before, after) = (iso_stats(&s, 16, delta), iso_stats(f, 16, delta));
    assert!(
        after.extrema_u + after.extrema_v <= before.extrema_u + before.extrema_v,
        "extrema {} -> {}",
        before.extrema_u + before.extrema_v,
        after.extrema_u + after.extrema_v
    );
    let (e0, e1) = (before.e_var_u + before.e_var_v, after.e_var_u + after.e_var_v);
    assert!(e1 < e0, "isocurve curvature variation {e0} -> {e1}");
}

/// `s` with the u-knot `u` inserted until its multiplicity is the degree (a C0 knot line, the joint of two
/// Bézier strips as CATIA writes them): column by column, each a rational curve (Boehm), so the geometry
/// is the same surface exactly.
fn with_c0_line_in_u(s: &BSplineSurface, u: f64) -> BSplineSurface {
    let (nu, nv, p) = (s.nu(), s.nv(), s.degree_u());
    let ones = vec![1.0; nu * nv];
    let w = s.weights().unwrap_or(&ones);
    let times = p - s.knots_u().multiplicity(u);
    let cols: Vec<BSplineCurve> = (0..nv)
        .map(|j| {
            let pts = (0..nu).map(|i| s.points()[i * nv + j]).collect();
            let ws = (0..nu).map(|i| w[i * nv + j]).collect();
            let c = BSplineCurve::try_new(p, s.knots_u().values().to_vec(), pts, Some(ws), 3).unwrap();
            c.insert_knot(u, times).unwrap()
        })
        .collect();
    let nu2 = cols[0].n_points();
    let (mut pts, mut ws) = (vec![], vec![]);
    for i in 0..nu2 {
        for c in &cols {
            pts.push(c.points()[i]);
            ws.push(c.weights().unwrap()[i]);
        }
    }
    BSplineSurface::try_new(
        p,
        s.degree_v(),
        cols[0].knots().values().to_vec(),
        s.knots_v().values().to_vec(),
        nu2,
        nv,
        pts,
        Some(ws),
    )
    .unwrap()
}

/// Issue 29: a NURBS face with an interior knot line of multiplicity = degree (C0 in the parameter) whose
/// stand-in's fair adds extrema fairs on its own knots and weights tile by tile (it was refused: "its region
/// crosses C0 knot lines"). The band is held against the rational original by an independent dense
/// closest-point check, the C0 line is kept (its knot multiplicity, the control rows on it and on each side
/// of it bit for bit, so the surface along it and its cross derivatives on both sides are unchanged), and the
/// face has no more isocurve curvature extrema than it had; the notes say which route was taken.
#[test]
fn rational_faces_with_c0_knot_lines_fair_on_their_own_knots_tile_by_tile() {
    let s0 = corpus_surface("impeller.igs", 738);
    let ((u0, u1), _) = s0.domain();
    let bps = s0.knots_u().breakpoints();
    // a line half way through the middle span: not a knot yet
    let mid = bps.len() / 2;
    let line = 0.5 * (bps[mid - 1] + bps[mid]);
    let s = with_c0_line_in_u(&s0, line);
    let p = s.degree_u();
    assert_eq!(s.knots_u().multiplicity(line), p);
    for k in 0..=50 {
        let (u, v) = (u0 + (u1 - u0) * k as f64 / 50.0, 0.37);
        assert!(s.point(u, v).distance(s0.point(u, v)) < 1e-9);
    }
    let (lo, hi) = s.control_bounds();
    let m = 5e-4 * (hi - lo).length();
    let r = fair_surface(&s, SurfaceFairingOptions::default().tolerance(m)).unwrap();
    let notes = r.notes.join(" | ");
    assert!(
        notes.contains("faired on its own knots and weights") && notes.contains("tile by tile"),
        "{notes}"
    );
    let f = &r.surface;
    assert_eq!((f.knots_u(), f.knots_v()), (s.knots_u(), s.knots_v()));
    assert_eq!(f.weights(), s.weights());
    assert!(f.points() != s.points(), "the face moved");
    // the C0 line: the joint row (the first row whose support starts at the line, less one) and one row on
    // each side held
    let nv = s.nv();
    let first = s.knots_u().values().iter().position(|&t| t == line).unwrap();
    for i in first - 2..=first {
        assert_eq!(
            &f.points()[i * nv..(i + 1) * nv],
            &s.points()[i * nv..(i + 1) * nv],
            "control row {i} next to the C0 line moved"
        );
    }
    // the band against the rational original: the sound bound, and an independent dense projection of
    // the faired surface's points onto the original (Newton from the nearest of a dense grid)
    let bound = r.band_bound.expect("a sound bound");
    assert!(bound <= m, "bound {bound} > m {m}");
    for (from, onto) in [(f, &s), (&s, f)] {
        let (projected, _) = deviation(from, onto, 81);
        assert!(projected <= bound, "projected {projected} > bound {bound}");
    }
    let ((a0, a1), (b0, b1)) = s.domain();
    let n = 160;
    let dense = (0..=n)
        .flat_map(|i| (0..=n).map(move |j| (i as f64 / n as f64, j as f64 / n as f64)))
        .map(|(a, b)| (a0 + a * (a1 - a0), b0 + b * (b1 - b0)))
        .map(|(u, v)| f.point(u, v).distance(s.point(u, v)))
        .fold(0.0f64, f64::max);
    assert!(
        dense <= bound && dense > 0.01 * m,
        "dense {dense}, bound {bound}, m {m}"
    );
    eprintln!("C0 NURBS face: m {m:.4e}, bound {bound:.4e}, dense {dense:.4e}; {notes}");
    let delta = 0.01 * iso_stats(&s, 16, 0.0).max_abs_kappa;
    let (before, after) = (iso_stats(&s, 16, delta), iso_stats(f, 16, delta));
    assert!(
        after.extrema_u + after.extrema_v <= before.extrema_u + before.extrema_v,
        "extrema {} -> {}",
        before.extrema_u + before.extrema_v,
        after.extrema_u + after.extrema_v
    );
}
