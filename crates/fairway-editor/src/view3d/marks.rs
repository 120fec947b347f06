//! The joins of a document's objects in the 3D views (the curve view and the surface views): a curve
//! join marked as on the 2D canvas, a shared patch edge as a line along it in its continuity's colour
//! with the marker at its middle; each marker a widget with its label, its measures on hover.

use eframe::egui;
use egui::{Rect, Stroke};

use super::View3d;
use crate::canvas_scene::{draw_marker, marker_widget};
use crate::scene_view::Mark3d;
use crate::shell::continuity_color;

/// Width of a shared edge's line, in points.
const EDGE_WIDTH: f32 = 4.0;

/// Draw `marks` over `view` in `rect` (markers outside it are left out); `pane` tells the panes of one
/// view apart.
pub(crate) fn marks_ui(ui: &egui::Ui, view: &View3d, rect: Rect, marks: &[Mark3d], pane: usize) {
    let painter = ui.painter_at(rect);
    for (k, m) in marks.iter().enumerate() {
        let pts: Vec<egui::Pos2> = m.points.iter().filter_map(|&p| view.to_screen(p, rect)).collect();
        if pts.len() >= 2 {
            painter.add(egui::Shape::line(
                pts.clone(),
                Stroke::new(EDGE_WIDTH, continuity_color(m.class)),
            ));
        }
        let Some(&at) = pts.get(pts.len() / 2).filter(|p| rect.contains(**p)) else {
            continue;
        };
        draw_marker(&painter, at, m.class);
        marker_widget(ui, ui.scope_id().with(("mark3d", pane, k)), at, &m.label, &m.detail);
    }
}
