//! What the CLI's end-to-end tests share: running the binary, scratch folders, the bundled files.
#![allow(dead_code)] // each test binary uses its own subset

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Run the `fairway` binary with `args`.
pub fn fairway(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_fairway"))
        .args(args)
        .output()
        .expect("run the fairway binary")
}

/// A file of the independent reference cases (`tests/data/reference`).
pub fn reference(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/reference")).join(name)
}

/// A bundled sample (`assets`).
pub fn asset(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets")).join(name)
}

/// A fresh folder for one test, removed when dropped; `tag` must be unique within the test binary.
pub struct Scratch(PathBuf);

impl Scratch {
    pub fn new(tag: &str) -> Self {
        let d = std::env::temp_dir().join(format!(
            "fairway-{}-{}-{tag}",
            env!("CARGO_CRATE_NAME"),
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        Scratch(d)
    }

    /// A path inside the folder.
    pub fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    /// A file inside the folder with `contents`.
    pub fn file(&self, name: &str, contents: &str) -> PathBuf {
        let p = self.0.join(name);
        std::fs::write(&p, contents).unwrap();
        p
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A path as a command-line argument.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Run, expect success, return (stdout, stderr).
pub fn run_ok(args: &[&str]) -> (String, String) {
    let out = fairway(args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{args:?}: exit {:?}: {err}", out.status.code());
    (String::from_utf8_lossy(&out.stdout).into_owned(), err)
}

/// Run, expect exit 1 with every needle in stderr and no panic.
pub fn run_fails(args: &[&str], needles: &[&str]) {
    let out = fairway(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: stderr {err:?} should mention {n:?}");
    }
    assert!(!err.contains("panicked"), "{err}");
}
