# SPDX-License-Identifier: LGPL-2.1-or-later
"""The nearest-face check (nearest_face_check=True, and by default within nearest_face_budget):
on a coarse mesh of the propeller, triangles
of the fillets between the hub and its caps cut so deep that their centroid lies nearer the cap
than their own fillet. Measured here with FreeCAD's Part (OpenCASCADE distToShape on the trimmed
faces), independently of ParaMesh: more than 5 % of the size off its own face and another face
nearer. Without the check such triangles exist; with it there are none, and the mesh stays
conformal and watertight."""
import os

import numpy as np
import pytest

import freecad.paramesh as pm
import bl_check as bc  # tests/tools, put on sys.path by tests/conftest.py

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

PROPELLER = os.path.join(ROOT, "tests", "data", "Propeller.brep")
H = 13.586781259739915  # bounding-box diagonal / 100
Part = bc.import_part()
needs_freecad = pytest.mark.skipif(Part is None, reason="needs FreeCAD (Part)")


def wrong_side(shape, res, h, only=None):
    """Triangles (of the faces `only`, default all) whose centroid is more than 0.05 h from its
    own CAD face and nearer another."""
    import FreeCAD
    faces = shape.Faces
    boxes = [f.BoundBox for f in faces]
    t = res.triangles
    c = res.nodes[t].mean(axis=1)
    bad = []
    for k in range(len(t)):
        if only is not None and int(res.triangle_face[k]) not in only:
            continue
        v = Part.Vertex(FreeCAD.Vector(*c[k]))
        own = int(res.triangle_face[k]) - 1
        d = v.distToShape(faces[own])[0]
        if d <= 0.05 * h:
            continue
        for j, f in enumerate(faces):
            if j == own:
                continue
            b = boxes[j]
            x, y, z = c[k]
            if (max(b.XMin - x, 0, x - b.XMax) ** 2 + max(b.YMin - y, 0, y - b.YMax) ** 2 +
                    max(b.ZMin - z, 0, z - b.ZMax) ** 2) >= d * d:
                continue  # its bounding box is farther than the own face
            if v.distToShape(f)[0] < d:
                bad.append((k, own + 1, j + 1))
                break
    return bad


def edge_uses(res):
    t = res.triangles
    e = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    _, c = np.unique(e, axis=0, return_counts=True)
    return c


@needs_freecad
def test_propeller_fillet_triangles_come_back_to_their_face():
    shape = bc.read_shape(PROPELLER)
    plain = pm.mesh_shape(PROPELLER, size=H, nearest_face_budget=0)
    assert "nearest_face_check" not in plain.report, "off with a zero budget"
    before = wrong_side(shape, plain, H)
    assert len(before) >= 4, before  # the fillet Face75 against the cap Face76, and others
    assert {(a, b) for _, a, b in before} >= {(75, 76)}
    r = pm.mesh_shape(PROPELLER, size=H, nearest_face_check=True)
    assert r.report["status"] == "ok"
    nf = r.report["nearest_face_check"]
    assert nf["flagged_per_round"][0] > 0 and nf["remaining"] == 0, nf
    assert wrong_side(shape, r, H) == []
    # conformal and closed; refined only locally: fewer than 1.2x the triangles, and more edges
    # within [h/sqrt2, h sqrt2] than Gmsh 4.8 Frontal's 82.44 % on this case (docs/benchmark.md)
    assert edge_uses(r).max() == 2 and edge_uses(r).min() == 2
    assert len(r.triangles) < 1.2 * len(plain.triangles)
    t = r.triangles
    e = np.unique(np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1), axis=0)
    L = np.linalg.norm(r.nodes[e[:, 0]] - r.nodes[e[:, 1]], axis=1) / H
    assert 100 * np.mean((L >= 2 ** -0.5) & (L <= 2 ** 0.5)) > 82.44


def test_nearest_face_check_is_a_bool():
    with pytest.raises(TypeError, match="nearest_face_check"):
        pm.mesh_shape(PROPELLER, nearest_face_check=1)


@needs_freecad
def test_by_default_refined_within_the_budget():
    """By default the check runs and its refinement is kept when it adds at most 10 % triangles:
    the propeller at diagonal/100 (4.4 % more) comes out like nearest_face_check=True; with a 1 %
    budget the unrefined mesh is kept, and the report warns how many triangles are wrong-side."""
    shape = bc.read_shape(PROPELLER)
    r = pm.mesh_shape(PROPELLER, size=H)
    nf = r.report["nearest_face_check"]
    assert nf["outcome"] == "refined" and nf["remaining"] == 0 and nf["triangle_growth"] <= 0.10, nf
    assert wrong_side(shape, r, H) == []
    assert edge_uses(r).max() == 2 and edge_uses(r).min() == 2, "conformal and closed"
    # the rounds after the first mesh again only the faces the new sizes reach (the others keep
    # their mesh: node for node the same as without the check)
    plain = pm.mesh_shape(PROPELLER, size=H, nearest_face_budget=0)
    nfaces = len(shape.Faces)
    again = nf["faces_remeshed_per_round"]
    assert len(again) == len(nf["flagged_per_round"]) - 1 and max(again) < 0.8 * nfaces, (again, nfaces)

    def face_points(res, f):
        t = res.triangles[res.triangle_face == f]
        return np.sort(np.round(res.nodes[t].reshape(-1, 3), 9), axis=0)

    same = sum(1 for f in range(1, nfaces + 1)
               if np.array_equal(face_points(r, f), face_points(plain, f)))
    assert same >= 0.3 * nfaces, (same, nfaces, again)  # measured: 37 of 76
    # the per-stage seconds are summed over the rounds (each round meshes edges and faces again):
    # together they account for the total (measured 0.998 of it; the last round's alone, before
    # this was fixed, left boxed_sphere d/200's 2.4 of 2.6 s unaccounted)
    sec = r.report["seconds"]
    staged = sum(v for k, v in sec.items() if k != "total")
    assert 0.8 * sec["total"] <= staged <= 1.001 * sec["total"], sec
    tight = pm.mesh_shape(PROPELLER, size=H, nearest_face_budget=0.01)
    nf = tight.report["nearest_face_check"]
    assert nf["outcome"] == "kept unrefined" and nf["remaining"] == nf["flagged_per_round"][0] > 0, nf
    assert any("nearer another CAD face" in w for w in tight.report["warnings"])
    # the first round refines in place (local deviation bounds on the flagged triangles' faces,
    # the size field unchanged) and is already over a 1 % budget: no round with size sources
    assert len(nf["flagged_per_round"]) == 2 and len(nf["faces_remeshed_per_round"]) == 1, nf
    assert nf["flagged_per_round"][1] < nf["flagged_per_round"][0], nf
    assert any("would add" in w for w in tight.report["warnings"])
    assert len(tight.triangles) == len(plain.triangles), "the unrefined mesh, exactly"
    assert np.array_equal(tight.triangles, plain.triangles)


BOXED = os.path.join(ROOT, "tests", "data", "boxed_sphere.step")


def test_feet_among_the_triangles_own_nodes_are_not_off_the_face():
    """boxed_sphere at diagonal/200: on the three-sided corner patches (Face4 and its copies) the
    projection of a centroid lands among the triangle's own (u,v) corners, yet the p-curves put it
    outside the patch (FreeCAD's isInside says so too). Such a foot is where the triangle's nodes
    say the face is, so those triangles are no candidates: before, 89 of them were flagged and
    refining flagged more each round (89, 155, 203); now at most a few are, the refinement adds
    almost nothing, and the corner patches keep the unrefined mesh."""
    h = 17.463420722835245 / 200  # bounding-box diagonal / 200
    plain = pm.mesh_shape(BOXED, size=h, nearest_face_budget=0)
    r = pm.mesh_shape(BOXED, size=h)
    nf = r.report["nearest_face_check"]
    assert nf["flagged_per_round"][0] <= 5 and nf["remaining"] == 0, nf  # measured: 2, then 0
    assert len(r.triangles) < 1.001 * len(plain.triangles)
    assert edge_uses(r).max() == 2 and edge_uses(r).min() == 2, "conformal and closed"
    for f in (4, 5, 6, 7):
        a = np.sort(np.round(r.nodes[r.triangles[r.triangle_face == f]].reshape(-1, 3), 9), axis=0)
        b = np.sort(np.round(plain.nodes[plain.triangles[plain.triangle_face == f]].reshape(-1, 3), 9), axis=0)
        assert np.array_equal(a, b), f


PS = os.path.join(ROOT, "tests", "data", "propeller_and_shaft.iges")


def angles(a, b, c):
    """The three angles (degrees, one row each) of triangles with side lengths a, b, c."""
    return np.degrees(np.arccos(np.clip(np.stack([(b * b + c * c - a * a) / (2 * b * c),
                                                  (c * c + a * a - b * b) / (2 * c * a),
                                                  (a * a + b * b - c * c) / (2 * a * b)]), -1, 1)))


def quality(res, h):
    """gamma mean, % of triangles with an angle below 30 degrees, % of edges in [h/sqrt2, h sqrt2]
    (the formulas of ../shared/tools/meshcheck.py)."""
    P, t = res.nodes, res.triangles
    a = np.linalg.norm(P[t[:, 1]] - P[t[:, 2]], axis=1)
    b = np.linalg.norm(P[t[:, 2]] - P[t[:, 0]], axis=1)
    c = np.linalg.norm(P[t[:, 0]] - P[t[:, 1]], axis=1)
    area = 0.5 * np.linalg.norm(np.cross(P[t[:, 1]] - P[t[:, 0]], P[t[:, 2]] - P[t[:, 0]]), axis=1)
    s = 0.5 * (a + b + c)
    gamma = 2 * (area / s) / (a * b * c / (4 * area))
    ang = angles(a, b, c)
    e = np.unique(np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1), axis=0)
    L = np.linalg.norm(P[e[:, 0]] - P[e[:, 1]], axis=1) / h
    return gamma.mean(), 100 * np.mean(ang.min(axis=0) < 30), 100 * np.mean((L >= 2 ** -0.5) & (L <= 2 ** 0.5))


@needs_freecad
def test_blade_edges_are_mended_in_place():
    """propeller_and_shaft at diagonal/200: on each of the five blades, triangles standing on the
    leading edge cut across the blade's nose (radius 1-13 mm, blade 1.4-6 mm thick, h = 9.5) so
    deep that their centroid is nearer the other skin. They are refined in place (a local bound on
    their face: centroids off the surface by at most 0.8 of their distance to the other skin's
    tangent plane), not through size sources (which refined both skins and took the edges within
    [h/sqrt2, h sqrt2] to 94.50 %, below Gmsh 4.8's 95.89 %): only the five skins are meshed
    again, the mesh grows by about 1 %, no triangle is left nearer another face, and the
    quality stays above Gmsh Frontal's on this case (docs/benchmark.md: gamma 0.9516, 3.00 %
    below 30 degrees, 95.89 % of edges in the band)."""
    h = 1904.9886655946982 / 200
    shape = bc.read_shape(PS)
    blades = set(range(7, 18)) - {9}
    plain = pm.mesh_shape(PS, size=h, nearest_face_budget=0)
    assert len(wrong_side(shape, plain, h, blades)) >= 10  # measured: 15, 3 on each blade
    r = pm.mesh_shape(PS, size=h)
    nf = r.report["nearest_face_check"]
    assert nf["outcome"] == "refined" and nf["remaining"] == 0, nf
    assert nf["faces_remeshed_per_round"][0] == 5, nf  # the skins holding the flagged triangles
    # measured 8066 / 7986 (+1.0 %; before the nose-cap collapses of the per-triangle repair,
    # 8062 against a plain mesh with its caps)
    assert len(r.triangles) < 1.015 * len(plain.triangles)
    assert wrong_side(shape, r, h, blades) == []
    assert edge_uses(r).max() == 2 and edge_uses(r).min() == 2, "conformal and closed"
    g, poor, band = quality(r, h)
    assert g > 0.9516 and poor < 3.00 and band > 95.89, (g, poor, band)  # measured 0.9702, 1.43, 97.18 (meshcheck)


@needs_freecad
def test_refinement_never_turns_a_triangle_inside_out():
    """propeller_and_shaft at diagonal/100: the nearest-face zones refine the blades' noses
    (radius down to 1 mm, h = 19) in place. A split there may put the new point on the far side
    of the nose; the triangles it makes would face away from the surface at all three of their
    nodes. Before the split and centroid insertions checked for it, one such triangle was left on
    Face8 (normal opposite the CAD's at its three nodes); now none is. Each node is judged by the
    normal of its own face at its projection (FreeCAD's Surface.parameter / normalAt)."""
    import FreeCAD
    h = 1904.9886655946982 / 100
    shape = bc.read_shape(PS)
    r = pm.mesh_shape(PS, size=h)
    nf = r.report["nearest_face_check"]
    assert nf["outcome"] == "refined" and nf["remaining"] == 0, nf
    faces = shape.Faces
    P, t, tf = r.nodes, r.triangles, r.triangle_face
    normal = {}
    inside_out = []
    for k in range(len(t)):
        f = faces[int(tf[k]) - 1]
        nt = np.cross(P[t[k, 1]] - P[t[k, 0]], P[t[k, 2]] - P[t[k, 0]])
        away = 0
        for v in t[k]:
            key = (int(v), int(tf[k]))
            if key not in normal:
                u, w = f.Surface.parameter(FreeCAD.Vector(*P[v]))
                n = f.normalAt(u, w)
                normal[key] = np.array([n.x, n.y, n.z])
            away += np.dot(nt, normal[key]) < 0
        if away == 3:
            inside_out.append((k, int(tf[k])))
    assert inside_out == [], inside_out
    assert edge_uses(r).max() == 2 and edge_uses(r).min() == 2, "conformal and closed"


@needs_freecad
def test_no_triangle_lies_across_a_blade_nose():
    """propeller_and_shaft at diagonal/100: at each blade tip, the seam Edge42 (and its copies on
    the other blades) runs along a nose far thinner than h = 19. The only triangles on its last
    segment that face like the surface at all three nodes were caps (171 degrees) lying inside
    the blade, their centroid nearer the far side, where the normal is reversed: meshcheck
    counted the five of them flipped (0.23 %). The per-triangle repair may now collapse such a
    cap's apex when the triangle left faces like the surface at its centroid's projection.
    Judged like meshcheck: each centroid against its own face (the nearest face when it lies
    more than 0.05 h from it), normal at Surface.parameter."""
    import FreeCAD
    import Part
    h = 1904.9886655946982 / 100
    shape = bc.read_shape(PS)
    faces = shape.Faces
    r = pm.mesh_shape(PS, size=h)
    P, t, tf = r.nodes, r.triangles, r.triangle_face
    flipped = []
    for k in range(len(t)):
        tri = P[t[k]]
        c = tri.mean(0)
        f = faces[int(tf[k]) - 1]
        v = Part.Vertex(FreeCAD.Vector(*c))
        if v.distToShape(f)[0] > 0.05 * h:
            f = min(faces, key=lambda g: v.distToShape(g)[0])
        u, w = f.Surface.parameter(FreeCAD.Vector(*c))
        n = f.normalAt(u, w)
        if np.dot(np.cross(tri[1] - tri[0], tri[2] - tri[0]), [n.x, n.y, n.z]) < 0:
            flipped.append((k, int(tf[k])))
    side = [np.linalg.norm(P[t[:, i]] - P[t[:, j]], axis=1) for i, j in ((1, 2), (2, 0), (0, 1))]
    worst = angles(*side).min()
    assert flipped == [], flipped  # before: 5, one per blade tip (Faces 7, 10, 12, 14, 16)
    assert worst > 5, worst  # measured 6.94 degrees; before 3.29 (the caps)
    assert edge_uses(r).max() == 2 and edge_uses(r).min() == 2, "conformal and closed"
