# SPDX-License-Identifier: LGPL-2.1-or-later
"""GUI test steps: the mesh's children, a leading-edge boundary layer (proposed edges, failing
faces named in the panel, the layer meshed) and a local size picked on two faces."""

import FreeCADGui
from PySide import QtGui

from gui_harness import (METRICS, active_panel, apply_and_wait, check, combo_view, press, report,
                        run_panel_command, select_only, shot_view, shot_widget, shot_window, show_model_tab,
                        wait_ms, wait_until, zoom_to)


def step_boundary_layer(doc, wing, mesh):
    import freecad.paramesh as pm
    from freecad.paramesh.gui import commands
    select_only(doc, wing, "Edge21")
    check("boundary layer command active", commands.BoundaryLayerCommand().IsActive())
    panel = run_panel_command("ParaMesh_BoundaryLayer")
    bl = panel.bl
    check("boundary layer created from the selected edge",
          [(o.Name, tuple(s)) for o, s in bl.References] == [(wing.Name, ("Edge21",))], bl.References)
    check("boundary layer listed in the mesh", list(mesh.BoundaryLayerList) == [bl])
    check("boundary layer is a child in the tree", bl in mesh.ViewObject.Proxy.claimChildren())
    check("creation is an undo step", doc.UndoNames and doc.UndoNames[0] == "Create ParaMesh boundary layer",
          doc.UndoNames[:2])
    has_propose = hasattr(pm, "propose_leading_edges")
    check("'propose leading edges' shown iff the core has it", (not panel.propose.isHidden()) == has_propose,
          f"shown={not panel.propose.isHidden()} core={has_propose}")
    if has_propose:
        panel.propose.click()
        names = panel.refs.names()
        check("proposal contains the leading edge Edge21", "Edge21" in names, names)
        extra = [n for n in names if n != "Edge21"]
        if extra:
            for i in range(panel.refs.list.count()):
                panel.refs.list.item(i).setSelected(panel.refs.list.item(i).text() in extra)
            panel.refs.remove.click()
        check("other proposals removed again", panel.refs.names() == ["Edge21"], panel.refs.names())
    # a layer thicker than the model's diagonal (2 mm x 1.3^40: 240 m on a 1.7 m wing) is refused,
    # the panel naming the parameter
    panel.refs.add("Edge9")
    panel.params.set_value("FirstHeight", 2.0)
    panel.params.set_value("Growth", 1.3)
    panel.params.set_value("Layers", 40)
    state = apply_and_wait(panel, 60)
    shown = panel.run.summary.text() + panel.run.log.toPlainText()
    check("a layer thicker than the model is refused, the panel saying why",
          state == "failed" and "diagonal" in shown, f"state {state}: {shown[-300:]}")
    # an aggressive layer on two edges (14 rows, 256 mm): faces that cannot be meshed are named
    panel.params.set_value("Layers", 14)
    state = apply_and_wait(panel, 60)
    r = report(mesh)
    bad = [f["name"] for f in r.get("faces", []) if f.get("status") != "ok"]
    shown = panel.run.summary.text() + panel.run.log.toPlainText()
    check("every face that did not mesh is named in the panel", state == "done" and all(b in shown for b in bad),
          f"status {r.get('status')}, faces not ok: {bad}")
    if bad:
        shot_widget(combo_view(), "task_boundary_layer_failed_face.png")
    from freecad.paramesh.gui.widgets import report_lines
    lines = report_lines({"status": "degraded", "message": "1 of 2 faces failed", "counts": {},
                          "faces": [{"name": "Face1", "status": "ok"},
                                    {"name": "Face7", "surface": "bspline", "status": "failed",
                                     "error": "boundary recovery failed"}]})
    check("report lines name the failing face and its reason",
          any(lv == "error" and "Face7" in t and "boundary recovery failed" in t for lv, t in lines), lines)
    panel.refs.remove_names({"Edge9"})
    panel.params.set_value("FirstHeight", 0.5)
    panel.params.set_value("Growth", 1.2)
    panel.params.set_value("Layers", 20)
    FreeCADGui.updateGui()
    shot_widget(combo_view(), "task_boundary_layer.png")
    shot_window("window_boundary_layer_panel.png")
    press(QtGui.QDialogButtonBox.Ok)  # writes the values, meshes, closes when done
    closed = wait_until(lambda: active_panel() is None, 60)
    r = report(mesh)
    c = r.get("counts", {})
    check("OK meshed with the leading-edge layer and closed", closed and mesh.Status == "ok",
          f"{mesh.Status} {r.get('message')}")
    check("boundary-layer quads present", c.get("quads", 0) > 1000, c)
    check("FemMesh holds triangles + quads", mesh.FemMesh.FaceCount == c.get("triangles", 0) + c.get("quads", 0),
          mesh.FemMesh.FaceCount)
    check("boundary layer values stored", (float(bl.FirstHeight), bl.Growth, bl.Layers) == (0.5, 1.2, 20),
          (float(bl.FirstHeight), bl.Growth, bl.Layers))
    METRICS["bl_triangles"], METRICS["bl_quads"] = c.get("triangles"), c.get("quads")
    view = FreeCADGui.ActiveDocument.ActiveView
    view.viewIsometric()
    view.fitAll()
    shot_view("wing_mesh.png")
    zoom_to(view, (30.0, 0.0, 0.0), 120.0, direction=(0.3, 0.8, -0.5))
    shot_view("wing_leading_edge_layer.png")
    view.fitAll()
    return bl


def step_local_size(doc, wing, mesh):
    tri_before = report(mesh)["counts"]["triangles"]
    select_only(doc, wing, "Face9")
    panel = run_panel_command("ParaMesh_LocalSize")
    ls = panel.ls
    check("local size created from the selected face",
          [(o.Name, tuple(s)) for o, s in ls.References] == [(wing.Name, ("Face9",))], ls.References)
    # a second face picked in the 3D view while the panel is open
    select_only(doc, wing, "Face3")
    wait_ms(50)
    check("picking a face in the 3D view adds it", panel.refs.names() == ["Face9", "Face3"], panel.refs.names())
    panel.params.set_value("Size", 5.0)
    state = apply_and_wait(panel, 60)
    tri = report(mesh)["counts"]["triangles"]
    check("local size refines the mesh", state == "done" and mesh.Status == "ok" and tri > tri_before * 1.1,
          f"{tri_before} -> {tri}")
    check("local size spec from References",
          [(s.kind, s.entities, s.size) for s in ls.Proxy.spec(ls)] == [("face", [9, 3], 5.0)],
          ls.Proxy.spec(ls))
    press(QtGui.QDialogButtonBox.Ok)
    check("OK without changes closes at once", wait_until(lambda: active_panel() is None, 5))
    check("mesh lists its children", list(mesh.LocalSizeList) == [ls]
          and set(mesh.ViewObject.Proxy.claimChildren()) == set(mesh.BoundaryLayerList) | {ls})
    show_model_tab(mesh)
    shot_window("window_tree.png")
    return ls
