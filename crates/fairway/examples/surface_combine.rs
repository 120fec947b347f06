//! Before/after measures of the four ways to combine the u- and v-isocurve
//! clouds ([`Combine`]), on noisy test surfaces with a known exact shape.
//!
//! ```sh
//! cargo run --release -p fairway --example surface_combine
//! REFAIR_LEVELS=1 cargo run --release -p fairway --example surface_combine   # isocurves re-faired per level
//! ```
//!
//! Columns: principal-curvature RMS error against the noise-free surface
//! (30×30 grid over [0.1, 0.9]² for the whole surface, over
//! [0.35, 0.65]×[0.3, 0.7] inside the local region [0.25, 0.75]×[0.2, 0.8]);
//! whole-surface figures: `mean_curv_var` = ∫|∇H|² dA, isocurve curvature
//! extrema (20 isocurves per direction, δ = 1% of the original's max |κ_n|),
//! verified max deviation.

use fairway::fair::{Combine, SurfaceFairingOptions, fair_surface};
use fairway::measure_surface::{iso_stats, mean_curvature_variation};
use fairway::{BSplineSurface, DVec3};

fn graph(n: usize, f: impl Fn(f64, f64) -> f64) -> BSplineSurface {
    fairway::fit_surface::fit_graph(n, f).unwrap()
}

fn noisy(s: &BSplineSurface, sigma: f64, seed: u64) -> BSplineSurface {
    let mut st = seed;
    let pts = s
        .points()
        .iter()
        .map(|p| {
            st = st.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let a = ((st >> 11) as f64 / (1u64 << 53) as f64).max(1e-300);
            st = st.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let b = (st >> 11) as f64 / (1u64 << 53) as f64;
            *p + DVec3::new(
                0.0,
                0.0,
                sigma * (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos(),
            )
        })
        .collect();
    s.with_points(pts).unwrap()
}

/// RMS principal-curvature error on a 30×30 grid of `[u0,u1]×[v0,v1]`.
fn curvature_error(s: &BSplineSurface, exact: &BSplineSurface, (u0, u1): (f64, f64), (v0, v1): (f64, f64)) -> f64 {
    let n = 30;
    let mut sum = 0.0;
    for k in 0..n {
        for l in 0..n {
            let (u, v) = (
                u0 + (u1 - u0) * k as f64 / (n - 1) as f64,
                v0 + (v1 - v0) * l as f64 / (n - 1) as f64,
            );
            let (a, b) = (s.curvature(u, v), exact.curvature(u, v));
            sum += (a.k_max - b.k_max).powi(2) + (a.k_min - b.k_min).powi(2);
        }
    }
    (sum / (n * n) as f64).sqrt()
}

type Case = (&'static str, Box<dyn Fn(f64, f64) -> f64>);

fn main() {
    let cases: Vec<Case> = vec![
        ("cylinder", Box::new(|u, _| (1.0 - (u - 0.5).powi(2)).sqrt())),
        (
            "bump",
            Box::new(|u, v| 0.3 * (-((u - 0.5).powi(2) + (v - 0.5).powi(2)) / 0.05).exp()),
        ),
        ("saddle", Box::new(|u, v| 0.4 * (u - 0.5) * (v - 0.5))),
        ("wave", Box::new(|u, v| 0.15 * (3.0 * u).sin() * (2.0 * v).cos())),
    ];
    println!("surface\tcombine\tregion\tcurv_err\tmean_curv_var\tiso_extrema\tdev_max");
    for (name, f) in cases {
        let exact = graph(20, f);
        let s = noisy(&exact, 1e-3, 7);
        let so = iso_stats(&s, 20, 0.0);
        let delta = 0.01 * so.max_abs_kappa;
        let se = iso_stats(&s, 20, delta);
        for region in [None, Some(((0.25, 0.75), (0.2, 0.8)))] {
            let rname = if region.is_some() { "local" } else { "whole" };
            // whole: interior [0.1, 0.9]²; local: inside the region, away from its border rows
            let (bu, bv) = if region.is_some() {
                ((0.35, 0.65), (0.3, 0.7))
            } else {
                ((0.1, 0.9), (0.1, 0.9))
            };
            println!(
                "{name}\toriginal\t{rname}\t{:.4}\t{:.4e}\t{}\t0",
                curvature_error(&s, &exact, bu, bv),
                mean_curvature_variation(&s),
                se.extrema_u + se.extrema_v
            );
            for combine in [Combine::Average, Combine::Border, Combine::Weighted, Combine::Smoothed] {
                let r = fair_surface(
                    &s,
                    SurfaceFairingOptions::default()
                        .tolerance(3e-3)
                        .combine(combine)
                        .region(region)
                        .refair_levels(std::env::var("REFAIR_LEVELS").is_ok()),
                )
                .unwrap();
                let st = iso_stats(&r.surface, 20, delta);
                println!(
                    "{name}\t{combine:?}\t{rname}\t{:.4}\t{:.4e}\t{}\t{:.2e}",
                    curvature_error(&r.surface, &exact, bu, bv),
                    mean_curvature_variation(&r.surface),
                    st.extrema_u + st.extrema_v,
                    r.max_deviation
                );
            }
        }
    }
}
