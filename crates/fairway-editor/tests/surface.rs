//! kittest tests of the surface workspace: open the bumpy sample surface,
//! select a region by dragging in the uv view, set the tolerance, accept,
//! undo — asserting on the document.

use eframe::egui;
use egui::{Pos2, Role};
use egui_kittest::kittest::Queryable;
use fairway::fair::surface::{SurfaceFairingOptions, SurfaceFairingResult, fair_surface};
use fairway::measure_surface::deviation;
use fairway::{BSplineSurface, Geometry};
use fairway_editor::{App, Command};

mod common;
use common::{asset, drag, harness, harness_without_waiting};

fn surface(app: &App) -> BSplineSurface {
    assert!(app.surface.is_some(), "surface workspace");
    match &app.doc.geometry {
        Geometry::Surface(s) => s.clone(),
        Geometry::Curve(_) => panic!("not a surface"),
    }
}

#[test]
fn bad_or_curve_files_do_not_open_the_surface_workspace() {
    let app = App::open_or_demo(Some(&asset("car_roof.json")));
    assert!(app.surface.is_none());
    let app = App::open_or_demo(Some(&asset("does_not_exist.json")));
    assert!(app.surface.is_none() && app.error.is_some());
}

#[test]
fn region_in_uv_view_tolerance_accept_undo() {
    let app = App::open_or_demo(Some(&asset("bumpy_surface.json")));
    assert!(app.surface.is_some(), "{:?}", app.error);
    let mut h = harness(app);
    let original = surface(h.state());
    let doc0 = h.state().doc.clone();
    // without a wgpu renderer the view says so instead of panicking
    assert!(h.query_by_label_contains("3D view unavailable").is_some());

    // region: drag in the uv view from (0.3, 0.25) to (0.7, 0.75)
    let r = h.get_by_label("uv domain").rect();
    let at = |u: f32, v: f32| Pos2::new(r.left() + u * r.width(), r.bottom() - v * r.height());
    let path: Vec<Pos2> = (0..=4)
        .map(|k| at(0.3 + 0.1 * k as f32, 0.25 + 0.125 * k as f32))
        .collect();
    drag(&mut h, &path);
    let ((u1, u2), (v1, v2)) = h.state().doc.settings.region_uv.expect("a region after the drag");
    for (x, want) in [(u1, 0.3), (u2, 0.7), (v1, 0.25), (v2, 0.75)] {
        assert!((x - want).abs() < 0.01, "region {:?}", ((u1, u2), (v1, v2)));
    }

    // tolerance
    let tol = 4e-3;
    h.get_by_role_and_label(Role::Slider, "Tolerance")
        .set_value_accesskit(tol);
    h.run();
    let s = h.state().surface.as_ref().unwrap();
    let t = h.state().tolerance();
    assert!((t - tol).abs() < 1e-12 * tol.max(1.0), "{t}");
    let p = s.preview.as_ref().expect("a live preview");
    assert!(p.max_deviation <= tol);
    assert!(!p.draft, "with the pointer up the preview is the full-quality one");
    // the panel says what the sound bound certifies, and it is the preview's
    let said = fairway_editor::surface_ui::band_certificate(p.band_bound, tol);
    let bound = p.band_bound.expect("a polynomial surface has a bound");
    assert!(
        p.max_deviation <= bound * (1.0 + 1e-9),
        "{} > bound {bound}",
        p.max_deviation
    );
    assert_eq!(said.starts_with("band certified everywhere"), bound <= tol, "{said}");
    assert!(h.query_by_label_contains(&said).is_some(), "the panel lacks “{said}”");
    // during a drag the preview is a one-level draft (in the background too); the release recomputes it
    // at full quality (in the background: the draft stays meanwhile, and Accept waits for the full fair)
    let final_points = p.surface.points().to_vec();
    let doc = h.state().doc.clone();
    let ws = h.state_mut().surface.as_mut().unwrap();
    ws.preview = None;
    ws.update_preview(&doc, true, None);
    assert!(
        ws.is_drafting() && ws.preview.is_none(),
        "the draft runs in the background"
    );
    ws.finish_job(&doc);
    assert!(!ws.is_drafting());
    let draft = ws.preview.as_ref().expect("a draft preview");
    assert!(draft.draft && draft.max_deviation <= tol);
    assert!(!ws.is_fairing() && !ws.can_accept(&doc));
    ws.update_preview(&doc, false, None);
    assert!(ws.is_fairing(), "the release starts the full fair");
    assert!(
        ws.preview.as_ref().is_some_and(|p| p.draft),
        "the draft stays meanwhile"
    );
    assert!(!ws.can_accept(&doc), "Accept waits for the full fair");
    ws.finish_job(&doc);
    let full = ws.preview.as_ref().expect("the full preview");
    assert!(!full.draft && !ws.is_fairing() && ws.can_accept(&doc));
    assert_eq!(
        full.surface.points(),
        &final_points[..],
        "release gives the full-quality result"
    );

    // accept: one undo step
    h.get_by_role_and_label(Role::Button, "Accept").click();
    h.run();
    let faired = surface(h.state());
    assert_ne!(faired.points(), original.points(), "accept changed nothing");
    // control points whose support misses the region are unchanged
    let (ku, kv) = (original.knots_u(), original.knots_v());
    let mut outside = 0;
    for i in 0..original.nu() {
        for j in 0..original.nv() {
            let (a, b) = ku.support(i);
            let (c, d) = kv.support(j);
            if b <= u1 || a >= u2 || d <= v1 || c >= v2 {
                outside += 1;
                let diff = (faired.point_at(i, j) - original.point_at(i, j)).length();
                assert!(diff <= 1e-12, "({i},{j}) moved by {diff}");
            }
        }
    }
    assert!(outside > 100, "{outside}");
    // deviation within the tolerance (independent dense check)
    let (dmax, _) = deviation(&original, &faired, 61);
    assert!(dmax <= tol * (1.0 + 1e-6), "deviation {dmax} > {tol}");

    // undo restores the document exactly; redo re-applies
    h.get_by_role_and_label(Role::Button, "Undo").click();
    h.run();
    assert_eq!(surface(h.state()).points(), original.points());
    assert_eq!(h.state().doc.settings.region_uv, Some(((u1, u2), (v1, v2))));
    h.get_by_role_and_label(Role::Button, "Redo").click();
    h.run();
    assert_eq!(surface(h.state()).points(), faired.points());
    // undo all the way back to the opened document
    for _ in 0..3 {
        h.get_by_role_and_label(Role::Button, "Undo").click();
        h.run();
    }
    assert_eq!(h.state().doc, doc0);
}

#[test]
fn ctrl_drag_on_the_surface_picks_the_uv_region_and_plain_drag_orbits() {
    let mut h = harness(App::open_or_demo(Some(&asset("bumpy_surface.json"))));
    let rect = h.get_by_label("3D view").rect();
    let s0 = surface(h.state());
    // screen positions of surface points S(u, v) through the editor's camera
    let at = |h: &egui_kittest::Harness<'static, App>, u: f64, v: f64| {
        let view = &h.state().surface.as_ref().unwrap().view;
        view.to_screen(s0.point(u, v), rect).expect("in front of the camera")
    };
    let ((du0, du1), (dv0, dv1)) = s0.domain();
    let uv = |a: f64, b: f64| (du0 + a * (du1 - du0), dv0 + b * (dv1 - dv0));
    let (a, b) = (uv(0.25, 0.3), uv(0.7, 0.8));
    let cam0 = h.state().surface.as_ref().unwrap().view.camera;
    let path: Vec<Pos2> = (0..=4)
        .map(|k| {
            let t = k as f64 / 4.0;
            at(&h, a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
        })
        .collect();
    assert!(path.iter().all(|p| rect.contains(*p)), "{path:?} not in {rect:?}");
    let ctrl = egui::Modifiers {
        ctrl: true,
        command: true,
        ..Default::default()
    };
    common::drag_with(&mut h, &path, ctrl);
    let s = h.state().surface.as_ref().unwrap();
    let ((u1, u2), (v1, v2)) = h.state().doc.settings.region_uv.expect("a region from the Ctrl+drag");
    // CPU ray picking (core pick_uv): the region's corners are the picked uv
    // of the first and last pointer positions
    for (x, want) in [(u1, a.0), (u2, b.0), (v1, a.1), (v2, b.1)] {
        assert!(
            (x - want).abs() < 2e-3,
            "region {:?}, wanted {a:?}..{b:?}",
            ((u1, u2), (v1, v2))
        );
    }
    assert_eq!(s.view.camera, cam0, "Ctrl+drag must not orbit");
    // one gesture = one undo step
    h.get_by_role_and_label(Role::Button, "Undo").click();
    h.run();
    assert_eq!(h.state().doc.settings.region_uv, None);

    // the same drag without Ctrl orbits and leaves the region alone
    drag(&mut h, &path);
    let s = h.state().surface.as_ref().unwrap();
    assert_eq!(h.state().doc.settings.region_uv, None);
    assert_ne!(s.view.camera, cam0, "plain drag did not orbit");
}

/// What the surface fair did besides the plain method (`SurfaceFairingResult::notes`) is shown in the
/// measures panel: here a cubic chain of Bézier patches (a C0 knot line in u and in v) is faired tile by
/// tile, and the panel says so.
#[test]
fn the_preview_notes_are_shown_in_the_measures_panel() {
    // knots of two cubic Bézier pieces per direction: the joint at 0.5 has multiplicity 3
    let knots = vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0];
    let n = knots.len() - 4;
    let grev = |i: usize| knots[i + 1..i + 4].iter().sum::<f64>() / 3.0;
    let mut pts = vec![];
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (grev(i), grev(j));
            let noise = 2e-3 * (((i * 7 + j * 13) % 5) as f64 / 4.0 - 0.5);
            pts.push(fairway::DVec3::new(
                x,
                y,
                0.2 * (3.0 * x).sin() * (2.0 * y).cos() + noise,
            ));
        }
    }
    let s = BSplineSurface::try_new(3, 3, knots.clone(), knots, n, n, pts, None).unwrap();
    let mut doc = fairway::io::Document::new(Geometry::Surface(s));
    doc.settings.region_uv = Some(((0.0, 1.0), (0.0, 1.0)));
    doc.settings.tolerance = Some(3e-3);
    let mut app = App::default();
    assert!(app.set_document(doc.clone(), None, Some(doc)), "{:?}", app.error);
    let mut h = harness(app);
    h.run();
    let p = h
        .state()
        .surface
        .as_ref()
        .unwrap()
        .preview
        .as_ref()
        .expect("a live preview");
    let note = p
        .notes
        .iter()
        .find(|n| n.contains("C0 knot lines"))
        .unwrap_or_else(|| panic!("no C0 note in {:?}", p.notes))
        .clone();
    assert!(h.query_by_label(&note).is_some(), "the panel lacks “{note}”");
}

/// The points of `s` as bits (a bit-for-bit comparison).
fn bits(s: &BSplineSurface) -> Vec<[u64; 3]> {
    s.points()
        .iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect()
}

/// The full fair the preview asks for, computed here on the test's thread.
fn fair_now(s: &BSplineSurface, region: fairway_editor::surface_ui::UvRect, tol: f64) -> SurfaceFairingResult {
    fair_surface(s, SurfaceFairingOptions::default().region(Some(region)).tolerance(tol)).unwrap()
}

/// The full fair of the preview runs as a background job: the frame that starts it returns with the
/// workspace "computing" and no preview; the result is not taken until a frame polls it (here after the
/// test waited for the job); then it is the synchronous `fair_surface` result bit for bit, with its
/// measures, and Accept takes it.
#[test]
fn the_full_surface_fair_arrives_through_the_job_equal_to_the_synchronous_fair() {
    let mut h = harness_without_waiting(App::open_or_demo(Some(&asset("bumpy_surface.json"))));
    let s0 = surface(h.state());
    let (region, tol) = (((0.2, 0.8), (0.25, 0.75)), 3e-3);
    h.state_mut().apply(Command::SetRegionUv(Some(region)));
    h.state_mut().apply(Command::SetTolerance(tol));
    assert!(!h.state().is_computing(), "commands start nothing before the frame");
    h.step();
    // the frame returned with the fair running: no preview yet (no drag, so no draft), Accept off
    let ws = h.state().surface.as_ref().unwrap();
    assert!(ws.is_fairing() && h.state().is_computing());
    let key = ws.preview_key(&h.state().doc).unwrap();
    assert_eq!(ws.fairing_key(), Some(key));
    assert!(ws.preview.is_none());
    assert!(!ws.can_accept(&h.state().doc));
    // the next frame draws the computing state (it polls after drawing the panels)
    h.step();
    assert!(
        h.query_by_label_contains("Fairing…").is_some(),
        "the panel shows no computing state"
    );
    // the result waits for a frame to take it
    h.state_mut().wait_for_jobs();
    assert!(
        h.state().surface.as_ref().unwrap().preview.is_none(),
        "taken before a frame polled it"
    );
    h.step();
    let ws = h.state().surface.as_ref().unwrap();
    assert!(!ws.is_fairing() && !h.state().is_computing());
    let p = ws.preview.as_ref().expect("the job's result is the preview");
    assert!(!p.draft && p.key() == key && p.measures.is_some());
    assert!(ws.measures_before.is_some_and(|(rev, _)| rev == key.0));
    let sync = fair_now(&s0, region, tol);
    assert_eq!(
        bits(&p.surface),
        bits(&sync.surface),
        "the job's fair differs from fair_surface"
    );
    assert_eq!(p.max_deviation.to_bits(), sync.max_deviation.to_bits());
    assert_eq!(p.band_bound.map(f64::to_bits), sync.band_bound.map(f64::to_bits));
    assert_eq!((p.rounds, &p.notes), (sync.rounds, &sync.notes));
    assert!(ws.can_accept(&h.state().doc));
    h.state_mut().apply(Command::AcceptSurface);
    assert_eq!(bits(&surface(h.state())), bits(&sync.surface));
}

/// A job whose key no longer matches is dropped: the tolerance changes while the fair of the old one
/// runs, and even when that fair has finished before the next frame, its result is not shown; the fair
/// of the new tolerance replaces it and is the synchronous result.
#[test]
fn a_stale_job_result_is_dropped_after_an_edit_that_changed_the_key() {
    let mut h = harness_without_waiting(App::open_or_demo(Some(&asset("bumpy_surface.json"))));
    let s0 = surface(h.state());
    let region = ((0.2, 0.8), (0.25, 0.75));
    let (t1, t2) = (3e-3, 1.5e-3);
    h.state_mut().apply(Command::SetRegionUv(Some(region)));
    h.state_mut().apply(Command::SetTolerance(t1));
    h.step();
    let k1 = h
        .state()
        .surface
        .as_ref()
        .unwrap()
        .fairing_key()
        .expect("the fair of t1 runs");
    // the fair of t1 finishes, then the tolerance changes before a frame took its result
    h.state_mut().wait_for_jobs();
    h.state_mut().apply(Command::SetTolerance(t2));
    h.step();
    let ws = h.state().surface.as_ref().unwrap();
    let k2 = ws.preview_key(&h.state().doc).unwrap();
    assert_ne!(k1, k2);
    assert!(ws.preview.is_none(), "the stale result of t1 was shown");
    assert_eq!(ws.fairing_key(), Some(k2), "the fair of t2 was not started");
    h.state_mut().wait_for_jobs();
    h.step();
    let ws = h.state().surface.as_ref().unwrap();
    let p = ws.preview.as_ref().expect("the fair of t2");
    assert_eq!(p.key(), k2);
    assert_eq!(bits(&p.surface), bits(&fair_now(&s0, region, t2).surface));
    assert_ne!(bits(&p.surface), bits(&fair_now(&s0, region, t1).surface));
}

/// An edit while a fair runs supersedes it at the next frame (the old result is discarded whenever it
/// comes); an error of the background fair is the same message as the synchronous call's.
#[test]
fn a_new_edit_supersedes_a_running_fair_and_errors_read_as_before() {
    let mut h = harness_without_waiting(App::open_or_demo(Some(&asset("bumpy_surface.json"))));
    let s0 = surface(h.state());
    h.state_mut()
        .apply(Command::SetRegionUv(Some(((0.2, 0.8), (0.25, 0.75)))));
    h.step();
    let k1 = h.state().surface.as_ref().unwrap().fairing_key().unwrap();
    // a region inside one knot span leaves no control point free: the core refuses it
    let tiny = ((0.5, 0.5001), (0.5, 0.5001));
    let tol = h.state().tolerance();
    let want = fair_surface(&s0, SurfaceFairingOptions::default().region(Some(tiny)).tolerance(tol))
        .expect_err("the core fairs a region inside one knot span")
        .to_string();
    h.state_mut().apply(Command::SetRegionUv(Some(tiny)));
    h.step();
    let ws = h.state().surface.as_ref().unwrap();
    let k2 = ws.fairing_key().expect("the new region's fair runs");
    assert_ne!(k1, k2, "the old fair was not superseded");
    h.state_mut().wait_for_jobs();
    h.step();
    let ws = h.state().surface.as_ref().unwrap();
    assert!(ws.preview.is_none() && !ws.is_fairing());
    assert_eq!(ws.preview_error.as_deref(), Some(want.as_str()));
    // not tried again until the key changes
    h.step();
    assert!(
        !h.state().surface.as_ref().unwrap().is_fairing(),
        "a failed fair is retried"
    );
}
