# SPDX-License-Identifier: LGPL-2.1-or-later
"""The report names the triangles left beyond the curvature bound, and why.

A torus tube of radius 0.5 meshed with --curvature-angle 10 needs edges of about 0.5 x 10 degrees
(0.087) to keep each centroid within 0.029 of its mean edge length from the surface. With
--min-size 1 the size field may not go below 1, so part of the triangles stay beyond the bound: the
report must count them as an independent measurement does (the analytic distance of each centroid
from the torus), give the surface's smallest radius of curvature under them (the tube's, 0.5), and
say that the min-size holds them back (0.5 is below min-size / angle = 5.73). With --min-size 0.01
the same torus meets the bound everywhere and the report says nothing."""
import math

import numpy as np
import pytest

import freecad.paramesh as pm
import bl_check as bc  # tests/tools, put on sys.path by tests/conftest.py

Part = bc.import_part()
needs_freecad = pytest.mark.skipif(Part is None, reason="needs FreeCAD (Part)")

R, r = 3.0, 0.5
RATIO = math.radians(10.0) / 6.0  # the mesher's bound for 10 degrees: 0.0291 of the mean edge


def _torus():
    import FreeCAD  # noqa: F401  (before Part's shapes)
    return Part.makeTorus(R, r)


def _measure(res):
    """Centroid distance to the torus / the bound, per triangle (analytic, independent of ParaMesh)."""
    P, T = res.nodes, res.triangles
    X = P[T]
    C = X.mean(1)
    d = np.abs(np.hypot(np.hypot(C[:, 0], C[:, 1]) - R, C[:, 2]) - r)
    L = (np.linalg.norm(X[:, 0] - X[:, 1], axis=1) + np.linalg.norm(X[:, 1] - X[:, 2], axis=1)
         + np.linalg.norm(X[:, 2] - X[:, 0], axis=1)) / 3
    return d / (RATIO * L)


def _over(rep):
    return [f["over_deviation_bound"] for f in rep["faces"] if "over_deviation_bound" in f]


@needs_freecad
def test_min_size_that_forbids_the_bound_is_reported():
    res = pm.mesh_shape(_torus(), size=1.0, min_size=1.0, curvature_angle=10.0)
    rep = res.report
    x = _measure(res)
    strict, loose = int((x > 1.001).sum()), int((x > 0.999).sum())
    # measured: 274 of 1 540 beyond (worst 4.26x its bound); the refinement splits edges down to
    # half the min-size, so only part of the tube stays beyond
    assert strict > 100, (strict, len(x))
    over = _over(rep)
    assert len(over) == 1  # one face
    o = over[0]
    assert strict <= o["triangles"] <= loose, (strict, o["triangles"], loose)
    assert o["worst_over_bound"] == pytest.approx(x.max(), rel=0.01)
    assert o["surface_radius_min"] == pytest.approx(r, rel=1e-3)
    assert o["radius_above_min_size_reach"] == 0
    w = [s for s in rep["warnings"] if "beyond the deviation bound" in s]
    assert len(w) == 1 and "min-size" in w[0] and "Face1" in w[0], rep["warnings"]


@needs_freecad
def test_bound_met_everywhere_is_not_reported():
    res = pm.mesh_shape(_torus(), size=1.0, min_size=0.01, curvature_angle=10.0)
    x = _measure(res)
    assert x.max() <= 1.0, x.max()  # measured: 0.65 of the bound at worst (30 044 triangles)
    assert _over(res.report) == []
    assert not [s for s in res.report["warnings"] if "beyond the deviation bound" in s]
