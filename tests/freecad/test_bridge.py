# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD bridge (App, no GUI): Part shapes in, Mesh and FEM meshes out, objects saved/restored."""
import json
import os
import runpy
import sys
import time

import numpy as np
import pytest

import FreeCAD
import Part
import Mesh  # noqa: F401
import Fem  # noqa: F401

import freecad.paramesh as pm

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(HERE), "data")
M6 = os.path.join(DATA, "AileM6_with_sharp_TE.stp")


def test_macro_m6_saves_and_reopens_with_the_same_counts(tmp_path):
    macro = os.path.join(HERE, "macro_m6.py")
    assert len(open(macro).read().strip().splitlines()) <= 15
    out = str(tmp_path / "m6.FCStd")
    argv = sys.argv
    sys.argv = [macro, M6, out]
    try:
        runpy.run_path(macro, run_name="__main__")
    finally:
        sys.argv = argv
    doc = FreeCAD.ActiveDocument
    fem = [o for o in doc.Objects if o.TypeId == "Fem::FemMeshObjectPython"][0]
    counts = (fem.FemMesh.NodeCount, fem.FemMesh.FaceCount, fem.MeshFeature.Mesh.CountFacets)
    names = (fem.Name, fem.MeshFeature.Name)
    tris, quads = fem.FemMesh.TriangleCount, fem.FemMesh.QuadrangleCount
    assert fem.Status == "ok" and counts[1] == tris + quads and tris > 5000
    assert quads > 1000, "the leading-edge layer's rows of quads"
    assert counts[2] == tris + 2 * quads, "the Mesh::Feature splits each quad in two triangles"
    bl = [o for o in doc.Objects if o.Name.startswith("BoundaryLayer")]
    assert len(bl) == 1 and bl[0] in fem.BoundaryLayerList
    assert sorted(bl[0].References[0][1]) == ["Edge21", "Edge6"] and bl[0].References[0][0] == fem.Part
    assert fem.Part.Name == "Wing" and fem in doc.getObject("Analysis").Group
    FreeCAD.closeDocument(doc.Name)
    d2 = FreeCAD.openDocument(out)
    try:
        f2, m2 = d2.getObject(names[0]), d2.getObject(names[1])
        assert (f2.FemMesh.NodeCount, f2.FemMesh.FaceCount, m2.Mesh.CountFacets) == counts
        assert f2.Proxy is not None and f2.SchemaVersion == 1 and f2.Part.Name == "Wing"
        assert [FreeCAD.Units.Quantity(f2.Size).Value] == [16.75]
        # restored objects recompute without error
        f2.touch()
        d2.recompute()
        assert f2.Status == "ok" and f2.FemMesh.FaceCount == counts[1]
    finally:
        FreeCAD.closeDocument(d2.Name)


def test_femmesh_has_one_group_per_cad_face_and_nodes_on_the_cad():
    shape = Part.read(M6)
    r = pm.mesh_shape(shape, size=30.0)
    fm = r.to_femmesh()
    names = sorted(fm.getGroupName(g) for g in fm.Groups)
    assert names == sorted(f"Face{i}" for i in range(1, 12))
    for g in fm.Groups:
        i = int(fm.getGroupName(g)[4:])
        assert len(fm.getGroupElements(g)) == int((r.face_of_element == i).sum())
    # every node of Face10's triangles lies on Face10 ...
    f10 = shape.Faces[9]
    on10 = np.unique(r.triangles[r.triangle_face == 10].ravel())
    d = max(Part.Vertex(FreeCAD.Vector(*r.nodes[i])).distToShape(f10)[0] for i in on10)
    assert d <= 1e-9 * shape.BoundBox.DiagonalLength
    # ... so FreeCAD's node lookup by CAD face (what constraints use) finds them. (It skips CAD
    # vertices whose tolerance is large: Vertex6/7 of this STEP file, 0.017 and 0.033.)
    by_face = set(fm.getNodesByFace(f10))
    expected = {int(i) + 1 for i in on10}
    assert by_face <= expected and len(by_face) >= len(expected) - 2


def test_mesh_and_femmesh_are_built_fast():
    r = pm.mesh_shape(os.path.join(DATA, "bottle.brep"), size=0.5)
    t0 = time.perf_counter()
    m = r.to_mesh()
    t_mesh = time.perf_counter() - t0
    t0 = time.perf_counter()
    f = r.to_femmesh()
    t_fem = time.perf_counter() - t0
    n = len(r.triangles)
    assert m.CountFacets == n and m.CountPoints == len(r.nodes) and m.countSegments() == 71
    assert f.FaceCount == n and f.NodeCount == len(r.nodes)
    # measured on the dev machine: ~1.6 us/triangle (Mesh), ~5 us/triangle (FemMesh)
    assert t_mesh < 10e-6 * n and t_fem < 30e-6 * n, (t_mesh, t_fem, n)


def test_placement_is_respected():
    box = Part.makeBox(10, 20, 30)
    box.Placement = FreeCAD.Placement(FreeCAD.Vector(100, 0, 0), FreeCAD.Rotation(FreeCAD.Vector(0, 0, 1), 90))
    r = pm.mesh_shape(box, size=3.0)
    bb = box.BoundBox
    assert np.allclose(r.nodes.min(0), [bb.XMin, bb.YMin, bb.ZMin], atol=1e-9)
    assert np.allclose(r.nodes.max(0), [bb.XMax, bb.YMax, bb.ZMax], atol=1e-9)


def test_orientation_follows_the_outward_normal():
    s = Part.read(os.path.join(DATA, "screw.step"))
    r = pm.mesh_shape(s, size=2.0)
    P = r.nodes
    vol = 0.0
    for t in r.triangles:  # divergence theorem: positive volume for outward normals
        a, b, c = P[t]
        vol += np.dot(a, np.cross(b, c)) / 6.0
    assert vol == pytest.approx(s.Volume, rel=0.02)


def test_bad_shapes_raise_and_freecad_survives():
    with pytest.raises(pm.InputError):
        pm.mesh_shape(Part.Shape())
    with pytest.raises(pm.InputError, match="no face"):
        pm.mesh_shape(Part.makeLine(FreeCAD.Vector(0, 0, 0), FreeCAD.Vector(1, 0, 0)))
    with pytest.raises(TypeError):
        pm.mesh_shape(Part.makeBox(1, 1, 1), size=[1])
    with pytest.raises(pm.ParameterError, match="Edge40"):
        pm.mesh_shape(Part.makeBox(1, 1, 1), boundary_layers=[{"edges": [40], "first_height": 0.1, "layers": 2}])
    # still alive and working
    assert len(pm.mesh_shape(Part.makeSphere(1.0), size=0.3).triangles) > 50


def test_failed_mesh_object_reports_instead_of_raising_in_recompute():
    doc = FreeCAD.newDocument("bad")
    try:
        obj = pm.app_factories().make_surface_mesh(doc, None) if hasattr(pm, "app_factories") else None
        from freecad.paramesh.app.factories import make_surface_mesh
        obj = make_surface_mesh(doc, None)
        doc.recompute()
        assert obj.Status == "failed" and "no Part" in json.loads(obj.Report)["message"]
    finally:
        FreeCAD.closeDocument(doc.Name)


def test_femmesh_has_one_group_per_boundary_layer_spec():
    """Two layers (leading edge Edge21 with quads; trailing-edge side Edge6 as split triangles):
    each gets a group 'BoundaryLayer<k>' holding exactly its rows."""
    specs = [{"edges": [21], "first_height": 0.5, "growth": 1.2, "layers": 12},
             {"edges": [6], "first_height": 0.5, "growth": 1.2, "layers": 6, "quads": False}]
    r = pm.mesh_shape(M6, size=30.0, boundary_layers=specs)
    layer = r.layer_of_element
    assert layer.shape == r.face_of_element.shape and set(np.unique(layer)) == {0, 1, 2}
    # spec 1 is made of quads only, spec 2 of triangles only; the isotropic mesh has no quads
    assert (r.quad_layer == 1).all() and (r.triangle_layer != 1).all()
    assert (r.triangle_layer == 2).sum() > 0 and (r.quad_layer != 2).all()
    # the element counts match the report's per-spec counts
    rep = {b["spec"]: b for b in r.report["boundary_layers"]}
    assert (layer == 1).sum() == rep[1]["elements"] and (layer == 2).sum() == rep[2]["elements"]
    fm = r.to_femmesh()
    groups = {fm.getGroupName(g): set(fm.getGroupElements(g)) for g in fm.Groups}
    assert groups["BoundaryLayer1"] == set((np.flatnonzero(layer == 1) + 1).tolist())
    assert groups["BoundaryLayer2"] == set((np.flatnonzero(layer == 2) + 1).tolist())
    # the quads of layer 1 are the rows grown from Edge21 into both faces beside it: their first
    # rows sit on the edge's segments, one quad per segment and side
    seg = r.segments[r.segment_edge == 21]
    on_edge = set(seg.ravel().tolist())
    touching = [q for q in r.quads[r.quad_layer == 1] if len(on_edge.intersection(q.tolist())) == 2]
    assert len(touching) == 2 * len(seg)


def test_max_elements_property_stops_a_runaway_mesh():
    """MaxElements (default 5e7) bounds the run: over it the object fails with the reason in its
    Report instead of filling the memory; within it the mesh is made."""
    from freecad.paramesh.app.factories import make_surface_mesh
    doc = FreeCAD.newDocument("budget")
    try:
        part = doc.addObject("Part::Feature", "Screw")
        part.Shape = Part.read(os.path.join(DATA, "screw.step"))
        obj = make_surface_mesh(doc, part)
        assert obj.MaxElements == 50000000
        obj.Size = 1.0
        obj.MaxElements = 2000  # the screw at size 1 has about 4 400 triangles
        doc.recompute()
        assert obj.Status == "failed", obj.Status
        assert "max_elements = 2000 " in json.loads(obj.Report)["message"]
        obj.MaxElements = 100000
        doc.recompute()
        assert obj.Status == "ok" and 2000 < obj.FemMesh.FaceCount < 100000
    finally:
        FreeCAD.closeDocument(doc.Name)


def _femmesh_content(fm):
    nodes = fm.Nodes
    elems = {e: fm.getElementNodes(e) for e in fm.Faces}
    groups = {fm.getGroupName(g): sorted(fm.getGroupElements(g)) for g in fm.Groups}
    return {k: tuple(v) for k, v in nodes.items()}, elems, groups


def test_femmesh_filled_by_the_gui_worker_equals_the_direct_one_and_can_be_cancelled():
    """The GUI's worker thread fills an empty FemMesh made on the GUI thread (nodes and elements in
    short calls), and the groups are added afterwards: the result is the same FemMesh, node for
    node, element for element, group for group, as the direct conversion; a cancel stops it."""
    from freecad.paramesh.app.to_femmesh import (BuildCancelled, add_result_groups,
                                                  result_to_femmesh)
    from freecad.paramesh.app.factories import make_boundary_layer, make_surface_mesh
    from freecad.paramesh.gui.runner import MeshRunner
    specs = [{"edges": [21], "first_height": 0.5, "growth": 1.2, "layers": 12}]
    doc = FreeCAD.newDocument("WorkerFem")
    try:
        wing = doc.addObject("Part::Feature", "Wing")
        wing.Shape = Part.read(M6)
        mesh = make_surface_mesh(doc, wing, size=30.0)
        make_boundary_layer(doc, mesh, edges=[21], first_height=0.5, growth=1.2, layers=12)
        runner = MeshRunner().prepare(mesh)
        runner.start()
        assert runner.wait(120) and runner.state == "done", runner.error
        result, fm = runner.collect(), runner.collect_femmesh()
        assert runner.t_start < runner.t_meshed <= runner.t_end
        assert fm.FaceCount == len(result.triangles) + len(result.quads) > 0 and fm.GroupCount == 0
        assert fm.QuadrangleCount == len(result.quads) > 0
        mesh.Proxy.apply_result(mesh, result, fm)
        direct = pm.mesh_shape(wing.Shape, size=30.0, boundary_layers=specs).to_femmesh()
        assert _femmesh_content(mesh.FemMesh) == _femmesh_content(direct)
        assert mesh.FemMesh.getGroupName(mesh.FemMesh.Groups[-1]) == "BoundaryLayer1"
        # a cancel between chunks stops the fill
        calls = []
        with pytest.raises(BuildCancelled):
            result_to_femmesh(result, femmesh=Fem.FemMesh(), cancelled=lambda: calls.append(1) or len(calls) > 1)
        later = result_to_femmesh(result, groups=False, femmesh=Fem.FemMesh(), cancelled=lambda: False)
        add_result_groups(later, result)
        assert _femmesh_content(later) == _femmesh_content(direct)
    finally:
        FreeCAD.closeDocument(doc.Name)
