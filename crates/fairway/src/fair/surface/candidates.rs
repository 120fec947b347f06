//! Step 8 of the surface engine (module docs of [`super`]): the fairest of the original, the isocurve
//! result, the reference smoother's answers and their blends.

use std::time::Instant;

use glam::DVec3;

use super::*;
/// A candidate of step 8: (rank, pick, surface, deviation bound, strength).
type Cand = (Rank, SurfacePick, BSplineSurface, f64, f64);

/// Step 8 (module docs): the fairest of the original, the isocurve result `result`, the reference
/// smoother's answers and their blends ([`smoother_candidates`], [`blend_candidates`], [`pick_fairest`]).
pub(super) fn fairest_candidate(g: &Grids<'_>, mut result: SurfaceFairingResult) -> Result<SurfaceFairingResult> {
    let s = g.s;
    let t0 = Instant::now();
    let grid_fit = GridFit::new(s, &g.us, &g.vs, g.free_u.clone(), g.free_v.clone())?;
    let plate = plate_fit(s, &grid_fit, &g.us, &g.vs, REFERENCE_ORDER)?;
    let fine = g.fine_check();
    let bands = g.bands(&fine);
    let ranker = Ranker::new(s, g.rect);
    let mut cands = smoother_candidates(g, &result, &grid_fit, &plate, &bands, &ranker)?;
    blend_candidates(g, &mut cands, &bands, &ranker)?;
    let (_, kind, f, mut dev, st) = pick_fairest(cands);
    if matches!(
        kind,
        SurfacePick::Reference | SurfacePick::Combined | SurfacePick::Blend
    ) {
        // the candidates were accepted by the quick check (same verdict, a bound that is not the fine
        // grid's maximum): the pick's figure from the full check
        dev = bands.holds(s, &f).unwrap_or(dev);
    }
    if kind != SurfacePick::Isocurves {
        result.surface = f;
        result.max_deviation = dev;
        result.alpha = if kind == SurfacePick::Original { 0.0 } else { 1.0 };
        result.smoothing = SurfaceSmoothing {
            strength_u: st,
            strength_v: st,
            order: REFERENCE_ORDER,
        };
        result.pick = kind;
    }
    result.timings.reference += t0.elapsed();
    Ok(result)
}

/// Step 8's first candidates, ranked: the original, the isocurve result `result` and the reference
/// smoother's strongest band-holding nets on the original's samples and on the isocurve result's.
fn smoother_candidates(
    g: &Grids<'_>,
    result: &SurfaceFairingResult,
    grid_fit: &GridFit<'_>,
    plate: &PlateFit<'_, '_>,
    bands: &Bands<'_>,
    ranker: &Ranker,
) -> Result<Vec<Cand>> {
    let (s, threads) = (g.s, g.threads);
    let mut cands: Vec<Cand> = vec![
        (ranker.rank(s), SurfacePick::Original, s.clone(), 0.0, 0.0),
        (
            ranker.rank(&result.surface),
            SurfacePick::Isocurves,
            result.surface.clone(),
            result.max_deviation,
            result.smoothing.strength_u,
        ),
    ];
    // the smoother on the original's samples (the reference; its answer is the largest band-holding
    // strength) and on the isocurve result's: independent searches
    let iso_grid = grid_points(&result.surface, &g.us, &g.vs);
    let rhs = [grid_fit.project(&g.orig)?, grid_fit.project(&iso_grid)?];
    let factors = PlateFactors::new(plate);
    let searches = par_map(&rhs, threads, |r| plate_search(s, plate, &factors, r, bands));
    let [reference, combined]: [_; 2] = (searches.into_iter().collect::<Result<Vec<_>>>()?)
        .try_into()
        .map_err(|_| Error::Solve("surface smoothing: one search per data set".into()))?;
    // the searches' strongest band-holding strengths, ranked in parallel (the ranking is most of step 8's cost)
    let mut found = Vec::new();
    for (pick, all) in [(SurfacePick::Reference, reference), (SurfacePick::Combined, combined)] {
        let keep = all.len().saturating_sub(SEARCH_CANDIDATES);
        for (pts, dev, st) in all.into_iter().skip(keep) {
            found.push((pick, s.with_points(pts)?, dev, st));
        }
    }
    let ranks = par_map(&found, threads, |c| ranker.rank(&c.1));
    cands.extend(
        found
            .into_iter()
            .zip(ranks)
            .map(|((pick, f, dev, st), r)| (r, pick, f, dev, st)),
    );
    Ok(cands)
}

/// Step 8's blends, ranked and appended to `cands`: pairs of anchors — the isocurve result, the
/// reference's answer and the fairest net of the smoother run on the isocurve result — blended by
/// `BLENDS`; |S_blend − S| is at most the larger of the two nets' changes at every point, and each blend
/// is checked on the fine grid again.
fn blend_candidates(g: &Grids<'_>, cands: &mut Vec<Cand>, bands: &Bands<'_>, ranker: &Ranker) -> Result<()> {
    let s = g.s;
    let mut anchors: Vec<usize> = vec![1];
    if let Some(i) = cands.iter().rposition(|c| c.1 == SurfacePick::Reference) {
        anchors.push(i);
    }
    let best_combined = (cands.iter().enumerate())
        .filter(|(_, c)| c.1 == SurfacePick::Combined)
        .min_by(|a, b| a.1.0.partial_cmp(&b.1.0).unwrap_or(std::cmp::Ordering::Equal))
        .map(|(i, _)| i);
    anchors.extend(best_combined);
    let mut blends = Vec::new();
    for (k, &i) in anchors.iter().enumerate() {
        for &j in &anchors[k + 1..] {
            crate::cancel::check()?;
            for w in BLENDS {
                let pts: Vec<DVec3> = (cands[i].2.points().iter().zip(cands[j].2.points()))
                    // a + (b − a)(1 − w): a held point (a = b) stays bit for bit
                    .map(|(a, b)| *a + (*b - *a) * (1.0 - w))
                    .collect();
                let f = s.with_points(pts)?;
                if let Some(dev) = bands.holds_quick(s, &f) {
                    blends.push((f, dev));
                }
            }
        }
    }
    let ranks = par_map(&blends, g.threads, |b| ranker.rank(&b.0));
    cands.extend(
        blends
            .into_iter()
            .zip(ranks)
            .map(|((f, dev), r)| (r, SurfacePick::Blend, f, dev, 0.0)),
    );
    Ok(())
}

/// Step 8's pick among `cands` (the original first, the isocurve result second): the lexicographically
/// fairest of the candidates that are no less fair than the reference and the isocurve result on either
/// measure and have no more extrema than the original; if none, of those no less fair than the reference
/// with no more extrema than the original; if none, of all.
fn pick_fairest(mut cands: Vec<Cand>) -> Cand {
    // the reference's rank: that of its answer (the original's when no strength held the band)
    let ref_rank = (cands.iter().rev())
        .find(|c| c.1 == SurfacePick::Reference)
        .map_or(cands[0].0, |c| c.0);
    let today = cands[1].0;
    let dominates = |r: &Rank, o: &Rank| r.0 <= o.0 && r.1 <= o.1;
    let best_of = |keep: &dyn Fn(&Rank) -> bool| {
        cands
            .iter()
            .enumerate()
            .filter(|(_, c)| keep(&c.0))
            .min_by(|a, b| a.1.0.partial_cmp(&b.1.0).unwrap_or(std::cmp::Ordering::Equal))
            .map(|(i, _)| i)
    };
    let orig_ext = cands[0].0.0;
    let pick = best_of(&|r| dominates(r, &ref_rank) && dominates(r, &today) && r.0 <= orig_ext)
        .or_else(|| best_of(&|r| dominates(r, &ref_rank) && r.0 <= orig_ext))
        .or_else(|| best_of(&|_| true))
        .unwrap_or(1);
    cands.swap_remove(pick)
}
