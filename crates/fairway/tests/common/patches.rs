//! Patches for the network tests: the bundled noisy surface cut at interior knots (so every shared edge
//! is exactly as continuous as the surface there), turned, lifted; the check of a joint fair.

use fairway::fair::closed::split;
use fairway::fair::network::{NetworkFair, NetworkOptions, fair_network};
use fairway::measure_surface::surface_measures;
use fairway::network::{Continuity, find_joins};
use fairway::{BSplineCurve, BSplineSurface, DVec3, Geometry};

/// The bundled bumpy surface: a noisy bicubic, 20 × 16 control points on uniform knots.
pub fn bumpy() -> BSplineSurface {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/bumpy_surface.json");
    fairway::io::load_geometry(&path).unwrap().as_surface().unwrap().clone()
}

/// The surface whose curves along u are `cs` (one per v index; one knot vector), on the v knots `kv`.
pub fn from_columns(cs: &[BSplineCurve], pv: usize, kv: &[f64]) -> BSplineSurface {
    let (nu, nv) = (cs[0].n_points(), cs.len());
    let pts = (0..nu).flat_map(|i| (0..nv).map(move |j| cs[j].points()[i])).collect();
    BSplineSurface::try_new(
        cs[0].degree(),
        pv,
        cs[0].knots().values().to_vec(),
        kv.to_vec(),
        nu,
        nv,
        pts,
        None,
    )
    .unwrap()
}

/// `s` cut across u at the parameters `at` (exact: each curve along u split there).
pub fn cut_u(s: &BSplineSurface, at: &[f64]) -> Vec<BSplineSurface> {
    let mut parts: Vec<Vec<BSplineCurve>> = vec![vec![]; at.len() + 1];
    for j in 0..s.nv() {
        let pts = (0..s.nu()).map(|i| s.point_at(i, j)).collect();
        let mut rest = BSplineCurve::try_new(s.degree_u(), s.knots_u().values().to_vec(), pts, None, 3).unwrap();
        for (k, &u) in at.iter().enumerate() {
            let (l, r) = split(&rest, u).unwrap();
            parts[k].push(l);
            rest = r;
        }
        parts[at.len()].push(rest);
    }
    parts
        .iter()
        .map(|cs| from_columns(cs, s.degree_v(), s.knots_v().values()))
        .collect()
}

/// `s` cut into a grid at the u knots `us` and the v knots `vs`: `grid[r][c]`, r along u, c along v.
pub fn cut(s: &BSplineSurface, us: &[f64], vs: &[f64]) -> Vec<Vec<BSplineSurface>> {
    cut_u(s, us)
        .iter()
        .map(|row| {
            cut_u(&row.transposed(), vs)
                .iter()
                .map(BSplineSurface::transposed)
                .collect()
        })
        .collect()
}

/// `s` with its u direction reversed (the same surface, u ↦ u₀ + u₁ − u).
pub fn reverse_u(s: &BSplineSurface) -> BSplineSurface {
    let (nu, nv) = (s.nu(), s.nv());
    let pts = (0..nu)
        .flat_map(|i| (0..nv).map(move |j| (nu - 1 - i, j)))
        .map(|(i, j)| s.point_at(i, j))
        .collect();
    let ku = s.knots_u().values();
    let (a, b) = (ku[0], ku[ku.len() - 1]);
    let ku: Vec<f64> = ku.iter().rev().map(|k| a + b - k).collect();
    BSplineSurface::try_new(
        s.degree_u(),
        s.degree_v(),
        ku,
        s.knots_v().values().to_vec(),
        nu,
        nv,
        pts,
        None,
    )
    .unwrap()
}

/// The `k`-th interior knot of a knot vector's breakpoints.
pub fn knot(s: &[f64], k: usize) -> f64 {
    let mut bp: Vec<f64> = s.to_vec();
    bp.dedup();
    bp[k]
}

/// What a grid test measures: the fair together and one by one (edges held).
pub struct Outcome {
    pub together: NetworkFair,
    pub held: NetworkFair,
}

/// Fair `patches` together and one by one at tolerance `m`; assert every shared edge keeps its
/// continuity (normal angle ≤ 0.01° and no gap where G1, G2 where it was G2), every patch its band, the
/// isocurve extrema down on every patch and fewer in all than one by one.
pub fn check(name: &str, patches: &[BSplineSurface], edges: usize, m: f64) -> Outcome {
    check_with(name, patches, edges, m, true)
}

/// [`check`], the comparison with one by one on each patch only where `each_vs_held` (else on the sum).
pub fn check_with(name: &str, patches: &[BSplineSurface], edges: usize, m: f64, each_vs_held: bool) -> Outcome {
    let objects: Vec<Geometry> = patches.iter().cloned().map(Into::into).collect();
    let before = find_joins(&objects);
    assert_eq!(before.surfaces.len(), edges, "{name}: {before:?}");
    let mut o = NetworkOptions::default();
    o.surface.tolerance = m;
    let together = fair_network(&objects, &[], &o).unwrap();
    assert!(
        together
            .outcome
            .iter()
            .all(|x| x.faired && x.group.len() == patches.len() && x.max_deviation <= m),
        "{name}: {:?} {:?}",
        together.outcome,
        together.notes
    );
    for (b, a) in before.surfaces.iter().zip(&together.joins_after.surfaces) {
        let (b, a) = (b.continuity, a.continuity);
        eprintln!(
            "{name}: edge {:?} → {:?}: normal angle {:.1e}° → {:.1e}°, gap {:.1e}, normal-curvature jump {:.1e} → {:.1e}",
            b.class,
            a.class,
            b.normal_angle.to_degrees(),
            a.normal_angle.to_degrees(),
            a.gap,
            b.curvature_jump,
            a.curvature_jump
        );
        assert!(a.normal_angle.to_degrees() <= 0.01 && a.gap <= 1e-9, "{name}: {a:?}");
        if b.class == Continuity::G2 {
            assert_eq!(a.class, Continuity::G2, "{name}: G2 kept: {a:?}");
        }
    }
    let held = fair_network(&objects, &[], &NetworkOptions { hold_all: true, ..o }).unwrap();
    let (mut sum_together, mut sum_held) = (0, 0);
    for (k, ((p, f), h)) in patches.iter().zip(&together.objects).zip(&held.objects).enumerate() {
        let f = f.as_surface().unwrap();
        assert_eq!((f.nu(), f.nv()), (p.nu(), p.nv()), "{name}: each patch on its own net");
        let (m0, mt, mh) = (
            surface_measures(p, p),
            surface_measures(p, f),
            surface_measures(p, h.as_surface().unwrap()),
        );
        eprintln!(
            "{name}: patch {k}: isocurve extrema {} → {} together, {} one by one (edges held); deviation {:.2e} / {:.2e}",
            m0.n_curv_extrema, mt.n_curv_extrema, mh.n_curv_extrema, mt.hausdorff, mh.hausdorff
        );
        assert!(
            mt.dev_max <= m && mt.hausdorff <= m,
            "{name}: patch {k} band: {}",
            mt.hausdorff
        );
        assert!(mt.n_curv_extrema < m0.n_curv_extrema, "{name}: patch {k}");
        assert!(
            !each_vs_held || mt.n_curv_extrema <= mh.n_curv_extrema,
            "{name}: patch {k} against one by one"
        );
        sum_together += mt.n_curv_extrema;
        sum_held += mh.n_curv_extrema;
    }
    eprintln!("{name}: isocurve extrema in all: together {sum_together}, one by one {sum_held}");
    assert!(
        sum_together < sum_held,
        "{name}: together {sum_together} vs one by one {sum_held}"
    );
    Outcome { together, held }
}

/// `p` with its third control row from its u₀ side lifted by a smooth bump (0.01 high) that vanishes three
/// columns short of its v sides: its u₀ side keeps its position and cross tangent (G1 with a neighbour
/// there) but not its curvature across (no longer G2), and its v sides are unchanged.
pub fn lift(p: &BSplineSurface) -> BSplineSurface {
    bumped(p, (Some(2), None))
}

/// `p` with one control row (`at.0`, along v) or column (`at.1`, along u) lifted in z by a smooth bump
/// 0.01 high that vanishes three points short of the line's ends.
fn bumped(p: &BSplineSurface, at: (Option<usize>, Option<usize>)) -> BSplineSurface {
    let (nu, nv) = (p.nu(), p.nv());
    let pts = (0..nu)
        .flat_map(|i| (0..nv).map(move |j| (i, j)))
        .map(|(i, j)| {
            let (on, k, n) = match at {
                (Some(r), _) => (i == r, j, nv),
                (_, Some(c)) => (j == c, i, nu),
                _ => (false, 0, 5),
            };
            let t = (k as f64 - 2.0) / (n as f64 - 5.0);
            let bump = if on && (0.0..=1.0).contains(&t) {
                0.01 * (std::f64::consts::PI * t).sin().powi(2)
            } else {
                0.0
            };
            p.point_at(i, j) + DVec3::new(0.0, 0.0, bump)
        })
        .collect();
    p.with_points(pts).unwrap()
}

/// A noisy tube: a bicubic with u along its axis (`nu` control rows from z = 0 to 2) and v around it, a
/// uniform periodic cubic of `n` control points (n a multiple of 4; radius 1, each moved radially by up
/// to ±`noise`), clamped exactly (first = last control column, C2 across v = 0 ≡ 1), cut at v = ¼, ½, ¾
/// into 4 patches: each shares an edge with the next and the last with the first, all exactly G2.
pub fn noisy_tube(nu: usize, n: usize, noise: f64) -> Vec<BSplineSurface> {
    noisy_tube_cut(nu, n, noise, &[]).remove(0)
}

/// [`noisy_tube`] cut across its axis too, at the u parameters `us`: `grid[r][c]`, r along the axis.
pub fn noisy_tube_cut(nu: usize, n: usize, noise: f64, us: &[f64]) -> Vec<Vec<BSplineSurface>> {
    let hash = |i: usize, j: usize| {
        let x = ((i * 7919 + j * 104_729) as f64 * 12.9898).sin() * 43_758.545_3;
        2.0 * (x - x.floor()) - 1.0
    };
    let rows: Vec<BSplineCurve> = (0..nu)
        .map(|i| {
            let z = 2.0 * i as f64 / (nu - 1) as f64;
            let q: Vec<DVec3> = (0..n)
                .map(|j| {
                    let t = std::f64::consts::TAU * j as f64 / n as f64;
                    let r = 1.0 + noise * hash(i, j);
                    DVec3::new(r * t.cos(), r * t.sin(), z)
                })
                .collect();
            fairway::fair::closed::periodic_cubic(&q, 3).unwrap()
        })
        .collect();
    // the rows along v as the tube's net: u clamped uniform over [0, 1]
    let mut ku = vec![0.0; 4];
    ku.extend((1..nu - 3).map(|k| k as f64 / (nu - 3) as f64));
    ku.extend([1.0; 4]);
    let nv = rows[0].n_points();
    let pts = rows.iter().flat_map(|c| c.points().iter().copied()).collect();
    let tube = BSplineSurface::try_new(3, 3, ku, rows[0].knots().values().to_vec(), nu, nv, pts, None).unwrap();
    cut(&tube, us, &[0.25, 0.5, 0.75])
}

/// `p` with its second control column from its v₀ side lifted by a smooth bump (0.01 high) that vanishes
/// three rows short of its u sides: its v₀ side keeps its position but not its tangent plane (a crease
/// with a neighbour there, G0), and its u sides are unchanged.
pub fn crease(p: &BSplineSurface) -> BSplineSurface {
    bumped(p, (None, Some(1)))
}
