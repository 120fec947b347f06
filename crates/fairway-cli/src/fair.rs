//! `fairway fair IN --tolerance m [options] -o OUT [--report REPORT.json]`:
//! fair a curve with the fast local method (or the iterative baseline), or a
//! surface with the isocurve-based surface engine, and write the result; the
//! optional report holds the measures of the result against the input (the
//! keys of `fairway measure`) and the solve time measured in-process.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use fairway::Geometry;
use fairway::fair::{
    Combine, CurveFairing, EndCondition, FairingOptions, FitMode, Integrator, IterativeOptions, Pass, PolishMethod,
    Seam, SurfaceFairingOptions, SurfaceMethod, TargetMethod, closed, fair_surface,
};
use fairway::io::{Document, Length, LengthError, Unit};
use fairway::measure::{Measures, measure};
use fairway::measure_surface::{SurfaceMeasures, surface_measures};
use fairway::{BSplineCurve, BSplineSurface};
use serde::Serialize;

use crate::common::{load_input, refuse_non_finite, refuse_same_files};

/// Arguments of `fairway fair`.
#[derive(clap::Args, Debug, Clone)]
pub struct Args {
    /// Input curve or surface (.json geometry, .ron document, .igs/.iges, .stp/.step, ...).
    pub input: PathBuf,
    /// IGES or STEP input (or a document with several objects): fair this one object alone and write it
    /// alone (0 = the first). Without it, a file with several objects is faired whole, keeping its joins.
    #[arg(long)]
    pub index: Option<usize>,
    /// A file with several objects: fair this object (its 0-based index or its name; repeat for more),
    /// keeping its joins; the others are written back unchanged. Default: every object.
    #[arg(long = "object", value_name = "N|NAME", conflicts_with = "index")]
    pub objects: Vec<String>,
    /// Tolerance m: max deviation from the input, in the coordinates' units (`0.05`), or with a unit
    /// (`0.05mm`, `0.002in`, `20um`) for an IGES or STEP input that declares its unit: converted to it.
    /// Default: the tolerance saved in the document (a `.ron` document saves one per object); given, it
    /// applies to every object. A file that saves none needs it.
    #[arg(long = "tolerance", value_name = "M", allow_hyphen_values = true, value_parser = Length::parse)]
    pub tolerance_given: Option<Length>,
    /// The tolerance in the coordinates' units (set once the input is read: `--tolerance`, or the saved one).
    #[arg(skip)]
    pub tolerance: f64,
    /// Where `tolerance` came from.
    #[arg(skip)]
    pub tolerance_from: ToleranceFrom,
    /// The input's length unit (IGES / STEP), declared by an IGES or STEP output (set once read).
    #[arg(skip)]
    pub unit: Option<Unit>,
    /// The input's bounds when it is a trimmed face (set once the input is read), written with the result.
    #[arg(skip)]
    pub trim: Option<fairway::FaceTrim>,
    /// Region to fair: `u1,u2` for a curve, `u1,u2,v1,v2` for a surface (default: everything). On a closed
    /// curve `u1 > u2` is the stretch across the seam ([u1, end] then [start, u2]).
    #[arg(long, value_parser = parse_region, allow_hyphen_values = true)]
    pub region: Option<Region>,
    /// Continuity at the region ends: g0, g1 or g2. A whole closed curve has no ends: it is faired G2 all
    /// round, across its seam.
    #[arg(long, default_value = "g2")]
    pub ends: EndCondition,
    /// Curves: at a G2 end that is an end of the (open) curve, ease the target into the kept end curvature
    /// within the end knot span instead of climbing to it from far inside. For noisy input whose end
    /// curvature is off but must be kept (fewer extra curvature extrema there); where the end curvature is
    /// real it can add wiggles near the ends, so compare the measures with and without.
    #[arg(long)]
    pub ease_ends: bool,
    /// Target curvature: heat (the averaging's heat flow, implicit, O(n); default), average (paper's passes),
    /// binomial or fit (paper eq. 3).
    #[arg(long, default_value = "heat")]
    pub target: TargetMethod,
    /// Smoothing strength of the target (passes, or the flow time in passes for heat; default from the number
    /// of samples).
    #[arg(long)]
    pub strength: Option<usize>,
    /// fast (default), smoothing (the reference: knot-keeping penalized least squares, its weight the largest
    /// that holds the band; on a surface the tensor-product curvature-variation smoother, likewise), iterative
    /// (paper 2.2 baseline) or paper (fast method as published: soft band). Surfaces: fast or smoothing.
    #[arg(long, default_value = "fast")]
    pub method: String,
    /// Curves: continuity kept at an end of an open curve (g0, g1 or g2; default: the weaker of --ends and
    /// g1, i.e. position and tangent, not the end curvature, which on noisy data is mostly noise).
    #[arg(long)]
    pub curve_ends: Option<EndCondition>,
    /// Curves, variation polish: how strongly the curvature follows the target against the curvature
    /// variation (β; default 0.1).
    #[arg(long)]
    pub target_weight: Option<f64>,
    /// Curves in 3D, variation polish: weight of the term that fairs the torsion too (the variation of
    /// κ²τ; 0 turns it off).
    #[arg(long, default_value_t = fairway::fair::TORSION_WEIGHT)]
    pub torsion_weight: f64,
    /// Integration scheme: euler, rk2 or arc.
    #[arg(long, default_value = "arc")]
    pub integrator: Integrator,
    /// Number of arc-length samples (curves; default: 10 per knot span).
    #[arg(long)]
    pub samples: Option<usize>,
    /// Curves, fast method: Gauss–Newton iterations of the E polish inside the band after the band search
    /// (0: none). More lower the paper's E further at more cost (about 0.2 ms each for 100 control points).
    #[arg(long, default_value_t = fairway::fair::curve::POLISH_ITERS)]
    pub polish_iterations: usize,
    /// Curves, fast method: how the polish works: variation (default: lowers ∫(dκ/ds)² over the whole
    /// region inside the band, never more curvature extrema than the reference smoother or the input),
    /// line-search (the paper's E, stops well short of its minimum in the band) or interior-point (the
    /// paper's E as closely as the band allows: for a target you typed in, pinned or shaped).
    #[arg(long, default_value = "variation")]
    pub polish_method: PolishMethod,
    /// Surfaces: combination of the u- and v-isocurve clouds: average (paper), border, weighted (default, as in
    /// the core) or smoothed.
    #[arg(long, default_value = "weighted")]
    pub combine: Combine,
    /// Surfaces: fair the isocurves again at each smaller isocurve tolerance m/3, m/9 (about twice the
    /// isocurve time) instead of scaling the correction of the pass at m (default).
    #[arg(long)]
    pub refair_levels: bool,
    /// Output file (.json, .ron, .igs/.iges or .stp/.step).
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Write a JSON report (measures, solve time) here.
    #[arg(long)]
    pub report: Option<PathBuf>,
}

/// The tolerance as given (see [`Length::parse`]) in the input's unit `to`, converted exactly; a
/// unit on an input that declares none is refused, naming the file.
pub(crate) fn resolve_tolerance(given: Length, to: Option<fairway::io::Unit>, input: &std::path::Path) -> Result<f64> {
    given.in_unit(to).map_err(|e| match e {
        LengthError::NoDocumentUnit(l) => anyhow!(
            "--tolerance {l}: {} declares no length unit, so a tolerance in {} cannot be converted; give a plain \
             number, in the coordinates' units",
            input.display(),
            l.unit.map_or("", |u| u.symbol())
        ),
        e => anyhow!("--tolerance {e}"),
    })
}

/// Where the tolerance an object was faired at came from (the report's `tolerance_from`).
#[derive(Serialize, Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ToleranceFrom {
    /// `--tolerance`.
    #[default]
    #[serde(rename = "command line")]
    CommandLine,
    /// The object's settings saved in the document.
    #[serde(rename = "document")]
    Document,
}

/// The tolerance of an object whose document saved `saved`, in the input's `unit`: `--tolerance` if
/// given, else the saved one; `None` if neither.
pub(crate) fn tolerance_of(a: &Args, saved: Option<f64>, unit: Option<Unit>) -> Result<Option<(f64, ToleranceFrom)>> {
    Ok(match (a.tolerance_given, saved) {
        (Some(l), _) => Some((resolve_tolerance(l, unit, &a.input)?, ToleranceFrom::CommandLine)),
        (None, Some(t)) => Some((t, ToleranceFrom::Document)),
        (None, None) => None,
    })
}

/// The error of an input that saves no tolerance (for `objects`, if it holds several) when none is given.
pub(crate) fn no_tolerance(input: &std::path::Path, objects: &[String]) -> anyhow::Error {
    let whose = if objects.is_empty() {
        String::new()
    } else {
        format!(" for {}", objects.join(", "))
    };
    anyhow!(
        "{} saves no tolerance{whose}: give one with --tolerance M, the largest deviation from the input allowed, \
         in the coordinates' units (0.01) or with a unit for an IGES or STEP file (0.05mm)",
        input.display()
    )
}

/// Say on stderr which tolerance `name` is faired at, in `unit` (the file's, if it declares one), where it
/// came from if not from `--tolerance`.
pub(crate) fn say_tolerance(name: &str, t: f64, unit: Option<Unit>, from: ToleranceFrom) {
    let (coords, unit) = unit.map_or((String::new(), String::new()), |u| {
        (format!("coordinates in {}: ", u.symbol()), format!(" {}", u.symbol()))
    });
    let from = match from {
        ToleranceFrom::CommandLine => "",
        ToleranceFrom::Document => " (saved in the document; --tolerance overrides it)",
    };
    eprintln!("fairway: {name}: {coords}tolerance {t}{unit}{from}");
}

/// A region as given on the command line: 2 (curve) or 4 (surface) parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Region(pub Vec<f64>);

fn parse_region(s: &str) -> std::result::Result<Region, String> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 2 && parts.len() != 4 {
        return Err(format!("expected u1,u2 (curve) or u1,u2,v1,v2 (surface), got {s:?}"));
    }
    parts
        .iter()
        .map(|p| p.trim().parse::<f64>().map_err(|e| format!("{p:?}: {e}")))
        .collect::<std::result::Result<Vec<f64>, String>>()
        .map(Region)
}

/// The report written by `--report` for a curve.
#[derive(Serialize, Debug)]
pub struct Report {
    /// "curve".
    pub kind: &'static str,
    /// fast, paper or iterative.
    pub method: String,
    /// The fast method's E polish: "line-search" or "interior-point" (absent for paper and iterative).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub polish: Option<&'static str>,
    /// The tolerance it was faired at.
    pub tolerance: f64,
    /// Where the tolerance came from: "command line" (`--tolerance`) or "document" (saved with it).
    pub tolerance_from: ToleranceFrom,
    /// Setup time (sampling, matrices), ms; for a whole closed curve, of its first pass (the second pass
    /// builds its setup inside the solve); with corners, of every stretch's setup.
    pub setup_ms: f64,
    /// Solve time (integration, fit, band control or simplex sweeps), ms.
    pub solve_ms: f64,
    /// Upper bound of the deviation verified by the solver.
    pub max_deviation_bound: f64,
    /// Fairness weight μ chosen.
    pub mu: f64,
    /// Update scale α (1 unless the band forced a partial step).
    pub alpha: f64,
    /// Linear solves done.
    pub solves: usize,
    /// Paper's E at the samples against the setup's target, before.
    pub energy_before: f64,
    /// The same after.
    pub energy: f64,
    /// Free control points [first, last) of the working curve (of the first pass for a closed curve).
    pub free_points: [usize; 2],
    /// The seam of a closed curve: "open", "untouched", "faired" or "held: …" (with the reason).
    pub seam: String,
    /// What the fair kept at the start and at the end of the region, in words (a curve end keeps at most
    /// its position and tangent by default; a region end inside the curve joins its neighbour).
    pub ends_kept: [String; 2],
    /// Measures of the result against the input.
    pub measures: Measures,
    /// The corners kept inside the region (tangent breaks above 1°, or points where the curve stops),
    /// whose stretches were faired one by one; absent if none. Then `energy_before`/`energy`/`solves` are the stretches' sums, `mu`/`alpha`
    /// their smallest values, and `free_points` spans from the first stretch's first free point to the
    /// last one's end (the points at the corners between them are held).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub corners: Vec<CornerReport>,
    /// The stretches between the corners, in order; absent if there are no corners.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub stretches: Vec<StretchReport>,
}

/// A corner kept (see `fairway::corners`).
#[derive(Serialize, Debug)]
pub struct CornerReport {
    /// Its knot.
    pub u: f64,
    /// The angle between the directions arriving and leaving, degrees.
    pub angle_deg: f64,
    /// The curve stops there (zero speed).
    pub stops: bool,
}

/// One stretch between corners.
#[derive(Serialize, Debug)]
pub struct StretchReport {
    /// Its region [u1, u2] (u1 > u2: across the seam).
    pub region: [f64; 2],
    /// Free control points [first, last).
    pub free_points: [usize; 2],
    /// E before and after, against the stretch's own target.
    pub energy_before: f64,
    /// See `energy_before`.
    pub energy: f64,
    /// Its verified deviation bound.
    pub max_deviation_bound: f64,
    /// Why it was left as it is, if it was.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub left: Option<String>,
}

/// The report written by `--report` for a surface.
#[derive(Serialize, Debug)]
pub struct SurfaceReport {
    /// "surface".
    pub kind: &'static str,
    /// "fast".
    pub method: String,
    /// The tolerance it was faired at.
    pub tolerance: f64,
    /// Where the tolerance came from: "command line" (`--tolerance`) or "document" (saved with it).
    pub tolerance_from: ToleranceFrom,
    /// Fairing time, ms (the surface engine has no separate setup).
    pub solve_ms: f64,
    /// Upper bound of the deviation verified by the solver (on its check grid).
    pub max_deviation_bound: f64,
    /// Sound bound of the deviation everywhere (the parametric difference's refined control net);
    /// ≤ the tolerance: the band is certified between the grid's points too.
    pub band_bound: Option<f64>,
    /// Whether `band_bound` certifies the tolerance.
    pub band_certified: bool,
    /// Update scale α.
    pub alpha: f64,
    /// Rounds of isocurve fairing.
    pub rounds: usize,
    /// Free control rows [first, last) (u).
    pub free_u: [usize; 2],
    /// Free control columns [first, last) (v).
    pub free_v: [usize; 2],
    /// Measures of the result against the input.
    pub measures: SurfaceMeasures,
    /// What the fair did besides the plain method (C0 knot lines kept, tiles held), also on stderr.
    pub notes: Vec<String>,
}

/// The report's `ends_kept`: what the fair kept at the region's start and end.
fn ends_kept(curve: &BSplineCurve, a: &Args, opts: &FairingOptions) -> [String; 2] {
    let (d0, d1) = curve.domain();
    let closed = closed::is_closed_curve(curve);
    let (u1, u2) = opts.region.unwrap_or((d0, d1));
    let eps = 1e-12 * (d1 - d0);
    let words = |e: EndCondition| match e {
        EndCondition::G0 => "position (G0)",
        EndCondition::G1 => "position and tangent (G1)",
        EndCondition::G2 => "position, tangent and curvature (G2)",
    };
    let side = |i: usize, at_curve_end: bool| {
        if closed && opts.region.is_none() {
            "a closed curve has no ends: faired G2 all round".to_string()
        } else if at_curve_end && !closed {
            let e = opts.curve_ends[i].unwrap_or(a.ends.min_by_order(EndCondition::G1));
            format!("curve end: {}", words(e))
        } else {
            format!("join with the untouched curve: {}", words(a.ends))
        }
    };
    [side(0, u1 <= d0 + eps), side(1, u2 >= d1 - eps)]
}

/// The report's `polish`: the fast method's polish, if it ran.
fn polish_name(a: &Args) -> Option<&'static str> {
    (a.method == "fast" && a.polish_iterations > 0).then_some(a.polish_method.name())
}

/// Run `fairway fair`.
pub fn run(a: &Args) -> Result<()> {
    if let Some(t) = a.tolerance_given.map(|l| l.value)
        && !(t.is_finite() && t > 0.0)
    {
        bail!("--tolerance must be a positive finite number, got {t}");
    }
    // the input, the output and the report must be three different files (links resolved), or one
    // would overwrite another: refused before any work
    refuse_same_files(&a.input, &a.output, a.report.as_deref())?;
    // the destinations' folders first: a missing folder is found before any work, and never after the
    // output was written
    for (what, path) in [("output", Some(&a.output)), ("report", a.report.as_ref())] {
        if let Some(path) = path {
            let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
            if let Some(dir) = dir.filter(|d| !d.is_dir()) {
                bail!(
                    "cannot write the {what} {}: folder {} does not exist",
                    path.display(),
                    dir.display()
                );
            }
        }
    }
    if a.index.is_none()
        && let Some((scene, notices)) = crate::common::load_scene_input(&a.input)?
        && (scene.objects.len() > 1 || !a.objects.is_empty() || scene.objects.iter().any(|o| o.trim.is_some()))
    {
        return crate::fair_scene::run(a, scene, &notices);
    }
    if !a.objects.is_empty() {
        bail!(
            "--object picks objects of a file with several (IGES, STEP, a .ron document); {} holds one",
            a.input.display()
        );
    }
    let input = load_input(&a.input, a.index)?;
    let mut a = a.clone();
    let name = a.input.display().to_string();
    (a.tolerance, a.tolerance_from) =
        tolerance_of(&a, input.doc.settings.tolerance, input.unit)?.ok_or_else(|| no_tolerance(&a.input, &[]))?;
    a.unit = input.unit;
    a.trim = input.trim;
    if input.unit.is_some() || a.tolerance_from == ToleranceFrom::Document {
        say_tolerance(&name, a.tolerance, input.unit, a.tolerance_from);
    }
    run_loaded(&a, input.doc)
}

/// The curve fairing's options from the command line (the region is set later), checked.
pub(crate) fn curve_options(a: &Args) -> Result<FairingOptions> {
    let mode = match a.method.as_str() {
        "fast" | "iterative" => FitMode::Fairway,
        "paper" => FitMode::Paper,
        "smoothing" => FitMode::Smoothing,
        m => {
            return Err(anyhow!(
                "unknown method {m:?}: expected fast, smoothing, iterative or paper"
            ));
        }
    };
    let opts = FairingOptions::default()
        .region(None)
        .tolerance(a.tolerance)
        .ends(a.ends)
        .target(a.target)
        .strength(a.strength)
        .integrator(a.integrator)
        .samples(a.samples)
        .mode(mode)
        .polish(true)
        .polish_iterations(a.polish_iterations)
        .ease_curve_ends(a.ease_ends)
        .polish_method(a.polish_method)
        .target_weight(a.target_weight.unwrap_or(FairingOptions::default().target_weight))
        .curve_ends([a.curve_ends; 2])
        .torsion_weight(a.torsion_weight);
    if !(opts.torsion_weight.is_finite() && opts.torsion_weight >= 0.0) {
        bail!(
            "--torsion-weight must be a finite number ≥ 0, got {}",
            opts.torsion_weight
        );
    }
    if !(opts.target_weight.is_finite() && opts.target_weight >= 0.0) {
        bail!(
            "--target-weight must be a finite number ≥ 0, got {}",
            opts.target_weight
        );
    }
    Ok(opts)
}

/// [`run`] once the input is read and the tolerance is in its units.
fn run_loaded(a: &Args, doc: Document) -> Result<()> {
    let opts = curve_options(a)?;
    // a tolerance below the precision of the coordinates cannot be verified: the same message for curves
    // and surfaces
    fairway::range::check_tolerance(a.tolerance, &doc.geometry).map_err(|e| tolerance_error(a.tolerance_from, &e))?;
    let region = region_to_fair(a, &doc)?;
    match &doc.geometry {
        Geometry::Curve(c) => fair_curve_cmd(a, c, opts, region.as_ref()),
        Geometry::Surface(s) => fair_surface_cmd(a, s, opts, region.as_ref()),
    }
}

/// A tolerance the input cannot be faired at, named as it was given (`--tolerance …` or
/// `settings.tolerance …`).
pub(crate) fn tolerance_error(from: ToleranceFrom, e: &fairway::Error) -> anyhow::Error {
    match from {
        ToleranceFrom::CommandLine => anyhow!("--{e}"),
        ToleranceFrom::Document => anyhow!("the document's settings.{e}: correct it, or give --tolerance"),
    }
}

/// The region to fair: `--region` if given, else the region saved in a document's settings
/// (`settings.region` of a curve, `settings.region_uv` of a surface), refused with the reason if it
/// cannot apply (non-finite, empty, outside the domain, of the other kind, backwards on an open curve).
/// The core checks the rest (a region too small to move a control point) as for `--region`.
fn region_to_fair(a: &Args, doc: &Document) -> Result<Option<Region>> {
    if a.region.is_some() {
        return Ok(a.region.clone());
    }
    let st = &doc.settings;
    let name = a.input.display();
    let fix = "correct it in the document, or give --region";
    let check = |r: (f64, f64), d: (f64, f64), what: &str| -> Result<()> {
        let s = fairway::range::short;
        let eps = 1e-12 * (d.1 - d.0);
        if !(r.0.is_finite() && r.1.is_finite()) {
            bail!("{name}: {what} ({}, {}) is not finite: {fix}", r.0, r.1);
        }
        if r.0 == r.1 {
            bail!("{name}: {what} ({}, {}) is empty: {fix}", s(r.0), s(r.1));
        }
        if [r.0, r.1].iter().any(|&u| u < d.0 - eps || u > d.1 + eps) {
            bail!(
                "{name}: {what} ({}, {}) is outside the domain [{}, {}]: {fix}",
                s(r.0),
                s(r.1),
                s(d.0),
                s(d.1)
            );
        }
        Ok(())
    };
    let region = match &doc.geometry {
        Geometry::Curve(c) => {
            if st.region.is_none() && st.region_uv.is_some() {
                bail!("{name}: settings.region_uv is a surface region, but the document holds a curve: {fix}");
            }
            let Some(r) = st.region else { return Ok(None) };
            check(r, c.domain(), "settings.region")?;
            if r.0 > r.1 && !closed::is_closed_curve(c) {
                bail!(
                    "{name}: settings.region ({}, {}) runs backwards on an open curve (only a closed curve has a \
                     region across its seam): {fix}",
                    fairway::range::short(r.0),
                    fairway::range::short(r.1)
                );
            }
            Region(vec![r.0, r.1])
        }
        Geometry::Surface(srf) => {
            if st.region_uv.is_none() && st.region.is_some() {
                bail!("{name}: settings.region is a curve region, but the document holds a surface: {fix}");
            }
            let Some((ru, rv)) = st.region_uv else { return Ok(None) };
            let (du, dv) = srf.domain();
            check(ru, du, "settings.region_uv in u")?;
            check(rv, dv, "settings.region_uv in v")?;
            Region(vec![ru.0, ru.1, rv.0, rv.1])
        }
    };
    let list: Vec<String> = region.0.iter().map(|&x| fairway::range::short(x)).collect();
    eprintln!(
        "fairway: {name}: fairing the document's region {} (--region overrides it)",
        list.join(", ")
    );
    Ok(Some(region))
}

/// Write the report after the output `written`: a failure says that the output is there.
pub(crate) fn write_report<T: Serialize>(path: &std::path::Path, report: &T, written: &std::path::Path) -> Result<()> {
    let text = serde_json::to_string_pretty(report)?;
    fairway::io::write_atomic(path, text.as_bytes()).with_context(|| {
        format!(
            "the result was written to {}, but the report could not be written",
            written.display()
        )
    })
}

fn fair_curve_cmd(a: &Args, curve: &BSplineCurve, mut opts: FairingOptions, region: Option<&Region>) -> Result<()> {
    opts.region = match region.map(|r| r.0.as_slice()) {
        None => None,
        Some(&[u1, u2]) => Some((u1, u2)),
        Some(r) => bail!(
            "{}: a curve takes --region u1,u2 (got {} values)",
            a.input.display(),
            r.len()
        ),
    };
    let t0 = Instant::now();
    let mut fairing = CurveFairing::new(curve, opts).context("fairing setup")?;
    let setup_ms = t0.elapsed().as_secs_f64() * 1e3;
    let pass = if a.method == "iterative" {
        Pass::Iterative(IterativeOptions::default())
    } else {
        Pass::Full
    };
    let t1 = Instant::now();
    let fair = fairing.fair(pass).context("fairing")?;
    let solve_ms = t1.elapsed().as_secs_f64() * 1e3;
    let result = &fair.result;
    for n in &result.notes {
        eprintln!("fairway: {}: {n}", a.input.display());
    }
    let free = fairing.free_points();
    let report = a.report.as_ref().map(|_| Report {
        kind: "curve",
        method: a.method.clone(),
        polish: polish_name(a),
        tolerance: a.tolerance,
        tolerance_from: a.tolerance_from,
        setup_ms,
        solve_ms,
        max_deviation_bound: result.max_deviation,
        mu: result.mu,
        alpha: result.alpha,
        solves: result.solves,
        energy_before: fair.energy_before,
        energy: result.energy,
        free_points: [free.start, free.end],
        seam: seam_text(&result.seam),
        ends_kept: ends_kept(curve, a, &opts),
        measures: measure(curve, &result.curve),
        corners: fair
            .corners
            .iter()
            .map(|c| CornerReport {
                u: c.u,
                angle_deg: c.angle_deg,
                stops: c.stops,
            })
            .collect(),
        stretches: fair
            .stretches
            .iter()
            .map(|s| StretchReport {
                region: [s.region.0, s.region.1],
                free_points: [s.free_points.start, s.free_points.end],
                energy_before: s.energy_before,
                energy: s.energy,
                max_deviation_bound: s.max_deviation,
                left: s.left.clone(),
            })
            .collect(),
    });
    save_result(a, Geometry::Curve(result.curve.clone()), report.as_ref())
}

/// Write the output and then the report (if asked for); a report holding a NaN or an infinity is refused
/// before either is written.
fn save_result<T: Serialize>(a: &Args, result: Geometry, report: Option<&T>) -> Result<()> {
    if let Some(r) = report {
        refuse_non_finite("the report", r)?;
    }
    // an IGES or STEP output declares the input's unit; a faired trimmed face keeps its bounds (the fair
    // keeps the surface's knots and parameters, so its uv loops bound the same part of it)
    let trim = a.trim.clone().filter(|_| matches!(result, Geometry::Surface(_)));
    crate::common::save_document(&a.output, Document::new(result), trim, a.unit)?;
    if let (Some(path), Some(r)) = (&a.report, report) {
        write_report(path, r, &a.output)?;
    }
    Ok(())
}

fn seam_text(seam: &Seam) -> String {
    match seam {
        Seam::Open => "open".into(),
        Seam::Untouched => "untouched".into(),
        Seam::Faired => "faired".into(),
        Seam::Held(why) => format!("held: {why}"),
    }
}

/// The surface engine's method for `--method`.
pub(crate) fn surface_method(a: &Args) -> Result<SurfaceMethod> {
    Ok(match a.method.as_str() {
        "fast" => SurfaceMethod::Fairway,
        "smoothing" => SurfaceMethod::Smoothing,
        m => bail!("surfaces are faired by the fast or the smoothing method (got --method {m})"),
    })
}

fn fair_surface_cmd(a: &Args, surface: &BSplineSurface, curve: FairingOptions, region: Option<&Region>) -> Result<()> {
    let method = surface_method(a)?;
    let region = match region.map(|r| r.0.as_slice()) {
        None => None,
        Some(&[u1, u2, v1, v2]) => Some(((u1, u2), (v1, v2))),
        Some(r) => bail!(
            "{}: a surface takes --region u1,u2,v1,v2 (got {} values)",
            a.input.display(),
            r.len()
        ),
    };
    let opts = SurfaceFairingOptions::default()
        .region(region)
        .tolerance(a.tolerance)
        .curve(curve)
        .combine(a.combine)
        .refair_levels(a.refair_levels)
        .method(method);
    let t0 = Instant::now();
    let result = fair_surface(surface, opts).context("surface fairing")?;
    let solve_ms = t0.elapsed().as_secs_f64() * 1e3;
    for n in &result.notes {
        eprintln!("fairway: {}: {n}", a.input.display());
    }
    let report = a.report.as_ref().map(|_| SurfaceReport {
        kind: "surface",
        method: a.method.clone(),
        tolerance: a.tolerance,
        tolerance_from: a.tolerance_from,
        solve_ms,
        max_deviation_bound: result.max_deviation,
        band_bound: result.band_bound,
        band_certified: result.band_bound.is_some_and(|b| b <= a.tolerance),
        alpha: result.alpha,
        rounds: result.rounds,
        free_u: [result.free_u.start, result.free_u.end],
        free_v: [result.free_v.start, result.free_v.end],
        measures: surface_measures(surface, &result.surface),
        notes: result.notes.clone(),
    });
    save_result(a, Geometry::Surface(result.surface.clone()), report.as_ref())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cmd {
        #[command(flatten)]
        args: Args,
    }

    #[test]
    fn combine_defaults_to_the_core_default_and_parses_every_variant() {
        let a = Cmd::try_parse_from(["fair", "in.json", "--tolerance", "1e-3", "-o", "out.json"]).unwrap();
        assert_eq!(a.args.combine, Combine::default());
        assert_eq!(a.args.combine, SurfaceFairingOptions::default().combine);
        assert_eq!(a.args.refair_levels, SurfaceFairingOptions::default().refair_levels);
        let r =
            Cmd::try_parse_from(["fair", "in.json", "--tolerance", "1", "-o", "o.json", "--refair-levels"]).unwrap();
        assert!(r.args.refair_levels);
        for (name, want) in [
            ("average", Combine::Average),
            ("border", Combine::Border),
            ("weighted", Combine::Weighted),
            ("smoothed", Combine::Smoothed),
        ] {
            let a = Cmd::try_parse_from(["fair", "in.json", "--tolerance", "1", "-o", "o.json", "--combine", name])
                .unwrap();
            assert_eq!(a.args.combine, want);
        }
        assert!(
            Cmd::try_parse_from(["fair", "in.json", "--tolerance", "1", "-o", "o.json", "--combine", "x"]).is_err()
        );
    }

    #[test]
    fn tolerances_with_units_parse_and_convert_exactly_into_the_inputs_unit() {
        use fairway::io::Unit;
        let parse = |t: &str| Cmd::try_parse_from(["fair", "in.stp", "--tolerance", t, "-o", "o.stp"]);
        let given = |t: &str| parse(t).unwrap().args.tolerance_given.expect("given");
        assert_eq!(given("1e-3mm").unit, Some(Unit::Millimeter));
        assert_eq!(given(" 2 in").value, 2.0);
        let p = std::path::Path::new("a.stp");
        // 0.05 mm in an inch file: the double nearest 1/508 (0.05 / 25.4 is one ulp off)
        assert_eq!(
            resolve_tolerance(given("0.05mm"), Some(Unit::Inch), p).unwrap(),
            1.0 / 508.0
        );
        assert_eq!(
            resolve_tolerance(given("0.3in"), Some(Unit::Millimeter), p).unwrap(),
            7.62
        );
        assert_eq!(resolve_tolerance(given("0.1"), Some(Unit::Inch), p).unwrap(), 0.1);
        let e = resolve_tolerance(given("0.1mm"), None, p).unwrap_err().to_string();
        assert_eq!(
            e,
            "--tolerance 0.1 mm: a.stp declares no length unit, so a tolerance in mm cannot be converted; give a \
             plain number, in the coordinates' units"
        );
        // bad text is a usage error, in the parser's words
        for (t, want) in [
            ("0.05 parsec", "\"parsec\" is not a length unit"),
            ("nan", "\"nan\" is not a finite length"),
        ] {
            let e = parse(t).err().unwrap().to_string();
            assert!(e.contains(want), "{t}: {e}");
        }
    }
}
