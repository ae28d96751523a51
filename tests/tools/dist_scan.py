#!/usr/bin/python3
"""Where does OpenCASCADE's distance to a face go wrong? (independent of ParaMesh)

usage: dist_scan.py CAD FACE U0 U1 V0 V1 [--n 40] [--size H]
Evaluates the face's surface on an (n+1) x (n+1) grid of (u,v) over [U0,U1] x [V0,V1], and prints
Part's distToShape from each of those points (which lie on the surface) to the face, in tenths
of H: '.' where it is below 1e-6 H, else the digit (9: 0.9 H or more). A point on the surface
inside the trimmed face is at distance 0; a digit inside the face is distToShape's error (its
foot classified outside the face, so the distance is measured to the face's edges). On
bearing.iges Face32 (a flat B-spline, (u,v) in [0,1]^2) the points of a band about 0.03 x 0.07
around (0.5, 0.19) get 0.4 to 0.6 H (H = 0.000807, the d/200 size), and meshcheck.py reported a
node there 0.62 H off the CAD:
  dist_scan.py ../shared/models/bearing.iges 32 0.3 0.7 0.0 0.4 --size 0.0008071234288420079
Run with Debian's /usr/bin/python3.
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
    for k in ('u0', 'u1', 'v0', 'v1'):
        ap.add_argument(k, type=float)
    ap.add_argument('--n', type=int, default=40)
    ap.add_argument('--size', type=float, default=1.0)
    a = ap.parse_args()
    f = read_cad(a.cad).Faces[a.face - 1]
    S = f.Surface
    wrong = 0
    for j in range(a.n, -1, -1):
        v = a.v0 + (a.v1 - a.v0) * j / a.n
        row = ''
        for i in range(a.n + 1):
            u = a.u0 + (a.u1 - a.u0) * i / a.n
            d = Part.Vertex(S.value(u, v)).distToShape(f)[0]
            inside = f.isPartOfDomain(u, v)
            ch = '.' if d < 1e-6 * a.size else str(min(9, int(10 * d / a.size)))
            wrong += inside and ch not in '.0'
            row += ch if inside else ' '
        print('%9.4f %s' % (v, row))
    print('points inside the face (Face.isPartOfDomain) at 0.1 H or more: %d of %d'
          % (wrong, (a.n + 1) ** 2))


if __name__ == '__main__':
    main()
