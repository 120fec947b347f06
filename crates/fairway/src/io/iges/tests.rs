use super::read::*;
use super::write::*;
use super::*;
use glam::DVec2;

fn sample_curve_2d() -> BSplineCurve {
    let pts = [
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0 / 3.0, 0.7),
        DVec2::new(1.1, -0.2),
        DVec2::new(2.0, std::f64::consts::PI),
        DVec2::new(3.0, 1e-9),
    ];
    BSplineCurve::new_2d(3, vec![0.0, 0.0, 0.0, 0.0, 0.1234567890123, 1.0, 1.0, 1.0, 1.0], &pts).unwrap()
}

fn sample_surface(rational: bool) -> BSplineSurface {
    let (nu, nv) = (4, 3);
    let mut pts = Vec::new();
    let mut w = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            pts.push(DVec3::new(i as f64 * 0.7, j as f64 / 3.0, ((i * j) as f64).sin()));
            w.push(1.0 + 0.1 * (i + 2 * j) as f64);
        }
    }
    BSplineSurface::try_new(
        2,
        2,
        vec![0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0],
        vec![0.0, 0.0, 0.0, 2.0, 2.0, 2.0],
        nu,
        nv,
        pts,
        rational.then_some(w),
    )
    .unwrap()
}

#[test]
fn records_are_80_columns_and_t_counts_match() {
    let text = write(
        &[sample_curve_2d().into(), sample_surface(true).into()],
        &WriteOptions::default(),
    );
    let mut counts = std::collections::BTreeMap::new();
    for l in text.lines() {
        assert_eq!(l.len(), 80, "{l:?}");
        *counts.entry(l.as_bytes()[72]).or_insert(0usize) += 1;
    }
    let t = text.lines().last().unwrap();
    let expect = format!(
        "S{:>7}G{:>7}D{:>7}P{:>7}",
        counts[&b'S'], counts[&b'G'], counts[&b'D'], counts[&b'P']
    );
    assert_eq!(&t[..32], expect);
    assert_eq!(counts[&b'D'], 4);
    // P back pointers point at the D entries, P pointers at the first P line.
    let plines: Vec<&str> = text.lines().filter(|l| l.as_bytes()[72] == b'P').collect();
    assert_eq!(plines[0][64..72].trim(), "1");
    assert_eq!(plines.last().unwrap()[64..72].trim(), "3");
    let d3 = text.lines().filter(|l| l.as_bytes()[72] == b'D').nth(2).unwrap();
    let pstart: usize = d3[8..16].trim().parse().unwrap();
    assert!(plines[pstart - 1].starts_with("128,"));
    assert_eq!(plines[pstart - 2][64..72].trim(), "1");
}

#[test]
fn round_trip_is_exact() {
    let c2 = sample_curve_2d();
    let c3 = BSplineCurve::try_new(
        2,
        vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0],
        vec![
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(-1e9, 0.1, 0.2),
            DVec3::new(1e-300, 5.5, -7.25),
            DVec3::new(0.1 + 0.2, 0.0, 1.0),
            DVec3::new(4.0, 4.0, 0.0),
        ],
        Some(vec![1.0, 0.5, 2.0, 0.3, 1.0]),
        3,
    )
    .unwrap();
    let objs: Vec<Geometry> = vec![
        c2.into(),
        c3.into(),
        sample_surface(true).into(),
        sample_surface(false).into(),
    ];
    let text = write(&objs, &WriteOptions::default());
    let back = read_all(text.as_bytes()).unwrap();
    assert_eq!(back.objects, objs, "bit-exact round trip");
    assert!(back.notices.is_empty(), "{:?}", back.notices);
    assert_eq!(back.unit, Some(Unit::Millimeter));
}

#[test]
fn entity_numbers_and_labels_are_reported() {
    let text = write(
        &[sample_curve_2d().into(), sample_surface(false).into()],
        &WriteOptions::default(),
    );
    assert_eq!(
        read_all(text.as_bytes()).unwrap().entities,
        vec![
            EntityInfo {
                entity: 1,
                label: String::new()
            },
            EntityInfo {
                entity: 3,
                label: String::new()
            }
        ]
    );
    // label "HULL" (field 18) with subscript 2 (field 19) on the surface's second D record
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            if &l[72..] == "D      4" {
                format!("{}{:>8}{:>8}{}", &l[..56], "HULL", 2, &l[72..])
            } else {
                l.to_string()
            }
        })
        .collect();
    let f = read_all(lines.join("\n").as_bytes()).unwrap();
    assert_eq!(f.entities[0].label, "");
    assert_eq!(f.entities[1].label, "HULL(2)");
    assert_eq!(f.entities[1].entity, 3);
}

#[test]
fn reals_parse_in_all_spellings() {
    for (s, v) in [
        ("1.", 1.0),
        (".5", 0.5),
        ("1.5D3", 1500.0),
        ("1.5E-3", 0.0015),
        ("-2", -2.0),
        ("+2.D0", 2.0),
        ("1D2", 100.0),
    ] {
        assert_eq!(parse_real(s), Some(v), "{s}");
    }
    for s in ["inf", "NaN", "", "-", "1.2.3", "D5", "1e", "0x10"] {
        assert_eq!(parse_real(s), None, "{s}");
    }
    for x in [0.1, -1e-300, 1.7976931348623157e308, 5e-324, 123456.789] {
        assert_eq!(parse_real(&format_real(x)), Some(x));
    }
}

/// Hand-written header with an unclamped uniform cubic (other CAD style)
/// in inches, and a line entity (110) that is skipped.
fn foreign_file(unit_flag: &str, scale: &str) -> String {
    let mut s = String::new();
    s.push_str(&record("foreign test", 'S', 1));
    let g = format!(
        "1H,,1H;,4HTEST,8Htest.igs,4HTEST,4HTEST,32,38,6,308,15,4HTEST,{scale},{unit_flag},2HIN,1,0.,15H20240101.000000,1.E-6,10.,,,11,0,;"
    );
    for (i, c) in g.as_bytes().chunks(72).enumerate() {
        s.push_str(&record(std::str::from_utf8(c).unwrap(), 'G', i + 1));
    }
    let line = "110,0.,0.,0.,1.,1.,1.;";
    // uniform knots 0..7 with 4 control points, degree 3 (unclamped)
    let bs = "126,3,3,0,0,1,0,0.,1.,2.,3.,4.,5.,6.,7.,1.,1.,1.,1.,0.,0.,0.,1.,2.,0.,2.,-1.,0.,3.,0.,1.,3.,4.,0.,0.,0.;";
    let d = |t: i64, p: usize, n: usize| {
        (
            format!(
                "{t:>8}{p:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
                0, 0, 0, 0, 0, 0, "00000000"
            ),
            format!("{t:>8}{:>8}{:>8}{n:>8}{:>8}", 0, 0, 0),
        )
    };
    let cut = bs[..64].rfind(',').unwrap() + 1;
    let bs_lines: Vec<&str> = vec![&bs[..cut], &bs[cut..]];
    let (a1, a2) = d(110, 1, 1);
    let (b1, b2) = d(126, 2, bs_lines.len());
    s.push_str(&record(&a1, 'D', 1));
    s.push_str(&record(&a2, 'D', 2));
    s.push_str(&record(&b1, 'D', 3));
    s.push_str(&record(&b2, 'D', 4));
    s.push_str(&format!("{line:<64} {:>7}P{:>7}\n", 1, 1));
    for (i, l) in bs_lines.iter().enumerate() {
        s.push_str(&format!("{l:<64} {:>7}P{:>7}\n", 3, i + 2));
    }
    s.push_str(&record("S      1G      2D      4P      3", 'T', 1));
    s
}

#[test]
fn foreign_unclamped_curve_is_clamped_exactly_and_units_converted() {
    let text = foreign_file("1", "1.0");
    let f = read_all(text.as_bytes()).unwrap();
    assert_eq!(f.unit, Some(Unit::Inch));
    assert_eq!(f.objects.len(), 1);
    assert_eq!(f.notices.len(), 2, "{:?}", f.notices);
    assert!(f.notices[0].contains("type 110"));
    assert!(f.notices[1].contains("clamped"));
    let c = f.objects[0].as_curve().unwrap();
    assert_eq!(c.domain(), (3.0, 4.0));
    assert_eq!(c.dim(), 3);
    // the uniform cubic B-spline on span [3,4]: C(u) = Σ N_i(u) P_i with
    // the uniform blending (1−t)³/6, (3t³−6t²+4)/6, (−3t³+3t²+3t+1)/6, t³/6
    let p = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 2.0, 0.0),
        DVec3::new(2.0, -1.0, 0.0),
        DVec3::new(3.0, 0.0, 1.0),
    ];
    for k in 0..=10 {
        let t = k as f64 / 10.0;
        let b = [
            (1.0 - t).powi(3) / 6.0,
            (3.0 * t.powi(3) - 6.0 * t * t + 4.0) / 6.0,
            (-3.0 * t.powi(3) + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
            t.powi(3) / 6.0,
        ];
        let want = p[0] * b[0] + p[1] * b[1] + p[2] * b[2] + p[3] * b[3];
        assert!((c.point(3.0 + t) - want).length() < 1e-13, "t={t}");
    }
    // converting inches to mm multiplies by 25.4 / scale
    let f2 = read_all_with(
        foreign_file("1", "2.0").as_bytes(),
        ReadOptions {
            unit: Some(Unit::Millimeter),
        },
    )
    .unwrap();
    let c2 = f2.objects[0].as_curve().unwrap();
    for (a, b) in c.points().iter().zip(c2.points()) {
        assert!((*a * 12.7 - *b).length() < 1e-12);
    }
}

/// G13 is model size over real size: a file drawn at 4 times real size (or at a quarter of it) reads
/// at real size, its coordinates divided by G13, with a notice; converted units apply on top; an invalid
/// G13 is ignored with a notice; the writer declares 1, so what it writes reads back unchanged.
#[test]
fn model_space_scale_gives_real_size_and_is_written_as_one() {
    let real = read_all(foreign_file("1", "1.0").as_bytes()).unwrap();
    assert_eq!(real.scale, 1.0);
    assert!(!real.notices.iter().any(|n| n.contains("G13")), "{:?}", real.notices);
    let pts = |f: &IgesFile| f.objects[0].as_curve().unwrap().points().to_vec();
    for (g13, factor) in [("4.0", 0.25), ("0.125", 8.0)] {
        let f = read_all(foreign_file("1", g13).as_bytes()).unwrap();
        assert_eq!(f.scale, 1.0 / factor);
        assert_eq!(f.unit, Some(Unit::Inch));
        let want: Vec<DVec3> = pts(&real).iter().map(|&q| q * factor).collect();
        assert_eq!(
            pts(&f),
            want,
            "G13 = {g13}: coordinates divided by it (exactly: a power of 2)"
        );
        let note = format!("model-space scale {} (G13)", 1.0 / factor);
        assert!(f.notices.iter().any(|n| n.contains(&note)), "{:?}", f.notices);
        // the unit conversion on top of real size
        let mm = read_all_with(
            foreign_file("1", g13).as_bytes(),
            ReadOptions {
                unit: Some(Unit::Millimeter),
            },
        )
        .unwrap();
        for (a, b) in want.iter().zip(pts(&mm)) {
            assert!((*a * 25.4 - b).length() <= 1e-13 * b.length(), "{a} in, {b} mm");
        }
        // written at real size with G13 = 1: read back as it is, no notice
        let back = read_all(write(&f.objects, &WriteOptions::default()).as_bytes()).unwrap();
        assert_eq!((back.scale, &back.objects), (1.0, &f.objects));
        assert!(!back.notices.iter().any(|n| n.contains("G13")), "{:?}", back.notices);
    }
    for bad in ["0.", "-2."] {
        let f = read_all(foreign_file("1", bad).as_bytes()).unwrap();
        assert_eq!((f.scale, pts(&f)), (1.0, pts(&real)), "G13 = {bad}");
        assert!(
            f.notices.iter().any(|n| n.contains("is invalid; 1 is used")),
            "{:?}",
            f.notices
        );
    }
}

#[test]
fn transformation_matrix_is_applied() {
    let c = sample_curve_2d();
    let text = write(&[c.clone().into()], &WriteOptions::default());
    // Append a 124 entity (translation by (1,2,3), rotation z by 90°) and point the curve at it.
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let d_idx = lines.iter().position(|l| l.as_bytes()[72] == b'D').unwrap();
    let p_count = lines.iter().filter(|l| l.as_bytes()[72] == b'P').count();
    let mut d1 = lines[d_idx].clone();
    d1.replace_range(48..56, &format!("{:>8}", 3));
    lines[d_idx] = d1;
    let m1 = format!(
        "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
        124,
        p_count + 1,
        0,
        0,
        0,
        0,
        0,
        0,
        "00000000"
    );
    let m2 = format!("{:>8}{:>8}{:>8}{:>8}{:>8}", 124, 0, 0, 1, 0);
    lines.insert(d_idx + 2, record(&m1, 'D', 3).trim_end_matches('\n').to_string());
    lines.insert(d_idx + 3, record(&m2, 'D', 4).trim_end_matches('\n').to_string());
    let t_idx = lines.len() - 1;
    let pbody = "124,0.,-1.,0.,1.,1.,0.,0.,2.,0.,0.,1.,3.;";
    lines.insert(t_idx, format!("{pbody:<64} {:>7}P{:>7}", 3, p_count + 1));
    let f = read_all(lines.join("\n").as_bytes()).unwrap();
    let g = f.objects[0].as_curve().unwrap();
    assert_eq!(g.dim(), 3);
    for (a, b) in c.points().iter().zip(g.points()) {
        let want = DVec3::new(-a.y + 1.0, a.x + 2.0, a.z + 3.0);
        assert!((want - *b).length() < 1e-15);
    }
}

#[test]
fn bad_files_give_clear_errors() {
    let good = to_string(&sample_curve_2d().into());
    // edit the parameter data, keeping the 64-column field
    let edit = |from: &str, to: &str| -> String {
        good.lines()
            .map(|l| {
                if l.as_bytes()[72] == b'P' && l[..64].contains(from) {
                    // make room: "1.0," and "0.0," have shorter spellings
                    let d = l[..64]
                        .replacen(from, to, 1)
                        .replace("1.0,", "1.,")
                        .replace("0.0,", "0.,");
                    let d = d.trim_end();
                    assert!(d.len() <= 64);
                    format!("{d:<64}{}\n", &l[64..])
                } else {
                    format!("{l}\n")
                }
            })
            .collect()
    };
    let cases: Vec<(String, &str)> = vec![
        (String::new(), "empty"),
        ("hello\n".into(), "80"),
        (edit("126,4,3", "126,900000000,3"), "more values"),
        (edit("126,4,3", "126,4,30"), "out of range"),
        (edit("126,4,3", "126,4,0"), "degree 0"),
        (edit("1.234567890123D-1", "1.234567890123D1"), "decrease"),
    ];
    for (text, want) in cases {
        let e = read_all(text.as_bytes()).unwrap_err().to_string();
        assert!(e.contains(want), "{want}: {e}");
    }
}

/// A bicubic patch over 10 × 10 units with some relief, and a uv loop on it: a quadrilateral and a
/// rational quadratic half circle closing it (exact in (u, v)).
fn trimmed_patch() -> (BSplineSurface, crate::trim::FaceTrim) {
    let n = 6;
    let k = crate::knots::KnotVector::uniform(3, n).unwrap().values().to_vec();
    let pts = (0..n * n)
        .map(|i| {
            let (x, y) = ((i / n) as f64 * 2.0, (i % n) as f64 * 2.0);
            DVec3::new(x, y, (0.4 * x).sin() * (0.3 * y).cos())
        })
        .collect();
    let s = BSplineSurface::try_new(3, 3, k.clone(), k, n, n, pts, None).unwrap();
    let line = |a: (f64, f64), b: (f64, f64)| {
        let pts = vec![DVec3::new(a.0, a.1, 0.0), DVec3::new(b.0, b.1, 0.0)];
        BSplineCurve::try_new(1, vec![0.0, 0.0, 1.0, 1.0], pts, None, 2).unwrap()
    };
    // the half circle about (0.5, 0.7), radius 0.2, from (0.7, 0.7) over the top to (0.3, 0.7)
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let arc = BSplineCurve::try_new(
        2,
        vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0],
        [(0.7, 0.7), (0.7, 0.9), (0.5, 0.9), (0.3, 0.9), (0.3, 0.7)]
            .iter()
            .map(|&(u, v)| DVec3::new(u, v, 0.0))
            .collect(),
        Some(vec![1.0, w, 1.0, w, 1.0]),
        2,
    )
    .unwrap();
    let outer = crate::trim::TrimLoop {
        outer: true,
        edges: vec![
            line((0.3, 0.7), (0.2, 0.15)),
            line((0.2, 0.15), (0.8, 0.2)),
            line((0.8, 0.2), (0.7, 0.7)),
            arc,
        ],
    };
    (s, crate::trim::FaceTrim { loops: vec![outer] })
}

/// Each point of `got` (16 a edge) is within `tol` in space of the exact loop `want` on `s` at the same
/// edge parameter, and the loops have as many edges, each from the same start to the same end in (u, v).
fn loops_agree(s: &BSplineSurface, got: &crate::trim::FaceTrim, want: &crate::trim::FaceTrim, tol: f64) {
    assert_eq!(got.loops.len(), want.loops.len());
    for (g, w) in got.loops.iter().zip(&want.loops) {
        assert_eq!((g.outer, g.edges.len()), (w.outer, w.edges.len()));
        for (eg, ew) in g.edges.iter().zip(&w.edges) {
            assert_eq!(eg.domain(), ew.domain(), "the model-space curve's parameter kept");
            let (a, b) = ew.domain();
            for k in 0..=64 {
                let t = a + (b - a) * k as f64 / 64.0;
                let (qg, qw) = (eg.point(t), ew.point(t));
                let d = s.point(qg.x, qg.y).distance(s.point(qw.x, qw.y));
                assert!(d <= tol, "{d:.3e} > {tol:.3e} at t = {t}");
                assert!(DVec2::new(qg.x - qw.x, qg.y - qw.y).length() <= 1e-5, "{qg} vs {qw}");
            }
        }
    }
}

/// A 142 with only a model-space curve (BPTR = 0), as some systems write: the reader projects it onto the
/// surface, and the uv loop it builds lies within the trim tolerance of the exact one (twice: the written
/// curve's own fit, then the projection), edge by edge, the curve's parameter kept.
#[test]
fn a_boundary_with_only_its_model_space_curve_is_projected_onto_the_surface() {
    let (s, trim) = trimmed_patch();
    let objects = vec![Geometry::Surface(s.clone())];
    let text = super::write::write_with(
        &objects,
        &[],
        &[Some(trim.clone())],
        &WriteOptions::default(),
        super::write_trim::Boundaries::ModelOnly,
    );
    let f = read_all(text.as_bytes()).unwrap();
    assert_eq!(f.objects, objects, "the surface alone: its edges are its trim");
    let got = f.trims[0]
        .as_ref()
        .unwrap_or_else(|| panic!("untrimmed: {:?}", f.notices));
    let tol = crate::trim::fit_tolerance(&s);
    loops_agree(&s, got, &trim, 2.0 * tol);
    assert!(got.largest_gap() <= 1e-6, "{}", got.largest_gap());
}

/// A 142 whose preference flag says model space (PREF = 2) is read from its model-space curve even where
/// it has a parameter-space curve too; with PREF = 1 the parameter-space curve is taken exactly.
#[test]
fn a_boundary_preferring_its_model_space_curve_is_read_from_it() {
    let (s, trim) = trimmed_patch();
    let objects = vec![Geometry::Surface(s.clone())];
    let text = write_trimmed(&objects, &[], &[Some(trim.clone())], &WriteOptions::default());
    assert_eq!(read_all(text.as_bytes()).unwrap().trims[0], Some(trim.clone()));
    // PREF is the 142's last parameter: 1 → 2 (same width)
    let pref2: String = text
        .lines()
        .map(|l| match l.starts_with("142,") {
            true => format!("{}\n", l.replacen(",1;", ",2;", 1)),
            false => format!("{l}\n"),
        })
        .collect();
    assert_ne!(pref2, text);
    let f = read_all(pref2.as_bytes()).unwrap();
    let got = f.trims[0]
        .as_ref()
        .unwrap_or_else(|| panic!("untrimmed: {:?}", f.notices));
    assert_ne!(got, &trim, "projected, not the uv curves");
    loops_agree(&s, got, &trim, 2.0 * crate::trim::fit_tolerance(&s));
}

/// A boundary whose model-space curve is not on the face's surface (and that has no parameter-space
/// curve) is refused with the reason; the file still opens, the surface untrimmed, with a notice.
#[test]
fn a_model_space_boundary_off_its_surface_leaves_the_face_untrimmed_with_a_notice() {
    let (s, trim) = trimmed_patch();
    let b = super::trim::Boundary {
        outer: true,
        uv: None,
        model: Some(vec![
            BSplineCurve::try_new(
                1,
                vec![0.0, 0.0, 1.0, 1.0],
                vec![DVec3::new(2.0, 2.0, 5.0), DVec3::new(8.0, 2.0, 5.0)],
                None,
                3,
            )
            .unwrap(),
        ]),
        model_first: false,
    };
    let t = super::trim::Trim144 {
        outer_is_domain: false,
        loops: vec![b],
    };
    let e = t.on(&s).unwrap_err().to_string();
    assert!(e.contains("cannot be projected onto the surface"), "{e}");
    assert!(e.contains("not on this face's surface"), "{e}");
    // through a file: the boundary's curves computed on the surface moved up by 5, its 144 pointing at
    // the original surface (entity 1 instead of 3, the same width)
    let moved =
        crate::io::interchange::map_points(Geometry::Surface(s.clone()), |q| q + DVec3::new(0.0, 0.0, 5.0)).unwrap();
    let objects = vec![Geometry::Surface(s), moved];
    let text = super::write::write_with(
        &objects,
        &[],
        &[None, Some(trim)],
        &WriteOptions::default(),
        super::write_trim::Boundaries::ModelOnly,
    );
    assert_eq!(text.matches("144,3,").count(), 1);
    let f = read_all(text.replacen("144,3,", "144,1,", 1).as_bytes()).unwrap();
    assert_eq!(f.objects, objects);
    assert_eq!(f.trims, vec![None, None]);
    assert!(
        f.notices
            .iter()
            .any(|n| n.contains("its 144's boundaries are not kept")
                && n.contains("cannot be projected onto the surface")),
        "{:?}",
        f.notices
    );
}
