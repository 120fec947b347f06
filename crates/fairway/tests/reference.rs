//! The core against reference evaluations made by an independent
//! implementation (SciPy `BSpline`, cross-checked with OpenCASCADE and
//! openNURBS; see `tests/data/reference/README.md`, a copy of
//! `../shared/reference`). Stated accuracy: positions ≤ 1e-12 relative to the
//! largest coordinate, curvatures ≤ 1e-9 relative to the largest |κ|.

use std::path::PathBuf;

use fairway::{DVec3, Geometry};
use serde_json::Value;

fn reference_dir() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/reference"))
}

fn load(name: &str) -> (Geometry, Value) {
    let dir = reference_dir();
    let g = fairway::io::load_geometry(&dir.join(format!("{name}.json"))).unwrap();
    let text = std::fs::read_to_string(dir.join(format!("{name}.eval.json"))).unwrap();
    (g, serde_json::from_str(&text).unwrap())
}

fn nums(v: &Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

fn vec3(v: &Value) -> DVec3 {
    let c = nums(v);
    DVec3::new(c[0], c[1], c.get(2).copied().unwrap_or(0.0))
}

fn vecs(v: &Value) -> Vec<DVec3> {
    v.as_array().unwrap().iter().map(vec3).collect()
}

/// max |a − b| / max |a| over vectors.
fn rel_vec(reference: &[DVec3], got: &[DVec3]) -> f64 {
    let scale = reference.iter().fold(0.0f64, |m, p| m.max(p.abs().max_element()));
    reference
        .iter()
        .zip(got)
        .fold(0.0f64, |m, (a, b)| m.max((*a - *b).abs().max_element()))
        / scale
}

fn rel_scalar(reference: &[f64], got: &[f64]) -> f64 {
    let scale = reference.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    reference.iter().zip(got).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / scale
}

fn check_curve(name: &str, dim: usize) {
    let (g, r) = load(name);
    let c = g.as_curve().unwrap();
    assert_eq!(c.dim(), dim);
    let params = nums(&r["parameters"]);
    assert_eq!(params.len(), 101);
    assert_eq!(params[0], c.domain().0);
    assert_eq!(*params.last().unwrap(), c.domain().1);
    let d: Vec<_> = params.iter().map(|&u| c.derivs(u)).collect();
    let pts: Vec<DVec3> = d.iter().map(|x| x.p).collect();
    let d1: Vec<DVec3> = d.iter().map(|x| x.d1).collect();
    let d2: Vec<DVec3> = d.iter().map(|x| x.d2).collect();
    let k: Vec<f64> = d.iter().map(|x| x.curvature(dim)).collect();
    let e_p = rel_vec(&vecs(&r["points"]), &pts);
    let e_d1 = rel_vec(&vecs(&r["d1"]), &d1);
    let e_d2 = rel_vec(&vecs(&r["d2"]), &d2);
    let e_k = rel_scalar(&nums(&r["curvature"]), &k);
    println!("{name}: points {e_p:.1e}, d1 {e_d1:.1e}, d2 {e_d2:.1e}, curvature {e_k:.1e}");
    assert!(e_p <= 1e-12, "{name} points {e_p:e}");
    assert!(e_d1 <= 1e-12, "{name} d1 {e_d1:e}");
    assert!(e_d2 <= 1e-11, "{name} d2 {e_d2:e}");
    assert!(e_k <= 1e-9, "{name} curvature {e_k:e}");
    // point() (A2.2 path) agrees with derivs() (A2.3 path)
    for (&u, p) in params.iter().zip(&pts) {
        assert!((c.point(u) - *p).abs().max_element() <= 1e-14 * (1.0 + p.abs().max_element()));
    }
}

#[test]
fn s_curve_2d_matches_reference() {
    check_curve("s_curve", 2);
}

#[test]
fn conical_spiral_3d_matches_reference() {
    check_curve("conical_spiral", 3);
}

#[test]
fn saddle_surface_matches_reference() {
    let (g, r) = load("saddle");
    let s = g.as_surface().unwrap();
    let us = nums(&r["u"]);
    let vs = nums(&r["v"]);
    assert_eq!((us.len(), vs.len()), (21, 21));
    let rows = |key: &str| -> Vec<Value> { r[key].as_array().unwrap().clone() };
    let (mut rp, mut rn, mut gp, mut gn) = (vec![], vec![], vec![], vec![]);
    let mut scal: [(Vec<f64>, Vec<f64>); 4] = Default::default();
    let keys = ["k_max", "k_min", "mean", "gauss"];
    for (i, &u) in us.iter().enumerate() {
        for (j, &v) in vs.iter().enumerate() {
            let d = s.derivs(u, v);
            let k = d.curvature();
            rp.push(vec3(&rows("points")[i][j]));
            rn.push(vec3(&rows("normals")[i][j]));
            gp.push(d.p);
            gn.push(k.normal);
            let got = [k.k_max, k.k_min, k.mean, k.gauss];
            for (t, key) in keys.iter().enumerate() {
                scal[t].0.push(r[*key][i][j].as_f64().unwrap());
                scal[t].1.push(got[t]);
            }
            assert!(k.k_max >= k.k_min);
            assert!((s.point(u, v) - d.p).abs().max_element() <= 1e-14);
        }
    }
    let e_p = rel_vec(&rp, &gp);
    let e_n = rel_vec(&rn, &gn);
    println!("saddle: points {e_p:.1e}, normals {e_n:.1e}");
    assert!(e_p <= 1e-12, "points {e_p:e}");
    assert!(e_n <= 1e-12, "normals {e_n:e}");
    for (t, key) in keys.iter().enumerate() {
        let e = rel_scalar(&scal[t].0, &scal[t].1);
        println!("saddle: {key} {e:.1e}");
        assert!(e <= 1e-9, "{key} {e:e}");
    }
}
