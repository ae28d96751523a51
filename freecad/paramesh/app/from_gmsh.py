# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD FEM hand-over: a FEM Gmsh mesh object (Fem::FemMeshGmsh) turned into a ParaMesh mesh
object of the same Part, with its settings mapped, its MeshRegion children as local sizes and its
MeshGroup children as named groups; the analysis then holds the ParaMesh mesh instead. What has no
ParaMesh counterpart is listed in the report view (and returned), never dropped silently."""
import FreeCAD

# Gmsh-only settings ParaMesh has no counterpart for (its own mesher and optimiser run instead);
# listed when they differ from a new Gmsh mesh object's defaults
_GMSH_ONLY = ("Algorithm2D", "Algorithm3D", "OptimizeStd", "OptimizeNetgen", "HighOrderOptimize",
              "RecombineAll", "Recombine3DAll", "RecombinationAlgorithm", "CoherenceMesh", "GeometryTolerance",
              "SecondOrderLinear")


def _value(v):
    return float(v.Value) if hasattr(v, "Value") else v


def _gmsh_defaults(doc):
    """Property values of a new FEM Gmsh mesh object (made and removed again)."""
    import ObjectsFem
    tmp = ObjectsFem.makeMeshGmsh(doc, "ParaMeshGmshDefaults")
    try:
        return {p: _value(getattr(tmp, p)) for p in _GMSH_ONLY if hasattr(tmp, p)}
    finally:
        doc.removeObject(tmp.Name)


def _refs(obj, part, notes, what):
    """'Face3', 'Edge2', ... of obj.References on part; references to other objects are noted."""
    out = []
    for ref_obj, subs in getattr(obj, "References", None) or []:
        subs = subs if isinstance(subs, (list, tuple)) else [subs]
        if ref_obj != part:
            notes.append(f"{what} {obj.Label}: references {ref_obj.Label} {', '.join(subs)}, not the meshed "
                         f"part {part.Label}: left out")
            continue
        out += [s for s in subs if s]
    return out


def gmsh_settings(gmsh_obj, notes):
    """The ParaMesh parameters (make_surface_mesh keywords) of a FEM Gmsh mesh object."""
    p = {}
    lmax, lmin = _value(gmsh_obj.CharacteristicLengthMax), _value(gmsh_obj.CharacteristicLengthMin)
    if lmax > 0:
        p["size"] = lmax  # Gmsh's maximum size is the size it meshes at where nothing asks for less
    if lmin > 0:
        p["min_size"] = lmin
    p["order"] = 2 if gmsh_obj.ElementOrder == "2nd" else 1
    dim = gmsh_obj.ElementDimension
    shape = gmsh_obj.Part.Shape
    if dim == "3D" or (dim == "From Shape" and len(shape.Solids) > 0):
        p["volume"] = True
    elif dim == "1D":
        notes.append("ElementDimension 1D: ParaMesh meshes surfaces (and solids); a surface mesh is made")
    n = int(getattr(gmsh_obj, "MeshSizeFromCurvature", 0) or 0)
    if n > 0:
        p["curvature_angle"] = 360.0 / n  # Gmsh: n elements per 2 pi
    return p


def from_gmsh_mesh(gmsh_obj, name=None):
    """Makes a ParaMesh mesh object from the FEM Gmsh mesh object gmsh_obj (same Part, mapped
    settings, local sizes from its MeshRegions, groups from its MeshGroups), puts it into the
    analyses that held gmsh_obj in its place (gmsh_obj stays in the document, outside them), meshes
    it and returns (paramesh object, notes): the settings that could not be carried over, also
    printed as warnings in the report view."""
    from .factories import make_surface_mesh
    from .objects.local_size import make_local_size
    doc = gmsh_obj.Document
    part = gmsh_obj.Part
    if part is None or not hasattr(part, "Shape"):
        raise ValueError(f"{gmsh_obj.Label}: no Part to mesh")
    notes = []
    params = gmsh_settings(gmsh_obj, notes)
    defaults = _gmsh_defaults(doc)
    for prop, default in defaults.items():
        v = _value(getattr(gmsh_obj, prop))
        if v != default:
            notes.append(f"{prop} = {v}: a Gmsh setting with no ParaMesh counterpart (ParaMesh's own mesher "
                         f"and optimiser run): ignored")
    for bl in getattr(gmsh_obj, "MeshBoundaryLayerList", None) or []:
        notes.append(f"MeshBoundaryLayer {bl.Label}: Gmsh's volume inflation layers have no ParaMesh "
                     f"counterpart yet (ParaMesh grows surface layers from edges): left out")
    obj = make_surface_mesh(doc, part, name=name or "ParaMeshFEM", **params)
    obj.Label = (name or gmsh_obj.Label + " (ParaMesh)")
    for region in getattr(gmsh_obj, "MeshRegionList", None) or []:
        size = _value(region.CharacteristicLength)
        refs = [r for r in _refs(region, part, notes, "MeshRegion") if r.startswith(("Face", "Edge", "Vertex"))]
        if size > 0 and refs:
            make_local_size(doc, obj, refs, size, name=region.Name)
        elif size > 0:
            notes.append(f"MeshRegion {region.Label}: no face, edge or vertex of {part.Label}: left out")
    groups = []
    for g in getattr(gmsh_obj, "MeshGroupList", None) or []:
        gname = g.Label if g.UseLabel else g.Name
        refs = _refs(g, part, notes, "MeshGroup")
        kinds = {r.rstrip("0123456789") for r in refs}
        if not refs or len(kinds) != 1 or kinds - {"Face", "Edge", "Solid"}:
            notes.append(f"MeshGroup {gname}: {', '.join(refs) or 'no reference'}: ParaMesh groups hold faces, "
                         f"edges or solids of one kind: left out")
            continue
        groups.append(f"{gname}={','.join(refs)}")
    obj.Groups = groups
    for parent in list(gmsh_obj.InList):
        if parent.isDerivedFrom("Fem::FemAnalysis"):
            group = [o for o in parent.Group if o != gmsh_obj]
            parent.Group = group + [obj]
    if FreeCAD.GuiUp and gmsh_obj.ViewObject is not None:
        gmsh_obj.ViewObject.Visibility = False  # the mesh in use is shown, not the one it replaced
    for n in notes:
        FreeCAD.Console.PrintWarning(f"{obj.Label}: {n}\n")
    doc.recompute()
    return obj, notes
