//! IGES B-splines with a break — an interior knot of multiplicity p + 1, as CATIA V4 writes them:
//! reduced to a C0 knot where the geometry is continuous, split into pieces where it jumps; each piece is
//! the B-spline on its side, listed in the picker, and the notices say what was done.

use fairway::geometry::Geometry;
use fairway::io::iges;
use glam::DVec3;

fn rec(body: &str, letter: char, seq: usize) -> String {
    assert!(body.len() <= 72, "{body}");
    format!("{body:<72}{letter}{seq:>7}\n")
}

/// A file of one entity (`t` 126 or 128) with the parameter list `params` (comma-separated, ending in `;`),
/// wrapped into 64-column P records at commas.
fn one_entity_file(t: i64, params: &str) -> String {
    let mut f = rec("hand-written after IGES 5.3: one B-spline with a break", 'S', 1);
    let g = [
        "1H,,1H;,4Htest,7Hbrk.igs,4Htest,8HIGES 5.3,32,38,6,308,15,4Htest,",
        "1.0,2,2HMM,1,0.01,15H20240115.103000,1.0E-4,250.0,1Ha,1Hb,11,0,",
        "15H20240115.103000;",
    ];
    for (i, l) in g.iter().enumerate() {
        f += &rec(l, 'G', i + 1);
    }
    let mut lines = vec![String::new()];
    for tok in params.split_inclusive(',') {
        if lines.last().unwrap().len() + tok.len() > 64 {
            lines.push(String::new());
        }
        lines.last_mut().unwrap().push_str(tok);
    }
    f += &rec(
        &format!(
            "{t:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
            1, 0, 1, 0, 0, 0, 0, "00000000"
        ),
        'D',
        1,
    );
    f += &rec(
        &format!(
            "{t:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
            0,
            4,
            lines.len(),
            0,
            "",
            "",
            "  BRK",
            1
        ),
        'D',
        2,
    );
    for (i, l) in lines.iter().enumerate() {
        f += &format!("{l:<64} {:>7}P{:>7}\n", 1, i + 1);
    }
    f += &rec(&format!("S{:>7}G{:>7}D{:>7}P{:>7}", 1, 3, 2, lines.len()), 'T', 1);
    f
}

fn list(v: &[f64]) -> String {
    v.iter().map(|x| format!("{x:?},")).collect()
}

fn curve_params(knots: &[f64], pts: &[DVec3]) -> String {
    let n = pts.len();
    let xyz: Vec<f64> = pts.iter().flat_map(|q| [q.x, q.y, q.z]).collect();
    format!(
        "126,{},3,0,0,1,0,{}{}{}{:?},{:?};",
        n - 1,
        list(knots),
        list(&vec![1.0; n]),
        list(&xyz),
        knots[0],
        knots[knots.len() - 1]
    )
}

fn cubic_with_break() -> (Vec<f64>, Vec<DVec3>) {
    let k = vec![0., 0., 0., 0., 1., 1., 1., 1., 2., 2., 2., 2.];
    let pts = (0..8)
        .map(|i| DVec3::new(i as f64, (i * i % 5) as f64, 0.25 * i as f64))
        .collect();
    (k, pts)
}

#[test]
fn a_curve_with_a_jump_is_split_into_its_two_pieces() {
    let (k, pts) = cubic_with_break();
    let f = iges::read_all(one_entity_file(126, &curve_params(&k, &pts)).as_bytes()).unwrap();
    assert_eq!(f.objects.len(), 2, "{:?}", f.notices);
    let (a, b) = (f.objects[0].as_curve().unwrap(), f.objects[1].as_curve().unwrap());
    assert_eq!(a.knots().values(), &[0., 0., 0., 0., 1., 1., 1., 1.]);
    assert_eq!(a.points(), &pts[..4]);
    assert_eq!(b.knots().values(), &[1., 1., 1., 1., 2., 2., 2., 2.]);
    assert_eq!(b.points(), &pts[4..]);
    assert_eq!(f.entities[0].label, "BRK(1), piece 1 of 2");
    assert_eq!(f.entities[1].label, "BRK(1), piece 2 of 2");
    assert!(
        f.notices
            .iter()
            .any(|n| n.contains("breaks at knot 1") && n.contains("split")),
        "{:?}",
        f.notices
    );
}

#[test]
fn a_continuous_curve_with_a_doubled_knot_is_reduced_to_a_c0_knot() {
    let (k, mut pts) = cubic_with_break();
    pts[4] = pts[3];
    let f = iges::read_all(one_entity_file(126, &curve_params(&k, &pts)).as_bytes()).unwrap();
    assert_eq!(f.objects.len(), 1, "{:?}", f.notices);
    let c = f.objects[0].as_curve().unwrap();
    assert_eq!(c.knots().values(), &[0., 0., 0., 0., 1., 1., 1., 2., 2., 2., 2.]);
    let want: Vec<DVec3> = pts
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != 4)
        .map(|(_, q)| *q)
        .collect();
    assert_eq!(c.points(), want.as_slice());
    // the same shape: each side is the Bézier piece of its four points
    let bez = |q: &[DVec3], t: f64| {
        let s = 1.0 - t;
        q[0] * s * s * s + q[1] * 3.0 * s * s * t + q[2] * 3.0 * s * t * t + q[3] * t * t * t
    };
    for k in 0..=10 {
        let t = k as f64 / 10.0;
        assert!(c.point(t).distance(bez(&pts[0..4], t)) < 1e-12);
        assert!(c.point(1.0 + t).distance(bez(&pts[4..8], t)) < 1e-12);
    }
    assert!(
        f.notices.iter().any(|n| n.contains("reduced to a C0 knot")),
        "{:?}",
        f.notices
    );
}

/// A bicubic with the CATIA V4 u-knots (an interior knot of multiplicity 4) and simple v-knots.
fn surface_params(jump: bool) -> (String, Vec<DVec3>) {
    let ku = [0., 0., 0., 0., 1., 1., 1., 1., 2., 2., 2., 2.];
    let kv = [0., 0., 0., 0., 0.5, 1., 1., 1., 1.];
    let (nu, nv) = (8, 5);
    // Fairway's row-major P(i, j); IGES writes u fastest
    let mut p: Vec<DVec3> = (0..nu * nv)
        .map(|k| {
            let (i, j) = (k / nv, k % nv);
            DVec3::new(i as f64, j as f64, ((i * 3 + j * 7) % 5) as f64 * 0.1)
        })
        .collect();
    if !jump {
        for j in 0..nv {
            p[4 * nv + j] = p[3 * nv + j];
        }
    }
    let xyz: Vec<f64> = (0..nv)
        .flat_map(|j| (0..nu).map(move |i| (i, j)))
        .flat_map(|(i, j)| {
            let q = p[i * nv + j];
            [q.x, q.y, q.z]
        })
        .collect();
    let s = format!(
        "128,{},{},3,3,0,0,1,0,0,{}{}{}{}0.,2.,0.,1.;",
        nu - 1,
        nv - 1,
        list(&ku),
        list(&kv),
        list(&vec![1.0; nu * nv]),
        list(&xyz)
    );
    (s, p)
}

#[test]
fn a_catia_v4_face_with_a_knot_of_multiplicity_four_opens() {
    // the geometry jumps at u = 1: two faces, each the rows on its side
    let (text, p) = surface_params(true);
    let f = iges::read_all(one_entity_file(128, &text).as_bytes()).unwrap();
    assert_eq!(f.objects.len(), 2, "{:?}", f.notices);
    for (k, rows) in [(0, 0..4), (1, 4..8)] {
        let s = f.objects[k].as_surface().unwrap();
        assert_eq!((s.nu(), s.nv()), (4, 5));
        for (a, i) in rows.enumerate() {
            for j in 0..5 {
                assert_eq!(s.point_at(a, j), p[i * 5 + j]);
            }
        }
    }
    // continuous at u = 1: one face with a C0 knot line there, which fairs
    let (text, p) = surface_params(false);
    let f = iges::read_all(one_entity_file(128, &text).as_bytes()).unwrap();
    assert_eq!(f.objects.len(), 1, "{:?}", f.notices);
    let Geometry::Surface(s) = &f.objects[0] else {
        panic!("a surface")
    };
    assert_eq!(s.knots_u().values(), &[0., 0., 0., 0., 1., 1., 1., 2., 2., 2., 2.]);
    assert_eq!(s.nu(), 7);
    assert_eq!(s.point_at(4, 2), p[5 * 5 + 2]);
    let m = 1e-2;
    let r = fairway::fair::fair_surface(s, fairway::fair::SurfaceFairingOptions::default().tolerance(m)).unwrap();
    assert!(r.band_bound.unwrap() <= m);
}
