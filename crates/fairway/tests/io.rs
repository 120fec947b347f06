//! File formats: exact JSON and RON round trips, extra keys ignored, and a
//! table of malformed files, each with its specific error.

mod shapes;

use fairway::io::{self, Document, DocumentSettings};
use fairway::{BSplineCurve, DVec3, Error, Geometry};
use shapes::*;

/// Bit-exact comparison of every float of two geometries.
fn bits(g: &Geometry) -> Vec<u64> {
    let mut v = vec![];
    let mut push_pts = |pts: &[DVec3], w: Option<&[f64]>, knots: &[&[f64]]| {
        for k in knots {
            v.extend(k.iter().map(|x| x.to_bits()));
        }
        for p in pts {
            v.extend(p.to_array().iter().map(|x| x.to_bits()));
        }
        if let Some(w) = w {
            v.extend(w.iter().map(|x| x.to_bits()));
        }
    };
    match g {
        Geometry::Curve(c) => push_pts(c.points(), c.weights(), &[c.knots().values()]),
        Geometry::Surface(s) => push_pts(s.points(), s.weights(), &[s.knots_u().values(), s.knots_v().values()]),
    }
    v
}

/// Floats that are hard to print and parse exactly.
fn awkward_curve(dim: usize, rational: bool) -> BSplineCurve {
    let vals = [
        0.1 + 0.2,
        1.0 / 3.0,
        std::f64::consts::PI * 1e-7,
        1e-300,
        5e-324,
        -2.2250738585072014e-308,
        123456789.12345679,
        -0.0,
        // the largest magnitudes a model may hold (fairway::range: derivatives up to 1e100 over these
        // knot spans); f64::MAX / 3 and -f64::MAX were used before the range check refused them
        1e95 / 3.0,
        9007199254740993.0,
        2.0f64.sqrt(),
        -1.7976931348623157e95,
        0.7,
        1e22,
        -4.35e-9,
    ];
    let pts: Vec<DVec3> = (0..5)
        .map(|i| {
            DVec3::new(
                vals[3 * i],
                vals[3 * i + 1],
                if dim == 3 { vals[3 * i + 2] } else { 0.0 },
            )
        })
        .collect();
    let knots = vec![0.0, 0.0, 0.0, 0.1 + 0.2, 1.0 / 3.0 + 0.5, 1.0, 1.0, 1.0];
    let w = rational.then(|| vec![1.0 / 3.0, 0.1 + 0.7, 2.0f64.sqrt(), 1e-10, 7.0]);
    BSplineCurve::try_new(2, knots, pts, w, dim).unwrap()
}

fn roundtrip_json(g: &Geometry) {
    let text = io::json::to_string(g);
    let back = io::json::from_str(&text).unwrap();
    assert_eq!(bits(g), bits(&back), "{text}");
    assert_eq!(io::json::to_string(&back), text, "idempotent");
}

fn roundtrip_ron(g: &Geometry) {
    let mut doc = Document::new(g.clone());
    doc.settings = DocumentSettings {
        tolerance: Some(0.1 + 0.2),
        region: Some((1.0 / 3.0, 0.7)),
        target: Some(vec![1e-300, -0.0, 1.0 / 7.0]),
        pinned: vec![0, 2],
        ..Default::default()
    };
    let text = doc.to_ron().unwrap();
    let back = Document::from_ron(&text).unwrap();
    assert_eq!(bits(g), bits(&back.geometry), "{text}");
    assert_eq!(back.settings, doc.settings);
    assert_eq!(back.settings.tolerance.unwrap().to_bits(), (0.1f64 + 0.2).to_bits());
    assert_eq!(back.to_ron().unwrap(), text);
}

#[test]
fn json_and_ron_round_trips_are_bit_exact() {
    let geoms: Vec<Geometry> = vec![
        awkward_curve(2, false).into(),
        awkward_curve(3, false).into(),
        awkward_curve(2, true).into(),
        awkward_curve(3, true).into(),
        wavy_bicubic().into(),
        wavy_rational().into(),
        sphere_octant(1.0 / 3.0).into(),
    ];
    for g in &geoms {
        roundtrip_json(g);
        roundtrip_ron(g);
    }
}

#[test]
fn save_and_load_by_extension() {
    let dir = std::env::temp_dir().join(format!("fairway-io-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let doc = Document::new(wavy_rational().into());
    for name in ["a.json", "a.ron", "a.fairway"] {
        let p = dir.join(name);
        io::save(&p, &doc).unwrap();
        let back = io::load(&p).unwrap();
        assert_eq!(bits(&doc.geometry), bits(&back.geometry), "{name}");
    }
    let e = io::save(&dir.join("a.dat"), &doc).unwrap_err();
    assert!(e.to_string().contains("unknown extension"), "{e}");
    let e = io::load(&dir.join("missing.json")).unwrap_err();
    assert!(
        matches!(e, Error::Io { .. }) && e.to_string().contains("missing.json"),
        "{e}"
    );
    // no temporary files left behind
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left.len(), 3, "{left:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn extra_keys_are_ignored_and_2d_points_stay_2d() {
    let g = io::json::from_str(
        r#"{"name": "x", "meta": {"a": [1, 2]}, "degree": 1, "knots": [0, 0, 1, 1],
            "points": [[0, 0], [1, 2]], "weights": null}"#,
    )
    .unwrap();
    let c = g.as_curve().unwrap();
    assert_eq!(c.dim(), 2);
    assert!(!c.is_rational());
    assert!(io::json::to_string(&g).contains("[[0.0,0.0],[1.0,2.0]]"));
}

const C6: &str = r#""points": [[0,0],[1,1],[2,0],[3,1],[4,0],[5,1]]"#;

/// Checks the variant of an error.
type IsVariant = fn(&Error) -> bool;

/// (what, file text, expected message fragments, variant check)
fn json_cases() -> Vec<(&'static str, String, Vec<&'static str>, IsVariant)> {
    let parse = |e: &Error| matches!(e, Error::Parse { .. });
    vec![
        ("empty file", "".into(), vec!["JSON", "empty"], parse),
        (
            "file of only whitespace",
            "  \n ".into(),
            vec!["JSON: the file holds no data (only whitespace)"],
            parse,
        ),
        (
            "syntax error",
            r#"{"degree": 3, "knots": [0, 0,"#.into(),
            vec!["JSON", "line 1"],
            parse,
        ),
        ("not an object", "[1, 2, 3]".into(), vec!["expected an object"], parse),
        (
            "neither curve nor surface",
            r#"{"name": "x"}"#.into(),
            vec!["neither a curve"],
            parse,
        ),
        (
            "degree is a string",
            format!(r#"{{"degree": "3", "knots": [0,0,0,0,0.3,0.6,1,1,1,1], {C6}}}"#),
            vec!["degree: expected a non-negative integer, found string \"3\""],
            parse,
        ),
        (
            "negative degree",
            format!(r#"{{"degree": -1, "knots": [0,0,0,0,0.3,0.6,1,1,1,1], {C6}}}"#),
            vec!["degree: expected a non-negative integer"],
            parse,
        ),
        (
            "knots not an array",
            format!(r#"{{"degree": 3, "knots": 5, {C6}}}"#),
            vec!["knots: expected an array, found number 5"],
            parse,
        ),
        (
            "coordinate is a string",
            r#"{"degree": 1, "knots": [0,0,1,1], "points": [[0,0],[1,"a"]]}"#.into(),
            vec!["points[1][1]: expected a number, found string \"a\""],
            parse,
        ),
        (
            "point not an array",
            r#"{"degree": 1, "knots": [0,0,1,1], "points": [[0,0], 7]}"#.into(),
            vec!["points[1]: expected an array"],
            parse,
        ),
        (
            "missing knots",
            format!(r#"{{"degree": 3, {C6}}}"#),
            vec!["missing key \"knots\""],
            parse,
        ),
        (
            "missing points",
            r#"{"degree": 3, "knots": [0,0,0,0,1,1,1,1]}"#.into(),
            vec!["missing key \"points\""],
            parse,
        ),
        (
            "knot count",
            format!(r#"{{"degree": 3, "knots": [0,0,0,0,0.5,1,1,1,1], {C6}}}"#),
            vec!["knots: 9 values, expected 10 for 6 points of degree 3"],
            |e| {
                matches!(
                    e,
                    Error::KnotCount {
                        count: 9,
                        expected: 10,
                        ..
                    }
                )
            },
        ),
        (
            "decreasing knots",
            format!(r#"{{"degree": 3, "knots": [0,0,0,0,0.6,0.3,1,1,1,1], {C6}}}"#),
            vec!["knots: knots decrease at index 5"],
            |e| matches!(e, Error::KnotsDecreasing { index: 5, .. }),
        ),
        (
            "not clamped",
            format!(r#"{{"degree": 3, "knots": [0,0,0,0.1,0.3,0.6,1,1,1,1], {C6}}}"#),
            vec!["knots: not clamped", "4 times"],
            |e| matches!(e, Error::KnotsNotClamped { needed: 4, .. }),
        ),
        (
            "interior multiplicity",
            format!(r#"{{"degree": 2, "knots": [0,0,0,0.5,0.5,0.5,1,1,1], {C6}}}"#),
            vec!["knots: interior knot 0.5 has multiplicity 3"],
            |e| matches!(e, Error::KnotMultiplicity { multiplicity: 3, .. }),
        ),
        (
            "empty domain",
            r#"{"degree": 1, "knots": [2,2,2,2], "points": [[0,0],[1,1]]}"#.into(),
            vec!["knots: the parameter domain [2, 2] is empty"],
            |e| matches!(e, Error::EmptyDomain { .. }),
        ),
        (
            "degree zero",
            r#"{"degree": 0, "knots": [0,1], "points": [[0,0]]}"#.into(),
            vec!["degree 0 is not supported"],
            |e| matches!(e, Error::BadDegree { degree: 0, .. }),
        ),
        (
            "too few points",
            r#"{"degree": 3, "knots": [0,0,0,0,1,1,1], "points": [[0,0],[1,1],[2,2]]}"#.into(),
            vec!["points: 3 control points, a curve of degree 3 needs at least 4"],
            |e| matches!(e, Error::TooFewPoints { .. }),
        ),
        (
            "zero weight",
            r#"{"degree": 1, "knots": [0,0,1,1], "points": [[0,0],[1,1]], "weights": [1, 0]}"#.into(),
            vec!["weights: weight 0 at index 1 must be positive"],
            |e| matches!(e, Error::BadWeight { index: 1, .. }),
        ),
        (
            "negative weight",
            r#"{"degree": 1, "knots": [0,0,1,1], "points": [[0,0],[1,1]], "weights": [-1, 1]}"#.into(),
            vec!["weights: weight -1 at index 0"],
            |e| matches!(e, Error::BadWeight { index: 0, .. }),
        ),
        (
            "weight count",
            r#"{"degree": 1, "knots": [0,0,1,1], "points": [[0,0],[1,1]], "weights": [1]}"#.into(),
            vec!["weights: 1 values, expected 2"],
            |e| matches!(e, Error::LengthMismatch { .. }),
        ),
        (
            "mixed dimensions",
            r#"{"degree": 1, "knots": [0,0,1,1], "points": [[0,0],[1,1,1]]}"#.into(),
            vec!["points: point 1 has 3 coordinates, expected 2"],
            |e| {
                matches!(
                    e,
                    Error::BadDimension {
                        index: 1,
                        found: 3,
                        expected: 2,
                        ..
                    }
                )
            },
        ),
        (
            "one-dimensional points",
            r#"{"degree": 1, "knots": [0,0,1,1], "points": [[0],[1]]}"#.into(),
            vec!["points: point 0 has 1 coordinates"],
            |e| matches!(e, Error::BadDimension { found: 1, .. }),
        ),
        (
            "number too large",
            r#"{"degree": 1, "knots": [0,0,1,1], "points": [[0,0],[1e999,1]]}"#.into(),
            vec!["JSON"],
            parse,
        ),
        (
            "surface row length",
            r#"{"degree_u": 1, "degree_v": 1, "knots_u": [0,0,1,1], "knots_v": [0,0,1,1],
                "points": [[[0,0,0],[0,1,0]], [[1,0,0]]]}"#
                .into(),
            vec!["points[1]: 1 values, expected 2"],
            |e| matches!(e, Error::LengthMismatch { .. }),
        ),
        (
            "surface 2D points",
            r#"{"degree_u": 1, "degree_v": 1, "knots_u": [0,0,1,1], "knots_v": [0,0,1,1],
                "points": [[[0,0],[0,1]], [[1,0],[1,1]]]}"#
                .into(),
            vec!["points: point 0 has 2 coordinates, expected 3"],
            |e| matches!(e, Error::BadDimension { .. }),
        ),
        (
            "surface knots_v count",
            r#"{"degree_u": 1, "degree_v": 1, "knots_u": [0,0,1,1], "knots_v": [0,0,1],
                "points": [[[0,0,0],[0,1,0]], [[1,0,0],[1,1,0]]]}"#
                .into(),
            vec!["knots_v: 3 values, expected 4 for 2 points of degree 1"],
            |e| matches!(e, Error::KnotCount { .. }),
        ),
        (
            "surface missing degree_v",
            r#"{"degree_u": 1, "knots_u": [0,0,1,1], "knots_v": [0,0,1,1], "points": []}"#.into(),
            vec!["missing key \"degree_v\""],
            parse,
        ),
        (
            "surface weights shape",
            r#"{"degree_u": 1, "degree_v": 1, "knots_u": [0,0,1,1], "knots_v": [0,0,1,1],
                "points": [[[0,0,0],[0,1,0]], [[1,0,0],[1,1,0]]], "weights": [[1,1],[1]]}"#
                .into(),
            vec!["weights: expected 2 rows of 2 values"],
            |e| matches!(e, Error::InvalidInput(_)),
        ),
    ]
}

#[test]
fn malformed_json_files_give_specific_errors() {
    for (what, text, needles, variant) in json_cases() {
        let e = match io::json::from_str(&text) {
            Ok(g) => panic!("{what}: accepted as {g:?}"),
            Err(e) => e,
        };
        let msg = e.to_string();
        for n in &needles {
            assert!(msg.contains(n), "{what}: message {msg:?} lacks {n:?}");
        }
        assert!(variant(&e), "{what}: unexpected variant {e:?}");
    }
}

#[test]
fn malformed_ron_documents_give_specific_errors() {
    let good = Document::new(wavy_bicubic().into()).to_ron().unwrap();
    assert!(Document::from_ron(&good).is_ok());
    let curve = r#"geometry: Curve((degree: 1, knots: [0.0, 0.0, 1.0, 1.0], points: [[0.0, 0.0], [1.0, NaN]]))"#;
    let cases: Vec<(&str, String, &str, IsVariant)> = vec![
        ("empty", "".into(), "RON: the file is empty", |e| {
            matches!(e, Error::Parse { .. })
        }),
        (
            "wrong format",
            good.replacen("\"fairway\"", "\"other\"", 1),
            "format is \"other\", expected \"fairway\"",
            |e| matches!(e, Error::Parse { .. }),
        ),
        (
            "future version",
            good.replacen("version: 1", "version: 99", 1),
            "document version 99 is not supported",
            |e| matches!(e, Error::Parse { .. }),
        ),
        (
            "unknown field",
            good.replacen("version: 1,", "version: 1, colour: 3,", 1),
            "colour",
            |e| matches!(e, Error::Parse { .. }),
        ),
        (
            "NaN coordinate",
            format!("(format: \"fairway\", version: 1, {curve})"),
            "points: value at index 1 is not a finite number",
            |e| matches!(e, Error::NotFinite { index: 1, .. }),
        ),
        (
            "negative tolerance",
            good.replacen("tolerance: None", "tolerance: Some(-1.0)", 1),
            "settings.tolerance: -1 must be a positive number",
            |e| matches!(e, Error::Parse { .. }),
        ),
        (
            "bad knots inside a document",
            format!(
                "(format: \"fairway\", version: 1, {})",
                curve
                    .replace("NaN", "1.0")
                    .replace("[0.0, 0.0, 1.0, 1.0]", "[0.0, 1.0, 1.0, 1.0]")
            ),
            "knots: not clamped",
            |e| matches!(e, Error::KnotsNotClamped { .. }),
        ),
    ];
    for (what, text, needle, variant) in cases {
        let e = match Document::from_ron(&text) {
            Ok(_) => panic!("{what}: accepted:\n{text}"),
            Err(e) => e,
        };
        assert!(e.to_string().contains(needle), "{what}: {e}");
        assert!(variant(&e), "{what}: {e:?}");
    }
}

/// Settings that cannot apply to the document's geometry are dropped (or reordered) with a message
/// that names them; the geometry and the settings that fit stay as they were.
#[test]
fn settings_that_do_not_fit_the_geometry_are_dropped_with_a_message() {
    let open = Geometry::Curve(wiggly_2d());
    let (d0, d1) = wiggly_2d().domain();
    let mid = |t: f64| d0 + t * (d1 - d0);
    let with = |g: &Geometry, f: &dyn Fn(&mut DocumentSettings)| {
        let mut d = Document::new(g.clone());
        d.settings.tolerance = Some(0.01);
        f(&mut d.settings);
        // through the file, as the editor gets it
        let mut back = Document::from_ron(&d.to_ron().unwrap()).unwrap();
        let notes = back.sanitize_settings();
        assert_eq!(bits(&back.geometry), bits(g), "the geometry is kept");
        assert_eq!(back.settings.tolerance, Some(0.01), "the settings that fit are kept");
        (back.settings, notes)
    };
    // fitting settings: no message, nothing changes
    let (s, notes) = with(&open, &|s| {
        s.region = Some((mid(0.2), mid(0.6)));
        s.target = Some(vec![0.5; 7]);
        s.pinned = vec![2];
    });
    assert!(notes.is_empty(), "{notes:?}");
    assert_eq!(s.region, Some((mid(0.2), mid(0.6))));
    assert_eq!((s.target.as_ref().map(Vec::len), s.pinned), (Some(7), vec![2]));
    // dropped regions, each with a message naming the problem
    for (r, needle) in [
        ((f64::NAN, mid(0.5)), "not finite"),
        ((mid(0.3), f64::INFINITY), "not finite"),
        ((mid(0.4), mid(0.4)), "empty"),
        ((mid(0.2), d1 + 1.0), "outside the domain"),
        ((d0 - 1.0, mid(0.5)), "outside the domain"),
    ] {
        let (s, notes) = with(&open, &|s| s.region = Some(r));
        assert_eq!(s.region, None, "{r:?}");
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(
            notes[0].contains(needle) && notes[0].contains("region"),
            "{r:?}: {notes:?}"
        );
    }
    // backwards on an open curve: reordered, and said
    let (s, notes) = with(&open, &|s| s.region = Some((mid(0.8), mid(0.2))));
    assert_eq!(s.region, Some((mid(0.2), mid(0.8))));
    assert!(notes.len() == 1 && notes[0].contains("backwards"), "{notes:?}");
    // backwards on a closed curve: a region across the seam, kept as it is
    let closed = Geometry::Curve(circle(1.0));
    let (c0, c1) = circle(1.0).domain();
    let r = (c0 + 0.8 * (c1 - c0), c0 + 0.2 * (c1 - c0));
    let (s, notes) = with(&closed, &|s| s.region = Some(r));
    assert!(notes.is_empty(), "{notes:?}");
    assert_eq!(s.region, Some(r));
    // a target with a NaN goes with its pins
    let (s, notes) = with(&open, &|s| {
        s.target = Some(vec![0.1, f64::NAN, 0.3]);
        s.pinned = vec![0, 2];
    });
    assert_eq!((s.target, s.pinned), (None, vec![]));
    assert!(notes.len() == 1 && notes[0].contains("sample 1"), "{notes:?}");
    // regions of the other kind
    let (s, notes) = with(&open, &|s| s.region_uv = Some(((0.1, 0.2), (0.3, 0.4))));
    assert!(
        s.region_uv.is_none() && notes.len() == 1 && notes[0].contains("surface region"),
        "{notes:?}"
    );
    let surf = Geometry::Surface(wavy_bicubic());
    let ((u0, u1), (v0, v1)) = wavy_bicubic().domain();
    let (su, sv) = (|t: f64| u0 + t * (u1 - u0), |t: f64| v0 + t * (v1 - v0));
    let (s, notes) = with(&surf, &|s| s.region = Some((su(0.1), su(0.2))));
    assert!(
        s.region.is_none() && notes.len() == 1 && notes[0].contains("curve region"),
        "{notes:?}"
    );
    // surface regions: backwards ends reordered, bad ones dropped
    let (s, notes) = with(&surf, &|s| s.region_uv = Some(((su(0.7), su(0.2)), (sv(0.1), sv(0.5)))));
    assert_eq!(s.region_uv, Some(((su(0.2), su(0.7)), (sv(0.1), sv(0.5)))));
    assert!(notes.len() == 1 && notes[0].contains("backwards"), "{notes:?}");
    let (s, notes) = with(&surf, &|s| {
        s.region_uv = Some(((su(0.2), su(0.7)), (sv(0.1), v1 + 5.0)))
    });
    assert_eq!(s.region_uv, None);
    assert!(
        notes.len() == 1 && notes[0].contains("in v") && notes[0].contains("outside"),
        "{notes:?}"
    );
}
