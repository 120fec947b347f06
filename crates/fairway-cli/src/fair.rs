//! `fairway fair IN --tolerance m [options] -o OUT [--report REPORT.json]`:
//! fair a curve with the fast local method (or the iterative baseline) and
//! write the result; the optional report holds the measures of the result
//! against the input and the solve time measured in-process.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use fairway::Geometry;
use fairway::fair::{
    EndCondition, FairingOptions, FairingSetup, FitMode, Integrator, IterativeOptions, TargetMethod, fair_iterative,
};
use fairway::io::Document;
use fairway::measure::{Measures, measure};
use serde::Serialize;

use crate::common::load_geometry;

/// Arguments of `fairway fair`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Input curve (.json geometry or .ron/.fairway document).
    pub input: PathBuf,
    /// Tolerance m: max deviation from the input (same units as the points).
    #[arg(long)]
    pub tolerance: f64,
    /// Region to fair, as `u1,u2` in the curve's parameter (default: the whole curve).
    #[arg(long, value_parser = parse_region, allow_hyphen_values = true)]
    pub region: Option<(f64, f64)>,
    /// Continuity at the region ends: g0, g1 or g2.
    #[arg(long, default_value = "g2")]
    pub ends: EndCondition,
    /// Target curvature: average (paper), binomial or fit (paper eq. 3).
    #[arg(long, default_value = "average")]
    pub target: TargetMethod,
    /// Smoothing strength of the target (passes; default from the number of samples).
    #[arg(long)]
    pub strength: Option<usize>,
    /// fast (default), iterative (paper 2.2 baseline) or paper (fast method as published: soft band).
    #[arg(long, default_value = "fast")]
    pub method: String,
    /// Integration scheme: euler, rk2 or arc.
    #[arg(long, default_value = "arc")]
    pub integrator: Integrator,
    /// Number of arc-length samples (default: 10 per knot span).
    #[arg(long)]
    pub samples: Option<usize>,
    /// Output file (.json or .ron).
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Write a JSON report (measures, solve time) here.
    #[arg(long)]
    pub report: Option<PathBuf>,
}

fn parse_region(s: &str) -> std::result::Result<(f64, f64), String> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 2 {
        return Err(format!("expected u1,u2, got {s:?}"));
    }
    let a = parts[0]
        .trim()
        .parse::<f64>()
        .map_err(|e| format!("{:?}: {e}", parts[0]))?;
    let b = parts[1]
        .trim()
        .parse::<f64>()
        .map_err(|e| format!("{:?}: {e}", parts[1]))?;
    Ok((a, b))
}

/// The report written by `--report`.
#[derive(Serialize, Debug)]
pub struct Report {
    /// fast, paper or iterative.
    pub method: String,
    /// The requested tolerance.
    pub tolerance: f64,
    /// Setup time (sampling, matrices), ms.
    pub setup_ms: f64,
    /// Solve time (integration, fit, band control or simplex sweeps), ms.
    pub solve_ms: f64,
    /// Upper bound of the deviation verified by the solver.
    pub max_deviation_bound: f64,
    /// Fairness weight μ chosen.
    pub mu: f64,
    /// Update scale α (1 unless the band forced a partial step).
    pub alpha: f64,
    /// Paper's E at the samples against the setup's target, before.
    pub energy_before: f64,
    /// The same after.
    pub energy: f64,
    /// Free control points [first, last) of the working curve.
    pub free_points: [usize; 2],
    /// Measures of the result against the input.
    pub measures: Measures,
}

/// Run `fairway fair`.
pub fn run(a: &Args) -> Result<()> {
    let g = load_geometry(&a.input)?;
    let Geometry::Curve(curve) = g else {
        bail!(
            "{}: fair works on curves; this file holds a {}",
            a.input.display(),
            g.kind()
        );
    };
    let mode = match a.method.as_str() {
        "fast" | "iterative" => FitMode::Fairway,
        "paper" => FitMode::Paper,
        m => return Err(anyhow!("unknown method {m:?}: expected fast, iterative or paper")),
    };
    let opts = FairingOptions {
        region: a.region,
        tolerance: a.tolerance,
        ends: a.ends,
        target: a.target,
        strength: a.strength,
        integrator: a.integrator,
        samples: a.samples,
        mode,
    };
    let t0 = Instant::now();
    let mut setup = FairingSetup::new(&curve, opts).context("fairing setup")?;
    let setup_ms = t0.elapsed().as_secs_f64() * 1e3;
    let t1 = Instant::now();
    let result = if a.method == "iterative" {
        fair_iterative(&setup, IterativeOptions::default())
    } else {
        setup.fair()
    }
    .context("fairing")?;
    let solve_ms = t1.elapsed().as_secs_f64() * 1e3;
    fairway::io::save(&a.output, &Document::new(Geometry::Curve(result.curve.clone())))?;
    if let Some(path) = &a.report {
        let report = Report {
            method: a.method.clone(),
            tolerance: a.tolerance,
            setup_ms,
            solve_ms,
            max_deviation_bound: result.max_deviation,
            mu: result.mu,
            alpha: result.alpha,
            energy_before: setup.energy(setup.working_curve()),
            energy: result.energy,
            free_points: [setup.free_points().start, setup.free_points().end],
            measures: measure(&curve, &result.curve),
        };
        let text = serde_json::to_string_pretty(&report)?;
        fairway::io::write_atomic(path, text.as_bytes())?;
    }
    Ok(())
}
