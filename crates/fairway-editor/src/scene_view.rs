//! The document's objects as the 2D canvas shows them: the view plane 3D curves are drawn on
//! ([`ViewPlane`], [`Frame`]), every curve of the document (the active one is the workspace's own
//! [`crate::CurveView`]; the others are drawn dimmed and picked by a click) and the joins between them
//! with their measured continuity ([`JoinMark`], measured by the core's [`fairway::network`]).

use fairway::network::{Continuity, CurveJoin, End, Joins, SurfaceJoin, find_joins};
use fairway::{BSplineCurve, DVec2, DVec3, Geometry};

/// The plane 3D curves are drawn on in the 2D canvas (a View menu choice, saved with the document).
pub use fairway::io::ViewPlane;

/// The menu tooltip of a view plane.
pub fn plane_tip(p: ViewPlane) -> &'static str {
    match p {
        ViewPlane::Xy => "Draw curves on the XY plane (x right, y up): the view of 2D curves",
        ViewPlane::Yz => "Draw curves on the YZ plane (y right, z up)",
        ViewPlane::Zx => "Draw curves on the ZX plane (z right, x up)",
        ViewPlane::BestFit => {
            "Draw curves on the plane that fits their control points best (its longest extent to the right)"
        }
    }
}

/// The frame of plane `p` for the curves of `objects`.
pub fn plane_frame(p: ViewPlane, objects: &[Geometry]) -> Frame {
    match p {
        ViewPlane::Xy => Frame::XY,
        ViewPlane::Yz => Frame::new(DVec3::Y, DVec3::Z),
        ViewPlane::Zx => Frame::new(DVec3::Z, DVec3::X),
        ViewPlane::BestFit => best_fit_frame(objects),
    }
}

/// An orthonormal frame: the canvas shows a point `p` at `(p·e1, p·e2)`; `n = e1 × e2` is the depth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// To the right.
    pub e1: DVec3,
    /// Up.
    pub e2: DVec3,
    /// Towards the viewer.
    pub n: DVec3,
}

impl Default for Frame {
    fn default() -> Self {
        Frame::XY
    }
}

impl Frame {
    /// The XY plane (x right, y up).
    pub const XY: Frame = Frame {
        e1: DVec3::X,
        e2: DVec3::Y,
        n: DVec3::Z,
    };

    /// The frame with `e1` to the right and `e2` (made orthogonal to it) up.
    pub fn new(e1: DVec3, e2: DVec3) -> Self {
        let e1 = e1.normalize();
        let e2 = (e2 - e1 * e1.dot(e2)).normalize();
        Frame {
            e1,
            e2,
            n: e1.cross(e2),
        }
    }

    /// The point on the canvas.
    pub fn project(&self, p: DVec3) -> DVec2 {
        DVec2::new(p.dot(self.e1), p.dot(self.e2))
    }

    /// The curve turned into this frame (its plane becomes XY; the same parameter, lengths and
    /// curvature): what the canvas samples and draws (dropping z). The curve itself on the XY plane.
    pub fn curve_in(&self, c: &BSplineCurve) -> BSplineCurve {
        if *self == Frame::XY {
            return c.clone();
        }
        let pts: Vec<DVec3> = c
            .points()
            .iter()
            .map(|&p| DVec3::new(p.dot(self.e1), p.dot(self.e2), p.dot(self.n)))
            .collect();
        BSplineCurve::try_new(
            c.degree(),
            c.knots().values().to_vec(),
            pts,
            c.weights().map(<[f64]>::to_vec),
            3,
        )
        .unwrap_or_else(|_| c.clone())
    }
}

/// The least-squares plane of the curves' control points (the XY plane if every curve is 2D or
/// there are fewer than three points): its normal the covariance's smallest eigenvector, facing +z
/// where it can; the largest to the right.
fn best_fit_frame(objects: &[Geometry]) -> Frame {
    let curves: Vec<&BSplineCurve> = objects.iter().filter_map(Geometry::as_curve).collect();
    if curves.iter().all(|c| c.dim() == 2) {
        return Frame::XY;
    }
    let pts: Vec<DVec3> = curves.iter().flat_map(|c| c.points().iter().copied()).collect();
    if pts.len() < 3 {
        return Frame::XY;
    }
    let mean = pts.iter().copied().sum::<DVec3>() / pts.len() as f64;
    let mut a = [[0.0; 3]; 3];
    for p in &pts {
        let d = (*p - mean).to_array();
        for i in 0..3 {
            for j in 0..3 {
                a[i][j] += d[i] * d[j];
            }
        }
    }
    let (values, vectors) = fairway::linalg::symmetric_eigen3(a);
    let mut order = [0, 1, 2];
    order.sort_by(|&i, &j| values[j].total_cmp(&values[i]));
    let axis = |k: usize| DVec3::new(vectors[0][k], vectors[1][k], vectors[2][k]);
    let mut e1 = axis(order[0]);
    let mut n = axis(order[2]);
    if n.z < 0.0 || (n.z == 0.0 && n.x + n.y < 0.0) {
        n = -n;
    }
    if e1.x + e1.y + e1.z < 0.0 {
        e1 = -e1;
    }
    Frame::new(e1, n.cross(e1))
}

/// An object's name for lists and messages: its own, else "curve k" / "surface k" (1-based).
pub fn object_label(k: usize, name: &str, g: &Geometry) -> String {
    if name.trim().is_empty() {
        let kind = if g.as_curve().is_some() { "curve" } else { "surface" };
        format!("{kind} {}", k + 1)
    } else {
        name.trim().to_string()
    }
}

/// One curve of the document as the canvas draws it.
#[derive(Debug, Clone)]
pub struct SceneCurve {
    /// Its index among the document's objects.
    pub object: usize,
    /// Its label ([`object_label`]).
    pub label: String,
    /// Points along it, on the view plane.
    pub pts: Vec<DVec2>,
    /// The same points in space (for the 3D view).
    pub pts3: Vec<DVec3>,
}

/// A join between two curve ends, as the canvas marks it.
#[derive(Debug, Clone)]
pub struct JoinMark {
    /// The joint on the view plane.
    pub point: DVec2,
    /// The measured continuity.
    pub class: Continuity,
    /// The two ends (object, end).
    pub ends: [(usize, End); 2],
    /// The marker's text: "G2 join", with the two curves.
    pub label: String,
    /// Its measures: gap, tangent angle, curvature ratio and jump.
    pub detail: String,
}

/// A join as the 3D views mark it: a curve join's point, or a shared patch edge along its length.
#[derive(Debug, Clone)]
pub struct Mark3d {
    /// The joint (one point), or points along the shared edge.
    pub points: Vec<DVec3>,
    /// The measured continuity.
    pub class: Continuity,
    /// "G2 join: SECTA end – SECTB start", "G1 edge: surface 1 u1 – surface 2 u0".
    pub label: String,
    /// Its measures.
    pub detail: String,
}

/// Every curve of the document and their joins on the view plane.
#[derive(Debug, Clone, Default)]
pub struct SceneView {
    /// The chosen plane.
    pub plane: ViewPlane,
    /// Its frame.
    pub frame: Frame,
    /// The curves (the active one too), in document order.
    pub curves: Vec<SceneCurve>,
    /// The curve joins.
    pub joins: Vec<JoinMark>,
    /// The curve joins and the shared patch edges in space, for the 3D views.
    pub marks3d: Vec<Mark3d>,
    /// The joins as the core measured them (curves and shared patch edges).
    pub measured: Joins,
    /// Bounding box (min, max) of every curve's points on the view plane.
    pub bbox: Option<(DVec2, DVec2)>,
}

impl SceneView {
    /// The view of `objects` (named `names`) on `plane`.
    pub fn new(objects: &[Geometry], names: &[String], plane: ViewPlane) -> Self {
        let frame = plane_frame(plane, objects);
        let label = |k: usize| object_label(k, names.get(k).map_or("", String::as_str), &objects[k]);
        let curves: Vec<SceneCurve> = objects
            .iter()
            .enumerate()
            .filter_map(|(k, g)| {
                g.as_curve().map(|c| {
                    let pts3 = sample_curve(c);
                    SceneCurve {
                        object: k,
                        label: label(k),
                        pts: pts3.iter().map(|&p| frame.project(p)).collect(),
                        pts3,
                    }
                })
            })
            .collect();
        let measured = if objects.len() > 1 {
            find_joins(objects)
        } else {
            Joins::default()
        };
        let joins: Vec<JoinMark> = measured.curves.iter().map(|j| join_mark(j, &frame, &label)).collect();
        let marks3d = measured
            .curves
            .iter()
            .zip(&joins)
            .map(|(j, m)| Mark3d {
                points: vec![j.point],
                class: m.class,
                label: m.label.clone(),
                detail: m.detail.clone(),
            })
            .chain(measured.surfaces.iter().filter_map(|j| edge_mark(j, objects, &label)))
            .collect();
        let mut bbox: Option<(DVec2, DVec2)> = None;
        for p in curves.iter().flat_map(|c| c.pts.iter()) {
            let b = bbox.get_or_insert((*p, *p));
            *b = (b.0.min(*p), b.1.max(*p));
        }
        SceneView {
            plane,
            frame,
            curves,
            joins,
            marks3d,
            measured,
            bbox,
        }
    }

    /// The continuity of the joins at the start and the end of curve `object` (the strongest where
    /// several curves meet there); `None` at a free end.
    pub fn end_joins(&self, object: usize) -> [Option<Continuity>; 2] {
        let mut out = [None, None];
        for j in &self.joins {
            for (o, e) in j.ends {
                if o == object {
                    let slot = &mut out[usize::from(e == End::End)];
                    *slot = Some(slot.map_or(j.class, |c: Continuity| c.max(j.class)));
                }
            }
        }
        out
    }
}

/// Points along `c`: 32 per knot span (at most 2000).
fn sample_curve(c: &BSplineCurve) -> Vec<DVec3> {
    let bps = c.knots().breakpoints();
    let per = (2000 / bps.len().max(2)).clamp(4, 32);
    let mut pts = Vec::with_capacity(bps.len() * per);
    for w in bps.windows(2) {
        for i in 0..per {
            let u = w[0] + (w[1] - w[0]) * i as f64 / per as f64;
            pts.push(c.point(u));
        }
    }
    if let Some(&b) = bps.last() {
        pts.push(c.point(b));
    }
    pts
}

/// Points along an edge shared by two patches, drawn in the 3D views.
const EDGE_SAMPLES: usize = 48;

/// The 3D mark of a shared patch edge: points along it (on its first patch), its label and measures.
fn edge_mark(j: &SurfaceJoin, objects: &[Geometry], label: &impl Fn(usize) -> String) -> Option<Mark3d> {
    let edge = j.a.1.curve(objects.get(j.a.0)?.as_surface()?);
    let (t0, t1) = edge.domain();
    let c = &j.continuity;
    let g = c.class.name();
    Some(Mark3d {
        points: (0..=EDGE_SAMPLES)
            .map(|k| edge.point(t0 + (t1 - t0) * k as f64 / EDGE_SAMPLES as f64))
            .collect(),
        class: c.class,
        label: format!(
            "{g} edge: {} {} – {} {}",
            label(j.a.0),
            j.a.1.name(),
            label(j.b.0),
            j.b.1.name()
        ),
        detail: format!(
            "{g}: gap {:.2e}, normal angle {:.4}°, normal-curvature jump {:.2e}",
            c.gap,
            c.normal_angle.to_degrees(),
            c.curvature_jump
        ),
    })
}

/// The marker of a join: its label and measures.
fn join_mark(j: &CurveJoin, frame: &Frame, label: &impl Fn(usize) -> String) -> JoinMark {
    let c = &j.continuity;
    let g = c.class.name();
    JoinMark {
        point: frame.project(j.point),
        class: c.class,
        ends: [(j.a.object, j.a.end), (j.b.object, j.b.end)],
        label: format!(
            "{g} join: {} {} – {} {}",
            label(j.a.object),
            j.a.end.name(),
            label(j.b.object),
            j.b.end.name()
        ),
        detail: format!(
            "{g}: gap {:.2e}, tangent angle {:.4}°, curvature ratio {:.4} (jump {:.2e})",
            c.gap,
            c.angle.to_degrees(),
            c.curvature_ratio,
            c.curvature_jump
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn yz_arc() -> BSplineCurve {
        // a quarter circle in the plane x = 0.3
        let pts = vec![
            DVec3::new(0.3, 1.0, 0.0),
            DVec3::new(0.3, 1.0, 1.0),
            DVec3::new(0.3, 0.0, 1.0),
        ];
        BSplineCurve::try_new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            pts,
            Some(vec![1.0, 0.5f64.sqrt(), 1.0]),
            3,
        )
        .unwrap()
    }

    fn extent(v: &SceneView) -> DVec2 {
        let (a, b) = v.bbox.unwrap();
        b - a
    }

    #[test]
    fn a_curve_in_the_yz_plane_is_a_line_on_xy_and_a_quarter_circle_on_yz_and_best_fit() {
        let objects = vec![Geometry::Curve(yz_arc())];
        let names = vec![String::new()];
        let xy = SceneView::new(&objects, &names, ViewPlane::Xy);
        assert!(extent(&xy).x < 1e-12, "degenerate on XY: {:?}", extent(&xy));
        let yz = extent(&SceneView::new(&objects, &names, ViewPlane::Yz));
        assert!((yz.x - 1.0).abs() < 1e-9 && (yz.y - 1.0).abs() < 1e-9, "{yz:?}");
        // the best-fit plane is x = 0.3, its longest extent (the chord, √2) to the right
        let best = SceneView::new(&objects, &names, ViewPlane::BestFit);
        assert!((best.frame.n.x.abs() - 1.0).abs() < 1e-9, "{:?}", best.frame);
        let e = extent(&best);
        assert!((e.x - 2f64.sqrt()).abs() < 1e-9 && e.y > 0.29, "{e:?}");
        // the turned curve keeps its curvature (radius 1)
        let f = plane_frame(ViewPlane::Yz, &objects);
        let turned = f.curve_in(&yz_arc());
        assert!((turned.curvature(0.37) - 1.0).abs() < 1e-9);
        assert!(turned.points().iter().all(|p| (p.z - 0.3).abs() < 1e-12));
    }
}
