//! Isophotes of a surface and their waviness ([`isophote_waviness`]): the reflection lines a designer
//! looks at, traced on a uv grid, and the sign changes of their geodesic curvature.

use glam::DVec3;

use crate::surface::BSplineSurface;

/// Light direction (normalized on use) of the isophotes in [`surface_measures`](crate::measure_surface::surface_measures).
pub const ISOPHOTE_LIGHT: [f64; 3] = [1.0, 1.0, 1.0];
/// Angle between successive isophotes in [`surface_measures`](crate::measure_surface::surface_measures), degrees.
pub const ISOPHOTE_STEP_DEG: f64 = 2.0;
/// uv grid nodes per knot span (and direction) on which the isophotes are traced (at least
/// `ISOPHOTE_MIN_NODES` per direction).
pub(crate) const ISOPHOTE_GRID_PER_SPAN: usize = 8;
/// Least number of uv grid nodes per direction of the isophote tracing.
pub(crate) const ISOPHOTE_MIN_NODES: usize = 240;
/// Most uv grid nodes per direction of the isophote tracing (memory and time stay bounded for huge nets;
/// beyond 128 spans fewer than 8 nodes per span, still ≥ 12 nodes per resampling step D/80).
pub(crate) const ISOPHOTE_MAX_NODES: usize = 1024;
/// Arc-length step of the resampled isophotes relative to D, the bounding-box diagonal.
pub(crate) const ISOPHOTE_STEP_REL: f64 = 1.0 / 80.0;
/// Dead band of the isophote inflection count: `ISOPHOTE_DEAD_BAND / D`, D the diagonal of the bounding
/// box of the surface's samples (an isophote must bend both ways with a radius below D / 2 to count).
pub const ISOPHOTE_DEAD_BAND: f64 = 2.0;

/// Isophote waviness of a surface ([`isophote_waviness`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct IsophoteStats {
    /// Isophote polylines traced (open or closed), of any length.
    pub n_isophotes: usize,
    /// Total geodesic-curvature sign changes (with the dead band) over all isophotes.
    pub n_inflections: usize,
    /// The dead band τ used (1/length).
    pub dead_band: f64,
}

/// Isophote waviness: sign changes of the geodesic curvature along the isophotes (module docs).
///
/// Definition. The isophotes of the light direction `light` are the level lines of `n·L` (n the unit
/// normal `S_u × S_v`) at the angles `arccos(n·L) = k · step_deg`, k = 1, 2, …: the reflection lines
/// a designer looks at. They are traced by marching squares on a uv grid of
/// `ISOPHOTE_GRID_PER_SPAN` nodes per knot span (at least `ISOPHOTE_MIN_NODES` per direction, at
/// most `ISOPHOTE_MAX_NODES`, then uniform in the parameter;
/// the ambiguous saddle cells resolved by the cell-centre value), linked into polylines, mapped to 3D
/// by linear interpolation of the node positions and normals along the crossed grid edges, and
/// resampled at equal arc length with a step `h = D ·` `ISOPHOTE_STEP_REL` (D the bounding-box
/// diagonal of the grid samples; a geometric scale, not the grid's, so refining the grid changes the
/// count only where it was unresolved; the grid's kinks average out). At each inner
/// resampled point the signed geodesic curvature is `κ_g = ∠(a, b) / h` with the turning angle
/// between the chords `a`, `b` before and after it, signed by `(a × b)·n` (intrinsic: it does not
/// depend on the parameterization). Sign changes are counted with hysteresis: a change counts only
/// when κ_g goes from above `τ` to below `−τ` or back, with `τ = dead_band_factor / D`, D the
/// bounding-box diagonal of the grid samples (scale-invariant: the same count for a scaled copy).
/// A plane has no isophotes, a cylinder straight ones and a sphere circles: 0 for all three; a noisy
/// surface's isophotes wiggle and count many. Cost: one `derivs` per grid node plus O(isophote length).
pub fn isophote_waviness(s: &BSplineSurface, light: DVec3, step_deg: f64, dead_band_factor: f64) -> IsophoteStats {
    let l = light.normalize_or_zero();
    let mut out = IsophoteStats::default();
    if l == DVec3::ZERO || !(step_deg > 0.0 && step_deg.is_finite()) {
        return out;
    }
    let g = IsophoteGrid::new(s, l);
    if !(g.diag > 0.0 && g.diag.is_finite()) {
        return out;
    }
    let tau = dead_band_factor / g.diag;
    out.dead_band = tau;
    let h = ISOPHOTE_STEP_REL * g.diag;
    let (fmin, fmax) =
        g.f.iter()
            .filter(|x| x.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    let mut adj = vec![[NO_EDGE; 2]; g.n_edges()];
    let mut tracer = ChainTracer::new(g.n_edges());
    let mut k = 1usize;
    loop {
        let theta = (k as f64 * step_deg).to_radians();
        k += 1;
        if theta >= std::f64::consts::PI {
            break;
        }
        let c = theta.cos();
        if c < fmin || c > fmax {
            continue;
        }
        g.link_crossings(c, &mut adj);
        tracer.trace(&g, &adj, c, h, tau, &mut out);
    }
    out
}

/// No neighbour: the end of a chain of crossed grid edges.
const NO_EDGE: u32 = u32::MAX;

/// The uv grid of [`isophote_waviness`]: node positions, unit normals and `n·L` (NaN where the normal
/// is undefined), u outer and v inner; its edges are the u-edges (i,j)-(i+1,j) then the v-edges
/// (i,j)-(i,j+1).
struct IsophoteGrid {
    nu: usize,
    nv: usize,
    pos: Vec<DVec3>,
    nrm: Vec<DVec3>,
    f: Vec<f64>,
    diag: f64,
}

/// The grid parameters of one direction: `ISOPHOTE_GRID_PER_SPAN` a span (at least
/// `ISOPHOTE_MIN_NODES` in all), or `ISOPHOTE_MAX_NODES` uniform in the parameter.
fn isophote_grid_params(k: &crate::knots::KnotVector) -> Vec<f64> {
    let bp = k.breakpoints();
    let spans = bp.len().saturating_sub(1).max(1);
    let per = ISOPHOTE_GRID_PER_SPAN.max(ISOPHOTE_MIN_NODES.div_ceil(spans));
    if spans * per + 1 > ISOPHOTE_MAX_NODES {
        let (a, b) = (bp[0], *bp.last().unwrap());
        let n = ISOPHOTE_MAX_NODES - 1;
        return (0..=n).map(|j| a + (b - a) * j as f64 / n as f64).collect();
    }
    let mut t = Vec::with_capacity(spans * per + 1);
    for w in bp.windows(2) {
        for j in 0..per {
            t.push(w[0] + (w[1] - w[0]) * j as f64 / per as f64);
        }
    }
    t.push(*bp.last().unwrap());
    t
}

impl IsophoteGrid {
    fn new(s: &BSplineSurface, l: DVec3) -> Self {
        let (us, vs) = (isophote_grid_params(s.knots_u()), isophote_grid_params(s.knots_v()));
        let (nu, nv) = (us.len(), vs.len());
        let mut pos = Vec::with_capacity(nu * nv);
        let mut nrm = Vec::with_capacity(nu * nv);
        let mut f = Vec::with_capacity(nu * nv);
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for &u in &us {
            for &v in &vs {
                let d = s.derivs(u, v);
                let n = d.su.cross(d.sv).normalize_or_zero();
                pos.push(d.p);
                nrm.push(n);
                f.push(if n == DVec3::ZERO { f64::NAN } else { n.dot(l) });
                lo = lo.min(d.p);
                hi = hi.max(d.p);
            }
        }
        Self {
            nu,
            nv,
            pos,
            nrm,
            f,
            diag: (hi - lo).length(),
        }
    }

    fn n_u_edges(&self) -> usize {
        (self.nu - 1) * self.nv
    }

    fn n_edges(&self) -> usize {
        self.n_u_edges() + self.nu * (self.nv - 1)
    }

    /// The two nodes of edge `e`.
    fn ends(&self, e: usize) -> (usize, usize) {
        let (n_ue, nv) = (self.n_u_edges(), self.nv);
        if e < n_ue {
            (e, e + nv)
        } else {
            let k = e - n_ue;
            let (i, j) = (k / (nv - 1), k % (nv - 1));
            (i * nv + j, i * nv + j + 1)
        }
    }

    /// Link the edges the level `n·L = c` crosses, cell by cell (marching squares; a saddle cell
    /// resolved by its centre value): `adj[e]` the up to two neighbours of edge `e`.
    fn link_crossings(&self, c: f64, adj: &mut [[u32; 2]]) {
        let (nu, nv, f) = (self.nu, self.nv, &self.f);
        let n_ue = self.n_u_edges();
        let ue = |i: usize, j: usize| i * nv + j;
        let ve = |i: usize, j: usize| n_ue + i * (nv - 1) + j;
        let above = |node: usize| f[node] >= c;
        let crossed = |e: usize| {
            let (a, b) = self.ends(e);
            f[a].is_finite() && f[b].is_finite() && above(a) != above(b)
        };
        adj.fill([NO_EDGE; 2]);
        let mut link = |a: usize, b: usize| {
            for (x, y) in [(a, b), (b, a)] {
                let s = &mut adj[x];
                if s[0] == NO_EDGE {
                    s[0] = y as u32;
                } else if s[1] == NO_EDGE {
                    s[1] = y as u32;
                }
            }
        };
        for i in 0..nu - 1 {
            for j in 0..nv - 1 {
                let e = [ue(i, j), ve(i + 1, j), ue(i, j + 1), ve(i, j)];
                let cr = e.map(crossed);
                let n_cr = cr.iter().filter(|&&x| x).count();
                if n_cr == 2 {
                    let mut it = (0..4).filter(|&q| cr[q]);
                    let (p, q) = (it.next().unwrap(), it.next().unwrap());
                    link(e[p], e[q]);
                } else if n_cr == 4 {
                    let corners = [i * nv + j, (i + 1) * nv + j, (i + 1) * nv + j + 1, i * nv + j + 1];
                    let centre = corners.iter().map(|&q| f[q]).sum::<f64>() * 0.25;
                    if (centre >= c) == above(corners[0]) {
                        link(e[0], e[1]);
                        link(e[2], e[3]);
                    } else {
                        link(e[3], e[0]);
                        link(e[1], e[2]);
                    }
                }
            }
        }
    }
}

/// Follows the linked crossed edges of one level into isophotes and counts their inflections; its
/// buffers are reused from level to level.
struct ChainTracer {
    seen: Vec<bool>,
    chain: Vec<usize>,
    pts: Vec<(DVec3, DVec3)>,
    kappa: Vec<f64>,
}

impl ChainTracer {
    fn new(n_edges: usize) -> Self {
        Self {
            seen: vec![false; n_edges],
            chain: Vec::new(),
            pts: Vec::new(),
            kappa: Vec::new(),
        }
    }

    /// Trace the isophotes of level `c` (open chains first, from an end, then closed loops), map each
    /// to 3D by interpolating positions and normals along the crossed edges, and add its count and
    /// sign changes to `out`.
    fn trace(&mut self, g: &IsophoteGrid, adj: &[[u32; 2]], c: f64, h: f64, tau: f64, out: &mut IsophoteStats) {
        self.seen.fill(false);
        for pass in 0..2 {
            for start in 0..adj.len() {
                if self.seen[start] || adj[start][0] == NO_EDGE {
                    continue;
                }
                let is_end = adj[start][1] == NO_EDGE;
                if (pass == 0) != is_end {
                    continue;
                }
                self.follow(adj, start);
                let closed = pass == 1;
                if closed {
                    self.chain.push(start);
                }
                out.n_isophotes += 1;
                self.pts.clear();
                for &e in &self.chain {
                    let (a, b) = g.ends(e);
                    let t = (g.f[a] - c) / (g.f[a] - g.f[b]);
                    let p = g.pos[a] + (g.pos[b] - g.pos[a]) * t;
                    let n = (g.nrm[a] + (g.nrm[b] - g.nrm[a]) * t).normalize_or_zero();
                    self.pts.push((p, n));
                }
                out.n_inflections += sign_changes(&self.pts, h, tau, &mut self.kappa, closed);
            }
        }
    }

    /// The chain of unseen linked edges from `start`, into `self.chain`.
    fn follow(&mut self, adj: &[[u32; 2]], start: usize) {
        self.chain.clear();
        let (mut prev, mut cur) = (usize::MAX, start);
        loop {
            self.seen[cur] = true;
            self.chain.push(cur);
            let nb = adj[cur];
            let next = if nb[0] != NO_EDGE && nb[0] as usize != prev && !self.seen[nb[0] as usize] {
                nb[0] as usize
            } else if nb[1] != NO_EDGE && nb[1] as usize != prev && !self.seen[nb[1] as usize] {
                nb[1] as usize
            } else {
                break;
            };
            prev = cur;
            cur = next;
        }
    }
}

/// Resample the polyline at arc-length step `h` and count the hysteresis sign changes of its turning
/// curvature (see [`isophote_waviness`]).
pub(super) fn sign_changes(pts: &[(DVec3, DVec3)], h: f64, tau: f64, kappa: &mut Vec<f64>, closed: bool) -> usize {
    // resample
    let mut res: Vec<(DVec3, DVec3)> = Vec::new();
    if pts.len() < 2 {
        return 0;
    }
    res.push(pts[0]);
    let (mut acc, mut next) = (0.0, h); // arc length at the segment start, of the next sample
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = a.0.distance(b.0);
        while len > 0.0 && next <= acc + len {
            let t = (next - acc) / len;
            res.push((a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t));
            next += h;
        }
        acc += len;
    }
    if closed && res.len() > 3 {
        // wrap around: the first two points follow the last
        let (r0, r1) = (res[0], res[1]);
        res.push(r0);
        res.push(r1);
    }
    kappa.clear();
    for w in res.windows(3) {
        let (a, b) = (w[1].0 - w[0].0, w[2].0 - w[1].0);
        let x = a.cross(b);
        let sgn = x.dot(w[1].1).signum();
        let ang = x.length().atan2(a.dot(b));
        kappa.push(sgn * ang / h);
    }
    let mut state = 0i8;
    let mut count = 0;
    for &k in kappa.iter() {
        if k > tau {
            if state < 0 {
                count += 1;
            }
            state = 1;
        } else if k < -tau {
            if state > 0 {
                count += 1;
            }
            state = -1;
        }
    }
    count
}
