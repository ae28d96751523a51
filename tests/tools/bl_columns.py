# SPDX-License-Identifier: LGPL-2.1-or-later
"""bl_check's column measures: the base nodes on the boundary-layer edges and their tangents, the
columns of quads walked upward from them, each column's rows measured (height, growth,
orthogonality, hand-off jump), and the fans and end columns among them. Imported by bl_check.py;
see its docstring for the definitions."""
import math
from collections import defaultdict

import numpy as np


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
        heights, visited = [], {k}
        if kind == "quad":  # the first row's bottom corners and the corners above them
            qa, qb, qc, qd = _quad_rotated(mesh.elements[k], a, b)
            b0, b1, t0, t1 = qa, qb, qd, qc
        else:  # a fan: both sides rise from the corner node a to the triangle's opposite edge b
            b0, b1, (t0, t1) = a, a, b
        base = (b0, b1)
        sides = [(b0, t0), (b1, t1)]
        heights.append(0.5 * (_length(P, b0, t0) + _length(P, b1, t1)))
        top = (t0, t1)
        left, right = [b0, t0], [b1, t1]
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
# Fans and end columns

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
