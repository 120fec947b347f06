//! Background surface fairs and their cancellation: a superseded full fair is cancelled (its thread ends
//! `Cancelled`, early), the draft during a drag runs as one coalesced background job at a time, and the
//! release fairs in full — each result the synchronous core call's, bit for bit (with the workspace's
//! isocurve cache, whose setups the draft at another tolerance reuses). Deterministic: jobs are
//! held at a gate (`App::set_job_gate`) where a test needs one still running, and waited for with
//! `App::wait_for_jobs`; no sleeps.

use eframe::egui;
use egui::{Pos2, Role};
use egui_kittest::kittest::Queryable;
use fairway::fair::surface::{SurfaceFairingOptions, fair_surface};
use fairway::io::Document;
use fairway::{BSplineSurface, Geometry};
use fairway_editor::jobs::{Gate, JobEnd};
use fairway_editor::surface_ui::{PreviewKey, SurfaceWorkspace, UvRect};
use fairway_editor::{App, Command};

mod common;
// the core's bench surface (its benches and `surface_timing` time the same net)
#[path = "../../fairway/benches/common/mod.rs"]
mod bench_common;
use bench_common::noisy_net;
use common::harness_without_waiting;

const WHOLE: UvRect = ((0.0, 1.0), (0.0, 1.0));

/// The editor on the `n × n` noisy net with the whole domain as the region, jobs held at `gate`.
fn app_on_net(n: usize, gate: &Gate) -> (egui_kittest::Harness<'static, App>, BSplineSurface) {
    let s = noisy_net(n);
    let mut doc = Document::new(Geometry::Surface(s.clone()));
    doc.settings.region_uv = Some(WHOLE);
    let mut app = App::default();
    assert!(app.set_document(doc, None, None), "{:?}", app.error);
    app.set_job_gate(Some(gate.clone()));
    (harness_without_waiting(app), s)
}

fn ws<'h>(h: &'h egui_kittest::Harness<'static, App>) -> &'h SurfaceWorkspace {
    h.state().surface.as_ref().expect("the surface workspace")
}

fn key(h: &egui_kittest::Harness<'static, App>) -> PreviewKey {
    ws(h).preview_key(&h.state().doc).expect("a region")
}

fn bits(s: &BSplineSurface) -> Vec<[u64; 3]> {
    s.points()
        .iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect()
}

fn tolerance(k: PreviewKey) -> f64 {
    f64::from_bits(k.2)
}

/// The full fair the preview asks for, on the test's thread.
fn full_now(s: &BSplineSurface, k: PreviewKey) -> BSplineSurface {
    let opts = SurfaceFairingOptions::default().region(k.1).tolerance(tolerance(k));
    fair_surface(s, opts).unwrap().surface
}

/// The draft the preview asks for during a drag (`SurfaceFairingOptions::draft`).
fn draft_now(s: &BSplineSurface, k: PreviewKey) -> BSplineSurface {
    fair_surface(s, draft_options(k)).unwrap().surface
}

fn draft_options(k: PreviewKey) -> SurfaceFairingOptions {
    SurfaceFairingOptions::default()
        .region(k.1)
        .tolerance(tolerance(k))
        .draft()
}

/// A new tolerance supersedes the running full fair: the job is dropped, its token set, and its thread
/// ends `Cancelled` — at once when it had not started (held at the gate: no checkpoint passed), early when
/// it had (mid-fair: far fewer checkpoints than the fair it was); the fair of the last tolerance arrives
/// equal to the synchronous `fair_surface`, bit for bit.
#[test]
fn a_superseded_full_fair_is_cancelled_and_its_thread_ends_cancelled() {
    let gate = Gate::closed();
    let (mut h, s) = app_on_net(30, &gate);
    let t0 = h.state().tolerance();
    h.state_mut().apply(Command::SetTolerance(t0 * 0.8));
    h.step();
    let held = ws(&h).watch_fair().expect("the full fair runs (held at the gate)");
    h.state_mut().apply(Command::SetTolerance(t0 * 0.6));
    h.step();
    assert!(held.is_cancelled(), "the superseded job's token was not set");
    let running = ws(&h).watch_fair().expect("the fair of the new tolerance");
    assert!(!running.is_cancelled());
    gate.open();
    assert_eq!(held.wait_end(), JobEnd::Cancelled);
    assert_eq!(held.checkpoints(), 0, "the held job computed after it was cancelled");
    // mid-fair: superseded once the core has passed a few checkpoints
    while running.checkpoints() < 3 && running.end().is_none() {
        std::thread::yield_now();
    }
    let seen = running.checkpoints();
    h.state_mut().apply(Command::SetTolerance(t0 * 0.5));
    h.step();
    assert!(running.is_cancelled());
    assert_eq!(
        running.wait_end(),
        JobEnd::Cancelled,
        "the superseded fair ran to its end"
    );
    let last = ws(&h).watch_fair().expect("the fair of the last tolerance");
    h.state_mut().wait_for_jobs();
    h.step();
    assert_eq!(last.wait_end(), JobEnd::Finished);
    let total = last.checkpoints();
    eprintln!(
        "superseded after {seen} checkpoints, ended at {} (the last fair passed {total})",
        running.checkpoints()
    );
    assert!(
        running.checkpoints() < total / 2,
        "{} of {total}",
        running.checkpoints()
    );
    let k = key(&h);
    let p = ws(&h).preview.as_ref().expect("the full fair of the last tolerance");
    assert!(!p.draft && p.key() == k);
    assert_eq!(bits(&p.surface), bits(&full_now(&s, k)));
}

/// Drag the tolerance slider over several values with the first draft job held: no second draft job
/// starts while it runs (the original stays on screen), and the keys in between are skipped; when it ends
/// its draft shows and one draft starts for the latest key, which ends the drag's drafts; the release
/// fairs in full. Every result is the synchronous core call's, bit for bit.
#[test]
fn a_drag_runs_one_draft_job_at_a_time_and_ends_with_the_draft_of_the_last_key() {
    let gate = Gate::closed();
    let (mut h, s) = app_on_net(40, &gate);
    let r = h.get_by_role_and_label(Role::Slider, "Tolerance").rect();
    let at = |f: f32| Pos2::new(r.left() + f * r.width(), r.center().y);
    let path: Vec<Pos2> = (0..6).map(|k| at(0.55 + 0.04 * k as f32)).collect();
    h.hover_at(path[0]);
    h.step();
    h.drag_at(path[0]);
    h.step();
    let first = ws(&h).drafting_key().expect("the press starts a draft");
    let watch = ws(&h).watch_draft().unwrap();
    let mut keys = vec![key(&h)];
    for &p in &path[1..] {
        h.hover_at(p);
        h.step();
        keys.push(key(&h));
        let w = ws(&h);
        assert_eq!(w.drafts_started, 1, "a second draft job started while one runs");
        assert_eq!(w.drafting_key(), Some(first));
        assert!(w.preview.is_none(), "the original stays on screen meanwhile");
        assert!(!w.is_fairing(), "a full fair started during the drag");
    }
    keys.dedup();
    assert!(keys.len() >= 4, "the drag moved the tolerance too little: {keys:?}");
    let last = *keys.last().unwrap();
    assert_ne!(first, last);
    // the first draft ends: shown (an earlier point of the drag), and one draft for the latest key starts
    gate.open();
    h.state_mut().wait_for_jobs();
    assert_eq!(watch.wait_end(), JobEnd::Finished);
    h.step();
    let w = ws(&h);
    let p = w.preview.as_ref().expect("the first draft shows");
    assert!(p.draft && p.key() == first);
    assert_eq!(bits(&p.surface), bits(&draft_now(&s, first)));
    assert_eq!(w.drafts_started, 2);
    assert_eq!(w.drafting_key(), Some(last), "the keys in between were not skipped");
    h.state_mut().wait_for_jobs();
    h.step();
    let w = ws(&h);
    let p = w.preview.as_ref().expect("the last draft");
    assert!(p.draft && p.key() == last && !w.is_drafting());
    assert_eq!(bits(&p.surface), bits(&draft_now(&s, last)));
    // the draft at another tolerance took every isocurve setup from the first draft's (and is the
    // uncached draft, above)
    let one = fairway::fair::IsocurveCache::new();
    fairway::fair::fair_surface_cached(&s, draft_options(first), &fairway::Cancel::new(), &one).unwrap();
    let (one, both) = (one.counts(), w.iso_cache.counts());
    assert!(
        one.misses > 0 && both.misses == one.misses,
        "built by one draft {one:?}, by both {both:?}"
    );
    assert!(both.hits >= one.hits + one.misses, "{both:?}");
    assert_eq!(w.drafts_started, 2, "the drag ran {} draft jobs", w.drafts_started);
    assert!(!w.can_accept(&h.state().doc), "Accept takes no draft");
    // the release: the full fair of the last key, the draft shown meanwhile
    h.drop_at(*path.last().unwrap());
    h.step();
    let w = ws(&h);
    assert_eq!(w.fairing_key(), Some(last));
    assert!(w.preview.as_ref().is_some_and(|p| p.draft && p.key() == last));
    h.state_mut().wait_for_jobs();
    h.step();
    let w = ws(&h);
    let p = w.preview.as_ref().expect("the full fair");
    assert!(!p.draft && p.key() == last && w.can_accept(&h.state().doc));
    assert_eq!(bits(&p.surface), bits(&full_now(&s, last)));
}

/// Released while the draft of an earlier point of the drag runs: that draft is outdated, so its job is
/// dropped (its thread ends `Cancelled`, having computed nothing), and the full fair of the last key
/// arrives equal to the synchronous one.
#[test]
fn the_release_cancels_a_draft_of_an_older_key_and_fairs_in_full() {
    let gate = Gate::closed();
    let (mut h, s) = app_on_net(40, &gate);
    let r = h.get_by_role_and_label(Role::Slider, "Tolerance").rect();
    let at = |f: f32| Pos2::new(r.left() + f * r.width(), r.center().y);
    h.hover_at(at(0.55));
    h.step();
    h.drag_at(at(0.55));
    h.step();
    let first = ws(&h).drafting_key().expect("the press starts a draft");
    let draft = ws(&h).watch_draft().unwrap();
    h.hover_at(at(0.7));
    h.step();
    h.drop_at(at(0.7));
    h.step();
    let last = key(&h);
    assert_ne!(first, last);
    let w = ws(&h);
    assert!(draft.is_cancelled(), "the outdated draft still runs");
    // there is no draft of the last key: one starts beside its full fair
    assert_eq!(w.drafting_key(), Some(last));
    assert_eq!(w.fairing_key(), Some(last));
    let last_draft = w.watch_draft().unwrap();
    gate.open();
    assert_eq!(draft.wait_end(), JobEnd::Cancelled);
    assert_eq!(draft.checkpoints(), 0);
    h.state_mut().wait_for_jobs();
    assert_eq!(last_draft.wait_end(), JobEnd::Finished);
    h.step();
    let p = ws(&h).preview.as_ref().expect("the full fair");
    assert!(!p.draft && p.key() == last);
    assert_eq!(bits(&p.surface), bits(&full_now(&s, last)));
    // the frames after it start nothing
    h.step();
    assert!(!h.state().is_computing());
}

/// A tolerance set with the pointer up (typed, or a command) has no draft: one runs beside the full fair,
/// for the same key, so that a provisional result can show before the full fair ends; once both have
/// ended the full fair's result is the preview (a draft that ends after it is not shown), bit for bit the
/// synchronous call's, and the draft's is the synchronous draft's.
#[test]
fn a_tolerance_set_with_the_pointer_up_drafts_beside_the_full_fair() {
    let gate = Gate::closed();
    let (mut h, s) = app_on_net(40, &gate);
    h.step();
    gate.open();
    h.state_mut().wait_for_jobs();
    h.step();
    assert!(
        ws(&h).preview.as_ref().is_some_and(|p| !p.draft),
        "the opening's full fair"
    );
    let before = ws(&h).drafts_started;
    let tol = 2.0 * h.state().tolerance();
    h.state_mut().apply(Command::SetTolerance(tol));
    h.step();
    let k = key(&h);
    let w = ws(&h);
    assert_eq!(w.fairing_key(), Some(k));
    assert_eq!(w.drafting_key(), Some(k), "no draft beside the full fair");
    assert_eq!(w.drafts_started, before + 1);
    let draft = w.watch_draft().unwrap();
    assert_eq!(draft.wait_end(), JobEnd::Finished);
    // the draft (ended first here: 1 level of isocurves against the full fair) shows as provisional
    h.step();
    let w = ws(&h);
    if w.is_fairing() {
        let p = w.preview.as_ref().expect("the draft shows while the full fair runs");
        assert!(p.draft && p.key() == k);
        assert_eq!(bits(&p.surface), bits(&draft_now(&s, k)));
    }
    h.state_mut().wait_for_jobs();
    h.step();
    let p = ws(&h).preview.as_ref().expect("the full fair");
    assert!(!p.draft && p.key() == k);
    assert_eq!(bits(&p.surface), bits(&full_now(&s, k)));
}
