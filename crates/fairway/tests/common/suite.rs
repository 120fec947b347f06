//! The fairness quality suite: curves of known shape (2D and 3D, open and closed, degrees 2 to 5,
//! 28 to 300 control points), made noisy the way scanned or hand-digitized data is — noisy samples
//! fitted by least squares, or noisy control points of a closed periodic cubic — each with its noise σ.
//! Shared by the quality tests (`tests/quality.rs`) and `examples/quality_table.rs`.

#![allow(dead_code)]

use fairway::fit::{Smoothing, fit_curve_points};
use fairway::{BSplineCurve, DVec3, KnotVector};

/// One curve of the suite.
pub struct Case {
    /// Short name.
    pub name: &'static str,
    /// The noisy curve.
    pub curve: BSplineCurve,
    /// The noise σ it was made with.
    pub sigma: f64,
}

/// The tolerances of each case, as multiples of its σ.
pub const TOLERANCE_FACTORS: [f64; 3] = [1.0, 3.0, 10.0];

/// A small deterministic generator (xorshift64*, Box–Muller).
struct Rng(u64);

impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn gauss(&mut self) -> f64 {
        let (a, b) = (self.uniform(), self.uniform());
        (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
    }
    fn vec(&mut self, dim: usize) -> DVec3 {
        let z = if dim == 3 { self.gauss() } else { 0.0 };
        DVec3::new(self.gauss(), self.gauss(), z)
    }
}

/// Points of a planar curve given by its curvature κ(s) over [0, length], by midpoint steps.
pub fn from_curvature(length: f64, kappa: impl Fn(f64) -> f64) -> impl Fn(f64) -> DVec3 {
    let m = 20_000;
    let ds = length / m as f64;
    let (mut x, mut ang) = (DVec3::ZERO, 0.0);
    let mut pts = vec![x];
    for k in 0..m {
        let s = (k as f64 + 0.5) * ds;
        let a = ang + 0.5 * kappa(s) * ds;
        x += DVec3::new(a.cos(), a.sin(), 0.0) * ds;
        ang += kappa(s) * ds;
        pts.push(x);
    }
    move |t: f64| {
        let f = t.clamp(0.0, 1.0) * m as f64;
        let i = (f.floor() as usize).min(m - 1);
        pts[i].lerp(pts[i + 1], f - i as f64)
    }
}

/// Noisy samples (12 per control point, the ends exact) of `shape` on t ∈ [0, 1], fitted by least squares
/// with the given knots; sample k at t = warp(k / (n − 1)), taken as its parameter too.
pub fn fitted(shape: &dyn Fn(f64) -> DVec3, dim: usize, knots: KnotVector, sigma: f64, seed: u64) -> BSplineCurve {
    fitted_warped(shape, dim, knots, sigma, seed, &|t| t)
}

fn fitted_warped(
    shape: &dyn Fn(f64) -> DVec3,
    dim: usize,
    knots: KnotVector,
    sigma: f64,
    seed: u64,
    warp: &dyn Fn(f64) -> f64,
) -> BSplineCurve {
    let p = knots.degree();
    let n = knots.n_points();
    let ns = 12 * n;
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let params: Vec<f64> = (0..ns).map(|k| warp(k as f64 / (ns - 1) as f64)).collect();
    let (u0, u1) = knots.domain();
    let data: Vec<DVec3> = params
        .iter()
        .enumerate()
        .map(|(k, &t)| {
            let q = shape(t);
            if k == 0 || k + 1 == ns {
                q
            } else {
                q + rng.vec(dim) * sigma
            }
        })
        .collect();
    let us: Vec<f64> = params.iter().map(|t| u0 + (u1 - u0) * t).collect();
    let cp = fit_curve_points(&knots, &us, &data, None, Smoothing::NONE, &[]).expect("suite fit");
    BSplineCurve::try_new(p, knots.values().to_vec(), cp, None, dim).expect("suite curve")
}

/// A closed uniform periodic cubic (written clamped) whose n control points are samples of the closed
/// `shape` (t ∈ [0, 1)) plus noise.
pub fn periodic(shape: &dyn Fn(f64) -> DVec3, dim: usize, n: usize, sigma: f64, seed: u64) -> BSplineCurve {
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let q: Vec<DVec3> = (0..n)
        .map(|j| shape(j as f64 / n as f64) + rng.vec(dim) * sigma)
        .collect();
    fairway::fair::closed::periodic_cubic(&q, dim).expect("suite closed curve")
}

pub fn uniform(p: usize, n: usize) -> KnotVector {
    KnotVector::uniform(p, n).expect("uniform knots")
}

/// Knots clustered towards the start: interior knots at (i/n)².
fn clustered(p: usize, n: usize) -> KnotVector {
    let inner = n - p - 1;
    let mut v = vec![0.0; p + 1];
    v.extend((1..=inner).map(|i| (i as f64 / (inner + 1) as f64).powi(2)));
    v.extend(vec![1.0; p + 1]);
    KnotVector::try_new(v, p, n, "knots").expect("clustered knots")
}

/// NACA 0012 section from the trailing edge over the upper side, the sharp leading edge and back along
/// the lower side: x = u², so that the leading edge (u = 0) is resolved.
fn naca0012(t: f64) -> DVec3 {
    let u = 2.0 * t - 1.0;
    let x = u * u;
    let a = u.abs();
    let yt = 5.0 * 0.12 * (0.2969 * a - 0.1260 * x - 0.3516 * x * x + 0.2843 * x * x * x - 0.1036 * x * x * x * x);
    DVec3::new(x, yt * u.signum(), 0.0)
}

/// The suite (see the module docs); every curve with its σ.
pub fn cases() -> Vec<Case> {
    cases_with_noise(1.0)
}

/// [`cases`] with the noise scaled by `scale` (0: the noise-free best fits on the same knots, which show
/// what the knots themselves allow); `sigma` stays the nominal one, so the tolerances do not change.
pub fn cases_with_noise(scale: f64) -> Vec<Case> {
    cases_seeded(scale, 0)
}

/// [`cases_with_noise`] with other noise draws: draw `draw` (0 is the suite's own) gives each case a
/// different seed, so the same shapes and knots with noise no test has seen.
pub fn cases_seeded(scale: f64, draw: u64) -> Vec<Case> {
    use std::f64::consts::{PI, TAU};
    let seed = |k: u64| k + 1000 * draw;
    let roof = from_curvature(3.0, |s| {
        0.25 + 2.2 * (-((s - 0.45) / 0.18).powi(2)).exp() + 1.6 * (-((s - 2.55) / 0.2).powi(2)).exp()
    });
    let clothoid = from_curvature(2.0, |s| s);
    let circle = |t: f64| DVec3::new((2.0 * t).cos(), (2.0 * t).sin(), 0.0);
    let ellipse = |t: f64| DVec3::new(2.0 * (2.5 * t).cos(), (2.5 * t).sin(), 0.0);
    let helix = |t: f64| DVec3::new((2.0 * TAU * t).cos(), (2.0 * TAU * t).sin(), 2.0 * t);
    let spiral = |t: f64| {
        let r = 1.0 - 0.6 * t;
        DVec3::new(r * (3.0 * TAU * t).cos(), r * (3.0 * TAU * t).sin(), 1.5 * t)
    };
    let shoulder = |t: f64| {
        DVec3::new(
            3.0 * t,
            0.3 * (TAU * t).sin() + 0.1 * t * t,
            0.4 * t * t - 0.2 * (3.0 * PI * t).sin(),
        )
    };
    let space = |t: f64| DVec3::new(2.0 * t, 0.4 * (PI * t).sin(), 0.3 * (2.0 * PI * t).cos() * t);
    let blob = |t: f64| {
        let th = TAU * t;
        let r = 1.0 + 0.15 * (3.0 * th).cos() + 0.05 * (5.0 * th).sin();
        DVec3::new(r * th.cos(), 0.8 * r * th.sin(), 0.0)
    };
    let trefoil = |t: f64| {
        let th = TAU * t;
        DVec3::new(
            th.sin() + 2.0 * (2.0 * th).sin(),
            th.cos() - 2.0 * (2.0 * th).cos(),
            -(3.0 * th).sin(),
        ) / 3.0
    };
    let s_curve = |t: f64| DVec3::new(2.0 * t, 0.3 * (TAU * t).sin(), 0.0);
    let sine = |t: f64| DVec3::new(2.0 * t, 0.2 * (3.0 * PI * t).sin(), 0.0);
    let long_wave = |t: f64| DVec3::new(10.0 * t, 0.3 * (6.0 * PI * t).sin() + 0.2 * (TAU * t).sin(), 0.0);
    // dense knots (and data) where the curve turns fastest, as on a CAD edge with a tight end
    let parabola = |t: f64| DVec3::new(t, 0.3 * (8.0 * t).atan() + 0.2 * t * t, 0.0);
    let tanh_s = |t: f64| DVec3::new(2.0 * t, 0.25 * (6.0 * (t - 0.5)).tanh(), 0.0);
    let sigma = 1e-3;
    vec![
        Case {
            name: "circle_arc",
            curve: fitted(&circle, 2, uniform(3, 40), scale * sigma, seed(1)),
            sigma,
        },
        Case {
            name: "ellipse_arc",
            curve: fitted(&ellipse, 2, uniform(3, 50), scale * sigma, seed(2)),
            sigma,
        },
        Case {
            name: "clothoid",
            curve: fitted(&clothoid, 2, uniform(3, 40), scale * sigma, seed(3)),
            sigma,
        },
        Case {
            name: "car_roof",
            curve: fitted(&roof, 2, uniform(3, 50), scale * 2.0 * sigma, seed(4)),
            sigma: 2.0 * sigma,
        },
        Case {
            name: "airfoil",
            curve: fitted(&naca0012, 2, uniform(3, 80), scale * 2e-4, seed(5)),
            sigma: 2e-4,
        },
        Case {
            name: "s_curve_inflections",
            curve: fitted(&tanh_s, 2, uniform(3, 28), scale * sigma, seed(6)),
            sigma,
        },
        Case {
            name: "quadratic_s",
            curve: fitted(&s_curve, 2, uniform(2, 30), scale * sigma, seed(7)),
            sigma,
        },
        Case {
            name: "quartic_sine",
            curve: fitted(&sine, 2, uniform(4, 50), scale * sigma, seed(8)),
            sigma,
        },
        Case {
            name: "quintic_ellipse",
            curve: fitted(&ellipse, 2, uniform(5, 40), scale * sigma, seed(9)),
            sigma,
        },
        Case {
            name: "long_wave_300",
            curve: fitted(&long_wave, 2, uniform(3, 300), scale * 2.0 * sigma, seed(10)),
            sigma: 2.0 * sigma,
        },
        Case {
            name: "clustered_knots",
            curve: fitted_warped(&parabola, 2, clustered(3, 40), scale * 5e-5, seed(11), &|t| t * t),
            sigma: 5e-5,
        },
        Case {
            name: "closed_blob",
            curve: periodic(&blob, 2, 60, scale * sigma, seed(12)),
            sigma,
        },
        Case {
            name: "helix",
            curve: fitted(&helix, 3, uniform(3, 60), scale * sigma, seed(13)),
            sigma,
        },
        Case {
            name: "conical_spiral",
            curve: fitted(&spiral, 3, uniform(3, 60), scale * sigma, seed(14)),
            sigma,
        },
        Case {
            name: "shoulder_3d",
            curve: fitted(&shoulder, 3, uniform(3, 36), scale * 2.0 * sigma, seed(15)),
            sigma: 2.0 * sigma,
        },
        Case {
            name: "space_quartic",
            curve: fitted(&space, 3, uniform(4, 40), scale * sigma, seed(16)),
            sigma,
        },
        Case {
            name: "closed_trefoil",
            curve: periodic(&trefoil, 3, 90, scale * sigma, seed(17)),
            sigma,
        },
    ]
}

/// A splitmix64 generator for [`unseen_shape`].
struct Mix(u64);

impl Mix {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.uniform()
    }
}

/// Shape `k` of a family no test was tuned on: a planar curve from a random curvature profile (a base
/// plus 1–4 Gaussian bumps of either sign) or a 3D curve of a few random Fourier terms, degree 2–5, 20–149
/// control points, noisy as the suite's curves are (σ between 2·10⁻⁴ and 3·10⁻³); with its σ.
pub fn unseen_shape(k: u64) -> Case {
    let mut rng = Mix(k * 7919 + 17);
    let p = 2 + (rng.uniform() * 4.0) as usize;
    let n = 20 + (rng.uniform() * 130.0) as usize;
    let dim = if rng.uniform() < 0.35 { 3 } else { 2 };
    let sigma = 10f64.powf(rng.range(-3.7, -2.5));
    let curve = if dim == 2 {
        let len = rng.range(1.5, 5.0);
        let base = rng.range(-0.5, 0.8);
        let bumps: Vec<(f64, f64, f64)> = (0..1 + (rng.uniform() * 4.0) as usize)
            .map(|_| (rng.range(0.0, len), rng.range(0.08, 0.6), rng.range(-2.5, 2.5)))
            .collect();
        let shape = from_curvature(len, move |s| {
            base + bumps
                .iter()
                .map(|(c, w, a)| a * (-((s - c) / w).powi(2)).exp())
                .sum::<f64>()
        });
        fitted(&shape, 2, uniform(p, n), sigma, k + 1)
    } else {
        let c: Vec<[f64; 6]> = (0..3).map(|_| std::array::from_fn(|_| rng.range(-0.5, 0.5))).collect();
        let f = rng.range(0.5, 2.0);
        let shape = move |t: f64| {
            let w = std::f64::consts::TAU * f * t;
            let comp = |a: &[f64; 6]| a[0] * w.sin() + a[1] * w.cos() + a[2] * (2.0 * w).sin() + a[3] * (3.0 * w).cos();
            DVec3::new(2.0 * t + comp(&c[0]), comp(&c[1]), comp(&c[2]))
        };
        fitted(&shape, 3, uniform(p, n), sigma, k + 1)
    };
    Case {
        name: "unseen",
        curve,
        sigma,
    }
}

/// Closed shape `k` of a family no test was tuned on: a periodic cubic through noisy points of a random
/// star-shaped outline (radius 1 plus harmonics 2–5), planar or lifted into 3D by random harmonics, 30–119
/// control points, σ between 2·10⁻⁴ and 3·10⁻³; with its σ.
pub fn unseen_closed_shape(k: u64) -> Case {
    let mut rng = Mix(k * 104_729 + 3);
    let n = 30 + (rng.uniform() * 90.0) as usize;
    let dim = if rng.uniform() < 0.35 { 3 } else { 2 };
    let sigma = 10f64.powf(rng.range(-3.7, -2.5));
    let harm: Vec<(f64, f64, f64)> = (2..6)
        .map(|j| {
            (
                j as f64,
                rng.range(0.0, 0.25) / j as f64,
                rng.range(0.0, std::f64::consts::TAU),
            )
        })
        .collect();
    let lift: Vec<f64> = (0..3).map(|_| rng.range(-0.3, 0.3)).collect();
    let shape = move |t: f64| {
        let th = std::f64::consts::TAU * t;
        let r = 1.0 + harm.iter().map(|(j, a, ph)| a * (j * th + ph).cos()).sum::<f64>();
        let z = if dim == 3 {
            lift[0] * th.sin() + lift[1] * (2.0 * th).cos() + lift[2] * (3.0 * th).sin()
        } else {
            0.0
        };
        DVec3::new(r * th.cos(), r * th.sin(), z)
    };
    Case {
        name: "unseen_closed",
        curve: periodic(&shape, dim, n, sigma, k + 1),
        sigma,
    }
}
