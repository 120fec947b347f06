//! Settings kept between sessions (eframe storage), not in documents.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::fairing::{self, FairOptions};

/// How comb tooth length grows with |κ|.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum CombScaling {
    /// Proportional to |κ|.
    Linear,
    /// Proportional to √|κ| (tames large peaks).
    Sqrt,
    /// Proportional to ln(1 + |κ|/κ̄).
    Log,
}

/// Settings kept between sessions (eframe storage), not in documents.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(default)]
pub struct Prefs {
    /// Comb length multiplier.
    pub comb_scale: f64,
    /// Comb scaling law.
    pub comb_scaling: CombScaling,
    /// Draw the curvature comb.
    pub show_comb: bool,
    /// Draw the control polygon.
    pub show_polygon: bool,
    /// Draw inflection and curvature-extremum markers.
    pub show_markers: bool,
    /// Recently opened files, newest first.
    pub recent: Vec<PathBuf>,
    /// Fairing options (edited through [`crate::Command::SetFairOptions`], one undo step each).
    pub fair: FairOptions,
}

impl Default for Prefs {
    fn default() -> Self {
        Self {
            comb_scale: 1.0,
            comb_scaling: CombScaling::Linear,
            show_comb: true,
            show_polygon: true,
            show_markers: true,
            recent: vec![],
            fair: FairOptions::default(),
        }
    }
}

impl Prefs {
    /// Out-of-range values (a hand-edited store) clamped.
    pub fn sanitized(mut self) -> Self {
        self.comb_scale = if self.comb_scale.is_finite() {
            self.comb_scale.clamp(0.02, 50.0)
        } else {
            Prefs::default().comb_scale
        };
        // the slider's range is 0..=4n; a huge stored strength would stall the Average method
        self.fair.strength = self.fair.strength.map(|n| n.min(100_000));
        self.fair.polish_iterations = self.fair.polish_iterations.min(fairing::MAX_POLISH);
        self
    }
}
