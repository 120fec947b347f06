//! Trimmed faces through the `fairway` binary (issue 29): `info` says a face is trimmed and how many
//! loops; `fair` and `convert` on a file with one trimmed face write it back trimmed (the loops kept).

use fairway::io::step;

mod common;
use common::*;

/// One trimmed face of the OpenCASCADE corpus file (its smallest: 4 edges), written alone as STEP.
fn one_trimmed_face(dir: &Scratch) -> (std::path::PathBuf, fairway::FaceTrim) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/corpus/impeller-faces-occ.step"
    );
    let f = step::read_all(&std::fs::read(path).unwrap()).unwrap();
    let (g, t) = (f.objects.iter().zip(&f.trims))
        .filter_map(|(g, t)| Some((g.clone(), t.clone()?)))
        .min_by_key(|(_, t)| t.loops[0].edges.len())
        .unwrap();
    let text = step::write_trimmed(&[g], &[String::new()], &[Some(t.clone())], &Default::default());
    (dir.file("face.stp", &text), t)
}

#[test]
fn info_fair_and_convert_keep_a_trimmed_face_trimmed() {
    let dir = Scratch::new("trims");
    let (face, trim) = one_trimmed_face(&dir);
    let (out, _) = run_ok(&["info", s(&face)]);
    assert!(
        out.contains("trim            trimmed: 1 outer loop, 0 inner loops, 4 edges"),
        "{out}"
    );
    let (json, _) = run_ok(&["info", s(&face), "--json"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["trim"]["outer_loops"], 1);
    assert_eq!(v["trim"]["edges"], 4);
    for cmd in ["fair", "convert"] {
        let out = dir.path(&format!("{cmd}.stp"));
        match cmd {
            "fair" => run_ok(&["fair", s(&face), "--tolerance", "0.01", "-o", s(&out)]),
            _ => run_ok(&["convert", s(&face), s(&out)]),
        };
        let back = step::read_all(&std::fs::read(&out).unwrap()).unwrap();
        let t = back.trims[0]
            .as_ref()
            .unwrap_or_else(|| panic!("{cmd}: the face lost its trim: {:?}", back.notices));
        assert_eq!((t.loops.len(), t.loops[0].edges.len(), t.loops[0].outer), (1, 4, true));
        for (a, b) in trim.polylines(16)[0].iter().zip(&t.polylines(16)[0]) {
            assert!(a.distance(*b) <= 1e-9, "{cmd}: {a} -> {b}");
        }
    }
}

/// The face's trim read back from `path` (any format Fairway reads: IGES, STEP, a .ron document), its one
/// object a surface.
fn trim_of(path: &std::path::Path, what: &str) -> fairway::FaceTrim {
    let (scene, notices) = fairway::io::load_scene(path).unwrap();
    assert_eq!(scene.objects.len(), 1, "{what}: {notices:?}");
    assert!(scene.objects[0].geometry.as_surface().is_some(), "{what}");
    scene.objects[0]
        .trim
        .clone()
        .unwrap_or_else(|| panic!("{what}: the face lost its trim: {notices:?}"))
}

/// The same loops, point for point (16 a edge) within `tol` in (u, v).
fn same_loops(a: &fairway::FaceTrim, b: &fairway::FaceTrim, tol: f64, what: &str) {
    assert_eq!(a.loops.len(), b.loops.len(), "{what}");
    for (la, lb) in a.polylines(16).iter().zip(&b.polylines(16)) {
        assert_eq!(la.len(), lb.len(), "{what}");
        for (p, q) in la.iter().zip(lb) {
            assert!(p.distance(*q) <= tol, "{what}: {p} -> {q}");
        }
    }
}

/// `convert` keeps a trimmed face's bounds in every format that holds them: STEP → IGES, IGES → STEP,
/// STEP → .ron and .ron (a one-object document of version 2) → IGES, the loops exactly as read; JSON
/// holds the surface alone, and says so.
#[test]
fn convert_keeps_the_trim_in_iges_step_and_ron() {
    let dir = Scratch::new("trims-convert");
    let (face, _) = one_trimmed_face(&dir);
    // the loops as Fairway reads the face (the reference for every output)
    let trim = trim_of(&face, "face.stp");
    let igs = dir.path("face.igs");
    run_ok(&["convert", s(&face), s(&igs)]);
    assert_eq!(trim_of(&igs, "stp → igs"), trim, "the uv curves exactly");
    let stp = dir.path("back.stp");
    run_ok(&["convert", s(&igs), s(&stp)]);
    same_loops(&trim_of(&stp, "igs → stp"), &trim, 1e-9, "igs → stp");
    let ron = dir.path("face.ron");
    run_ok(&["convert", s(&face), s(&ron)]);
    assert_eq!(trim_of(&ron, "stp → ron"), trim);
    let igs2 = dir.path("from-ron.igs");
    run_ok(&["convert", s(&ron), s(&igs2)]);
    assert_eq!(trim_of(&igs2, "ron → igs"), trim);
    let json = dir.path("face.json");
    let (_, err) = run_ok(&["convert", s(&face), s(&json)]);
    assert!(err.contains("a JSON geometry file holds no trim"), "{err}");
    assert!(fairway::io::load(&json).unwrap().geometry.as_surface().is_some());
}

/// `fair` of a trimmed face writes it back trimmed to IGES, STEP and .ron, whether the file is faired as
/// it is (its one object), with `--index 0` (one object's route) or `--object 0`; from an IGES input too.
/// The fair keeps the surface's knots, so the loops are the same (exactly through IGES and .ron, within
/// 10⁻⁹ through STEP).
#[test]
fn fair_keeps_the_trim_on_every_route_and_output() {
    let dir = Scratch::new("trims-fair");
    let (face, _) = one_trimmed_face(&dir);
    let trim = trim_of(&face, "face.stp");
    let igs_in = dir.path("face.igs");
    run_ok(&["convert", s(&face), s(&igs_in)]);
    let cases: [(&std::path::Path, &[&str], &str); 8] = [
        (&face, &[], "igs"),
        (&face, &[], "stp"),
        (&face, &[], "ron"),
        (&face, &["--index", "0"], "igs"),
        (&face, &["--index", "0"], "ron"),
        (&face, &["--object", "0"], "igs"),
        (&igs_in, &[], "stp"),
        (&igs_in, &["--index", "0"], "stp"),
    ];
    for (k, (input, pick, ext)) in cases.into_iter().enumerate() {
        let what = format!("{} {pick:?} → {ext}", input.display());
        let out = dir.path(&format!("faired-{k}.{ext}"));
        let mut args = vec!["fair", s(input), "--tolerance", "0.01", "-o", s(&out)];
        args.extend(pick.iter().copied());
        run_ok(&args);
        let got = trim_of(&out, &what);
        match ext {
            "stp" => same_loops(&got, &trim, 1e-9, &what),
            _ => assert_eq!(got, trim, "{what}"),
        }
    }
}
