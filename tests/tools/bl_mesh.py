# SPDX-License-Identifier: LGPL-2.1-or-later
"""bl_check's model of its inputs: FreeCAD's Part (optional) and the CAD edges and faces it is asked
about (CadModel), and the surface mesh with its adjacency (SurfMesh, read from a Gmsh MSH 4.1 file or
a freecad.paramesh MeshResult). Imported by bl_check.py; see its docstring for what is measured."""
import os
import sys
from collections import defaultdict

import numpy as np

FREECAD_LIB = "/usr/lib/freecad-python3/lib"


# ----------------------------------------------------------------------------------------------
# FreeCAD (optional)

def import_part():
    """FreeCAD's Part module, or None when FreeCAD cannot be imported."""
    if FREECAD_LIB not in sys.path and os.path.isdir(FREECAD_LIB):
        sys.path.append(FREECAD_LIB)
    try:
        import FreeCAD  # noqa: F401  (FreeCAD before Part)
        import Part
        return Part
    except Exception:  # pragma: no cover - FreeCAD missing
        return None


def read_shape(path_or_shape):
    """A Part.Shape from a STEP/IGES/BREP path (or a shape, returned as is)."""
    if hasattr(path_or_shape, "Faces"):
        return path_or_shape
    Part = import_part()
    if Part is None:
        raise RuntimeError("FreeCAD (Part) is needed to read the CAD model")
    s = Part.Shape()
    s.read(os.fspath(path_or_shape))
    return s


class CadModel:
    """The CAD edges and faces the checker asks about (FreeCAD numbering, 1-based)."""

    def __init__(self, shape):
        import FreeCAD
        self.V = FreeCAD.Vector
        self.Part = import_part()
        self.shape = shape
        self.edges = shape.Edges
        self.faces = shape.Faces

    def edge_distance(self, e, points):
        """Distances of points (K, 3) to CAD edge e (1-based)."""
        edge = self.edges[e - 1]
        return np.array([edge.distToShape(self.Part.Vertex(self.V(*p)))[0] for p in points])

    def edge_polyline(self, e, n=400):
        return np.array([[q.x, q.y, q.z] for q in self.edges[e - 1].discretize(n)])

    def edge_tangent(self, e, p):
        edge = self.edges[e - 1]
        u = edge.Curve.parameter(self.V(*p))
        t = edge.tangentAt(u)
        return np.array([t.x, t.y, t.z])

    def vertex_points(self, edges):
        pts = []
        for e in edges:
            for v in self.edges[e - 1].Vertexes:
                pts.append([v.Point.x, v.Point.y, v.Point.z])
        return np.array(pts).reshape(-1, 3)

    def face_normal(self, f, p):
        """Outward normal of CAD face f (1-based) at the point nearest to p; Face.normalAt
        includes the face orientation."""
        face = self.faces[f - 1]
        u, v = face.Surface.parameter(self.V(*p))
        n = face.normalAt(u, v)
        return np.array([n.x, n.y, n.z])


# ----------------------------------------------------------------------------------------------
# The mesh

class SurfMesh:
    """A surface mesh: nodes, triangles, quads, their CAD faces, the CAD edges' segments and the
    CAD entity of each node (dim 0/1/2 and 1-based number; dim -1 unknown)."""

    def __init__(self, points, tris, quads, tri_face, quad_face, segments=None, segment_edge=None,
                 node_dim=None, node_entity=None, node_param=None, name="mesh"):
        self.points = np.ascontiguousarray(points, dtype=float)
        self.tris = np.asarray(tris, dtype=np.int64).reshape(-1, 3)
        self.quads = np.asarray(quads, dtype=np.int64).reshape(-1, 4)
        self.tri_face = np.asarray(tri_face, dtype=np.int64).reshape(-1)
        self.quad_face = np.asarray(quad_face, dtype=np.int64).reshape(-1)
        n = len(self.points)
        self.segments = np.asarray([] if segments is None else segments, np.int64).reshape(-1, 2)
        self.segment_edge = np.asarray([] if segment_edge is None else segment_edge, np.int64).reshape(-1)
        self.node_dim = np.full(n, -1, np.int64) if node_dim is None else np.asarray(node_dim, np.int64)
        self.node_entity = np.zeros(n, np.int64) if node_entity is None else np.asarray(node_entity, np.int64)
        self.node_param = None if node_param is None else np.asarray(node_param, float).reshape(-1, 2)
        self.name = name
        self._build_adjacency()

    # -- constructors
    @classmethod
    def from_msh(cls, path):
        """Reads a Gmsh MSH 4.1 file with meshio (cell entity tags, node dim/tags)."""
        import meshio
        m = meshio.read(os.fspath(path), file_format="gmsh")
        geo = m.cell_data.get("gmsh:geometrical")
        tris, tf, quads, qf, segs, se = [], [], [], [], [], []
        for k, block in enumerate(m.cells):
            tags = geo[k] if geo is not None else np.zeros(len(block.data), np.int64)
            if block.type == "triangle":
                tris.append(block.data)
                tf.append(tags)
            elif block.type == "quad":
                quads.append(block.data)
                qf.append(tags)
            elif block.type == "line":
                segs.append(block.data)
                se.append(tags)
        cat = lambda a, w: np.concatenate(a) if a else np.zeros((0, w) if w else 0, np.int64)  # noqa: E731
        dim = ent = None
        if "gmsh:dim_tags" in m.point_data:
            dt = np.asarray(m.point_data["gmsh:dim_tags"])
            dim, ent = dt[:, 0], dt[:, 1]
        return cls(m.points, cat(tris, 3), cat(quads, 4), cat(tf, 0), cat(qf, 0), cat(segs, 2), cat(se, 0),
                   dim, ent, name=os.fspath(path))

    @classmethod
    def from_result(cls, r, name="result"):
        """From a freecad.paramesh MeshResult (first-order)."""
        return cls(r.nodes, r.triangles, r.quads, r.triangle_face, r.quad_face, r.segments, r.segment_edge,
                   r.node_dim, r.node_entity, r.node_param, name=name)

    # -- topology
    def _build_adjacency(self):
        """edge (i<j) -> list of (element id, position); elements are triangles 0..M-1 then quads."""
        self.n_tris = len(self.tris)
        self.elements = [tuple(t) for t in self.tris] + [tuple(q) for q in self.quads]
        self.elem_face = np.concatenate([self.tri_face, self.quad_face])
        self.edge_elems = defaultdict(list)
        for k, el in enumerate(self.elements):
            m = len(el)
            for i in range(m):
                a, b = el[i], el[(i + 1) % m]
                self.edge_elems[(a, b) if a < b else (b, a)].append(k)
        self.seg_set = set()
        self.seg_edge_of = {}
        for (a, b), e in zip(self.segments, self.segment_edge):
            key = (int(min(a, b)), int(max(a, b)))
            self.seg_set.add(key)
            self.seg_edge_of[key] = int(e)

    def is_quad(self, k):
        return k >= self.n_tris

    def other_elem(self, k, a, b):
        key = (a, b) if a < b else (b, a)
        for j in self.edge_elems.get(key, ()):
            if j != k:
                return j
        return None
