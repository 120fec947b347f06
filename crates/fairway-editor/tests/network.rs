//! Documents with many objects (issue 30): a multi-curve IGES file opens as one document, a click on
//! a curve selects it, fairing it keeps its joins, undo steps back through the fair and the selection;
//! the join markers say their continuity; "Fair all (keep joins)" is one undo step; the view plane
//! choice changes what the canvas draws.

mod common;

use std::path::PathBuf;

use common::harness;
use eframe::egui;
use egui_kittest::kittest::{NodeT, Queryable};
use fairway::io::{DocumentSettings, Scene, SceneObject};
use fairway::network::{Continuity, find_joins};
use fairway::{BSplineCurve, DVec2, DVec3, Geometry};
use fairway_editor::App;
use fairway_editor::scene_view::ViewPlane;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fairway-network-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `c` split at its interior knot `u` (inserted to multiplicity p): the two pieces, exact.
fn split(c: &BSplineCurve, u: f64) -> (BSplineCurve, BSplineCurve) {
    let p = c.degree();
    let r = c.insert_knot(u, p - c.knots().multiplicity(u)).unwrap();
    let k = r.knots().values();
    let s = k.iter().position(|&x| x == u).unwrap();
    let pts = r.points();
    let mut left_k = k[..s + p].to_vec();
    left_k.push(u);
    let mut right_k = vec![u];
    right_k.extend_from_slice(&k[s..]);
    let piece = |kn: Vec<f64>, pts: &[DVec3]| BSplineCurve::try_new(p, kn, pts.to_vec(), None, 2).unwrap();
    (piece(left_k, &pts[..s]), piece(right_k, &pts[s - 1..]))
}

/// Five named curves: the noisy demo curve split into a G2 chain of three, a straight lead-in meeting
/// its start with G1 and a drop meeting its end at a corner (G0).
pub fn network_scene() -> Scene {
    let c = fairway_editor::demo_curve_n(40);
    let kn = c.knots().values().to_vec();
    let (u1, u2) = (kn[14], kn[28]);
    let (a, rest) = split(&c, u1);
    let (b, d) = split(&rest, u2);
    let (s0, t0) = (c.point(0.0), c.tangent(0.0));
    let lead = BSplineCurve::new_3d(1, vec![0.0, 0.0, 1.0, 1.0], vec![s0 - t0 * 0.4, s0]).unwrap();
    let lead = BSplineCurve::try_new(1, lead.knots().values().to_vec(), lead.points().to_vec(), None, 2).unwrap();
    let e = c.point(1.0);
    let drop = BSplineCurve::new_2d(
        1,
        vec![0.0, 0.0, 1.0, 1.0],
        &[e.truncate(), e.truncate() - DVec2::new(0.0, 0.3)],
    )
    .unwrap();
    let names = ["SECTA", "SECTB", "SECTC", "LEADIN", "DROP"];
    Scene {
        objects: [a, b, d, lead, drop]
            .into_iter()
            .zip(names)
            .map(|(c, n)| SceneObject {
                name: n.into(),
                geometry: c.into(),
                settings: DocumentSettings::default(),
            })
            .collect(),
        unit: None,
    }
}

fn write_network(dir: &std::path::Path) -> PathBuf {
    let path = dir.join("network.igs");
    fairway::io::save_scene(&path, &network_scene()).unwrap();
    // FAIRWAY_WRITE_NETWORK=path: also write the scene there (for the screenshot in the README)
    if let Some(out) = std::env::var_os("FAIRWAY_WRITE_NETWORK") {
        fairway::io::save_scene(std::path::Path::new(&out), &network_scene()).unwrap();
    }
    path
}

fn click(h: &mut egui_kittest::Harness<'static, App>, p: egui::Pos2) {
    h.hover_at(p);
    h.step();
    h.drag_at(p);
    h.step();
    h.drop_at(p);
    h.run();
}

fn joins_of(app: &App, object: usize) -> Vec<Continuity> {
    let geoms: Vec<Geometry> = app.objects_now().into_iter().map(|o| o.geometry).collect();
    find_joins(&geoms)
        .curves
        .iter()
        .filter(|j| j.a.object == object || j.b.object == object)
        .map(|j| j.continuity.class)
        .collect()
}

#[test]
fn a_multi_curve_file_opens_whole_a_click_selects_fairing_keeps_the_joins_and_undo_steps_back() {
    let dir = temp_dir("click");
    let path = write_network(&dir);
    let mut h = harness(App::default());
    h.state_mut().open_now(&path);
    h.run();
    let app = h.state();
    assert!(app.error.is_none(), "{:?}", app.error);
    assert!(app.object_pick.is_none(), "all objects open, no picker");
    assert_eq!(app.objects.len(), 5);
    assert_eq!(app.active, 0);
    assert_eq!(
        app.path.as_deref(),
        Some(std::fs::canonicalize(&path).unwrap().as_path())
    );
    let original = app.objects_now();
    // the objects panel lists them by their IGES labels
    h.get_by_label("2. SECTB");
    // the join markers on the canvas say their continuity (label; the measures on hover)
    let markers: Vec<String> = h
        .query_all_by_role(egui::accesskit::Role::Image)
        .filter_map(|n| n.accesskit_node().label())
        .collect();
    for m in [
        "G2 join: SECTA end – SECTB start",
        "G2 join: SECTB end – SECTC start",
        "G1 join: LEADIN end – SECTA start",
        "G0 join: SECTC end – DROP start",
    ] {
        assert!(markers.iter().any(|l| l == m), "{m:?} not in {markers:?}");
    }
    h.get_by_role_and_label(egui::accesskit::Role::Image, "G1 join: LEADIN end – SECTA start")
        .hover();
    h.run();
    h.get_by_label_contains("G1: gap");
    h.get_by_label_contains("curvature ratio");

    // click on the second curve (its middle, on the canvas) selects it: one undo step
    let p = {
        let ws = &h.state().curve_ws;
        let c = ws.scene.curves.iter().find(|c| c.object == 1).unwrap();
        ws.canvas.to_screen(c.pts[c.pts.len() / 2])
    };
    click(&mut h, p);
    assert_eq!(h.state().active, 1, "{}", h.state().status);
    assert!(h.state().history.can_undo());
    assert_eq!(h.state().doc.geometry, original[1].geometry);

    // fair it whole: both ends are G2 joins, kept G2 by default
    h.get_by_label("Whole curve").click();
    h.run();
    assert_eq!(h.state().curve_ws.view.domain, h.state().curve().domain());
    h.get_by_label_contains("Start: a curve end at a join, kept G2");
    h.get_by_label("Accept").click();
    h.run();
    let app = h.state();
    assert_ne!(app.doc.geometry, original[1].geometry, "{}", app.status);
    assert_eq!(joins_of(app, 1), vec![Continuity::G2; 2], "both joins still G2");
    assert_eq!(app.objects_now()[0], original[0], "the neighbours are untouched");

    // undo: the fair, the region, then the selection
    h.state_mut().apply(fairway_editor::Command::Undo);
    h.run();
    assert_eq!(h.state().active, 1);
    assert_eq!(h.state().doc.geometry, original[1].geometry);
    assert!(h.state().region().is_some());
    h.state_mut().apply(fairway_editor::Command::Undo);
    h.run();
    assert_eq!(h.state().objects_now(), original);
    h.state_mut().apply(fairway_editor::Command::Undo);
    h.run();
    assert_eq!(h.state().active, 0);
    assert!(!h.state().is_dirty());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn fair_all_keeps_the_joins_in_one_undo_step_and_saves_every_object_with_its_label() {
    let dir = temp_dir("all");
    let path = write_network(&dir);
    let mut h = harness(App::default());
    h.state_mut().open_now(&path);
    h.run();
    let original = h.state().objects_now();
    h.get_by_label("Fair all (keep joins)").click();
    h.run();
    let app = h.state();
    assert!(app.error.is_none(), "{:?}", app.error);
    assert!(app.status.starts_with("Fair all:"), "{}", app.status);
    let after = app.objects_now();
    assert_ne!(after, original);
    let geoms: Vec<Geometry> = after.iter().map(|o| o.geometry.clone()).collect();
    let before: Vec<Geometry> = original.iter().map(|o| o.geometry.clone()).collect();
    let classes = |g: &[Geometry]| {
        find_joins(g)
            .curves
            .iter()
            .map(|j| j.continuity.class)
            .collect::<Vec<_>>()
    };
    assert_eq!(classes(&geoms), classes(&before), "every join keeps its continuity");
    // saved: every object, in order, with its label
    let out = dir.join("faired.igs");
    h.state_mut().apply(fairway_editor::Command::SaveTo(out.clone()));
    let (back, _) = fairway::io::load_scene(&out).unwrap();
    assert_eq!(back.names(), ["SECTA", "SECTB", "SECTC", "LEADIN", "DROP"]);
    assert_eq!(back.geometries(), geoms);
    assert!(!h.state().is_dirty());
    // one undo step
    h.state_mut().apply(fairway_editor::Command::Undo);
    h.run();
    assert_eq!(h.state().objects_now(), original);
    assert!(!h.state().history.can_undo());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_view_plane_choice_draws_a_yz_curve_flat_on_xy_and_whole_on_yz() {
    // an S-curve in the plane x = 0.2
    let pts = vec![
        DVec3::new(0.2, 0.0, 0.0),
        DVec3::new(0.2, 0.4, 0.5),
        DVec3::new(0.2, 0.8, -0.5),
        DVec3::new(0.2, 1.2, 0.0),
    ];
    let c = BSplineCurve::new_3d(3, vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0], pts).unwrap();
    let doc = fairway::io::Document::new(Geometry::Curve(c));
    let mut h = harness(App::with_document(doc, None));
    let extent = |h: &egui_kittest::Harness<'static, App>| {
        let (a, b) = h.state().curve_ws.view.sampled.bbox;
        b - a
    };
    let e = extent(&h);
    assert!(e.x < 1e-12, "flat on XY: {e:?}");
    h.get_by_label("View").click();
    h.run();
    h.get_by_label("YZ plane").click();
    h.run();
    assert_eq!(h.state().view_plane, ViewPlane::Yz);
    let e = extent(&h);
    assert!((e.x - 1.2).abs() < 1e-9 && e.y > 0.2, "whole on YZ: {e:?}");
    // the best-fit plane finds it too
    h.state_mut()
        .apply(fairway_editor::Command::SetViewPlane(ViewPlane::BestFit));
    h.run();
    let e = extent(&h);
    assert!(e.x > 1.0 && e.y > 0.2, "whole on the best-fit plane: {e:?}");
}

#[test]
fn a_document_of_many_objects_is_autosaved_and_restored_whole() {
    let dir = temp_dir("autosave");
    let path = write_network(&dir);
    let mut app = App::default().with_autosave(dir.join("autosave"));
    app.open_now(&path);
    app.apply(fairway_editor::Command::Select(2));
    app.apply(fairway_editor::Command::SetTolerance(2e-3));
    assert!(app.is_dirty());
    app.autosave_tick(std::time::Instant::now());
    let r = fairway_editor::autosave::pending(&dir.join("autosave"))
        .unwrap()
        .unwrap();
    assert_eq!(r.objects, app.objects_now(), "every object, named, with its settings");
    let mut back = App::default();
    back.recovery = Some(r);
    back.apply(fairway_editor::Command::RestoreAutosave);
    assert_eq!(back.objects_now(), app.objects_now());
    assert!(back.is_dirty(), "against the file on disk");
    let _ = std::fs::remove_dir_all(&dir);
}
