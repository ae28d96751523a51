# SPDX-License-Identifier: LGPL-2.1-or-later
"""Surface boundary layers that meet each other: fans at reflex corners and a merged column at an
outer corner (a plate with a square and a 12-gon hole), layers meeting across a chamfer, in a V
notch, across a strip or a slot, and two runs colliding on CrankArm. Measured with
tests/tools/bl_check.py through bl_helpers.py, as in test_boundary_layer.py."""
import math
import os

import numpy as np
import pytest

import freecad.paramesh as pm
import bl_check as bc  # tests/tools, put on sys.path by tests/conftest.py
from bl_helpers import (DATA, _part, assert_rows_exact, assert_valid_mesh, measure,  # tests/python
                        needs_freecad)


# ----------------------------------------------------------------------------------------------
# Plate with a square and a 12-gon hole: fans at reflex corners, a merged column at the outer corner

PLATE_BL_EDGES = [1, 2] + list(range(5, 21))   # the left and bottom sides, both holes


def plate_with_holes():
    """FreeCAD: a 200 x 200 plate with a 40 x 40 square hole and a 12-gon hole (radius 25)."""
    Part = _part()
    import FreeCAD
    V = FreeCAD.Vector
    plate = Part.makePlane(200, 200, V(-100, -100, 0))
    square = Part.Face(Part.makePolygon([V(-60, -20, 0), V(-20, -20, 0), V(-20, 20, 0), V(-60, 20, 0),
                                         V(-60, -20, 0)]))
    pts = [V(50 + 25 * math.cos(math.pi * k / 6), 25 * math.sin(math.pi * k / 6), 0) for k in range(12)]
    dodecagon = Part.Face(Part.makePolygon(pts + [pts[0]]))
    shape = plate.cut(square).cut(dodecagon)
    area = 200 * 200 - 40 * 40 - 0.5 * 12 * 25 ** 2 * math.sin(math.pi / 6)
    return shape, area


@pytest.fixture(scope="module")
def plate():
    shape, area = plate_with_holes()
    # Edge1 x=-100, Edge2 y=-100 (they meet at the outer corner), Edge5-8 square, Edge9-20 12-gon
    assert [round(v.Point.x) for v in shape.Edges[0].Vertexes] == [-100, -100]
    bl = dict(edges=PLATE_BL_EDGES, first_height=0.3, growth=1.2, layers=12)
    r = pm.mesh_shape(shape, size=8.0, boundary_layers=[bl])
    return shape, area, r, measure(r, PLATE_BL_EDGES, 0.3, 1.2, 12)


@needs_freecad
def test_plate_fans_at_reflex_corners(plate):
    shape, _, r, res = plate
    assert r.report["status"] == "ok"
    bl = r.report["boundary_layers"][0]
    assert bl["fans"] == 16 and bl["merges"] == 1      # 4 square corners + 12 polygon corners
    corners = {tuple(np.round(c["xyz"][:2], 3)): c["columns"] for c in res["fan"]["corners"]}
    square = {(-60.0, -20.0), (-20.0, -20.0), (-20.0, 20.0), (-60.0, 20.0)}
    polygon = {(round(50 + 25 * math.cos(math.pi * k / 6), 3), round(25 * math.sin(math.pi * k / 6), 3))
               for k in range(12)}
    assert set(corners) == square | polygon
    # 270 degree corners: the two edge columns and 3 fan columns share the corner node;
    # 210 degree corners of the 12-gon: one fan column between the two edge columns
    assert all(corners[c] == 5 for c in square) and all(corners[c] == 3 for c in polygon)
    assert res["fan_columns"] == 4 * 4 + 12 * 2 and res["fan"]["layers"]["min"] == 12
    assert abs(res["fan"]["first_height"]["max"] - 0.3) < 1e-9
    assert_rows_exact(res)


@needs_freecad
def test_plate_merged_outer_corner_without_crossing(plate):
    shape, area, r, res = plate
    m = res["_mesh"]
    corner = int(np.nonzero(np.linalg.norm(r.nodes - [-100, -100, 0], axis=1) < 1e-9)[0][0])
    rising = bc.rising_sides(res["_columns"])[corner]
    assert len(rising) == 1                            # one merged column on the bisector
    d = r.nodes[rising.pop()] - r.nodes[corner]
    assert abs(d[0] - d[1]) < 1e-9 * np.linalg.norm(d) and d[0] > 0
    # no inverted element against the CAD normal, conformal, and the elements tile the face
    # exactly once (their areas add up to the face area: nothing overlaps, nothing is missing)
    cad = bc.CadModel(shape)
    assert bc.check(m, PLATE_BL_EDGES, 0.3, 1.2, 12, cad=cad)["quads"]["inverted"] == 0
    assert_valid_mesh(res, watertight=False)
    normal = bc.element_normals(m)
    assert (normal[:, 2] * np.sign(normal[:, 2].sum()) > 0).all()
    assert abs(np.linalg.norm(normal, axis=1).sum() - area) < 1e-6 * area


@needs_freecad
def test_plate_merged_outer_corner_thick_layer():
    # a layer much thicker than the spacing at a 90-degree face corner: converging columns stop
    # and the front never crosses itself
    shape, _ = plate_with_holes()
    r = pm.mesh_shape(shape, size=8.0, boundary_layers=[dict(edges=[1, 2], first_height=0.5, growth=1.2,
                                                             layers=14)])
    assert r.report["status"] == "ok"
    bl = r.report["boundary_layers"][0]
    assert bl["elements"] == len(r.quads) > 0
    assert bl["stops"]["collision"] + bl["stops"]["folding"] > 0


# ----------------------------------------------------------------------------------------------
# Layers meeting each other: a chamfer, a V notch, a strip, a slot, two runs on CrankArm

@needs_freecad
@pytest.mark.parametrize("chamfer", [0.5, 0.6])
def test_layers_meeting_across_a_chamfer_of_exactly_the_first_height(chamfer):
    """A 10 x 10 square with one corner chamfered, layers on the two sides beside the chamfer. When
    the chamfer is exactly h0 long (0.5), each run's end column used to climb along it onto the
    other run's root, the two first rows crossed, and the face failed ("two boundary segments
    cross"). An end column now stops before another run's root. The 0.6 chamfer (= h0 + 0.1, no end
    column) is the comparison; both mesh, rows exact, no quad inverted."""
    Part = _part()
    import FreeCAD
    V = FreeCAD.Vector
    a = chamfer / math.sqrt(2)
    face = Part.Face(Part.makePolygon([V(0, 0, 0), V(10, 0, 0), V(10, 10 - a, 0), V(10 - a, 10, 0),
                                       V(0, 10, 0), V(0, 0, 0)]))
    assert abs(face.Edges[2].Length - chamfer) < 1e-12 and face.Edges[1].Length > 9
    r = pm.mesh_shape(face, size=1.0, boundary_layers=[dict(edges=[2, 4], first_height=0.5, growth=1.2,
                                                            layers=4)])
    assert r.report["status"] == "ok" and not r.failed_faces, r.report.get("message")
    bl = r.report["boundary_layers"][0]
    assert bl["full_columns"] >= 17 and bl["elements"] >= 63, bl   # measured 17 and 63 at 0.5
    res = measure(r, [2, 4], 0.5, 1.2, 4)
    assert_rows_exact(res)
    assert_valid_mesh(res, watertight=False)


@needs_freecad
def test_layers_meeting_in_a_v_notch_stop_at_each_other():
    """A 10 x 1 strip with a V notch from the top reaching down to 0.3, layers on the bottom and on
    both sides of the notch (h0 0.03, 6 rows: 0.45 thick, more than the 0.3 gap). A fan column at
    the notch's apex used to run down past the bottom layer's first row (to y = 0.0165), the two
    runs crossed and the face failed ("two boundary segments cross"); since stop 25 the face was
    then meshed without any layer. Now a column stops where its step would cross a row or column
    of a run grown before, or come within half its row height of the face's boundary: every run
    keeps its rows up to the collision, and nothing is dropped."""
    Part = _part()
    import FreeCAD
    V = FreeCAD.Vector
    pts = [V(0, 0, 0), V(10, 0, 0), V(10, 1, 0), V(6, 1, 0), V(5, 0.3, 0), V(4, 1, 0), V(0, 1, 0)]
    face = Part.Face(Part.makePolygon(pts + [pts[0]]))
    r = pm.mesh_shape(face, size=0.4, boundary_layers=[dict(edges=[1, 4, 5], first_height=0.03, growth=1.2,
                                                            layers=6)])
    assert r.report["status"] == "ok" and not r.failed_faces, r.report.get("message")
    assert not [w for w in r.report["warnings"] if "dropped" in w], r.report["warnings"]
    bl = r.report["boundary_layers"][0]
    assert bl["stops"]["collision"] >= 1 and bl["full_columns"] >= 30, bl   # measured 2 and 32 of 37
    res = measure(r, [1, 4, 5], 0.03, 1.2, 6)
    assert_rows_exact(res)
    assert_valid_mesh(res, watertight=False)
    tri_area = lambda a, b, c: 0.5 * np.linalg.norm(np.cross(r.nodes[b] - r.nodes[a], r.nodes[c] - r.nodes[a]))
    area = sum(tri_area(a, b, c) for a, b, c in r.triangles) + sum(
        tri_area(a, b, c) + tri_area(a, c, d) for a, b, c, d in r.quads)
    assert abs(area - (10 - 0.5 * 2 * 0.7)) < 1e-9, area                 # the whole face, no more
    # no node a hair above the boundary (the apex column's last point had been 0.0011 above it)
    poly = [np.array(p) for p in pts] + [np.array(pts[0])]

    def to_boundary(p):
        return min(np.linalg.norm(p - (a + np.clip((p - a) @ (b - a) / ((b - a) @ (b - a)), 0, 1) * (b - a)))
                   for a, b in zip(poly[:-1], poly[1:]))
    d = np.array([to_boundary(p) for p in r.nodes])
    assert d[d > 1e-9].min() > 0.5 * 0.03, d[d > 1e-9].min()            # measured 0.03
    q = r.report["quality"]
    assert q["angle_min"] > 4 and q["angle_max"] < 165, q               # measured 4.6 and 161.4


def test_layers_facing_each_other_across_a_strip_meet_without_slivers():
    """A quarter annulus 2 wide (radii 8 and 10) with layers on both arcs, 4 rows from h0 0.262
    (1.41 thick: the two layers cannot both fit). Scaled from bearing.iges's Face94, found by a
    sweep of random layers: the second run's columns crossed the first run's rows and the face was
    meshed without its layers; with the crossing test alone, a front then ended 0.016 below the
    other's and the triangles between had angles of 0.18 and 179.3 degrees. Now each run keeps its
    rows up to the other's, and the triangles between the fronts are well shaped."""
    Part = _part()
    import FreeCAD
    V = FreeCAD.Vector
    outer = Part.ArcOfCircle(Part.Circle(V(0, 0, 0), V(0, 0, 1), 10), 0, math.pi / 2).toShape()
    inner = Part.ArcOfCircle(Part.Circle(V(0, 0, 0), V(0, 0, 1), 8), 0, math.pi / 2).toShape()
    lines = [Part.makeLine(V(8, 0, 0), V(10, 0, 0)), Part.makeLine(V(0, 10, 0), V(0, 8, 0))]
    face = Part.Face(Part.Wire(Part.__sortEdges__([outer, lines[0], inner, lines[1]])))
    arcs = [i + 1 for i, e in enumerate(face.Edges) if isinstance(e.Curve, Part.Circle)]
    assert len(arcs) == 2
    h0 = 0.26219144202413333
    r = pm.mesh_shape(face, size=1.61425, boundary_layers=[dict(edges=arcs, first_height=h0, growth=1.2, layers=4)])
    assert r.report["status"] == "ok" and not r.failed_faces, r.report.get("message")
    assert not [w for w in r.report["warnings"] if "dropped" in w], r.report["warnings"]
    bl = r.report["boundary_layers"][0]
    assert bl["stops"]["collision"] >= 1 and bl["layers_min"] >= 1 and bl["full_columns"] >= 8, bl  # measured 7, 1, 9
    res = measure(r, arcs, h0, 1.2, 4)
    assert_rows_exact(res)
    assert_valid_mesh(res, watertight=False)
    q = r.report["quality"]
    assert q["angle_min"] > 10 and q["angle_max"] < 160, q               # measured 13.7 and 146.5


def test_a_row_does_not_pass_just_below_another_layers_front():
    """A 10 x 4 plate with a 1-wide slot from the top down to y = 1, layers on the base, on the
    top on both sides of the slot, and on the slot's bottom (h0 0.3, 4 rows: 1.61 thick, more
    than the 1 between the slot and the base). The slot's layer, grown first, ended 0.02 to 0.04
    above the base layer's first row, which ran under the slot between two columns 2 apart
    without crossing it: triangles of 0.9 and 177.6 degrees between the two. A row that passes
    within a quarter row height of another layer's points now stops its columns."""
    Part = _part()
    import FreeCAD
    V = FreeCAD.Vector
    pts = [V(0, 0, 0), V(10, 0, 0), V(10, 4, 0), V(5.5, 4, 0), V(5.5, 1, 0), V(4.5, 1, 0), V(4.5, 4, 0),
           V(0, 4, 0)]
    face = Part.Face(Part.makePolygon(pts + [pts[0]]))
    r = pm.mesh_shape(face, size=2.0, boundary_layers=[dict(edges=[1, 3, 5, 7], first_height=0.3, growth=1.2,
                                                            layers=4)])
    assert r.report["status"] == "ok" and not r.failed_faces, r.report.get("message")
    assert not [w for w in r.report["warnings"] if "dropped" in w], r.report["warnings"]
    res = measure(r, [1, 3, 5, 7], 0.3, 1.2, 4)
    assert_rows_exact(res)
    assert_valid_mesh(res, watertight=False)
    q = r.report["quality"]
    assert q["angle_min"] > 5 and q["angle_max"] < 165, q                # measured 6.1 and 159.5


def test_crankarm_face_where_two_runs_collide_keeps_its_layer():
    """Found by a sweep of random layers: with these eight edges, CrankArm's Face19 failed ("two
    boundary segments cross") and the run was 'degraded'; at stop 25 Face19 was meshed without its
    rows. Now a column stops where it would cross another run's rows: Face19 keeps its layer."""
    size = 1.7449074614308635  # diagonal / 100
    edges = [28, 42, 53, 58, 77, 114, 115, 124]
    r = pm.mesh_shape(os.path.join(DATA, "CrankArm.brep"), size=size,
                      boundary_layers=[dict(edges=edges, first_height=0.3577962419905549, growth=1.2, layers=4)])
    assert r.report["status"] == "ok" and not r.failed_faces, r.report.get("message")
    assert not [w for w in r.report["warnings"] if "dropped" in w], r.report["warnings"]
    quad_faces = set(np.unique(r.quad_face).tolist())
    assert 19 in quad_faces and len(quad_faces) >= 14, quad_faces        # measured 14 faces
    assert r.report["boundary_layers"][0]["stops"]["collision"] >= 1, r.report["boundary_layers"][0]
    assert r.report["quality"]["angle_min"] > 0.3, r.report["quality"]   # measured 0.45 (stop 25: 0.17)
    res = measure(r, edges, 0.3577962419905549, 1.2, 4)
    assert_valid_mesh(res, watertight=True)
    assert_rows_exact(res)
