# SPDX-License-Identifier: LGPL-2.1-or-later
"""bl_check's whole-mesh checks: conformity (edge use, cracks, orientation), element normals, inverted
quads and the triangles at the layer's hand-off. Imported by bl_check.py; see its docstring."""
from collections import defaultdict

import numpy as np


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
