//! NURBS faces whose non-rational stand-in cannot be faired without adding isocurve curvature extrema:
//! faired on their own knots and weights instead (`fair/surface/own_weights.rs`), on a real face of the
//! corpus (`tests/data/corpus/impeller.igs`, a blade face the stand-in route refused before).

use fairway::fair::{SurfaceFairingOptions, fair_surface};
use fairway::measure_surface::{deviation, iso_stats};
use fairway::{BSplineSurface, Geometry};

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
