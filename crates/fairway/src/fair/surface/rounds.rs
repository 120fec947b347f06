//! The isocurve rounds of the surface engine (module docs of [`super`], steps 3–7): each round fairs the
//! isocurves at one tolerance level, fits the smoothing strengths to the combined cloud and checks the band.

use std::ops::ControlFlow;
use std::time::Instant;

use glam::DVec3;

use super::*;
/// The fairest candidate of a level holding the band: (points, dev, m_iso, smoothing, round, energy).
type Pick = (Vec<DVec3>, f64, f64, SurfaceSmoothing, usize, f64);

/// A fitted candidate of one level: (smoothing, points, surface).
type Fitted = (SurfaceSmoothing, Vec<DVec3>, BSplineSurface);

/// The state of the isocurve rounds (module docs, steps 5–7) of [`isocurve_rounds`].
struct Rounds<'g, 'a> {
    g: &'g Grids<'a>,
    opts: &'g SurfaceFairingOptions,
    /// The smoothing strengths tried (`AUTO_STRENGTHS`, or the options' smoothing alone as NaN).
    ladder: &'static [f64],
    /// Fairness energy over the moving rectangle (auto-smoothing selection, module docs step 6).
    energy: Option<FairnessGrid>,
    grid_fit: GridFit<'a>,
    tm: SurfaceTimings,
    /// The isocurve tolerance of the round and the rounds so far.
    m_iso: f64,
    rounds: usize,
    /// The candidate of least deviation so far: (points, dev).
    best: Option<(Vec<DVec3>, f64)>,
    /// The fairest candidate holding the band so far.
    pick: Option<Pick>,
}

/// Steps 3–7: the isocurve rounds, each fitting the smoothing strengths to its level's cloud and checking
/// the band; the fairest band-holding candidate, or the α fallback when no round held the band.
pub(super) fn isocurve_rounds(
    g: &Grids<'_>,
    opts: &SurfaceFairingOptions,
    tm: SurfaceTimings,
) -> Result<SurfaceFairingResult> {
    let m = g.m;
    let mut r = Rounds {
        g,
        opts,
        ladder: if opts.auto_smoothing {
            &AUTO_STRENGTHS
        } else {
            &[f64::NAN]
        },
        energy: opts.auto_smoothing.then(|| FairnessGrid::new(g.s, g.rect.0, g.rect.1)),
        grid_fit: GridFit::new(g.s, &g.us, &g.vs, g.free_u.clone(), g.free_v.clone())?,
        tm,
        m_iso: m,
        rounds: 0,
        best: None,
        pick: None,
    };
    let max_rounds = if opts.auto_smoothing {
        MAX_ROUNDS.max(opts.iso_levels.max(1))
    } else {
        MAX_ROUNDS
    };
    let mut level_clouds = r.level_clouds()?;
    for _ in 0..max_rounds {
        crate::cancel::check()?;
        r.rounds += 1;
        let data = match level_clouds.iter().position(|(l, _)| *l == r.m_iso) {
            Some(i) => level_clouds.swap_remove(i).1,
            None => r.cloud(&[r.m_iso])?.pop().expect("one level"),
        };
        let (rhs, cands) = r.fit_level(&data)?;
        let level_best = match r.check_level(cands)? {
            ControlFlow::Break(done) => return Ok(done),
            ControlFlow::Continue(level_best) => level_best,
        };
        if r.next_level(level_best, &rhs)? {
            break;
        }
    }
    r.finish()
}

impl Rounds<'_, '_> {
    /// Step 3–4: the combined clouds of the isocurves faired at each tolerance of `levels`.
    fn cloud(&mut self, levels: &[f64]) -> Result<Vec<Vec<DVec3>>> {
        let g = self.g;
        combined_cloud(g.s, self.opts, levels, g.ru, g.rv, &g.us, &g.vs, &g.orig, &mut self.tm)
    }

    /// The clouds of the levels made up front: with auto smoothing, those of all `iso_levels` levels m,
    /// m/3, m/9, … are made in the first round (the correction of the pass at m scaled by 1/3, 1/9, … or,
    /// with `refair_levels`, the isocurves faired at each tolerance: one setup per isocurve, re-faired per
    /// level). The rounds that step down a level take their cloud from here; a tightening round (no level
    /// held the band) fairs the isocurves at its own m_iso.
    fn level_clouds(&mut self) -> Result<Vec<(f64, Vec<DVec3>)>> {
        let opts = self.opts;
        let mut level_clouds: Vec<(f64, Vec<DVec3>)> = Vec::new();
        if opts.auto_smoothing && opts.iso_levels > 1 {
            let mut levels = vec![self.m_iso];
            for _ in 1..opts.iso_levels {
                levels.push(levels[levels.len() - 1] * ISO_LEVEL_FACTOR);
            }
            let clouds = if opts.refair_levels {
                self.cloud(&levels)?
            } else {
                let first = self.cloud(&levels[..1])?;
                let first = first.into_iter().next().expect("one level");
                let t0 = Instant::now();
                let orig = &self.g.orig;
                let scaled = levels
                    .iter()
                    .map(|l| {
                        let a = l / levels[0];
                        first.iter().zip(orig).map(|(c, o)| *o + (*c - *o) * a).collect()
                    })
                    .collect();
                self.tm.combine += t0.elapsed();
                scaled
            };
            level_clouds = levels.into_iter().zip(clouds).collect();
        }
        Ok(level_clouds)
    }

    /// Step 5 for one level's cloud `data`: the fits of the strengths tried (all of the ladder in the first
    /// level, after it the pick's and its two neighbours'), in parallel. Returns the projected data term and
    /// the candidates in ladder order (their fairness energies follow in [`Self::check_level`]).
    fn fit_level(&mut self, data: &[DVec3]) -> Result<(Vec<DVec3>, Vec<Result<Fitted>>)> {
        let (s, opts, ladder) = (self.g.s, self.opts, self.ladder);
        // the fits are independent: computed in parallel, then checked in order
        let t0 = Instant::now();
        // After the first level only the pick's strength and its two neighbours on the ladder are fitted
        // (module docs, step 6): the fairest strength moves little from one level to the next.
        let near: Vec<f64> = match &self.pick {
            Some(pk) => {
                let i = ladder.iter().position(|&x| x == pk.3.strength_u).unwrap_or(0);
                ladder[i.saturating_sub(1)..(i + 2).min(ladder.len())].to_vec()
            }
            _ => ladder.to_vec(),
        };
        // the data term is the same for every strength: projected once per level
        let rhs = self.grid_fit.project(data)?;
        let grid_fit = &self.grid_fit;
        let cands = par_map(&near, self.g.threads, |&st| {
            let sm = if st.is_nan() {
                opts.smoothing
            } else {
                SurfaceSmoothing {
                    strength_u: st,
                    strength_v: st,
                    order: opts.smoothing.order,
                }
            };
            let pts = grid_fit.solve(&rhs, sm)?;
            let faired = s.with_points(pts.clone())?;
            Ok::<_, Error>((sm, pts, faired))
        });
        self.tm.fit += t0.elapsed();
        Ok((rhs, cands))
    }

    /// Step 7 for one level's candidates, in order: the band check (coarse, then full) of each candidate
    /// fairer than the level's best. Without auto smoothing the first that holds the band is the result
    /// (`Break`); otherwise returns the level's fairest band-holding candidate. Every checked candidate
    /// competes for the least deviation (`self.best`). The fairness energies (auto smoothing) are computed
    /// when the first candidate holds the band, for it and the candidates after it, in parallel: the ones
    /// before it were checked against no level best, so their energies were never read (on a draft of the
    /// 30 × 30 bench net the two strongest strengths break the band: 2 of 8 energies).
    fn check_level(&mut self, cands: Vec<Result<Fitted>>) -> Result<ControlFlow<SurfaceFairingResult, Option<Pick>>> {
        let g = self.g;
        let (s, m, m_iso, rounds) = (g.s, g.m, self.m_iso, self.rounds);
        let mut level_best: Option<Pick> = None;
        let mut energies: Vec<Option<f64>> = vec![None; cands.len()];
        for (i, cand) in cands.iter().enumerate() {
            let (sm, pts, faired) = cand.as_ref().map_err(Clone::clone)?;
            let sm = *sm;
            let t1 = Instant::now();
            // with auto smoothing: a candidate no fairer than the level's best is not checked
            if let (Some(e), Some(lb)) = (energies[i], level_best.as_ref())
                && e >= lb.5
            {
                self.tm.verify += t1.elapsed();
                continue;
            }
            // coarse check first (cheap), the full check only for a candidate that passes it
            if g.coarse_check.deviation(s, faired, &g.free_u, &g.free_v, m, true) > m {
                self.tm.verify += t1.elapsed();
                continue;
            }
            let dev = g.full_check.deviation(s, faired, &g.free_u, &g.free_v, m, false);
            self.tm.verify += t1.elapsed();
            if dev <= m {
                let Some(eg) = &self.energy else {
                    return Ok(ControlFlow::Break(g.iso_result(
                        faired.clone(),
                        dev,
                        (m_iso, rounds, 1.0),
                        sm,
                        self.tm,
                    )));
                };
                if level_best.is_none() {
                    let t0 = Instant::now();
                    let es = par_map(&cands[i..], g.threads, |c| c.as_ref().ok().map(|c| eg.energy(&c.2)));
                    energies[i..].copy_from_slice(&es);
                    self.tm.fit += t0.elapsed();
                }
                let e = energies[i].expect("the energy of a band-holding candidate");
                level_best = Some((pts.clone(), dev, m_iso, sm, rounds, e));
            }
            if self.best.as_ref().is_none_or(|b| dev < b.1) {
                self.best = Some((pts.clone(), dev));
            }
        }
        Ok(ControlFlow::Continue(level_best))
    }

    /// Step 6/7 after a level: a fairer level's pick is kept and the next level (m_iso / 3) follows, until
    /// a level is no fairer or `iso_levels` are done; with no band-holding candidate yet, the isocurve
    /// tolerance is tightened by the least deviation so far (`rhs`: the level's projected data, fitted with
    /// the options' smoothing when nothing was checked). Returns whether the rounds stop.
    fn next_level(&mut self, level_best: Option<Pick>, rhs: &[DVec3]) -> Result<bool> {
        let g = self.g;
        if let Some(lb) = level_best {
            let improved = self.pick.as_ref().is_none_or(|p| lb.5 < p.5);
            if improved {
                self.pick = Some(lb);
            }
            if !improved || self.rounds >= self.opts.iso_levels.max(1) {
                return Ok(true);
            }
            self.m_iso *= ISO_LEVEL_FACTOR;
            return Ok(false);
        }
        if self.pick.is_some() {
            self.m_iso *= ISO_LEVEL_FACTOR;
            return Ok(false);
        }
        if self.best.is_none() {
            let t0 = Instant::now();
            let pts = self.grid_fit.solve(rhs, self.opts.smoothing)?;
            let t1 = Instant::now();
            self.tm.fit += t1 - t0;
            let dev = g
                .full_check
                .deviation(g.s, &g.s.with_points(pts.clone())?, &g.free_u, &g.free_v, g.m, false);
            self.tm.verify += t1.elapsed();
            self.best = Some((pts, dev));
        }
        let dev = self.best.as_ref().unwrap().1;
        self.m_iso *= 0.8 * g.m / dev;
        Ok(false)
    }

    /// The result of the rounds: the pick, or (no candidate held the band) the α fallback, the largest
    /// α ∈ [0, 1] whose blend `S + α (S_best − S)` of the least-deviation candidate holds the band, bisected.
    fn finish(self) -> Result<SurfaceFairingResult> {
        let g = self.g;
        let (s, m) = (g.s, g.m);
        let mut tm = self.tm;
        if let Some((pts, dev, m_iso, sm, round, _)) = self.pick {
            return Ok(g.iso_result(s.with_points(pts)?, dev, (m_iso, round, 1.0), sm, tm));
        }
        // α fallback: bisect the largest α ∈ [0, 1] whose blend holds the band
        let (pts, _) = self.best.expect("at least one round");
        let blend = |alpha: f64| -> Vec<DVec3> {
            s.points()
                .iter()
                .zip(&pts)
                .map(|(a, b)| *a + (*b - *a) * alpha)
                .collect()
        };
        let t0 = Instant::now();
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        let mut lo_dev = 0.0;
        for _ in 0..20 {
            let mid = 0.5 * (lo + hi);
            let f = s.with_points(blend(mid))?;
            let d = g.full_check.deviation(s, &f, &g.free_u, &g.free_v, m, true);
            if d <= m {
                lo = mid;
                lo_dev = d;
            } else {
                hi = mid;
            }
            if hi - lo < 1e-4 {
                break;
            }
        }
        tm.verify += t0.elapsed();
        let surface = s.with_points(blend(lo))?;
        Ok(g.iso_result(surface, lo_dev, (self.m_iso, self.rounds, lo), self.opts.smoothing, tm))
    }
}
