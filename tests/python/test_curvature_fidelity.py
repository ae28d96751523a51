# SPDX-License-Identifier: LGPL-2.1-or-later
"""--curvature-angle 10 resolves the ONERA M6's tip trailing edge (issue 2's fidelity bound).

Each triangle's centroid must lie within 0.03 of its mean edge length from its own CAD face,
beyond the offset its own nodes carry (nodes on the STEP file's tip edges, which lie up to
0.0058 mm off their faces, put centroids off by that much whatever the triangles do). Measured
like tests/tools/fidelity_check.py, here on every triangle of the tip's trailing-edge corner,
where the bound was missed: two triangles at 0.0300 and 0.0304 until 012f0e4. The face mesher
added to their bound the offset of a node from the surface point at its (u,v) (2.3e-4), where
the node itself lies 9e-6 from the surface."""
import os

import numpy as np
import pytest

import freecad.paramesh as pm
import bl_check as bc  # tests/tools, put on sys.path by tests/conftest.py

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

M6 = os.path.join(ROOT, "tests", "data", "AileM6_with_sharp_TE.stp")
Part = bc.import_part()
needs_freecad = pytest.mark.skipif(Part is None, reason="needs FreeCAD (Part)")
TIP_TE = np.array([1146.3, 1196.3, 0.0])  # the tip's trailing-edge corner (mm)


@needs_freecad
def test_m6_tip_trailing_edge_within_the_fidelity_bound():
    import FreeCAD
    shape = bc.read_shape(M6)
    faces = shape.Faces
    r = pm.mesh_file(M6, curvature_angle=10.0)
    P, T, F = r.nodes, r.triangles, r.face_of_element
    C = P[T].mean(1)
    near = np.nonzero(np.linalg.norm(C - TIP_TE, axis=1) < 1.0)[0]
    assert len(near) > 200, len(near)  # measured 1 434 triangles within 1 mm
    checked, worst = 0, 0.0
    for k in near:
        f = faces[int(F[k]) - 1]
        if f.Surface.__class__.__name__ == "Plane":
            continue
        tri = P[T[k]]
        L = np.mean([np.linalg.norm(tri[i] - tri[(i + 1) % 3]) for i in range(3)])
        d = Part.Vertex(FreeCAD.Vector(*tri.mean(0))).distToShape(f)[0]
        S = f.Surface
        gap = 0.0
        for p in tri:
            v = FreeCAD.Vector(*p)
            u, w = S.parameter(v)
            gap += (S.value(u, w) - v).Length / 3
        worst = max(worst, max(d - gap, 0.0) / L)
        checked += 1
    assert checked > 200, checked  # 893 of them on curved faces
    assert worst <= 0.03, worst  # measured 0.0289 (the build before 012f0e4: 0.0304)
