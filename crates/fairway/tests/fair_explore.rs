mod common;
use common::*;
use fairway::fair::*;

#[test]
#[ignore]
fn explore() {
    for shape in KNOWN_SHAPES {
        let c = noisy_curve(shape, 40, 1e-3, 7);
        let (r0, m0) = curvature_error(&c, shape);
        println!(
            "{shape:?}: before rms {r0:.4} max {m0:.4} extrema {}",
            extrema(&c, 0.01)
        );
        {
            let setup = FairingSetup::new(&c, FairingOptions::default().tolerance(1e-3)).unwrap();
            let g = setup.target().values();
            let n = g.len();
            let (_, kt) = shape.dense(n);
            let e: Vec<f64> = (n / 20..n - n / 20).map(|k| g[k] - kt[k]).collect();
            let rms = (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt();
            let orig = setup.target().original();
            let e0: Vec<f64> = (n / 20..n - n / 20).map(|k| orig[k] - kt[k]).collect();
            let rms0 = (e0.iter().map(|x| x * x).sum::<f64>() / e0.len() as f64).sqrt();
            for k in (0..n).step_by(n / 12) {
                println!("   k {k}: g {:.3} orig {:.3} truth {:.3}", g[k], orig[k], kt[k]);
            }
            println!("target err rms {rms:.4} (orig {rms0:.4}) n {n}");
            for tol in [1e-3, 1e-2] {
                let mut s2 = setup.clone();
                s2.set_tolerance(tol).unwrap();
                let r = s2.fair().unwrap();
                let y = s2.integrated_points();
                let (pt, _) = shape.dense(n);
                let dy = y.iter().zip(&pt).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
                let k: Vec<f64> = s2.params().iter().map(|&u| r.curve.curvature(u)).collect();
                let ek = (n / 20..n - n / 20).map(|i| (k[i] - g[i]).powi(2)).sum::<f64>() / (0.9 * n as f64);
                println!(
                    "  tol {tol}: integrated pts max dist to truth {dy:.2e}; result kappa vs target rms {:.4}",
                    ek.sqrt()
                );
            }
        }
        for mode in [FitMode::Paper, FitMode::Fairway] {
            for integ in [Integrator::Euler, Integrator::Arc] {
                for tol in [1e-3, 3e-3, 1e-2] {
                    let opts = FairingOptions::default().tolerance(tol).mode(mode).integrator(integ);
                    let t = std::time::Instant::now();
                    let r = fair_curve(&c, opts).unwrap();
                    let el = t.elapsed();
                    let (r1, m1) = curvature_error(&r.curve, shape);
                    println!(
                        "  {mode:?} {integ:?} tol {tol}: rms {r1:.4} max {m1:.4} extrema {} dev {:.2e} mu {:.1e} alpha {:.3} E {:.3e} {:?}",
                        extrema(&r.curve, 0.01),
                        r.max_deviation,
                        r.mu,
                        r.alpha,
                        r.energy,
                        el
                    );
                }
            }
        }
    }
}
