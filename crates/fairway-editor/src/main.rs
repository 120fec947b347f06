//! `fairway-editor [FILE]`: opens FILE, or the bundled sample
//! `assets/car_roof.ron` (looked up in the working directory, then next to
//! the workspace this binary was built from).

use std::path::PathBuf;

use eframe::egui;

const USAGE: &str = "usage: fairway-editor [FILE.ron|FILE.json] [--region U1 U2] [--tolerance M]
       fairway-editor --bench-frames N [--demo-points P] [--region U1 U2]
  --region U1 U2     preselect the region [U1, U2] (curve parameter; U1 > U2 on a closed curve: across the seam)
  --tolerance M      preselect the tolerance (model units)
  --bench-frames N   N frames: sweep the tolerance, drag a target point, drag the region end; print CPU times, quit
  --demo-points P    use the built-in noisy demo curve with P control points
  --region-uv U1 U2 V1 V2   preselect a surface region
  --shade MODE       3D shading: shaded, isophotes, zebra, mean, gauss, kmax, kmin
  --side-by-side     surfaces: before and after side by side
  --view3d           curves: open the 3D view (--extrusion: extrusion isophotes)
  --stripe DEG       isophote / zebra stripe width in degrees
  --export-png PATH  write the view as PNG once laid out, then quit (for reports and scripts)
  --window-size W H  initial window size in points (default 1500 950)";

fn default_sample() -> Option<PathBuf> {
    let rel = PathBuf::from("assets/car_roof.ron");
    if rel.exists() {
        return Some(rel);
    }
    let built = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/car_roof.ron");
    built.exists().then_some(built)
}

/// Remove `name` and its `count` values from `args`; the parsed values.
fn take<T: std::str::FromStr>(args: &mut Vec<String>, name: &str, count: usize) -> Result<Option<Vec<T>>, String> {
    let Some(i) = args.iter().position(|a| a == name) else {
        return Ok(None);
    };
    if i + count >= args.len() {
        return Err(format!("{name} needs {count} value(s)"));
    }
    let vals: Result<Vec<T>, _> = args.drain(i..=i + count).skip(1).map(|v| v.parse::<T>()).collect();
    vals.map(Some).map_err(|_| format!("{name}: bad value"))
}

fn main() -> eframe::Result {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!("{USAGE}");
        return Ok(());
    }
    let parsed = (|| -> Result<_, String> {
        let region = take::<f64>(&mut args, "--region", 2)?;
        let tolerance = take::<f64>(&mut args, "--tolerance", 1)?;
        let bench = take::<usize>(&mut args, "--bench-frames", 1)?;
        let demo = take::<usize>(&mut args, "--demo-points", 1)?;
        let export_png = take::<PathBuf>(&mut args, "--export-png", 1)?.map(|mut v| v.remove(0));
        let size = take::<f32>(&mut args, "--window-size", 2)?;
        if size
            .as_ref()
            .is_some_and(|s| s.iter().any(|x| !(200.0..=10000.0).contains(x)))
        {
            return Err("--window-size: W and H must be in [200, 10000]".into());
        }
        let v3 = View3dArgs {
            region_uv: take::<f64>(&mut args, "--region-uv", 4)?,
            shade: take::<fairway_editor::view3d::ShadeMode>(&mut args, "--shade", 1)?.map(|v| v[0]),
            side_by_side: take::<String>(&mut args, "--side-by-side", 0)?.is_some(),
            view3d: take::<String>(&mut args, "--view3d", 0)?.is_some(),
            extrusion: take::<String>(&mut args, "--extrusion", 0)?.is_some(),
            stripe: take::<f64>(&mut args, "--stripe", 1)?.map(|v| v[0]),
        };
        if let Some(a) = args.iter().find(|a| a.starts_with("--")) {
            return Err(format!("unknown option {a}"));
        }
        Ok((region, tolerance, bench, demo, v3, export_png, size))
    })();
    let (region, tolerance, bench, demo, v3, export_png, size) = match parsed {
        Ok(v) => v,
        Err(e) => {
            eprintln!("fairway-editor: {e}\n{USAGE}");
            std::process::exit(2);
        }
    };
    let path = if demo.is_some() {
        None
    } else {
        args.first().map(PathBuf::from).or_else(default_sample)
    };
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
                    fairway::io::Document::new(fairway::Geometry::Curve(fairway_editor::demo_curve_n(n[0]))),
                    None,
                )
                .with_default_autosave();
                app.prefs = prefs;
            }
            if let Some(r) = region {
                let v = &app.view;
                app.doc.settings.region = Some(fairway_editor::region::canonical((r[0], r[1]), v.domain, v.closed));
            }
            if let Some(t) = &tolerance {
                app.doc.settings.tolerance = Some(t[0]);
            }
            v3.apply(&mut app, tolerance.as_ref().map(|t| t[0]));
            app.bench = bench.map(|f| fairway_editor::Bench::new(f[0]));
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
                s.doc.settings.region_uv = Some(((r[0], r[1]), (r[2], r[3])));
            }
            if let Some(t) = &tolerance {
                s.doc.settings.tolerance = Some(*t);
            }
            if let Some(m) = self.shade {
                s.shading.mode = m;
            }
            if let Some(w) = self.stripe {
                s.shading.stripe_deg = w;
            }
            s.compare.side_by_side = self.side_by_side;
        }
        app.curve3d.enabled |= self.view3d || self.extrusion;
        app.curve3d.extrusion |= self.extrusion;
        if let Some(m) = self.shade {
            app.curve3d.shading.mode = m;
        }
        if let Some(w) = self.stripe {
            app.curve3d.shading.stripe_deg = w;
        }
    }
}
