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
