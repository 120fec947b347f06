//! The screen, bullet by bullet, through the real UI (egui_kittest,
//! accessible labels): shared hover cursor, pin / smooth / strength / reset
//! of the target, end conditions and integrator, compare (Space, blend,
//! trio), the measures panel's max-deviation marker, keyboard shortcuts,
//! drag-and-drop and recent files, settings persisted in eframe storage,
//! tooltips. Assertions are on the document and the app's state.

use std::sync::Arc;

use eframe::egui;
use egui::{Key, Modifiers, Pos2, Role};
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use fairway::fair::{EndCondition, Integrator};
use fairway_editor::{App, CombScaling, TargetTool};

mod common;
use common::{MemStorage, asset, drag, harness};

/// The demo curve with the whole curve selected (a preview is ready).
fn whole_curve() -> Harness<'static, App> {
    let mut h = harness(App::default());
    h.get_by_role_and_label(Role::Button, "Whole curve").click();
    h.run();
    assert!(h.state().curve_ws.preview().is_some());
    h
}

/// Screen x of target sample `k` on the κ plot, and the plot's mid height.
fn plot_xy(h: &Harness<'static, App>, k: usize) -> (f32, f32) {
    let app = h.state();
    let p = app.curve_ws.preview().unwrap();
    let len = app.curve_ws.view.sampled.length;
    (
        app.curve_ws.plot.x(app.curve_ws.target_s(p, k), len),
        app.curve_ws.plot.rect.unwrap().center().y,
    )
}

/// A primary click at `q` (press and release without moving).
fn click_at(h: &mut Harness<'static, App>, q: Pos2) {
    h.hover_at(q);
    h.step();
    h.drag_at(q);
    h.step();
    h.drop_at(q);
    h.run();
}

/// Σ (second difference)² of `v` over `a..=b`.
fn roughness(v: &[f64], a: usize, b: usize) -> f64 {
    (a + 1..b).map(|k| (v[k - 1] - 2.0 * v[k] + v[k + 1]).powi(2)).sum()
}

#[test]
fn hovering_the_canvas_or_the_plot_moves_one_shared_cursor() {
    let mut h = harness(App::default());
    let (q, s_expected, ds) = {
        let app = h.state();
        let s = &app.curve_ws.view.sampled;
        let q = app.curve_ws.canvas.to_screen(s.point_at_u(0.4));
        (q, s.s_at_u(0.4), s.length / s.len() as f64)
    };
    h.hover_at(q);
    h.run();
    let hs = h.state().curve_ws.hover_s.expect("hover on the curve sets the cursor");
    assert!((hs - s_expected).abs() <= 2.0 * ds, "{hs} vs {s_expected}");
    // the status bar shows the cursor's s and κ
    assert!(h.query_by_label_contains("s = ").is_some());
    // hover on the plot: the cursor follows the plot's arc length
    let (r, len) = (
        h.state().curve_ws.plot.rect.unwrap(),
        h.state().curve_ws.view.sampled.length,
    );
    h.hover_at(Pos2::new(r.left() + 0.7 * r.width(), r.center().y));
    h.run();
    let hs = h.state().curve_ws.hover_s.expect("hover on the plot sets the cursor");
    assert!((hs / len - 0.7).abs() < 0.005, "{}", hs / len);
    // away from both: no cursor
    let c = h.get_by_label("Canvas").rect();
    h.hover_at(c.left_top() + egui::vec2(3.0, 3.0));
    h.run();
    assert!(h.state().curve_ws.hover_s.is_none());
}

#[test]
fn pin_tool_pins_a_target_value_that_a_drag_then_keeps() {
    let mut h = whole_curve();
    let n = h.state().curve_ws.preview().unwrap().target.len();
    let k = n / 2;
    let pins0 = h.state().curve_ws.preview().unwrap().pinned.clone();
    assert!(!pins0[k]);
    h.get_by_label("Pin").click();
    h.run();
    assert_eq!(h.state().curve_ws.tool, TargetTool::Pin);
    let (x, y) = plot_xy(&h, k);
    h.hover_at(Pos2::new(x, y));
    h.run();
    click_at(&mut h, Pos2::new(x, y));
    let p = h.state().curve_ws.preview().unwrap().clone();
    let mut want = pins0.clone();
    want[k] = true;
    assert_eq!(p.pinned, want, "one click pins the nearest sample, only it");
    assert!(h.state().doc.settings.pinned.contains(&k));
    let g_k = p.target[k];
    // a target drag next to the pin moves its neighbours, not the pinned value
    h.get_by_label("Drag").click();
    h.run();
    let (x1, _) = plot_xy(&h, k + 2);
    let y1 = {
        let app = h.state();
        app.curve_ws.plot.y(app.curve_ws.preview().unwrap().target[k + 2])
    };
    drag(
        &mut h,
        &[Pos2::new(x1, y1), Pos2::new(x1, y1 - 15.0), Pos2::new(x1, y1 - 30.0)],
    );
    let t = h.state().doc.settings.target.clone().expect("edited");
    assert_eq!(t[k], g_k, "the pinned value moved");
    assert!(t[k + 2] > p.target[k + 2]);
    assert_eq!(
        h.state().curve_ws.preview().unwrap().target,
        t,
        "re-faired with the edit"
    );
    // a second click on the same sample unpins it
    h.get_by_label("Pin").click();
    h.run();
    click_at(&mut h, Pos2::new(x, y));
    assert_eq!(h.state().curve_ws.preview().unwrap().pinned, pins0, "unpinned");
}

#[test]
fn smooth_brush_strength_slider_and_reset_target() {
    let mut h = whole_curve();
    // strength 0: the target is the original curvature itself
    h.get_by_role_and_label(Role::Slider, "Strength")
        .set_value_accesskit(0.0);
    h.run();
    let p0 = h.state().curve_ws.preview().unwrap().clone();
    assert_eq!(h.state().prefs.fair.strength, Some(0));
    assert_eq!(p0.target, p0.original);
    let n = p0.target.len();
    let (a, b) = (n / 4, n / 2);
    // the brush smooths the dragged stretch of that raw target
    h.get_by_label("Smooth").click();
    h.run();
    let ((xa, y), (xb, _)) = (plot_xy(&h, a), plot_xy(&h, b));
    drag(
        &mut h,
        &[Pos2::new(xa, y), Pos2::new(0.5 * (xa + xb), y), Pos2::new(xb, y)],
    );
    let t = h.state().doc.settings.target.clone().expect("hand-edited target");
    let (r0, r1) = (roughness(&p0.target, a, b), roughness(&t, a, b));
    assert!(r1 < 0.5 * r0, "roughness {r0} -> {r1}");
    assert_eq!(t[..a - 2], p0.target[..a - 2], "outside the stretch changed");
    assert_eq!(t[b + 2..], p0.target[b + 2..], "outside the stretch changed");
    // the strength slider is disabled while the target is hand-edited
    assert!(
        h.get_by_role_and_label(Role::Slider, "Strength")
            .accesskit_node()
            .is_disabled()
    );
    // reset: back to the automatic target
    h.get_by_role_and_label(Role::Button, "Reset target").click();
    h.run();
    assert!(h.state().doc.settings.target.is_none());
    assert_eq!(h.state().curve_ws.preview().unwrap().target, p0.target);
    // a stronger automatic target is smoother everywhere
    h.get_by_role_and_label(Role::Slider, "Strength")
        .set_value_accesskit(40.0);
    h.run();
    let p40 = h.state().curve_ws.preview().unwrap().clone();
    assert!(roughness(&p40.target, 1, n - 2) < 0.5 * roughness(&p0.target, 1, n - 2));
}

#[test]
fn end_conditions_and_integrator_re_fair_the_preview() {
    let mut h = harness(App::default());
    h.state_mut()
        .apply(fairway_editor::Command::SetRegion(Some((0.3, 0.6))));
    h.run();
    let m = h.state().tolerance();
    let c0 = h.state().curve().clone();
    // the default ends are G2: the faired curvature meets the original's at u1 and u2
    assert_eq!(h.state().ends(), [EndCondition::G2; 2]);
    let g2 = h.state().curve_ws.preview().unwrap().result.curve.clone();
    let kmax = h.state().curve_ws.view.sampled.kappa_range.1.abs().max(1e-9);
    for u in [0.3, 0.6] {
        let (ko, kf) = (c0.curvature(u), g2.curvature(u));
        assert!((ko - kf).abs() < 1e-6 * kmax, "κ jumps at u = {u}: {ko} vs {kf}");
    }
    // G0 at both ends (one button per end): a different fair, still in the band,
    // still joined in position
    for side in 0..2 {
        let buttons = h.get_all_by_label("G0").collect::<Vec<_>>();
        assert_eq!(buttons.len(), 2);
        buttons[side].click();
        h.run();
    }
    // the ends are the document's (saved with it), each click an undo step
    assert_eq!(h.state().ends(), [EndCondition::G0; 2]);
    assert_eq!(h.state().doc.settings.ends, Some([EndCondition::G0; 2]));
    h.state_mut().apply(fairway_editor::Command::Undo);
    h.run();
    assert_eq!(h.state().ends(), [EndCondition::G0, EndCondition::G2]);
    h.state_mut().apply(fairway_editor::Command::Redo);
    h.run();
    assert_eq!(h.state().ends(), [EndCondition::G0; 2]);
    let p = h.state().curve_ws.preview().unwrap().clone();
    assert_ne!(p.result.curve.points(), g2.points(), "G0 ends did not re-fair");
    assert!(p.result.max_deviation <= m * (1.0 + 1e-9));
    for u in [0.3, 0.6] {
        assert!(
            (c0.point(u) - p.result.curve.point(u)).length() < 1e-9,
            "gap at u = {u}"
        );
    }
    // Advanced ▸ integrator: Euler re-fairs and still holds the band
    h.get_by_label("Advanced").click();
    h.run();
    // (the integrated fit is one start of the default variation polish, which may pick another: the line
    // search polishes the fit itself)
    h.get_by_label("Line search").click();
    h.run();
    let p = h.state().curve_ws.preview().unwrap().clone();
    h.get_by_label("Euler").click();
    h.run();
    assert_eq!(h.state().prefs.fair.integrator, Integrator::Euler);
    let pe = h.state().curve_ws.preview().unwrap().clone();
    assert_ne!(pe.result.curve, p.result.curve, "the integrator did not re-fair");
    assert!(pe.result.max_deviation <= m * (1.0 + 1e-9));
}

/// "Ease G2 curve ends": re-fairs a region that reaches the curve's start (the start keeps its curvature,
/// the band holds) and leaves a region inside the curve exactly as it was.
#[test]
fn ease_g2_curve_ends_checkbox_re_fairs_a_region_at_the_curve_end() {
    let mut h = harness(App::default());
    let (d0, d1) = h.state().curve().domain();
    let inner = (d0 + 0.3 * (d1 - d0), d0 + 0.6 * (d1 - d0));
    h.state_mut().apply(fairway_editor::Command::SetRegion(Some(inner)));
    h.run();
    let inner_plain = h.state().curve_ws.preview().unwrap().result.curve.clone();
    let at_start = (d0, d0 + 0.5 * (d1 - d0));
    h.state_mut().apply(fairway_editor::Command::SetRegion(Some(at_start)));
    h.run();
    let plain = h.state().curve_ws.preview().unwrap().result.curve.clone();
    assert!(!h.state().prefs.fair.ease_ends);
    assert!(
        !h.get_by_role_and_label(Role::CheckBox, "Ease G2 curve ends")
            .accesskit_node()
            .is_disabled()
    );
    h.get_by_role_and_label(Role::CheckBox, "Ease G2 curve ends").click();
    h.run();
    assert!(h.state().prefs.fair.ease_ends);
    let m = h.state().tolerance();
    let c0 = h.state().curve().clone();
    let p = h.state().curve_ws.preview().unwrap().clone();
    assert_ne!(p.result.curve.points(), plain.points(), "easing did not re-fair");
    assert!(p.result.max_deviation <= m * (1.0 + 1e-9));
    let (ko, kf) = (c0.curvature(d0), p.result.curve.curvature(d0));
    assert!(
        (ko - kf).abs() < 1e-9 * ko.abs().max(1.0),
        "the G2 curve end keeps κ: {ko} vs {kf}"
    );
    h.state_mut().apply(fairway_editor::Command::SetRegion(Some(inner)));
    h.run();
    assert_eq!(
        h.state().curve_ws.preview().unwrap().result.curve.points(),
        inner_plain.points()
    );
    // nothing to ease there: the box is greyed out
    assert!(
        h.get_by_role_and_label(Role::CheckBox, "Ease G2 curve ends")
            .accesskit_node()
            .is_disabled()
    );
}

#[test]
fn compare_space_toggle_blend_overlay_and_the_trio() {
    let mut h = harness(App::default());
    h.state_mut()
        .apply(fairway_editor::Command::SetRegion(Some((0.3, 0.6))));
    h.run();
    assert!(h.state().curve_ws.compare.show_after);
    h.key_press(Key::Space);
    h.run();
    assert!(!h.state().curve_ws.compare.show_after, "Space shows the original");
    h.key_press(Key::Space);
    h.run();
    assert!(h.state().curve_ws.compare.show_after, "Space shows the result again");
    h.get_by_role_and_label(Role::Slider, "Blend").set_value_accesskit(0.25);
    h.run();
    assert_eq!(h.state().curve_ws.compare.blend, 0.25);
    h.get_by_role_and_label(Role::CheckBox, "Overlay original").click();
    h.run();
    assert!(!h.state().curve_ws.compare.overlay);
    // the trio: three fairs at m/3, m, 3m, each within its own band, shown side by side
    h.get_by_role_and_label(Role::CheckBox, "Tight / medium / loose")
        .click();
    h.run();
    let m = h.state().tolerance();
    let trio = h.state().curve_ws.fairing.trio.clone().expect("trio computed");
    let mut devs = vec![];
    for ((mi, r), f) in trio.iter().zip([1.0 / 3.0, 1.0, 3.0]) {
        assert!((mi / (m * f) - 1.0).abs() < 1e-12);
        let p = r.as_ref().expect("trio fair");
        assert!(p.result.max_deviation <= mi * (1.0 + 1e-9));
        devs.push(p.result.max_deviation);
    }
    assert!(devs[0] < devs[2], "tight deviates less than loose: {devs:?}");
    for (mi, _) in &trio {
        assert!(
            h.query_by_label(&format!("m = {mi:.2e}")).is_some(),
            "no view for m = {mi}"
        );
    }
    assert!(h.query_all_by_label_contains("κ extrema").count() >= 3);
}

#[test]
fn measures_panel_marks_where_the_deviation_is_largest() {
    let mut h = harness(App::default());
    h.state_mut()
        .apply(fairway_editor::Command::SetRegion(Some((0.3, 0.6))));
    h.run();
    let app = h.state();
    let (before, after) = app.curve_ws.fairing.measures.clone().expect("measures after the frame");
    let u = app.curve_ws.fairing.dev_at.expect("max-deviation marker");
    assert!((0.3..=0.6).contains(&u), "marker outside the region: {u}");
    let p = app.curve_ws.preview().unwrap();
    // the marked point is (one of) the farthest from the faired curve
    let proj = fairway::closest::CurveProjector::new(&p.result.curve, 32);
    let q = app.curve().point(u);
    let d = (proj.project(q).point - q).length();
    assert!(
        d >= 0.98 * after.dev_max && after.dev_max > 0.0,
        "{d} vs {}",
        after.dev_max
    );
    assert!(after.dev_max <= app.tolerance() * (1.0 + 1e-6));
    // the core's verified bound (the fairing panel's figure) bounds the measured deviation
    assert!(after.dev_max <= p.result.max_deviation * (1.0 + 1e-9));
    assert!(h.query_by_label_contains("deviation bound").is_some());
    assert!(
        before.dev_max < 1e-12,
        "the original deviates from itself: {}",
        before.dev_max
    );
    // counts print as integers, the original's round-off self-distance as 0
    let n = after.n_curv_extrema;
    // (another count may show the same number, so look for any node with it)
    assert!(h.query_all_by_label(&n.to_string()).next().is_some(), "no count {n}");
    assert!(h.query_all_by_label(&format!("{:.4}", n as f64)).next().is_none());
    assert!(h.query_all_by_label("0").next().is_some());
    for row in ["max deviation", "κ extrema", "inflections", "E (paper)", "∫(dκ/ds)² ds"] {
        assert!(h.query_by_label(row).is_some(), "no row {row}");
    }
}

#[test]
fn keyboard_shortcuts_undo_and_redo() {
    let mut h = whole_curve();
    let region = h.state().region();
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    assert_eq!(h.state().region(), None, "Ctrl+Z");
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    h.run();
    assert_eq!(h.state().region(), region, "Ctrl+Shift+Z");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    h.key_press_modifiers(Modifiers::COMMAND, Key::Y);
    h.run();
    assert_eq!(h.state().region(), region, "Ctrl+Y");
    // F fits the view, also after a zoom and a pan
    h.hover_at(h.get_by_label("Canvas").rect().left_top() + egui::vec2(3.0, 3.0));
    h.key_press(Key::F);
    h.run();
    let (ppu, c) = (h.state().curve_ws.canvas.ppu, h.state().curve_ws.canvas.center);
    h.state_mut().curve_ws.canvas.ppu *= 3.0;
    h.state_mut().curve_ws.canvas.center += fairway::DVec2::new(0.3, 0.1);
    h.key_press(Key::F);
    h.run();
    assert!((h.state().curve_ws.canvas.ppu / ppu - 1.0).abs() < 1e-9);
    assert!((h.state().curve_ws.canvas.center - c).length() < 1e-12);
}

fn temp_dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("fairway-screen-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A file dropped on the window (as winit hands it to egui).
#[derive(Debug)]
struct Dropped(std::path::PathBuf);

impl egui::DroppedFile for Dropped {
    fn path(&self) -> &std::path::Path {
        &self.0
    }
    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

#[test]
fn dropped_files_open_and_land_in_the_recent_menu() {
    let mut h = harness(App::default());
    let dir = temp_dir("drop");
    let roof = asset("car_roof.ron");
    h.input_mut().dropped_files.push(Arc::new(Dropped(roof.clone())));
    h.run();
    assert_eq!(h.state().doc, fairway::io::load(&roof).unwrap());
    assert!(h.state().title().starts_with("car_roof.ron"), "{}", h.state().title());
    let roof_abs = std::fs::canonicalize(&roof).unwrap();
    assert_eq!(h.state().prefs.recent.first(), Some(&roof_abs));
    // a bad dropped file: error in the UI, the document stays
    let bad = dir.join("bad.ron");
    std::fs::write(&bad, "not a document").unwrap();
    h.input_mut().dropped_files.push(Arc::new(Dropped(bad)));
    h.run();
    assert!(h.state().error.is_some());
    assert_eq!(h.state().doc, fairway::io::load(&roof).unwrap());
    // save a copy under another name, then reopen the roof from File ▸ Recent
    let copy = dir.join("copy.ron");
    h.state_mut().apply(fairway_editor::Command::SaveTo(copy.clone()));
    h.state_mut()
        .apply(fairway_editor::Command::SetRegion(Some((0.2, 0.3))));
    h.run();
    assert!(h.state().title().starts_with("* copy.ron"), "{}", h.state().title());
    h.state_mut().open_now(&copy);
    h.state_mut().apply(fairway_editor::Command::SetRegion(None));
    h.run();
    h.get_by_role_and_label(Role::Button, "File").click();
    h.run();
    h.get_by_label("Recent").hover();
    // the submenu opens after a few frames of hover
    let _ = h.try_run();
    h.get_by_label(&roof_abs.display().to_string()).click();
    let _ = h.try_run();
    let _ = h.try_run();
    assert_eq!(h.state().doc, fairway::io::load(&roof).unwrap());
    assert!(h.state().title().starts_with("car_roof.ron"), "{}", h.state().title());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn settings_set_in_the_ui_survive_a_restart() {
    let mut h = harness(App::default());
    h.get_by_label("log").click();
    h.run();
    h.get_by_role_and_label(Role::Slider, "Comb scale")
        .set_value_accesskit(3.0);
    h.run();
    h.get_by_role_and_label(Role::CheckBox, "Control polygon").click();
    h.run();
    h.state_mut()
        .apply(fairway_editor::Command::SetRegion(Some((0.3, 0.6))));
    h.run();
    h.get_all_by_label("G2").next().unwrap().click();
    h.run();
    h.state_mut().open_now(&asset("car_roof.ron"));
    let set = h.state().prefs.clone();
    assert_eq!(set.comb_scaling, CombScaling::Log);
    assert!((set.comb_scale - 3.0).abs() < 1e-9);
    assert!(!set.show_polygon);
    assert_eq!(set.fair.ends[0], EndCondition::G2);
    let mut mem = MemStorage::default();
    eframe::App::save(h.state_mut(), &mut mem);
    let mut fresh = App::default();
    fresh.load_prefs(&mem);
    let got = &fresh.prefs;
    assert_eq!(got.comb_scaling, set.comb_scaling);
    assert_eq!(got.comb_scale, set.comb_scale);
    assert_eq!(got.show_polygon, set.show_polygon);
    assert_eq!(got.fair, set.fair);
    assert_eq!(got.recent, set.recent);
    // a hand-edited store: clamped, never a panic; unreadable: nothing changes
    mem.0.insert(
        "prefs".into(),
        "(comb_scale: 1e300, fair: (strength: Some(999999999)))".into(),
    );
    let mut app = App::default();
    app.load_prefs(&mem);
    assert_eq!(app.prefs.comb_scale, 50.0);
    assert_eq!(app.prefs.fair.strength, Some(100_000));
    mem.0.insert("prefs".into(), "((((".into());
    let mut app = App::default();
    app.load_prefs(&mem);
    assert_eq!(app.prefs.comb_scale, 1.0);
}

#[test]
fn controls_show_their_tooltips() {
    let mut h = harness(App::default());
    for (label, role, tip) in [
        ("Whole curve", Role::Button, "Select the whole curve as the region"),
        ("Show comb", Role::CheckBox, "Curvature comb on the canvas"),
    ] {
        h.get_by_role_and_label(role, label).hover();
        // tooltips appear after egui's delay
        for _ in 0..40 {
            h.step();
            if h.query_by_label(tip).is_some() {
                break;
            }
        }
        assert!(h.query_by_label(tip).is_some(), "no tooltip on {label}");
    }
}

#[test]
fn region_handle_drag_exact_tolerance_field_and_ctrl_s() {
    let mut h = harness(App::default());
    h.state_mut()
        .apply(fairway_editor::Command::SetRegion(Some((0.3, 0.6))));
    h.run();
    let doc0 = h.state().doc.clone();
    // drag the end handle along the curve from u = 0.6 to u = 0.7: one undo step
    let path: Vec<Pos2> = (0..=5)
        .map(|k| {
            let app = h.state();
            app.curve_ws
                .canvas
                .to_screen(app.curve_ws.view.sampled.point_at_u(0.6 + 0.02 * k as f64))
        })
        .collect();
    drag(&mut h, &path);
    let (u1, u2) = h.state().region().unwrap();
    assert_eq!(u1, 0.3, "the start moved");
    assert!((u2 - 0.7).abs() < 0.005, "end handle at {u2}");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    assert_eq!(h.state().doc, doc0, "a handle drag is one undo step");
    // the exact tolerance field
    h.get_by_role_and_label(Role::SpinButton, "Tolerance (exact)")
        .set_value_accesskit(0.00123);
    h.run();
    assert_eq!(h.state().doc.settings.tolerance, Some(0.00123));
    assert!(h.state().curve_ws.preview().unwrap().result.max_deviation <= 0.00123 * (1.0 + 1e-9));
    // Ctrl+S saves to the document's path without a dialog
    let dir = temp_dir("ctrl-s");
    let path = dir.join("doc.ron");
    h.state_mut().apply(fairway_editor::Command::SaveTo(path.clone()));
    h.state_mut().apply(fairway_editor::Command::SetTolerance(0.002));
    h.run();
    assert!(h.state().is_dirty());
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    assert!(!h.state().is_dirty(), "{:?}", h.state().error);
    assert_eq!(fairway::io::load(&path).unwrap(), h.state().doc);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn wheel_zooms_about_the_pointer() {
    let mut h = harness(App::default());
    let q = h.get_by_label("Canvas").rect().center() + egui::vec2(100.0, -40.0);
    h.hover_at(q);
    h.run();
    let (ppu, w) = (h.state().curve_ws.canvas.ppu, h.state().curve_ws.canvas.to_world(q));
    h.event(egui::Event::MouseWheel {
        unit: egui::MouseWheelUnit::Point,
        delta: egui::vec2(0.0, 120.0),
        phase: egui::TouchPhase::Move,
        modifiers: Modifiers::NONE,
        source: egui::MouseWheelSource::Wheel,
    });
    let _ = h.try_run();
    for _ in 0..30 {
        h.step();
    }
    let app = h.state();
    assert!(
        app.curve_ws.canvas.ppu > 1.1 * ppu,
        "no zoom: {} -> {}",
        ppu,
        app.curve_ws.canvas.ppu
    );
    assert!(
        (app.curve_ws.canvas.to_world(q) - w).length()
            < 1e-9 * app.curve_ws.view.diag.max(1.0) + 1e-6 / app.curve_ws.canvas.ppu
    );
}

#[test]
fn region_edge_drag_on_the_kappa_plot_moves_only_that_end() {
    let mut h = harness(App::default());
    h.state_mut()
        .apply(fairway_editor::Command::SetRegion(Some((0.3, 0.6))));
    h.run();
    let (x0, x1, y, len) = {
        let app = h.state();
        let s = &app.curve_ws.view.sampled;
        let len = s.length;
        (
            app.curve_ws.plot.x(s.s_at_u(0.3), len),
            app.curve_ws.plot.x(s.s_at_u(0.3), len) - 40.0,
            app.curve_ws.plot.rect.unwrap().top() + 5.0,
            len,
        )
    };
    drag(
        &mut h,
        &[Pos2::new(x0, y), Pos2::new(0.5 * (x0 + x1), y), Pos2::new(x1, y)],
    );
    let app = h.state();
    let (u1, u2) = app.region().unwrap();
    assert_eq!(u2, 0.6, "the other end moved");
    let want = app.curve_ws.plot.s(x1, len);
    assert!(
        (app.curve_ws.view.sampled.s_at_u(u1) - want).abs() < 1e-3 * len,
        "start at u = {u1}"
    );
    assert!(u1 < 0.3);
}

#[test]
fn a_drag_previews_a_draft_and_the_release_fairs_in_full() {
    let mut h = harness(App::default());
    let pts: Vec<Pos2> = (0..=6)
        .map(|k| {
            let app = h.state();
            app.curve_ws
                .canvas
                .to_screen(app.curve_ws.view.sampled.point_at_u(0.3 + 0.05 * k as f64))
        })
        .collect();
    h.hover_at(pts[0]);
    h.step();
    h.drag_at(pts[0]);
    h.step();
    for &p in &pts[1..] {
        h.hover_at(p);
        h.step();
    }
    h.step();
    // still dragging: a draft (no E polish), in the band, and Accept waits
    assert!(h.state().curve_ws.drag_in_progress);
    let m = h.state().tolerance();
    let draft = h
        .state()
        .curve_ws
        .preview()
        .expect("live preview while dragging")
        .clone();
    assert!(draft.draft);
    assert!(draft.result.max_deviation <= m * (1.0 + 1e-9));
    assert!(
        h.get_by_role_and_label(Role::Button, "Accept")
            .accesskit_node()
            .is_disabled()
    );
    h.drop_at(*pts.last().unwrap());
    h.run();
    assert!(!h.state().curve_ws.drag_in_progress);
    let full = h.state().curve_ws.preview().expect("preview after the release").clone();
    assert!(!full.draft, "the release did not re-fair in full");
    assert_eq!(full.params, draft.params, "same region, same samples");
    assert!(full.result.max_deviation <= m * (1.0 + 1e-9));
    // the full fair (variation polish) is no less fair than the draft: no more curvature extrema
    let c0 = h.state().curve().clone();
    let (md, mf) = (
        fairway::measure::measure(&c0, &draft.result.curve),
        fairway::measure::measure(&c0, &full.result.curve),
    );
    assert!(
        mf.n_curv_extrema <= md.n_curv_extrema,
        "extrema {} -> {}",
        md.n_curv_extrema,
        mf.n_curv_extrema
    );
    assert_ne!(full.result.curve, draft.result.curve, "the polish changed nothing");
    assert!(
        !h.get_by_role_and_label(Role::Button, "Accept")
            .accesskit_node()
            .is_disabled()
    );
}
