#!/usr/bin/python3
"""Is OpenCASCADE's distance to a face right at a point? (independent of ParaMesh)

usage: dist_probe.py CAD FACE X Y Z [--step S]
Prints Part's distToShape from (X, Y, Z) to FACE and from the 26 points of the cube of half-side S
around it. A distance function is 1-Lipschitz: |d(p) - d(q)| <= |p - q| for any p, q. A pair that
breaks this shows a wrong distance (a misclassified projection foot), not a mesh problem: on
bearing.iges Face143 (a flat B-spline face) the interior node (0.00047373, -0.05546657, 0.005) of
the d/200 mesh gets 4.7e-4 while every point 5e-5 around it gets 0, and meshcheck.py then reports
a node deviation of 0.58 h. Run with Debian's /usr/bin/python3.
"""
import argparse
import itertools
import math
import sys

sys.path.append('/usr/lib/freecad-python3/lib')
import FreeCAD  # noqa: E402,F401  (FreeCAD before Part)
import Part  # noqa: E402
from cad_read import read_cad  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('cad'); ap.add_argument('face', type=int)
    ap.add_argument('x', type=float); ap.add_argument('y', type=float); ap.add_argument('z', type=float)
    ap.add_argument('--step', type=float, default=5e-5)
    a = ap.parse_args()
    s = read_cad(a.cad)
    f = s.Faces[a.face - 1]
    p = FreeCAD.Vector(a.x, a.y, a.z)
    d0 = Part.Vertex(p).distToShape(f)[0]
    print('Face%d %s: distance at the point %.3g' % (a.face, type(f.Surface).__name__, d0))
    broken = 0
    for dx, dy, dz in itertools.product((-1, 0, 1), repeat=3):
        if dx == dy == dz == 0:
            continue
        q = FreeCAD.Vector(a.x + dx * a.step, a.y + dy * a.step, a.z + dz * a.step)
        d = Part.Vertex(q).distToShape(f)[0]
        gap = math.sqrt(dx * dx + dy * dy + dz * dz) * a.step
        bad = abs(d - d0) > gap * (1 + 1e-9)
        broken += bad
        print('  %+d %+d %+d  %.3g%s' % (dx, dy, dz, d, '   <- |d(p) - d(q)| > |p - q|' if bad else ''))
    print('pairs breaking the 1-Lipschitz bound: %d of 26' % broken)


if __name__ == '__main__':
    main()
