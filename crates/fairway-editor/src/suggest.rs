//! "Suggest regions": asks the core ([`fairway::suggest`]) for the wiggly
//! stretches of the curve, lists them ranked, selects one with a click, and
//! outlines them on the κ plot.

use eframe::egui;
use egui::{Align2, Color32, FontId, Pos2, Rect, Stroke};
use fairway::suggest::{SuggestOptions, Suggestion, suggest_regions};

use crate::Command;
use crate::canvas::colors;
use crate::curve_ws::CurveCx;

/// Suggestions for one revision of the curve.
#[derive(Debug, Clone, Default)]
pub struct Suggestions {
    /// The ranked stretches (or the core's error), for [`Suggestions::rev`].
    pub list: Option<Result<Vec<Suggestion>, String>>,
    /// Curve revision the list belongs to.
    pub rev: u64,
}

impl crate::curve_ws::CurveWorkspace {
    /// The current suggestions, if they belong to the current curve.
    pub fn suggestions(&self) -> Option<&[Suggestion]> {
        match &self.suggest.list {
            Some(Ok(v)) if self.suggest.rev == self.curve_rev => Some(v),
            _ => None,
        }
    }
}

impl CurveCx<'_> {
    /// Compute the suggestions for the current curve now.
    pub fn suggest_now(&mut self) {
        let r = suggest_regions(self.curve(), &SuggestOptions::default()).map_err(|e| e.to_string());
        *self.status = match &r {
            Ok(v) if v.is_empty() => "No wiggly stretch found".into(),
            Ok(v) => format!(
                "{} wiggly stretch(es) found, best first: click one to select it",
                v.len()
            ),
            Err(e) => format!("Suggest regions failed: {e}"),
        };
        self.ws.suggest = Suggestions {
            list: Some(r),
            rev: self.ws.curve_rev,
        };
    }

    /// The "Suggest regions" button and the ranked list.
    pub fn suggest_ui(&mut self, ui: &mut egui::Ui) {
        if ui
            .button("Suggest regions")
            .on_hover_text(
                "Find the stretches where the curvature is wiggly (many curvature extrema, far from a smoothed \
                 target), ranked by ∫(κ − g)² ds; click one to select it",
            )
            .clicked()
        {
            self.suggest_now();
        }
        if self.ws.suggest.rev != self.ws.curve_rev {
            return;
        }
        match self.ws.suggest.list.clone() {
            None => {}
            Some(Err(e)) => {
                ui.colored_label(Color32::from_rgb(230, 80, 60), e);
            }
            Some(Ok(v)) if v.is_empty() => {
                ui.weak("No wiggly stretch: the curvature has no cluster of extrema.");
            }
            Some(Ok(v)) => {
                for (i, s) in v.iter().enumerate() {
                    let selected = self.region() == Some((s.u1, s.u2));
                    let text = format!("#{} s {:.3}–{:.3} · {} extrema", i + 1, s.s1, s.s2, s.extrema);
                    if ui
                        .selectable_label(selected, text)
                        .on_hover_text(format!(
                            "u in [{:.4}, {:.4}]; RMS of κ − g: {:.3e}; ∫(κ − g)² ds = {:.3e}. Click to select.",
                            s.u1, s.u2, s.rms, s.score
                        ))
                        .clicked()
                    {
                        self.push(Command::SetRegion(Some((s.u1, s.u2))));
                    }
                }
            }
        }
    }

    /// Outline the suggestions on the κ plot (numbered, best = 1).
    pub fn draw_plot_suggestions(&self, painter: &egui::Painter, rect: Rect) {
        let Some(list) = self.ws.suggestions() else { return };
        let len = self.ws.view.sampled.length;
        let col = colors::REGION.gamma_multiply(0.7);
        for (i, s) in list.iter().enumerate() {
            let (x1, x2) = (self.ws.plot.x(s.s1, len), self.ws.plot.x(s.s2, len));
            let y = rect.top() + 3.0;
            painter.line_segment([Pos2::new(x1, y), Pos2::new(x2, y)], Stroke::new(3.0, col));
            for x in [x1, x2] {
                painter.line_segment([Pos2::new(x, y), Pos2::new(x, y + 8.0)], Stroke::new(1.0, col));
            }
            painter.text(
                Pos2::new(0.5 * (x1 + x2), y + 2.0),
                Align2::CENTER_TOP,
                format!("#{}", i + 1),
                FontId::proportional(11.0),
                col,
            );
        }
    }
}
