//! Surfaces: sphere and cylinder curvatures in closed form, derivatives
//! against finite differences, isocurves against surface evaluation.

mod shapes;

use fairway::{BSplineSurface, DVec3};
use shapes::*;

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn sphere_patch_is_umbilic_with_curvature_one_over_r() {
    for r in [0.5, 1.0, 4.0] {
        let s = sphere_octant(r);
        for i in 0..=12 {
            for j in 0..=12 {
                // avoid the pole (u = 1), where Su × Sv = 0
                let (u, v) = (0.9 * i as f64 / 12.0, j as f64 / 12.0);
                let p = s.point(u, v);
                assert!(close(p.length(), r, 1e-14 * r), "on the sphere");
                let k = s.curvature(u, v);
                // sign convention: positive where the surface bends towards the normal
                let side = k.normal.dot(p / r);
                assert!(close(side.abs(), 1.0, 1e-13), "normal is radial");
                let expect = -side.signum() / r;
                for (name, got) in [("k_max", k.k_max), ("k_min", k.k_min), ("mean", k.mean)] {
                    assert!(
                        close(got, expect, 1e-12 / r),
                        "r={r} ({u},{v}) {name}={got} vs {expect}"
                    );
                }
                assert!(close(k.gauss, 1.0 / (r * r), 1e-12 / (r * r)));
                assert!(close(k.dir_max.length(), 1.0, 1e-12) && close(k.dir_max.dot(k.normal), 0.0, 1e-12));
            }
        }
    }
}

#[test]
fn cylinder_curvatures() {
    let (r, h) = (1.5, 3.0);
    let s = cylinder(r, h);
    for i in 0..=16 {
        for j in 0..=4 {
            let (u, v) = (i as f64 / 16.0, j as f64 / 4.0);
            let p = s.point(u, v);
            assert!(close(p.truncate().length(), r, 1e-14 * r) && close(p.z, v * h, 1e-14));
            let k = s.curvature(u, v);
            // Su runs counter-clockwise, Sv up: Su × Sv points outwards, the
            // cylinder bends away from it
            let radial = DVec3::new(p.x, p.y, 0.0) / r;
            assert!((k.normal - radial).length() <= 1e-13);
            assert!(close(k.k_max, 0.0, 1e-13), "k_max {}", k.k_max);
            assert!(close(k.k_min, -1.0 / r, 1e-13), "k_min {}", k.k_min);
            assert!(close(k.mean, -0.5 / r, 1e-13));
            assert!(close(k.gauss, 0.0, 1e-13));
            // principal directions: straight rulings for k_max = 0, circles for k_min
            assert!(close(k.dir_max.z.abs(), 1.0, 1e-12), "{:?}", k.dir_max);
            assert!(close(k.dir_min.z, 0.0, 1e-12));
        }
    }
}

fn fd(f: impl Fn(f64) -> DVec3, x: f64, h: f64) -> DVec3 {
    (f(x + h) - f(x - h)) / (2.0 * h)
}

fn check_surface_fd(s: &BSplineSurface) {
    let h = 1e-5;
    for &u in &[0.1, 0.2, 0.42, 0.7, 0.9] {
        for &v in &[0.15, 0.3, 0.66, 0.85] {
            let d = s.derivs(u, v);
            let tol = |x: DVec3, t: f64| t * (1.0 + x.length());
            let checks = [
                ("su", fd(|t| s.point(t, v), u, h), d.su, 1e-7),
                ("sv", fd(|t| s.point(u, t), v, h), d.sv, 1e-7),
                ("suu", fd(|t| s.derivs(t, v).su, u, h), d.suu, 1e-6),
                ("svv", fd(|t| s.derivs(u, t).sv, v, h), d.svv, 1e-6),
                ("suv", fd(|t| s.derivs(u, t).su, v, h), d.suv, 1e-6),
                ("svu", fd(|t| s.derivs(t, v).sv, u, h), d.suv, 1e-6),
            ];
            for (name, numeric, exact, t) in checks {
                assert!(
                    (numeric - exact).length() <= tol(exact, t),
                    "({u},{v}) {name}: {numeric} vs {exact}"
                );
            }
            // normal curvature in the principal directions from the second
            // derivative of a surface curve through (u, v) along (a, b):
            // κ_n = c''·n / |c'|² with c(t) = S(u + a t, v + b t)
            let k = d.curvature();
            assert!(k.k_max >= k.k_min);
            assert!(close(k.mean, 0.5 * (k.k_max + k.k_min), 1e-12 * (1.0 + k.mean.abs())));
            assert!(close(k.gauss, k.k_max * k.k_min, 1e-10 * (1.0 + k.gauss.abs())));
            for (dir, kk) in [(k.dir_max, k.k_max), (k.dir_min, k.k_min)] {
                // dir = a Su + b Sv: solve in the tangent plane
                let (e, f, g) = (d.su.dot(d.su), d.su.dot(d.sv), d.sv.dot(d.sv));
                let (r1, r2) = (dir.dot(d.su), dir.dot(d.sv));
                let det = e * g - f * f;
                let (a, b) = ((g * r1 - f * r2) / det, (e * r2 - f * r1) / det);
                let hh = 1e-4;
                let c = |t: f64| s.point(u + a * t, v + b * t);
                let c2 = (c(hh) - 2.0 * c(0.0) + c(-hh)) / (hh * hh);
                let c1 = (c(hh) - c(-hh)) / (2.0 * hh);
                let kn = c2.dot(k.normal) / c1.length_squared();
                assert!(close(kn, kk, 1e-5 * (1.0 + kk.abs())), "({u},{v}): κ_n {kn} vs {kk}");
            }
        }
    }
}

#[test]
fn surface_derivatives_match_finite_differences() {
    check_surface_fd(&wavy_bicubic());
    check_surface_fd(&wavy_rational());
    check_surface_fd(&sphere_octant(2.0));
}

#[test]
fn isocurves_match_surface_evaluation() {
    for s in [wavy_bicubic(), wavy_rational(), sphere_octant(1.0), cylinder(1.0, 2.0)] {
        for &fixed in &[0.0, 0.13, 0.5, 0.77, 1.0] {
            let cu = s.iso_u(fixed);
            let cv = s.iso_v(fixed);
            assert_eq!(cu.is_rational(), s.is_rational());
            for k in 0..=30 {
                let t = k as f64 / 30.0;
                let d = s.derivs(t, fixed);
                let c = cu.derivs(t);
                assert!((c.p - d.p).length() <= 1e-13, "iso_u p");
                assert!((c.d1 - d.su).length() <= 1e-12 * (1.0 + d.su.length()), "iso_u d1");
                assert!((c.d2 - d.suu).length() <= 1e-11 * (1.0 + d.suu.length()), "iso_u d2");
                let d = s.derivs(fixed, t);
                let c = cv.derivs(t);
                assert!((c.p - d.p).length() <= 1e-13, "iso_v p");
                assert!((c.d1 - d.sv).length() <= 1e-12 * (1.0 + d.sv.length()), "iso_v d1");
                assert!((c.d2 - d.svv).length() <= 1e-11 * (1.0 + d.svv.length()), "iso_v d2");
            }
        }
    }
    // a meridian of the sphere is a circle of radius r
    let m = sphere_octant(3.0).iso_u(0.4);
    for k in 0..=10 {
        assert!(close(m.curvature(k as f64 / 10.0), 1.0 / 3.0, 1e-13));
    }
}

/// A rational surface with unequal weights and different degrees, knots and sizes in u and v: its
/// transpose evaluates to the same point with the parameters swapped, and transposing twice gives the
/// surface back bit for bit.
#[test]
fn a_transposed_surface_swaps_its_parameters_weights_included() {
    let (nu, nv) = (5, 4);
    let ku = vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0];
    let kv = vec![0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0];
    let pts: Vec<DVec3> = (0..nu * nv)
        .map(|k| DVec3::new((k / nv) as f64, (k % nv) as f64, ((k * 7 % 5) as f64) * 0.2))
        .collect();
    let w: Vec<f64> = (0..nu * nv).map(|k| 1.0 + 0.3 * ((k * 3 % 4) as f64)).collect();
    let s = BSplineSurface::try_new(3, 2, ku, kv, nu, nv, pts, Some(w)).unwrap();
    let t = s.transposed();
    assert_eq!((t.nu(), t.nv(), t.degree_u(), t.degree_v()), (nv, nu, 2, 3));
    for (u, v) in [(0.0, 0.0), (0.3, 0.7), (0.9, 0.2), (1.0, 1.0)] {
        let d = (s.point(u, v) - t.point(v, u)).length();
        assert!(d <= 1e-12, "({u}, {v}): {d}");
    }
    assert_eq!(t.transposed(), s);
}
