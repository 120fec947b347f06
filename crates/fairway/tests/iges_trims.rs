//! Trimmed faces through IGES (issue 29): a surface with its uv loops written as a trimmed surface (144)
//! whose boundaries (142) carry each loop as its parameter-space curves (exact) and as model-space curves
//! recomputed on the surface as it is now; read back by Fairway's own reader.

use fairway::io::{iges, step};
use fairway::measure_surface::SurfaceProjector;
use fairway::trim::{FaceTrim, TrimLoop, fit_tolerance};
use fairway::{BSplineCurve, BSplineSurface, DVec3, Geometry, KnotVector};

fn corpus(name: &str) -> Vec<u8> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/corpus")
        .join(name);
    std::fs::read(path).unwrap()
}

/// The trimmed faces of the OpenCASCADE corpus file (10 rational B-spline faces, one loop each).
fn occ_faces() -> (Vec<Geometry>, Vec<Option<FaceTrim>>) {
    let f = step::read_all(&corpus("impeller-faces-occ.step")).unwrap();
    (f.objects.iter().zip(&f.trims))
        .filter_map(|(g, t)| Some((g.clone(), Some(t.clone()?))))
        .unzip()
}

/// A noisy bicubic patch on [0, 1]², 7 × 7 control points over 10 × 10 units.
fn patch() -> BSplineSurface {
    let n = 7;
    let k = KnotVector::uniform(3, n).unwrap().values().to_vec();
    let pts = (0..n * n)
        .map(|i| {
            let (x, y) = ((i / n) as f64 * 10.0 / 6.0, (i % n) as f64 * 10.0 / 6.0);
            DVec3::new(
                x,
                y,
                0.8 * (0.4 * x).sin() * (0.3 * y).cos() + 0.01 * ((i * 7919) % 13) as f64,
            )
        })
        .collect();
    BSplineSurface::try_new(3, 3, k.clone(), k, n, n, pts, None).unwrap()
}

/// A closed uv polygon through `corners` (degree-1 edges), and a circle of radius `r` about `c` as two
/// rational quadratic halves (exact arcs), reversed for a hole.
fn polygon(corners: &[(f64, f64)], outer: bool) -> TrimLoop {
    let n = corners.len();
    let edges = (0..n)
        .map(|k| {
            let (a, b) = (corners[k], corners[(k + 1) % n]);
            let pts = vec![DVec3::new(a.0, a.1, 0.0), DVec3::new(b.0, b.1, 0.0)];
            BSplineCurve::try_new(1, vec![0.0, 0.0, 1.0, 1.0], pts, None, 2).unwrap()
        })
        .collect();
    TrimLoop { outer, edges }
}

fn circle(c: (f64, f64), r: f64) -> TrimLoop {
    // a half circle as a rational quadratic with 5 points (two quarter arcs), clockwise (a hole)
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let half = |sign: f64| {
        let pts = [(1.0, 0.0), (1.0, -1.0), (0.0, -1.0), (-1.0, -1.0), (-1.0, 0.0)]
            .iter()
            .map(|&(x, y)| DVec3::new(c.0 + sign * r * x, c.1 + sign * r * y, 0.0))
            .collect();
        BSplineCurve::try_new(
            2,
            vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0],
            pts,
            Some(vec![1.0, w, 1.0, w, 1.0]),
            2,
        )
        .unwrap()
    };
    TrimLoop {
        outer: false,
        edges: vec![half(1.0), half(-1.0)],
    }
}

/// The IGES text as another system would send it: the same entities, but global fields 3, 5 and 12 no
/// longer name Fairway (Hollerith strings of the same length), so the model-space curves are read as
/// the curves they are.
fn as_if_from_elsewhere(text: &str) -> String {
    text.replace("7HFairway", "7HOthers ")
}

/// Every object of `f` that is a curve lies on `s` within `tol` (at 200 parameters each).
fn curves_on(f: &fairway::io::InterchangeFile, s: &BSplineSurface, tol: f64) -> usize {
    let proj = SurfaceProjector::new(s, 4);
    let mut n = 0;
    for c in f.objects.iter().filter_map(Geometry::as_curve) {
        let (a, b) = c.domain();
        for k in 0..=200 {
            let d = proj.project(c.point(a + (b - a) * k as f64 / 200.0)).distance;
            assert!(
                d <= tol,
                "a model-space edge {d:.3e} from the surface (tolerance {tol:.3e})"
            );
        }
        n += 1;
    }
    n
}

/// The OpenCASCADE corpus faces written as IGES and read back by Fairway: the same objects (the edges'
/// curves in space are the trims, not objects), each surface bit for bit, each face's loops equal
/// (exactly: the uv curves are written as they are stored, every real as its shortest round-trip
/// decimal), no notice of anything skipped.
#[test]
fn iges_round_trip_keeps_the_loops_and_the_surfaces_exactly() {
    let (objects, trims) = occ_faces();
    assert_eq!(objects.len(), 10);
    let names: Vec<String> = (1..=10).map(|k| format!("FACE({k})")).collect();
    let text = iges::write_trimmed(&objects, &names, &trims, &Default::default());
    let back = iges::read_all(text.as_bytes()).unwrap();
    assert_eq!(
        back.objects, objects,
        "surfaces bit for bit, no edge curve as an object"
    );
    assert_eq!(back.trims, trims, "loops equal");
    let labels: Vec<&str> = back.entities.iter().map(|e| e.label.as_str()).collect();
    assert_eq!(labels, names);
    assert!(
        !back.notices.iter().any(|n| n.contains("skipped")),
        "{:?}",
        back.notices
    );
    assert!(
        back.notices
            .iter()
            .any(|n| n.starts_with("10 trimmed surfaces (144) read with their boundaries")),
        "{:?}",
        back.notices
    );
}

/// The model-space curves are written on the surface as it is now: a face whose surface was changed
/// (every control point moved) has its edges recomputed on the new surface, within the trim tolerance
/// (10⁻⁶ × the control box's diagonal). Read as another system's file, those curves come back as objects
/// (one per edge), each on the surface, and the face still trimmed from its uv curves.
#[test]
fn iges_model_space_edges_lie_on_the_surface_as_written() {
    let s0 = patch();
    let trim = FaceTrim {
        loops: vec![
            polygon(&[(0.1, 0.1), (0.9, 0.15), (0.85, 0.9), (0.2, 0.8)], true),
            circle((0.5, 0.5), 0.15),
        ],
    };
    // "faired": the same knots, the points moved
    let pts: Vec<DVec3> = s0
        .points()
        .iter()
        .enumerate()
        .map(|(i, q)| *q + DVec3::new(0.0, 0.0, 0.05 * ((i % 5) as f64 - 2.0)))
        .collect();
    let s = BSplineSurface::try_new(
        3,
        3,
        s0.knots_u().values().to_vec(),
        s0.knots_v().values().to_vec(),
        s0.nu(),
        s0.nv(),
        pts,
        None,
    )
    .unwrap();
    let objects = vec![Geometry::Surface(s.clone())];
    let text = iges::write_trimmed(&objects, &[], &[Some(trim.clone())], &Default::default());
    let own = iges::read_all(text.as_bytes()).unwrap();
    assert_eq!(own.objects, objects);
    assert_eq!(own.trims, vec![Some(trim.clone())]);
    let other = iges::read_all(as_if_from_elsewhere(&text).as_bytes()).unwrap();
    assert_eq!(other.objects[0], objects[0]);
    assert_eq!(other.trims[0], Some(trim), "the uv curves still bound the face");
    let edges = curves_on(&other, &s, fit_tolerance(&s));
    assert_eq!(edges, 4 + 2, "one model-space curve per edge");
    // and not on the surface before the change
    let proj = SurfaceProjector::new(&s0, 4);
    let far = other
        .objects
        .iter()
        .filter_map(Geometry::as_curve)
        .map(|c| proj.project(c.point(0.37)).distance)
        .fold(0.0f64, f64::max);
    assert!(far > 1e-3, "{far}");
}

/// A face with two outer loops (a hole in the second) is written as two 144s on one surface and read
/// back as the same loops; a face with only a hole keeps the hole, its outer bound the surface's domain.
#[test]
fn iges_faces_with_several_outer_loops_or_none_round_trip() {
    let s = patch();
    let two = FaceTrim {
        loops: vec![
            polygon(&[(0.05, 0.05), (0.4, 0.05), (0.4, 0.95), (0.05, 0.95)], true),
            polygon(&[(0.5, 0.05), (0.95, 0.05), (0.95, 0.95), (0.5, 0.95)], true),
            circle((0.72, 0.5), 0.1),
        ],
    };
    let hole_only = FaceTrim {
        loops: vec![circle((0.5, 0.5), 0.2)],
    };
    let objects = vec![Geometry::Surface(s.clone()), Geometry::Surface(s.clone())];
    let trims = vec![Some(two.clone()), Some(hole_only.clone())];
    let text = iges::write_trimmed(&objects, &[], &trims, &Default::default());
    assert_eq!(text.lines().filter(|l| l.starts_with("     144")).count(), 2 * 2 + 2);
    let back = iges::read_all(text.as_bytes()).unwrap();
    assert_eq!(back.objects, objects);
    assert_eq!(back.trims[0], Some(two));
    let t = back.trims[1].as_ref().unwrap();
    assert_eq!((t.outer_loops(), t.inner_loops()), (1, 1));
    assert_eq!(t.loops[1], hole_only.loops[0]);
    let ((u0, u1), (v0, v1)) = s.domain();
    let corners: Vec<(f64, f64)> = t.loops[0]
        .edges
        .iter()
        .map(|e| {
            let q = e.point(e.domain().0);
            (q.x, q.y)
        })
        .collect();
    assert_eq!(corners, [(u0, v0), (u1, v0), (u1, v1), (u0, v1)]);
}

/// Curves and untrimmed surfaces beside a trimmed face are written as before (no 144 or 142 without a
/// trim), and mixed with a trimmed face they all come back in order, the trim on its own surface.
#[test]
fn iges_untrimmed_objects_are_unchanged_beside_a_trimmed_face() {
    let s = patch();
    let c = BSplineCurve::try_new(
        2,
        vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        vec![DVec3::ZERO, DVec3::new(1.0, 2.0, 0.5), DVec3::new(3.0, 0.0, 1.0)],
        None,
        3,
    )
    .unwrap();
    let objects = vec![Geometry::Curve(c), Geometry::Surface(s.clone()), Geometry::Surface(s)];
    let opts = iges::WriteOptions {
        date: Some(iges::Timestamp {
            year: 2026,
            month: 12,
            day: 7,
            hour: 0,
            minute: 0,
            second: 0,
        }),
        ..Default::default()
    };
    let plain = iges::write_trimmed(&objects, &[], &[None, None, None], &opts);
    assert!(
        !plain
            .lines()
            .any(|l| l.starts_with("     144") || l.starts_with("     142"))
    );
    let trim = FaceTrim {
        loops: vec![polygon(&[(0.1, 0.1), (0.9, 0.1), (0.5, 0.9)], true)],
    };
    let trims = vec![None, None, Some(trim)];
    let back = iges::read_all(iges::write_trimmed(&objects, &[], &trims, &opts).as_bytes()).unwrap();
    assert_eq!(back.objects, objects);
    assert_eq!(back.trims, trims);
}
