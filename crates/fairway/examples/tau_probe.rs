use fairway::fair::{FairingOptions, FitMode, fair_curve};
use fairway::measure::{arc_params, measure};
fn main() {
    let doc = fairway::io::load(std::path::Path::new("/tmp/c3959.json")).unwrap();
    let c = doc.geometry.as_curve().unwrap().clone();
    let (lo, hi) = c.control_bounds();
    let m = 5e-4 * (hi - lo).length();
    let w: f64 = std::env::var("W").map_or(1.0, |v| v.parse().unwrap());
    let opts = FairingOptions::default().tolerance(m).torsion_weight(w);
    let r = fair_curve(&c, opts.mode(FitMode::Smoothing)).unwrap().curve;
    let fr = fair_curve(&c, opts).unwrap();
    eprintln!("fw notes {:?} energy {} mu {}", fr.notes, fr.energy, fr.mu);
    let f = fr.curve;
    let np = fair_curve(&c, opts.polish(false)).unwrap().curve;
    let t0 = fair_curve(&c, opts.torsion_weight(0.0)).unwrap().curve;
    for (name, x) in [("orig", &c), ("ref", &r), ("fw", &f), ("nopolish", &np), ("tw0", &t0)] {
        let ms = measure(&c, x);
        let us = arc_params(x, 41);
        let tau: Vec<String> = us.iter().map(|&u| format!("{:.2}", x.derivs(u).torsion())).collect();
        let kap: Vec<String> = us.iter().map(|&u| format!("{:.3}", x.derivs(u).curvature(3))).collect();
        println!(
            "{name}: τext {:?} κext {} E_var {:.3e}\n  τ {}\n  κ {}",
            ms.n_torsion_extrema,
            ms.n_curv_extrema,
            ms.E_var,
            tau.join(" "),
            kap.join(" ")
        );
    }
}
