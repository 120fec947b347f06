//! Frame-time benchmark (`fairway-editor --bench-frames N`): the first half
//! of the frames sweeps the tolerance (as a slider drag does), the second
//! half drags a target point up and down with the soft falloff (as the κ
//! plot's Drag tool does). Each frame re-fairs and redraws everything; the
//! CPU times of `App::show` (UI + re-fair + shape building), of the re-fair
//! alone, and eframe's whole frame (UI + tessellation + wgpu submission) are
//! printed as median / p90 / max, then the app quits.

use eframe::egui;

use crate::{App, Command};

/// Frame-time benchmark state.
#[derive(Debug, Clone, Default)]
pub struct Bench {
    /// Frames to run.
    pub frames: usize,
    /// `show` wall times so far (ms), per phase (0: tolerance, 1: target).
    pub times: [Vec<f64>; 2],
    /// `show` thread CPU times so far (ms), per phase.
    pub cpu: [Vec<f64>; 2],
    /// Re-fair times so far (ms), per phase.
    pub fair: [Vec<f64>; 2],
    /// eframe's whole-frame CPU time (ms), per phase.
    pub frame: [Vec<f64>; 2],
    frame_no: usize,
    start_target: Option<Vec<f64>>,
}

impl Bench {
    /// A benchmark of `frames` (≥ 20) frames.
    pub fn new(frames: usize) -> Self {
        Self {
            frames: frames.max(20),
            ..Default::default()
        }
    }
}

/// CPU time of the calling thread in ns (Linux `/proc/thread-self/schedstat`),
/// so that a busy machine does not inflate the figures as wall time does.
fn thread_cpu_ns() -> Option<u64> {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

fn quantiles(v: &[f64]) -> Option<(f64, f64, f64)> {
    // skip warm-up frames
    let mut t: Vec<f64> = v.iter().copied().skip(5).filter(|x| x.is_finite()).collect();
    if t.is_empty() {
        return None;
    }
    t.sort_by(f64::total_cmp);
    let q = |x: f64| t[((t.len() - 1) as f64 * x).round() as usize];
    Some((q(0.5), q(0.9), q(1.0)))
}

impl App {
    /// One frame of the benchmark.
    pub(crate) fn bench_frame(&mut self, ui: &mut egui::Ui, last_frame_cpu: Option<f32>) {
        let Some(b) = self.bench.as_mut() else { return };
        let i = b.frame_no;
        let half = b.frames / 2;
        let phase = usize::from(i >= half);
        if i > 0
            && let Some(c) = last_frame_cpu
        {
            // eframe reports the previous frame
            b.frame[usize::from(i > half)].push(c as f64 * 1e3);
        }
        b.frame_no += 1;
        if i == 0 && self.region().is_none() {
            let (a, e) = self.curve().domain();
            self.apply(Command::SetRegion(Some((a + 0.2 * (e - a), a + 0.8 * (e - a)))));
        }
        let d = self.view.diag;
        if phase == 0 {
            self.apply(Command::SetTolerance(d * 1e-3 * (1.0 + 0.5 * (i as f64 * 0.3).sin())));
        } else if let Some(p) = self.preview().cloned() {
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
            let pinned = p
                .pinned
                .iter()
                .enumerate()
                .filter(|(_, b)| **b)
                .map(|(k, _)| k)
                .collect();
            self.apply(Command::SetTarget {
                values: Some(values),
                pinned,
            });
        }
        let t0 = std::time::Instant::now();
        let c0 = thread_cpu_ns();
        self.show(ui);
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        let cpu = thread_cpu_ns()
            .zip(c0)
            .map(|(b, a)| (b - a) as f64 * 1e-6)
            .unwrap_or(f64::NAN);
        let fair = self.preview().map(|p| p.fair_ms).unwrap_or(f64::NAN);
        let b = self.bench.as_mut().unwrap();
        b.cpu[phase].push(cpu);
        b.times[phase].push(ms);
        b.fair[phase].push(fair);
        ui.ctx().request_repaint();
        if b.frame_no >= b.frames {
            let n_points = self.curve().n_points();
            let b = self.bench.take().unwrap();
            for (ph, name) in [(0, "tolerance slider"), (1, "target point drag")] {
                let mut line = format!("bench ({name}, {n_points} control points):");
                for (what, v) in [
                    ("show() thread CPU", &b.cpu[ph]),
                    ("show() wall", &b.times[ph]),
                    ("re-fair wall", &b.fair[ph]),
                    (
                        "whole frame wall (eframe: UI + tessellation + wgpu submit)",
                        &b.frame[ph],
                    ),
                ] {
                    if let Some((m, p90, max)) = quantiles(v) {
                        line += &format!(" {what} median {m:.2} ms, p90 {p90:.2}, max {max:.2};");
                    }
                }
                println!("{line}");
            }
            self.allow_close = true;
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }
}
