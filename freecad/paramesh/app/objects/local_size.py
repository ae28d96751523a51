# SPDX-License-Identifier: LGPL-2.1-or-later
"""Local-size child of a ParaMesh surface mesh: a target element size near CAD faces, edges or
vertices picked in the 3D view (App::PropertyLinkSubList ``References``). The parent SurfaceMesh
reads ``spec(obj)`` when it meshes."""
import FreeCAD

from .base import BaseProxy, add_property
from .boundary_layer import sub_numbers, check_references
from ...core.params import LocalSize as LocalSizeSpec

GROUP = "ParaMesh Local Size"
_PREFIXES = (("face", "Face"), ("edge", "Edge"), ("vertex", "Vertex"))


class LocalSize(BaseProxy):
    """Proxy of a local-size object (App::FeaturePython child of a SurfaceMesh)."""

    Type = "ParaMesh::LocalSize"

    def init_properties(self, obj):
        super().init_properties(obj)
        add_property(obj, "App::PropertyLinkSubList", "References", GROUP,
                     "CAD faces, edges or vertices (FaceN/EdgeN/VertexN of the meshed Part) near which Size applies")
        add_property(obj, "App::PropertyLength", "Size", GROUP,
                     "Target element size near the referenced entities; the mesh grades away from them "
                     "by the parent's Grading [length, > 0]", 1.0)

    def execute(self, obj):
        pass

    def spec(self, obj):
        """A list of core LocalSize objects, one per kind of referenced entity."""
        check_references(obj)
        out = []
        for kind, prefix in _PREFIXES:
            nums = sub_numbers(obj.References, prefix)
            if nums:
                out.append(LocalSizeSpec(kind, nums, float(obj.Size)))
        if not out:
            raise ValueError(f"{obj.Label}: no face, edge or vertex referenced")
        return out


def _names(refs):
    out = []
    for r in refs:
        if isinstance(r, str):
            out.append(r)
        else:
            raise TypeError(f"local size reference must be 'FaceN', 'EdgeN' or 'VertexN', got {r!r}")
    return out


def make_local_size(doc, mesh_obj, refs=(), size=1.0, name="LocalSize"):
    """Adds a local-size child to the ParaMesh surface mesh mesh_obj and returns it. refs: sub-element
    names of mesh_obj.Part ('Face3', 'Edge2', 'Vertex1'). Not meshed until recompute."""
    obj = doc.addObject("App::FeaturePython", name)
    LocalSize(obj)
    names = _names(refs)
    if names:
        if mesh_obj.Part is None:
            raise ValueError(f"{mesh_obj.Label} has no Part: cannot reference its entities")
        obj.References = [(mesh_obj.Part, tuple(names))]
    obj.Size = size
    children = list(mesh_obj.LocalSizeList)
    children.append(obj)
    mesh_obj.LocalSizeList = children
    if FreeCAD.GuiUp:
        from ...gui.view_local_size import ViewProviderLocalSize
        ViewProviderLocalSize(obj.ViewObject)
    return obj


def make_local_size_from_spec(doc, mesh_obj, spec):
    """make_local_size from a dict {'faces': [3], 'size': 0.5}, a string 'Face3=0.5' or a LocalSize."""
    s = LocalSizeSpec.parse(spec)
    s.validate()
    prefix = dict(_PREFIXES)[s.kind]
    return make_local_size(doc, mesh_obj, [f"{prefix}{i}" for i in s.entities], s.size)
