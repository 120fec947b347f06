//! `fairway fair FILE [--tolerance m] -o OUT` on a file with several objects (IGES, STEP, a `.ron`
//! document of version 2), or with `--object`: every object (or those chosen) faired together, keeping
//! their joins (`fairway::fair::network`), each at its own tolerance saved in the document unless
//! `--tolerance` gives one for all, and the whole file written back in order with its names; the report
//! lists each object's tolerance (and where it came from), its measures and each join's continuity before
//! and after.

use std::time::Instant;

use anyhow::{Result, anyhow, bail};
use fairway::Geometry;
use fairway::fair::SurfaceFairingOptions;
use fairway::fair::network::{NetworkOptions, fair_network_at};
use fairway::io::Scene;
use fairway::network::{Continuity, CurveContinuity, Joins};
use serde::Serialize;

use crate::fair::{
    Args, ToleranceFrom, curve_options, no_tolerance, say_tolerance, surface_method, tolerance_error, tolerance_of,
    write_report,
};
use crate::joins::{CurveJoinInfo, SurfaceJoinInfo, curve_join, surface_join};

/// An object's measures: a curve's or a surface's (the keys of `fairway measure`).
#[derive(Serialize, Debug)]
#[serde(untagged)]
pub enum ObjectMeasures {
    /// A curve's.
    Curve(Box<fairway::measure::Measures>),
    /// A surface's.
    Surface(Box<fairway::measure_surface::SurfaceMeasures>),
}

/// One object in the report.
#[derive(Serialize, Debug)]
pub struct ObjectReport {
    /// 0-based index.
    pub index: usize,
    /// Its name.
    pub name: String,
    /// "curve" or "surface".
    pub kind: &'static str,
    /// Whether it was faired (chosen, and not refused).
    pub faired: bool,
    /// Its tolerance, its deviation's limit (`null` if not chosen); objects faired as one are faired at the
    /// smallest of theirs (a note says so).
    pub tolerance: Option<f64>,
    /// Where `tolerance` came from: "command line" (`--tolerance`) or "document" (its saved settings).
    pub tolerance_from: Option<ToleranceFrom>,
    /// The objects faired together with it as one curve or surface.
    pub group: Vec<usize>,
    /// The route its fair took: "not faired", "alone", "chain" (curves concatenated), "strip", "ring",
    /// "grid" or "layout" (patches joined into one surface; `fairway::fair::network::Route`).
    pub route: &'static str,
    /// A sound bound of its own deviation from the input (0 if not faired); a patch faired with others
    /// has its own, at most the joined surface's.
    pub max_deviation_bound: f64,
    /// Its measures against the input (`null` for an object not faired: it is as it was).
    pub measures: Option<ObjectMeasures>,
    /// What the fair did (also on stderr).
    pub notes: Vec<String>,
}

/// A curve join before and after.
#[derive(Serialize, Debug)]
pub struct CurveJoinReport {
    /// Measured on the input.
    pub before: CurveJoinInfo,
    /// Measured on the result.
    pub after: CurveJoinInfo,
    /// The continuity is kept: the class is at least what it was, and a G0 join (a corner) keeps its
    /// angle to 1e-9 rad.
    pub kept: bool,
}

/// A shared edge before and after.
#[derive(Serialize, Debug)]
pub struct SurfaceJoinReport {
    /// Measured on the input.
    pub before: SurfaceJoinInfo,
    /// Measured on the result.
    pub after: SurfaceJoinInfo,
    /// The class is at least what it was.
    pub kept: bool,
}

/// The report written by `--report` for a file with several objects.
#[derive(Serialize, Debug)]
pub struct SceneReport {
    /// "scene".
    pub kind: &'static str,
    /// fast, smoothing or paper.
    pub method: String,
    /// `--tolerance`, every object's (`null`: each object's own, see `objects`).
    pub tolerance: Option<f64>,
    /// Fairing time, ms.
    pub solve_ms: f64,
    /// Every object, in the file's order.
    pub objects: Vec<ObjectReport>,
    /// The curve joins.
    pub curve_joins: Vec<CurveJoinReport>,
    /// The shared patch edges.
    pub surface_joins: Vec<SurfaceJoinReport>,
    /// How each join was kept: concatenated (faired as one) or held, and why.
    pub notes: Vec<String>,
}

/// Is a curve join's continuity kept from `b` to `a`?
fn kept(b: &CurveContinuity, a: &CurveContinuity) -> bool {
    a.class >= b.class && (b.class != Continuity::G0 || (a.angle - b.angle).abs() <= 1e-9)
}

/// The objects `--object` names (all if none), or the error listing what the file holds.
fn selection(a: &Args, scene: &Scene) -> Result<Vec<usize>> {
    let mut out = vec![];
    for key in &a.objects {
        let Some(i) = scene.find(key) else {
            let names: Vec<String> = scene
                .objects
                .iter()
                .enumerate()
                .map(|(i, o)| {
                    if o.name.is_empty() {
                        i.to_string()
                    } else {
                        format!("{i} {:?}", o.name)
                    }
                })
                .collect();
            bail!(
                "--object {key}: {} holds no such object (it holds {}: {})",
                a.input.display(),
                scene.objects.len(),
                names.join(", ")
            );
        };
        if !out.contains(&i) {
            out.push(i);
        }
    }
    Ok(out)
}

/// Each object's tolerance and where it came from (`None` for an object not chosen), checked against its
/// coordinates; an error lists the chosen objects that save none when `--tolerance` is not given.
fn tolerances(a: &Args, scene: &Scene, chosen: &[usize]) -> Result<Vec<Option<(f64, ToleranceFrom)>>> {
    let mut missing = vec![];
    let mut out = vec![];
    for (i, o) in scene.objects.iter().enumerate() {
        if !(chosen.is_empty() || chosen.contains(&i)) {
            out.push(None);
            continue;
        }
        let t = tolerance_of(a, o.settings.tolerance, scene.unit)?;
        match t {
            None => missing.push(object_name(scene, i)),
            Some((t, from)) => fairway::range::check_tolerance(t, &o.geometry)
                .map_err(|e| anyhow!("{}: {}", object_name(scene, i), tolerance_error(from, &e)))?,
        }
        out.push(t);
    }
    if !missing.is_empty() {
        return Err(no_tolerance(&a.input, &missing));
    }
    Ok(out)
}

/// An object for messages: `object 1 "MID"` (without the name if it has none).
fn object_name(scene: &Scene, i: usize) -> String {
    match scene.objects[i].name.as_str() {
        "" => format!("object {i}"),
        n => format!("object {i} {n:?}"),
    }
}

/// Say on stderr which tolerance each chosen object is faired at: one line for `--tolerance`, else one
/// per object.
fn say_tolerances(a: &Args, scene: &Scene, tols: &[Option<(f64, ToleranceFrom)>]) {
    let name = a.input.display();
    if a.tolerance_given.is_some() {
        say_tolerance(&name.to_string(), a.tolerance, scene.unit, ToleranceFrom::CommandLine);
        return;
    }
    for (i, t) in tols.iter().enumerate() {
        if let Some((t, from)) = t {
            say_tolerance(&format!("{name}: {}", object_name(scene, i)), *t, scene.unit, *from);
        }
    }
}

/// The options of the network fair from the command line (the tolerances are each object's).
fn options(a: &Args, scene: &Scene) -> Result<NetworkOptions> {
    if a.region.is_some() {
        bail!("--region applies to one object: pick it with --index");
    }
    if a.method == "iterative" {
        bail!("--method iterative fairs one curve: pick it with --index");
    }
    let curve = curve_options(a)?;
    let surfaces = scene.objects.iter().any(|o| matches!(o.geometry, Geometry::Surface(_)));
    let method = if surfaces {
        surface_method(a)?
    } else {
        Default::default()
    };
    Ok(NetworkOptions {
        curve,
        surface: SurfaceFairingOptions::default()
            .tolerance(a.tolerance)
            .curve(curve)
            .combine(a.combine)
            .refair_levels(a.refair_levels)
            .method(method),
        hold_all: false,
    })
}

/// Run `fairway fair` on the objects of `scene` (module docs); `notices` are the reader's.
pub fn run(a: &Args, scene: Scene, notices: &[String]) -> Result<()> {
    let name = a.input.display();
    for n in notices {
        eprintln!("fairway: {name}: {n}");
    }
    let mut a = a.clone();
    a.unit = scene.unit;
    let chosen = selection(&a, &scene)?;
    let tols = tolerances(&a, &scene, &chosen)?;
    // the network options' own tolerance: every object's is given to the fair
    a.tolerance = tols.iter().flatten().map(|t| t.0).fold(f64::INFINITY, f64::min);
    if scene.objects.len() > 1 && matches!(fairway::io::Format::from_path(&a.output), Ok(fairway::io::Format::Json)) {
        bail!(
            "{}: a JSON geometry file holds one object and {name} has {}; write .ron, .igs or .stp (or fair one \
             object with --index)",
            a.output.display(),
            scene.objects.len()
        );
    }
    let opts = options(&a, &scene)?;
    say_tolerances(&a, &scene, &tols);
    eprintln!(
        "fairway: {name}: {} objects, fairing {} together, keeping their joins",
        scene.objects.len(),
        if chosen.is_empty() {
            "all".to_string()
        } else {
            format!("{chosen:?}")
        }
    );
    let geoms = scene.geometries();
    let t0 = Instant::now();
    let per_object: Vec<Option<f64>> = tols.iter().map(|t| t.map(|t| t.0)).collect();
    let r = fair_network_at(&geoms, &chosen, &opts, &per_object)?;
    let solve_ms = t0.elapsed().as_secs_f64() * 1e3;
    for n in &r.notes {
        eprintln!("fairway: {name}: {n}");
    }
    for (i, o) in r.outcome.iter().enumerate() {
        if o.faired {
            eprintln!(
                "fairway: {name}: object {i}: route {} (with objects {:?}), its deviation ≤ {}",
                o.route.name(),
                o.group,
                fairway::range::short(o.max_deviation)
            );
        }
        for n in &o.notes {
            eprintln!("fairway: {name}: object {i}: {n}");
        }
    }
    let report = a.report.as_ref().map(|_| scene_report(&a, &scene, &tols, &r, solve_ms));
    if let Some(rep) = &report {
        crate::common::refuse_non_finite("the report", rep)?;
    }
    let mut out = scene.clone();
    for (o, g) in out.objects.iter_mut().zip(r.objects) {
        o.geometry = g;
    }
    fairway::io::save_scene(&a.output, &out)?;
    if let (Some(path), Some(rep)) = (&a.report, &report) {
        write_report(path, rep, &a.output)?;
    }
    Ok(())
}

/// Every object's part of the report of a network fair.
fn object_reports(
    scene: &Scene,
    tols: &[Option<(f64, ToleranceFrom)>],
    r: &fairway::fair::network::NetworkFair,
) -> Vec<ObjectReport> {
    scene
        .objects
        .iter()
        .zip(&r.objects)
        .zip(&r.outcome)
        .enumerate()
        .map(|(index, ((o, g), f))| ObjectReport {
            index,
            name: o.name.clone(),
            kind: o.geometry.kind(),
            faired: f.faired,
            tolerance: tols[index].map(|t| t.0),
            tolerance_from: tols[index].map(|t| t.1),
            group: f.group.clone(),
            route: f.route.name(),
            max_deviation_bound: f.max_deviation,
            measures: f.faired.then(|| match (&o.geometry, g) {
                (Geometry::Curve(c0), Geometry::Curve(c1)) => {
                    ObjectMeasures::Curve(Box::new(fairway::measure::measure(c0, c1)))
                }
                (Geometry::Surface(s0), Geometry::Surface(s1)) => {
                    ObjectMeasures::Surface(Box::new(fairway::measure_surface::surface_measures(s0, s1)))
                }
                _ => unreachable!("an object keeps its kind"),
            }),
            notes: f.notes.clone(),
        })
        .collect()
}

/// The report of a network fair.
fn scene_report(
    a: &Args,
    scene: &Scene,
    tols: &[Option<(f64, ToleranceFrom)>],
    r: &fairway::fair::network::NetworkFair,
    solve_ms: f64,
) -> SceneReport {
    let objects = object_reports(scene, tols, r);
    let (b, af): (&Joins, &Joins) = (&r.joins_before, &r.joins_after);
    SceneReport {
        kind: "scene",
        method: a.method.clone(),
        tolerance: a.tolerance_given.is_some().then_some(a.tolerance),
        solve_ms,
        objects,
        curve_joins: b
            .curves
            .iter()
            .zip(&af.curves)
            .map(|(x, y)| CurveJoinReport {
                before: curve_join(x),
                after: curve_join(y),
                kept: kept(&x.continuity, &y.continuity),
            })
            .collect(),
        surface_joins: b
            .surfaces
            .iter()
            .zip(&af.surfaces)
            .map(|(x, y)| SurfaceJoinReport {
                before: surface_join(x),
                after: surface_join(y),
                kept: y.continuity.class >= x.continuity.class,
            })
            .collect(),
        notes: r.notes.clone(),
    }
}
