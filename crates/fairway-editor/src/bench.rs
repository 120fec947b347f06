//! Frame-time benchmark (`fairway-editor --bench-frames N`): the first third
//! of the frames sweeps the tolerance (as a slider drag does), the second
//! third drags a target point up and down with the soft falloff (as the κ
//! plot's Drag tool does), the last third drags the region's end back and
//! forth (as the region handles do: a new core `FairingSetup` every frame).
//! Each frame re-fairs and redraws everything; the
//! CPU times of `App::show` (UI + re-fair + shape building), of the re-fair
//! alone, and eframe's whole frame (UI + tessellation + wgpu submission) are
//! printed as median / p95 / max, then the app quits.

use eframe::egui;

use crate::{App, Command};

/// Frame-time benchmark state.
#[derive(Debug, Clone, Default)]
pub struct Bench {
    /// Frames to run.
    pub frames: usize,
    /// `show` wall times so far (ms), per phase (0: tolerance, 1: target, 2: region).
    pub times: [Vec<f64>; 3],
    /// `show` thread CPU times so far (ms), per phase.
    pub cpu: [Vec<f64>; 3],
    /// Re-fair times so far (ms), per phase (region phase: setup + fair).
    pub fair: [Vec<f64>; 3],
    /// eframe's whole-frame time (ms; eframe's `cpu_usage`, a wall time), per phase.
    pub frame: [Vec<f64>; 3],
    /// Main-thread CPU time of one whole frame cycle (ms): UI, re-fair,
    /// tessellation, wgpu submission, event handling — everything eframe does
    /// on the UI thread from one frame's start to the next.
    pub frame_cpu: [Vec<f64>; 3],
    /// Process CPU time per frame cycle (ms), all threads (llvmpipe's too).
    pub frame_proc: [Vec<f64>; 3],
    last_cpu: Option<(u64, u64)>,
    frame_no: usize,
    start_target: Option<Vec<f64>>,
    start_region: Option<(f64, f64)>,
}

impl Bench {
    /// A benchmark of `frames` (≥ 30) frames.
    pub fn new(frames: usize) -> Self {
        Self {
            frames: frames.max(30),
            ..Default::default()
        }
    }
}

/// CPU time of the calling thread in ns (`clock_gettime(CLOCK_THREAD_CPUTIME_ID)`),
/// so that a busy machine does not inflate the figures as wall time does.
/// (`/proc/thread-self/schedstat`, used before, only advances at scheduler
/// ticks and read 0 ms for most sub-tick frames.)
#[cfg(target_os = "linux")]
fn thread_cpu_ns() -> Option<u64> {
    let t = rustix::time::clock_gettime(rustix::time::ClockId::ThreadCPUTime);
    Some(t.tv_sec as u64 * 1_000_000_000 + t.tv_nsec as u64)
}

/// CPU time of the whole process in ns (all threads: with llvmpipe this
/// includes the software rasterizer's threads).
#[cfg(target_os = "linux")]
fn process_cpu_ns() -> Option<u64> {
    let t = rustix::time::clock_gettime(rustix::time::ClockId::ProcessCPUTime);
    Some(t.tv_sec as u64 * 1_000_000_000 + t.tv_nsec as u64)
}

#[cfg(not(target_os = "linux"))]
fn thread_cpu_ns() -> Option<u64> {
    None
}

#[cfg(not(target_os = "linux"))]
fn process_cpu_ns() -> Option<u64> {
    None
}

fn quantiles(v: &[f64]) -> Option<(f64, f64, f64)> {
    // skip warm-up frames
    let mut t: Vec<f64> = v.iter().copied().skip(5).filter(|x| x.is_finite()).collect();
    if t.is_empty() {
        return None;
    }
    t.sort_by(f64::total_cmp);
    let q = |x: f64| t[((t.len() - 1) as f64 * x).round() as usize];
    Some((q(0.5), q(0.95), q(1.0)))
}

impl App {
    /// One frame of the benchmark.
    pub(crate) fn bench_frame(&mut self, ui: &mut egui::Ui, last_frame_cpu: Option<f32>) {
        let Some((i, phase)) = self.bench_record_cycle(last_frame_cpu) else {
            return;
        };
        self.curve_ws.benchmarking = true;
        self.bench_drive(i, phase);
        self.bench_timed_show(ui, phase);
        if self.bench.as_ref().is_some_and(|b| b.frame_no >= b.frames) {
            self.bench_finish(ui);
        }
    }

    /// Records the previous frame cycle's times and advances the frame counter: the frame's
    /// number and phase, `None` when no benchmark runs.
    fn bench_record_cycle(&mut self, last_frame_cpu: Option<f32>) -> Option<(usize, usize)> {
        let b = self.bench.as_mut()?;
        let i = b.frame_no;
        let third = b.frames / 3;
        let phase_of = |i: usize| (i / third).min(2);
        let phase = phase_of(i);
        if i > 0
            && let Some(c) = last_frame_cpu
        {
            // eframe reports the previous frame
            b.frame[phase_of(i - 1)].push(c as f64 * 1e3);
        }
        // one whole frame cycle, measured from this frame's start to the previous one's
        let now = thread_cpu_ns().zip(process_cpu_ns());
        if let (Some((t0, p0)), Some((t1, p1))) = (b.last_cpu, now)
            && i > 0
        {
            b.frame_cpu[phase_of(i - 1)].push((t1 - t0) as f64 * 1e-6);
            b.frame_proc[phase_of(i - 1)].push((p1 - p0) as f64 * 1e-6);
        }
        b.last_cpu = now;
        b.frame_no += 1;
        Some((i, phase))
    }

    /// Simulates this frame's input: a tolerance sweep, a target point drag or a region end drag.
    fn bench_drive(&mut self, i: usize, phase: usize) {
        if i == 0 && self.region().is_none() {
            let (a, e) = self.curve().domain();
            self.apply(Command::SetRegion(Some((a + 0.2 * (e - a), a + 0.8 * (e - a)))));
        }
        let d = self.curve_ws.view.diag;
        if phase == 0 {
            self.apply(Command::SetTolerance(d * 1e-3 * (1.0 + 0.5 * (i as f64 * 0.3).sin())));
        } else if phase == 2 {
            // drag the region's end handle: ±5% of the domain around where it started
            let (u1, u2) = *self
                .bench
                .as_mut()
                .unwrap()
                .start_region
                .get_or_insert(self.doc.settings.region.unwrap_or_default());
            let (a, e) = self.curve().domain();
            let h = 1e-3 * (e - a);
            let moved = u2 + 0.05 * (e - a) * (i as f64 * 0.3).sin();
            // a region across the seam (u1 > u2) keeps its end in [a, u1)
            let u2 = if u1 > u2 {
                moved.min(u1 - h).max(a + h)
            } else {
                moved.max(u1 + h).min(e)
            };
            self.apply(Command::SetRegion(Some((u1, u2))));
        } else if let Some(p) = self.curve_ws.preview().cloned() {
            // drag the middle target point: quintic falloff over 10% of the samples
            let start = self
                .bench
                .as_mut()
                .unwrap()
                .start_target
                .get_or_insert(p.target.clone())
                .clone();
            let n = start.len();
            let (k0, radius) = (n / 2, (n as f64 * 0.1).max(2.0));
            let kmax = start.iter().fold(0.0f64, |a, x| a.max(x.abs())).max(1e-12);
            let dk = 0.3 * kmax * (i as f64 * 0.3).sin();
            let values: Vec<f64> = (0..n)
                .map(|k| {
                    let r = (k as f64 - k0 as f64).abs() / radius;
                    if r < 1.0 && !p.pinned[k] {
                        start[k] + dk * fairway::fair::target::quintic(1.0 - r)
                    } else {
                        start[k]
                    }
                })
                .collect();
            let pinned = crate::fairing::pinned_indices(&p.pinned);
            self.apply(Command::SetTarget {
                values: Some(values),
                pinned,
            });
        }
    }

    /// Runs `show` and records its wall and CPU times and the re-fair time.
    fn bench_timed_show(&mut self, ui: &mut egui::Ui, phase: usize) {
        let t0 = std::time::Instant::now();
        let c0 = thread_cpu_ns();
        self.show(ui);
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        let cpu = thread_cpu_ns()
            .zip(c0)
            .map(|(b, a)| (b - a) as f64 * 1e-6)
            .unwrap_or(f64::NAN);
        let mut fair = self.curve_ws.preview().map(|p| p.fair_ms).unwrap_or(f64::NAN);
        if phase == 2 {
            fair += self.curve_ws.fairing.setup_ms;
        }
        let b = self.bench.as_mut().unwrap();
        b.cpu[phase].push(cpu);
        b.times[phase].push(ms);
        b.fair[phase].push(fair);
        ui.ctx().request_repaint();
    }

    /// Prints the quantiles of each phase and closes the app.
    fn bench_finish(&mut self, ui: &mut egui::Ui) {
        let n_points = self.curve().n_points();
        let b = self.bench.take().unwrap();
        for (ph, name) in [
            (0, "tolerance slider"),
            (1, "target point drag"),
            (2, "region end drag, new setup per frame"),
        ] {
            let mut line = format!(
                "bench ({name}, {n_points} control points, target {:?}, integrator {:?}):",
                self.prefs.fair.method, self.prefs.fair.integrator
            );
            for (what, v) in [
                ("show() thread CPU", &b.cpu[ph]),
                ("whole frame main-thread CPU", &b.frame_cpu[ph]),
                (
                    "whole frame process CPU (all threads, llvmpipe included)",
                    &b.frame_proc[ph],
                ),
                ("show() wall", &b.times[ph]),
                (if ph == 2 { "setup + fair wall" } else { "re-fair wall" }, &b.fair[ph]),
                ("eframe frame wall (UI + tessellation + wgpu submit)", &b.frame[ph]),
            ] {
                if let Some((m, p95, max)) = quantiles(v) {
                    line += &format!(" {what} median {m:.2} ms, p95 {p95:.2}, max {max:.2};");
                }
            }
            println!("{line}");
        }
        self.allow_close();
        ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
    }
}
