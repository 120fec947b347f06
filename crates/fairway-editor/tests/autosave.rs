//! Autosave and recovery (the editor's `autosave`): the timing rule, a simulated restart,
//! and a real `kill -9` of a process that autosaved, after which the next
//! start is offered the document.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use fairway::BSplineCurve;
use fairway::io::{Document, DocumentSettings};
use fairway_editor::autosave::{Autosave, pending};

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fairway-autosave-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// A cubic with a double knot.
fn wiggly_2d() -> BSplineCurve {
    let pts = [
        (0., 0.),
        (1., 2.),
        (2.5, 1.5),
        (3., -1.),
        (4.5, 0.),
        (5., 2.),
        (6.5, 1.),
        (8., 0.),
    ];
    let pts: Vec<_> = pts.iter().map(|&(x, y)| fairway::DVec2::new(x, y)).collect();
    BSplineCurve::new_2d(3, vec![0., 0., 0., 0., 0.15, 0.4, 0.4, 0.7, 1., 1., 1., 1.], &pts).unwrap()
}

fn document() -> Document {
    let mut d = Document::new(wiggly_2d().into());
    d.settings = DocumentSettings {
        tolerance: Some(0.0125),
        region: Some((0.25, 0.75)),
        target: Some(vec![0.1, 1.0 / 3.0]),
        pinned: vec![4],
        ..Default::default()
    };
    d
}

#[test]
fn writes_only_when_dirty_and_due() {
    let dir = scratch("tick");
    let doc = document();
    let mut a = Autosave::new(&dir, Duration::from_secs(30));
    let t0 = Instant::now();
    assert!(
        !a.tick(&doc, None, false, t0).unwrap(),
        "clean document: nothing written"
    );
    assert!(!dir.join("autosave.ron").exists());
    assert!(a.tick(&doc, None, true, t0).unwrap(), "first dirty frame writes");
    assert!(!a.tick(&doc, None, true, t0 + Duration::from_secs(29)).unwrap());
    assert!(a.tick(&doc, None, true, t0 + Duration::from_secs(30)).unwrap());
    a.clear().unwrap();
    assert!(!dir.join("autosave.ron").exists() && !dir.join("autosave.meta").exists());
    assert_eq!(pending(&dir).unwrap(), None);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn restart_offers_the_autosaved_document_exactly() {
    let dir = scratch("restart");
    let doc = document();
    let source = Path::new("/home/designer/hull section.ron");
    {
        let mut a = Autosave::new(&dir, Duration::from_secs(60));
        a.tick(&doc, Some(source), true, Instant::now()).unwrap();
        // the session ends without clear(): a crash
    }
    let r = pending(&dir).unwrap().expect("restore offered");
    assert_eq!(r.document, doc);
    assert_eq!(r.source.as_deref(), Some(source));
    assert!(r.saved_at.elapsed().unwrap() < Duration::from_secs(3600));
    // declining (or restoring and saving) clears it
    Autosave::new(&dir, Duration::from_secs(60)).clear().unwrap();
    assert_eq!(pending(&dir).unwrap(), None);
    // an unreadable autosave is reported, not silently dropped
    std::fs::write(dir.join("autosave.ron"), "(format: \"fairway\", vers").unwrap();
    assert!(pending(&dir).unwrap_err().to_string().contains("RON"));
    std::fs::remove_dir_all(&dir).unwrap();
}

const CHILD_ENV: &str = "FAIRWAY_AUTOSAVE_CHILD_DIR";

/// Child side of `kill_9_then_next_start_offers_restore` (does nothing unless that test starts it).
#[test]
fn child_process_autosaves_then_waits_to_be_killed() {
    let Some(dir) = std::env::var_os(CHILD_ENV) else { return };
    let mut a = Autosave::new(PathBuf::from(dir), Duration::from_secs(1));
    a.tick(&document(), None, true, Instant::now()).unwrap();
    std::thread::sleep(Duration::from_secs(120));
}

#[cfg(unix)]
#[test]
fn kill_9_then_next_start_offers_restore() {
    let dir = scratch("kill");
    let mut child = std::process::Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "child_process_autosaves_then_waits_to_be_killed",
            "--nocapture",
        ])
        .env(CHILD_ENV, &dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let t = Instant::now();
    while !dir.join("autosave.meta").exists() {
        assert!(t.elapsed() < Duration::from_secs(60), "child never autosaved");
        std::thread::sleep(Duration::from_millis(20));
    }
    if cfg!(target_os = "linux") {
        assert_eq!(
            pending(&dir).unwrap(),
            None,
            "a running session's autosave is not offered"
        );
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let r = pending(&dir).unwrap().expect("restore offered after kill -9");
    assert_eq!(r.document, document());
    std::fs::remove_dir_all(&dir).unwrap();
}
