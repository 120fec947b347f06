//! A panic guard for interactive callers: the editor runs each fairing (or
//! any computation that builds a new document) through [`catch_panic`] at
//! the frame boundary, so a bug shows as an error message instead of taking
//! the application — and the designer's unsaved work — down.
//!
//! The computation must only *produce* a value from borrowed inputs (the
//! core's functions take `&BSplineCurve` and return a new result); the caller
//! applies the result to its document only on `Ok`, so the document is
//! never half-changed.

use std::panic::{AssertUnwindSafe, catch_unwind};

use fairway::{Error, Result};

/// Run `f`, turning a panic into [`Error::InvalidInput`] with the panic's
/// message: `internal error in <what>: <message> (nothing was changed)`.
/// `f`'s own errors pass through unchanged.
pub fn catch_panic<T>(what: &str, f: impl FnOnce() -> Result<T>) -> Result<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => {
            let msg = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(Error::InvalidInput(format!(
                "internal error in {what}: {msg} (nothing was changed)"
            )))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panics_become_errors_and_results_pass_through() {
        assert_eq!(catch_panic("sum", || Ok(1 + 1)).unwrap(), 2);
        let e = catch_panic::<()>("fairing", || Err(Error::InvalidInput("bad region".into()))).unwrap_err();
        assert_eq!(e.to_string(), "bad region");
        let mut doc = vec![1.0, 2.0];
        let r = catch_panic("fairing", || {
            let v: Vec<f64> = doc.iter().map(|x| x * 2.0).collect();
            if v[1] > 3.0 {
                panic!("index {} out of range", 7);
            }
            Ok(v)
        });
        assert_eq!(
            r.unwrap_err().to_string(),
            "internal error in fairing: index 7 out of range (nothing was changed)"
        );
        // the caller applies only Ok results: the document is as before
        if let Ok(v) = catch_panic("noop", || Ok(vec![0.0])) {
            doc = v;
        }
        assert_eq!(doc, vec![0.0]);
        let e = catch_panic::<()>("static", || panic!("plain")).unwrap_err();
        assert!(e.to_string().contains("plain"));
    }
}
