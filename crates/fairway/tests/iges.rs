//! IGES interchange: a structural check of written files against the IGES 5.3
//! fixed-format rules, exact round trips (curves 2D/3D, surfaces, rational or
//! not, also for random geometry), and a hand-written multi-entity file "from
//! another system" with entities that are skipped with a notice.

mod shapes;

use fairway::io::iges::{self, WriteOptions};
use fairway::{BSplineCurve, BSplineSurface, DVec3, Geometry};
use proptest::prelude::*;
use shapes::*;

/// Split free-format parameter text at `,` up to the first `;`, honouring
/// Hollerith strings `nH...` (independent of the reader under test).
fn split_params(text: &str) -> Result<Vec<String>, String> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    loop {
        while i < b.len() && b[i] == b' ' {
            i += 1;
        }
        let start = i;
        let mut j = i;
        while j < b.len() && b[j].is_ascii_digit() {
            j += 1;
        }
        if j > i && j < b.len() && b[j] == b'H' {
            let n: usize = text[i..j].parse().map_err(|_| "bad Hollerith count")?;
            if j + 1 + n > b.len() {
                return Err("Hollerith string runs past the end".into());
            }
            out.push(text[j + 1..j + 1 + n].to_string());
            i = j + 1 + n;
        } else {
            while i < b.len() && b[i] != b',' && b[i] != b';' {
                i += 1;
            }
            out.push(text[start..i].trim().to_string());
        }
        match b.get(i) {
            Some(b',') => i += 1,
            Some(b';') => return Ok(out),
            _ => return Err(format!("no record delimiter ';' (stopped at column {i} of {text:?})")),
        }
    }
}

/// Check a fixed-format IGES file against the rules of IGES 5.3 §2: 80-column
/// records, section letters S G D P T in order, sequence numbers from 1 in
/// each section, directory entries in pairs with matching entity types,
/// parameter pointers and line counts that cover the P section exactly once,
/// P back pointers to the owning directory entry, parameter data starting
/// with the entity type and the right number of parameters for 126/128, and
/// the terminate record's counts.
fn check_iges_5_3(text: &str) -> Result<(), String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut sections: Vec<(u8, Vec<&str>)> = vec![];
    for (n, l) in lines.iter().enumerate() {
        if l.len() != 80 || !l.bytes().all(|c| (32..127).contains(&c)) {
            return Err(format!(
                "line {}: {} columns or non-printable characters",
                n + 1,
                l.len()
            ));
        }
        let letter = l.as_bytes()[72];
        match sections.last_mut() {
            Some((s, v)) if *s == letter => v.push(l),
            _ => sections.push((letter, vec![l])),
        }
    }
    let order: Vec<u8> = sections.iter().map(|s| s.0).collect();
    if order != b"SGDPT" {
        return Err(format!("sections in order {:?}", String::from_utf8_lossy(&order)));
    }
    for (letter, v) in &sections {
        for (k, l) in v.iter().enumerate() {
            let seq: usize = l[73..80]
                .trim()
                .parse()
                .map_err(|_| format!("{}: bad sequence field {:?}", *letter as char, &l[73..80]))?;
            if seq != k + 1 || !l[73..80].ends_with(&(k + 1).to_string()) {
                return Err(format!("{}{}: sequence number {seq}", *letter as char, k + 1));
            }
        }
    }
    let sec = |c: u8| &sections.iter().find(|s| s.0 == c).unwrap().1;
    let (s, g, d, p, t) = (sec(b'S'), sec(b'G'), sec(b'D'), sec(b'P'), sec(b'T'));
    // Global section: 1H,,1H; then at least 25 fields (5.3 has 26, the last optional).
    let gtext: String = g.iter().map(|l| &l[..72]).collect();
    if !gtext.starts_with("1H,,1H;,") {
        return Err("global section does not start with the default delimiters".into());
    }
    let gf = split_params(&gtext)?;
    if gf.len() < 25 {
        return Err(format!("global section has {} fields", gf.len()));
    }
    let unit: i64 = gf[13].parse().map_err(|_| "G14 not an integer")?;
    let version: i64 = gf[22].parse().map_err(|_| "G23 not an integer")?;
    if !(1..=11).contains(&unit) || version != 11 || gf[17].len() != 15 || gf[24].len() != 15 {
        return Err(format!("G14 {unit}, G23 {version}, dates {:?} {:?}", gf[17], gf[24]));
    }
    // Directory: pairs of records; 8-column right-justified integer fields.
    if d.len() % 2 != 0 {
        return Err("odd number of D records".into());
    }
    let field = |l: &str, k: usize| -> Result<i64, String> {
        let f = &l[8 * k..8 * k + 8];
        if f.trim().is_empty() {
            return Ok(0);
        }
        if f.trim_start() != f.trim() || f.ends_with(' ') {
            return Err(format!("field {:?} not right-justified", f));
        }
        f.trim().parse().map_err(|_| format!("field {f:?} is not an integer"))
    };
    let mut next_p = 1;
    for pair in d.chunks(2).enumerate() {
        let (k, pair) = pair;
        let de = 2 * k + 1;
        let (a, b) = (pair[0], pair[1]);
        let etype = field(a, 0)?;
        if field(b, 0)? != etype {
            return Err(format!(
                "D{de}: entity type {etype} / {} in the two records",
                field(b, 0)?
            ));
        }
        let status = &a[64..72];
        if !status.bytes().all(|c| c.is_ascii_digit()) {
            return Err(format!("D{de}: status {status:?} is not eight digits"));
        }
        let (pstart, count) = (field(a, 1)? as usize, field(b, 3)? as usize);
        if pstart != next_p || count == 0 || pstart + count - 1 > p.len() {
            return Err(format!(
                "D{de}: P pointer {pstart} with {count} records, expected start {next_p}"
            ));
        }
        next_p += count;
        let mut ptext = String::new();
        for (j, l) in p[pstart - 1..pstart - 1 + count].iter().enumerate() {
            if &l[64..65] != " " {
                return Err(format!("P{}: column 65 not blank", pstart + j));
            }
            let back: usize = l[65..72].trim().parse().map_err(|_| "P back pointer")?;
            if back != de {
                return Err(format!("P{}: back pointer {back}, owner is D{de}", pstart + j));
            }
            ptext.push_str(&l[..64]);
        }
        let params = split_params(&ptext)?;
        if params[0] != etype.to_string() {
            return Err(format!("D{de}: parameter data starts with {:?}", params[0]));
        }
        let int =
            |i: usize| -> Result<usize, String> { params[i].parse().map_err(|_| format!("D{de}: {:?}", params[i])) };
        let expected = match etype {
            126 => {
                let (k, m) = (int(1)?, int(2)?);
                7 + (k + m + 2) + 4 * (k + 1) + 2 + 3
            }
            128 => {
                let (k1, k2, m1, m2) = (int(1)?, int(2)?, int(3)?, int(4)?);
                10 + (k1 + m1 + 2) + (k2 + m2 + 2) + 4 * (k1 + 1) * (k2 + 1) + 4
            }
            _ => params.len(),
        };
        if params.len() != expected {
            return Err(format!(
                "D{de}: {} parameters, entity {etype} needs {expected}",
                params.len()
            ));
        }
    }
    if next_p != p.len() + 1 {
        return Err(format!("P records {next_p}..{} belong to no entity", p.len()));
    }
    let want = format!("S{:>7}G{:>7}D{:>7}P{:>7}", s.len(), g.len(), d.len(), p.len());
    if t.len() != 1 || t[0][..32] != want || !t[0][32..72].trim().is_empty() {
        return Err(format!("terminate record {:?}, expected {want:?}", &t[0][..72]));
    }
    Ok(())
}

fn max_diff(a: &Geometry, b: &Geometry) -> f64 {
    fn d(x: &[f64], y: &[f64]) -> f64 {
        assert_eq!(x.len(), y.len());
        x.iter().zip(y).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
    }
    fn flat(p: &[DVec3]) -> Vec<f64> {
        p.iter().flat_map(|q| q.to_array()).collect()
    }
    match (a, b) {
        (Geometry::Curve(a), Geometry::Curve(b)) => {
            assert_eq!(
                (a.degree(), a.dim(), a.is_rational()),
                (b.degree(), b.dim(), b.is_rational())
            );
            d(a.knots().values(), b.knots().values())
                .max(d(&flat(a.points()), &flat(b.points())))
                .max(d(a.weights().unwrap_or(&[]), b.weights().unwrap_or(&[])))
        }
        (Geometry::Surface(a), Geometry::Surface(b)) => {
            assert_eq!(
                (a.degree_u(), a.degree_v(), a.nu(), a.nv()),
                (b.degree_u(), b.degree_v(), b.nu(), b.nv())
            );
            d(a.knots_u().values(), b.knots_u().values())
                .max(d(a.knots_v().values(), b.knots_v().values()))
                .max(d(&flat(a.points()), &flat(b.points())))
                .max(d(a.weights().unwrap_or(&[]), b.weights().unwrap_or(&[])))
        }
        _ => panic!("kind changed"),
    }
}

fn sample_objects() -> Vec<Geometry> {
    vec![
        wiggly_2d().into(),
        circle(2.5).into(),
        twisted_cubic().into(),
        rational_3d().into(),
        quartic_3d().into(),
        wavy_bicubic().into(),
        wavy_rational().into(),
        sphere_octant(3.0).into(),
        cylinder(1.0, 2.0).into(),
    ]
}

#[test]
fn written_files_follow_the_iges_5_3_rules() {
    let objs = sample_objects();
    let text = iges::write(&objs, &WriteOptions::default());
    check_iges_5_3(&text).unwrap();
    for g in &objs {
        check_iges_5_3(&iges::to_string(g)).unwrap();
    }
    // the checker itself catches broken files
    let broken: Vec<(String, &str)> = vec![
        (text.replacen("     1P      1", "     3P      1", 1), "back pointer"),
        (text.replace("D     18P", "D     20P"), "terminate"),
        (
            {
                let mut l: Vec<String> = text.lines().map(String::from).collect();
                let k = l.iter().position(|x| x.as_bytes()[72] == b'P').unwrap();
                l[k].replace_range(79..80, "7");
                l.join("\n")
            },
            "sequence",
        ),
        (
            {
                // change the degree M of the first curve (one digit): the count no longer fits
                let k = text.find("\n126,").unwrap() + 1;
                let third = k + text[k..].match_indices(',').nth(1).unwrap().0 + 1;
                let mut t = text.clone();
                let m = &t[third..third + 1];
                let other = if m == "2" { "3" } else { "2" };
                t.replace_range(third..third + 1, other);
                t
            },
            "parameters",
        ),
    ];
    for (b, want) in broken {
        let e = check_iges_5_3(&b).unwrap_err();
        assert!(e.contains(want), "{want}: {e}");
    }
}

#[test]
fn round_trip_fairway_iges_fairway_is_exact() {
    let objs = sample_objects();
    let text = iges::write(&objs, &WriteOptions::default());
    let back = iges::read_all(text.as_bytes()).unwrap();
    assert!(back.notices.is_empty(), "{:?}", back.notices);
    assert_eq!(back.objects.len(), objs.len());
    for (a, b) in objs.iter().zip(&back.objects) {
        assert!(max_diff(a, b) <= 1e-12);
        assert_eq!(a, b, "bit-exact");
    }
}

fn arb_curve() -> impl Strategy<Value = BSplineCurve> {
    (1usize..=5, 0usize..6, 2usize..=3, any::<bool>()).prop_flat_map(|(p, extra, dim, rational)| {
        let n = p + 1 + extra;
        (
            proptest::collection::vec(-1e6..1e6f64, 3 * n),
            proptest::collection::vec(0.01..10.0f64, n),
            proptest::collection::vec(0.0..1.0f64, n - p - 1),
            -100.0..100.0f64,
            1e-6..1e3f64,
        )
            .prop_map(move |(c, w, mut inner, a, len)| {
                inner.sort_by(f64::total_cmp);
                let mut knots = vec![a; p + 1];
                knots.extend(inner.iter().map(|t| a + len * t));
                knots.extend(std::iter::repeat_n(a + len, p + 1));
                let pts = (0..n)
                    .map(|i| DVec3::new(c[3 * i], c[3 * i + 1], if dim == 3 { c[3 * i + 2] } else { 0.0 }))
                    .collect();
                BSplineCurve::try_new(p, knots, pts, rational.then_some(w), dim).unwrap()
            })
    })
}

fn arb_surface() -> impl Strategy<Value = BSplineSurface> {
    (1usize..=3, 1usize..=3, 0usize..3, 0usize..3, any::<bool>()).prop_flat_map(|(pu, pv, eu, ev, rational)| {
        let (nu, nv) = (pu + 1 + eu, pv + 1 + ev);
        (
            proptest::collection::vec(-1e3..1e3f64, 3 * nu * nv),
            proptest::collection::vec(0.1..5.0f64, nu * nv),
        )
            .prop_map(move |(c, w)| {
                let clamped = |p: usize, n: usize| {
                    let mut k = vec![0.0; p + 1];
                    k.extend((1..n - p).map(|i| i as f64 / (n - p) as f64 + 1e-3 / 7.0));
                    k.extend(std::iter::repeat_n(1.0, p + 1));
                    k
                };
                let pts = (0..nu * nv)
                    .map(|i| DVec3::new(c[3 * i], c[3 * i + 1], c[3 * i + 2]))
                    .collect();
                BSplineSurface::try_new(
                    pu,
                    pv,
                    clamped(pu, nu),
                    clamped(pv, nv),
                    nu,
                    nv,
                    pts,
                    rational.then_some(w),
                )
                .unwrap()
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn random_curves_and_surfaces_round_trip_bit_exactly(c in arb_curve(), s in arb_surface()) {
        let objs: Vec<Geometry> = vec![c.into(), s.into()];
        let text = iges::write(&objs, &WriteOptions::default());
        prop_assert!(check_iges_5_3(&text).is_ok(), "{:?}", check_iges_5_3(&text));
        let back = iges::read_all(text.as_bytes()).unwrap();
        prop_assert_eq!(back.objects, objs);
    }
}

/// A record of the fixed format: 72 columns of data, section letter, sequence.
fn rec(body: &str, letter: char, seq: usize) -> String {
    assert!(body.len() <= 72, "{body}");
    format!("{body:<72}{letter}{seq:>7}\n")
}

/// A file as another CAD system writes it, by hand after the IGES 5.3 spec:
/// a line (110), a planar rational quarter circle (126), a circular arc
/// (100), a 3D cubic over two P records with `E`/`D` exponents and spaces
/// (126), a degree 1×2 surface in the spec's u-fastest order (128), and a
/// name property (406) whose Hollerith string contains both delimiters.
fn foreign_multi_entity_file() -> String {
    let mut f = String::new();
    f += &rec(
        "Exported by SolidCAD 12.4 (hand-written test file after IGES 5.3)",
        'S',
        1,
    );
    f += &rec("Part: bracket section curves", 'S', 2);
    let g = [
        "1H,,1H;,8HSolidCAD,11Hbracket.igs,13HSolidCAD 12.4,8HIGES 5.3,",
        "32,38,6,308,15,7Hbracket,1.0,2,2HMM,1,0.01,15H20240115.103000,1.0E-4,",
        "250.0,4HAnne,",
        "4HACME,11,0,15H20240115.103000;",
    ];
    for (i, l) in g.iter().enumerate() {
        f += &rec(l, 'G', i + 1);
    }
    // parameter data: (entity type, form, records of columns 1-64)
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let arc = format!("126,2,2,1,0,0,0,0.,0.,0.,1.,1.,1.,1.0,{w:.17},1.0,");
    let entities: Vec<(i64, i64, Vec<String>)> = vec![
        (110, 0, vec!["110,0.,0.,0.,10.,5.,0.;".into()]),
        (126, 2, vec![arc, "1.,0.,0.,1.,1.,0.,0.,1.,0.,0.,1.,0.,0.,1.;".into()]),
        (100, 0, vec!["100,0.,0.,0.,1.,0.,0.,1.;".into()]),
        (
            126,
            0,
            vec![
                "126, 4, 3, 0, 0, 1, 0, 0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0,".into(),
                "1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0E0, 0.0D0, 0.0,".into(),
                "1.5D0, 2., .5, 3.0, -1.0, 1.25E+1, 4., 0.5, 2.0, 5.0, 0., 0.,".into(),
                "0., 1., 0., 0., 0.;".into(),
            ],
        ),
        (
            128,
            0,
            vec![
                "128,1,2,1,2,0,0,1,0,0,0.,0.,1.,1.,0.,0.,0.,2.,2.,2.,1.,1.,1.,1.,".into(),
                "1.,1.,0.,0.,0.,1.,0.,0.1,0.,1.,0.,1.,1.,0.2,0.,2.,0.5,1.,2.,0.3,".into(),
                "0.,1.,0.,2.;".into(),
            ],
        ),
        (406, 15, vec!["406,1,8HBR,KT;01;".into()]),
    ];
    let mut d = String::new();
    let mut p = String::new();
    let (mut pseq, mut dseq) = (1, 1);
    for (t, form, lines) in &entities {
        let status = if *t == 406 { "00010200" } else { "00000000" };
        d += &rec(
            &format!(
                "{t:>8}{pseq:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{status:>8}",
                0, 1, 0, 0, 0, 0
            ),
            'D',
            dseq,
        );
        d += &rec(
            &format!(
                "{t:>8}{:>8}{:>8}{:>8}{form:>8}{:>8}{:>8}{:>8}{:>8}",
                0,
                4,
                lines.len(),
                "",
                "",
                "  CURVE",
                1
            ),
            'D',
            dseq + 1,
        );
        for l in lines {
            assert!(l.len() <= 64, "{l} {}", l.len());
            p += &format!("{l:<64} {dseq:>7}P{pseq:>7}\n");
            pseq += 1;
        }
        dseq += 2;
    }
    f += &d;
    f += &p;
    f += &rec(
        &format!("S{:>7}G{:>7}D{:>7}P{:>7}", 2, g.len(), dseq - 1, pseq - 1),
        'T',
        1,
    );
    f
}

#[test]
fn multi_entity_file_from_another_system_loads_all_objects_with_notices() {
    let text = foreign_multi_entity_file();
    check_iges_5_3(&text).unwrap();
    let f = iges::read_all(text.as_bytes()).unwrap();
    assert_eq!(f.unit, Some(iges::Unit::Millimeter));
    assert_eq!(f.objects.len(), 3, "two curves and a surface");
    assert_eq!(f.notices.len(), 3, "{:?}", f.notices);
    for (n, (de, t)) in f.notices.iter().zip([(1, 110), (5, 100), (11, 406)]) {
        assert!(
            n.contains(&format!("entity {de} (type {t}")) && n.contains("skipped"),
            "{n}"
        );
    }
    // planar rational quarter circle → 2D curve on the unit circle
    let c = f.objects[0].as_curve().unwrap();
    assert_eq!((c.dim(), c.degree(), c.is_rational()), (2, 2, true));
    for k in 0..=20 {
        let q = c.point(k as f64 / 20.0);
        assert!((q.length() - 1.0).abs() < 1e-14, "{q}");
    }
    // 3D cubic: values exactly as written
    let c = f.objects[1].as_curve().unwrap();
    assert_eq!((c.dim(), c.degree(), c.is_rational()), (3, 3, false));
    assert_eq!(c.knots().values(), &[0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0]);
    assert_eq!(
        c.points(),
        &[
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.5, 2.0, 0.5),
            DVec3::new(3.0, -1.0, 12.5),
            DVec3::new(4.0, 0.5, 2.0),
            DVec3::new(5.0, 0.0, 0.0),
        ]
    );
    // surface: IGES (i, j) at i + j·nu, Fairway at i·nv + j; P(i, j) = (i, j, z_ij)
    let s = f.objects[2].as_surface().unwrap();
    assert_eq!((s.degree_u(), s.degree_v(), s.nu(), s.nv()), (1, 2, 2, 3));
    assert!(!s.is_rational());
    for i in 0..2 {
        for j in 0..3 {
            let z = [[0.0, 0.0, 0.5], [0.1, 0.2, 0.3]][i][j];
            let want = DVec3::new(i as f64, j as f64, z);
            assert_eq!(s.point_at(i, j), want, "({i},{j})");
        }
    }
    // io::load returns the first object
    let dir = std::env::temp_dir().join(format!("fairway-iges-multi-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bracket.igs");
    std::fs::write(&path, &text).unwrap();
    assert_eq!(fairway::io::load(&path).unwrap().geometry, f.objects[0]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// One bad entity skips that entity, not the file: the foreign file's 3D cubic with decreasing knots
/// is listed in the notices with its reason, and the quarter circle and the surface still open. (A file
/// whose only object is bad is refused with that object's reason: the IGES rows of the degenerate tables.)
#[test]
fn a_bad_entity_is_skipped_with_its_reason_and_the_rest_opens() {
    let text = foreign_multi_entity_file();
    let bad = text.replacen("0.0, 0.5, 1.0, 1.0,", "0.0, 1.5, 1.0, 1.0,", 1);
    assert_ne!(bad, text);
    let f = iges::read_all(bad.as_bytes()).unwrap();
    assert_eq!(f.objects.len(), 2, "the quarter circle and the surface");
    let skipped: Vec<&String> = f
        .notices
        .iter()
        .filter(|n| n.starts_with("entity 7 (curve, 126) skipped"))
        .collect();
    assert_eq!(skipped.len(), 1, "{:?}", f.notices);
    assert!(skipped[0].contains("knot"), "{}", skipped[0]);
    assert_eq!(f.entities.iter().map(|e| e.entity).collect::<Vec<_>>(), vec![3, 9]);
}
