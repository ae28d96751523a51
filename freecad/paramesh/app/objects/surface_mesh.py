# SPDX-License-Identifier: LGPL-2.1-or-later
"""The ParaMesh surface mesh: a Fem::FemMeshObjectPython with a Part link (what FreeCAD 0.20's
CalculiX writer reads to find constraint nodes), the meshing parameters, and the run report.
Recompute re-meshes when an input changed."""
import json

import FreeCAD

from .base import BaseProxy, add_property
from ...core.params import FIELDS

GROUP = "ParaMesh"


def _tip(name):
    unit, text = FIELDS[name]
    return f"{text} [{unit}]"


class SurfaceMesh(BaseProxy):
    Type = "ParaMesh::SurfaceMesh"

    def init_properties(self, obj):
        super().init_properties(obj)
        add_property(obj, "App::PropertyLink", "Part", "FEM Mesh",
                     "The Part object (any shape with faces) that is meshed")
        add_property(obj, "App::PropertyLength", "Size", GROUP, _tip("size"), 0.0)
        add_property(obj, "App::PropertyLength", "MinSize", GROUP, _tip("min_size"), 0.0)
        add_property(obj, "App::PropertyLength", "MaxSize", GROUP, _tip("max_size"), 0.0)
        add_property(obj, "App::PropertyAngle", "CurvatureAngle", GROUP, _tip("curvature_angle"), 0.0)
        add_property(obj, "App::PropertyFloat", "MaxDeviation", GROUP, _tip("max_deviation"), 0.0)
        add_property(obj, "App::PropertyFloat", "Grading", GROUP, _tip("grading"), 1.3)
        add_property(obj, "App::PropertyEnumeration", "ElementOrder", GROUP, _tip("order"),
                     enum=["1st", "2nd"])
        add_property(obj, "App::PropertyBool", "Quads", GROUP, _tip("quads"), False)
        add_property(obj, "App::PropertyInteger", "Threads", GROUP, _tip("threads"), 0)
        add_property(obj, "App::PropertyInteger", "OptimizePasses", GROUP, _tip("optimize_passes"), 4)
        add_property(obj, "App::PropertyLinkList", "BoundaryLayerList", GROUP,
                     "ParaMesh boundary-layer objects applied to this mesh")
        add_property(obj, "App::PropertyLinkList", "LocalSizeList", GROUP,
                     "ParaMesh local-size objects applied to this mesh")
        add_property(obj, "App::PropertyBool", "CreateMeshFeature", GROUP,
                     "Also keep a Mesh::Feature (triangles, one segment per CAD face) up to date", False)
        add_property(obj, "App::PropertyLink", "MeshFeature", GROUP,
                     "The Mesh::Feature made from this mesh (when CreateMeshFeature is on)", mode=1)
        add_property(obj, "App::PropertyString", "Status", "Result",
                     "Outcome of the last run: ok, degraded (faces failed, named in Report) or failed", mode=1)
        add_property(obj, "App::PropertyString", "Report", "Result",
                     "JSON report of the last run (counts, per-face status, timings, quality)", mode=1)

    def params(self, obj):
        """The MeshParams of this object and its children."""
        from ...core.params import MeshParams
        p = MeshParams(size=float(obj.Size), min_size=float(obj.MinSize), max_size=float(obj.MaxSize),
                       curvature_angle=float(obj.CurvatureAngle), max_deviation=float(obj.MaxDeviation),
                       grading=float(obj.Grading), threads=int(obj.Threads),
                       order=2 if obj.ElementOrder == "2nd" else 1, quads=bool(obj.Quads),
                       optimize_passes=int(obj.OptimizePasses))
        for child in obj.LocalSizeList:
            if hasattr(child, "Proxy") and hasattr(child.Proxy, "spec"):
                p.local_sizes.extend(child.Proxy.spec(child))
        for child in obj.BoundaryLayerList:
            if hasattr(child, "Proxy") and hasattr(child.Proxy, "spec"):
                p.boundary_layers.append(child.Proxy.spec(child))
        return p.validate()

    def execute(self, obj):
        if obj.Part is None or not hasattr(obj.Part, "Shape"):
            obj.Status = "failed"
            obj.Report = json.dumps({"status": "failed", "message": "no Part to mesh"})
            FreeCAD.Console.PrintError(f"{obj.Label}: no Part to mesh\n")
            return
        from ...core.api import MeshJob, ParaMeshError
        try:
            result = MeshJob(obj.Part.Shape, self.params(obj)).run()
        except (ParaMeshError, ValueError, TypeError) as e:
            obj.Status = "failed"
            obj.Report = json.dumps({"status": "failed", "message": str(e)})
            FreeCAD.Console.PrintError(f"{obj.Label}: {e}\n")
            return
        self.apply_result(obj, result)

    @staticmethod
    def analysis_constraints(obj):
        """FEM constraints of the analyses this mesh belongs to."""
        out = []
        for parent in obj.InList:
            if parent.isDerivedFrom("Fem::FemAnalysis"):
                out += [m for m in parent.Group if m.isDerivedFrom("Fem::Constraint")]
        return out

    def apply_result(self, obj, result):
        """Stores a finished MeshResult in the object (also used by the GUI's worker thread)."""
        fm = result.to_femmesh()
        from ..to_femmesh import add_constraint_groups
        add_constraint_groups(fm, result, obj.Part, self.analysis_constraints(obj))
        obj.FemMesh = fm
        obj.Status = result.report["status"]
        obj.Report = json.dumps(result.report)
        if result.report["status"] != "ok":
            FreeCAD.Console.PrintWarning(f"{obj.Label}: {result.report['message']}\n")
        if obj.CreateMeshFeature:
            doc = obj.Document
            mf = obj.MeshFeature
            if mf is None:
                mf = doc.addObject("Mesh::Feature", obj.Name + "_Mesh")
                mf.Label = obj.Label + " (triangles)"
                obj.MeshFeature = mf
            mf.Mesh = result.to_mesh()
