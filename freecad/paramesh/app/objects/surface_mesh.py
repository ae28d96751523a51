# SPDX-License-Identifier: LGPL-2.1-or-later
"""The ParaMesh surface mesh: a Fem::FemMeshObjectPython with a Part link (what FreeCAD 0.20's
CalculiX writer reads to find constraint nodes), the meshing parameters, and the run report.
Recompute re-meshes when an input changed."""
import json
import os

import numpy as np

import FreeCAD

from .base import BaseProxy, add_property


def is_mesh_feature(part):
    """A Mesh::Feature (triangulated input: remeshed by the discrete backend)."""
    return part is not None and hasattr(part, "Mesh") and hasattr(part.Mesh, "Topology") and not hasattr(part, "Shape")


def mesh_source(part):
    """What MeshJob meshes for the linked object: its Part.Shape, or for a Mesh::Feature its
    (points, triangles) arrays. Raises ValueError naming the object when there is nothing to mesh."""
    if part is None:
        raise ValueError("no Part to mesh (set its Part property)")
    if is_mesh_feature(part):
        pts, facets = part.Mesh.Topology
        if not facets:
            raise ValueError(f"{part.Label}: the mesh has no facet")
        return (np.array([[p.x, p.y, p.z] for p in pts], dtype=float), np.array(facets, dtype=np.int64).reshape(-1, 3))
    if not hasattr(part, "Shape"):
        raise ValueError(f"{part.Label}: neither a Part nor a Mesh object")
    return part.Shape
from ...core.params import FIELDS
from ...core.report_text import volume_lines

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
        add_property(obj, "App::PropertyInteger", "Proximity", GROUP, _tip("proximity"), 0)
        add_property(obj, "App::PropertyBool", "NearestFaceCheck", GROUP, _tip("nearest_face_check"), False)
        add_property(obj, "App::PropertyFloat", "NearestFaceBudget", GROUP, _tip("nearest_face_budget"), 0.10)
        add_property(obj, "App::PropertyInteger", "Threads", GROUP, _tip("threads"), 0)
        add_property(obj, "App::PropertyInteger", "OptimizePasses", GROUP, _tip("optimize_passes"), 4)
        add_property(obj, "App::PropertyInteger", "MaxElements", GROUP, _tip("max_elements"), 50000000)
        add_property(obj, "App::PropertyBool", "Volume3D", GROUP, "3D: " + _tip("volume"), False)
        add_property(obj, "App::PropertyLength", "VolumeMaxSize", GROUP, _tip("volume_max_size"), 0.0)
        add_property(obj, "App::PropertyInteger", "VolumeOptimize", GROUP, _tip("volume_optimize"), 1)
        add_property(obj, "App::PropertyLinkList", "BoundaryLayerList", GROUP,
                     "ParaMesh boundary-layer objects applied to this mesh")
        add_property(obj, "App::PropertyLinkList", "LocalSizeList", GROUP,
                     "ParaMesh local-size objects applied to this mesh")
        add_property(obj, "App::PropertyStringList", "Groups", GROUP, _tip("groups") +
                     " One 'NAME=Face3,Face7' a line.")
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
        # a property at 0 means "left out" (FreeCAD properties cannot be empty)
        p = MeshParams(size=float(obj.Size) or None, min_size=float(obj.MinSize) or None,
                       max_size=float(obj.MaxSize) or None,
                       curvature_angle=float(obj.CurvatureAngle), max_deviation=float(obj.MaxDeviation),
                       grading=float(obj.Grading), threads=int(obj.Threads),
                       order=2 if obj.ElementOrder == "2nd" else 1, quads=bool(obj.Quads),
                       optimize_passes=int(obj.OptimizePasses),
                       proximity=int(getattr(obj, "Proximity", 0)),
                       nearest_face_check=bool(getattr(obj, "NearestFaceCheck", False)),
                       nearest_face_budget=float(getattr(obj, "NearestFaceBudget", 0.10)),
                       max_elements=int(getattr(obj, "MaxElements", 50000000)),
                       volume=bool(getattr(obj, "Volume3D", False)),
                       volume_max_size=float(getattr(obj, "VolumeMaxSize", 0.0)) or None,
                       volume_optimize=int(getattr(obj, "VolumeOptimize", 1)),
                       groups=[g for g in getattr(obj, "Groups", []) if g.strip()])
        for child in obj.LocalSizeList:
            if hasattr(child, "Proxy") and hasattr(child.Proxy, "spec"):
                p.local_sizes.extend(child.Proxy.spec(child))
        for child in obj.BoundaryLayerList:
            if hasattr(child, "Proxy") and hasattr(child.Proxy, "spec"):
                p.boundary_layers.append(child.Proxy.spec(child))
        return p.validate()

    def execute(self, obj):
        try:
            source = mesh_source(obj.Part)
        except ValueError as e:
            obj.Status = "failed"
            obj.Report = json.dumps({"status": "failed", "message": str(e)})
            FreeCAD.Console.PrintError(f"{obj.Label}: {e}\n")
            return
        from ...core.api import MeshJob, ParaMeshError
        try:
            result = MeshJob(source, self.params(obj)).run()
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

    def apply_result(self, obj, result, femmesh=None):
        """Stores a finished MeshResult in the object (also used by the GUI's worker thread).
        femmesh: the result's nodes and elements already in a Fem.FemMesh without groups (the GUI
        fills it in its worker thread); the groups are added here."""
        from ..to_femmesh import add_constraint_groups, add_result_groups
        if femmesh is not None:
            fm = femmesh
            add_result_groups(fm, result)
        else:
            fm = result.to_femmesh()
        add_constraint_groups(fm, result, obj.Part, self.analysis_constraints(obj))
        obj.FemMesh = fm
        self._result = result  # kept in memory (not saved) for exports and the quality view
        obj.Status = result.report["status"]
        obj.Report = json.dumps(result.report)
        if result.report["status"] != "ok":
            FreeCAD.Console.PrintWarning(f"{obj.Label}: {result.report['message']}\n")
        for level, text in volume_lines(result.report):  # the tetrahedra per solid, in the report view
            (FreeCAD.Console.PrintError if level == "error" else FreeCAD.Console.PrintMessage)(f"{obj.Label}: {text}\n")
        if obj.CreateMeshFeature:
            doc = obj.Document
            mf = obj.MeshFeature
            if mf is None:
                mf = doc.addObject("Mesh::Feature", obj.Name + "_Mesh")
                mf.Label = obj.Label + " (triangles)"
                obj.MeshFeature = mf
            mf.Mesh = result.to_mesh()

    def last_result(self, obj):
        """The MeshResult applied last in this session, or None (after a document is reopened the
        mesh lives only in FemMesh)."""
        r = getattr(self, "_result", None)
        if r is not None and obj.FemMesh.NodeCount != len(r.nodes):
            return None  # FemMesh was replaced by other means
        return r

    def mesh_arrays(self, obj):
        """The mesh as arrays, from the last result or else from FemMesh (slower): a MeshArrays with
        nodes (N, 3) float64, triangles (M, 3) and quads (K, 4) int32 0-based corner indices,
        triangle_face (M,) / quad_face (K,) 1-based CAD faces (0: unknown), element_ids (M+K,) the
        FemMesh ids of triangles then quads."""
        r = self.last_result(obj)
        if r is not None:
            m, k = len(r.triangles), len(r.quads)
            return MeshArrays(r.nodes, r.triangles, r.quads, r.triangle_face, r.quad_face,
                              np.arange(1, m + k + 1, dtype=np.int64), np.arange(1, len(r.nodes) + 1),
                              tets=r.tetrahedra[:, :4], tet_ids=np.arange(m + k + 1, m + k + 1 + len(r.tetrahedra)))
        return femmesh_arrays(obj.FemMesh)

    def export(self, obj, path):
        """Writes the mesh to path; the format comes from the extension. .msh (Gmsh 4.1), .vtu,
        .stl and .inp are written by the core from the last result (re-meshing with the object's
        parameters first when the document was reopened: the mesher is deterministic); other
        extensions FreeCAD's FemMesh writes (.unv, .med, .vtk, .z88, .dat) come from FemMesh."""
        path = os.fspath(path)
        ext = os.path.splitext(path)[1].lower()
        if ext in (".msh", ".vtu", ".stl", ".inp"):
            r = self.last_result(obj)
            if r is None:
                from ...core.api import MeshJob
                r = MeshJob(mesh_source(obj.Part), self.params(obj)).run()
                self.apply_result(obj, r)
            r.write(path)
        elif ext in (".unv", ".med", ".vtk", ".z88", ".dat"):
            obj.FemMesh.write(path)
        else:
            raise ValueError(f"cannot export {os.path.basename(path)}: use .msh, .vtu, .stl, .inp, .unv, .med, .vtk")
        return path

    def update_mesh_feature(self, obj):
        """Creates or refreshes the Mesh::Feature of this mesh (sets CreateMeshFeature) and returns it."""
        obj.CreateMeshFeature = True
        r = self.last_result(obj)
        if r is None:
            r = self.mesh_arrays(obj)
        from ..to_femmesh import result_to_mesh
        mf = obj.MeshFeature
        if mf is None:
            mf = obj.Document.addObject("Mesh::Feature", obj.Name + "_Mesh")
            mf.Label = obj.Label + " (triangles)"
            obj.MeshFeature = mf
        mf.Mesh = result_to_mesh(r)
        return mf


class MeshArrays:
    """Plain mesh arrays (the attributes result_to_mesh and the quality view read); element_ids and
    node_ids are the FemMesh ids of the elements (triangles then quads) and of the nodes;
    display_ids the FemMesh ids to colour for each element: the element itself, or on a mesh with
    tetrahedra (tets: (K, 4) rows of node indices, tet_ids their FemMesh ids) the tetrahedron the
    triangle is a face of, as FreeCAD then draws the volumes' faces only."""

    def __init__(self, nodes, triangles, quads, triangle_face, quad_face, element_ids, node_ids=None,
                 tets=None, tet_ids=None):
        self.nodes = np.asarray(nodes, dtype=np.float64).reshape(-1, 3)
        self.triangles = np.asarray(triangles, dtype=np.int32).reshape(-1, 3)
        self.quads = np.asarray(quads, dtype=np.int32).reshape(-1, 4)
        self.triangle_face = np.asarray(triangle_face, dtype=np.int32)
        self.quad_face = np.asarray(quad_face, dtype=np.int32)
        self.element_ids = np.asarray(element_ids, dtype=np.int64)
        self.node_ids = (np.arange(1, len(self.nodes) + 1) if node_ids is None
                         else np.asarray(node_ids, dtype=np.int64))  #: FemMesh node id per row of nodes
        self.display_ids = self.element_ids
        if tets is not None and len(tets) and not len(self.quads):
            from ..to_femmesh import owner_tetrahedra
            owner = owner_tetrahedra(self.triangles, tets)
            ids = np.asarray(tet_ids, dtype=np.int64)
            self.display_ids = np.where(owner >= 0, ids[np.maximum(owner, 0)], self.element_ids)


def femmesh_arrays(fm):
    """MeshArrays of the face elements of a Fem.FemMesh (corner nodes only; CAD faces from the
    'Face<i>' groups)."""
    all_nodes = fm.Nodes if fm.NodeCount else {}  # FemMesh builds this dict on each access: read it once
    node_ids = sorted(all_nodes)
    index = {nid: i for i, nid in enumerate(node_ids)}
    nodes = np.array([tuple(all_nodes[n]) for n in node_ids], dtype=np.float64).reshape(-1, 3)
    face_of = {}
    for g in fm.Groups:
        name = fm.getGroupName(g)
        if name.startswith("Face") and name[4:].isdigit() and fm.getGroupElementType(g) == "Face":
            for e in fm.getGroupElements(g):
                face_of[e] = int(name[4:])
    tris, quads, tf, qf, tid, qid = [], [], [], [], [], []
    tet_ids = list(fm.Volumes) if fm.VolumeCount else []
    tets = [[index[i] for i in fm.getElementNodes(v)[:4]] for v in tet_ids]
    for e in fm.Faces:
        n = fm.getElementNodes(e)
        if len(n) in (3, 6):
            tris.append([index[i] for i in n[:3]])
            tf.append(face_of.get(e, 0))
            tid.append(e)
        elif len(n) in (4, 8):
            quads.append([index[i] for i in n[:4]])
            qf.append(face_of.get(e, 0))
            qid.append(e)
    return MeshArrays(nodes, tris, quads, tf, qf, tid + qid, node_ids, tets=tets, tet_ids=tet_ids)
