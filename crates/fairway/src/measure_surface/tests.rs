use super::isophotes::sign_changes;
use super::*;
use crate::knots::KnotVector;

/// z = c x³ over [0,1]×[0,1] as an exact bicubic (Bézier in u, linear data in v).
fn cubic_cylinder(c: f64) -> BSplineSurface {
    // x(u) = u, z = c u³: Bézier control values of u³ are 0,0,0,1; of u: 0,1/3,2/3,1
    let ku = KnotVector::uniform(3, 4).unwrap();
    let kv = KnotVector::uniform(3, 4).unwrap();
    let zs = [0.0, 0.0, 0.0, c];
    let mut pts = Vec::new();
    for i in 0..4 {
        for j in 0..4 {
            pts.push(DVec3::new(i as f64 / 3.0, j as f64 / 3.0, zs[i]));
        }
    }
    BSplineSurface::try_new(3, 3, ku.values().to_vec(), kv.values().to_vec(), 4, 4, pts, None).unwrap()
}

#[test]
fn mean_curvature_variation_matches_closed_form() {
    let c = 0.7;
    let s = cubic_cylinder(c);
    // H(x) = κ/2 with κ = z''/(1+z'²)^{3/2} (sign by normal Su×Sv = (−z', 0, 1)·…, squared anyway)
    let hh = |x: f64| 0.5 * 6.0 * c * x / (1.0 + 9.0 * c * c * x.powi(4)).powf(1.5);
    // ∫∫|∇H|² dA = ∫ H'(x)² / sqrt(1+z'²) dx (width 1 in y)
    let n = 20000;
    let mut exact = 0.0;
    for k in 0..n {
        let x = (k as f64 + 0.5) / n as f64;
        let h = 1e-6;
        let dh = (hh(x + h) - hh(x - h)) / (2.0 * h);
        exact += dh * dh / (1.0 + 9.0 * c * c * x.powi(4)).sqrt() / n as f64;
    }
    let got = mean_curvature_variation(&s);
    assert!((got - exact).abs() < 1e-3 * exact, "{got} vs {exact}");
    // a plane has none
    let flat = cubic_cylinder(0.0);
    assert!(mean_curvature_variation(&flat).abs() < 1e-12);
}

#[test]
fn cell_derivatives_are_those_of_the_surface_bit_for_bit() {
    let s = crate::fit_surface::fit_graph(7, |u, v| (3.0 * u).sin() * (2.0 * v).cos() + u * v * v).unwrap();
    let bp = s.knots_u().breakpoints();
    let (a0, a1) = (bp[1], bp[2]);
    let us: Vec<f64> = (0..7).map(|k| a0 + (a1 - a0) * (0.05 + 0.9 * k as f64 / 6.0)).collect();
    let vs: Vec<f64> = (0..5).map(|k| a0 + (a1 - a0) * (0.1 + 0.2 * k as f64)).collect();
    let mut cell = CellDerivs::default();
    cell.prepare(&s, &us, &vs);
    for (a, &u) in us.iter().enumerate() {
        for (b, &v) in vs.iter().enumerate() {
            assert_eq!(cell.at(a, b), s.derivs(u, v), "({u}, {v})");
        }
    }
}

#[test]
fn mean_curvature_variation_vanishes_on_a_sphere_and_a_cylinder() {
    // ∇H = 0 where H is constant: rational (exact) patches of a sphere and a cylinder
    for (name, s, r) in [
        ("sphere", sphere_patch(2.0), 2.0),
        ("cylinder", cylinder_patch(1.5, 2.0), 1.5),
    ] {
        // the patch is where it should be and H is the constant ∓1/r (sphere) or ∓1/(2r) (cylinder)
        let p = s.point(0.3, 0.6);
        let k = s.curvature(0.3, 0.6);
        if name == "sphere" {
            assert!(
                (p.length() - r).abs() < 1e-12 && (k.mean.abs() - 1.0 / r).abs() < 1e-12,
                "{k:?}"
            );
        } else {
            assert!((p.truncate().length() - r).abs() < 1e-12 && (k.mean.abs() - 0.5 / r).abs() < 1e-12);
        }
        let h = mean_curvature_variation(&s);
        assert!(h.abs() < 1e-12, "{name}: {h}");
    }
}

/// A patch of the sphere of radius `r`: longitude 0..90° (a quarter circle as one rational quadratic)
/// times latitude 0..60° (likewise; it stays away from the pole, where Su × Sv vanishes). Both
/// arcs' homogeneous forms multiply, so the patch lies on the sphere exactly.
fn sphere_patch(r: f64) -> BSplineSurface {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let lon = [(1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
    let a = std::f64::consts::FRAC_PI_3;
    let h = 0.5 * a;
    // the middle control point at the end tangents' crossing, weight cos(half angle)
    let lat = [(1.0, 0.0), (1.0, h.tan()), (a.cos(), a.sin())];
    let (w_lon, w_lat) = ([1.0, w, 1.0], [1.0, h.cos(), 1.0]);
    let mut pts = Vec::new();
    let mut ws = Vec::new();
    for (i, &(c, sn)) in lat.iter().enumerate() {
        for (j, &(x, y)) in lon.iter().enumerate() {
            pts.push(DVec3::new(r * c * x, r * c * y, r * sn));
            ws.push(w_lat[i] * w_lon[j]);
        }
    }
    let k = vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
    BSplineSurface::try_new(2, 2, k.clone(), k, 3, 3, pts, Some(ws)).unwrap()
}

/// A quarter of the cylinder of radius `r` and height `h`: a rational quadratic arc in u, linear in v.
fn cylinder_patch(r: f64, h: f64) -> BSplineSurface {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let arc = [(1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
    let mut pts = Vec::new();
    let mut ws = Vec::new();
    for (i, &(x, y)) in arc.iter().enumerate() {
        for z in [0.0, h] {
            pts.push(DVec3::new(r * x, r * y, z));
            ws.push([1.0, w, 1.0][i]);
        }
    }
    BSplineSurface::try_new(
        2,
        1,
        vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        vec![0.0, 0.0, 1.0, 1.0],
        3,
        2,
        pts,
        Some(ws),
    )
    .unwrap()
}

#[test]
fn mean_curvature_variation_of_a_polynomial_graph_matches_a_direct_quadrature() {
    // the separable evaluation against a point-by-point one of the same rule: bit-identical H, so the
    // totals agree to rounding of the sum
    let s = crate::fit_surface::fit_graph(6, |u, v| 0.3 * (2.0 * u).sin() * v + 0.2 * u * u * v);
    let s = s.unwrap();
    let gl = crate::quadrature::GaussLegendre::new(4);
    let mut direct = 0.0;
    let bp = s.knots_u().breakpoints();
    for w in bp.windows(2) {
        for z in bp.windows(2) {
            let (a0, a1, b0, b1) = (w[0], w[1], z[0], z[1]);
            let (hu, hv) = (1e-5 * (a1 - a0), 1e-5 * (b1 - b0));
            for (x, wx) in gl.nodes.iter().zip(&gl.weights) {
                for (y, wy) in gl.nodes.iter().zip(&gl.weights) {
                    let u = 0.5 * (a0 + a1) + 0.5 * (a1 - a0) * x;
                    let v = 0.5 * (b0 + b1) + 0.5 * (b1 - b0) * y;
                    let d = s.derivs(u, v);
                    let (e, f, g) = (d.su.dot(d.su), d.su.dot(d.sv), d.sv.dot(d.sv));
                    let det = e * g - f * f;
                    let h_u = (mean_at(&s, u + hu, v) - mean_at(&s, u - hu, v)) / (2.0 * hu);
                    let h_v = (mean_at(&s, u, v + hv) - mean_at(&s, u, v - hv)) / (2.0 * hv);
                    let grad2 = (g * h_u * h_u - 2.0 * f * h_u * h_v + e * h_v * h_v) / det;
                    let jac = 0.25 * (a1 - a0) * (b1 - b0) * wx * wy;
                    direct += grad2 * det.sqrt() * jac;
                }
            }
        }
    }
    let got = mean_curvature_variation_rule(&s, s.domain(), &gl);
    assert!(direct > 0.0);
    assert_eq!(got, direct);
}

#[test]
fn projection_recovers_offset_points() {
    let s = cubic_cylinder(0.5);
    let proj = SurfaceProjector::new(&s, 4);
    for &(u, v) in &[(0.3, 0.4), (0.9, 0.1), (0.5, 0.5)] {
        let d = s.derivs(u, v);
        let n = d.su.cross(d.sv).normalize();
        let q = d.p + n * 0.01;
        let r = proj.project(q);
        assert!((r.distance - 0.01).abs() < 1e-10, "{r:?}");
        assert!((r.uv.0 - u).abs() < 1e-8 && (r.uv.1 - v).abs() < 1e-8);
        let r2 = proj.project_near(q, (u + 0.05, v - 0.05));
        assert!((r2.distance - 0.01).abs() < 1e-10);
    }
    // beyond the boundary: clamps to the border
    let q = s.point(1.0, 0.5) + DVec3::new(0.2, 0.0, 0.0);
    let r = proj.project(q);
    assert!((r.uv.0 - 1.0).abs() < 1e-12);
}

#[test]
fn deviation_of_an_offset_plane() {
    let a = cubic_cylinder(0.0);
    let moved: Vec<DVec3> = a.points().iter().map(|p| *p + DVec3::new(0.0, 0.0, 0.02)).collect();
    let b = a.with_points(moved).unwrap();
    let (max, rms) = deviation(&a, &b, 11);
    assert!((max - 0.02).abs() < 1e-12 && (rms - 0.02).abs() < 1e-12);
}

#[test]
fn isophote_sign_changes_of_a_sine() {
    // y = sin x over [0, 4π] in the plane z = 0 (normal +z): inflections at π, 2π, 3π
    let n = 2000;
    let up = DVec3::Z;
    let pts: Vec<(DVec3, DVec3)> = (0..=n)
        .map(|i| {
            let x = 4.0 * std::f64::consts::PI * i as f64 / n as f64;
            // zig-zag noise at the point spacing: its turning is large, its scale tiny
            let z = if i % 2 == 0 { 2e-5 } else { -2e-5 };
            (DVec3::new(x, x.sin() + z, 0.0), up)
        })
        .collect();
    let mut k = Vec::new();
    assert_eq!(sign_changes(&pts, 0.05, 0.2, &mut k, false), 3);
    // the curvature along it is −sin x (turning left is positive about +z)
    let mid = k.len() / 8; // x ≈ π/2
    assert!((k[mid] + 1.0).abs() < 0.05, "{}", k[mid]);
    // without resampling (step of the point spacing) and dead band the noise counts
    assert!(sign_changes(&pts, 4.0 * std::f64::consts::PI / n as f64, 0.0, &mut k, false) > 100);
}

/// Least-squares bicubic graph of `f` over [0,1]² (test helper).
fn graph(n: usize, f: impl Fn(f64, f64) -> f64) -> BSplineSurface {
    crate::fit_surface::fit_graph(n, f).unwrap()
}

fn default_iso(s: &BSplineSurface) -> IsophoteStats {
    isophote_waviness(
        s,
        DVec3::from_array(ISOPHOTE_LIGHT),
        ISOPHOTE_STEP_DEG,
        ISOPHOTE_DEAD_BAND,
    )
}

#[test]
fn isophotes_of_plane_cylinder_and_sphere_do_not_wave() {
    // plane: n·L constant, no isophote
    let plane = graph(8, |u, v| 0.2 * u - 0.1 * v);
    assert_eq!(
        default_iso(&plane),
        IsophoteStats {
            dead_band: default_iso(&plane).dead_band,
            ..Default::default()
        }
    );
    // cylinder: straight isophotes along the rulings
    let cyl = graph(12, |u, _| (1.0 - (u - 0.5).powi(2)).sqrt());
    let c = default_iso(&cyl);
    eprintln!("cylinder {c:?}");
    assert!(c.n_isophotes >= 5 && c.n_inflections == 0, "{c:?}");
    // sphere cap lit from its pole: circles, curvature cot θ / R > 0 everywhere, so even with no dead
    // band no sign change
    let sph = graph(12, |u, v| (4.0 - (u - 0.5).powi(2) - (v - 0.5).powi(2)).sqrt());
    let sp = isophote_waviness(&sph, DVec3::Z, ISOPHOTE_STEP_DEG, 0.0);
    eprintln!("sphere {sp:?}");
    assert!(sp.n_isophotes >= 5 && sp.n_inflections == 0, "{sp:?}");
    let sp = default_iso(&sph);
    assert!(sp.n_isophotes >= 5 && sp.n_inflections == 0, "{sp:?}");
}

#[test]
fn isophote_grid_is_capped_for_long_nets() {
    // 300 × 4 net (297 spans in u: 8 per span would be 2377 nodes): capped, still straight isophotes
    let (n, m) = (300, 4);
    let ku = KnotVector::uniform(3, n).unwrap();
    let kv = KnotVector::uniform(3, m).unwrap();
    let (gu, gv) = (ku.greville(), kv.greville());
    let mut pts = Vec::new();
    for &u in &gu {
        for &v in &gv {
            pts.push(DVec3::new(u, v, (1.0 - (u - 0.5).powi(2)).sqrt()));
        }
    }
    let s = BSplineSurface::try_new(3, 3, ku.values().to_vec(), kv.values().to_vec(), n, m, pts, None).unwrap();
    let st = default_iso(&s);
    assert!(st.n_isophotes >= 5 && st.n_inflections == 0, "{st:?}");
}

#[test]
fn isophotes_of_a_noisy_surface_wave_and_fairing_calms_them() {
    let exact = graph(16, |u, v| 0.15 * (4.0 * u).sin() * (4.8 * v).cos() + 0.05 * u * v);
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let pts: Vec<DVec3> = exact
        .points()
        .iter()
        .map(|p| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            *p + DVec3::new(0.0, 0.0, 2e-3 * ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5))
        })
        .collect();
    let noisy = exact.with_points(pts).unwrap();
    let (c0, c1) = (default_iso(&exact), default_iso(&noisy));
    let faired = crate::fair::fair_surface(
        &noisy,
        crate::fair::SurfaceFairingOptions {
            tolerance: 2e-3,
            ..Default::default()
        },
    )
    .unwrap()
    .surface;
    let c2 = default_iso(&faired);
    eprintln!("exact {c0:?}\nnoisy {c1:?}\nfaired {c2:?}");
    // the clean wave's isophotes meander and have genuine inflections (129 measured; 126 on a grid twice
    // as fine); the noise adds many (204 / 203), the fairing removes most of them (136 / 137)
    let (n0, n1, n2) = (
        c0.n_inflections as i64,
        c1.n_inflections as i64,
        c2.n_inflections as i64,
    );
    assert!(n0 > 0 && 4 * n1 >= 5 * n0, "{c0:?} {c1:?}");
    assert!(4 * (n2 - n0).max(0) <= n1 - n0, "{c0:?} {c1:?} {c2:?}");
}

#[test]
fn extrema_count() {
    let k: Vec<f64> = (0..200).map(|i| (i as f64 * 0.1).sin()).collect(); // x ∈ [0, 19.9]: extrema at π/2 + kπ
    assert_eq!(count_extrema(&k, 0.01), 6);
    let noisy: Vec<f64> = (0..200).map(|i| if i % 2 == 0 { 0.001 } else { 0.0 }).collect();
    assert_eq!(count_extrema(&noisy, 0.01), 0);
}

#[test]
fn iso_extrema_are_those_of_iso_stats_bit_for_bit() {
    // the κ samples by cell (polynomial) and point by point (the same surface made rational with unit
    // weights): the same counts and max |κ_n| on a rectangle that clips knot spans
    let s = crate::fit_surface::fit_graph(9, |u, v| (3.0 * u).sin() * (2.0 * v).cos() + 0.3 * u * v * v).unwrap();
    let rect = ((0.13, 0.91), (0.05, 0.77));
    let full = iso_stats_in(&s, rect, 7, 0.0);
    let delta = 0.01 * full.max_abs_kappa;
    let (a, b) = (iso_stats_in(&s, rect, 7, delta), iso_extrema_in(&s, rect, 7, delta));
    assert!(a.extrema_u + a.extrema_v > 0 && a.e_var_u > 0.0);
    assert_eq!((a.extrema_u, a.extrema_v), (b.extrema_u, b.extrema_v));
    assert_eq!(a.max_abs_kappa.to_bits(), b.max_abs_kappa.to_bits());
    assert_eq!((b.e_var_u, b.e_var_v), (0.0, 0.0));
    let w = vec![1.0; s.nu() * s.nv()];
    let r = BSplineSurface::try_new(
        3,
        3,
        s.knots_u().values().to_vec(),
        s.knots_v().values().to_vec(),
        s.nu(),
        s.nv(),
        s.points().to_vec(),
        Some(w),
    )
    .unwrap();
    assert!(r.is_rational());
    let c = iso_extrema_in(&r, rect, 7, delta);
    assert_eq!((a.extrema_u, a.extrema_v), (c.extrema_u, c.extrema_v));
    assert!((a.max_abs_kappa - c.max_abs_kappa).abs() < 1e-9 * a.max_abs_kappa);
}

#[test]
fn analytic_gradient_agrees_with_the_difference_rule() {
    // ∇H from the third partials against the central differences of H, on a wavy net over the domain
    // and on a rectangle that clips knot spans, with the 10- and 5-point rules; and on the closed form
    let s = crate::fit_surface::fit_graph(9, |u, v| (3.0 * u).sin() * (2.0 * v).cos() + 0.3 * u * v * v).unwrap();
    for rect in [s.domain(), ((0.13, 0.91), (0.05, 0.77))] {
        for gl in [
            crate::quadrature::GaussLegendre::new(10),
            crate::quadrature::GaussLegendre::new(5),
        ] {
            let fd = mean_curvature_variation_rule(&s, rect, &gl);
            let an = mean_curvature_variation_grad(&s, rect, &gl);
            assert!(fd > 0.0 && (an - fd).abs() < 1e-8 * fd, "{an} vs {fd}");
        }
    }
    let c = cubic_cylinder(0.7);
    let gl = crate::quadrature::GaussLegendre::new(10);
    let (fd, an) = (
        mean_curvature_variation(&c),
        mean_curvature_variation_grad(&c, c.domain(), &gl),
    );
    assert!((an - fd).abs() < 1e-8 * fd, "{an} vs {fd}");
    assert!(mean_curvature_variation_grad(&cubic_cylinder(0.0), c.domain(), &gl).abs() < 1e-12);
}

#[test]
fn adaptive_rule_agrees_with_the_ten_point_rule() {
    // the step-8 ranking's ∫∫|∇H|² (4- and 5-point rules per cell, 10 points where they disagree) against
    // the 10-point rule everywhere: a smooth wavy net, the same with noise of 1e-3 (the bench surfaces),
    // a clipped rectangle, and a net with a collapsed row (H singular at the pole: both cheap rules are far
    // off there, so those cells must take the 10-point rule)
    let gl = crate::quadrature::GaussLegendre::new(10);
    let wavy = crate::fit_surface::fit_graph(12, |u, v| (3.0 * u).sin() * (2.0 * v).cos() + 0.3 * u * v * v).unwrap();
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let noisy = wavy
        .with_points(
            wavy.points()
                .iter()
                .map(|p| {
                    state = state
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    *p + DVec3::Z * (((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 3.4e-3)
                })
                .collect(),
        )
        .unwrap();
    // a dome whose first row collapses to its apex
    let nv = wavy.nv();
    let dome = wavy
        .with_points(
            (wavy.points().iter().enumerate())
                .map(|(k, p)| if k < nv { DVec3::new(0.0, 0.5, 1.0) } else { *p })
                .collect(),
        )
        .unwrap();
    let mut worst_five = 0.0f64;
    for s in [&wavy, &noisy, &dome] {
        for rect in [s.domain(), ((0.13, 0.91), (0.05, 0.77))] {
            let full = mean_curvature_variation_grad(s, rect, &gl);
            let cheap = mean_curvature_variation_adaptive(s, rect, &gl, 1e-7);
            assert!(full > 0.0 && (cheap - full).abs() <= 1e-9 * full, "{cheap} vs {full}");
            // the 5-point rule alone is not that close: the test sees a fallback that does not happen
            let five = mean_curvature_variation_grad(s, rect, &crate::quadrature::GaussLegendre::new(5));
            worst_five = worst_five.max((five - full).abs() / full);
        }
    }
    assert!(worst_five > 1e-6, "{worst_five}");
}
