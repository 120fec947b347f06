//! Interior-region surface fairing quality on `assets/bumpy_surface.json`:
//! measures inside the region, outside it, and over the whole surface, before
//! and after fairing `[0.1, 0.9]²` for several tolerances.
//!
//! ```sh
//! cargo run --release -p fairway --example surface_region_quality [u1 u2 v1 v2]
//! REFAIR_LEVELS=1 cargo run --release -p fairway --example surface_region_quality   # isocurves re-faired per level
//! ```
//!
//! Columns: Σ∫(dκ_n/ds)² ds of 20 isocurves per direction (`E`) and
//! `∫∫|∇H|² dA` (`H'`), each over the region ("in") and the whole surface
//! ("all"), as ratios faired/original; isocurve curvature extrema (whole
//! surface); the smoothing strength, rounds, α and verified deviation.

use fairway::Geometry;
use fairway::fair::{SurfaceFairingOptions, fair_surface};
use fairway::measure_surface::{
    ISOPHOTE_DEAD_BAND, ISOPHOTE_LIGHT, ISOPHOTE_STEP_DEG, iso_stats, iso_stats_in, isophote_waviness,
    mean_curvature_variation, mean_curvature_variation_in,
};

fn main() {
    let args: Vec<f64> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let region = if args.len() == 4 {
        ((args[0], args[1]), (args[2], args[3]))
    } else {
        ((0.1, 0.9), (0.1, 0.9))
    };
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/bumpy_surface.json");
    let Geometry::Surface(s) = fairway::io::load_geometry(&path).expect("load") else {
        panic!("not a surface")
    };
    let e = |x: &fairway::BSplineSurface, r| {
        let st = iso_stats_in(x, r, 20, 0.0);
        st.e_var_u + st.e_var_v
    };
    let so = iso_stats(&s, 20, 0.0);
    let delta = 0.01 * so.max_abs_kappa;
    let (e_in0, e_all0) = (e(&s, region), so.e_var_u + so.e_var_v);
    let (h_in0, h_all0) = (mean_curvature_variation_in(&s, region), mean_curvature_variation(&s));
    let ext0 = iso_stats(&s, 20, delta);
    let iso = |x: &fairway::BSplineSurface| {
        isophote_waviness(
            x,
            fairway::DVec3::from_array(ISOPHOTE_LIGHT),
            ISOPHOTE_STEP_DEG,
            ISOPHOTE_DEAD_BAND,
        )
    };
    let i0 = iso(&s);
    println!("isophotes: {} traced, {} inflections", i0.n_isophotes, i0.n_inflections);
    println!(
        "region {region:?}; original: E in {e_in0:.4e} all {e_all0:.4e}, H' in {h_in0:.4e} all {h_all0:.4e}, extrema {}",
        ext0.extrema_u + ext0.extrema_v
    );
    println!("   m     | E in  | E all | H' in | H' all | extrema | strength | rounds | alpha | dev");
    for m in [2e-3, 4e-3, 6e-3, 1e-2, 2e-2] {
        let r = fair_surface(
            &s,
            SurfaceFairingOptions::default()
                .region(Some(region))
                .tolerance(m)
                .combine(
                    std::env::var("COMBINE")
                        .ok()
                        .map_or(Default::default(), |c| c.parse().unwrap()),
                )
                .auto_smoothing(std::env::var("STRENGTH").is_err())
                .refair_levels(std::env::var("REFAIR_LEVELS").is_ok())
                .smoothing(fairway::fit_surface::SurfaceSmoothing {
                    strength_u: std::env::var("STRENGTH").ok().map_or(0.0, |c| c.parse().unwrap()),
                    strength_v: std::env::var("STRENGTH").ok().map_or(0.0, |c| c.parse().unwrap()),
                    order: 3,
                }),
        )
        .expect("fair");
        let f = &r.surface;
        let ext = iso_stats(f, 20, delta);
        let inner = ((0.3, 0.7), (0.3, 0.7));
        let i1 = iso(f);
        eprintln!(
            "   isophotes: {} traced, {} inflections",
            i1.n_isophotes, i1.n_inflections
        );
        eprintln!(
            "   inner [0.3,0.7]^2: E {:.3} H' {:.3}",
            e(f, inner) / e(&s, inner),
            mean_curvature_variation_in(f, inner) / mean_curvature_variation_in(&s, inner)
        );
        println!(
            "{m:.0e} | {:.3} | {:.3} | {:.3} | {:.3} | {} | {:.0e} | {} | {:.3} | {:.2e}",
            e(f, region) / e_in0,
            {
                let st = iso_stats(f, 20, 0.0);
                (st.e_var_u + st.e_var_v) / e_all0
            },
            mean_curvature_variation_in(f, region) / h_in0,
            mean_curvature_variation(f) / h_all0,
            ext.extrema_u + ext.extrema_v,
            r.smoothing.strength_u,
            r.rounds,
            r.alpha,
            r.max_deviation
        );
    }
}
