//! Fairing controls: target tools, end conditions, advanced options,
//! compare (overlay, Space toggle, blend, tight/medium/loose trio), measures,
//! accept.

use eframe::egui;
use egui::{Color32, Pos2, Rect, RichText, Shape, Stroke};
use fairway::DVec2;
use fairway::fair::{EndCondition, FitMode, Integrator, PolishMethod, Seam, TargetMethod};

use crate::Command;
use crate::canvas::colors;
use crate::curve_ws::CurveCx;
use crate::fairing::{FairOptions, MAX_POLISH, Preview, default_strength, pinned_indices};
use crate::region;

/// What a drag on the κ plot does to the target.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TargetTool {
    /// Drag target points up and down with a soft falloff.
    #[default]
    Drag,
    /// Click to pin / unpin a target sample.
    Pin,
    /// Drag across a stretch to smooth it.
    Smooth,
    /// Drag across a stretch to flatten it to constant curvature.
    Flatten,
}

/// Compare settings.
#[derive(Debug, Clone)]
pub struct Compare {
    /// Show the faired result (Space toggles before/after).
    pub show_after: bool,
    /// Draw the original dimmed under the result.
    pub overlay: bool,
    /// Blend original (0) ↔ faired (1).
    pub blend: f64,
    /// Show the tight / medium / loose trio.
    pub trio: bool,
}

impl Default for Compare {
    fn default() -> Self {
        Self {
            show_after: true,
            overlay: true,
            blend: 1.0,
            trio: false,
        }
    }
}

/// A target drag in progress.
#[derive(Debug, Clone)]
pub struct TargetDrag {
    /// Sample index grabbed (Drag tool) or where the stretch starts (brushes).
    pub k0: usize,
    /// κ under the pointer when the drag started.
    pub k_start: f64,
    /// Target values when the drag started.
    pub start: Vec<f64>,
}

impl CurveCx<'_> {
    /// The preview, if fairing succeeded.
    pub fn preview(&self) -> Option<&Preview> {
        self.ws.fairing.preview.as_ref().and_then(|r| r.as_ref().ok())
    }

    /// Arc length (on the original) of target sample k.
    pub fn target_s(&self, p: &Preview, k: usize) -> f64 {
        self.ws.view.sampled.s_at_u(p.params[k])
    }

    /// Arc length of the region (both parts for a region across the seam); 0 without a region.
    pub fn region_s_length(&self) -> f64 {
        let Some(r) = self.region() else { return 0.0 };
        let o = &self.ws.view.sampled;
        region::parts(r, self.ws.view.domain)
            .iter()
            .map(|&(a, b)| o.s_at_u(b) - o.s_at_u(a))
            .sum()
    }

    /// Arc-length distance between `s1` and `s2` along the curve: around the loop (the shorter way)
    /// when the region runs across the seam, so a target edit reaches through it.
    fn s_distance(&self, s1: f64, s2: f64) -> f64 {
        let d = (s1 - s2).abs();
        if self.region().is_some_and(region::wraps) {
            d.min(self.ws.view.sampled.length - d)
        } else {
            d
        }
    }

    /// Under a preview of a region with corners: what was kept, the stretches left as they are, and one
    /// button per stretch between corners that makes it the region (to shape that stretch's target
    /// alone).
    fn corner_stretches_ui(&mut self, ui: &mut egui::Ui) {
        let Some(Ok(p)) = &self.ws.fairing.preview else {
            return;
        };
        if p.corners.is_empty() {
            return;
        }
        let list: Vec<String> = p.corners.iter().map(fairway::corners::Corner::describe).collect();
        ui.weak(format!(
            "{} kept (tangent break or stop): the {} stretches between them faired one by one",
            fairway::corners::counted(&p.corners),
            p.stretches.len()
        ))
        .on_hover_text(format!(
            "Fairing across a corner would round it off into a curvature spike, so the region is faired \
             stretch by stretch, G1 at a kink (its point and angle stay exactly). Corners {}.",
            list.join(", ")
        ));
        for note in &p.result.notes {
            ui.colored_label(Color32::YELLOW, note);
        }
        let mut picked = None;
        ui.horizontal_wrapped(|ui| {
            ui.weak("Fair one stretch only:");
            for &(a, b) in &p.stretches {
                if ui
                    .small_button(format!("u {a:.4} to {b:.4}"))
                    .on_hover_text("Make this stretch between corners the region")
                    .clicked()
                {
                    picked = Some((a, b));
                }
            }
        });
        if let Some(r) = picked {
            self.push(Command::SetRegion(Some(r)));
        }
    }

    /// The fairing section of the side panel.
    pub fn fairing_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Fairing");
        if self.region().is_none() {
            ui.weak("Select a region to see the faired preview.");
            return;
        }
        self.fair_status_ui(ui);
        self.corner_stretches_ui(ui);
        if self.ws.fairing.target_mismatch {
            ui.colored_label(
                Color32::YELLOW,
                "The saved target does not fit this region's samples; using the automatic target.",
            );
        }
        ui.horizontal(|ui| {
            // a draft (drag in progress) is not accepted: the full fair follows the release
            let can = self.ws.preview().is_some_and(|p| !p.draft);
            if ui
                .add_enabled(can, egui::Button::new(RichText::new("Accept").strong()))
                .on_hover_text("Replace the region by the faired curve (one undo step)")
                .clicked()
                && let Some(c) = self.ws.preview().map(|p| p.result.curve.clone())
            {
                self.push(Command::ReplaceCurve(Box::new(c)));
            }
        });
        ui.add_space(4.0);
        // the options are edited on a copy: a change is a command (one undo step per gesture)
        let mut opts = self.prefs.fair;
        self.target_ui(ui, &mut opts);
        ui.add_space(4.0);
        self.end_conditions_ui(ui, &mut opts);
        egui::CollapsingHeader::new("Advanced").show(ui, |ui| advanced_ui(ui, &mut opts));
        if opts != self.prefs.fair {
            self.push(Command::SetFairOptions(opts));
        }
        ui.add_space(4.0);
        self.compare_ui(ui);
    }

    /// The preview's status: error, or deviation bound, timing and what happened at the seam.
    fn fair_status_ui(&self, ui: &mut egui::Ui) {
        match &self.ws.fairing.preview {
            Some(Err(e)) => {
                ui.label(RichText::new(format!("Error: {e}")).color(Color32::from_rgb(230, 80, 60)));
            }
            Some(Ok(p)) => {
                let m = self.tolerance();
                let ok = p.result.max_deviation <= m * (1.0 + 1e-9);
                ui.label(
                    RichText::new(format!(
                        "deviation bound {:.3e} {} m = {:.3e}",
                        p.result.max_deviation,
                        if ok { "≤" } else { ">" },
                        m
                    ))
                    .color(if ok {
                        colors::FAIRED
                    } else {
                        Color32::from_rgb(230, 80, 60)
                    }),
                )
                .on_hover_text(
                    "The core's verified upper bound on the distance from the original, everywhere along the \
                     curve (from the control polygon of the difference, refined where it comes near the \
                     tolerance); the measured closest-point deviation (Measures) is at most this",
                );
                if p.draft {
                    ui.weak(format!("draft while dragging (no E polish), {:.2} ms", p.fair_ms))
                        .on_hover_text("The full fair (with the E polish) runs when the drag ends");
                } else {
                    ui.weak(format!("re-fair {:.2} ms", p.fair_ms));
                }
                match &p.result.seam {
                    Seam::Faired if !p.corners.is_empty() => {
                        ui.weak("closed curve: faired across the seam, its corners kept")
                            .on_hover_text(
                                "The curve was re-seamed exactly (at a kink for the whole curve, in the untouched \
                                 rest for a region across the seam), faired stretch by stretch between its \
                                 corners and mapped back onto the original knots: as smooth at the old seam as \
                                 the original.",
                            );
                    }
                    Seam::Faired if self.ws.fairing.across_seam() => {
                        ui.weak("closed curve: region faired through the seam (as smooth there as the original)")
                            .on_hover_text(
                                "The region runs across the seam: the core fairs it on the curve re-seamed in the \
                             middle of the untouched rest and maps the result back onto the original knots. On \
                             the κ plot its target runs from the right edge on through the left one.",
                            );
                    }
                    Seam::Faired => {
                        ui.weak("closed curve: faired across the seam (as smooth there as the original)")
                            .on_hover_text(
                                "Two passes, the second on the curve re-seamed exactly opposite the seam, blended \
                                 and mapped back onto the original knots: C^(p-1) across the seam (C2 for a cubic)",
                            );
                    }
                    Seam::Held(why) if p.corners.iter().any(|c| c.u == p.result.curve.domain().0) => {
                        ui.weak("closed curve: its seam is a corner, kept (G1 on both sides)")
                            .on_hover_text(why.as_str());
                    }
                    Seam::Held(why) => {
                        ui.weak("closed curve: seam held (G2, unchanged there)")
                            .on_hover_text(why.as_str());
                    }
                    Seam::Open | Seam::Untouched => {}
                }
            }
            None => {}
        }
    }

    /// Target tools, falloff, automatic strength and the target reset.
    fn target_ui(&mut self, ui: &mut egui::Ui, opts: &mut FairOptions) {
        ui.strong("Target");
        ui.horizontal_wrapped(|ui| {
            for (t, name, tip) in [
                (
                    TargetTool::Drag,
                    "Drag",
                    "Drag target points on the κ plot (soft falloff)",
                ),
                (TargetTool::Pin, "Pin", "Click the κ plot to pin / unpin a target value"),
                (
                    TargetTool::Smooth,
                    "Smooth",
                    "Drag across the κ plot to smooth a stretch of the target",
                ),
                (
                    TargetTool::Flatten,
                    "Flatten",
                    "Drag across the κ plot to flatten a stretch (constant κ)",
                ),
            ] {
                ui.selectable_value(&mut self.ws.tool, t, name).on_hover_text(tip);
            }
        });
        ui.add(
            egui::Slider::new(&mut self.ws.falloff, 0.005..=0.5)
                .logarithmic(true)
                .text("Falloff"),
        )
        .on_hover_text("Radius of a target drag, as a fraction of the region length");
        let n = self.ws.preview().map(|p| p.target.len()).unwrap_or(100);
        let hand_edited = self.doc.settings.target.is_some();
        let mut strength = opts.strength.unwrap_or(default_strength(opts.method, n));
        let r = ui
            .add_enabled(
                !hand_edited,
                egui::Slider::new(&mut strength, 0..=(4 * n).max(10)).text("Strength"),
            )
            .on_hover_text("Automatic smoothing strength (passes); disabled while the target is hand-edited")
            .on_disabled_hover_text("The target is hand-edited: Reset to use automatic smoothing");
        if r.changed() {
            opts.strength = Some(strength);
        }
        if ui
            .button("Reset target")
            .on_hover_text("Forget hand edits and pins; back to the automatic target")
            .clicked()
        {
            self.push(Command::SetTarget {
                values: None,
                pinned: vec![],
            });
        }
    }

    /// The region's end conditions (a document edit) and easing of G2 curve ends.
    fn end_conditions_ui(&mut self, ui: &mut egui::Ui, opts: &mut FairOptions) {
        ui.strong("End conditions");
        // the document's (an undo step; a hand-edited target is resampled onto the new samples)
        let mut ends = self.ends();
        for (side, label) in [(0, "Start"), (1, "End")] {
            ui.horizontal(|ui| {
                ui.label(label);
                for (e, name, tip) in [
                    (EndCondition::G0, "G0", "position only"),
                    (EndCondition::G1, "G1", "position and tangent"),
                    (EndCondition::G2, "G2", "position, tangent and curvature"),
                ] {
                    ui.selectable_value(&mut ends[side], e, name)
                        .on_hover_text(format!("{label} of the region joins its neighbour with {name}: {tip}"));
                }
            });
        }
        if ends != self.ends() {
            self.push(Command::SetEnds(ends));
        }
        for (held, label) in self.join_holds().into_iter().zip(["Start", "End"]) {
            if let Some(h) = held {
                ui.weak(format!("{label}: a curve end at a join, kept {h:?} by default"))
                    .on_hover_text(
                        "This region end is an end of the curve where another curve joins it: by default it keeps \
                         the join's measured continuity, so the neighbour still meets it as before",
                    );
            }
        }
        // only a G2 region end at an end of an open curve is eased (the core ignores the rest)
        let (d0, d1) = self.ws.view.domain;
        let eps = 1e-12 * (d1 - d0);
        let easable = !self.ws.view.closed
            && self.region().is_some_and(|(u1, u2)| {
                (u1 <= d0 + eps && ends[0] == EndCondition::G2) || (u2 >= d1 - eps && ends[1] == EndCondition::G2)
            });
        ui.add_enabled(easable, egui::Checkbox::new(&mut opts.ease_ends, "Ease G2 curve ends"))
            .on_disabled_hover_text("Applies to a G2 region end at an end of an open curve; this region has none")
            .on_hover_text(
                "Where a G2 end is an end of the (open) curve, its own end curvature is kept. On noisy data it \
                 is often far off: eased, the target reaches it within the end knot span instead of climbing \
                 to it from far inside (fewer wiggles near noisy ends; where the end curvature is real it can \
                 add some: compare). Region ends inside the curve and closed curves are not affected.",
            );
    }

    /// Before / after comparison toggles.
    fn compare_ui(&mut self, ui: &mut egui::Ui) {
        ui.strong("Compare");
        ui.checkbox(&mut self.ws.compare.show_after, "Show result (Space)")
            .on_hover_text("Toggle between before and after (Space)");
        ui.checkbox(&mut self.ws.compare.overlay, "Overlay original")
            .on_hover_text("Draw the original dimmed under the result");
        ui.add(egui::Slider::new(&mut self.ws.compare.blend, 0.0..=1.0).text("Blend"))
            .on_hover_text("Blend the drawn curve between the original (0) and the faired result (1)");
        ui.checkbox(&mut self.ws.compare.trio, "Tight / medium / loose")
            .on_hover_text("Three side-by-side previews at m/3, m and 3m");
    }

    /// Target editing input on the κ plot; returns true if it took the drag.
    pub fn target_plot_input(&mut self, ui: &egui::Ui, resp: &egui::Response) -> bool {
        let Some(p) = self.ws.preview().cloned() else {
            return false;
        };
        let len = self.ws.view.sampled.length;
        let near = |app: &CurveCx<'_>, q: Pos2, need_y: bool| -> Option<usize> {
            let mut best = (usize::MAX, f32::INFINITY);
            for k in 0..p.target.len() {
                let x = app.ws.plot.x(app.ws.target_s(&p, k), len);
                let d = if need_y {
                    Pos2::new(x, app.ws.plot.y(p.target[k])).distance(q)
                } else {
                    (x - q.x).abs()
                };
                if d < best.1 {
                    best = (k, d);
                }
            }
            (best.1 < if need_y { 10.0 } else { 8.0 }).then_some(best.0)
        };
        if self.ws.tool == TargetTool::Pin {
            if resp.clicked()
                && let Some(q) = resp.interact_pointer_pos()
                && let Some(k) = near(&*self, q, false)
            {
                let mut pins = pinned_indices(&p.pinned);
                if let Some(i) = pins.iter().position(|&j| j == k) {
                    pins.remove(i);
                } else {
                    pins.push(k);
                }
                self.push(Command::SetTarget {
                    values: Some(p.target.clone()),
                    pinned: pins,
                });
                return true;
            }
            return false;
        }
        if resp.drag_started_by(egui::PointerButton::Primary)
            && let Some(q) = ui.input(|i| i.pointer.press_origin())
        {
            let k = near(&*self, q, self.ws.tool == TargetTool::Drag);
            self.ws.target_drag = k.map(|k0| TargetDrag {
                k0,
                k_start: self.ws.plot.k(q.y),
                start: p.target.clone(),
            });
        }
        let Some(d) = self.ws.target_drag.clone() else {
            return false;
        };
        if resp.dragged_by(egui::PointerButton::Primary)
            && let Some(q) = resp.interact_pointer_pos()
            && let Some(mut t) = self.ws.fairing.target()
        {
            for (k, &g) in d.start.iter().enumerate() {
                t.set(k, g);
            }
            match self.ws.tool {
                TargetTool::Drag => self.falloff_drag(&p, &d, q, &mut t),
                TargetTool::Smooth | TargetTool::Flatten => {
                    let s = self.ws.plot.s(q.x, len);
                    let mut k1 = 0;
                    let mut best = f64::INFINITY;
                    for k in 0..p.params.len() {
                        let e = (self.ws.target_s(&p, k) - s).abs();
                        if e < best {
                            best = e;
                            k1 = k;
                        }
                    }
                    let (a, b) = (d.k0.min(k1), d.k0.max(k1));
                    // stretch by stretch: smoothing or flattening across a corner would blend the
                    // curvature of its two sides (which the corner keeps apart)
                    for r in stretch_pieces(&p.breaks, d.start.len(), a, b) {
                        let (a, b) = (r.start, r.end - 1);
                        if self.ws.tool == TargetTool::Smooth {
                            let strength = default_strength(self.prefs.fair.method, p.target.len()).max(4);
                            t.smooth_range(a, b, self.prefs.fair.method, strength);
                        } else {
                            t.flatten_range(a, b);
                        }
                    }
                }
                TargetTool::Pin => {}
            }
            self.push(Command::SetTarget {
                values: Some(t.values().to_vec()),
                pinned: pinned_indices(t.pinned()),
            });
        }
        if resp.drag_stopped() {
            self.ws.target_drag = None;
        }
        true
    }

    /// A Drag-tool edit: move target sample `d.k0` with the pointer at `q`, its neighbours within
    /// the falloff radius by a quintic falloff (pins stay, a corner bounds the reach).
    fn falloff_drag(&self, p: &Preview, d: &TargetDrag, q: Pos2, t: &mut fairway::fair::Target) {
        let dk = self.ws.plot.k(q.y) - d.k_start;
        let s0 = self.ws.target_s(p, d.k0);
        let radius = (self.ws.falloff * self.region_s_length()).max(1e-12);
        // a corner bounds the falloff: the other stretch's target is its own
        let n = d.start.len();
        let own = stretch_pieces(&p.breaks, n, 0, n - 1)
            .find(|r| r.contains(&d.k0))
            .unwrap_or(0..n);
        for k in own {
            if p.pinned[k] {
                continue;
            }
            let r = self.s_distance(self.ws.target_s(p, k), s0) / radius;
            if r < 1.0 {
                t.set(k, d.start[k] + dk * fairway::fair::target::quintic(1.0 - r));
            }
        }
    }

    /// Draw target and faired curvature on the κ plot.
    pub fn draw_plot_fairing(&self, painter: &egui::Painter) {
        let Some(p) = self.ws.preview() else { return };
        let len = self.ws.view.sampled.length;
        let pl = &self.ws.plot;
        // faired κ over the region's samples
        let fs = &p.sampled;
        let reg = self.region().unwrap_or((0.0, 0.0));
        let wraps = region::wraps(reg);
        // the reach of a target drag (falloff radius) around the pointer (around the loop, through
        // the plot's edges, for a region across the seam)
        if self.ws.tool == TargetTool::Drag
            && let Some(hs) = self.ws.hover_s
        {
            let r = self.ws.falloff * self.region_s_length();
            let y = pl.rect.unwrap_or(Rect::NOTHING).y_range();
            let shifts: &[f64] = if wraps { &[-len, 0.0, len] } else { &[0.0] };
            // a corner bounds the reach (the drag stays in its stretch); drawn for a region that does
            // not run across the seam, where the stretches are intervals of the plot
            let (lo, hi) = if wraps {
                (0.0, len)
            } else {
                p.breaks
                    .iter()
                    .map(|&b| self.ws.target_s(p, b))
                    .fold((0.0f64, len), |(lo, hi), sb| {
                        if sb <= hs { (lo.max(sb), hi) } else { (lo, hi.min(sb)) }
                    })
            };
            for &sh in shifts {
                let (x1, x2) = (
                    pl.x((hs - r + sh).clamp(lo, hi), len),
                    pl.x((hs + r + sh).clamp(lo, hi), len),
                );
                if x2 > x1 {
                    painter.rect_filled(
                        Rect::from_x_y_ranges(x1..=x2, y),
                        0.0,
                        colors::TARGET.gamma_multiply(0.08),
                    );
                }
            }
        }
        // faired κ over the region (in two parts across the seam)
        for (u1, u2) in region::parts(reg, self.ws.view.domain) {
            let (i1, i2) = (fs.index_at_u(u1).floor() as usize, fs.index_at_u(u2).ceil() as usize);
            let pts: Vec<Pos2> = (i1..=i2.min(fs.len() - 1))
                .map(|i| Pos2::new(pl.x(self.ws.view.sampled.s_at_u(fs.u[i]), len), pl.y(fs.kappa[i])))
                .collect();
            painter.add(Shape::line(pts, Stroke::new(1.8, colors::FAIRED)));
        }
        let tpts: Vec<Pos2> = (0..p.target.len())
            .map(|k| Pos2::new(pl.x(self.ws.target_s(p, k), len), pl.y(p.target[k])))
            .collect();
        // one polyline per run of increasing parameters (the target of a region across the seam jumps
        // from the plot's right edge to its left one) and per stretch between corners
        let mut start = 0;
        for k in 1..=tpts.len() {
            if k == tpts.len() || p.params[k] < p.params[k - 1] || p.breaks.contains(&k) {
                painter.add(Shape::line(tpts[start..k].to_vec(), Stroke::new(1.8, colors::TARGET)));
                start = k;
            }
        }
        for (k, q) in tpts.iter().enumerate() {
            if p.pinned[k] {
                painter.rect_filled(Rect::from_center_size(*q, egui::vec2(6.0, 6.0)), 0.0, colors::TARGET);
            }
        }
    }

    /// Target comb envelope on the canvas (model units).
    pub fn target_envelope(&self, p: &Preview) -> Vec<DVec2> {
        let o = &self.ws.view.sampled;
        let mut tmp = crate::Sampled {
            p: Vec::with_capacity(p.params.len()),
            n: Vec::with_capacity(p.params.len()),
            ..Default::default()
        };
        for &u in &p.params {
            let i = o.index_at_u(u).round() as usize;
            tmp.p.push(o.p[i]);
            tmp.n.push(o.n[i]);
        }
        let mut out = vec![];
        self.comb_tips(&tmp, &p.target, &mut out);
        out
    }
}

/// The fairing panel's "Advanced" section: integrator, target method, E polish, fit method, polish method.
fn advanced_ui(ui: &mut egui::Ui, o: &mut FairOptions) {
    ui.horizontal(|ui| {
        ui.label("Integrator:");
        for (i, name, tip) in [
            (Integrator::Euler, "Euler", "Explicit Euler (the paper's first scheme)"),
            (
                Integrator::Rk2,
                "RK2",
                "Second-order Runge–Kutta (the paper's second scheme)",
            ),
            (Integrator::Arc, "Arc", "Exact circular-arc steps (default)"),
        ] {
            ui.selectable_value(&mut o.integrator, i, name).on_hover_text(tip);
        }
    });
    ui.horizontal(|ui| {
        ui.label("Target:");
        for (m, name, tip) in [
            (
                TargetMethod::Heat,
                "Heat",
                "Heat flow of the averaging, implicit: fast at any strength",
            ),
            (TargetMethod::Average, "Average", "Neighbour averaging (the paper's)"),
            (TargetMethod::Binomial, "Binomial", "(1,2,1)/4 kernel, damps zig-zag"),
            (TargetMethod::Fit, "Fit", "Smoothing-spline fit of the curvature"),
        ] {
            ui.selectable_value(&mut o.method, m, name).on_hover_text(tip);
        }
    });
    ui.add(egui::Slider::new(&mut o.polish_iterations, 0..=MAX_POLISH).text("E polish"))
        .on_hover_text(
            "Gauss–Newton iterations of the E polish after the band search (full fair; a draft \
             skips it): more lower the paper's E further inside the band at about 0.2 ms each for \
             100 control points; a lower E is not always fewer curvature extrema",
        );
    ui.horizontal(|ui| {
        ui.label("Method:");
        for (m, name, tip) in [
            (
                FitMode::Fairway,
                "Fairway",
                "Integration of the target, fit, polish (default)",
            ),
            (
                FitMode::Smoothing,
                "Smoothing spline",
                "The reference: knot-keeping penalized least squares, its weight the largest that holds \
                 the band (what a SciPy smoothing spline with a search on its factor gives)",
            ),
        ] {
            ui.selectable_value(&mut o.mode, m, name).on_hover_text(tip);
        }
    });
    ui.horizontal(|ui| {
        ui.label("Polish:");
        for (m, name, tip) in [
            (
                PolishMethod::Variation,
                "Variation",
                "Lowers the curvature variation ∫(dκ/ds)² over the whole region inside the band, \
                 following the target a little (default): never more curvature extrema than the \
                 reference smoothing spline or the original",
            ),
            (
                PolishMethod::LineSearch,
                "Line search",
                "Stops well short of the lowest E in the band: the previous default",
            ),
            (
                PolishMethod::InteriorPoint,
                "Interior point",
                "Follows the target as closely as the band allows, in a few iterations: for a target \
                 you shaped, pinned or typed in",
            ),
        ] {
            ui.selectable_value(&mut o.polish_method, m, name).on_hover_text(tip);
        }
    });
}

/// The parts of the target samples `a..=b` in each stretch between corners: `breaks` are the first
/// samples of the second, third, … stretch of a target of `n` samples (the preview's `breaks`).
/// One range `a..b + 1` without corners.
pub fn stretch_pieces(breaks: &[usize], n: usize, a: usize, b: usize) -> impl Iterator<Item = std::ops::Range<usize>> {
    let starts = std::iter::once(0).chain(breaks.iter().copied());
    let ends = breaks.iter().copied().chain(std::iter::once(n));
    starts
        .zip(ends)
        .map(move |(lo, hi)| lo.max(a)..hi.min(b + 1))
        .filter(|r| r.start < r.end)
}

#[cfg(test)]
mod tests {
    use super::stretch_pieces;

    #[test]
    fn stretch_pieces_split_a_range_at_the_corners() {
        let v = |breaks: &[usize], a, b| stretch_pieces(breaks, 10, a, b).collect::<Vec<_>>();
        assert_eq!(v(&[], 2, 7), vec![2..8]);
        assert_eq!(v(&[4], 2, 7), vec![2..4, 4..8]);
        assert_eq!(v(&[4], 4, 7), vec![4..8]);
        assert_eq!(v(&[4], 1, 3), vec![1..4]);
        assert_eq!(v(&[3, 6], 0, 9), vec![0..3, 3..6, 6..10]);
        assert_eq!(v(&[3, 6], 5, 5), vec![5..6]);
    }
}
