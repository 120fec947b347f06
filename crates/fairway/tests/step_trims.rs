//! Trimmed faces through STEP (issue 29): bounds read as uv loops, kept with the surface, written back as
//! `ADVANCED_FACE`s whose 3D edges are recomputed on the (faired) surface within
//! `trim::fit_tolerance` (10⁻⁶ × the surface's control-box diagonal).

use fairway::fair::{SurfaceFairingOptions, fair_surface};
use fairway::io::{Scene, step};
use fairway::measure_surface::SurfaceProjector;
use fairway::trim::{FaceTrim, fit_tolerance};
use fairway::{BSplineSurface, Geometry};

fn corpus(name: &str) -> Vec<u8> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/corpus")
        .join(name);
    std::fs::read(path).unwrap()
}

/// A file of `tests/data/trims` (trimmed faces from other systems, not faired by the corpus test).
fn trims_data(name: &str) -> Vec<u8> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/trims")
        .join(name);
    std::fs::read(path).unwrap()
}

fn surface(g: &Geometry) -> &BSplineSurface {
    g.as_surface().expect("a surface")
}

/// Every B-spline face of the OpenCASCADE file (10 of 12; 2 are surfaces of revolution) opens with its
/// bound: one closed loop each (the gap between edges in (u, v) at the file's own tolerance), the loop's
/// points inside the surface's domain and on the face's 3D edges; the edges' 3D curves are the trims, not
/// objects of their own.
#[test]
fn the_corpus_faces_open_with_their_bounds() {
    let f = step::read_all(&corpus("impeller-faces-occ.step")).unwrap();
    let faces: Vec<(&BSplineSurface, &FaceTrim)> = (f.objects.iter().zip(&f.trims))
        .filter_map(|(g, t)| Some((g.as_surface()?, t.as_ref()?)))
        .collect();
    assert_eq!(faces.len(), 10, "{:?}", f.notices);
    assert_eq!(f.objects.iter().filter(|g| g.as_surface().is_some()).count(), 10);
    assert!(
        f.notices
            .iter()
            .any(|n| n.starts_with("10 trimmed faces read with their bounds")),
        "{:?}",
        f.notices
    );
    for (s, t) in faces {
        assert_eq!((t.outer_loops(), t.inner_loops()), (1, 0));
        let ((u0, u1), (v0, v1)) = s.domain();
        assert!(
            t.largest_gap() <= 1e-5 * (u1 - u0).hypot(v1 - v0),
            "{}",
            t.largest_gap()
        );
        for l in t.polylines(8) {
            for q in l {
                assert!(q.x >= u0 - 1e-9 && q.x <= u1 + 1e-9 && q.y >= v0 - 1e-9 && q.y <= v1 + 1e-9);
            }
        }
    }
}

/// The uv loops of `a` and `b` are the same: as many loops, outer/inner alike, as many edges, and each
/// loop's points (16 a edge) within `tol`.
fn same_loops(a: &FaceTrim, b: &FaceTrim, tol: f64) {
    assert_eq!(a.loops.len(), b.loops.len());
    for (la, lb) in a.loops.iter().zip(&b.loops) {
        assert_eq!((la.outer, la.edges.len()), (lb.outer, lb.edges.len()));
    }
    for (pa, pb) in a.polylines(16).iter().zip(&b.polylines(16)) {
        assert_eq!(pa.len(), pb.len());
        let worst = pa.iter().zip(pb).map(|(x, y)| x.distance(*y)).fold(0.0, f64::max);
        assert!(worst <= tol, "uv loop points moved by {worst}");
    }
}

/// Read → fair trimmed faces → write → read: the loops come back (count, orientation and points),
/// and the 3D edge curves written — recomputed on the faired surface — lie on it within the stated
/// tolerance, by an independent closest-point check of 200 points an edge; they start and end at the
/// surface's points at the loop's uv vertices.
#[test]
fn faired_trimmed_faces_write_back_with_their_loops_and_edges_on_the_faired_surface() {
    let f = step::read_all(&corpus("impeller-faces-occ.step")).unwrap();
    let original = f.clone();
    let mut scene = Scene::from_interchange(f);
    let mut faired = 0;
    // every third face faired (the time of a debug test run); the others are written as read, their edges
    // recomputed all the same
    for o in scene.objects.iter_mut().filter(|o| o.trim.is_some()).step_by(3) {
        let s = surface(&o.geometry).clone();
        let (lo, hi) = s.control_bounds();
        let m = 5e-4 * (hi - lo).length();
        if let Ok(r) = fair_surface(&s, SurfaceFairingOptions::default().tolerance(m)) {
            assert_eq!(r.surface.domain(), s.domain());
            o.geometry = r.surface.into();
            faired += 1;
        }
    }
    assert!(faired >= 3, "{faired} faces faired");
    let (objects, names) = (scene.geometries(), scene.names());
    let trims: Vec<_> = scene.objects.iter().map(|o| o.trim.clone()).collect();
    let text = step::write_trimmed(&objects, &names, &trims, &Default::default());
    let back = step::read_all(text.as_bytes()).unwrap();
    assert_eq!(back.objects.len(), objects.len(), "{:?}", back.notices);
    assert_eq!(back.objects, objects, "the objects in order, bit for bit");
    assert_eq!(back.trims.len(), trims.len());
    for (k, (a, b)) in trims.iter().zip(&back.trims).enumerate() {
        match (a, b) {
            (None, None) => {}
            (Some(a), Some(b)) => same_loops(a, b, 1e-9),
            _ => panic!("object {k}: trim {} -> {}", a.is_some(), b.is_some()),
        }
    }
    // and against the file first read: the loops of the faces are those OpenCASCADE wrote
    for (a, b) in original.trims.iter().flatten().zip(back.trims.iter().flatten()) {
        same_loops(a, b, 1e-9);
    }
    // the written 3D edges: with the faces taken out of the file, the reader returns them as curves
    let unfaced = text.replace("ADVANCED_FACE(", "FACE_WAS_HERE(");
    let edges = step::read_all(unfaced.as_bytes()).unwrap();
    let mut checked = 0;
    for (g, t) in objects.iter().zip(&trims) {
        let (Geometry::Surface(s), Some(t)) = (g, t) else {
            continue;
        };
        let tol = fit_tolerance(s);
        let proj = SurfaceProjector::new(s, 6);
        let mine: Vec<&fairway::BSplineCurve> = t.loops.iter().flat_map(|l| &l.edges).collect();
        for e in mine {
            let (a, b) = e.domain();
            let (p, q) = (e.point(a), e.point(b));
            let (p, q) = (s.point(p.x, p.y), s.point(q.x, q.y));
            // the written edge of this uv edge: the 3D curve starting and ending there
            let c = (edges.objects.iter().filter_map(Geometry::as_curve))
                .find(|c| {
                    let (c0, c1) = c.domain();
                    c.point(c0).distance(p) <= tol && c.point(c1).distance(q) <= tol && c.dim() == 3
                })
                .expect("a 3D edge from vertex to vertex");
            let (c0, c1) = c.domain();
            let worst = (0..=200)
                .map(|k| c.point(c0 + (c1 - c0) * k as f64 / 200.0))
                .map(|x| proj.project(x).distance)
                .fold(0.0f64, f64::max);
            assert!(
                worst <= tol,
                "an edge lies {worst:.3e} off the faired surface (tol {tol:.3e})"
            );
            checked += 1;
        }
    }
    assert!(checked >= 100, "{checked} edges checked");
    eprintln!("{faired} faces faired, {checked} written edges on their faired surfaces");
}

/// The OpenCASCADE file with every edge's p-curves taken away (`SURFACE_CURVE(name, 3D curve, ())`).
fn without_pcurves(text: &str) -> String {
    let mut parts = text.split("SURFACE_CURVE('',#");
    let mut out = parts.next().unwrap().to_string();
    for p in parts {
        out.push_str("SURFACE_CURVE('',#");
        let open = p.find(",(").unwrap();
        let close = open + p[open..].find(')').unwrap();
        out.push_str(&p[..open + 2]);
        out.push_str(&p[close..]);
    }
    out
}

/// Where an edge has only its 3D curve, the face's loop is that curve projected onto the surface: the
/// same loops and edges in the same orientation (each edge's ends within 10⁻⁴ of the domain's size of the
/// p-curves' ends), and on the surface every point of the projected loop within 2·10⁻³ × the surface's
/// diagonal of the exact loop of the p-curves (densely sampled). The bound is the file's, not the
/// projection's: OpenCASCADE's 3D edges and p-curves of these faces (healed from IGES) disagree — edges run
/// up to 1.3·10⁻² mm past a surface's boundary (its points there project onto the boundary), and on two
/// small faces (diagonal 2.4 mm) the p-curve runs along u = 0 where the 3D edge is at u ≈ 6·10⁻⁴.
#[test]
fn edges_without_p_curves_are_projected_onto_the_surface() {
    let text = String::from_utf8(corpus("impeller-faces-occ.step")).unwrap();
    let exact = step::read_all(text.as_bytes()).unwrap();
    let projected = step::read_all(without_pcurves(&text).as_bytes()).unwrap();
    let faces = (projected.notices.iter())
        .filter(|n| n.contains("(ADVANCED_FACE) on line"))
        .cloned()
        .collect::<Vec<_>>();
    assert!(faces.is_empty(), "{faces:?}");
    assert!(exact.objects == projected.objects, "the same objects");
    let (mut compared, mut worst) = (0, 0.0f64);
    for ((g, a), b) in exact.objects.iter().zip(&exact.trims).zip(&projected.trims) {
        let (Some(a), Some(b)) = (a, b) else {
            assert_eq!(a.is_some(), b.is_some());
            continue;
        };
        let s = surface(g);
        let ((u0, u1), (v0, v1)) = s.domain();
        let span = (u1 - u0).hypot(v1 - v0);
        let (lo, hi) = s.control_bounds();
        let diag = (hi - lo).length();
        assert_eq!(a.loops.len(), b.loops.len());
        for (la, lb) in a.loops.iter().zip(&b.loops) {
            assert_eq!((la.outer, la.edges.len()), (lb.outer, lb.edges.len()));
            let dense: Vec<_> = (la.edges.iter())
                .flat_map(|e| {
                    let (t0, t1) = e.domain();
                    (0..=400).map(move |k| e.point(t0 + (t1 - t0) * k as f64 / 400.0))
                })
                .map(|q| s.point(q.x, q.y))
                .collect();
            for (ea, eb) in la.edges.iter().zip(&lb.edges) {
                // same direction: the same start and end
                let ends = |e: &fairway::BSplineCurve| (e.point(e.domain().0), e.point(e.domain().1));
                let ((a0, a1), (b0, b1)) = (ends(ea), ends(eb));
                assert!(a0.distance(b0) <= 1e-4 * span && a1.distance(b1) <= 1e-4 * span);
                for q in eb.points() {
                    let x = s.point(q.x, q.y);
                    let d = dense.iter().map(|y| y.distance(x)).fold(f64::INFINITY, f64::min);
                    assert!(
                        d <= 2e-3 * diag,
                        "a projected point {d:.3e} off the loop (diagonal {diag})"
                    );
                    worst = worst.max(d / diag);
                }
            }
        }
        compared += 1;
    }
    assert_eq!(compared, 10);
    eprintln!("projected loops: at most {worst:.3e} × the diagonal off the p-curves' loops");
}

/// An edge whose curve is not one the reader takes: that face opens untrimmed, a notice names the face,
/// the edge and the reason; the other faces keep their bounds, nothing else is lost.
#[test]
fn a_face_with_an_unreadable_edge_opens_untrimmed_with_the_reason() {
    let text = String::from_utf8(corpus("impeller-faces-occ.step")).unwrap();
    let broken = text.replace(
        "#83 = EDGE_CURVE('',#84,#86,#88,.T.);",
        "#83 = EDGE_CURVE('',#84,#86,#85,.T.);",
    );
    assert_ne!(broken, text);
    let f = step::read_all(broken.as_bytes()).unwrap();
    let note = (f.notices.iter())
        .find(|n| n.starts_with("#79 (ADVANCED_FACE)"))
        .unwrap_or_else(|| panic!("{:?}", f.notices));
    assert!(
        note.contains(
            "its bounds are not read, the surface #93 opens untrimmed: edge #83: its curve #85 is a \
                       CARTESIAN_POINT, which is not read"
        ),
        "{note}"
    );
    assert_eq!(f.trims.iter().flatten().count(), 9);
    let exact = step::read_all(text.as_bytes()).unwrap();
    let surfaces = |f: &fairway::io::InterchangeFile| {
        f.objects
            .iter()
            .filter_map(Geometry::as_surface)
            .cloned()
            .collect::<Vec<_>>()
    };
    assert_eq!(surfaces(&f), surfaces(&exact), "every surface still opens");
}

/// The face reader on damaged bounds: lines of the OpenCASCADE file removed or their references pointed
/// elsewhere (200 seeded cases) never panic; each file opens or is refused with a message, and every
/// face that keeps its bounds has closed loops.
#[test]
fn damaged_face_bounds_never_panic() {
    let text = String::from_utf8(corpus("impeller-faces-occ.step")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut next = |n: usize| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % n as u64) as usize
    };
    for case in 0..200 {
        let mut l: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
        for _ in 0..3 {
            let k = next(l.len());
            if case % 2 == 0 {
                l.remove(k);
            } else if let Some(p) = l[k].find(",#") {
                let r = next(4000);
                l[k] = format!(
                    "{},#{r}{}",
                    &l[k][..p],
                    &l[k][p + 2..].trim_start_matches(char::is_numeric)
                );
            }
        }
        let bytes = l.join("\n");
        if let Ok(f) = std::panic::catch_unwind(|| step::read_all(bytes.as_bytes()))
            .unwrap_or_else(|_| panic!("case {case} panicked"))
        {
            for t in f.trims.iter().flatten() {
                assert!(t.loops.iter().all(|l| !l.edges.is_empty()), "case {case}");
            }
        }
    }
}

/// A scene with trimmed faces saved as a document (RON version 2) and read back keeps every face's loops
/// exactly; a trim on a curve is refused with the object named.
#[test]
fn documents_keep_the_trims() {
    let f = step::read_all(&corpus("impeller-faces-occ.step")).unwrap();
    let scene = Scene::from_interchange(f);
    let back = Scene::from_ron(&scene.to_ron().unwrap()).unwrap();
    assert_eq!(back, scene);
    assert_eq!(back.objects.iter().filter(|o| o.trim.is_some()).count(), 10);
    let curve = scene
        .objects
        .iter()
        .position(|o| o.trim.is_none() && o.geometry.as_curve().is_some())
        .unwrap();
    let mut bad = scene.clone();
    bad.objects[curve].trim = scene.objects.iter().find_map(|o| o.trim.clone());
    let err = Scene::from_ron(&bad.to_ron().unwrap()).unwrap_err().to_string();
    assert!(
        err.contains(&format!("objects[{curve}].trim: a curve has no trim")),
        "{err}"
    );
}

/// IGES trimmed surfaces (144 with 142 boundaries, parameter-space curves): the impeller's surfaces keep
/// their loops (each closed in (u, v), inside the domain); those that cannot are named with the reason;
/// written as STEP and read back, the loops are the same (within the IGES loops' own gaps).
#[test]
fn iges_trimmed_surfaces_keep_their_loops_and_export_to_step() {
    let f = fairway::io::iges::read_all(&corpus("impeller.igs")).unwrap();
    let trimmed = f.trims.iter().flatten().count();
    let not_read = f
        .notices
        .iter()
        .filter(|n| n.contains("(trimmed surface, 144): its boundaries are not read"))
        .count();
    eprintln!("impeller.igs: {trimmed} surfaces trimmed, {not_read} 144s not read");
    for n in f
        .notices
        .iter()
        .filter(|n| n.contains("144)") || n.contains("(surface, 128):"))
        .take(4)
    {
        eprintln!("  {n}");
    }
    assert!(trimmed >= 200, "{trimmed} of 277 trimmed surfaces read");
    for (g, t) in f.objects.iter().zip(&f.trims) {
        let Some(t) = t else { continue };
        let ((u0, u1), (v0, v1)) = surface(g).domain();
        let span = (u1 - u0).hypot(v1 - v0);
        assert!(t.largest_gap() <= 1e-4 * span);
        assert!(t.outer_loops() == 1, "{}", t.summary());
        for l in t.polylines(4) {
            for q in l {
                let tol = 1e-6 * span;
                assert!(
                    q.x >= u0 - tol && q.x <= u1 + tol && q.y >= v0 - tol && q.y <= v1 + tol,
                    "{q}"
                );
            }
        }
    }
    // a few of them through STEP: the loops come back
    let picked: Vec<usize> = (0..f.objects.len())
        .filter(|&k| f.trims[k].is_some())
        .step_by(40)
        .collect();
    let objects: Vec<Geometry> = picked.iter().map(|&k| f.objects[k].clone()).collect();
    let trims: Vec<_> = picked.iter().map(|&k| f.trims[k].clone()).collect();
    let names = vec![String::new(); picked.len()];
    let text = step::write_trimmed(&objects, &names, &trims, &Default::default());
    let back = step::read_all(text.as_bytes()).unwrap();
    assert_eq!(back.objects, objects);
    // the STEP edges share their vertices, so an edge ends where the next begins: the IGES loops' own gaps
    // between edges (up to 1e-4 of the domain) move the loop points by about that much, no more
    for (a, b) in trims.iter().zip(&back.trims) {
        let a = a.as_ref().unwrap();
        same_loops(
            a,
            b.as_ref().expect("the trim read back"),
            1e-9 + 10.0 * a.largest_gap(),
        );
    }
}

/// OpenCASCADE's p-curves that are not B-splines (`tests/data/trims/occ-conic-trims.step`, written by
/// `make_conic_trims_step.py`): a face bounded by a uv rectangle (4 `LINE`s) with a circular hole (a
/// `CIRCLE`), and one bounded by a pentagon (5 `LINE`s) with an elliptical hole (an `ELLIPSE`). Lines are
/// read as degree-1 edges through the corners, the circle and the ellipse exactly as rational
/// quadratics: every point of them on the conic to rounding, not to a fit tolerance.
#[test]
fn occ_line_circle_and_ellipse_p_curves_are_read_exactly() {
    let f = step::read_all(&trims_data("occ-conic-trims.step")).unwrap();
    assert_eq!(f.objects.len(), 2, "{:?}", f.notices);
    assert!(
        !f.notices
            .iter()
            .any(|n| n.contains("untrimmed") || n.contains("not read")),
        "{:?}",
        f.notices
    );
    let trims: Vec<&FaceTrim> = f.trims.iter().map(|t| t.as_ref().expect("trimmed")).collect();
    for t in &trims {
        assert_eq!((t.outer_loops(), t.inner_loops()), (1, 1), "{}", t.summary());
        assert!(t.largest_gap() <= 1e-7, "{}", t.largest_gap());
    }
    let corners = |l: &fairway::trim::TrimLoop| -> Vec<(f64, f64)> {
        l.edges
            .iter()
            .map(|e| {
                assert_eq!((e.degree(), e.is_rational()), (1, false), "a line");
                let q = e.point(e.domain().0);
                (q.x, q.y)
            })
            .collect()
    };
    let near = |got: Vec<(f64, f64)>, want: &[(f64, f64)]| {
        assert_eq!(got.len(), want.len());
        // the loop may start at any corner and run either way round
        let found = want
            .iter()
            .all(|w| got.iter().any(|g| (g.0 - w.0).hypot(g.1 - w.1) <= 1e-6));
        assert!(found, "{got:?} vs {want:?}");
    };
    near(
        corners(&trims[0].loops[0]),
        &[(0.1, 0.1), (0.9, 0.1), (0.9, 0.9), (0.1, 0.9)],
    );
    let pentagon: Vec<(f64, f64)> = (0..5)
        .map(|k| {
            let a = std::f64::consts::FRAC_PI_2 + std::f64::consts::TAU * k as f64 / 5.0;
            (0.5 + 0.42 * a.cos(), 0.5 + 0.42 * a.sin())
        })
        .collect();
    near(corners(&trims[1].loops[0]), &pentagon);
    // the holes: rational quadratics exactly on the circle and on the ellipse, all the way round
    let on = |l: &fairway::trim::TrimLoop, f: &dyn Fn(f64, f64) -> f64| {
        let mut turn = 0.0;
        for e in &l.edges {
            assert_eq!((e.degree(), e.is_rational()), (2, true));
            let (a, b) = e.domain();
            for k in 0..=100 {
                let q = e.point(a + (b - a) * k as f64 / 100.0);
                assert!(f(q.x, q.y).abs() <= 1e-12, "{q}: {}", f(q.x, q.y));
            }
            turn += b - a;
        }
        turn
    };
    let circle = on(&trims[0].loops[1], &|u, v| (u - 0.5).hypot(v - 0.5) / 0.15 - 1.0);
    let ellipse = on(&trims[1].loops[1], &|u, v| {
        ((u - 0.45) / 0.2).hypot((v - 0.5) / 0.1) - 1.0
    });
    for turn in [circle, ellipse] {
        assert!((turn - std::f64::consts::TAU).abs() <= 1e-9, "a whole turn: {turn}");
    }
}

/// A p-curve given as a `TRIMMED_CURVE` of a `LINE` (running with it or against it), and one given as a
/// `POLYLINE` through the same corners, bound the face as the `LINE` did (the same corners, degree 1); a p-curve of a kind that is
/// not read (a `HYPERBOLA` here) leaves that face untrimmed with a notice naming it (its edges then curves
/// of their own), the other face and the file read as before.
#[test]
fn trimmed_curve_and_polyline_p_curves_bound_the_face_as_their_line_did() {
    let text = String::from_utf8(trims_data("occ-conic-trims.step")).unwrap();
    let original = step::read_all(text.as_bytes()).unwrap();
    // the first rectangle side: u = 0.1 (a vertical line through (0.1, 0) in (u, v))
    assert!(text.contains("#124 = DEFINITIONAL_REPRESENTATION('',(#125),#129);"));
    let with = |item: &str, extra: &str| {
        text.replace(
            "#124 = DEFINITIONAL_REPRESENTATION('',(#125),#129);",
            &format!("#124 = DEFINITIONAL_REPRESENTATION('',({item}),#129);\n{extra}"),
        )
    };
    let trimmed = with(
        "#9001",
        "#9001 = TRIMMED_CURVE('',#125,(PARAMETER_VALUE(0.1)),(PARAMETER_VALUE(0.9)),.T.,.PARAMETER.);",
    );
    // the same side through a trimmed curve that runs against its basis line (sense agreement .F.)
    let against = with(
        "#9001",
        "#9001 = TRIMMED_CURVE('',#125,(PARAMETER_VALUE(0.9)),(PARAMETER_VALUE(0.1)),.F.,.PARAMETER.);",
    );
    let polyline = with(
        "#9001",
        "#9001 = POLYLINE('',(#9002,#9003,#9004));\n#9002 = CARTESIAN_POINT('',(0.1,0.));\n\
         #9003 = CARTESIAN_POINT('',(0.1,0.5));\n#9004 = CARTESIAN_POINT('',(0.1,1.));",
    );
    let first = |f: &fairway::io::InterchangeFile| f.trims[0].clone().expect("trimmed");
    let want = first(&original);
    for (what, t) in [
        ("trimmed curve", trimmed),
        ("trimmed curve against its line", against),
        ("polyline", polyline),
    ] {
        let f = step::read_all(t.as_bytes()).unwrap();
        let got = first(&f);
        assert_eq!((got.loops.len(), got.loops[0].edges.len()), (2, 4), "{what}");
        same_loops(&got, &want, 1e-12);
        assert_eq!(f.trims[1], original.trims[1], "{what}: the other face as it was");
    }
    let hyperbola = with(
        "#9001",
        "#9001 = HYPERBOLA('',#9002,0.1,0.1);\n#9002 = AXIS2_PLACEMENT_2D('',#126,#128);",
    );
    let f = step::read_all(hyperbola.as_bytes()).unwrap();
    // the file still opens: both surfaces (and the untrimmed face's 3D edges as curves of their own)
    let surfaces: Vec<usize> = (0..f.objects.len())
        .filter(|&k| f.objects[k].as_surface().is_some())
        .collect();
    assert_eq!(surfaces.len(), 2, "{:?}", f.notices);
    assert_eq!(f.trims[surfaces[0]], None);
    assert_eq!(f.trims[surfaces[1]], original.trims[1]);
    assert!(
        f.notices
            .iter()
            .any(|n| n.contains("opens untrimmed") && n.contains("is a HYPERBOLA, which is not read")),
        "{:?}",
        f.notices
    );
}
