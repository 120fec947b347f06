//! Shared kittest set-up for the editor's GUI tests: `mod common;` in a test
//! file, then `common::harness(app)`, `common::drag(&mut h, &path)` and
//! `common::asset("name")`. Each test binary compiles this module on its own,
//! so helpers one binary does not use are allowed to be dead there.
#![allow(dead_code)]

use std::collections::HashMap;
use std::path::PathBuf;

use eframe::egui;
use egui::Pos2;
use egui_kittest::Harness;
use fairway_editor::App;

/// Window size of every GUI test (large enough for all panels).
pub const SIZE: egui::Vec2 = egui::vec2(1400.0, 900.0);

/// A harness that shows `app` in a 1400×900 window, run once (first layout done). After each frame it
/// finishes the background jobs the frame started ([`App::finish_jobs`]: the surface preview's full
/// fair, "Fair all"), so a test sees their results after the frame, deterministically; tests of the
/// jobs themselves use [`harness_without_waiting`].
pub fn harness(app: App) -> Harness<'static, App> {
    let mut h = Harness::builder().with_size(SIZE).build_ui_state(
        |ui, app: &mut App| {
            app.show(ui);
            app.finish_jobs();
        },
        app,
    );
    h.run();
    h
}

/// A harness that shows `app` as the editor does: background jobs run on while frames go on, and a
/// frame takes a job's result only once it has finished. Stepped by hand (`h.step()`); a test waits
/// for the jobs with [`App::wait_for_jobs`].
pub fn harness_without_waiting(app: App) -> Harness<'static, App> {
    let mut h = Harness::builder()
        .with_size(SIZE)
        .build_ui_state(|ui, app: &mut App| app.show(ui), app);
    h.step();
    h
}

/// Drag with the primary button through `path` (first point: press, last: release).
pub fn drag(h: &mut Harness<'static, App>, path: &[Pos2]) {
    drag_with(h, path, egui::Modifiers::NONE);
}

/// Like [`drag`], with `modifiers` held during the whole gesture (e.g. Ctrl).
pub fn drag_with(h: &mut Harness<'static, App>, path: &[Pos2], modifiers: egui::Modifiers) {
    h.event(egui::Event::ModifiersChanged(modifiers));
    h.hover_at(path[0]);
    h.step();
    h.drag_at(path[0]);
    h.step();
    for &p in &path[1..] {
        h.hover_at(p);
        h.step();
    }
    h.drop_at(*path.last().unwrap());
    h.run();
    h.event(egui::Event::ModifiersChanged(egui::Modifiers::NONE));
    h.run();
}

/// Path of a file in the workspace's `assets/` folder.
pub fn asset(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets")
        .join(name)
}

/// A harness with the asset `name` open (as from the command line), run once.
pub fn harness_with_asset(name: &str) -> Harness<'static, App> {
    let path = asset(name);
    let doc = fairway::io::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    harness(App::with_document(doc, Some(path)))
}

/// In-memory eframe storage.
#[derive(Default)]
pub struct MemStorage(pub HashMap<String, String>);

impl eframe::Storage for MemStorage {
    fn get_string(&self, key: &str) -> Option<String> {
        self.0.get(key).cloned()
    }
    fn set_string(&mut self, key: &str, value: String) {
        self.0.insert(key.to_owned(), value);
    }
    fn remove_string(&mut self, key: &str) {
        self.0.remove(key);
    }
    fn flush(&mut self) {}
}
