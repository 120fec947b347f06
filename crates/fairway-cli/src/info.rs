//! `fairway info FILE [--json]`: what a geometry file holds.
//!
//! Curves: kind, dimension, degree, control points, rational, knot spans,
//! domain, arc length (adaptive Gauss–Legendre, relative accuracy 1e-12),
//! curvature range and inflections (2D). Surfaces: kind, degrees, control
//! net, spans, domain and the ranges of the principal, mean and Gaussian
//! curvatures.
//!
//! Curvature ranges are sampled: [`SAMPLES_PER_SPAN`] uniform parameters in
//! every knot span (per direction for surfaces), breakpoints included;
//! undefined values (cusps, singular points) are skipped.

use std::path::PathBuf;

use anyhow::Result;
use fairway::{BSplineCurve, BSplineSurface, Geometry};
use serde::Serialize;

use crate::common::{Input, load_input, print_json, refuse_non_finite};

/// Samples per knot span for the curvature ranges.
pub const SAMPLES_PER_SPAN: usize = 32;

/// Arguments of `fairway info`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Geometry file (.json geometry, .ron/.fairway document, .igs/.iges, .stp/.step).
    pub file: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// IGES or STEP file: which object to summarize (0 = the first, the default).
    #[arg(long)]
    pub index: Option<usize>,
}

/// What an IGES or STEP file says about the object summarized.
#[derive(Serialize, Debug, Default)]
pub struct FileInfo {
    /// The file's length unit (`mm`, `in`, ...); `null` if it declares none Fairway knows. Lengths and
    /// curvatures are in this unit (curvatures per unit).
    pub unit: Option<&'static str>,
    /// The object summarized (0-based, as `--index`).
    pub index: usize,
    /// How many curves and surfaces the file holds.
    pub objects: usize,
}

/// Summary of a curve.
#[derive(Serialize, Debug)]
pub struct CurveInfo {
    /// "curve".
    pub kind: &'static str,
    /// 2 or 3.
    pub dimension: usize,
    /// Degree.
    pub degree: usize,
    /// Number of control points.
    pub control_points: usize,
    /// Has (unequal or equal) weights.
    pub rational: bool,
    /// Non-empty knot spans.
    pub spans: usize,
    /// Parameter domain.
    pub domain: [f64; 2],
    /// Arc length.
    pub length: f64,
    /// Smallest sampled curvature (signed in 2D); `null` if undefined everywhere (a curve that is a point).
    pub curvature_min: Option<f64>,
    /// Largest sampled curvature; `null` if undefined everywhere.
    pub curvature_max: Option<f64>,
    /// Number of inflections (2D; 0 in 3D).
    pub n_inflections: usize,
    /// Parameters of the inflections (2D).
    pub inflections: Vec<f64>,
    /// IGES / STEP input: its unit and which object this is (absent for other formats).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<FileInfo>,
    /// A file with several objects: all of them and their joins (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub network: Option<crate::joins::NetworkInfo>,
}

/// Summary of a surface.
#[derive(Serialize, Debug)]
pub struct SurfaceInfo {
    /// "surface".
    pub kind: &'static str,
    /// Always 3.
    pub dimension: usize,
    /// Degree in u.
    pub degree_u: usize,
    /// Degree in v.
    pub degree_v: usize,
    /// Control points in u.
    pub control_points_u: usize,
    /// Control points in v.
    pub control_points_v: usize,
    /// Has weights.
    pub rational: bool,
    /// Knot spans in u.
    pub spans_u: usize,
    /// Knot spans in v.
    pub spans_v: usize,
    /// Domain in u.
    pub domain_u: [f64; 2],
    /// Domain in v.
    pub domain_v: [f64; 2],
    /// Range of k_max (`null` if undefined everywhere, as the ranges below).
    pub k_max_range: Option<[f64; 2]>,
    /// Range of k_min.
    pub k_min_range: Option<[f64; 2]>,
    /// Range of the mean curvature.
    pub mean_range: Option<[f64; 2]>,
    /// Range of the Gaussian curvature.
    pub gauss_range: Option<[f64; 2]>,
    /// IGES / STEP input: its unit and which object this is (absent for other formats).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<FileInfo>,
    /// A file with several objects: all of them and their joins (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub network: Option<crate::joins::NetworkInfo>,
    /// A trimmed face (STEP, IGES): its bounds (absent for an untrimmed surface).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trim: Option<TrimInfo>,
}

/// The bounds of a trimmed face.
#[derive(Debug, Clone, Serialize)]
pub struct TrimInfo {
    /// Outer loops (1 for a face).
    pub outer_loops: usize,
    /// Holes.
    pub inner_loops: usize,
    /// Edges of all loops.
    pub edges: usize,
}

/// Call `f` at `m` uniform parameters in each span, then at the domain end (without storing them: a curve of
/// a million spans takes no memory for its samples).
fn for_span_samples(breakpoints: &[f64], m: usize, mut f: impl FnMut(f64)) {
    for w in breakpoints.windows(2) {
        for k in 0..m {
            f(w[0] + (w[1] - w[0]) * k as f64 / m as f64);
        }
    }
    f(*breakpoints.last().unwrap());
}

/// Parameters: `m` uniform samples in each span, plus the domain end.
fn span_samples(breakpoints: &[f64], m: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity((breakpoints.len() - 1) * m + 1);
    for w in breakpoints.windows(2) {
        for k in 0..m {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / m as f64);
        }
    }
    out.push(*breakpoints.last().unwrap());
    out
}

#[derive(Clone, Copy)]
struct Range([f64; 2]);

impl Range {
    const EMPTY: Self = Range([f64::INFINITY, f64::NEG_INFINITY]);
    fn add(&mut self, x: f64) {
        if x.is_finite() {
            self.0[0] = self.0[0].min(x);
            self.0[1] = self.0[1].max(x);
        }
    }
    /// The range, `None` if no sample was finite (never NaN).
    fn get(self) -> Option<[f64; 2]> {
        (self.0[0] <= self.0[1]).then_some(self.0)
    }
}

/// Summarize a curve.
pub fn curve_info(c: &BSplineCurve) -> CurveInfo {
    let (a, b) = c.domain();
    let mut k = Range::EMPTY;
    for_span_samples(&c.knots().breakpoints(), SAMPLES_PER_SPAN, |u| k.add(c.curvature(u)));
    let (kmin, kmax) = k.get().map_or((None, None), |[a, b]| (Some(a), Some(b)));
    let inflections = c.inflections(SAMPLES_PER_SPAN);
    CurveInfo {
        kind: "curve",
        dimension: c.dim(),
        degree: c.degree(),
        control_points: c.n_points(),
        rational: c.is_rational(),
        spans: c.knots().n_spans(),
        domain: [a, b],
        length: c.length(1e-12),
        curvature_min: kmin,
        curvature_max: kmax,
        n_inflections: inflections.len(),
        inflections,
        file: None,
        network: None,
    }
}

/// Summarize a surface.
pub fn surface_info(s: &BSplineSurface) -> SurfaceInfo {
    let ((u0, u1), (v0, v1)) = s.domain();
    let us = span_samples(&s.knots_u().breakpoints(), SAMPLES_PER_SPAN / 4);
    let vs = span_samples(&s.knots_v().breakpoints(), SAMPLES_PER_SPAN / 4);
    let (mut kx, mut kn, mut h, mut g) = (Range::EMPTY, Range::EMPTY, Range::EMPTY, Range::EMPTY);
    for &u in &us {
        for &v in &vs {
            let k = s.curvature(u, v);
            kx.add(k.k_max);
            kn.add(k.k_min);
            h.add(k.mean);
            g.add(k.gauss);
        }
    }
    SurfaceInfo {
        kind: "surface",
        dimension: 3,
        degree_u: s.degree_u(),
        degree_v: s.degree_v(),
        control_points_u: s.nu(),
        control_points_v: s.nv(),
        rational: s.is_rational(),
        spans_u: s.knots_u().n_spans(),
        spans_v: s.knots_v().n_spans(),
        domain_u: [u0, u1],
        domain_v: [v0, v1],
        k_max_range: kx.get(),
        k_min_range: kn.get(),
        mean_range: h.get(),
        gauss_range: g.get(),
        file: None,
        network: None,
        trim: None,
    }
}

/// The objects and joins of a file with several objects (`None` for one object).
fn network(path: &std::path::Path, input: &Input) -> Result<Option<crate::joins::NetworkInfo>> {
    if input.object.is_none_or(|(_, n)| n < 2) {
        return Ok(None);
    }
    let Some((scene, _)) = crate::common::load_scene_input(path)? else {
        return Ok(None);
    };
    let joins = fairway::network::find_joins(&scene.geometries());
    Ok(Some(crate::joins::network_info(&scene, &joins)))
}

/// Run `fairway info`.
pub fn run(args: &Args) -> Result<()> {
    let name = args.file.display();
    let input = load_input(&args.file, args.index)?;
    let file = file_info(&input);
    let network = network(&args.file, &input)?;
    match input.doc.geometry {
        Geometry::Curve(c) => {
            let mut i = curve_info(&c);
            i.file = file;
            i.network = network;
            refuse_non_finite("the summary", &i)?;
            if args.json {
                return print_json(&i);
            }
            println!("{name}: {}D curve", i.dimension);
            print_file_info(i.file.as_ref());
            println!("  degree          {}", i.degree);
            println!(
                "  control points  {}{}",
                i.control_points,
                if i.rational { " (rational)" } else { "" }
            );
            println!("  knot spans      {}", i.spans);
            println!("  domain          [{}, {}]", i.domain[0], i.domain[1]);
            println!("  length          {:.12}", i.length);
            match (i.curvature_min, i.curvature_max) {
                (Some(a), Some(b)) => println!("  curvature       {a:.6e} .. {b:.6e}"),
                _ => println!("  curvature       undefined (the curve is a point)"),
            }
            if i.dimension == 2 {
                println!("  inflections     {}", inflection_list(&i.inflections));
            }
            if let Some(n) = &i.network {
                crate::joins::print_network(n);
            }
        }
        Geometry::Surface(s) => {
            let mut i = surface_info(&s);
            i.file = file;
            i.network = network;
            i.trim = input.trim.as_ref().map(|t| TrimInfo {
                outer_loops: t.outer_loops(),
                inner_loops: t.inner_loops(),
                edges: t.loops.iter().map(|l| l.edges.len()).sum(),
            });
            refuse_non_finite("the summary", &i)?;
            if args.json {
                return print_json(&i);
            }
            println!("{name}: surface");
            print_file_info(i.file.as_ref());
            println!("  degrees         {} × {}", i.degree_u, i.degree_v);
            println!(
                "  control points  {} × {}{}",
                i.control_points_u,
                i.control_points_v,
                if i.rational { " (rational)" } else { "" }
            );
            println!("  knot spans      {} × {}", i.spans_u, i.spans_v);
            println!(
                "  domain          [{}, {}] × [{}, {}]",
                i.domain_u[0], i.domain_u[1], i.domain_v[0], i.domain_v[1]
            );
            let r = |x: Option<[f64; 2]>| x.map_or("undefined".into(), |x| format!("{:.6e} .. {:.6e}", x[0], x[1]));
            println!("  k_max           {}", r(i.k_max_range));
            println!("  k_min           {}", r(i.k_min_range));
            println!("  mean            {}", r(i.mean_range));
            println!("  gauss           {}", r(i.gauss_range));
            match (&input.trim, i.file.is_some()) {
                (Some(t), _) => println!("  trim            {}", t.summary()),
                (None, true) => println!("  trim            none (the whole surface)"),
                (None, false) => {}
            }
            if let Some(n) = &i.network {
                crate::joins::print_network(n);
            }
        }
    }
    Ok(())
}

fn file_info(input: &Input) -> Option<FileInfo> {
    input.object.map(|(index, objects)| FileInfo {
        unit: input.unit.map(fairway::io::Unit::symbol),
        index,
        objects,
    })
}

/// The object and unit lines of an IGES or STEP input.
fn print_file_info(f: Option<&FileInfo>) {
    let Some(f) = f else { return };
    println!(
        "  object          {} of {} (--index {})",
        f.index + 1,
        f.objects,
        f.index
    );
    match f.unit {
        Some(u) => println!("  unit            {u} (lengths in {u}, curvatures in 1/{u})"),
        None => println!("  unit            not declared (or not known): lengths in the file's units"),
    }
}

/// Inflections to print: all of them up to [`LISTED_INFLECTIONS`], else the count with the first and last
/// few (`--json` has them all).
fn inflection_list(us: &[f64]) -> String {
    let fmt = |s: &[f64]| s.iter().map(|u| format!("{u:.6}")).collect::<Vec<_>>().join(", ");
    if us.len() <= LISTED_INFLECTIONS {
        format!("{} [{}]", us.len(), fmt(us))
    } else {
        let k = LISTED_INFLECTIONS / 2;
        format!(
            "{} [{}, … {} more …, {}] (--json lists them all)",
            us.len(),
            fmt(&us[..k]),
            us.len() - 2 * k,
            fmt(&us[us.len() - k..])
        )
    }
}

/// Inflections listed one by one in the text summary.
const LISTED_INFLECTIONS: usize = 20;
