//! Step 0 of the default fair (module docs of `fair::surface`): a **pole** (a boundary row whose control
//! points coincide: the apex of a dome, the pole of a surface of revolution, the collapsed side of a
//! triangular patch) is made smooth before the fair, instead of being held with its noise.
//!
//! The fair holds the pole row and the two after it ([`POLE_ROWS`]): they fix the pole's position,
//! tangent plane and curvature. Held as they come, a noisy first ring makes the pole a low cone — the
//! surface has no tangent plane there, the mean curvature grows like 1/r towards it and `∫∫|∇H|²` is
//! dominated by it (the suite's apex dome: 4.67·10⁹ where the same dome with a smooth pole has 10³), a
//! highlight that pinches into the apex. This step moves the first ring (the row after the pole) into
//! its least-squares plane through the pole — the tangent plane: the surface is then G1 there — and the
//! second ring along that plane's normal onto the least-squares quadratic form of its in-plane
//! positions (a height `½(a x² + 2b xy + c y²)` over the tangent plane, with no linear or constant part:
//! the condition for the curvature at the pole to be a quadratic form, i.e. G2). The pole point stays.
//!
//! A pole whose first ring rises more than [`POLE_TIP_DEG`] out of its plane is a tip the design has (a
//! cone, a nose), not noise, and is left as it is. The step uses at most [`POLE_BAND_SHARE`] of the band
//! (its sound bound, [`crate::fair::verify::surface_band_bound`]; where the full step needs more, it is
//! taken part of the way), the fair the rest. The caller fairs both the original and the pole-smoothed
//! surface and keeps the pole route only where it is no less fair on both measures.

use glam::DVec3;

use super::isocurves::{POLE_ROWS, collapsed, net_size};
use crate::error::Result;
use crate::fit_surface::free_range;
use crate::surface::BSplineSurface;

/// Largest angle (degrees) by which a pole's first ring may rise out of its least-squares plane for the
/// pole to be taken as a smooth point with noise; above it the pole is a tip of the design and stays.
pub(crate) const POLE_TIP_DEG: f64 = 5.0;

/// Share of the band the pole step may use (its sound bound); the fair gets the rest.
pub(crate) const POLE_BAND_SHARE: f64 = 0.5;

/// A boundary side of the control net: the pole row is row 0 counted from that side.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Side {
    UStart,
    UEnd,
    VStart,
    VEnd,
}

impl Side {
    const ALL: [Side; 4] = [Side::UStart, Side::UEnd, Side::VStart, Side::VEnd];

    /// (rows away from the side, points along a row) on a `nu × nv` net.
    fn counts(self, nu: usize, nv: usize) -> (usize, usize) {
        match self {
            Side::UStart | Side::UEnd => (nu, nv),
            Side::VStart | Side::VEnd => (nv, nu),
        }
    }

    /// Index into the net of point `k` of row `row` (row 0 on this side).
    fn index(self, nu: usize, nv: usize, row: usize, k: usize) -> usize {
        match self {
            Side::UStart => row * nv + k,
            Side::UEnd => (nu - 1 - row) * nv + k,
            Side::VStart => k * nv + row,
            Side::VEnd => k * nv + (nv - 1 - row),
        }
    }

    fn name(self) -> &'static str {
        match self {
            Side::UStart => "u = start",
            Side::UEnd => "u = end",
            Side::VStart => "v = start",
            Side::VEnd => "v = end",
        }
    }
}

/// The pole-smoothed surface, its sound deviation bound from the original and what was done.
pub(super) struct PoleStep {
    pub surface: BSplineSurface,
    /// Sound upper bound of its distance from the original (≤ [`POLE_BAND_SHARE`] × m).
    pub bound: f64,
    /// Whether rows (u) / columns (v) next to a pole moved: they count as free in the result.
    pub moved_u: bool,
    pub moved_v: bool,
    pub notes: Vec<String>,
}

/// The poles of polynomial `s` inside `region` (the whole of the pole's ring and its [`POLE_ROWS`]
/// rows must be free) made smooth within [`POLE_BAND_SHARE`] × `m`; `None` if there is no such pole or
/// nothing to move. Tips (module docs) are listed in `tips` with their angle.
pub(super) fn smoothed_poles(
    s: &BSplineSurface,
    region: Option<((f64, f64), (f64, f64))>,
    m: f64,
    tips: &mut Vec<String>,
) -> Result<Option<PoleStep>> {
    let (nu, nv) = (s.nu(), s.nv());
    let size = net_size(s);
    let ((du0, du1), (dv0, dv1)) = s.domain();
    let ((u1, u2), (v1, v2)) = region.unwrap_or(((du0, du1), (dv0, dv1)));
    let (fu, fv) = (free_range(s.knots_u(), u1, u2), free_range(s.knots_v(), v1, v2));
    let mut pts = s.points().to_vec();
    let (mut moved_u, mut moved_v, mut done) = (false, false, Vec::new());
    for side in Side::ALL {
        let (rows, along) = side.counts(nu, nv);
        let (reach, across) = match side {
            Side::UStart => (fu.start == 0, fv.clone()),
            Side::UEnd => (fu.end == nu, fv.clone()),
            Side::VStart => (fv.start == 0, fu.clone()),
            Side::VEnd => (fv.end == nv, fu.clone()),
        };
        let at = |row: usize, k: usize| side.index(nu, nv, row, k);
        if rows < 2 * POLE_ROWS || !reach || across != (0..along) {
            continue;
        }
        if !collapsed((0..along).map(|k| pts[at(0, k)]), size) {
            continue;
        }
        let ring: Vec<DVec3> = (0..along).map(|k| pts[at(1, k)]).collect();
        let second: Vec<DVec3> = (0..along).map(|k| pts[at(2, k)]).collect();
        let Some(smooth) = smooth_pole(pts[at(0, 0)], &ring, &second) else {
            continue;
        };
        if smooth.tip_deg > POLE_TIP_DEG {
            tips.push(format!(
                "pole at {}: kept as it is, a tip — its first ring rises {:.1}° out of its plane (above \
                 {POLE_TIP_DEG}°)",
                side.name(),
                smooth.tip_deg
            ));
            continue;
        }
        for k in 0..along {
            pts[at(1, k)] = smooth.ring[k];
            pts[at(2, k)] = smooth.second[k];
        }
        match side {
            Side::UStart | Side::UEnd => moved_u = true,
            Side::VStart | Side::VEnd => moved_v = true,
        }
        done.push((side, smooth.tip_deg));
    }
    if done.is_empty() {
        return Ok(None);
    }
    let full = s.with_points(pts)?;
    let Some(b1) = crate::fair::verify::surface_band_bound(s, &full, m) else {
        return Ok(None);
    };
    // a pole already smooth (a surface of revolution whose profile meets the axis square) is left alone
    if !(b1 > 1e-6 * m) {
        return Ok(None);
    }
    let t = (POLE_BAND_SHARE * m / b1).min(1.0);
    let surface = if t < 1.0 {
        let stepped: Vec<DVec3> = (s.points().iter().zip(full.points()))
            .map(|(&a, &f)| a + t * (f - a))
            .collect();
        s.with_points(stepped)?
    } else {
        full
    };
    let Some(bound) = crate::fair::verify::surface_band_bound(s, &surface, m) else {
        return Ok(None);
    };
    let notes = done
        .iter()
        .map(|(side, deg)| {
            format!(
                "pole at {}: made smooth before the fair (its first ring, {deg:.2}° out of plane, moved into \
                 the tangent plane, the second ring onto a quadratic height over it){}; the pole step moved the \
                 surface ≤ {bound:.3e}, the fair had the rest of the band",
                side.name(),
                if t < 1.0 {
                    format!(", {:.0} % of the way (the band allowed no more)", 100.0 * t)
                } else {
                    String::new()
                }
            )
        })
        .collect();
    Ok(Some(PoleStep {
        surface,
        bound,
        moved_u,
        moved_v,
        notes,
    }))
}

/// The smoothed first and second rings of a pole at `apex`, and how far (degrees) the first ring rose
/// out of its plane; `None` if the ring spans no plane (all on a line through the apex, or collapsed).
struct SmoothPole {
    ring: Vec<DVec3>,
    second: Vec<DVec3>,
    tip_deg: f64,
}

fn smooth_pole(apex: DVec3, ring: &[DVec3], second: &[DVec3]) -> Option<SmoothPole> {
    // the tangent plane: the least-squares plane through the apex of the first ring
    let mut cov = [[0.0; 3]; 3];
    for p in ring {
        let d = (*p - apex).to_array();
        for (i, row) in cov.iter_mut().enumerate() {
            for (j, c) in row.iter_mut().enumerate() {
                *c += d[i] * d[j];
            }
        }
    }
    let (values, vectors) = crate::linalg::symmetric_eigen3(cov);
    let mut order = [0, 1, 2];
    order.sort_by(|&i, &j| values[i].total_cmp(&values[j]));
    let axis = |k: usize| DVec3::new(vectors[0][k], vectors[1][k], vectors[2][k]);
    // the plane must be spanned: the middle eigenvalue well above the smallest
    if !(values[order[1]] > 1e-6 * values[order[2]]) {
        return None;
    }
    let n = axis(order[0]).normalize_or_zero();
    let (e1, e2) = (axis(order[2]).normalize_or_zero(), axis(order[1]).normalize_or_zero());
    if n == DVec3::ZERO || e1 == DVec3::ZERO || e2 == DVec3::ZERO {
        return None;
    }
    let tip_deg = ring
        .iter()
        .filter_map(|p| {
            let d = *p - apex;
            let l = d.length();
            (l > 0.0).then(|| (d.dot(n).abs() / l).clamp(0.0, 1.0).asin().to_degrees())
        })
        .fold(0.0, f64::max);
    let new_ring: Vec<DVec3> = ring.iter().map(|p| *p - n * (*p - apex).dot(n)).collect();
    // the second ring's heights over the plane: the least-squares form ½(a x² + 2b xy + c y²)
    let local: Vec<(f64, f64, f64)> = second
        .iter()
        .map(|p| {
            let d = *p - apex;
            (d.dot(e1), d.dot(e2), d.dot(n))
        })
        .collect();
    let mut normal = [[0.0; 3]; 3];
    let mut rhs = [0.0; 3];
    for &(x, y, z) in &local {
        let f = [0.5 * x * x, x * y, 0.5 * y * y];
        for i in 0..3 {
            rhs[i] += f[i] * z;
            for j in 0..3 {
                normal[i][j] += f[i] * f[j];
            }
        }
    }
    let q = solve3(normal, rhs)?;
    let new_second = second
        .iter()
        .zip(&local)
        .map(|(p, &(x, y, z))| *p + n * (0.5 * q[0] * x * x + q[1] * x * y + 0.5 * q[2] * y * y - z))
        .collect();
    Some(SmoothPole {
        ring: new_ring,
        second: new_second,
        tip_deg,
    })
}

/// The solution of the symmetric positive semi-definite 3×3 system `a x = b` by its eigen-decomposition,
/// `None` if it is singular (the second ring's in-plane positions do not determine a quadratic form).
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let (values, vectors) = crate::linalg::symmetric_eigen3(a);
    let top = values.iter().fold(0.0f64, |x, &v| x.max(v.abs()));
    let mut x = [0.0; 3];
    for k in 0..3 {
        if !(values[k].abs() > 1e-10 * top) {
            return None;
        }
        let vb: f64 = (0..3).map(|i| vectors[i][k] * b[i]).sum();
        for (i, xi) in x.iter_mut().enumerate() {
            *xi += vectors[i][k] * vb / values[k];
        }
    }
    Some(x)
}
