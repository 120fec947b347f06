//! Issue 26, the CLI side: no file is lost (output through a link, the input as the output), numbers near
//! the limits of f64 are refused with one message (no command writes NaN or inf, or exits 0 with them),
//! reads are bounded (size limit, special files), and a document's region is honoured or refused. Each
//! case checks the exact stderr line and exit code 1, and that nothing was written.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn reference(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/reference")).join(name)
}

fn run(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_fairway"));
    c.args(args).env_remove("FAIRWAY_MAX_INPUT_BYTES");
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run the fairway binary")
}

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fairway-cli-limits-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Exit 1 with exactly `fairway: error: <want>` on stderr, nothing on stdout.
fn fails(args: &[&str], env: &[(&str, &str)], want: &str) {
    let out = run(args, env);
    assert_eq!(
        out.status.code(),
        Some(1),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!("fairway: error: {want}\n"),
        "{args:?}"
    );
    assert!(
        out.stdout.is_empty(),
        "{args:?} printed {}",
        String::from_utf8_lossy(&out.stdout)
    );
}

fn ok(out: &Output) {
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
}

/// The s-curve of the reference data with one coordinate or the knots changed.
fn s_curve_with(dir: &Path, name: &str, edit: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(reference("s_curve.json")).unwrap()).unwrap();
    edit(&mut v);
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string(&v).unwrap()).unwrap();
    p
}

const BIG: &str = "points: control point 3 has a coordinate of 1e308, beyond the 1e100 Fairway computes with \
                   (squared distances and curvatures would overflow): rescale the model";

#[test]
fn numbers_near_the_limits_of_f64_are_refused_by_every_command() {
    let dir = temp_dir("range");
    let big = s_curve_with(&dir, "big.json", |v| v["points"][3][1] = 1e308.into());
    let b = s(&big).to_string();
    let c = reference("s_curve.json");
    let out = dir.join("out.svg");
    let o = s(&out).to_string();
    fails(&["info", &b], &[], &format!("{b}: {BIG}"));
    fails(&["info", "--json", &b], &[], &format!("{b}: {BIG}"));
    fails(&["eval", "--json", &b], &[], &format!("{b}: {BIG}"));
    fails(&["measure", s(&c), &b], &[], &format!("{b}: {BIG}"));
    fails(&["convert", &b, &o], &[], &format!("{b}: {BIG}"));
    fails(
        &["fair", &b, "--tolerance", "0.01", "-o", &o],
        &[],
        &format!("{b}: {BIG}"),
    );
    assert!(!out.exists());

    // knots scaled by 1e300 (length 0 before) and by 1e-300 (NaN before)
    let scale = |f: f64| {
        move |v: &mut serde_json::Value| {
            let k: Vec<f64> = v["knots"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap() * f)
                .collect();
            v["knots"] = k.into();
        }
    };
    let long = s_curve_with(&dir, "long.json", scale(1e300));
    fails(
        &["info", s(&long)],
        &[],
        &format!(
            "{}: knots: the domain [0, 1e300] is too long for control points spanning 3.081: first derivatives \
             (speeds) of about 1e-300 would underflow (Fairway computes with derivatives between 1e-100 and 1e100): \
             rescale the knots, e.g. to [0, 1]",
            s(&long)
        ),
    );
    let short = s_curve_with(&dir, "short.json", scale(1e-300));
    fails(
        &["info", s(&short)],
        &[],
        &format!(
            "{}: knots: the knot span [6.3644e-301, 6.7075e-301] (length 3.4307e-302) is too short for control points \
             spanning 3.081: first derivatives (speeds) of about 1e302 would overflow (Fairway computes with \
             derivatives between 1e-100 and 1e100): rescale the knots, e.g. to [0, 1], or remove the \
             near-duplicate knot",
            s(&short)
        ),
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_tolerance_below_the_precision_of_the_coordinates_is_refused_for_curves_and_surfaces_alike() {
    let dir = temp_dir("tolerance");
    let o = dir.join("out.json");
    for (name, size, eps, min) in [
        ("s_curve.json", "3.0001", "6.6615e-16", "3.0001e-13"),
        ("saddle.json", "1", "2.2205e-16", "1e-13"),
    ] {
        fails(
            &["fair", s(&reference(name)), "--tolerance", "1e-300", "-o", s(&o)],
            &[],
            &format!(
                "--tolerance 1e-300 is below the precision of the coordinates: they reach {size} in magnitude, \
                 where a double resolves about {eps}, so the smallest tolerance is {min} (1e-13 × {size})"
            ),
        );
    }
    assert!(!o.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_svg_whose_drawing_would_overflow_is_refused() {
    let dir = temp_dir("svg");
    let out = dir.join("out.svg");
    let c = reference("s_curve.json");
    fails(
        &["convert", s(&c), s(&out), "--band", "1e308"],
        &[],
        &format!(
            "{}: the drawing's coordinates overflow (the curve spans 3.081, the band is inf wide): nothing was written",
            s(&out)
        ),
    );
    assert!(!out.exists());
    // an ordinary band is drawn, all finite
    ok(&run(&["convert", s(&c), s(&out), "--band", "0.01"], &[]));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(!text.contains("NaN") && !text.contains("inf"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn reads_are_bounded_and_special_files_refused_at_once() {
    let dir = temp_dir("bounded");
    let c = reference("s_curve.json");
    let len = std::fs::metadata(&c).unwrap().len();
    let small = (len - 1).to_string();
    let kb = |n: u64| format!("{:.1} kB", n as f64 / 1e3);
    fails(
        &["info", s(&c)],
        &[("FAIRWAY_MAX_INPUT_BYTES", &small)],
        &format!(
            "{}: is {} ({len} bytes), more than the limit of {} ({small} bytes); set FAIRWAY_MAX_INPUT_BYTES to \
             a larger number of bytes to read it",
            s(&c),
            kb(len),
            kb(len - 1)
        ),
    );
    ok(&run(&["info", s(&c)], &[("FAIRWAY_MAX_INPUT_BYTES", &len.to_string())]));
    fails(
        &["info", s(&c)],
        &[("FAIRWAY_MAX_INPUT_BYTES", "2GB")],
        &format!(
            "{}: FAIRWAY_MAX_INPUT_BYTES=\"2GB\" is not a number of bytes (e.g. FAIRWAY_MAX_INPUT_BYTES=5000000000)",
            s(&c)
        ),
    );
    // a link to an endless device: refused before reading (it used to read until memory ran out)
    #[cfg(unix)]
    {
        let zero = dir.join("zero.json");
        std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
        let t = std::time::Instant::now();
        fails(
            &["info", s(&zero)],
            &[],
            &format!(
                "{}: is a character device, not a regular file: only files are read",
                s(&zero)
            ),
        );
        assert!(t.elapsed().as_secs_f64() < 5.0, "{:?}", t.elapsed());
        let zero_igs = dir.join("zero.igs");
        std::os::unix::fs::symlink("/dev/zero", &zero_igs).unwrap();
        fails(
            &["convert", s(&zero_igs), s(&dir.join("o.json"))],
            &[],
            &format!(
                "{}: is a character device, not a regular file: only files are read",
                s(&zero_igs)
            ),
        );
    }
    let folder = dir.join("folder.json");
    std::fs::create_dir(&folder).unwrap();
    fails(
        &["info", s(&folder)],
        &[],
        &format!("{}: is a folder, not a regular file: only files are read", s(&folder)),
    );
    // a file of only spaces is not "empty"
    let spaces = dir.join("spaces.json");
    std::fs::write(&spaces, vec![b' '; 100_000]).unwrap();
    fails(
        &["info", s(&spaces)],
        &[],
        &format!("{}: JSON: the file holds no data (only whitespace)", s(&spaces)),
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[cfg(unix)]
#[test]
fn output_through_a_link_keeps_the_link_and_the_mode_of_its_file() {
    use std::os::unix::fs::PermissionsExt;
    let dir = temp_dir("link-out");
    let real = dir.join("real.json");
    std::fs::write(&real, "old").unwrap();
    std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o600)).unwrap();
    let link = dir.join("link.json");
    std::os::unix::fs::symlink("real.json", &link).unwrap();
    let rep_real = dir.join("report-real.json");
    let rep = dir.join("report.json");
    std::os::unix::fs::symlink(&rep_real, &rep).unwrap();
    let c = reference("s_curve.json");
    ok(&run(
        &[
            "fair",
            s(&c),
            "--tolerance",
            "0.01",
            "-o",
            s(&link),
            "--report",
            s(&rep),
        ],
        &[],
    ));
    for l in [&link, &rep] {
        assert!(
            std::fs::symlink_metadata(l).unwrap().file_type().is_symlink(),
            "{l:?} was replaced"
        );
    }
    let faired = fairway::io::load_geometry(&real).unwrap();
    assert!(faired.as_curve().is_some());
    assert_eq!(std::fs::metadata(&real).unwrap().permissions().mode() & 0o777, 0o600);
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&rep_real).unwrap()).unwrap();
    assert_eq!(report["kind"], "curve");
    // convert through a link too
    ok(&run(&["convert", s(&c), s(&link)], &[]));
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
    assert_eq!(std::fs::metadata(&real).unwrap().permissions().mode() & 0o777, 0o600);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn convert_refuses_to_write_over_its_input() {
    let dir = temp_dir("convert-same");
    let input = dir.join("a.json");
    std::fs::copy(reference("s_curve.json"), &input).unwrap();
    let before = std::fs::read(&input).unwrap();
    fails(
        &["convert", s(&input), s(&input)],
        &[],
        &format!(
            "the output {} is the input file: write the result to another file",
            s(&input)
        ),
    );
    #[cfg(unix)]
    {
        let link = dir.join("link.json");
        std::os::unix::fs::symlink(&input, &link).unwrap();
        fails(
            &["convert", s(&input), s(&link)],
            &[],
            &format!(
                "the output {} is the input file: write the result to another file",
                s(&link)
            ),
        );
    }
    assert_eq!(std::fs::read(&input).unwrap(), before);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A .ron document of the s-curve with the given settings.
fn document(dir: &Path, name: &str, settings: &str) -> PathBuf {
    let g = fairway::io::load_geometry(&reference("s_curve.json")).unwrap();
    let text = fairway::io::Document::new(g).to_ron().unwrap();
    // the document of a geometry alone ends with its default settings: replace them
    let i = text.rfind("settings:").expect("settings written");
    let text = format!("{}settings: {settings},\n)\n", &text[..i]);
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn the_region_of_a_document_is_faired_unless_region_is_given_and_refused_if_invalid() {
    let dir = temp_dir("doc-region");
    let c = fairway::io::load_geometry(&reference("s_curve.json")).unwrap();
    let c = c.as_curve().unwrap().clone();
    let (o, rep) = (dir.join("out.json"), dir.join("rep.json"));
    let doc = document(&dir, "r.ron", "(region: Some((0.3, 0.7)))");
    let out = run(
        &["fair", s(&doc), "--tolerance", "0.01", "-o", s(&o), "--report", s(&rep)],
        &[],
    );
    ok(&out);
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!(
            "fairway: {}: fairing the document's region 0.3, 0.7 (--region overrides it)\n",
            s(&doc)
        )
    );
    // outside [0.3, 0.7] the curve is unchanged: the control points whose support lies outside are kept
    let f = fairway::io::load_geometry(&o).unwrap().as_curve().unwrap().clone();
    let moved: Vec<usize> = (0..c.n_points()).filter(|&i| c.points()[i] != f.points()[i]).collect();
    assert!(!moved.is_empty(), "nothing faired");
    let k = c.knots().values();
    let p = c.degree();
    for &i in &moved {
        assert!(
            k[i] >= 0.3 - 1e-12 && k[i + p + 1] <= 0.7 + 1e-12,
            "control point {i} moved outside the region"
        );
    }
    let fr = |args: &[&str]| {
        let mut a = vec!["fair", s(&doc), "--tolerance", "0.01", "-o", s(&o)];
        a.extend(args);
        ok(&run(&a, &[]));
        fairway::io::load_geometry(&o).unwrap().as_curve().unwrap().clone()
    };
    // --region overrides it: the same result as a document without a region, faired over 0,1
    let whole = fr(&["--region", "0,1"]);
    assert_ne!(whole.points(), f.points());
    let plain = document(&dir, "none.ron", "()");
    let out = run(&["fair", s(&plain), "--tolerance", "0.01", "-o", s(&o)], &[]);
    ok(&out);
    assert!(out.stderr.is_empty(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(
        fairway::io::load_geometry(&o).unwrap().as_curve().unwrap().points(),
        whole.points()
    );
    // without --region, the document's region again
    assert_eq!(fr(&[]).points(), f.points());
    // invalid regions are refused with the reason, before any output
    std::fs::remove_file(&o).unwrap();
    for (name, settings, why) in [
        (
            "out.ron",
            "(region: Some((0.5, 1.5)))",
            "settings.region (0.5, 1.5) is outside the domain [0, 1]",
        ),
        (
            "empty.ron",
            "(region: Some((0.4, 0.4)))",
            "settings.region (0.4, 0.4) is empty",
        ),
        (
            "nan.ron",
            "(region: Some((NaN, 0.4)))",
            "settings.region (NaN, 0.4) is not finite",
        ),
        (
            "back.ron",
            "(region: Some((0.7, 0.3)))",
            "settings.region (0.7, 0.3) runs backwards on an open curve (only a closed curve has a region across \
             its seam)",
        ),
        (
            "uv.ron",
            "(region_uv: Some(((0.1, 0.2), (0.3, 0.4))))",
            "settings.region_uv is a surface region, but the document holds a curve",
        ),
    ] {
        let d = document(&dir, name, settings);
        fails(
            &["fair", s(&d), "--tolerance", "0.01", "-o", s(&o)],
            &[],
            &format!("{}: {why}: correct it in the document, or give --region", s(&d)),
        );
        assert!(!o.exists(), "{name}");
        // --region overrides an invalid one too
        ok(&run(
            &["fair", s(&d), "--tolerance", "0.01", "--region", "0.2,0.8", "-o", s(&o)],
            &[],
        ));
        std::fs::remove_file(&o).unwrap();
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
