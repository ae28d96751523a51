# SPDX-License-Identifier: LGPL-2.1-or-later
"""Factories for the ParaMesh document objects (no GUI; view providers are attached when the GUI
is up). Commands call these through FreeCADGui.doCommand so that actions are macro-recordable."""
import FreeCAD


def _attach_view(obj, module, cls):
    if FreeCAD.GuiUp:
        import importlib
        mod = importlib.import_module("freecad.paramesh.gui." + module)
        getattr(mod, cls)(obj.ViewObject)


def make_surface_mesh(doc, part_object=None, name="ParaMeshSurface", **params):
    """A ParaMesh surface mesh object (Fem::FemMeshObjectPython) linked to part_object; keyword
    parameters (size, min_size, curvature_angle, grading, order, quads, threads, volume,
    volume_max_size...) set its properties. Not meshed until recompute."""
    from .objects.surface_mesh import SurfaceMesh
    obj = doc.addObject("Fem::FemMeshObjectPython", name)
    SurfaceMesh(obj)
    if part_object is not None:
        obj.Part = part_object
    mapping = {"size": "Size", "min_size": "MinSize", "max_size": "MaxSize", "curvature_angle": "CurvatureAngle",
               "max_deviation": "MaxDeviation", "grading": "Grading", "threads": "Threads",
               "optimize_passes": "OptimizePasses", "quads": "Quads", "volume": "Volume3D",
               "volume_max_size": "VolumeMaxSize", "volume_optimize": "VolumeOptimize"}
    bl = params.pop("boundary_layers", None)
    ls = params.pop("local_sizes", None)
    for k, v in params.items():
        if k == "order":
            obj.ElementOrder = "2nd" if int(v) == 2 else "1st"
        elif k in mapping:
            setattr(obj, mapping[k], v)
        elif k == "create_mesh_feature":
            obj.CreateMeshFeature = bool(v)
        else:
            doc.removeObject(obj.Name)
            raise TypeError(f"unknown parameter {k!r}")
    if bl:
        from .objects.boundary_layer import make_boundary_layer_from_spec
        for spec in (bl if isinstance(bl, list) else [bl]):
            make_boundary_layer_from_spec(doc, obj, spec)
    if ls:
        from .objects.local_size import make_local_size_from_spec
        for spec in (ls if isinstance(ls, list) else [ls]):
            make_local_size_from_spec(doc, obj, spec)
    _attach_view(obj, "view_surface_mesh", "ViewProviderSurfaceMesh")
    return obj


def make_fem_mesh(doc, part_object, analysis=None, **params):
    """Creates, meshes and returns a ParaMesh FEM mesh object for part_object, added to analysis
    (a Fem::FemAnalysis) when given. Raises the meshing error when the mesh cannot be made."""
    obj = make_surface_mesh(doc, part_object, **params)
    if analysis is not None:
        analysis.addObject(obj)
    doc.recompute()
    if obj.Status == "failed":
        import json
        msg = json.loads(obj.Report or "{}").get("message", "meshing failed")
        from ..core.api import ParaMeshError
        raise ParaMeshError(f"{obj.Label}: {msg}")
    return obj


def make_boundary_layer(doc, mesh_obj, edges=(), first_height=1.0, growth=1.2, layers=10, thickness=0.0,
                        max_aspect=0.0, quads=True, auto=False, name="BoundaryLayer"):
    """A boundary-layer child of the surface mesh mesh_obj growing from edges (1-based numbers or
    'EdgeN' of mesh_obj.Part; auto=True adds the detected leading edges at each run); give layers or
    (layers=0 and) thickness. Not meshed until recompute."""
    from .objects.boundary_layer import make_boundary_layer as _make
    return _make(doc, mesh_obj, edges, first_height=first_height, growth=growth, layers=layers,
                 thickness=thickness, max_aspect=max_aspect, quads=quads, auto=auto, name=name)


def make_local_size(doc, mesh_obj, refs=(), size=1.0, name="LocalSize"):
    """A local-size child of the surface mesh mesh_obj near refs ('Face3', 'Edge2', 'Vertex1' of
    mesh_obj.Part). Not meshed until recompute."""
    from .objects.local_size import make_local_size as _make
    return _make(doc, mesh_obj, refs, size, name=name)


def make_mesh_feature(mesh_obj):
    """Creates (or refreshes) the Mesh::Feature of a surface mesh and keeps it up to date on later
    runs (CreateMeshFeature). Returns the Mesh::Feature."""
    return mesh_obj.Proxy.update_mesh_feature(mesh_obj)


def export_mesh(mesh_obj, path):
    """Writes a surface mesh to path (.msh, .vtu, .stl, .inp; .unv, .med, .vtk through FemMesh)."""
    return mesh_obj.Proxy.export(mesh_obj, path)
