//! Background jobs: an engine call that can take seconds (the full surface fair of the preview, a
//! network fair) runs on its own thread, so the UI thread stays responsive. A [`Job`] holds the key
//! of the state it was started for and the receiving end of its result. Its owner polls it once a
//! frame and uses the result only if the key still matches its state; a job whose key no longer
//! matches is dropped, and with it its result (the thread runs to its end: the core's calls cannot be
//! interrupted, only their results discarded).
//!
//! The computation runs under [`crate::guard::catch_panic`], so a panic becomes the same error message
//! as on the UI thread. When it finishes, the job asks egui for a repaint, and the frame that follows
//! takes the result.

use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::time::{Duration, Instant};

use eframe::egui;
use fairway::{Error, Result};

/// One computation on its own thread, started for the state named by `key`.
pub struct Job<K, T> {
    key: K,
    what: &'static str,
    rx: Receiver<Result<T>>,
    /// The result, once received (by [`Job::poll`] or [`Job::wait`]) and not yet taken.
    done: Option<Result<T>>,
    repaint: Option<egui::Context>,
    started: Instant,
}

impl<K, T: Send + 'static> Job<K, T> {
    /// Run `f` on a new thread under the panic guard (`what` names the computation in its error
    /// message). `repaint`, if given, is asked for a repaint when the result is ready.
    pub fn spawn(
        key: K,
        what: &'static str,
        repaint: Option<&egui::Context>,
        f: impl FnOnce() -> Result<T> + Send + 'static,
    ) -> Self {
        let (tx, rx) = mpsc::channel();
        let ctx = repaint.cloned();
        let spawned = std::thread::Builder::new()
            .name(format!("fairway: {what}"))
            .spawn(move || {
                let r = crate::guard::catch_panic(what, f);
                // the job may have been dropped (superseded): then nobody wants the result
                if tx.send(r).is_ok()
                    && let Some(ctx) = ctx
                {
                    // after the send, so the frame it causes finds the result
                    ctx.request_repaint();
                }
            });
        let done = spawned.err().map(|e| {
            Err(Error::InvalidInput(format!(
                "could not start {what}: {e} (nothing was changed)"
            )))
        });
        Self {
            key,
            what,
            rx,
            done,
            repaint: repaint.cloned(),
            started: Instant::now(),
        }
    }
}

impl<K, T> Job<K, T> {
    /// The key of the state the job was started for.
    pub fn key(&self) -> &K {
        &self.key
    }

    /// The key, the job given up (its result, if it comes, is discarded).
    pub fn into_key(self) -> K {
        self.key
    }

    /// How long ago the job was started.
    pub fn elapsed(&self) -> Duration {
        self.started.elapsed()
    }

    /// Whether the job's result has not been received yet (neither [`Job::poll`] nor [`Job::wait`]
    /// has seen it).
    pub fn is_running(&self) -> bool {
        self.done.is_none()
    }

    /// The result if the job has finished (once: the owner drops the job after it), else `None`
    /// without waiting.
    pub fn poll(&mut self) -> Option<Result<T>> {
        if self.done.is_none() {
            self.done = match self.rx.try_recv() {
                Ok(r) => Some(r),
                Err(TryRecvError::Empty) => None,
                Err(TryRecvError::Disconnected) => Some(Err(self.lost())),
            };
        }
        self.done.take()
    }

    /// Block until the job has finished; the result stays for the next [`Job::poll`], and a repaint
    /// is requested so that a frame comes to take it. For tests and scripts that need a deterministic
    /// point where the result is there: the UI never waits.
    pub fn wait(&mut self) {
        if self.done.is_none() {
            self.done = Some(self.rx.recv().unwrap_or_else(|_| Err(self.lost())));
        }
        if let Some(ctx) = &self.repaint {
            ctx.request_repaint();
        }
    }

    /// The error of a thread that ended without a result (it cannot happen under the guard, but a
    /// job must end).
    fn lost(&self) -> Error {
        Error::InvalidInput(format!(
            "internal error in {}: the computation ended without a result (nothing was changed)",
            self.what
        ))
    }
}

impl<K: std::fmt::Debug, T> std::fmt::Debug for Job<K, T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Job")
            .field("key", &self.key)
            .field("what", &self.what)
            .field("running", &self.is_running())
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_job_delivers_its_result_once_and_only_when_finished() {
        let (go, wait_go) = mpsc::channel::<()>();
        let mut job = Job::spawn(7u32, "sum", None, move || {
            wait_go.recv().unwrap();
            Ok(40 + 2)
        });
        assert_eq!(*job.key(), 7);
        // held back by the test: still running, poll does not wait
        assert!(job.poll().is_none());
        assert!(job.is_running());
        go.send(()).unwrap();
        job.wait();
        assert!(!job.is_running(), "waited: the result is there");
        assert_eq!(job.poll().unwrap().unwrap(), 42);
    }

    #[test]
    fn errors_and_panics_of_a_job_are_the_guards_messages() {
        let mut job = Job::spawn((), "fairing", None, || -> Result<()> {
            Err(Error::InvalidInput("bad".into()))
        });
        job.wait();
        assert_eq!(job.poll().unwrap().unwrap_err().to_string(), "bad");
        let mut job = Job::spawn((), "surface fairing", None, || -> Result<()> {
            panic!("index {} out of range", 9)
        });
        job.wait();
        assert_eq!(
            job.poll().unwrap().unwrap_err().to_string(),
            "internal error in surface fairing: index 9 out of range (nothing was changed)"
        );
    }

    #[test]
    fn dropping_a_running_job_does_not_wait_for_it() {
        let (go, wait_go) = mpsc::channel::<()>();
        let job = Job::spawn((), "slow", None, move || {
            let _ = wait_go.recv();
            Ok(())
        });
        drop(job);
        // the thread is still blocked on `go`; releasing it now lets it end (its send finds no receiver)
        let _ = go.send(());
    }
}
