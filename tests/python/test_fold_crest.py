# SPDX-License-Identifier: LGPL-2.1-or-later
"""--curvature-angle 10 lines propeller_and_shaft's blade-tip folds with edges.

The blades' trailing edges near the tips are folds of their B-spline faces, about 0.004 mm in
radius, far below the default min-size (0.038 mm). A triangle whose edge runs across such a fold
has its centroid inside the wedge, up to 0.44 of its edge length off the face (issue 2 bounds it
at 0.03), and splitting that edge at the chord's projected midpoint lands on a flank, never on
the fold. The deviation refinement now splits such an edge where the surface runs farthest from
its chord (the fold's crest) and flips edges that run across a fold into ones along it.

Where the fold closes into the cusp at the tip its flanks face opposite ways (vertex normals 120
to 170 degrees apart), and the crest splits were refused: a new triangle faced away from a crest
vertex's normal. A vertex split onto such a crest now keeps no normal and is never moved (the
triangles on each flank are judged by their flank vertices), and no split leaves a triangle
upside down on a flank.

Measured like tests/tools/fidelity_check.py on every triangle of blade Face7 within 0.3 mm of the
point where stop 20's worst triangle lay: 119 of 498 triangles were beyond the bound (max 0.44);
18 of 310 (max 0.27) with the crest splits (stop 21); 0 of 307 (max 0.0286) at stop 27, 0 of 302
(max 0.0286) at stop 28."""
import os

import numpy as np
import pytest

import freecad.paramesh as pm
import bl_check as bc  # tests/tools, put on sys.path by tests/conftest.py

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

PS = os.path.join(ROOT, "tests", "data", "propeller_and_shaft.iges")
Part = bc.import_part()
needs_freecad = pytest.mark.skipif(Part is None, reason="needs FreeCAD (Part)")
FOLD = np.array([-8.2035, -12.3952, -124.362])  # on the trailing-edge fold of blade Face7 (mm)


@pytest.fixture(scope="module")
def ps_mesh():
    """propeller_and_shaft meshed once for this module with --curvature-angle 10 (about 20 s),
    and fidelity_check set up on its shape (limit 0.03)."""
    import fidelity_check as fc
    fc._limit = 0.03
    fc._shape = bc.read_shape(PS)
    return fc, pm.mesh_file(PS, curvature_angle=10.0)


@needs_freecad
def test_blade_tip_fold_is_lined_with_edges(ps_mesh):
    fc, r = ps_mesh
    P, T, F = r.nodes, r.triangles, r.face_of_element
    near = np.nonzero((np.linalg.norm(P[T].mean(1) - FOLD, axis=1) < 0.3) & (F == 7))[0]
    assert len(near) > 150, len(near)  # measured 302 (stop 21: 310)
    res = np.array(fc._work((P[T[near]], F[near])))
    beyond = res[:, 1]  # distance over mean edge length, beyond the nodes' own offset
    assert (beyond > 0.03).sum() == 0, (beyond > 0.03).sum()  # measured 0 / 302; 0 / 307; 18 / 310; 119 / 498
    assert beyond.max() <= 0.03, beyond.max()  # measured 0.0286 (stop 28, 27); 0.27 (stop 21); 0.44 (stop 20)
    # and none of them faces against the face (meshcheck's test: the CAD normal where the
    # centroid projects)
    cad = bc.CadModel(fc._shape)
    against = 0
    for t in near:
        x = P[T[t]]
        if np.dot(np.cross(x[1] - x[0], x[2] - x[0]), cad.face_normal(7, x.mean(0))) < 0:
            against += 1
    assert against == 0, against


@needs_freecad
def test_triangles_left_beyond_the_bound_are_where_min_size_cannot_follow(ps_mesh):
    """What the bound still misses lies where the CAD's radius of curvature is below what the
    min-size can follow at 10 degrees (min-size / angle: 0.218 mm): the run report says so per
    face, and fidelity_check's own curvature measurement agrees around each face's worst triangle.
    Toward the tip edges the radius falls to 1e-5 mm (docs/benchmark.md, stop 28)."""
    import math
    fc, r = ps_mesh
    rep = r.report
    reach = rep["parameters"]["min_size"] / math.radians(10.0)
    assert reach == pytest.approx(0.2183, rel=1e-3)
    over = {f["face"]: f["over_deviation_bound"] for f in rep["faces"] if "over_deviation_bound" in f}
    # measured: 18 triangles on the five blade faces (7, 10, 12, 14, 16), radius
    # 0.0009-0.0042 mm (stop 28: 60; stop 29: 34, splitting edges below the min-size floor at a
    # crease's crest and collapsing vertices left beside it; stop 30 embeds each blade's
    # trailing-edge crest, 127-128 segments a blade)
    assert set(over) <= {7, 10, 12, 14, 16}, sorted(over)
    total = sum(o["triangles"] for o in over.values())
    assert total <= 25, total
    crest = {f["face"]: f.get("crest_segments", 0) for f in rep["faces"]}
    assert all(crest[f] >= 100 for f in (7, 10, 12, 14, 16)), crest
    assert sum(crest.values()) == sum(crest[f] for f in (7, 10, 12, 14, 16)), crest
    assert all(o["radius_above_min_size_reach"] == 0 and o["surface_radius_min"] < reach for o in over.values())
    w = [s for s in rep["warnings"] if "beyond the deviation bound" in s]
    assert len(w) == (1 if over else 0)
    P, T, F = r.nodes, r.triangles, r.face_of_element
    C = P[T].mean(1)
    checked = beyond_total = 0
    for face, o in over.items():
        near = np.nonzero((np.linalg.norm(C - np.array(o["worst_at"]), axis=1) < 0.3) & (F == face))[0]
        res = np.array(fc._work((P[T[near]], F[near])))
        beyond = res[:, 1] > 0.03
        checked += len(near)
        beyond_total += int(beyond.sum())
        assert beyond.sum() <= o["triangles"] + 2, (face, int(beyond.sum()), o["triangles"])
        # the independent radius (OpenCASCADE's principal curvatures under each triangle)
        assert (res[beyond, 5] < reach).all(), (face, res[beyond, 5].max())
    # measured at stop 29: 1 212 triangles within 0.3 mm of the faces' worst, 24 of them beyond
    # the bound (stop 28: 1 168, 32)
    assert checked > 300 and beyond_total > 0, (checked, beyond_total)
