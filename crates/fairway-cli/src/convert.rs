//! `fairway convert IN OUT`: convert geometry between formats, chosen by
//! extension: JSON (`.json`), Fairway document (`.ron`, `.fairway`), IGES
//! (`.igs`, `.iges`), STEP (`.stp`, `.step`), point lists (`.csv`, `.txt`, `.xyz`, input only:
//! fitted by a B-spline), SVG (`.svg`, output only: curve, control polygon,
//! curvature comb).
//!
//! An IGES or STEP input with several objects converts the first one unless
//! `--index` picks another; skipped entities are listed on stderr. An IGES
//! or STEP output declares the unit of an IGES or STEP input (millimetres
//! otherwise): coordinates are copied, never scaled.

use std::path::{Path, PathBuf};

use anyhow::{Result, anyhow, bail};
use fairway::Geometry;
use fairway::io::{self, Document, points, svg};

/// Arguments of `fairway convert`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Input file (.json, .ron, .fairway, .igs, .iges, .stp, .step, .csv, .txt, .xyz).
    pub input: PathBuf,
    /// Output file (.json, .ron, .fairway, .igs, .iges, .stp, .step, .svg).
    pub output: PathBuf,
    /// Point input: number of control points of the fitted curve (default: half the points, 4 to 40).
    #[arg(long)]
    pub control_points: Option<usize>,
    /// Point input: degree of the fitted curve.
    #[arg(long, default_value_t = 3)]
    pub degree: usize,
    /// Point input: parametrisation, `chord` or `centripetal`.
    #[arg(long, default_value = "chord")]
    pub param: String,
    /// IGES or STEP input: which object to convert (0 = the first, the default).
    #[arg(long)]
    pub index: Option<usize>,
    /// SVG output: also draw the tolerance band of this half-width (model units).
    #[arg(long)]
    pub band: Option<f64>,
}

fn ext(p: &Path) -> String {
    p.extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default()
}

fn with_path(path: &Path, e: fairway::Error) -> anyhow::Error {
    match e {
        e @ fairway::Error::Io { .. } => anyhow!("{e}"),
        e => anyhow!("{}: {e}", path.display()),
    }
}

/// Read the input: a document, and the unit of an IGES or STEP file.
pub fn read_input(a: &Args) -> Result<crate::common::Input> {
    let path = &a.input;
    match ext(path).as_str() {
        "csv" | "txt" | "xyz" => {
            let text = io::read_text(path).map_err(|e| with_path(path, e))?;
            let set = points::parse(&text).map_err(|e| with_path(path, e))?;
            let opts = points::FitOptions {
                control_points: a.control_points,
                degree: a.degree,
                param: a.param.parse().map_err(|e| anyhow!("--param: {e}"))?,
            };
            if let Some(k) = a.index {
                bail!(
                    "--index {k}: {} is a point list; --index picks an object of an IGES or STEP file",
                    path.display()
                );
            }
            let c = points::fit_points(&set, &opts).map_err(|e| with_path(path, e))?;
            Ok(crate::common::Input {
                doc: Document::new(c.into()),
                unit: None,
                object: None,
                trim: None,
            })
        }
        _ => Ok(crate::common::load_input(path, a.index)?),
    }
}

/// Run the conversion.
pub fn run(a: &Args) -> Result<()> {
    if ext(&a.output) == "svg" && ext(&a.input) != "svg" {
        // checked before reading so a bad --band fails fast
        if let Some(m) = a.band
            && !(m.is_finite() && m > 0.0)
        {
            bail!("--band {m}: must be a positive number");
        }
    }
    // the output must be another file than the input (links resolved), or the input would be lost
    crate::common::refuse_same_files(&a.input, &a.output, None)?;
    let input = read_input(a)?;
    let (doc, trim) = (input.doc, input.trim);
    match ext(&a.output).as_str() {
        "svg" => {
            let Geometry::Curve(c) = &doc.geometry else {
                bail!(
                    "{}: SVG export draws curves; the input is a surface",
                    a.output.display()
                );
            };
            let opts = svg::SvgOptions {
                band: a.band.or(doc.settings.tolerance),
                ..Default::default()
            };
            let text = svg::try_curve_svg(c, None, &opts).map_err(|e| with_path(&a.output, e))?;
            io::write_atomic(&a.output, text.as_bytes()).map_err(|e| with_path(&a.output, e))
        }
        // an IGES or STEP output declares the input's unit (the coordinates are not scaled); a trimmed face
        // keeps its bounds where the output can hold them (IGES, STEP, a .ron document)
        _ => crate::common::save_document(&a.output, doc, trim, input.unit).map_err(|e| with_path(&a.output, e)),
    }
}
