//! The editor shell: one history for every document edit (fairing options included, one step per
//! drag) and for both workspaces, and the shortcut table that dispatches and fills the help overlay.

mod common;

use eframe::egui;
use egui::accesskit::Role;
use egui::{Key, Modifiers};
use egui_kittest::kittest::Queryable;
use fairway::fair::Integrator;
use fairway_editor::shortcuts::SHORTCUTS;
use fairway_editor::{App, Command};

use common::{asset, drag, harness};

fn ctrl_z(h: &mut egui_kittest::Harness<'static, App>) {
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
}

#[test]
fn tolerance_set_in_the_panel_is_restored_by_ctrl_z() {
    let mut h = harness(App::default());
    let t0 = h.state().tolerance();
    let d = h.state().curve_ws.view.diag;
    h.get_by_role_and_label(Role::Slider, "Tolerance")
        .set_value_accesskit(d * 0.01);
    h.run();
    let t = h.state().tolerance();
    assert!((t / (d * 0.01) - 1.0).abs() < 1e-9, "{t}");
    ctrl_z(&mut h);
    assert_eq!(h.state().doc.settings.tolerance, None);
    assert_eq!(h.state().tolerance(), t0);
    assert!(!h.state().is_dirty());
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    h.run();
    assert_eq!(h.state().tolerance(), t);
}

#[test]
fn fairing_options_are_undo_steps_and_a_slider_drag_is_one() {
    let mut h = harness(App::default());
    let (a, b) = h.state().curve().domain();
    h.state_mut()
        .apply(Command::SetRegion(Some((a + 0.2 * (b - a), a + 0.8 * (b - a)))));
    h.run();
    let before = h.state().prefs.fair;
    // a choice in the Advanced section
    h.get_by_label("Advanced").click();
    h.run();
    h.get_by_label("RK2").click();
    h.run();
    assert_eq!(h.state().prefs.fair.integrator, Integrator::Rk2);
    ctrl_z(&mut h);
    assert_eq!(h.state().prefs.fair, before, "Ctrl+Z restores the options");
    assert!(h.state().region().is_some(), "and only them");
    // a drag along the strength slider: several values, one undo step
    let r = h.get_by_role_and_label(Role::Slider, "Strength").rect();
    let path: Vec<_> = (0..=5)
        .map(|k| egui::pos2(r.left() + 4.0 + k as f32 * 0.15 * r.width(), r.center().y))
        .collect();
    drag(&mut h, &path);
    let dragged = h.state().prefs.fair.strength;
    assert!(dragged.is_some() && dragged != before.strength, "{dragged:?}");
    ctrl_z(&mut h);
    assert_eq!(h.state().prefs.fair, before, "one Ctrl+Z undoes the whole drag");
    assert!(h.state().region().is_some());
}

#[test]
fn a_shortcut_from_the_table_runs_its_command_and_is_listed_in_the_help() {
    let mut h = harness(App::default());
    let row = |f: fn(&Command) -> bool| SHORTCUTS.iter().find(|s| f(&s.command)).expect("in the table");
    let toggle = row(|c| matches!(c, Command::ToggleBeforeAfter));
    assert!(h.state().curve_ws.compare.show_after);
    h.key_press_modifiers(toggle.modifiers, toggle.key);
    h.run();
    assert!(!h.state().curve_ws.compare.show_after, "the shortcut ran its command");

    assert!(h.query_by_label("Keyboard shortcuts").is_none());
    let help = row(|c| matches!(c, Command::ToggleHelp));
    h.key_press_modifiers(help.modifiers, help.key);
    h.run();
    assert!(h.state().show_help);
    for s in &SHORTCUTS {
        let keys = h.ctx.format_shortcut(&s.shortcut());
        assert!(h.query_all_by_label(&keys).next().is_some(), "the help lacks {keys}");
        assert!(
            h.query_all_by_label(s.description).next().is_some(),
            "the help lacks “{}”",
            s.description
        );
    }
    h.key_press_modifiers(help.modifiers, help.key);
    h.run();
    assert!(!h.state().show_help);
}

#[test]
fn surface_edits_go_through_the_shell_history() {
    let mut h = harness(App::open_or_demo(Some(&asset("bumpy_surface.json"))));
    assert!(h.state().surface.is_some());
    assert!(!h.state().history.can_undo());
    h.get_by_role_and_label(Role::Button, "Whole surface").click();
    h.run();
    let region = h.state().doc.settings.region_uv;
    assert!(region.is_some());
    assert!(
        h.state().history.can_undo(),
        "the edit is a step of the shell's history"
    );
    ctrl_z(&mut h);
    assert_eq!(h.state().doc.settings.region_uv, None);
    assert!(!h.state().is_dirty());
    h.key_press_modifiers(Modifiers::COMMAND, Key::Y);
    h.run();
    assert_eq!(h.state().doc.settings.region_uv, region);
    assert!(h.state().title().ends_with("(surface)"), "{}", h.state().title());
}
