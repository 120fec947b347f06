#!/usr/bin/env bash
# Trimmed faces against OpenCASCADE (OCCT through cadquery-ocp in a throw-away venv; not part of CI).
# OCC makes a trimmed face: a noisy bicubic B-spline surface bounded by the rectangle [0.1, 0.9]² of its
# parameters with a circular hole (a circle in (u, v), radius 0.15), and writes it as STEP. Fairway reads
# it (`fairway info --json`: one outer and one inner loop), fairs it (`fairway fair --tolerance m`,
# m = 5e-4 × the face's size) and writes STEP; OCC reads that back: the shape must be valid
# (BRepCheck_Analyzer), one face with two wires, and its area within perimeter × m of the original face's
# (the fair moves the surface by at most m in its parameters; the trims keep the same part of it). The same
# file converted without a fair (`fairway convert`) must give the original area within perimeter × the trim
# tolerance (1e-6 × the surface's diagonal).
#
# Usage: scripts/step_trims_occ.sh [VENV]   (default VENV: /tmp/occ-venv)
source "$(dirname "$0")/occ-env.sh"
"$VENV/bin/python" - "$FAIRWAY" "$WORK" <<'PY'
import json, math, random, subprocess, sys
from OCP.OCP.collections import Array1_double, Array1_int, Array2_gp_Pnt
from OCP.gp import gp_Pnt, gp_Pnt2d, gp_Dir2d, gp_Ax2d
from OCP.Geom import Geom_BSplineSurface
from OCP.Geom2d import Geom2d_Circle
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire
from OCP.BRepLib import BRepLib
from OCP.ShapeFix import ShapeFix_Face
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.GProp import GProp_GProps
from OCP.BRepGProp import BRepGProp
from OCP.STEPControl import STEPControl_Writer, STEPControl_Reader, STEPControl_StepModelType
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
info = json.loads(subprocess.run([FAIRWAY, "info", "--json", f"{WORK}/face.stp"], capture_output=True, text=True, check=True).stdout)
print("fairway info:", info.get("trim"))
assert info.get("trim", {}).get("outer_loops") == 1 and info["trim"]["inner_loops"] == 1, info.get("trim")
m = 5e-4 * math.hypot(10, 10)
run = subprocess.run([FAIRWAY, "fair", f"{WORK}/face.stp", "--tolerance", str(m), "-o", f"{WORK}/faired.stp"], capture_output=True, text=True)
print(run.stderr.strip())
assert run.returncode == 0
subprocess.run([FAIRWAY, "convert", f"{WORK}/face.stp", f"{WORK}/converted.stp"], capture_output=True, check=True)
def load(path):
    r = STEPControl_Reader(); r.ReadFile(path); r.TransferRoots(); shape = r.OneShape()
    faces, wires = 0, 0
    ex = TopExp_Explorer(shape, TopAbs_ShapeEnum.TopAbs_FACE)
    while ex.More():
        faces += 1; ex.Next()
    ex = TopExp_Explorer(shape, TopAbs_ShapeEnum.TopAbs_WIRE)
    while ex.More():
        wires += 1; ex.Next()
    return shape, faces, wires, BRepCheck_Analyzer(shape).IsValid(), area(shape)
ok = True
# converted (not faired): the same face, its boundary written within Fairway's trim tolerance
# (1e-6 × the surface's diagonal), so the area within perimeter × that; faired: the surface moves by at
# most m in its parameters, so the boundary by at most m and the area by at most perimeter × m (plus the
# change of the surface inside, of order m × mean curvature × area, far smaller here)
g = GProp_GProps(); BRepGProp.LinearProperties_s(face, g); perimeter = g.Mass()
diag = math.hypot(10, 10)
for name, bound in [("converted", perimeter * 1e-6 * diag / a0), ("faired", perimeter * m / a0)]:
    shape, faces, wires, valid, a1 = load(f"{WORK}/{name}.stp")
    print(f"OCC reads Fairway's {name} file: {faces} face(s), {wires} wire(s), valid {valid}; area {a1:.9f} vs "
          f"original {a0:.9f} ({(a1 - a0) / a0:+.3e} relative; bound {bound:.2e})")
    ok = ok and faces == 1 and wires == 2 and valid and abs(a1 - a0) <= bound * a0
sys.exit(0 if ok else 1)
PY
