//! Knot vectors: validation, span search, multiplicity, spans.
//!
//! A knot vector of a B-spline of degree p with n control points holds
//! n + p + 1 non-decreasing values. Fairway only stores *clamped* vectors: the
//! first and last values appear p + 1 times, so the curve interpolates its end
//! control points, and the parameter domain is `[t_p, t_n]`. Interior knots
//! have multiplicity at most p (The NURBS Book, ch. 2).

use crate::error::{Error, Result};

/// The largest degree Fairway evaluates (fixed-size stack buffers in the basis).
pub const MAX_DEGREE: usize = 15;

/// A validated, clamped knot vector of a given degree.
#[derive(Debug, Clone, PartialEq)]
pub struct KnotVector {
    values: Vec<f64>,
    degree: usize,
}

impl KnotVector {
    /// Validate `values` as the knot vector of `points` control points of
    /// degree `degree`. `field` names the input in error messages.
    pub fn try_new(values: Vec<f64>, degree: usize, points: usize, field: &str) -> Result<Self> {
        let f = || field.to_string();
        if degree == 0 || degree > MAX_DEGREE {
            return Err(Error::BadDegree {
                field: f(),
                degree,
                max: MAX_DEGREE,
            });
        }
        if points < degree + 1 {
            return Err(Error::TooFewPoints {
                field: "points".into(),
                count: points,
                degree,
                needed: degree + 1,
            });
        }
        let expected = points + degree + 1;
        if values.len() != expected {
            return Err(Error::KnotCount {
                field: f(),
                count: values.len(),
                expected,
                points,
                degree,
            });
        }
        if let Some(index) = values.iter().position(|v| !v.is_finite()) {
            return Err(Error::NotFinite { field: f(), index });
        }
        for i in 1..values.len() {
            if values[i] < values[i - 1] {
                return Err(Error::KnotsDecreasing {
                    field: f(),
                    index: i,
                    prev: values[i - 1],
                    next: values[i],
                });
            }
        }
        let first = values[0];
        let last = values[values.len() - 1];
        let clamped_start = values[..=degree].iter().all(|&v| v == first);
        let clamped_end = values[values.len() - degree - 1..].iter().all(|&v| v == last);
        if !clamped_start || !clamped_end {
            return Err(Error::KnotsNotClamped {
                field: f(),
                needed: degree + 1,
            });
        }
        if last <= first {
            return Err(Error::EmptyDomain {
                field: f(),
                start: first,
                end: last,
            });
        }
        // Interior multiplicity: the runs strictly inside the clamped ends.
        let interior = &values[degree + 1..values.len() - degree - 1];
        let mut i = 0;
        while i < interior.len() {
            let v = interior[i];
            let mut j = i;
            while j < interior.len() && interior[j] == v {
                j += 1;
            }
            let mult = j - i;
            if mult > degree || v == first || v == last {
                return Err(Error::KnotMultiplicity {
                    field: f(),
                    value: v,
                    multiplicity: if v == first || v == last {
                        mult + degree + 1
                    } else {
                        mult
                    },
                    degree,
                });
            }
            i = j;
        }
        Ok(Self { values, degree })
    }

    /// A clamped uniform knot vector for `points` control points of `degree` on `[0, 1]`.
    pub fn uniform(degree: usize, points: usize) -> Result<Self> {
        if degree == 0 || degree > MAX_DEGREE || points < degree + 1 {
            return Self::try_new(vec![], degree, points, "knots");
        }
        let spans = points - degree;
        let mut v = vec![0.0; degree + 1];
        for i in 1..spans {
            v.push(i as f64 / spans as f64);
        }
        v.extend(std::iter::repeat_n(1.0, degree + 1));
        Self::try_new(v, degree, points, "knots")
    }

    /// The knot values.
    #[inline]
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The degree p.
    #[inline]
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The number of control points, `len − p − 1`.
    #[inline]
    pub fn n_points(&self) -> usize {
        self.values.len() - self.degree - 1
    }

    /// The parameter domain `[t_p, t_n]`.
    #[inline]
    pub fn domain(&self) -> (f64, f64) {
        (self.values[self.degree], self.values[self.n_points()])
    }

    /// The index `i` of the knot span `[t_i, t_{i+1})` holding `u`, with
    /// `p ≤ i ≤ n − 1`; `u` is clamped to the domain and the end of the domain
    /// belongs to the last non-empty span (The NURBS Book, A2.1).
    #[inline]
    pub fn find_span(&self, u: f64) -> usize {
        find_span(&self.values, self.degree, self.n_points(), u)
    }

    /// [`Self::find_span`] for increasing parameters: `hint` is the previous answer, and when `u` lies
    /// strictly inside the domain in that span or the next one, no search is needed. Same result.
    #[inline]
    pub fn find_span_from(&self, u: f64, hint: usize) -> usize {
        let (k, n) = (&self.values, self.n_points());
        if u > k[self.degree] && u < k[n] && hint >= self.degree && hint < n {
            if k[hint] <= u && u < k[hint + 1] {
                return hint;
            }
            if hint + 1 < n && k[hint + 1] <= u && u < k[hint + 2] {
                return hint + 1;
            }
        }
        self.find_span(u)
    }

    /// Multiplicity of the value `u` in the knot vector (0 if absent): the length of its run, found by
    /// two binary searches in the non-decreasing values (O(log n): the fair asks it at every breakpoint).
    pub fn multiplicity(&self, u: f64) -> usize {
        let lo = self.values.partition_point(|&v| v < u);
        let hi = self.values.partition_point(|&v| v <= u);
        hi - lo
    }

    /// The distinct breakpoints `t_p < … < t_n` of the domain.
    pub fn breakpoints(&self) -> Vec<f64> {
        let n = self.n_points();
        let mut out: Vec<f64> = Vec::with_capacity(n - self.degree + 1);
        for &v in &self.values[self.degree..=n] {
            if out.last() != Some(&v) {
                out.push(v);
            }
        }
        out
    }

    /// Number of non-empty knot spans.
    pub fn n_spans(&self) -> usize {
        self.breakpoints().len() - 1
    }

    /// Support `[t_i, t_{i+p+1}]` of basis function `i`.
    #[inline]
    pub fn support(&self, i: usize) -> (f64, f64) {
        (self.values[i], self.values[i + self.degree + 1])
    }

    /// Greville abscissae: the average of the p knots after each index, one per control point.
    pub fn greville(&self) -> Vec<f64> {
        let p = self.degree;
        (0..self.n_points())
            .map(|i| self.values[i + 1..=i + p].iter().sum::<f64>() / p as f64)
            .collect()
    }

    /// A new knot vector with `u` inserted once (no validation of multiplicity beyond p).
    pub(crate) fn with_inserted(&self, u: f64) -> Vec<f64> {
        let mut v = self.values.clone();
        let pos = v.partition_point(|&k| k <= u);
        v.insert(pos, u);
        v
    }

    /// Clamp `u` into the domain.
    #[inline]
    pub fn clamp(&self, u: f64) -> f64 {
        let (a, b) = self.domain();
        u.clamp(a, b)
    }
}

/// Span search on a raw knot slice (The NURBS Book, A2.1), `n` = number of
/// control points. `u` outside the domain is clamped.
#[inline]
pub fn find_span(knots: &[f64], p: usize, n: usize, u: f64) -> usize {
    let hi = n; // domain end index
    if u >= knots[hi] {
        // last non-empty span
        let mut i = hi - 1;
        while i > p && knots[i] == knots[hi] {
            i -= 1;
        }
        return i;
    }
    if u <= knots[p] {
        let mut i = p;
        while i + 1 < hi && knots[i + 1] == knots[p] {
            i += 1;
        }
        return i;
    }
    // binary search: knots[low] <= u < knots[high]
    let mut low = p;
    let mut high = hi;
    while high - low > 1 {
        let mid = (low + high) / 2;
        if u < knots[mid] {
            high = mid;
        } else {
            low = mid;
        }
    }
    low
}

/// What [`resolve_breaks`] does with one knot of multiplicity above p (a break).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Break {
    /// The geometry is continuous there (the two control points next to it coincide): one copy of the
    /// knot and one of the points are dropped, leaving a C0 knot of multiplicity p, the same geometry.
    Reduced(f64),
    /// The geometry jumps there (or the knot has more than p + 1 copies): the object is split.
    Split(f64),
}

/// One piece of [`resolve_breaks`]: its knots and the indices of the control points (lines of a
/// surface) it keeps.
#[derive(Debug, Clone, PartialEq)]
pub struct Piece {
    /// The piece's knot vector (clamped, interior multiplicities at most p).
    pub knots: Vec<f64>,
    /// Indices into the input's control points (rows) that the piece keeps, in order.
    pub points: Vec<usize>,
}

/// Knots of multiplicity above `p` inside a clamped knot vector (a break, "C−1", which
/// [`KnotVector::try_new`] refuses), resolved: where `same(a − 1, a)` says the control points (rows) on the
/// two sides of the break coincide, the knot is reduced to multiplicity p (same geometry); otherwise the
/// B-spline is split there into pieces, each a valid clamped B-spline (a knot of s > p + 1 copies also
/// drops the s − p − 1 control points whose basis functions are zero). Returns the pieces (one when there
/// is no split) and what was done at each break. Only the structure is checked: counts that do not match
/// the knots return the input as one piece, for the caller's validation to refuse.
pub fn resolve_breaks(knots: &[f64], p: usize, same: impl Fn(usize, usize) -> bool) -> (Vec<Piece>, Vec<Break>) {
    let whole = |kn: &[f64]| Piece {
        knots: kn.to_vec(),
        points: (0..kn.len().saturating_sub(p + 1)).collect(),
    };
    if p == 0 || knots.len() < 2 * (p + 1) || knots.iter().any(|k| !k.is_finite()) {
        return (vec![whole(knots)], vec![]);
    }
    let n = knots.len() - p - 1;
    let (lo, hi) = (knots[0], knots[knots.len() - 1]);
    let mut breaks = vec![];
    let mut i = 0;
    while i < knots.len() {
        let mut s = 1;
        while i + s < knots.len() && knots[i + s] == knots[i] {
            s += 1;
        }
        if knots[i] > lo && knots[i] < hi && s > p {
            breaks.push((i, s));
        }
        i += s;
    }
    if breaks.is_empty() {
        return (vec![whole(knots)], vec![]);
    }
    let (mut kdrop, mut pdrop) = (vec![], vec![]);
    let mut pieces = vec![];
    let mut done = vec![];
    let (mut k0, mut p0) = (0, 0);
    let piece = |k0: usize, k1: usize, p0: usize, p1: usize, kdrop: &[usize], pdrop: &[usize]| Piece {
        knots: (k0..k1).filter(|k| !kdrop.contains(k)).map(|k| knots[k]).collect(),
        points: (p0..p1).filter(|q| !pdrop.contains(q)).collect(),
    };
    for (a, s) in breaks {
        if s == p + 1 && a >= 1 && a < n && same(a - 1, a) {
            kdrop.push(a + p);
            pdrop.push(a);
            done.push(Break::Reduced(knots[a]));
            continue;
        }
        pieces.push(piece(k0, a + p + 1, p0, a.min(n), &kdrop, &pdrop));
        (k0, p0) = (a + s - p - 1, a + s - p - 1);
        done.push(Break::Split(knots[a]));
    }
    pieces.push(piece(k0, knots.len(), p0, n, &kdrop, &pdrop));
    (pieces, done)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn find_span_from_agrees_with_find_span() {
        let values = vec![
            0., 0., 0., 0., 0.1, 0.1, 0.3, 0.55, 0.55, 0.55, 0.7, 0.71, 1., 1., 1., 1.,
        ];
        let kv = KnotVector::try_new(values, 3, 12, "knots").unwrap();
        let mut hint = 0;
        for i in 0..=2000 {
            let u = -0.1 + 1.2 * (i as f64 / 2000.0).powf(1.5);
            let s = kv.find_span_from(u, hint);
            assert_eq!(s, kv.find_span(u), "u {u}");
            hint = s;
            // any hint gives the same answer
            assert_eq!(kv.find_span_from(u, i % 20), kv.find_span(u));
        }
    }

    #[test]
    fn validation_messages() {
        let e = KnotVector::try_new(vec![0.0; 9], 3, 6, "knots").unwrap_err();
        assert_eq!(e.to_string(), "knots: 9 values, expected 10 for 6 points of degree 3");
        let e = KnotVector::try_new(vec![0., 0., 0., 0.5, 0.4, 1., 1., 1.], 2, 5, "knots").unwrap_err();
        assert!(matches!(e, Error::KnotsDecreasing { index: 4, .. }), "{e}");
        let e = KnotVector::try_new(vec![0., 0., 0.2, 0.5, 1., 1., 1., 1.], 3, 4, "knots").unwrap_err();
        assert!(matches!(e, Error::KnotsNotClamped { .. }), "{e}");
        let e = KnotVector::try_new(vec![0., 0., 0., 0.5, 0.5, 0.5, 1., 1., 1.], 2, 6, "knots").unwrap_err();
        assert!(matches!(e, Error::KnotMultiplicity { multiplicity: 3, .. }), "{e}");
        let e = KnotVector::try_new(vec![1., 1., 1., 1., 1., 1.], 2, 3, "knots").unwrap_err();
        assert!(matches!(e, Error::EmptyDomain { .. }), "{e}");
        let e = KnotVector::try_new(vec![0., 0., f64::NAN, 1., 1., 1.], 2, 3, "knots").unwrap_err();
        assert!(matches!(e, Error::NotFinite { index: 2, .. }), "{e}");
        let e = KnotVector::try_new(vec![0., 0., 1., 1.], 1, 1, "knots").unwrap_err();
        assert!(matches!(e, Error::TooFewPoints { .. }), "{e}");
        let e = KnotVector::try_new(vec![0.; 4], 0, 3, "knots").unwrap_err();
        assert!(matches!(e, Error::BadDegree { .. }), "{e}");
    }

    #[test]
    fn span_search() {
        let k = KnotVector::try_new(vec![0., 0., 0., 1., 2., 2., 3., 4., 4., 4.], 2, 7, "k").unwrap();
        assert_eq!(k.find_span(0.0), 2);
        assert_eq!(k.find_span(0.5), 2);
        assert_eq!(k.find_span(1.0), 3);
        assert_eq!(k.find_span(2.0), 5);
        assert_eq!(k.find_span(2.5), 5);
        assert_eq!(k.find_span(4.0), 6);
        assert_eq!(k.find_span(9.0), 6);
        assert_eq!(k.find_span(-1.0), 2);
        assert_eq!(k.breakpoints(), vec![0., 1., 2., 3., 4.]);
        assert_eq!(k.n_spans(), 4);
        assert_eq!(k.multiplicity(2.0), 2);
    }

    #[test]
    fn multiplicity_counts_the_run_of_each_value() {
        let v = vec![0., 0., 0., 0., 0.5, 1., 1., 1., 2., 3., 3., 3., 3.];
        let k = KnotVector::try_new(v.clone(), 3, 9, "k").unwrap();
        for u in [
            -1.0,
            -0.0,
            0.0,
            0.25,
            0.5,
            1.0,
            1.5,
            2.0,
            3.0,
            4.0,
            f64::NAN,
            f64::INFINITY,
        ] {
            let count = v.iter().filter(|&&x| x == u).count();
            assert_eq!(k.multiplicity(u), count, "u = {u}");
        }
        assert_eq!(k.multiplicity(0.0), 4);
        assert_eq!(k.multiplicity(1.0), 3);
        assert_eq!(k.multiplicity(0.75), 0);
    }

    #[test]
    fn breaks_split_or_reduce_into_valid_pieces() {
        // cubic, a break (multiplicity 4) at 1 and a simple knot at 2: points 0..=3 | 4..=8
        let k = [0., 0., 0., 0., 1., 1., 1., 1., 2., 3., 3., 3., 3.];
        let (pieces, done) = resolve_breaks(&k, 3, |_, _| false);
        assert_eq!(done, vec![Break::Split(1.0)]);
        assert_eq!(pieces.len(), 2);
        assert_eq!(pieces[0].knots, vec![0., 0., 0., 0., 1., 1., 1., 1.]);
        assert_eq!(pieces[0].points, vec![0, 1, 2, 3]);
        assert_eq!(pieces[1].knots, vec![1., 1., 1., 1., 2., 3., 3., 3., 3.]);
        assert_eq!(pieces[1].points, vec![4, 5, 6, 7, 8]);
        for pc in &pieces {
            KnotVector::try_new(pc.knots.clone(), 3, pc.points.len(), "k").unwrap();
        }
        // continuous there: one knot and point 4 dropped, a C0 knot of multiplicity 3 left
        let (pieces, done) = resolve_breaks(&k, 3, |a, b| (a, b) == (3, 4));
        assert_eq!(done, vec![Break::Reduced(1.0)]);
        assert_eq!(pieces.len(), 1);
        assert_eq!(pieces[0].knots, vec![0., 0., 0., 0., 1., 1., 1., 2., 3., 3., 3., 3.]);
        assert_eq!(pieces[0].points, vec![0, 1, 2, 3, 5, 6, 7, 8]);
        KnotVector::try_new(pieces[0].knots.clone(), 3, 8, "k").unwrap();
        // five copies at degree 3: the point whose basis function is zero is dropped
        let k5 = [0., 0., 0., 0., 1., 1., 1., 1., 1., 2., 2., 2., 2.];
        let (pieces, _) = resolve_breaks(&k5, 3, |_, _| true);
        assert_eq!(pieces[0].points, vec![0, 1, 2, 3]);
        assert_eq!(pieces[1].points, vec![5, 6, 7, 8]);
        assert_eq!(pieces[1].knots, vec![1., 1., 1., 1., 2., 2., 2., 2.]);
        // no break: one piece, the input
        let simple = [0., 0., 0., 1., 2., 2., 2.];
        let (pieces, done) = resolve_breaks(&simple, 2, |_, _| true);
        assert!(done.is_empty());
        assert_eq!(
            pieces,
            vec![Piece {
                knots: simple.to_vec(),
                points: vec![0, 1, 2, 3]
            }]
        );
    }
}
