//! End-to-end tests of STEP files through the `fairway` binary: `convert` both ways reproduces every
//! float and keeps the file's unit, `info` names the object and the unit, `--index` picks an object,
//! a broken entity is skipped with its reason, `fair` takes a tolerance with a unit and writes STEP in
//! the input's unit, and bad files fail with a clear message and leave no output.

use std::path::Path;

use fairway::io::{self, Unit, step};
use fairway::{BSplineCurve, DVec3, Geometry};
use serde_json::Value;

mod common;
use common::*;

/// A rational cubic in 3D (weights ≠ 1).
fn rational_curve() -> BSplineCurve {
    BSplineCurve::try_new(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0],
        vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.5),
            DVec3::new(2.5, 2.2, -0.3),
            DVec3::new(4.0, 0.7, 0.1),
            DVec3::new(5.1, 1.3, 0.9),
        ],
        Some(vec![1.0, 0.7, 1.3, 0.9, 1.0]),
        3,
    )
    .unwrap()
}

fn three_objects() -> Vec<Geometry> {
    vec![
        io::load_geometry(&reference("s_curve.json")).unwrap(),
        rational_curve().into(),
        io::load_geometry(&reference("saddle.json")).unwrap(),
    ]
}

fn write_step(path: &Path, objects: &[Geometry], unit: Unit) {
    let opts = step::WriteOptions {
        unit,
        ..Default::default()
    };
    std::fs::write(path, step::write(objects, &opts)).unwrap();
}

#[test]
fn convert_json_step_json_reproduces_every_float_and_keeps_the_unit() {
    let sc = Scratch::new("chain");
    for (k, g) in three_objects().iter().enumerate() {
        let json = sc.path(&format!("{k}.json"));
        io::save(&json, &io::Document::new(g.clone())).unwrap();
        let stp = sc.path(&format!("{k}.STEP"));
        run_ok(&["convert", s(&json), s(&stp)]);
        let f = step::read_all(&std::fs::read(&stp).unwrap()).unwrap();
        assert_eq!(f.unit, Some(Unit::Millimeter), "a unitless input is written in mm");
        assert_eq!(&f.objects, std::slice::from_ref(g));
        let back = sc.path(&format!("{k}.back.json"));
        run_ok(&["convert", s(&stp), s(&back)]);
        assert_eq!(&io::load_geometry(&back).unwrap(), g, "exact");
    }
    // STEP → STEP and STEP → IGES keep the file's unit, coordinates untouched
    let inch = sc.path("inch.stp");
    write_step(&inch, &three_objects()[1..2], Unit::Inch);
    for out in ["copy.stp", "copy.igs"] {
        let out = sc.path(out);
        run_ok(&["convert", s(&inch), s(&out)]);
        let f = io::read_interchange(&out).unwrap().unwrap();
        assert_eq!(f.unit, Some(Unit::Inch), "{}", out.display());
        assert_eq!(f.objects, three_objects()[1..2]);
    }
}

#[test]
fn info_and_convert_pick_objects_by_index_and_show_the_unit() {
    let sc = Scratch::new("index");
    let stp = sc.path("three.stp");
    let objects = three_objects();
    write_step(&stp, &objects, Unit::Inch);
    let (text, err) = run_ok(&["info", s(&stp)]);
    assert!(
        err.contains("3 objects, using number 0 (choose with --index, 0 to 2)"),
        "{err}"
    );
    assert!(
        text.contains("2D curve") && text.contains("object          1 of 3 (--index 0)"),
        "{text}"
    );
    assert!(
        text.contains("unit            in (lengths in in, curvatures in 1/in)"),
        "{text}"
    );
    let (json, err) = run_ok(&["info", s(&stp), "--json", "--index", "2"]);
    assert!(err.is_empty(), "{err}");
    let v: Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["kind"], "surface");
    assert_eq!(v["file"]["unit"], "in");
    assert_eq!(v["file"]["index"], 2);
    assert_eq!(v["file"]["objects"], 3);
    assert_eq!(v["rational"], false);
    let (json, _) = run_ok(&["info", s(&stp), "--json", "--index", "1"]);
    let v: Value = serde_json::from_str(&json).unwrap();
    assert_eq!(
        (v["kind"].as_str(), v["rational"].as_bool()),
        (Some("curve"), Some(true))
    );
    // a JSON file has no "file" part
    let (json, _) = run_ok(&["info", s(&reference("s_curve.json")), "--json"]);
    assert!(serde_json::from_str::<Value>(&json).unwrap().get("file").is_none());

    let out = sc.path("second.json");
    run_ok(&["convert", s(&stp), s(&out), "--index", "1"]);
    assert_eq!(io::load_geometry(&out).unwrap(), objects[1]);
    run_fails(
        &["convert", s(&stp), s(&sc.path("x.json")), "--index", "3"],
        &["three.stp", "--index 3", "3 objects (0 to 2)"],
    );
    assert!(!sc.path("x.json").exists());
    run_fails(
        &["info", s(&reference("s_curve.json")), "--index", "1"],
        &["--index 1", "one document"],
    );
}

#[test]
fn a_broken_entity_is_skipped_with_its_reason_and_the_rest_converts() {
    let sc = Scratch::new("broken");
    let objects = three_objects();
    let text = step::write(&objects, &step::WriteOptions::default());
    // the rational curve's weights: one more than its control points
    let broken = text.replacen("RATIONAL_B_SPLINE_CURVE((", "RATIONAL_B_SPLINE_CURVE((1.0,", 1);
    assert_ne!(broken, text);
    let stp = sc.path("broken.stp");
    std::fs::write(&stp, broken).unwrap();
    let (text, err) = run_ok(&["info", s(&stp), "--index", "1"]);
    assert!(
        err.contains("broken.stp: #") && err.contains("skipped: 6 weights for 5 control points"),
        "{err}"
    );
    assert!(
        text.contains("object          2 of 2") && text.contains("surface"),
        "{text}"
    );
    let out = sc.path("surface.json");
    run_ok(&["convert", s(&stp), s(&out), "--index", "1"]);
    assert_eq!(io::load_geometry(&out).unwrap(), objects[2]);
}

#[test]
fn fair_takes_a_step_file_and_a_tolerance_with_a_unit_and_writes_step_in_the_files_unit() {
    let sc = Scratch::new("fair");
    let c = io::load_geometry(&reference("s_curve.json")).unwrap();
    let stp = sc.path("s.stp");
    write_step(&stp, std::slice::from_ref(&c), Unit::Inch);
    let diag = {
        let c = c.as_curve().unwrap();
        let (lo, hi) = c
            .points()
            .iter()
            .fold((DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)), |(a, b), p| {
                (a.min(*p), b.max(*p))
            });
        (hi - lo).length()
    };
    // the tolerance in mm, the file in inches: 5e-3 of the diagonal
    let m_in = 5e-3 * diag;
    let m_mm = format!("{}mm", m_in * 25.4);
    let out = sc.path("faired.stp");
    let (_, err) = run_ok(&["fair", s(&stp), "--tolerance", &m_mm, "-o", s(&out)]);
    assert!(err.contains("s.stp: coordinates in in: tolerance"), "{err}");
    let f = step::read_all(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(f.unit, Some(Unit::Inch), "written in the input's unit");
    let faired = f.objects[0].as_curve().unwrap();
    let original = c.as_curve().unwrap();
    let dev = fairway::measure::deviations(original, faired, 2000)
        .into_iter()
        .fold(0.0, f64::max);
    assert!(dev > 0.0, "the curve was faired");
    assert!(dev <= m_in * (1.0 + 1e-9), "deviation {dev} in, tolerance {m_in} in");
    // a unit on a file without one is refused
    run_fails(
        &[
            "fair",
            s(&reference("s_curve.json")),
            "--tolerance",
            "0.1mm",
            "-o",
            s(&sc.path("o.json")),
        ],
        &["declares no length unit"],
    );
    // an unknown unit is a usage error (exit 2), said before anything is read
    let o = fairway(&["fair", s(&stp), "--tolerance", "0.1parsec", "-o", s(&sc.path("o.json"))]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("\"parsec\" is not a length unit; known units: in, mm,"));
    // so is a tolerance that is not a finite number
    let o = fairway(&["fair", s(&stp), "--tolerance", "nan", "-o", s(&sc.path("o.json"))]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("\"nan\" is not a finite length"));
}

/// `--tolerance 0.05mm` on an inch file is 1/508 in, the nearest double (the naive 0.05 / 25.4 is one ulp
/// off): said on stderr and written in the report.
#[test]
fn a_tolerance_in_mm_on_an_inch_file_is_converted_exactly() {
    let sc = Scratch::new("exact");
    let c = io::load_geometry(&reference("s_curve.json")).unwrap();
    let stp = sc.path("s.stp");
    write_step(&stp, std::slice::from_ref(&c), Unit::Inch);
    let (out, report) = (sc.path("f.stp"), sc.path("r.json"));
    let (_, err) = run_ok(&[
        "fair",
        s(&stp),
        "--tolerance",
        "0.05mm",
        "-o",
        s(&out),
        "--report",
        s(&report),
    ]);
    let m = 1.0 / 508.0;
    assert!(err.contains(&format!("tolerance {m} in")), "{err}");
    let r: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(r["tolerance"].as_f64(), Some(m));
    assert_ne!(0.05 / 25.4, m);
}

#[test]
fn bad_step_files_fail_clearly_and_leave_no_output() {
    let sc = Scratch::new("bad");
    let out = sc.path("out.json");
    let cases: [(&str, &[u8], &[&str]); 4] = [
        ("empty.stp", b"", &["empty.stp", "STEP: the file is empty"]),
        ("json.step", b"{\"degree\": 3}", &["not a STEP (ISO 10303-21) file"]),
        (
            "points.stp",
            b"ISO-10303-21;HEADER;ENDSEC;DATA;#1=CARTESIAN_POINT('',(0.,0.,0.));ENDSEC;END-ISO-10303-21;",
            &["points.stp: no B-spline curve or surface in the file"],
        ),
        (
            "cut.stp",
            b"ISO-10303-21;HEADER;ENDSEC;DATA;#1=CARTESIAN_POINT('',(0.,0.,",
            &["cut.stp", "ends without END-ISO-10303-21"],
        ),
    ];
    for (name, bytes, needles) in cases {
        let p = sc.path(name);
        std::fs::write(&p, bytes).unwrap();
        run_fails(&["convert", s(&p), s(&out)], needles);
        assert!(!out.exists(), "{name}");
        run_fails(&["info", s(&p)], needles);
        run_fails(&["fair", s(&p), "--tolerance", "0.1", "-o", s(&out)], needles);
        assert!(!out.exists(), "{name}");
    }
    // an existing output is replaced only by a complete file
    std::fs::write(&out, "old").unwrap();
    run_fails(&["convert", s(&sc.path("empty.stp")), s(&out)], &["empty"]);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "old");
}
