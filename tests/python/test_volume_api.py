# SPDX-License-Identifier: LGPL-2.1-or-later
"""mesh_shape(volume=True): the tetrahedra arrays, measured in numpy against the surface mesh and
the CAD. Boxes are exact (flat faces: the tetrahedra fill the CAD volume to round-off); the
CrankArm's curved faces leave the chord error of the surface triangles, which the tetrahedra
must reproduce exactly (divergence theorem on the triangles)."""
import os

import numpy as np
import pytest

import freecad.paramesh as pm

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(HERE), "data")
BOX = os.path.join(HERE, "data", "box_10x20x30.brep")            # Part.makeBox(10, 20, 30)
TWO_BOXES = os.path.join(HERE, "data", "two_boxes_touching.brep")  # + makeBox(15, 20, 30) at x = 10, a compound
CRANK = os.path.join(DATA, "CrankArm.brep")
# FreeCAD 0.20.2: [s.Volume for s in Part.read("tests/data/CrankArm.brep").Solids]
CRANK_VOLUMES = [15390.285418817992, 38684.678961664154]

#: outward faces of a positive tetrahedron (a, b, c, d): ((b-a)x(c-a)).(d-a) > 0
TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])


def tet_volumes(r):
    p = r.nodes[r.tetrahedra[:, :4]]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6


def boundary_faces(tets):
    """Outward faces (F, 3) that belong to one tetrahedron only."""
    f = tets[:, TET_FACES].reshape(-1, 3)
    _, idx, counts = np.unique(np.sort(f, axis=1), axis=0, return_index=True, return_counts=True)
    return f[idx[counts == 1]]


def cyclic_key(tri):
    """The triangle's nodes rotated so that the smallest comes first (keeps the orientation)."""
    k = int(np.argmin(tri))
    return tuple(int(x) for x in np.roll(tri, -k))


def check_solid_boundaries(r):
    """Per solid: the tetrahedra's boundary faces are the surface triangles of the solid's CAD
    faces (as node sets), and per CAD face all of them have the triangles' orientation or all the
    opposite one. Returns {(solid, face): True when outward == the triangles' orientation}."""
    tris = r.triangles
    agree = {}
    for s in r.solids:
        assert s["ok"], s
        bnd = boundary_faces(r.tetrahedra[r.tetra_solid == s["solid"], :4])
        mine = np.isin(r.triangle_face, s["faces"])
        assert {tuple(sorted(t)) for t in bnd.tolist()} == {tuple(sorted(t)) for t in tris[mine].tolist()}
        oriented = {cyclic_key(t): True for t in bnd}
        for f in s["faces"]:
            same = [cyclic_key(t) in oriented for t in tris[r.triangle_face == f]]
            assert all(same) or not any(same), f"Solid{s['solid']} Face{f}: mixed orientation"
            agree[s["solid"], f] = all(same)
    return agree


def enclosed_volume(r, faces, flip=()):
    """Volume inside the surface triangles of faces (divergence theorem), faces in flip reversed."""
    total = 0.0
    for f in faces:
        p = r.nodes[r.triangles[r.triangle_face == f]]
        v = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6
        total += -v if f in flip else v
    return total


def test_box_tetrahedra_fill_it_exactly():
    r = pm.mesh_shape(BOX, size=3.0, volume=True)
    t = r.tetrahedra
    assert t.dtype == np.int32 and t.ndim == 2 and t.shape[1] == 4 and len(t) > 200
    assert r.tetra_solid.dtype == np.int32 and r.tetra_solid.shape == (len(t),)
    assert set(r.tetra_solid.tolist()) == {1} and r.num_solids == 1
    assert t.min() >= 0 and t.max() < len(r.nodes)
    v = tet_volumes(r)
    assert v.min() > 0
    assert abs(v.sum() - 6000.0) < 1e-9 * 6000
    # every boundary face outward == the surface triangle's own orientation (out of the CAD face)
    assert all(check_solid_boundaries(r).values())
    vol = r.report["volume"]
    assert vol["tetrahedra"] == len(t) and vol["solids_filled"] == 1
    assert vol["solids"][0]["tetrahedra"] == len(t) and abs(vol["solids"][0]["volume"] - 6000.0) < 1e-6
    # interior nodes: dimension 3, entity = the solid, strictly inside the box
    inner = r.node_dim == 3
    assert inner.sum() == vol["solids"][0]["interior_nodes"] > 0 and set(r.node_entity[inner].tolist()) == {1}
    p = r.nodes[inner]
    assert (p.min(axis=0) > 1e-9).all() and (p.max(axis=0) < np.array([10, 20, 30]) - 1e-9).all()
    assert "tetrahedra" in repr(r)


def test_box_tet10_mid_nodes_are_the_edge_midpoints_in_c3d10_order():
    r = pm.mesh_shape(BOX, size=4.0, volume=True, order=2)
    t = r.tetrahedra
    assert t.shape[1] == 10 and t.dtype == np.int32
    assert tet_volumes(r).min() > 0
    p = r.nodes
    for k, (i, j) in enumerate([(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]):  # ab bc ca ad bd cd
        assert np.abs(p[t[:, 4 + k]] - 0.5 * (p[t[:, i]] + p[t[:, j]])).max() < 1e-9
    # the tet10's mid-nodes on the surface are the tria6 mid-nodes (one node per mesh edge)
    edge_mid = {}
    for tri, mid in zip(r.triangles, r.triangle_mid):
        for (i, j), m in zip([(0, 1), (1, 2), (2, 0)], mid):
            edge_mid[min(tri[i], tri[j]), max(tri[i], tri[j])] = m
    seen = 0
    for row in t:
        for k, (i, j) in enumerate([(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]):
            key = (min(row[i], row[j]), max(row[i], row[j]))
            if key in edge_mid:
                assert edge_mid[key] == row[4 + k]
                seen += 1
    assert seen >= len(edge_mid)


def test_two_touching_boxes_share_their_interface():
    r = pm.mesh_shape(TWO_BOXES, size=3.0, volume=True)
    assert r.num_solids == 2 and set(r.tetra_solid.tolist()) == {1, 2}
    v = tet_volumes(r)
    assert v.min() > 0
    per_solid = np.bincount(r.tetra_solid, weights=v)[1:]
    assert np.allclose(per_solid, [6000.0, 9000.0], rtol=1e-9, atol=0)
    assert [s["tetrahedra"] for s in r.solids] == np.bincount(r.tetra_solid)[1:].tolist()
    agree = check_solid_boundaries(r)
    # every boundary face points out of its own solid like its triangle (each face's triangles
    # are oriented out of the CAD face); the interface is meshed once: Box 2's copy of the face
    # takes Box 1's triangles, same nodes, reversed
    assert all(agree.values())
    assert r.report["coincident_faces"] == [[2, 7]]
    own, copy = r.triangles[r.triangle_face == 2], r.triangles[r.triangle_face == 7]
    assert sorted(cyclic_key(t) for t in own) == sorted(cyclic_key(t[::-1]) for t in copy)
    # conformal: no node is duplicated (the 24 + 24 CAD faces' triangles use one set of nodes)
    assert len(np.unique(np.round(r.nodes, 9), axis=0)) == len(r.nodes)


def test_crank_arm_tetrahedra_fill_the_surface_mesh_and_the_cad():
    r = pm.mesh_shape(CRANK, size=2.0, volume=True)
    assert r.num_solids == 2 and r.report["volume"]["solids_filled"] == 2
    v = tet_volumes(r)
    assert v.min() > 0
    per_solid = np.bincount(r.tetra_solid, weights=v)[1:]
    agree = check_solid_boundaries(r)
    for s, vs, cad in zip(r.solids, per_solid, CRANK_VOLUMES):
        flip = [f for f in s["faces"] if not agree[s["solid"], f]]
        # the tetrahedra fill exactly what the surface triangles enclose ...
        assert abs(vs - enclosed_volume(r, s["faces"], flip)) < 1e-9 * cad
        # ... which is the CAD volume up to the triangles' chords on curved faces
        assert abs(vs - cad) < 0.005 * cad, (s["solid"], vs, cad)


def test_volume_parameters():
    coarse = pm.mesh_shape(BOX, size=3.0, volume=True)
    fine = pm.mesh_shape(BOX, size=3.0, volume=True, volume_max_size=1.5)
    assert len(fine.tetrahedra) > 2 * len(coarse.tetrahedra)
    assert len(fine.triangles) == len(coarse.triangles)  # the surface is the same
    # tetrahedron edges inside the solid stay near volume_max_size
    t = fine.tetrahedra
    e = np.linalg.norm(fine.nodes[t[:, [0, 0, 0, 1, 1, 2]]] - fine.nodes[t[:, [1, 2, 3, 2, 3, 3]]], axis=2)
    assert np.median(e) < 1.5 * 1.3
    # nglib's optimisation passes improve the tetrahedra (box at size 3: min dihedral 5.4 deg with
    # none, 16.3 with the default one pass)
    raw = pm.mesh_shape(BOX, size=3.0, volume=True, volume_optimize=0)
    assert abs(tet_volumes(raw).sum() - 6000.0) < 1e-9 * 6000
    assert coarse.solids[0]["min_dihedral"] > raw.solids[0]["min_dihedral"]
    assert coarse.solids[0]["mean_radius_ratio"] > raw.solids[0]["mean_radius_ratio"]
    surface_only = pm.mesh_shape(BOX, size=3.0)
    assert surface_only.tetrahedra.shape == (0, 4) and "volume" not in surface_only.report
    assert surface_only.solids == []
    with pytest.raises(pm.ParameterError, match="quads"):
        pm.mesh_shape(BOX, size=3.0, volume=True, quads=True)
    with pytest.raises(TypeError, match="volume"):
        pm.mesh_shape(BOX, volume="yes")
    with pytest.raises(ValueError, match="volume_max_size"):
        pm.mesh_shape(BOX, volume=True, volume_max_size=-1)
    with pytest.raises(ValueError, match="volume_optimize"):
        pm.mesh_shape(BOX, volume=True, volume_optimize=11)
