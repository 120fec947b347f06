use fairway::fair::FairingSetup;
#[path = "../benches/common/mod.rs"]
mod common;
use common::{noisy_curve, opts};
fn main() {
    for n in [100usize, 1000] {
        let cv = noisy_curve(n);
        let r = FairingSetup::new(&cv, opts(10 * n)).unwrap().fair().unwrap();
        let m = fairway::measure::measure(&cv, &r.curve);
        let m0 = fairway::measure::measure(&cv, &cv);
        println!(
            "{n} cps: dev_max {:.6e} bound {:.6e} extrema {} (orig {}) E_var {:.6e} (orig {:.6e}) E {:.6e} solves {}",
            m.dev_max, r.max_deviation, m.n_curv_extrema, m0.n_curv_extrema, m.E_var, m0.E_var, r.energy, r.solves
        );
    }
}
