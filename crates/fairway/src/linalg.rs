//! Banded symmetric positive definite systems — the one place Fairway
//! solves linear systems, so the backend can be swapped.
//!
//! B-spline least squares has normal equations `AᵀA` whose bandwidth is
//! the degree p (basis functions overlap only when `|i − j| ≤ p`), so a
//! banded Cholesky factorization `LLᵀ` costs O(n p²) and the solve O(n p)
//! (Golub & Van Loan, §4.3.5). Storage: row `i` holds `A[i][i−k]` at
//! offset `k`, `k = 0..=bw`.

use glam::DVec3;

use crate::error::{Error, Result};

/// A symmetric banded matrix (lower band stored), factorized in place.
#[derive(Debug, Clone, Default)]
pub struct BandedSpd {
    n: usize,
    bw: usize,
    data: Vec<f64>,
    factored: bool,
}

impl BandedSpd {
    /// An `n × n` zero matrix of half-bandwidth `bw`.
    pub fn zeros(n: usize, bw: usize) -> Self {
        Self {
            n,
            bw,
            data: vec![0.0; n * (bw + 1)],
            factored: false,
        }
    }

    /// Reset to an `n × n` zero matrix of bandwidth `bw`, reusing the allocation.
    pub fn reset(&mut self, n: usize, bw: usize) {
        self.n = n;
        self.bw = bw;
        self.data.clear();
        self.data.resize(n * (bw + 1), 0.0);
        self.factored = false;
    }

    /// Size.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Half-bandwidth.
    pub fn bandwidth(&self) -> usize {
        self.bw
    }

    /// `A[i][j]` (0 outside the band).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        if i - j > self.bw {
            0.0
        } else {
            self.data[i * (self.bw + 1) + (i - j)]
        }
    }

    /// `A[i][j] += v` (and the symmetric entry). Panics outside the band.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        assert!(i - j <= self.bw, "entry ({i}, {j}) outside the band {}", self.bw);
        self.data[i * (self.bw + 1) + (i - j)] += v;
    }

    /// `A[base + a][base + b] += v[a] v[b]` for all a, b < `v.len()` (a rank-1 update on a diagonal
    /// block, e.g. one row of a Jacobian into `JᵀJ`). Panics if the block leaves the band or the matrix.
    #[inline]
    pub fn add_outer(&mut self, base: usize, v: &[f64]) {
        let w = self.bw + 1;
        assert!(
            v.len() <= w && base + v.len() <= self.n,
            "block outside the band or the matrix"
        );
        for (a, &va) in v.iter().enumerate() {
            if va == 0.0 {
                continue;
            }
            // row base + a holds A[i][i − k] at offset k: entries b = a, a − 1, …, 0 are offsets 0..=a
            let row = &mut self.data[(base + a) * w..(base + a) * w + a + 1];
            for (k, x) in row.iter_mut().enumerate() {
                *x += va * v[a - k];
            }
        }
    }

    /// [`Self::add_outer`] with the block width known at compile time (the polish's Jacobian rows).
    #[inline]
    pub fn add_outer_fixed<const W: usize>(&mut self, base: usize, v: &[f64; W]) {
        let w = self.bw + 1;
        assert!(W <= w && base + W <= self.n, "block outside the band or the matrix");
        let data = &mut self.data[base * w..(base + W) * w];
        for a in 0..W {
            let va = v[a];
            if va == 0.0 {
                continue;
            }
            let row = &mut data[a * w..a * w + a + 1];
            for (k, x) in row.iter_mut().enumerate() {
                *x += va * v[a - k];
            }
        }
    }

    /// Cholesky factorization in place. Fails, naming the row, if the matrix
    /// is not positive definite (to working precision).
    pub fn factor(&mut self) -> Result<()> {
        let (n, bw) = (self.n, self.bw);
        let w = bw + 1;
        let scale = (0..n).map(|i| self.data[i * w].abs()).fold(0.0, f64::max);
        for i in 0..n {
            let j0 = i.saturating_sub(bw);
            for j in j0..=i {
                let mut s = self.data[i * w + (i - j)];
                let k0 = j0.max(j.saturating_sub(bw));
                for k in k0..j {
                    s -= self.data[i * w + (i - k)] * self.data[j * w + (j - k)];
                }
                if i == j {
                    if !(s > 1e-14 * scale) || !s.is_finite() {
                        return Err(Error::Solve(format!(
                            "matrix not positive definite at row {i} (pivot {s:e})"
                        )));
                    }
                    self.data[i * w] = s.sqrt();
                } else {
                    self.data[i * w + (i - j)] = s / self.data[j * w];
                }
            }
        }
        self.factored = true;
        Ok(())
    }

    /// Solve `A x = b` in place for vector right-hand sides (after [`Self::factor`]).
    pub fn solve_in_place(&self, b: &mut [DVec3]) {
        assert!(self.factored, "factor() first");
        let (n, bw) = (self.n, self.bw);
        let w = bw + 1;
        for i in 0..n {
            let mut s = b[i];
            for k in i.saturating_sub(bw)..i {
                s -= b[k] * self.data[i * w + (i - k)];
            }
            b[i] = s / self.data[i * w];
        }
        for i in (0..n).rev() {
            let mut s = b[i];
            for k in i + 1..(i + bw + 1).min(n) {
                s -= b[k] * self.data[k * w + (k - i)];
            }
            b[i] = s / self.data[i * w];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn add_outer_matches_entrywise_adds() {
        let v = [0.5, -1.25, 0.0, 2.0];
        let (mut a, mut b) = (BandedSpd::zeros(9, 4), BandedSpd::zeros(9, 4));
        a.add_outer(3, &v);
        a.add_outer(5, &v[..3]);
        for (base, len) in [(3, 4), (5, 3)] {
            for x in 0..len {
                for y in 0..=x {
                    b.add(base + x, base + y, v[x] * v[y]);
                }
            }
        }
        for i in 0..9 {
            for j in 0..9 {
                assert_eq!(a.get(i, j), b.get(i, j), "({i}, {j})");
            }
        }
        // the fixed-width form adds the same entries, bit for bit
        let mut c = BandedSpd::zeros(9, 4);
        c.add_outer_fixed(3, &v);
        c.add_outer_fixed(5, &[v[0], v[1], v[2]]);
        for i in 0..9 {
            for j in 0..9 {
                assert_eq!(a.get(i, j).to_bits(), c.get(i, j).to_bits(), "({i}, {j})");
            }
        }
    }

    #[test]
    fn solves_a_tridiagonal_system() {
        let n = 50;
        let mut a = BandedSpd::zeros(n, 1);
        for i in 0..n {
            a.add(i, i, 4.0);
            if i > 0 {
                a.add(i, i - 1, -1.0);
            }
        }
        let x: Vec<DVec3> = (0..n)
            .map(|i| DVec3::new(i as f64, (i * i) as f64 * 0.1, 1.0))
            .collect();
        let mut b: Vec<DVec3> = (0..n)
            .map(|i| {
                let mut s = x[i] * 4.0;
                if i > 0 {
                    s -= x[i - 1];
                }
                if i + 1 < n {
                    s -= x[i + 1];
                }
                s
            })
            .collect();
        a.factor().unwrap();
        a.solve_in_place(&mut b);
        for i in 0..n {
            assert!((b[i] - x[i]).length() < 1e-12, "{i}");
        }
    }

    #[test]
    fn rejects_indefinite() {
        let mut a = BandedSpd::zeros(2, 1);
        a.add(0, 0, 1.0);
        a.add(1, 0, 2.0);
        a.add(1, 1, 1.0);
        assert!(a.factor().is_err());
    }
}
