//! The other objects of a document on the 2D canvas: the curves that are not active, drawn dimmed
//! with their names (a click on one selects it), and the joins between curves, marked by their
//! measured continuity (G0 red, G1 yellow, G2 green; hover: gap, tangent angle, curvature ratio).
//! The drawing of the dimmed curves and of a marker is shared with the 3D views (`view3d::marks`).

use eframe::egui;
use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Stroke, Vec2};

use crate::Command;
use crate::curve_ws::CurveCx;
use crate::scene_view::SceneCurve;
use crate::shell::continuity_color;
use fairway::network::Continuity;

/// Pick radius around another curve, in points.
const PICK: f32 = 8.0;
/// Radius of a join marker, in points.
const MARKER: f32 = 5.5;

impl CurveCx<'_> {
    /// The curves that are not active, dimmed, each with its name near its middle.
    pub(crate) fn draw_other_curves(&self, painter: &egui::Painter) {
        let scr = |c: &SceneCurve| c.pts.iter().map(|&p| self.ws.canvas.to_screen(p)).collect();
        draw_curves_dimmed(painter, &self.ws.scene.curves, self.ws.active_object, scr);
    }

    /// The join markers: a dot in the continuity's colour with its class beside it.
    pub(crate) fn draw_joins(&self, painter: &egui::Painter) {
        for j in &self.ws.scene.joins {
            draw_marker(painter, self.ws.canvas.to_screen(j.point), j.class);
        }
    }

    /// Each join marker as a widget of its own: its label ("G2 join: curve 1 end – curve 2 start") for
    /// screen readers and tests, its measures as hover text.
    pub(crate) fn join_markers_ui(&self, ui: &egui::Ui, rect: Rect) {
        for (k, j) in self.ws.scene.joins.iter().enumerate() {
            let c = self.ws.canvas.to_screen(j.point);
            if rect.contains(c) {
                marker_widget(ui, ui.scope_id().with(("join", k)), c, &j.label, &j.detail);
            }
        }
    }

    /// The curve (not the active one) under screen point `q`, unless the active curve is nearer than
    /// the pick radius.
    pub(crate) fn other_curve_at(&self, q: Pos2) -> Option<usize> {
        let scr = |p| self.ws.canvas.to_screen(p);
        let near_active = self.ws.view.sampled.p.iter().any(|&p| scr(p).distance(q) < PICK);
        if near_active {
            return None;
        }
        let dist = |pts: &[fairway::DVec2]| {
            pts.windows(2)
                .map(|w| segment_distance(q, scr(w[0]), scr(w[1])))
                .fold(f32::INFINITY, f32::min)
        };
        self.ws
            .scene
            .curves
            .iter()
            .filter(|c| c.object != self.ws.active_object)
            .map(|c| (c.object, dist(&c.pts)))
            .filter(|(_, d)| *d < PICK)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(k, _)| k)
    }

    /// A click on another curve selects it (one undo step).
    pub(crate) fn click_to_select(&mut self, resp: &egui::Response) {
        if resp.clicked()
            && let Some(q) = resp.interact_pointer_pos()
            && let Some(k) = self.other_curve_at(q)
        {
            self.push(Command::Select(k));
        }
    }
}

/// The curves that are not `active`, dimmed, and with more than one curve each one's name near its
/// middle; `screen` gives a curve's points on the screen.
pub(crate) fn draw_curves_dimmed(
    painter: &egui::Painter,
    curves: &[SceneCurve],
    active: usize,
    screen: impl Fn(&SceneCurve) -> Vec<Pos2>,
) {
    for c in curves {
        let pts = screen(c);
        let is_active = c.object == active;
        if !is_active {
            painter.add(egui::Shape::line(pts.clone(), Stroke::new(1.5, Color32::from_gray(95))));
        }
        if curves.len() > 1
            && let Some(&mid) = pts.get(pts.len() / 2)
        {
            let color = Color32::from_gray(if is_active { 200 } else { 120 });
            painter.text(
                mid + Vec2::new(6.0, -6.0),
                Align2::LEFT_BOTTOM,
                &c.label,
                FontId::proportional(12.0),
                color,
            );
        }
    }
}

/// A join marker at `c`: a dot in the continuity's colour with its class beside it.
pub(crate) fn draw_marker(painter: &egui::Painter, c: Pos2, class: Continuity) {
    let color = continuity_color(class);
    painter.circle(c, MARKER, color, Stroke::new(1.5, Color32::from_gray(20)));
    painter.text(
        c + Vec2::new(MARKER + 3.0, MARKER + 2.0),
        Align2::LEFT_TOP,
        class.name(),
        FontId::proportional(12.0),
        color,
    );
}

/// The marker at `c` as a widget of its own: `label` for screen readers and tests, `label` and
/// `detail` (its measures) as hover text.
pub(crate) fn marker_widget(ui: &egui::Ui, id: egui::Id, c: Pos2, label: &str, detail: &str) {
    let r = Rect::from_center_size(c, Vec2::splat(2.0 * MARKER + 4.0));
    let resp = ui.interact(r, id, Sense::hover());
    resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Image, true, label));
    resp.on_hover_text(format!("{label}\n{detail}"));
}

/// The distance from `q` to the segment `a b`.
fn segment_distance(q: Pos2, a: Pos2, b: Pos2) -> f32 {
    let ab = b - a;
    let t = if ab.length_sq() > 0.0 {
        ((q - a).dot(ab) / ab.length_sq()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    q.distance(a + ab * t)
}
