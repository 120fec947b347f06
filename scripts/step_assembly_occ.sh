#!/usr/bin/env bash
# STEP assembly placements against OpenCASCADE (OCCT, through its Python package cadquery-ocp in a
# throw-away venv; not part of CI). OCC's XCAF writes a part (a cubic edge and a bicubic face) placed
# twice, rotated and moved, in a sub-assembly that is itself rotated and moved in the top assembly
# (REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION, two levels). Fairway reads it (`fairway info
# --json`, `fairway convert --index k`); every object Fairway reads is evaluated at sample parameters
# against the nearest edge or face OCC reads back with its locations applied. Exits 1 if any distance
# exceeds 1e-7 mm (the model is ~100 mm across).
#
# Usage: scripts/step_assembly_occ.sh [VENV]   (default VENV: /tmp/occ-venv)
source "$(dirname "$0")/occ-env.sh"
"$VENV/bin/python" - "$WORK/assembly.stp" > /dev/null <<'PY'
import json, math, os, subprocess, sys
from OCP.OCP.collections import Array1_gp_Pnt, Array1_double, Array1_int, Array2_gp_Pnt
from OCP.gp import gp_Pnt, gp_Trsf, gp_Vec, gp_Ax1, gp_Dir
from OCP.Geom import Geom_BSplineCurve, Geom_BSplineSurface
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace
from OCP.BRep import BRep_Builder
from OCP.TopoDS import TopoDS_Compound, TopoDS
from OCP.TopLoc import TopLoc_Location
from OCP.TDocStd import TDocStd_Document
from OCP.XCAFApp import XCAFApp_Application
from OCP.XCAFDoc import XCAFDoc_DocumentTool
from OCP.TCollection import TCollection_ExtendedString
from OCP.STEPCAFControl import STEPCAFControl_Writer
from OCP.STEPControl import STEPControl_StepModelType, STEPControl_Reader
from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Surface
from OCP.TopExp import TopExp_Explorer
from OCP.TopAbs import TopAbs_ShapeEnum

def arr1(cls, vals):
    a = cls(1, len(vals))
    for i, v in enumerate(vals): a.SetValue(i + 1, v)
    return a

# the part: a cubic edge and a bicubic face
poles = [(0, 0, 0), (1, 0.3, 0), (2, -0.2, 0.5), (3, 0, 1), (4, 0.5, 1.2)]
curve = Geom_BSplineCurve(arr1(Array1_gp_Pnt, [gp_Pnt(*p) for p in poles]), arr1(Array1_double, [0, 0.5, 1]),
                          arr1(Array1_int, [4, 1, 4]), 3, False)
P = Array2_gp_Pnt(1, 4, 1, 4)
for i in range(4):
    for j in range(4):
        P.SetValue(i + 1, j + 1, gp_Pnt(i, j, 0.2 * math.sin(i + 2 * j)))
surf = Geom_BSplineSurface(P, arr1(Array1_double, [0, 1]), arr1(Array1_double, [0, 1]), arr1(Array1_int, [4, 4]),
                           arr1(Array1_int, [4, 4]), 3, 3)
b = BRep_Builder(); part = TopoDS_Compound(); b.MakeCompound(part)
b.Add(part, BRepBuilderAPI_MakeEdge(curve).Edge())
b.Add(part, BRepBuilderAPI_MakeFace(surf, 1e-7).Face())

def loc(axis, angle, t):
    tr = gp_Trsf(); tr.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(*axis)), angle)
    tt = gp_Trsf(); tt.SetTranslation(gp_Vec(*t))
    return TopLoc_Location(tt.Multiplied(tr))

app = XCAFApp_Application.GetApplication_s()
doc = TDocStd_Document(TCollection_ExtendedString("XmlOcaf"))
app.InitDocument(doc)
st = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
part_l = st.AddShape(part, False)
sub = st.NewShape()
st.AddComponent(sub, part_l, loc((0, 0, 1), math.pi / 2, (10, 0, 0)))
st.AddComponent(sub, part_l, loc((1, 1, 0), 0.7, (0, 0, 5)))
top = st.NewShape()
st.AddComponent(top, sub, loc((0, 1, 0), -0.4, (0, 100, 3)))
st.UpdateAssemblies()
w = STEPCAFControl_Writer()
w.Transfer(doc, STEPControl_StepModelType.STEPControl_AsIs)
w.Write(sys.argv[1])
PY
"$VENV/bin/python" - "$FAIRWAY" "$WORK/assembly.stp" "$WORK" <<'PY'
import json, os, subprocess, sys
from OCP.OCP.collections import Array1_gp_Pnt, Array1_double, Array1_int, Array2_gp_Pnt, Array2_double
from OCP.gp import gp_Pnt
from OCP.Geom import Geom_BSplineCurve, Geom_BSplineSurface
from OCP.STEPControl import STEPControl_Reader
from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Surface
from OCP.TopExp import TopExp_Explorer
from OCP.TopAbs import TopAbs_ShapeEnum
from OCP.TopoDS import TopoDS

FAIRWAY, FILE, WORK = sys.argv[1], sys.argv[2], sys.argv[3]

def distinct(full):
    ks, ms = [], []
    for u in full:
        if ks and u == ks[-1]: ms[-1] += 1
        else: ks.append(u); ms.append(1)
    return ks, ms

def arr1(cls, vals):
    a = cls(1, len(vals))
    for i, v in enumerate(vals): a.SetValue(i + 1, v)
    return a

def from_json(g):
    if "degree_u" in g:
        nu, nv = len(g["points"]), len(g["points"][0])
        P = Array2_gp_Pnt(1, nu, 1, nv)
        for i in range(nu):
            for j in range(nv): P.SetValue(i + 1, j + 1, gp_Pnt(*g["points"][i][j]))
        (ku, mu), (kv, mv) = distinct(g["knots_u"]), distinct(g["knots_v"])
        args = (arr1(Array1_double, ku), arr1(Array1_double, kv), arr1(Array1_int, mu), arr1(Array1_int, mv), g["degree_u"], g["degree_v"])
        if g.get("weights") is None: return Geom_BSplineSurface(P, *args)
        W = Array2_double(1, nu, 1, nv)
        for i in range(nu):
            for j in range(nv): W.SetValue(i + 1, j + 1, g["weights"][i][j])
        return Geom_BSplineSurface(P, W, *args)
    ks, ms = distinct(g["knots"])
    P = arr1(Array1_gp_Pnt, [gp_Pnt(*(p + [0.0] * (3 - len(p)))) for p in g["points"]])
    if g.get("weights") is None: return Geom_BSplineCurve(P, arr1(Array1_double, ks), arr1(Array1_int, ms), g["degree"], False)
    return Geom_BSplineCurve(P, arr1(Array1_double, g["weights"]), arr1(Array1_double, ks), arr1(Array1_int, ms), g["degree"], False)

r = STEPControl_Reader()
r.ReadFile(FILE); r.TransferRoots(); shape = r.OneShape()
edges, faces = [], []
ex = TopExp_Explorer(shape, TopAbs_ShapeEnum.TopAbs_EDGE)
while ex.More(): edges.append(BRepAdaptor_Curve(TopoDS.Edge(ex.Current()))); ex.Next()
ex = TopExp_Explorer(shape, TopAbs_ShapeEnum.TopAbs_FACE)
while ex.More(): faces.append(BRepAdaptor_Surface(TopoDS.Face(ex.Current()), False)); ex.Next()

info = json.loads(subprocess.run([FAIRWAY, "info", "--json", FILE], capture_output=True, text=True, check=True).stdout)
n = info["file"]["objects"]
worst, bad = 0.0, 0
for k in range(n):
    out = os.path.join(WORK, f"o{k}.json")
    subprocess.run([FAIRWAY, "convert", "--index", str(k), FILE, out], capture_output=True, check=True)
    g = from_json(json.load(open(out)))
    if isinstance(g, Geom_BSplineSurface):
        u0, u1, v0, v1 = g.Bounds()
        pars = [(u0 + (u1 - u0) * i / 4, v0 + (v1 - v0) * j / 4) for i in range(5) for j in range(5)]
        mine = [g.Value(u, v) for u, v in pars]
        dists = [max(f.Value(u, v).Distance(p) for (u, v), p in zip(pars, mine)) for f in faces]
    else:
        t0, t1 = g.FirstParameter(), g.LastParameter()
        pars = [t0 + (t1 - t0) * i / 10 for i in range(11)]
        mine = [g.Value(t) for t in pars]
        dists = [max(e.Value(t).Distance(p) for t, p in zip(pars, mine)) if abs(e.FirstParameter() - t0) < 1e-9 and abs(e.LastParameter() - t1) < 1e-9 else 1e300 for e in edges]
    d = min(dists)
    worst = max(worst, d)
    bad += d > 1e-9 * 100
    print(f"object {k}: {'surface' if isinstance(g, Geom_BSplineSurface) else 'curve'} nearest OCC {'face' if isinstance(g, Geom_BSplineSurface) else 'edge'} at {d:.3e} mm")
print(f"{n} objects (OCC: {len(edges)} edges, {len(faces)} faces); largest distance {worst:.3e} mm; {bad} beyond 1e-7 mm")
sys.exit(1 if bad else 0)
PY
