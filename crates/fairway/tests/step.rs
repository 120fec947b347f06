//! STEP interchange: exact round trips (curves 2D/3D, rational or not,
//! degrees 2–5, multiple knots; surfaces), a hand-written file as a CAD
//! system exports it (complex rational instances, comments, entities over
//! several lines, odd spacing), a file with one broken B-spline, units, and
//! truncated or mutated files that must never panic.

mod shapes;

use fairway::io::step::{self, ReadOptions, Unit, WriteOptions};
use fairway::{BSplineCurve, BSplineSurface, DVec3, Geometry};
use proptest::prelude::*;
use shapes::*;

fn opts(unit: Unit) -> WriteOptions {
    WriteOptions {
        unit,
        file_name: Some("test.stp".into()),
        date: Some(fairway::io::Timestamp::from_unix(1_767_225_600)), // 2026-01-01
    }
}

/// Every number of two geometries equal bit for bit (so -0.0 ≠ 0.0 and NaN would be caught).
fn assert_bits_equal(a: &Geometry, b: &Geometry) {
    fn bits(g: &Geometry) -> (usize, Vec<u64>) {
        let mut v = Vec::new();
        let (kind, knots, pts, w) = match g {
            Geometry::Curve(c) => (
                c.dim() * 10 + c.degree(),
                vec![c.knots().values()],
                c.points(),
                c.weights(),
            ),
            Geometry::Surface(s) => (
                100 + s.degree_u() * 10 + s.degree_v() + 1000 * s.nu(),
                vec![s.knots_u().values(), s.knots_v().values()],
                s.points(),
                s.weights(),
            ),
        };
        for k in knots {
            v.push(k.len() as u64);
            v.extend(k.iter().map(|x| x.to_bits()));
        }
        v.extend(pts.iter().flat_map(|q| q.to_array()).map(f64::to_bits));
        v.extend(w.unwrap_or(&[]).iter().map(|x| x.to_bits()));
        v.push(w.is_some() as u64);
        (kind, v)
    }
    assert_eq!(bits(a), bits(b));
}

/// A deterministic source of awkward doubles (full 53-bit mantissas, some tiny, some huge).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let unit = (self.0 >> 11) as f64 / (1u64 << 53) as f64;
        match self.0 % 7 {
            0 => unit * 1e-9,
            1 => -unit * 3e5,
            _ => unit * 100.0 - 50.0,
        }
    }
}

fn curve(rng: &mut Lcg, degree: usize, interior: &[(f64, usize)], dim: usize, rational: bool) -> BSplineCurve {
    let mut knots = vec![0.0; degree + 1];
    for &(u, m) in interior {
        knots.extend(std::iter::repeat_n(u, m));
    }
    knots.extend(std::iter::repeat_n(1.0 / 3.0 + 1.0, degree + 1));
    let n = knots.len() - degree - 1;
    let pts = (0..n)
        .map(|_| DVec3::new(rng.next(), rng.next(), if dim == 3 { rng.next() } else { 0.0 }))
        .collect();
    let w = rational.then(|| (0..n).map(|_| 0.1 + rng.next().abs().min(10.0)).collect());
    BSplineCurve::try_new(degree, knots, pts, w, dim).unwrap()
}

#[test]
fn curves_round_trip_bit_exact() {
    let mut rng = Lcg(7);
    let mut objects: Vec<Geometry> = Vec::new();
    for degree in 2..=5 {
        for (dim, rational) in [(2, false), (3, false), (2, true), (3, true)] {
            let interior = [(0.1, 1), (0.1 + 0.2, degree), (0.37, degree - 1), (1.0, 2)];
            objects.push(curve(&mut rng, degree, &interior, dim, rational).into());
        }
    }
    objects.push(circle(2.5).into());
    objects.push(rational_3d().into());
    objects.push(twisted_cubic().into());
    let text = step::write(&objects, &opts(Unit::Millimeter));
    let f = step::read_all(text.as_bytes()).unwrap();
    assert!(f.notices.is_empty(), "{:?}", f.notices);
    assert_eq!(f.unit, Some(Unit::Millimeter));
    // the 2D curves are written with z = 0 and named so: read back as 2D curves
    assert_eq!(f.objects.len(), objects.len());
    for (a, b) in objects.iter().zip(&f.objects) {
        assert_bits_equal(a, b);
    }
    // each object is labelled with its instance number and name
    assert!(
        f.entities
            .iter()
            .all(|e| e.entity > 0 && (e.label.starts_with("curve ") || e.label.starts_with("2D curve ")))
    );
    // every point has three coordinates (a 2D context is ignored by other systems)
    assert!(!text.contains("CARTESIAN_POINT('',(0.0,0.0))"));
    assert!(
        text.lines()
            .filter(|l| l.contains("CARTESIAN_POINT"))
            .all(|l| l.matches(',').count() >= 3)
    );
    assert!(!text.contains("GEOMETRIC_REPRESENTATION_CONTEXT(2)"));
    // a 3D curve in the plane z = 0 under another name stays 3D
    let flat3 = curve(&mut rng, 3, &[], 2, false);
    let flat3 = BSplineCurve::try_new(3, flat3.knots().values().to_vec(), flat3.points().to_vec(), None, 3).unwrap();
    let back = step::read_first(step::to_string(&flat3.into()).as_bytes()).unwrap();
    assert_eq!(back.as_curve().unwrap().dim(), 3);
}

#[test]
fn surfaces_and_mixed_files_round_trip_bit_exact() {
    let objects: Vec<Geometry> = vec![
        wavy_bicubic().into(),
        wavy_rational().into(),
        sphere_octant(3.0).into(),
        cylinder(1.5, 2.0).into(),
        rational_3d().into(),
        wiggly_2d().into(),
    ];
    for unit in [Unit::Millimeter, Unit::Inch, Unit::Meter] {
        let text = step::write(&objects, &opts(unit));
        let f = step::read_all(text.as_bytes()).unwrap();
        assert!(f.notices.is_empty(), "{:?}", f.notices);
        assert_eq!(f.unit, Some(unit));
        assert_eq!(f.objects.len(), objects.len());
        for (a, b) in objects.iter().zip(&f.objects) {
            assert_bits_equal(a, b);
        }
    }
    // a surface with a C0 knot line and a multiple knot in v
    let s = BSplineSurface::try_new(
        2,
        3,
        vec![0., 0., 0., 0.5, 0.5, 1., 1., 1.],
        vec![0., 0., 0., 0., 0.25, 0.25, 1., 1., 1., 1.],
        5,
        6,
        (0..30)
            .map(|k| DVec3::new(k as f64 * 0.1, (k % 6) as f64, (k as f64).sin()))
            .collect(),
        None,
    )
    .unwrap();
    let g: Geometry = s.into();
    let back = step::read_first(step::to_string(&g).as_bytes()).unwrap();
    assert_bits_equal(&g, &back);
}

#[test]
fn written_reals_are_part_21_reals() {
    for (x, s) in [
        (1.0, "1.0"),
        (-0.0, "-0.0"),
        (0.1, "0.1"),
        (1e-7, "1.0E-7"),
        (1.5e300, "1.5E300"),
        (123456.75, "123456.75"),
    ] {
        assert_eq!(step::format_real(x), s);
    }
}

/// As a CAD system writes it: header comment, complex rational instance over several lines, mixed
/// spacing and case, CRLF line ends, a curve referred to by an edge and a trimmed curve, a face, a
/// p-curve in a DEFINITIONAL_REPRESENTATION, a line and a plane.
const CAD_SNIPPET: &str = "ISO-10303-21;\r\nHEADER;\r\n/* Generated by a CAD system */\r\n\
FILE_DESCRIPTION(('CAD model'),'2;1');\r\n\
FILE_NAME('part.stp','2024-05-01T10:00:00',('it''s me'),(''),'kernel','cad','');\r\n\
FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\r\nENDSEC;\r\nDATA;\r\n\
#1 = ( LENGTH_UNIT ( ) NAMED_UNIT ( * ) SI_UNIT ( .MILLI., .METRE. ) );\r\n\
#2 = ( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) );\r\n\
#3 = ( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNIT_ASSIGNED_CONTEXT((#1,#2))\r\n\
       REPRESENTATION_CONTEXT('ctx','3D') );\r\n\
#10=CARTESIAN_POINT('',(10.,0.,0.));\r\n\
#11=CARTESIAN_POINT('',(1.E1,10.0,0.));\r\n\
#12=cartesian_point('',(0.,+10.,0.));\r\n\
/* the quarter circle of radius 10 */\r\n\
#13=(\r\n  BOUNDED_CURVE()\r\n  B_SPLINE_CURVE(2,(#10,#11,#12),.CIRCULAR_ARC.,.F.,.F.)\r\n\
  B_SPLINE_CURVE_WITH_KNOTS((3,3),(0.,1.5707963267949),.UNSPECIFIED.)\r\n\
  CURVE()\tGEOMETRIC_REPRESENTATION_ITEM()\r\n  RATIONAL_B_SPLINE_CURVE((1.,0.707106781186548,1.))\r\n\
  REPRESENTATION_ITEM('arc')\r\n);\r\n\
#14=VERTEX_POINT('',#10);\r\n#15=VERTEX_POINT('',#12);\r\n\
#16=EDGE_CURVE('',#14,#15,#13,.T.);\r\n\
#17=TRIMMED_CURVE('',#13,(PARAMETER_VALUE(0.)),(PARAMETER_VALUE(1.)),.T.,.PARAMETER.);\r\n\
#20=CARTESIAN_POINT('',(0.,0.,0.));#21=CARTESIAN_POINT('',(0.,5.,1.));\r\n\
#22=CARTESIAN_POINT('',(0.,10.,0.));#23=CARTESIAN_POINT('',(10.,0.,0.));\r\n\
#24=CARTESIAN_POINT ( 'NONE',  ( 5.E+000, 5.0E0 , 2.5E-1 ) ) ;\r\n\
#25=CARTESIAN_POINT('',(10.,10.,0.));\r\n\
#26=B_SPLINE_SURFACE_WITH_KNOTS('skin',1,2,((#20,#21,#22),(#23,#24,#25)),\r\n\
  .UNSPECIFIED.,.F.,.F.,.F.,(2,2),(3,3),(0.,1.),(-2.,2.),.UNSPECIFIED.);\r\n\
#27=ADVANCED_FACE('',(),#26,.T.);\r\n\
#30=CARTESIAN_POINT('',(0.,0.));#31=CARTESIAN_POINT('',(0.5,0.5));#32=CARTESIAN_POINT('',(1.,1.));\r\n\
#33=B_SPLINE_CURVE_WITH_KNOTS('',2,(#30,#31,#32),.UNSPECIFIED.,.F.,.F.,(3,3),(0.,1.),.UNSPECIFIED.);\r\n\
#34=DEFINITIONAL_REPRESENTATION('',(#33),#3);\r\n\
#35=PCURVE('',#26,#34);\r\n\
#40=LINE('',#10,#41);#41=VECTOR('',#42,1.);#42=DIRECTION('',(1.,0.,0.));\r\n\
#43=PLANE('',#44);\r\n\
ENDSEC;\r\nEND-ISO-10303-21;\r\n";

#[test]
#[allow(clippy::approx_constant)] // π/2 and 1/√2 to 15 digits, as the file has them
fn a_file_as_a_cad_system_writes_it_is_read_with_known_values() {
    let f = step::read_all(CAD_SNIPPET.as_bytes()).unwrap();
    assert_eq!(f.unit, Some(Unit::Millimeter));
    assert_eq!(f.objects.len(), 2, "{:?}", f.notices);
    assert_eq!((f.entities[0].entity, f.entities[0].label.as_str()), (13, "arc"));
    assert_eq!((f.entities[1].entity, f.entities[1].label.as_str()), (26, "skin"));
    let c = f.objects[0].as_curve().unwrap();
    assert_eq!((c.degree(), c.dim()), (2, 3));
    assert_eq!(
        c.knots().values(),
        [0., 0., 0., 1.5707963267949, 1.5707963267949, 1.5707963267949]
    );
    assert_eq!(c.weights().unwrap(), [1., 0.707106781186548, 1.]);
    assert_eq!(c.points()[1], DVec3::new(10., 10., 0.));
    assert_eq!(c.points()[2], DVec3::new(0., 10., 0.));
    // the middle of a quarter circle of radius 10: (10/√2, 10/√2)
    let mid = c.point(1.5707963267949 / 2.0);
    let r = 10.0 / 2f64.sqrt();
    assert!((mid - DVec3::new(r, r, 0.)).length() < 1e-12, "{mid}");
    let s = f.objects[1].as_surface().unwrap();
    assert_eq!((s.degree_u(), s.degree_v(), s.nu(), s.nv()), (1, 2, 2, 3));
    assert_eq!(s.knots_u().values(), [0., 0., 1., 1.]);
    assert_eq!(s.knots_v().values(), [-2., -2., -2., 2., 2., 2.]);
    assert_eq!(s.point_at(1, 1), DVec3::new(5., 5., 0.25));
    assert_eq!(s.point_at(0, 1), DVec3::new(0., 5., 1.));
    assert!(s.weights().is_none());
    // the p-curve, the line and plane, and the trims not applied are listed, nothing else
    assert_eq!(f.notices.len(), 3, "{:?}", f.notices);
    assert_eq!(
        f.notices[0],
        "#33 (B_SPLINE_CURVE_WITH_KNOTS) skipped: a curve in a surface's parameter space"
    );
    assert_eq!(
        f.notices[1],
        "2 other curves and surfaces skipped (only B-splines are read): 1 LINE, 1 PLANE"
    );
    assert_eq!(
        f.notices[2],
        "trims not applied (1 ADVANCED_FACE, 1 EDGE_CURVE, 1 TRIMMED_CURVE): the B-splines are read whole"
    );
}

#[test]
fn one_broken_b_spline_is_skipped_with_its_reason_and_the_others_are_read() {
    let objects: Vec<Geometry> = vec![twisted_cubic().into(), rational_3d().into(), wavy_bicubic().into()];
    let text = step::write(&objects, &opts(Unit::Millimeter));
    // break the rational curve's multiplicities: (4,1,1,4) → (4,1,1,5)
    let k = text
        .find("B_SPLINE_CURVE_WITH_KNOTS((4,1,1,4)")
        .expect("the rational curve");
    let broken = format!("{}B_SPLINE_CURVE_WITH_KNOTS((4,1,1,5){}", &text[..k], &text[k + 35..]);
    let f = step::read_all(broken.as_bytes()).unwrap();
    assert_eq!(f.objects.len(), 2);
    assert_bits_equal(&f.objects[0], &objects[0]);
    assert_bits_equal(&f.objects[1], &objects[2]);
    assert_eq!(f.notices.len(), 1, "{:?}", f.notices);
    let n = &f.notices[0];
    assert!(
        n.contains("(B_SPLINE_CURVE_WITH_KNOTS) on line")
            && n.ends_with("skipped: knot multiplicities add up to 11, expected 10 for 6 control points of degree 3"),
        "{n}"
    );
    // a point reference to nothing, a negative weight, decreasing knots
    let cases = [
        (
            "CARTESIAN_POINT('',(",
            "CARTESIAN_POINT('',(1.0,",
            "has 4 coordinates, not 2 or 3",
        ),
        (
            "RATIONAL_B_SPLINE_CURVE((1.0,",
            "RATIONAL_B_SPLINE_CURVE((-1.0,",
            "weight 1 is -1, weights must be positive",
        ),
        ("(0.0,0.25,", "(0.0,0.3,0.25,", "4 knot multiplicities for 5 knots"),
        (
            "B_SPLINE_CURVE_WITH_KNOTS((4,1,1,4),(0.0,",
            "B_SPLINE_CURVE_WITH_KNOTS((4,1,1,4),(0.5,",
            "knots must increase: knot 2 (0.25) is not above knot 1 (0.5)",
        ),
    ];
    let single = step::write(&[rational_3d().into()], &opts(Unit::Millimeter));
    for (from, to, why) in cases {
        let bad = single.replacen(from, to, 1);
        assert_ne!(bad, single, "{from}");
        let e = step::read_all(bad.as_bytes()).unwrap_err().to_string();
        assert!(e.starts_with("STEP: #") && e.contains(why), "{e}");
    }
    // a syntax error in one instance loses only that instance
    let garbled = text.replacen("CARTESIAN_POINT('',(", "CARTESIAN_POINT('',(,", 1);
    let f = step::read_all(garbled.as_bytes()).unwrap();
    assert_eq!(f.objects.len(), 2, "{:?}", f.notices);
    assert!(
        f.notices[0].contains("expected a value but found ','"),
        "{:?}",
        f.notices
    );
    assert!(f.notices[1].contains("refers to #"), "{:?}", f.notices);
}

fn unit_file(unit_instances: &str) -> String {
    format!(
        "ISO-10303-21;HEADER;ENDSEC;DATA;\n{unit_instances}\n\
         #9=(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNIT_ASSIGNED_CONTEXT((#1))REPRESENTATION_CONTEXT('',''));\n\
         #10=CARTESIAN_POINT('',(0.,0.,0.));#11=CARTESIAN_POINT('',(1.,2.,0.));\n\
         #12=B_SPLINE_CURVE_WITH_KNOTS('',1,(#10,#11),.UNSPECIFIED.,.F.,.F.,(2,2),(0.,1.),.UNSPECIFIED.);\n\
         ENDSEC;END-ISO-10303-21;"
    )
}

#[test]
fn units_are_detected_and_converted_on_request() {
    let cases = [
        (
            "#1=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));",
            Some(Unit::Millimeter),
        ),
        ("#1=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT($,.METRE.));", Some(Unit::Meter)),
        (
            "#1=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.CENTI.,.METRE.));",
            Some(Unit::Centimeter),
        ),
        (
            "#1=(CONVERSION_BASED_UNIT('INCH',#3)LENGTH_UNIT()NAMED_UNIT(#4));\
             #2=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));\
             #3=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#2);#4=DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.);",
            Some(Unit::Inch),
        ),
        (
            // an unusual name: recognised by its conversion factor (0.3048 m = 1 foot)
            "#1=(CONVERSION_BASED_UNIT('pied',#3)LENGTH_UNIT()NAMED_UNIT(*));\
             #2=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT($,.METRE.));#3=MEASURE_WITH_UNIT(LENGTH_MEASURE(0.3048),#2);",
            Some(Unit::Foot),
        ),
        (
            // the factor decides, not the name
            "#1=(CONVERSION_BASED_UNIT('INCH',#3)LENGTH_UNIT()NAMED_UNIT(*));\
             #2=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));#3=MEASURE_WITH_UNIT(LENGTH_MEASURE(304.8),#2);",
            Some(Unit::Foot),
        ),
        (
            // no factor to follow: the name
            "#1=(CONVERSION_BASED_UNIT('inch',$)LENGTH_UNIT()NAMED_UNIT(*));",
            Some(Unit::Inch),
        ),
        ("#1=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.NANO.,.METRE.));", None),
    ];
    for (units, expected) in cases {
        let text = unit_file(units);
        let f = step::read_all(text.as_bytes()).unwrap();
        assert_eq!(f.unit, expected, "{units}");
        assert_eq!(f.notices.is_empty(), expected.is_some(), "{:?}", f.notices);
    }
    // inch file read in mm: coordinates × 25.4
    let text = unit_file(cases[3].0);
    let f = step::read_all_with(
        text.as_bytes(),
        ReadOptions {
            unit: Some(Unit::Millimeter),
        },
    )
    .unwrap();
    assert_eq!(f.objects[0].as_curve().unwrap().points()[1], DVec3::new(25.4, 50.8, 0.));
    // an unknown unit cannot be converted
    let text = unit_file(cases.last().unwrap().0);
    let e = step::read_all_with(
        text.as_bytes(),
        ReadOptions {
            unit: Some(Unit::Millimeter),
        },
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "STEP: the file's length unit is not recognised, cannot convert to MM"
    );
}

#[test]
fn empty_and_foreign_files_get_clear_errors() {
    let e = |b: &[u8]| step::read_all(b).unwrap_err().to_string();
    assert_eq!(e(b""), "STEP: the file is empty");
    assert_eq!(e(b" \n"), "STEP: the file holds no data (only whitespace)");
    assert_eq!(
        e(b"{\"degree\": 3}"),
        "STEP: not a STEP (ISO 10303-21) file: unexpected character '{'"
    );
    let no_geometry = "ISO-10303-21;HEADER;ENDSEC;DATA;#1=CARTESIAN_POINT('',(0.,0.,0.));ENDSEC;END-ISO-10303-21;";
    assert!(step::read_all(no_geometry.as_bytes()).unwrap().objects.is_empty());
    assert_eq!(
        step::read_first(no_geometry.as_bytes()).unwrap_err().to_string(),
        "STEP: no B-spline curve or surface in the file"
    );
}

#[test]
fn every_truncation_of_a_valid_file_is_read_or_refused_without_panic() {
    let text = step::write(&[rational_3d().into(), sphere_octant(1.0).into()], &opts(Unit::Inch));
    let b = text.as_bytes();
    let t = std::time::Instant::now();
    let mut read = 0;
    for n in 0..b.len() {
        if let Ok(f) = step::read_all(&b[..n]) {
            read += f.objects.len();
            for g in &f.objects {
                fairway::range::check_geometry(g).unwrap();
            }
        }
    }
    // the prefixes that hold the whole first curve read it
    assert!(read > 0);
    assert!(t.elapsed().as_secs() < 60, "{:?}", t.elapsed());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_files_never_panic(
        seed in 0usize..3,
        edits in proptest::collection::vec((any::<proptest::sample::Index>(), any::<u8>(), 0u8..4), 1..8),
    ) {
        let seeds = [
            step::write(&[rational_3d().into(), wiggly_2d().into()], &opts(Unit::Millimeter)),
            step::write(&[wavy_rational().into()], &opts(Unit::Foot)),
            CAD_SNIPPET.to_string(),
        ];
        let mut b = seeds[seed].clone().into_bytes();
        for (at, byte, op) in edits {
            if b.is_empty() { break; }
            let i = at.index(b.len());
            match op {
                0 => b[i] = byte,
                1 => { b.remove(i); }
                2 => b.insert(i, b"();,#'.$*E-0123456789("[byte as usize % 22]),
                _ => { let j = (i + byte as usize).min(b.len()); b.drain(i..j); }
            }
        }
        if let Ok(f) = step::read_all(&b) {
            for g in &f.objects {
                prop_assert!(fairway::range::check_geometry(g).is_ok());
            }
        }
    }
}

#[test]
fn a_rational_surface_with_a_short_or_long_row_of_weights_is_skipped_with_its_reason() {
    let text = step::write(
        &[wavy_rational().into(), twisted_cubic().into()],
        &opts(Unit::Millimeter),
    );
    let s = wavy_rational();
    for (to, why) in [
        (
            "RATIONAL_B_SPLINE_SURFACE(((2.0,",
            format!("weights row 1 has {} weights for {} control points", s.nv() + 1, s.nv()),
        ),
        (
            "RATIONAL_B_SPLINE_SURFACE(((2.0),(",
            format!("{} rows of weights for {} rows of control points", s.nu() + 1, s.nu()),
        ),
    ] {
        let bad = text.replacen("RATIONAL_B_SPLINE_SURFACE(((", to, 1);
        assert_ne!(bad, text);
        let f = step::read_all(bad.as_bytes()).unwrap();
        assert_eq!(f.objects.len(), 1, "{:?}", f.notices);
        assert_bits_equal(&f.objects[0], &twisted_cubic().into());
        assert_eq!(f.notices.len(), 1, "{:?}", f.notices);
        assert!(f.notices[0].ends_with(&format!("skipped: {why}")), "{:?}", f.notices);
    }
}

/// The uniform quadratic B-spline basis on a span, at t ∈ [0, 1]: the weights of its three control points.
fn uniform_quadratic(t: f64) -> [f64; 3] {
    [
        (1.0 - t).powi(2) / 2.0,
        (-2.0 * t * t + 2.0 * t + 1.0) / 2.0,
        t * t / 2.0,
    ]
}

/// Control point `k` of the unclamped test curves and surfaces.
fn unclamped_point(i: usize, j: usize) -> DVec3 {
    DVec3::new(
        i as f64 * 3.0 + (j as f64).sin(),
        j as f64 * 2.0 + (i as f64).cos(),
        ((i * 7 + j * 3) % 5) as f64,
    )
}

fn unclamped_file(curve_knots: &str, surface_form: &str) -> String {
    let mut t = String::from("ISO-10303-21;HEADER;ENDSEC;DATA;\n");
    for i in 0..4 {
        for j in 0..5 {
            let q = unclamped_point(i, j);
            t += &format!(
                "#{}=CARTESIAN_POINT('',({:?},{:?},{:?}));\n",
                100 + i * 10 + j,
                q.x,
                q.y,
                q.z
            );
        }
    }
    let row = |i: usize| {
        (0..5)
            .map(|j| format!("#{}", 100 + i * 10 + j))
            .collect::<Vec<_>>()
            .join(",")
    };
    let weights: Vec<String> = (0..4)
        .map(|i| {
            format!(
                "({})",
                (0..5)
                    .map(|j| format!("{:?}", 0.5 + ((i + j) % 3) as f64 * 0.5))
                    .collect::<Vec<_>>()
                    .join(",")
            )
        })
        .collect();
    t += &format!(
        "#1=B_SPLINE_CURVE_WITH_KNOTS('',2,({}),.UNSPECIFIED.,.F.,.F.,{curve_knots},.UNSPECIFIED.);\n",
        row(0)
    );
    let rows: Vec<String> = (0..4).map(|i| format!("({})", row(i))).collect();
    t += &format!(
        "#2=(BOUNDED_SURFACE()B_SPLINE_SURFACE(2,2,({}),.UNSPECIFIED.,.F.,.F.,.F.){surface_form}\
         GEOMETRIC_REPRESENTATION_ITEM()RATIONAL_B_SPLINE_SURFACE(({}))REPRESENTATION_ITEM('')SURFACE());\n",
        rows.join(","),
        weights.join(",")
    );
    t + "ENDSEC;END-ISO-10303-21;"
}

#[test]
fn unclamped_b_splines_are_clamped_exactly_and_said() {
    // the uniform knots 0..7 (written as multiplicities), and the UNIFORM_SURFACE form (knots -2..6)
    let text = unclamped_file("(1,1,1,1,1,1,1,1),(0.,1.,2.,3.,4.,5.,6.,7.)", "UNIFORM_SURFACE()");
    let f = step::read_all(text.as_bytes()).unwrap();
    assert_eq!(f.objects.len(), 2, "{:?}", f.notices);
    assert_eq!(f.notices.len(), 2, "{:?}", f.notices);
    assert!(
        f.notices[0].starts_with("#1 (B_SPLINE_CURVE_WITH_KNOTS): unclamped knots"),
        "{:?}",
        f.notices
    );
    assert!(
        f.notices[1].starts_with("#2 (UNIFORM_SURFACE): unclamped knots"),
        "{:?}",
        f.notices
    );
    // the curve: domain [2, 5], on [2 + s, 3 + s) the uniform basis of points s, s + 1, s + 2
    let c = f.objects[0].as_curve().unwrap();
    assert_eq!(c.domain(), (2.0, 5.0));
    assert!(c.weights().is_none());
    for k in 0..=60 {
        let u = 2.0 + 3.0 * k as f64 / 60.0;
        let span = ((u - 2.0).floor() as usize).min(2);
        let b = uniform_quadratic(u - 2.0 - span as f64);
        let want: DVec3 = (0..3).map(|r| unclamped_point(0, span + r) * b[r]).sum();
        assert!(
            (c.point(u) - want).length() < 1e-12,
            "u = {u}: {} vs {want}",
            c.point(u)
        );
    }
    // the rational surface: knots -2..5 (u, 4 points) and -2..6 (v, 5 points): domain [0, 2] × [0, 3]
    let s = f.objects[1].as_surface().unwrap();
    assert_eq!(s.domain(), ((0.0, 2.0), (0.0, 3.0)));
    let w = |i: usize, j: usize| 0.5 + ((i + j) % 3) as f64 * 0.5;
    for a in 0..=10 {
        for b in 0..=10 {
            let (u, v) = (2.0 * a as f64 / 10.0, 3.0 * b as f64 / 10.0);
            let (su, sv) = ((u.floor() as usize).min(1), (v.floor() as usize).min(2));
            let (bu, bv) = (uniform_quadratic(u - su as f64), uniform_quadratic(v - sv as f64));
            let (mut num, mut den) = (DVec3::ZERO, 0.0);
            for r in 0..3 {
                for q in 0..3 {
                    let k = bu[r] * bv[q] * w(su + r, sv + q);
                    num += unclamped_point(su + r, sv + q) * k;
                    den += k;
                }
            }
            let got = s.point(u, v);
            assert!((got - num / den).length() < 1e-12, "({u}, {v}): {got} vs {}", num / den);
        }
    }
    // a knot vector with an empty domain is still refused
    let text = unclamped_file("(1,1,6),(0.,1.,2.)", "UNIFORM_SURFACE()");
    let f = step::read_all(text.as_bytes()).unwrap();
    assert_eq!(f.objects.len(), 1);
    assert!(
        f.notices[0].starts_with("#1 (B_SPLINE_CURVE_WITH_KNOTS) on line"),
        "{:?}",
        f.notices
    );
}

/// A STEP file whose curves have an interior knot of multiplicity p + 1 (a break), as some CAD systems
/// write Bézier chains: `(3,2,3)` knots at degree 2.
fn break_file(joint_b: &str) -> String {
    format!(
        "ISO-10303-21;\r\nHEADER;\r\nFILE_DESCRIPTION((''),'2;1');\r\nFILE_NAME('b','',(''),(''),'','','');\r\n\
         FILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\r\nENDSEC;\r\nDATA;\r\n\
         #1=CARTESIAN_POINT('',(0.,0.,0.));#2=CARTESIAN_POINT('',(1.,1.,0.));#3=CARTESIAN_POINT('',(2.,0.,0.));\r\n\
         #4=CARTESIAN_POINT('',({joint_b}));#5=CARTESIAN_POINT('',(3.,-1.,0.));#6=CARTESIAN_POINT('',(4.,0.,0.));\r\n\
         #7=B_SPLINE_CURVE_WITH_KNOTS('chain',2,(#1,#2,#3,#4,#5,#6),.UNSPECIFIED.,.F.,.F.,(3,3,3),(0.,1.,2.),\
         .UNSPECIFIED.);\r\nENDSEC;\r\nEND-ISO-10303-21;\r\n"
    )
}

#[test]
fn a_break_in_a_step_curve_is_reduced_where_continuous_and_split_where_not() {
    // the two Bézier pieces meet (#3 = #4): one curve with a C0 knot, the same shape
    let f = step::read_all(break_file("2.,0.,0.").as_bytes()).unwrap();
    assert_eq!(f.objects.len(), 1, "{:?}", f.notices);
    let c = f.objects[0].as_curve().unwrap();
    assert_eq!(c.knots().values(), [0., 0., 0., 1., 1., 2., 2., 2.]);
    assert_eq!(c.n_points(), 5);
    for (u, q) in [
        (0.5, DVec3::new(1.0, 0.5, 0.0)),
        (1.0, DVec3::new(2.0, 0.0, 0.0)),
        (1.5, DVec3::new(3.0, -0.5, 0.0)),
    ] {
        assert!((c.point(u) - q).length() < 1e-15, "{u}: {}", c.point(u));
    }
    assert!(
        f.notices.iter().any(|n| n.contains("reduced to a C0 knot")),
        "{:?}",
        f.notices
    );
    // they do not meet (#4 moved): two curves, each the Bézier on its side, labelled as pieces
    let f = step::read_all(break_file("2.,0.5,0.").as_bytes()).unwrap();
    assert_eq!(f.objects.len(), 2, "{:?}", f.notices);
    let labels: Vec<&str> = f.entities.iter().map(|e| e.label.as_str()).collect();
    assert_eq!(labels, ["chain, piece 1 of 2", "chain, piece 2 of 2"]);
    let (a, b) = (f.objects[0].as_curve().unwrap(), f.objects[1].as_curve().unwrap());
    assert_eq!(a.knots().values(), [0., 0., 0., 1., 1., 1.]);
    assert_eq!(b.knots().values(), [1., 1., 1., 2., 2., 2.]);
    assert_eq!(a.points()[2], DVec3::new(2.0, 0.0, 0.0));
    assert_eq!(b.points()[0], DVec3::new(2.0, 0.5, 0.0));
    assert!(
        f.notices.iter().any(|n| n.contains("split there, 2 pieces")),
        "{:?}",
        f.notices
    );
}

/// A part (a cubic in its own wireframe representation) placed twice in a sub-assembly, which is placed
/// in the top assembly: each occurrence is read in world coordinates, x ↦ A₂ A₁⁻¹ x at every level
/// (`ITEM_DEFINED_TRANSFORMATION(item in the child, item in the parent)`), the parent's placement applied
/// after the child's.
#[test]
fn assembly_placements_put_each_occurrence_of_a_part_where_the_assembly_places_it() {
    let text = "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('asm.stp','',(''),(''),'','','');\n\
        FILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n\
        #1=CARTESIAN_POINT('',(0.,0.,0.));\n#2=CARTESIAN_POINT('',(1.,0.,0.));\n\
        #3=CARTESIAN_POINT('',(2.,1.,0.));\n#4=CARTESIAN_POINT('',(3.,0.,1.));\n\
        #5=B_SPLINE_CURVE_WITH_KNOTS('rib',3,(#1,#2,#3,#4),.UNSPECIFIED.,.F.,.F.,(4,4),(0.,1.),.UNSPECIFIED.);\n\
        #6=GEOMETRIC_CURVE_SET('',(#5));\n\
        #10=CARTESIAN_POINT('',(0.,0.,0.));\n#11=AXIS2_PLACEMENT_3D('',#10,$,$);\n\
        #12=GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION('part',(#6,#11),#100);\n\
        #21=AXIS2_PLACEMENT_3D('',#22,#23,#24);\n#22=CARTESIAN_POINT('',(10.,0.,0.));\n\
        #23=DIRECTION('',(0.,0.,1.));\n#24=DIRECTION('',(0.,1.,0.));\n\
        #31=AXIS2_PLACEMENT_3D('',#32,#33,#34);\n#32=CARTESIAN_POINT('',(0.,0.,5.));\n\
        #33=DIRECTION('',(1.,0.,0.));\n#34=DIRECTION('',(0.,1.,0.));\n\
        #35=AXIS2_PLACEMENT_3D('',#10,$,$);\n\
        #20=SHAPE_REPRESENTATION('sub-assembly',(#35,#21,#31),#100);\n\
        #40=ITEM_DEFINED_TRANSFORMATION('','',#11,#21);\n\
        #41=(REPRESENTATION_RELATIONSHIP('','',#12,#20)REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#40)\
        SHAPE_REPRESENTATION_RELATIONSHIP());\n\
        #42=ITEM_DEFINED_TRANSFORMATION('','',#11,#31);\n\
        #43=(REPRESENTATION_RELATIONSHIP('','',#12,#20)REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#42)\
        SHAPE_REPRESENTATION_RELATIONSHIP());\n\
        #52=AXIS2_PLACEMENT_3D('',#53,$,#24);\n#53=CARTESIAN_POINT('',(0.,100.,0.));\n\
        #50=SHAPE_REPRESENTATION('top',(#52),#100);\n\
        #54=ITEM_DEFINED_TRANSFORMATION('','',#35,#52);\n\
        #55=(REPRESENTATION_RELATIONSHIP('','',#20,#50)REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#54)\
        SHAPE_REPRESENTATION_RELATIONSHIP());\n\
        #100=(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNIT_ASSIGNED_CONTEXT((#101))REPRESENTATION_CONTEXT('',''));\n\
        #101=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));\n\
        ENDSEC;\nEND-ISO-10303-21;\n";
    let f = step::read_all(text.as_bytes()).unwrap();
    let pts = |k: usize| match &f.objects[k] {
        Geometry::Curve(c) => c.points().to_vec(),
        g => panic!("a curve, not {}", g.kind()),
    };
    assert_eq!(f.objects.len(), 2, "{:?}", f.notices);
    assert_eq!(f.entities[0].label, "rib (occurrence 1 of 2)");
    assert_eq!(f.entities[1].label, "rib (occurrence 2 of 2)");
    // the top turns the sub-assembly by 90° about z and moves it by (0, 100, 0): (x, y, z) ↦ (−y, x + 100, z)
    let top = |q: DVec3| DVec3::new(-q.y, q.x + 100.0, q.z);
    // occurrence 1: turned by 90° about z, moved by (10, 0, 0): (x, y, z) ↦ (10 − y, x, z)
    let first = |q: DVec3| DVec3::new(10.0 - q.y, q.x, q.z);
    // occurrence 2: axes x' = (0,1,0), z' = (1,0,0), y' = z' × x' = (0,0,1), at (0, 0, 5): (x, y, z) ↦ (z, x, y + 5)
    let second = |q: DVec3| DVec3::new(q.z, q.x, q.y + 5.0);
    let part = [DVec3::ZERO, DVec3::X, DVec3::new(2., 1., 0.), DVec3::new(3., 0., 1.)];
    for (k, place) in [(0, &first as &dyn Fn(DVec3) -> DVec3), (1, &second)] {
        for (got, q) in pts(k).iter().zip(part) {
            let want = top(place(q));
            assert!(
                (*got - want).length() < 1e-12,
                "occurrence {}: {q} -> {got}, expected {want}",
                k + 1
            );
        }
    }
    assert!(
        f.notices
            .iter()
            .any(|n| n.contains("assembly placements applied: 2 representations")),
        "{:?}",
        f.notices
    );
    // the same file without its relationships: the part once, where it is written
    let flat: String = text
        .lines()
        .filter(|l| !l.contains("RELATIONSHIP"))
        .collect::<Vec<_>>()
        .join("\n");
    let f = step::read_all(flat.as_bytes()).unwrap();
    assert_eq!(f.objects.len(), 1);
    assert_eq!(f.objects[0].as_curve().unwrap().points(), part);
    assert!(!f.notices.iter().any(|n| n.contains("placements")), "{:?}", f.notices);
}

/// A `MAPPED_ITEM` places its `REPRESENTATION_MAP`'s representation (origin → target placement) in the
/// representation that holds the item.
#[test]
fn a_mapped_item_places_its_representation_at_its_target() {
    let text = "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('m.stp','',(''),(''),'','','');\n\
        FILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n\
        #1=CARTESIAN_POINT('',(0.,0.,0.));\n#2=CARTESIAN_POINT('',(1.,0.,0.));\n\
        #3=CARTESIAN_POINT('',(2.,1.,0.));\n#4=CARTESIAN_POINT('',(3.,0.,1.));\n\
        #5=B_SPLINE_CURVE_WITH_KNOTS('rib',3,(#1,#2,#3,#4),.UNSPECIFIED.,.F.,.F.,(4,4),(0.,1.),.UNSPECIFIED.);\n\
        #6=GEOMETRIC_CURVE_SET('',(#5));\n\
        #10=CARTESIAN_POINT('',(1.,1.,1.));\n#11=AXIS2_PLACEMENT_3D('',#10,$,$);\n\
        #12=GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION('part',(#6,#11),#100);\n\
        #21=AXIS2_PLACEMENT_3D('',#22,#23,#24);\n#22=CARTESIAN_POINT('',(10.,0.,0.));\n\
        #23=DIRECTION('',(0.,0.,1.));\n#24=DIRECTION('',(0.,1.,0.));\n\
        #30=REPRESENTATION_MAP(#11,#12);\n#31=MAPPED_ITEM('',#30,#21);\n\
        #20=SHAPE_REPRESENTATION('top',(#31),#100);\n\
        #100=(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNIT_ASSIGNED_CONTEXT((#101))REPRESENTATION_CONTEXT('',''));\n\
        #101=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));\n\
        ENDSEC;\nEND-ISO-10303-21;\n";
    let f = step::read_all(text.as_bytes()).unwrap();
    assert_eq!(f.objects.len(), 1, "{:?}", f.notices);
    // origin (1, 1, 1) with the file's axes onto the target at (10, 0, 0) turned by 90° about z:
    // (x, y, z) ↦ (10 − (y − 1), x − 1, z − 1)
    let part = [DVec3::ZERO, DVec3::X, DVec3::new(2., 1., 0.), DVec3::new(3., 0., 1.)];
    for (got, q) in f.objects[0].as_curve().unwrap().points().iter().zip(part) {
        let want = DVec3::new(11.0 - q.y, q.x - 1.0, q.z - 1.0);
        assert!((*got - want).length() < 1e-12, "{q} -> {got}, expected {want}");
    }
}
