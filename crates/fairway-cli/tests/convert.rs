//! End-to-end tests of `fairway convert`: chains JSON → RON → IGES → JSON
//! that reproduce every float, IGES files with several objects (`--index`),
//! point lists fitted on the way in, SVG out, and clear failures.

use fairway::io::{self, Document};
use fairway::{DVec3, Geometry};

mod common;
use common::*;

fn convert_ok(args: &[&str]) -> String {
    let mut all = vec!["convert"];
    all.extend_from_slice(args);
    let out = fairway(&all);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        out.status.success(),
        "convert {args:?}: exit {:?}: {err}",
        out.status.code()
    );
    err
}

fn convert_fails(args: &[&str], needles: &[&str]) {
    let mut all = vec!["convert"];
    all.extend_from_slice(args);
    let out = fairway(&all);
    assert_eq!(out.status.code(), Some(1), "convert {args:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    for n in needles {
        assert!(err.contains(n), "stderr of {args:?} lacks {n:?}: {err}");
    }
}

#[test]
fn json_ron_iges_chain_reproduces_every_float() {
    let sc = Scratch::new("chain");
    for src in [
        reference("s_curve.json"),
        reference("conical_spiral.json"),
        reference("saddle.json"),
        asset("bumpy_surface.json"),
    ] {
        let original = io::load_geometry(&src).unwrap();
        let ron = sc.path("a.ron");
        let igs = sc.path("b.igs");
        let json = sc.path("c.json");
        let iges2 = sc.path("d.IGES");
        convert_ok(&[s(&src), s(&ron)]);
        convert_ok(&[s(&ron), s(&igs)]);
        convert_ok(&[s(&igs), s(&json)]);
        convert_ok(&[s(&json), s(&iges2)]);
        for p in [&ron, &igs, &json, &iges2] {
            assert_eq!(
                io::load_geometry(p).unwrap(),
                original,
                "{} via {}",
                src.display(),
                p.display()
            );
        }
        let igs_text = std::fs::read_to_string(&igs).unwrap();
        assert!(igs_text.lines().all(|l| l.len() == 80));
        assert!(igs_text.contains(match original {
            Geometry::Curve(_) => "126,",
            Geometry::Surface(_) => "128,",
        }));
    }
}

#[test]
fn ron_document_settings_survive_ron_to_ron_and_geometry_survives_iges() {
    let sc = Scratch::new("ron");
    let src = asset("car_roof.ron");
    let doc = Document::from_ron(&std::fs::read_to_string(&src).unwrap()).unwrap();
    let out = sc.path("copy.fairway");
    convert_ok(&[s(&src), s(&out)]);
    assert_eq!(io::load(&out).unwrap(), doc);
    let igs = sc.path("roof.igs");
    convert_ok(&[s(&src), s(&igs)]);
    assert_eq!(io::load_geometry(&igs).unwrap(), doc.geometry);
}

#[test]
fn iges_with_several_objects_picks_by_index_and_reports() {
    let sc = Scratch::new("multi");
    let a = io::load_geometry(&reference("s_curve.json")).unwrap();
    let b = io::load_geometry(&reference("saddle.json")).unwrap();
    let igs = sc.path("two.igs");
    std::fs::write(
        &igs,
        io::iges::write(&[a.clone(), b.clone()], &io::iges::WriteOptions::default()),
    )
    .unwrap();
    let out0 = sc.path("first.json");
    let err = convert_ok(&[s(&igs), s(&out0)]);
    assert!(err.contains("2 objects") && err.contains("--index"), "{err}");
    assert_eq!(io::load_geometry(&out0).unwrap(), a);
    let out1 = sc.path("second.ron");
    convert_ok(&[s(&igs), s(&out1), "--index", "1"]);
    assert_eq!(io::load_geometry(&out1).unwrap(), b);
    convert_fails(
        &[s(&igs), s(&sc.path("x.json")), "--index", "2"],
        &["--index 2", "2 objects"],
    );
}

#[test]
fn points_are_fitted_on_the_way_in_and_svg_is_written() {
    let sc = Scratch::new("points");
    let csv = sc.path("section.csv");
    let mut text = String::from("x,y\n");
    for k in 0..=40 {
        let t = k as f64 / 40.0 * std::f64::consts::FRAC_PI_2;
        text += &format!("{},{}\n", 3.0 * t.cos(), 3.0 * t.sin());
    }
    std::fs::write(&csv, text).unwrap();
    let json = sc.path("section.json");
    convert_ok(&[s(&csv), s(&json), "--control-points", "8", "--param", "centripetal"]);
    let c = io::load_geometry(&json).unwrap();
    let c = c.as_curve().unwrap();
    assert_eq!((c.n_points(), c.dim()), (8, 2));
    assert!((c.points()[0] - DVec3::new(3.0, 0.0, 0.0)).length() < 1e-12);
    for k in 0..=50 {
        let (a, b) = c.domain();
        let r = c.point(a + (b - a) * k as f64 / 50.0).length();
        assert!((r - 3.0).abs() < 1e-3, "radius {r}");
    }
    let svg = sc.path("section.svg");
    convert_ok(&[s(&json), s(&svg), "--band", "0.05"]);
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.contains("id=\"comb\"") && text.contains("id=\"band\""));
    convert_fails(&[s(&csv), s(&json), "--param", "uniformish"], &["--param"]);
    convert_fails(&[s(&asset("bumpy_surface.json")), s(&svg)], &["surface"]);
}

#[test]
fn bad_input_or_output_fails_clearly_and_leaves_no_output() {
    let sc = Scratch::new("bad");
    let bad = sc.path("bad.igs");
    std::fs::write(&bad, "not an iges file\n").unwrap();
    let out = sc.path("out.json");
    convert_fails(&[s(&bad), s(&out)], &["bad.igs", "IGES", "80"]);
    assert!(!out.exists());
    convert_fails(
        &[s(&reference("s_curve.json")), s(&sc.path("out.csv"))],
        &["import only"],
    );
    convert_fails(&[s(&reference("s_curve.json")), s(&sc.path("out.dat"))], &["extension"]);
    convert_fails(
        &[s(&reference("s_curve.json")), s(&sc.path("no/such/dir/out.json"))],
        &["out.json"],
    );
    // an existing output is replaced only by a complete file
    std::fs::write(&out, "old").unwrap();
    convert_fails(&[s(&bad), s(&out)], &["IGES"]);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "old");
}
