#!/usr/bin/python3
"""Elements across narrow faces (independent of ParaMesh's code).

usage: across_check.py MESH --size H [--min 3]
For every CAD face of the mesh (MSH entity tag), its width is measured across it between parts of
its boundary that face each other (distance from each boundary node to the boundary segments that
are roughly perpendicular to the connecting line, excluding neighbours). Faces narrower than
`--min` x size are "narrow"; for each, the number of elements across is estimated as
width / median edge length of the face (and, conservatively, width / longest edge). Prints JSON; exit status 1 when a narrow face has fewer than
`--min` elements across.
"""
import argparse, json, sys
import numpy as np
import meshio


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('mesh'); ap.add_argument('--size', type=float, required=True)
    ap.add_argument('--min', type=float, default=3)
    a = ap.parse_args()
    m = meshio.read(a.mesh)
    P = np.asarray(m.points, float)
    T, E = [], []
    for i, c in enumerate(m.cells):
        if c.type == 'triangle':
            T.append(c.data); E.append(m.cell_data['gmsh:geometrical'][i])
    T = np.concatenate(T); E = np.concatenate(E)
    faces = []
    worst = None
    for f in np.unique(E):
        tf = T[E == f]
        e = np.sort(np.concatenate([tf[:, [0, 1]], tf[:, [1, 2]], tf[:, [2, 0]]]), axis=1)
        ue, cnt = np.unique(e, axis=0, return_counts=True)
        b = ue[cnt == 1]
        L = np.linalg.norm(P[ue[:, 0]] - P[ue[:, 1]], axis=1)
        if not len(b):
            continue
        # boundary loops with cumulative arc length, to tell "across" from "around a corner"
        nb = {}
        for s_, (x, y) in enumerate(b):
            nb.setdefault(int(x), []).append(int(y)); nb.setdefault(int(y), []).append(int(x))
        loop_of, pos, total = {}, {}, {}
        lid = 0
        for start in nb:
            if start in loop_of:
                continue
            cur, prev, acc = start, None, 0.0
            while True:
                loop_of[cur] = lid; pos[cur] = acc
                nxt = [w for w in nb[cur] if w != prev and (w not in loop_of or w == start)]
                if not nxt or nxt[0] == start:
                    if nxt:
                        acc += np.linalg.norm(P[start] - P[cur])
                    break
                acc += np.linalg.norm(P[nxt[0]] - P[cur]); prev, cur = cur, nxt[0]
            total[lid] = acc; lid += 1
        nodes = np.array(sorted(nb))
        width = np.inf
        for v in nodes:
            p = P[v]
            d = np.linalg.norm(P[nodes] - p, axis=1)
            along = np.array([abs(pos[v] - pos[w]) if loop_of[w] == loop_of[v] else np.inf for w in nodes])
            along = np.minimum(along, np.array([total[loop_of[v]] - x if np.isfinite(x) else np.inf for x in along]))
            ok = (d > 0) & (along >= 2.5 * d)
            if ok.any():
                width = min(width, d[ok].min())
        if width < a.min * a.size:
            across = width / np.median(L)
            faces.append({'face': int(f), 'width': float(width), 'median_edge': float(np.median(L)),
                          'max_edge': float(L.max()), 'across': float(across),
                          'across_by_longest_edge': float(width / L.max())})
            if worst is None or across < worst['across']:
                worst = faces[-1]
    out = {'narrow_faces': len(faces), 'min_elements_across': worst['across'] if worst else None,
           'worst': worst, 'faces_below_min': sum(1 for f in faces if f['across'] < a.min)}
    print(json.dumps(out, indent=1))
    sys.exit(1 if out['faces_below_min'] else 0)


if __name__ == '__main__':
    main()
