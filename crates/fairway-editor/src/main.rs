//! `fairway-editor [FILE] [options]` (`--help` lists them, parsed by clap): opens FILE, or the bundled sample
//! `assets/car_roof.ron` (looked up in the working directory, then next to
//! the workspace this binary was built from).

use std::path::PathBuf;

use eframe::egui;

/// The Fairway editor: fair B-spline curves and surfaces inside a tolerance band.
#[derive(clap::Parser, Debug)]
#[command(name = "fairway-editor", version, about)]
struct Args {
    /// The file to open (.ron, .json, .igs, .stp, ...; default: the bundled sample assets/car_roof.ron).
    file: Option<PathBuf>,
    /// Preselect the region [U1, U2] (curve parameter; U1 > U2 on a closed curve: across the seam).
    #[arg(long, num_args = 2, value_names = ["U1", "U2"], allow_hyphen_values = true)]
    region: Option<Vec<f64>>,
    /// Preselect the tolerance (model units).
    #[arg(long, allow_hyphen_values = true)]
    tolerance: Option<f64>,
    /// Run N frames (sweep the tolerance, drag a target point, drag the region end), print CPU times, quit.
    #[arg(long, value_name = "N")]
    bench_frames: Option<usize>,
    /// Use the built-in noisy demo curve with P control points.
    #[arg(long, value_name = "P")]
    demo_points: Option<usize>,
    /// Preselect a surface region.
    #[arg(long, num_args = 4, value_names = ["U1", "U2", "V1", "V2"], allow_hyphen_values = true)]
    region_uv: Option<Vec<f64>>,
    /// 3D shading: shaded, isophotes, zebra, mean, gauss, kmax, kmin.
    #[arg(long, value_name = "MODE")]
    shade: Option<fairway_editor::view3d::ShadeMode>,
    /// Surfaces: before and after side by side.
    #[arg(long)]
    side_by_side: bool,
    /// Curves: open the 3D view.
    #[arg(long)]
    view3d: bool,
    /// Curves: open the 3D view with extrusion isophotes.
    #[arg(long)]
    extrusion: bool,
    /// Isophote / zebra stripe width in degrees.
    #[arg(long, value_name = "DEG")]
    stripe: Option<f64>,
    /// Write the view as PNG once laid out, then quit (for reports and scripts).
    #[arg(long, value_name = "PATH")]
    export_png: Option<PathBuf>,
    /// Initial window size in points (default 1500 950; each in [200, 10000]).
    #[arg(long, num_args = 2, value_names = ["W", "H"], value_parser = window_side)]
    window_size: Option<Vec<f32>>,
}

impl Args {
    /// The file to open at start: none with `--demo-points`, else FILE or the bundled sample.
    fn file_to_open(&self) -> Option<PathBuf> {
        if self.demo_points.is_some() {
            None
        } else {
            self.file.clone().or_else(default_sample)
        }
    }
}

fn window_side(s: &str) -> Result<f32, String> {
    let x: f32 = s.parse().map_err(|e| format!("{s:?}: {e}"))?;
    if (200.0..=10000.0).contains(&x) {
        Ok(x)
    } else {
        Err(format!("{x} is outside [200, 10000]"))
    }
}

fn default_sample() -> Option<PathBuf> {
    let rel = PathBuf::from("assets/car_roof.ron");
    if rel.exists() {
        return Some(rel);
    }
    let built = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/car_roof.ron");
    built.exists().then_some(built)
}

fn main() -> eframe::Result {
    let args = <Args as clap::Parser>::parse();
    let (region, tolerance, bench, demo, export_png, size) = (
        args.region.clone(),
        args.tolerance,
        args.bench_frames,
        args.demo_points,
        args.export_png.clone(),
        args.window_size.clone(),
    );
    let v3 = View3dArgs {
        region_uv: args.region_uv.clone(),
        shade: args.shade,
        side_by_side: args.side_by_side,
        view3d: args.view3d,
        extrusion: args.extrusion,
        stripe: args.stripe,
    };
    let path = args.file_to_open();
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size(size.map(|s| [s[0], s[1]]).unwrap_or([1500.0, 950.0]))
            .with_title("Fairway")
            .with_drag_and_drop(true),
        renderer: eframe::Renderer::Wgpu,
        ..Default::default()
    };
    eframe::run_native(
        "Fairway",
        options,
        Box::new(move |cc| {
            let mut app = fairway_editor::App::new(cc, path.as_deref());
            if let Some(n) = demo {
                let prefs = app.prefs.clone();
                app = fairway_editor::App::with_document(
                    fairway::io::Document::new(fairway::Geometry::Curve(fairway_editor::demo_curve_n(n))),
                    None,
                )
                .with_default_autosave();
                app.prefs = prefs;
            }
            if let Some(r) = region.filter(|_| app.surface.is_none()) {
                let v = &app.curve_ws.view;
                app.doc.settings.region = Some(fairway_editor::region::canonical((r[0], r[1]), v.domain, v.closed));
            }
            if let Some(t) = tolerance {
                app.doc.settings.tolerance = Some(t);
            }
            v3.apply(&mut app, tolerance);
            app.bench = bench.map(fairway_editor::Bench::new);
            if app.bench.is_some() {
                // measure the defaults, not whatever fairing options this user's stored settings hold
                // (an old stored target method, e.g. Average, changes the cost)
                app.prefs = fairway_editor::Prefs::default();
            }
            if let Some(p) = export_png.clone() {
                app.export_png_then_quit(p);
            }
            Ok(Box::new(app))
        }),
    )
}

/// Command-line presets of the 3D views (for screenshots and demos).
struct View3dArgs {
    region_uv: Option<Vec<f64>>,
    shade: Option<fairway_editor::view3d::ShadeMode>,
    side_by_side: bool,
    view3d: bool,
    extrusion: bool,
    stripe: Option<f64>,
}

impl View3dArgs {
    fn apply(&self, app: &mut fairway_editor::App, tolerance: Option<f64>) {
        if let Some(s) = app.surface.as_mut() {
            if let Some(r) = &self.region_uv {
                app.doc.settings.region_uv = Some(((r[0], r[1]), (r[2], r[3])));
            }
            if let Some(t) = &tolerance {
                app.doc.settings.tolerance = Some(*t);
            }
            if let Some(m) = self.shade {
                s.shading.mode = m;
            }
            if let Some(w) = self.stripe {
                s.shading.stripe_deg = w;
            }
            s.compare.side_by_side = self.side_by_side;
        }
        app.curve_ws.curve3d.enabled |= self.view3d || self.extrusion;
        app.curve_ws.curve3d.extrusion |= self.extrusion;
        if let Some(m) = self.shade {
            app.curve_ws.curve3d.shading.mode = m;
        }
        if let Some(w) = self.stripe {
            app.curve_ws.curve3d.shading.stripe_deg = w;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;
    use clap::error::ErrorKind;
    use fairway_editor::view3d::ShadeMode;

    fn parse(args: &[&str]) -> Result<Args, clap::Error> {
        Args::try_parse_from(std::iter::once("fairway-editor").chain(args.iter().copied()))
    }

    #[test]
    fn no_arguments_open_the_sample_with_nothing_preset() {
        let a = parse(&[]).unwrap();
        assert_eq!(a.file, None);
        assert_eq!((&a.region, a.tolerance, &a.region_uv), (&None, None, &None));
        assert_eq!((a.bench_frames, a.demo_points, &a.window_size), (None, None, &None));
        assert!(!a.side_by_side && !a.view3d && !a.extrusion);
        assert_eq!(a.file_to_open(), default_sample());
    }

    #[test]
    fn every_option_is_parsed() {
        let a = parse(&[
            "hull.stp",
            "--region",
            "-0.25",
            "0.5",
            "--tolerance",
            "1e-3",
            "--bench-frames",
            "20",
            "--region-uv",
            "0.1",
            "0.9",
            "-0.2",
            "0.8",
            "--shade",
            "zebra",
            "--side-by-side",
            "--view3d",
            "--extrusion",
            "--stripe",
            "7.5",
            "--export-png",
            "out.png",
            "--window-size",
            "800",
            "600",
        ])
        .unwrap();
        assert_eq!(a.file.as_deref(), Some(std::path::Path::new("hull.stp")));
        assert_eq!(a.file_to_open(), Some(PathBuf::from("hull.stp")));
        assert_eq!(a.region, Some(vec![-0.25, 0.5]), "negative parameters are values");
        assert_eq!(a.tolerance, Some(1e-3));
        assert_eq!(a.bench_frames, Some(20));
        assert_eq!(a.region_uv, Some(vec![0.1, 0.9, -0.2, 0.8]));
        assert_eq!(a.shade, Some(ShadeMode::Zebra));
        assert!(a.side_by_side && a.view3d && a.extrusion);
        assert_eq!(a.stripe, Some(7.5));
        assert_eq!(a.export_png, Some(PathBuf::from("out.png")));
        assert_eq!(a.window_size, Some(vec![800.0, 600.0]));
    }

    #[test]
    fn demo_points_open_no_file() {
        let a = parse(&["hull.ron", "--demo-points", "12"]).unwrap();
        assert_eq!(a.demo_points, Some(12));
        assert_eq!(a.file_to_open(), None);
    }

    #[test]
    fn bad_arguments_are_refused() {
        let kind = |args: &[&str]| parse(args).map(|_| ()).unwrap_err().kind();
        assert_eq!(kind(&["--region", "0.5"]), ErrorKind::WrongNumberOfValues);
        assert_eq!(kind(&["--region-uv", "0", "1", "0"]), ErrorKind::WrongNumberOfValues);
        assert_eq!(kind(&["--tolerance", "small"]), ErrorKind::ValueValidation);
        assert_eq!(kind(&["--shade", "plaid"]), ErrorKind::ValueValidation);
        assert_eq!(kind(&["--window-size", "100", "600"]), ErrorKind::ValueValidation);
        assert_eq!(kind(&["--window-size", "800", "20000"]), ErrorKind::ValueValidation);
        assert_eq!(kind(&["--bench-frames", "-3"]), ErrorKind::UnknownArgument);
        assert_eq!(kind(&["--no-such-option"]), ErrorKind::UnknownArgument);
        assert_eq!(kind(&["a.ron", "b.ron"]), ErrorKind::UnknownArgument);
        assert_eq!(kind(&["--help"]), ErrorKind::DisplayHelp);
        assert_eq!(kind(&["--version"]), ErrorKind::DisplayVersion);
    }
}
