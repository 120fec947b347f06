//! 3D views of the curve editor (the κ plot, region and target editing stay
//! as they are):
//! - the curve in 3D with its curvature comb (teeth along κN, the principal
//!   normal scaled by the curvature), the control polygon and the faired
//!   preview — drawn with the painter through the orbit camera, so it works
//!   without a GPU too; the document's other curves dimmed, and the joins and
//!   shared patch edges marked by their continuity (`view3d::marks`);
//! - for planar curves, **extrusion isophotes** (the paper's interrogation of
//!   curves): the curve extruded along z, shown with isophotes, before and
//!   after fairing side by side.

use std::sync::Arc;

use eframe::egui;
use egui::{Color32, Pos2, Rect, Sense, Stroke};
use fairway::{BSplineCurve, BSplineSurface, DVec3};

use crate::canvas_scene::draw_curves_dimmed;
use crate::scene_view::SceneCurve;
use crate::view3d::scene::surface_scene;
use crate::view3d::{self, ShadeMode, Shading, View3d, View3dPrefs};
use fairway::mesh::{SurfaceMesh, curve_comb_3d, extrude_curve};

/// What the extrusion scenes depend on: curve revision, preview hash, and
/// the shading fields baked into the scene (mode, density, isolines, net).
type ExtrusionKey = (u64, u64, ShadeMode, usize, bool, bool);

/// State of the curve editor's 3D view.
pub struct Curve3dState {
    /// Show the 3D view instead of the 2D canvas.
    pub enabled: bool,
    /// Camera.
    pub view: View3d,
    /// Show extrusion isophotes (planar curves).
    pub extrusion: bool,
    /// Shading of the extrusions (persisted).
    pub shading: Shading,
    /// Shading of the surface workspace, kept here between surfaces and for
    /// eframe storage (the open surface's own settings take precedence).
    pub surface_shading: Shading,
    key: Option<ExtrusionKey>,
    scenes: Vec<Arc<view3d::Scene>>,
    extrusions: Vec<(BSplineSurface, SurfaceMesh)>,
    origin: DVec3,
    comb_key: Option<(u64, u64, u64, u64)>,
    combs: Vec<Vec<(DVec3, DVec3)>>,
}

impl Default for Curve3dState {
    fn default() -> Self {
        Self {
            enabled: false,
            view: View3d::default(),
            extrusion: false,
            shading: Shading::extrusion(),
            surface_shading: Shading::default(),
            key: None,
            scenes: vec![],
            extrusions: vec![],
            origin: DVec3::ZERO,
            comb_key: None,
            combs: vec![],
        }
    }
}

impl Curve3dState {
    /// The extruded surfaces shown side by side and their tessellations:
    /// the original curve's first, then the faired preview's (if any).
    pub fn extrusions(&self) -> &[(BSplineSurface, SurfaceMesh)] {
        &self.extrusions
    }

    /// The comb teeth `(base, tip)` drawn in the 3D curve view: the
    /// original curve's first, then the faired preview's (if any).
    pub fn combs(&self) -> &[Vec<(DVec3, DVec3)>] {
        &self.combs
    }
}

/// Comb teeth of `c` (the core's `curve_comb_3d`: equal arc length, teeth
/// on the outside of the bend): `samples` bases and tips, scaled so that the
/// longest tooth is `frac · size` long.
pub fn comb(c: &BSplineCurve, samples: usize, size: f64, frac: f64) -> Vec<(DVec3, DVec3)> {
    let unit = curve_comb_3d(c, samples, 1.0);
    let kmax = unit.iter().map(|(a, b)| (*b - *a).length()).fold(0.0, f64::max);
    let scale = if kmax > 0.0 { frac * size / kmax } else { 0.0 };
    unit.into_iter().map(|(a, b)| (a, a + (b - a) * scale)).collect()
}

/// Extrusion height for a curve of bounding-box diagonal `diag`.
pub fn extrusion_height(diag: f64) -> f64 {
    0.35 * diag
}

impl crate::curve_ws::CurveCx<'_> {
    /// The 3D view of the curve (replaces the canvas when enabled).
    pub(crate) fn curve3d_ui(&mut self, ui: &mut egui::Ui) {
        let curve = self.curve().clone();
        let faired = self.ws.preview().map(|p| p.result.curve.clone());
        let planar = curve.dim() == 2;
        ui.horizontal(|ui| {
            ui.selectable_value(&mut self.ws.curve3d.enabled, false, "2D canvas")
                .on_hover_text("Back to the 2D canvas");
            self.ws.curve3d.view.toolbar_ui(ui);
            ui.separator();
            ui.add_enabled(
                planar,
                egui::Checkbox::new(&mut self.ws.curve3d.extrusion, "Extrusion isophotes"),
            )
            .on_hover_text("Extrude the planar curve along z and show isophotes, before and after fairing");
            if self.ws.curve3d.extrusion {
                ui.add(
                    egui::Slider::new(&mut self.ws.curve3d.shading.stripe_deg, view3d::STRIPE_RANGE)
                        .text("Stripe width °"),
                )
                .on_hover_text("Angular width of one isophote stripe");
                self.ws.curve3d.shading.light_ui(ui);
            }
        });
        let full = ui.available_rect_before_wrap();
        let extrude = planar && self.ws.curve3d.extrusion;
        let bb = self.content_box(&curve, extrude);
        if bb != self.ws.curve3d.view.bbox {
            self.ws.curve3d.view.set_bbox(bb, true);
        }
        if extrude {
            self.extrusion_panes(ui, full, &curve, faired.as_ref());
        } else {
            self.curve_view(ui, full, &curve, faired.as_ref());
        }
    }

    /// The box the camera fits: the curve (and its extrusion), else the whole network.
    fn content_box(&self, curve: &BSplineCurve, extrude: bool) -> (DVec3, DVec3) {
        let mut pts: Vec<DVec3> = curve.points().to_vec();
        if extrude {
            let h = extrusion_height(self.ws.view.diag);
            pts.extend(curve.points().iter().map(|p| *p + DVec3::Z * h));
        } else {
            let active = self.ws.active_object;
            let others = self.ws.scene.curves.iter().filter(|c| c.object != active);
            pts.extend(others.flat_map(|c| c.pts3.iter().copied()));
        }
        view3d::camera::bbox(pts).unwrap_or((DVec3::splat(-1.0), DVec3::splat(1.0)))
    }

    /// The curve in 3D in `full`: comb, polygon, preview, the other curves dimmed and the joins marked.
    fn curve_view(&mut self, ui: &mut egui::Ui, full: Rect, curve: &BSplineCurve, faired: Option<&BSplineCurve>) {
        let resp = ui.interact(full, ui.scope_id().with("curve3d"), Sense::click_and_drag());
        resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "3D curve view"));
        self.ws.curve3d.view.fit_if_needed(full);
        self.ws.curve3d.view.interact(ui, &resp, true);
        self.update_combs(curve, faired);
        let painter = ui.painter_at(full);
        painter.rect_filled(full, 0.0, Color32::from_gray(24));
        self.draw_curve3d(&painter, full, curve, faired);
        let v = &self.ws.curve3d.view;
        let screen = |c: &SceneCurve| c.pts3.iter().filter_map(|&p| v.to_screen(p, full)).collect();
        draw_curves_dimmed(&painter, &self.ws.scene.curves, self.ws.active_object, screen);
        view3d::marks::marks_ui(ui, v, full, &self.ws.scene.marks3d, 0);
    }

    /// Number of comb teeth and curve samples drawn for `c`.
    fn comb_samples(c: &BSplineCurve) -> usize {
        (c.n_points() * 12).clamp(200, 1500)
    }

    /// Recompute the cached comb teeth if the curve, the preview or the comb
    /// scale changed.
    fn update_combs(&mut self, curve: &BSplineCurve, faired: Option<&BSplineCurve>) {
        let frac = 0.2 * self.prefs.comb_scale;
        let key = (
            self.ws.curve_rev,
            faired.map(|c| hash_points(c.points())).unwrap_or(0),
            frac.to_bits(),
            self.ws.view.diag.to_bits(),
        );
        if self.ws.curve3d.comb_key == Some(key) {
            return;
        }
        self.ws.curve3d.combs = [Some(curve), faired]
            .into_iter()
            .flatten()
            .map(|c| comb(c, Self::comb_samples(c), self.ws.view.diag, frac))
            .collect();
        self.ws.curve3d.comb_key = Some(key);
    }

    fn draw_curve3d(&self, painter: &egui::Painter, rect: Rect, curve: &BSplineCurve, faired: Option<&BSplineCurve>) {
        let v = &self.ws.curve3d.view;
        let proj = |p: DVec3| v.to_screen(p, rect);
        // axes at the box corner
        let (lo, hi) = v.bbox;
        let len = 0.15 * (hi - lo).length();
        for (d, c) in [
            (DVec3::X, Color32::from_rgb(200, 70, 70)),
            (DVec3::Y, Color32::from_rgb(70, 180, 70)),
            (DVec3::Z, Color32::from_rgb(80, 120, 230)),
        ] {
            if let (Some(a), Some(b)) = (proj(lo), proj(lo + d * len)) {
                painter.line_segment([a, b], Stroke::new(1.5, c));
            }
        }
        let line = |pts: &[DVec3], stroke: Stroke| {
            let s: Vec<Pos2> = pts.iter().filter_map(|p| proj(*p)).collect();
            if s.len() >= 2 {
                painter.add(egui::Shape::line(s, stroke));
            }
        };
        if self.prefs.show_polygon {
            line(curve.points(), Stroke::new(1.0, Color32::from_gray(90)));
            for p in curve.points() {
                if let Some(q) = proj(*p) {
                    painter.circle_filled(q, 2.5, Color32::from_gray(140));
                }
            }
        }
        let n = Self::comb_samples(curve);
        let has_after = faired.is_some();
        for (k, (c, is_after)) in [(Some(curve), false), (faired, true)].into_iter().enumerate() {
            let Some(c) = c else { continue };
            // original: blue comb, white curve (dimmed under a preview); preview: orange
            let (comb_rgb, curve_col) = if is_after {
                ((255, 150, 60), Color32::from_rgb(255, 170, 80))
            } else if has_after {
                ((90, 160, 255), Color32::from_gray(110))
            } else {
                ((90, 160, 255), Color32::from_gray(230))
            };
            if self.prefs.show_comb
                && let Some(teeth) = self.ws.curve3d.combs.get(k)
            {
                let a = if is_after || !has_after { 150 } else { 120 };
                let tooth = Color32::from_rgba_unmultiplied(comb_rgb.0, comb_rgb.1, comb_rgb.2, a);
                for (k, (a, b)) in teeth.iter().enumerate() {
                    if k % 3 == 0
                        && let (Some(p), Some(q)) = (proj(*a), proj(*b))
                    {
                        painter.line_segment([p, q], Stroke::new(1.0, tooth));
                    }
                }
                line(&teeth.iter().map(|t| t.1).collect::<Vec<_>>(), Stroke::new(1.2, tooth));
            }
            let (a, b) = c.domain();
            let pts: Vec<DVec3> = (0..=n).map(|k| c.point(a + (b - a) * k as f64 / n as f64)).collect();
            line(&pts, Stroke::new(2.0, curve_col));
        }
        painter.text(
            rect.left_bottom() + egui::vec2(8.0, -8.0),
            egui::Align2::LEFT_BOTTOM,
            "drag: orbit · right-drag: pan · wheel: zoom · comb: κN (blue original, orange faired)",
            egui::FontId::proportional(12.0),
            Color32::GRAY,
        );
    }

    fn extrusion_panes(&mut self, ui: &mut egui::Ui, full: Rect, curve: &BSplineCurve, faired: Option<&BSplineCurve>) {
        let sh_key = self.ws.curve3d.shading;
        let key = (
            self.ws.curve_rev,
            faired.map(|c| hash_points(c.points())).unwrap_or(0),
            sh_key.mode,
            sh_key.density,
            sh_key.show_iso,
            sh_key.show_net,
        );
        if self.ws.curve3d.key != Some(key) || self.ws.curve3d.scenes.is_empty() {
            let h = extrusion_height(self.ws.view.diag);
            let (lo, hi) = self.ws.curve3d.view.bbox;
            self.ws.curve3d.origin = 0.5 * (lo + hi);
            let mut scenes = vec![];
            let mut extrusions = vec![];
            for c in [Some(curve), faired] {
                let Some(c) = c else { continue };
                match extrude_curve(c, h).and_then(|s| {
                    let nu = (c.n_points() * 8).clamp(100, 800).max(sh_key.density);
                    SurfaceMesh::tessellate(&s, nu, 8).map(|m| (s, m))
                }) {
                    Ok((s, m)) => {
                        scenes.push(Arc::new(surface_scene(
                            &s,
                            &m,
                            &sh_key,
                            1.0,
                            None,
                            self.ws.curve3d.origin,
                        )));
                        extrusions.push((s, m));
                    }
                    Err(e) => *self.error = Some(format!("extrusion failed: {e}")),
                }
            }
            self.ws.curve3d.scenes = scenes;
            self.ws.curve3d.extrusions = extrusions;
            self.ws.curve3d.key = Some(key);
        }
        let n = self.ws.curve3d.scenes.len().max(1);
        let w = full.width() / n as f32;
        for k in 0..self.ws.curve3d.scenes.len() {
            let rect =
                Rect::from_min_size(full.min + egui::vec2(w * k as f32, 0.0), egui::vec2(w, full.height())).shrink(1.0);
            let resp = ui.interact(rect, ui.scope_id().with(("extr", k)), Sense::click_and_drag());
            resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "Extrusion view"));
            self.ws.curve3d.view.fit_if_needed(rect);
            self.ws.curve3d.view.interact(ui, &resp, true);
            let scene = self.ws.curve3d.scenes[k].clone();
            let origin = self.ws.curve3d.origin;
            let shading = self.ws.curve3d.shading;
            self.ws.curve3d.view.paint(
                ui,
                rect,
                ui.scope_id().with(("extr_paint", k)),
                &scene,
                origin,
                &shading,
            );
            let name = if k == 0 {
                "Before (original)"
            } else {
                "After (faired preview)"
            };
            ui.painter_at(rect).text(
                rect.left_top() + egui::vec2(8.0, 6.0),
                egui::Align2::LEFT_TOP,
                name,
                egui::FontId::proportional(15.0),
                Color32::WHITE,
            );
        }
        if faired.is_none() {
            ui.painter_at(full).text(
                full.center_bottom() + egui::vec2(0.0, -10.0),
                egui::Align2::CENTER_BOTTOM,
                "select a region to see the faired extrusion next to the original",
                egui::FontId::proportional(13.0),
                Color32::GRAY,
            );
        }
    }
}

impl crate::App {
    /// The 3D display settings to keep between sessions: the open surface's
    /// shading (else the last one used) and the extrusion view's.
    pub fn view3d_prefs(&self) -> View3dPrefs {
        View3dPrefs {
            surface: self
                .surface
                .as_ref()
                .map_or(self.curve_ws.curve3d.surface_shading, |s| s.shading),
            extrusion: self.curve_ws.curve3d.shading,
        }
    }

    /// Apply 3D display settings ([`View3dPrefs::sanitized`]) to the views,
    /// including an already open surface.
    pub fn set_view3d_prefs(&mut self, prefs: View3dPrefs) {
        let p = prefs.sanitized();
        self.curve_ws.curve3d.shading = p.extrusion;
        self.curve_ws.curve3d.surface_shading = p.surface;
        if let Some(s) = self.surface.as_mut()
            && let fairway::Geometry::Surface(surface) = &self.doc.geometry
            && let Err(e) = s.set_shading(p.surface, surface)
        {
            self.error = Some(e.to_string());
        }
    }

    /// Restore the 3D display settings from eframe storage (key
    /// [`View3dPrefs::KEY`]); nothing happens if they are missing or unreadable.
    pub fn load_view3d_prefs(&mut self, storage: &dyn eframe::Storage) {
        if let Some(p) = eframe::get_value::<View3dPrefs>(storage, View3dPrefs::KEY) {
            self.set_view3d_prefs(p);
        }
    }
}

fn hash_points(p: &[DVec3]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for q in p {
        q.x.to_bits().hash(&mut h);
        q.y.to_bits().hash(&mut h);
        q.z.to_bits().hash(&mut h);
    }
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comb_of_a_circle_points_away_from_the_centre_with_the_requested_length() {
        // quarter circle of radius 2 as a rational quadratic
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let c = BSplineCurve::try_new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(2.0, 2.0, 0.0),
                DVec3::new(0.0, 2.0, 0.0),
            ],
            Some(vec![1.0, w, 1.0]),
            2,
        )
        .unwrap();
        let teeth = comb(&c, 21, 10.0, 0.1);
        assert_eq!(teeth.len(), 21);
        for (a, b) in teeth {
            assert!((a.length() - 2.0).abs() < 1e-9);
            let t = b - a;
            assert!((t.length() - 1.0).abs() < 1e-6, "{}", t.length()); // 0.1 · 10, κ constant
            // teeth on the outside of the bend (the core's convention)
            assert!(t.normalize().dot(a.normalize()) > 1.0 - 1e-9);
        }
    }
}
