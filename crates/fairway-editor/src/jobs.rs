//! Background jobs: an engine call that can take seconds (the full surface fair of the preview, its
//! draft during a drag on a large surface, a network fair) runs on its own thread, so the UI thread stays
//! responsive. A [`Job`] holds the key of the state it was started for, the receiving end of its result
//! and the job's [`Cancel`] token, which the computation receives ([`Job::spawn`]) and hands to the core
//! (`fair_surface_cached`, `fair_network_at_with`). Its owner polls it once a frame and uses the result only
//! if the key still matches its state; a job whose key no longer matches is dropped, and dropping a job
//! sets its token: the core stops at its next checkpoint (before the next block of isocurves, round or
//! smoother attempt) and the thread ends with `Error::Cancelled`, which nobody receives. So a superseded
//! fair does not keep competing for the cores with the one that replaced it.
//!
//! The computation runs under [`crate::guard::catch_panic`], so a panic becomes the same error message
//! as on the UI thread. When it finishes, the job asks egui for a repaint, and the frame that follows
//! takes the result.

use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

use eframe::egui;
use fairway::{Cancel, Error, Result};

/// How a job's thread ended (seen through a [`JobWatch`], also after the job was dropped).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JobEnd {
    /// The computation returned a result.
    Finished,
    /// It returned `Error::Cancelled`: its token was set (the job was dropped or superseded) and the core
    /// stopped at a checkpoint.
    Cancelled,
    /// It returned another error (or panicked).
    Failed,
}

/// The end of a job's thread, shared with its watches.
type EndSlot = Arc<(Mutex<Option<JobEnd>>, Condvar)>;

/// One computation on its own thread, started for the state named by `key`. Dropping it (or
/// [`Job::into_key`]) sets its cancel token.
pub struct Job<K, T> {
    /// The key (taken only by [`Job::into_key`]).
    key: Option<K>,
    what: &'static str,
    rx: Receiver<Result<T>>,
    /// The result, once received (by [`Job::poll`] or [`Job::wait`]) and not yet taken.
    done: Option<Result<T>>,
    repaint: Option<egui::Context>,
    started: Instant,
    cancel: Cancel,
    end: EndSlot,
}

impl<K, T: Send + 'static> Job<K, T> {
    /// Run `f` on a new thread under the panic guard (`what` names the computation in its error
    /// message), with the job's cancel token: `f` hands it to the core, which stops early once the job is
    /// dropped. `repaint`, if given, is asked for a repaint when the result is ready.
    pub fn spawn(
        key: K,
        what: &'static str,
        repaint: Option<&egui::Context>,
        f: impl FnOnce(&Cancel) -> Result<T> + Send + 'static,
    ) -> Self {
        let (tx, rx) = mpsc::channel();
        let ctx = repaint.cloned();
        let cancel = Cancel::new();
        let end: EndSlot = Arc::default();
        let (token, slot) = (cancel.clone(), Arc::clone(&end));
        let spawned = std::thread::Builder::new()
            .name(format!("fairway: {what}"))
            .spawn(move || {
                let r = crate::guard::catch_panic(what, || f(&token));
                let how = match &r {
                    Ok(_) => JobEnd::Finished,
                    Err(Error::Cancelled) => JobEnd::Cancelled,
                    Err(_) => JobEnd::Failed,
                };
                // the job may have been dropped (superseded): then nobody wants the result
                if tx.send(r).is_ok()
                    && let Some(ctx) = ctx
                {
                    // after the send, so the frame it causes finds the result
                    ctx.request_repaint();
                }
                *slot.0.lock().unwrap_or_else(|e| e.into_inner()) = Some(how);
                slot.1.notify_all();
            });
        let done = spawned.err().map(|e| {
            Err(Error::InvalidInput(format!(
                "could not start {what}: {e} (nothing was changed)"
            )))
        });
        Self {
            key: Some(key),
            what,
            rx,
            done,
            repaint: repaint.cloned(),
            started: Instant::now(),
            cancel,
            end,
        }
    }
}

impl<K, T> Job<K, T> {
    /// The key of the state the job was started for.
    pub fn key(&self) -> &K {
        self.key.as_ref().expect("a job keeps its key until into_key")
    }

    /// The key, the job given up: its token is set (a computation still running stops early) and its
    /// result, if it comes, is discarded.
    pub fn into_key(mut self) -> K {
        self.key.take().expect("a job keeps its key until into_key")
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

    /// A watch on the job's thread and token, which outlives the job: for tests and diagnostics (did a
    /// superseded job stop early?).
    pub fn watch(&self) -> JobWatch {
        JobWatch {
            cancel: self.cancel.clone(),
            end: Arc::clone(&self.end),
        }
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

impl<K, T> Drop for Job<K, T> {
    /// A job given up sets its token: a computation still running stops at its next checkpoint (after
    /// it has finished, setting the token changes nothing).
    fn drop(&mut self) {
        self.cancel.cancel();
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

/// A gate that holds jobs at their start until it is opened: for tests that need a job still running,
/// deterministically (the editor's workspaces pass their jobs through it only when a test set one).
#[derive(Debug, Clone, Default)]
pub struct Gate(Arc<(Mutex<bool>, Condvar)>);

impl Gate {
    /// A closed gate.
    pub fn closed() -> Self {
        Self::default()
    }

    /// Open the gate: the jobs waiting at it go on, and later ones pass at once.
    pub fn open(&self) {
        *self.0.0.lock().unwrap_or_else(|e| e.into_inner()) = true;
        self.0.1.notify_all();
    }

    /// Wait until the gate is open (on the job's thread).
    pub fn pass(&self) {
        let (lock, cv) = &*self.0;
        let mut open = lock.lock().unwrap_or_else(|e| e.into_inner());
        while !*open {
            open = cv.wait(open).unwrap_or_else(|e| e.into_inner());
        }
    }
}

/// A watch on a job's thread ([`Job::watch`]): how it ended, and its token.
#[derive(Debug, Clone)]
pub struct JobWatch {
    cancel: Cancel,
    end: EndSlot,
}

impl JobWatch {
    /// Block until the job's thread has ended; how it ended.
    pub fn wait_end(&self) -> JobEnd {
        let (lock, cv) = &*self.end;
        let mut end = lock.lock().unwrap_or_else(|e| e.into_inner());
        loop {
            if let Some(e) = *end {
                return e;
            }
            end = cv.wait(end).unwrap_or_else(|e| e.into_inner());
        }
    }

    /// How the job's thread ended, `None` while it runs.
    pub fn end(&self) -> Option<JobEnd> {
        *self.end.0.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Whether the job's token was set (it was dropped or superseded).
    pub fn is_cancelled(&self) -> bool {
        self.cancel.is_cancelled()
    }

    /// The checkpoints the core passed with the job's token ([`Cancel::checkpoints`]): its progress.
    pub fn checkpoints(&self) -> usize {
        self.cancel.checkpoints()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_job_delivers_its_result_once_and_only_when_finished() {
        let (go, wait_go) = mpsc::channel::<()>();
        let mut job = Job::spawn(7u32, "sum", None, move |_| {
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
        let mut job = Job::spawn((), "fairing", None, |_| -> Result<()> {
            Err(Error::InvalidInput("bad".into()))
        });
        job.wait();
        assert_eq!(job.poll().unwrap().unwrap_err().to_string(), "bad");
        let mut job = Job::spawn((), "surface fairing", None, |_| -> Result<()> {
            panic!("index {} out of range", 9)
        });
        job.wait();
        assert_eq!(
            job.poll().unwrap().unwrap_err().to_string(),
            "internal error in surface fairing: index 9 out of range (nothing was changed)"
        );
    }

    /// Dropping a job sets its token: the computation sees it and ends `Cancelled`, which its watch
    /// reports after the job is gone; a job that finished ends `Finished`, and a dropped one after it had
    /// finished is not reported as cancelled.
    #[test]
    fn dropping_a_job_sets_its_token_and_its_thread_ends_cancelled() {
        let gate = Gate::closed();
        let g = gate.clone();
        let job = Job::spawn((), "wait", None, move |cancel: &Cancel| -> Result<()> {
            g.pass();
            // a computation with checkpoints: stops when its token is set
            while !cancel.is_cancelled() {
                std::thread::yield_now();
            }
            Err(Error::Cancelled)
        });
        let watch = job.watch();
        assert_eq!(watch.end(), None);
        assert!(!watch.is_cancelled());
        drop(job);
        assert!(watch.is_cancelled(), "dropping the job did not set its token");
        gate.open();
        assert_eq!(watch.wait_end(), JobEnd::Cancelled);
        let mut job = Job::spawn((), "sum", None, |_| Ok(1));
        let watch = job.watch();
        job.wait();
        assert_eq!(job.poll().unwrap().unwrap(), 1);
        assert_eq!(watch.wait_end(), JobEnd::Finished);
        drop(job);
        assert_eq!(watch.end(), Some(JobEnd::Finished));
    }

    #[test]
    fn dropping_a_running_job_does_not_wait_for_it() {
        let (go, wait_go) = mpsc::channel::<()>();
        let job = Job::spawn((), "slow", None, move |_| {
            let _ = wait_go.recv();
            Ok(())
        });
        drop(job);
        // the thread is still blocked on `go`; releasing it now lets it end (its send finds no receiver)
        let _ = go.send(());
    }
}
