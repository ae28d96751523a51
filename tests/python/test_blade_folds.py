# SPDX-License-Identifier: LGPL-2.1-or-later
"""Refinement on strongly uneven parametrisations. propeller_and_shaft.iges models the blades'
trailing edges as folds of the B-spline faces (radius about 0.005 mm) over which the (u,v)
parametrisation is very uneven. With --curvature-angle, the deviation refinement split edges
there whose (u,v) midpoint landed, in 3D, on a vertex already present (or, after a swap had
rebuilt an edge over an earlier split vertex, at that vertex's very (u,v)): the meshes held
stacks of up to 8 coincident nodes and triangles with a zero-length edge (27 duplicate nodes at
curvature angle 30, 34 at 10, judged like meshcheck.py). Every insertion now has to keep its new
triangles valid in (u,v) and stay clear of the corners it splits in 3D."""
import os

import numpy as np

import freecad.paramesh as pm

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PS = os.path.join(ROOT, "tests", "data", "propeller_and_shaft.iges")


def test_no_coincident_nodes_on_blade_folds():
    r = pm.mesh_file(PS, curvature_angle=30.0)
    P, T = r.nodes, r.triangles
    assert len(T) > 100000
    used = np.unique(T)
    diag = float(np.linalg.norm(P[used].max(0) - P[used].min(0)))
    # meshcheck.py's duplicate test: nodes coincident within 1e-9 of the bounding-box diagonal
    key = np.round(P[used] / (diag * 1e-9)).astype(np.int64)
    assert len(key) == len(np.unique(key, axis=0))
    # no triangle with an edge all but zero next to its others (before: 54 below 1e-3 of the
    # longest, down to 0; now the least is about 0.009)
    L = np.stack([np.linalg.norm(P[T[:, i]] - P[T[:, (i + 1) % 3]], axis=1) for i in range(3)], axis=1)
    assert (L.min(axis=1) / L.max(axis=1)).min() > 1e-3
