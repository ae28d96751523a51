#!/usr/bin/python3
"""Every triangle's normal against its own CAD face's normal (independent of ParaMesh).

usage: normal_check.py CAD MESH.msh [--cos 0.2]
For each triangle of the MSH file (entity tag = FreeCAD face number): the face's normalAt at the
surface parameters of the triangle's centroid (Surface.parameter), and the cosine with the
triangle's normal. Lists the triangles below --cos (flipped: negative) with their edge lengths,
centroid and (u,v). Unlike meshcheck.py it checks every triangle, and always against its own face.
Run with Debian's /usr/bin/python3.
"""
import argparse
import sys

sys.path.append('/usr/lib/freecad-python3/lib')
import numpy as np  # noqa: E402
import meshio  # noqa: E402
import FreeCAD  # noqa: E402  (FreeCAD before Part)
import Part  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('cad'); ap.add_argument('mesh'); ap.add_argument('--cos', type=float, default=0.2)
    a = ap.parse_args()
    if a.cad.lower().endswith(('.brep', '.brp')):
        S = Part.Shape(); S.read(a.cad)
    else:
        S = Part.read(a.cad)
    m = meshio.read(a.mesh)
    T, E = [], []
    for cb, cd in zip(m.cells, m.cell_data['gmsh:geometrical']):
        if cb.type == 'triangle':
            T.append(cb.data); E.append(cd)
    T = np.concatenate(T); E = np.concatenate(E); P = m.points
    F = S.Faces
    n = 0
    for k, (t, e) in enumerate(zip(T, E)):
        tri = P[t]; c = tri.mean(0); f = F[int(e) - 1]
        u, v = f.Surface.parameter(FreeCAD.Vector(*c)); nf = f.normalAt(u, v)
        nt = np.cross(tri[1] - tri[0], tri[2] - tri[0])
        cs = float(np.dot(nt, [nf.x, nf.y, nf.z]) / max(np.linalg.norm(nt), 1e-300))
        if cs < a.cos:
            n += 1
            L = [np.linalg.norm(tri[i] - tri[(i + 1) % 3]) for i in range(3)]
            print(k, 'Face%d' % e, 'cos %.3f' % cs, 'edges', np.round(L, 2), 'centroid', np.round(c, 2),
                  'uv %.3f %.3f' % (u, v))
    print('below cos %g: %d of %d triangles' % (a.cos, n, len(T)))


if __name__ == '__main__':
    main()
