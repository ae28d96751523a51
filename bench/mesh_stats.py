#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Quality of a mesh file without the CAD: the size-free part of meshcheck.py, in a second.

usage: mesh_stats.py MESH H
Prints JSON: triangles, triangles with an angle below 30 degrees (count and %), gamma mean (radius
ratio 2 r_in / r_circ), % of unique edges (triangles and quads) within [H/sqrt2, sqrt2 H]. Same
formulas as ../shared/tools/meshcheck.py (which also checks against the CAD and is authoritative);
handy for sweeping many cases while developing. Run with Debian's /usr/bin/python3.
"""
import json
import math
import sys

import meshio
import numpy as np


def radius_ratios(P, T):
    """meshcheck's radius ratio 2 r_in / r_circ per triangle, and the side lengths a, b, c (a
    opposite corner 0)."""
    a = np.linalg.norm(P[T[:, 1]] - P[T[:, 2]], axis=1)
    b = np.linalg.norm(P[T[:, 2]] - P[T[:, 0]], axis=1)
    c = np.linalg.norm(P[T[:, 0]] - P[T[:, 1]], axis=1)
    area = 0.5 * np.linalg.norm(np.cross(P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]]), axis=1)
    with np.errstate(all='ignore'):
        s = 0.5 * (a + b + c)
        g = np.where(area > 0, 2 * (area / s) / (a * b * c / (4 * area)), 0.0)
    return g, a, b, c


def main():
    m = meshio.read(sys.argv[1])
    h = float(sys.argv[2])
    P = m.points
    T = np.concatenate([c.data for c in m.cells if c.type == 'triangle'])
    quads = [c.data for c in m.cells if c.type == 'quad']
    Q = np.concatenate(quads) if quads else np.zeros((0, 4), int)
    g, a, b, c = radius_ratios(P, T)
    with np.errstate(all='ignore'):
        cA = np.clip((b * b + c * c - a * a) / (2 * b * c), -1, 1)
        cB = np.clip((a * a + c * c - b * b) / (2 * a * c), -1, 1)
    A = np.degrees(np.arccos(cA)); B = np.degrees(np.arccos(cB)); C = 180 - A - B
    amin = np.minimum(np.minimum(A, B), C)
    E = [T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]
    if len(Q):
        E += [Q[:, [0, 1]], Q[:, [1, 2]], Q[:, [2, 3]], Q[:, [3, 0]]]
    E = np.unique(np.sort(np.concatenate(E), axis=1), axis=0)
    L = np.linalg.norm(P[E[:, 0]] - P[E[:, 1]], axis=1) / h
    print(json.dumps({'tris': int(len(T)), 'poor': int((amin < 30).sum()), 'pct30': float(100 * (amin < 30).mean()),
                      'gamma': float(g.mean()),
                      'len': float(100 * ((L >= 1 / math.sqrt(2)) & (L <= math.sqrt(2))).mean())}))


if __name__ == '__main__':
    main()
