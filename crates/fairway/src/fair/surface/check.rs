//! The check grids that verify the band on the surface (module docs of `fair::surface`, step 7).

use super::par_map;
use crate::basis::{MAX_ORDER, basis_funs};
use crate::knots::KnotVector;
use crate::measure_surface::newton_project;
use crate::surface::BSplineSurface;
use glam::DVec3;
use std::ops::Range;

/// Basis values of one direction at the parameters of a check grid.
struct GridBasis {
    spans: Vec<usize>,
    vals: Vec<[f64; MAX_ORDER]>,
    params: Vec<f64>,
}

impl GridBasis {
    fn new(k: &KnotVector, ts: &[f64]) -> Self {
        let p = k.degree();
        let mut spans = Vec::with_capacity(ts.len());
        let mut vals = Vec::with_capacity(ts.len());
        for &t in ts {
            let sp = k.find_span(t);
            let mut n = [0.0; MAX_ORDER];
            basis_funs(k.values(), sp, k.clamp(t), p, &mut n);
            spans.push(sp);
            vals.push(n);
        }
        Self {
            spans,
            vals,
            params: ts.to_vec(),
        }
    }
}

/// A check grid (module docs, step 7) with its basis values, so that the
/// change `S_f − S = Σ ΔD_ij N_i(u) M_j(v)` is evaluated separably
/// (O(grid · p)) instead of by two point evaluations per sample.
pub(super) struct CheckGrid {
    u: GridBasis,
    v: GridBasis,
    pu: usize,
    pv: usize,
    threads: Option<usize>,
    /// The v-parameters in runs of one knot span, for [`Self::change_peaks`]: `(span, first, end)`.
    v_runs: Vec<(usize, usize, usize)>,
    /// The v-basis values transposed per run: for run `r`, `v_vals_t[r]` holds `pv + 1` rows of its
    /// parameters' values (row `jb`: `M_{span − pv + jb}` at each parameter of the run), so that the
    /// change along a grid row is evaluated a run at a time, each coordinate over contiguous memory.
    v_vals_t: Vec<Vec<f64>>,
}

/// A flag per (u, v) knot-span index pair of a net.
struct SpanMask {
    nv: usize,
    bits: Vec<bool>,
}

impl SpanMask {
    fn new(nu: usize, nv: usize) -> Self {
        Self {
            nv,
            bits: vec![false; nu * nv],
        }
    }

    fn set(&mut self, i: usize, j: usize) {
        self.bits[i * self.nv + j] = true;
    }

    /// False outside the net.
    fn get(&self, i: usize, j: usize) -> bool {
        j < self.nv && self.bits.get(i * self.nv + j).copied().unwrap_or(false)
    }
}

/// Rows of a check grid per unit of parallel work (fixed, so the result does not depend on the threads).
const CHECK_ROWS_PER_TASK: usize = 16;

/// The surface at every grid node `(us[k], vs[l])` (row-major over k), evaluated separably:
/// `T[k][j] = Σ_i N_i(u_k) P_ij`, then `S = Σ_j M_j(v_l) T[k][j]` (O(grid · p) instead of a point
/// evaluation per node).
pub(super) fn grid_points(s: &BSplineSurface, us: &[f64], vs: &[f64]) -> Vec<DVec3> {
    let (bu, bv) = (GridBasis::new(s.knots_u(), us), GridBasis::new(s.knots_v(), vs));
    let (pu, pv, nv) = (s.degree_u(), s.degree_v(), s.nv());
    let pts = s.points();
    let mut out = Vec::with_capacity(us.len() * vs.len());
    let mut row = vec![DVec3::ZERO; nv];
    for k in 0..us.len() {
        row.fill(DVec3::ZERO);
        let sp = bu.spans[k];
        for a in 0..=pu {
            let w = bu.vals[k][a];
            let src = &pts[(sp - pu + a) * nv..(sp - pu + a + 1) * nv];
            for (r, q) in row.iter_mut().zip(src) {
                *r += *q * w;
            }
        }
        for l in 0..vs.len() {
            let sp = bv.spans[l];
            out.push((0..=pv).map(|b| row[sp - pv + b] * bv.vals[l][b]).sum());
        }
    }
    out
}

impl CheckGrid {
    /// The parametric change `|S_b − S_a|` on the grid (`b` differing from `a` only in the control block
    /// `fu × fv`, evaluated separably from the change of that block): its maximum and the nodes where it
    /// exceeds `thresh` and is no smaller than at its four grid neighbours, as `(change, u, v)`. As soon as
    /// a grid row's change exceeds `stop_above`, returns that row's maximum (above `stop_above`, not the
    /// grid's maximum) and no peaks: a proof that the band is broken.
    ///
    /// With `every_node` false, the nodes of a knot-span cell whose control points all moved by at most
    /// `thresh` (less 1e-9 of it, against rounding) are not evaluated: the change there is a convex
    /// combination of those moves (the B-spline basis is non-negative and sums to one), so no such node can
    /// exceed `thresh`, be a peak or break the band, and as a neighbour it cannot hide a peak (see
    /// `hot_cells`). The peaks
    /// and the verdict are then those of the whole grid, bit for bit (each evaluated node's sums are the
    /// same, in the same order), but the maximum returned is over the evaluated nodes only — the grid's
    /// maximum where that is above `thresh`, a figure ≤ `thresh` otherwise. On the smoother's nets of
    /// step 8 this skips all but 0–5 of the 729 cells of a 30 × 30 net.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn change_peaks(
        &self,
        a: &BSplineSurface,
        b: &BSplineSurface,
        fu: &Range<usize>,
        fv: &Range<usize>,
        thresh: f64,
        stop_above: f64,
        every_node: bool,
    ) -> (f64, Vec<(f64, f64, f64)>) {
        let nv = a.nv();
        let nfv = fv.len();
        let (mu, mv) = (self.u.params.len(), self.v.params.len());
        let (pa, pb) = (a.points(), b.points());
        let hot = if every_node {
            None
        } else {
            match self.hot_cells(a, b, fu, fv, thresh) {
                Some(h) => Some(h),
                // no cell can reach thresh: no peak, the band holds on the grid
                None => return (0.0, Vec::new()),
            }
        };
        // whether the nodes of u-span `su` and v-span `sv` are evaluated
        let needed = |su: usize, sv: usize| hot.as_ref().is_none_or(|h| h.get(su, sv));
        let row_needed = |k: usize| self.v_runs.iter().any(|&(sv, _, _)| needed(self.u.spans[k], sv));
        let mut tmp = vec![DVec3::ZERO; mu * nfv];
        for k in 0..mu {
            if !row_needed(k) {
                continue;
            }
            let sp = self.u.spans[k];
            for ia in 0..=self.pu {
                let i = sp - self.pu + ia;
                if !fu.contains(&i) {
                    continue;
                }
                let w = self.u.vals[k][ia];
                for (jj, t) in tmp[k * nfv..(k + 1) * nfv].iter_mut().enumerate() {
                    let idx = i * nv + fv.start + jj;
                    *t += (pb[idx] - pa[idx]) * w;
                }
            }
        }
        // |Σ_jb T[k][j] M_jb(v_l)| over the free j, a run of one knot span at a time and each coordinate
        // over the run's parameters: per coordinate the same sums in the same order (jb ascending, from
        // 0) as a DVec3 accumulation, and the length as `DVec3::length` ((x² + y²) + z², then √)
        // the squared changes of grid row k into `d` (mv values)
        let mut xyz = [Vec::new(), Vec::new(), Vec::new()];
        // (a node not evaluated reads 0: no larger than any peak it neighbours)
        let mut row_sq = |k: usize, d: &mut [f64]| {
            let trow = &tmp[k * nfv..(k + 1) * nfv];
            for (&(sp, l0, l1), wt) in self.v_runs.iter().zip(&self.v_vals_t) {
                if !needed(self.u.spans[k], sp) {
                    d[l0..l1].fill(0.0);
                    continue;
                }
                let len = l1 - l0;
                for x in &mut xyz {
                    x.clear();
                    x.resize(len, 0.0);
                }
                for jb in 0..=self.pv {
                    let j = sp - self.pv + jb;
                    if !fv.contains(&j) {
                        continue;
                    }
                    let t = trow[j - fv.start].to_array();
                    let w = &wt[jb * len..(jb + 1) * len];
                    for (x, tc) in xyz.iter_mut().zip(t) {
                        for (xl, &wl) in x.iter_mut().zip(w) {
                            *xl += tc * wl;
                        }
                    }
                }
                let [xs, ys, zs] = &xyz;
                for (((o, &x), &y), &z) in d[l0..l1].iter_mut().zip(xs).zip(ys).zip(zs) {
                    *o = x * x + y * y + z * z;
                }
            }
        };
        // the rows hold squared changes: √ is monotone and correctly rounded, so the largest √ is the √ of
        // the largest square, and the square roots are taken only where they are compared. A square at
        // most thresh²·(1 − 1e-12) has its √ at most thresh: only larger ones are looked at as peaks.
        let below = thresh * thresh * (1.0 - 1e-12);
        let below = if below.is_finite() && thresh > 0.0 {
            below
        } else {
            f64::NEG_INFINITY
        };
        // rows k − 1, k, k + 1 in a rolling window (the grid's rows in order, the peaks of row k once row
        // k + 1 is known: as from the whole grid, without its memory)
        let (mut prev, mut cur, mut next) = (vec![0.0f64; mv], vec![0.0f64; mv], vec![0.0f64; mv]);
        let mut max_sq = 0.0f64;
        // row k into `d`, the grid's largest square so far raised by it; the row's maximum if it is above
        // `stop_above` (the band is broken)
        let mut load = |k: usize, d: &mut [f64], max_sq: &mut f64| {
            row_sq(k, d);
            let row_sq_max = d.iter().fold(0.0f64, |m, &x| m.max(x));
            *max_sq = max_sq.max(row_sq_max);
            Some(row_sq_max.sqrt()).filter(|&m| m > stop_above)
        };
        let mut out = Vec::new();
        for k in 0..mu {
            if k == 0
                && let Some(m) = load(0, &mut cur, &mut max_sq)
            {
                return (m, Vec::new());
            }
            if k + 1 < mu
                && let Some(m) = load(k + 1, &mut next, &mut max_sq)
            {
                return (m, Vec::new());
            }
            for l in 0..mv {
                if cur[l] <= below {
                    continue;
                }
                let x = cur[l].sqrt();
                if !(x > thresh) {
                    continue;
                }
                let nb = [
                    (k > 0).then(|| prev[l]),
                    (k + 1 < mu).then(|| next[l]),
                    (l > 0).then(|| cur[l - 1]),
                    (l + 1 < mv).then(|| cur[l + 1]),
                ];
                if nb.iter().flatten().all(|&y| y.sqrt() <= x) {
                    out.push((x, self.u.params[k], self.v.params[l]));
                }
            }
            std::mem::swap(&mut prev, &mut cur);
            std::mem::swap(&mut cur, &mut next);
        }
        let max = max_sq.sqrt();
        (max, out)
    }

    /// The knot-span cells (by span indices) whose nodes [`Self::change_peaks`] must evaluate: those with
    /// a control point of the free block `fu × fv` that moved by more than `thresh · (1 − 1e-9)` among the
    /// (pu + 1)(pv + 1) that a node of the cell is evaluated from (a node's span is the one its basis
    /// values were computed in, so its change is a convex combination of exactly those moves). `None` if
    /// there is no such cell.
    fn hot_cells(
        &self,
        a: &BSplineSurface,
        b: &BSplineSurface,
        fu: &Range<usize>,
        fv: &Range<usize>,
        thresh: f64,
    ) -> Option<SpanMask> {
        let (nu, nv) = (a.nu(), a.nv());
        let (pu, pv) = (self.pu, self.pv);
        let (pa, pb) = (a.points(), b.points());
        let limit = thresh * (1.0 - 1e-9);
        // a cell (span su, sv) is evaluated from the control points su − pu ..= su, sv − pv ..= sv: a point
        // that moved by more than `limit` (NaN-safe) makes the cells su ∈ i ..= i + pu, sv ∈ j ..= j + pv hot
        let mut hot = SpanMask::new(nu, nv);
        let mut any = false;
        for i in fu.clone() {
            for j in fv.clone() {
                if !((pb[i * nv + j] - pa[i * nv + j]).length() <= limit) {
                    any = true;
                    for su in i..(i + pu + 1).min(nu) {
                        for sv in j..(j + pv + 1).min(nv) {
                            hot.set(su, sv);
                        }
                    }
                }
            }
        }
        if !any {
            return None;
        }
        Some(hot)
    }

    pub(super) fn new(s: &BSplineSurface, cu: &[f64], cv: &[f64], threads: Option<usize>) -> Self {
        let v = GridBasis::new(s.knots_v(), cv);
        let pv = s.degree_v();
        let mut v_runs = Vec::new();
        let mut l0 = 0;
        while l0 < v.spans.len() {
            let sp = v.spans[l0];
            let l1 = l0 + v.spans[l0..].iter().take_while(|&&x| x == sp).count();
            v_runs.push((sp, l0, l1));
            l0 = l1;
        }
        let v_vals_t = (v_runs.iter())
            .map(|&(_, l0, l1)| {
                (0..=pv)
                    .flat_map(|jb| v.vals[l0..l1].iter().map(move |n| n[jb]))
                    .collect()
            })
            .collect();
        Self {
            u: GridBasis::new(s.knots_u(), cu),
            v,
            pu: s.degree_u(),
            pv,
            threads,
            v_runs,
            v_vals_t,
        }
    }

    /// Upper bound of the deviation between `a` (the original) and `b` (same
    /// knots, control points differing only in the block `fu × fv`) on the
    /// grid: `|S_b − S_a|` at every sample, sharpened by Newton projections
    /// in both directions where it exceeds `m`. With `stop_early`, returns
    /// the first sharpened value above `m` (a proof that the band is broken,
    /// not the maximum).
    pub(super) fn deviation(
        &self,
        a: &BSplineSurface,
        b: &BSplineSurface,
        fu: &Range<usize>,
        fv: &Range<usize>,
        m: f64,
        stop_early: bool,
    ) -> f64 {
        let nv = a.nv();
        let nfv = fv.len();
        let (mu, mv) = (self.u.params.len(), self.v.params.len());
        // T[k][jj] = Σ_a N_a(u_k) ΔD[i][fv.start + jj]
        let mut tmp = vec![DVec3::ZERO; mu * nfv];
        let (pa, pb) = (a.points(), b.points());
        for k in 0..mu {
            let sp = self.u.spans[k];
            for ia in 0..=self.pu {
                let i = sp - self.pu + ia;
                if !fu.contains(&i) {
                    continue;
                }
                let w = self.u.vals[k][ia];
                let row = &mut tmp[k * nfv..(k + 1) * nfv];
                for (jj, t) in row.iter_mut().enumerate() {
                    let idx = i * nv + fv.start + jj;
                    *t += (pb[idx] - pa[idx]) * w;
                }
            }
        }
        // rows in fixed chunks, in parallel; each chunk returns (its max, whether it stopped at a violation)
        let chunks: Vec<(usize, Range<usize>)> = (0..mu)
            .step_by(CHECK_ROWS_PER_TASK)
            .map(|k0| k0..(k0 + CHECK_ROWS_PER_TASK).min(mu))
            .enumerate()
            .collect();
        // with stop_early, chunks after one that proved a violation need not finish (the result is the
        // violation of the first such chunk in grid order, as a sequential scan would return)
        let first_violation = std::sync::atomic::AtomicUsize::new(usize::MAX);
        let per_chunk = par_map(&chunks, self.threads, |(c, rows)| {
            let mut max = 0.0f64;
            for k in rows.clone() {
                if stop_early && first_violation.load(std::sync::atomic::Ordering::Relaxed) < *c {
                    return (max, false);
                }
                for l in 0..mv {
                    let sp = self.v.spans[l];
                    let mut d = DVec3::ZERO;
                    for jb in 0..=self.pv {
                        let j = sp - self.pv + jb;
                        if fv.contains(&j) {
                            d += tmp[k * nfv + j - fv.start] * self.v.vals[l][jb];
                        }
                    }
                    let mut dist = d.length();
                    if dist > m {
                        let (u, v) = (self.u.params[k], self.v.params[l]);
                        let (qa, qb) = (a.point(u, v), b.point(u, v));
                        let d1 = newton_project(b, qa, (u, v)).distance;
                        let d2 = newton_project(a, qb, (u, v)).distance;
                        dist = dist.min(d1.max(d2));
                        if stop_early && dist > m {
                            first_violation.fetch_min(*c, std::sync::atomic::Ordering::Relaxed);
                            return (dist, true);
                        }
                    }
                    max = max.max(dist);
                }
            }
            (max, false)
        });
        // with stop_early: the first chunk (in grid order) that proved a violation
        if let Some(&(d, _)) = per_chunk.iter().find(|c| c.1) {
            return d;
        }
        per_chunk.iter().fold(0.0f64, |acc, c| acc.max(c.0))
    }
}
