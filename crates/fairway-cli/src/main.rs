//! `fairway`: the command-line tool of Fairway.
//!
//! Each subcommand lives in its own module (`eval.rs`, `info.rs`, ...) with
//! an `Args` struct (clap derive) and a `run(&Args) -> anyhow::Result<()>`;
//! this file only parses the command line and dispatches.
//!
//! Exit codes: 0 success, 1 runtime error (bad file, impossible request),
//! 2 usage error (clap's default: unknown option, bad value).

mod common;
mod convert;
mod eval;
mod fair;
mod fair_scene;
mod info;
mod joins;
mod measure;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Fair B-spline curves and surfaces; evaluate and inspect geometry files.
#[derive(Parser, Debug)]
#[command(name = "fairway", version, about, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Evaluate a curve or surface at uniform parameters (points, derivatives, curvature).
    Eval(eval::Args),
    /// Summarize a curve or surface: kind, degree, control points, spans, length, curvature range, inflections.
    Info(info::Args),
    /// Fair a curve within a tolerance band (fast local method, or the iterative baseline).
    Fair(fair::Args),
    /// Measure a faired curve against its original (deviation, extrema, inflections, energies).
    Measure(measure::Args),
    /// Convert between formats by extension: JSON, RON, IGES, STEP, point lists (input), SVG (output).
    Convert(convert::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse(); // usage errors exit with code 2
    let result = match &cli.command {
        Command::Eval(a) => eval::run(a),
        Command::Info(a) => info::run(a),
        Command::Fair(a) => fair::run(a),
        Command::Measure(a) => measure::run(a),
        Command::Convert(a) => convert::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("fairway: error: {e:#}");
            ExitCode::from(1)
        }
    }
}
