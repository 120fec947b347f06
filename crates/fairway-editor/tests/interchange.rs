//! Interchange and hardening in the editor (issue 8), driven through the
//! real UI with egui_kittest where the UI is the point: autosave and the
//! "Restore unsaved work?" prompt, failed saves, SVG / PNG export, the IGES
//! object picker, and panics in the fairing engine. Each test uses its own
//! temporary folder (also as the autosave folder), never the user's.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use eframe::egui;
use egui::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use fairway::io::Document;
use fairway::{BSplineCurve, BSplineSurface, DVec2, DVec3, Geometry};
use fairway_editor::autosave::Autosave;
use fairway_editor::{App, Command};

mod common;
use common::harness;

/// A fresh, empty temporary folder for one test.
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fairway-editor-interchange-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Type `text` into the File menu's path field (menu left open).
fn type_path(h: &mut Harness<'static, App>, text: &str) {
    h.state_mut().path_input.clear();
    h.get_by_role_and_label(Role::Button, "File").click();
    h.run();
    let field = h.get_by_role(Role::TextInput);
    field.focus();
    field.type_text(text);
    h.run();
}

/// Type a path in the File menu and press the button `button` next to it.
fn path_action(h: &mut Harness<'static, App>, path: &Path, button: &str) {
    type_path(h, &path.display().to_string());
    h.get_by_role_and_label(Role::Button, button).click();
    h.run();
}

fn autosave_file(dir: &Path) -> PathBuf {
    dir.join("autosave.ron")
}

fn curve(doc: &Document) -> &BSplineCurve {
    match &doc.geometry {
        Geometry::Curve(c) => c,
        Geometry::Surface(_) => panic!("a surface"),
    }
}

#[test]
fn dirty_document_is_autosaved_and_restored_exactly_after_a_crash() {
    let dir = temp_dir("restore");
    let mut h = harness(App::default().with_autosave(&dir));
    assert!(h.state().recovery.is_none());
    h.run();
    assert!(!autosave_file(&dir).exists(), "a clean document is not autosaved");
    h.get_by_role_and_label(Role::Button, "Whole curve").click();
    h.run();
    assert!(h.state().is_dirty());
    let first = std::fs::read_to_string(autosave_file(&dir)).expect("autosaved as soon as dirty");
    // periodic: a later change is written only once the interval has passed
    h.state_mut().push(Command::SetTolerance(0.0123));
    h.run();
    assert_eq!(std::fs::read_to_string(autosave_file(&dir)).unwrap(), first);
    h.state_mut()
        .autosave_tick(Instant::now() + fairway_editor::interchange::AUTOSAVE_INTERVAL + Duration::from_secs(1));
    let second = std::fs::read_to_string(autosave_file(&dir)).unwrap();
    assert_ne!(second, first);
    let expected = h.state().doc.clone();
    assert_eq!(expected.settings.tolerance, Some(0.0123));
    drop(h); // a crash: nothing is cleared

    // next start: the prompt, then Restore gives the same document, unsaved
    let mut h = harness(App::default().with_autosave(&dir));
    assert!(h.state().recovery.is_some());
    h.get_by_label("Restore unsaved work?");
    assert_ne!(h.state().doc, expected, "nothing restored before the user chooses");
    h.get_by_role_and_label(Role::Button, "Restore").click();
    h.run();
    assert!(h.state().recovery.is_none());
    assert_eq!(h.state().doc, expected);
    let (a, b) = (curve(&h.state().doc), curve(&expected));
    assert_eq!(a.points(), b.points(), "control points bit for bit");
    assert_eq!(a.knots(), b.knots());
    assert!(h.state().is_dirty());
    assert!(h.state().title().starts_with("* "), "{}", h.state().title());
    assert!(autosave_file(&dir).exists());

    // a clean save removes the autosave
    let saved = dir.join("restored.ron");
    path_action(&mut h, &saved, "Save to path");
    assert!(!h.state().is_dirty(), "{:?}", h.state().error);
    assert_eq!(fairway::io::load(&saved).unwrap(), expected);
    assert!(!autosave_file(&dir).exists(), "autosave left after a clean save");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn discard_removes_the_autosave_and_keeps_the_start_document() {
    let dir = temp_dir("discard");
    let mut crashed = Document::new(Geometry::Curve(fairway_editor::demo_curve_n(12)));
    crashed.settings.tolerance = Some(0.5);
    Autosave::new(&dir, Duration::from_secs(30))
        .write(&crashed, None)
        .unwrap();
    let mut h = harness(App::default().with_autosave(&dir));
    h.get_by_label("Restore unsaved work?");
    h.get_by_role_and_label(Role::Button, "Discard").click();
    h.run();
    assert!(h.state().recovery.is_none());
    assert!(!autosave_file(&dir).exists());
    assert!(!dir.join("autosave.meta").exists());
    assert_eq!(h.state().doc, App::default().doc);
    assert!(!h.state().is_dirty());
    // and a later start has nothing to offer
    assert!(App::default().with_autosave(&dir).recovery.is_none());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn clean_exit_and_returning_to_the_saved_state_remove_the_autosave() {
    let dir = temp_dir("exit");
    let mut app = App::default().with_autosave(&dir);
    app.apply(Command::SetTolerance(0.02));
    app.autosave_tick(Instant::now());
    assert!(autosave_file(&dir).exists());
    // undo back to the saved state: clean again, the autosave goes
    app.apply(Command::Undo);
    assert!(!app.is_dirty());
    app.autosave_tick(Instant::now());
    assert!(!autosave_file(&dir).exists());
    // dirty again, then a clean exit (the user confirmed losing the work)
    app.apply(Command::SetTolerance(0.03));
    app.autosave_tick(Instant::now() + Duration::from_secs(60));
    assert!(autosave_file(&dir).exists());
    eframe::App::on_exit(&mut app);
    assert!(!autosave_file(&dir).exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn failed_saves_report_the_error_keep_the_document_dirty_and_the_file_untouched() {
    let dir = temp_dir("failsave");
    let mut h = harness(App::default());
    h.get_by_role_and_label(Role::Button, "Whole curve").click();
    h.run();
    let edited = h.state().doc.clone();
    let keep = dir.join("keep.csv");
    std::fs::write(&keep, "0 0\n1 1\n2 0\n3 1\n").unwrap();
    let as_dir = dir.join("folder.ron");
    std::fs::create_dir(&as_dir).unwrap();
    for target in [dir.join("no/such/folder/a.ron"), as_dir.clone(), keep.clone()] {
        h.state_mut().error = None;
        path_action(&mut h, &target, "Save to path");
        let err = h.state().error.clone().unwrap_or_default();
        assert!(err.starts_with("Could not save"), "{target:?}: {err:?}");
        h.get_by_label_contains("Error: Could not save");
        assert!(h.state().is_dirty(), "{target:?}");
        assert!(h.state().title().starts_with("* "), "{}", h.state().title());
        assert_eq!(h.state().doc, edited);
        assert_eq!(h.state().path, None);
    }
    assert_eq!(std::fs::read_to_string(&keep).unwrap(), "0 0\n1 1\n2 0\n3 1\n");
    assert!(as_dir.is_dir() && std::fs::read_dir(&as_dir).unwrap().next().is_none());
    assert!(!dir.join("no").exists());
    // no temporary files left behind by the atomic writer
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn svg_export_holds_what_the_canvas_shows() {
    let dir = temp_dir("svg");
    let mut h = harness(App::default());
    h.get_by_role_and_label(Role::Button, "Whole curve").click();
    h.run();
    assert!(h.state().curve_ws.preview().is_some());
    let out = dir.join("canvas.svg");
    path_action(&mut h, &out, "Export SVG to path");
    let svg = std::fs::read_to_string(&out).unwrap_or_else(|e| panic!("{e}: {:?}", h.state().error));
    assert!(
        svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""),
        "{}",
        &svg[..80]
    );
    assert!(svg.trim_end().ends_with("</svg>"));
    assert_eq!(
        svg.matches("<g ").count(),
        svg.matches("</g>").count(),
        "unbalanced groups"
    );
    for id in ["curve", "comb", "band", "faired", "control-polygon"] {
        assert!(svg.contains(&format!("id=\"{id}\"")), "missing {id}");
    }
    // the drawing follows the canvas: no comb or polygon when hidden, no
    // band or faired curve without a region
    h.state_mut().prefs.show_comb = false;
    h.state_mut().prefs.show_polygon = false;
    h.get_by_role_and_label(Role::Button, "Clear").click();
    h.run();
    path_action(&mut h, &out, "Export SVG to path");
    let svg = std::fs::read_to_string(&out).unwrap();
    assert!(svg.contains("id=\"curve\""));
    for id in ["comb", "band", "faired", "control-polygon"] {
        assert!(!svg.contains(&format!("id=\"{id}\"")), "unexpected {id}");
    }
    assert!(h.state().status.starts_with("Exported"), "{}", h.state().status);
    // a path that is not .svg is refused (never overwrite a document by mistake)
    let doc_path = dir.join("doc.ron");
    std::fs::write(&doc_path, "precious").unwrap();
    path_action(&mut h, &doc_path, "Export SVG to path");
    assert!(h.state().error.as_deref().unwrap_or("").contains(".svg"));
    assert_eq!(std::fs::read_to_string(&doc_path).unwrap(), "precious");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn png_export_writes_the_view_as_an_image() {
    let dir = temp_dir("png");
    let mut h = harness(App::default());
    let out = dir.join("view.png");
    path_action(&mut h, &out, "Export PNG to path");
    for _ in 0..5 {
        if out.exists() {
            break;
        }
        h.run();
    }
    assert!(h.state().png_export.is_none(), "export still pending");
    let img = image::open(&out)
        .unwrap_or_else(|e| panic!("{e}: {:?}", h.state().error))
        .to_rgba8();
    let r = h.state().view_rect;
    assert!(
        (img.width() as f32 - r.width()).abs() <= 1.0 && (img.height() as f32 - r.height()).abs() <= 1.0,
        "{}x{} vs view {r:?}",
        img.width(),
        img.height()
    );
    // the canvas background (gray 24) dominates, and the curve and comb are drawn on it
    let bg = img.pixels().filter(|p| p.0 == [24, 24, 24, 255]).count();
    let total = (img.width() * img.height()) as usize;
    assert!(bg > total / 2, "{bg} of {total} background pixels");
    let colours: std::collections::HashSet<[u8; 4]> = img.pixels().map(|p| p.0).collect();
    assert!(colours.len() > 20, "only {} colours", colours.len());
    let _ = std::fs::remove_dir_all(&dir);
}

fn test_surface() -> BSplineSurface {
    let (nu, nv) = (4, 3);
    let pts: Vec<DVec3> = (0..nu)
        .flat_map(|i| (0..nv).map(move |j| DVec3::new(i as f64, j as f64, 0.1 * (i * j) as f64)))
        .collect();
    BSplineSurface::try_new(
        3,
        2,
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
        vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        nu,
        nv,
        pts,
        None,
    )
    .unwrap()
}

fn test_curve_3d() -> BSplineCurve {
    BSplineCurve::try_new(
        2,
        vec![0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0],
        vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.5),
            DVec3::new(2.0, -1.0, 1.0),
            DVec3::new(3.0, 0.0, 0.25),
        ],
        Some(vec![1.0, 0.8, 1.2, 1.0]),
        3,
    )
    .unwrap()
}

#[test]
fn iges_with_several_objects_opens_a_picker_and_one_object_opens_directly() {
    let dir = temp_dir("iges");
    let c2 = fairway_editor::demo_curve_n(9);
    let objects: Vec<Geometry> = vec![c2.clone().into(), test_surface().into(), test_curve_3d().into()];
    let text = fairway::io::iges::write(&objects, &Default::default());
    // label the surface (directory field 18 of its second D record) as another CAD system would
    let text: String = text
        .lines()
        .map(|l| {
            if &l[72..] == "D      4" {
                format!("{}{:>8}{:>8}{}\n", &l[..56], "HULL", 0, &l[72..])
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    let multi = dir.join("multi.igs");
    std::fs::write(&multi, text).unwrap();

    let mut h = harness(App::default());
    // opened, every object is in the document, the first curve active
    path_action(&mut h, &multi, "Open path");
    assert!(h.state().object_pick.is_none(), "{:?}", h.state().error);
    let names: Vec<String> = h.state().objects.iter().map(|o| o.name.clone()).collect();
    assert_eq!(names, ["", "HULL", ""]);
    let geometries: Vec<Geometry> = h.state().objects.iter().map(|o| o.geometry.clone()).collect();
    assert_eq!(geometries, objects, "exact");
    assert_eq!((h.state().active, &h.state().doc.geometry), (0, &objects[0]));
    assert!(!h.state().is_dirty());
    h.get_by_label("2. HULL");

    // imported, one object through the picker
    let mut h = harness(App::default());
    let before = h.state().doc.clone();
    path_action(&mut h, &multi, "Import one object");
    assert!(h.state().object_pick.is_some(), "{:?}", h.state().error);
    assert_eq!(h.state().doc, before, "nothing opened before the choice");
    h.get_by_label("Choose an object");
    h.get_by_label_contains("curve 2D, degree 3, 9 control points");
    h.get_by_label_contains("surface, degree 3x2, 4x3 control points, entity 3, label HULL");
    h.get_by_label_contains("curve 3D, degree 2, 4 control points, rational");
    h.get_by_role_and_label(Role::Button, "Open object 3").click();
    h.run();
    assert!(h.state().object_pick.is_none());
    assert!(h.state().surface.is_none());
    assert_eq!(h.state().doc.geometry, objects[2], "exact");
    assert_eq!(
        h.state().path,
        None,
        "untitled: saving must not overwrite the IGES file"
    );
    assert!(!h.state().is_dirty());

    // again, choosing the surface opens the surface workspace
    path_action(&mut h, &multi, "Import one object");
    h.get_by_role_and_label(Role::Button, "Open object 2").click();
    h.run();
    assert!(h.state().surface.is_some(), "surface workspace");
    assert_eq!(h.state().doc.geometry, objects[1]);
    assert!(!h.state().is_dirty());

    // cancel keeps what is open (the surface)
    path_action(&mut h, &multi, "Import one object");
    h.get_by_role_and_label(Role::Button, "Cancel import").click();
    h.run();
    assert!(h.state().object_pick.is_none());
    assert!(h.state().surface.is_some());
    assert_eq!(h.state().doc.geometry, objects[1]);

    // a file with one object opens directly, keeping its path
    let single = dir.join("single.iges");
    std::fs::write(&single, fairway::io::iges::write(&objects[..1], &Default::default())).unwrap();
    path_action(&mut h, &single, "Open path");
    assert!(h.state().object_pick.is_none());
    assert_eq!(h.state().doc.geometry, objects[0]);
    assert_eq!(h.state().path.as_deref(), Some(single.as_path()));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_panic_in_the_fairing_engine_is_reported_and_changes_nothing() {
    let mut h = harness(App::default());
    let geometry = h.state().doc.geometry.clone();
    // panic while preparing the fairing of a new region
    h.state_mut().curve_ws.fairing.inject_panic = true;
    h.get_by_role_and_label(Role::Button, "Whole curve").click();
    h.run();
    let err = h.state().error.clone().expect("reported");
    assert!(
        err.starts_with("internal error in fairing setup: injected panic") && err.ends_with("(nothing was changed)"),
        "{err}"
    );
    // shown on the status line and in the fairing panel
    assert_eq!(
        h.query_all_by_label_contains("Error: internal error in fairing setup")
            .count(),
        2
    );
    assert!(h.state().curve_ws.preview().is_none());
    assert!(
        h.get_by_role_and_label(Role::Button, "Accept")
            .accesskit_node()
            .is_disabled()
    );
    assert_eq!(h.state().doc.geometry, geometry);
    // the editor goes on: a new region fairs normally
    h.state_mut().error = None;
    h.get_by_role_and_label(Role::Button, "Clear").click();
    h.run();
    h.get_by_role_and_label(Role::Button, "Whole curve").click();
    h.run();
    assert!(h.state().curve_ws.preview().is_some());
    assert!(h.state().error.is_none());
    // panic while re-fairing at a new tolerance
    h.state_mut().curve_ws.fairing.inject_panic = true;
    let tol = h.state().tolerance() * 2.0;
    h.state_mut().push(Command::SetTolerance(tol));
    h.run();
    let err = h.state().error.clone().expect("reported");
    assert!(err.starts_with("internal error in fairing: injected panic"), "{err}");
    assert!(h.state().curve_ws.preview().is_none());
    assert!(
        h.get_by_role_and_label(Role::Button, "Accept")
            .accesskit_node()
            .is_disabled()
    );
    assert_eq!(h.state().doc.geometry, geometry);
}

#[test]
fn a_surface_document_is_autosaved_and_restored_into_the_surface_workspace() {
    let dir = temp_dir("surface");
    let path = dir.join("patch.json");
    let doc = Document::new(Geometry::Surface(test_surface()));
    fairway::io::save(&path, &doc).unwrap();
    let mut h = harness(App::default().with_autosave(&dir));
    path_action(&mut h, &path, "Open path");
    assert!(h.state().surface.is_some(), "surface workspace");
    h.state_mut().push(fairway_editor::Command::SetTolerance(0.25));
    h.run();
    assert!(h.state().is_dirty());
    let expected = h.state().doc.clone();
    assert!(autosave_file(&dir).exists());
    drop(h);
    let mut h = harness(App::default().with_autosave(&dir));
    assert_eq!(
        h.state().recovery.as_ref().and_then(|r| r.source.clone()),
        Some(path.clone()),
        "the autosave knows the file it belongs to"
    );
    h.get_by_role_and_label(Role::Button, "Restore").click();
    h.run_steps(8); // the surface workspace lays out its views over a few frames
    assert!(h.state().surface.is_some(), "restored into the surface workspace");
    assert_eq!(h.state().doc, expected);
    assert_eq!(h.state().path.as_deref(), Some(path.as_path()));
    assert!(h.state().is_dirty(), "differs from the file on disk");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_unreadable_autosave_is_reported_not_offered_and_replaced_by_the_next_one() {
    let dir = temp_dir("garbage");
    std::fs::write(autosave_file(&dir), "this is not a document").unwrap();
    let mut app = App::default().with_autosave(&dir);
    assert!(app.recovery.is_none());
    let err = app.error.clone().expect("reported");
    assert!(err.contains("could not be read"), "{err}");
    app.apply(Command::SetTolerance(0.02));
    app.autosave_tick(Instant::now());
    let text = std::fs::read_to_string(autosave_file(&dir)).unwrap();
    assert_eq!(Document::from_ron(&text).unwrap(), app.doc);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn opened_files_are_remembered_by_absolute_path_for_the_autosave() {
    let dir = temp_dir("relative");
    // the test runs in the crate's folder: a relative path to the sample
    let rel = Path::new("../../assets/car_roof.ron");
    let mut app = App::default().with_autosave(&dir);
    app.open_now(rel);
    assert!(app.error.is_none(), "{:?}", app.error);
    let p = app.path.clone().unwrap();
    assert!(p.is_absolute() && p.ends_with("assets/car_roof.ron"), "{p:?}");
    app.apply(Command::SetTolerance(0.01));
    app.autosave_tick(Instant::now());
    let r = fairway_editor::autosave::pending(&dir).unwrap().unwrap();
    assert_eq!(r.source.as_deref(), Some(p.as_path()));
    assert_eq!(fairway::io::load(&p).unwrap(), fairway::io::load(rel).unwrap());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn export_png_then_quit_writes_the_canvas_once_laid_out() {
    // the command-line `--export-png PATH` (scripts, reports): no clicks needed
    let dir = temp_dir("pngquit");
    let out = dir.join("shot.png");
    let mut app = App::default();
    app.export_png_then_quit(out.clone());
    let mut h = harness(app);
    for _ in 0..10 {
        if out.exists() {
            break;
        }
        h.run();
    }
    let img = image::open(&out).expect("written").to_rgba8();
    let r = h.state().view_rect;
    assert!(
        (img.width() as f32 - r.width()).abs() <= 1.0,
        "{} vs {r:?}",
        img.width()
    );
    assert!(h.state().status.starts_with("Exported"), "{}", h.state().status);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_iges_picker_also_opens_from_the_surface_workspace() {
    let dir = temp_dir("iges_from_surface");
    let surf = dir.join("patch.json");
    fairway::io::save(&surf, &Document::new(Geometry::Surface(test_surface()))).unwrap();
    let objects: Vec<Geometry> = vec![test_curve_3d().into(), test_surface().into()];
    let multi = dir.join("two.IGS");
    std::fs::write(&multi, fairway::io::iges::write(&objects, &Default::default())).unwrap();
    let mut h = harness(App::default());
    path_action(&mut h, &surf, "Open path");
    assert!(h.state().surface.is_some());
    path_action(&mut h, &multi, "Import one object");
    assert!(h.state().object_pick.is_some(), "{:?}", h.state().error);
    assert!(
        h.state().surface.is_some(),
        "the surface stays open until a choice is made"
    );
    h.get_by_role_and_label(Role::Button, "Open object 1").click();
    h.run();
    assert!(h.state().surface.is_none(), "a curve returns to the curve editor");
    assert_eq!(h.state().doc.geometry, objects[0]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A curve whose drawing would overflow (it spans more than f64 holds) is not exported: the error says
/// why, nothing is written, and an existing file at the path is kept.
#[test]
fn svg_export_of_a_curve_too_large_to_draw_writes_nothing() {
    let dir = temp_dir("svg-huge");
    let pts = [
        DVec2::new(-1e308, 0.0),
        DVec2::new(0.0, 1e308),
        DVec2::new(1e308, 0.0),
        DVec2::new(1.5e308, -1e308),
    ];
    let c = BSplineCurve::new_2d(3, vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0], &pts).unwrap();
    let mut app = App::with_document(Document::new(Geometry::Curve(c)), None);
    let out = dir.join("huge.svg");
    std::fs::write(&out, "kept").unwrap();
    app.export_svg(&out);
    let err = app.error.clone().unwrap_or_default();
    assert!(
        err.contains("overflow") && err.contains("nothing was written"),
        "{err:?}"
    );
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "kept");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A STEP file opens through the same picker as IGES: its unit is shown in the picker, the status bar and
/// the tolerance heading, a broken entity is listed with its reason, and saving as STEP declares the
/// file's unit (the coordinates untouched).
#[test]
fn step_with_several_objects_opens_the_picker_with_its_unit_and_saves_in_that_unit() {
    use fairway::io::{Unit, step};
    let dir = temp_dir("step");
    let c2 = fairway_editor::demo_curve_n(9);
    let objects: Vec<Geometry> = vec![c2.clone().into(), test_surface().into(), test_curve_3d().into()];
    let opts = step::WriteOptions {
        unit: Unit::Inch,
        ..Default::default()
    };
    let text = step::write(&objects, &opts);
    // one more curve, broken: its weights list is one too long
    let extra = step::write(&[test_curve_3d().into()], &opts);
    let broken = extra.replacen("RATIONAL_B_SPLINE_CURVE((", "RATIONAL_B_SPLINE_CURVE((1.0,", 1);
    // the broken curve's instances, renumbered after the first file's
    let body = |t: &str| -> String {
        let a = t.find("DATA;\n").unwrap() + 6;
        let b = t.find("ENDSEC;\nEND-ISO").unwrap();
        t[a..b].to_string()
    };
    let shifted = body(&broken).replace('#', "#9");
    let merged = text.replace("ENDSEC;\nEND-ISO", &format!("{shifted}ENDSEC;\nEND-ISO"));
    let multi = dir.join("multi.stp");
    std::fs::write(&multi, merged).unwrap();

    let mut h = harness(App::default());
    let before = h.state().doc.clone();
    path_action(&mut h, &multi, "Import one object");
    assert!(h.state().object_pick.is_some(), "{:?}", h.state().error);
    assert_eq!(h.state().doc, before, "nothing opened before the choice");
    h.get_by_label("Choose an object");
    h.get_by_label("multi.stp holds 3 curves and surfaces (unit in):");
    h.get_by_label_contains("curve 2D, degree 3, 9 control points, entity");
    h.get_by_label_contains("surface, degree 3x2, 4x3 control points, entity");
    h.get_by_label_contains("curve 3D, degree 2, 4 control points, rational, entity");
    h.get_by_label_contains("skipped: 5 weights for 4 control points");
    h.get_by_role_and_label(Role::Button, "Open object 2").click();
    h.run();
    assert!(h.state().object_pick.is_none());
    assert!(h.state().surface.is_some(), "surface workspace");
    assert_eq!(h.state().doc.geometry, objects[1], "exact");
    assert_eq!(h.state().unit, Some(Unit::Inch));
    assert_eq!(
        h.state().path,
        None,
        "untitled: saving must not overwrite the STEP file"
    );
    h.get_by_label("unit in");
    h.get_by_label("Tolerance (in)");
    // saved as STEP: declares inch, the surface exact
    let out = dir.join("surface.step");
    path_action(&mut h, &out, "Save to path");
    let f = step::read_all(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!((f.unit, f.objects.as_slice()), (Some(Unit::Inch), &objects[1..2]));

    // the 2D curve, to the curve editor: the unit in the status bar and beside the tolerance
    path_action(&mut h, &multi, "Import one object");
    h.get_by_role_and_label(Role::Button, "Open object 1").click();
    h.run();
    assert!(h.state().surface.is_none());
    assert_eq!(h.state().doc.geometry, objects[0]);
    assert_eq!(h.state().unit, Some(Unit::Inch));
    h.get_by_label("Tolerance (in)");
    h.get_by_label("unit in");
    assert!(h.state().status.contains("(unit in)"), "{}", h.state().status);
    let out = dir.join("curve.stp");
    path_action(&mut h, &out, "Save to path");
    let f = step::read_all(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!((f.unit, f.objects.as_slice()), (Some(Unit::Inch), &objects[..1]));

    // a file of Fairway's own with one object opens directly, keeping its path and unit
    path_action(&mut h, &out, "Open path");
    assert!(h.state().object_pick.is_none());
    assert_eq!(h.state().path.as_deref(), Some(out.as_path()));
    assert_eq!(h.state().unit, Some(Unit::Inch));
    // a JSON file has no unit
    let json = dir.join("c.json");
    fairway::io::save(&json, &Document::new(objects[2].clone())).unwrap();
    path_action(&mut h, &json, "Open path");
    assert_eq!(h.state().unit, None);
    assert!(h.query_by_label("unit in").is_none());

    // a file that is not STEP: an error in user terms, the document kept
    let bad = dir.join("bad.stp");
    std::fs::write(&bad, "solid cube\nendsolid\n").unwrap();
    path_action(&mut h, &bad, "Open path");
    let e = h.state().error.clone().unwrap_or_default();
    assert!(
        e.contains("bad.stp") && e.contains("not a STEP (ISO 10303-21) file"),
        "{e}"
    );
    assert_eq!(h.state().doc.geometry, objects[2]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Type `text` into the exact tolerance field and press Enter.
fn type_tolerance(h: &mut Harness<'static, App>, text: &str) {
    h.get_by_role_and_label(Role::SpinButton, "Tolerance (exact)").focus();
    h.run();
    h.event(egui::Event::Text(text.into()));
    h.run();
    h.key_press(egui::Key::Enter);
    h.run();
}

/// The exact tolerance field takes a typed unit and converts it into the document's unit (0.05 mm in
/// an inch document is 1/508 in, the nearest double), shows the unit beside it, and keeps the old value
/// with a message in the user's terms for an entry that is not a tolerance — in both workspaces.
#[test]
fn tolerance_field_takes_typed_units_converted_into_the_documents_unit() {
    use fairway::io::Unit;
    let mut app = App::with_document(Document::new(fairway_editor::demo_curve_n(9).into()), None);
    app.unit = Some(Unit::Inch);
    let mut h = harness(app);
    h.get_by_label("Tolerance (in)");
    assert!(h.query_all_by_label("in").count() >= 1, "the unit beside the field");
    type_tolerance(&mut h, "0.05mm");
    assert_eq!(
        h.state().doc.settings.tolerance,
        Some(1.0 / 508.0),
        "{:?}",
        h.state().error
    );
    assert_eq!(h.state().error, None);
    // a plain number is in the document's unit
    type_tolerance(&mut h, "0.002");
    assert_eq!(h.state().doc.settings.tolerance, Some(0.002));
    type_tolerance(&mut h, "0.1 mil");
    assert_eq!(h.state().doc.settings.tolerance, Some(1e-4));
    // bad entries: the value kept, the reason on the error line
    for (text, reason) in [
        ("0.05 parsec", "\"parsec\" is not a length unit; known units: in, mm,"),
        ("abc", "\"abc\" is not a number"),
        ("-1mm", "-1 mm is not a tolerance: it must be more than 0"),
        ("nan", "\"nan\" is not a finite length"),
    ] {
        h.state_mut().error = None;
        type_tolerance(&mut h, text);
        assert_eq!(h.state().doc.settings.tolerance, Some(1e-4), "{text}");
        let e = h.state().error.clone().unwrap_or_default();
        assert!(
            e.contains(reason) && e.ends_with("the tolerance stays 0.0001 in"),
            "{text}: {e}"
        );
    }
    // one undo step per accepted entry: back to 0.002 in
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run();
    assert_eq!(h.state().doc.settings.tolerance, Some(0.002));

    // a surface in millimetres: 0.002 in is 0.0508 mm
    let mut app = App::with_document(Document::new(test_surface().into()), None);
    app.unit = Some(Unit::Millimeter);
    let mut h = harness(app);
    h.get_by_label("Tolerance (mm)");
    type_tolerance(&mut h, "0.002in");
    assert_eq!(h.state().doc.settings.tolerance, Some(0.0508), "{:?}", h.state().error);

    // a document without a unit: plain numbers only
    let mut h = harness(App::with_document(Document::new(test_curve_3d().into()), None));
    h.get_by_label("model units");
    type_tolerance(&mut h, "0.03");
    assert_eq!(h.state().doc.settings.tolerance, Some(0.03));
    type_tolerance(&mut h, "0.05mm");
    assert_eq!(h.state().doc.settings.tolerance, Some(0.03));
    let e = h.state().error.clone().unwrap_or_default();
    assert!(
        e.contains("the document declares no length unit; type a plain number"),
        "{e}"
    );
}

/// A trimmed face keeps its bounds through the editor (issue 29): opened from a STEP file of one face,
/// imported through the picker from an IGES file with other objects beside it, and saved back as IGES,
/// STEP and a .ron document (each read back with the same loops; the surface workspace draws them).
#[test]
fn a_trimmed_face_keeps_its_trim_when_opened_picked_and_saved() {
    use fairway::io::{iges, load_scene, step};
    use fairway::trim::{FaceTrim, TrimLoop};
    let dir = temp_dir("trims");
    let s = test_surface();
    let ((u0, u1), (v0, v1)) = s.domain();
    let at = |a: f64, b: f64| DVec3::new(u0 + a * (u1 - u0), v0 + b * (v1 - v0), 0.0);
    let corners = [at(0.1, 0.1), at(0.9, 0.2), at(0.8, 0.9), at(0.15, 0.8)];
    let edges = (0..4)
        .map(|k| {
            BSplineCurve::try_new(
                1,
                vec![0.0, 0.0, 1.0, 1.0],
                vec![corners[k], corners[(k + 1) % 4]],
                None,
                2,
            )
        })
        .collect::<Result<Vec<_>, _>>()
        .unwrap();
    let trim = FaceTrim {
        loops: vec![TrimLoop { outer: true, edges }],
    };
    let face: Geometry = s.into();
    let one = dir.join("face.stp");
    let text = step::write_trimmed(
        std::slice::from_ref(&face),
        &[String::new()],
        &[Some(trim.clone())],
        &Default::default(),
    );
    std::fs::write(&one, text).unwrap();
    let saved_trim = |p: &Path| {
        let (scene, notices) = load_scene(p).unwrap();
        assert_eq!(scene.objects.len(), 1, "{}: {notices:?}", p.display());
        scene.objects[0].trim.clone()
    };

    // opened directly: the face and its trim
    let mut h = harness(App::default());
    path_action(&mut h, &one, "Open path");
    assert!(h.state().surface.is_some(), "{:?}", h.state().error);
    assert_eq!(h.state().objects.len(), 1);
    let got = h.state().objects[0].trim.clone().expect("opened with its trim");
    assert_eq!(got.summary(), "trimmed: 1 outer loop, 0 inner loops, 4 edges");
    assert!(
        h.state_mut().surface.as_ref().unwrap().trim.is_some(),
        "the 3D view draws the loop"
    );
    for (ext, exact) in [("igs", true), ("stp", false), ("ron", true)] {
        let out = dir.join(format!("saved.{ext}"));
        path_action(&mut h, &out, "Save to path");
        assert!(h.state().error.is_none(), "{:?}", h.state().error);
        let back = saved_trim(&out).unwrap_or_else(|| panic!("saved as .{ext} without its trim"));
        if exact {
            assert_eq!(back, got, "{ext}");
        } else {
            assert_eq!(back.summary(), got.summary());
        }
    }

    // imported through the picker from an IGES file with a curve before the face
    let multi = dir.join("multi.igs");
    let objects = vec![test_curve_3d().into(), face.clone()];
    let text = iges::write_trimmed(&objects, &[], &[None, Some(trim.clone())], &Default::default());
    std::fs::write(&multi, text).unwrap();
    path_action(&mut h, &multi, "Import one object");
    assert!(h.state().object_pick.is_some(), "{:?}", h.state().error);
    h.get_by_role_and_label(Role::Button, "Open object 2").click();
    h.run();
    assert_eq!(h.state().doc.geometry, face);
    assert_eq!(
        h.state().objects[0].trim.as_ref(),
        Some(&trim),
        "picked with its trim, exactly"
    );
    let out = dir.join("picked.igs");
    path_action(&mut h, &out, "Save to path");
    assert_eq!(saved_trim(&out), Some(trim));
    let _ = std::fs::remove_dir_all(&dir);
}
