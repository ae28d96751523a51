# SPDX-License-Identifier: LGPL-2.1-or-later
"""Surface boundary layers at their ends and on awkward edges: a blade's leading edge that closes to
a crease at its tip (propeller_and_shaft.iges), end columns beside tangent, reflex or in-line
neighbouring edges, one-segment edges, and a layer that grows nowhere. Measured with
tests/tools/bl_check.py through bl_helpers.py, as in test_boundary_layer.py."""
import os

import numpy as np
import pytest

import freecad.paramesh as pm
import bl_check as bc  # tests/tools, put on sys.path by tests/conftest.py
from bl_helpers import (BOTTLE, DATA, M6, SCREW, _part, assert_rows_exact, assert_valid_mesh,  # tests/python
                        measure, needs_freecad)


# ----------------------------------------------------------------------------------------------
# propeller_and_shaft.iges: unsewn IGES, the leading edge of a blade (Edge42 of Face7 coincides
# with Edge49 of Face8), a nose of radius ~1 mm that closes to a crease at the blade tip, where
# the tip face (Face18) is a strip with zero-length ends

PS = os.path.join(DATA, "propeller_and_shaft.iges")
PS_SIZE = 1904.9886655946982 / 200   # diagonal / 200


def min_angles(r):
    """(M,) smallest angle of each triangle, degrees."""
    P, t = r.nodes, r.triangles
    ang = []
    for i in range(3):
        u = P[t[:, (i + 1) % 3]] - P[t[:, i]]
        v = P[t[:, (i + 2) % 3]] - P[t[:, i]]
        c = (u * v).sum(axis=1) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))
        ang.append(np.degrees(np.arccos(np.clip(c, -1, 1))))
    return np.min(ang, axis=0)


def blade_layer(first_height, layers, edges=(42,)):
    return pm.mesh_shape(PS, size=PS_SIZE, nearest_face_budget=0,
                         boundary_layers=[dict(edges=list(edges), first_height=first_height, growth=1.2,
                                               layers=layers)])


@pytest.fixture(scope="module")
def ps_plain():
    return pm.mesh_shape(PS, size=PS_SIZE, nearest_face_budget=0)


@pytest.mark.parametrize("first_height, layers", [(3.8, 1), (2.0, 2), (1.0, 3), (0.2, 10), (0.05, 20)])
def test_blade_leading_edge_layer(ps_plain, first_height, layers):
    """A first row of 3.8 on a nose of radius ~1: the steps around the nose did not converge in
    four projections, those columns stopped at the edge, and the one column between them that
    grew stood alone: the front ran up and down it through the same nodes and Face7 failed with
    "two boundary points coincide in (u,v)". Now every face is meshed, the rows are exact, the
    columns at the blade root run along the hub's edges (Edge32/Edge31, through which the skins'
    root edges are meshed), and the mesh is as closed as the plain one. The plain mesh has its
    smallest angle, 2.42 degrees, at each blade's leading-edge tip (Faces 7, 10, 12, 14, 16),
    where the nose closes to a crease and the surface normal turns over within 0.05 of (u,v):
    the layer may not take the mesh below 2 degrees (measured 2.30-2.42; before: the face failed,
    2.42, 1.75, 0.0 and 0.44 degrees)."""
    plain = bc.conformity(bc.SurfMesh.from_result(ps_plain))
    assert plain["ok"] and plain["watertight"], plain          # every mesh edge used twice
    r = blade_layer(first_height, layers)
    assert r.report["status"] == "ok" and not r.failed_faces, r.failed_faces
    res = measure(r, [42], first_height, 1.2, layers)
    assert set(res["faces"]) == {"7", "8"}
    assert_rows_exact(res)
    assert res["height_err_full"]["max"] <= 1e-6                  # measured <= 8e-8
    assert res["pct_full"] >= 90                                   # measured 91.2-100 %
    assert res["ortho_deg"]["min"] >= 85                           # measured 89.0-89.9
    assert_valid_mesh(res, watertight=True)                        # like the plain mesh
    along = {(e["face"], e["along_edge"]) for e in res["end_columns"] if e["rows"] >= 1}
    assert {(7, 32), (8, 31)} <= along, along                      # the root ends
    assert min_angles(r).min() >= 2.0, min_angles(r).min()


@pytest.mark.xfail(strict=True, reason="0.73 degrees at the blade tip, where the nose closes to a crease "
                                       "(docs/boundary_layers.md, known weaknesses)")
def test_blade_leading_edge_layer_at_the_tip_quality():
    assert min_angles(blade_layer(0.5, 5)).min() >= 2.0


@pytest.mark.xfail(strict=True, reason="the final audit finds 4 folds (normals over 160 degrees apart, the surface's "
                                       "own normals not) on Face7 near the blade tip: degraded, open (docs/audit.md)")
def test_blade_tip_edge_layer_meets_the_tip_face():
    """Rows grown from the blade's tip edge (Edge43, coincident with Edge91 of the tip strip
    Face18, whose ends are zero-length edges): on Face18 a column grew rows while both its
    neighbours stopped at the strip's ends, and the face failed with "two boundary points
    coincide in (u,v)". Such a column now stops with its neighbours."""
    r = blade_layer(0.2, 10, edges=(43,))
    assert r.report["status"] == "ok" and not r.failed_faces, r.failed_faces
    res = measure(r, [43], 0.2, 1.2, 10)
    assert_rows_exact(res)
    assert_valid_mesh(res, watertight=True)


def test_hub_circle_layer_stops_at_the_blade_roots():
    """Rows grown from the hub's end circle (Edge10, merged with Edge24 of the hub Face5): the
    blade roots on Face5 come within 2.7 of the circle, under the layer's 3.72. Each column
    stopped at the roots, but a root's corner poked between two columns and the row joining them
    crossed it: Face5 failed with "two boundary segments cross in (u,v)". A row that crosses the
    face's boundary now stops both its columns."""
    r = blade_layer(0.5, 5, edges=(10,))
    assert r.report["status"] == "ok" and not r.failed_faces, r.failed_faces
    bl = r.report["boundary_layers"][0]
    assert bl["layers_min"] >= 3 and bl["layers_max"] == 5, bl        # measured 3 and 5
    assert bl["stops"]["face_boundary"] > 0, bl
    res = measure(r, [10], 0.5, 1.2, 5)
    assert_rows_exact(res)
    assert_valid_mesh(res, watertight=True)


@pytest.mark.parametrize("first_height,layers", [(0.186, 5), (0.62, 8)])
def test_end_columns_not_along_a_tangent_neighbour(first_height, layers):
    """nist_ctc_01's Edge326 (a 22.8 line, one segment at diagonal/100) runs tangentially into the
    arcs of a slot on the plane Face117. Its end columns ran along those arcs, i.e. along the BL
    edge's own line: the rows between them crossed the slot, so Face117 failed ("two boundary
    segments cross in (u,v)", h0 0.62 with 8 rows) or got an element facing the other way (h0
    0.186 with 5 rows). An end whose neighbouring edge carries on within 30 degrees of straight
    keeps no rows; the strip Face136 on the other side keeps its layer."""
    r = pm.mesh_shape(os.path.join(DATA, "nist_ctc_01.brep"), size=18.60107524375957,
                      boundary_layers=[dict(edges=[326], first_height=first_height, growth=1.2, layers=layers)])
    assert r.report["status"] == "ok" and not r.failed_faces, r.failed_faces
    res = measure(r, [326], first_height, 1.2, layers)
    assert_valid_mesh(res, watertight=True)                  # before: 1 orientation mismatch
    assert res["quads"]["min_corner_sine"] >= 0.99, res["quads"]   # measured 1.0 (before 0.015)


@pytest.mark.parametrize("model,edge,size", [
    # bottle.brep's Edge89 (8 columns) ends where its neighbouring edge carries on in line: the end
    # column ran along the BL edge's own line and the first quad there had a straight corner
    # (bl_check: 1 inverted quad, corner sine 0.0). An end whose neighbouring edge carries on
    # within 10 degrees of straight (30 in a run of one segment) now keeps no rows.
    (BOTTLE, 89, 1.8979771361014846),
    # the M6's Edge15: the first quad beside its end column along the tip was convex in (u,v) but
    # had a reflex corner in 3D (corner sine -0.077). A layer quad must now be convex in 3D too.
    (M6, 15, 33.500098860449405),
])
def test_end_quads_valid(model, edge, size):
    """h0 = size/20 with 10 rows, size = diagonal / 100 (found by a sweep over random edges)."""
    r = pm.mesh_shape(model, size=size, boundary_layers=[dict(edges=[edge], first_height=size / 20, growth=1.2,
                                                               layers=10)])
    assert r.report["status"] == "ok" and not r.failed_faces, r.failed_faces
    res = measure(r, [edge], size / 20, 1.2, 10)
    assert_valid_mesh(res, watertight=True)
    assert res["quads"]["min_corner_sine"] >= 0.8, res["quads"]   # measured 0.91 on both


@needs_freecad
def test_no_rows_outside_the_face_at_reflex_ends():
    """screw.step's Edge12 is one segment (a 2.5-long arc) at the bottom of a slot, between the cone
    Face7 and the slot's floor. On Face7 the slot's walls (Edges 4 and 9) rise away from the face:
    end columns along them put the rows outside Face7 (a row point 0.094 off the face, bl_check:
    1 orientation mismatch, status ok). The layer's side was a probe off the segment's chord,
    which the arc bulges past; it is now judged on the true boundary, and an end column must leave
    into the layer's side (30 degrees or more in a run of one segment), else it is marched square
    to the edge when that direction lies inside the face (here: Face7 gets rows between two
    marched columns). Any row that still stands outside the true boundary is cut back."""
    size = 2.0620488559318572  # diagonal / 50: Edge12 is one segment
    part = _part()
    shape = bc.read_shape(SCREW)
    for h0, layers, quads in ((size / 100, 5, True), (size / 20, 10, True), (size / 60, 6, False)):
        r = pm.mesh_shape(SCREW, size=size, boundary_layers=[dict(edges=[12], first_height=h0, growth=1.2,
                                                                    layers=layers, quads=quads)])
        assert r.report["status"] == "ok" and not r.failed_faces, r.failed_faces
        assert r.report["boundary_layers"][0]["elements"] > 0
        res = measure(r, [12], h0, 1.2, layers)
        assert_valid_mesh(res, watertight=True)                  # before: 1 orientation mismatch
        if not quads:
            continue
        # every node of the layers lies on its own trimmed face (before: a row point 0.094 off
        # Face7, outside its domain), on both faces: on Face7 the run's end columns are now
        # marched square to the edge, into the face
        P, Q = np.asarray(r.nodes), np.asarray(r.quads)
        faces = bc.SurfMesh.from_result(r).quad_face
        assert set(int(f) for f in faces) == {3, 7}, set(faces)
        for q, f in zip(Q, faces):
            for p in P[q]:
                d = part.Vertex(*p).distToShape(shape.Faces[int(f) - 1])[0]
                assert d < 1e-6 * size, (f, p, d)


@needs_freecad
@pytest.mark.parametrize("model,edge,size,min_sine", [
    # ANC101's Edge138 runs along the bottom of a notch cut into the plane Face41. The domain guard
    # read a band of the notch as inside the face (the notch's bottom lay on a row of its grid's
    # reference points), so the layer's side came out wrong and its rows stood in the notch,
    # overlapped by the face's triangles (bl_check: 4 orientation mismatches, status ok). Its end
    # columns, along the notch's sides, now stop: those sides leave away from Face41.
    ("ANC101.stp", 138, 5.090788821813393, 0.9),
    # CrankArm's Edge39 ends where its neighbouring edge leaves 1.6 degrees from it, into Face11:
    # the end column ran almost back along the BL edge (quad corners of 1.1 and 1.6 degrees,
    # corner sine 0.007). An end column must leave at 10 degrees or more.
    ("CrankArm.brep", 39, 1.7449074614308635, 0.9),
])
def test_end_columns_leave_into_the_face(model, edge, size, min_sine):
    path = os.path.join(DATA, model)
    r = pm.mesh_shape(path, size=size, boundary_layers=[dict(edges=[edge], first_height=size / 100, growth=1.2,
                                                               layers=5)])
    assert r.report["status"] == "ok" and not r.failed_faces, r.failed_faces
    assert r.report["boundary_layers"][0]["elements"] > 0
    res = measure(r, [edge], size / 100, 1.2, 5)
    assert_valid_mesh(res, watertight=True)                          # ANC101 before: 4 mismatches
    assert res["quads"]["min_corner_sine"] >= min_sine, res["quads"]  # measured 0.988 / 0.999
    shape = bc.read_shape(path)
    P, faces = np.asarray(r.nodes), bc.SurfMesh.from_result(r).quad_face
    for q, f in zip(np.asarray(r.quads), faces):
        d = _part().Vertex(*P[q].mean(0)).distToShape(shape.Faces[int(f) - 1])[0]
        assert d < 1e-3 * size, (f, d)                               # ANC101 before: 0.378 off Face41


@pytest.mark.parametrize("edge", [78, 334])
def test_one_segment_edge_between_tangent_neighbours_gets_rows(edge):
    """small-edges-01's outline is 382 edges, most running on in line into the next. A BL edge of
    one segment there had both ends dropped (an end column along an in-line neighbour would lie
    along the BL edge itself) and got no rows at all, with status ok (elements 0). Its ends are now
    marched square to the edge: 2 full columns, 5 quads."""
    size = 0.6252955824300142  # diagonal / 100
    r = pm.mesh_shape(os.path.join(DATA, "small-edges-01.brep"), size=size,
                      boundary_layers=[dict(edges=[edge], first_height=size / 100, growth=1.2, layers=5)])
    assert r.report["status"] == "ok" and not r.failed_faces, r.failed_faces
    bl = r.report["boundary_layers"][0]
    assert bl["elements"] == 5 and bl["full_columns"] == 2, bl     # before: 0 elements
    res = measure(r, [edge], size / 100, 1.2, 5)
    assert_rows_exact(res)
    assert_valid_mesh(res, watertight=False)                      # one open face
    assert res["quads"]["min_corner_sine"] >= 0.99, res["quads"]  # measured 1.0


def test_a_layer_that_grows_nowhere_is_reported():
    """The M6's Edge2 is 0.51 long, at the tip; with h0 = size/100 its columns on Face1 and Face4
    stop before a first row is shared (elements 0): the run is degraded, naming the layer, and the
    report says so for each face."""
    size = 33.500098860449405
    r = pm.mesh_shape(M6, size=size, boundary_layers=[dict(edges=[2], first_height=size / 100, growth=1.2,
                                                            layers=5)])
    assert r.report["status"] == "degraded"
    assert "boundary layer 1 (Edge2) produced no element on any face" in r.report["message"], r.report["message"]
    assert r.report["boundary_layers"][0]["elements"] == 0
    msgs = [w for w in r.report["warnings"] if w.startswith("boundary layer 1 (Edge2) got no element")]
    assert [m.split(" on ")[1].split(" ")[0] for m in msgs] == ["Face1", "Face4"], r.report["warnings"]
    assert "stopped: 1 at the face boundary" in msgs[1], msgs
    # a layer that grows says nothing of the kind
    r = pm.mesh_shape(M6, size=size, boundary_layers=[dict(edges=[21], first_height=size / 100, growth=1.2,
                                                            layers=5)])
    assert r.report["boundary_layers"][0]["elements"] > 0
    assert not [w for w in r.report["warnings"] if "got no element" in w], r.report["warnings"]
