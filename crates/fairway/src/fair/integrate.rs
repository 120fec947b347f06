//! Twofold integration of a target curvature (paper §3.1, phases 2 and 3).
//!
//! In arc-length parameterization `T' = g N` and `x' = T`. Starting at one
//! end of the region with the original point and unit tangent, the samples
//! `x_k` (spacing `h`) are integrated from the left and from the right and
//! blended with the quintic weight `λ(t) = 6t⁵ − 15t⁴ + 10t³`
//! ([`super::target::quintic`]).
//!
//! Schemes ([`Integrator`]):
//! * `Euler` — the paper's first: `T ← T + h g_k N`, `x ← x + h T`
//!   (T is not renormalized, as in the paper);
//! * `Rk2` — the paper's second-order midpoint scheme, applied on every step:
//!   `T½ = T + (h/2) g_k N(T)`, `T ← T + h g_{k+½} N(T½)`, `x ← x + h T½`;
//! * `Arc` (default) — exact circular-arc steps for a curvature that is
//!   constant on each step (`θ = h (g_k + g_{k+1})/2`): the tangent turns by θ
//!   in the osculating plane spanned by (T, N), the point moves along the
//!   chord `h·sinc(θ/2)` at angle θ/2. Exact for circles and straight lines
//!   and second order in general, with |T| = 1 kept exactly.
//!
//! The normal N: in 2D the tangent turned by +90° (curvature signed); in 3D
//! the original's sign-consistent principal normal at the sample (see
//! [`super::curve`]), made orthogonal to the current tangent.
//!
//! Deviation control: the paper's pull-back `c = min[1, (|d|/m)²]·d`,
//! `d = f(p_k) − x_k`, is added to every new point. The paper corrects only
//! the position, so the tangent keeps drifting with the accumulated error;
//! with `correct_tangent` the tangent is pulled towards the original's
//! with the same weight (and renormalized).

use glam::DVec3;

use super::target::quintic;
use crate::error::Error;

/// Numerical integration scheme.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Integrator {
    /// Explicit Euler (paper's first scheme).
    Euler,
    /// Second-order Runge–Kutta, midpoint (paper's second scheme).
    Rk2,
    /// Exact circular-arc steps (default).
    #[default]
    Arc,
}

impl std::str::FromStr for Integrator {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s.to_ascii_lowercase().as_str() {
            "euler" => Ok(Self::Euler),
            "rk2" => Ok(Self::Rk2),
            "arc" => Ok(Self::Arc),
            _ => Err(Error::InvalidInput(format!(
                "unknown integrator {s:?}: expected euler, rk2 or arc"
            ))),
        }
    }
}

/// The original samples an integration follows.
#[derive(Debug, Clone, Copy)]
pub struct Track<'a> {
    /// Original points f(p_k).
    pub points: &'a [DVec3],
    /// Original unit tangents.
    pub tangents: &'a [DVec3],
    /// Unit normals (3D only; 2D uses the tangent turned by 90°).
    pub normals: &'a [DVec3],
    /// 2 or 3.
    pub dim: usize,
    /// Arc-length step h.
    pub h: f64,
}

/// Deviation control of an integration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PullBack {
    /// Band width m (≤ 0 or infinite: no pull-back).
    pub tolerance: f64,
    /// Also pull the tangent back (Fairway), not only the point (paper).
    pub correct_tangent: bool,
}

#[inline]
fn normal_of(t: DVec3, k: usize, tr: &Track<'_>) -> DVec3 {
    if tr.dim == 2 {
        let l = (t.x * t.x + t.y * t.y).sqrt();
        DVec3::new(-t.y / l, t.x / l, 0.0)
    } else {
        normal_of_unit(t.normalize(), tr.normals[k])
    }
}

/// The 3D normal at a unit tangent `tu`: the sample's normal `n` made orthogonal to `tu`.
#[inline]
fn normal_of_unit(tu: DVec3, n: DVec3) -> DVec3 {
    let m = n - tu * n.dot(tu);
    let l2 = m.length_squared();
    if l2 > 1e-24 {
        m * (1.0 / l2.sqrt())
    } else {
        tu.any_orthonormal_vector()
    }
}

/// `(sin(θ/2), cos(θ/2), sin(θ/2)/(θ/2))`. Arc steps turn by small angles (θ = h·g), where the
/// Taylor series to x⁹ / x⁸ (x = θ/2, |x| ≤ 0.05: truncation below 1e-17) is exact to rounding
/// and several times cheaper than `sin_cos`.
#[inline]
fn half_angle(th: f64) -> (f64, f64, f64) {
    let x = 0.5 * th;
    if x.abs() <= 0.05 {
        let x2 = x * x;
        // multiplications by the reciprocals: a division by a constant is not turned into one (it is
        // not exact), and eight dependent divisions per step were the integrator's largest cost
        const R: [f64; 8] = [
            1.0 / 6.0,
            1.0 / 20.0,
            1.0 / 42.0,
            1.0 / 72.0,
            1.0 / 2.0,
            1.0 / 12.0,
            1.0 / 30.0,
            1.0 / 56.0,
        ];
        let sinc = 1.0 - x2 * R[0] * (1.0 - x2 * R[1] * (1.0 - x2 * R[2] * (1.0 - x2 * R[3])));
        let c = 1.0 - x2 * R[4] * (1.0 - x2 * R[5] * (1.0 - x2 * R[6] * (1.0 - x2 * R[7])));
        (x * sinc, c, sinc)
    } else {
        let (s, c) = x.sin_cos();
        (s, c, s / x)
    }
}

/// One direction of an integration: its running point and tangent (module docs).
struct Walker {
    backward: bool,
    /// 2D: reversing the direction negates the signed curvature and the normal; g·N is unchanged
    /// when N is recomputed from the reversed tangent, so negate g. 3D normals are explicit.
    gs: f64,
    sgn: f64,
    x: DVec3,
    t: DVec3,
}

impl Walker {
    /// Start at the first sample of the direction, writing it into `xs`, `ts`.
    fn start(tr: &Track<'_>, n: usize, backward: bool, xs: &mut [DVec3], ts: &mut [DVec3]) -> Self {
        let gs = if backward && tr.dim == 2 { -1.0 } else { 1.0 };
        let sgn = if backward { -1.0 } else { 1.0 };
        let k0 = if backward { n - 1 } else { 0 };
        let (x, t) = (tr.points[k0], tr.tangents[k0] * sgn);
        xs[k0] = x;
        ts[k0] = t * sgn;
        Self {
            backward,
            gs,
            sgn,
            x,
            t,
        }
    }

    /// Step j → j + 1 of the direction, writing the new sample into `xs`, `ts`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn step(
        &mut self,
        tr: &Track<'_>,
        g: &[f64],
        scheme: Integrator,
        pull: PullBack,
        inv_m2: f64,
        j: usize,
        xs: &mut [DVec3],
        ts: &mut [DVec3],
    ) {
        let n = g.len();
        let (k, k1) = if self.backward {
            (n - 1 - j, n - 2 - j)
        } else {
            (j, j + 1)
        };
        let h = tr.h;
        let (ga, gb) = (self.gs * g[k], self.gs * g[k1]);
        let (mut x, mut t) = (self.x, self.t);
        match scheme {
            Integrator::Euler => {
                let nn = normal_of(t, k, tr);
                let tn = t + nn * (h * ga);
                x += t * h;
                t = tn;
            }
            Integrator::Rk2 => {
                let nn = normal_of(t, k, tr);
                let th = t + nn * (0.5 * h * ga);
                let nm = normal_of(th, if tr.dim == 2 { k } else { k1 }, tr);
                let tn = t + nm * (h * 0.5 * (ga + gb));
                x += th * h;
                t = tn;
            }
            Integrator::Arc => {
                // arc steps and the tangent pull-back keep |t| = 1 (to rounding): no renormalization
                let tu = t;
                let nn = if tr.dim == 2 {
                    DVec3::new(-tu.y, tu.x, 0.0)
                } else {
                    normal_of_unit(tu, tr.normals[k])
                };
                let th = h * 0.5 * (ga + gb);
                let (s2, c2, sinc) = half_angle(th);
                // double angle: sin θ = 2 sin(θ/2) cos(θ/2), cos θ = 1 − 2 sin²(θ/2)
                let (s, c) = (2.0 * s2 * c2, 1.0 - 2.0 * s2 * s2);
                x += (tu * c2 + nn * s2) * (h * sinc);
                t = tu * c + nn * s;
            }
        }
        let m = pull.tolerance;
        if m > 0.0 && m.is_finite() {
            let d = tr.points[k1] - x;
            let w = (d.length_squared() * inv_m2).min(1.0);
            x += d * w;
            if pull.correct_tangent && w > 0.0 {
                let to = tr.tangents[k1] * self.sgn;
                let tl = t.length();
                let tn = t + (to * tl - t) * w;
                t = tn * (tl / tn.length());
            }
        }
        xs[k1] = x;
        if scheme != Integrator::Arc {
            ts[k1] = t.normalize() * self.sgn;
        } else {
            ts[k1] = t * self.sgn;
        }
        (self.x, self.t) = (x, t);
    }
}

/// Integrate forward over all samples (dir = +1) or backward (dir = −1),
/// writing points and unit tangents (in the forward direction) into `xs`, `ts`.
pub fn integrate_one(
    tr: &Track<'_>,
    g: &[f64],
    scheme: Integrator,
    pull: PullBack,
    backward: bool,
    xs: &mut [DVec3],
    ts: &mut [DVec3],
) {
    let n = g.len();
    let inv_m2 = 1.0 / (pull.tolerance * pull.tolerance);
    let mut w = Walker::start(tr, n, backward, xs, ts);
    for j in 0..n - 1 {
        w.step(tr, g, scheme, pull, inv_m2, j, xs, ts);
    }
}

/// Both directions of [`integrate_one`] in one loop: two independent dependency chains per step,
/// which the processor overlaps (each step is a serial chain of square roots and divisions).
#[allow(clippy::too_many_arguments)]
fn integrate_both(
    tr: &Track<'_>,
    g: &[f64],
    scheme: Integrator,
    pull: PullBack,
    fx: &mut [DVec3],
    ft: &mut [DVec3],
    bx: &mut [DVec3],
    bt: &mut [DVec3],
) {
    let n = g.len();
    let inv_m2 = 1.0 / (pull.tolerance * pull.tolerance);
    let mut f = Walker::start(tr, n, false, fx, ft);
    let mut b = Walker::start(tr, n, true, bx, bt);
    for j in 0..n - 1 {
        f.step(tr, g, scheme, pull, inv_m2, j, fx, ft);
        b.step(tr, g, scheme, pull, inv_m2, j, bx, bt);
    }
}

/// Scratch buffers of [`integrate_blended`].
#[derive(Debug, Clone, Default)]
pub struct IntegrationScratch {
    left: Vec<DVec3>,
    left_t: Vec<DVec3>,
    right: Vec<DVec3>,
    right_t: Vec<DVec3>,
}

/// Integrate from both ends and blend with the quintic weight of
/// `t = k/(n−1)` (paper §3.1 phase 3). Writes the blended points and unit
/// tangents into `xs`, `ts` (resized to n).
pub fn integrate_blended(
    tr: &Track<'_>,
    g: &[f64],
    scheme: Integrator,
    pull: PullBack,
    scratch: &mut IntegrationScratch,
    xs: &mut Vec<DVec3>,
    ts: &mut Vec<DVec3>,
) {
    let n = g.len();
    for v in [
        &mut scratch.left,
        &mut scratch.left_t,
        &mut scratch.right,
        &mut scratch.right_t,
    ] {
        v.clear();
        v.resize(n, DVec3::ZERO);
    }
    integrate_both(
        tr,
        g,
        scheme,
        pull,
        &mut scratch.left,
        &mut scratch.left_t,
        &mut scratch.right,
        &mut scratch.right_t,
    );
    xs.clear();
    ts.clear();
    for k in 0..n {
        let w = quintic(k as f64 / (n - 1) as f64);
        xs.push(scratch.left[k] * (1.0 - w) + scratch.right[k] * w);
        let t = scratch.left_t[k] * (1.0 - w) + scratch.right_t[k] * w;
        ts.push(t.normalize_or(tr.tangents[k]));
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn half_angle_matches_sin_cos() {
        for k in -400..=400 {
            let th = k as f64 * 2.6e-4; // up to 0.104: both branches
            let (s, c, sinc) = super::half_angle(th);
            let (s0, c0) = (0.5 * th).sin_cos();
            assert!((s - s0).abs() <= 2e-17 + 1e-15 * s0.abs(), "{th}: {s} {s0}");
            assert!((c - c0).abs() <= 1e-16, "{th}: {c} {c0}");
            if th != 0.0 {
                assert!((sinc - s0 / (0.5 * th)).abs() <= 1e-15, "{th}");
            } else {
                assert_eq!(sinc, 1.0);
            }
        }
    }

    use super::*;

    fn circle(n: usize, r: f64, arc: f64) -> (Vec<DVec3>, Vec<DVec3>, Vec<DVec3>, f64) {
        let h = r * arc / (n - 1) as f64;
        let mut p = vec![];
        let mut t = vec![];
        let mut nn = vec![];
        for k in 0..n {
            let a = arc * k as f64 / (n - 1) as f64;
            p.push(DVec3::new(r * a.cos(), r * a.sin(), 0.0));
            t.push(DVec3::new(-a.sin(), a.cos(), 0.0));
            nn.push(DVec3::new(-a.cos(), -a.sin(), 0.0));
        }
        (p, t, nn, h)
    }

    #[test]
    fn schemes_reproduce_a_circle_with_their_order() {
        for dim in [2, 3] {
            let (p, t, nn, h) = circle(101, 2.0, 1.5);
            let tr = Track {
                points: &p,
                tangents: &t,
                normals: &nn,
                dim,
                h,
            };
            let g = vec![0.5; 101];
            let none = PullBack {
                tolerance: 0.0,
                correct_tangent: false,
            };
            let mut xs = vec![DVec3::ZERO; 101];
            let mut ts = vec![DVec3::ZERO; 101];
            let mut errs = vec![];
            for s in [Integrator::Euler, Integrator::Rk2, Integrator::Arc] {
                integrate_one(&tr, &g, s, none, false, &mut xs, &mut ts);
                let e = xs.iter().zip(&p).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
                errs.push(e);
                // backward too
                integrate_one(&tr, &g, s, none, true, &mut xs, &mut ts);
                let eb = xs.iter().zip(&p).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
                assert!((eb - e).abs() < 1e-3 + e, "{s:?} {e} {eb}");
            }
            assert!(errs[0] > 1e-3 && errs[0] < 0.1, "euler {errs:?}");
            assert!(errs[1] < errs[0] / 10.0, "rk2 {errs:?}");
            assert!(errs[2] < 1e-12, "arc {errs:?}");
        }
    }

    #[test]
    fn pull_back_keeps_points_near() {
        let (p, t, nn, h) = circle(201, 1.0, 3.0);
        let tr = Track {
            points: &p,
            tangents: &t,
            normals: &nn,
            dim: 2,
            h,
        };
        let g = vec![0.8; 201]; // wrong curvature
        let mut xs = vec![];
        let mut ts = vec![];
        let mut sc = IntegrationScratch::default();
        let free = PullBack {
            tolerance: 0.0,
            correct_tangent: false,
        };
        integrate_blended(&tr, &g, Integrator::Arc, free, &mut sc, &mut xs, &mut ts);
        let e0 = xs.iter().zip(&p).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
        let pulled = PullBack {
            tolerance: 0.01,
            correct_tangent: true,
        };
        integrate_blended(&tr, &g, Integrator::Arc, pulled, &mut sc, &mut xs, &mut ts);
        let e1 = xs.iter().zip(&p).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
        assert!(e0 > 0.05, "{e0}");
        assert!(e1 < 0.02, "{e1}");
        assert_eq!(xs[0], p[0]);
        assert!((xs[200] - p[200]).length() < 1e-12);
    }
}
