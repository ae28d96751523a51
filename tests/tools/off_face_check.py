#!/usr/bin/python3
"""Triangles whose centroid is off their own CAD face, and which face is nearer (independent of ParaMesh).

usage: off_face_check.py CAD MESH.msh --size H [--limit 0.05]
For every triangle (MSH entity tag = FreeCAD face number): Part's distToShape from its centroid to
its own face, over H. For those over --limit (meshcheck.py's 0.05 h), the nearest CAD face: when
it is another face, meshcheck judges the triangle (flip and node deviation) against that face.
Checks every triangle, not a sample. Run with Debian's /usr/bin/python3.
"""
import argparse
import json
import sys

sys.path.append('/usr/lib/freecad-python3/lib')
import numpy as np  # noqa: E402
import meshio  # noqa: E402
import FreeCAD  # noqa: E402  (FreeCAD before Part)
import Part  # noqa: E402
from cad_read import read_cad  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('cad'); ap.add_argument('mesh')
    ap.add_argument('--size', type=float, required=True)
    ap.add_argument('--limit', type=float, default=0.05)
    a = ap.parse_args()
    s = read_cad(a.cad)
    faces = s.Faces
    m = meshio.read(a.mesh)
    P = m.points
    T, E = [], []
    for i, cb in enumerate(m.cells):
        if cb.type == 'triangle':
            T.append(cb.data); E.append(m.cell_data['gmsh:geometrical'][i])
    T = np.concatenate(T); E = np.concatenate(E)
    off, nearer = [], []
    for k, (c, e) in enumerate(zip(P[T].mean(1), E)):
        v = Part.Vertex(FreeCAD.Vector(*c))
        d = v.distToShape(faces[e - 1])[0] / a.size
        if d <= a.limit:
            continue
        off.append(k)
        dist = [v.distToShape(f)[0] / a.size for f in faces]
        best = int(np.argmin(dist))
        if best != e - 1:
            nearer.append({'triangle': k, 'face': int(e), 'own': d, 'nearer_face': best + 1, 'other': dist[best],
                           'centroid': [float(x) for x in c]})
    print(json.dumps({'triangles': int(len(T)), 'over_limit': len(off), 'nearer_another_face': len(nearer),
                      'those': nearer[:50]}, indent=1))


if __name__ == '__main__':
    main()
