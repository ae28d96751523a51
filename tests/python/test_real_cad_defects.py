# SPDX-License-Identifier: LGPL-2.1-or-later
"""Regressions of defects found on real CAD (issue 35), each on a shape built here that reproduces it.

- A face of revolution closing at a pole on its boundary (a half body of revolution cut by its
  symmetry plane, the nose on the axis): a triangle of the curved face joined three boundary nodes
  across the pole and lay in the cut plane, on a triangle of the flat face; the solid then had
  edges used by four triangles (../shared/tools/make_half_ellipsoid.py at --size 9: 4 such edges).
- sheet_metal_54 Face3 at the parameter sweep's case: boundary recovery picked a wrong apex among
  nearly collinear p-curve points (a straight p-curve a few 1e-10 off a parameter line) and the face
  failed as open."""
import math
import os

import numpy as np
import pytest

import freecad.paramesh as pm
import bl_check as bc  # tests/tools, put on sys.path by tests/conftest.py

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHEET = os.path.join(ROOT, "tests", "data", "sheet_metal_54.brep")
Part = bc.import_part()
needs_freecad = pytest.mark.skipif(Part is None, reason="needs FreeCAD (Part)")


def half_ellipsoid(a=250.0, b=10.0):
    """The upper half of an ellipse (semi-axes a along x, b) revolved by half a turn about x: a face
    of revolution with a pole at each end of its boundary, closed by the plane y = 0."""
    import FreeCAD
    V = FreeCAD.Vector
    pts = [V(-a * math.cos(t), 0, b * math.sin(t)) for t in (math.pi * i / 60 for i in range(61))]
    profile = Part.BSplineCurve()
    profile.interpolate(pts)
    face = Part.SurfaceOfRevolution(profile, V(0, 0, 0), V(1, 0, 0)).toShape(
        0, math.pi, profile.FirstParameter, profile.LastParameter)
    cut = Part.Face(Part.Wire(Part.__sortEdges__([e for e in face.Edges if e.Length > 1e-9])))
    shell = Part.Shape(Part.Shell([face, cut]))
    shell.sewShape()
    solid = Part.Solid(Part.Shell(shell.Faces))
    assert solid.isValid()
    return solid


def oriented_edge_uses(t):
    """(undirected uses, directed uses) counts of every edge of triangles t."""
    d = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    _, und = np.unique(np.sort(d, axis=1), axis=0, return_counts=True)
    _, dirc = np.unique(d, axis=0, return_counts=True)
    return und, dirc


def assert_closed_oriented(res):
    t = res.triangles
    und, dirc = oriented_edge_uses(t)
    assert und.min() == 2 and und.max() == 2, (und.min(), und.max(), int((und != 2).sum()))
    assert dirc.max() == 1  # each edge once each way: consistently oriented
    keys = np.unique(np.sort(t, axis=1), axis=0)
    assert len(keys) == len(t)  # no two triangles on the same nodes
    a = res.report["audit"]
    assert a["passed"], a


@needs_freecad
@pytest.mark.parametrize("size", [3.0, 5.0, 9.0, 12.0])
def test_half_body_of_revolution_closes_at_its_poles(size):
    solid = half_ellipsoid()
    res = pm.mesh_shape(solid, size=size)
    assert res.report["status"] == "ok" and not res.failed_faces, res.report["message"]
    assert_closed_oriented(res)
    # no triangle of the curved face lies in the cut plane (y = 0), where the flat face's are
    curved = res.triangles[res.triangle_face == 1]
    y = np.abs(res.nodes[curved][:, :, 1]).max(axis=1)
    assert y.min() > 1e-6, y.min()
    # every node of the curved face on the ellipsoid (x/a)^2 + (r/b)^2 = 1 (the profile is a
    # 61-point interpolation: within 1e-4 of the exact ellipse)
    p = res.nodes[np.unique(curved)]
    r = np.hypot(p[:, 1], p[:, 2])
    assert np.abs((p[:, 0] / 250.0) ** 2 + (r / 10.0) ** 2 - 1).max() < 1e-3
    # and no triangle folded: each faces away from the axis or the nose (outward)
    X = res.nodes[curved]
    n = np.cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0])
    c = X.mean(axis=1)
    out = np.stack([c[:, 0] / 250.0 ** 2, c[:, 1] / 10.0 ** 2, c[:, 2] / 10.0 ** 2], axis=1)
    assert (np.einsum("ij,ij->i", n, out) > 0).all()


def test_sheet_metal_54_face3_at_the_sweep_case_meshes():
    res = pm.mesh_shape(SHEET, size=0.8305892293702677, max_deviation=0.00387, proximity=3)
    bad = [(f["name"], f.get("error")) for f in res.faces if f["status"] != "ok"]
    assert res.report["status"] == "ok" and not bad, (res.report["message"], bad)
    assert_closed_oriented(res)


def test_bottle_thread_run_out_strip_does_not_fold_at_the_default_size():
    """bottle.brep at its default size (diagonal / 50): Face6, a cylinder strip about 0.06 high
    under chords of about 1.3 (their sagitta larger than the strip), had two triangles folded onto
    each other (normals over 160 degrees apart, the audit's 4 fold edges): the nearest-face round's
    deviation refinement put a node inside a triangle lying across the strip. A node that would
    fold the triangles it makes is refused now (splitFolds)."""
    res = pm.mesh_file(os.path.join(ROOT, "tests", "data", "bottle.brep"))
    assert res.report["status"] == "ok", res.report["message"]
    assert res.report["audit"]["passed"] and res.report["audit"]["counts"]["folds"] == 0
    assert_closed_oriented(res)
    # no two triangles of Face6 sharing an edge face more than 160 degrees apart
    t = res.triangles[res.triangle_face == 6]
    p = res.nodes[t]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    n /= np.linalg.norm(n, axis=1)[:, None]
    edges = {}
    for i, tri in enumerate(t):
        for a, b in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])):
            edges.setdefault((min(a, b), max(a, b)), []).append(i)
    worst = min(float(n[u] @ n[v]) for u, v in (e for e in edges.values() if len(e) == 2))
    assert worst > math.cos(math.radians(160)), worst
