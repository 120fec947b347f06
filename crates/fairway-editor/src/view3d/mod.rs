//! The 3D view: an orbit camera ([`camera`]), scenes built from the core's
//! tessellation with exact per-vertex curvature ([`scene`]), colour maps
//! ([`colormap`]), the wgpu paint callback ([`render`]) and the joins of a
//! document's objects drawn over it ([`marks`]).
//!
//! Without a wgpu render state (the glow renderer, a test harness, or no
//! adapter at all) the view says so in place of the picture; nothing panics.

pub mod camera;
pub mod colormap;
pub mod marks;
pub mod render;
pub mod scene;

use std::sync::Arc;

use eframe::egui;
use egui::{Color32, Rect};
use glam::{DMat4, DVec2, DVec3};
use serde::{Deserialize, Serialize};

pub use camera::{Camera, StandardView};
pub use render::Scene;

/// How the surface is coloured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum ShadeMode {
    /// Plain lit grey.
    #[default]
    Shaded,
    /// Isophotes: stripes of equal angle between normal and light.
    Isophotes,
    /// Zebra / reflection lines.
    Zebra,
    /// Mean curvature H.
    Mean,
    /// Gaussian curvature K.
    Gauss,
    /// Maximum principal curvature κ₁.
    KMax,
    /// Minimum principal curvature κ₂.
    KMin,
}

impl ShadeMode {
    /// All modes, in menu order.
    pub const ALL: [ShadeMode; 7] = [
        ShadeMode::Shaded,
        ShadeMode::Isophotes,
        ShadeMode::Zebra,
        ShadeMode::Mean,
        ShadeMode::Gauss,
        ShadeMode::KMax,
        ShadeMode::KMin,
    ];

    /// Menu label.
    pub fn label(self) -> &'static str {
        match self {
            ShadeMode::Shaded => "Shaded",
            ShadeMode::Isophotes => "Isophotes",
            ShadeMode::Zebra => "Zebra",
            ShadeMode::Mean => "Mean H",
            ShadeMode::Gauss => "Gaussian K",
            ShadeMode::KMax => "κ max",
            ShadeMode::KMin => "κ min",
        }
    }

    /// Whether this is a curvature colour map.
    pub fn is_curvature(self) -> bool {
        matches!(
            self,
            ShadeMode::Mean | ShadeMode::Gauss | ShadeMode::KMax | ShadeMode::KMin
        )
    }

    /// Shader mode number (curvature maps are shaded vertex colours).
    pub fn shader_mode(self) -> u32 {
        match self {
            ShadeMode::Isophotes => 1,
            ShadeMode::Zebra => 2,
            _ => 0,
        }
    }
}

impl std::str::FromStr for ShadeMode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Ok(match s.to_ascii_lowercase().as_str() {
            "shaded" => ShadeMode::Shaded,
            "isophotes" => ShadeMode::Isophotes,
            "zebra" => ShadeMode::Zebra,
            "mean" => ShadeMode::Mean,
            "gauss" | "gaussian" => ShadeMode::Gauss,
            "kmax" => ShadeMode::KMax,
            "kmin" => ShadeMode::KMin,
            _ => return Err(format!("unknown shading {s:?}")),
        })
    }
}

/// Shading settings shared by the views of a workspace (persisted).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Shading {
    /// Colour mode.
    pub mode: ShadeMode,
    /// Stripe width of isophotes and zebra (degrees).
    pub stripe_deg: f64,
    /// Symmetric curvature range of the colour map (`None`: automatic).
    pub range: Option<f64>,
    /// Draw the control net.
    pub show_net: bool,
    /// Draw isoparametric lines at the knots.
    pub show_iso: bool,
    /// Tessellation vertices per direction.
    pub density: usize,
    /// Light direction: azimuth in degrees from the viewing direction
    /// towards the view's right (the light turns with the camera).
    pub light_azimuth: f64,
    /// Light direction: elevation in degrees above the viewing direction.
    pub light_elevation: f64,
}

/// Range of [`Shading::density`] offered in the UI and accepted from storage.
pub const DENSITY_RANGE: std::ops::RangeInclusive<usize> = 8..=200;
/// Range of [`Shading::stripe_deg`].
pub const STRIPE_RANGE: std::ops::RangeInclusive<f64> = 0.5..=30.0;
/// Range of the light angles (degrees).
pub const LIGHT_RANGE: std::ops::RangeInclusive<f64> = -85.0..=85.0;

impl Default for Shading {
    fn default() -> Self {
        Self {
            mode: ShadeMode::Shaded,
            stripe_deg: 5.0,
            range: None,
            show_net: false,
            show_iso: true,
            density: 80,
            light_azimuth: 25.0,
            light_elevation: 34.0,
        }
    }
}

impl Shading {
    /// The defaults of the curve editor's extrusion view: isophotes, no
    /// isolines, a finer tessellation along the curve.
    pub fn extrusion() -> Self {
        Self {
            mode: ShadeMode::Isophotes,
            show_iso: false,
            density: 160,
            ..Default::default()
        }
    }

    /// The settings with every number brought into its valid range (values
    /// restored from storage may be stale or hand-edited): NaN or out-of-range
    /// values are replaced by the default or clamped; a non-positive or
    /// non-finite colour range becomes automatic.
    pub fn sanitized(self) -> Self {
        let d = Self::default();
        let clamp = |x: f64, r: &std::ops::RangeInclusive<f64>, def: f64| {
            if x.is_finite() {
                x.clamp(*r.start(), *r.end())
            } else {
                def
            }
        };
        Self {
            stripe_deg: clamp(self.stripe_deg, &STRIPE_RANGE, d.stripe_deg),
            range: self.range.filter(|r| r.is_finite() && *r > 0.0),
            density: self.density.clamp(*DENSITY_RANGE.start(), *DENSITY_RANGE.end()),
            light_azimuth: clamp(self.light_azimuth, &LIGHT_RANGE, d.light_azimuth),
            light_elevation: clamp(self.light_elevation, &LIGHT_RANGE, d.light_elevation),
            ..self
        }
    }

    /// Unit direction towards the light for a camera with right, up and
    /// back (towards the eye) axes `r`, `u`, `b`:
    /// `cos(el)·(sin(az)·r + cos(az)·b) + sin(el)·u`.
    pub fn light_dir(&self, r: DVec3, u: DVec3, b: DVec3) -> DVec3 {
        let (az, el) = (self.light_azimuth.to_radians(), self.light_elevation.to_radians());
        (el.cos() * (az.sin() * r + az.cos() * b) + el.sin() * u).normalize()
    }

    /// Sliders of the light direction.
    pub fn light_ui(&mut self, ui: &mut egui::Ui) {
        ui.add(egui::Slider::new(&mut self.light_azimuth, LIGHT_RANGE).text("Light azimuth"))
            .on_hover_text("Light direction: degrees to the right of the viewing direction (turns with the camera)");
        ui.add(egui::Slider::new(&mut self.light_elevation, LIGHT_RANGE).text("Light elevation"))
            .on_hover_text("Light direction: degrees above the viewing direction");
    }
}

/// 3D display settings kept between sessions in eframe storage (key
/// [`View3dPrefs::KEY`]): the surface workspace's shading and the curve
/// editor's extrusion view's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct View3dPrefs {
    /// Shading of the surface workspace.
    pub surface: Shading,
    /// Shading of the extrusion isophotes of planar curves.
    pub extrusion: Shading,
}

impl View3dPrefs {
    /// eframe storage key.
    pub const KEY: &'static str = "view3d";

    /// Both settings [`Shading::sanitized`].
    pub fn sanitized(self) -> Self {
        Self {
            surface: self.surface.sanitized(),
            extrusion: self.extrusion.sanitized(),
        }
    }
}

impl Default for View3dPrefs {
    fn default() -> Self {
        Self {
            surface: Shading::default(),
            extrusion: Shading::extrusion(),
        }
    }
}

/// Key in egui's context data holding the adapter description (set by [`install`]).
fn gpu_key() -> egui::Id {
    egui::Id::unique("fairway3d_gpu")
}

/// Register the 3D renderer with eframe's wgpu render state (call once from
/// the app's constructor). Without a render state the views show a message.
pub fn install(cc: &eframe::CreationContext<'_>) {
    if let Some(rs) = cc.wgpu_render_state.as_ref() {
        let name = render::install(rs);
        cc.egui_ctx.data_mut(|d| d.insert_temp(gpu_key(), Arc::new(name)));
    }
}

/// The adapter description if the 3D renderer is installed.
pub fn gpu(ctx: &egui::Context) -> Option<Arc<String>> {
    ctx.data(|d| d.get_temp::<Arc<String>>(gpu_key()))
}

/// Camera state of a 3D view plus the box it fits.
#[derive(Debug, Clone)]
pub struct View3d {
    /// The camera.
    pub camera: Camera,
    /// Bounding box of the content.
    pub bbox: (DVec3, DVec3),
    /// Fit the box on the next frame.
    pub needs_fit: bool,
}

impl Default for View3d {
    fn default() -> Self {
        Self {
            camera: Camera::default(),
            bbox: (DVec3::splat(-1.0), DVec3::splat(1.0)),
            needs_fit: true,
        }
    }
}

impl View3d {
    /// Set the content box (fits on the next frame if `fit`).
    pub fn set_bbox(&mut self, bbox: (DVec3, DVec3), fit: bool) {
        self.bbox = bbox;
        self.camera.scene_radius = (0.5 * (bbox.1 - bbox.0).length()).max(1e-9);
        self.needs_fit |= fit;
    }

    /// Fit / standard view buttons.
    pub fn toolbar_ui(&mut self, ui: &mut egui::Ui) {
        if ui
            .button("Fit all")
            .on_hover_text("Fit the whole model in the view (F)")
            .clicked()
        {
            self.needs_fit = true;
        }
        for (v, name, key) in [
            (StandardView::Front, "Front", "1"),
            (StandardView::Top, "Top", "7"),
            (StandardView::Side, "Side", "3"),
            (StandardView::Iso, "Iso", "5"),
        ] {
            if ui.button(name).on_hover_text(format!("{name} view ({key})")).clicked() {
                self.camera.set_view(v);
                self.needs_fit = true;
            }
        }
    }

    /// Mouse and keys: left drag orbits, right/middle (or Shift+left) drag
    /// pans, the wheel zooms; with the pointer over the view, arrows orbit,
    /// Shift+arrows pan, +/− zoom, F fits, 1/3/7/5 front/side/top/iso.
    pub fn interact(&mut self, ui: &egui::Ui, r: &egui::Response, orbit_with_primary: bool) {
        let shift = ui.input(|i| i.modifiers.shift);
        let d = r.drag_delta();
        if d != egui::Vec2::ZERO {
            let pan = r.dragged_by(egui::PointerButton::Secondary)
                || r.dragged_by(egui::PointerButton::Middle)
                || (r.dragged_by(egui::PointerButton::Primary) && shift);
            if pan {
                self.camera.pan(d.x as f64, d.y as f64, r.rect.height() as f64);
            } else if orbit_with_primary && r.dragged_by(egui::PointerButton::Primary) {
                self.camera.orbit(d.x as f64 * 0.01, d.y as f64 * 0.01);
            }
        }
        if r.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                self.camera.zoom((-scroll as f64 * 0.002).exp());
            }
            if !ui.ctx().egui_wants_keyboard_input() {
                use egui::Key;
                let step = 5f64.to_radians();
                let h = r.rect.height() as f64;
                ui.input(|i| {
                    for (k, dx, dy) in [
                        (Key::ArrowLeft, -1.0, 0.0),
                        (Key::ArrowRight, 1.0, 0.0),
                        (Key::ArrowUp, 0.0, -1.0),
                        (Key::ArrowDown, 0.0, 1.0),
                    ] {
                        if i.key_pressed(k) {
                            if shift {
                                self.camera.pan(dx * 20.0, dy * 20.0, h);
                            } else {
                                self.camera.orbit(dx * step, -dy * step);
                            }
                        }
                    }
                    if i.key_pressed(Key::Plus) || i.key_pressed(Key::Equals) {
                        self.camera.zoom(1.0 / 1.15);
                    }
                    if i.key_pressed(Key::Minus) {
                        self.camera.zoom(1.15);
                    }
                    if i.key_pressed(Key::F) {
                        self.needs_fit = true;
                    }
                    for (k, v) in [
                        (Key::Num1, StandardView::Front),
                        (Key::Num3, StandardView::Side),
                        (Key::Num7, StandardView::Top),
                        (Key::Num5, StandardView::Iso),
                    ] {
                        if i.key_pressed(k) {
                            self.camera.set_view(v);
                            self.needs_fit = true;
                        }
                    }
                });
            }
        }
    }

    /// Fit now if requested, for a viewport of `rect`.
    pub fn fit_if_needed(&mut self, rect: Rect) {
        if self.needs_fit && rect.width() > 1.0 && rect.height() > 1.0 {
            self.camera
                .fit(self.bbox.0, self.bbox.1, (rect.width() / rect.height()) as f64);
            self.needs_fit = false;
        }
    }

    /// Screen position (points) of world point `p` in `rect`.
    pub fn to_screen(&self, p: DVec3, rect: Rect) -> Option<egui::Pos2> {
        let s = self
            .camera
            .project(p, DVec2::new(rect.width() as f64, rect.height() as f64))?;
        Some(rect.min + egui::vec2(s.x as f32, s.y as f32))
    }

    /// World ray through screen position `pos` in `rect`.
    pub fn ray(&self, pos: egui::Pos2, rect: Rect) -> (DVec3, DVec3) {
        let s = pos - rect.min;
        self.camera.ray(
            DVec2::new(s.x as f64, s.y as f64),
            DVec2::new(rect.width() as f64, rect.height() as f64),
        )
    }

    /// Add the paint callback drawing `scene` (coordinates relative to
    /// `origin`) into `rect`, or a message when no wgpu renderer is available.
    pub fn paint(
        &self,
        ui: &mut egui::Ui,
        rect: Rect,
        key: egui::Id,
        scene: &Arc<Scene>,
        origin: DVec3,
        shading: &Shading,
    ) {
        let painter = ui.painter_at(rect);
        if gpu(ui.ctx()).is_none() {
            painter.rect_filled(rect, 0.0, Color32::from_gray(40));
            ui.put(
                rect,
                egui::Label::new(
                    egui::RichText::new(
                        "3D view unavailable: no wgpu renderer/adapter.\n\
                         Run with the wgpu renderer (mesa llvmpipe/lavapipe works without a GPU).\n\
                         The uv view, fairing and measures still work.",
                    )
                    .color(Color32::from_gray(210)),
                )
                .selectable(false),
            );
            return;
        }
        let aspect = (rect.width() / rect.height().max(1.0)) as f64;
        let vp = self.camera.view_proj(aspect) * DMat4::from_translation(origin);
        let (r, u, b) = self.camera.basis();
        let light = shading.light_dir(r, u, b);
        let f3 = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32];
        let uniforms = render::Uniforms {
            view_proj: vp.to_cols_array().map(|x| x as f32),
            eye: f3(self.camera.eye() - origin),
            light: f3(light),
            axis_b: f3(u),
            axis_c: f3(b),
            mode: shading.mode.shader_mode(),
            stripe: shading.stripe_deg.to_radians() as f32,
            background: [0.16, 0.17, 0.19, 1.0],
        };
        painter.add(eframe::egui_wgpu::Callback::new_paint_callback(
            rect,
            render::ViewCallback {
                key: key.value(),
                scene: scene.clone(),
                uniforms,
                rect,
            },
        ));
    }
}

/// Layout of the colour-map legend in the view `rect`: `(box, bar)` for a
/// title of width `title_w` and value labels of width `label_w` (points).
/// The box sits in the top-right corner below the view's name, a margin
/// inside the right edge, wide enough for the bar and its labels; the bar
/// is 45 % of the view's height (80..260 points, less in a short view).
pub fn legend_layout(rect: Rect, title_w: f32, label_w: f32) -> (Rect, Rect) {
    const MARGIN: f32 = 8.0;
    const PAD: f32 = 8.0;
    const BAR_W: f32 = 18.0;
    const GAP: f32 = 4.0;
    const TITLE_H: f32 = 14.0;
    const TOP: f32 = 30.0;
    let content_w = title_w.max(BAR_W + GAP + label_w);
    let room = rect.height() - TOP - MARGIN - 2.0 * PAD - TITLE_H - 12.0;
    let h = (rect.height() * 0.45).clamp(80.0, 260.0).min(room.max(20.0));
    let size = egui::vec2(content_w + 2.0 * PAD, 2.0 * PAD + TITLE_H + 12.0 + h);
    let min = egui::pos2(rect.right() - MARGIN - size.x, rect.top() + TOP);
    let bx = Rect::from_min_size(min, size);
    let bar = Rect::from_min_size(
        egui::pos2(bx.left() + PAD, bx.top() + PAD + TITLE_H + 6.0),
        egui::vec2(BAR_W, h),
    );
    (bx, bar)
}

/// Draw the legend of a curvature colour map in the top-right corner of
/// `rect` (see [`legend_layout`]); returns the legend's box.
pub fn legend(painter: &egui::Painter, rect: Rect, title: &str, range: f64) -> Rect {
    let font = egui::FontId::proportional(11.0);
    let labels: Vec<_> = [range, 0.0, -range]
        .iter()
        .map(|v| painter.layout_no_wrap(format!("{v:+.3e}"), font.clone(), Color32::WHITE))
        .collect();
    let title_g = painter.layout_no_wrap(title.to_owned(), font, Color32::WHITE);
    let label_w = labels.iter().map(|g| g.size().x).fold(0.0, f32::max);
    let (bx, bar) = legend_layout(rect, title_g.size().x, label_w);
    painter.rect_filled(bx, 4.0, Color32::from_black_alpha(140));
    let n = 48;
    let h = bar.height();
    for k in 0..n {
        let t0 = k as f32 / n as f32;
        let t1 = (k + 1) as f32 / n as f32;
        let v = range * (1.0 - 2.0 * ((t0 + t1) * 0.5) as f64);
        let c = colormap::diverging(v, range);
        let seg = Rect::from_x_y_ranges(bar.x_range(), (bar.top() + t0 * h)..=(bar.top() + t1 * h));
        painter.rect_filled(seg, 0.0, to_color32(c));
    }
    for (t, g) in [0.0, 0.5, 1.0].into_iter().zip(labels) {
        let pos = egui::pos2(bar.right() + 4.0, bar.top() + t * h - 0.5 * g.size().y);
        painter.galley(pos, g, Color32::WHITE);
    }
    let tpos = egui::pos2(bar.left(), bar.top() - 6.0 - title_g.size().y);
    painter.galley(tpos, title_g, Color32::WHITE);
    bx
}

/// sRGB 0..1 → egui colour.
pub fn to_color32(c: [f32; 3]) -> Color32 {
    Color32::from_rgb((c[0] * 255.0) as u8, (c[1] * 255.0) as u8, (c[2] * 255.0) as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Run `f` with a painter of a real egui context (fonts loaded).
    fn with_painter(f: impl FnOnce(&egui::Painter)) {
        let ctx = egui::Context::default();
        let mut f = Some(f);
        let mut out = ctx.run_ui(egui::RawInput::default(), |ui| {
            if let Some(f) = f.take() {
                f(ui.painter());
            }
        });
        out.textures_delta.clear();
    }

    #[test]
    fn legend_box_stays_inside_the_view_and_holds_its_labels() {
        with_painter(|painter| {
            for (w, h) in [(1400.0, 900.0), (640.0, 480.0), (300.0, 220.0)] {
                for (title, range) in [("Gaussian K", 1.234e-5), ("Mean H", 0.5), ("κ max", 123.456)] {
                    let rect = Rect::from_min_size(egui::pos2(50.0, 20.0), egui::vec2(w, h));
                    let bx = legend(painter, rect, title, range);
                    assert!(rect.contains_rect(bx), "{bx:?} not inside {rect:?}");
                    // the widest value label fits between the bar and the box edge
                    let g = painter.layout_no_wrap(
                        format!("{:+.3e}", -range),
                        egui::FontId::proportional(11.0),
                        Color32::WHITE,
                    );
                    let t = painter.layout_no_wrap(title.into(), egui::FontId::proportional(11.0), Color32::WHITE);
                    let (_, bar) = legend_layout(rect, t.size().x, g.size().x);
                    assert!(bx.contains_rect(bar));
                    assert!(bar.right() + 4.0 + g.size().x <= bx.right(), "labels clipped");
                }
            }
        });
    }

    #[test]
    fn light_direction_is_a_unit_vector_at_the_given_angles() {
        let (r, u, b) = (DVec3::X, DVec3::Z, -DVec3::Y);
        let mut s = Shading::default();
        let l = s.light_dir(r, u, b);
        assert!((l.length() - 1.0).abs() < 1e-12);
        // default: above and to the right of the viewing direction, towards the viewer
        assert!(l.dot(r) > 0.0 && l.dot(u) > 0.0 && l.dot(b) > 0.0);
        s.light_azimuth = 0.0;
        s.light_elevation = 0.0;
        assert!((s.light_dir(r, u, b) - b).length() < 1e-12, "headlight");
        s.light_azimuth = 30.0;
        s.light_elevation = 20.0;
        let l = s.light_dir(r, u, b);
        assert!((l.dot(u) - 20f64.to_radians().sin()).abs() < 1e-12);
        assert!((l.dot(r).atan2(l.dot(b)) - 30f64.to_radians()).abs() < 1e-12);
    }

    #[test]
    fn sanitized_keeps_valid_settings_and_repairs_bad_ones() {
        let good = Shading {
            mode: ShadeMode::KMin,
            stripe_deg: 3.5,
            range: Some(0.2),
            show_net: true,
            show_iso: false,
            density: 64,
            light_azimuth: -40.0,
            light_elevation: 10.0,
        };
        assert_eq!(good.sanitized(), good);
        let bad = Shading {
            stripe_deg: f64::NAN,
            range: Some(f64::INFINITY),
            density: 100_000,
            light_azimuth: -1e9,
            light_elevation: f64::NAN,
            ..good
        }
        .sanitized();
        assert_eq!(bad.stripe_deg, 5.0);
        assert_eq!(bad.range, None);
        assert_eq!(bad.density, 200);
        assert_eq!(bad.light_azimuth, -85.0);
        assert_eq!(bad.light_elevation, Shading::default().light_elevation);
        assert_eq!((bad.mode, bad.show_net, bad.show_iso), (ShadeMode::KMin, true, false));
        let p = View3dPrefs::default();
        assert_eq!(p.sanitized(), p);
        let text = ron::to_string(&p).unwrap();
        assert_eq!(ron::from_str::<View3dPrefs>(&text).unwrap(), p);
    }
}
