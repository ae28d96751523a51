# SPDX-License-Identifier: LGPL-2.1-or-later
"""--max-deviation (an absolute bound on each triangle centroid's distance from the surface),
measured against analytic spheres, independently of ParaMesh.

boxed_sphere.step's eight box corners are sphere octants (radius 0.29) whose pcurves stray from
their 3D circles by up to 0.055 (the edges' tolerance says so): the face's trim in (u,v) lay a
strip inside the nodes of its own edges, no interior node could go there, and the triangles along
the edges stayed up to 4.5 times beyond the bound (the whole model at --max-deviation 0.001: 519
triangles on the 8 corners). The trim now follows the 3D edges projected on the surface where the
pcurves stray from them.

The max-deviation splits used to come after the optimiser's repairs, with one smoothing and one
swap pass behind them: a unit sphere at --max-deviation 0.001 had mean gamma 0.836. They now come
before the repairs, which keep the bound."""
import os

import numpy as np
import pytest

import freecad.paramesh as pm
import bl_check as bc  # tests/tools, put on sys.path by tests/conftest.py

Part = bc.import_part()
needs_freecad = pytest.mark.skipif(Part is None, reason="needs FreeCAD (Part)")
DATA = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "data")

BOXED_SIZE = 0.3492684213844517  # boxed_sphere.step's default size (diagonal / 50)


def _gamma(X):
    a = np.linalg.norm(X[:, 1] - X[:, 2], axis=1)
    b = np.linalg.norm(X[:, 2] - X[:, 0], axis=1)
    c = np.linalg.norm(X[:, 0] - X[:, 1], axis=1)
    s = (a + b + c) / 2
    area = np.sqrt(np.maximum(s * (s - a) * (s - b) * (s - c), 0))
    return 2 * (area / s) / (a * b * c / (4 * area))


def _sphere_dev(res, centre, radius):
    """Each triangle centroid's distance from the sphere, and each node's."""
    C = res.nodes[res.triangles].mean(1)
    return (np.abs(np.linalg.norm(C - centre, axis=1) - radius),
            np.abs(np.linalg.norm(res.nodes - centre, axis=1) - radius))


CORNERS = (4, 16, 36, 48, 84, 96, 116, 128)  # the eight corner octants (radius 0.29)


@needs_freecad
@pytest.mark.parametrize("face_no", CORNERS)
def test_corner_octant_with_stray_pcurves_meets_the_bound(face_no):
    import FreeCAD  # noqa: F401  (before Part's shapes)
    shape = Part.Shape()
    shape.read(os.path.join(DATA, "boxed_sphere.step"))
    face = shape.Faces[face_no - 1]
    centre, radius = np.array(face.Edges[0].Curve.Center), 0.29
    assert all(abs(e.Curve.Radius - radius) < 1e-9 for e in face.Edges)
    # the CAD defect the test is about: some pcurve maps 0.05 off its circle
    def stray(e):
        c2d, a, b = face.curveOnSurface(e)[:3]
        p = c2d.value(0.5 * (a + b))
        return e.distToShape(Part.Vertex(face.Surface.value(p.x, p.y)))[0]
    assert max(stray(e) for e in face.Edges) > 0.04
    res = pm.mesh_shape(face, size=BOXED_SIZE, max_deviation=0.001)
    assert res.report["status"] == "ok" and not res.failed_faces
    bound = 0.001 * BOXED_SIZE
    dc, dn = _sphere_dev(res, centre, radius)
    assert dn.max() < 1e-9, dn.max()                       # nodes on the sphere
    # measured 0.93-0.9999 of the bound; before: 1.8-4.5 times it on every corner
    assert dc.max() <= 1.0001 * bound, (dc.max() / bound)
    # the mesh covers the whole octant: nodes reach the three circles' middles
    for e in face.Edges:
        mid = np.array(e.valueAt(0.5 * sum(e.ParameterRange)))
        assert np.linalg.norm(res.nodes - mid, axis=1).min() < 0.02, mid
    g = _gamma(res.nodes[res.triangles])
    assert g.mean() >= 0.9, g.mean()                       # measured 0.92-0.93; before 0.83-0.85
    assert g.min() >= 0.09, g.min()                        # measured 0.104-0.18


@needs_freecad
def test_sphere_at_max_deviation_keeps_its_shape():
    import FreeCAD  # noqa: F401
    res = pm.mesh_shape(Part.makeSphere(1.0), size=1.0, max_deviation=0.001)
    assert res.report["status"] == "ok" and not res.failed_faces
    dc, dn = _sphere_dev(res, np.zeros(3), 1.0)
    assert dn.max() < 1e-9
    assert dc.max() <= 0.001, dc.max()
    g = _gamma(res.nodes[res.triangles])
    assert g.mean() >= 0.92, g.mean()                      # measured 0.937; before 0.836
    assert np.percentile(g, 1) >= 0.6, np.percentile(g, 1)
