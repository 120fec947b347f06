//! Helpers shared by the subcommands: loading files with clear messages,
//! uniform parameters, JSON output.

use std::io::Write;
use std::path::Path;

use anyhow::{Result, anyhow};
use fairway::{DVec3, Geometry};

/// Load the geometry of a JSON or RON file. Errors name the file and the problem.
pub fn load_geometry(path: &Path) -> Result<Geometry> {
    match fairway::io::load_geometry(path) {
        Ok(g) => Ok(g),
        // I/O errors already start with the path
        Err(e @ fairway::Error::Io { .. }) => Err(anyhow!("{e}")),
        Err(e) => Err(anyhow!("{}: {e}", path.display())),
    }
}

/// `n ≥ 2` uniform parameters over `[a, b]`, first and last included:
/// `a + i·(b − a)/(n − 1)`, the last set to `b` exactly (the same values as
/// NumPy's `linspace`, so outputs compare bit for bit with references made
/// with it).
pub fn uniform_params(a: f64, b: f64, n: usize) -> Vec<f64> {
    let n = n.max(2);
    let step = (b - a) / (n - 1) as f64;
    let mut v: Vec<f64> = (0..n).map(|i| i as f64 * step + a).collect();
    v[n - 1] = b;
    v
}

/// A point or vector as `[x, y]` (2D) or `[x, y, z]`.
pub fn coords(p: DVec3, dim: usize) -> Vec<f64> {
    p.to_array()[..dim].to_vec()
}

/// Write a serializable value as one line of JSON to stdout (exact floats;
/// NaN and infinities become `null`).
pub fn print_json<T: serde::Serialize>(value: &T) -> Result<()> {
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    serde_json::to_writer(&mut out, value)?;
    writeln!(out)?;
    out.flush()?;
    Ok(())
}
