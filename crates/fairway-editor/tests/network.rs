//! Documents with many objects (issue 30): a multi-curve IGES file opens as one document, a click on
//! a curve selects it, fairing it keeps its joins, undo steps back through the fair and the selection;
//! the join markers say their continuity; "Fair all (keep joins)" is one undo step; the view plane
//! choice changes what the canvas draws, is saved with the document and is an undo step.

mod common;

use std::path::PathBuf;

use common::{harness, harness_without_waiting};
use eframe::egui;
use egui_kittest::kittest::{NodeT, Queryable};
use fairway::fair::network::fair_network_at;
use fairway::io::{DocumentSettings, Scene, SceneObject};
use fairway::network::{Continuity, find_joins};
use fairway::{BSplineCurve, DVec2, DVec3, Geometry};
use fairway_editor::scene_view::ViewPlane;
use fairway_editor::{App, Command};

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
                trim: None,
                geometry: c.into(),
                settings: DocumentSettings::default(),
            })
            .collect(),
        ..Default::default()
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

#[test]
fn the_view_plane_is_saved_with_the_document_reopens_and_undoes() {
    use fairway_editor::Command;
    let dir = temp_dir("plane");
    let path = write_network(&dir);
    let mut h = harness(App::default());
    h.state_mut().open_now(&path);
    h.run();
    assert_eq!(h.state().view_plane, ViewPlane::Xy, "an IGES file saves no plane: XY");
    assert!(!h.state().is_dirty());
    // chosen in the View menu: an undo step, and the document changed
    h.get_by_label("View").click();
    h.run();
    h.get_by_label("YZ plane").click();
    h.run();
    let app = h.state_mut();
    assert_eq!(
        (app.view_plane, app.curve_ws.scene.plane),
        (ViewPlane::Yz, ViewPlane::Yz)
    );
    assert!(app.is_dirty() && app.history.can_undo());
    app.apply(Command::Undo);
    assert_eq!(
        (app.view_plane, app.curve_ws.scene.plane),
        (ViewPlane::Xy, ViewPlane::Xy)
    );
    assert!(!app.is_dirty(), "back as opened");
    app.apply(Command::Redo);
    assert_eq!(app.view_plane, ViewPlane::Yz);
    // saved with the document, and restored when it is opened again
    let ron = dir.join("network.ron");
    app.apply(Command::SaveTo(ron.clone()));
    assert!(app.error.is_none(), "{:?}", app.error);
    assert!(!app.is_dirty());
    let text = std::fs::read_to_string(&ron).unwrap();
    assert!(text.contains("view_plane: YZ"), "{text}");
    let objects = app.objects_now();
    let mut back = App::default();
    back.open_now(&ron);
    assert!(back.error.is_none(), "{:?}", back.error);
    assert_eq!(
        (back.view_plane, back.curve_ws.scene.plane),
        (ViewPlane::Yz, ViewPlane::Yz)
    );
    assert_eq!(back.objects_now(), objects);
    assert!(!back.is_dirty() && !back.history.can_undo());
    // one curve: a plain (version 1) document on XY, a version 2 one to keep another plane
    let mut one = App::default();
    let file = dir.join("one.ron");
    one.apply(Command::SetViewPlane(ViewPlane::Zx));
    one.apply(Command::SaveTo(file.clone()));
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("version: 2") && text.contains("view_plane: ZX"), "{text}");
    let mut again = App::default();
    again.open_now(&file);
    assert_eq!(again.view_plane, ViewPlane::Zx);
    assert_eq!(again.objects_now(), one.objects_now());
    again.apply(Command::SetViewPlane(ViewPlane::Xy));
    again.apply(Command::SaveTo(file.clone()));
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("version: 1") && !text.contains("view_plane"), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The bundled bumpy surface split across u into two patches sharing a G2 edge, named.
fn two_patches() -> Scene {
    let path = common::asset("bumpy_surface.json");
    let s = fairway::io::load_geometry(&path).unwrap().as_surface().unwrap().clone();
    let u = s.knots_u().values()[10];
    let (mut left, mut right) = (vec![], vec![]);
    for j in 0..s.nv() {
        let pts = (0..s.nu()).map(|i| s.point_at(i, j)).collect();
        let row = BSplineCurve::try_new(3, s.knots_u().values().to_vec(), pts, None, 3).unwrap();
        let (l, r) = fairway::fair::closed::split(&row, u).unwrap();
        left.push(l);
        right.push(r);
    }
    let net = |rows: &[BSplineCurve]| -> Geometry {
        let (nu, nv) = (rows[0].n_points(), rows.len());
        let pts = (0..nu)
            .flat_map(|i| (0..nv).map(move |j| rows[j].points()[i]))
            .collect();
        let k = (rows[0].knots().values().to_vec(), s.knots_v().values().to_vec());
        fairway::BSplineSurface::try_new(3, 3, k.0, k.1, nu, nv, pts, None)
            .unwrap()
            .into()
    };
    Scene {
        objects: [("PORT", net(&left)), ("STARBOARD", net(&right))]
            .into_iter()
            .map(|(n, geometry)| SceneObject {
                name: n.into(),
                trim: None,
                geometry,
                settings: DocumentSettings::default(),
            })
            .collect(),
        ..Default::default()
    }
}

/// The labels of the markers (images) shown.
fn marker_labels(h: &egui_kittest::Harness<'static, App>) -> Vec<String> {
    h.query_all_by_role(egui::accesskit::Role::Image)
        .filter_map(|n| n.accesskit_node().label())
        .collect()
}

#[test]
fn the_3d_views_mark_curve_joins_and_shared_patch_edges() {
    let dir = temp_dir("marks3d");
    curve_view_marks_every_join(&dir);
    surface_view_marks_a_shared_edge(&dir);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The network's joins in the 3D curve view, each where it projects, and none for a curve alone.
fn curve_view_marks_every_join(dir: &std::path::Path) {
    let mut h = harness(App::default());
    h.state_mut().open_now(&write_network(dir));
    h.run();
    h.get_by_label("3D view").click();
    h.run();
    let view = h.get_by_label("3D curve view").rect();
    let marks = marker_labels(&h);
    for m in [
        "G2 join: SECTA end – SECTB start",
        "G2 join: SECTB end – SECTC start",
        "G1 join: LEADIN end – SECTA start",
        "G0 join: SECTC end – DROP start",
    ] {
        assert!(marks.iter().any(|l| l == m), "{m:?} not in {marks:?}");
    }
    let app = h.state();
    let joint = app.curve_ws.scene.measured.curves[0].point;
    let at = app.curve_ws.curve3d.view.to_screen(joint, view).unwrap();
    let label = app.curve_ws.scene.marks3d[0].label.clone();
    let marker = h.get_by_role_and_label(egui::accesskit::Role::Image, &label).rect();
    assert!(
        marker.center().distance(at) < 0.5,
        "{label}: {:?} vs {at:?}",
        marker.center()
    );
    // the measures on hover
    h.get_by_role_and_label(egui::accesskit::Role::Image, "G1 join: LEADIN end – SECTA start")
        .hover();
    h.run();
    h.get_by_label_contains("G1: gap");
    // one curve: nothing to mark
    let mut one = harness(App::default());
    one.get_by_label("3D view").click();
    one.run();
    assert!(one.query_by_label("3D curve view").is_some());
    assert_eq!(marker_labels(&one), Vec::<String>::new());
}

/// Two patches: the shared edge marked in the surface's 3D view; a patch alone: nothing.
fn surface_view_marks_a_shared_edge(dir: &std::path::Path) {
    let ron = dir.join("patches.ron");
    fairway::io::save_scene(&ron, &two_patches()).unwrap();
    // FAIRWAY_WRITE_PATCHES=path: also write the patches there (for the screenshot in the README)
    if let Some(out) = std::env::var_os("FAIRWAY_WRITE_PATCHES") {
        fairway::io::save_scene(std::path::Path::new(&out), &two_patches()).unwrap();
    }
    let mut h = harness(App::default());
    h.state_mut().open_now(&ron);
    h.run();
    assert!(h.state().error.is_none(), "{:?}", h.state().error);
    assert!(h.state().surface.is_some(), "a surface is active");
    let marks = marker_labels(&h);
    assert_eq!(marks, vec!["G2 edge: PORT u1 – STARBOARD u0".to_string()]);
    h.get_by_role_and_label(egui::accesskit::Role::Image, &marks[0]).hover();
    h.run();
    h.get_by_label_contains("normal angle");
    // one patch alone: no edge
    let one = Scene {
        objects: two_patches().objects[..1].to_vec(),
        ..Default::default()
    };
    let path = dir.join("one_patch.ron");
    fairway::io::save_scene(&path, &one).unwrap();
    let mut h = harness(App::default());
    h.state_mut().open_now(&path);
    h.run();
    assert!(h.state().surface.is_some());
    assert_eq!(marker_labels(&h), Vec::<String>::new());
}

/// Position, unit tangent and curvature of `c` at its start or end.
fn end_state(c: &BSplineCurve, at_end: bool) -> (DVec3, DVec3, f64) {
    let (a, b) = c.domain();
    let u = if at_end { b } else { a };
    (c.point(u), c.d1(u).normalize(), c.curvature(u))
}

#[test]
fn fairing_a_curve_joined_at_one_end_keeps_that_join_and_frees_the_other_end() {
    // the noisy demo curve split in two: FORE's end meets AFT's start with G2, AFT's end is free
    let c = fairway_editor::demo_curve_n(40);
    let (fore, aft) = split(&c, c.knots().values()[20]);
    let scene = Scene {
        objects: [("FORE", fore), ("AFT", aft.clone())]
            .into_iter()
            .map(|(n, c)| SceneObject {
                name: n.into(),
                trim: None,
                geometry: c.into(),
                settings: DocumentSettings::default(),
            })
            .collect(),
        ..Default::default()
    };
    let dir = temp_dir("one-join");
    let path = dir.join("two.ron");
    fairway::io::save_scene(&path, &scene).unwrap();
    let mut h = harness(App::default());
    h.state_mut().open_now(&path);
    h.run();
    h.state_mut().apply(fairway_editor::Command::Select(1));
    h.run();
    h.get_by_label("Whole curve").click();
    h.run();
    h.get_by_label_contains("Start: a curve end at a join, kept G2");
    assert!(h.query_by_label_contains("End: a curve end at a join").is_none());
    h.get_by_label("Accept").click();
    h.run();
    let app = h.state();
    let after = app.doc.geometry.as_curve().unwrap().clone();
    assert_ne!(after, aft, "{}", app.status);
    let size = fairway::network::scene_diagonal(&scene.geometries());
    // the joined start: position, tangent and curvature as they were (the join stays G2)
    let ((p0, t0, k0), (p1, t1, k1)) = (end_state(&aft, false), end_state(&after, false));
    let dk = (k1 - k0).abs() / k0.abs();
    eprintln!(
        "joined end: Δposition {:.1e} × size, Δtangent {:.1e} rad, Δκ {dk:.1e} relative",
        p0.distance(p1) / size,
        t0.angle_between(t1)
    );
    assert!(p0.distance(p1) <= 1e-12 * size && t0.angle_between(t1) <= 1e-9 && dk <= 1e-9);
    assert_eq!(joins_of(app, 1), vec![Continuity::G2]);
    // the free end: position and tangent kept (the default), its curvature free, and it moved
    let ((p0, t0, k0), (p1, t1, k1)) = (end_state(&aft, true), end_state(&after, true));
    let dk = (k1 - k0).abs() / k0.abs();
    eprintln!("free end: Δκ {dk:.1e} relative (κ {k0:.4} → {k1:.4})");
    assert!(p0.distance(p1) <= 1e-12 * size && t0.angle_between(t1) <= 1e-9);
    assert!(dk > 1e-3, "the free end's curvature changed: {dk:.1e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The bundled bumpy surface cut into a 2 × 2 grid of patches at interior knots (every edge G2), named.
fn four_patches() -> Scene {
    let s = fairway::io::load_geometry(&common::asset("bumpy_surface.json"))
        .unwrap()
        .as_surface()
        .unwrap()
        .clone();
    // `s` cut across u at its knot `u`: the two patches
    let halves = |s: &fairway::BSplineSurface, u: f64| -> [fairway::BSplineSurface; 2] {
        let (mut left, mut right) = (vec![], vec![]);
        for j in 0..s.nv() {
            let pts = (0..s.nu()).map(|i| s.point_at(i, j)).collect();
            let row = BSplineCurve::try_new(3, s.knots_u().values().to_vec(), pts, None, 3).unwrap();
            let (l, r) = fairway::fair::closed::split(&row, u).unwrap();
            left.push(l);
            right.push(r);
        }
        [left, right].map(|rows| {
            let rows = &rows;
            let (nu, nv) = (rows[0].n_points(), rows.len());
            let pts = (0..nu)
                .flat_map(|i| (0..nv).map(move |j| rows[j].points()[i]))
                .collect();
            let k = (rows[0].knots().values().to_vec(), s.knots_v().values().to_vec());
            fairway::BSplineSurface::try_new(3, 3, k.0, k.1, nu, nv, pts, None).unwrap()
        })
    };
    let (u, v) = (s.knots_u().values()[12], s.knots_v().values()[10]);
    let patches: Vec<fairway::BSplineSurface> = halves(&s, u)
        .iter()
        .flat_map(|h| halves(&h.transposed(), v).map(|p| p.transposed()))
        .collect();
    Scene {
        objects: patches
            .into_iter()
            .zip(["AFT_PORT", "AFT_STBD", "FWD_PORT", "FWD_STBD"])
            .map(|(p, n)| SceneObject {
                name: n.into(),
                trim: None,
                geometry: p.into(),
                settings: DocumentSettings::default(),
            })
            .collect(),
        ..Default::default()
    }
}

#[test]
fn the_surface_view_draws_every_patch_a_click_selects_one_and_fair_all_keeps_the_grid_edges() {
    let dir = temp_dir("grid3d");
    let ron = dir.join("grid.ron");
    fairway::io::save_scene(&ron, &four_patches()).unwrap();
    // FAIRWAY_WRITE_GRID=path: also write the patches there (for the screenshot in the README)
    if let Some(out) = std::env::var_os("FAIRWAY_WRITE_GRID") {
        fairway::io::save_scene(std::path::Path::new(&out), &four_patches()).unwrap();
    }
    let mut h = harness(App::default());
    h.state_mut().open_now(&ron);
    h.run();
    let app = h.state();
    assert!(app.error.is_none(), "{:?}", app.error);
    let ws = app.surface.as_ref().expect("a surface is active");
    assert_eq!(app.active, 0);
    assert_eq!(ws.others.iter().map(|o| o.object).collect::<Vec<_>>(), vec![1, 2, 3]);
    // every patch painted: the active one's triangles and the three others' (one density)
    let per_patch = ws.mesh.indices.len() / 3;
    assert_eq!(ws.drawn_triangles(), 4 * per_patch);
    // a click on the middle of the fourth patch selects it
    let view = h.get_by_label("3D view").rect();
    let ws = h.state().surface.as_ref().unwrap();
    let target = &ws.others[2].surface;
    let ((u0, u1), (v0, v1)) = target.domain();
    let at = ws
        .view
        .to_screen(target.point(0.5 * (u0 + u1), 0.5 * (v0 + v1)), view)
        .unwrap();
    click(&mut h, at);
    h.run();
    let app = h.state();
    assert_eq!(app.active, 3, "{}", app.status);
    let ws = app.surface.as_ref().unwrap();
    assert_eq!(ws.others.iter().map(|o| o.object).collect::<Vec<_>>(), vec![0, 1, 2]);
    assert_eq!(ws.drawn_triangles(), 4 * per_patch);
    // Fair all: the grid faired as one, every shared edge still G1 (to 0.01°) and G2
    let before = find_joins(&h.state().objects.iter().map(|o| o.geometry.clone()).collect::<Vec<_>>());
    assert_eq!(before.surfaces.len(), 4);
    h.get_by_label("Fair all (keep joins)").click();
    h.run();
    let app = h.state();
    assert!(
        app.status.starts_with("Fair all: 4 of 4 objects changed"),
        "{}",
        app.status
    );
    assert!(
        app.status.contains("4 of 4 joins keep their continuity"),
        "{}",
        app.status
    );
    let after = find_joins(&app.objects.iter().map(|o| o.geometry.clone()).collect::<Vec<_>>());
    for j in &after.surfaces {
        assert!(j.continuity.normal_angle.to_degrees() <= 0.01, "{j:?}");
        assert_eq!(j.continuity.class, Continuity::G2, "{j:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// An L of three patches (the grid less its last patch): "Fair all" takes the layout route (the status
/// says so), every shared edge stays G2 (to 0.01°).
#[test]
fn fair_all_on_an_l_of_patches_takes_the_layout_route_and_keeps_its_edges() {
    let dir = temp_dir("layout3d");
    let ron = dir.join("l.ron");
    let mut scene = four_patches();
    scene.objects.pop();
    fairway::io::save_scene(&ron, &scene).unwrap();
    // FAIRWAY_WRITE_L=path: also write the patches there (for the screenshot)
    if let Some(out) = std::env::var_os("FAIRWAY_WRITE_L") {
        fairway::io::save_scene(std::path::Path::new(&out), &scene).unwrap();
    }
    let mut h = harness(App::default());
    h.state_mut().open_now(&ron);
    h.run();
    assert!(h.state().error.is_none(), "{:?}", h.state().error);
    h.get_by_label("Fair all (keep joins)").click();
    h.run();
    let app = h.state();
    assert!(
        app.status.starts_with("Fair all: 3 of 3 objects changed"),
        "{}",
        app.status
    );
    assert!(app.status.contains("routes: layout ×3"), "{}", app.status);
    assert!(
        app.status.contains("2 of 2 joins keep their continuity"),
        "{}",
        app.status
    );
    let after = find_joins(&app.objects.iter().map(|o| o.geometry.clone()).collect::<Vec<_>>());
    for j in &after.surfaces {
        assert!(j.continuity.normal_angle.to_degrees() <= 0.01, "{j:?}");
        assert_eq!(j.continuity.class, Continuity::G2, "{j:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two of the chain's curves checked in the objects panel and "Fair checked": those two change, faired
/// together; the others stay bit for bit; every join keeps its continuity (the checked curves' joins with
/// the others are held); one undo step.
#[test]
fn fair_checked_fairs_the_checked_objects_together_and_leaves_the_others() {
    let dir = temp_dir("checked");
    let path = write_network(&dir);
    let mut h = harness(App::default());
    h.state_mut().open_now(&path);
    h.run();
    let original = h.state().objects_now();
    // each object's checkbox sits on its row of the list
    for label in ["1. SECTA", "2. SECTB"] {
        let row = h.get_by_label(label).rect().center().y;
        let boxes: Vec<_> = h
            .get_all_by_role(egui::accesskit::Role::CheckBox)
            .filter(|b| (b.rect().center().y - row).abs() < 4.0)
            .collect();
        assert_eq!(boxes.len(), 1, "one checkbox on the row of {label}");
        boxes[0].click();
        h.run();
    }
    assert_eq!(h.state().fair_set.iter().copied().collect::<Vec<_>>(), [0, 1]);
    h.get_by_label("Fair checked (2, keep joins)").click();
    h.run();
    let app = h.state();
    assert!(app.error.is_none(), "{:?}", app.error);
    assert!(
        app.status.starts_with("Fair checked: 2 of 2 objects changed"),
        "{}",
        app.status
    );
    let after = app.objects_now();
    for k in 0..after.len() {
        if k < 2 {
            assert_ne!(after[k].geometry, original[k].geometry, "{k} is checked: faired");
        } else {
            assert_eq!(
                after[k].geometry, original[k].geometry,
                "{k} is not checked: bit for bit"
            );
        }
    }
    let classes = |objects: &[fairway::io::SceneObject]| {
        let g: Vec<Geometry> = objects.iter().map(|o| o.geometry.clone()).collect();
        find_joins(&g)
            .curves
            .iter()
            .map(|j| j.continuity.class)
            .collect::<Vec<_>>()
    };
    assert_eq!(classes(&after), classes(&original), "every join keeps its continuity");
    h.state_mut().apply(fairway_editor::Command::Undo);
    h.run();
    assert_eq!(h.state().objects_now(), original);
    assert!(!h.state().history.can_undo());
    let _ = std::fs::remove_dir_all(&dir);
}

/// "Fair all" runs in the background: the command returns at once with the status saying so and the
/// document untouched; another network fair is refused meanwhile; the result waits for a frame to take
/// it, is the synchronous `fair_network_at` result on the same input, and is one undo step.
#[test]
fn fair_all_runs_as_a_background_job_with_the_synchronous_result_in_one_undo_step() {
    let dir = temp_dir("job");
    let path = write_network(&dir);
    let mut h = harness_without_waiting(App::default());
    h.state_mut().open_now(&path);
    h.step();
    let original = h.state().objects_now();
    let all: Vec<usize> = (0..original.len()).collect();
    let input = h.state().network_input(&all).unwrap();
    let sync = fair_network_at(&input.geometries(), &input.which, &input.options, &input.tolerances).unwrap();
    h.get_by_label("Fair all (keep joins)").click();
    h.step();
    let app = h.state();
    assert!(app.is_computing(), "{}", app.status);
    assert_eq!(app.network_fair_running().map(|(what, _)| what), Some("Fair all"));
    assert!(app.status.starts_with("Fair all: fairing 5 objects"), "{}", app.status);
    assert_eq!(app.objects_now(), original, "applied before the job finished");
    assert!(!app.history.can_undo());
    // a second network fair is refused while this one runs
    h.state_mut().apply(Command::FairSet(vec![0, 1]));
    assert!(
        h.state().status.starts_with("Fair checked: Fair all is still running"),
        "{}",
        h.state().status
    );
    h.step();
    assert!(
        h.query_by_label_contains("Fair all: fairing…").is_some(),
        "no busy state in the status bar"
    );
    assert!(
        h.get_by_label("Fair all (keep joins)").accesskit_node().is_disabled(),
        "Fair all is offered while it runs"
    );
    // finished, but not yet taken by a frame
    h.state_mut().wait_for_jobs();
    assert_eq!(h.state().objects_now(), original);
    h.step();
    let app = h.state();
    assert!(!app.is_computing());
    assert!(
        app.status.starts_with("Fair all: 3 of 5 objects changed"),
        "{}",
        app.status
    );
    let after: Vec<Geometry> = app.objects_now().into_iter().map(|o| o.geometry).collect();
    assert_eq!(after, sync.objects, "the job's fair differs from fair_network_at");
    assert_eq!(app.doc.geometry, sync.objects[app.active]);
    // one undo step restores the original
    h.state_mut().apply(Command::Undo);
    h.step();
    assert_eq!(h.state().objects_now(), original);
    assert!(!h.state().history.can_undo());
    let _ = std::fs::remove_dir_all(&dir);
}

/// An edit while "Fair all" runs makes its result stale: it is discarded with a note, the edit stays
/// (and is the only undo step); a running fair can be cancelled.
#[test]
fn a_fair_all_result_is_discarded_when_the_objects_changed_meanwhile_and_can_be_cancelled() {
    let dir = temp_dir("job-stale");
    let path = write_network(&dir);
    let mut h = harness_without_waiting(App::default());
    h.state_mut().open_now(&path);
    h.step();
    let original = h.state().objects_now();
    h.state_mut().apply(Command::FairAll);
    assert!(h.state().is_computing());
    let t = h.state().tolerance() * 2.0;
    h.state_mut().apply(Command::SetTolerance(t));
    let edited = h.state().objects_now();
    assert_ne!(edited, original);
    h.state_mut().wait_for_jobs();
    h.step();
    let app = h.state();
    assert!(!app.is_computing());
    assert_eq!(app.status, "Fair all: the objects changed while fairing; run it again");
    assert_eq!(app.objects_now(), edited, "a stale network fair was applied");
    h.state_mut().apply(Command::Undo);
    h.step();
    assert_eq!(h.state().objects_now(), original);
    assert!(!h.state().history.can_undo(), "the discarded fair left an undo step");
    // cancel: the result is dropped, nothing changes
    h.state_mut().apply(Command::FairAll);
    assert!(h.state().is_computing());
    h.state_mut().cancel_network_fair();
    assert!(!h.state().is_computing());
    assert_eq!(h.state().status, "Fair all: cancelled; the document is unchanged");
    h.step();
    assert_eq!(h.state().objects_now(), original);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The status bar's Cancel stops a running "Fair all": the job's token is set, so its thread ends
/// `Cancelled` instead of running to its end — here held at a gate before it started, so
/// deterministically before the core passed a single checkpoint — and the document is unchanged.
#[test]
fn cancelling_fair_all_stops_its_thread() {
    let dir = temp_dir("job-cancel");
    let path = write_network(&dir);
    let mut h = harness_without_waiting(App::default());
    h.state_mut().open_now(&path);
    h.step();
    let original = h.state().objects_now();
    let gate = fairway_editor::jobs::Gate::closed();
    h.state_mut().set_job_gate(Some(gate.clone()));
    h.state_mut().apply(Command::FairAll);
    let watch = h.state().watch_network_fair().expect("Fair all runs");
    h.step();
    h.get_by_role_and_label(egui::accesskit::Role::Button, "Cancel").click();
    h.step();
    assert!(watch.is_cancelled(), "Cancel did not set the job's token");
    assert!(!h.state().is_computing());
    assert_eq!(h.state().status, "Fair all: cancelled; the document is unchanged");
    gate.open();
    assert_eq!(watch.wait_end(), fairway_editor::jobs::JobEnd::Cancelled);
    assert_eq!(watch.checkpoints(), 0);
    h.step();
    assert_eq!(h.state().objects_now(), original);
    let _ = std::fs::remove_dir_all(&dir);
}
