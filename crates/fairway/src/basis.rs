//! B-spline basis functions and their derivatives, allocation free.
//!
//! The NURBS Book (Piegl & Tiller, 2nd ed.), algorithms A2.2 (`basis_funs`)
//! and A2.3 (`ders_basis_funs`). Buffers are fixed-size stack arrays sized by
//! [`crate::knots::MAX_DEGREE`].

use crate::knots::MAX_DEGREE;

/// Order bound used for stack buffers: `MAX_DEGREE + 1`.
pub const MAX_ORDER: usize = MAX_DEGREE + 1;

/// Non-zero basis values `N_{span−p+j, p}(u)`, `j = 0..=p`, written to `out[..=p]`
/// (A2.2). `span` must come from [`find_span`](crate::knots::find_span).
#[inline]
pub fn basis_funs(knots: &[f64], span: usize, u: f64, p: usize, out: &mut [f64]) {
    let mut left = [0.0; MAX_ORDER];
    let mut right = [0.0; MAX_ORDER];
    out[0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            let temp = out[r] / (right[r + 1] + left[j - r]);
            out[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        out[j] = saved;
    }
}

/// Basis values and derivatives up to order `nd` (A2.3):
/// `ders[k][j] = d^k/du^k N_{span−p+j, p}(u)` for `k = 0..=nd`, `j = 0..=p`.
/// Derivatives above the degree are zero.
#[inline]
pub fn ders_basis_funs<const D: usize>(knots: &[f64], span: usize, u: f64, p: usize, ders: &mut [[f64; MAX_ORDER]; D]) {
    // The triangular work table is sized for the degree at hand: zeroing a
    // MAX_ORDER² table (2 KiB) on every call cost more than the algorithm
    // itself for cubics.
    if p < 4 {
        ders_impl::<D, 4>(knots, span, u, p, ders)
    } else if p < 8 {
        ders_impl::<D, 8>(knots, span, u, p, ders)
    } else {
        ders_impl::<D, MAX_ORDER>(knots, span, u, p, ders)
    }
}

#[inline(always)]
fn ders_impl<const D: usize, const N: usize>(
    knots: &[f64],
    span: usize,
    u: f64,
    p: usize,
    ders: &mut [[f64; MAX_ORDER]; D],
) {
    let nd = D - 1;
    let mut ndu = [[0.0; N]; N];
    let mut left = [0.0; N];
    let mut right = [0.0; N];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            // lower triangle: knot differences
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            // upper triangle: basis values
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    for row in ders.iter_mut() {
        row[..=p].fill(0.0);
    }
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
    }
    let mut a = [[0.0; N]; 2];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0][0] = 1.0;
        for k in 1..=nd.min(p) {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if r >= k {
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk as usize];
                d = a[s2][0] * ndu[rk as usize][pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if r as isize - 1 <= pk as isize { k - 1 } else { p - r };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                d += a[s2][j] * ndu[idx][pk];
            }
            if r <= pk {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut fac = p as f64;
    for k in 1..=nd.min(p) {
        for j in 0..=p {
            ders[k][j] *= fac;
        }
        fac *= (p - k) as f64;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::knots::find_span;

    const KNOTS: [f64; 12] = [0., 0., 0., 0., 0.2, 0.45, 0.5, 0.8, 1., 1., 1., 1.];
    // degree 3, 8 points

    #[test]
    fn partition_of_unity_and_nonnegativity() {
        for i in 0..=100 {
            let u = i as f64 / 100.0;
            let span = find_span(&KNOTS, 3, 8, u);
            let mut n = [0.0; MAX_ORDER];
            basis_funs(&KNOTS, span, u, 3, &mut n);
            let s: f64 = n[..4].iter().sum();
            assert!((s - 1.0).abs() < 1e-14);
            assert!(n[..4].iter().all(|&x| x >= -1e-15));
            let mut d = [[0.0; MAX_ORDER]; 4];
            ders_basis_funs(&KNOTS, span, u, 3, &mut d);
            for j in 0..4 {
                assert!((d[0][j] - n[j]).abs() < 1e-14);
            }
            // derivatives of a partition of unity sum to zero
            for k in 1..4 {
                assert!(d[k][..4].iter().sum::<f64>().abs() < 1e-9, "k={k}");
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-6;
        for &u in &[0.1, 0.3, 0.47, 0.66, 0.9] {
            let span = find_span(&KNOTS, 3, 8, u);
            let mut d = [[0.0; MAX_ORDER]; 3];
            ders_basis_funs(&KNOTS, span, u, 3, &mut d);
            let (mut np, mut nm) = ([0.0; MAX_ORDER], [0.0; MAX_ORDER]);
            basis_funs(&KNOTS, span, u + h, 3, &mut np);
            basis_funs(&KNOTS, span, u - h, 3, &mut nm);
            for j in 0..4 {
                let fd = (np[j] - nm[j]) / (2.0 * h);
                assert!((fd - d[1][j]).abs() < 1e-6, "u={u} j={j}: {fd} vs {}", d[1][j]);
                let fd2 = (np[j] - 2.0 * d[0][j] + nm[j]) / (h * h);
                assert!(
                    (fd2 - d[2][j]).abs() < 1e-2 * (1.0 + d[2][j].abs()),
                    "second u={u} j={j}"
                );
            }
        }
    }
}
