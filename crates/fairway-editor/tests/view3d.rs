//! kittest tests of the curve editor's 3D views, driven by accessible
//! labels: extrusion isophotes of a planar curve before and after fairing,
//! the curvature comb of a spatial curve in 3D, and the persistence of the
//! 3D shading settings through eframe storage.

use eframe::egui;
use egui::{Pos2, Role};
use egui_kittest::kittest::{NodeT, Queryable};
use fairway::closest::CurveProjector;
use fairway::{BSplineCurve, DVec3};
use fairway_editor::App;
use fairway_editor::curve3d::extrusion_height;
use fairway_editor::view3d::{ShadeMode, Shading, View3dPrefs};

mod common;
use common::{MemStorage, asset, drag, harness};

#[test]
fn extrusion_isophotes_show_the_curve_and_the_faired_curve_side_by_side() {
    let mut h = harness(App::open_or_demo(Some(&asset("car_roof.ron"))));
    h.get_by_label("3D view").click();
    h.run();
    assert!(h.state().curve_ws.curve3d.enabled);
    h.get_by_role_and_label(Role::CheckBox, "Extrusion isophotes").click();
    h.run();
    assert!(h.state().curve_ws.curve3d.extrusion);
    // no region yet: only the original's extrusion
    assert_eq!(h.state().curve_ws.curve3d.extrusions().len(), 1);
    assert_eq!(h.query_all_by_label("Extrusion view").count(), 1);
    // without a wgpu renderer the panes say so instead of panicking
    assert!(h.query_by_label_contains("3D view unavailable").is_some());

    // region by dragging across the κ plot (it stays below the 3D view)
    let r = h.state().curve_ws.plot.rect.expect("κ plot");
    let y = r.center().y;
    let (x1, x2) = (r.left() + 0.3 * r.width(), r.left() + 0.6 * r.width());
    drag(
        &mut h,
        &[Pos2::new(x1, y), Pos2::new(0.5 * (x1 + x2), y), Pos2::new(x2, y)],
    );
    h.run();
    let app = h.state();
    let (u1, u2) = app.region().expect("a region from the κ plot");
    let before = app.curve().clone();
    let p = app.curve_ws.preview().expect("a faired preview");
    let after = p.result.curve.clone();
    let dev = p.result.max_deviation;
    assert!(dev > 0.0);
    assert_eq!(
        h.query_all_by_label("Extrusion view").count(),
        2,
        "before and after side by side"
    );
    let ex = app.curve_ws.curve3d.extrusions();
    assert_eq!(ex.len(), 2);
    let (m0, m1) = (&ex[0].1, &ex[1].1);
    assert_eq!((m0.nu, m0.nv), (m1.nu, m1.nv));
    assert_eq!(m0.uv, m1.uv);

    // each mesh is the extrusion of its curve: S(u, v) = c(u) + v·h·z with
    // the curve's right normal c' × z (horizontal)
    let diag = app.curve_ws.view.diag;
    let height = extrusion_height(diag);
    for (c, m) in [(&before, m0), (&after, m1)] {
        for k in 0..m.positions.len() {
            let uv = m.uv[k];
            let want = c.point(uv.x) + DVec3::Z * (uv.y * height);
            assert!(
                (m.positions[k] - want).length() <= 1e-12 * diag,
                "vertex {k} off the extrusion"
            );
            let n = c.d1(uv.x).cross(DVec3::Z).normalize();
            assert!(
                (m.normals[k] - n).length() <= 1e-9,
                "normal {k}: {:?} vs {n:?}",
                m.normals[k]
            );
        }
    }
    // the two differ inside the region and agree outside it
    let (mut inside, mut outside, mut max_in, mut max_n_in) = (0, 0, 0.0f64, 0.0f64);
    for k in 0..m0.positions.len() {
        let u = m0.uv[k].x;
        let dp = (m0.positions[k] - m1.positions[k]).length();
        let dn = (m0.normals[k] - m1.normals[k]).length();
        if u < u1 - 1e-9 || u > u2 + 1e-9 {
            outside += 1;
            assert!(
                dp <= 1e-12 * diag && dn <= 1e-9,
                "u = {u} outside [{u1}, {u2}] moved: {dp:e}, {dn:e}"
            );
        } else {
            inside += 1;
            max_in = max_in.max(dp);
            max_n_in = max_n_in.max(dn);
        }
    }
    assert!(inside > 20 && outside > 20, "{inside} inside, {outside} outside");
    // the same-parameter displacement is not bounded by the deviation (the
    // fairing may slide the parametrization along the curve), but every
    // faired vertex lies inside the tolerance band around the original
    assert!(max_in > 0.1 * dev, "moved {max_in:e}, deviation {dev:e}");
    let m_tol = app.tolerance();
    let proj = CurveProjector::new(&before, 32);
    for k in 0..m1.positions.len() {
        let q = m1.positions[k] * DVec3::new(1.0, 1.0, 0.0);
        let d = proj.project(q).distance;
        assert!(d <= m_tol * (1.0 + 1e-6), "vertex {k} {d:e} outside the band {m_tol:e}");
    }
    assert!(
        max_n_in > 1e-4,
        "isophotes cannot change: normals moved by {max_n_in:e}"
    );

    // the stripe width is a control of this view
    h.get_by_role_and_label(Role::Slider, "Stripe width °")
        .set_value_accesskit(10.0);
    h.run();
    assert_eq!(h.state().curve_ws.curve3d.shading.stripe_deg, 10.0);
}

/// Check comb teeth `(base, tip)` of `c`: the base on the curve, the tooth
/// along −κN (the core's curvature vector) with one common scale, for every
/// `step`-th tooth; returns that scale |tooth| / |κ|.
fn check_comb(c: &BSplineCurve, teeth: &[(DVec3, DVec3)], step: usize, diag: f64) -> f64 {
    let proj = CurveProjector::new(c, 16);
    let mut scale: Option<f64> = None;
    let mut checked = 0;
    for (a, b) in teeth.iter().step_by(step) {
        let cp = proj.project(*a);
        assert!(
            cp.distance <= 1e-9 * diag,
            "tooth base {a:?} off the curve by {}",
            cp.distance
        );
        let kv = c.curvature_vector(cp.param);
        let t = *b - *a;
        if kv.length() < 1e-6 {
            continue;
        }
        let cos = t.normalize().dot(-kv.normalize());
        assert!(cos > 1.0 - 1e-8, "tooth at u = {} not along -κN: cos = {cos}", cp.param);
        assert!(t.dot(c.tangent(cp.param)).abs() <= 1e-8 * t.length());
        let s = t.length() / kv.length();
        if let Some(s0) = scale {
            assert!((s / s0 - 1.0).abs() < 1e-6, "scale {s} vs {s0} at u = {}", cp.param);
        }
        scale = Some(s);
        checked += 1;
    }
    assert!(checked >= 10, "only {checked} teeth checked");
    scale.unwrap()
}

#[test]
fn comb_of_a_spatial_curve_lies_along_the_principal_normal_in_3d() {
    let mut h = harness(App::open_or_demo(Some(&asset("spatial_curve.json"))));
    assert_eq!(h.state().curve().dim(), 3);
    h.get_by_label("3D view").click();
    h.run();
    assert!(h.query_by_label("3D curve view").is_some());
    // extrusion isophotes are for planar curves only
    let check = h.get_by_role_and_label(Role::CheckBox, "Extrusion isophotes");
    assert!(check.accesskit_node().is_disabled());

    let c = h.state().curve().clone();
    let diag = h.state().curve_ws.view.diag;
    let teeth = h.state().curve_ws.curve3d.combs()[0].clone();
    assert_eq!(h.state().curve_ws.curve3d.combs().len(), 1);
    let n = teeth.len();
    assert!(n >= 200, "{n} teeth");
    let scale = check_comb(&c, &teeth, n / 25, diag);
    // the longest tooth is 0.2 · comb scale · diagonal
    let longest = teeth.iter().map(|(a, b)| (*b - *a).length()).fold(0.0, f64::max);
    let want = 0.2 * h.state().prefs.comb_scale * diag;
    assert!((longest / want - 1.0).abs() < 1e-9, "{longest} vs {want}");
    // a spatial comb: the teeth are not confined to one plane
    let zs: Vec<f64> = teeth.iter().map(|(a, b)| (*b - *a).normalize().z).collect();
    let spread =
        zs.iter().copied().fold(f64::NEG_INFINITY, f64::max) - zs.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(spread > 0.1, "teeth z-components spread {spread}");

    // orbiting moves the camera, not the comb
    let yaw0 = h.state().curve_ws.curve3d.view.camera.yaw;
    let r = h.get_by_label("3D curve view").rect();
    let a = r.center();
    drag(&mut h, &[a, a + egui::vec2(40.0, 0.0), a + egui::vec2(90.0, 10.0)]);
    assert!(
        (h.state().curve_ws.curve3d.view.camera.yaw - yaw0).abs() > 0.1,
        "did not orbit"
    );
    assert_eq!(h.state().curve_ws.curve3d.combs()[0], teeth);
    assert!(h.state().region().is_none(), "the orbit drag edited the document");

    // with a faired preview its comb is drawn too, on the faired curve
    h.get_by_role_and_label(Role::Button, "Whole curve").click();
    h.run();
    let faired = h.state().curve_ws.preview().expect("preview").result.curve.clone();
    let combs = h.state().curve_ws.curve3d.combs().to_vec();
    assert_eq!(combs.len(), 2);
    assert_eq!(combs[0], teeth);
    let scale_after = check_comb(&faired, &combs[1], combs[1].len() / 25, diag);
    assert_ne!(combs[1], teeth);
    // each comb is scaled to its own largest curvature
    assert!(scale_after.is_finite() && scale.is_finite());
}

#[test]
fn shading_settings_set_in_the_ui_survive_a_restart() {
    let mut h = harness(App::open_or_demo(Some(&asset("bumpy_surface.json"))));
    assert!(h.state().surface.is_some());
    h.get_by_label("Gaussian K").click();
    h.run();
    h.get_by_role_and_label(Role::Slider, "Mesh density")
        .set_value_accesskit(40.0);
    h.run();
    h.get_by_role_and_label(Role::Slider, "Light azimuth")
        .set_value_accesskit(-30.0);
    h.run();
    h.get_by_role_and_label(Role::CheckBox, "Control net").click();
    h.run();
    h.get_by_role_and_label(Role::CheckBox, "Isoparametric lines").click();
    h.run();
    let s = h.state().surface.as_ref().unwrap();
    let set = s.shading;
    assert_eq!(set.mode, ShadeMode::Gauss);
    assert_eq!(set.density, 40);
    assert_eq!(s.mesh.nu, 40, "density re-tessellates");
    assert_eq!(set.light_azimuth, -30.0);
    assert!(set.show_net && !set.show_iso);
    assert_ne!(set, Shading::default());

    let mut mem = MemStorage::default();
    eframe::App::save(h.state_mut(), &mut mem);
    assert!(mem.0.contains_key(View3dPrefs::KEY));

    // a fresh editor on the same file starts with the defaults, then restores
    let mut fresh = App::open_or_demo(Some(&asset("bumpy_surface.json")));
    assert_eq!(fresh.surface.as_ref().unwrap().shading, Shading::default());
    fresh.load_view3d_prefs(&mem);
    let s = fresh.surface.as_ref().unwrap();
    assert_eq!(s.shading, set);
    assert_eq!(s.mesh.nu, 40);
    // a curve session keeps them for the next surface it opens
    let mut curve_app = App::open_or_demo(Some(&asset("car_roof.ron")));
    curve_app.load_view3d_prefs(&mem);
    assert_eq!(curve_app.curve_ws.curve3d.surface_shading, set);
    curve_app.open_now(&asset("bumpy_surface.json"));
    assert_eq!(curve_app.surface.as_ref().expect("surface opened").shading, set);
    // and saves them again unchanged
    let mut mem2 = MemStorage::default();
    eframe::App::save(&mut curve_app, &mut mem2);
    assert_eq!(mem2.0.get(View3dPrefs::KEY), mem.0.get(View3dPrefs::KEY));
}

#[test]
fn extrusion_settings_round_trip_and_bad_stored_values_are_sanitized() {
    let mut app = App::open_or_demo(Some(&asset("car_roof.ron")));
    let ex = Shading {
        mode: ShadeMode::Zebra,
        stripe_deg: 2.25,
        light_elevation: -10.0,
        ..Shading::extrusion()
    };
    app.curve_ws.curve3d.shading = ex;
    let mut mem = MemStorage::default();
    eframe::App::save(&mut app, &mut mem);
    let mut fresh = App::open_or_demo(Some(&asset("car_roof.ron")));
    assert_eq!(fresh.curve_ws.curve3d.shading, Shading::extrusion());
    fresh.load_view3d_prefs(&mem);
    assert_eq!(fresh.curve_ws.curve3d.shading, ex);

    // hand-edited or stale storage: clamped / defaulted, never a panic or a
    // failed tessellation
    mem.set(
        View3dPrefs::KEY,
        "(surface: (density: 0, stripe_deg: 1000.0, range: Some(-1.0), light_azimuth: 400.0), extrusion: (mode: Mean))",
    );
    let mut app = App::open_or_demo(Some(&asset("bumpy_surface.json")));
    app.load_view3d_prefs(&mem);
    let s = app.surface.as_ref().unwrap();
    assert_eq!(s.shading.density, 8);
    assert_eq!(s.shading.stripe_deg, 30.0);
    assert_eq!(s.shading.range, None);
    assert_eq!(s.shading.light_azimuth, 85.0);
    assert_eq!(s.mesh.nu, 8);
    // missing fields take the defaults of the settings struct
    assert_eq!(app.curve_ws.curve3d.shading.mode, ShadeMode::Mean);
    assert_eq!(app.curve_ws.curve3d.shading.stripe_deg, 5.0);
    // unreadable: nothing changes
    mem.set(View3dPrefs::KEY, "not ron at all (");
    let before = app.view3d_prefs();
    app.load_view3d_prefs(&mem);
    assert_eq!(app.view3d_prefs(), before);
}

impl MemStorage {
    fn set(&mut self, k: &str, v: &str) {
        self.0.insert(k.into(), v.into());
    }
}
