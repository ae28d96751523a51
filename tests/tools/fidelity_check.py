#!/usr/bin/python3
"""Geometric fidelity of a surface mesh, triangle by triangle (independent of ParaMesh's code).

usage: fidelity_check.py CAD MESH [--ratio 0.03] [--sample N]
For every triangle (or a random sample of N), the distance from its centroid to its own CAD face
(MSH entity tag = FreeCAD face number) divided by the triangle's mean edge length. Prints JSON:
max and percentiles of that ratio, and how many triangles exceed --ratio. Uses FreeCAD's Part
(OpenCASCADE distToShape); run with Debian's /usr/bin/python3.
"""
import argparse, json, sys
sys.path.append('/usr/lib/freecad-python3/lib')
import numpy as np
import meshio
import FreeCAD, Part


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('cad'); ap.add_argument('mesh')
    ap.add_argument('--ratio', type=float, default=0.03)
    ap.add_argument('--sample', type=int, default=0)
    a = ap.parse_args()
    if a.cad.lower().endswith(('.brep', '.brp')):
        shape = Part.Shape(); shape.read(a.cad)
    else:
        shape = Part.read(a.cad)
    faces = shape.Faces
    m = meshio.read(a.mesh)
    P = np.asarray(m.points, float)
    T, E = [], []
    for i, c in enumerate(m.cells):
        if c.type == 'triangle':
            T.append(c.data); E.append(m.cell_data['gmsh:geometrical'][i])
    T = np.concatenate(T); E = np.concatenate(E)
    idx = np.arange(len(T))
    if a.sample and a.sample < len(T):
        idx = np.random.default_rng(0).choice(len(T), a.sample, replace=False)
    ratios = np.empty(len(idx))
    for k, t in enumerate(idx):
        tri = P[T[t]]
        c = tri.mean(0)
        L = (np.linalg.norm(tri[0]-tri[1]) + np.linalg.norm(tri[1]-tri[2]) + np.linalg.norm(tri[2]-tri[0])) / 3
        d = Part.Vertex(FreeCAD.Vector(*c)).distToShape(faces[int(E[t]) - 1])[0]
        ratios[k] = d / L
    out = {'triangles': int(len(T)), 'checked': int(len(idx)), 'ratio_max': float(ratios.max()),
           'ratio_p99': float(np.percentile(ratios, 99)), 'ratio_mean': float(ratios.mean()),
           'limit': a.ratio, 'over_limit': int((ratios > a.ratio).sum())}
    print(json.dumps(out, indent=1))
    sys.exit(0 if out['over_limit'] == 0 else 1)


if __name__ == '__main__':
    main()
