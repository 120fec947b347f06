//! A seeded "monkey": random drags, clicks, scrolls and keys over the whole editor window on a copy
//! of the sample document in a temporary folder (saves go there; no autosave). After every action: no
//! panic (a panic fails the test), no internal error reported by the engine guard, the curve finite,
//! a region (if any) finite and inside the curve's domain, a tolerance (if any) positive. The short
//! run is part of the tests; `cargo test -p fairway-editor --test monkey -- --ignored` runs long.

use eframe::egui;
use egui::{Event, Key, Modifiers, PointerButton, Pos2};
use egui_kittest::Harness;
use fairway::Geometry;
use fairway_editor::App;

mod common;
use common::{SIZE, asset};

/// splitmix64: a small seeded generator (no dependency).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn pos(&mut self) -> Pos2 {
        Pos2::new(self.unit() * SIZE.x, self.unit() * SIZE.y)
    }
}

/// What must hold after every action.
fn check(h: &Harness<'static, App>, file: &str, seed: u64, step: usize, what: &str) {
    let app = h.state();
    let at = format!("{file}, seed {seed}, action {step} ({what})");
    if let Some(e) = app.error.as_deref() {
        assert!(!e.contains("internal error"), "{at}: {e}");
    }
    if let (Some(_), Geometry::Surface(surface)) = (&app.surface, &app.doc.geometry) {
        if let Some(((u1, u2), (v1, v2))) = app.doc.settings.region_uv {
            let ((a, b), (c, d)) = surface.domain();
            let inside =
                |x: f64, lo: f64, hi: f64| x.is_finite() && x >= lo - 1e-9 * (hi - lo) && x <= hi + 1e-9 * (hi - lo);
            assert!(
                inside(u1, a, b) && inside(u2, a, b) && inside(v1, c, d) && inside(v2, c, d),
                "{at}: surface region ({u1}, {u2}) × ({v1}, {v2}) outside the domain"
            );
        }
        if let Some(t) = app.doc.settings.tolerance {
            assert!(t.is_finite() && t > 0.0, "{at}: tolerance {t}");
        }
        return;
    }
    let c = app.curve();
    assert!(c.points().iter().all(|p| p.is_finite()), "{at}: curve not finite");
    if let Some((u1, u2)) = app.doc.settings.region {
        let (a, b) = c.domain();
        let eps = 1e-9 * (b - a);
        assert!(u1.is_finite() && u2.is_finite(), "{at}: region ({u1}, {u2})");
        assert!(
            u1 >= a - eps && u1 <= b + eps && u2 >= a - eps && u2 <= b + eps,
            "{at}: region ({u1}, {u2}) outside [{a}, {b}]"
        );
    }
    if let Some(t) = app.doc.settings.tolerance {
        assert!(t.is_finite() && t > 0.0, "{at}: tolerance {t}");
    }
}

/// The primary button pressed or released at `pos`.
fn primary(h: &Harness<'static, App>, pos: Pos2, pressed: bool, modifiers: Modifiers) {
    h.event(Event::PointerButton {
        pos,
        button: PointerButton::Primary,
        pressed,
        modifiers,
    });
}

fn monkey(file: &str, seed: u64, actions: usize) {
    let dir = std::env::temp_dir().join(format!("fairway-monkey-{}-{seed}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(file);
    std::fs::copy(asset(file), &path).unwrap();
    let mut app = App::default();
    app.open_now(&path);
    let mut h = Harness::builder().with_size(SIZE).build_ui_state(
        |ui, app: &mut App| {
            app.show(ui);
            // background fairs finish within the frame that started them: the run stays
            // deterministic for its seed
            app.finish_jobs();
        },
        app,
    );
    h.run_steps(2);
    let mut rng = Rng(seed);
    let keys = [
        Key::Space,
        Key::Escape,
        Key::Enter,
        Key::Delete,
        Key::Z,
        Key::Y,
        Key::A,
        Key::F,
        Key::ArrowLeft,
        Key::ArrowRight,
        Key::Num0,
        Key::Num5,
        Key::Minus,
        Key::Period,
    ];
    for step in 0..actions {
        let what = match rng.below(10) {
            0..=3 => {
                // a drag through a few points (canvas regions, κ plot edits, sliders, handles, panels)
                let mods = if rng.below(4) == 0 {
                    Modifiers::CTRL
                } else {
                    Modifiers::NONE
                };
                h.event(Event::ModifiersChanged(mods));
                let mut p = rng.pos();
                h.event(Event::PointerMoved(p));
                h.step();
                primary(&h, p, true, mods);
                h.step();
                for _ in 0..1 + rng.below(5) {
                    p += egui::vec2(rng.unit() - 0.5, rng.unit() - 0.5) * 300.0;
                    h.event(Event::PointerMoved(p));
                    h.step();
                }
                primary(&h, p, false, mods);
                h.event(Event::ModifiersChanged(Modifiers::NONE));
                "drag"
            }
            4..=6 => {
                let p = rng.pos();
                h.event(Event::PointerMoved(p));
                h.step();
                for pressed in [true, false] {
                    primary(&h, p, pressed, Modifiers::NONE);
                }
                "click"
            }
            7 => {
                h.event(Event::PointerMoved(rng.pos()));
                h.event(Event::MouseWheel {
                    unit: egui::MouseWheelUnit::Line,
                    delta: egui::vec2(0.0, (rng.unit() - 0.5) * 10.0),
                    modifiers: Modifiers::NONE,
                    phase: egui::TouchPhase::Move,
                    source: egui::MouseWheelSource::Wheel,
                });
                "scroll"
            }
            8 => {
                let k = keys[rng.below(keys.len())];
                let mods = [Modifiers::NONE, Modifiers::CTRL, Modifiers::SHIFT][rng.below(3)];
                h.key_press_modifiers(mods, k);
                "key"
            }
            _ => {
                let s: String = (0..1 + rng.below(4))
                    .map(|_| b"0123456789.-e"[rng.below(13)] as char)
                    .collect();
                h.event(Event::Text(s));
                "text"
            }
        };
        h.run_steps(3);
        check(&h, file, seed, step, what);
    }
    let app = h.state();
    match &app.surface {
        Some(_) => println!(
            "{file} seed {seed}: surface region {:?}, tolerance {:?}, dirty {}, error {:?}",
            app.doc.settings.region_uv,
            app.doc.settings.tolerance,
            app.is_dirty(),
            app.error
        ),
        None => println!(
            "{file} seed {seed}: region {:?}, tolerance {:?}, preview {}, dirty {}, error {:?}",
            app.doc.settings.region,
            app.doc.settings.tolerance,
            app.curve_ws.preview().is_some(),
            app.is_dirty(),
            app.error
        ),
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn random_gestures_keep_the_editor_consistent() {
    for (file, seed) in [
        ("car_roof.ron", 1),
        ("car_roof.ron", 2),
        ("closed_section.json", 3),
        ("bumpy_surface.json", 4),
    ] {
        monkey(file, seed, 120);
    }
}

#[test]
#[ignore]
fn random_gestures_long_run() {
    let seeds: u64 = std::env::var("MONKEY_SEEDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20);
    for seed in 100..100 + seeds {
        for file in [
            "car_roof.ron",
            "closed_section.json",
            "spatial_curve.json",
            "bumpy_surface.json",
        ] {
            monkey(file, seed, 400);
        }
    }
}
