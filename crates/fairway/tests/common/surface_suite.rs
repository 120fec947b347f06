//! The surface quality suite: surfaces of known shape made noisy the way scanned data is (samples with
//! Gaussian noise σ, fitted by least squares on fixed knots), each with its σ: noisy bumps, a car-roof-like
//! patch, a dome whose first control row collapses to an apex, a patch with a C1 knot line (a double knot
//! where the curvature jumps), and the bundled `assets/bumpy_surface.json`. Shared by
//! `tests/surface_quality.rs` and `examples/surface_quality_table.rs`.

#![allow(dead_code)]

use fairway::fit_surface::{SurfaceSmoothing, fit_surface_grid};
use fairway::{BSplineSurface, DVec3, Geometry, KnotVector};

/// One surface of the suite.
pub struct SurfaceCase {
    /// Short name.
    pub name: &'static str,
    /// The noisy surface.
    pub surface: BSplineSurface,
    /// The noise σ of its samples.
    pub sigma: f64,
}

/// The tolerances of each case, as multiples of its σ.
pub const TOLERANCE_FACTORS: [f64; 3] = [1.0, 3.0, 10.0];

/// xorshift64* with a Box–Muller normal: a fixed, dependency-free noise source.
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
}

fn uniform_params(n: usize) -> Vec<f64> {
    (0..n).map(|k| k as f64 / (n - 1) as f64).collect()
}

/// Noisy samples of `shape` (noise σ along z; 4 samples per control point and direction, uniform in the
/// parameters) fitted by least squares with the knots `ku`, `kv`; control rows `u_held` (at the start of
/// u) keep the values of `held(v)` (e.g. an apex).
fn fitted(
    shape: &dyn Fn(f64, f64) -> DVec3,
    ku: KnotVector,
    kv: KnotVector,
    sigma: f64,
    seed: u64,
    u_held: usize,
    held: &dyn Fn(usize) -> DVec3,
) -> BSplineSurface {
    let (nu, nv) = (ku.n_points(), kv.n_points());
    let (us, vs) = (uniform_params(4 * nu), uniform_params(4 * nv));
    let mut rng = Rng(seed);
    let mut data = Vec::with_capacity(us.len() * vs.len());
    for &u in &us {
        for &v in &vs {
            data.push(shape(u, v) + DVec3::new(0.0, 0.0, sigma * rng.gauss()));
        }
    }
    let mut pts = vec![DVec3::ZERO; nu * nv];
    for i in 0..u_held {
        for j in 0..nv {
            pts[i * nv + j] = held(j);
        }
    }
    let base = BSplineSurface::try_new(
        ku.degree(),
        kv.degree(),
        ku.values().to_vec(),
        kv.values().to_vec(),
        nu,
        nv,
        pts,
        None,
    )
    .expect("base surface");
    let pts = fit_surface_grid(&base, &us, &vs, &data, u_held..nu, 0..nv, SurfaceSmoothing::NONE).expect("fit");
    base.with_points(pts).expect("net")
}

/// Knots of degree 3 with `n` control points and a double knot at 1/2 (C1 there).
fn c1_knots(n: usize) -> KnotVector {
    // n = 4 + interior knots; the interior: uniform on each half plus the double knot at 1/2
    let interior = n - 4; // ≥ 2, even split: (interior − 2)/2 single knots per half
    let per_half = (interior - 2) / 2;
    let mut v = vec![0.0; 4];
    for k in 1..=per_half {
        v.push(0.5 * k as f64 / (per_half + 1) as f64);
    }
    v.extend([0.5, 0.5]);
    for k in 1..=per_half {
        v.push(0.5 + 0.5 * k as f64 / (per_half + 1) as f64);
    }
    v.extend([1.0; 4]);
    KnotVector::try_new(v, 3, n, "c1 knots").expect("c1 knots")
}

/// The suite with nets of about `n × n` control points (n ≥ 8; the table uses 16, the tests 10).
pub fn surface_cases(n: usize) -> Vec<SurfaceCase> {
    let n = n.max(8);
    let k = |m: usize| KnotVector::uniform(3, m).expect("knots");
    let none = |_: usize| DVec3::ZERO;
    let mut out = Vec::new();

    // three Gaussian bumps of different heights and widths on a 2 × 1.6 plate
    let bumps = |u: f64, v: f64| {
        let (x, y) = (2.0 * u, 1.6 * v);
        let b = |cx: f64, cy: f64, h: f64, w: f64| h * (-((x - cx).powi(2) + (y - cy).powi(2)) / (w * w)).exp();
        DVec3::new(
            x,
            y,
            b(0.6, 0.5, 0.12, 0.3) + b(1.4, 1.0, 0.08, 0.25) + b(1.0, 0.3, -0.05, 0.2),
        )
    };
    let sigma = 1e-3;
    out.push(SurfaceCase {
        name: "noisy_bumps",
        surface: fitted(&bumps, k(n), k(n), sigma, 21, 0, &none),
        sigma,
    });

    // a car roof: 1.8 m long, 1.3 m wide, crowned 9 cm along and 5 cm across, steeper towards the windscreen
    let roof = |u: f64, v: f64| {
        let (x, y) = (1.8 * u, 1.3 * (v - 0.5));
        let along = 0.09 * (1.0 - ((x - 0.8) / 1.0).powi(2)) - 0.03 * (x / 1.8).powi(3);
        let across = 0.05 * (1.0 - (y / 0.65).powi(2));
        DVec3::new(x, y, along + across)
    };
    let sigma = 5e-4;
    out.push(SurfaceCase {
        name: "car_roof",
        surface: fitted(&roof, k(n), k(n * 3 / 4), sigma, 22, 0, &none),
        sigma,
    });

    // a dome (half a paraboloid cap): u runs from the apex (row 0, collapsed to one point) to the rim,
    // v half-way around
    let apex = DVec3::new(0.0, 0.0, 0.3);
    let dome = move |u: f64, v: f64| {
        let t = std::f64::consts::PI * v;
        let r = 0.6 * u;
        DVec3::new(r * t.cos(), r * t.sin(), 0.3 * (1.0 - u * u))
    };
    let sigma = 5e-4;
    out.push(SurfaceCase {
        name: "apex_dome",
        surface: fitted(&dome, k(n), k(n), sigma, 23, 1, &|_| apex),
        sigma,
    });

    // flat for x < 1, a parabolic rise after it (the curvature jumps across x = 1, a C1 line on a double
    // knot), a gentle wave across
    let c1 = |u: f64, v: f64| {
        let (x, y) = (2.0 * u, 1.2 * v);
        let rise = if x > 1.0 { 0.15 * (x - 1.0).powi(2) } else { 0.0 };
        DVec3::new(x, y, rise + 0.02 * (2.5 * y).sin())
    };
    let sigma = 5e-4;
    let n_c1 = n + (n % 2); // even, so the double knot sits at 1/2
    out.push(SurfaceCase {
        name: "c1_knot_line",
        surface: fitted(&c1, c1_knots(n_c1), k(n), sigma, 24, 0, &none),
        sigma,
    });
    out
}

/// The bundled surface assets with their noise σ (`assets/README.md`).
pub fn asset_cases() -> Vec<SurfaceCase> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/bumpy_surface.json");
    let Geometry::Surface(s) = fairway::io::load_geometry(&path).expect("load bumpy_surface.json") else {
        panic!("bumpy_surface.json is not a surface")
    };
    vec![SurfaceCase {
        name: "bumpy_surface (asset)",
        surface: s,
        sigma: 2e-3,
    }]
}
