//! Documents with many objects (issue 30, item 1): RON version 2, and IGES/STEP files with several
//! objects read into one scene and written back in order with their names, bit-exact.

use fairway::io::{Document, DocumentSettings, Scene, SceneObject, Unit, load_scene, save_scene};
use fairway::{BSplineCurve, BSplineSurface, DVec2, DVec3, Geometry};

fn curve2d(shift: f64) -> BSplineCurve {
    let pts: Vec<DVec2> = (0..7)
        .map(|i| DVec2::new(i as f64 * 0.37 + shift, (i as f64 * 0.9).sin() * 0.731 + 1.0 / 3.0))
        .collect();
    BSplineCurve::new_2d(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 0.25, 1.0 / 3.0, 0.7, 1.0, 1.0, 1.0, 1.0],
        &pts,
    )
    .unwrap()
}

fn curve3d() -> BSplineCurve {
    let pts: Vec<DVec3> = (0..6)
        .map(|i| DVec3::new(i as f64 * 0.1, (i as f64).cos() * 1e-3, 0.1 * i as f64 * i as f64 + 0.1))
        .collect();
    BSplineCurve::new_3d(4, vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.41, 1.7, 1.7, 1.7, 1.7, 1.7], pts).unwrap()
}

fn surface() -> BSplineSurface {
    let (nu, nv) = (5, 4);
    let pts: Vec<DVec3> = (0..nu)
        .flat_map(|i| {
            (0..nv).map(move |j| DVec3::new(i as f64 / 3.0, j as f64 * 0.7, ((i * j) as f64 * 0.77).sin() / 7.0))
        })
        .collect();
    BSplineSurface::try_new(
        3,
        2,
        vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0],
        vec![0.0, 0.0, 0.0, 0.3, 1.0, 1.0, 1.0],
        nu,
        nv,
        pts,
        None,
    )
    .unwrap()
}

fn scene() -> Scene {
    let obj = |name: &str, g: Geometry| SceneObject {
        name: name.into(),
        trim: None,
        geometry: g,
        settings: DocumentSettings::default(),
    };
    Scene {
        objects: vec![
            obj("SHEER", curve2d(0.0).into()),
            obj("DECK", surface().into()),
            obj("CHINE(2)", curve3d().into()),
            obj("KEEL", curve2d(5.0).into()),
        ],
        unit: Some(Unit::Millimeter),
        ..Default::default()
    }
}

fn tmp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("fairway-scene-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Every object, its name and the order kept, the geometry bit-exact; and written again, the same file.
fn round_trip(ext: &str) {
    let s = scene();
    let path = tmp(&format!("many.{ext}"));
    save_scene(&path, &s).unwrap();
    let (back, notices) = load_scene(&path).unwrap();
    assert!(notices.is_empty(), "{notices:?}");
    assert_eq!(back.objects.len(), 4);
    for (a, b) in s.objects.iter().zip(&back.objects) {
        assert_eq!(a.name, b.name, "{ext}: names in order");
        assert_eq!(a.geometry, b.geometry, "{ext}: {} bit-exact", a.name);
    }
    assert_eq!(back.unit, Some(Unit::Millimeter));
    // written back unchanged: the same objects again (and the same bytes but for the time stamp)
    let again = tmp(&format!("again.{ext}"));
    save_scene(&again, &back).unwrap();
    let (third, _) = load_scene(&again).unwrap();
    assert_eq!(third, back);
}

#[test]
fn iges_with_many_objects_round_trips_bit_exact_with_labels() {
    round_trip("igs");
}

#[test]
fn step_with_many_objects_round_trips_bit_exact_with_names() {
    round_trip("stp");
}

#[test]
fn ron_version_2_round_trips_and_keeps_each_objects_settings() {
    let mut s = scene();
    s.objects[1].settings.tolerance = Some(0.002);
    s.objects[2].settings.region = Some((0.2, 1.1));
    let text = s.to_ron().unwrap();
    assert!(text.contains("version: 2"), "{text}");
    let back = Scene::from_ron(&text).unwrap();
    assert_eq!(back, s);
    let path = tmp("many.ron");
    save_scene(&path, &s).unwrap();
    assert_eq!(load_scene(&path).unwrap().0, s);
    // a single-object reader refuses several objects, naming the count
    let e = Document::from_ron(&text).unwrap_err().to_string();
    assert!(e.contains("4 objects"), "{e}");
    // JSON holds one object only
    assert!(save_scene(&tmp("many.json"), &s).is_err());
}

#[test]
fn old_version_1_documents_still_open_as_documents_and_scenes() {
    let mut doc = Document::new(curve2d(0.0).into());
    doc.settings.tolerance = Some(0.01);
    let v1 = doc.to_ron().unwrap();
    assert!(v1.contains("version: 1"), "{v1}");
    assert_eq!(Document::from_ron(&v1).unwrap(), doc);
    let s = Scene::from_ron(&v1).unwrap();
    assert_eq!(s.objects.len(), 1);
    assert_eq!(s.objects[0].geometry, doc.geometry);
    assert_eq!(s.objects[0].settings, doc.settings);
    // a hand-written version 1 file (as older Fairways saved them)
    let old = "(format: \"fairway\", version: 1, geometry: Curve((degree: 1, knots: [0.0, 0.0, 1.0, 1.0], \
               points: [[0.0, 0.0], [1.0, 2.0]])), settings: (tolerance: Some(0.5)))";
    assert_eq!(Scene::from_ron(old).unwrap().objects[0].settings.tolerance, Some(0.5));
    assert_eq!(Document::from_ron(old).unwrap().settings.tolerance, Some(0.5));
    // a version 2 file with one object opens as a document
    let one = Scene::from(doc.clone()).to_ron().unwrap();
    assert_eq!(Document::from_ron(&one).unwrap(), doc);
    // a version 3 is refused
    let e = Scene::from_ron(&one.replacen("version: 2", "version: 3", 1))
        .unwrap_err()
        .to_string();
    assert!(e.contains("version 3"), "{e}");
}

#[test]
fn the_view_plane_is_saved_in_version_2_and_optional() {
    use fairway::io::ViewPlane;
    // every choice round-trips through the text and a file
    for p in ViewPlane::ALL {
        let s = Scene {
            view_plane: p,
            ..scene()
        };
        let text = s.to_ron().unwrap();
        assert_eq!(
            text.contains("view_plane"),
            p != ViewPlane::Xy,
            "{p:?}: XY is the default, not written"
        );
        assert_eq!(Scene::from_ron(&text).unwrap(), s, "{p:?}");
        let path = tmp("plane.ron");
        save_scene(&path, &s).unwrap();
        assert_eq!(load_scene(&path).unwrap().0.view_plane, p);
    }
    let yz = Scene {
        view_plane: ViewPlane::Yz,
        ..scene()
    }
    .to_ron()
    .unwrap();
    assert!(yz.contains("view_plane: YZ"), "{yz}");
    // a file written before the field existed opens on XY
    let old = yz.replacen("view_plane: YZ,", "", 1);
    assert!(!old.contains("view_plane"), "{old}");
    let back = Scene::from_ron(&old).unwrap();
    assert_eq!(back.view_plane, ViewPlane::Xy);
    assert_eq!(back.objects, scene().objects);
    // an unknown plane is refused with the field's name
    let e = Scene::from_ron(&yz.replacen("view_plane: YZ", "view_plane: XW", 1))
        .unwrap_err()
        .to_string();
    assert!(e.contains("XW"), "{e}");
}
