//! The control net of a layout's frame: each filled cell's block of the frame's net found from its
//! patch (the restriction of the frame's B-splines to the cell, inverted), the empty cells' points
//! filled by the smoothest extension (least second differences of the net).

use glam::DVec3;

use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::fair::closed::split;

/// The frame's basis functions that reach the cell `[a, b]` of the knot vector `knots` (degree `p`):
/// the first one's index and the matrix taking their coefficients to the cell's own clamped net
/// (`n` × `n`, row by row; column k: the k-th function restricted to the cell). Errors if the cell's net
/// is not `n` points (its knots are not the frame's between `a` and `b`).
pub(super) fn restriction(knots: &[f64], p: usize, (a, b): (f64, f64), n: usize) -> Result<(usize, Vec<Vec<f64>>)> {
    let count = knots.len() - p - 1;
    let reach: Vec<usize> = (0..count).filter(|&i| knots[i] < b && knots[i + p + 1] > a).collect();
    if reach.len() != n {
        return Err(Error::InvalidInput(format!(
            "a cell's knots do not match the frame's ({} functions reach it, its net has {n})",
            reach.len()
        )));
    }
    let (lo, hi) = (knots[p], knots[count]);
    let mut m = vec![vec![0.0; n]; n];
    for (k, &i) in reach.iter().enumerate() {
        let mut pts = vec![DVec3::ZERO; count];
        pts[i] = DVec3::X;
        let mut c = BSplineCurve::try_new(p, knots.to_vec(), pts, None, 3)?;
        if a > lo {
            c = split(&c, a)?.1;
        }
        if b < hi {
            c = split(&c, b)?.0;
        }
        if c.n_points() != n {
            return Err(Error::InvalidInput("a cell's restriction has the wrong size".into()));
        }
        for (row, q) in m.iter_mut().zip(c.points()) {
            row[k] = q.x;
        }
    }
    Ok((reach[0], m))
}

/// Solve `m x = rhs` in place (Gaussian elimination with partial pivoting; `m` small and square).
pub(super) fn solve(m: &[Vec<f64>], rhs: &mut [DVec3]) -> Result<()> {
    let n = m.len();
    let mut a: Vec<Vec<f64>> = m.to_vec();
    let scale = a.iter().flatten().fold(0.0f64, |s, x| s.max(x.abs()));
    for col in 0..n {
        let piv = (col..n)
            .max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))
            .unwrap_or(col);
        if !(a[piv][col].abs() > 1e-13 * scale) {
            return Err(Error::InvalidInput("a cell's restriction is singular".into()));
        }
        a.swap(col, piv);
        rhs.swap(col, piv);
        for r in col + 1..n {
            let f = a[r][col] / a[col][col];
            if f != 0.0 {
                for k in col..n {
                    a[r][k] -= f * a[col][k];
                }
                let v = rhs[col];
                rhs[r] -= f * v;
            }
        }
    }
    for col in (0..n).rev() {
        let mut v = rhs[col];
        for k in col + 1..n {
            v -= a[col][k] * rhs[k];
        }
        rhs[col] = v / a[col][col];
    }
    Ok(())
}

/// `mu · block · mvᵀ`: a block of the frame's net (`mu` columns × `mv` columns, row-major) restricted to a
/// cell.
pub(super) fn restrict(block: &[DVec3], mu: &[Vec<f64>], mv: &[Vec<f64>]) -> Vec<DVec3> {
    let (nu, nv) = (mu.len(), mv.len());
    // along v first: t[i][l] = Σ_j block[i][j] mv[l][j]
    let t: Vec<DVec3> = (0..nu)
        .flat_map(|i| (0..nv).map(move |l| (0..nv).fold(DVec3::ZERO, |s, j| s + block[i * nv + j] * mv[l][j])))
        .collect();
    (0..nu)
        .flat_map(|k| (0..nv).map(move |l| (k, l)))
        .map(|(k, l)| (0..nu).fold(DVec3::ZERO, |s, i| s + t[i * nv + l] * mu[k][i]))
        .collect()
}

/// The block of the frame's net whose restriction to a cell is the cell's net `cell` (`nu × nv`,
/// row-major): `mu⁻¹ · cell · mv⁻ᵀ`.
pub(super) fn unrestrict(cell: &[DVec3], mu: &[Vec<f64>], mv: &[Vec<f64>]) -> Result<Vec<DVec3>> {
    let (nu, nv) = (mu.len(), mv.len());
    let mut x = cell.to_vec();
    for j in 0..nv {
        let mut col: Vec<DVec3> = (0..nu).map(|i| x[i * nv + j]).collect();
        solve(mu, &mut col)?;
        (0..nu).for_each(|i| x[i * nv + j] = col[i]);
    }
    for i in 0..nu {
        solve(mv, &mut x[i * nv..(i + 1) * nv])?;
    }
    Ok(x)
}

/// The second-difference stencils of a net (offsets in i, j and coefficients): along i, along j, and the
/// twist (weighted √2, so that its square counts twice, as in the thin-plate energy).
const STENCILS: [&[(i64, i64, f64)]; 3] = [
    &[(-1, 0, 1.0), (0, 0, -2.0), (1, 0, 1.0)],
    &[(0, -1, 1.0), (0, 0, -2.0), (0, 1, 1.0)],
    &[
        (0, 0, std::f64::consts::SQRT_2),
        (1, 0, -std::f64::consts::SQRT_2),
        (0, 1, -std::f64::consts::SQRT_2),
        (1, 1, std::f64::consts::SQRT_2),
    ],
];

/// Fill the points of the `nu × nv` net not `known` with the smoothest extension of the known ones: a
/// first guess extrapolated layer by layer from the known points, then Gauss–Seidel sweeps on the sum of
/// the squared second differences (a discrete thin plate) until the largest move is below `eps` (at most
/// 4000 sweeps; the result is a valid net whatever the sweeps reach).
pub(super) fn fill(net: &mut [DVec3], known: &[bool], (nu, nv): (usize, usize), eps: f64) {
    let at = |i: i64, j: i64| {
        (i >= 0 && j >= 0 && (i as usize) < nu && (j as usize) < nv).then(|| i as usize * nv + j as usize)
    };
    let mut have = known.to_vec();
    let free: Vec<usize> = (0..nu * nv).filter(|&k| !known[k]).collect();
    if free.is_empty() || !known.iter().any(|&k| k) {
        return;
    }
    while have.iter().any(|&h| !h) {
        let mut next = have.clone();
        for &k in &free {
            if have[k] {
                continue;
            }
            let (i, j) = ((k / nv) as i64, (k % nv) as i64);
            let (mut sum, mut n) = (DVec3::ZERO, 0.0);
            for (di, dj) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
                let near = at(i + di, j + dj).filter(|&q| have[q]);
                let far = at(i + 2 * di, j + 2 * dj).filter(|&q| have[q]);
                match (near, far) {
                    (Some(a), Some(b)) => (sum, n) = (sum + 2.0 * net[a] - net[b], n + 1.0),
                    (Some(a), None) => (sum, n) = (sum + net[a], n + 1.0),
                    _ => {}
                }
            }
            if n > 0.0 {
                net[k] = sum / n;
                next[k] = true;
            }
        }
        have = next;
    }
    for _ in 0..4000 {
        let mut moved = 0.0f64;
        for &k in &free {
            let (i, j) = ((k / nv) as i64, (k % nv) as i64);
            let (mut num, mut den) = (DVec3::ZERO, 0.0);
            for st in STENCILS {
                for &(oi, oj, c) in st {
                    // the stencil anchored so that (i, j) is its point (oi, oj)
                    let (ai, aj) = (i - oi, j - oj);
                    let idx: Option<Vec<(usize, f64)>> = st
                        .iter()
                        .map(|&(si, sj, cs)| at(ai + si, aj + sj).map(|q| (q, cs)))
                        .collect();
                    let Some(idx) = idx else { continue };
                    let rest = idx
                        .iter()
                        .filter(|&&(q, _)| q != k)
                        .fold(DVec3::ZERO, |s, &(q, cs)| s + net[q] * cs);
                    num -= rest * c;
                    den += c * c;
                }
            }
            if den > 0.0 {
                let x = num / den;
                moved = moved.max(x.distance(net[k]));
                net[k] = x;
            }
        }
        if moved <= eps {
            break;
        }
    }
}
