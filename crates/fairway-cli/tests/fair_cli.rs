//! End-to-end tests of `fairway fair` and `fairway measure`: the binary is
//! run on files in a temporary directory; the outputs are read back with the
//! core library and checked (tolerance kept, control points outside the
//! region unchanged, report keys = the reference's measure keys, exit codes
//! and messages on bad input).

use std::path::{Path, PathBuf};
use std::process::Output;

use fairway::{BSplineCurve, BSplineSurface, Geometry};
use serde_json::Value;

mod common;
use common::*;

/// A fresh temporary directory for one test.
fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fairway-cli-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "exit {:?}, stderr: {}",
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );
}

fn fails_with(out: &Output, code: i32, needle: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "stderr: {err}");
    assert!(err.contains(needle), "stderr {err:?} should mention {needle:?}");
    assert!(!err.contains("panicked"), "{err}");
}

fn load(path: &Path) -> Geometry {
    fairway::io::load_geometry(path).unwrap()
}

fn curve(path: &Path) -> BSplineCurve {
    load(path).as_curve().unwrap().clone()
}

fn surface(path: &Path) -> BSplineSurface {
    match load(path) {
        Geometry::Surface(s) => s,
        g => panic!("expected a surface, got a {}", g.kind()),
    }
}

fn json_file(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The reference's measure keys (README of shared/reference).
fn reference_keys() -> Vec<String> {
    let v = json_file(&reference("s_curve.smoothed.measures.json"));
    v.as_object().unwrap().keys().cloned().collect()
}

#[test]
fn fair_curve_keeps_tolerance_and_reports_reference_keys() {
    let dir = temp_dir("curve");
    let (out, rep) = (dir.join("out.json"), dir.join("report.json"));
    let input = reference("s_curve.json");
    ok(&fairway(&[
        "fair",
        s(&input),
        "--tolerance",
        "0.01",
        "-o",
        s(&out),
        "--report",
        s(&rep),
    ]));
    let (a, b) = (curve(&input), curve(&out));
    assert_eq!(a.knots().values(), b.knots().values(), "original knots kept");
    let r = json_file(&rep);
    assert_eq!(r["kind"], "curve");
    assert!(r["solve_ms"].as_f64().unwrap() > 0.0);
    let m = &r["measures"];
    for k in reference_keys() {
        assert!(m.get(&k).is_some(), "report.measures lacks the reference key {k}");
    }
    let dev = m["dev_max"].as_f64().unwrap();
    assert!(dev <= 0.01 && dev > 1e-4, "dev_max {dev}");
    // the measures agree with an independent call of the core
    let direct = fairway::measure::measure(&a, &b);
    assert!((direct.dev_max - dev).abs() <= 1e-12 * dev.max(1.0));
    assert_eq!(direct.n_curv_extrema as u64, m["n_curv_extrema"].as_u64().unwrap());
    // fairer than the input (already fair-ish: 2 extrema, the reference's own smoothing has 3, E_var 19.2):
    // no more curvature extrema and a clearly smaller ∫(dκ/ds)²
    let before = fairway::measure::measure(&a, &a);
    assert!(direct.n_curv_extrema <= before.n_curv_extrema);
    assert!(
        direct.E_var < 0.8 * before.E_var,
        "{} vs {}",
        direct.E_var,
        before.E_var
    );
    // `measure --json` on the files prints the same numbers
    let o = fairway(&["measure", s(&input), s(&out), "--json"]);
    ok(&o);
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["dev_max"].as_f64().unwrap(), direct.dev_max);
    assert_eq!(v["n_inflections"].as_u64().unwrap(), direct.n_inflections as u64);
}

/// `--polish-method interior-point` on the reference S-curve: the band holds, the report names the
/// polish, its E is below the line search's at the same iteration count and the iterative baseline's,
/// and a bad method name is refused with the choices.
#[test]
fn fair_curve_with_the_interior_point_polish() {
    let dir = temp_dir("interior");
    let input = reference("s_curve.json");
    let mut e = vec![];
    for (method, polish) in [
        ("fast", "line-search"),
        ("fast", "interior-point"),
        ("iterative", "line-search"),
    ] {
        let (out, rep) = (dir.join(format!("{polish}-{method}.json")), dir.join("report.json"));
        ok(&fairway(&[
            "fair",
            s(&input),
            "--tolerance",
            "0.01",
            "--method",
            method,
            "--polish-method",
            polish,
            "-o",
            s(&out),
            "--report",
            s(&rep),
        ]));
        let r = json_file(&rep);
        let want = if method == "fast" {
            Value::from(polish)
        } else {
            Value::Null
        };
        assert_eq!(
            r.get("polish").cloned().unwrap_or(Value::Null),
            want,
            "{method} {polish}"
        );
        let dev = fairway::measure::measure(&curve(&input), &curve(&out)).dev_max;
        assert!(dev <= 0.01, "{method} {polish}: {dev}");
        e.push(r["energy"].as_f64().unwrap());
    }
    println!("E: line search {}, interior point {}, iterative {}", e[0], e[1], e[2]);
    assert!(e[1] < e[0] && e[1] <= e[2], "{e:?}");
    let out = dir.join("x.json");
    fails_with(
        &fairway(&[
            "fair",
            s(&input),
            "--tolerance",
            "0.01",
            "--polish-method",
            "newton",
            "-o",
            s(&out),
        ]),
        2,
        "line-search or interior-point",
    );
}

#[test]
fn fair_curve_region_leaves_outside_control_points_unchanged() {
    let dir = temp_dir("region");
    let out = dir.join("out.json");
    let input = reference("s_curve.json");
    for ends in ["g2", "g1", "g0"] {
        ok(&fairway(&[
            "fair",
            s(&input),
            "--tolerance",
            "0.005",
            "--region",
            "0.3,0.7",
            "--ends",
            ends,
            "--target",
            "binomial",
            "--integrator",
            "rk2",
            "-o",
            s(&out),
        ]));
        let (a, b) = (curve(&input), curve(&out));
        // G0/G1 insert knots at the region ends: compare on the refined original
        let a = a.refine(&extra_knots(&a, &b)).unwrap();
        assert_eq!(a.n_points(), b.n_points(), "{ends}");
        let mut moved = 0;
        for i in 0..a.n_points() {
            let (lo, hi) = a.knots().support(i);
            let d = a.points()[i].distance(b.points()[i]);
            if lo < 0.3 - 1e-12 || hi > 0.7 + 1e-12 {
                assert!(d <= 1e-12, "{ends}: point {i} (support [{lo}, {hi}]) moved by {d}");
            } else if d > 1e-9 {
                moved += 1;
            }
        }
        assert!(moved > 0, "{ends}: nothing moved inside the region");
        let m = fairway::measure::measure(&curve(&input), &b);
        assert!(m.dev_max <= 0.005, "{ends}: {}", m.dev_max);
    }
}

/// Knots of `b` that `a` lacks (with multiplicity).
fn extra_knots(a: &BSplineCurve, b: &BSplineCurve) -> Vec<f64> {
    let mut ka = a.knots().values().to_vec();
    let mut extra = vec![];
    for &x in b.knots().values() {
        if let Some(i) = ka.iter().position(|&y| y == x) {
            ka.remove(i);
        } else {
            extra.push(x);
        }
    }
    extra
}

#[test]
fn fair_3d_curve_and_iterative_method() {
    let dir = temp_dir("3d");
    let (out, rep) = (dir.join("out.ron"), dir.join("report.json"));
    let input = reference("conical_spiral.json");
    ok(&fairway(&[
        "fair",
        s(&input),
        "--tolerance",
        "0.02",
        "-o",
        s(&out),
        "--report",
        s(&rep),
    ]));
    let m = fairway::measure::measure(&curve(&input), &curve(&out));
    assert!(m.dev_max <= 0.02, "{}", m.dev_max);
    let fast_e = json_file(&rep)["energy"].as_f64().unwrap();
    // the iterative baseline on a short stretch (it is slow by design)
    ok(&fairway(&[
        "fair",
        s(&input),
        "--tolerance",
        "0.02",
        "--region",
        "0.2,0.5",
        "--method",
        "iterative",
        "-o",
        s(&out),
        "--report",
        s(&rep),
    ]));
    let r = json_file(&rep);
    assert_eq!(r["method"], "iterative");
    assert!(r["energy"].as_f64().unwrap() <= r["energy_before"].as_f64().unwrap());
    assert!(r["measures"]["dev_max"].as_f64().unwrap() <= 0.02);
    assert!(fast_e.is_finite());
}

#[test]
fn fair_surface_region_and_surface_measures() {
    let dir = temp_dir("surface");
    let (out, rep) = (dir.join("out.json"), dir.join("report.json"));
    let input = reference("saddle.json");
    ok(&fairway(&[
        "fair",
        s(&input),
        "--tolerance",
        "0.01",
        "--region",
        "0.2,0.8,0.2,0.8",
        "-o",
        s(&out),
        "--report",
        s(&rep),
    ]));
    let (a, b) = (surface(&input), surface(&out));
    let r = json_file(&rep);
    assert_eq!(r["kind"], "surface");
    let (fu, fv) = (&r["free_u"], &r["free_v"]);
    let fu = fu[0].as_u64().unwrap() as usize..fu[1].as_u64().unwrap() as usize;
    let fv = fv[0].as_u64().unwrap() as usize..fv[1].as_u64().unwrap() as usize;
    let (nu, nv) = (a.nu(), a.nv());
    let mut moved = 0;
    for i in 0..nu {
        for j in 0..nv {
            let d = a.points()[i * nv + j].distance(b.points()[i * nv + j]);
            if fu.contains(&i) && fv.contains(&j) {
                moved += usize::from(d > 1e-9);
            } else {
                assert!(d <= 1e-12, "held control point ({i}, {j}) moved by {d}");
            }
        }
    }
    assert!(moved > 0);
    let m = &r["measures"];
    for k in [
        "dev_max",
        "dev_rms",
        "hausdorff",
        "n_curv_extrema",
        "E_var",
        "mean_curv_var",
        "n_isophote_inflections",
        "n_isophotes",
    ] {
        assert!(m.get(k).is_some(), "surface report lacks {k}");
    }
    assert!(m["dev_max"].as_f64().unwrap() <= 0.01);
    // the sound bound covers the measured deviation, and says whether it certifies the band
    let bound = r["band_bound"].as_f64().expect("a polynomial surface has a band bound");
    assert!(m["dev_max"].as_f64().unwrap() <= bound * (1.0 + 1e-9));
    assert_eq!(r["band_certified"].as_bool(), Some(bound <= 0.01));
    let o = fairway(&["measure", s(&input), s(&out), "--json"]);
    ok(&o);
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["dev_max"], m["dev_max"]);
    // a curve region on a surface is a usage error with a message
    let bad = fairway(&[
        "fair",
        s(&input),
        "--tolerance",
        "0.01",
        "--region",
        "0.2,0.8",
        "-o",
        s(&out),
    ]);
    fails_with(&bad, 1, "u1,u2,v1,v2");
    let bad = fairway(&["measure", s(&input), s(&reference("s_curve.json")), "--json"]);
    fails_with(&bad, 1, "cannot measure a curve against a surface");
}

/// `--method smoothing` on a surface is the curvature-variation reference smoother: it holds the band, moves the
/// surface, and the default fair is no less fair than it (curvature extrema and ∫∫|∇H|² of the reports);
/// an unknown method is a clear error.
#[test]
fn fair_surface_with_the_reference_smoother() {
    let dir = temp_dir("surface_smoothing");
    let input = reference("saddle.json");
    let mut reports = vec![];
    for method in ["smoothing", "fast"] {
        let (out, rep) = (
            dir.join(format!("{method}.json")),
            dir.join(format!("{method}.report.json")),
        );
        ok(&fairway(&[
            "fair",
            s(&input),
            "--tolerance",
            "0.01",
            "--method",
            method,
            "-o",
            s(&out),
            "--report",
            s(&rep),
        ]));
        let r = json_file(&rep);
        assert_eq!(r["method"], method);
        let moved = surface(&input)
            .points()
            .iter()
            .zip(surface(&out).points())
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max);
        assert!(moved > 1e-6, "{method}: nothing moved");
        assert!(r["measures"]["dev_max"].as_f64().unwrap() <= 0.01);
        reports.push(r["measures"].clone());
    }
    let (sm, fw) = (&reports[0], &reports[1]);
    assert!(
        fw["n_curv_extrema"].as_u64() <= sm["n_curv_extrema"].as_u64(),
        "{fw} vs {sm}"
    );
    assert!(
        fw["mean_curv_var"].as_f64() <= sm["mean_curv_var"].as_f64(),
        "{fw} vs {sm}"
    );
    let bad = fairway(&[
        "fair",
        s(&input),
        "--tolerance",
        "0.01",
        "--method",
        "iterative",
        "-o",
        s(&dir.join("x.json")),
    ]);
    fails_with(&bad, 1, "fast or the smoothing method");
}

#[test]
fn measure_with_a_target() {
    let dir = temp_dir("target");
    let t = dir.join("target.json");
    let input = reference("s_curve.json");
    std::fs::write(&t, "[0.0, 0.0]").unwrap();
    let o = fairway(&["measure", s(&input), s(&input), "--target", s(&t), "--json"]);
    ok(&o);
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    // against a zero target, E is Σ κ² over the 200 samples
    let c = curve(&input);
    let want: f64 = fairway::measure::arc_params(&c, 200)
        .into_iter()
        .map(|u| c.curvature(u).powi(2))
        .sum();
    let got = v["E_paper_target"].as_f64().unwrap();
    assert!((got - want).abs() <= 1e-12 * want, "{got} {want}");
    std::fs::write(&t, "[1.0]").unwrap();
    fails_with(
        &fairway(&["measure", s(&input), s(&input), "--target", s(&t)]),
        1,
        "at least 2",
    );
    std::fs::write(&t, "{\"a\": 1}").unwrap();
    fails_with(
        &fairway(&["measure", s(&input), s(&input), "--target", s(&t)]),
        1,
        "JSON array",
    );
}

#[test]
fn fair_bad_input_gives_clear_errors() {
    let dir = temp_dir("bad");
    let out = dir.join("out.json");
    let input = reference("s_curve.json");
    let run = |extra: &[&str]| {
        let mut args = vec!["fair", s(&input), "-o", s(&out)];
        args.extend_from_slice(extra);
        fairway(&args)
    };
    for t in ["0", "-1"] {
        fails_with(&run(&["--tolerance", t]), 1, "tolerance must be a positive");
    }
    // not a number at all: a usage error, in the length parser's words
    for t in ["NaN", "inf"] {
        fails_with(&run(&["--tolerance", t]), 2, "not a finite length");
    }
    fails_with(&run(&["--tolerance", "0.01", "--region", "1.5,2"]), 1, "region");
    fails_with(
        &run(&["--tolerance", "0.01", "--region", "0.6,0.4"]),
        1,
        "the curve is not closed: give u1 < u2",
    );
    fails_with(&run(&["--tolerance", "0.01", "--region", "0.5,0.51"]), 1, "too small");
    fails_with(&run(&["--tolerance", "0.01", "--region", "a,b"]), 2, "region");
    fails_with(&run(&["--tolerance", "0.01", "--ends", "g5"]), 2, "g0, g1 or g2");
    fails_with(
        &run(&["--tolerance", "0.01", "--target", "median"]),
        2,
        "average, binomial or fit",
    );
    fails_with(
        &run(&["--tolerance", "0.01", "--integrator", "rk9"]),
        2,
        "euler, rk2 or arc",
    );
    fails_with(&run(&["--tolerance", "0.01", "--method", "slow"]), 1, "unknown method");
    fails_with(
        &run(&["--tolerance", "0.01", "--region", "0.2,0.4,0.1,0.9"]),
        1,
        "u1,u2",
    );
    let missing = fairway(&["fair", s(&dir.join("nope.json")), "--tolerance", "0.01", "-o", s(&out)]);
    fails_with(&missing, 1, "nope.json");
    // a report (or output) into a folder that does not exist: said before any work, nothing written
    let report = dir.join("no_such_folder").join("r.json");
    fails_with(
        &run(&["--tolerance", "0.01", "--report", s(&report)]),
        1,
        "cannot write the report",
    );
    let nowhere = dir.join("no_such_folder").join("out.json");
    let lost = fairway(&["fair", s(&input), "--tolerance", "0.01", "-o", s(&nowhere)]);
    fails_with(&lost, 1, "folder");
    assert!(!out.exists(), "no output written on errors");
    // a report that cannot be written although its folder exists (here: it is a folder): the error says
    // that the result was written
    let clash = dir.join("report_is_a_folder");
    std::fs::create_dir_all(&clash).unwrap();
    fails_with(
        &run(&["--tolerance", "0.01", "--report", s(&clash)]),
        1,
        "the result was written to",
    );
    assert!(out.exists());
}

/// A closed, C2 cubic: the uniform periodic B-spline of `n` wavy points around a circle, written
/// exactly as a clamped curve (blossoms at the seam: P0 = (Q₋₁ + 4Q₀ + Q₁)/6, P1 = (2Q₀ + Q₁)/3, …).
fn closed_wavy(n: usize) -> BSplineCurve {
    let q: Vec<fairway::DVec3> = (0..n)
        .map(|j| {
            let t = std::f64::consts::TAU * j as f64 / n as f64;
            let r = 1.0 + 0.01 * ((7 * j) % 5) as f64;
            fairway::DVec3::new(r * t.cos(), r * t.sin(), 0.0)
        })
        .collect();
    fairway::fair::closed::periodic_cubic(&q, 2).unwrap()
}

#[test]
fn fair_closed_curve_across_the_seam() {
    let dir = temp_dir("closed");
    let (input, out, rep) = (dir.join("in.json"), dir.join("out.json"), dir.join("report.json"));
    let c = closed_wavy(40);
    fairway::io::save(&input, &fairway::io::Document::new(Geometry::Curve(c.clone()))).unwrap();
    // `fairway fair` at tolerance 0.005 with `extra` options, writing `out` and the report `rep`
    let fair = |extra: &[&str]| {
        let mut args = vec![
            "fair",
            s(&input),
            "--tolerance",
            "0.005",
            "-o",
            s(&out),
            "--report",
            s(&rep),
        ];
        args.extend_from_slice(extra);
        ok(&fairway(&args));
    };
    fair(&[]);
    let f = curve(&out);
    assert_eq!(json_file(&rep)["seam"], "faired");
    assert_eq!(f.knots().values(), c.knots().values());
    assert!(f.is_closed(1e-12));
    // the seam moved: one pass would have held the first control points
    assert!(f.points()[1].distance(c.points()[1]) > 1e-6);
    assert!(fairway::measure::measure(&c, &f).dev_max <= 0.005);
    // a loop has no ends: --ends does not change the result, and the report's E before and after are
    // both the first pass's (G2, p points held at each end), whatever --ends says
    let r2 = json_file(&rep);
    let n = c.n_points() as u64;
    assert_eq!(r2["free_points"], serde_json::json!([3, n - 3]));
    assert!(r2["energy"].as_f64().unwrap() < r2["energy_before"].as_f64().unwrap());
    for ends in ["g0", "g1"] {
        fair(&["--ends", ends]);
        let r = json_file(&rep);
        assert_eq!(curve(&out).points(), f.points(), "--ends {ends}");
        for key in ["energy_before", "energy", "free_points", "max_deviation_bound"] {
            assert_eq!(r[key], r2[key], "--ends {ends}: {key}");
        }
    }
    // the iterative baseline fairs across the seam too (the same two passes and blend)
    fair(&["--method", "iterative"]);
    let fi = curve(&out);
    assert_eq!(json_file(&rep)["seam"], "faired");
    assert_eq!(fi.knots().values(), c.knots().values());
    assert!(fi.is_closed(1e-12) && fi.points()[1].distance(c.points()[1]) > 1e-6);
    assert!(fairway::measure::measure(&c, &fi).dev_max <= 0.005);
    // a region across the seam (u1 > u2): faired as one stretch, the rest [0.3, 0.7] untouched
    fair(&["--region", "0.7,0.3"]);
    let f = curve(&out);
    assert_eq!(json_file(&rep)["seam"], "faired");
    assert_eq!(f.knots().values(), c.knots().values());
    assert!(f.is_closed(1e-12) && f.points()[0].distance(c.points()[0]) > 1e-6);
    for k in 0..=40 {
        let u = 0.3 + 0.4 * k as f64 / 40.0;
        assert!(f.point(u).distance(c.point(u)) <= 1e-12, "moved at {u}");
    }
    assert!(fairway::measure::measure(&c, &f).dev_max <= 0.005);
}

/// `--polish-iterations` caps the E polish: the same trajectory run longer, so the paper's E never
/// rises with more iterations (and drops from none to the default on a noisy profile); every result
/// keeps the band; a negative count is a usage error.
#[test]
fn polish_iterations_trade_time_for_a_lower_energy() {
    let dir = temp_dir("polish");
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/car_roof.json");
    let m = 0.005;
    let energy = |n: &str| {
        let (out, rep) = (dir.join(format!("out{n}.json")), dir.join(format!("rep{n}.json")));
        ok(&fairway(&[
            "fair",
            s(&input),
            "--tolerance",
            &m.to_string(),
            "--polish-iterations",
            n,
            "-o",
            s(&out),
            "--report",
            s(&rep),
        ]));
        let dev = fairway::measure::measure(&curve(&input), &curve(&out)).dev_max;
        assert!(dev <= m, "{n} iterations: dev_max {dev}");
        json_file(&rep)["energy"].as_f64().unwrap()
    };
    let (e0, e8, e24) = (energy("0"), energy("8"), energy("24"));
    assert!(
        e8 < e0 && e24 <= e8,
        "E with 0 / 8 / 24 polish iterations: {e0} / {e8} / {e24}"
    );
    // the default is 8 iterations
    let (out, rep) = (dir.join("default.json"), dir.join("default_rep.json"));
    ok(&fairway(&[
        "fair",
        s(&input),
        "--tolerance",
        &m.to_string(),
        "-o",
        s(&out),
        "--report",
        s(&rep),
    ]));
    assert_eq!(json_file(&rep)["energy"].as_f64().unwrap(), e8);
    let bad = fairway(&[
        "fair",
        s(&input),
        "--tolerance",
        "0.005",
        "--polish-iterations",
        "-1",
        "-o",
        s(&out),
    ]);
    assert!(!bad.status.success());
}

/// `--ease-ends`: a different fair of an open curve with G2 ends, still in the band, keeping the end
/// curvature; with `--ends g1` the flag changes nothing (there is no kept end curvature to ease into).
#[test]
fn ease_ends_re_fairs_g2_curve_ends_only() {
    let dir = temp_dir("ease");
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/car_roof.json");
    let m = 0.005;
    let fair = |name: &str, extra: &[&str]| {
        let out = dir.join(format!("{name}.json"));
        let mut args = vec!["fair", s(&input), "--tolerance", "0.005", "-o", s(&out)];
        args.extend_from_slice(extra);
        ok(&fairway(&args));
        curve(&out)
    };
    let c0 = curve(&input);
    let (d0, d1) = c0.domain();
    // G2 kept at the curve ends (by default they keep position and tangent only)
    let plain = fair("plain", &["--curve-ends", "g2"]);
    let eased = fair("eased", &["--curve-ends", "g2", "--ease-ends"]);
    assert_ne!(plain.points(), eased.points(), "--ease-ends changed nothing");
    assert!(fairway::measure::measure(&c0, &eased).dev_max <= m);
    for u in [d0, d1] {
        let (k0, k1) = (c0.curvature(u), eased.curvature(u));
        assert!((k0 - k1).abs() < 1e-9 * k0.abs().max(1.0), "end κ {k0} -> {k1}");
    }
    let g1 = fair("g1", &["--ends", "g1"]);
    let g1_eased = fair("g1_eased", &["--ends", "g1", "--ease-ends"]);
    assert_eq!(g1.points(), g1_eased.points());
}

#[test]
fn fair_curve_with_a_corner_keeps_it_and_reports_the_stretches() {
    let dir = temp_dir("corner");
    let (out, rep) = (dir.join("out.json"), dir.join("report.json"));
    // the bundled profile with a 20° kink at the triple knot u = 0.6 (its control point 23)
    let input = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/kinked_profile.json"));
    let c = curve(&input);
    let j = 23;
    let m = 3e-3;
    for method in ["fast", "iterative"] {
        let o = fairway(&[
            "fair",
            s(&input),
            "--tolerance",
            "0.003",
            "--method",
            method,
            "-o",
            s(&out),
            "--report",
            s(&rep),
        ]);
        ok(&o);
        assert!(o.stderr.is_empty(), "{}", String::from_utf8_lossy(&o.stderr));
        let f = curve(&out);
        let r = json_file(&rep);
        assert_eq!(r["corners"].as_array().unwrap().len(), 1, "{method}: {r}");
        assert_eq!(r["corners"][0]["u"], 0.6);
        assert_eq!(r["corners"][0]["stops"], false);
        let angle = r["corners"][0]["angle_deg"].as_f64().unwrap();
        assert!((angle - 20.3).abs() < 0.1, "{angle}");
        let st = r["stretches"].as_array().unwrap();
        assert_eq!(st.len(), 2);
        assert_eq!(st[0]["region"], serde_json::json!([0.0, 0.6]));
        assert_eq!(st[1]["region"], serde_json::json!([0.6, 1.0]));
        assert!(st.iter().all(|x| x.get("left").is_none()));
        // the kink stays: its point exactly, the tangent direction on each side (its neighbours move
        // along it only); the band holds; fairer
        assert_eq!(f.points()[j], c.points()[j], "{method}");
        for (i, k) in [(j - 1, j), (j + 1, j)] {
            let (t0, t1) = (
                (c.points()[k] - c.points()[i]).normalize(),
                (f.points()[k] - f.points()[i]).normalize(),
            );
            assert!(
                t0.distance(t1) < 1e-12,
                "{method}: tangent at the kink from {i}: {t0} -> {t1}"
            );
        }
        assert_ne!(f.points()[10], c.points()[10], "{method}: faired");
        let meas = fairway::measure::measure(&c, &f);
        assert!(meas.dev_max <= m, "{method}: {}", meas.dev_max);
        assert!(
            r["energy"].as_f64().unwrap() < r["energy_before"].as_f64().unwrap(),
            "{method}"
        );
    }
    // a region across the corner is split at it too
    ok(&fairway(&[
        "fair",
        s(&input),
        "--tolerance",
        "0.003",
        "--region",
        "0.2,0.8",
        "-o",
        s(&out),
        "--report",
        s(&rep),
    ]));
    let st = json_file(&rep)["stretches"].clone();
    assert_eq!(st[0]["region"], serde_json::json!([0.2, 0.6]));
    assert_eq!(st[1]["region"], serde_json::json!([0.6, 0.8]));
    // a stretch too short to fair is left with a note on stderr, the rest is faired
    let o = fairway(&[
        "fair",
        s(&input),
        "--tolerance",
        "0.003",
        "--region",
        "0.1,0.62",
        "-o",
        s(&out),
        "--report",
        s(&rep),
    ]);
    ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("the stretch [0.6, 0.62] between corners was left as it is: region [0.6, 0.62] is too small"),
        "{err}"
    );
    let r = json_file(&rep);
    assert!(r["stretches"][1]["left"].as_str().unwrap().contains("too small"));
    assert!(r["stretches"][0].get("left").is_none());
}

/// The bundled closed section with two chines: `fairway fair` keeps both, fairs the section across its
/// seam (re-seamed at the first chine: the report says `faired`, the stretch between the chines through
/// the seam is given as u1 > u2), the result is closed, on the original knots, inside the band and
/// fairer; a region across the seam holding the second chine is split at it.
#[test]
fn fair_a_closed_curve_with_chines_across_its_seam() {
    let dir = temp_dir("chines");
    let (out, rep) = (dir.join("out.json"), dir.join("report.json"));
    let input = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/chined_section.json"));
    let c = curve(&input);
    let m = 3e-3;
    let run = |extra: &[&str]| {
        let mut args = vec![
            "fair",
            s(&input),
            "--tolerance",
            "0.003",
            "-o",
            s(&out),
            "--report",
            s(&rep),
        ];
        args.extend_from_slice(extra);
        let o = fairway(&args);
        ok(&o);
        (curve(&out), json_file(&rep))
    };
    let (f, r) = run(&[]);
    assert_eq!(r["seam"], "faired", "{r}");
    let us: Vec<f64> = r["corners"]
        .as_array()
        .unwrap()
        .iter()
        .map(|k| k["u"].as_f64().unwrap())
        .collect();
    assert_eq!(us, vec![0.375, 0.875]);
    let st = r["stretches"].as_array().unwrap();
    assert_eq!(st[0]["region"], serde_json::json!([0.375, 0.875]));
    assert_eq!(
        st[1]["region"],
        serde_json::json!([0.875, 0.375]),
        "the stretch through the seam"
    );
    assert_eq!(f.knots().values(), c.knots().values());
    assert_eq!(f.points()[0], *f.points().last().unwrap(), "closed");
    assert_ne!(f.points()[0], c.points()[0], "the seam is faired, not held");
    for u in [0.375, 0.875] {
        assert!(f.point(u).distance(c.point(u)) == 0.0, "the chine at {u} moved");
    }
    let (before, after) = (fairway::measure::measure(&c, &c), fairway::measure::measure(&c, &f));
    assert!(after.dev_max <= m, "{}", after.dev_max);
    assert!(after.E_var < 0.5 * before.E_var, "{} -> {}", before.E_var, after.E_var);
    assert!(after.n_curv_extrema < before.n_curv_extrema);
    // a region across the seam that holds the chine at 0.875
    let (f, r) = run(&["--region", "0.8,0.2"]);
    let st = r["stretches"].as_array().unwrap();
    assert_eq!(st[0]["region"], serde_json::json!([0.8, 0.875]));
    assert_eq!(st[1]["region"], serde_json::json!([0.875, 0.2]));
    assert!(fairway::measure::measure(&c, &f).dev_max <= m);
    assert!(f.point(0.5).distance(c.point(0.5)) <= 1e-12, "outside the region");
}

/// `--method smoothing` is the reference smoother: it holds the band, and the default fair is at least as
/// fair as it (fewer or as many curvature extrema, no larger ∫(dκ/ds)²); the report says what each end kept.
#[test]
fn smoothing_method_is_the_reference_and_the_default_is_at_least_as_fair() {
    let dir = temp_dir("smoothing");
    let input = reference("s_curve.json");
    let m = "0.002";
    let run = |method: &str, tag: &str| -> Value {
        let (out, rep) = (dir.join(format!("{tag}.json")), dir.join(format!("{tag}.report.json")));
        ok(&fairway(&[
            "fair",
            input.to_str().unwrap(),
            "--tolerance",
            m,
            "--method",
            method,
            "-o",
            out.to_str().unwrap(),
            "--report",
            rep.to_str().unwrap(),
        ]));
        serde_json::from_str(&std::fs::read_to_string(rep).unwrap()).unwrap()
    };
    let (s, f) = (run("smoothing", "smooth"), run("fast", "fast"));
    for r in [&s, &f] {
        assert!(r["measures"]["dev_max"].as_f64().unwrap() <= 0.002);
        assert!(
            r["ends_kept"][0]
                .as_str()
                .unwrap()
                .starts_with("curve end: position and tangent"),
            "{r}"
        );
    }
    let ext = |r: &Value| r["measures"]["n_curv_extrema"].as_u64().unwrap();
    let ev = |r: &Value| r["measures"]["E_var"].as_f64().unwrap();
    assert!(ext(&f) <= ext(&s) && ev(&f) <= ev(&s), "fast {f} vs smoothing {s}");
    assert_eq!(f["polish"], "variation");
}

/// `--report` or `-o` naming the input (also through a link), or the report naming the output, is refused
/// before any work: nothing is overwritten.
#[test]
fn report_and_output_must_not_overwrite_the_input_or_each_other() {
    let dir = temp_dir("same-files");
    let input = dir.join("a.json");
    std::fs::copy(reference("s_curve.json"), &input).unwrap();
    let before = std::fs::read(&input).unwrap();
    let link = dir.join("link.json");
    #[cfg(unix)]
    std::os::unix::fs::symlink(&input, &link).unwrap();
    let (i, b, l) = (input.to_str().unwrap(), dir.join("b.json"), link.to_str().unwrap());
    let b = b.to_str().unwrap();
    for (args, what) in [
        (vec!["-o", b, "--report", i], "the report"),
        (vec!["-o", i], "the output"),
        (vec!["-o", b, "--report", b], "the report"),
        (vec!["-o", b, "--report", l], "the report"),
        (vec!["-o", l], "the output"),
    ] {
        let mut all = vec!["fair", i, "--tolerance", "0.002"];
        all.extend(args.iter().copied());
        let out = fairway(&all);
        assert!(!out.status.success(), "{all:?} was accepted");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(what), "{all:?}: {err}");
        assert_eq!(std::fs::read(&input).unwrap(), before, "{all:?} changed the input");
    }
    assert!(!dir.join("b.json").exists(), "nothing written");
}

/// `fairway fair` fairs a 3D curve's torsion by default (the library's `TORSION_WEIGHT`), and
/// `--torsion-weight 0` turns it off: on the bundled spatial curve the default ends with far fewer torsion
/// extrema, and no more curvature extrema and no larger ∫(dκ/ds)² than without the term, both in the band.
#[test]
fn a_3d_curve_has_its_torsion_faired_by_default() {
    let dir = temp_dir("torsion");
    let input = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/spatial_curve.json"));
    let run = |extra: &[&str], tag: &str| -> Value {
        let (out, rep) = (dir.join(format!("{tag}.json")), dir.join(format!("{tag}.report.json")));
        let mut args = vec!["fair", input.to_str().unwrap(), "--tolerance", "0.01"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["-o", out.to_str().unwrap(), "--report", rep.to_str().unwrap()]);
        ok(&fairway(&args));
        json_file(&rep)
    };
    let (on, off) = (run(&[], "default"), run(&["--torsion-weight", "0"], "off"));
    let m = |r: &Value, k: &str| r["measures"][k].as_f64().unwrap();
    println!(
        "torsion extrema {} vs {}, curvature extrema {} vs {}, E_var {} vs {}",
        m(&on, "n_torsion_extrema"),
        m(&off, "n_torsion_extrema"),
        m(&on, "n_curv_extrema"),
        m(&off, "n_curv_extrema"),
        m(&on, "E_var"),
        m(&off, "E_var")
    );
    assert!(4.0 * m(&on, "n_torsion_extrema") < m(&off, "n_torsion_extrema"));
    assert!(m(&on, "n_curv_extrema") <= m(&off, "n_curv_extrema"));
    assert!(m(&on, "E_var") <= m(&off, "E_var"));
    for r in [&on, &off] {
        assert!(m(r, "dev_max") <= 0.01 * (1.0 + 1e-9));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
