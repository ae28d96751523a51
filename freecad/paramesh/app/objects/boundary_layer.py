# SPDX-License-Identifier: LGPL-2.1-or-later
"""Boundary-layer child of a ParaMesh surface mesh: rows of stretched elements grown inside the
surface from CAD edges picked in the 3D view (App::PropertyLinkSubList ``References``).

The object does no work itself: the parent SurfaceMesh reads ``spec(obj)`` when it meshes, so a
change here makes the parent re-mesh on the next recompute (the parent links this object through
its BoundaryLayerList).
"""
import FreeCAD

from .base import BaseProxy, add_property
from ...core.params import BoundaryLayer as BoundaryLayerSpec

GROUP = "ParaMesh Boundary Layer"


def sub_numbers(references, prefix):
    """1-based numbers of the sub-elements named '<prefix>N' in a LinkSubList value
    [(obj, ('Edge21', ...)), ...], in order and without duplicates."""
    out = []
    for _obj, subs in references or []:
        for s in (subs if isinstance(subs, (list, tuple)) else [subs]):
            if s.startswith(prefix) and s[len(prefix):].isdigit():
                n = int(s[len(prefix):])
                if n not in out:
                    out.append(n)
    return out


def parent_mesh(obj):
    """The ParaMesh surface mesh that lists obj in its BoundaryLayerList or LocalSizeList."""
    for p in obj.InList:
        if obj in (getattr(p, "BoundaryLayerList", None) or []) or obj in (getattr(p, "LocalSizeList", None) or []):
            return p
    return None


def check_references(obj):
    """Raises ValueError when the references point to another object than the parent's Part (the
    numbers would then mean other edges)."""
    parent = parent_mesh(obj)
    part = getattr(parent, "Part", None) if parent is not None else None
    for ref_obj, _subs in obj.References or []:
        if part is not None and ref_obj != part:
            raise ValueError(f"{obj.Label}: references {ref_obj.Label}, but {parent.Label} meshes {part.Label}")


class BoundaryLayer(BaseProxy):
    """Proxy of a boundary-layer object (App::FeaturePython child of a SurfaceMesh)."""

    Type = "ParaMesh::BoundaryLayer"

    def init_properties(self, obj):
        super().init_properties(obj)
        add_property(obj, "App::PropertyLinkSubList", "References", GROUP,
                     "CAD edges the layer grows from (EdgeN of the meshed Part; select them in the 3D view)")
        add_property(obj, "App::PropertyLength", "FirstHeight", GROUP,
                     "Height of the first row of elements, next to the edge [length, > 0]", 1.0)
        add_property(obj, "App::PropertyFloat", "Growth", GROUP,
                     "Ratio between the heights of consecutive rows [ratio, 1 to 5]", 1.2)
        add_property(obj, "App::PropertyInteger", "Layers", GROUP,
                     "Number of rows; 0: as many as needed to reach Thickness [count]", 10)
        add_property(obj, "App::PropertyLength", "Thickness", GROUP,
                     "Total thickness of the layer; used when Layers is 0 [length, 0: from Layers]", 0.0)
        add_property(obj, "App::PropertyFloat", "MaxAspect", GROUP,
                     "A column stops when its row height is this many times smaller than the spacing along "
                     "the edge [ratio, 0: off]", 0.0)
        add_property(obj, "App::PropertyBool", "Quads", GROUP,
                     "Stretched quadrilaterals (True) or each quad split into two triangles (False)", True)
        add_property(obj, "App::PropertyBool", "AutoEdges", GROUP,
                     "Also grow from the leading edges the mesher detects at each run (smooth edges across "
                     "which the surface curves far more than along them)", False)

    def execute(self, obj):
        pass

    def edges(self, obj):
        """1-based numbers of the referenced edges."""
        return sub_numbers(obj.References, "Edge")

    def spec(self, obj):
        """The core BoundaryLayer of this object (1-based FreeCAD edge numbers)."""
        check_references(obj)
        kw = dict(edges=self.edges(obj), first_height=float(obj.FirstHeight), growth=float(obj.Growth),
                  layers=int(obj.Layers), thickness=float(obj.Thickness), max_aspect=float(obj.MaxAspect),
                  quads=bool(obj.Quads))
        if obj.AutoEdges:
            kw["auto"] = True
        return BoundaryLayerSpec(**kw)


def _edge_names(edges):
    names = []
    for e in edges:
        if isinstance(e, str):
            names.append(e if e.startswith("Edge") else f"Edge{int(e)}")
        else:
            names.append(f"Edge{int(e)}")
    return names


def make_boundary_layer(doc, mesh_obj, edges=(), first_height=1.0, growth=1.2, layers=10, thickness=0.0,
                        max_aspect=0.0, quads=True, auto=False, name="BoundaryLayer"):
    """Adds a boundary-layer child to the ParaMesh surface mesh mesh_obj, growing from edges (1-based
    numbers or 'EdgeN' names of mesh_obj.Part; with auto=True also from the detected leading edges)
    and returns it. Not meshed until recompute."""
    obj = doc.addObject("App::FeaturePython", name)
    BoundaryLayer(obj)
    if edges:
        if mesh_obj.Part is None:
            raise ValueError(f"{mesh_obj.Label} has no Part: cannot reference edges")
        obj.References = [(mesh_obj.Part, tuple(_edge_names(edges)))]
    obj.FirstHeight = first_height
    obj.Growth = growth
    obj.Layers = int(layers)
    obj.Thickness = thickness
    obj.MaxAspect = max_aspect
    obj.Quads = bool(quads)
    obj.AutoEdges = bool(auto)
    children = list(mesh_obj.BoundaryLayerList)  # a LinkList property does not support append
    children.append(obj)
    mesh_obj.BoundaryLayerList = children
    if FreeCAD.GuiUp:
        from ...gui.view_boundary_layer import ViewProviderBoundaryLayer
        ViewProviderBoundaryLayer(obj.ViewObject)
    return obj


def make_boundary_layer_from_spec(doc, mesh_obj, spec):
    """make_boundary_layer from a dict {'edges': [21], 'first_height': 0.5, ...} or a BoundaryLayer."""
    b = BoundaryLayerSpec.parse(spec)
    return make_boundary_layer(doc, mesh_obj, b.edges, first_height=b.first_height, growth=b.growth,
                               layers=b.layers, thickness=b.thickness, max_aspect=b.max_aspect, quads=b.quads,
                               auto=bool(getattr(b, "auto", False)))
