//! Cooperative cancellation of the long fairs: a [`Cancel`] token that a caller sets from any thread
//! ([`Cancel::cancel`]) while [`fair_surface_with`](crate::fair::surface::fair_surface_with) or
//! [`fair_network_at_with`](crate::fair::network::fair_network_at_with) runs with it; the fair then
//! returns [`Error::Cancelled`] at its next checkpoint — never a partial result.
//!
//! ```
//! use fairway::Cancel;
//! use fairway::fair::surface::{SurfaceFairingOptions, fair_surface_with};
//! # let s = fairway::BSplineSurface::try_new(3, 3, [[0.0; 4], [1.0; 4]].concat(), [[0.0; 4], [1.0; 4]].concat(),
//! #     4, 4, (0..16).map(|k| fairway::DVec3::new((k / 4) as f64, (k % 4) as f64, 0.1 * (k % 3) as f64)).collect(), None)?;
//! let cancel = Cancel::new();
//! cancel.cancel(); // e.g. from the UI thread, while the fair runs on another
//! let r = fair_surface_with(&s, SurfaceFairingOptions::default().tolerance(0.01), &cancel);
//! assert!(matches!(r, Err(fairway::Error::Cancelled)));
//! # Ok::<(), fairway::Error>(())
//! ```
//!
//! **Checkpoints** are coarse (each costs one thread-local read and an atomic load): before each block of
//! isocurves, each isocurve round, step 8 and each attempt of its smoother searches, each blend pair, each
//! tile; in a network fair before each curve chain and between its stages. A token that is never set
//! changes nothing: the fair takes the same steps and returns the same bits.
//!
//! **How the token reaches them.** The `_with` entry points install the token for the calling thread
//! for the duration of the call (`scoped`); the engine's one parallel map
//! (`fair::surface::par_map`) carries it into its workers, item by item. So every
//! nested fair — C0 tiles, the smoothed-pole route, a NURBS face's stand-in, each route of a network fair
//! — sees it without the token being threaded through their signatures, and the options stay `Copy`
//! and comparable (a token compares by identity, which would make equal options unequal). A checkpoint
//! must therefore run on the fair's calling thread or inside a `par_map` item, as all of them do; outside
//! a `_with` call there is no token and a checkpoint never fires.
//!
//! Where an inner step turns an error into a fallback (a route that failed is replaced by another), a
//! cancelled inner fair may lead to a fallback result: the `_with` entry points therefore check the
//! token once more at the end and return [`Error::Cancelled`] whenever it was set during the call.

use std::cell::RefCell;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use crate::error::{Error, Result};

/// A cancel token: cheap to clone (the clones share one flag), set from any thread.
#[derive(Clone, Default)]
pub struct Cancel(Arc<Inner>);

#[derive(Default)]
struct Inner {
    cancelled: AtomicBool,
    /// Checkpoints passed (not cancelled) by the fairs run with this token.
    passed: AtomicUsize,
    /// Tests: the token sets itself at the checkpoint with this number (0: off).
    #[cfg(test)]
    trip_at: AtomicUsize,
}

impl Cancel {
    /// A token that is not set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Set the token: a fair running with it returns [`Error::Cancelled`] at its next checkpoint (one that
    /// has not started yet returns it at once). It cannot be unset.
    pub fn cancel(&self) {
        self.0.cancelled.store(true, Ordering::Relaxed);
    }

    /// Whether the token was set.
    pub fn is_cancelled(&self) -> bool {
        self.0.cancelled.load(Ordering::Relaxed)
    }

    /// How many checkpoints the fairs run with this token have passed without being cancelled: a
    /// measure of progress for tests and diagnostics. For one uncancelled fair it is the same on every run
    /// and any thread count (the checkpoints are fixed by the work, as the isocurve blocks are).
    pub fn checkpoints(&self) -> usize {
        self.0.passed.load(Ordering::Relaxed)
    }

    /// `Err(Cancelled)` if the token is set, else counts a checkpoint passed.
    fn check(&self) -> Result<()> {
        if self.is_cancelled() {
            return Err(Error::Cancelled);
        }
        let _n = self.0.passed.fetch_add(1, Ordering::Relaxed) + 1;
        #[cfg(test)]
        if _n == self.0.trip_at.load(Ordering::Relaxed) {
            self.cancel();
            return Err(Error::Cancelled);
        }
        Ok(())
    }

    /// Tests: the token sets itself at the `n`-th checkpoint (1-based; counted with those passed so far),
    /// which then returns `Cancelled`: a deterministic cancel at every checkpoint in turn.
    #[cfg(test)]
    pub(crate) fn trip_at(&self, n: usize) {
        self.0.trip_at.store(n, Ordering::Relaxed);
    }

    /// Run `f` with this token installed (see the module docs), and return [`Error::Cancelled`] if the
    /// token is set before `f` starts or by the time it ends, whatever `f` returned: a fair cancelled in
    /// the middle never hands back a result (not even a fallback's).
    pub(crate) fn run<T>(&self, f: impl FnOnce() -> Result<T>) -> Result<T> {
        scoped(Some(self), || {
            self.check()?;
            let r = f();
            if self.is_cancelled() {
                return Err(Error::Cancelled);
            }
            r
        })
    }
}

impl std::fmt::Debug for Cancel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Cancel")
            .field("cancelled", &self.is_cancelled())
            .field("checkpoints", &self.checkpoints())
            .finish()
    }
}

thread_local! {
    /// The token of the fair running on this thread (set by [`scoped`]).
    static CURRENT: RefCell<Option<Cancel>> = const { RefCell::new(None) };
}

/// A checkpoint: `Err(Cancelled)` if the token of the fair running on this thread is set; `Ok` when it is
/// not, or when no token is installed (a call without one).
pub(crate) fn check() -> Result<()> {
    CURRENT.with(|c| match &*c.borrow() {
        Some(t) => t.check(),
        None => Ok(()),
    })
}

/// The token of the fair running on this thread, to hand to worker threads.
pub(crate) fn current() -> Option<Cancel> {
    CURRENT.with(|c| c.borrow().clone())
}

/// Run `f` with `token` installed on this thread (`None`: none), the previous one restored afterwards,
/// also when `f` panics. Installing `None` matters too: a rayon worker may run an item of another fair
/// while it waits inside an item of this one, and must not see this one's token.
pub(crate) fn scoped<R>(token: Option<&Cancel>, f: impl FnOnce() -> R) -> R {
    scoped_local(&CURRENT, token, f)
}

/// Run `f` with `value` installed in the thread-local `key` (`None`: none), the previous value restored
/// afterwards, also when `f` panics: the fair's context that [`crate::fair`]'s parallel maps carry into
/// their workers (this module's token, the surface engine's isocurve cache).
pub(crate) fn scoped_local<T: Clone + 'static, R>(
    key: &'static std::thread::LocalKey<RefCell<Option<T>>>,
    value: Option<&T>,
    f: impl FnOnce() -> R,
) -> R {
    struct Restore<T: 'static>(&'static std::thread::LocalKey<RefCell<Option<T>>>, Option<T>);
    impl<T: 'static> Drop for Restore<T> {
        fn drop(&mut self) {
            let prev = self.1.take();
            self.0.with(|c| *c.borrow_mut() = prev);
        }
    }
    let prev = key.with(|c| std::mem::replace(&mut *c.borrow_mut(), value.cloned()));
    let _restore = Restore(key, prev);
    f()
}

#[cfg(test)]
mod tests;
