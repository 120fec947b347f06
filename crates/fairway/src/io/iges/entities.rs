//! Entities 126 (curve) and 128 (surface): parameters checked and turned into geometry.

use super::*;

/// Check `needed` parameters are present before allocating anything for them.
pub(super) fn need(p: &Params<'_>, needed: Option<usize>) -> Result<()> {
    match needed {
        Some(n) if n <= p.remaining() => Ok(()),
        _ => Err(perr(format!(
            "{}: the counts in the parameters need {} more values, only {} present",
            p.what,
            needed.map_or("too many".to_string(), |n| n.to_string()),
            p.remaining()
        ))),
    }
}

pub(super) fn read_126(p: &mut Params<'_>, notices: &mut Vec<String>) -> Result<Vec<Geometry>> {
    let k = p.count("K (number of control points − 1)", i64::from(u32::MAX))?;
    let m = p.count("M (degree)", MAX_DEGREE as i64)?;
    if m == 0 {
        return Err(perr(format!(
            "{}: degree 0 is not supported (1 to {MAX_DEGREE})",
            p.what
        )));
    }
    let planar = p.int()?;
    let _closed = p.int()?;
    let polynomial = p.int()?;
    let periodic = p.int()?;
    let n_pts = k.checked_add(1);
    let n_knots = k.checked_add(m).and_then(|v| v.checked_add(2));
    need(
        p,
        n_knots.and_then(|a| {
            n_pts
                .and_then(|b| b.checked_mul(4))
                .and_then(|b| b.checked_add(a))
                .map(|x| x + 2)
        }),
    )?;
    let (n_pts, n_knots) = (k + 1, k + m + 2);
    if n_pts < m + 1 {
        return Err(Error::TooFewPoints {
            field: format!("{} points", p.what),
            count: n_pts,
            degree: m,
            needed: m + 1,
        });
    }
    let mut knots = Vec::with_capacity(n_knots);
    for _ in 0..n_knots {
        knots.push(p.real()?);
    }
    let mut w = Vec::with_capacity(n_pts);
    for _ in 0..n_pts {
        w.push(p.real()?);
    }
    let mut pts = Vec::with_capacity(n_pts);
    for _ in 0..n_pts {
        pts.push(DVec3::new(p.real()?, p.real()?, p.real()?));
    }
    let v0 = p.real()?;
    let v1 = p.real()?;
    let rational = polynomial == 0;
    check_weights(&w, rational, &p.what)?;
    let hom: Vec<DVec4> = pts
        .iter()
        .zip(&w)
        .map(|(q, &wi)| if rational { (*q * wi).extend(wi) } else { q.extend(1.0) })
        .collect();
    // Already clamped: the values as read (bit-exact); otherwise converted.
    let (knots, pts, weights) = match clamp_to(knots.clone(), hom, m, v0, v1, periodic != 0, &p.what, notices)? {
        None => (knots, pts, rational.then_some(w)),
        Some((k, hom)) => (
            k,
            hom.iter().map(|h| h.truncate() / h.w).collect(),
            rational.then(|| hom.iter().map(|h| h.w).collect()),
        ),
    };
    let dim = if planar == 1 && pts.iter().all(|q| q.z == 0.0) {
        2
    } else {
        3
    };
    crate::io::breaks::curve_pieces(&p.what, notices, m, knots, pts, weights, dim)
}

pub(super) fn check_weights(w: &[f64], rational: bool, what: &str) -> Result<()> {
    if rational && let Some((i, &x)) = w.iter().enumerate().find(|(_, x)| **x <= 0.0) {
        return Err(Error::BadWeight {
            field: format!("{what} weights"),
            index: i,
            value: x,
        });
    }
    Ok(())
}

pub(super) fn read_128(p: &mut Params<'_>, notices: &mut Vec<String>) -> Result<Vec<Geometry>> {
    let h = read_128_header(p)?;
    let (nu, nv, total, rational) = (h.nu, h.nv, h.nu * h.nv, h.polynomial == 0);
    let (ku, kv, w, pts, (u0, u1, v0, v1)) = read_128_values(p, &h)?;
    check_weights(&w, rational, &p.what)?;
    // IGES order: index (i, j) at i + j*nu (u fastest); Fairway's is row-major i*nv + j.
    let hom_at = |i: usize, j: usize| {
        let q = pts[i + j * nu];
        let wi = w[i + j * nu];
        if rational { (q * wi).extend(wi) } else { q.extend(1.0) }
    };
    // clamp in u: for each j, the row over i
    let rows: Vec<Vec<DVec4>> = (0..nv).map(|j| (0..nu).map(|i| hom_at(i, j)).collect()).collect();
    let (new_ku, cols) = clamp_lines(&ku, rows, h.m1, (u0, u1), h.periodic_u != 0, &p.what, "u", notices)?;
    let nu2 = cols.first().map_or(0, |c| c.len());
    // clamp in v: for each i, the column over j
    let by_i: Vec<Vec<DVec4>> = (0..nu2).map(|i| cols.iter().map(|c| c[i]).collect()).collect();
    let (new_kv, grid) = clamp_lines(&kv, by_i, h.m2, (v0, v1), h.periodic_v != 0, &p.what, "v", notices)?;
    let nv2 = grid.first().map_or(0, |c| c.len());
    let (points, weights) = if new_ku.is_none() && new_kv.is_none() {
        // Already clamped: the values as read (bit-exact).
        let mut points = Vec::with_capacity(total);
        let mut ws = Vec::with_capacity(total);
        for i in 0..nu {
            for j in 0..nv {
                points.push(pts[i + j * nu]);
                ws.push(w[i + j * nu]);
            }
        }
        (points, rational.then_some(ws))
    } else {
        let flat: Vec<DVec4> = grid.into_iter().flatten().collect();
        (
            flat.iter().map(|h| h.truncate() / h.w).collect(),
            rational.then(|| flat.iter().map(|h| h.w).collect()),
        )
    };
    let (ku, kv) = (new_ku.unwrap_or(ku), new_kv.unwrap_or(kv));
    if points.len() != nu2 * nv2 {
        return Ok(vec![Geometry::Surface(BSplineSurface::try_new(
            h.m1, h.m2, ku, kv, nu2, nv2, points, weights,
        )?)]);
    }
    crate::io::breaks::surface_pieces(&p.what, notices, (h.m1, h.m2), (ku, kv), nv2, points, weights)
}

/// The counts and flags heading an entity 128's parameters.
pub(super) struct Header128 {
    pub(super) nu: usize,
    pub(super) nv: usize,
    pub(super) m1: usize,
    pub(super) m2: usize,
    pub(super) polynomial: i64,
    pub(super) periodic_u: i64,
    pub(super) periodic_v: i64,
}

/// Entity 128 header: counts, degrees and flags read and checked (degrees, enough values
/// present before anything is allocated, enough points per direction).
pub(super) fn read_128_header(p: &mut Params<'_>) -> Result<Header128> {
    let k1 = p.count("K1", i64::from(u32::MAX))?;
    let k2 = p.count("K2", i64::from(u32::MAX))?;
    let m1 = p.count("M1 (degree in u)", MAX_DEGREE as i64)?;
    let m2 = p.count("M2 (degree in v)", MAX_DEGREE as i64)?;
    if m1 == 0 || m2 == 0 {
        return Err(perr(format!(
            "{}: degree 0 is not supported (1 to {MAX_DEGREE})",
            p.what
        )));
    }
    let _closed_u = p.int()?;
    let _closed_v = p.int()?;
    let polynomial = p.int()?;
    let periodic_u = p.int()?;
    let periodic_v = p.int()?;
    let nu = k1.checked_add(1);
    let nv = k2.checked_add(1);
    let nk_u = k1.checked_add(m1 + 2);
    let nk_v = k2.checked_add(m2 + 2);
    let total = nu.zip(nv).and_then(|(a, b)| a.checked_mul(b));
    let needed = total
        .and_then(|t| t.checked_mul(4))
        .zip(nk_u.zip(nk_v))
        .and_then(|(a, (b, c))| a.checked_add(b)?.checked_add(c)?.checked_add(4));
    need(p, needed)?;
    let (nu, nv) = (k1 + 1, k2 + 1);
    for (n, m, f) in [(nu, m1, "u"), (nv, m2, "v")] {
        if n < m + 1 {
            return Err(Error::TooFewPoints {
                field: format!("{} points in {f}", p.what),
                count: n,
                degree: m,
                needed: m + 1,
            });
        }
    }
    Ok(Header128 {
        nu,
        nv,
        m1,
        m2,
        polynomial,
        periodic_u,
        periodic_v,
    })
}

/// The values of an entity 128: knots in u and v, weights, points and the (u0, u1, v0, v1)
/// parameter range.
pub(super) type Values128 = (Vec<f64>, Vec<f64>, Vec<f64>, Vec<DVec3>, (f64, f64, f64, f64));

/// Entity 128 values: knots, weights, points (IGES order) and parameter range, as read.
pub(super) fn read_128_values(p: &mut Params<'_>, h: &Header128) -> Result<Values128> {
    let (nk_u, nk_v, total) = (h.nu + h.m1 + 1, h.nv + h.m2 + 1, h.nu * h.nv);
    let mut ku = Vec::with_capacity(nk_u);
    for _ in 0..nk_u {
        ku.push(p.real()?);
    }
    let mut kv = Vec::with_capacity(nk_v);
    for _ in 0..nk_v {
        kv.push(p.real()?);
    }
    let mut w = Vec::with_capacity(total);
    for _ in 0..total {
        w.push(p.real()?);
    }
    let mut pts = Vec::with_capacity(total);
    for _ in 0..total {
        pts.push(DVec3::new(p.real()?, p.real()?, p.real()?));
    }
    let range = (p.real()?, p.real()?, p.real()?, p.real()?);
    Ok((ku, kv, w, pts, range))
}

/// The new knots (if any line was converted) and the lines of homogeneous points.
pub(super) type ClampedLines = (Option<Vec<f64>>, Vec<Vec<DVec4>>);
