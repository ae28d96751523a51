#!/usr/bin/python3
"""Independent check of a second-order surface mesh against its CAD model (no ParaMesh code).

usage: midnode_check.py MODEL MESH.msh --size H [--tol 1e-6] [--jmin 0]

Reads the mesh with meshio (tria6 / quad8 cells, entity tag = CAD face number) and the CAD with
FreeCAD's Part (OCCT). Measures
  * every mid-edge node of every tria6 / quad8: distance to the CAD, required <= tol * H. A mid
    node of a segment along a CAD edge (the mesh's line3 cells, entity tag = edge number) is
    measured against that edge's curve (its distance to the face surface can only be bounded by
    the CAD's edge tolerance, reported as edge_mids_off_face_beyond_edge_tolerance); every other
    mid against the surface of the element's face (Surface.parameter + value, i.e. an orthogonal
    projection; distToShape on the trimmed face as a fall-back when that looks wrong);
  * inversion: the Jacobian J = x_r x x_s of the quadratic map (tria6: 6-node Lagrange, quad8:
    serendipity) at the corners, mid-edges and centroid (tria6) / the 3x3 Gauss-Lobatto points
    (quad8), dotted with a reference normal. Scaled Jacobian = min_s (J_s . n) / max_s |J_s|.
    Two references are used, both must give > jmin: the straight element's normal (corners only)
    and the CAD face normal at the element (at one of its face mid-nodes), oriented like the majority of the face's
    elements (a face meshed with the other orientation is reported as 'faces_flipped_vs_cad',
    not as inverted elements).
Prints JSON; exit status 1 when a requirement fails.
"""
import argparse
import json
import sys

sys.path.append('/usr/lib/freecad-python3/lib')
import numpy as np
import meshio
import FreeCAD  # noqa: F401  (must precede Part)
import Part
from cad_read import read_cad


# --- shape-function derivatives -------------------------------------------------------------------
def tri6_derivs(r, s):
    """dN/dr, dN/ds for nodes (c0, c1, c2, m01, m12, m20) at (r, s); L0 = 1-r-s, L1 = r, L2 = s."""
    L0 = 1 - r - s
    dr = np.array([-(4 * L0 - 1), 4 * r - 1, 0, 4 * (L0 - r), 4 * s, -4 * s])
    ds = np.array([-(4 * L0 - 1), 0, 4 * s - 1, -4 * r, 4 * r, 4 * (L0 - s)])
    return dr, ds


def quad8_derivs(r, s):
    """Serendipity quad8: corners (-1,-1),(1,-1),(1,1),(-1,1), mids (0,-1),(1,0),(0,1),(-1,0)."""
    cr = [-1, 1, 1, -1]
    cs = [-1, -1, 1, 1]
    dr, ds = np.zeros(8), np.zeros(8)
    for k in range(4):
        ri, si = cr[k], cs[k]
        dr[k] = 0.25 * ri * (1 + s * si) * (2 * r * ri + s * si)
        ds[k] = 0.25 * si * (1 + r * ri) * (r * ri + 2 * s * si)
    # mids with N = (1-r^2)(1+s si)/2 or (1+r ri)(1-s^2)/2
    for k, (ri, si) in enumerate([(0, -1), (1, 0), (0, 1), (-1, 0)]):
        if ri == 0:
            dr[4 + k] = -r * (1 + s * si)
            ds[4 + k] = 0.5 * si * (1 - r * r)
        else:
            dr[4 + k] = 0.5 * ri * (1 - s * s)
            ds[4 + k] = -s * (1 + r * ri)
    return dr, ds


TRI_SAMPLES = [(0, 0), (1, 0), (0, 1), (0.5, 0), (0.5, 0.5), (0, 0.5), (1 / 3, 1 / 3)]
QUAD_SAMPLES = [(r, s) for r in (-1, 0, 1) for s in (-1, 0, 1)]
TRI_D = [tri6_derivs(*p) for p in TRI_SAMPLES]
QUAD_D = [quad8_derivs(*p) for p in QUAD_SAMPLES]


def jacobians(X, derivs):
    """X: (n, k, 3) element node coordinates; returns (n, samples, 3) Jacobian normals."""
    out = []
    for dr, ds in derivs:
        xr = np.einsum('k,nkd->nd', dr, X)
        xs = np.einsum('k,nkd->nd', ds, X)
        out.append(np.cross(xr, xs))
    return np.stack(out, axis=1)


def scaled_jacobian(J, n):
    """min_s (J_s . n) / max_s |J_s| per element; n: (m, 3) unit normals."""
    d = np.einsum('nsd,nd->ns', J, n)
    mag = np.linalg.norm(J, axis=2).max(axis=1)
    with np.errstate(divide='ignore', invalid='ignore'):
        return np.where(mag > 0, d.min(axis=1) / mag, -1.0)


def read_mesh(path):
    m = meshio.read(path)
    P = np.asarray(m.points, dtype=float)[:, :3]
    ent_key = next((k for k in ('gmsh:geometrical', 'gmsh:physical') if k in m.cell_data), None)
    if ent_key is None:
        raise SystemExit('mesh has no entity tags (gmsh:geometrical)')
    blocks = {'line3': ([], []), 'triangle6': ([], []), 'quad8': ([], []), 'triangle': ([], []), 'quad': ([], [])}
    for i, cb in enumerate(m.cells):
        if cb.type in blocks:
            blocks[cb.type][0].append(np.asarray(cb.data))
            blocks[cb.type][1].append(np.asarray(m.cell_data[ent_key][i]))
    out = {}
    for t, (d, e) in blocks.items():
        nn = {'line3': 3, 'triangle6': 6, 'quad8': 8, 'triangle': 3, 'quad': 4}[t]
        out[t] = (np.concatenate(d) if d else np.zeros((0, nn), int),
                  np.concatenate(e) if e else np.zeros(0, int))
    return P, out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('model')
    ap.add_argument('mesh')
    ap.add_argument('--size', type=float, required=True)
    ap.add_argument('--tol', type=float, default=1e-6, help='mid-node distance limit, fraction of H')
    ap.add_argument('--jmin', type=float, default=0.0, help='scaled Jacobian must be > jmin')
    ap.add_argument('--worst', type=int, default=5, help='list this many worst offenders')
    a = ap.parse_args()
    shape = read_cad(a.model)
    faces = shape.Faces
    edges = shape.Edges
    P, cells = read_mesh(a.mesh)
    T6, T6e = cells['triangle6']
    Q8, Q8e = cells['quad8']
    res = {'model': a.model, 'mesh': a.mesh, 'size': a.size, 'tria6': int(len(T6)), 'quad8': int(len(Q8)),
           'linear_elements': int(len(cells['triangle'][0]) + len(cells['quad'][0]))}

    # ---- mid-node distance to the CAD ------------------------------------------------------------
    # mids of segments along CAD edges (line3 cells, entity tag = edge number) must lie on the edge's
    # curve; their distance to the face surface is bounded by the CAD's own edge tolerance only
    # (reported separately); every other mid must lie on its face's surface.
    on_edge = {}
    L3, L3e = cells['line3']
    for row, e in zip(L3, L3e):
        on_edge[int(row[2])] = int(e)
    pairs = set()
    for E, ent, first in ((T6, T6e, 3), (Q8, Q8e, 4)):
        for row, f in zip(E[:, first:], ent):
            for v in row:
                pairs.add((int(v), int(f)))
    pairs = sorted(pairs, key=lambda p: (p[1], p[0]))
    dist = np.zeros(len(pairs))
    uv_of = {}
    fallback = 0
    edge_face_excess = 0
    edge_dist = {}
    for i, (v, f) in enumerate(pairs):
        p = FreeCAD.Vector(*P[v])
        if v in on_edge:
            if v not in edge_dist:
                edge = edges[on_edge[v] - 1]
                try:
                    d = (edge.Curve.value(edge.Curve.parameter(p)) - p).Length
                except Exception:
                    d = float('inf')
                if d > a.tol * a.size:
                    fallback += 1
                    d = min(d, edge.distToShape(Part.Vertex(p))[0])
                edge_dist[v] = (d, edge.Tolerance)
            d, etol = edge_dist[v]
            dist[i] = d
            # also on the face within the edge's tolerance (sampled: fallback distance only if needed)
            face = faces[f - 1]
            u, w = face.Surface.parameter(p)
            df = (face.Surface.value(u, w) - p).Length
            if df > max(a.tol * a.size, 1.01 * etol) and face.distToShape(Part.Vertex(p))[0] > max(a.tol * a.size, 1.01 * etol):
                edge_face_excess += 1
            continue
        face = faces[f - 1]
        try:
            u, w = face.Surface.parameter(p)
            d = (face.Surface.value(u, w) - p).Length
            uv_of[(v, f)] = (u, w)
        except Exception:
            d = float('inf')
        if d > a.tol * a.size:  # projection may have picked a wrong branch: measure the trimmed face
            fallback += 1
            d = min(d, face.distToShape(Part.Vertex(p))[0])
        dist[i] = d
    res['mid_nodes'] = len(pairs)
    res['mid_nodes_on_cad_edges'] = len(edge_dist)
    res['mid_node_projection_fallbacks'] = fallback
    res['max_mid_node_dist_over_h'] = float(dist.max() / a.size) if len(dist) else 0.0
    res['mid_nodes_off_cad'] = int((dist > a.tol * a.size).sum())
    res['edge_mids_off_face_beyond_edge_tolerance'] = edge_face_excess
    if res['mid_nodes_off_cad']:
        worst = np.argsort(-dist)[:a.worst]
        res['worst_mid_nodes'] = [{'node': pairs[k][0] + 1, 'face': pairs[k][1], 'dist_over_h': float(dist[k] / a.size),
                                   'on_edge': on_edge.get(pairs[k][0]),
                                   'xyz': [round(float(c), 6) for c in P[pairs[k][0]]]} for k in worst]

    # ---- inversion --------------------------------------------------------------------------------
    elems = []
    for name, E, ent, derivs, nc in (('tria6', T6, T6e, TRI_D, 3), ('quad8', Q8, Q8e, QUAD_D, 4)):
        if not len(E):
            continue
        X = P[E]
        J = jacobians(X, derivs)
        C = X[:, :nc]
        if nc == 3:
            ns = np.cross(C[:, 1] - C[:, 0], C[:, 2] - C[:, 0])
        else:
            ns = np.cross(C[:, 2] - C[:, 0], C[:, 3] - C[:, 1])
        ns = ns / np.maximum(np.linalg.norm(ns, axis=1), 1e-300)[:, None]
        cen = C.mean(axis=1)
        ncad = np.zeros_like(ns)
        for i, (row, c, f) in enumerate(zip(E[:, nc:], cen, ent)):
            face = faces[int(f) - 1]
            # CAD normal at a face-interior mid-node of the element (already projected), else at
            # the projection of the centroid
            uv = next((uv_of[(int(v), int(f))] for v in row if (int(v), int(f)) in uv_of), None)
            try:
                if uv is None:
                    uv = face.Surface.parameter(FreeCAD.Vector(*c))
                nv = face.normalAt(*uv)
                ncad[i] = (nv.x, nv.y, nv.z)
            except Exception:
                ncad[i] = ns[i]
        elems.append((name, E, ent, J, ns, ncad))
    # per-face orientation of the mesh against the CAD normal: majority vote
    agree = {}
    for name, E, ent, J, ns, ncad in elems:
        s = np.einsum('nd,nd->n', ns, ncad)
        for f, v in zip(ent, s):
            agree.setdefault(int(f), [0, 0])[0 if v >= 0 else 1] += 1
    flip = {f: (c[1] > c[0]) for f, c in agree.items()}
    res['faces_flipped_vs_cad'] = sorted(f for f, x in flip.items() if x)
    res['elements_against_face_majority'] = int(sum(min(c) for c in agree.values()))
    sj_all, sjc_all, bad = [], [], []
    for name, E, ent, J, ns, ncad in elems:
        sgn = np.array([-1.0 if flip[int(f)] else 1.0 for f in ent])
        sj = scaled_jacobian(J, ns)
        sjc = scaled_jacobian(J, ncad * sgn[:, None])
        sj_all.append(sj)
        sjc_all.append(sjc)
        res[f'{name}_min_scaled_jacobian'] = float(sj.min())
        res[f'{name}_min_scaled_jacobian_vs_cad'] = float(sjc.min())
        res[f'{name}_inverted'] = int(((sj <= a.jmin) | (sjc <= a.jmin)).sum())
        for k in np.argsort(np.minimum(sj, sjc))[:a.worst]:
            if min(sj[k], sjc[k]) <= a.jmin:
                bad.append({'type': name, 'index': int(k), 'face': int(ent[k]), 'sj': float(sj[k]), 'sj_cad': float(sjc[k]),
                            'centroid': [round(float(c), 4) for c in P[E[k]].mean(axis=0)]})
    sj_all = np.concatenate(sj_all) if sj_all else np.zeros(0)
    sjc_all = np.concatenate(sjc_all) if sjc_all else np.zeros(0)
    res['elements'] = int(len(sj_all))
    res['min_scaled_jacobian'] = float(sj_all.min()) if len(sj_all) else None
    res['min_scaled_jacobian_vs_cad'] = float(sjc_all.min()) if len(sjc_all) else None
    res['inverted'] = int(((sj_all <= a.jmin) | (sjc_all <= a.jmin)).sum())
    if bad:
        res['worst_elements'] = bad
    failures = []
    if res['elements'] == 0:
        failures.append('no second-order elements')
    if res['linear_elements']:
        failures.append(f"{res['linear_elements']} linear elements in a second-order mesh")
    if res['mid_nodes_off_cad']:
        failures.append(f"{res['mid_nodes_off_cad']} mid-nodes farther than {a.tol:g}*H from their CAD face")
    if res['inverted']:
        failures.append(f"{res['inverted']} inverted elements")
    if res['edge_mids_off_face_beyond_edge_tolerance']:
        failures.append(f"{res['edge_mids_off_face_beyond_edge_tolerance']} edge mid-nodes off their face beyond the edge tolerance")
    res['ok'] = not failures
    res['failures'] = failures
    print(json.dumps(res, indent=1))
    return 0 if res['ok'] else 1


if __name__ == '__main__':
    sys.exit(main())
