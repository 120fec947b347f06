#!/usr/bin/env bash
# Trimmed faces exported as IGES (144 → 128 + 142 per loop) against OpenCASCADE (OCCT through cadquery-ocp in
# a throw-away venv; not part of CI). OCC makes the face of step_trims_occ.sh (a noisy bicubic B-spline
# surface bounded by the rectangle [0.1, 0.9]² of its parameters, with a circular hole of radius 0.15 in
# (u, v)) and writes it as STEP. Fairway converts it to IGES (`fairway convert face.stp face.igs`) and to
# STEP (the STEP route), and fairs it to IGES (`fairway fair --tolerance m -o faired.igs`, m = 5e-4 × the
# face's size). OCC reads each IGES file (IGESControl_Reader): it must be one valid face (BRepCheck_Analyzer)
# with two wires (the outer loop and the hole) on a B-spline surface; every edge's 3D curve must lie on the
# face's surface (the largest distance at 200 points an edge, within 1e-6 × the surface's diagonal, the
# trims' fit tolerance, with a little slack); its area must agree with the STEP route's within perimeter ×
# that tolerance (converted) and with the original within perimeter × m (faired).
#
# Usage: scripts/iges_trims_occ.sh [VENV]   (default VENV: /tmp/occ-venv)
source "$(dirname "$0")/occ-env.sh"
"$VENV/bin/python" - "$FAIRWAY" "$WORK" <<'PY'
import json, math, random, subprocess, sys
from OCP.OCP.collections import Array1_double, Array1_int, Array2_gp_Pnt
from OCP.gp import gp_Pnt, gp_Pnt2d, gp_Dir2d, gp_Ax2d
from OCP.Geom import Geom_BSplineSurface
from OCP.Geom2d import Geom2d_Circle
from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire
from OCP.BRepLib import BRepLib
from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.BRep import BRep_Tool
from OCP.ShapeFix import ShapeFix_Face
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.GProp import GProp_GProps
from OCP.BRepGProp import BRepGProp
from OCP.STEPControl import STEPControl_Writer, STEPControl_Reader, STEPControl_StepModelType
from OCP.IGESControl import IGESControl_Reader
from OCP.TopExp import TopExp_Explorer
from OCP.TopAbs import TopAbs_ShapeEnum
from OCP.TopoDS import TopoDS

FAIRWAY, WORK = sys.argv[1], sys.argv[2]
random.seed(29)
n = 8
P = Array2_gp_Pnt(1, n, 1, n)
for i in range(n):
    for j in range(n):
        x, y = 10.0 * i / (n - 1), 10.0 * j / (n - 1)
        P.SetValue(i + 1, j + 1, gp_Pnt(x, y, 0.8 * math.sin(0.4 * x) * math.cos(0.3 * y) + 0.05 * random.uniform(-1, 1)))
def arr(cls, vals):
    a = cls(1, len(vals))
    for k, v in enumerate(vals): a.SetValue(k + 1, v)
    return a
knots = arr(Array1_double, [0.0, 0.2, 0.4, 0.6, 0.8, 1.0])
mults = arr(Array1_int, [4, 1, 1, 1, 1, 4])
surf = Geom_BSplineSurface(P, knots, knots, mults, mults, 3, 3)
face = BRepBuilderAPI_MakeFace(surf, 0.1, 0.9, 0.1, 0.9, 1e-7).Face()
hole = BRepBuilderAPI_MakeEdge(Geom2d_Circle(gp_Ax2d(gp_Pnt2d(0.5, 0.5), gp_Dir2d(1, 0)), 0.15), surf).Edge()
BRepLib.BuildCurves3d_s(hole)
wire = BRepBuilderAPI_MakeWire(hole).Wire()
face = BRepBuilderAPI_MakeFace(face, TopoDS.Wire(wire.Reversed())).Face()
fix = ShapeFix_Face(face); fix.Perform(); face = fix.Face()
def area(shape):
    # adaptive integration to 1e-10 relative: OCC's default fixed Gauss order is off by ~1e-4 relative on
    # rational p-curves (an exact circle), more than the bounds checked here
    g = GProp_GProps(); BRepGProp.SurfaceProperties_s(shape, g, 1e-10); return g.Mass()
assert BRepCheck_Analyzer(face).IsValid(), "OCC's own face is not valid"
w = STEPControl_Writer(); w.Transfer(face, STEPControl_StepModelType.STEPControl_AsIs); w.Write(f"{WORK}/face.stp")
a0 = area(face)
g = GProp_GProps(); BRepGProp.LinearProperties_s(face, g); perimeter = g.Mass()
m = 5e-4 * math.hypot(10, 10)
def fairway(*args):
    run = subprocess.run([FAIRWAY, *args], capture_output=True, text=True)
    if run.stderr.strip(): print(run.stderr.strip())
    assert run.returncode == 0, args
fairway("convert", f"{WORK}/face.stp", f"{WORK}/converted.igs")
fairway("convert", f"{WORK}/face.stp", f"{WORK}/converted.stp")
fairway("fair", f"{WORK}/face.stp", "--tolerance", str(m), "-o", f"{WORK}/faired.igs")
info = json.loads(subprocess.run([FAIRWAY, "info", "--json", f"{WORK}/converted.igs"], capture_output=True, text=True, check=True).stdout)
print("fairway info converted.igs:", info.get("trim"))
def explore(shape, kind):
    ex, out = TopExp_Explorer(shape, kind), []
    while ex.More():
        out.append(ex.Current()); ex.Next()
    return out
def load_step(path):
    r = STEPControl_Reader(); r.ReadFile(path); r.TransferRoots(); return r.OneShape()
def load_iges(path):
    r = IGESControl_Reader(); status = r.ReadFile(path)
    assert int(status) == 1, f"IGESControl_Reader.ReadFile({path}): status {status}"
    r.TransferRoots(); return r.OneShape()
def on_surface(shape):
    """The largest distance from an edge's 3D curve to its face's surface (200 points an edge)."""
    worst = 0.0
    for f in explore(shape, TopAbs_ShapeEnum.TopAbs_FACE):
        f = TopoDS.Face(f)
        s = BRep_Tool.Surface_s(f)
        for e in explore(f, TopAbs_ShapeEnum.TopAbs_EDGE):
            c = BRepAdaptor_Curve(TopoDS.Edge(e))
            t0, t1 = c.FirstParameter(), c.LastParameter()
            for k in range(201):
                p = c.Value(t0 + (t1 - t0) * k / 200)
                proj = GeomAPI_ProjectPointOnSurf(p, s)
                if proj.NbPoints() > 0:
                    worst = max(worst, proj.LowerDistance())
    return worst
diag = math.hypot(math.hypot(10, 10), 1.8)  # the control box's diagonal, about
tol = 1e-6 * diag
step_area = area(load_step(f"{WORK}/converted.stp"))
print(f"original face (OCC): area {a0:.9f}, perimeter {perimeter:.6f}; Fairway's STEP route read by OCC: area {step_area:.9f}")
ok = True
for name, ref, bound, what in [("converted", step_area, perimeter * tol, "STEP route"), ("faired", a0, perimeter * m, "original")]:
    shape = load_iges(f"{WORK}/{name}.igs")
    faces = explore(shape, TopAbs_ShapeEnum.TopAbs_FACE)
    wires = explore(shape, TopAbs_ShapeEnum.TopAbs_WIRE)
    valid = BRepCheck_Analyzer(shape).IsValid()
    kind = BRep_Tool.Surface_s(TopoDS.Face(faces[0])).DynamicType().Name() if faces else "-"
    a1 = area(shape)
    off = on_surface(shape)
    print(f"OCC reads Fairway's {name}.igs: {len(faces)} face(s) on {kind}, {len(wires)} wire(s), valid {valid}; "
          f"edges at most {off:.3e} from the surface (trim tolerance {tol:.2e}); area {a1:.9f} vs {what} {ref:.9f} "
          f"({(a1 - ref) / ref:+.3e} relative, {abs(a1 - ref):.3e} absolute; bound {bound:.3e})")
    ok = ok and len(faces) == 1 and len(wires) == 2 and valid and off <= 10 * tol and abs(a1 - ref) <= bound
sys.exit(0 if ok else 1)
PY
