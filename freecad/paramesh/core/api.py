# SPDX-License-Identifier: LGPL-2.1-or-later
"""The FreeCAD-free Python API: mesh a file, a BREP string or (duck-typed) a Part.Shape."""
import json
import os
import threading

import numpy as np

from .params import MeshParams

try:
    from .. import _native
except ImportError as e:  # pragma: no cover - a missing build is reported clearly on first use
    _native = None
    _import_error = e

if _native is not None:
    ParaMeshError = _native.ParaMeshError
    ParameterError = _native.ParameterError
    InputError = _native.InputError
    Cancelled = _native.Cancelled
else:  # pragma: no cover
    class ParaMeshError(RuntimeError):
        pass

    class ParameterError(ParaMeshError, ValueError):
        pass

    class InputError(ParaMeshError, ValueError):
        pass

    class Cancelled(ParaMeshError):
        pass


def _require_native():
    if _native is None:
        raise ImportError("the ParaMesh native module is not built: run `cmake -S . -B build && cmake --build "
                          f"build` in the repository ({_import_error})")


class MeshResult:
    """A surface mesh and its report.

    Arrays (0-based indices, C order): ``nodes`` (N, 3) float64; ``triangles`` (M, 3) int32,
    counter-clockwise seen from outside the CAD face; ``quads`` (K, 4) int32; ``triangle_face`` (M,)
    and ``quad_face`` (K,) int32 1-based CAD faces; ``face_of_element`` (M+K,) the same for
    triangles then quads; ``node_dim`` (N,) 0/1/2 (vertex/edge/face) and ``node_entity`` (N,) its
    1-based number; ``node_param`` (N, 2); ``segments`` (S, 2) and ``segment_edge`` (S,) the mesh
    edges on CAD edges. ``report`` is the run report (dict); ``faces`` its per-face list.

    With ``volume=True``: ``tetrahedra`` (K, 4) int32 of positive volume (((b-a)x(c-a)).(d-a) > 0,
    CalculiX C3D4 order), (K, 10) at order 2 (corners, then the mid-nodes of ab, bc, ca, ad, bd,
    cd: C3D10 order); ``tetra_solid`` (K,) int32 1-based CAD solid (FreeCAD's Solid<i>); nodes
    inside a solid have ``node_dim`` 3 and ``node_entity`` the solid; ``solids`` is the report's
    per-solid list (tetrahedra, dihedral angles, radius ratio, volume, error when not filled).
    """

    def __init__(self, native_result):
        self._r = native_result
        self._cache = {}

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        if name not in self._cache:
            self._cache[name] = getattr(self._r, name)
        return self._cache[name]

    @property
    def face_of_element(self):
        return np.concatenate([self.triangle_face, self.quad_face]).astype(np.int32)

    @property
    def layer_of_element(self):
        """(M+K,) int32: 1-based boundary-layer spec of each element (triangles then quads), 0
        outside the layers."""
        return np.concatenate([self.triangle_layer, self.quad_layer]).astype(np.int32)

    @property
    def report(self):
        if "report" not in self._cache:
            self._cache["report"] = json.loads(self._r.report_json)
        return self._cache["report"]

    @property
    def faces(self):
        return self.report["faces"]

    @property
    def solids(self):
        """The report's per-solid volume entries ([] without volume=True)."""
        return self.report.get("volume", {}).get("solids", [])

    @property
    def failed_faces(self):
        return [f for f in self.faces if f["status"] != "ok"]

    def write(self, path, stl_groups=False):
        """Writes .msh (Gmsh 4.1), .vtu, .stl, .inp or .su2 (format from the extension) with the named
        groups (Face<i>, Solid<i> and the groups parameter's); stl_groups: .stl as named multi-solid
        ASCII (OpenFOAM), the default when the parameters hold face groups."""
        self._r.write(os.fspath(path), bool(stl_groups))

    def render_png(self, path, **kw):
        """Writes a PNG picture (width, height, azimuth, elevation, color='face'|'quality', focus)."""
        self._r.render_png(os.fspath(path), **kw)

    def to_mesh(self):
        """A FreeCAD Mesh.Mesh (needs FreeCAD)."""
        from ..app.to_femmesh import result_to_mesh
        return result_to_mesh(self)

    def to_femmesh(self, groups=True):
        """A FreeCAD Fem.FemMesh with one face group per CAD face named 'Face<i>' (needs FreeCAD);
        with tetrahedra, Tetra4/Tetra10 volumes too (after the surface elements) and one volume
        group per solid named 'Solid<i>'."""
        from ..app.to_femmesh import result_to_femmesh
        return result_to_femmesh(self, groups=groups)

    def __repr__(self):
        r = self.report
        tets = f", {r['volume']['tetrahedra']} tetrahedra" if "volume" in r else ""
        return (f"<MeshResult {r['status']}: {r['counts']['nodes']} nodes, {r['counts']['triangles']} triangles, "
                f"{r['counts']['quads']} quads{tets}>")


class MeshJob:
    """A meshing run that can be cancelled from another thread and reports progress.

    job = MeshJob(source, size=2.0); job.run(progress=cb) in a worker thread; job.cancel() from
    anywhere. progress(fraction, stage) is called from worker threads; returning False cancels.
    """

    def __init__(self, source, params=None, **kw):
        _require_native()
        if params is not None and kw:
            raise TypeError("give either a MeshParams object or keyword parameters, not both")
        if params is not None and not isinstance(params, MeshParams):
            raise TypeError(f"params must be a MeshParams, got {type(params).__name__}")
        self.params = params if params is not None else MeshParams.from_kwargs(**kw)
        self.params.validate()
        self.model = _load(source)
        for b in self.params.boundary_layers:
            if b.auto and b.first_height == 0:
                # the last of N rows about as tall as the surface size (an isotropic hand-off)
                size = self.params.size or self.model.diagonal / 50.0
                n = b.layers or 20
                b.layers = n
                b.first_height = size / b.growth ** (n - 1)
        self._mesher = _native.Mesher(self.model, self.params.to_native())
        self._lock = threading.Lock()

    def run(self, progress=None, log=None):
        return MeshResult(self._mesher.run(progress, log))

    def cancel(self):
        self._mesher.cancel()


def _load(source):
    if _native is not None and isinstance(source, _native.Model):
        return source
    if hasattr(source, "exportBrepToString"):  # a Part.Shape (FreeCAD), with its placement
        if source.isNull():
            raise InputError("the shape is empty (null shape)")
        if not source.Faces:
            raise InputError(f"the shape has no face to mesh (type {source.ShapeType})")
        return _native.Model.from_brep(source.exportBrepToString())
    if isinstance(source, (str, os.PathLike)):
        s = os.fspath(source)
        if "CASCADE Topology" in s[:200]:
            return _native.Model.from_brep(s)
        if "\n" in s:
            raise InputError("not a BREP string (no 'CASCADE Topology' header) and not a file path")
        return _native.Model.from_file(s)
    if isinstance(source, bytes):
        return _load(source.decode("utf-8", "replace"))
    if hasattr(source, "Topology") and hasattr(source, "CountFacets"):  # a FreeCAD Mesh.Mesh
        pts, facets = source.Topology
        return _native.Model.from_arrays(np.array([[p.x, p.y, p.z] for p in pts], dtype=float),
                                         np.array(facets, dtype=np.int64).reshape(-1, 3))
    if isinstance(source, tuple) and len(source) == 2:  # (points, triangles) arrays
        return _native.Model.from_arrays(np.asarray(source[0], dtype=float), np.asarray(source[1], dtype=np.int64))
    raise TypeError(f"cannot mesh a {type(source).__name__}: give a file path (STEP/IGES/BREP/STL/OBJ), a BREP "
                    "string, a Part.Shape, a Mesh.Mesh or (points, triangles) arrays")


def mesh_shape(shape_or_path, progress=None, log=None, **params):
    """Meshes a Part.Shape, a STEP/IGES/BREP file path or a BREP string, or remeshes triangulated
    input (an STL/OBJ path, a Mesh.Mesh, (points, triangles) arrays); returns a MeshResult.

    Parameters are the CLI's options in snake_case (see MeshParams): size, min_size, max_size,
    curvature_angle, max_deviation, grading, threads, order, quads, local_sizes, boundary_layers,
    volume (tetrahedra in every closed solid), volume_max_size.
    """
    return MeshJob(shape_or_path, **params).run(progress=progress, log=log)


def propose_leading_edges(shape_or_path):
    """Edges along which the surface is smooth but curves far more across than along (the
    rounded leading edges of wings and blades), as dicts: edge (1-based FreeCAD number), radius
    (across the edge), curvature_ratio, coincident_edges (twins in unsewn CAD)."""
    _require_native()
    return _load(shape_or_path).propose_leading_edges()


def discrete_features(source, feature_angle=40.0):
    """What the discrete backend finds in triangulated input: an STL/OBJ path, (points,
    triangles) arrays or a FreeCAD Mesh.Mesh. Returns a dict: points, triangles (repaired),
    triangle_face (0-based face per triangle), edges [{nodes, vertices, faces}], vertex_nodes,
    face_loops, repair (counts, tolerance, lines), description (`paramesh info`'s lines)."""
    _require_native()
    if isinstance(source, (str, os.PathLike)):
        return _native.discrete_features(os.fspath(source), feature_angle=feature_angle)
    if hasattr(source, "Topology"):  # a FreeCAD Mesh.Mesh: (points, facets)
        pts, facets = source.Topology
        source = (np.array([[p.x, p.y, p.z] for p in pts], dtype=float), np.array(facets, dtype=np.int64))
    points, triangles = source
    return _native.discrete_features("", np.asarray(points, dtype=float), np.asarray(triangles, dtype=np.int64),
                                     feature_angle=feature_angle)


def mesh_file(path, **params):
    """Meshes a STEP/IGES/BREP file."""
    return mesh_shape(os.fspath(path), **params)


def mesh_brep(brep, **params):
    """Meshes an OpenCASCADE BREP text (Part.Shape.exportBrepToString())."""
    _require_native()
    return MeshJob(_native.Model.from_brep(brep), **params).run()
