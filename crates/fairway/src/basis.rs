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
    if p == 3 {
        // the same operations unrolled (bit-identical)
        let mut d = [[0.0; MAX_ORDER]; 1];
        cubic_ders::<1>(knots, span, u, &mut d);
        out[..4].copy_from_slice(&d[0][..4]);
        return;
    }
    basis_funs_general(knots, span, u, p, out);
}

/// A2.2 for any degree.
#[inline]
fn basis_funs_general(knots: &[f64], span: usize, u: f64, p: usize, out: &mut [f64]) {
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
    if p == 3 {
        cubic_ders::<D>(knots, span, u, ders)
    } else if p < 4 {
        ders_impl::<D, 4>(knots, span, u, p, ders)
    } else if p < 8 {
        ders_impl::<D, 8>(knots, span, u, p, ders)
    } else {
        ders_impl::<D, MAX_ORDER>(knots, span, u, p, ders)
    }
}

/// [`ders_basis_funs`] for cubics (derivatives above the third are zero): the
/// triangular table of A2.2 for degrees 1–3, then the derivative recurrence
/// `N'_{k,q} = q (N_{k,q−1} / (t_{k+q} − t_k) − N_{k+1,q−1} / (t_{k+q+1} − t_{k+1}))` on the
/// functions that are non-zero in the span (whose denominators are therefore positive).
#[inline(always)]
fn cubic_ders<const D: usize>(t: &[f64], i: usize, u: f64, ders: &mut [[f64; MAX_ORDER]; D]) {
    let (l1, l2, l3) = (u - t[i], u - t[i - 1], u - t[i - 2]);
    let (r1, r2, r3) = (t[i + 1] - u, t[i + 2] - u, t[i + 3] - u);
    // degree 1: N_{i−1,1}, N_{i,1}
    let tmp = 1.0 / (r1 + l1);
    let n1 = [r1 * tmp, l1 * tmp];
    // degree 2: N_{i−2..i,2}
    let a = n1[0] / (r1 + l2);
    let b = n1[1] / (r2 + l1);
    let n2 = [r1 * a, l2 * a + r2 * b, l1 * b];
    // degree 3
    let a = n2[0] / (r1 + l3);
    let b = n2[1] / (r2 + l2);
    let c = n2[2] / (r3 + l1);
    ders[0][..4].copy_from_slice(&[r1 * a, l3 * a + r2 * b, l2 * b + r3 * c, l1 * c]);
    if D == 1 {
        return;
    }
    // 3 N_{i−2+m,2} / (t_{i+1+m} − t_{i−2+m}), m = 0..2
    let w3 = [
        3.0 / (t[i + 1] - t[i - 2]),
        3.0 / (t[i + 2] - t[i - 1]),
        3.0 / (t[i + 3] - t[i]),
    ];
    let q = [n2[0] * w3[0], n2[1] * w3[1], n2[2] * w3[2]];
    ders[1][..4].copy_from_slice(&[-q[0], q[0] - q[1], q[1] - q[2], q[2]]);
    if D == 2 {
        return;
    }
    // N'_{i−2+m,2} from 2 N_{i−1+m',1} / (t_{i+1+m'} − t_{i−1+m'}), m' = 0..1
    let rr = [2.0 * n1[0] / (t[i + 1] - t[i - 1]), 2.0 * n1[1] / (t[i + 2] - t[i])];
    let d2 = [-rr[0], rr[0] - rr[1], rr[1]];
    let sq = [d2[0] * w3[0], d2[1] * w3[1], d2[2] * w3[2]];
    ders[2][..4].copy_from_slice(&[-sq[0], sq[0] - sq[1], sq[1] - sq[2], sq[2]]);
    if D == 3 {
        return;
    }
    // N''_{i−2+m,2} from N'_{i−1,1} = −e, N'_{i,1} = e (e = 1 / (t_{i+1} − t_i))
    let e = 1.0 / (t[i + 1] - t[i]);
    let pp = [-2.0 * e / (t[i + 1] - t[i - 1]), 2.0 * e / (t[i + 2] - t[i])];
    let dd2 = [-pp[0], pp[0] - pp[1], pp[1]];
    let sc = [dd2[0] * w3[0], dd2[1] * w3[1], dd2[2] * w3[2]];
    ders[3][..4].copy_from_slice(&[-sc[0], sc[0] - sc[1], sc[1] - sc[2], sc[2]]);
    for row in ders.iter_mut().skip(4) {
        row[..4].fill(0.0);
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

    /// The cubic path agrees with the general algorithms, also next to double and triple knots: the
    /// values are A2.2's arithmetic bit for bit, the derivatives (up to the third) match A2.3 to 1e-13.
    #[test]
    fn cubic_path_matches_the_general_algorithms() {
        let knots = [
            0., 0., 0., 0., 0.1, 0.1, 0.3, 0.55, 0.55, 0.55, 0.7, 0.71, 1., 1., 1., 1.,
        ];
        let n = knots.len() - 4;
        for i in 0..=1000 {
            let u = (i as f64 / 1000.0).powf(1.3);
            let span = find_span(&knots, 3, n, u);
            let (mut a, mut b) = ([0.0; MAX_ORDER], [0.0; MAX_ORDER]);
            basis_funs(&knots, span, u, 3, &mut a);
            basis_funs_general(&knots, span, u, 3, &mut b);
            assert_eq!(a[..4], b[..4], "u {u}");
            let mut fast = [[0.0; MAX_ORDER]; 5];
            let mut general = [[0.0; MAX_ORDER]; 5];
            ders_basis_funs(&knots, span, u, 3, &mut fast);
            ders_impl::<5, 4>(&knots, span, u, 3, &mut general);
            assert_eq!(fast[0][..4], b[..4], "u {u}");
            for k in 0..5 {
                let scale = general[k][..4].iter().fold(1.0f64, |m, x| m.max(x.abs()));
                for j in 0..4 {
                    assert!(
                        (fast[k][j] - general[k][j]).abs() <= 1e-13 * scale,
                        "u {u} k {k} j {j}: {} vs {}",
                        fast[k][j],
                        general[k][j]
                    );
                }
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
