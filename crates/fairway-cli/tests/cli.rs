//! End-to-end tests of the `fairway` binary: `eval` against reference
//! outputs of an independent implementation (SciPy; see
//! `tests/data/reference/README.md`), `info`, and exit codes / messages on
//! bad input.

use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::Value;

mod common;
use common::*;

fn reference_dir() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/reference"))
}

fn stdout_json(out: &Output) -> Value {
    assert!(
        out.status.success(),
        "exit {:?}, stderr: {}",
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("stdout is JSON")
}

fn flat(v: &Value, out: &mut Vec<f64>) {
    match v {
        Value::Array(a) => a.iter().for_each(|x| flat(x, out)),
        Value::Number(n) => out.push(n.as_f64().unwrap()),
        other => panic!("unexpected JSON value {other}"),
    }
}

/// Shape of a nested array (lengths at each level, first element followed).
fn shape(v: &Value) -> Vec<usize> {
    let mut s = vec![];
    let mut cur = v;
    while let Value::Array(a) = cur {
        s.push(a.len());
        match a.first() {
            Some(x) => cur = x,
            None => break,
        }
    }
    s
}

/// Max difference of two JSON arrays relative to the largest |value| of the reference.
fn rel_diff(reference: &Value, got: &Value) -> f64 {
    assert_eq!(shape(reference), shape(got));
    let (mut a, mut b) = (vec![], vec![]);
    flat(reference, &mut a);
    flat(got, &mut b);
    assert_eq!(a.len(), b.len());
    let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale
}

fn check_eval(name: &str, samples: &str, tolerances: &[(&str, f64)]) {
    let dir = reference_dir();
    let file = dir.join(format!("{name}.json"));
    let out = fairway(&["eval", file.to_str().unwrap(), "--samples", samples, "--json"]);
    let got = stdout_json(&out);
    let text = std::fs::read_to_string(dir.join(format!("{name}.eval.json"))).unwrap();
    let reference: Value = serde_json::from_str(&text).unwrap();
    let got_keys: Vec<&String> = got.as_object().unwrap().keys().collect();
    let ref_keys: Vec<&String> = reference.as_object().unwrap().keys().collect();
    let (mut g, mut r) = (got_keys.clone(), ref_keys.clone());
    g.sort();
    r.sort();
    assert_eq!(g, r, "{name}: output keys");
    for (key, tol) in tolerances {
        let d = rel_diff(&reference[*key], &got[*key]);
        assert!(d <= *tol, "{name}.{key}: relative difference {d:e} > {tol:e}");
    }
}

#[test]
fn eval_2d_curve_matches_reference() {
    check_eval(
        "s_curve",
        "101",
        &[
            ("parameters", 0.0),
            ("points", 1e-12),
            ("d1", 1e-12),
            ("d2", 1e-11),
            ("curvature", 1e-9),
        ],
    );
}

#[test]
fn eval_3d_curve_matches_reference() {
    check_eval(
        "conical_spiral",
        "101",
        &[
            ("parameters", 0.0),
            ("points", 1e-12),
            ("d1", 1e-12),
            ("d2", 1e-11),
            ("curvature", 1e-9),
        ],
    );
}

#[test]
fn eval_surface_matches_reference() {
    check_eval(
        "saddle",
        "21",
        &[
            ("u", 0.0),
            ("v", 0.0),
            ("points", 1e-12),
            ("normals", 1e-12),
            ("k_max", 1e-9),
            ("k_min", 1e-9),
            ("mean", 1e-9),
            ("gauss", 1e-9),
        ],
    );
}

#[test]
fn eval_2d_points_have_two_coordinates() {
    let file = reference_dir().join("s_curve.json");
    let got = stdout_json(&fairway(&["eval", file.to_str().unwrap(), "--samples", "7", "--json"]));
    for key in ["points", "d1", "d2"] {
        assert_eq!(shape(&got[key]), vec![7, 2], "{key}");
    }
    assert_eq!(got["parameters"][0].as_f64(), Some(0.0));
    assert_eq!(got["parameters"][6].as_f64(), Some(1.0));
}

#[test]
fn eval_text_output_has_one_line_per_sample() {
    let file = reference_dir().join("conical_spiral.json");
    let out = fairway(&["eval", file.to_str().unwrap(), "--samples", "5"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(lines.len(), 5);
    // u, 3 point coords, 3 + 3 derivative coords, curvature
    assert_eq!(lines[0].split_whitespace().count(), 11);
}

#[test]
fn info_curve_json() {
    let file = reference_dir().join("s_curve.json");
    let got = stdout_json(&fairway(&["info", file.to_str().unwrap(), "--json"]));
    assert_eq!(got["kind"], "curve");
    assert_eq!(got["dimension"], 2);
    assert_eq!(got["degree"], 3);
    assert_eq!(got["control_points"], 28);
    assert_eq!(got["rational"], false);
    // the reference README: an S-curve with two inflections
    assert_eq!(got["n_inflections"], 2);
    assert_eq!(got["inflections"].as_array().unwrap().len(), 2);
    let g = fairway::io::load_geometry(&file).unwrap();
    let c = g.as_curve().unwrap();
    assert_eq!(got["spans"].as_u64().unwrap() as usize, c.knots().n_spans());
    let len = got["length"].as_f64().unwrap();
    assert!((len - c.length(1e-13)).abs() <= 1e-10 * len);
    // the curvature range contains every curvature of the reference evaluation
    let text = std::fs::read_to_string(reference_dir().join("s_curve.eval.json")).unwrap();
    let reference: Value = serde_json::from_str(&text).unwrap();
    let (kmin, kmax) = (
        got["curvature_min"].as_f64().unwrap(),
        got["curvature_max"].as_f64().unwrap(),
    );
    assert!(kmin < 0.0 && kmax > 0.0);
    for k in reference["curvature"].as_array().unwrap() {
        let k = k.as_f64().unwrap();
        assert!(k >= kmin - 1e-12 && k <= kmax + 1e-12, "{k} outside [{kmin}, {kmax}]");
    }
}

#[test]
fn info_surface_json_and_text() {
    let file = reference_dir().join("saddle.json");
    let got = stdout_json(&fairway(&["info", file.to_str().unwrap(), "--json"]));
    assert_eq!(got["kind"], "surface");
    assert_eq!(got["control_points_u"], 14);
    assert_eq!(got["control_points_v"], 12);
    // a saddle: negative Gaussian curvature everywhere
    assert!(got["gauss_range"][1].as_f64().unwrap() < 0.0);
    let out = fairway(&["info", file.to_str().unwrap()]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("14 × 12"), "{text}");
}

fn expect_failure(args: &[&str], code: i32, needles: &[&str]) {
    let out = fairway(args);
    assert_eq!(out.status.code(), Some(code), "args {args:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    for n in needles {
        assert!(err.contains(n), "stderr of {args:?} lacks {n:?}: {err}");
    }
    if code == 1 {
        assert!(out.stdout.is_empty(), "no output on error");
    }
}

#[test]
fn bad_files_exit_1_with_file_and_problem() {
    let s = Scratch::new("bad");
    let knots = s.file(
        "knots.json",
        r#"{"degree": 3, "knots": [0,0,0,0,0.5,1,1,1,1], "points": [[0,0],[1,1],[2,0],[3,1],[4,0],[5,1]]}"#,
    );
    let k = knots.to_str().unwrap();
    expect_failure(
        &["eval", k, "--json"],
        1,
        &[k, "knots: 9 values, expected 10 for 6 points of degree 3"],
    );
    expect_failure(&["info", k], 1, &[k, "knots"]);
    let empty = s.file("empty.json", "  \n");
    let e = empty.to_str().unwrap();
    expect_failure(&["eval", e], 1, &[e, "empty"]);
    let syntax = s.file("syntax.json", r#"{"degree": 3, "knots": [0,0,"#);
    expect_failure(&["eval", syntax.to_str().unwrap()], 1, &["syntax.json", "JSON"]);
    let ext = s.file("curve.dat", "{}");
    expect_failure(&["eval", ext.to_str().unwrap()], 1, &["curve.dat", "extension"]);
    let pts = s.file("curve.txt", "{}");
    expect_failure(&["eval", pts.to_str().unwrap()], 1, &["curve.txt", "no points found"]);
    let missing = s.path("missing.json");
    expect_failure(
        &["eval", missing.to_str().unwrap()],
        1,
        &["missing.json", "No such file"],
    );
}

#[test]
fn usage_errors_exit_2() {
    let file = reference_dir().join("s_curve.json");
    let f = file.to_str().unwrap();
    expect_failure(&["eval", f, "--samples", "1"], 2, &["--samples"]);
    expect_failure(&["eval", f, "--samples", "many"], 2, &["--samples"]);
    expect_failure(&["eval"], 2, &["FILE"]);
    expect_failure(&["frobnicate"], 2, &["frobnicate"]);
    expect_failure(&[], 2, &["Usage"]);
}

#[test]
fn eval_reads_ron_documents() {
    let s = Scratch::new("ron");
    let src = reference_dir().join("s_curve.json");
    let g = fairway::io::load_geometry(&src).unwrap();
    let ron_path = s.path("s_curve.ron");
    fairway::io::save(&ron_path, &fairway::io::Document::new(g)).unwrap();
    let from_json = stdout_json(&fairway(&["eval", src.to_str().unwrap(), "--samples", "33", "--json"]));
    let from_ron = stdout_json(&fairway(&[
        "eval",
        ron_path.to_str().unwrap(),
        "--samples",
        "33",
        "--json",
    ]));
    assert_eq!(
        from_json, from_ron,
        "RON round trip is exact, so the outputs are identical"
    );
    assert!(Path::new(&ron_path).exists());
}

/// A curve with many inflections: the text summary gives the count with the first and last few, `--json`
/// lists every one (a 1.25 M-point curve printed 903,167 parameters on one line).
#[test]
fn info_summarizes_many_inflections() {
    let n = 60;
    let knots: Vec<f64> = (0..n + 4)
        .map(|i| (i as f64 - 3.0).clamp(0.0, (n - 3) as f64) / (n - 3) as f64)
        .collect();
    let points: Vec<[f64; 2]> = (0..n)
        .map(|i| [i as f64, if i % 2 == 0 { 1.0 } else { -1.0 }])
        .collect();
    let dir = std::env::temp_dir().join(format!("fairway-cli-infl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("zigzag.json");
    let json = serde_json::json!({"degree": 3, "knots": knots, "points": points});
    std::fs::write(&file, json.to_string()).unwrap();
    let got = stdout_json(&fairway(&["info", file.to_str().unwrap(), "--json"]));
    let n_infl = got["n_inflections"].as_u64().unwrap() as usize;
    assert!(n_infl > 40, "{n_infl}");
    assert_eq!(got["inflections"].as_array().unwrap().len(), n_infl);
    let out = fairway(&["info", file.to_str().unwrap()]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let line = text.lines().find(|l| l.contains("inflections")).unwrap();
    assert!(line.contains(&format!("{n_infl} [")), "{line}");
    assert!(line.contains(&format!("{} more", n_infl - 20)), "{line}");
    // 20 parameters listed, not all of them
    assert_eq!(line.matches('.').count(), 20, "{line}");
    std::fs::remove_dir_all(&dir).ok();
}
