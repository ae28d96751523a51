#!/usr/bin/python3
"""Geometric fidelity of a surface mesh, triangle by triangle (independent of ParaMesh's code).

usage: fidelity_check.py CAD MESH [--ratio 0.03] [--sample N] [--jobs J] [--worst K]
                         [--faces F1,F2,...] [--max-edge L] [--min-size M --angle DEG]
For every triangle (or a random sample of N), the distance from its centroid to its own CAD face
(MSH entity tag = FreeCAD face number) divided by the triangle's mean edge length. Triangles of
planar faces are skipped (a plane has no sag). Prints JSON: max and percentiles of that ratio, how
many triangles exceed --ratio, and the worst K with their face and position.

For each triangle over the limit it also measures how far its own nodes lie from the face's
surface (Surface.parameter/value, not the trimmed face): nodes on a CAD edge that lies off the
face within the edge's tolerance carry that offset into every triangle built on them, and no
refinement can remove it. `over_limit_beyond_cad_gap` counts the triangles still over the limit
after subtracting the mean offset of their nodes. Uses FreeCAD's Part (OpenCASCADE distToShape);
run with Debian's /usr/bin/python3.

The distance is an upper bound taken as the smallest of three: distToShape to the face, and the
distance to the surface at two feet found on the surface itself (Surface.parameter, and a
Gauss-Newton descent from the (u,v) of the triangle's own nodes and of their mean), each counted
only when the foot lies inside the trimmed face (Face.isPartOfDomain). distToShape alone misses
the foot on strongly skewed parametrisations: on propeller_and_shaft's blade tips (du and dv 1.4
degrees apart) it puts points that lie on the surface well inside the face 0.0009 mm off it.
`dist_to_shape_overestimated` counts the triangles over the limit by distToShape whose distance a
surface foot lowered.

With --min-size and --angle (the run's --min-size and --curvature-angle), each triangle over the
limit also gets the CAD's smallest radius of curvature under it (1 / the largest principal
curvature in magnitude, from OpenCASCADE's Surface.curvature 'Max' and 'Min', which are signed, at
its centroid's foot, its nodes and its edges' (u,v) midpoints). A triangle can subtend at most the angle when its
edges are at most radius x angle; where that is below the min-size, the min-size (the size field's
floor) forbids the triangles the bound needs. `over_limit_resolvable` counts the triangles over
the limit (beyond the CAD gap) whose radius is at least min-size / angle: those the min-size allowed
to meet it.

Issue 2 words the limit as a distance "from the CAD": for each triangle over the limit against its
own face, the distance from its centroid to the whole shape (every face) is measured too, and
`over_limit_to_cad` counts those still over it (a centroid that left its own trimmed face across a
curved trim boundary can lie on the neighbouring face).
"""
import argparse, json, sys
sys.path.append('/usr/lib/freecad-python3/lib')
import numpy as np
import meshio

_shape = None


def _load(cad):
    global _shape
    from cad_read import read_cad
    _shape = read_cad(cad)


def _finite(x):
    return float(x) if np.isfinite(x) else None


def _newton_foot(S, C, u, w):
    """Local closest point of C on S from (u, w): Gauss-Newton on |S(u,w) - C|^2."""
    u0, u1, w0, w1 = S.bounds()
    for _ in range(30):
        r = np.array(S.value(u, w) - C)
        a = np.array(S.getDN(u, w, 1, 0)); b = np.array(S.getDN(u, w, 0, 1))
        J = np.stack([a, b], 1)
        try:
            du, dw = np.linalg.solve(J.T @ J, -J.T @ r)
        except np.linalg.LinAlgError:
            break
        t = 1.0
        f0 = r @ r
        while t > 1e-4:
            un, wn = min(max(u + t * du, u0), u1), min(max(w + t * dw, w0), w1)
            rn = np.array(S.value(un, wn) - C)
            if rn @ rn <= f0:
                break
            t *= 0.5
        if t <= 1e-4:
            break
        u, w = un, wn
        if abs(t * du) + abs(t * dw) < 1e-15:
            break
    return u, w


def _work(args):
    import FreeCAD, Part
    tris, ents = args
    faces = _shape.Faces
    out = []
    for tri, e in zip(tris, ents):
        f = faces[int(e) - 1]
        c = tri.mean(0)
        L = (np.linalg.norm(tri[0] - tri[1]) + np.linalg.norm(tri[1] - tri[2]) + np.linalg.norm(tri[2] - tri[0])) / 3
        d = Part.Vertex(FreeCAD.Vector(*c)).distToShape(f)[0]
        gap = 0.0
        over = 0
        if d / L > _limit:
            # distToShape is an upper bound that can miss the foot on a strongly skewed
            # parametrisation (propeller_and_shaft's blade tips: points lying on the surface, well
            # inside the face, get 0.0009 mm); the surface's own projection (Surface.parameter),
            # where its foot is inside the trimmed face, is another upper bound: keep the smaller
            # a third: Gauss-Newton from the (u,v) of the triangle's own nodes and their mean
            S = f.Surface
            C = FreeCAD.Vector(*c)
            seeds = [S.parameter(C)]
            foot = seeds[0]
            nodes = [S.parameter(FreeCAD.Vector(*p)) for p in tri]
            seeds += nodes + [tuple(np.mean(nodes, 0))]
            for k, (u, w) in enumerate(seeds):
                if k > 0:
                    u, w = _newton_foot(S, C, u, w)
                if f.isPartOfDomain(u, w):
                    ds = (S.value(u, w) - C).Length
                    if ds < d:
                        over = 1
                        d = ds
                        foot = (u, w)
        dcad = d
        radius = float('inf')
        if d / L > _limit:  # still over after the feet above (S, C, nodes and foot are set)
            dcad = min(d, Part.Vertex(C).distToShape(_shape)[0])
            for p, (u, w) in zip(tri, nodes):
                gap += (S.value(u, w) - FreeCAD.Vector(*p)).Length / 3
            # the sharpest curvature under the triangle: at its centroid's foot, its nodes and
            # the (u,v) midpoints of its edges (across a crest the foot can lie on a flank)
            at = [foot] + nodes + [((nodes[i][0] + nodes[i - 1][0]) / 2, (nodes[i][1] + nodes[i - 1][1]) / 2)
                                   for i in range(3)]
            k = 0.0
            for u, w in at:
                try:
                    k = max(k, abs(S.curvature(u, w, 'Max')), abs(S.curvature(u, w, 'Min')))
                except Exception:
                    pass
            radius = 1.0 / k if k > 0 else float('inf')
        out.append((d / L, max(d - gap, 0.0) / L, L, dcad / L, over, radius))
    return out


def main():
    global _limit
    ap = argparse.ArgumentParser()
    ap.add_argument('cad'); ap.add_argument('mesh')
    ap.add_argument('--ratio', type=float, default=0.03)
    ap.add_argument('--sample', type=int, default=0)
    ap.add_argument('--jobs', type=int, default=2)
    ap.add_argument('--worst', type=int, default=5)
    ap.add_argument('--faces', default='', help='only these faces (comma-separated FreeCAD numbers)')
    ap.add_argument('--max-edge', type=float, default=0, help='only triangles whose mean edge is at most this')
    ap.add_argument('--min-size', type=float, default=0, help="the run's --min-size (with --angle)")
    ap.add_argument('--angle', type=float, default=0, help="the run's --curvature-angle, degrees")
    a = ap.parse_args()
    _limit = a.ratio
    _load(a.cad)
    planar = [f.Surface.__class__.__name__ == 'Plane' for f in _shape.Faces]
    m = meshio.read(a.mesh)
    P = np.asarray(m.points, float)
    T, E = [], []
    for i, c in enumerate(m.cells):
        if c.type == 'triangle':
            T.append(c.data); E.append(m.cell_data['gmsh:geometrical'][i])
    T = np.concatenate(T); E = np.concatenate(E)
    keep = {int(x) for x in a.faces.split(',') if x.strip()}
    idx = np.array([t for t in range(len(T)) if not planar[int(E[t]) - 1] and (not keep or int(E[t]) in keep)], dtype=int)
    if a.max_edge > 0 and len(idx):
        X = P[T[idx]]
        L = (np.linalg.norm(X[:, 0] - X[:, 1], axis=1) + np.linalg.norm(X[:, 1] - X[:, 2], axis=1)
             + np.linalg.norm(X[:, 2] - X[:, 0], axis=1)) / 3
        idx = idx[L <= a.max_edge]
    if a.sample and a.sample < len(idx):
        idx = np.random.default_rng(0).choice(idx, a.sample, replace=False)
    chunks = [idx[k::max(1, a.jobs)] for k in range(max(1, a.jobs))]
    if a.jobs > 1:
        import multiprocessing as mp
        with mp.get_context('fork').Pool(a.jobs) as pool:
            parts = pool.map(_work, [(P[T[c]], E[c]) for c in chunks])
    else:
        parts = [_work((P[T[c]], E[c])) for c in chunks]
    order = np.concatenate(chunks)
    res = np.array([r for part in parts for r in part]) if len(order) else np.zeros((0, 6))
    ratios, beyond = res[:, 0], res[:, 1]
    worst = np.argsort(-ratios)[:a.worst]
    out = {'triangles': int(len(T)), 'checked': int(len(order)), 'ratio_max': float(ratios.max()),
           'ratio_p99': float(np.percentile(ratios, 99)), 'ratio_mean': float(ratios.mean()),
           'limit': a.ratio, 'over_limit': int((ratios > a.ratio).sum()),
           'over_limit_beyond_cad_gap': int((beyond > a.ratio).sum()),
           'ratio_beyond_cad_gap_max': float(beyond.max()),
           'over_limit_to_cad': int((res[:, 3] > a.ratio).sum()),
           'ratio_to_cad_max': float(res[:, 3].max()),
           'dist_to_shape_overestimated': int(res[:, 4].sum()),
           'over_limit_radius_min': _finite(res[ratios > a.ratio, 5].min()) if (ratios > a.ratio).any() else None,
           'worst': [{'ratio': float(ratios[k]), 'beyond_cad_gap': float(beyond[k]), 'to_cad': float(res[k, 3]), 'face': int(E[order[k]]),
                      'mean_edge': float(res[k, 2]), 'centroid': [round(float(x), 4) for x in P[T[order[k]]].mean(0)]}
                     for k in worst]}
    for w, k in zip(out['worst'], worst):
        if ratios[k] > a.ratio:
            w['cad_radius'] = _finite(res[k, 5])
    if a.min_size > 0 and a.angle > 0:
        reach = a.min_size / np.radians(a.angle)
        out['min_size_reach_radius'] = float(reach)
        out['over_limit_resolvable'] = int(((beyond > a.ratio) & (res[:, 5] >= reach)).sum())
    print(json.dumps(out, indent=1))
    sys.exit(0 if out['over_limit'] == 0 else 1)


if __name__ == '__main__':
    main()
