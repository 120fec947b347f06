//! Tests of cooperative cancellation: the token and its scope, then the surface and network fairs with a
//! token set before the call, from another thread during it, at every checkpoint in turn, and never.

use super::*;
use crate::curve::BSplineCurve;
use crate::fair::closed::split;
use crate::fair::network::{NetworkFair, NetworkOptions, fair_network_at, fair_network_at_with};
use crate::fair::surface::{
    SurfaceFairingOptions, SurfaceFairingResult, SurfaceMethod, fair_surface, fair_surface_with,
};
use crate::geometry::Geometry;
use crate::knots::KnotVector;
use crate::surface::BSplineSurface;
use glam::DVec3;

#[test]
fn a_checkpoint_fires_only_inside_the_scope_of_a_set_token() {
    assert!(check().is_ok(), "no token installed");
    let t = Cancel::new();
    scoped(Some(&t), || {
        assert!(check().is_ok());
        t.cancel();
        assert_eq!(check(), Err(Error::Cancelled));
        // a nested scope without a token (another fair's item on this worker) does not see it
        scoped(None, || assert!(check().is_ok()));
        assert_eq!(
            check(),
            Err(Error::Cancelled),
            "the token is restored after the nested scope"
        );
    });
    assert!(check().is_ok(), "the scope ended");
    assert_eq!(t.checkpoints(), 1);
}

#[test]
fn run_reports_a_cancel_during_the_call_even_if_the_work_swallowed_it() {
    let t = Cancel::new();
    let r = t.run(|| {
        t.cancel();
        // a fallback that ignored the cancelled inner step
        let _ = check();
        Ok(1)
    });
    assert_eq!(r, Err(Error::Cancelled));
    let t = Cancel::new();
    assert_eq!(t.run(|| Ok(2)), Ok(2));
}

#[test]
fn the_token_is_restored_after_a_panic() {
    let t = Cancel::new();
    t.cancel();
    let r = std::panic::catch_unwind(|| scoped(Some(&t), || panic!("boom")));
    assert!(r.is_err());
    assert!(check().is_ok(), "the panicking scope left its token installed");
}

/// A fixed, dependency-free noise in [-0.5, 0.5) (an LCG, as `examples/surface_timing.rs`).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

/// `n × n` bicubic net over [0,1]² on `knots` (uniform if `None`): a smooth wave with noise of amplitude
/// `noise` on z (the surface of `examples/surface_timing.rs` for `noise` 3.4e-3); `weights` makes it rational.
fn wave(n: usize, noise: f64, knots: Option<Vec<f64>>, weights: Option<fn(usize, usize) -> f64>) -> BSplineSurface {
    let k = match knots {
        Some(k) => KnotVector::try_new(k, 3, n, "u").unwrap(),
        None => KnotVector::uniform(3, n).unwrap(),
    };
    let g = k.greville();
    let mut rng = Lcg(0x9E37_79B9_7F4A_7C15);
    let mut pts = Vec::with_capacity(n * n);
    for &u in &g {
        for &v in &g {
            pts.push(DVec3::new(
                u,
                v,
                0.3 * (3.0 * u).sin() * (2.0 * v).cos() + noise * rng.next(),
            ));
        }
    }
    let w = weights.map(|f| (0..n * n).map(|i| f(i / n, i % n)).collect());
    BSplineSurface::try_new(3, 3, k.values().to_vec(), k.values().to_vec(), n, n, pts, w).unwrap()
}

/// A noisy dome over a disc whose first control row is one point (a pole: step 0's route).
fn dome(n: usize) -> BSplineSurface {
    let k = KnotVector::uniform(3, n).unwrap();
    let g = k.greville();
    let mut rng = Lcg(31);
    let mut pts = Vec::new();
    for &r in &g {
        for &t in &g {
            let a = 0.8 * std::f64::consts::TAU * t;
            let z = if r > 0.0 { 3e-3 * rng.next() } else { 0.0 };
            pts.push(DVec3::new(r * a.cos(), r * a.sin(), 0.5 * r * r + z));
        }
    }
    BSplineSurface::try_new(3, 3, k.values().to_vec(), k.values().to_vec(), n, n, pts, None).unwrap()
}

/// `r` without its timings (wall clock), to compare two fairs.
fn untimed(mut r: SurfaceFairingResult) -> SurfaceFairingResult {
    r.timings = Default::default();
    r
}

fn bits(s: &BSplineSurface) -> Vec<[u64; 3]> {
    s.points()
        .iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect()
}

/// The fair with `cancel` equals the fair without one, bit for bit (timings aside).
fn assert_same(a: SurfaceFairingResult, b: SurfaceFairingResult, what: &str) {
    assert_eq!(bits(&a.surface), bits(&b.surface), "{what}: control points differ");
    assert_eq!(
        (a.max_deviation.to_bits(), a.band_bound.map(f64::to_bits)),
        (b.max_deviation.to_bits(), b.band_bound.map(f64::to_bits)),
        "{what}"
    );
    assert_eq!(untimed(a), untimed(b), "{what}");
}

#[test]
fn a_token_set_before_the_call_gives_cancelled_at_once() {
    let s = wave(20, 3.4e-3, None, None);
    let c = Cancel::new();
    c.cancel();
    let r = fair_surface_with(&s, SurfaceFairingOptions::default().tolerance(3e-3), &c);
    assert_eq!(r, Err(Error::Cancelled));
    assert_eq!(c.checkpoints(), 0, "work was done for a token set before the call");
    let (objects, opts) = network();
    let r = fair_network_at_with(&objects, &[], &opts, &[], &c);
    assert!(matches!(r, Err(Error::Cancelled)), "{r:?}");
    assert_eq!(c.checkpoints(), 0);
}

/// A token never set: the same result as the call without one, bit for bit (and a checkpoint count that
/// does not depend on the thread count).
#[test]
fn a_token_never_set_gives_the_bit_identical_result() {
    for (name, s, opts) in surfaces() {
        let c = Cancel::new();
        let with = fair_surface_with(&s, opts, &c).unwrap();
        assert!(c.checkpoints() > 0, "{name}: no checkpoint passed");
        assert_same(with, fair_surface(&s, opts).unwrap(), name);
        let one = Cancel::new();
        fair_surface_with(&s, opts.threads(Some(1)), &one).unwrap();
        assert_eq!(one.checkpoints(), c.checkpoints(), "{name}: checkpoints on one thread");
    }
    let (objects, opts) = network();
    let c = Cancel::new();
    let with = fair_network_at_with(&objects, &[], &opts, &[], &c).unwrap();
    assert_network_same(&with, &fair_network_at(&objects, &[], &opts, &[]).unwrap());
}

fn assert_network_same(a: &NetworkFair, b: &NetworkFair) {
    assert_eq!(a.objects, b.objects);
    assert_eq!(a.outcome, b.outcome);
    assert_eq!(a.notes, b.notes);
    assert!(a.outcome.iter().all(|o| o.faired), "{:?}", a.outcome);
}

/// The surfaces of the sweep, each through another route of `fair_surface`: whole and in a region, the
/// three methods, across a C0 knot line (tiles), with a pole (step 0), rational (the stand-in).
fn surfaces() -> Vec<(&'static str, BSplineSurface, SurfaceFairingOptions)> {
    let m = SurfaceFairingOptions::default().tolerance(3e-3);
    let crease = [
        vec![0.0; 4],
        vec![0.125, 0.25, 0.375, 0.5, 0.5, 0.5, 0.625, 0.75, 0.875],
        vec![1.0; 4],
    ]
    .concat();
    vec![
        ("whole", wave(12, 3.4e-3, None, None), m),
        (
            "region",
            wave(12, 3.4e-3, None, None),
            m.region(Some(((0.2, 0.8), (0.1, 0.7)))),
        ),
        (
            "isocurves",
            wave(12, 3.4e-3, None, None),
            m.method(SurfaceMethod::Isocurves).iso_levels(1),
        ),
        (
            "smoothing",
            wave(12, 3.4e-3, None, None),
            m.method(SurfaceMethod::Smoothing),
        ),
        ("tiles", wave(13, 3.4e-3, Some(crease), None), m),
        ("pole", dome(12), m.tolerance(1.5e-2)),
        (
            "rational",
            wave(8, 3.4e-3, None, Some(|i, j| 1.0 + 0.02 * (i + j) as f64)),
            m,
        ),
    ]
}

/// A noisy curve split into a G2 chain of three, and a noisy 16 × 12 patch split into two sharing an edge:
/// the chain route and a surface route with its fallbacks.
fn network() -> (Vec<Geometry>, NetworkOptions) {
    let n = 24;
    let k = KnotVector::uniform(3, n).unwrap();
    let mut rng = Lcg(7);
    let pts: Vec<DVec3> = (k.greville().iter())
        .map(|&t| {
            let a = 2.5 * t;
            DVec3::new(2.0 * a.cos(), a.sin(), 0.0) + DVec3::new(0.0, 4e-3 * rng.next(), 0.0)
        })
        .collect();
    let c = BSplineCurve::try_new(3, k.values().to_vec(), pts, None, 2).unwrap();
    let bp = c.knots().breakpoints();
    let (a, rest) = split(&c, bp[bp.len() / 3]).unwrap();
    let (b, cc) = split(&rest, bp[2 * bp.len() / 3]).unwrap();
    // the patch's v-rows as curves along u, each split at one knot: two patches on the same edge
    let s = wave(12, 3.4e-3, None, None);
    let u = s.knots_u().values()[8];
    let (mut left, mut right) = (vec![], vec![]);
    for j in 0..s.nv() {
        let row = (0..s.nu()).map(|i| s.point_at(i, j)).collect();
        let row = BSplineCurve::try_new(3, s.knots_u().values().to_vec(), row, None, 3).unwrap();
        let (l, r) = split(&row, u).unwrap();
        left.push(l);
        right.push(r);
    }
    let patch = |rows: &[BSplineCurve]| {
        let (nu, nv) = (rows[0].n_points(), rows.len());
        let pts = (0..nu * nv).map(|k| rows[k % nv].points()[k / nv]).collect();
        let ku = rows[0].knots().values().to_vec();
        BSplineSurface::try_new(3, 3, ku, s.knots_v().values().to_vec(), nu, nv, pts, None).unwrap()
    };
    let objects = vec![a.into(), b.into(), cc.into(), patch(&left).into(), patch(&right).into()];
    let mut opts = NetworkOptions::default();
    opts.curve.tolerance = 3e-3;
    opts.surface.tolerance = 3e-3;
    (objects, opts)
}

/// A token that sets itself at checkpoint k, for every k of an uncancelled run in turn (one thread, so
/// the count is exact): each call returns `Cancelled` — never a result, not even a fallback route's —
/// having passed exactly k checkpoints; one past the last, the call runs to its end.
#[test]
fn cancelled_at_any_checkpoint_a_fair_returns_cancelled_never_a_result() {
    for (name, s, opts) in surfaces() {
        let t0 = std::time::Instant::now();
        let opts = opts.threads(Some(1));
        let full = Cancel::new();
        let want = fair_surface_with(&s, opts, &full).unwrap();
        let total = full.checkpoints();
        // each surface takes the route it stands for
        let noted = |what: &str| want.notes.iter().any(|n| n.contains(what));
        match name {
            "tiles" => assert!(noted("C0 knot lines"), "{:?}", want.notes),
            "pole" => assert_eq!(want.smoothed_poles, 1, "{:?}", want.notes),
            "rational" => assert!(noted("rational surface (unequal weights)"), "{:?}", want.notes),
            _ => {}
        }
        for k in 1..=total {
            let c = Cancel::new();
            c.trip_at(k);
            let r = fair_surface_with(&s, opts, &c);
            assert_eq!(
                r.err(),
                Some(Error::Cancelled),
                "{name}: cancelled at checkpoint {k} of {total}"
            );
            assert_eq!(c.checkpoints(), k, "{name}: work went on after the cancel at {k}");
        }
        let c = Cancel::new();
        c.trip_at(total + 1);
        assert_same(fair_surface_with(&s, opts, &c).unwrap(), want, name);
        eprintln!("{name}: {total} checkpoints, {:?}", t0.elapsed());
    }
    let (objects, mut opts) = network();
    opts.surface.threads = Some(1);
    let full = Cancel::new();
    let want = fair_network_at_with(&objects, &[], &opts, &[], &full).unwrap();
    let total = full.checkpoints();
    for k in 1..=total {
        let c = Cancel::new();
        c.trip_at(k);
        let r = fair_network_at_with(&objects, &[], &opts, &[], &c);
        assert!(
            matches!(r, Err(Error::Cancelled)),
            "network: at checkpoint {k} of {total}: {r:?}"
        );
    }
    let c = Cancel::new();
    c.trip_at(total + 1);
    assert_network_same(&fair_network_at_with(&objects, &[], &opts, &[], &c).unwrap(), &want);
    eprintln!("network: {total} checkpoints");
}

/// A 50 × 50 fair on all cores, cancelled from another thread once it has passed a few checkpoints (the
/// first isocurve blocks): it returns `Cancelled` having passed far fewer checkpoints than the uncancelled
/// run (no timing is measured: the count is the progress).
#[test]
fn a_token_set_from_another_thread_stops_a_50x50_fair_early() {
    let s = std::sync::Arc::new(wave(50, 3.4e-3, None, None));
    let opts = SurfaceFairingOptions::default().tolerance(3e-3);
    let full = Cancel::new();
    fair_surface_with(&s, opts, &full).unwrap();
    let total = full.checkpoints();
    assert!(total > 40, "{total} checkpoints: too coarse to stop early");
    let c = Cancel::new();
    let (s2, c2) = (s.clone(), c.clone());
    let fair = std::thread::spawn(move || fair_surface_with(&s2, opts, &c2));
    let at = 4;
    while c.checkpoints() < at && !fair.is_finished() {
        std::thread::yield_now();
    }
    c.cancel();
    let seen = c.checkpoints();
    let r = fair.join().unwrap();
    assert_eq!(r.err(), Some(Error::Cancelled));
    let done = c.checkpoints();
    eprintln!("cancelled after {seen} checkpoints, {done} passed in all, of {total}");
    // the checkpoints under way when the token was set may still pass: one per worker at most
    assert!(
        done <= seen + rayon::current_num_threads() + 1,
        "{done} passed after the cancel at {seen}"
    );
    assert!(done < total / 2, "{done} of {total} checkpoints");
}
