//! The surface workspace's 3D views: before / after (blended, or side by side), ray-picked region
//! with Ctrl+drag, hover readout; scenes cached per view.

use std::sync::Arc;

use eframe::egui;
use egui::{Color32, Rect, Sense};
use fairway::mesh::{SurfaceMesh, pick_uv};
use fairway::{BSplineSurface, DVec3};

use super::{SceneCache, SurfaceCx, SurfaceWorkspace, points_hash};
use crate::Command;
use crate::view3d::scene::{append_other, append_outline, append_trim, effective_range, mode_values, surface_scene};
use crate::view3d::{self, ShadeMode, Shading};

impl SurfaceWorkspace {
    /// The surface shown as "after": the preview blended with the original.
    fn after_surface(&mut self, surface: &BSplineSurface) -> Option<(u64, BSplineSurface, SurfaceMesh)> {
        let p = self.preview.as_ref()?;
        let t = self.compare.blend.clamp(0.0, 1.0);
        let id = points_hash(&p.surface) ^ t.to_bits().rotate_left(17);
        if t == 1.0 {
            return Some((id, p.surface.clone(), p.mesh.clone()));
        }
        if let Some((k, s, m)) = &self.blend_cache
            && *k == (self.rev, id)
        {
            return Some((id, s.clone(), m.clone()));
        }
        let orig = surface;
        let pts: Vec<DVec3> = orig
            .points()
            .iter()
            .zip(p.surface.points())
            .map(|(a, b)| a.lerp(*b, t))
            .collect();
        let s = p.surface.with_points(pts).ok()?;
        let n = self.shading.density;
        let m = SurfaceMesh::tessellate(&s, n, n).ok()?;
        self.blend_cache = Some(((self.rev, id), s.clone(), m.clone()));
        Some((id, s, m))
    }

    fn scene(
        &mut self,
        slot: usize,
        id: u64,
        s: &BSplineSurface,
        mesh: &SurfaceMesh,
        region: Option<super::UvRect>,
    ) -> Arc<view3d::Scene> {
        let values = mode_values(&self.mesh, self.shading.mode).unwrap_or(&[]);
        let range = effective_range(&self.shading, values);
        // stripe width and light are uniforms of the paint callback, not part of the scene
        let baked = Shading {
            stripe_deg: 0.0,
            light_azimuth: 0.0,
            light_elevation: 0.0,
            ..self.shading
        };
        let key = (self.rev, id, baked, range.to_bits(), region, self.others_rev);
        if let Some(c) = &self.scenes[slot]
            && c.key == key
        {
            return c.scene.clone();
        }
        let origin = 0.5 * (self.view.bbox.0 + self.view.bbox.1);
        let mut scene = surface_scene(s, mesh, &self.shading, range, region, origin);
        if !self.others.is_empty() {
            for o in &self.others {
                append_other(&mut scene, &o.mesh, &self.shading, range, origin);
            }
            append_outline(&mut scene, s, origin);
        }
        if let Some(t) = &self.trim {
            append_trim(&mut scene, s, t, origin);
        }
        let scene = Arc::new(scene);
        self.scenes[slot] = Some(SceneCache {
            key,
            scene: scene.clone(),
        });
        scene
    }
}

impl SurfaceCx<'_> {
    pub(super) fn views_ui(&mut self, ui: &mut egui::Ui) {
        let full = ui.available_rect_before_wrap();
        let orig = self.surface().clone();
        let orig_mesh = self.ws.mesh.clone();
        let after = if self.ws.compare.show_after || self.ws.compare.side_by_side {
            self.ws.after_surface(self.surface())
        } else {
            None
        };
        // a draft (computed during a drag) is provisional while the full fair runs, or while the next
        // draft is computed (then it may be the draft of an earlier point of the drag)
        let fairing = self.ws.is_fairing();
        let drafting = self.ws.is_drafting();
        let draft = self.ws.preview.as_ref().is_some_and(|p| p.draft);
        let after_name = match (draft, fairing, drafting) {
            (false, _, _) => "After",
            (true, true, _) => "After (draft, provisional; fairing…)",
            (true, false, true) => "After (draft, provisional; updating…)",
            (true, false, false) => "After (draft, provisional)",
        };
        let mut panes: Vec<(Rect, &str, u64, BSplineSurface, SurfaceMesh, usize)> = vec![];
        if self.ws.compare.side_by_side {
            let (l, r) = full.split_left_right_at_fraction(0.5);
            panes.push((l.shrink(1.0), "Before", 0, orig.clone(), orig_mesh.clone(), 0));
            let none = if fairing {
                "After (fairing…)"
            } else if drafting {
                "After (drafting…)"
            } else {
                "After (no preview)"
            };
            match after {
                Some((id, s, m)) => panes.push((r.shrink(1.0), after_name, id, s, m, 1)),
                None => panes.push((r.shrink(1.0), none, 0, orig, orig_mesh, 1)),
            }
        } else {
            let none = match (fairing, drafting, self.ws.compare.show_after) {
                (true, _, true) => "Before (fairing…)",
                (false, true, true) => "Before (drafting…)",
                _ => "Before",
            };
            match after {
                Some((id, s, m)) => panes.push((full, after_name, id, s, m, 1)),
                None => panes.push((full, none, 0, orig, orig_mesh, 0)),
            }
        }
        let origin = 0.5 * (self.ws.view.bbox.0 + self.ws.view.bbox.1);
        for (k, (rect, name, id, s, mesh, slot)) in panes.into_iter().enumerate() {
            let resp = ui.interact(rect, ui.scope_id().with(("surf3d", k)), Sense::click_and_drag());
            resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "3D view"));
            self.ws.view.fit_if_needed(rect);
            let ctrl = ui.input(|i| i.modifiers.command);
            // Ctrl+drag: region by ray picking on the surface
            if ctrl || self.ws.pick_drag.is_some() {
                if resp.drag_started()
                    && let Some(p) = ui.input(|i| i.pointer.press_origin())
                {
                    let (o, d) = self.ws.view.ray(p, rect);
                    self.ws.pick_drag = pick_uv(&s, &mesh, o, d);
                }
                if let (Some(a), Some(p)) = (self.ws.pick_drag, resp.interact_pointer_pos())
                    && resp.dragged()
                {
                    let (o, d) = self.ws.view.ray(p, rect);
                    if let Some(b) = pick_uv(&s, &mesh, o, d)
                        && (b.x - a.x).abs() > 1e-9
                        && (b.y - a.y).abs() > 1e-9
                    {
                        self.push(Command::SetRegionUv(Some(((a.x, b.x), (a.y, b.y)))));
                    }
                }
                if resp.drag_stopped() {
                    self.ws.pick_drag = None;
                }
                self.ws.view.interact(ui, &resp, false);
            } else {
                self.ws.view.interact(ui, &resp, true);
            }
            if resp.clicked()
                && !ctrl
                && let Some(p) = resp.interact_pointer_pos()
                && let Some(k) = self.ws.picked_other(&s, &mesh, self.ws.view.ray(p, rect))
            {
                self.push(Command::Select(k));
            }
            if let Some(p) = resp.hover_pos() {
                let (o, d) = self.ws.view.ray(p, rect);
                let hv = pick_uv(&s, &mesh, o, d).map(|uv| {
                    let c = s.curvature(uv.x, uv.y);
                    let v = match self.ws.shading.mode {
                        ShadeMode::Gauss => c.gauss,
                        ShadeMode::KMax => c.k_max,
                        ShadeMode::KMin => c.k_min,
                        _ => c.mean,
                    };
                    (uv, v)
                });
                if hv != self.ws.hover {
                    self.ws.hover = hv;
                }
            }
            let scene = self.ws.scene(slot, id, &s, &mesh, self.region());
            self.ws.view.paint(
                ui,
                rect,
                ui.scope_id().with(("surf3d_paint", k)),
                &scene,
                origin,
                &self.ws.shading,
            );
            view3d::marks::marks_ui(ui, &self.ws.view, rect, &self.ws.marks, k);
            let painter = ui.painter_at(rect);
            // a draft, or the original standing in while the full fair runs, is named in the draft colour
            let provisional = (draft || fairing || drafting) && name != "Before";
            painter.text(
                rect.left_top() + egui::vec2(8.0, 6.0),
                egui::Align2::LEFT_TOP,
                name,
                egui::FontId::proportional(15.0),
                if provisional {
                    super::panels::DRAFT_COLOR
                } else {
                    Color32::WHITE
                },
            );
            if self.ws.shading.mode.is_curvature() {
                let values = mode_values(&self.ws.mesh, self.ws.shading.mode).unwrap_or(&[]);
                let range = effective_range(&self.ws.shading, values);
                view3d::legend(&painter, rect, self.ws.shading.mode.label(), range);
            }
        }
    }
}

impl SurfaceWorkspace {
    /// The triangles of the scenes last drawn (every pane's: the active patch and the others).
    pub fn drawn_triangles(&self) -> usize {
        self.scenes
            .iter()
            .flatten()
            .map(|c| c.scene.tri_indices.len() / 3)
            .sum()
    }

    /// The object of the other patch that the ray `(origin, dir)` hits nearer than the active patch
    /// `s` (tessellated as `mesh`), if any: a click there selects it.
    pub fn picked_other(&self, s: &BSplineSurface, mesh: &SurfaceMesh, (o, d): (DVec3, DVec3)) -> Option<usize> {
        let depth =
            |s: &BSplineSurface, m: &SurfaceMesh| pick_uv(s, m, o, d).map(|uv| (s.point(uv.x, uv.y) - o).dot(d));
        let active = depth(s, mesh).unwrap_or(f64::INFINITY);
        self.others
            .iter()
            .filter_map(|p| depth(&p.surface, &p.mesh).map(|t| (t, p.object)))
            .filter(|&(t, _)| t < active)
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, k)| k)
    }
}

/// Bounding box of a mesh's vertices.
pub fn bbox_of(mesh: &SurfaceMesh) -> (DVec3, DVec3) {
    view3d::camera::bbox(mesh.positions.iter().copied()).unwrap_or((DVec3::splat(-1.0), DVec3::splat(1.0)))
}
