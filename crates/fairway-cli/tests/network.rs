//! End-to-end tests of files with several objects (issue 30): `info` lists the joins (text and JSON),
//! `fair` fairs every object (or those `--object` names) keeping the joins and writes the file back in
//! order with its names, the report has each object's measures and each join before and after;
//! `--index` still fairs one object alone.

use std::path::Path;

use fairway::fair::closed::split;
use fairway::io::{DocumentSettings, Scene, SceneObject, Unit, load_scene, save_scene};
use fairway::network::{Continuity, find_joins};
use fairway::{BSplineCurve, DVec3, Geometry};
use serde_json::Value;

mod common;
use common::*;

/// A noisy planar cubic (a sine arc, 30 control points, deterministic noise of ±4e-3) split at two
/// interior knots: three curves meeting with G2.
fn chain() -> Vec<BSplineCurve> {
    let n = 30;
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let pts: Vec<DVec3> = (0..n)
        .map(|i| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let noise = if i == 0 || i == n - 1 {
                0.0
            } else {
                ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 8e-3
            };
            let x = 4.0 * i as f64 / (n - 1) as f64;
            DVec3::new(x, 0.5 * (1.2 * x).sin() + noise, 0.0)
        })
        .collect();
    let knots = fairway::KnotVector::uniform(3, n).unwrap().values().to_vec();
    let c = BSplineCurve::try_new(3, knots, pts, None, 2).unwrap();
    let bp = c.knots().breakpoints();
    let (a, rest) = split(&c, bp[9]).unwrap();
    let (b, cc) = split(&rest, bp[18]).unwrap();
    vec![a, b, cc]
}

fn write_chain(path: &Path) -> Scene {
    let names = ["BOW", "MID", "STERN"];
    let scene = Scene {
        objects: chain()
            .into_iter()
            .zip(names)
            .map(|(c, n)| SceneObject {
                name: n.into(),
                trim: None,
                geometry: c.into(),
                settings: DocumentSettings::default(),
            })
            .collect(),
        unit: Some(Unit::Millimeter),
        ..Default::default()
    };
    save_scene(path, &scene).unwrap();
    scene
}

#[test]
fn info_lists_the_joins_as_text_and_json() {
    let sc = Scratch::new("info");
    let igs = sc.path("chain.igs");
    write_chain(&igs);
    let (text, err) = run_ok(&["info", s(&igs)]);
    assert!(err.contains("3 objects, using number 0"), "{err}");
    assert!(
        text.contains("objects         3: 0 curve \"BOW\", 1 curve \"MID\", 2 curve \"STERN\""),
        "{text}"
    );
    assert!(text.contains("joins           2"), "{text}");
    assert_eq!(text.matches(": G2  gap").count(), 2, "{text}");
    let (json, _) = run_ok(&["info", s(&igs), "--json"]);
    let v: Value = serde_json::from_str(&json).unwrap();
    let joins = v["network"]["curve_joins"].as_array().unwrap();
    assert_eq!(joins.len(), 2);
    assert_eq!(joins[0]["continuity"], "G2");
    assert_eq!(joins[0]["objects"], serde_json::json!([0, 1]));
    assert_eq!(joins[0]["ends"], serde_json::json!(["end", "start"]));
    assert!(joins[0]["angle_deg"].as_f64().unwrap() < 1e-9);
    assert_eq!(v["network"]["objects"][2]["name"], "STERN");
}

#[test]
fn fair_on_a_file_with_several_objects_fairs_them_all_keeping_the_joins() {
    let sc = Scratch::new("fair");
    let igs = sc.path("chain.igs");
    let scene = write_chain(&igs);
    let (out, rep) = (sc.path("faired.igs"), sc.path("report.json"));
    let m = "0.004";
    let (_, err) = run_ok(&["fair", s(&igs), "--tolerance", m, "-o", s(&out), "--report", s(&rep)]);
    assert!(err.contains("3 objects, fairing all together"), "{err}");
    let (back, _) = load_scene(&out).unwrap();
    assert_eq!(back.names(), scene.names(), "names and order kept");
    assert_eq!(back.unit, Some(Unit::Millimeter));
    let joins = find_joins(&back.geometries());
    assert_eq!(joins.curves.len(), 2);
    for j in &joins.curves {
        let c = j.continuity;
        assert_eq!(c.class, Continuity::G2, "{c:?}");
        assert!(c.angle <= 1e-9 && c.curvature_jump <= 1e-9, "{c:?}");
    }
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
    assert_eq!(v["kind"], "scene");
    let objects = v["objects"].as_array().unwrap();
    assert_eq!(objects.len(), 3);
    let mut extrema = (0, 0);
    for (o, orig) in objects.iter().zip(&scene.objects) {
        assert_eq!(o["faired"], true, "{o}");
        assert_eq!(o["group"], serde_json::json!([0, 1, 2]));
        assert!(o["measures"]["dev_max"].as_f64().unwrap() <= 0.004);
        extrema.1 += o["measures"]["n_curv_extrema"].as_u64().unwrap();
        let c = orig.geometry.as_curve().unwrap();
        extrema.0 += fairway::measure::measure(c, c).n_curv_extrema as u64;
    }
    assert!(extrema.1 < extrema.0, "curvature extrema {extrema:?}");
    for j in v["curve_joins"].as_array().unwrap() {
        assert_eq!(j["kept"], true, "{j}");
        assert_eq!(
            (j["before"]["continuity"].as_str(), j["after"]["continuity"].as_str()),
            (Some("G2"), Some("G2"))
        );
    }
    assert!(
        v["notes"][0].as_str().unwrap().contains("concatenated"),
        "{}",
        v["notes"]
    );
    // a .ron document of version 2 in and out
    let ron = sc.path("chain.ron");
    save_scene(&ron, &scene).unwrap();
    let ron_out = sc.path("faired.ron");
    run_ok(&["fair", s(&ron), "--tolerance", m, "-o", s(&ron_out)]);
    assert_eq!(load_scene(&ron_out).unwrap().0.objects.len(), 3);
    // JSON holds one object: refused before any work
    run_fails(
        &["fair", s(&igs), "--tolerance", m, "-o", s(&sc.path("x.json"))],
        &["x.json", "holds one object", "--index"],
    );
    assert!(!sc.path("x.json").exists());
}

#[test]
fn object_picks_what_is_faired_and_index_still_fairs_one_object_alone() {
    let sc = Scratch::new("object");
    let stp = sc.path("chain.stp");
    let scene = write_chain(&stp);
    let out = sc.path("mid.stp");
    let (_, err) = run_ok(&[
        "fair",
        s(&stp),
        "--tolerance",
        "0.004",
        "-o",
        s(&out),
        "--object",
        "MID",
    ]);
    assert!(
        err.contains("held"),
        "the joins with the curves not faired are held: {err}"
    );
    let (back, _) = load_scene(&out).unwrap();
    assert_eq!(
        back.objects[0].geometry, scene.objects[0].geometry,
        "not chosen: bit-exact"
    );
    assert_eq!(back.objects[2].geometry, scene.objects[2].geometry);
    assert_ne!(back.objects[1].geometry, scene.objects[1].geometry, "chosen: faired");
    for (b, a) in find_joins(&scene.geometries())
        .curves
        .iter()
        .zip(find_joins(&back.geometries()).curves)
    {
        assert!(a.continuity.class >= b.continuity.class, "{a:?}");
        assert!(a.continuity.gap <= 1e-12 && a.continuity.angle <= 1e-9, "{a:?}");
    }
    // by index, repeated
    run_ok(&[
        "fair",
        s(&stp),
        "--tolerance",
        "0.004",
        "-o",
        s(&out),
        "--object",
        "0",
        "--object",
        "2",
    ]);
    run_fails(
        &[
            "fair",
            s(&stp),
            "--tolerance",
            "0.004",
            "-o",
            s(&out),
            "--object",
            "KEEL",
        ],
        &["--object KEEL", "holds no such object", "\"STERN\""],
    );
    // --index: the one object alone, written alone (as before)
    let one = sc.path("one.json");
    run_ok(&["fair", s(&stp), "--tolerance", "0.004", "-o", s(&one), "--index", "1"]);
    let g: Geometry = fairway::io::load_geometry(&one).unwrap();
    assert!(g.as_curve().is_some());
}

/// The bundled bumpy surface split across u into two patches (the edge C2: G2).
fn two_patches() -> Vec<Geometry> {
    use fairway::BSplineSurface;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/bumpy_surface.json");
    let s = fairway::io::load_geometry(&path).unwrap().as_surface().unwrap().clone();
    let u = s.knots_u().values()[10];
    let (mut left, mut right) = (vec![], vec![]);
    for j in 0..s.nv() {
        let pts = (0..s.nu()).map(|i| s.point_at(i, j)).collect();
        let c = BSplineCurve::try_new(3, s.knots_u().values().to_vec(), pts, None, 3).unwrap();
        let (l, r) = split(&c, u).unwrap();
        left.push(l);
        right.push(r);
    }
    let net = |cs: &[BSplineCurve]| -> Geometry {
        let (nu, nv) = (cs[0].n_points(), cs.len());
        let pts = (0..nu).flat_map(|i| (0..nv).map(move |j| cs[j].points()[i])).collect();
        BSplineSurface::try_new(
            3,
            3,
            cs[0].knots().values().to_vec(),
            s.knots_v().values().to_vec(),
            nu,
            nv,
            pts,
            None,
        )
        .unwrap()
        .into()
    };
    vec![net(&left), net(&right)]
}

#[test]
fn patches_sharing_an_edge_are_listed_and_faired_together() {
    let sc = Scratch::new("patches");
    let stp = sc.path("patches.stp");
    let scene = Scene {
        objects: two_patches()
            .into_iter()
            .zip(["PORT", "STARBOARD"])
            .map(|(g, n)| SceneObject {
                name: n.into(),
                trim: None,
                geometry: g,
                settings: DocumentSettings::default(),
            })
            .collect(),
        unit: None,
        ..Default::default()
    };
    save_scene(&stp, &scene).unwrap();
    let (text, _) = run_ok(&["info", s(&stp)]);
    assert!(text.contains("surface 0 u1 – surface 1 u0: G2"), "{text}");
    let (out, rep) = (sc.path("out.stp"), sc.path("rep.json"));
    run_ok(&[
        "fair",
        s(&stp),
        "--tolerance",
        "0.004",
        "-o",
        s(&out),
        "--report",
        s(&rep),
    ]);
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
    let e = &v["surface_joins"][0];
    assert_eq!(e["kept"], true, "{e}");
    assert!(e["after"]["normal_angle_deg"].as_f64().unwrap() <= 0.01, "{e}");
    for o in v["objects"].as_array().unwrap() {
        assert_eq!(o["group"], serde_json::json!([0, 1]));
        assert!(o["measures"]["hausdorff"].as_f64().unwrap() <= 0.004);
        assert!(o["measures"]["n_curv_extrema"].as_u64().unwrap() < 60, "{o}");
    }
    assert_eq!(load_scene(&out).unwrap().0.names(), vec!["PORT", "STARBOARD"]);
}

/// `s` cut across u at its knot `u` (each curve along u split there, exact): the two patches.
fn halves(s: &fairway::BSplineSurface, u: f64) -> [fairway::BSplineSurface; 2] {
    let (mut left, mut right) = (vec![], vec![]);
    for j in 0..s.nv() {
        let pts = (0..s.nu()).map(|i| s.point_at(i, j)).collect();
        let c = BSplineCurve::try_new(3, s.knots_u().values().to_vec(), pts, None, 3).unwrap();
        let (l, r) = split(&c, u).unwrap();
        left.push(l);
        right.push(r);
    }
    [left, right].map(|cs| {
        let cs = &cs;
        let (nu, nv) = (cs[0].n_points(), cs.len());
        let pts = (0..nu).flat_map(|i| (0..nv).map(move |j| cs[j].points()[i])).collect();
        let k = (cs[0].knots().values().to_vec(), s.knots_v().values().to_vec());
        fairway::BSplineSurface::try_new(3, 3, k.0, k.1, nu, nv, pts, None).unwrap()
    })
}

#[test]
fn a_two_by_two_grid_of_patches_is_faired_as_one_keeping_every_edge() {
    let sc = Scratch::new("grid");
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/bumpy_surface.json");
    let whole = fairway::io::load_geometry(&path).unwrap().as_surface().unwrap().clone();
    let (u, v) = (whole.knots_u().values()[12], whole.knots_v().values()[10]);
    let patches: Vec<fairway::BSplineSurface> = halves(&whole, u)
        .iter()
        .flat_map(|h| halves(&h.transposed(), v).map(|p| p.transposed()))
        .collect();
    let ron = sc.path("grid.ron");
    let scene = Scene {
        objects: patches
            .into_iter()
            .zip(["A", "B", "C", "D"])
            .map(|(g, n)| SceneObject {
                name: n.into(),
                trim: None,
                geometry: g.into(),
                settings: DocumentSettings::default(),
            })
            .collect(),
        unit: None,
        ..Default::default()
    };
    save_scene(&ron, &scene).unwrap();
    let (out, rep) = (sc.path("out.ron"), sc.path("rep.json"));
    let (_, err) = run_ok(&[
        "fair",
        s(&ron),
        "--tolerance",
        "0.004",
        "-o",
        s(&out),
        "--report",
        s(&rep),
    ]);
    assert!(err.contains("a 2 × 2 grid of patches"), "{err}");
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
    let edges = v["surface_joins"].as_array().unwrap();
    assert_eq!(edges.len(), 4, "{v}");
    for e in edges {
        assert_eq!(e["kept"], true, "{e}");
        assert!(e["after"]["normal_angle_deg"].as_f64().unwrap() <= 0.01, "{e}");
    }
    let mut bounds = vec![];
    for o in v["objects"].as_array().unwrap() {
        assert_eq!(o["group"], serde_json::json!([0, 1, 2, 3]), "{o}");
        let (h, b) = (
            o["measures"]["hausdorff"].as_f64().unwrap(),
            o["max_deviation_bound"].as_f64().unwrap(),
        );
        // each patch's own bound: sound (not below its measured deviation) and within the band
        eprintln!("{}: deviation {h:.3e}, its own bound {b:.3e}", o["name"]);
        assert!(h <= b && b <= 0.004, "{o}");
        assert!(
            o["notes"]
                .as_array()
                .unwrap()
                .iter()
                .any(|n| n.as_str().unwrap().contains("its own deviation bound")),
            "{o}"
        );
        bounds.push(b);
    }
    // not one figure for the grid: the patches moved by different amounts
    assert!(bounds.iter().any(|&b| b != bounds[0]), "{bounds:?}");
    assert!(err.contains("its deviation ≤ "), "{err}");
    let (back, _) = load_scene(&out).unwrap();
    assert_eq!(back.names(), vec!["A", "B", "C", "D"]);
    let after = find_joins(&back.geometries());
    assert!(
        after.surfaces.iter().all(|j| j.continuity.class == Continuity::G2),
        "{after:?}"
    );
}

/// The deviation of each object of `out` from the same object of `scene` (`fairway::measure`).
fn deviations(scene: &Scene, out: &Path) -> Vec<f64> {
    let (back, _) = load_scene(out).unwrap();
    scene
        .objects
        .iter()
        .zip(&back.objects)
        .map(|(a, b)| fairway::measure::measure(a.geometry.as_curve().unwrap(), b.geometry.as_curve().unwrap()).dev_max)
        .collect()
}

#[test]
fn fair_uses_each_objects_saved_tolerance_unless_tolerance_is_given() {
    let sc = Scratch::new("saved-tolerances");
    // the chain's first and last curves: two objects that do not meet, each with its own tolerance
    let mut pieces = chain();
    let (bow, stern) = (pieces.remove(0), pieces.remove(1));
    let (m_bow, m_stern) = (0.001, 0.006);
    let object = |name: &str, c: BSplineCurve, m: f64| SceneObject {
        name: name.into(),
        trim: None,
        geometry: c.into(),
        settings: DocumentSettings {
            tolerance: Some(m),
            ..Default::default()
        },
    };
    let scene = Scene {
        objects: vec![object("BOW", bow, m_bow), object("STERN", stern, m_stern)],
        ..Default::default()
    };
    let ron = sc.path("two.ron");
    save_scene(&ron, &scene).unwrap();
    let (out, rep) = (sc.path("out.ron"), sc.path("rep.json"));
    let (_, err) = run_ok(&["fair", s(&ron), "-o", s(&out), "--report", s(&rep)]);
    assert!(
        err.contains("object 0 \"BOW\": tolerance 0.001 (saved in the document"),
        "{err}"
    );
    let dev = deviations(&scene, &out);
    eprintln!("saved tolerances {m_bow}, {m_stern}: deviations {dev:?}");
    assert!(dev[0] <= m_bow, "BOW within its own tolerance: {dev:?}");
    assert!(dev[1] <= m_stern, "STERN within its own tolerance: {dev:?}");
    assert!(dev[1] > m_bow, "STERN used its wider band, not BOW's: {dev:?}");
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
    assert_eq!(v["tolerance"], Value::Null, "no --tolerance: {v}");
    for (o, m) in v["objects"].as_array().unwrap().iter().zip([m_bow, m_stern]) {
        assert_eq!(o["tolerance"].as_f64(), Some(m), "{o}");
        assert_eq!(o["tolerance_from"], "document", "{o}");
        assert!(o["measures"]["dev_max"].as_f64().unwrap() <= m, "{o}");
    }
    // --tolerance overrides both
    let m = 0.002;
    let (_, err) = run_ok(&[
        "fair",
        s(&ron),
        "--tolerance",
        "0.002",
        "-o",
        s(&out),
        "--report",
        s(&rep),
    ]);
    assert!(!err.contains("saved in the document"), "{err}");
    let dev = deviations(&scene, &out);
    eprintln!("--tolerance {m}: deviations {dev:?}");
    assert!(dev.iter().all(|&d| d <= m), "both within --tolerance: {dev:?}");
    assert!(dev[0] > m_bow, "BOW used --tolerance, not its saved one: {dev:?}");
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
    assert_eq!(v["tolerance"].as_f64(), Some(m));
    for o in v["objects"].as_array().unwrap() {
        assert_eq!(o["tolerance"].as_f64(), Some(m), "{o}");
        assert_eq!(o["tolerance_from"], "command line", "{o}");
    }
}

#[test]
fn a_single_object_document_is_faired_at_its_saved_tolerance_and_a_bare_file_asks_for_one() {
    let sc = Scratch::new("one-saved-tolerance");
    let c = chain().remove(1);
    let m = 0.0015;
    let doc = fairway::io::Document {
        geometry: c.clone().into(),
        settings: DocumentSettings {
            tolerance: Some(m),
            ..Default::default()
        },
    };
    let ron = sc.path("one.ron");
    fairway::io::save(&ron, &doc).unwrap();
    let (out, rep) = (sc.path("out.json"), sc.path("rep.json"));
    let (_, err) = run_ok(&["fair", s(&ron), "-o", s(&out), "--report", s(&rep)]);
    assert!(err.contains("tolerance 0.0015 (saved in the document"), "{err}");
    let faired = fairway::io::load_geometry(&out).unwrap();
    let dev = fairway::measure::measure(&c, faired.as_curve().unwrap()).dev_max;
    eprintln!("saved tolerance {m}: deviation {dev}");
    assert!(
        dev <= m && dev > 0.5 * m,
        "faired within its saved band, using it: {dev}"
    );
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
    assert_eq!(v["tolerance"].as_f64(), Some(m));
    assert_eq!(v["tolerance_from"], "document");
    // a bare geometry file saves no tolerance: asked for one
    let json = sc.path("bare.json");
    fairway::io::save(&json, &fairway::io::Document::new(c.into())).unwrap();
    run_fails(
        &["fair", s(&json), "-o", s(&sc.path("x.json"))],
        &["bare.json saves no tolerance", "give one with --tolerance"],
    );
    // an IGES file with several objects names them all
    let igs = sc.path("chain.igs");
    write_chain(&igs);
    run_fails(
        &["fair", s(&igs), "-o", s(&sc.path("x.igs"))],
        &[
            "chain.igs saves no tolerance for object 0 \"BOW\", object 1 \"MID\", object 2 \"STERN\"",
            "--tolerance",
        ],
    );
    assert!(!sc.path("x.json").exists() && !sc.path("x.igs").exists());
}

#[test]
fn an_l_of_patches_in_an_iges_file_takes_the_layout_route_and_keeps_its_edges() {
    let sc = Scratch::new("layout");
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/bumpy_surface.json");
    let whole = fairway::io::load_geometry(&path).unwrap().as_surface().unwrap().clone();
    let (u, v) = (whole.knots_u().values()[12], whole.knots_v().values()[10]);
    // the 2 × 2 grid cut from the bumpy surface, less its last patch: an L of three, its edges G2
    let mut patches: Vec<fairway::BSplineSurface> = halves(&whole, u)
        .iter()
        .flat_map(|h| halves(&h.transposed(), v).map(|p| p.transposed()))
        .collect();
    patches.pop();
    let igs = sc.path("l.igs");
    let scene = Scene {
        objects: patches
            .iter()
            .zip(["CORNER", "EAST", "NORTH"])
            .map(|(g, n)| SceneObject {
                name: n.into(),
                geometry: g.clone().into(),
                settings: DocumentSettings::default(),
                trim: None,
            })
            .collect(),
        unit: Some(Unit::Millimeter),
        ..Default::default()
    };
    save_scene(&igs, &scene).unwrap();
    let (out, rep) = (sc.path("out.igs"), sc.path("rep.json"));
    let m = 0.004;
    let (_, err) = run_ok(&[
        "fair",
        s(&igs),
        "--tolerance",
        "0.004",
        "-o",
        s(&out),
        "--report",
        s(&rep),
    ]);
    assert!(err.contains("object 0: route layout (with objects [0, 1, 2])"), "{err}");
    assert!(err.contains("a layout of 3 patches"), "{err}");
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
    let edges = v["surface_joins"].as_array().unwrap();
    assert_eq!(edges.len(), 2, "{v}");
    for e in edges {
        eprintln!("edge before {} after {}", e["before"], e["after"]);
        assert_eq!(e["before"]["continuity"], "G2", "{e}");
        assert_eq!(e["after"]["continuity"], "G2", "{e}");
        assert_eq!(e["kept"], true, "{e}");
        assert!(e["after"]["normal_angle_deg"].as_f64().unwrap() <= 0.01, "{e}");
    }
    let (back, _) = load_scene(&out).unwrap();
    assert_eq!(back.names(), vec!["CORNER", "EAST", "NORTH"]);
    for ((o, p), b) in v["objects"]
        .as_array()
        .unwrap()
        .iter()
        .zip(&patches)
        .zip(back.geometries())
    {
        assert_eq!(o["route"], "layout", "{o}");
        assert_eq!(o["group"], serde_json::json!([0, 1, 2]), "{o}");
        let before = fairway::measure_surface::surface_measures(p, p).n_curv_extrema as u64;
        let after = o["measures"]["n_curv_extrema"].as_u64().unwrap();
        // independently of the report: the patch read back, against the original
        let mine = fairway::measure_surface::surface_measures(p, b.as_surface().unwrap());
        eprintln!(
            "{}: isocurve extrema {before} → {after}, deviation {:.2e}",
            o["name"], mine.hausdorff
        );
        assert!(after < before, "{o}");
        assert!(mine.hausdorff <= m, "{}", mine.hausdorff);
    }
}
