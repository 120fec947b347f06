//! Fairway's editor: an eframe app for fairing B-spline curves and surfaces.
//!
//! One shell ([`App`], in [`shell`]) owns the document, its file, the undo [`History`], the status
//! line, the menus and the [`shortcuts`]; the open document is shown by a [`Workspace`]: the curve
//! workspace ([`curve_ws`]: canvas, κ plot, fairing panel) or the surface workspace ([`surface_ui`]).
//! Panels push [`Command`]s; the shell applies them after the panels, and every document edit
//! (fairing options included) is one undo step ([`commands`]). No fairing maths lives here: the
//! editor calls the core.

pub mod autosave;
pub mod bench;
pub mod canvas;
pub mod canvas_scene;
pub mod commands;
pub mod curve3d;
pub mod curve_panel;
pub mod curve_ws;
pub mod fair_ui;
pub mod fairing;
pub mod guard;
pub mod history;
pub mod interchange;
pub mod jobs;
pub mod measures_ui;
pub mod plot;
pub mod prefs;
pub mod region;
pub mod sampled;
pub mod scene_view;
pub mod shell;
pub mod shortcuts;
pub mod suggest;
pub mod surface_ui;
pub mod view3d;
pub mod widgets;
pub mod workspace;

use fairway::{BSplineCurve, DVec2};

pub use bench::Bench;
pub use commands::{Command, Pending};
pub use curve_ws::{CurveView, CurveWorkspace};
pub use fair_ui::{Compare, TargetDrag, TargetTool};
pub use fairing::{FairOptions, Fairing};
pub use history::{Gesture, History};
pub use prefs::{CombScaling, Prefs};
pub use sampled::Sampled;
pub use shell::App;
pub use surface_ui::SurfaceWorkspace;
pub use widgets::tolerance_heading;
pub use workspace::Workspace;

/// A noisy car-roof-like cubic curve (used when no file is given and no
/// sample is found): 40 control points on a flat arc with a deterministic
/// ripple.
pub fn demo_curve() -> BSplineCurve {
    demo_curve_n(40)
}

/// The demo curve with `n` (≥ 4) control points.
pub fn demo_curve_n(n: usize) -> BSplineCurve {
    let n = n.max(4);
    let p = 3;
    let pts: Vec<DVec2> = (0..n)
        .map(|i| {
            let t = i as f64 / (n - 1) as f64;
            let x = 2.0 * t;
            let y = 0.35 * (std::f64::consts::PI * t).sin() + 0.004 * ((i * 7919 % 13) as f64 / 6.0 - 1.0);
            DVec2::new(x, y)
        })
        .collect();
    let inner = n - p - 1;
    let mut knots = vec![0.0; p + 1];
    knots.extend((1..=inner).map(|k| k as f64 / (inner + 1) as f64));
    knots.extend(vec![1.0; p + 1]);
    BSplineCurve::new_2d(p, knots, &pts).expect("valid demo curve")
}
