//! The CLI rows of docs/DEGENERATE_INPUTS.md: each bad input or request exits
//! with code 1, prints exactly one line `fairway: error: ...` with the
//! message, and leaves an existing output file untouched.

use std::path::PathBuf;
use std::process::Command;

#[test]
fn degenerate_inputs_exit_1_with_the_exact_message_and_keep_the_output() {
    let dir = std::env::temp_dir().join(format!("fairway-cli-degenerate-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = |name: &str, text: &str| -> String {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let empty = file("empty.json", "");
    let types = file(
        "types.json",
        r#"{"degree": "3", "knots": [0,0,1,1], "points": [[0,0],[1,1]]}"#,
    );
    let coincident = file("same.csv", "1,2\n1,2\n1,2\n1,2\n");
    let curve = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/reference/s_curve.json"
    ));
    let c = curve.to_str().unwrap().to_string();
    let out = dir.join("out.json");
    let o = out.to_str().unwrap().to_string();
    std::fs::write(&out, "previous result").unwrap();
    let too_many = |n: &str| {
        format!(
            "fairing setup: {n} samples are too many: at most 2000000 (each million takes about 0.4 GB of memory); \
             ask for fewer samples, or fair a region of the curve"
        )
    };
    let rows: Vec<(Vec<&str>, String)> = vec![
        (
            vec!["fair", &empty, "--tolerance", "0.01", "-o", &o],
            format!("{empty}: JSON: the file is empty"),
        ),
        (
            vec!["fair", &types, "--tolerance", "0.01", "-o", &o],
            format!(r#"{types}: JSON: degree: expected a non-negative integer, found string "3""#),
        ),
        (vec!["convert", &empty, &o], format!("{empty}: JSON: the file is empty")),
        (
            vec!["convert", &coincident, &o],
            format!(
                "{coincident}: degenerate geometry: all 4 points coincide (or their extent overflows): no curve can be fitted"
            ),
        ),
        (
            vec!["fair", &c, "--tolerance", "0", "-o", &o],
            "--tolerance must be a positive finite number, got 0".into(),
        ),
        (
            vec!["fair", &c, "--tolerance", "-0.01", "-o", &o],
            "--tolerance must be a positive finite number, got -0.01".into(),
        ),
        (
            vec!["fair", &c, "--tolerance", "0.01", "--region", "0.5,0.5", "-o", &o],
            "fairing setup: region [0.5, 0.5] is empty (u1 must be < u2)".into(),
        ),
        (
            vec!["fair", &c, "--tolerance", "0.01", "--region", "0.5,1.5", "-o", &o],
            "fairing setup: region end: 1.5 is outside the domain [0, 1]".into(),
        ),
        (
            vec!["fair", &c, "--tolerance", "0.01", "--samples", "100000000", "-o", &o],
            too_many("100000000"),
        ),
        (
            vec![
                "fair",
                &c,
                "--tolerance",
                "0.01",
                "--method",
                "iterative",
                "--samples",
                "2000001",
                "-o",
                &o,
            ],
            too_many("2000001"),
        ),
        (
            vec![
                "fair",
                &c,
                "--tolerance",
                "0.01",
                "--samples",
                "1000",
                "--target",
                "average",
                "--strength",
                "99999999",
                "-o",
                &o,
            ],
            "fairing setup: target strength 99999999 is too much work for the average target: its passes cost \
             strength × samples, and 1000 samples allow at most 1000000 passes; use the heat target (the implicit \
             heat flow of the averaging), whose cost stays bounded at any strength"
                .into(),
        ),
    ];
    for (args, want) in rows {
        let r = Command::new(env!("CARGO_BIN_EXE_fairway"))
            .args(&args)
            .output()
            .unwrap();
        assert_eq!(r.status.code(), Some(1), "{args:?}");
        assert_eq!(
            String::from_utf8_lossy(&r.stderr),
            format!("fairway: error: {want}\n"),
            "{args:?}"
        );
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "previous result", "{args:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
