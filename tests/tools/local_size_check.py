#!/usr/bin/python3
"""Local size check (independent of ParaMesh's code): how element sizes grow away from a face.

usage: local_size_check.py MESH.msh --face N --local HL --global H [--grading G]
                           [--plot FILE.png] [--table FILE.md]

The size of a triangle is the mean of its three straight edge lengths; its distance is the 3D
distance from its centroid to the nearest point of face N's triangles (MSH entity tag N), 0 on
the face. Measured:
  - on the face: the fraction of its triangles whose size is within [HL/sqrt2, sqrt2*HL], and the
    extreme ratios size/HL;
  - away from it: the median and 90th percentile size per distance bin; the growth per element
    implied by the median curve, m(d + m(d)) / m(d), at most G (+5 %: the bins' own noise);
  - the distance at which the median size reaches 0.9*H, against the distance a field that grows
    by G per element (dh/dd = G - 1) needs for it: (0.9*H - HL) / (G - 1).
Also reported (information, not part of the exit status), in the graded zone d < (H - HL)/(G - 1):
  - cad_edge_segments_over_law: the CAD-edge segments (line elements) against the law
    HL + (G - 1) d at their midpoints; they are spaced by integrating 1/h of ParaMesh's size field
    along the edge, so this measures the size field itself;
  - triangles_over_law: the triangle sizes against the same law at their centroids (what the face
    mesher makes of the field);
  - outward_neighbour_growth: for neighbours (sharing an edge) not both on the face, the size of the
    farther one over the nearer one; neighbour_ratio_on_face: the same scatter where the target is
    constant (both on the face).
Prints JSON; exit status 1 when a requirement fails: < 99 % of the face's triangles in range,
growth above G*1.05, or 0.9*H reached later than 1.5 x the implied distance (or never).
"""
import argparse
import json
import math
import sys

import numpy as np
import meshio
from scipy.spatial import cKDTree


def point_triangle_distance(P, A, B, C):
    """Distances from points P (n,3) to triangles (A,B,C) (n,3 each), row-wise (Ericson's method)."""
    ab, ac, ap = B - A, C - A, P - A
    d1, d2 = (ab * ap).sum(1), (ac * ap).sum(1)
    bp = P - B
    d3, d4 = (ab * bp).sum(1), (ac * bp).sum(1)
    cp = P - C
    d5, d6 = (ab * cp).sum(1), (ac * cp).sum(1)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    den = va + vb + vc
    den = np.where(np.abs(den) > 0, den, 1.0)
    v, w = vb / den, vc / den
    Q = A + v[:, None] * ab + w[:, None] * ac  # interior projection
    # regions (vertex / edge) overwrite the interior result where they apply
    def seg(X, Y):
        d = Y - X
        t = np.clip(((P - X) * d).sum(1) / np.maximum((d * d).sum(1), 1e-300), 0, 1)
        return X + t[:, None] * d
    inside = (va >= 0) & (vb >= 0) & (vc >= 0)
    cands = [seg(A, B), seg(B, C), seg(C, A)]
    best = np.min([np.linalg.norm(P - c, axis=1) for c in cands], axis=0)
    return np.where(inside, np.minimum(np.linalg.norm(P - Q, axis=1), best), best)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mesh")
    ap.add_argument("--face", type=int, required=True)
    ap.add_argument("--local", type=float, required=True)
    ap.add_argument("--global", dest="glob", type=float, required=True)
    ap.add_argument("--grading", type=float, default=1.3)
    ap.add_argument("--plot", default="")
    ap.add_argument("--table", default="")
    a = ap.parse_args()
    m = meshio.read(a.mesh)
    P = np.asarray(m.points, float)
    T, E = [], []
    for i, c in enumerate(m.cells):
        if c.type == "triangle":
            T.append(c.data)
            E.append(m.cell_data["gmsh:geometrical"][i])
    T = np.concatenate(T).astype(np.int64)
    E = np.concatenate(E)
    X = P[T]  # (n,3,3)
    L = np.stack([np.linalg.norm(X[:, 1] - X[:, 0], axis=1), np.linalg.norm(X[:, 2] - X[:, 1], axis=1),
                  np.linalg.norm(X[:, 0] - X[:, 2], axis=1)], axis=1)
    size = L.mean(1)
    cen = X.mean(1)
    onf = E == a.face
    if not onf.any():
        print(json.dumps({"error": f"no triangle of face {a.face}"}))
        return 1
    F = X[onf]
    # distance to the face: candidates from a kd-tree of face-triangle centroids, refined exactly
    tree = cKDTree(F.mean(1))

    def face_distance(Q):
        k = min(8, len(F))
        _, idx = tree.query(Q, k=k)
        idx = idx.reshape(len(Q), -1)
        dq = np.full(len(Q), np.inf)
        for j in range(idx.shape[1]):
            f = F[idx[:, j]]
            dq = np.minimum(dq, point_triangle_distance(Q, f[:, 0], f[:, 1], f[:, 2]))
        return dq

    dist = face_distance(cen)
    dist[onf] = 0.0
    r = size[onf] / a.local
    in_range = float(np.mean((r >= 2 ** -0.5) & (r <= 2 ** 0.5)))
    out = {"face": a.face, "local": a.local, "global": a.glob, "grading": a.grading,
           "face_triangles": int(onf.sum()), "face_pct_in_range": 100 * in_range,
           "face_ratio_min": float(r.min()), "face_ratio_max": float(r.max()),
           "face_ratio_median": float(np.median(r))}
    # median size per distance bin (bins of half the local size near the face, growing)
    edges = [0.0, 1e-12]
    w = 0.5 * a.local
    while edges[-1] < 4 * (a.glob - a.local) / (a.grading - 1):
        edges.append(edges[-1] + w)
        w = min(w * 1.15, 0.5 * a.glob)
    edges = np.array(edges)
    rows = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (dist >= lo) & (dist < hi) if hi > 1e-12 else dist == 0
        if sel.sum() < 5:
            continue
        d = 0.0 if hi <= 1e-12 else float(np.median(dist[sel]))
        rows.append((d, float(np.median(size[sel])), float(np.percentile(size[sel], 90)), int(sel.sum())))
    D = np.array([x[0] for x in rows])
    M = np.array([x[1] for x in rows])
    # growth per element from the median curve: m(d + m(d)) / m(d), where d + m(d) is sampled
    growth = []
    for d, s in zip(D, M):
        if d + s > D[-1]:
            break
        growth.append(float(np.interp(d + s, D, M) / s))
    gmax = max(growth) if growth else float("nan")
    # neighbour pairs: the size ratio across each interior edge (for information: it includes the
    # element-to-element scatter of an unstructured mesh, not only the field's growth)
    e = np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]])
    owner = np.tile(np.arange(len(T)), 3)
    e.sort(1)
    key = e[:, 0] * (len(P) + 1) + e[:, 1]
    order = np.argsort(key, kind="stable")
    ks, ow = key[order], owner[order]
    pair = ks[1:] == ks[:-1]
    t1, t2 = ow[:-1][pair], ow[1:][pair]
    ratio = np.maximum(size[t1], size[t2]) / np.minimum(size[t1], size[t2])
    near = (dist[t1] < (a.glob - a.local) / (a.grading - 1)) | (dist[t2] < (a.glob - a.local) / (a.grading - 1))
    # where the median reaches 0.9 H, against the implied distance
    target = 0.9 * a.glob
    reach = next((d for d, s in zip(D, M) if s >= target), None)
    implied = (target - a.local) / (a.grading - 1)
    out.update({"growth_per_element_max": gmax,
                "neighbour_ratio_p50_in_graded_zone": float(np.median(ratio[near])) if near.any() else None,
                "neighbour_ratio_p99_in_graded_zone": float(np.percentile(ratio[near], 99)) if near.any() else None,
                "distance_to_0.9H": reach, "implied_distance_to_0.9H": implied,
                "bins": [{"distance": d, "median_size": s, "p90_size": p, "n": n} for d, s, p, n in rows]})
    # the field law itself, h_L + (G-1) d below H (information): the CAD-edge segments (line
    # elements), which are spaced by integrating 1/h of the size field along the edge, against the
    # triangles of the graded zone (their size against the law at their centroid distance)
    dfull = (a.glob - a.local) / (a.grading - 1)
    law = lambda d: a.local + (a.grading - 1) * d
    S = [c.data for c in m.cells if c.type == "line"]
    if S:
        S = np.concatenate(S).astype(np.int64)
        sd = face_distance(0.5 * (P[S[:, 0]] + P[S[:, 1]]))
        sl = np.linalg.norm(P[S[:, 0]] - P[S[:, 1]], axis=1)
        z = (sd > 0.5 * a.local) & (sd < dfull)
        if z.any():
            q = sl[z] / law(sd[z])
            out["cad_edge_segments_over_law_in_graded_zone"] = {
                "n": int(z.sum()), "p10": float(np.percentile(q, 10)), "median": float(np.median(q)),
                "p90": float(np.percentile(q, 90))}
    z = (~onf) & (dist < dfull)
    if z.any():
        q = size[z] / law(dist[z])
        out["triangles_over_law_in_graded_zone"] = {
            "n": int(z.sum()), "p1": float(np.percentile(q, 1)), "p10": float(np.percentile(q, 10)),
            "median": float(np.median(q)), "p90": float(np.percentile(q, 90)), "max": float(q.max())}
    # growth per element away from the face, pair by pair: for neighbours not both on the face,
    # the size of the farther one over the nearer one, in the graded zone; the same ratio between
    # neighbours on the face (constant target) is the mesh's own scatter
    farther = np.where(dist[t1] <= dist[t2], t2, t1)
    nearer = np.where(dist[t1] <= dist[t2], t1, t2)
    zone = (dist[farther] > dist[nearer]) & (dist[nearer] < dfull)
    both = onf[t1] & onf[t2]
    if zone.any():
        gr = size[farther[zone]] / size[nearer[zone]]
        out["outward_neighbour_growth_in_graded_zone"] = {
            "pairs": int(zone.sum()), "median": float(np.median(gr)), "p99": float(np.percentile(gr, 99)),
            "max": float(gr.max())}
    if both.any():
        out["neighbour_ratio_on_face"] = {"p99": float(np.percentile(ratio[both], 99)), "max": float(ratio[both].max())}
    ok = in_range >= 0.99 and gmax <= a.grading * 1.05 and reach is not None and reach <= 1.5 * implied
    out["ok"] = bool(ok)
    if a.table:
        with open(a.table, "w") as f:
            f.write("| distance from the face | median size | p90 size | field h_L + (G-1) d | triangles |\n")
            f.write("|---|---|---|---|---|\n")
            for d, s, p, n in rows:
                if d > 2.0 * implied:
                    break
                f.write(f"| {d:.2f} | {s:.3f} | {p:.3f} | {min(a.glob, a.local + (a.grading - 1) * d):.3f} | {n} |\n")
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7, 4.2), dpi=120)
        sel = dist < 2.5 * implied
        ax.scatter(dist[sel], size[sel], s=1, alpha=0.15, color="0.5", label="triangles")
        ax.plot(D[D < 2.5 * implied], M[D < 2.5 * implied], "b.-", label="median per distance bin")
        dd = np.linspace(0, 2.5 * implied, 200)
        ax.plot(dd, np.minimum(a.glob, a.local + (a.grading - 1) * dd), "r--",
                label=f"h_L + (G-1) d, G = {a.grading}")
        ax.axhline(a.local * 2 ** 0.5, color="g", lw=0.6, ls=":")
        ax.axhline(a.local * 2 ** -0.5, color="g", lw=0.6, ls=":", label="local size x [1/sqrt2, sqrt2]")
        ax.set_xlabel("3D distance from the face")
        ax.set_ylabel("element size (mean edge length)")
        ax.set_title(f"Face{a.face}: local size {a.local:g} inside global {a.glob:g}")
        ax.legend(loc="lower right", fontsize=8)
        fig.tight_layout()
        fig.savefig(a.plot)
    print(json.dumps(out, indent=1))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
