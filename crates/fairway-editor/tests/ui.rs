//! GUI tests driving the real editor through egui_kittest: widgets are found
//! by their accessible labels, the canvas and the κ plot by their labels and
//! rectangles; assertions are on the document.

use eframe::egui;
use egui::{Pos2, Role};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use fairway_editor::App;

mod common;
use common::{drag, harness};

fn curve_screen_point(h: &Harness<'static, App>, u: f64) -> Pos2 {
    let app = h.state();
    app.curve_ws.canvas.to_screen(app.curve_ws.view.sampled.point_at_u(u))
}

#[test]
fn drag_along_the_curve_selects_a_region_and_undo_redo_restore_it() {
    let mut h = harness(App::default());
    assert!(h.state().region().is_none());
    let before = h.state().doc.clone();
    // follow the curve as it is displayed at each step (the layout may change
    // while the region appears, e.g. the side panel grows)
    let us: Vec<f64> = (0..=6).map(|k| 0.3 + 0.05 * k as f64).collect();
    let p0 = curve_screen_point(&h, us[0]);
    h.hover_at(p0);
    h.step();
    h.drag_at(p0);
    h.step();
    for &u in &us[1..] {
        let p = curve_screen_point(&h, u);
        h.hover_at(p);
        h.step();
    }
    let last = curve_screen_point(&h, *us.last().unwrap());
    h.drop_at(last);
    h.run();
    let (u1, u2) = h.state().region().expect("a region after dragging along the curve");
    assert!((u1 - 0.3).abs() < 0.01 && (u2 - 0.6).abs() < 0.01, "region {u1} {u2}");
    // one drag = one undo step: undo goes straight back to no region
    h.get_by_role_and_label(Role::Button, "Undo").click();
    h.run();
    assert_eq!(h.state().doc, before);
    h.get_by_role_and_label(Role::Button, "Redo").click();
    h.run();
    assert_eq!(h.state().region(), Some((u1, u2)));
}

#[test]
fn dragging_off_the_curve_pans_without_editing() {
    let mut h = harness(App::default());
    let rect = h.get_by_label("Canvas").rect();
    let c0 = h.state().curve_ws.canvas.center;
    let a = rect.left_top() + egui::vec2(30.0, 30.0);
    drag(&mut h, &[a, a + egui::vec2(40.0, 0.0), a + egui::vec2(80.0, 20.0)]);
    assert!(h.state().region().is_none());
    assert!(!h.state().is_dirty());
    assert!(
        (h.state().curve_ws.canvas.center - c0).length() > 0.0,
        "view did not pan"
    );
}

#[test]
fn drag_across_the_kappa_plot_selects_a_region() {
    let mut h = harness(App::default());
    let r = h.state().curve_ws.plot.rect.unwrap();
    let y = r.center().y;
    let (x1, x2) = (r.left() + 0.2 * r.width(), r.left() + 0.5 * r.width());
    drag(
        &mut h,
        &[Pos2::new(x1, y), Pos2::new(0.5 * (x1 + x2), y), Pos2::new(x2, y)],
    );
    let app = h.state();
    let (u1, u2) = app.region().expect("region from the κ plot");
    let len = app.curve_ws.view.sampled.length;
    let (s1, s2) = (
        app.curve_ws.view.sampled.s_at_u(u1),
        app.curve_ws.view.sampled.s_at_u(u2),
    );
    assert!(
        (s1 / len - 0.2).abs() < 0.01 && (s2 / len - 0.5).abs() < 0.01,
        "{s1} {s2} of {len}"
    );
}

#[test]
fn tolerance_slider_sets_the_document_tolerance_in_one_undo_step() {
    let mut h = harness(App::default());
    let t0 = h.state().doc.settings.tolerance;
    let d = h.state().curve_ws.view.diag;
    h.get_by_role_and_label(Role::Slider, "Tolerance")
        .set_value_accesskit(d * 0.01);
    h.run();
    let t = h.state().doc.settings.tolerance.expect("tolerance set");
    assert!((t / (d * 0.01) - 1.0).abs() < 1e-9, "{t}");
    assert!(h.state().is_dirty());
    h.get_by_role_and_label(Role::Button, "Undo").click();
    h.run();
    assert_eq!(h.state().doc.settings.tolerance, t0);
}

#[test]
fn whole_curve_button_and_bad_file_keep_the_document() {
    let mut h = harness(App::default());
    h.get_by_role_and_label(Role::Button, "Whole curve").click();
    h.run();
    assert_eq!(h.state().region(), Some(h.state().curve().domain()));
    let doc = h.state().doc.clone();
    let dir = std::env::temp_dir().join(format!("fairway-editor-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.json");
    std::fs::write(&bad, "{\"degree\": 3, \"knots\": [0,1], \"points\": [[0,0]]}").unwrap();
    h.state_mut().open_now(&bad);
    h.run();
    assert!(h.state().error.as_deref().unwrap_or("").contains("bad.json"));
    assert_eq!(h.state().doc, doc);
    // save, then reopen: the same document, not dirty
    let good = dir.join("saved.ron");
    h.state_mut().apply(fairway_editor::Command::SaveTo(good.clone()));
    assert!(!h.state().is_dirty());
    h.state_mut().open_now(&good);
    assert_eq!(h.state().doc, doc);
    assert!(h.state().title().contains("saved.ron"));
    let _ = std::fs::remove_dir_all(&dir);
}

fn sample_path() -> std::path::PathBuf {
    common::asset("car_roof.ron")
}

/// Open a file through the File menu's path field and the "Open path" button.
fn open_via_menu(h: &mut Harness<'static, App>, path: &std::path::Path) {
    h.state_mut().path_input.clear();
    h.get_by_role_and_label(Role::Button, "File").click();
    h.run();
    let field = h.get_by_role(Role::TextInput);
    field.focus();
    field.type_text(&path.display().to_string());
    h.run();
    h.get_by_role_and_label(Role::Button, "Open path").click();
    h.run();
}

#[test]
fn open_the_sample_suggest_a_region_and_fair_it() {
    let mut h = harness(App::default());
    let path = sample_path();
    open_via_menu(&mut h, &path);
    let expected = fairway::io::load(&path).unwrap();
    assert_eq!(h.state().doc, expected, "{:?}", h.state().error);
    assert!(h.state().title().contains("car_roof.ron"));
    // suggest, then one click on the best suggestion selects it
    h.get_by_role_and_label(Role::Button, "Suggest regions").click();
    h.run();
    let best = h.state().curve_ws.suggestions().expect("suggestions")[0];
    h.get_by_label_contains("#1 ").click();
    h.run();
    assert_eq!(h.state().region(), Some((best.u1, best.u2)));
    let m = h.state().tolerance();
    let p = h
        .state()
        .curve_ws
        .preview()
        .expect("a faired preview of the suggested region");
    assert!(p.result.max_deviation <= m * (1.0 + 1e-9));
    // the suggested stretch is wiggly and fairing it removes extrema there
    assert!(best.extrema >= 3);
    h.state_mut().curve_ws.fairing.update_measures(false);
    let (before, after) = h.state().curve_ws.fairing.measures.clone().unwrap();
    assert!(
        after.n_curv_extrema < before.n_curv_extrema,
        "{} -> {}",
        before.n_curv_extrema,
        after.n_curv_extrema
    );
}

#[test]
fn opening_over_unsaved_work_asks_first() {
    let mut h = harness(App::default());
    h.get_by_role_and_label(Role::Button, "Whole curve").click();
    h.run();
    let edited = h.state().doc.clone();
    assert!(h.state().is_dirty());
    assert!(h.state().title().starts_with('*'), "{}", h.state().title());
    open_via_menu(&mut h, &sample_path());
    assert!(h.state().confirm.is_some(), "no prompt");
    h.get_by_role_and_label(Role::Button, "Cancel").click();
    h.run();
    assert_eq!(h.state().doc, edited, "cancel kept the work");
    open_via_menu(&mut h, &sample_path());
    h.get_by_role_and_label(Role::Button, "Discard changes").click();
    h.run();
    assert_eq!(h.state().doc, fairway::io::load(&sample_path()).unwrap());
    assert!(!h.state().is_dirty());
}

#[test]
fn flatten_tool_makes_a_stretch_of_the_target_constant() {
    let mut h = harness(App::default());
    h.get_by_role_and_label(Role::Button, "Whole curve").click();
    h.run();
    let p = h.state().curve_ws.preview().expect("preview").clone();
    h.get_by_label("Flatten").click();
    h.run();
    let n = p.target.len();
    let (a, b) = (n / 4, n / 2);
    let (xa, xb, y) = {
        let app = h.state();
        let len = app.curve_ws.view.sampled.length;
        (
            app.curve_ws.plot.x(app.curve_ws.target_s(&p, a), len),
            app.curve_ws.plot.x(app.curve_ws.target_s(&p, b), len),
            app.curve_ws.plot.rect.unwrap().center().y,
        )
    };
    drag(
        &mut h,
        &[Pos2::new(xa, y), Pos2::new(0.5 * (xa + xb), y), Pos2::new(xb, y)],
    );
    let t = h.state().doc.settings.target.clone().expect("hand-edited target");
    let (lo, hi) = t[a + 1..b]
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), &v| (l.min(v), u.max(v)));
    assert!(hi - lo < 1e-12, "not flat: [{lo}, {hi}]");
    assert_eq!(
        t[..a.saturating_sub(2)],
        p.target[..a.saturating_sub(2)],
        "outside the stretch changed"
    );
    // one drag = one undo step
    h.get_by_role_and_label(Role::Button, "Undo").click();
    h.run();
    assert!(h.state().doc.settings.target.is_none());
}

/// A document whose saved settings do not fit its curve (a hand-edited or corrupted file): it opens
/// with its geometry, the bad settings are dropped with a message in the status bar, the document
/// shows as changed, and the editor settles (a NaN in the saved target used to re-fair every frame).
#[test]
fn saved_settings_that_do_not_fit_open_with_a_message() {
    let dir = std::env::temp_dir().join(format!("fairway-editor-settings-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let base = fairway::io::load(&sample_path()).unwrap();
    let (d0, d1) = base.geometry.as_curve().unwrap().domain();
    let at = |t: f64| d0 + t * (d1 - d0);
    /// A saved file: its region and target, the region the editor should keep, a word of the message.
    struct Case {
        name: &'static str,
        region: Option<(f64, f64)>,
        target: Option<Vec<f64>>,
        want: Option<(f64, f64)>,
        needle: &'static str,
    }
    let case = |name, region, target, want, needle| Case {
        name,
        region,
        target,
        want,
        needle,
    };
    let cases = [
        case("nan", Some((f64::NAN, at(0.5))), None, None, "not finite"),
        case("outside", Some((at(0.2), d1 + 1.0)), None, None, "outside the domain"),
        case(
            "backwards",
            Some((at(0.8), at(0.2))),
            None,
            Some((at(0.2), at(0.8))),
            "backwards",
        ),
        case(
            "target",
            Some((at(0.2), at(0.6))),
            Some(vec![f64::NAN; 5]),
            Some((at(0.2), at(0.6))),
            "non-finite",
        ),
    ];
    for Case {
        name,
        region,
        target,
        want,
        needle,
    } in cases
    {
        let mut doc = base.clone();
        doc.settings.region = region;
        doc.settings.target = target;
        let path = dir.join(format!("{name}.ron"));
        std::fs::write(&path, doc.to_ron().unwrap()).unwrap();
        let mut h = harness(App::default());
        h.state_mut().open_now(&path);
        // `run` fails if the editor keeps asking for frames
        h.run();
        h.run();
        let app = h.state();
        assert_eq!(app.doc.geometry, base.geometry, "{name}: the geometry is kept");
        assert_eq!(app.doc.settings.region, want, "{name}");
        assert_eq!(app.doc.settings.target, None, "{name}");
        let msg = app.error.clone().unwrap_or_default();
        assert!(msg.contains("did not fit") && msg.contains(needle), "{name}: {msg:?}");
        assert!(app.is_dirty(), "{name}: the changed settings show as unsaved");
        // the region that is left is used: the fairing preview ran on it
        if want.is_some() {
            assert!(matches!(app.curve_ws.fairing.preview, Some(Ok(_))), "{name}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Measures table describes the preview on screen: a new region at the same tolerance and target is
/// measured anew (it used to keep the old region's figures until the tolerance was touched), and the
/// region's own figures sit beside the whole curve's.
#[test]
fn measures_follow_a_new_region_and_show_the_regions_figures() {
    let mut h = harness(App::default());
    let path = sample_path();
    open_via_menu(&mut h, &path);
    let orig = match fairway::io::load(&path).unwrap().geometry {
        fairway::Geometry::Curve(c) => c,
        _ => panic!("a curve"),
    };
    let mut figures = vec![];
    for region in [(0.35, 0.55), (0.5, 0.8)] {
        h.state_mut().apply(fairway_editor::Command::SetRegion(Some(region)));
        h.run();
        h.state_mut().curve_ws.fairing.update_measures(false);
        assert!(!h.state().curve_ws.fairing.measures_stale());
        let p = h.state().curve_ws.preview().expect("a preview").result.curve.clone();
        let (_, after) = h.state().curve_ws.fairing.measures.clone().expect("measures");
        // the table's "after" is the preview on screen
        let now = fairway::measure::measure(&orig, &p);
        assert_eq!(after.n_curv_extrema, now.n_curv_extrema, "{region:?}");
        assert!((after.dev_max - now.dev_max).abs() <= 1e-12, "{region:?}");
        let ((eb, vb), (ea, va)) = h.state().curve_ws.fairing.region_measures.expect("region figures");
        let (e0, v0) = fairway::measure::region_curvature(&orig, region.0, region.1, after.threshold_delta);
        assert_eq!((eb, vb), (e0, v0));
        assert!(
            ea <= eb && va < vb,
            "{region:?}: region extrema {eb} -> {ea}, E_var {vb} -> {va}"
        );
        figures.push(after.dev_max);
    }
    assert_ne!(figures[0], figures[1], "the second region's measures are its own");
}
