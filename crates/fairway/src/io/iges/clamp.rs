//! Non-clamped, periodic and range-narrowed B-splines made clamped by knot insertion (the geometry
//! unchanged); and `read_first`.

use super::*;

/// Entity 128 clamping in one direction: each line of homogeneous points clamped to the
/// parameter range `(t0, t1)` (the first line's notices kept, tagged with `dir`), as (the new
/// knots if any line was converted, the lines).
#[allow(clippy::too_many_arguments)]
pub(super) fn clamp_lines(
    knots: &[f64],
    lines: Vec<Vec<DVec4>>,
    degree: usize,
    (t0, t1): (f64, f64),
    periodic: bool,
    what: &str,
    dir: &str,
    notices: &mut Vec<String>,
) -> Result<ClampedLines> {
    let mut new_knots = None;
    let mut out: Vec<Vec<DVec4>> = Vec::with_capacity(lines.len());
    for (j, line) in lines.into_iter().enumerate() {
        let mut sink = Vec::new();
        match clamp_to(knots.to_vec(), line.clone(), degree, t0, t1, periodic, what, &mut sink)? {
            None => out.push(line),
            Some((k, r)) => {
                new_knots = Some(k);
                out.push(r);
            }
        }
        if j == 0 {
            notices.extend(sink.into_iter().map(|s| format!("{s} ({dir} direction)")));
        }
    }
    Ok((new_knots, out))
}

/// Boehm insertion (The NURBS Book A5.1) of `u` once into an arbitrary
/// (possibly unclamped) knot vector, on homogeneous points.
pub(super) fn insert_once(knots: &[f64], pts: &[DVec4], p: usize, u: f64) -> (Vec<f64>, Vec<DVec4>) {
    let n = pts.len();
    // span k: knots[k] <= u < knots[k+1], with p <= k <= n-1
    let mut k = p;
    while k + 1 < n && knots[k + 1] <= u {
        k += 1;
    }
    let s = knots[..=k].iter().filter(|&&t| t == u).count();
    let mut q = Vec::with_capacity(n + 1);
    for i in 0..=n {
        if i + p <= k {
            q.push(pts[i]);
        } else if i > k.saturating_sub(s) {
            q.push(pts[i - 1]);
        } else {
            let a = (u - knots[i]) / (knots[i + p] - knots[i]);
            q.push(pts[i] * a + pts[i - 1] * (1.0 - a));
        }
    }
    let mut kn = Vec::with_capacity(knots.len() + 1);
    kn.extend_from_slice(&knots[..=k]);
    kn.push(u);
    kn.extend_from_slice(&knots[k + 1..]);
    (kn, q)
}

/// Make a B-spline clamped on `[v0, v1] ∩ [t_p, t_n]` by inserting the ends
/// until their multiplicity is p, then dropping the knots and points outside.
/// The curve over the kept range is unchanged.
#[allow(clippy::too_many_arguments)]
pub(super) fn clamp_to(
    mut knots: Vec<f64>,
    mut pts: Vec<DVec4>,
    p: usize,
    v0: f64,
    v1: f64,
    periodic: bool,
    what: &str,
    notices: &mut Vec<String>,
) -> Result<Option<(Vec<f64>, Vec<DVec4>)>> {
    let n = pts.len();
    if knots.len() != n + p + 1 {
        return Err(perr(format!("{what}: knot count does not match")));
    }
    if let Some(i) = (1..knots.len()).find(|&i| knots[i] < knots[i - 1]) {
        return Err(Error::KnotsDecreasing {
            field: format!("{what} knots"),
            index: i,
            prev: knots[i - 1],
            next: knots[i],
        });
    }
    let (ta, tb) = (knots[p], knots[n]);
    if tb <= ta {
        return Err(Error::EmptyDomain {
            field: format!("{what} knots"),
            start: ta,
            end: tb,
        });
    }
    // A parameter range outside the knot domain (or not given) means the whole domain.
    let (mut a, mut b) = (v0.max(ta), v1.min(tb));
    if !(a < b) {
        a = ta;
        b = tb;
    }
    let clamped = knots[..=p].iter().all(|&t| t == knots[0])
        && knots[n..].iter().all(|&t| t == knots[n + p])
        && a == knots[0]
        && b == knots[n + p];
    if clamped {
        return Ok(None);
    }
    for u in [a, b] {
        let mut guard = 0;
        loop {
            let k = knots.iter().filter(|&&t| t == u).count();
            if k >= p || guard > p {
                break;
            }
            (knots, pts) = insert_once(&knots, &pts, p, u);
            guard += 1;
        }
    }
    // Now a and b have multiplicity >= p. With the run of a starting at
    // index s: C(a) = P[s-1] when the run has exactly p knots (the basis
    // functions before it vanish on [a, b]), P[s + mult - p - 1] when longer.
    let first_a = knots.iter().position(|&t| t == a).unwrap_or(0);
    let mult_a = knots.iter().filter(|&&t| t == a).count();
    let i0 = if mult_a > p {
        first_a + mult_a - p - 1
    } else {
        first_a.saturating_sub(1)
    };
    // The kept knots: a (p + 1 times), the interior ones, b (p + 1 times).
    let mut new_knots = vec![a; p + 1];
    new_knots.extend(knots.iter().copied().filter(|&t| t > a && t < b));
    new_knots.extend(std::iter::repeat_n(b, p + 1));
    let n_new = new_knots.len() - p - 1;
    if i0 + n_new > pts.len() {
        return Err(perr(format!("{what}: cannot clamp the knot vector")));
    }
    let new_pts = pts[i0..i0 + n_new].to_vec();
    notices.push(format!(
        "{what}: {} knot vector converted to a clamped one on [{a}, {b}] by knot insertion",
        if periodic { "periodic" } else { "non-clamped" }
    ));
    Ok(Some((new_knots, new_pts)))
}

/// Read the first curve or surface of an IGES file.
pub fn read_first(bytes: &[u8]) -> Result<Geometry> {
    let f = read_all(bytes)?;
    f.objects.into_iter().next().ok_or_else(|| {
        perr(format!(
            "no B-spline curve (126) or surface (128) in the file{}",
            if f.notices.is_empty() {
                String::new()
            } else {
                format!(" ({})", f.notices.join("; "))
            }
        ))
    })
}
