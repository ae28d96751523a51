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
(max 0.0286) at stop 28.

Stop 30 embeds each blade's trailing-edge crest as mesh edges; stop 31 adds rows parallel to it
where its flanks keep turning (test_fold_shoulders_are_lined_with_rows)."""
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


# where stop 30 left its worst triangles (18 in the run report, all on a flank beside a blade's
# embedded crest, up to 0.058 of their edge off the face): Face10, Face12, Face14
STOP30_WORST = {10: (-8.5419, -122.3031, -25.7503), 12: (-8.2600, -62.9508, 107.9635), 14: (-8.6826, 84.0860, 92.4786)}


@needs_freecad
def test_fold_shoulders_are_lined_with_rows(ps_mesh):
    """Beside each blade's embedded crest the flanks still turn 55 degrees within 0.02 mm (the
    size there is 0.038 mm), so a triangle with an edge on the crest and its apex on the flank
    cut the fold's shoulder. Rows of points parallel to the crest (algo/Crest, embedCrestRows),
    at distances where the flank would sag from their chord, now line the shoulders: the run
    report has no triangle beyond the bound left, and fidelity_check (independent of ParaMesh)
    finds none around stop 30's worst ones."""
    import math
    fc, r = ps_mesh
    rep = r.report
    reach = rep["parameters"]["min_size"] / math.radians(10.0)
    assert reach == pytest.approx(0.2183, rel=1e-3)
    over = {f["face"]: f["over_deviation_bound"] for f in rep["faces"] if "over_deviation_bound" in f}
    # measured: none (stop 30: 18 on the five blade faces, stop 29: 34, stop 28: 60)
    assert sum(o["triangles"] for o in over.values()) == 0, over
    assert not [s for s in rep["warnings"] if "beyond the deviation bound" in s]
    blades = (7, 10, 12, 14, 16)
    crest = {f["face"]: f.get("crest_segments", 0) for f in rep["faces"]}
    rows = {f["face"]: f.get("crest_row_segments", 0) for f in rep["faces"]}
    # measured: 127-128 crest segments and 821-837 row segments a blade, nowhere else
    assert all(crest[f] >= 100 for f in blades), crest
    assert all(rows[f] >= 4 * crest[f] for f in blades), rows
    assert sum(crest.values()) == sum(crest[f] for f in blades), crest
    assert sum(rows.values()) == sum(rows[f] for f in blades), rows
    P, T, F = r.nodes, r.triangles, r.face_of_element
    C = P[T].mean(1)
    checked = 0
    for face, at in STOP30_WORST.items():
        near = np.nonzero((np.linalg.norm(C - np.array(at), axis=1) < 0.25) & (F == face))[0]
        res = np.array(fc._work((P[T[near]], F[near])))
        beyond = res[:, 1]
        checked += len(near)
        # measured: 0 beyond, max 0.0297 (stop 30: 9 on Face10, 5 on Face12, 2 on Face14, up to 0.058)
        assert (beyond > 0.03).sum() == 0, (face, int((beyond > 0.03).sum()), beyond.max())
    assert checked > 300, checked
