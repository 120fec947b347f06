//! `fairway measure ORIGINAL FAIRED [--target T] [--json]`: deviation,
//! curvature extrema, inflections and fairness energies of FAIRED against
//! ORIGINAL, with the definitions and key names of the reference (see
//! `fairway::measure`); for two surfaces the surface measures
//! (`fairway::measure_surface`).
//!
//! `--target T` adds `E_paper_target`: the paper's E of FAIRED against a
//! given target curvature (a JSON array of numbers, uniform in normalized
//! arc length, or a `.ron` document whose settings hold a target).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use fairway::Geometry;
use fairway::measure::{measure, paper_energy};
use fairway::measure_surface::surface_measures;
use serde_json::Value;

use crate::common::{load_geometry, print_json, refuse_non_finite};

/// Arguments of `fairway measure`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The original curve or surface.
    pub original: PathBuf,
    /// The faired curve or surface.
    pub faired: PathBuf,
    /// Target curvature for `E_paper_target` (curves): a JSON array of κ values uniform in
    /// normalized arc length, or a .ron document with a target.
    #[arg(long)]
    pub target: Option<PathBuf>,
    /// Print JSON (the reference's keys) instead of text.
    #[arg(long)]
    pub json: bool,
}

fn load_target(path: &Path) -> Result<Vec<f64>> {
    let is_ron = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("ron"));
    if is_ron {
        let doc = fairway::io::load(path).map_err(|e| anyhow!("{}: {e}", path.display()))?;
        return doc
            .settings
            .target
            .ok_or_else(|| anyhow!("{}: the document holds no target curvature", path.display()));
    }
    let text = fairway::io::read_text(path).map_err(|e| anyhow!("{e}"))?;
    let v: Vec<f64> = serde_json::from_str(&text)
        .with_context(|| format!("{}: expected a JSON array of curvature values", path.display()))?;
    Ok(v)
}

/// Run `fairway measure`.
pub fn run(a: &Args) -> Result<()> {
    let value = match (load_geometry(&a.original)?, load_geometry(&a.faired)?) {
        (Geometry::Curve(o), Geometry::Curve(f)) => {
            if o.dim() != f.dim() {
                bail!("the curves have different dimensions ({}D and {}D)", o.dim(), f.dim());
            }
            let m = measure(&o, &f);
            refuse_non_finite("the measures", &m)?;
            let mut v = serde_json::to_value(m)?;
            if let Some(path) = &a.target {
                let g = load_target(path)?;
                let e = paper_energy(&f, &g).ok_or_else(|| {
                    anyhow!(
                        "{}: a target needs at least 2 finite values (got {})",
                        path.display(),
                        g.len()
                    )
                })?;
                refuse_non_finite("E_paper_target", &e)?;
                v["E_paper_target"] = Value::from(e);
            }
            v
        }
        (Geometry::Surface(o), Geometry::Surface(f)) => {
            if a.target.is_some() {
                bail!("--target applies to curves only");
            }
            let m = surface_measures(&o, &f);
            refuse_non_finite("the measures", &m)?;
            serde_json::to_value(m)?
        }
        (o, f) => bail!(
            "cannot measure a {} against a {} ({} and {})",
            f.kind(),
            o.kind(),
            a.faired.display(),
            a.original.display()
        ),
    };
    if a.json {
        return print_json(&value);
    }
    if let Some(obj) = value.as_object() {
        for (k, x) in obj {
            if k != "params" {
                println!("{k:>20}  {x}");
            }
        }
    }
    Ok(())
}
