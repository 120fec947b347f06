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

    /// `A[base + aD + r][base + bD + q] += b[a] b[b] m[r][q]` for every pair on or below the diagonal:
    /// the Kronecker product `(b bᵀ) ⊗ m` (`m` symmetric, `D × D`) as a diagonal block of width `N·D`
    /// (e.g. one band constraint's Hessian in the polish: basis row `b` over the points, `m` over the
    /// coordinates). Panics if the block leaves the band or the matrix.
    #[inline]
    pub fn add_kron_fixed<const N: usize, const D: usize>(&mut self, base: usize, b: &[f64; N], m: &[[f64; D]; D]) {
        let w = self.bw + 1;
        assert!(
            N * D <= w && base + N * D <= self.n,
            "block outside the band or the matrix"
        );
        let data = &mut self.data[base * w..(base + N * D) * w];
        for a in 0..N {
            for r in 0..D {
                let row = a * D + r;
                let line = &mut data[row * w..row * w + row + 1];
                for bb in 0..=a {
                    let ab = b[a] * b[bb];
                    let qmax = if bb == a { r + 1 } else { D };
                    for q in 0..qmax {
                        line[row - (bb * D + q)] += ab * m[r][q];
                    }
                }
            }
        }
    }

    /// Cholesky factorization in place. Fails, naming the row, if the matrix
    /// is not positive definite (to working precision).
    pub fn factor(&mut self) -> Result<()> {
        // the common bandwidths (cubic fits: 3; the polish's 2D and 3D Gauss–Newton systems: 7 and 11)
        // take a path with the row width known at compile time: the same operations in the same order
        // (bit-identical), without the index arithmetic and bounds checks of the general loop
        match self.bw {
            3 => self.factor_rows::<4>(),
            7 => self.factor_rows::<8>(),
            11 => self.factor_rows::<12>(),
            // wide bands (the surface smoother's 2D systems): rows four at a time
            bw if bw >= BLOCK_MIN_BW => self.factor_blocked(),
            _ => self.factor_rows::<0>(),
        }
    }

    /// Cholesky factorization with the rows below the first `bw` taken four at a time: their entries left
    /// of the block's diagonal need only earlier rows, so the four rows' sums run interleaved (four
    /// independent chains instead of one chain bound by the latency of each subtraction). Every entry is
    /// the general loop's sum, term for term in the same order (bit-identical), and the pivots are checked
    /// row by row in order, so a failure names the same row and pivot.
    fn factor_blocked(&mut self) -> Result<()> {
        let (n, bw) = (self.n, self.bw);
        let w = bw + 1;
        let scale = (0..n).map(|i| self.data[i * w].abs()).fold(0.0, f64::max);
        let head = bw.min(n);
        for i in 0..head {
            self.factor_row_general(i, scale)?;
        }
        let mut i = head;
        while i + 4 <= n {
            // rows i + r, r < 4: first column j0 + r (j0 = i − bw); columns j < i from earlier rows only
            let j0 = i - bw;
            let (before, rest) = self.data.split_at_mut(i * w);
            let rows = &mut rest[..4 * w];
            for j in j0..i {
                let pj = &before[j * w..(j + 1) * w];
                // rows r ≤ j − j0 have column j
                let active = (j - j0 + 1).min(4);
                let mut s = [0.0f64; 4];
                // each row's terms k = j0 + r .. j0 + active − 1 (the first of its sum) by itself
                let common = j0 + active - 1;
                for (r, sr) in s.iter_mut().enumerate().take(active) {
                    let row = &rows[r * w..(r + 1) * w];
                    let ir = i + r;
                    *sr = row[ir - j];
                    for k in j0 + r..common {
                        *sr -= row[ir - k] * pj[j - k];
                    }
                }
                // then k = common .. j − 1 for every active row, interleaved; offsets fall as k rises
                let m = j - common;
                if active == 4 {
                    let p = pj[1..=m].iter().rev();
                    let r0 = rows[i - j + 1..=i - common].iter().rev();
                    let r1 = rows[w + i + 1 - j + 1..=w + i + 1 - common].iter().rev();
                    let r2 = rows[2 * w + i + 2 - j + 1..=2 * w + i + 2 - common].iter().rev();
                    let r3 = rows[3 * w + i + 3 - j + 1..=3 * w + i + 3 - common].iter().rev();
                    let [mut s0, mut s1, mut s2, mut s3] = s;
                    for ((((&pk, &a0), &a1), &a2), &a3) in p.zip(r0).zip(r1).zip(r2).zip(r3) {
                        s0 -= a0 * pk;
                        s1 -= a1 * pk;
                        s2 -= a2 * pk;
                        s3 -= a3 * pk;
                    }
                    s = [s0, s1, s2, s3];
                } else {
                    for (r, sr) in s.iter_mut().enumerate().take(active) {
                        let ir = i + r;
                        for k in common..j {
                            *sr -= rows[r * w + ir - k] * pj[j - k];
                        }
                    }
                }
                for (r, &sr) in s.iter().enumerate().take(active) {
                    rows[r * w + i + r - j] = sr / pj[0];
                }
            }
            // columns i .. i + r of each row (within the block), row by row
            for r in 0..4 {
                self.factor_row_from(i + r, i, scale)?;
            }
            i += 4;
        }
        for i in i..n {
            self.factor_row_general(i, scale)?;
        }
        self.factored = true;
        Ok(())
    }

    /// Columns `from..=i` of row `i` of the factorization by the general loop (the earlier columns done).
    fn factor_row_from(&mut self, i: usize, from: usize, scale: f64) -> Result<()> {
        let bw = self.bw;
        let w = bw + 1;
        let j0 = i.saturating_sub(bw);
        for j in from.max(j0)..=i {
            let mut s = self.data[i * w + (i - j)];
            let k0 = j0.max(j.saturating_sub(bw));
            for k in k0..j {
                s -= self.data[i * w + (i - k)] * self.data[j * w + (j - k)];
            }
            if i == j {
                self.data[i * w] = pivot_root(s, scale, i)?;
            } else {
                self.data[i * w + (i - j)] = s / self.data[j * w];
            }
        }
        Ok(())
    }

    /// Row `i` of the factorization by the general loop.
    fn factor_row_general(&mut self, i: usize, scale: f64) -> Result<()> {
        self.factor_row_from(i, 0, scale)
    }

    /// Cholesky factorization with row width `W = bw + 1` (`W = 0`: any width, general loop).
    fn factor_rows<const W: usize>(&mut self) -> Result<()> {
        let (n, bw) = (self.n, self.bw);
        let w = bw + 1;
        let scale = (0..n).map(|i| self.data[i * w].abs()).fold(0.0, f64::max);
        let head = if W == 0 { n } else { bw.min(n) };
        for i in 0..head {
            self.factor_row_general(i, scale)?;
        }
        if W == 0 {
            self.factored = true;
            return Ok(());
        }
        debug_assert_eq!(W, w);
        // rows i ≥ bw: the band is full, the row's columns are j = i − bw + jj (jj = 0..W) and the sum
        // over k runs from i − bw to j − 1 (t = k − (i − bw) = 0..jj), as in the general loop
        for i in bw..n {
            let (before, rest) = self.data.split_at_mut(i * W);
            let prev: &[f64] = &before[(i - bw) * W..];
            let row: &mut [f64; W] = (&mut rest[..W]).try_into().expect("row of width W");
            for jj in 0..W - 1 {
                let pj: &[f64; W] = prev[jj * W..(jj + 1) * W].try_into().expect("row of width W");
                let mut s = row[bw - jj];
                for t in 0..jj {
                    s -= row[bw - t] * pj[jj - t];
                }
                row[bw - jj] = s / pj[0];
            }
            let mut s = row[0];
            for t in 0..bw {
                s -= row[bw - t] * row[bw - t];
            }
            row[0] = pivot_root(s, scale, i)?;
        }
        self.factored = true;
        Ok(())
    }

    /// Solve `A x = b` in place for vector right-hand sides (after [`Self::factor`]).
    pub fn solve_in_place(&self, b: &mut [DVec3]) {
        assert!(self.factored, "factor() first");
        assert!(b.len() >= self.n, "right-hand side shorter than the matrix");
        match self.bw {
            3 => self.solve_rows::<4>(b),
            7 => self.solve_rows::<8>(b),
            11 => self.solve_rows::<12>(b),
            _ => self.solve_rows::<0>(b),
        }
    }

    /// Forward and back substitution with row width `W = bw + 1` (`W = 0`: general loop); the same
    /// operations in the same order on every path.
    fn solve_rows<const W: usize>(&self, b: &mut [DVec3]) {
        let (n, bw) = (self.n, self.bw);
        let w = bw + 1;
        let fixed = W != 0 && n > bw;
        // forward: rows below bw (all rows on the general path) by the general loop
        let head = if fixed { bw } else { n };
        for i in 0..head {
            let mut s = b[i];
            for k in i.saturating_sub(bw)..i {
                s -= b[k] * self.data[i * w + (i - k)];
            }
            b[i] = s / self.data[i * w];
        }
        if fixed {
            for i in bw..n {
                let row: &[f64; W] = self.data[i * W..(i + 1) * W].try_into().expect("row of width W");
                let (before, rest) = b.split_at_mut(i);
                let prev = &before[i - bw..];
                let mut s = rest[0];
                for t in 0..W - 1 {
                    // k = i − bw + t, offset i − k = bw − t
                    s -= prev[t] * row[bw - t];
                }
                rest[0] = s / row[0];
            }
        }
        // back: rows with a full band below them (i + bw < n) on the fixed path, the last bw rows general
        let tail = if fixed { n - bw } else { 0 };
        for i in (tail..n).rev() {
            let mut s = b[i];
            for k in i + 1..(i + bw + 1).min(n) {
                s -= b[k] * self.data[k * w + (k - i)];
            }
            b[i] = s / self.data[i * w];
        }
        if fixed {
            for i in (0..tail).rev() {
                let (head_b, rest) = b.split_at_mut(i + 1);
                let next = &rest[..bw];
                let block = &self.data[(i + 1) * W..(i + 1 + bw) * W];
                let mut s = head_b[i];
                for t in 0..W - 1 {
                    // k = i + 1 + t, offset k − i = t + 1
                    s -= next[t] * block[t * W + t + 1];
                }
                head_b[i] = s / self.data[i * W];
            }
        }
    }
}

/// The diagonal of the Cholesky factor: the root of a pivot, or an error naming the row when the
/// matrix is not positive definite (to working precision).
/// Half-bandwidths from which [`BandedSpd::factor`] takes rows four at a time.
const BLOCK_MIN_BW: usize = 8;

fn pivot_root(s: f64, scale: f64, i: usize) -> Result<f64> {
    if !(s > 1e-14 * scale) || !s.is_finite() {
        return Err(Error::Solve(format!(
            "matrix not positive definite at row {i} (pivot {s:e})"
        )));
    }
    Ok(s.sqrt())
}

/// Eigenvalues and eigenvectors (the columns) of a symmetric 3×3 matrix, by cyclic Jacobi rotations.
pub fn symmetric_eigen3(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..50 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let scale = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= 1e-15 * scale.max(1e-300) {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() < 1e-300 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let (c, s) = (1.0 / (t * t + 1.0).sqrt(), t / (t * t + 1.0).sqrt());
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocked_factor_is_the_general_loop_bit_for_bit() {
        // wide bands (rows four at a time) against the general loop, on matrices with every band entry
        // set (diagonally dominant), sizes not a multiple of 4 and smaller than the band
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for (n, bw) in [(50, 9), (61, 13), (10, 12), (37, 36), (200, 27), (5, 8)] {
            let mut a = BandedSpd::zeros(n, bw);
            for i in 0..n {
                for j in i.saturating_sub(bw)..i {
                    a.add(i, j, rnd());
                }
                a.add(i, i, 2.0 * bw as f64 + 1.0 + rnd());
            }
            let mut general = a.clone();
            general.factor_rows::<0>().unwrap();
            a.factor().unwrap();
            assert!(a.factored);
            for (x, y) in a.data.iter().zip(&general.data) {
                assert_eq!(x.to_bits(), y.to_bits(), "n {n} bw {bw}");
            }
            let b: Vec<DVec3> = (0..n).map(|_| DVec3::new(rnd(), rnd(), rnd())).collect();
            let (mut x, mut y) = (b.clone(), b);
            a.solve_in_place(&mut x);
            general.solve_in_place(&mut y);
            assert_eq!(x, y);
        }
        // an indefinite matrix fails at the same row with the same pivot
        let mut a = BandedSpd::zeros(40, 10);
        for i in 0..40 {
            a.add(i, i, if i == 29 { -1.0 } else { 1.0 });
        }
        let mut general = a.clone();
        let e = a.factor().unwrap_err().to_string();
        assert_eq!(e, general.factor_rows::<0>().unwrap_err().to_string());
        assert!(e.contains("row 29"), "{e}");
    }

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
    fn add_kron_matches_the_dense_kronecker_product() {
        // (b bᵀ) ⊗ m for 4 basis values and a symmetric 2 × 2 m, at base 2 of a 12 × 12 matrix of
        // half-bandwidth 7, against the entries of the dense product added one by one
        let b = [0.125, 0.5, -0.75, 2.0];
        let m = [[3.0, -0.5], [-0.5, 1.5]];
        let (mut a, mut e) = (BandedSpd::zeros(12, 7), BandedSpd::zeros(12, 7));
        a.add_kron_fixed::<4, 2>(2, &b, &m);
        for x in 0..8 {
            for y in 0..=x {
                e.add(2 + x, 2 + y, b[x / 2] * b[y / 2] * m[x % 2][y % 2]);
            }
        }
        for i in 0..12 {
            for j in 0..12 {
                let (u, v) = (a.get(i, j), e.get(i, j));
                assert!((u - v).abs() <= 1e-15 * v.abs(), "({i}, {j}): {u} vs {v}");
            }
        }
        assert!(a.get(1, 2) == 0.0 && a.get(10, 9) == 0.0 && a.get(3, 3) != 0.0);
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

    /// A banded SPD matrix from random rank-1 rows of width bw + 1 (like the engine's normal
    /// equations) plus a small diagonal.
    fn random_band(n: usize, bw: usize, seed: u64) -> BandedSpd {
        let mut state = seed;
        let mut rnd = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut a = BandedSpd::zeros(n, bw);
        for base in 0..n {
            let width = (bw + 1).min(n - base);
            for _ in 0..2 {
                let v: Vec<f64> = (0..width).map(|_| rnd()).collect();
                a.add_outer(base, &v);
            }
            a.add(base, base, 1e-3);
        }
        a
    }

    #[test]
    fn fixed_width_paths_are_the_general_loop_bit_for_bit() {
        // the dispatched paths (bw 3, 7, 11) against the general loop, on sizes below, at and above the
        // bandwidth; and the solution really solves the system
        for bw in [3, 7, 11] {
            for n in [1, bw - 1, bw, bw + 1, bw + 2, 3 * bw + 5, 200] {
                let a = random_band(n, bw, (n * 31 + bw) as u64);
                let (mut fast, mut general) = (a.clone(), a.clone());
                fast.factor().unwrap();
                general.factor_rows::<0>().unwrap();
                assert!(
                    fast.data
                        .iter()
                        .zip(&general.data)
                        .all(|(x, y)| x.to_bits() == y.to_bits()),
                    "factor differs, bw {bw}, n {n}"
                );
                let x: Vec<DVec3> = (0..n)
                    .map(|i| DVec3::new(i as f64 * 0.3 - 1.0, (i % 7) as f64, 2.0 - (i % 3) as f64))
                    .collect();
                // b = A x from the unfactored matrix
                let b: Vec<DVec3> = (0..n)
                    .map(|i| {
                        let lo = i.saturating_sub(bw);
                        let hi = (i + bw + 1).min(n);
                        (lo..hi).fold(DVec3::ZERO, |s, j| s + x[j] * a.get(i, j))
                    })
                    .collect();
                let (mut y1, mut y2) = (b.clone(), b.clone());
                fast.solve_in_place(&mut y1);
                general.solve_rows::<0>(&mut y2);
                for i in 0..n {
                    assert_eq!(
                        y1[i].to_array().map(f64::to_bits),
                        y2[i].to_array().map(f64::to_bits),
                        "bw {bw}, n {n}, row {i}"
                    );
                    assert!(
                        (y1[i] - x[i]).length() < 1e-8 * (1.0 + x[i].length()),
                        "bw {bw}, n {n}, row {i}: {} vs {}",
                        y1[i],
                        x[i]
                    );
                }
            }
        }
    }

    #[test]
    fn fixed_width_path_names_the_failing_row() {
        // an indefinite pivot past the first bw rows is reported with its row on the fixed path too
        let mut a = random_band(40, 7, 5);
        a.add(30, 30, -1e6);
        let err = a.factor().unwrap_err().to_string();
        assert!(err.contains("row 30"), "{err}");
    }

    #[test]
    fn eigen_of_a_diagonal_and_a_rotated_matrix() {
        let (vals, _) = symmetric_eigen3([[3.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.0]]);
        assert_eq!(vals, [3.0, 1.0, 2.0]);
        let (vals, v) = symmetric_eigen3([[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 5.0]]);
        let mut s = vals;
        s.sort_by(f64::total_cmp);
        assert!((s[0] - 1.0).abs() < 1e-12 && (s[1] - 3.0).abs() < 1e-12 && (s[2] - 5.0).abs() < 1e-12);
        let k = vals.iter().position(|&x| (x - 1.0).abs() < 1e-9).unwrap();
        let e = glam::DVec3::new(v[0][k], v[1][k], v[2][k]);
        assert!((e.x + e.y).abs() < 1e-12 && e.z.abs() < 1e-12, "{e}");
    }
}
