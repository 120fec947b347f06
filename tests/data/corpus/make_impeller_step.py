"""Write every 20th face of impeller.igs (at most N) to a STEP AP214 file with OpenCASCADE.

Usage: python make_impeller_step.py N OUT.step   (in a venv with `pip install cadquery-ocp`)
"""
import sys
from OCP.IGESControl import IGESControl_Reader
from OCP.STEPControl import STEPControl_Writer, STEPControl_StepModelType
from OCP.TopExp import TopExp_Explorer
from OCP.TopAbs import TopAbs_FACE
from OCP.TopoDS import TopoDS
from OCP.BRep import BRep_Builder
from OCP.TopoDS import TopoDS_Compound
from OCP.Interface import Interface_Static
r = IGESControl_Reader()
import os
r.ReadFile(os.path.join(os.path.dirname(os.path.abspath(__file__)), 'impeller.igs'))
r.TransferRoots()
shape = r.OneShape()
exp = TopExp_Explorer(shape, TopAbs_FACE)
b = BRep_Builder(); comp = TopoDS_Compound(); b.MakeCompound(comp)
n = 0; total = 0
while exp.More():
    if total % 20 == 0 and n < int(sys.argv[1]):
        b.Add(comp, TopoDS.Face(exp.Current())); n += 1
    total += 1
    exp.Next()
print("faces", total, "kept", n)
Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
Interface_Static.SetCVal_s("write.step.unit", "MM")
w = STEPControl_Writer()
w.Transfer(comp, STEPControl_StepModelType.STEPControl_AsIs)
w.Write(sys.argv[2])
