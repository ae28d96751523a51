# SPDX-License-Identifier: LGPL-2.1-or-later
"""ParaMesh: a parametric CAD surface mesher with surface boundary layers.

FreeCAD-free API (numpy only)::

    import freecad.paramesh as pm
    r = pm.mesh_shape("wing.step", size=10.0, curvature_angle=10)
    r.nodes          # (N, 3) float64
    r.triangles      # (M, 3) int32, 0-based node indices
    r.report         # dict: status, per-face status, timings, quality
    v = pm.mesh_shape("part.step", size=2.0, volume=True, order=2)
    v.tetrahedra     # (K, 10) int32 (K, 4 at order 1), CalculiX C3D10 / C3D4 node order
    v.tetra_solid    # (K,) int32, 1-based solid (FreeCAD's Solid<i>)

With FreeCAD (no GUI needed)::

    r = pm.mesh_shape(doc.getObject("Body").Shape, size=5)
    mesh = r.to_mesh()        # Mesh.Mesh, for a Mesh::Feature
    fem = r.to_femmesh()      # Fem.FemMesh, one group per CAD face "Face<i>" (and solid "Solid<i>")
    obj = pm.make_fem_mesh(doc, part_object, analysis, size=5)   # volume=True: tetrahedra too

The package imports without FreeCAD; FreeCAD modules are imported only by the functions that need
them.
"""
import os

__version__ = "0.1.0"


def resource_path(*parts):
    """Absolute path of a file shipped with the package (icons live in the repository's icons/)."""
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(os.path.dirname(here))
    return os.path.join(root, *parts)


from .core.params import MeshParams, BoundaryLayer, LocalSize  # noqa: E402
from .core.api import (mesh_shape, mesh_file, mesh_brep, MeshResult, ParaMeshError, ParameterError,  # noqa: E402
                       InputError, Cancelled, MeshJob, propose_leading_edges, discrete_features)


def make_fem_mesh(doc, part_object, analysis=None, **params):
    """Creates a ParaMesh FEM mesh object (Fem::FemMeshObjectPython with a Part link) meshing
    part_object, optionally added to an analysis; volume=True fills its solids with tetrahedra
    (the FemMesh then holds Tetra4/Tetra10 for FreeCAD's CalculiX writer). Needs FreeCAD (no GUI)."""
    from .app.factories import make_fem_mesh as _make
    return _make(doc, part_object, analysis=analysis, **params)
