#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""ParaMesh's boundary-layer checker: measures the rows of quads grown from CAD edges.

Usage:
  bl_check.py CAD MESH --edges 21,6 --first-height H0 --growth R --layers N
              [--json] [--verbose] [--nodes auto|tags|cad] [--tol T]
              [--require [--max-height-err 0.02] [--max-growth-err 0.02] [--min-full 95]
                         [--min-ortho 75] [--max-jump 1.5] [--max-inverted 0]]

MESH is a Gmsh MSH 4.1 file (read with meshio): triangles are the isotropic mesh, quads are the
boundary-layer (BL) rows, line elements are the CAD edges' segments (entity tag = 1-based FreeCAD
edge number) and every node carries the CAD entity it lies on (dim 0/1/2, tag).

What is measured
  base nodes   the mesh nodes on the BL edges: from the node entity tags and line elements of the
               MSH file (`--nodes tags`: exact for ParaMesh's own meshes), or geometrically, the
               nodes within --tol (default 0.05 * H0) of the CAD edges with FreeCAD's distToShape
               (`--nodes cad`: works on any mesh). `auto`: tags when the file has them.
  column       a stack of quads over one mesh segment of a BL edge, walked upward row by row
               across each quad's top edge (a fan column at a reflex corner starts with the fan
               triangle at the corner). It ends at a triangle (the isotropic hand-off), at the
               face boundary, or where the next quad touches a BL edge again (another layer).
  height       of a row: the mean of the quad's two side lengths (straight 3D lengths).
  first height the first row's height; error = |h_1 - H0| / H0.
  growth       h_(k+1) / h_k between consecutive rows; error = max |g - R| / R over the column.
  layers       rows reached; a column is full when it has N rows.
  orthogonality the angle between a column's first side segment and the edge tangent at its base
               node (90 = orthogonal); sides standing on a CAD vertex (the end columns, which run
               along the neighbouring edge, and corners) are left out. The tangent comes from the CAD
               edge (FreeCAD) when available, else from the edge's mesh segments.
  jump         the size jump at the hand-off: the height of the triangle standing on the column's
               top edge (2 area / top length) against the last row's height, max(t/h, h/t).
  mesh checks  every mesh edge used by 1 or 2 elements (triangles and quads), edges used once only
               on CAD edges that are free (all their segments used once), neighbours in one face
               traversing their shared edge in opposite directions, and quads convex and facing
               like the surface normal: the CAD face normal (FreeCAD) when available, else the
               normals of the neighbouring elements of the same face.

Height and growth errors for --require are taken over the full columns (partial columns are
listed with their stop reason); fan columns are measured apart (their first row is a triangle).
Exit status: 0 ok, 1 a --require threshold failed, 2 bad input.
Needs numpy and meshio; FreeCAD (Part) only for --nodes cad and CAD normals/tangents.
Run with Debian's /usr/bin/python3.
"""
import argparse
import json
import math
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



# ----------------------------------------------------------------------------------------------
# Base nodes (on the BL edges) and tangents

def base_nodes_from_tags(mesh, edges):
    """{node: set of BL edges} from the line elements and the node entity tags."""
    edges = set(edges)
    on = defaultdict(set)
    for (a, b), e in zip(mesh.segments, mesh.segment_edge):
        if int(e) in edges:
            on[int(a)].add(int(e))
            on[int(b)].add(int(e))
    for i in np.nonzero((mesh.node_dim == 1) & np.isin(mesh.node_entity, list(edges)))[0]:
        on[int(i)].add(int(mesh.node_entity[i]))
    return on


def base_nodes_from_cad(mesh, cad, edges, tol):
    """{node: set of BL edges}: the nodes within tol of each CAD edge (FreeCAD distToShape)."""
    on = defaultdict(set)
    P = mesh.points
    for e in edges:
        poly = cad.edge_polyline(e)
        seg_a, seg_b = poly[:-1], poly[1:]
        # chord deviation of the polyline bounds the pre-filter's error
        lo = poly.min(axis=0) - tol
        hi = poly.max(axis=0) + tol
        span = np.linalg.norm(poly.max(axis=0) - poly.min(axis=0))
        slack = max(tol, 0.02 * span / max(len(poly) - 1, 1)) + tol
        box = np.nonzero(np.all((P >= lo - slack) & (P <= hi + slack), axis=1))[0]
        cand = []
        for chunk in np.array_split(box, max(1, len(box) // 2000 + 1)):
            d = _point_polyline_distance(P[chunk], seg_a, seg_b)
            cand.extend(chunk[d < 10 * slack].tolist())
        if not cand:
            continue
        d = cad.edge_distance(e, P[cand])
        for i, di in zip(cand, d):
            if di <= tol:
                on[int(i)].add(e)
    return on


def _point_polyline_distance(Q, A, B):
    """Distance of each point of Q (K, 3) to the polyline of segments A[i]-B[i]."""
    AB = B - A
    L2 = np.maximum((AB * AB).sum(axis=1), 1e-300)
    best = np.full(len(Q), np.inf)
    for start in range(0, len(A), 256):
        a, ab, l2 = A[start:start + 256], AB[start:start + 256], L2[start:start + 256]
        t = np.clip(((Q[:, None, :] - a[None]) * ab[None]).sum(axis=2) / l2[None], 0, 1)
        proj = a[None] + t[:, :, None] * ab[None]
        best = np.minimum(best, np.linalg.norm(Q[:, None, :] - proj, axis=2).min(axis=1))
    return best


def vertex_nodes(mesh, on, cad=None, tol=0.0):
    """Base nodes standing on a CAD vertex (an end of a BL edge)."""
    if cad is not None:
        V = cad.vertex_points(sorted({e for s in on.values() for e in s}))
        out = set()
        for i in on:
            if len(V) and np.linalg.norm(V - mesh.points[i], axis=1).min() <= tol:
                out.add(i)
        return out
    if (mesh.node_dim >= 0).any():
        return {i for i in on if mesh.node_dim[i] == 0}
    return {i for i in on if len(on[i]) > 1}


def mesh_tangents(mesh, on):
    """Unit edge tangent at each base node from the edges' mesh segments (central difference)."""
    nbr = defaultdict(list)
    keys = [k for k in mesh.seg_set if k[0] in on and k[1] in on]
    if not keys:  # no line elements: quad edges joining two base nodes
        keys = [k for k, els in mesh.edge_elems.items()
                if k[0] in on and k[1] in on and any(mesh.is_quad(j) for j in els)]
    for a, b in keys:
        nbr[a].append(b)
        nbr[b].append(a)
    T = {}
    P = mesh.points
    for i, ns in nbr.items():
        if len(ns) >= 2:
            # orient the two neighbours along the edge: the pair farthest apart
            best = max(((x, y) for x in ns for y in ns if x != y), key=lambda xy: np.linalg.norm(P[xy[0]] - P[xy[1]]))
            t = P[best[1]] - P[best[0]]
        else:
            t = P[ns[0]] - P[i]
        n = np.linalg.norm(t)
        if n > 0:
            T[i] = t / n
    return T


def cad_tangents(cad, mesh, on):
    T = {}
    for i, es in on.items():
        e = min(es)
        t = cad.edge_tangent(e, mesh.points[i])
        n = np.linalg.norm(t)
        if n > 0:
            T[i] = t / n
    return T


# ----------------------------------------------------------------------------------------------
# Columns

def _quad_rotated(q, a, b):
    """The quad's nodes rotated so that (a, b) is its bottom edge in either direction; returns
    (a, b, c, d) with c above b and d above a."""
    q = list(q)
    for i in range(4):
        if q[i] == a and q[(i + 1) % 4] == b:
            return q[i], q[(i + 1) % 4], q[(i + 2) % 4], q[(i + 3) % 4]
        if q[i] == b and q[(i + 1) % 4] == a:
            # reversed orientation: a at i+1, b at i; d above a is i+2, c above b is i+3
            return a, b, q[(i + 3) % 4], q[(i + 2) % 4]
    raise ValueError("edge not in quad")


def _length(P, i, j):
    return float(np.linalg.norm(P[i] - P[j]))


def walk_columns(mesh, on, max_rows=10000):
    """All columns over the BL edges. Returns a list of dicts with the row heights, the side
    segments of the first row, the top edge, the stop reason and the hand-off triangle."""
    P = mesh.points
    starts = []
    # ordinary columns: quad edges between two base nodes
    for key, els in mesh.edge_elems.items():
        a, b = key
        if a in on and b in on:
            for k in els:
                if mesh.is_quad(k):
                    starts.append(("quad", k, a, b))
    # fan columns: a triangle with one base node whose opposite edge carries a quad
    for k, t in enumerate(mesh.tris):
        t = [int(x) for x in t]
        inb = [x in on for x in t]
        if sum(inb) != 1:
            continue
        i = inb.index(True)
        c, a, b = t[i], t[(i + 1) % 3], t[(i + 2) % 3]
        q = mesh.other_elem(k, a, b)
        if q is not None and mesh.is_quad(q) and mesh.elem_face[q] == mesh.elem_face[k]:
            starts.append(("fan", k, c, (a, b)))
    cols = []
    for kind, k, a, b in starts:
        face = int(mesh.elem_face[k])
        heights, sides, visited = [], [], {k}
        if kind == "quad":
            qa, qb, qc, qd = _quad_rotated(mesh.elements[k], a, b)
            base = (qa, qb)
            sides = [(qa, qd), (qb, qc)]
            heights.append(0.5 * (_length(P, qa, qd) + _length(P, qb, qc)))
            top = (qd, qc)
            left, right = [qa, qd], [qb, qc]
            cur = k
        else:
            c = a
            ta, tb = b
            base = (c, c)
            sides = [(c, ta), (c, tb)]
            heights.append(0.5 * (_length(P, c, ta) + _length(P, c, tb)))
            top = (ta, tb)
            left, right = [c, ta], [c, tb]
            cur = k
        stop, handoff = "boundary", None
        while len(heights) < max_rows:
            nxt = mesh.other_elem(cur, top[0], top[1])
            if nxt is None:
                stop = "boundary"
                break
            if int(mesh.elem_face[nxt]) != face:
                stop = "face_edge"
                break
            if not mesh.is_quad(nxt):
                stop = "handoff"
                handoff = nxt
                break
            if nxt in visited:
                stop = "loop"
                break
            _, _, qc, qd = _quad_rotated(mesh.elements[nxt], top[0], top[1])
            if qc in on or qd in on:
                stop = "other_layer"
                break
            visited.add(nxt)
            heights.append(0.5 * (_length(P, top[0], qd) + _length(P, top[1], qc)))
            top = (qd, qc)
            left.append(qd)
            right.append(qc)
            cur = nxt
        cols.append({"kind": kind, "face": face, "base": base, "sides": sides, "heights": heights,
                     "left": left, "right": right, "top": top, "stop": stop, "handoff": handoff,
                     "where": (0.5 * (P[base[0]] + P[base[1]])).tolist()})
    return cols


def _triangle_height(P, tri, top):
    a, b = top
    c = [x for x in tri if x != a and x != b]
    if len(c) != 1:
        return None
    area2 = np.linalg.norm(np.cross(P[b] - P[a], P[c[0]] - P[a]))
    L = np.linalg.norm(P[b] - P[a])
    return float(area2 / L) if L > 0 else None


def measure_columns(mesh, cols, on, vertices, tangents, h0, r, n):
    """Adds the measures to each column (in place) and returns them."""
    P = mesh.points
    for c in cols:
        h = np.asarray(c["heights"])
        c["layers"] = len(h)
        c["full"] = len(h) >= n
        c["first_height"] = float(h[0])
        c["height_err"] = abs(h[0] - h0) / h0
        g = h[1:] / h[:-1] if len(h) > 1 else np.zeros(0)
        c["growth"] = g.tolist()
        c["growth_err"] = float(np.abs(g - r).max() / r) if len(g) else 0.0
        # row k should be h0 r^k: the largest deviation over the column
        c["row_err"] = float((np.abs(h - h0 * r ** np.arange(len(h))) / (h0 * r ** np.arange(len(h)))).max())
        ang = []
        if c["kind"] == "quad":
            for s0, s1 in c["sides"]:
                if s0 in vertices or s0 not in tangents:
                    continue
                v = P[s1] - P[s0]
                nv = np.linalg.norm(v)
                if nv == 0:
                    continue
                cosang = min(1.0, abs(float(np.dot(v / nv, tangents[s0]))))
                ang.append(math.degrees(math.acos(cosang)))
        c["ortho"] = min(ang) if ang else None
        # the whole column: its sides from base to top against the edge tangent (end blending
        # turns the upper rows; the first segment stays orthogonal)
        whole = []
        if c["kind"] == "quad":
            for chain in (c["left"], c["right"]):
                s0 = chain[0]
                if s0 in vertices or s0 not in tangents:
                    continue
                v = P[chain[-1]] - P[s0]
                nv = np.linalg.norm(v)
                if nv > 0:
                    whole.append(math.degrees(math.acos(min(1.0, abs(float(np.dot(v / nv, tangents[s0])))))))
        c["ortho_whole"] = min(whole) if whole else None
        # the quad's own corner angles at the base (side against the base segment, a chord of the
        # edge): differs from the tangent angle by half the edge's turn over the segment
        corner = []
        if c["kind"] == "quad":
            a, b = c["base"]
            for (s0, s1), other in zip(c["sides"], (b, a)):
                if s0 in vertices:
                    continue
                v, w = P[s1] - P[s0], P[other] - P[s0]
                den = np.linalg.norm(v) * np.linalg.norm(w)
                if den > 0:
                    cosang = min(1.0, abs(float(np.dot(v, w))) / den)
                    corner.append(math.degrees(math.acos(cosang)))
        c["base_angle"] = min(corner) if corner else None
        # a side running along a CAD edge (the end columns): all its nodes above the base on it
        c["along_edge"] = None
        for chain in (c["left"], c["right"]):
            up = chain[1:]
            if up and (mesh.node_dim[up] == 1).all() and len(set(mesh.node_entity[up].tolist())) == 1:
                c["along_edge"] = int(mesh.node_entity[up[0]])
        if not c["full"] and c["along_edge"] is not None and c["stop"] == "handoff":
            c["stop"] = "edge_end"
        c["jump"] = None
        if c["handoff"] is not None:
            th = _triangle_height(P, mesh.elements[c["handoff"]], c["top"])
            if th:
                c["jump"] = max(th / h[-1], h[-1] / th)
                c["handoff_height"] = th
    return cols


# ----------------------------------------------------------------------------------------------
# Whole-mesh checks

def conformity(mesh):
    """Edge use counts: every mesh edge used by 1 or 2 elements, edges used once only on free CAD
    edges, consistent orientation between neighbours of one face."""
    counts = defaultdict(int)
    nonmanifold, boundary, orient_bad = [], [], 0
    for key, els in mesh.edge_elems.items():
        counts[len(els)] += 1
        if len(els) > 2:
            nonmanifold.append(key)
        elif len(els) == 1:
            boundary.append(key)
        else:
            k1, k2 = els
            if mesh.elem_face[k1] == mesh.elem_face[k2]:
                if _direction(mesh.elements[k1], key) == _direction(mesh.elements[k2], key):
                    orient_bad += 1
    off_cad = [k for k in boundary if mesh.seg_set and k not in mesh.seg_set]
    # a CAD edge is free when all its segments are used once; a CAD edge with some segments used
    # once and others twice is a crack (non-conformal faces along it)
    use_by_edge = defaultdict(set)
    for key in mesh.seg_set:
        use_by_edge[mesh.seg_edge_of[key]].add(len(mesh.edge_elems.get(key, ())))
    cracked = sorted(e for e, s in use_by_edge.items() if 1 in s and len(s - {1}) > 0)
    free = sorted(e for e, s in use_by_edge.items() if s == {1})
    missing = sorted(e for e, s in use_by_edge.items() if 0 in s)
    ok = not nonmanifold and not off_cad and not cracked and not missing and orient_bad == 0
    return {"ok": ok, "edges": sum(counts.values()), "used_once": counts.get(1, 0), "used_twice": counts.get(2, 0),
            "used_more": len(nonmanifold), "boundary_off_cad_edges": len(off_cad), "free_cad_edges": free,
            "cracked_cad_edges": cracked, "segments_without_element": missing,
            "orientation_mismatches": orient_bad,
            "watertight": counts.get(1, 0) == 0 and not nonmanifold}


def _direction(el, key):
    a, b = key
    m = len(el)
    for i in range(m):
        if el[i] == a and el[(i + 1) % m] == b:
            return 1
        if el[i] == b and el[(i + 1) % m] == a:
            return -1
    return 0


def element_normals(mesh):
    """Vector area of every element (triangles, then quads: half the cross product of the
    diagonals, the Newell normal of a quad)."""
    P = mesh.points
    t, q = mesh.tris, mesh.quads
    nt = 0.5 * np.cross(P[t[:, 1]] - P[t[:, 0]], P[t[:, 2]] - P[t[:, 0]]) if len(t) else np.zeros((0, 3))
    nq = 0.5 * np.cross(P[q[:, 2]] - P[q[:, 0]], P[q[:, 3]] - P[q[:, 1]]) if len(q) else np.zeros((0, 3))
    return np.concatenate([nt, nq])


def cad_quad_normals(mesh, cad):
    """CAD normal for each quad: the face normal at its corners (from the nodes' (u,v) when the mesh
    has them, else by projecting the centroid on the surface)."""
    out = np.zeros((len(mesh.quads), 3))
    have_uv = mesh.node_param is not None
    for qi, q in enumerate(mesh.quads):
        f = int(mesh.quad_face[qi])
        face = cad.faces[f - 1]
        n = np.zeros(3)
        if have_uv:
            for i in q:
                if mesh.node_dim[i] == 2 and mesh.node_entity[i] == f:
                    v = face.normalAt(float(mesh.node_param[i, 0]), float(mesh.node_param[i, 1]))
                    n += (v.x, v.y, v.z)
        if not n.any():
            n = cad.face_normal(f, mesh.points[q].mean(axis=0))
        out[qi] = n
    return out


def quad_validity(mesh, cad=None):
    """Inverted quads: a corner whose turn (cross product of its two edges) does not face like the
    reference normal (non-convex, bow-tie or folded quads), or a quad whose own normal faces
    against it. The reference normal is the CAD face's normal (cad given), else the sum of the
    unit normals of the quad's neighbours across its edges in the same face (its own when it has
    none)."""
    P = mesh.points
    K = len(mesh.quads)
    if K == 0:
        return {"quads": 0, "inverted": 0, "flipped": 0, "nonconvex": 0, "min_corner_sine": 1.0, "bad_quads": []}
    en = element_normals(mesh)
    own = en[mesh.n_tris:]
    if cad is not None:
        ref = cad_quad_normals(mesh, cad)
    else:
        unit = en / np.maximum(np.linalg.norm(en, axis=1), 1e-300)[:, None]
        ref = np.zeros((K, 3))
        for qi, q in enumerate(mesh.quads):
            k = mesh.n_tris + qi
            for i in range(4):
                j = mesh.other_elem(k, int(q[i]), int(q[(i + 1) % 4]))
                if j is not None and mesh.elem_face[j] == mesh.elem_face[k]:
                    ref[qi] += unit[j]
            if not ref[qi].any():
                ref[qi] = own[qi]
    ref = ref / np.maximum(np.linalg.norm(ref, axis=1), 1e-300)[:, None]
    p = P[mesh.quads]                       # (K, 4, 3)
    e_in = p - np.roll(p, 1, axis=1)        # edge arriving at corner i
    e_out = np.roll(p, -1, axis=1) - p      # edge leaving corner i
    cr = np.cross(e_in, e_out)
    den = np.linalg.norm(e_in, axis=2) * np.linalg.norm(e_out, axis=2)
    turns = np.where(den > 0, (cr * ref[:, None, :]).sum(axis=2) / np.maximum(den, 1e-300), -1.0)
    mt = turns.min(axis=1)
    facing = (own * ref).sum(axis=1)
    flipped = facing <= 0
    nonconvex = (mt <= 0) & ~flipped
    bad = np.nonzero(flipped | nonconvex)[0]
    return {"quads": K, "inverted": int(len(bad)), "flipped": int(flipped.sum()),
            "nonconvex": int(nonconvex.sum()), "min_corner_sine": float(mt.min()),
            "bad_quads": bad[:20].tolist()}


def handoff_triangles(mesh):
    """Smallest angle (degrees) of the triangles sharing a node with a quad (the isotropic
    triangles next to the layer, fan triangles included), and how many are below 10 degrees."""
    if not len(mesh.quads) or not len(mesh.tris):
        return {"n": 0, "min_angle": None, "below_10": 0}
    in_quad = np.zeros(len(mesh.points), bool)
    in_quad[mesh.quads.ravel()] = True
    t = mesh.tris[in_quad[mesh.tris].any(axis=1)]
    P = mesh.points
    ang = []
    for i in range(3):
        u = P[t[:, (i + 1) % 3]] - P[t[:, i]]
        v = P[t[:, (i + 2) % 3]] - P[t[:, i]]
        c = (u * v).sum(axis=1) / np.maximum(np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1), 1e-300)
        ang.append(np.degrees(np.arccos(np.clip(c, -1, 1))))
    m = np.min(ang, axis=0)
    return {"n": int(len(t)), "min_angle": float(m.min()) if len(m) else None, "below_10": int((m < 10).sum())}


def rising_sides(cols):
    """{base node: set of the nodes one row above it} over all columns."""
    rising = defaultdict(set)
    for c in cols:
        for s0, s1 in c["sides"]:
            rising[s0].add(s1)
    return rising


def corner_fans(mesh, cols):
    """Base nodes from which more than two column sides rise (fans), as a list of
    {node, xyz, columns}."""
    return [{"node": int(i), "xyz": mesh.points[i].tolist(), "columns": len(s)}
            for i, s in sorted(rising_sides(cols).items()) if len(s) > 2]


def end_columns(mesh, cols, vertices):
    """The columns standing on a CAD vertex: which CAD edge their side runs along and how many
    rows, as a list of {face, vertex, xyz, along_edge, rows, nodes_on_edge}."""
    out = []
    for c in cols:
        if c["kind"] != "quad":
            continue
        for chain in (c["left"], c["right"]):
            if chain[0] in vertices:
                up = chain[1:]
                ents = set(mesh.node_entity[up].tolist())
                along = ents.pop() if (mesh.node_dim[up] == 1).all() and len(ents) == 1 else None
                out.append({"face": c["face"], "vertex": int(chain[0]), "xyz": mesh.points[chain[0]].tolist(),
                            "along_edge": along,
                            "rows": len(up), "dims": sorted(set(mesh.node_dim[up].tolist())),
                            "entities": sorted(set(mesh.node_entity[up].tolist())), "nodes": [int(x) for x in up]})
    return out


# ----------------------------------------------------------------------------------------------
# The whole check

def _stats(v):
    v = [x for x in v if x is not None]
    if not v:
        return {"n": 0, "min": None, "max": None, "mean": None}
    a = np.asarray(v, float)
    return {"n": int(len(a)), "min": float(a.min()), "max": float(a.max()), "mean": float(a.mean())}


def check(mesh, edges, first_height, growth, layers, cad=None, nodes="auto", tol=None, normals="auto",
          tangents="auto"):
    """Measures the BL columns grown from `edges` (1-based CAD edges) in `mesh` (a SurfMesh).
    cad: a CadModel, a Part.Shape or a path (optional; needed for nodes='cad'). Returns a dict
    (JSON-serialisable) with the summary, and the per-column list under '_columns'."""
    if isinstance(edges, int):
        edges = [edges]
    edges = [int(e) for e in edges]
    if first_height <= 0 or growth <= 0 or layers < 1:
        raise ValueError("first_height and growth must be > 0 and layers >= 1")
    tol = 0.05 * first_height if tol is None else tol
    if cad is not None and not isinstance(cad, CadModel):
        cad = CadModel(read_shape(cad))
    if nodes == "auto":
        nodes = "tags" if (len(mesh.segments) or (mesh.node_dim >= 0).any()) else "cad"
    if nodes == "tags":
        on = base_nodes_from_tags(mesh, edges)
    elif nodes == "cad":
        if cad is None:
            raise ValueError("--nodes cad needs the CAD model and FreeCAD")
        on = base_nodes_from_cad(mesh, cad, edges, tol)
    else:
        raise ValueError(f"nodes must be auto, tags or cad, got {nodes!r}")
    if not on:
        raise ValueError(f"no mesh node lies on the edges {edges}")
    verts = vertex_nodes(mesh, on, cad if nodes == "cad" else None, tol)
    use_cad_t = cad is not None and tangents in ("auto", "cad")
    T = cad_tangents(cad, mesh, on) if use_cad_t else mesh_tangents(mesh, on)
    cols = walk_columns(mesh, on)
    measure_columns(mesh, cols, on, verts, T, first_height, growth, layers)
    reg = [c for c in cols if c["kind"] == "quad"]
    fan = [c for c in cols if c["kind"] == "fan"]
    full = [c for c in reg if c["full"]]
    use_cad_n = cad is not None and normals in ("auto", "cad")
    ends = end_columns(mesh, cols, verts)
    out = {
        "mesh": mesh.name,
        "edges": edges,
        "first_height": first_height, "growth": growth, "layers": layers,
        "node_source": nodes, "tangent_source": "cad" if use_cad_t else "mesh",
        "normal_source": "cad" if use_cad_n else "mesh",
        "base_nodes": len(on), "vertex_nodes": len(verts),
        "columns": len(reg), "fan_columns": len(fan), "full_columns": len(full),
        "pct_full": 100.0 * len(full) / len(reg) if reg else 0.0,
        "faces": {str(f): sum(1 for c in reg if c["face"] == f) for f in sorted({c["face"] for c in reg})},
        "layers_reached": _stats([c["layers"] for c in reg]),
        "first_height_measured": _stats([c["first_height"] for c in reg]),
        "height_err_full": _stats([c["height_err"] for c in full]),
        "height_err_all": _stats([c["height_err"] for c in reg]),
        "growth_measured": _stats([g for c in reg for g in c["growth"]]),
        "growth_err_full": _stats([c["growth_err"] for c in full]),
        "growth_err_all": _stats([c["growth_err"] for c in reg]),
        "row_err_full": _stats([c["row_err"] for c in full]),
        "ortho_deg": _stats([c["ortho"] for c in reg]),
        "base_angle_deg": _stats([c["base_angle"] for c in reg]),
        "ortho_whole_deg": _stats([c["ortho_whole"] for c in reg]),
        "jump": _stats([c["jump"] for c in reg + fan]),
        "handoff_triangles": handoff_triangles(mesh),
        "stops": {s: sum(1 for c in reg if c["stop"] == s and not c["full"]) for s in
                  sorted({c["stop"] for c in reg if not c["full"]})},
        "fan": {"columns": len(fan), "layers": _stats([c["layers"] for c in fan]),
                "first_height": _stats([c["first_height"] for c in fan]),
                "corners": corner_fans(mesh, cols)},
        "end_columns": [{k: v for k, v in e.items() if k != "nodes"} for e in ends],
        "conformity": conformity(mesh),
        "quads": quad_validity(mesh, cad if use_cad_n else None),
        "_columns": cols,
        "_vertices": verts,
        "_base": on,
        "_ends": ends,
        "_mesh": mesh,
    }
    return out


def requirements(res, max_height_err=0.02, max_growth_err=0.02, min_full=95.0, min_ortho=75.0, max_jump=1.5,
                 max_inverted=0, conformal=True):
    """The failed requirements as a list of strings (empty when all hold)."""
    fails = []
    he = res["height_err_full"]["max"]
    if he is None or he > max_height_err:
        fails.append(f"first height error {he} > {max_height_err} on a full column")
    ge = res["growth_err_full"]["max"]
    if ge is None or ge > max_growth_err:
        fails.append(f"growth error {ge} > {max_growth_err} on a full column")
    if res["pct_full"] < min_full:
        fails.append(f"full columns {res['pct_full']:.1f}% < {min_full}%")
    om = res["ortho_deg"]["min"]
    if om is not None and om < min_ortho:
        fails.append(f"orthogonality {om:.1f} deg < {min_ortho}")
    jm = res["jump"]["max"]
    if jm is not None and jm > max_jump:
        fails.append(f"hand-off jump {jm:.2f} > {max_jump}")
    if res["quads"]["inverted"] > max_inverted:
        fails.append(f"{res['quads']['inverted']} inverted quads > {max_inverted}")
    if conformal and not res["conformity"]["ok"]:
        fails.append(f"mesh not conformal: {json.dumps(res['conformity'])}")
    return fails


def worst_columns(res, count=5):
    """The worst columns for each measure, as printable lines."""
    cols = [c for c in res["_columns"] if c["kind"] == "quad"]
    lines = []

    def where(c):
        x, y, z = c["where"]
        return f"Face{c['face']} at ({x:.4g}, {y:.4g}, {z:.4g}), {c['layers']} rows, stop {c['stop']}"

    for title, key, rev, only in (("first height error", "height_err", True, True),
                                  ("growth error", "growth_err", True, True),
                                  ("orthogonality (deg)", "ortho", False, False),
                                  ("hand-off jump", "jump", True, False),
                                  ("layers", "layers", False, False)):
        pool = [c for c in cols if c[key] is not None and (c["full"] or not only)]
        pool.sort(key=lambda c: c[key], reverse=rev)
        lines.append(f"worst {title}:")
        for c in pool[:count]:
            lines.append(f"  {c[key]:.4g}  {where(c)}")
    return lines


def summary_json(res):
    return {k: v for k, v in res.items() if not k.startswith("_")}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[1:]))
    ap.add_argument("cad", help="the CAD model (STEP/IGES/BREP); '-' for none (tags only)")
    ap.add_argument("mesh", help="the mesh (Gmsh MSH 4.1)")
    ap.add_argument("--edges", required=True, help="BL edges, 1-based FreeCAD numbers: 21,6")
    ap.add_argument("--first-height", type=float, required=True)
    ap.add_argument("--growth", type=float, required=True)
    ap.add_argument("--layers", type=int, required=True)
    ap.add_argument("--nodes", choices=("auto", "tags", "cad"), default="auto",
                    help="how the base nodes are found (default: tags when the file has them)")
    ap.add_argument("--tol", type=float, default=None, help="distance to a CAD edge (default 0.05 * first height)")
    ap.add_argument("--no-cad", action="store_true", help="do not load the CAD (mesh tangents and normals)")
    ap.add_argument("--json", action="store_true", help="print the summary as JSON")
    ap.add_argument("--verbose", "-v", action="store_true", help="also print the worst columns")
    ap.add_argument("--require", action="store_true", help="exit 1 when a threshold below fails")
    ap.add_argument("--max-height-err", type=float, default=0.02)
    ap.add_argument("--max-growth-err", type=float, default=0.02)
    ap.add_argument("--min-full", type=float, default=95.0)
    ap.add_argument("--min-ortho", type=float, default=75.0)
    ap.add_argument("--max-jump", type=float, default=1.5)
    ap.add_argument("--max-inverted", type=int, default=0)
    a = ap.parse_args(argv)
    try:
        edges = [int(x.strip().removeprefix("Edge")) for x in a.edges.split(",") if x.strip()]
        if not os.path.isfile(a.mesh):
            raise ValueError(f"cannot read the mesh {a.mesh!r}: no such file")
        try:
            mesh = SurfMesh.from_msh(a.mesh)
        except (Exception, SystemExit) as e:  # meshio raises ReadError or calls sys.exit(1)
            raise ValueError(f"cannot read the mesh {a.mesh!r}: {e}") from e
        cad = None
        if a.cad != "-" and not a.no_cad:
            if import_part() is None:
                if a.nodes == "cad":
                    raise ValueError("--nodes cad needs FreeCAD")
                print("note: FreeCAD not available, using mesh tangents and normals", file=sys.stderr)
            else:
                cad = CadModel(read_shape(a.cad))
        res = check(mesh, edges, a.first_height, a.growth, a.layers, cad=cad, nodes=a.nodes, tol=a.tol)
    except (OSError, ValueError, RuntimeError) as e:
        print(f"bl_check: {e}", file=sys.stderr)
        return 2
    fails = requirements(res, a.max_height_err, a.max_growth_err, a.min_full, a.min_ortho, a.max_jump,
                         a.max_inverted) if a.require else []
    if a.json:
        out = summary_json(res)
        if a.require:
            out["failed_requirements"] = fails
        print(json.dumps(out, indent=1))
    else:
        print(format_text(res))
        for f in fails:
            print("FAIL:", f)
    if a.verbose:
        for line in worst_columns(res):
            print(line, file=sys.stderr if a.json else sys.stdout)
    return 1 if fails else 0


def _fmt(s, f="{:.4g}"):
    if s["n"] == 0:
        return "-"
    return f"min {f.format(s['min'])}  max {f.format(s['max'])}  mean {f.format(s['mean'])}"


def format_text(res):
    c, q, t = res["conformity"], res["quads"], res["handoff_triangles"]
    fans = ", ".join("({:.4g}, {:.4g}, {:.4g}): {}".format(*f["xyz"], f["columns"]) for f in res["fan"]["corners"])
    along = ", ".join(f"Face{e['face']} along Edge{e['along_edge']} ({e['rows']} rows)"
                      for e in res["end_columns"] if e["along_edge"])
    corner_sides = sum(1 for e in res["end_columns"] if not e["along_edge"])
    min_angle = "-" if t["min_angle"] is None else f"{t['min_angle']:.2f}"
    lines = [
        f"{res['mesh']}: BL on edges {res['edges']} (h0 {res['first_height']}, r {res['growth']}, "
        f"N {res['layers']}); nodes from {res['node_source']}, tangents {res['tangent_source']}, "
        f"normals {res['normal_source']}",
        f"  columns {res['columns']} (+{res['fan_columns']} fan), full {res['full_columns']} "
        f"({res['pct_full']:.1f}%), per face {res['faces']}",
        f"  layers reached      {_fmt(res['layers_reached'], '{:.0f}')}",
        f"  first height        {_fmt(res['first_height_measured'])}",
        f"  height error (full) {_fmt(res['height_err_full'], '{:.2e}')}",
        f"  growth              {_fmt(res['growth_measured'])}",
        f"  growth error (full) {_fmt(res['growth_err_full'], '{:.2e}')}",
        f"  orthogonality (deg) {_fmt(res['ortho_deg'], '{:.2f}')}  (to the edge tangent)",
        f"  base angle (deg)    {_fmt(res['base_angle_deg'], '{:.2f}')}  (to the base segment)",
        f"  column tilt (deg)   {_fmt(res['ortho_whole_deg'], '{:.2f}')}  (base-to-top chord to the edge tangent)",
        f"  hand-off jump       {_fmt(res['jump'], '{:.3f}')}",
        f"  partial columns by stop: {res['stops']}",
        f"  triangles touching the layer: {t['n']}, smallest angle {min_angle} deg, {t['below_10']} below 10 deg",
        f"  fan corners: {fans or '-'}",
        f"  end columns along CAD edges: {along or '-'}; {corner_sides} other column sides on CAD vertices",
        f"  mesh edges {c['edges']}: used once {c['used_once']}, twice {c['used_twice']}, more {c['used_more']}; "
        f"free CAD edges {c['free_cad_edges']}; cracked {c['cracked_cad_edges']}; "
        f"orientation mismatches {c['orientation_mismatches']}; conformal {'yes' if c['ok'] else 'NO'}",
        f"  quads {q['quads']}: inverted {q['inverted']} (flipped {q['flipped']}, non-convex {q['nonconvex']}), "
        f"min corner sine {q['min_corner_sine']:.3g}",
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
