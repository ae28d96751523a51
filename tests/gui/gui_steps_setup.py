# SPDX-License-Identifier: LGPL-2.1-or-later
"""GUI test steps: the workbench and its commands, the M6 document, the surface-mesh panel
(parameter errors, element limit, quads, the M6 mesh), cancelling a long run, second order."""
import os
import time

import FreeCAD
import FreeCADGui
from PySide import QtGui

from gui_harness import (M6, METRICS, REPO, active_panel, apply_and_wait, check, combo_view, main_window,
                        press, report, run_panel_command, select_only, shot_widget, shot_window,
                        show_tasks_tab, surface_meshes, wait_ms, wait_until)


def step_workbench():
    wbs = FreeCADGui.listWorkbenches()
    check("workbench registered from the Mod folder", "ParaMeshWorkbench" in wbs, sorted(wbs)[:3])
    import freecad.paramesh as pm
    user = FreeCAD.getUserAppDataDir()
    where = os.path.realpath(os.path.dirname(pm.__file__))
    check("freecad.paramesh resolves through the freecad namespace (Mod link)",
          os.path.realpath(os.path.join(user, "Mod", "ParaMesh", "freecad", "paramesh")) == where, where)
    FreeCADGui.activateWorkbench("ParaMeshWorkbench")
    wait_ms(300)
    check("workbench active", FreeCADGui.activeWorkbench().name() == "ParaMeshWorkbench",
          FreeCADGui.activeWorkbench().name())
    ids = ["ParaMesh_SurfaceMesh", "ParaMesh_BoundaryLayer", "ParaMesh_LocalSize", "ParaMesh_Quality",
           "ParaMesh_Export", "ParaMesh_ToMesh", "ParaMesh_FromGmsh"]
    cmds = FreeCADGui.listCommands()
    check("all commands registered", all(i in cmds for i in ids), [i for i in ids if i not in cmds])
    icons = [os.path.join(REPO, "icons", i + ".svg") for i in ids + ["ParaMeshWorkbench"]]
    check("an SVG icon per command and for the workbench", all(os.path.isfile(p) for p in icons),
          [os.path.basename(p) for p in icons if not os.path.isfile(p)])
    tb = [t for t in main_window().findChildren(QtGui.QToolBar) if t.objectName() == "ParaMesh"]
    check("ParaMesh toolbar shown", bool(tb) and tb[0].isVisible())
    if tb:
        names = [a.text() for a in tb[0].actions()]
        check("toolbar holds the eight commands", len([a for a in tb[0].actions() if not a.isSeparator()]) >= 8, names)
    menus = [m.title() for m in main_window().menuBar().findChildren(QtGui.QMenu)]
    check("ParaMesh menu", any(t.replace("&", "") == "ParaMesh" for t in menus))


def step_document():
    import Part
    import ObjectsFem
    import FemGui
    doc = FreeCAD.newDocument("M6")
    wing = doc.addObject("Part::Feature", "Wing")
    wing.Shape = Part.read(M6)
    analysis = ObjectsFem.makeAnalysis(doc, "Analysis")
    FemGui.setActiveAnalysis(analysis)
    doc.recompute()
    view = FreeCADGui.ActiveDocument.ActiveView
    view.viewIsometric()
    view.fitAll()
    check("M6 imported", len(wing.Shape.Faces) == 11 and len(wing.Shape.Edges) == 21)
    return doc, wing, analysis


def step_surface_mesh(doc, wing, analysis):
    from freecad.paramesh.gui import commands
    FreeCADGui.Selection.clearSelection()
    check("surface mesh command inactive without a selection", not commands.SurfaceMeshCommand().IsActive())
    FreeCADGui.Selection.addSelection(doc.Name, wing.Name)
    check("surface mesh command active with the wing selected", commands.SurfaceMeshCommand().IsActive())
    wait_ms(200)  # let the toolbar update its enabled state
    tb = [t for t in main_window().findChildren(QtGui.QToolBar) if t.objectName() == "ParaMesh"]
    if tb:
        shot_widget(tb[0], "toolbar.png")
    shot_window("window_workbench.png")
    FreeCADGui.runCommand("ParaMesh_SurfaceMesh")
    ok = wait_until(lambda: active_panel() is not None, 5)
    panel = active_panel()
    meshes = surface_meshes(doc)
    check("command created one surface mesh and opened its panel", ok and len(meshes) == 1)
    mesh = meshes[0]
    check("new mesh joined the active analysis", mesh in analysis.Group)
    check("creation is an undo step", "Create ParaMesh surface mesh" in doc.UndoNames, doc.UndoNames[:3])
    check("mesh links the wing", mesh.Part == wing)
    show_tasks_tab()
    tips = {f.prop: f.widget.toolTip() for f in panel.params.fields}
    check("every parameter has a tooltip", all(tips.values()), [k for k, v in tips.items() if not v])
    limits = {k: panel.params.values()[k] for k in ("MaxElements", "NearestFaceBudget", "NearestFaceCheck")}
    check("the panel shows the element limit and the nearest-face settings",
          limits == {"MaxElements": mesh.MaxElements, "NearestFaceBudget": mesh.NearestFaceBudget,
                     "NearestFaceCheck": mesh.NearestFaceCheck} and limits["MaxElements"] == 50000000, limits)
    size_text = panel.params.widget("Size").text()
    check("lengths shown with units", "mm" in size_text, size_text)

    # a parameter error is a normal error in the panel, never a dialog
    panel.params.set_value("Size", 16.75)
    panel.params.set_value("MinSize", 20.0)
    panel.params.set_value("MaxSize", 10.0)
    state = apply_and_wait(panel, 30)
    err = panel.run.error
    check("a parameter error is shown in the panel", state == "failed" and "min_size" in err, err[:200])
    check("the error is in the panel's summary", "min_size" in panel.run.summary.text())
    check("no dialog box for a meshing error", QtGui.QApplication.activeModalWidget() is None)
    panel.params.set_value("MinSize", 0.0)
    panel.params.set_value("MaxSize", 0.0)
    # the element limit set in the panel reaches the run: the wing at 16.75 needs more than 1000
    panel.params.set_value("MaxElements", 1000)
    state = apply_and_wait(panel, 30)
    err = panel.run.error
    check("MaxElements from the panel stops a run over it, in the panel",
          state == "failed" and "max_elements" in err and mesh.MaxElements == 1000, err[:200])
    panel.params.set_value("MaxElements", 50000000)
    # quad-dominant: either meshed with quads or (older cores) a normal error in the panel
    panel.params.set_value("Quads", True)
    state = apply_and_wait(panel, 30)
    quads = report(mesh).get("counts", {}).get("quads", 0)
    check("quads=True meshes quads or is reported in the panel",
          (state == "done" and quads > 0) or (state == "failed" and "quad" in panel.run.error.lower()),
          f"{state} quads={quads} {panel.run.error[:100]}")
    METRICS["quad_dominant_quads"] = quads
    panel.params.set_value("Quads", False)

    panel.params.set_value("Size", 16.75)
    panel.params.set_value("ElementOrder", "1st")
    state = apply_and_wait(panel, 60)
    r = report(mesh)
    check("M6 meshed from the panel (size 16.75)", state == "done" and mesh.Status == "ok",
          f"{state} {mesh.Status} {r.get('message')}")
    tri = r.get("counts", {}).get("triangles", 0)
    check("FemMesh holds the reported triangles", mesh.FemMesh.FaceCount == tri and tri > 10000,
          f"{mesh.FemMesh.FaceCount} vs {tri}")
    check("size stored in the object", abs(float(mesh.Size) - 16.75) < 1e-9, float(mesh.Size))
    check("object not left touched (no re-mesh on recompute)", "Touched" not in mesh.State, mesh.State)
    METRICS["m6_triangles"] = tri
    METRICS["m6_run_seconds"] = round(panel.run.last_seconds, 3)
    FreeCADGui.ActiveDocument.ActiveView.fitAll()
    shot_widget(combo_view(), "task_surface_mesh.png")
    shot_window("window_surface_mesh.png")
    press(QtGui.QDialogButtonBox.Ok)
    check("OK closes the panel", wait_until(lambda: active_panel() is None and not FreeCADGui.Control.activeDialog(), 5))
    return mesh


def step_cancel(doc, wing):
    before = sorted(o.Name for o in doc.Objects)
    select_only(doc, wing)
    panel = run_panel_command("ParaMesh_SurfaceMesh")
    new = panel.mesh
    panel.params.set_value("Size", 0.5)
    panel.params.set_value("Threads", 0)
    press(QtGui.QDialogButtonBox.Apply)
    running = wait_until(lambda: panel.run.running and panel.run.runner.elapsed > 1.5, 10)
    check("size 0.5 run started in the background", running, panel.run.state)
    stage = panel.run.runner.stage
    t0 = time.perf_counter()
    panel.run.cancel_button.click()
    # the worker stops first; the panel learns it through a queued signal (or its 200 ms timer)
    stopped = wait_until(lambda: not panel.run.running and panel.run.state != "running", 10, step=5)
    dt = time.perf_counter() - t0
    METRICS["cancel_seconds"] = round(dt, 3)
    check("cancel takes effect quickly (< 1 s)", stopped and panel.run.state == "cancelled" and dt < 1.0,
          f"{dt * 1000:.0f} ms during '{stage}', state {panel.run.state}")
    check("cancelled mesh left empty", new.FemMesh.NodeCount == 0)
    press(QtGui.QDialogButtonBox.Cancel)
    wait_until(lambda: active_panel() is None, 5)
    wait_ms(100)
    after = sorted(o.Name for o in doc.Objects)
    check("cancelling the new mesh leaves no partial object", after == before, set(after) ^ set(before))


def step_second_order(doc, mesh):
    FreeCADGui.ActiveDocument.setEdit(mesh.Name)
    wait_until(lambda: active_panel() is not None, 5)
    panel = active_panel()
    check("double-click/edit reopens the surface mesh panel without 'created' flag",
          panel is not None and not panel.created)
    panel.params.set_value("ElementOrder", "2nd")
    state = apply_and_wait(panel, 60)
    fm = mesh.FemMesh
    n = {len(fm.getElementNodes(e)) for e in list(fm.Faces)[:2000]}
    check("2nd order gives tria6 / quad8 elements", state == "done" and n <= {6, 8} and 6 in n,
          f"{n} state={state} order={mesh.ElementOrder} error={panel.run.error!r} status={mesh.Status}")
    panel.params.set_value("ElementOrder", "1st")
    press(QtGui.QDialogButtonBox.Ok)
    closed = wait_until(lambda: active_panel() is None, 60)
    n = {len(mesh.FemMesh.getElementNodes(e)) for e in list(mesh.FemMesh.Faces)[:2000]}
    check("back to 1st order", closed and n <= {3, 4}, n)
