//! The parallel map of the surface engine (and of a network fair's curve chains).

/// `f` over `items`, results in the order of `items`, on rayon's global pool (`threads` `None`; its size
/// is rayon's choice, `RAYON_NUM_THREADS` if set), on a pool of `threads` workers, or here in this thread
/// (`Some(1)`). The result of each item does not depend on the thread count. A panic in a worker is
/// re-raised here (the editor's frame guard reports it). Each item runs with the calling thread's cancel
/// token installed ([`crate::cancel`]), so the checkpoints inside it see the token of the fair it belongs
/// to, on whichever worker it runs; likewise the fair's isocurve cache ([`super::IsocurveCache`]).
pub(crate) fn par_map<T: Sync, R: Send>(
    items: &[T],
    threads: Option<usize>,
    f: impl Fn(&T) -> R + Sync + Send,
) -> Vec<R> {
    use rayon::prelude::*;
    let token = crate::cancel::current();
    let cache = super::setup_cache::current();
    let f = |x: &T| crate::cancel::scoped(token.as_ref(), || super::setup_cache::scoped(cache.as_ref(), || f(x)));
    match threads {
        Some(0 | 1) => items.iter().map(f).collect(),
        None => items.par_iter().map(f).collect(),
        Some(n) => match rayon::ThreadPoolBuilder::new().num_threads(n).build() {
            Ok(pool) => pool.install(|| items.par_iter().map(&f).collect()),
            Err(_) => items.iter().map(f).collect(),
        },
    }
}
