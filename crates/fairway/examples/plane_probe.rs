use glam::DVec3;
fn main() {
    for path in std::env::args().skip(1) {
        let doc = fairway::io::load(std::path::Path::new(&path)).unwrap();
        let c = doc.geometry.as_curve().unwrap().clone();
        let (lo, hi) = c.control_bounds();
        let m = 5e-4 * (hi - lo).length();
        let pts = c.points();
        let mean = pts.iter().copied().sum::<DVec3>() / pts.len() as f64;
        let mut a = [[0.0; 3]; 3];
        for p in pts {
            let d = (*p - mean).to_array();
            for i in 0..3 {
                for j in 0..3 {
                    a[i][j] += d[i] * d[j];
                }
            }
        }
        let (vals, vecs) = fairway::linalg::symmetric_eigen3(a);
        let k = (0..3).min_by(|&i, &j| vals[i].total_cmp(&vals[j])).unwrap();
        let n = DVec3::new(vecs[0][k], vecs[1][k], vecs[2][k]);
        let res: Vec<f64> = pts.iter().map(|p| (*p - mean).dot(n)).collect();
        let maxr = res.iter().fold(0.0f64, |x, r| x.max(r.abs()));
        let t0 = (pts[1] - pts[0]).normalize();
        let t1 = (pts[pts.len() - 1] - pts[pts.len() - 2]).normalize();
        println!(
            "{path}: n={} m={m:.3e} max plane residual {maxr:.3e} = {:.2} m; end tangents out of plane {:.3}° {:.3}°",
            pts.len(),
            maxr / m,
            t0.dot(n).asin().to_degrees(),
            t1.dot(n).asin().to_degrees()
        );
        println!(
            "  residuals/m: {}",
            res.iter()
                .map(|r| format!("{:.2}", r / m))
                .collect::<Vec<_>>()
                .join(" ")
        );
    }
}
