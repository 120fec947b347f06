//! [`IsocurveCache`]: the isocurves' curve-engine setups kept from one surface fair to the next.
//!
//! An isocurve's setup (arc-length table, samples, basis rows, frames, normal matrices, target) depends
//! on the isocurve and its fairing options, not on the tolerance. While the user drags the tolerance of a
//! surface preview, every draft fairs the same isocurves at another tolerance: with a cache, the drafts
//! after the first (and the full fair after the release) take the setups of the one before instead of
//! building them again (about a third of a 30 × 30 draft's CPU).
//!
//! Entries are found by their content — the isocurve's degree, knots, control points and weights and
//! the options of its setup — not by the caller's idea of "the same surface", so a cache can never hand
//! out a setup of another curve: an edited net, another region or other options simply miss. A setup
//! taken from the cache is reset to its state after the build ([`FairingSetup::as_new`]), so a fair
//! with a cache is the fair without, bit for bit (tests `cached_setups_give_the_same_surface`,
//! `a_reused_setup_fairs_as_a_new_one`).

use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex, PoisonError, TryLockError};

use glam::DVec3;

use crate::curve::BSplineCurve;
use crate::error::Result;
use crate::fair::curve::{FairingOptions, FairingSetup};

/// Samples a cache holds at most by default ([`IsocurveCache::new`]), over all its setups. An isocurve
/// setup without check samples holds about 770 bytes per sample (measured: a full cache of 150,000 samples
/// raised a draft's peak memory from 24 to 140 MB), so this is about 50 MB: every isocurve of a 30 × 30 net
/// faired whole (164 isocurves, 18,000 samples) or of a 50 × 50 one (54,000); a 100 × 100 net (about 580
/// isocurves of 390 samples) keeps the setups that fit and builds the rest.
pub const CACHE_SAMPLES: usize = 64_000;

/// Isocurve setups kept between surface fairs ([`super::fair_surface_cached`]): a surface faired again at
/// another tolerance (the editor's drafts while the tolerance is dragged, the full fair after them, a
/// fair's own tightening rounds) takes its isocurves' setups from here instead of building them again.
/// A setup is found by its content (the isocurve's degree, knots, control points and weights, and the
/// setup's options; the tolerance is not part of a setup), never by the caller's idea of "the same
/// surface", and is reset before reuse, so a fair with a cache is the fair without, bit for bit. Cloning
/// shares the cache; several fairs may use it at once, on any threads (a setup in use by one is built
/// afresh by the other). It holds at most [`CACHE_SAMPLES`] samples (or its own capacity).
#[derive(Clone)]
pub struct IsocurveCache(Arc<Mutex<State>>);

impl Default for IsocurveCache {
    fn default() -> Self {
        Self::with_capacity(CACHE_SAMPLES)
    }
}

impl std::fmt::Debug for IsocurveCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = self.lock();
        f.debug_struct("IsocurveCache")
            .field("setups", &s.entries.values().map(Vec::len).sum::<usize>())
            .field("samples", &s.samples)
            .finish()
    }
}

struct State {
    /// Entries by the hash of their key (a bucket holds the entries whose keys share it).
    entries: HashMap<u64, Vec<Entry>>,
    /// Samples held over all entries, and at most.
    samples: usize,
    capacity: usize,
    /// Fairs run with this cache so far: an entry last used by an earlier one may be dropped for room.
    fairs: u64,
    /// Setups taken from the cache / built, over the cache's life (for tests and timing).
    hits: usize,
    misses: usize,
}

impl State {
    /// Drop the entries `drop` picks, with their samples.
    fn drop_entries(&mut self, drop: impl Fn(&Entry) -> bool) {
        let mut freed = 0;
        for bucket in self.entries.values_mut() {
            bucket.retain(|e| {
                let gone = drop(e);
                if gone {
                    freed += e.samples;
                }
                !gone
            });
        }
        self.entries.retain(|_, b| !b.is_empty());
        self.samples -= freed;
    }
}

struct Entry {
    key: Key,
    setup: Arc<Mutex<FairingSetup>>,
    samples: usize,
    /// The fair (`State::fairs`) that last took it.
    used: u64,
}

/// What an isocurve setup is built from (the tolerance aside).
#[derive(PartialEq)]
struct Key {
    degree: usize,
    knots: Vec<f64>,
    points: Vec<DVec3>,
    weights: Option<Vec<f64>>,
    opts: FairingOptions,
}

impl Key {
    fn new(c: &BSplineCurve, mut opts: FairingOptions) -> Self {
        opts.tolerance = 0.0;
        Self {
            degree: c.degree(),
            knots: c.knots().values().to_vec(),
            points: c.points().to_vec(),
            weights: c.weights().map(<[f64]>::to_vec),
            opts,
        }
    }

    /// A hash of the geometry (the options are compared on a hit).
    fn hash(&self) -> u64 {
        let mut h = std::hash::DefaultHasher::new();
        self.degree.hash(&mut h);
        let bits = self
            .knots
            .iter()
            .copied()
            .chain(self.points.iter().flat_map(|p| p.to_array()));
        for x in bits.chain(self.weights.iter().flatten().copied()) {
            x.to_bits().hash(&mut h);
        }
        h.finish()
    }
}

/// How many setups a cache handed out and built (see [`IsocurveCache::counts`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CacheCounts {
    /// Setups taken from the cache.
    pub hits: usize,
    /// Setups built (not found, or in use by another fair).
    pub misses: usize,
    /// Setups held now.
    pub held: usize,
    /// Samples held now, over all setups.
    pub samples: usize,
}

impl IsocurveCache {
    /// An empty cache holding at most [`CACHE_SAMPLES`] samples.
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty cache holding at most `samples` samples over all its setups.
    pub fn with_capacity(samples: usize) -> Self {
        Self(Arc::new(Mutex::new(State {
            entries: HashMap::new(),
            samples: 0,
            capacity: samples,
            fairs: 0,
            hits: 0,
            misses: 0,
        })))
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Setups handed out and built so far, and held now.
    pub fn counts(&self) -> CacheCounts {
        let s = self.lock();
        CacheCounts {
            hits: s.hits,
            misses: s.misses,
            held: s.entries.values().map(Vec::len).sum(),
            samples: s.samples,
        }
    }

    /// Drop every setup.
    pub fn clear(&self) {
        self.lock().drop_entries(|_| true);
    }

    /// Run `f` (a surface fair) with this cache installed for the isocurves' setups ([`with_setup`]), on
    /// this thread and on the workers of its parallel maps.
    pub(crate) fn run<T>(&self, f: impl FnOnce() -> T) -> T {
        self.lock().fairs += 1;
        scoped(Some(self), f)
    }

    /// The setup held for `key`, if any.
    fn take(&self, key: &Key, hash: u64) -> Option<Arc<Mutex<FairingSetup>>> {
        let mut s = self.lock();
        let now = s.fairs;
        let e = s.entries.get_mut(&hash)?.iter_mut().find(|e| e.key == *key)?;
        e.used = now;
        Some(e.setup.clone())
    }

    /// Drop the entry for `key` (its setup was poisoned by a panic during a fair).
    fn remove(&self, key: &Key) {
        self.lock().drop_entries(|e| e.key == *key);
    }

    /// Keep `setup` for `key`, if there is room (entries not used by the current fair are dropped for it).
    fn put(&self, key: Key, hash: u64, setup: FairingSetup) {
        let samples = setup.params().len();
        let mut s = self.lock();
        if s.entries.get(&hash).is_some_and(|b| b.iter().any(|e| e.key == key)) {
            return;
        }
        if s.samples + samples > s.capacity {
            let now = s.fairs;
            s.drop_entries(|e| e.used != now);
        }
        if s.samples + samples > s.capacity {
            return;
        }
        s.samples += samples;
        let used = s.fairs;
        s.entries.entry(hash).or_default().push(Entry {
            key,
            setup: Arc::new(Mutex::new(setup)),
            samples,
            used,
        });
    }
}

thread_local! {
    static CURRENT: std::cell::RefCell<Option<IsocurveCache>> = const { std::cell::RefCell::new(None) };
}

/// The cache installed on this thread ([`IsocurveCache::run`]), if any.
pub(crate) fn current() -> Option<IsocurveCache> {
    CURRENT.with(|c| c.borrow().clone())
}

/// Run `f` with `cache` installed on this thread (and the previous one restored after).
pub(crate) fn scoped<R>(cache: Option<&IsocurveCache>, f: impl FnOnce() -> R) -> R {
    crate::cancel::scoped_local(&CURRENT, cache, f)
}

/// Run `f` on the setup of isocurve `c` with `opts` (its tolerance set by `f`): the installed cache's if
/// it holds one that no other fair is using, else a new one (kept in the cache afterwards if one is
/// installed). The result is the same either way.
pub(super) fn with_setup<R>(
    c: &BSplineCurve,
    opts: FairingOptions,
    f: impl FnOnce(&mut FairingSetup) -> Result<R>,
) -> Result<R> {
    let build = || FairingSetup::with_check_samples(c, opts, 0);
    let Some(cache) = current() else {
        return f(&mut build()?);
    };
    let key = Key::new(c, opts);
    let hash = key.hash();
    if let Some(slot) = cache.take(&key, hash) {
        match slot.try_lock() {
            Ok(mut st) => {
                cache.lock().hits += 1;
                st.as_new();
                return f(&mut st);
            }
            Err(TryLockError::Poisoned(_)) => cache.remove(&key),
            Err(TryLockError::WouldBlock) => {}
        }
    }
    cache.lock().misses += 1;
    let mut st = build()?;
    let r = f(&mut st);
    if r.is_ok() {
        cache.put(key, hash, st);
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fair::surface::tests::{graph, noisy};
    use crate::fair::surface::{SurfaceFairingOptions, fair_surface, fair_surface_cached};
    use crate::surface::BSplineSurface;

    fn net() -> BSplineSurface {
        noisy(&graph(12, |u, v| 0.3 * (2.0 * u).sin() * (1.5 * v).cos()), 1e-3, 7)
    }

    fn fair_both(s: &BSplineSurface, opts: SurfaceFairingOptions, cache: &IsocurveCache) -> (Vec<DVec3>, Vec<DVec3>) {
        let cached = fair_surface_cached(s, opts, &crate::Cancel::new(), cache).unwrap();
        let plain = fair_surface(s, opts).unwrap();
        (cached.surface.points().to_vec(), plain.surface.points().to_vec())
    }

    /// A fair at one tolerance, then fairs at others with the same cache (the editor's drafts during a
    /// tolerance drag, and the full fair after): every one is the fair without a cache, bit for bit; the
    /// second draft takes all its setups from the cache; an edited net misses where its isocurves changed.
    #[test]
    fn cached_setups_give_the_same_surface() {
        let s = net();
        let draft = SurfaceFairingOptions::default().draft();
        let cache = IsocurveCache::new();
        let (a, b) = fair_both(&s, draft.tolerance(3e-3), &cache);
        assert_eq!(a, b);
        let first = cache.counts();
        // (a fair's tightening rounds, which fair the same isocurves at a smaller tolerance, hit already)
        assert!(first.misses > 0 && first.held == first.misses, "{first:?}");
        for m in [2.5e-3, 4e-3, 1e-3] {
            let (a, b) = fair_both(&s, draft.tolerance(m), &cache);
            assert_eq!(a, b, "draft at m = {m}");
        }
        let c = cache.counts();
        assert_eq!(
            c.misses, first.misses,
            "every isocurve of a draft at another tolerance is held: {c:?}"
        );
        assert!(c.hits >= first.hits + 3 * first.misses, "{c:?}");
        // the full fair (its levels, step 8) after the drafts: it takes the drafts' setups, though its
        // isocurves step μ below the band's limit (`fairest_isocurves`: set per fair, not in the key)
        let (a, b) = fair_both(&s, SurfaceFairingOptions::default().tolerance(2e-3), &cache);
        assert_eq!(a, b, "full fair");
        let c = cache.counts();
        assert_eq!(c.misses, first.misses, "the full fair built setups: {c:?}");
        // and a draft after it stops at the band's limit again
        let (a, b) = fair_both(&s, draft.tolerance(3e-3), &cache);
        assert_eq!(a, b, "draft after the full fair");
        // one control point moved: the isocurves through its support change and are built anew
        let mut pts = s.points().to_vec();
        pts[5 * 12 + 6].z += 2e-3;
        let edited = s.with_points(pts).unwrap();
        let before = cache.counts();
        let (a, b) = fair_both(&edited, draft.tolerance(3e-3), &cache);
        assert_eq!(a, b, "edited net");
        let after = cache.counts();
        assert!(after.misses > before.misses, "{before:?} {after:?}");
        assert!(
            after.hits > before.hits,
            "isocurves away from the edit are still held: {after:?}"
        );
    }

    /// A setup faired at one tolerance and reset ([`FairingSetup::as_new`]) fairs at another exactly as a
    /// setup built for it.
    #[test]
    fn a_reused_setup_fairs_as_a_new_one() {
        let s = net();
        let opts = SurfaceFairingOptions::default();
        let iso = s.iso_u(0.37);
        let fo = super::super::isocurves::isocurve_options(&opts, 2e-3, s.domain().0, 9);
        let mut used = FairingSetup::with_check_samples(&iso, fo, 0).unwrap();
        used.fair().unwrap();
        used.set_mu_hint(Some(1e-3));
        used.fair().unwrap();
        for m in [1e-3, 5e-3, 2e-3] {
            used.as_new();
            used.set_tolerance(m).unwrap();
            let mut fresh = FairingSetup::with_check_samples(&iso, fo, 0).unwrap();
            fresh.set_tolerance(m).unwrap();
            let (a, b) = (used.fair().unwrap(), fresh.fair().unwrap());
            assert_eq!(a.curve.points(), b.curve.points(), "m = {m}");
            assert_eq!((a.mu, a.solves), (b.mu, b.solves), "m = {m}");
        }
    }

    /// Fairs on two threads at once with one cache (a draft and a full fair in the editor): both are
    /// the fairs without a cache; with a small capacity the cache never holds more than it.
    #[test]
    fn shared_and_bounded() {
        let s = net();
        let cache = IsocurveCache::with_capacity(600);
        let draft = SurfaceFairingOptions::default().draft();
        std::thread::scope(|sc| {
            let h: Vec<_> = [3e-3, 2e-3, 3e-3]
                .into_iter()
                .map(|m| {
                    let (s, cache) = (&s, cache.clone());
                    sc.spawn(move || fair_both(s, draft.tolerance(m), &cache))
                })
                .collect();
            for j in h {
                let (a, b) = j.join().unwrap();
                assert_eq!(a, b);
            }
        });
        let c = cache.counts();
        assert!(c.samples <= 600 && c.held > 0, "{c:?}");
        cache.clear();
        assert_eq!((cache.counts().held, cache.counts().samples), (0, 0));
    }
}
