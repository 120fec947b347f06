//! The curve workspace: the 2D canvas (or the curve's 3D view), the κ plot, the side panel
//! (region, tolerance, comb, fairing, measures) and the live fairing preview. Its panels are written
//! against [`CurveCx`] (the workspace with the shell's document, settings and command queue); it
//! applies the curve's document edits for the shell ([`Workspace::apply_edit`]).

use eframe::egui;
use fairway::fair::EndCondition;
use fairway::io::Document;
use fairway::network::Continuity;
use fairway::{BSplineCurve, DVec2, Geometry};

use crate::commands::{set_fair_options, set_tolerance};
use crate::fair_ui::{Compare, TargetDrag, TargetTool};
use crate::fairing::{FairOptions, Fairing, Preview};
use crate::scene_view::{Frame, SceneView};
use crate::shell::doc_curve;
use crate::workspace::{Cx, ShellCx, Workspace};
use crate::{Command, Sampled, canvas, curve3d, plot, region, suggest};

/// Data derived from the document's curve, rebuilt when the curve changes.
#[derive(Debug, Clone, Default)]
pub struct CurveView {
    /// Dense samples of the curve.
    pub sampled: Sampled,
    /// Control points projected onto the view plane.
    pub control: Vec<DVec2>,
    /// Diagonal of the bounding box (model units).
    pub diag: f64,
    /// The curve is closed (first point = last point): its parameter is circular and a region may
    /// run across the seam ([`region`]).
    pub closed: bool,
    /// The curve's parameter domain `(a, b)`.
    pub domain: (f64, f64),
}

impl CurveView {
    /// The derived data of `curve`, drawn on the view plane of `frame`.
    pub fn new(curve: &BSplineCurve, frame: &Frame) -> Self {
        let spans = curve.knots().breakpoints().len().saturating_sub(1).max(1);
        let sampled = Sampled::new(&frame.curve_in(curve), (spans * 24).clamp(400, 4000));
        let control: Vec<DVec2> = curve.points().iter().map(|&p| frame.project(p)).collect();
        let (a, b) = sampled.bbox;
        let diag = (b - a).length().max(1e-12);
        Self {
            sampled,
            control,
            diag,
            closed: fairway::fair::closed::is_closed_curve(curve),
            domain: curve.domain(),
        }
    }
}

/// The curve workspace's state: derived data, views, interaction and the fairing preview.
pub struct CurveWorkspace {
    /// Derived drawing data of the document's curve.
    pub view: CurveView,
    /// Bumped whenever the document's curve changes.
    pub curve_rev: u64,
    /// Canvas camera and interaction state.
    pub canvas: canvas::CanvasState,
    /// κ plot interaction state.
    pub plot: plot::PlotState,
    /// Arc length under the pointer (canvas or κ plot), shared by both.
    pub hover_s: Option<f64>,
    pub(crate) next_hover_s: Option<f64>,
    /// Live fairing preview.
    pub fairing: Fairing,
    /// Compare settings.
    pub compare: Compare,
    /// Target tool on the κ plot.
    pub tool: TargetTool,
    /// Falloff radius of a target drag (fraction of the region length).
    pub falloff: f64,
    /// Target drag in progress.
    pub target_drag: Option<TargetDrag>,
    /// A drag (slider, canvas, κ plot) is in progress: the preview is a draft.
    pub drag_in_progress: bool,
    /// The frame-time benchmark drives the editor (its frames count as drags).
    pub benchmarking: bool,
    /// "Suggest regions" results.
    pub suggest: suggest::Suggestions,
    /// The curve's 3D view (3D comb, extrusion isophotes).
    pub curve3d: curve3d::Curve3dState,
    /// Every curve of the document and their joins, on the view plane (set by the shell).
    pub scene: SceneView,
    /// The index of the document's object this workspace shows.
    pub active_object: usize,
}

/// The curve workspace with the shell's context: what its panels are written against.
pub type CurveCx<'a> = Cx<'a, CurveWorkspace>;

impl CurveWorkspace {
    /// The workspace for `curve`.
    pub fn new(curve: &BSplineCurve) -> Self {
        Self {
            view: CurveView::new(curve, &Frame::XY),
            curve_rev: 0,
            canvas: Default::default(),
            plot: Default::default(),
            hover_s: None,
            next_hover_s: None,
            fairing: Fairing::default(),
            compare: Compare::default(),
            tool: TargetTool::default(),
            falloff: 0.08,
            target_drag: None,
            drag_in_progress: false,
            benchmarking: false,
            suggest: Default::default(),
            curve3d: Default::default(),
            scene: SceneView::default(),
            active_object: 0,
        }
    }

    /// Show `curve` (a newly opened document): new derived data, fitted view.
    pub fn set_curve(&mut self, curve: &BSplineCurve) {
        self.show_curve(curve);
        self.canvas.needs_fit = true;
    }

    /// Show `curve` (another object of the document, or the same on another view plane) in the same view.
    pub fn show_curve(&mut self, curve: &BSplineCurve) {
        self.fairing.frame = self.scene.frame;
        self.view = CurveView::new(curve, &self.scene.frame);
        self.curve_rev += 1;
    }

    /// The preview, if fairing succeeded.
    pub fn preview(&self) -> Option<&Preview> {
        self.fairing.preview.as_ref().and_then(|r| r.as_ref().ok())
    }

    /// Arc length (on the original) of target sample k.
    pub fn target_s(&self, p: &Preview, k: usize) -> f64 {
        self.view.sampled.s_at_u(p.params[k])
    }
}

impl<'a> CurveCx<'a> {
    /// The document's curve.
    pub fn curve(&self) -> &'a BSplineCurve {
        doc_curve(self.doc).expect("the curve workspace shows a curve document")
    }

    /// The tolerance in effect (document value or a default from the size).
    pub fn tolerance(&self) -> f64 {
        self.doc.settings.tolerance.unwrap_or(self.ws.default_tolerance())
    }

    /// The region `[u1, u2]`, if one is selected (`u1 > u2`: across the seam of a closed curve).
    pub fn region(&self) -> Option<(f64, f64)> {
        self.doc.settings.region
    }

    /// The end conditions of the curve region: the document's, else the default of the preferences,
    /// where a region end is a curve end joining another curve: the join's continuity
    /// ([`CurveCx::join_holds`]).
    pub fn ends(&self) -> [EndCondition; 2] {
        if let Some(e) = self.doc.settings.ends {
            return e;
        }
        let (base, held) = (self.prefs.fair.ends, self.join_holds());
        [0, 1].map(|i| held[i].unwrap_or(base[i]))
    }

    /// For each end of the region: if it is an end of the (open) curve that joins other curves, the
    /// condition that keeps the join as measured (its continuity, at least G1 so an angle stays, as the
    /// core's network fair holds a join); else `None`.
    pub fn join_holds(&self) -> [Option<EndCondition>; 2] {
        let Some((u1, u2)) = self.region() else {
            return [None; 2];
        };
        if self.ws.view.closed {
            return [None; 2];
        }
        let (d0, d1) = self.ws.view.domain;
        let eps = 1e-9 * (d1 - d0);
        let reaches = [u1 <= d0 + eps, u2 >= d1 - eps];
        let joins = self.ws.scene.end_joins(self.ws.active_object);
        [0, 1].map(|i| {
            joins[i].filter(|_| reaches[i]).map(|c| match c {
                Continuity::G2 => EndCondition::G2,
                _ => EndCondition::G1,
            })
        })
    }

    /// The condition the core keeps at each curve end the region reaches: at a join, the region end's
    /// own condition (not weakened to G1 as at a free curve end); `None` at a free end (the core's
    /// default there).
    fn held_curve_ends(&self) -> [Option<EndCondition>; 2] {
        let ends = self.ends();
        let held = self.join_holds();
        [0, 1].map(|i| held[i].map(|_| ends[i]))
    }

    /// Bring the fairing preview up to date with the document; true if it was recomputed.
    pub fn update_fairing(&mut self) -> bool {
        let tol = self.tolerance();
        let opts = FairOptions {
            ends: self.ends(),
            curve_ends: self.held_curve_ends(),
            ..self.prefs.fair
        };
        let curve = self.curve();
        let ws = &mut *self.ws;
        ws.fairing.update(
            curve,
            ws.curve_rev,
            &self.doc.settings,
            tol,
            opts,
            ws.compare.trio,
            ws.drag_in_progress,
        )
    }

    /// The status bar: pointer readout and the curve's description.
    fn status_ui(&mut self, ui: &mut egui::Ui) {
        if let Some(s) = self.ws.hover_s {
            let k = self.ws.view.sampled.kappa_at_s(s);
            ui.label(format!("s = {s:.4}  κ = {k:.5}"));
            ui.separator();
        }
        let c = self.curve();
        ui.label(format!(
            "{}D, degree {}, {} control points, length {:.4}{}",
            c.dim(),
            c.degree(),
            c.n_points(),
            self.ws.view.sampled.length,
            self.unit.map_or(String::new(), |u| format!(" {}", u.symbol()))
        ));
        if let Some(u) = self.unit {
            ui.label(format!("unit {}", u.symbol()))
                .on_hover_text("The length unit of the file this curve came from (IGES / STEP)");
        }
    }
}

impl Workspace for CurveWorkspace {
    fn default_tolerance(&self) -> f64 {
        self.view.diag * 1e-3
    }

    fn view_menu_ui(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>) {
        let p = &mut *sh.prefs;
        ui.checkbox(&mut p.show_polygon, "Control polygon")
            .on_hover_text("Show the control points and polygon");
        ui.checkbox(&mut p.show_comb, "Curvature comb")
            .on_hover_text("Curvature comb on the canvas");
        ui.checkbox(&mut p.show_markers, "Inflections and extrema")
            .on_hover_text("Green diamonds: inflections; orange dots: curvature extrema");
    }

    fn toolbar_ui(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>) {
        let fit = format!(
            "Fit the curve to the view ({})",
            crate::shortcuts::shortcut_text(ui.ctx(), &Command::FitView)
        );
        if ui.button("Fit").on_hover_text(fit).clicked() {
            sh.commands.push(Command::FitView);
        }
        ui.toggle_value(&mut self.curve3d.enabled, "3D view")
            .on_hover_text("The curve and its comb in 3D; extrusion isophotes for planar curves");
    }

    fn status_ui(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>) {
        sh.with(self).status_ui(ui);
    }

    fn hint(&self) -> &'static str {
        "Drag along the curve or the κ plot to select a region · wheel: zoom · right-drag: pan · F: fit · F1: keys"
    }

    fn panels_ui(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>) {
        self.next_hover_s = None;
        let mut cx = sh.with(self);
        egui::Panel::right("controls")
            .resizable(true)
            .default_size(270.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| cx.controls_ui(ui));
            });
        egui::Panel::bottom("kappa")
            .resizable(true)
            .default_size(210.0)
            .show(ui, |ui| cx.plot_ui(ui));
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>) {
        let mut cx = sh.with(self);
        if cx.ws.curve3d.enabled {
            cx.curve3d_ui(ui);
        } else {
            cx.canvas_ui(ui);
        }
        cx.trio_ui(&ui.ctx().clone());
    }

    fn apply_edit(&mut self, c: &Command, doc: &mut Document, fair: &mut FairOptions) -> bool {
        let s = &mut doc.settings;
        match c {
            Command::SetRegion(r) => {
                let (dom, closed) = (self.view.domain, self.view.closed);
                let r = r.map(|r| region::canonical(r, dom, closed));
                if s.region == r {
                    return false;
                }
                s.region = r;
                // a hand-edited target belongs to the old region's samples
                clear_target(s);
                true
            }
            Command::SetTolerance(t) => set_tolerance(doc, *t),
            Command::SetFairOptions(o) => set_fair_options(fair, *o),
            Command::SetEnds(ends) => {
                if s.ends == Some(*ends) {
                    return false;
                }
                s.ends = Some(*ends);
                true
            }
            Command::SetTarget { values, pinned } => {
                if s.target == *values && s.pinned == *pinned {
                    return false;
                }
                // the edit was made on the preview's samples: their curve parameters go with it, so
                // that it survives other samples (other end conditions, a reopened file)
                s.target_params = match (values, &self.fairing.preview) {
                    (Some(v), Some(Ok(p))) if p.params.len() == v.len() => Some(p.params.clone()),
                    _ => None,
                };
                s.target = values.clone();
                s.pinned = pinned.clone();
                true
            }
            Command::ReplaceCurve(c) => {
                s.region = None;
                clear_target(s);
                doc.geometry = Geometry::Curve((**c).clone());
                self.show_curve(c);
                true
            }
            _ => false,
        }
    }

    fn document_changed(&mut self, doc: &Document, geometry_changed: bool) {
        if geometry_changed && let Some(c) = doc_curve(doc) {
            self.show_curve(c);
        }
    }

    fn after_commands(&mut self, ui: &mut egui::Ui, sh: &mut ShellCx<'_>) {
        // a drag on a slider, the canvas or the κ plot: fair a draft (no E polish) until it ends
        // (buttons are clicks, not drags: Accept never starts a draft); the bench counts as a drag
        self.drag_in_progress = self.benchmarking
            || ui.ctx().dragged_id().is_some()
            || self.canvas.drag != canvas::CanvasDrag::None
            || self.plot.drag != plot::PlotDrag::None
            || self.target_drag.is_some();
        if sh.with(self).update_fairing() {
            ui.ctx().request_repaint();
        }
        if let Some(e) = self.fairing.internal_error.take() {
            *sh.error = Some(e);
        }
        if self.hover_s != self.next_hover_s {
            self.hover_s = self.next_hover_s;
            ui.ctx().request_repaint();
        }
    }

    fn fit_view(&mut self) {
        self.canvas.needs_fit = true;
    }

    fn toggle_before_after(&mut self) {
        self.compare.show_after = !self.compare.show_after;
    }
}

/// Forget the hand-edited target and its pins.
fn clear_target(s: &mut fairway::io::DocumentSettings) {
    s.target = None;
    s.pinned.clear();
    s.target_params = None;
}
