#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Where OpenCASCADE's face classifier calls points of a face outside it (no mesh involved).

usage: classifier_probe.py bottle    ../shared/models/bottle.brep
       classifier_probe.py bearing   ../shared/models/bearing.iges

meshcheck.py measures a triangle against its own face with `distToShape`, which keeps the foot
on the surface only when OpenCASCADE's classifier puts it inside the face; otherwise the distance
is to the face's edges, and meshcheck then judges the triangle (and its nodes) by the nearest
other face. Two node-deviation rows of the benchmark (docs/benchmark.md) come from that. This
probe asks the same classifier (FreeCAD's `Face.isInside(point, 1e-7, True)`) about points of the
surface that lie inside the face's (u,v) domain by construction:

- bottle Face6, a helical strip winding twice round its cylinder (u from 0.12 to 12.45): points
  on the midline between its two p-curves and at 25 % and 75 % across, at 49 values along it;
- bearing Face32, whose domain is the square [0,1]^2 bounded by four straight p-curves: points
  along u = 0.496 for v from 0 to 0.4.

Prints JSON. Run with Debian's /usr/bin/python3."""
import json
import math
import sys

import numpy as np

from cad_read import read_cad
import Part  # noqa: E402  (FreeCAD imported first by cad_read)


def bottle(path):
    face = read_cad(path).Faces[5]
    surf = face.Surface
    ellipse, line = (face.curveOnSurface(e) for e in face.Edges)
    p0, p1 = line[0].value(line[1]), line[0].value(line[2])

    def v_line(u):
        return p0.y + (u - p0.x) * (p1.y - p0.y) / (p1.x - p0.x)

    rows = []
    for t in np.linspace(0.02, 0.98, 49):
        q = ellipse[0].value(ellipse[1] + (ellipse[2] - ellipse[1]) * t)
        for f in (0.25, 0.5, 0.75):
            v = v_line(q.x) + f * (q.y - v_line(q.x))
            x = surf.value(q.x, v)
            rows.append({'u': q.x, 'v': v, 'across': f, 'inside': bool(face.isInside(x, 1e-7, True)),
                         'dist_to_shape': face.distToShape(Part.Vertex(x))[0]})
    first = [r for r in rows if r['u'] < 2 * math.pi]
    second = [r for r in rows if r['u'] >= 2 * math.pi]
    return {'face': 6, 'u_range': list(face.ParameterRange[:2]), 'points': len(rows),
            'outside': sum(not r['inside'] for r in rows),
            'first_turn_outside': f"{sum(not r['inside'] for r in first)} of {len(first)}",
            'second_turn_outside': f"{sum(not r['inside'] for r in second)} of {len(second)}",
            'dist_to_shape_max_outside': max((r['dist_to_shape'] for r in rows if not r['inside']), default=0)}


def bearing(path):
    face = read_cad(path).Faces[31]
    surf = face.Surface
    rows = []
    for v in np.linspace(0.0, 0.4, 21):
        x = surf.value(0.496, v)
        rows.append({'v': round(float(v), 3), 'inside': bool(face.isInside(x, 1e-7, True)),
                     'dist_to_shape': face.distToShape(Part.Vertex(x))[0]})
    pcurves = []
    for e in face.Edges:
        c = face.curveOnSurface(e)
        a, b = c[0].value(c[1]), c[0].value(c[2])
        pcurves.append({'type': type(c[0]).__name__, 'from': [a.x, a.y], 'to': [b.x, b.y], 'tolerance': e.Tolerance})
    return {'face': 32, 'pcurves': pcurves, 'along_u_0.496': rows}


if __name__ == '__main__':
    which, path = sys.argv[1], sys.argv[2]
    print(json.dumps({'bottle': bottle, 'bearing': bearing}[which](path), indent=1))
