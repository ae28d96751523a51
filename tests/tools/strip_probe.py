#!/usr/bin/python3
"""Probe OpenCASCADE's point classification across a face (independent of ParaMesh).

usage: strip_probe.py CAD FACE X Y Z [--span 0.07] [--steps 15]
Walks along the z direction through (X, Y, Z) projected radially onto FACE's surface, and prints
for each point: whether Part.Face.isInside says it is in the face, its distToShape to the face and
to each of the face's edges. On bottle.brep Face6 (a two-turn helical strip of a cylinder, u range
12.3 rad) every point between its two boundary edges is classified outside, and its distance to the
face equals its distance to the nearer edge: meshcheck.py then finds triangle centroids of that strip
"off" the face by up to half its width. Run with Debian's /usr/bin/python3.
"""
import argparse
import sys

sys.path.append('/usr/lib/freecad-python3/lib')
import FreeCAD  # noqa: E402,F401  (FreeCAD before Part)
import Part  # noqa: E402
from cad_read import read_cad  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('cad'); ap.add_argument('face', type=int)
    ap.add_argument('x', type=float); ap.add_argument('y', type=float); ap.add_argument('z', type=float)
    ap.add_argument('--span', type=float, default=0.07); ap.add_argument('--steps', type=int, default=15)
    a = ap.parse_args()
    s = read_cad(a.cad)
    f = s.Faces[a.face - 1]
    S = f.Surface
    print('Face%d: %s, parameter range %s' % (a.face, type(S).__name__, tuple(round(x, 4) for x in f.ParameterRange)))
    for k in range(a.steps):
        z = a.z - a.span + 2 * a.span * k / (a.steps - 1)
        u, v = S.parameter(FreeCAD.Vector(a.x, a.y, z))
        p = S.value(u, v)
        d = Part.Vertex(p).distToShape(f)[0]
        de = [round(Part.Vertex(p).distToShape(e)[0], 4) for e in f.Edges]
        print('z %.4f  inside %-5s  dist to face %.4f  to edges %s' % (p.z, f.isInside(p, 1e-6, True), d, de))


if __name__ == '__main__':
    main()
