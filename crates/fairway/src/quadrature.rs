//! Gauss–Legendre quadrature nodes and weights on [−1, 1].
//!
//! Nodes are the roots of the Legendre polynomial P_n, found by Newton's
//! method from Chebyshev guesses (Numerical Recipes, §4.5 `gauleg`); weights
//! `2 / ((1 − x²) P_n'(x)²)`. Accurate to a few ulps for n ≤ 64.

use std::sync::OnceLock;

/// Nodes and weights of an n-point Gauss–Legendre rule on [−1, 1].
#[derive(Debug, Clone)]
pub struct GaussLegendre {
    /// Nodes, ascending.
    pub nodes: Vec<f64>,
    /// Weights, matching `nodes`.
    pub weights: Vec<f64>,
}

impl GaussLegendre {
    /// Compute the n-point rule (n ≥ 1).
    pub fn new(n: usize) -> Self {
        assert!(n >= 1, "Gauss–Legendre needs at least one node");
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        let m = n.div_ceil(2);
        for i in 0..m {
            let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut pp = 0.0;
            for _ in 0..100 {
                let (mut p1, mut p2) = (1.0, 0.0);
                for j in 0..n {
                    let p3 = p2;
                    p2 = p1;
                    p1 = ((2 * j + 1) as f64 * z * p2 - j as f64 * p3) / (j + 1) as f64;
                }
                pp = n as f64 * (z * p1 - p2) / (z * z - 1.0);
                let z1 = z;
                z = z1 - p1 / pp;
                if (z - z1).abs() < 1e-16 {
                    break;
                }
            }
            nodes[i] = -z;
            nodes[n - 1 - i] = z;
            let w = 2.0 / ((1.0 - z * z) * pp * pp);
            weights[i] = w;
            weights[n - 1 - i] = w;
        }
        if n % 2 == 1 {
            nodes[n / 2] = 0.0;
        }
        Self { nodes, weights }
    }

    /// Integrate `f` over `[a, b]`.
    #[inline]
    pub fn integrate(&self, a: f64, b: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
        let h = 0.5 * (b - a);
        let c = 0.5 * (a + b);
        let mut s = 0.0;
        for (x, w) in self.nodes.iter().zip(&self.weights) {
            s += w * f(c + h * x);
        }
        s * h
    }
}

/// The shared 5-point rule (exact for polynomials of degree ≤ 9).
pub fn gl5() -> &'static GaussLegendre {
    static R: OnceLock<GaussLegendre> = OnceLock::new();
    R.get_or_init(|| GaussLegendre::new(5))
}

/// The shared 10-point rule (exact for polynomials of degree ≤ 19).
pub fn gl10() -> &'static GaussLegendre {
    static R: OnceLock<GaussLegendre> = OnceLock::new();
    R.get_or_init(|| GaussLegendre::new(10))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_for_polynomials() {
        for n in 1..12 {
            let g = GaussLegendre::new(n);
            for deg in 0..2 * n {
                let exact = (2f64.powi(deg as i32 + 1) - 0.0) / (deg as f64 + 1.0); // ∫_0^2 x^deg
                let got = g.integrate(0.0, 2.0, |x| x.powi(deg as i32));
                assert!(
                    (got - exact).abs() < 1e-12 * exact.max(1.0),
                    "n={n} deg={deg}: {got} vs {exact}"
                );
            }
        }
        let g = gl10();
        assert!((g.nodes[9] - 0.973_906_528_517_171_7).abs() < 1e-15);
        assert!((g.weights[9] - 0.066_671_344_308_688_1).abs() < 1e-15);
    }
}
