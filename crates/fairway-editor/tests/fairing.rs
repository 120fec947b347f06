//! Live fairing through the UI: select a region on the canvas, set the
//! tolerance, drag a target point on the κ plot, accept, undo, redo.

use eframe::egui;
use egui::{Pos2, Role};
use egui_kittest::kittest::Queryable;
use fairway::fair::PolishMethod;
use fairway_editor::App;

mod common;
use common::{drag, harness};

#[test]
fn select_fair_edit_target_accept_undo_redo() {
    let mut h = harness(App::default());
    let original = h.state().doc.clone();
    let c0 = h.state().curve().clone();
    // region by dragging along the curve on the canvas
    let path: Vec<Pos2> = (0..=8)
        .map(|k| {
            let app = h.state();
            app.curve_ws
                .canvas
                .to_screen(app.curve_ws.view.sampled.point_at_u(0.25 + 0.05 * k as f64))
        })
        .collect();
    drag(&mut h, &path);
    let (u1, u2) = h.state().region().expect("region");
    // tolerance through the slider
    let m = h.state().curve_ws.view.diag * 2e-3;
    h.get_by_role_and_label(Role::Slider, "Tolerance")
        .set_value_accesskit(m);
    h.run();
    let m = h.state().doc.settings.tolerance.unwrap();
    let p = h.state().curve_ws.preview().expect("a faired preview").clone();
    assert!(
        p.result.max_deviation <= m * (1.0 + 1e-9),
        "{} > {m}",
        p.result.max_deviation
    );

    // drag a target point in the middle of the region upwards on the κ plot
    let k0 = p.target.len() / 2;
    let (x, y) = {
        let app = h.state();
        let len = app.curve_ws.view.sampled.length;
        (
            app.curve_ws.plot.x(app.curve_ws.target_s(&p, k0), len),
            app.curve_ws.plot.y(p.target[k0]),
        )
    };
    drag(
        &mut h,
        &[Pos2::new(x, y), Pos2::new(x, y - 10.0), Pos2::new(x, y - 25.0)],
    );
    let t = h.state().doc.settings.target.clone().expect("hand-edited target");
    assert!(t[k0] > p.target[k0], "target point did not move up");
    assert_eq!(t[0], p.target[0], "the pinned end moved");
    let p2 = h.state().curve_ws.preview().expect("re-faired").clone();
    assert_eq!(p2.target, t, "the preview uses the edited target");
    assert!(p2.result.max_deviation <= m * (1.0 + 1e-9));

    // accept: one undo step; outside the region the curve is unchanged
    h.get_by_role_and_label(Role::Button, "Accept").click();
    h.run();
    let faired = h.state().curve().clone();
    assert_ne!(faired.points(), c0.points());
    for u in (0..=200).map(|i| i as f64 / 200.0) {
        if u < u1 - 1e-9 || u > u2 + 1e-9 {
            assert!(
                (faired.point(u) - c0.point(u)).length() < 1e-12,
                "moved outside the region at u = {u}"
            );
        }
    }
    let dev = fairway::measure::deviations(&c0, &faired, 2000);
    let max = dev.iter().copied().fold(0.0, f64::max);
    assert!(max <= m * (1.0 + 1e-6), "max deviation {max} > tolerance {m}");

    // undo the accept, the target drag, the tolerance and the region: exactly the original
    for _ in 0..4 {
        h.get_by_role_and_label(Role::Button, "Undo").click();
        h.run();
    }
    assert_eq!(h.state().doc, original);
    for _ in 0..4 {
        h.get_by_role_and_label(Role::Button, "Redo").click();
        h.run();
    }
    assert_eq!(h.state().curve(), &faired);
}

/// A closed curve faired whole: the full preview goes through the core's two-pass seam fairing (seam
/// faired, C2, original knots, band held, the seam's control points moved) and the panel says so; a
/// hand-edited target keeps the single pass, whose seam is held.
#[test]
fn closed_curve_is_faired_across_the_seam() {
    let mut h = common::harness_with_asset("closed_section.json");
    let c0 = h.state().curve().clone();
    h.get_by_role_and_label(Role::Button, "Whole curve").click();
    h.run();
    let m = h.state().tolerance();
    let p = h.state().curve_ws.preview().expect("a faired preview").clone();
    assert_eq!(p.result.seam, fairway::fair::Seam::Faired, "{:?}", p.result.seam);
    let f = &p.result.curve;
    assert_eq!(f.knots().values(), c0.knots().values());
    let (n, q) = (f.points().len(), f.points());
    assert!(q[0].distance(q[n - 1]) <= 1e-12, "closed");
    assert!(q[1].distance(c0.points()[1]) > 0.0, "the seam's control points moved");
    let dev = fairway::measure::deviations(&c0, f, 2000);
    assert!(dev.iter().all(|d| *d <= m * (1.0 + 1e-6)), "band");
    h.get_by_label_contains("faired across the seam");
    // a hand-edited target: one pass, seam held, and the panel says that instead
    let k = p.target.len() / 2;
    let mut t = p.target.clone();
    t[k] *= 1.02;
    h.state_mut().push(fairway_editor::Command::SetTarget {
        values: Some(t),
        pinned: vec![],
    });
    h.run();
    let p2 = h.state().curve_ws.preview().expect("re-faired").clone();
    assert!(
        matches!(p2.result.seam, fairway::fair::Seam::Held(_)),
        "{:?}",
        p2.result.seam
    );
    h.get_by_label_contains("seam held");
}

/// The demo curve, its whole length as the region at a tolerance of 2e-3 of the view's diagonal, and
/// Fairing ▸ Advanced open.
fn whole_curve_with_advanced_options() -> egui_kittest::Harness<'static, App> {
    let mut h = harness(App::default());
    h.get_by_role_and_label(Role::Button, "Whole curve").click();
    h.run();
    let m = h.state().curve_ws.view.diag * 2e-3;
    h.get_by_role_and_label(Role::Slider, "Tolerance")
        .set_value_accesskit(m);
    h.run();
    h.get_by_label("Advanced").click();
    h.run();
    h
}

/// The "E polish" slider (Fairing ▸ Advanced) sets the core's polish cap for the full fair: the same
/// trajectory run longer, so the paper's E of the preview never rises with more iterations and drops
/// from none to the default; the band holds each time.
#[test]
fn e_polish_slider_caps_the_polish_of_the_full_fair() {
    let mut h = whole_curve_with_advanced_options();
    let mut energy = |n: usize| {
        h.get_by_role_and_label(Role::Slider, "E polish")
            .set_value_accesskit(n as f64);
        h.run();
        assert_eq!(h.state().prefs.fair.polish_iterations, n);
        let m = h.state().doc.settings.tolerance.expect("tolerance");
        let p = h.state().curve_ws.preview().expect("a faired preview").clone();
        assert!(!p.draft);
        assert!(p.result.max_deviation <= m * (1.0 + 1e-9));
        p.result.energy
    };
    let (e0, e8, e24) = (energy(0), energy(8), energy(24));
    assert!(
        e8 < e0 && e24 <= e8,
        "E with 0 / 8 / 24 polish iterations: {e0} / {e8} / {e24}"
    );
}

/// The "Polish" choice (Fairing ▸ Advanced): each choice re-fairs the preview with that polish of the core,
/// inside the band — "Interior point" gives another curve than "Line search", "Variation" (the default)
/// no more curvature extrema than either — and choosing "Line search" again brings its result back, bit
/// for bit.
#[test]
fn polish_choice_refairs_the_preview_inside_the_band() {
    let mut h = whole_curve_with_advanced_options();
    let mut fair = |name: &str| {
        h.get_by_label(name).click();
        h.run();
        let m = h.state().doc.settings.tolerance.expect("tolerance");
        let p = h.state().curve_ws.preview().expect("a faired preview").clone();
        assert!(!p.draft);
        assert!(p.result.max_deviation <= m * (1.0 + 1e-9), "{name}: band");
        let mm = fairway::measure::measure(h.state().curve(), &p.result.curve);
        assert!(mm.dev_max <= m * (1.0 + 1e-9), "{name}: measured {}", mm.dev_max);
        (
            h.state().prefs.fair.polish_method,
            mm.n_curv_extrema,
            p.result.curve.points().to_vec(),
        )
    };
    let (m0, x0, p0) = fair("Line search");
    let (m1, x1, p1) = fair("Interior point");
    let (m3, x3, _) = fair("Variation");
    let (m2, _, p2) = fair("Line search");
    assert_eq!(
        (m0, m1, m3, m2),
        (
            PolishMethod::LineSearch,
            PolishMethod::InteriorPoint,
            PolishMethod::Variation,
            PolishMethod::LineSearch
        )
    );
    assert_ne!(p0, p1, "the interior point is another fair");
    assert!(
        x3 <= x0.min(x1),
        "extrema: variation {x3}, line search {x0}, interior point {x1}"
    );
    assert_eq!(p2, p0);
}

/// The bundled profile with a 20° kink (a triple knot at u = 0.6, its control point 23): a region across
/// it is faired stretch by stretch as `fairway fair` does, the kink kept (G1: its control points stay);
/// the κ plot's target is the stretches' targets end to end, and a hand edit of it reaches the stretch
/// it was made on; one button per stretch makes that stretch the region.
/// The κ plot's target tools respect a corner: flattening across it makes each stretch constant on its
/// own (the mean of its own dragged samples), and a drag's falloff stops at it.
#[test]
fn target_tools_keep_the_two_sides_of_a_corner_apart() {
    let mut h = common::harness_with_asset("kinked_profile.json");
    h.state_mut().push(fairway_editor::Command::SetRegion(Some((0.2, 0.8))));
    h.run();
    let p = h.state().curve_ws.preview().expect("faired stretch by stretch").clone();
    assert_eq!(p.breaks.len(), 1);
    let (b, n) = (p.breaks[0], p.target.len());
    let xy = |h: &egui_kittest::Harness<'static, App>, k: usize, on_target: bool| {
        let app = h.state();
        let len = app.curve_ws.view.sampled.length;
        let y = if on_target {
            app.curve_ws.plot.y(p.target[k])
        } else {
            app.curve_ws.plot.rect.unwrap().center().y
        };
        Pos2::new(app.curve_ws.plot.x(app.curve_ws.target_s(&p, k), len), y)
    };
    // flatten from 15 samples before the kink to 15 after it
    h.get_by_label("Flatten").click();
    h.run();
    let (a, c) = (b - 15, b + 15);
    let (qa, qc) = (xy(&h, a, false), xy(&h, c, false));
    drag(&mut h, &[qa, Pos2::new(0.5 * (qa.x + qc.x), qa.y), qc]);
    let t = h.state().doc.settings.target.clone().expect("hand-edited target");
    let (ka, kc) = (
        h.state().curve_ws.plot.x(
            h.state().curve_ws.target_s(&p, a),
            h.state().curve_ws.view.sampled.length,
        ),
        h.state().curve_ws.plot.x(
            h.state().curve_ws.target_s(&p, c),
            h.state().curve_ws.view.sampled.length,
        ),
    );
    assert_eq!((ka, kc), (qa.x, qc.x));
    for (lo, hi) in [(a, b - 1), (b, c)] {
        let mean = p.target[lo..=hi].iter().sum::<f64>() / (hi - lo + 1) as f64;
        for k in lo..=hi {
            if !p.pinned[k] {
                assert!(
                    (t[k] - mean).abs() < 1e-12,
                    "sample {k}: {} vs its stretch's mean {mean}",
                    t[k]
                );
            }
        }
    }
    assert_eq!(t[..a], p.target[..a], "before the dragged stretch");
    assert_eq!(t[c + 1..], p.target[c + 1..], "after the dragged stretch");
    h.get_by_role_and_label(Role::Button, "Undo").click();
    h.run();
    assert!(h.state().doc.settings.target.is_none());

    // drag a target point 3 samples before the kink up: its falloff (8 % of the region) would reach
    // past the kink, but the second stretch's target stays as it was
    h.get_by_label("Drag").click();
    h.run();
    let k0 = b - 3;
    let q0 = xy(&h, k0, true);
    drag(&mut h, &[q0, q0 - egui::vec2(0.0, 15.0), q0 - egui::vec2(0.0, 30.0)]);
    let t = h.state().doc.settings.target.clone().expect("hand-edited target");
    assert!(
        t[k0] > p.target[k0],
        "the dragged point rose: {} -> {}",
        p.target[k0],
        t[k0]
    );
    assert!(t[k0 - 10] > p.target[k0 - 10], "its falloff reaches its neighbours");
    assert_eq!(t[b..], p.target[b..], "the falloff crossed the corner");
    assert!(n > b + 10);
}

#[test]
fn a_region_across_a_corner_is_faired_stretch_by_stretch_with_the_corner_kept() {
    let mut h = common::harness_with_asset("kinked_profile.json");
    let c0 = h.state().curve().clone();
    h.state_mut().push(fairway_editor::Command::SetRegion(Some((0.2, 0.8))));
    h.run();
    let p = h.state().curve_ws.preview().expect("faired stretch by stretch").clone();
    h.get_by_label_contains("a corner kept (tangent break or stop): the 2 stretches between them");
    let m = h.state().tolerance();
    assert!(p.result.max_deviation <= m * (1.0 + 1e-9));
    assert_eq!(p.corners.len(), 1);
    assert!((p.corners[0].u - 0.6).abs() < 1e-12 && (p.corners[0].angle_deg - 20.0).abs() < 0.5);
    assert_eq!(p.stretches, vec![(0.2, 0.6), (0.6, 0.8)]);
    let f = &p.result.curve;
    for i in [12, 30] {
        assert_ne!(
            f.points()[i],
            c0.points()[i],
            "control point {i} on either side is faired"
        );
    }
    // G1 at the kink: its control point stays, its neighbours only slide along the tangents
    assert_eq!(f.points()[23], c0.points()[23], "the kink's control point moved");
    for i in [22, 24] {
        let dir = |c: &fairway::BSplineCurve| (c.points()[i] - c.points()[23]).normalize();
        assert!(
            (dir(f) - dir(&c0)).length() < 1e-9,
            "the tangent at the kink turned (control point {i})"
        );
    }
    // the target: both stretches' samples end to end, increasing along the region, and both sides faired
    assert_eq!(p.params.len(), p.target.len());
    assert!(p.params.windows(2).all(|w| w[0] <= w[1]));
    assert!(p.params[0] >= 0.2 - 1e-12 && *p.params.last().unwrap() <= 0.8 + 1e-12);
    let split = p.params.partition_point(|&u| u < 0.6);
    assert!(split > 3 && p.params.len() - split > 3);
    // the second stretch's target starts a line of its own on the κ plot, at the kink
    assert_eq!(p.breaks.len(), 1);
    let b = p.breaks[0];
    assert!(
        (p.params[b - 1] - 0.6).abs() < 1e-12 && (p.params[b] - 0.6).abs() < 1e-12,
        "{b}"
    );

    // raise the target over the second stretch (not its pinned end samples): that stretch bends more
    let mut values = p.target.clone();
    let n = values.len();
    for v in &mut values[split + 2..n - 2] {
        *v += 0.5;
    }
    let pinned = fairway_editor::fairing::pinned_indices(&p.pinned);
    h.state_mut().push(fairway_editor::Command::SetTarget {
        values: Some(values.clone()),
        pinned,
    });
    h.run();
    assert!(
        !h.state().curve_ws.fairing.target_mismatch,
        "the edited target fits the stretches' samples"
    );
    let q = h.state().curve_ws.preview().expect("re-faired").clone();
    assert_eq!(q.target, values, "the edited target is the one faired");
    let g = &q.result.curve;
    for i in 0..=23 {
        assert_eq!(
            g.points()[i],
            f.points()[i],
            "control point {i} of the first stretch or the kink moved"
        );
    }
    assert_ne!(g.points()[30], f.points()[30], "the edited stretch changed");
    assert!(q.result.max_deviation <= m * (1.0 + 1e-9));

    h.get_by_role_and_label(Role::Button, "u 0.6000 to 0.8000").click();
    h.run();
    assert_eq!(h.state().region(), Some((0.6, 0.8)));
    let r = h.state().curve_ws.preview().expect("the stretch is faired").clone();
    assert!(r.corners.is_empty(), "the stretch holds no corner");
    for i in 0..=23 {
        assert_eq!(
            r.result.curve.points()[i],
            c0.points()[i],
            "control point {i} outside the stretch moved"
        );
    }
}
