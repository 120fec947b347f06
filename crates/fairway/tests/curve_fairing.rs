//! `fair::CurveFairing`, the one curve-fairing entry point: each route gives what the route's own
//! functions give (bit for bit on a fresh fair), the band holds, a draft and the full fair share one
//! setup, and run options change without a new setup while setup options prepare afresh.

mod common;

use common::{KNOWN_SHAPES, Rng, dev_max, noisy_curve, opts};
use fairway::fair::closed::{fair_closed, periodic_cubic, setup_across_seam};
use fairway::fair::{
    CurveFairing, EndCondition, FairingOptions, FairingSetup, Pass, PolishMethod, Seam, TargetMethod,
    fair_between_corners,
};
use fairway::{BSplineCurve, DVec3};

/// A noisy closed circle (periodic cubic through 40 noisy points, C2 seam).
fn noisy_loop(seed: u64) -> BSplineCurve {
    let mut rng = Rng::new(seed);
    let q: Vec<DVec3> = (0..40)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / 40.0;
            let r = 1.0 + 2e-3 * rng.gauss();
            DVec3::new(r * t.cos(), r * t.sin(), 0.0)
        })
        .collect();
    periodic_cubic(&q, 2).unwrap()
}

/// `c` with a kink at u = 0.5: the knot tripled (exact) and the control point on the curve there moved.
fn kinked(c: &BSplineCurve) -> BSplineCurve {
    let r = c.insert_knot(0.5, 3).unwrap();
    let k = (0..r.n_points())
        .min_by(|&i, &j| {
            let d = |i: usize| r.points()[i].distance(r.point(0.5));
            d(i).total_cmp(&d(j))
        })
        .unwrap();
    let mut pts = r.points().to_vec();
    pts[k] += DVec3::new(0.0, 0.1, 0.0);
    r.with_points(pts).unwrap()
}

fn same(a: &BSplineCurve, b: &BSplineCurve) -> bool {
    a.knots() == b.knots() && a.points() == b.points()
}

#[test]
fn every_route_gives_what_its_own_functions_give() {
    let m = 3e-3;
    // one setup: an open curve, whole and a region with G1 ends
    let open = noisy_curve(KNOWN_SHAPES[0], 30, 2e-3, 3);
    for (region, ends) in [(None, EndCondition::G2), (Some((0.2, 0.7)), EndCondition::G1)] {
        let o = (opts(m)).region(region).ends(ends);
        let mut f = CurveFairing::new(&open, o).unwrap();
        assert!(!f.whole_loop() && !f.across_seam() && f.corners().is_empty());
        let got = f.fair(Pass::Full).unwrap();
        let mut s = FairingSetup::new(&open, o).unwrap();
        let want = s.fair().unwrap();
        assert!(same(&got.result.curve, &want.curve), "{region:?}");
        assert_eq!(got.energy_before.to_bits(), s.original_energy().to_bits());
        assert_eq!(f.free_points(), s.free_points());
        assert_eq!(f.sample_params(), s.params());
        assert!(got.result.max_deviation <= m && dev_max(&open, &got.result.curve) <= m);
    }
    // a whole loop: the two passes across the seam
    let lp = noisy_loop(7);
    let mut f = CurveFairing::new(&lp, opts(m)).unwrap();
    assert!(f.whole_loop());
    let got = f.fair(Pass::Full).unwrap();
    let want = fair_closed(&lp, opts(m)).unwrap();
    assert!(same(&got.result.curve, &want.curve));
    assert_eq!(got.result.seam, Seam::Faired);
    assert!(dev_max(&lp, &got.result.curve) <= m);
    // a draft of the loop holds the seam (its first pass alone)
    let draft = f.fair(Pass::Draft).unwrap();
    assert!(matches!(draft.result.seam, Seam::Held(_)), "{:?}", draft.result.seam);
    assert!(dev_max(&lp, &draft.result.curve) <= m);
    // a region across the seam: on the re-seamed curve, rotated back
    let o = (opts(m)).region(Some((0.8, 0.3)));
    let mut f = CurveFairing::new(&lp, o).unwrap();
    assert!(f.across_seam());
    let got = f.fair(Pass::Full).unwrap();
    let (mut s, back) = setup_across_seam(&lp, o).unwrap();
    let want = back.back(s.fair().unwrap()).unwrap();
    assert!(same(&got.result.curve, &want.curve));
    assert_eq!(got.result.curve.domain(), lp.domain());
    // its samples run from u1 to the end, then from the start to u2, all on the original's domain
    let u = f.sample_params();
    assert_eq!(u[0], 0.8);
    assert!((u.last().unwrap() - 0.3).abs() < 1e-12, "{}", u.last().unwrap());
    assert!(u.iter().all(|&x| (0.0..=1.0).contains(&x)));
    let wrap = u.windows(2).filter(|w| w[1] < w[0]).count();
    assert_eq!(wrap, 1, "one step back across the seam");
    // corners: the stretches between them
    let kc = kinked(&open);
    let mut f = CurveFairing::new(&kc, opts(m)).unwrap();
    assert_eq!(f.corners().len(), 1);
    assert_eq!(f.stretches().len(), 2);
    let got = f.fair(Pass::Full).unwrap();
    let want = fair_between_corners(&kc, opts(m), |s| s.fair()).unwrap().unwrap();
    assert!(same(&got.result.curve, &want.result.curve));
    assert_eq!(got.stretches.len(), 2);
    assert_eq!(f.stretch_starts().len(), 1);
    assert_eq!(f.target().len(), f.sample_params().len());
    assert!(dev_max(&kc, &got.result.curve) <= m);
}

/// A draft is the fit without the polish on the same setup, and the full fair after it is the polished
/// one: the draft is what a fresh setup without the polish gives, bit for bit; the full fair after it
/// holds the band, differs from the draft (the polish ran) and has no more curvature extrema (the
/// variation polish starts from the draft's fit among its candidates and ranks by extrema first).
#[test]
fn a_draft_and_the_full_fair_share_one_setup() {
    let m = 2e-3;
    let c = noisy_curve(KNOWN_SHAPES[2], 40, 1e-3, 11);
    let mut f = CurveFairing::new(&c, opts(m)).unwrap();
    let draft = f.fair(Pass::Draft).unwrap();
    let fresh = FairingSetup::new(&c, (opts(m)).polish(false)).unwrap().fair().unwrap();
    assert!(same(&draft.result.curve, &fresh.curve));
    let full = f.fair(Pass::Full).unwrap();
    assert!(full.result.max_deviation <= m && dev_max(&c, &full.result.curve) <= m);
    assert!(!same(&full.result.curve, &draft.result.curve), "the polish ran");
    let ext = |x: &BSplineCurve| fairway::measure::measure(&c, x).n_curv_extrema;
    assert!(
        ext(&full.result.curve) <= ext(&draft.result.curve),
        "{} vs {}",
        ext(&full.result.curve),
        ext(&draft.result.curve)
    );
    // and a second draft is again the unpolished fit
    let again = f.fair(Pass::Draft).unwrap();
    assert!(again.result.max_deviation <= m);
}

#[test]
fn run_options_change_in_place_and_setup_options_prepare_afresh() {
    let m = 3e-3;
    let c = noisy_curve(KNOWN_SHAPES[1], 30, 2e-3, 5);
    let base = (opts(m)).region(Some((0.1, 0.9)));
    let mut f = CurveFairing::new(&c, base).unwrap();
    let n = f.target().len();
    // a hand-edited target and a pin stay through run-option changes
    let mut g = f.target().values().to_vec();
    g[n / 2] += 0.5;
    assert!(f.set_target(Some(&g), &[n / 3]));
    let run = base
        .tolerance(2e-3)
        .polish_method(PolishMethod::LineSearch)
        .polish_iterations(3);
    assert!(!f.set_options(run).unwrap(), "run options: no new setup");
    assert_eq!(f.target().values(), g.as_slice());
    assert!(f.target().pinned()[n / 3]);
    assert_eq!(f.options().tolerance, 2e-3);
    let r = f.fair(Pass::Full).unwrap();
    let mut s = FairingSetup::new(&c, run).unwrap();
    for (k, &v) in g.iter().enumerate() {
        s.target_mut().set(k, v);
    }
    s.target_mut().pin(n / 3);
    assert!(
        same(&r.result.curve, &s.fair().unwrap().curve),
        "same as a fresh setup with that target"
    );
    // back to the automatic target, then a new automatic target method re-smooths it in place
    assert!(f.set_target(None, &[]));
    let auto = f.target().values().to_vec();
    let fresh = |o: FairingOptions| FairingSetup::new(&c, o).unwrap().target().values().to_vec();
    assert_eq!(auto, fresh(run));
    let binomial = run.target(TargetMethod::Binomial);
    assert!(!f.set_options(binomial).unwrap());
    assert_eq!(f.target().values(), fresh(binomial).as_slice());
    // a region, end or mode change prepares afresh
    for o in [binomial.region(Some((0.2, 0.8))), binomial.ends(EndCondition::G1)] {
        let mut f2 = f.clone();
        assert!(f2.set_options(o).unwrap(), "{o:?}");
        assert_eq!(f2.sample_params(), FairingSetup::new(&c, o).unwrap().params());
    }
    // a hand-edited target that does not fit the samples is refused: the automatic one is used
    assert!(!f.set_target(Some(&g[1..]), &[]));
    assert_eq!(f.target().values(), fresh(binomial).as_slice());
    // too much smoothing work is refused with the target's name, nothing changed
    let heavy = binomial.target(TargetMethod::Average).strength(Some(usize::MAX / 4));
    let e = f.set_options(heavy).unwrap_err().to_string();
    assert!(e.contains("average target"), "{e}");
    assert_eq!(f.options().target, TargetMethod::Binomial);
}

#[test]
fn the_iterative_baseline_runs_on_every_route() {
    let m = 3e-3;
    let it = Pass::Iterative(fairway::fair::IterativeOptions {
        max_sweeps: 2,
        max_evals: 20,
    });
    for c in [
        noisy_curve(KNOWN_SHAPES[0], 20, 2e-3, 2),
        noisy_loop(3),
        kinked(&noisy_curve(KNOWN_SHAPES[0], 20, 2e-3, 2)),
    ] {
        let r = CurveFairing::new(&c, opts(m)).unwrap().fair(it).unwrap();
        assert!(dev_max(&c, &r.result.curve) <= m * (1.0 + 1e-9));
        assert!(r.energy_before > 0.0);
    }
}

/// A hand-edited target saved at curve parameters survives other samples: linear in u on each stretch
/// (a jump at the corner), saved on one set of samples, resampled onto the samples of other end
/// conditions it is the same function there (linear interpolation is exact for it), each stretch its
/// own; beyond the saved samples (the G0 end frees more) the automatic target; pins go to the nearest
/// sample; a target of a region covering less than half of the samples is refused.
#[test]
fn a_target_saved_at_parameters_is_resampled_onto_other_samples() {
    let m = 3e-3;
    let kc = kinked(&noisy_curve(KNOWN_SHAPES[0], 30, 2e-3, 4));
    let g2 = (opts(m)).region(Some((0.15, 0.85)));
    let saved = CurveFairing::new(&kc, g2).unwrap();
    assert_eq!(saved.corners().len(), 1);
    let at = saved.sample_params();
    let starts = saved.stretch_starts();
    let stretch_of = |k: usize, starts: &[usize]| starts.iter().filter(|&&s| s <= k).count();
    let g = |u: f64, j: usize| 2.0 * u + 1.0 + 10.0 * j as f64;
    let values: Vec<f64> = at
        .iter()
        .enumerate()
        .map(|(k, &u)| g(u, stretch_of(k, &starts)))
        .collect();
    let pin = at.len() / 3;
    let mut other = CurveFairing::with_ends(&kc, g2, [EndCondition::G1, EndCondition::G0]).unwrap();
    let new = other.sample_params();
    assert_ne!(new, at, "other end conditions, other samples");
    let auto = {
        let mut a = other.clone();
        a.set_target(None, &[]);
        a.target().values().to_vec()
    };
    assert!(other.set_target_at(&at, &values, &[pin]));
    let t = other.target();
    let new_starts = other.stretch_starts();
    let (lo, hi) = (at[0], *at.last().unwrap());
    let mut checked = 0;
    for (k, &u) in new.iter().enumerate() {
        let want = if u < lo || u > hi {
            auto[k]
        } else {
            g(u, stretch_of(k, &new_starts))
        };
        if t.pinned()[k] && k != 0 && k + 1 != new.len() && u != at[pin] {
            continue;
        }
        assert!(
            (t.values()[k] - want).abs() < 1e-9,
            "sample {k} at u = {u}: {} vs {want}",
            t.values()[k]
        );
        checked += 1;
    }
    assert!(checked > new.len() / 2);
    let near = (0..new.len())
        .min_by(|&x, &y| (new[x] - at[pin]).abs().total_cmp(&(new[y] - at[pin]).abs()))
        .unwrap();
    assert!(t.pinned()[near], "the pin moved to the nearest sample");
    assert!(other.fair(Pass::Full).unwrap().result.max_deviation <= m);
    // the same samples: exactly the values
    let mut same_fair = CurveFairing::new(&kc, g2).unwrap();
    assert!(same_fair.set_target_at(&at, &values, &[]));
    assert_eq!(same_fair.target().values(), values.as_slice());
    // a target of a much shorter region does not cover this one: refused, the automatic target used
    let short = CurveFairing::new(&kc, (opts(m)).region(Some((0.45, 0.6)))).unwrap();
    let sat = short.sample_params();
    let sv = vec![1.0; sat.len()];
    let auto = other.clone();
    assert!(!other.set_target_at(&sat, &sv, &[]));
    let mut a2 = auto;
    a2.set_target(None, &[]);
    assert_eq!(other.target().values(), a2.target().values());
}

/// A setup made without the polish builds the polish's rows (curvature variation, extrema probes, the
/// smoother's penalty) only when a fair asks for them: turning the polish on, or the smoother's mode, on
/// such a setup gives what a setup made with them gives, bit for bit — a planar curve, a region with G1
/// ends, and a non-planar 3D curve (its torsion rows).
#[test]
fn the_polish_rows_built_later_give_the_same_fair() {
    let m = 2e-3;
    let planar = noisy_curve(KNOWN_SHAPES[2], 40, 1e-3, 11);
    let helix: Vec<DVec3> = (0..36)
        .map(|i| {
            let t = i as f64 * 0.3;
            DVec3::new(t.cos(), t.sin(), 0.15 * t + 1e-3 * ((i * 7 % 5) as f64 - 2.0))
        })
        .collect();
    let knots = fairway::KnotVector::uniform(3, helix.len()).unwrap();
    let space = BSplineCurve::try_new(3, knots.values().to_vec(), helix, None, 3).unwrap();
    let region = opts(m).region(Some((0.2, 0.8))).ends(EndCondition::G1);
    for (c, o) in [(&planar, opts(m)), (&planar, region), (&space, opts(m))] {
        let eager = FairingSetup::new(c, o).unwrap().fair().unwrap();
        let mut lazy = FairingSetup::new(c, o.polish(false)).unwrap();
        let draft = lazy.fair().unwrap();
        lazy.set_polish(true);
        let later = lazy.fair().unwrap();
        assert!(same(&later.curve, &eager.curve), "the polish on a draft's setup");
        assert!(!same(&later.curve, &draft.curve), "the polish ran");
        let smooth = |polish: bool| {
            let mut s = FairingSetup::new(c, o.polish(polish)).unwrap();
            s.set_mode(fairway::fair::FitMode::Smoothing);
            s.fair().unwrap().curve
        };
        assert!(same(&smooth(false), &smooth(true)), "the smoother on a draft's setup");
    }
}
