//! Generator of Fairway's sample assets: noisy samples of analytic shapes
//! fitted by least squares with fixed knot vectors (`fairway::fit`).
//!
//! Deterministic: a hand-written SplitMix64 generator with fixed seeds and
//! Box–Muller normals, so that running it again gives byte-identical files
//! (checked by `tests/tests/assets.rs`). Shared by the `make_assets` example
//! and that test.

use std::f64::consts::PI;

use fairway::fit::{Smoothing, fit_curve_points};
use fairway::io::{Document, DocumentSettings, json};
use fairway::{BSplineCurve, BSplineSurface, DVec3, Geometry, KnotVector};

/// SplitMix64 (Steele, Lea, Flood 2014) with Box–Muller normal deviates.
pub struct Rng(u64);

impl Rng {
    /// A generator with a fixed seed.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    /// Uniform in [0, 1) with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Standard normal deviate (Box–Muller, one of the pair).
    pub fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform(); // (0, 1]
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
    }
}

/// Fit a cubic with `n_ctrl` control points on uniform knots over [0, 1]
/// to samples `pts` at parameters `params`, end points interpolated.
fn fit_curve(params: &[f64], pts: &[DVec3], n_ctrl: usize, dim: usize) -> BSplineCurve {
    let knots = KnotVector::uniform(3, n_ctrl).unwrap();
    let mut fixed = vec![None; n_ctrl];
    fixed[0] = Some(pts[0]);
    fixed[n_ctrl - 1] = Some(*pts.last().unwrap());
    let ctrl = fit_curve_points(&knots, params, pts, None, Smoothing::NONE, &fixed).unwrap();
    BSplineCurve::try_new(3, knots.values().to_vec(), ctrl, None, dim).unwrap()
}

fn uniform(n: usize) -> Vec<f64> {
    (0..n).map(|i| i as f64 / (n - 1) as f64).collect()
}

/// A car-roof-like profile (4 m long, 0.55 m high, asymmetric: steeper
/// windscreen, longer rear), 400 samples with σ = 0.6 mm noise normal to
/// the x axis, fitted with 64 control points: small wiggles in the comb.
pub fn car_roof() -> BSplineCurve {
    let mut rng = Rng::new(0x0CA7_200F);
    let t = uniform(400);
    let pts: Vec<DVec3> = t
        .iter()
        .map(|&t| {
            let u = 2.0 * t - 1.0;
            let y = 0.55 * (1.0 - u.powi(4)) * (1.0 + 0.15 * u) + 0.04 * (PI * t).sin();
            DVec3::new(4.0 * t, y + 0.0006 * rng.normal(), 0.0)
        })
        .collect();
    // interpolate exact end points (the noise-free shape ends at y = 0)
    let mut pts = pts;
    pts[0].y = 0.0;
    pts.last_mut().unwrap().y = 0.0;
    fit_curve(&t, &pts, 64, 2)
}

/// A 2D S-like wave y = 0.5·sin(3πt) over x = 3t (two interior
/// inflections), 300 samples with σ = 1 mm noise, 40 control points.
pub fn s_curve() -> BSplineCurve {
    let mut rng = Rng::new(0x005C_011E);
    let t = uniform(300);
    let mut pts: Vec<DVec3> = t
        .iter()
        .map(|&t| DVec3::new(3.0 * t, 0.5 * (3.0 * PI * t).sin() + 0.001 * rng.normal(), 0.0))
        .collect();
    pts.last_mut().unwrap().y = 0.0;
    pts[0].y = 0.0;
    fit_curve(&t, &pts, 40, 2)
}

/// A 3D conical spiral: radius 1 → 0.5, two turns, height 1.5; 400
/// samples with σ = 1 mm noise in every coordinate, 50 control points.
pub fn spatial_curve() -> BSplineCurve {
    let mut rng = Rng::new(0x003D_C0A1);
    let t = uniform(400);
    let pts: Vec<DVec3> = t
        .iter()
        .map(|&t| {
            let r = 1.0 - 0.5 * t;
            let a = 4.0 * PI * t;
            let noise = DVec3::new(rng.normal(), rng.normal(), rng.normal()) * 0.001;
            DVec3::new(r * a.cos(), r * a.sin(), 1.5 * t) + noise
        })
        .collect();
    fit_curve(&t, &pts, 50, 3)
}

/// A closed 2D section (a hull-like rounded profile, 2.4 × 1.3): the uniform periodic cubic of 48
/// control points `Q_j` on `x = 1.2 cos t, y = 0.6 sin t + 0.08 sin 2t` with σ = 1 mm noise, written
/// exactly as a clamped curve (`fairway::fair::closed::periodic_cubic`), so the seam is C2 and as noisy
/// as anywhere else.
pub fn closed_section() -> BSplineCurve {
    noisy_section(0x00C1_05ED)
}

/// The closed cubic of 48 cyclic points on the section `(1.2 cos t, 0.6 sin t + 0.08 sin 2t)` with
/// σ = 1 mm noise from the seed (C2 seam at u = 0).
fn noisy_section(seed: u64) -> BSplineCurve {
    let mut rng = Rng::new(seed);
    let n = 48;
    let q: Vec<DVec3> = (0..n)
        .map(|j| {
            let t = 2.0 * PI * j as f64 / n as f64;
            let noise = DVec3::new(rng.normal(), rng.normal(), 0.0) * 0.001;
            DVec3::new(1.2 * t.cos(), 0.6 * t.sin() + 0.08 * (2.0 * t).sin(), 0.0) + noise
        })
        .collect();
    fairway::fair::closed::periodic_cubic(&q, 2).unwrap()
}

/// A closed 2D section with two chines: 48 noisy cyclic points as in [`closed_section`] (another seed)
/// written as a closed cubic (C2 seam at u = 0), its knots u = 0.375 and 0.875 tripled (exact) and a tent
/// of outward displacement raised on each: two chines (kinks of about 20°), corners that fairing keeps
/// (the whole section is re-seamed at the first one and faired across its seam).
pub fn chined_section() -> BSplineCurve {
    let mut c = noisy_section(0x00C4_14ED);
    for u in [0.375, 0.875] {
        c = c.insert_knot(u, 2).unwrap();
    }
    // a tent of outward displacement on each chine (6 cm high, 0.06 of the parameter wide on each side),
    // on the control points by their Greville abscissae: C0 at the chine's triple knot, smooth around it
    let g = c.knots().greville();
    let pts: Vec<DVec3> = c
        .points()
        .iter()
        .zip(&g)
        .map(|(p, &x)| {
            let tent: f64 = [0.375, 0.875]
                .iter()
                .map(|u| (1.0 - (x - u).abs() / 0.06).max(0.0))
                .sum();
            *p + p.normalize() * 0.06 * tent
        })
        .collect();
    c.with_points(pts).unwrap()
}

/// A 2D rear-deck profile with a kink (a character line): a gentle rise from (0, 0) to (1.8, 0.5)
/// and a steeper fall to (3, 0), meeting at a 20° tangent break. Each part: 200 samples with σ = 0.6 mm
/// noise fitted with 24 control points (end points exact); the parts joined at a triple knot u = 0.6, so
/// the curve is C0 there and the kink is a corner that fairing keeps (the stretches on either side are
/// faired one by one).
pub fn kinked_profile() -> BSplineCurve {
    let mut rng = Rng::new(0x00C0_4E12);
    let t = uniform(200);
    let part = |rng: &mut Rng, f: &dyn Fn(f64) -> DVec3| {
        let mut pts: Vec<DVec3> = t
            .iter()
            .map(|&t| f(t) + DVec3::new(0.0, 0.0006 * rng.normal(), 0.0))
            .collect();
        pts[0] = f(0.0);
        *pts.last_mut().unwrap() = f(1.0);
        fit_curve(&t, &pts, 24, 2)
    };
    let a = part(&mut rng, &|s| DVec3::new(1.8 * s, 0.45 * s * (2.0 - s) + 0.05 * s, 0.0));
    let b = part(&mut rng, &|r| {
        DVec3::new(1.8 + 1.2 * r, 0.5 - 0.5 * (0.8 * r + 0.2 * r * r), 0.0)
    });
    let ka = a.knots().values();
    let mut knots: Vec<f64> = ka[..ka.len() - 1].iter().map(|k| 0.6 * k).collect();
    knots.extend(b.knots().values()[4..].iter().map(|k| 0.6 + 0.4 * k));
    let mut pts = a.points().to_vec();
    pts.extend_from_slice(&b.points()[1..]);
    BSplineCurve::try_new(3, knots, pts, None, 2).unwrap()
}

/// A bumpy bicubic surface over [0, 2] × [0, 1.6]:
/// z = 0.15·sin(2x)·cos(3y) + 0.05·x·y, sampled on an 80 × 64 grid with
/// σ = 2 mm noise in z, fitted with 20 × 16 control points. The grid makes
/// the tensor-product least squares separable: fit each sample row in v,
/// then each column of those control points in u (exactly the LSQ solution
/// of the whole grid).
pub fn bumpy_surface() -> BSplineSurface {
    let mut rng = Rng::new(0x000B_04B5);
    let (mu, mv) = (80, 64);
    let (nu, nv) = (20, 16);
    let (tu, tv) = (uniform(mu), uniform(mv));
    let ku = KnotVector::uniform(3, nu).unwrap();
    let kv = KnotVector::uniform(3, nv).unwrap();
    let mut rows: Vec<Vec<DVec3>> = Vec::with_capacity(mu);
    for &u in &tu {
        let samples: Vec<DVec3> = tv
            .iter()
            .map(|&v| {
                let (x, y) = (2.0 * u, 1.6 * v);
                let z = 0.15 * (2.0 * x).sin() * (3.0 * y).cos() + 0.05 * x * y + 0.002 * rng.normal();
                DVec3::new(x, y, z)
            })
            .collect();
        rows.push(fit_curve_points(&kv, &tv, &samples, None, Smoothing::NONE, &[]).unwrap());
    }
    let mut net = vec![DVec3::ZERO; nu * nv];
    for j in 0..nv {
        let col: Vec<DVec3> = rows.iter().map(|r| r[j]).collect();
        let c = fit_curve_points(&ku, &tu, &col, None, Smoothing::NONE, &[]).unwrap();
        for i in 0..nu {
            net[i * nv + j] = c[i];
        }
    }
    BSplineSurface::try_new(3, 3, ku.values().to_vec(), kv.values().to_vec(), nu, nv, net, None).unwrap()
}

/// Every asset: `(file name in assets/, contents)`.
pub fn generate() -> Vec<(&'static str, String)> {
    let roof = car_roof();
    let mut doc = Document::new(Geometry::Curve(roof.clone()));
    doc.settings = DocumentSettings {
        tolerance: Some(0.002),
        ..Default::default()
    };
    vec![
        ("car_roof.json", json::to_string(&roof.into())),
        ("car_roof.ron", doc.to_ron().unwrap()),
        ("s_curve_inflections.json", json::to_string(&s_curve().into())),
        ("spatial_curve.json", json::to_string(&spatial_curve().into())),
        ("closed_section.json", json::to_string(&closed_section().into())),
        ("kinked_profile.json", json::to_string(&kinked_profile().into())),
        ("chined_section.json", json::to_string(&chined_section().into())),
        ("bumpy_surface.json", json::to_string(&bumpy_surface().into())),
    ]
}
