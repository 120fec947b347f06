"""Two trimmed B-spline faces whose bounds are not B-splines, written to STEP AP214 by OpenCASCADE.

Face 1: a bicubic B-spline surface (8 x 8 points over 10 x 10, z = 0.8 sin(0.4x) cos(0.3y)) bounded by the
parameter rectangle [0.1, 0.9]^2 with a circular hole (a Geom2d_Circle in (u, v), centre (0.5, 0.5),
radius 0.15). Face 2: the same surface bounded by a pentagon in (u, v) (Geom2d lines trimmed to the sides) with an
elliptical hole (Geom2d_Ellipse, centre (0.45, 0.5), semi-axes 0.2 and 0.1, major axis along u).
OCC writes the p-curves as LINE, CIRCLE and ELLIPSE in a DEFINITIONAL_REPRESENTATION (some as B-splines)
and the 3D edges as B-splines. The exact loops are printed for the test.

Usage: python make_conic_trims_step.py OUT.step   (in a venv with `pip install cadquery-ocp`)
"""
import math, sys
from OCP.OCP.collections import Array1_double, Array1_int, Array2_gp_Pnt
from OCP.gp import gp_Pnt, gp_Pnt2d, gp_Dir2d, gp_Ax2d
from OCP.Geom import Geom_BSplineSurface
from OCP.Geom2d import Geom2d_Circle, Geom2d_Ellipse, Geom2d_Line, Geom2d_TrimmedCurve
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire
from OCP.BRepLib import BRepLib
from OCP.ShapeFix import ShapeFix_Face
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRep import BRep_Builder
from OCP.TopoDS import TopoDS, TopoDS_Compound
from OCP.STEPControl import STEPControl_Writer, STEPControl_StepModelType
from OCP.Interface import Interface_Static

n = 8
P = Array2_gp_Pnt(1, n, 1, n)
for i in range(n):
    for j in range(n):
        x, y = 10.0 * i / (n - 1), 10.0 * j / (n - 1)
        P.SetValue(i + 1, j + 1, gp_Pnt(x, y, 0.8 * math.sin(0.4 * x) * math.cos(0.3 * y)))
def arr(cls, vals):
    a = cls(1, len(vals))
    for k, v in enumerate(vals): a.SetValue(k + 1, v)
    return a
knots = arr(Array1_double, [0.0, 0.2, 0.4, 0.6, 0.8, 1.0])
mults = arr(Array1_int, [4, 1, 1, 1, 1, 4])
surf = Geom_BSplineSurface(P, knots, knots, mults, mults, 3, 3)

def edge(c2d):
    e = BRepBuilderAPI_MakeEdge(c2d, surf).Edge()
    BRepLib.BuildCurves3d_s(e)
    return e

def with_hole(outer_face, hole_edges):
    wm = BRepBuilderAPI_MakeWire()
    for e in hole_edges: wm.Add(e)
    f = BRepBuilderAPI_MakeFace(outer_face, TopoDS.Wire(wm.Wire().Reversed())).Face()
    fix = ShapeFix_Face(f); fix.Perform(); return fix.Face()

# face 1: rectangle, circular hole
f1 = BRepBuilderAPI_MakeFace(surf, 0.1, 0.9, 0.1, 0.9, 1e-7).Face()
f1 = with_hole(f1, [edge(Geom2d_Circle(gp_Ax2d(gp_Pnt2d(0.5, 0.5), gp_Dir2d(1, 0)), 0.15))])
# face 2: pentagon, elliptical hole
pent = [(0.5 + 0.42 * math.cos(math.pi / 2 + 2 * math.pi * k / 5), 0.5 + 0.42 * math.sin(math.pi / 2 + 2 * math.pi * k / 5)) for k in range(5)]
wm = BRepBuilderAPI_MakeWire()
for k in range(5):
    a, b = pent[k], pent[(k + 1) % 5]
    L = math.hypot(b[0] - a[0], b[1] - a[1])
    line = Geom2d_Line(gp_Pnt2d(*a), gp_Dir2d(b[0] - a[0], b[1] - a[1]))
    wm.Add(edge(Geom2d_TrimmedCurve(line, 0.0, L)))
f2 = BRepBuilderAPI_MakeFace(surf, wm.Wire()).Face()
fix = ShapeFix_Face(f2); fix.Perform(); f2 = fix.Face()
f2 = with_hole(f2, [edge(Geom2d_Ellipse(gp_Ax2d(gp_Pnt2d(0.45, 0.5), gp_Dir2d(1, 0)), 0.2, 0.1))])
for f in (f1, f2):
    assert BRepCheck_Analyzer(f).IsValid(), "not a valid face"
b = BRep_Builder(); comp = TopoDS_Compound(); b.MakeCompound(comp)
b.Add(comp, f1); b.Add(comp, f2)
Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
Interface_Static.SetCVal_s("write.step.unit", "MM")
w = STEPControl_Writer()
w.Transfer(comp, STEPControl_StepModelType.STEPControl_AsIs)
w.Write(sys.argv[1])
print("pentagon", pent)
