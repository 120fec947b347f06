#!/usr/bin/env bash
# STEP round trips against an independent reader/writer: OpenCASCADE (OCCT), through its Python
# package cadquery-ocp in a throw-away venv. Not part of CI (the package is large and slow to install).
#
#   OCC → Fairway: OCC writes B-spline curves (as edges: non-rational, rational circle arcs, random
#   weights, multiple knots, a periodic full circle, which Fairway reads clamped) and surfaces (as faces: non-rational, a rational sphere
#   patch, random weights) to STEP, in mm and in inch; `fairway info --json` must list them with the
#   file's unit, `fairway convert --index k` extracts each to JSON, and the curve or surface Fairway read
#   is evaluated (by OCC, and by `fairway eval`) against OCC's original at sample parameters.
#   Fairway → OCC: `fairway convert` writes STEP (from JSON, and STEP → STEP keeping the inch unit);
#   OCC reads it back (in mm, its session unit) and evaluates against the original.
#
# Prints one line per case with the largest point distance (mm) at the sample parameters; exits 1 if
# any distance exceeds 1e-9 × the object's size or a file is not read.
#
# Usage: scripts/step_roundtrip_occ.sh [VENV]   (default VENV: /tmp/occ-venv)
source "$(dirname "$0")/occ-env.sh"
FAIRWAY="$FAIRWAY" WORK="$WORK" "$VENV/bin/python" - <<'PY'
import json, math, os, random, subprocess, sys

from OCP.OCP.collections import Array1_gp_Pnt, Array1_double, Array1_int, Array2_gp_Pnt, Array2_double
from OCP.gp import gp_Pnt, gp_Ax2, gp_Ax3, gp_Dir, gp_Circ
from OCP.Geom import (Geom_BSplineCurve, Geom_BSplineSurface, Geom_Circle, Geom_TrimmedCurve,
                      Geom_SphericalSurface, Geom_RectangularTrimmedSurface)
from OCP.GeomConvert import GeomConvert
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace
from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Surface
from OCP.STEPControl import STEPControl_Writer, STEPControl_Reader, STEPControl_StepModelType
from OCP.IFSelect import IFSelect_ReturnStatus
from OCP.Interface import Interface_Static
from OCP.TopExp import TopExp_Explorer
from OCP.TopAbs import TopAbs_ShapeEnum
from OCP.TopoDS import TopoDS

FAIRWAY, WORK = os.environ["FAIRWAY"], os.environ["WORK"]
INCH = 25.4
rng = random.Random(29)
failures = []


class quiet:
    """OCC prints transfer statistics on stdout: send fd 1 to /dev/null meanwhile."""
    def __enter__(self):
        sys.stdout.flush()
        self.saved = os.dup(1)
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 1)
        os.close(devnull)

    def __exit__(self, *a):
        sys.stdout.flush()
        os.dup2(self.saved, 1)
        os.close(self.saved)


def distinct(full):
    """Full knot vector → (distinct knots, multiplicities)."""
    ks, ms = [], []
    for u in full:
        if ks and u == ks[-1]:
            ms[-1] += 1
        else:
            ks.append(u)
            ms.append(1)
    return ks, ms


def arr1(cls, values):
    a = cls(1, len(values))
    for i, v in enumerate(values):
        a.SetValue(i + 1, v)
    return a


def occ_curve(degree, knots, poles, weights=None, periodic=False):
    ks, ms = distinct(knots) if not periodic else knots
    P = arr1(Array1_gp_Pnt, [gp_Pnt(*p) for p in poles])
    K, M = arr1(Array1_double, ks), arr1(Array1_int, ms)
    if weights is None:
        return Geom_BSplineCurve(P, K, M, degree, periodic)
    return Geom_BSplineCurve(P, arr1(Array1_double, weights), K, M, degree, periodic)


def occ_surface(du, dv, ku, kv, poles, weights=None):
    nu, nv = len(poles), len(poles[0])
    P = Array2_gp_Pnt(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            P.SetValue(i + 1, j + 1, gp_Pnt(*poles[i][j]))
    (kus, mus), (kvs, mvs) = distinct(ku), distinct(kv)
    args = (arr1(Array1_double, kus), arr1(Array1_double, kvs), arr1(Array1_int, mus), arr1(Array1_int, mvs), du, dv)
    if weights is None:
        return Geom_BSplineSurface(P, *args)
    W = Array2_double(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            W.SetValue(i + 1, j + 1, weights[i][j])
    return Geom_BSplineSurface(P, W, *args)


def from_json(g, scale=1.0):
    """A Fairway JSON geometry as an OCC B-spline, coordinates × scale."""
    if "degree_u" in g:
        pts = [[[x * scale for x in p] for p in row] for row in g["points"]]
        return occ_surface(g["degree_u"], g["degree_v"], g["knots_u"], g["knots_v"], pts, g.get("weights"))
    pts = [[x * scale for x in (p + [0.0] * (3 - len(p)))] for p in g["points"]]
    return occ_curve(g["degree"], g["knots"], pts, g.get("weights"))


def full_knots(ks, ms):
    return [k for k, m in zip(ks, ms) for _ in range(m)]


def to_json(geom):
    """An OCC non-periodic B-spline as Fairway JSON."""
    if isinstance(geom, Geom_BSplineSurface):
        nu, nv = geom.NbUPoles(), geom.NbVPoles()
        pts = [[list(geom.Pole(i, j).Coord()) for j in range(1, nv + 1)] for i in range(1, nu + 1)]
        g = {"degree_u": geom.UDegree(), "degree_v": geom.VDegree(),
             "knots_u": full_knots([geom.UKnot(i) for i in range(1, geom.NbUKnots() + 1)],
                                   [geom.UMultiplicity(i) for i in range(1, geom.NbUKnots() + 1)]),
             "knots_v": full_knots([geom.VKnot(i) for i in range(1, geom.NbVKnots() + 1)],
                                   [geom.VMultiplicity(i) for i in range(1, geom.NbVKnots() + 1)]),
             "points": pts}
        if geom.IsURational() or geom.IsVRational():
            g["weights"] = [[geom.Weight(i, j) for j in range(1, nv + 1)] for i in range(1, nu + 1)]
        return g
    n = geom.NbPoles()
    g = {"degree": geom.Degree(),
         "knots": full_knots([geom.Knot(i) for i in range(1, geom.NbKnots() + 1)],
                             [geom.Multiplicity(i) for i in range(1, geom.NbKnots() + 1)]),
         "points": [list(geom.Pole(i).Coord()) for i in range(1, n + 1)]}
    if geom.IsRational():
        g["weights"] = [geom.Weight(i) for i in range(1, n + 1)]
    return g


def params(a, b, n):
    return [a + (b - a) * k / (n - 1) for k in range(n)]


def dist(p, q):
    return math.dist(p.Coord() if hasattr(p, "Coord") else p, q.Coord() if hasattr(q, "Coord") else q)


def size(geom):
    """Diagonal of the control points' box, for the relative bound."""
    g = to_json(geom)
    pts = [p for row in g["points"] for p in row] if "degree_u" in g else g["points"]
    lo = [min(p[k] for p in pts) for k in range(3)]
    hi = [max(p[k] for p in pts) for k in range(3)]
    return math.dist(lo, hi)


def max_dist(orig, other, n=201):
    """Largest distance between two curves (or surfaces) at the same parameters: n (or √n × √n)
    uniform samples of orig's domain."""
    if isinstance(orig, Geom_BSplineSurface):
        u0, u1, v0, v1 = orig.Bounds()
        m = 41
        return max(dist(orig.Value(u, v), other.Value(u, v)) for u in params(u0, u1, m) for v in params(v0, v1, m))
    return max(dist(orig.Value(u), other.Value(u)) for u in params(orig.FirstParameter(), orig.LastParameter(), n))


def write_occ(geom, path, unit):
    Interface_Static.SetCVal_s("write.step.unit", unit)
    shape = (BRepBuilderAPI_MakeFace(geom, 1e-7).Face() if isinstance(geom, Geom_BSplineSurface)
             else BRepBuilderAPI_MakeEdge(geom).Edge())
    w = STEPControl_Writer()
    with quiet():
        ok = w.Transfer(shape, STEPControl_StepModelType.STEPControl_AsIs) == IFSelect_ReturnStatus.IFSelect_RetDone
        ok = ok and w.Write(path) == IFSelect_ReturnStatus.IFSelect_RetDone
    assert ok, f"OCC could not write {path}"
    Interface_Static.SetCVal_s("write.step.unit", "MM")


def read_occ(path, surface):
    """The first face's surface or the first edge's curve of a STEP file read by OCC (in mm), as an
    evaluator with .Value (BRepAdaptor)."""
    r = STEPControl_Reader()
    with quiet():
        status = r.ReadFile(path)
        if status != IFSelect_ReturnStatus.IFSelect_RetDone:
            return None, f"ReadFile: {status}"
        r.TransferRoots()
        shape = r.OneShape()
    kind = TopAbs_ShapeEnum.TopAbs_FACE if surface else TopAbs_ShapeEnum.TopAbs_EDGE
    ex = TopExp_Explorer(shape, kind)
    if not ex.More():
        return None, "no face" if surface else "no edge"
    if surface:
        return BRepAdaptor_Surface(TopoDS.Face(ex.Current())), None
    return BRepAdaptor_Curve(TopoDS.Edge(ex.Current())), None


def fairway(*args):
    return subprocess.run([FAIRWAY, *args], capture_output=True, text=True)


def fairway_eval(path, geom, scale):
    """Fairway's own evaluation of a JSON file against OCC's original at the same parameters."""
    if isinstance(geom, Geom_BSplineSurface):
        e = json.loads(fairway("eval", path, "--json", "-n", "41").stdout)
        return max(dist(geom.Value(u, v), [x * scale for x in e["points"][i][j]])
                   for i, u in enumerate(e["u"]) for j, v in enumerate(e["v"]))
    e = json.loads(fairway("eval", path, "--json", "-n", "201").stdout)
    return max(dist(geom.Value(u), [x * scale for x in (p + [0.0] * (3 - len(p)))])
               for u, p in zip(e["parameters"], e["points"]))


def check(name, d, geom, what):
    bound = 1e-9 * max(size(geom), 1.0)
    flag = "ok" if d <= bound else "FAIL"
    if flag == "FAIL":
        failures.append(f"{name} {what}")
    print(f"  {name:<28} {what:<34} max distance {d:.3e} mm  ({flag}, bound {bound:.1e})")


# ---------------------------------------------------------------- the cases
def random_curve(degree, n, rational, interior_mults):
    k = [0.0] * (degree + 1)
    free = n - degree - 1
    u, interior = 0.0, []
    for m in interior_mults:
        u += rng.uniform(0.5, 1.5)
        interior += [u] * m
    while len(interior) < free:
        u += rng.uniform(0.5, 1.5)
        interior.append(u)
    k += interior[:free] + [u + 1.0] * (degree + 1)
    poles = [[rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-20, 20)] for _ in range(n)]
    w = [rng.uniform(0.3, 3.0) for _ in range(n)] if rational else None
    return occ_curve(degree, k, poles, w)


def random_surface(du, dv, nu, nv, rational):
    def knots(d, n):
        inner = sorted(rng.uniform(0.05, 0.95) for _ in range(n - d - 1))
        return [0.0] * (d + 1) + inner + [1.0] * (d + 1)
    poles = [[[i * 10.0 + rng.uniform(-2, 2), j * 10.0 + rng.uniform(-2, 2), rng.uniform(-5, 5)]
              for j in range(nv)] for i in range(nu)]
    w = [[rng.uniform(0.5, 2.0) for _ in range(nv)] for _ in range(nu)] if rational else None
    return occ_surface(du, dv, knots(du, nu), knots(dv, nv), poles, w)


arc = GeomConvert.CurveToBSplineCurve_s(
    Geom_TrimmedCurve(Geom_Circle(gp_Ax2(gp_Pnt(1, 2, 3), gp_Dir(0, 0, 1)), 25.0), 0.0, 2.0 * math.pi / 3.0))
full_circle = GeomConvert.CurveToBSplineCurve_s(Geom_Circle(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 1, 1)), 10.0))
sphere_patch = GeomConvert.SurfaceToBSplineSurface_s(
    Geom_RectangularTrimmedSurface(Geom_SphericalSurface(gp_Ax3(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 40.0),
                                   0.2, 1.4, -0.6, 0.9))
cases = [
    ("cubic, knots x1 x2", random_curve(3, 9, False, [1, 2]), "MM"),
    ("cubic, knots x1 x2 (inch)", random_curve(3, 9, False, [1, 2]), "INCH"),
    ("rational arc 120 deg", arc, "MM"),
    ("rational quintic, x3 knot", random_curve(5, 12, True, [3, 1]), "MM"),
    ("full circle (periodic)", full_circle, "MM"),
    ("bicubic 7x6", random_surface(3, 3, 7, 6, False), "MM"),
    ("rational sphere patch", sphere_patch, "MM"),
    ("rational sphere patch (inch)", sphere_patch, "INCH"),
    ("rational 2x3 random w", random_surface(2, 3, 5, 6, True), "MM"),
]

print("OCC → Fairway (OCC writes, fairway info/convert/eval read)")
for k, (name, geom, unit) in enumerate(cases):
    surface = isinstance(geom, Geom_BSplineSurface)
    stp = os.path.join(WORK, f"occ{k}.stp")
    write_occ(geom, stp, unit)
    info = fairway("info", stp, "--json")
    if info.returncode != 0:
        failures.append(f"{name}: fairway info failed")
        print(f"  {name:<28} fairway info failed: {info.stderr.strip()}")
        continue
    meta = json.loads(info.stdout)["file"]
    want_unit = "in" if unit == "INCH" else "mm"
    if meta["unit"] != want_unit:
        failures.append(f"{name}: unit {meta['unit']}")
    scale = INCH if meta["unit"] == "in" else 1.0
    # the object of the right kind: a face's file also holds its boundary curves
    found = None
    for idx in range(meta["objects"]):
        out = os.path.join(WORK, f"occ{k}_{idx}.json")
        r = fairway("convert", stp, out, "--index", str(idx))
        if r.returncode != 0:
            continue
        g = json.load(open(out))
        if ("degree_u" in g) == surface:
            found = (out, g)
            break
    notes = [l for l in info.stderr.splitlines() if "skipped" in l or "not applied" in l or "clamped" in l]
    if found is None:
        failures.append(f"{name}: not read")
        print(f"  {name:<28} NOT READ ({meta['objects']} objects, unit {meta['unit']}): {' | '.join(notes)}")
        continue
    out, g = found
    print(f"  {name:<28} {meta['objects']} objects, unit {meta['unit']}"
          + (f"; notices: {' | '.join(n.split(': ', 2)[-1] for n in notes)}" if notes else ""))
    check(name, max_dist(geom, from_json(g, scale)), geom, "read (OCC evaluates)")
    check(name, fairway_eval(out, geom, scale), geom, "read (fairway eval)")

print("Fairway → OCC (fairway convert writes STEP, OCC reads it in mm)")
for k, (name, geom, unit) in enumerate(cases):
    surface = isinstance(geom, Geom_BSplineSurface)
    periodic = not surface and geom.IsPeriodic()
    if unit == "MM" and not periodic:
        src = os.path.join(WORK, f"fw{k}.json")
        json.dump(to_json(geom), open(src, "w"))
    else:
        # OCC's file, STEP → STEP: keeps the inch unit; a periodic curve is written clamped
        src = os.path.join(WORK, f"occ{k}.stp")
    stp = os.path.join(WORK, f"fw{k}.stp")
    r = fairway("convert", src, stp, "--index", "0") if src.endswith(".stp") else fairway("convert", src, stp)
    if r.returncode != 0:
        failures.append(f"{name}: fairway convert failed")
        print(f"  {name:<28} fairway convert failed: {r.stderr.strip()}")
        continue
    if src.endswith(".stp") and surface:
        # object 0 of a face file may be a boundary curve: take the surface's index from info
        meta = json.loads(fairway("info", src, "--json").stdout)["file"]
        for idx in range(meta["objects"]):
            j = json.loads(fairway("info", src, "--json", "--index", str(idx)).stdout)
            if j["kind"] == "surface":
                fairway("convert", src, stp, "--index", str(idx))
                break
    back, err = read_occ(stp, surface)
    if back is None:
        failures.append(f"{name}: OCC could not read Fairway's file")
        print(f"  {name:<28} OCC could not read Fairway's file: {err}")
        continue
    check(name, max_dist(geom, back), geom, f"OCC reads Fairway's {unit} file")

# a 2D curve: Fairway writes it in a 2D context of its own
c2 = {"degree": 2, "knots": [0, 0, 0, 0.5, 1, 1, 1], "points": [[0, 0], [1, 2], [3, 2], [4, 0]],
      "weights": [1, 0.8, 1.3, 1]}
src, stp = os.path.join(WORK, "c2.json"), os.path.join(WORK, "c2.stp")
json.dump(c2, open(src, "w"))
fairway("convert", src, stp)
back, err = read_occ(stp, False)
geom = from_json(c2)
if back is None:
    print(f"  {'2D rational quadratic':<28} OCC reads no edge from Fairway's 2D curve ({err})")
else:
    check("2D rational quadratic", max_dist(geom, back), geom, "OCC reads Fairway's MM file")

if failures:
    print("FAILED:", "; ".join(failures))
    sys.exit(1)
print("all round trips within 1e-9 of the object's size")
PY
