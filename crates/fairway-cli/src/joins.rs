//! The joins of a file with several objects (`fairway::network`), as `fairway info` lists them and
//! `fairway fair --report` reports them before and after.

use fairway::io::Scene;
use fairway::network::{CurveJoin, Joins, SurfaceJoin};
use serde::Serialize;

/// One object of the file.
#[derive(Serialize, Debug)]
pub struct ObjectEntry {
    /// 0-based, as `--index` and `--object` take it.
    pub index: usize,
    /// Its name (IGES label, STEP entity name; empty if none).
    pub name: String,
    /// "curve" or "surface".
    pub kind: &'static str,
}

/// A join of two curve ends, measured.
#[derive(Serialize, Debug, Clone)]
pub struct CurveJoinInfo {
    /// The two objects: arriving by the first, leaving by the second.
    pub objects: [usize; 2],
    /// Which end of each: "start" or "end".
    pub ends: [&'static str; 2],
    /// The joint.
    pub point: [f64; 3],
    /// "G0", "G1" or "G2".
    pub continuity: &'static str,
    /// Distance between the two end points.
    pub gap: f64,
    /// Angle between the tangent directions, degrees.
    pub angle_deg: f64,
    /// |κ₁N₁ − κ₂N₂| / max(κ₁, κ₂).
    pub curvature_jump: f64,
    /// κ₂ / κ₁ (`null` where κ₁ = 0 < κ₂).
    pub curvature_ratio: Option<f64>,
}

/// An edge two patches share, measured along it.
#[derive(Serialize, Debug, Clone)]
pub struct SurfaceJoinInfo {
    /// The two patches.
    pub objects: [usize; 2],
    /// Their sides: "u0", "u1", "v0" or "v1".
    pub sides: [&'static str; 2],
    /// The sides run in opposite directions.
    pub reversed: bool,
    /// "G0", "G1" or "G2".
    pub continuity: &'static str,
    /// Largest distance between the two sides.
    pub gap: f64,
    /// Largest angle between the normals, degrees.
    pub normal_angle_deg: f64,
    /// Largest jump of the normal curvature across the edge, relative to the larger one.
    pub curvature_jump: f64,
}

/// The objects of a file and their joins.
#[derive(Serialize, Debug)]
pub struct NetworkInfo {
    /// Every object.
    pub objects: Vec<ObjectEntry>,
    /// Ends (sides) closer than this are joined: 1e-6 × the diagonal of all control points.
    pub join_tolerance: f64,
    /// Curve joins.
    pub curve_joins: Vec<CurveJoinInfo>,
    /// Shared patch edges.
    pub surface_joins: Vec<SurfaceJoinInfo>,
}

/// A curve join for a report.
pub fn curve_join(j: &CurveJoin) -> CurveJoinInfo {
    let c = j.continuity;
    CurveJoinInfo {
        objects: [j.a.object, j.b.object],
        ends: [j.a.end.name(), j.b.end.name()],
        point: j.point.to_array(),
        continuity: c.class.name(),
        gap: c.gap,
        angle_deg: c.angle.to_degrees(),
        curvature_jump: c.curvature_jump,
        curvature_ratio: c.curvature_ratio.is_finite().then_some(c.curvature_ratio),
    }
}

/// A surface join for a report.
pub fn surface_join(j: &SurfaceJoin) -> SurfaceJoinInfo {
    let c = j.continuity;
    SurfaceJoinInfo {
        objects: [j.a.0, j.b.0],
        sides: [j.a.1.name(), j.b.1.name()],
        reversed: j.reversed,
        continuity: c.class.name(),
        gap: c.gap,
        normal_angle_deg: c.normal_angle.to_degrees(),
        curvature_jump: c.curvature_jump,
    }
}

/// The objects of `scene` and the joins `joins` found on them.
pub fn network_info(scene: &Scene, joins: &Joins) -> NetworkInfo {
    NetworkInfo {
        objects: scene
            .objects
            .iter()
            .enumerate()
            .map(|(index, o)| ObjectEntry {
                index,
                name: o.name.clone(),
                kind: o.geometry.kind(),
            })
            .collect(),
        join_tolerance: joins.tolerance,
        curve_joins: joins.curves.iter().map(curve_join).collect(),
        surface_joins: joins.surfaces.iter().map(surface_join).collect(),
    }
}

/// One line per curve join, for text output.
pub fn curve_line(j: &CurveJoinInfo) -> String {
    let ratio = j.curvature_ratio.map_or("–".into(), |r| format!("{r:.6}"));
    format!(
        "curve {} {} – curve {} {} at ({:.6}, {:.6}, {:.6}): {}  gap {:.3e}  angle {:.3e}°  curvature jump {:.3e} \
         (ratio {ratio})",
        j.objects[0],
        j.ends[0],
        j.objects[1],
        j.ends[1],
        j.point[0],
        j.point[1],
        j.point[2],
        j.continuity,
        j.gap,
        j.angle_deg,
        j.curvature_jump
    )
}

/// One line per shared edge, for text output.
pub fn surface_line(j: &SurfaceJoinInfo) -> String {
    format!(
        "surface {} {} – surface {} {}{}: {}  gap {:.3e}  normal angle {:.3e}°  normal-curvature jump {:.3e}",
        j.objects[0],
        j.sides[0],
        j.objects[1],
        j.sides[1],
        if j.reversed { " (reversed)" } else { "" },
        j.continuity,
        j.gap,
        j.normal_angle_deg,
        j.curvature_jump
    )
}

/// Print the objects and joins of a file as `fairway info` does.
pub fn print_network(n: &NetworkInfo) {
    let list: Vec<String> = n
        .objects
        .iter()
        .map(|o| {
            if o.name.is_empty() {
                format!("{} {}", o.index, o.kind)
            } else {
                format!("{} {} {:?}", o.index, o.kind, o.name)
            }
        })
        .collect();
    println!("  objects         {}: {}", n.objects.len(), list.join(", "));
    println!(
        "  joins           {} (ends and edges within {:.3e} are joined)",
        n.curve_joins.len() + n.surface_joins.len(),
        n.join_tolerance
    );
    for j in &n.curve_joins {
        println!("    {}", curve_line(j));
    }
    for j in &n.surface_joins {
        println!("    {}", surface_line(j));
    }
}
