//! `fairway measure ORIGINAL FAIRED [--json]`: deviation, curvature extrema,
//! inflections and fairness energies of FAIRED against ORIGINAL, with the
//! definitions and key names of the reference (see `fairway::measure`).

use std::path::PathBuf;

use anyhow::{Result, bail};
use fairway::measure::measure;
use fairway::{BSplineCurve, Geometry};

use crate::common::{load_geometry, print_json};

/// Arguments of `fairway measure`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The original curve.
    pub original: PathBuf,
    /// The faired curve.
    pub faired: PathBuf,
    /// Print JSON (the reference's keys) instead of text.
    #[arg(long)]
    pub json: bool,
}

fn curve(path: &PathBuf) -> Result<BSplineCurve> {
    match load_geometry(path)? {
        Geometry::Curve(c) => Ok(c),
        g => bail!(
            "{}: measure works on curves; this file holds a {}",
            path.display(),
            g.kind()
        ),
    }
}

/// Run `fairway measure`.
pub fn run(a: &Args) -> Result<()> {
    let (o, f) = (curve(&a.original)?, curve(&a.faired)?);
    if o.dim() != f.dim() {
        bail!("the curves have different dimensions ({}D and {}D)", o.dim(), f.dim());
    }
    let m = measure(&o, &f);
    if a.json {
        return print_json(&m);
    }
    let v = serde_json::to_value(&m)?;
    if let Some(obj) = v.as_object() {
        for (k, x) in obj {
            if k != "params" {
                println!("{k:>20}  {x}");
            }
        }
    }
    Ok(())
}
