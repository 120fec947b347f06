//! Writing Part 21 (AP214, `AUTOMOTIVE_DESIGN`): a minimal product
//! structure, a representation context with the length unit, and the
//! B-splines as `B_SPLINE_..._WITH_KNOTS` (rational ones as complex
//! instances).

use glam::DVec3;

use super::units::{conversion_name, si_prefix};
use super::{PLANAR_NAME, WriteOptions};
use crate::curve::BSplineCurve;
use crate::geometry::Geometry;
use crate::surface::BSplineSurface;
use crate::trim::FaceTrim;

/// A float as a Part 21 real: the shortest decimal that parses back to the same f64, always with a
/// decimal point, the exponent as `E` (`1.5`, `1.0E-7`, `-0.0`).
pub fn format_real(x: f64) -> String {
    let s = format!("{x:?}");
    let (mant, exp) = match s.split_once('e') {
        Some((m, e)) => (m.to_string(), Some(e)),
        None => (s.clone(), None),
    };
    let mant = if mant.contains('.') { mant } else { format!("{mant}.0") };
    match exp {
        Some(e) => format!("{mant}E{e}"),
        None => mant,
    }
}

/// A Part 21 string literal: `'` doubled, `\` doubled, non-ASCII as `\X2\..\X0\` (UTF-16).
pub(super) fn string(s: &str) -> String {
    let mut out = String::from("'");
    for c in s.chars() {
        match c {
            '\'' => out.push_str("''"),
            '\\' => out.push_str("\\\\"),
            ' '..='~' => out.push(c),
            _ => {
                out.push_str("\\X2\\");
                let mut buf = [0u16; 2];
                for u in c.encode_utf16(&mut buf) {
                    out.push_str(&format!("{u:04X}"));
                }
                out.push_str("\\X0\\");
            }
        }
    }
    out.push('\'');
    out
}

fn reals(v: impl IntoIterator<Item = f64>) -> String {
    let v: Vec<String> = v.into_iter().map(format_real).collect();
    format!("({})", v.join(","))
}

pub(super) fn refs(v: &[u64]) -> String {
    let v: Vec<String> = v.iter().map(|r| format!("#{r}")).collect();
    format!("({})", v.join(","))
}

/// Distinct knots and their multiplicities, as (multiplicities, knots) lists.
fn knot_lists(knots: &[f64]) -> (String, String) {
    let mut mults: Vec<usize> = Vec::new();
    let mut values: Vec<f64> = Vec::new();
    for &u in knots {
        if values.last() == Some(&u) {
            *mults.last_mut().expect("a value has a count") += 1;
        } else {
            values.push(u);
            mults.push(1);
        }
    }
    let m: Vec<String> = mults.iter().map(usize::to_string).collect();
    (format!("({})", m.join(",")), reals(values))
}

fn logical(b: bool) -> &'static str {
    if b { ".T." } else { ".F." }
}

/// The data section being written: numbered instances, lines wrapped at commas.
pub(super) struct Data {
    text: String,
    next: u64,
}

impl Data {
    pub(super) fn add(&mut self, body: &str) -> u64 {
        let id = self.next;
        self.next += 1;
        let line = format!("#{id}={body};");
        self.text.push_str(&wrap(&line, 78));
        self.text.push('\n');
        id
    }

    pub(super) fn point(&mut self, q: DVec3) -> u64 {
        self.add(&format!("CARTESIAN_POINT('',{})", reals([q.x, q.y, q.z])))
    }

    fn curve(&mut self, c: &BSplineCurve, name: &str) -> u64 {
        self.curve_in(c, name, 3)
    }

    /// A curve whose points are written with `dim` coordinates (2: a curve in a surface's (u, v)).
    pub(super) fn curve_in(&mut self, c: &BSplineCurve, name: &str, dim: usize) -> u64 {
        let pts: Vec<u64> = (c.points().iter())
            .map(|&q| match dim {
                2 => self.add(&format!("CARTESIAN_POINT('',{})", reals([q.x, q.y]))),
                _ => self.point(q),
            })
            .collect();
        let (mults, knots) = knot_lists(c.knots().values());
        let closed = logical(c.points().first() == c.points().last());
        let base = format!("{},{},.UNSPECIFIED.,{closed},.F.", c.degree(), refs(&pts));
        let body = match c.weights() {
            None => format!(
                "B_SPLINE_CURVE_WITH_KNOTS({},{base},{mults},{knots},.UNSPECIFIED.)",
                string(name)
            ),
            Some(w) => format!(
                "(BOUNDED_CURVE()B_SPLINE_CURVE({base})B_SPLINE_CURVE_WITH_KNOTS({mults},{knots},.UNSPECIFIED.)\
                 CURVE()GEOMETRIC_REPRESENTATION_ITEM()RATIONAL_B_SPLINE_CURVE({})REPRESENTATION_ITEM({}))",
                reals(w.iter().copied()),
                string(name)
            ),
        };
        self.add(&body)
    }

    pub(super) fn surface(&mut self, s: &BSplineSurface, name: &str) -> u64 {
        let (nu, nv) = (s.nu(), s.nv());
        let mut rows = Vec::with_capacity(nu);
        for i in 0..nu {
            let row: Vec<u64> = (0..nv).map(|j| self.point(s.point_at(i, j))).collect();
            rows.push(refs(&row));
        }
        let (mu, ku) = knot_lists(s.knots_u().values());
        let (mv, kv) = knot_lists(s.knots_v().values());
        let u_closed = (0..nv).all(|j| s.point_at(0, j) == s.point_at(nu - 1, j));
        let v_closed = (0..nu).all(|i| s.point_at(i, 0) == s.point_at(i, nv - 1));
        let base = format!(
            "{},{},({}),.UNSPECIFIED.,{},{},.F.",
            s.degree_u(),
            s.degree_v(),
            rows.join(","),
            logical(u_closed),
            logical(v_closed)
        );
        let knots = format!("{mu},{mv},{ku},{kv},.UNSPECIFIED.");
        let body = match s.weights() {
            None => format!("B_SPLINE_SURFACE_WITH_KNOTS({},{base},{knots})", string(name)),
            Some(w) => {
                let wrows: Vec<String> = w.chunks(nv).map(|r| reals(r.iter().copied())).collect();
                format!(
                    "(BOUNDED_SURFACE()B_SPLINE_SURFACE({base})B_SPLINE_SURFACE_WITH_KNOTS({knots})\
                     GEOMETRIC_REPRESENTATION_ITEM()RATIONAL_B_SPLINE_SURFACE(({}))REPRESENTATION_ITEM({})SURFACE())",
                    wrows.join(","),
                    string(name)
                )
            }
        };
        self.add(&body)
    }

    /// The length unit and a 3D representation context using it.
    pub(super) fn context(&mut self, opts: &WriteOptions) -> u64 {
        let length = match si_prefix(opts.unit) {
            Some(prefix) => self.add(&format!("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT({prefix},.METRE.))")),
            None => {
                let mm = self.add("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))");
                let dims = self.add("DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.)");
                let factor = self.add(&format!(
                    "LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE({}),#{mm})",
                    format_real(opts.unit.in_mm())
                ));
                self.add(&format!(
                    "(CONVERSION_BASED_UNIT({},#{factor})LENGTH_UNIT()NAMED_UNIT(#{dims}))",
                    string(conversion_name(opts.unit))
                ))
            }
        };
        let angle = self.add("(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.))");
        let solid = self.add("(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT())");
        let unc = self.add(&format!(
            "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.0E-7),#{length},'distance_accuracy_value','confusion accuracy')"
        ));
        self.add(&format!(
            "(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#{unc}))\
             GLOBAL_UNIT_ASSIGNED_CONTEXT((#{length},#{angle},#{solid}))REPRESENTATION_CONTEXT('3D','3D context'))"
        ))
    }
}

/// Break a line after commas (outside strings) so no line is longer than about `width`.
fn wrap(line: &str, width: usize) -> String {
    let mut out = String::with_capacity(line.len() + line.len() / width);
    let (mut col, mut in_str) = (0, false);
    for c in line.chars() {
        out.push(c);
        col += 1;
        if c == '\'' {
            in_str = !in_str;
        }
        if c == ',' && !in_str && col >= width {
            out.push('\n');
            col = 0;
        }
    }
    out
}

/// The product structure (`PRODUCT` .. `PRODUCT_DEFINITION_SHAPE`); returns the shape's number.
fn product(d: &mut Data, name: &str) -> u64 {
    let app = d.add("APPLICATION_CONTEXT('automotive design')");
    d.add(&format!(
        "APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,#{app})"
    ));
    let pc = d.add(&format!("PRODUCT_CONTEXT('',#{app},'mechanical')"));
    let n = string(name);
    let prod = d.add(&format!("PRODUCT({n},{n},'',(#{pc}))"));
    d.add(&format!("PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#{prod}))"));
    let form = d.add(&format!("PRODUCT_DEFINITION_FORMATION('','',#{prod})"));
    let pdc = d.add(&format!(
        "PRODUCT_DEFINITION_CONTEXT('part definition',#{app},'design')"
    ));
    let pd = d.add(&format!("PRODUCT_DEFINITION('design','',#{form},#{pdc})"));
    d.add(&format!("PRODUCT_DEFINITION_SHAPE('','',#{pd})"))
}

/// One shape representation of `items` in a 3D context: a wireframe one with a
/// `GEOMETRIC_CURVE_SET` when all are curves, else a surface one with a `GEOMETRIC_SET`.
fn representation(d: &mut Data, opts: &WriteOptions, shape: u64, items: &[u64], curves_only: bool) {
    let ctx = d.context(opts);
    let (set, rep) = if curves_only {
        (
            "GEOMETRIC_CURVE_SET",
            "GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION",
        )
    } else {
        ("GEOMETRIC_SET", "GEOMETRICALLY_BOUNDED_SURFACE_SHAPE_REPRESENTATION")
    };
    let set = d.add(&format!("{set}('',{})", refs(items)));
    let rep = d.add(&format!("{rep}('',(#{set}),#{ctx})"));
    d.add(&format!("SHAPE_DEFINITION_REPRESENTATION(#{shape},#{rep})"));
}

/// The whole file; see [`super::write`] (`trims[k]`: the bounds of `objects[k]`, a surface written as a
/// trimmed face, [`super::write_trim`]).
pub fn write(objects: &[Geometry], names: &[String], trims: &[Option<FaceTrim>], opts: &WriteOptions) -> String {
    let stamp = opts.date_or_now().to_iso8601();
    let file_name = opts.file_name_or("fairway.stp");
    let stem = std::path::Path::new(file_name)
        .file_stem()
        .map_or("fairway".into(), |s| s.to_string_lossy().into_owned());
    let mut d = Data {
        text: String::new(),
        next: 1,
    };
    let shape = product(&mut d, &stem);
    // 2D curves go in the 3D representation with z = 0, as every CAD system reads them (OpenCASCADE
    // ignores a 2D context), named "2D curve k" so Fairway reads them back as 2D curves
    let mut faces = vec![];
    let mut items = vec![];
    for (k, g) in objects.iter().enumerate() {
        let name = names.get(k).filter(|n| !n.is_empty());
        if let (Geometry::Surface(s), Some(Some(t))) = (g, trims.get(k)) {
            let name = name.cloned().unwrap_or_else(|| format!("surface {}", k + 1));
            faces.push(super::write_trim::face(&mut d, s, t, &name));
            continue;
        }
        items.push({
            match (g, name) {
                (Geometry::Curve(c), None) if c.dim() == 2 => d.curve(c, &format!("{PLANAR_NAME} {}", k + 1)),
                (Geometry::Curve(c), Some(n)) if c.dim() == 2 => d.curve(c, &format!("{PLANAR_NAME}: {n}")),
                (Geometry::Curve(c), None) => d.curve(c, &format!("curve {}", k + 1)),
                (Geometry::Surface(s), None) => d.surface(s, &format!("surface {}", k + 1)),
                (Geometry::Curve(c), Some(n)) => d.curve(c, n),
                (Geometry::Surface(s), Some(n)) => d.surface(s, n),
            }
        });
    }
    let curves_only = objects.iter().all(|g| matches!(g, Geometry::Curve(_)));
    if !items.is_empty() {
        representation(&mut d, opts, shape, &items, curves_only);
    }
    if !faces.is_empty() {
        super::write_trim::faces_representation(&mut d, opts, shape, &faces);
    }
    format!(
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('Fairway export: B-spline curves and surfaces'),'2;1');\n\
         FILE_NAME({},{},(''),(''),{},'Fairway','');\n\
         FILE_SCHEMA(('AUTOMOTIVE_DESIGN {{ 1 0 10303 214 1 1 1 1 }}'));\nENDSEC;\nDATA;\n{}ENDSEC;\nEND-ISO-10303-21;\n",
        string(file_name),
        string(&stamp),
        string(&format!("Fairway {}", env!("CARGO_PKG_VERSION"))),
        d.text
    )
}
