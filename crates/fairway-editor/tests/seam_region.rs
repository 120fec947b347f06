//! A region across the seam of a closed curve (`u1 > u2`): selected by dragging along the canvas curve
//! past the seam, by dragging a region handle past it or by leaving the κ plot at an edge; faired
//! through the core's re-seamed setup (nothing moves outside the region); accepted and undone; saved
//! and loaded; a seam that cannot be re-seamed is an error message, not a panic.

use eframe::egui;
use egui::{Pos2, Role};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use fairway::BSplineCurve;
use fairway::io::Document;
use fairway_editor::{App, Command};

mod common;
use common::{asset, drag, harness};

fn closed_app() -> App {
    let path = asset("closed_section.json");
    let doc = fairway::io::load(&path).expect("closed sample");
    App::with_document(doc, Some(path))
}

/// Screen point of the canvas curve at parameter `u`.
fn at(h: &Harness<'static, App>, u: f64) -> Pos2 {
    let app = h.state();
    app.curve_ws.canvas.to_screen(app.curve_ws.view.sampled.point_at_u(u))
}

/// Drag along the canvas curve through the parameters `us` (each a frame).
fn drag_along(h: &mut Harness<'static, App>, us: &[f64]) {
    let path: Vec<Pos2> = us.iter().map(|&u| at(h, u)).collect();
    drag(h, &path);
}

/// Parameters from `from` forward to `to` through the seam of the domain [0, 1], in steps of about `step`.
fn through_seam(from: f64, to: f64, step: f64) -> Vec<f64> {
    let total = 1.0 - from + to;
    let n = (total / step).ceil() as usize;
    (0..=n)
        .map(|k| {
            let u = from + total * k as f64 / n as f64;
            if u > 1.0 { u - 1.0 } else { u }
        })
        .collect()
}

/// Control points whose support `[t_i, t_{i+p+1}]` lies in `[lo, hi]` (the untouched stretch).
fn supported_in(c: &BSplineCurve, lo: f64, hi: f64) -> Vec<usize> {
    let (k, p) = (c.knots().values(), c.degree());
    (0..c.n_points())
        .filter(|&i| k[i] >= lo && k[i + p + 1] <= hi)
        .collect()
}

#[test]
fn canvas_drag_past_the_seam_selects_faires_and_accepts_a_region_across_it() {
    let mut h = harness(closed_app());
    let c0 = h.state().curve().clone();
    assert!(h.state().curve_ws.view.closed);
    drag_along(&mut h, &through_seam(0.85, 0.15, 0.02));
    let (u1, u2) = h.state().region().expect("a region");
    assert!(u1 > u2, "not across the seam: {u1} {u2}");
    assert!((u1 - 0.85).abs() < 0.01 && (u2 - 0.15).abs() < 0.01, "{u1} {u2}");
    assert!(h.state().history.can_undo());
    // the panel's readout says so
    h.get_by_label_contains("(across the seam)");

    // the full preview (the drag is over): faired through the re-seamed setup, back on the original knots
    let m = h.state().tolerance();
    let p = h.state().curve_ws.preview().expect("a faired preview").clone();
    assert!(!p.draft);
    assert!(h.state().curve_ws.fairing.across_seam());
    assert_eq!(p.result.seam, fairway::fair::Seam::Faired);
    let f = &p.result.curve;
    assert_eq!(f.knots(), c0.knots());
    let n = f.n_points();
    assert!(f.points()[0].distance(f.points()[n - 1]) <= 1e-12, "still closed");
    // outside the region nothing moves: the control points supported in [u2, u1], and the curve there
    let outside = supported_in(&c0, u2, u1);
    assert!(outside.len() > n / 3, "{} of {n}", outside.len());
    for &i in &outside {
        assert!(
            f.points()[i].distance(c0.points()[i]) <= 1e-12,
            "control point {i} outside the region moved"
        );
    }
    for k in 0..=100 {
        let u = u2 + (u1 - u2) * k as f64 / 100.0;
        assert!(f.point(u).distance(c0.point(u)) <= 1e-12, "moved at u = {u}");
    }
    // inside it, on both sides of the seam, the curve changed
    let moved = |u: f64| f.point(u).distance(c0.point(u));
    assert!(moved(0.5 * (u1 + 1.0)) > 1e-9 && moved(0.5 * u2) > 1e-9);
    assert!(
        f.points()[0].distance(c0.points()[0]) > 1e-9,
        "the seam inside the region moved"
    );
    let dev = fairway::measure::deviations(&c0, f, 2000);
    assert!(dev.iter().all(|d| *d <= m * (1.0 + 1e-6)), "band");
    // the target's samples are on the original's parameter: from u1 up to b, then from a up to u2
    let drops = p.params.windows(2).filter(|w| w[1] < w[0]).count();
    assert_eq!(drops, 1, "one step back at the seam");
    assert!(p.params.iter().all(|u| (0.0..=1.0).contains(u)));
    // (the setup's stretch starts and ends at knots, within a span of 1/48 of the region's ends)
    let (first, last) = (p.params[0], *p.params.last().unwrap());
    assert!(
        (first - u1).abs() < 0.025 && (last - u2).abs() < 0.025,
        "{first} {last}"
    );

    // accept: the curve is the preview's; undo restores the document exactly (region across the seam too)
    let before = h.state().doc.clone();
    h.get_by_role_and_label(Role::Button, "Accept").click();
    h.run();
    assert_eq!(h.state().curve(), f);
    assert_eq!(h.state().region(), None);
    h.get_by_role_and_label(Role::Button, "Undo").click();
    h.run();
    assert_eq!(h.state().doc, before);
    assert_eq!(h.state().region(), Some((u1, u2)));
    // the restored region is faired again, to the same curve
    assert_eq!(
        &h.state().curve_ws.preview().expect("preview after undo").result.curve,
        f
    );
    h.get_by_role_and_label(Role::Button, "Redo").click();
    h.run();
    assert_eq!(h.state().curve(), f);
}

#[test]
fn a_region_handle_dragged_past_the_seam_wraps_the_region_and_back() {
    let mut app = closed_app();
    app.apply(Command::SetRegion(Some((0.6, 0.9))));
    let mut h = harness(app);
    // the end handle at 0.9, along the curve through the seam to 0.1
    drag_along(&mut h, &through_seam(0.9, 0.1, 0.02));
    let (u1, u2) = h.state().region().unwrap();
    assert_eq!(u1, 0.6, "the other end stays");
    assert!((u2 - 0.1).abs() < 0.01, "{u2}");
    assert!(
        h.state().curve_ws.preview().is_some(),
        "{:?}",
        h.state().curve_ws.fairing.preview
    );
    // and the start handle of the region across the seam, forward through the seam: ordinary again
    let us: Vec<f64> = (0..=9).map(|k| 0.6 + 0.04 * k as f64).chain([0.02, 0.05]).collect();
    drag_along(&mut h, &us);
    let (v1, v2) = h.state().region().unwrap();
    assert!(v1 < v2 && (v1 - 0.05).abs() < 0.01 && v2 == u2, "{v1} {v2}");
}

#[test]
fn a_drag_leaving_the_kappa_plot_at_its_right_edge_goes_on_through_the_seam() {
    let mut h = harness(closed_app());
    let r = h.state().curve_ws.plot.rect.unwrap();
    let y = r.center().y;
    let xs = [0.8, 0.9, 0.97, 1.03, 1.1, 1.15];
    let path: Vec<Pos2> = xs.iter().map(|&f| Pos2::new(r.left() + f * r.width(), y)).collect();
    drag(&mut h, &path);
    let app = h.state();
    let (u1, u2) = app.region().expect("region from the κ plot");
    assert!(u1 > u2, "{u1} {u2}");
    let len = app.curve_ws.view.sampled.length;
    let (s1, s2) = (
        app.curve_ws.view.sampled.s_at_u(u1),
        app.curve_ws.view.sampled.s_at_u(u2),
    );
    // the side panel widens a little once a region shows, so the plot is narrower at the release:
    // the last point's fraction of the plot as it is then, one length on
    let r2 = app.curve_ws.plot.rect.unwrap();
    let f2 = (path.last().unwrap().x - r2.left()) / r2.width() - 1.0;
    assert!(
        (s1 / len - 0.8).abs() < 0.01 && (s2 / len - f2 as f64).abs() < 0.01,
        "{s1} {s2} of {len} ({f2})"
    );
}

#[test]
fn a_region_across_the_seam_round_trips_through_a_saved_document() {
    let mut app = closed_app();
    app.apply(Command::SetRegion(Some((0.8, 0.2))));
    assert_eq!(app.region(), Some((0.8, 0.2)), "kept as given on a closed curve");
    let dir = std::env::temp_dir().join(format!("fairway-editor-seam-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("wrap.ron");
    app.apply(Command::SaveTo(path.clone()));
    assert!(app.error.is_none(), "{:?}", app.error);
    let doc = fairway::io::load(&path).expect("saved document");
    assert_eq!(doc.settings.region, Some((0.8, 0.2)));
    let h = harness(App::with_document(doc, Some(path)));
    assert!(h.state().curve_ws.fairing.across_seam());
    assert!(
        h.state().curve_ws.preview().is_some(),
        "{:?}",
        h.state().curve_ws.fairing.preview
    );
    h.get_by_label_contains("u from 0.8000 to 0.2000 (across the seam)");
    std::fs::remove_dir_all(&dir).ok();
    // on an open curve the ends are put in order
    let mut open = App::default();
    open.apply(Command::SetRegion(Some((0.8, 0.2))));
    assert_eq!(open.region(), Some((0.2, 0.8)));
}

#[test]
fn a_seam_that_cannot_be_re_seamed_is_an_error_message() {
    let c = fairway::io::load(&asset("closed_section.json")).unwrap();
    let fairway::Geometry::Curve(c) = c.geometry else {
        panic!("a curve")
    };
    let last = c.n_points() - 1;
    // a kink at the seam is a corner: a region across it is faired as its two sides, G1 at the seam
    let mut q = c.points().to_vec();
    let d = q[1] - q[0];
    q[1] += fairway::DVec3::new(-d.y, d.x, 0.0) * 0.5;
    q[last - 1] -= fairway::DVec3::new(-d.y, d.x, 0.0) * 0.3;
    let mut doc = Document::new(fairway::Geometry::Curve(c.with_points(q).unwrap()));
    doc.settings.region = Some((0.8, 0.2));
    let h = harness(App::with_document(doc, None));
    let p = h
        .state()
        .curve_ws
        .preview()
        .expect("faired as the two sides of the seam");
    assert_eq!(p.stretches, vec![(0.8, 1.0), (0.0, 0.2)]);
    assert_eq!(p.corners[0].u, 0.0);
    // a seam that is smooth (G1) but not parametrically C2 (the speed jumps) cannot be re-seamed: an error
    let mut q = c.points().to_vec();
    q[1] = q[0] + (q[1] - q[0]) * 1.5;
    let mut doc = Document::new(fairway::Geometry::Curve(c.with_points(q).unwrap()));
    doc.settings.region = Some((0.8, 0.2));
    let h = harness(App::with_document(doc, None));
    match &h.state().curve_ws.fairing.preview {
        Some(Err(e)) => assert!(e.contains("re-seamed"), "{e}"),
        other => panic!("expected an error, got {other:?}"),
    }
    h.get_by_label_contains("Error:");
    assert!(h.state().error.is_none(), "no internal error");
    // the preview engine given a region across the seam of an open curve: the core's message, no panic
    let mut f = fairway_editor::Fairing::default();
    let settings = fairway::io::DocumentSettings {
        region: Some((0.8, 0.2)),
        ..Default::default()
    };
    let open = fairway_editor::demo_curve();
    f.update(&open, 1, &settings, 1e-3, Default::default(), false, false);
    match &f.preview {
        Some(Err(e)) => assert!(e.contains("not closed"), "{e}"),
        _ => panic!("expected an error"),
    }
    assert!(f.internal_error.is_none());
}

/// The κ plot's target of a region across the seam runs from the plot's right edge on through its left
/// one: a target point dragged up just after the seam (left edge) pulls its neighbours just before the
/// seam (right edge) along, and the re-fair uses the edited target.
#[test]
fn target_drag_next_to_the_seam_reaches_through_it() {
    let mut app = closed_app();
    app.apply(Command::SetRegion(Some((0.85, 0.15))));
    let mut h = harness(app);
    let p = h.state().curve_ws.preview().expect("preview").clone();
    let k0 = p.params.windows(2).position(|w| w[1] < w[0]).expect("the seam") + 1;
    let (x, y) = {
        let app = h.state();
        let len = app.curve_ws.view.sampled.length;
        (
            app.curve_ws.plot.x(app.curve_ws.target_s(&p, k0), len),
            app.curve_ws.plot.y(p.target[k0]),
        )
    };
    assert!(
        x - h.state().curve_ws.plot.rect.unwrap().left() < 5.0,
        "the sample after the seam is at the left edge"
    );
    drag(
        &mut h,
        &[Pos2::new(x, y), Pos2::new(x, y - 10.0), Pos2::new(x, y - 25.0)],
    );
    let t = h.state().doc.settings.target.clone().expect("hand-edited target");
    assert_eq!(t.len(), p.target.len());
    assert!(t[k0] > p.target[k0], "the grabbed point did not move up");
    assert!(
        t[k0 - 2] > p.target[k0 - 2],
        "the falloff did not reach through the seam"
    );
    let far = k0 + (t.len() - k0) / 2;
    assert_eq!(t[far], p.target[far], "a point far away moved");
    let p2 = h.state().curve_ws.preview().expect("re-faired").clone();
    assert_eq!(p2.target, t);
    assert!(h.state().curve_ws.fairing.across_seam());
}

/// The κ plot's edge of a region across the seam: the end u2 (left part of the plot) dragged out past
/// the plot's left edge goes on from the right end, through the seam: the region becomes the ordinary
/// [u1, u] (u1 unchanged).
#[test]
fn a_plot_edge_dragged_out_of_the_plot_goes_on_through_the_seam() {
    let mut app = closed_app();
    app.apply(Command::SetRegion(Some((0.7, 0.15))));
    let mut h = harness(app);
    let (r, x2) = {
        let app = h.state();
        let len = app.curve_ws.view.sampled.length;
        (
            app.curve_ws.plot.rect.unwrap(),
            app.curve_ws.plot.x(app.curve_ws.view.sampled.s_at_u(0.15), len),
        )
    };
    // (near the top: away from the target curve, which a press would grab instead)
    let y = r.top() + 4.0;
    let path: Vec<Pos2> = [0.0, -20.0, -40.0, -(x2 - r.left()) - 30.0, -(x2 - r.left()) - 60.0]
        .iter()
        .map(|&dx| Pos2::new(x2 + dx, y))
        .collect();
    drag(&mut h, &path);
    let app = h.state();
    let (u1, u2) = app.region().unwrap();
    assert_eq!(u1, 0.7, "the other end stays");
    assert!(u2 > u1 && u2 < 1.0, "{u2}");
    // 60 points past the left edge: that far before the right edge, on the plot as it is now
    let r2 = app.curve_ws.plot.rect.unwrap();
    let x = app
        .curve_ws
        .plot
        .x(app.curve_ws.view.sampled.s_at_u(u2), app.curve_ws.view.sampled.length);
    assert!(
        (x - (r2.right() - 60.0)).abs() < 0.02 * r2.width(),
        "{x} vs {}",
        r2.right() - 60.0
    );
}

/// The whole closed curve selected: both handles sit on the seam point; dragging it backwards along the
/// curve shrinks the region from its end, forwards from its start.
#[test]
fn the_whole_closed_curve_shrinks_from_the_side_the_seam_point_is_dragged_to() {
    let mut h = harness(closed_app());
    h.get_by_role_and_label(Role::Button, "Whole curve").click();
    h.run();
    assert_eq!(h.state().region(), Some((0.0, 1.0)));
    drag_along(&mut h, &[0.0, 0.99, 0.97, 0.95, 0.93, 0.9]);
    let (u1, u2) = h.state().region().unwrap();
    assert!(u1 == 0.0 && (u2 - 0.9).abs() < 0.01, "{u1} {u2}");
    h.get_by_role_and_label(Role::Button, "Whole curve").click();
    h.run();
    drag_along(&mut h, &[0.0, 0.01, 0.03, 0.05, 0.07, 0.1]);
    let (u1, u2) = h.state().region().unwrap();
    assert!((u1 - 0.1).abs() < 0.01 && u2 == 1.0, "{u1} {u2}");
}

/// `closed_section.json` with a kink at the interior knot nearest u = 0.1: the knot tripled (exact) and
/// its control point, on the curve, pulled away from the centroid by 5 %. Returns the curve, the kink's
/// parameter and its control point index.
fn closed_with_a_kink() -> (BSplineCurve, f64, usize) {
    let fairway::Geometry::Curve(c) = fairway::io::load(&asset("closed_section.json")).unwrap().geometry else {
        panic!("a curve")
    };
    let bp = c.knots().breakpoints();
    let u0 = *bp
        .iter()
        .min_by(|a, b| (*a - 0.1).abs().total_cmp(&(*b - 0.1).abs()))
        .unwrap();
    let s = c.knots().multiplicity(u0);
    let c = c.insert_knot(u0, 3 - s).unwrap();
    let k = c.points().iter().position(|p| p.distance(c.point(u0)) < 1e-12).unwrap();
    let centroid = c.points().iter().copied().sum::<fairway::DVec3>() / c.n_points() as f64;
    let mut q = c.points().to_vec();
    q[k] = centroid + (q[k] - centroid) * 1.05;
    (c.with_points(q).unwrap(), u0, k)
}

/// A closed curve with a kink: the whole curve is faired across its seam (re-seamed at the kink), the
/// kink kept; a region across the seam that holds the kink is faired stretch by stretch (before: the
/// whole curve's seam was held, and the region was refused), its first stretch shown running across the
/// seam.
#[test]
fn a_closed_curve_with_a_kink_is_faired_across_its_seam_with_the_kink_kept() {
    let (c, u0, k) = closed_with_a_kink();
    let mut doc = Document::new(fairway::Geometry::Curve(c.clone()));
    let (a, b) = c.domain();
    doc.settings.region = Some((a, b));
    let mut h = harness(App::with_document(doc, None));
    let p = h.state().curve_ws.preview().expect("the whole curve is faired").clone();
    assert_eq!(p.result.seam, fairway::fair::Seam::Faired);
    assert_eq!(p.corners.len(), 1);
    assert_eq!(p.corners[0].u, u0);
    h.get_by_label_contains("closed curve: faired across the seam, its corners kept");
    let f = &p.result.curve;
    assert_eq!(f.points()[k], c.points()[k], "the kink moved");
    assert_eq!(f.points()[0], *f.points().last().unwrap(), "closed");
    assert_ne!(f.points()[0], c.points()[0], "the seam is faired, not held");
    assert!(p.result.max_deviation <= h.state().tolerance() * (1.0 + 1e-9));
    // the κ plot's samples are the original's parameters
    assert!(
        p.params.iter().all(|&u| (a..=b).contains(&u)),
        "sample parameters outside the domain"
    );

    // a region across the seam holding the kink
    h.state_mut().push(Command::SetRegion(Some((0.8, 0.3))));
    h.run();
    let p = h.state().curve_ws.preview().expect("faired stretch by stretch").clone();
    assert_eq!(p.stretches.len(), 2, "{:?}", p.stretches);
    assert_eq!(p.stretches[0].0, 0.8);
    assert!((p.stretches[0].1 - u0).abs() < 1e-12, "{:?}", p.stretches);
    let f = &p.result.curve;
    for i in supported_in(&c, 0.3, 0.8) {
        assert!(
            f.points()[i].distance(c.points()[i]) <= 1e-12,
            "control point {i} outside the region moved"
        );
    }
    assert_eq!(f.points()[k], c.points()[k], "the kink moved");
    h.get_by_role_and_label(Role::Button, &format!("u 0.8000 to {u0:.4}"));
}

/// A closed curve whose seam is a kink (a sharp trailing edge), faired whole: the seam is kept as a corner
/// with G1 on both sides (its point and tangents stay), and the panel says so.
#[test]
fn a_kink_at_the_seam_is_kept_as_a_corner_when_the_whole_curve_is_faired() {
    let (c, u0, _) = closed_with_a_kink();
    // re-seamed at the kink (exact), the domain back to [0, 1]
    let r = fairway::fair::closed::rotate(&c, u0).unwrap();
    let (a, b) = r.domain();
    let knots = r.knots().values().iter().map(|u| (u - a) / (b - a)).collect();
    let c = BSplineCurve::try_new(3, knots, r.points().to_vec(), None, 2).unwrap();
    let mut doc = Document::new(fairway::Geometry::Curve(c.clone()));
    doc.settings.region = Some((0.0, 1.0));
    let h = harness(App::with_document(doc, None));
    let p = h.state().curve_ws.preview().expect("faired").clone();
    h.get_by_label_contains("closed curve: its seam is a corner, kept (G1 on both sides)");
    assert_eq!(p.corners.len(), 1);
    assert_eq!(p.corners[0].u, 0.0);
    let (q0, q1) = (c.points(), p.result.curve.points());
    let n = q0.len();
    assert_eq!(q1[0], q0[0]);
    assert_eq!(q1[n - 1], q0[n - 1]);
    assert!(q1[1..n - 1].iter().zip(&q0[1..n - 1]).any(|(x, y)| x != y), "faired");
}
