# SPDX-License-Identifier: LGPL-2.1-or-later
"""ParaMesh GUI test, run inside FreeCAD 0.20 (GUI) under Xvfb: `bash tests/gui/run.sh`.

Drives the workbench as a user would: activates it, imports the ONERA M6 wing, runs every command
through FreeCADGui.runCommand, fills and presses the task panels, cancels a long mesh, meshes with a
leading-edge boundary layer, opens the quality view, exports, saves and reopens the document, and
measures the event-loop latency while a ~1 million triangle mesh is computed. Screenshots go to
$PARAMESH_GUI_OUT (default out/gui). Writes summary.txt / summary.json there and quits FreeCAD with
status 0 (all checks passed) or 1.
"""
import faulthandler
import json
import os
import sys
import threading
import time
import traceback

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

REPO = os.environ.get("PARAMESH_REPO") or os.getcwd()
OUT = os.environ.get("PARAMESH_GUI_OUT") or os.path.join(REPO, "out", "gui")
M6 = os.path.join(REPO, "tests", "data", "AileM6_with_sharp_TE.stp")
BIG_SIZE = float(os.environ.get("PARAMESH_GUI_BIG_SIZE", "1.9"))  # ~1.0 M triangles on the M6
WATCHDOG_S = float(os.environ.get("PARAMESH_GUI_WATCHDOG", "360"))
os.makedirs(OUT, exist_ok=True)

_T0 = time.perf_counter()
_log_file = open(os.path.join(OUT, "gui_test.log"), "w")
_fault_file = open(os.path.join(OUT, "faulthandler.log"), "w")
faulthandler.enable(_fault_file, all_threads=True)
CHECKS = []
METRICS = {}
SHOTS = []


def log(msg):
    line = f"[{time.perf_counter() - _T0:7.1f}s] {msg}"
    for stream in (sys.__stdout__, _log_file):
        try:
            stream.write(line + "\n")
            stream.flush()
        except Exception:
            pass


def check(name, ok, detail=""):
    CHECKS.append((name, bool(ok), str(detail)))
    log(f"{'PASS' if ok else 'FAIL'} {name}{': ' + str(detail) if detail else ''}")
    return bool(ok)


def wait_ms(ms):
    loop = QtCore.QEventLoop()
    QtCore.QTimer.singleShot(int(ms), loop.quit)
    loop.exec_()


def wait_until(cond, timeout, step=20):
    t0 = time.perf_counter()
    while True:
        try:
            if cond():
                return True
        except Exception:
            pass
        if time.perf_counter() - t0 > timeout:
            return False
        wait_ms(step)


# -- report view observer ------------------------------------------------------------------------------


class ReportObserver:
    """Watches FreeCAD's Report view (where FreeCAD.Console and Python errors go) for errors: red
    text or tracebacks. FreeCAD 0.20 has no Python console observer API, so the Report view's
    document is observed instead."""

    def __init__(self):
        mw = FreeCADGui.getMainWindow()
        self.view = mw.findChild(QtGui.QTextEdit, "Report view")
        self.errors = []
        self._seen_blocks = 0
        if self.view is not None:
            self.view.document().contentsChanged.connect(self.scan)
        p = FreeCAD.ParamGet("User parameter:BaseApp/Preferences/OutputWindow")
        c = p.GetUnsigned("colorError", 0xFF000000)
        self.error_rgb = ((c >> 24) & 0xFF, (c >> 16) & 0xFF, (c >> 8) & 0xFF)

    def scan(self):
        if self.view is None:
            return
        doc = self.view.document()
        block = doc.findBlockByNumber(max(0, self._seen_blocks - 1))
        while block.isValid():
            it = block.begin()
            while not it.atEnd():
                frag = it.fragment()
                if frag.isValid():
                    col = frag.charFormat().foreground().color()
                    text = frag.text().strip()
                    if text and ((col.red(), col.green(), col.blue()) == self.error_rgb or "Traceback" in text):
                        key = (block.blockNumber(), text)
                        if key not in [(b, t) for b, t in self.errors]:
                            self.errors.append(key)
                it += 1
            self._seen_blocks = block.blockNumber() + 1
            block = block.next()

    def texts(self):
        self.scan()
        return [t for _b, t in self.errors]


# -- GUI helpers ----------------------------------------------------------------------------------------


def main_window():
    return FreeCADGui.getMainWindow()


def task_buttons(which):
    """The standard button `which` of the open task dialog."""
    for box in main_window().findChildren(QtGui.QDialogButtonBox):
        b = box.button(which)
        if b is not None and b.isVisible():
            return box
    return None


def press(which):
    box = None
    if wait_until(lambda: task_buttons(which) is not None, 3):
        box = task_buttons(which)
    if box is None:
        found = [(b.objectName(), b.isVisible(), [x.text() for x in b.buttons()])
                 for b in main_window().findChildren(QtGui.QDialogButtonBox)]
        raise RuntimeError(f"no task dialog button {which} visible; button boxes: {found}")
    b = box.button(which)
    if b is None:
        raise RuntimeError(f"task dialog has no button {which}")
    b.click()


def shot_view(name, width=1200, height=800):
    path = os.path.join(OUT, name)
    FreeCADGui.updateGui()
    FreeCADGui.ActiveDocument.ActiveView.saveImage(path, width, height, "White")
    SHOTS.append(path)
    log(f"screenshot {path}")
    return path


def shot_window(name):
    """The whole main window as on screen (including the OpenGL view, read from the X server)."""
    path = os.path.join(OUT, name)
    FreeCADGui.updateGui()
    wait_ms(150)
    mw = main_window()
    pix = QtGui.QGuiApplication.primaryScreen().grabWindow(mw.winId())
    pix.save(path)
    SHOTS.append(path)
    log(f"screenshot {path}")
    return path


def shot_widget(widget, name):
    path = os.path.join(OUT, name)
    FreeCADGui.updateGui()
    widget.grab().save(path)
    SHOTS.append(path)
    log(f"screenshot {path}")
    return path


def combo_view():
    for d in main_window().findChildren(QtGui.QDockWidget):
        if d.objectName() == "Combo View":
            return d
    return None


def show_tasks_tab():
    cv = combo_view()
    if cv is None:
        return
    for tw in cv.findChildren(QtGui.QTabWidget):
        for i in range(tw.count()):
            if tw.tabText(i) == "Tasks":
                tw.setCurrentIndex(i)


def show_model_tab(select=None):
    cv = combo_view()
    if cv is None:
        return
    for tw in cv.findChildren(QtGui.QTabWidget):
        for i in range(tw.count()):
            if tw.tabText(i) == "Model":
                tw.setCurrentIndex(i)
    for tree in cv.findChildren(QtGui.QTreeWidget):
        tree.expandAll()
    if select is not None:
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(select.Document.Name, select.Name)
    wait_ms(200)


def fill_file_dialog(path, timeout=10.0):
    """Answers the next modal file dialog with path (as a user typing it and pressing Save)."""
    t0 = time.perf_counter()

    def attempt():
        w = QtGui.QApplication.activeModalWidget()
        if isinstance(w, QtGui.QFileDialog):
            edit = w.findChild(QtGui.QLineEdit, "fileNameEdit")
            if edit is not None:
                edit.setText(path)  # typed by the "user"; selectFile() is asynchronous across folders
            else:
                w.selectFile(path)
            w.accept()
        elif time.perf_counter() - t0 < timeout:
            QtCore.QTimer.singleShot(50, attempt)
    QtCore.QTimer.singleShot(50, attempt)


class Ticker:
    """A 20 ms QTimer recording when it fires: the gaps show how long the event loop was blocked."""

    def __init__(self, interval=20):
        self.timer = QtCore.QTimer()
        self.timer.setInterval(interval)
        self.timer.timeout.connect(self._tick)
        self.ticks = []

    def _tick(self):
        self.ticks.append(time.perf_counter())

    def start(self):
        self.ticks = [time.perf_counter()]
        self.timer.start()

    def stop(self):
        self.timer.stop()

    def gaps_over(self, limit, origin, until=None):
        ts = [t for t in self.ticks if until is None or t <= until]
        return [(round(a - origin, 3), round((b - a) * 1000, 1)) for a, b in zip(ts, ts[1:]) if b - a > limit]

    def max_gap(self, until=None):
        ts = [t for t in self.ticks if until is None or t <= until]
        if until is not None:
            ts.append(until)
        gaps = [b - a for a, b in zip(ts, ts[1:])]
        return (max(gaps) if gaps else 0.0), len(ts)


class PaintCounter(QtCore.QObject):
    def __init__(self, widget):
        super().__init__()
        self.count = 0
        widget.installEventFilter(self)

    def eventFilter(self, obj, event):
        if event.type() == QtCore.QEvent.Paint:
            self.count += 1
        return False


def active_panel():
    from freecad.paramesh.gui import task_base
    return task_base.ACTIVE


def surface_meshes(doc):
    return [o for o in doc.Objects if getattr(getattr(o, "Proxy", None), "Type", "") == "ParaMesh::SurfaceMesh"]


def report(obj):
    return json.loads(obj.Report or "{}")


def wait_run(panel, timeout):
    ok = wait_until(lambda: panel.run.state in ("done", "failed", "cancelled") and not panel.run.running, timeout)
    return ok and panel.run.state


# -- the test -------------------------------------------------------------------------------------------


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
           "ParaMesh_Export", "ParaMesh_ToMesh"]
    cmds = FreeCADGui.listCommands()
    check("all commands registered", all(i in cmds for i in ids), [i for i in ids if i not in cmds])
    icons = [os.path.join(REPO, "icons", i + ".svg") for i in ids + ["ParaMeshWorkbench"]]
    check("an SVG icon per command and for the workbench", all(os.path.isfile(p) for p in icons),
          [os.path.basename(p) for p in icons if not os.path.isfile(p)])
    tb = [t for t in main_window().findChildren(QtGui.QToolBar) if t.objectName() == "ParaMesh"]
    check("ParaMesh toolbar shown", bool(tb) and tb[0].isVisible())
    if tb:
        names = [a.text() for a in tb[0].actions()]
        check("toolbar holds the six commands", len([a for a in tb[0].actions() if not a.isSeparator()]) >= 6, names)
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
    press(QtGui.QDialogButtonBox.Apply)
    state = wait_run(panel, 30)
    err = panel.run.error
    check("a parameter error is shown in the panel", state == "failed" and "min_size" in err, err[:200])
    check("the error is in the panel's summary", "min_size" in panel.run.summary.text())
    check("no dialog box for a meshing error", QtGui.QApplication.activeModalWidget() is None)
    panel.params.set_value("MinSize", 0.0)
    panel.params.set_value("MaxSize", 0.0)
    # the element limit set in the panel reaches the run: the wing at 16.75 needs more than 1000
    panel.params.set_value("MaxElements", 1000)
    press(QtGui.QDialogButtonBox.Apply)
    state = wait_run(panel, 30)
    err = panel.run.error
    check("MaxElements from the panel stops a run over it, in the panel",
          state == "failed" and "max_elements" in err and mesh.MaxElements == 1000, err[:200])
    panel.params.set_value("MaxElements", 50000000)
    # quad-dominant: either meshed with quads or (older cores) a normal error in the panel
    panel.params.set_value("Quads", True)
    press(QtGui.QDialogButtonBox.Apply)
    state = wait_run(panel, 30)
    quads = report(mesh).get("counts", {}).get("quads", 0)
    check("quads=True meshes quads or is reported in the panel",
          (state == "done" and quads > 0) or (state == "failed" and "quad" in panel.run.error.lower()),
          f"{state} quads={quads} {panel.run.error[:100]}")
    METRICS["quad_dominant_quads"] = quads
    panel.params.set_value("Quads", False)

    panel.params.set_value("Size", 16.75)
    panel.params.set_value("ElementOrder", "1st")
    press(QtGui.QDialogButtonBox.Apply)
    state = wait_run(panel, 60)
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
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, wing.Name)
    FreeCADGui.runCommand("ParaMesh_SurfaceMesh")
    wait_until(lambda: active_panel() is not None, 5)
    panel = active_panel()
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


def step_boundary_layer(doc, wing, mesh):
    import freecad.paramesh as pm
    from freecad.paramesh.gui import commands
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, wing.Name, "Edge21")
    check("boundary layer command active", commands.BoundaryLayerCommand().IsActive())
    FreeCADGui.runCommand("ParaMesh_BoundaryLayer")
    wait_until(lambda: active_panel() is not None, 5)
    panel = active_panel()
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
    # an aggressive layer on two edges: faces that cannot be meshed are named in the panel
    panel.refs.add("Edge9")
    panel.params.set_value("FirstHeight", 2.0)
    panel.params.set_value("Growth", 1.3)
    panel.params.set_value("Layers", 40)
    press(QtGui.QDialogButtonBox.Apply)
    state = wait_run(panel, 60)
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


def zoom_to(view, center, height, direction=(0.3, 0.8, -0.5)):
    cam = view.getCameraNode()
    d = FreeCAD.Vector(*direction)
    d.normalize()
    view.setViewDirection((d.x, d.y, d.z))
    pos = FreeCAD.Vector(*center) - d * (height * 5)
    cam.position.setValue(pos.x, pos.y, pos.z)
    cam.focalDistance.setValue(height * 5)
    if hasattr(cam, "height"):
        cam.height.setValue(height)
    FreeCADGui.updateGui()


def step_local_size(doc, wing, mesh):
    tri_before = report(mesh)["counts"]["triangles"]
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, wing.Name, "Face9")
    FreeCADGui.runCommand("ParaMesh_LocalSize")
    wait_until(lambda: active_panel() is not None, 5)
    panel = active_panel()
    ls = panel.ls
    check("local size created from the selected face",
          [(o.Name, tuple(s)) for o, s in ls.References] == [(wing.Name, ("Face9",))], ls.References)
    # a second face picked in the 3D view while the panel is open
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, wing.Name, "Face3")
    wait_ms(50)
    check("picking a face in the 3D view adds it", panel.refs.names() == ["Face9", "Face3"], panel.refs.names())
    panel.params.set_value("Size", 5.0)
    press(QtGui.QDialogButtonBox.Apply)
    state = wait_run(panel, 60)
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


def step_second_order(doc, mesh):
    FreeCADGui.ActiveDocument.setEdit(mesh.Name)
    wait_until(lambda: active_panel() is not None, 5)
    panel = active_panel()
    check("double-click/edit reopens the surface mesh panel without 'created' flag",
          panel is not None and not panel.created)
    panel.params.set_value("ElementOrder", "2nd")
    press(QtGui.QDialogButtonBox.Apply)
    state = wait_run(panel, 60)
    fm = mesh.FemMesh
    n = {len(fm.getElementNodes(e)) for e in list(fm.Faces)[:2000]}
    check("2nd order gives tria6 / quad8 elements", state == "done" and n <= {6, 8} and 6 in n,
          f"{n} state={state} order={mesh.ElementOrder} error={panel.run.error!r} status={mesh.Status}")
    panel.params.set_value("ElementOrder", "1st")
    press(QtGui.QDialogButtonBox.Ok)
    closed = wait_until(lambda: active_panel() is None, 60)
    n = {len(mesh.FemMesh.getElementNodes(e)) for e in list(mesh.FemMesh.Faces)[:2000]}
    check("back to 1st order", closed and n <= {3, 4}, n)


def step_quality(doc, mesh):
    from freecad.paramesh.gui import task_quality
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, mesh.Name)
    FreeCADGui.runCommand("ParaMesh_Quality")
    ok = wait_until(lambda: task_quality.ACTIVE is not None, 10)
    q = task_quality.ACTIVE
    check("quality view opened", ok and q is not None)
    if q is None:
        return
    show_tasks_tab()
    c = report(mesh)["counts"]
    n = c["triangles"] + c["quads"]
    check("quality covers every element", len(q.quality) == n == mesh.FemMesh.FaceCount, (len(q.quality), n))
    check("angle histogram counts every corner",
          int(q.h_angle.counts.sum()) == 3 * c["triangles"] + 4 * c["quads"], int(q.h_angle.counts.sum()))
    check("radius-ratio and edge-ratio histograms filled",
          int(q.h_gamma.counts.sum()) == n and int(q.h_edge.counts.sum()) == n)
    check("colour map on every element", getattr(q, "colored", 0) == mesh.FemMesh.FaceCount, getattr(q, "colored", 0))
    rr = q.quality.radius_ratio
    worst = q.rows[0]
    check("worst element listed first", rr[worst] == rr.min() and q.table.rowCount() == q.WORST,
          f"{rr[worst]:.4f} vs {rr.min():.4f}")
    METRICS["quality"] = {k: (round(v, 4) if isinstance(v, float) else v) for k, v in q.quality.summary().items()}
    view = FreeCADGui.ActiveDocument.ActiveView
    view.viewIsometric()
    view.fitAll()
    shot_view("quality_colormap.png")
    shot_widget(combo_view(), "task_quality.png")
    q.select_row(0)
    wait_ms(100)
    hn = list(mesh.ViewObject.HighlightedNodes)
    check("selecting a worst element highlights its nodes",
          sorted(hn) == sorted(int(q.arrays.node_ids[i]) for i in q.quality.corners(worst)), hn)
    shot_view("quality_worst_element.png")
    shot_window("window_quality.png")
    q.combo.setCurrentIndex(1)  # minimum angle
    wait_ms(50)
    check("colour by minimum angle", q.metric == "min_angle" and q.table.rowCount() > 0)
    zoom_to(view, (30.0, 0.0, 0.0), 120.0, direction=(0.3, 0.8, -0.5))
    shot_view("quality_min_angle_leading_edge.png")
    press(QtGui.QDialogButtonBox.Close)
    check("quality view closed", wait_until(lambda: task_quality.ACTIVE is None, 5))
    view.fitAll()


def step_export(doc, mesh, tag=""):
    paths = {}
    for ext in (".msh", ".vtu", ".stl", ".inp"):
        path = os.path.join(OUT, f"m6{tag}{ext}")
        if os.path.exists(path):
            os.remove(path)
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(doc.Name, mesh.Name)
        fill_file_dialog(path)
        FreeCADGui.runCommand("ParaMesh_Export")
        wait_until(lambda: os.path.exists(path) and os.path.getsize(path) > 0, 60)
        paths[ext] = path
    heads = {}
    for ext, p in paths.items():
        if os.path.exists(p):
            with open(p, "rb") as f:
                heads[ext] = f.read(200)
    check(f"export{tag} wrote msh, vtu, stl, inp", len(heads) == 4, sorted(heads))
    check(f"export{tag} formats look right",
          heads.get(".msh", b"").startswith(b"$MeshFormat") and b"VTKFile" in heads.get(".vtu", b"")
          and b"*" in heads.get(".inp", b"") and len(heads.get(".stl", b"")) > 80,
          {k: v[:20] for k, v in heads.items()})
    return paths


def step_to_mesh(doc, mesh):
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, mesh.Name)
    FreeCADGui.runCommand("ParaMesh_ToMesh")
    mf = mesh.MeshFeature
    c = report(mesh)["counts"]
    check("Mesh feature created (quads split in two)",
          mf is not None and mf.Mesh.CountFacets == c["triangles"] + 2 * c["quads"],
          mf and mf.Mesh.CountFacets)
    check("Mesh feature has one segment per CAD face", mf is not None and mf.Mesh.countSegments() == 11,
          mf and mf.Mesh.countSegments())
    return mf


def step_save_reopen(doc, mesh):
    path = os.path.join(OUT, "m6_gui.FCStd")
    counts = (mesh.FemMesh.NodeCount, mesh.FemMesh.FaceCount)
    names = {"mesh": mesh.Name, "bl": mesh.BoundaryLayerList[0].Name, "ls": mesh.LocalSizeList[0].Name,
             "mf": mesh.MeshFeature.Name}
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    wait_ms(200)
    doc = FreeCAD.openDocument(path)
    wait_ms(300)
    m = doc.getObject(names["mesh"])
    check("reopened: surface mesh with its proxy and schema", m is not None and m.Proxy is not None
          and m.SchemaVersion == 1 and m.Status == "ok")
    check("reopened: same FemMesh", (m.FemMesh.NodeCount, m.FemMesh.FaceCount) == counts,
          (m.FemMesh.NodeCount, m.FemMesh.FaceCount))
    bl, ls = doc.getObject(names["bl"]), doc.getObject(names["ls"])
    check("reopened: children restored", list(m.BoundaryLayerList) == [bl] and list(m.LocalSizeList) == [ls]
          and bl.References[0][1] == ("Edge21",) and ls.References[0][1] == ("Face9", "Face3"))
    from freecad.paramesh.gui.view_surface_mesh import ViewProviderSurfaceMesh
    check("reopened: view providers restored", isinstance(m.ViewObject.Proxy, ViewProviderSurfaceMesh)
          and set(m.ViewObject.Proxy.claimChildren()) == {bl, ls})
    check("reopened: Mesh feature", doc.getObject(names["mf"]) is not None
          and doc.getObject(names["mf"]).Mesh.CountFacets > 0)
    ours = [m, bl, ls]
    check("reopened: nothing to recompute", not any("Touched" in o.State for o in ours),
          [o.Name for o in ours if "Touched" in o.State])
    # a changed input re-meshes on recompute (the parametric path; small mesh, so synchronously)
    faces_before = m.FemMesh.FaceCount
    bl.Layers = 10
    doc.recompute()
    r = report(m)
    check("recompute re-meshes after an input changed", m.Status == "ok" and m.FemMesh.FaceCount != faces_before
          and r["counts"]["quads"] > 0, (faces_before, m.FemMesh.FaceCount))
    return doc, m


def step_reopened_quality_and_export(doc, m):
    """After reopening there is no MeshResult in memory: the quality view reads FemMesh and the export
    re-meshes in the background first."""
    from freecad.paramesh.gui import task_quality
    m.Proxy._result = None
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, m.Name)
    FreeCADGui.runCommand("ParaMesh_Quality")
    ok = wait_until(lambda: task_quality.ACTIVE is not None, 10)
    q = task_quality.ACTIVE
    check("quality from a reopened FemMesh", ok and len(q.quality) == m.FemMesh.FaceCount)
    if q is not None:
        press(QtGui.QDialogButtonBox.Close)
        wait_until(lambda: task_quality.ACTIVE is None, 5)
    path = os.path.join(OUT, "m6_reopened.msh")
    if os.path.exists(path):
        os.remove(path)
    fill_file_dialog(path)
    FreeCADGui.runCommand("ParaMesh_Export")
    check("export .msh after reopening (background re-mesh)", os.path.exists(path) and os.path.getsize(path) > 1000)


def _read_first_line(path):
    try:
        with open(path) as f:
            return f.readline().strip()
    except OSError:
        return ""


def step_latency():
    import Part
    doc = FreeCAD.newDocument("Big")
    wing = doc.addObject("Part::Feature", "Wing")
    wing.Shape = Part.read(M6)
    doc.recompute()
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, wing.Name)
    FreeCADGui.runCommand("ParaMesh_SurfaceMesh")
    wait_until(lambda: active_panel() is not None, 5)
    panel = active_panel()
    mesh = panel.mesh
    panel.params.set_value("Size", BIG_SIZE)
    panel.params.set_value("Threads", 0)
    paints = PaintCounter(panel.run.time_label)
    ticker = Ticker(20)
    ticker.start()
    press(QtGui.QDialogButtonBox.Apply)
    ok = wait_until(lambda: not panel.run.running and panel.run.state != "running", 240, step=20)
    runner = panel.run.runner
    t_end = runner.t_end or time.perf_counter()
    gap, n = ticker.max_gap(until=t_end)
    compute = runner.mesh_seconds  # the core's run
    build = runner.elapsed - compute  # the worker filling the FemMesh after it
    paints_during = paints.count
    wait_until(lambda: panel.run.state in ("done", "failed", "cancelled"), 120)
    ticker.stop()
    log(f"RunBox tick max {getattr(panel.run, 'tick_max', 0) * 1000:.1f} ms")
    log(f"gaps > 50 ms (s after the worker started, ms): {ticker.gaps_over(0.05, runner.t_start, t_end)}")
    r = report(mesh)
    tri = r.get("counts", {}).get("triangles", 0)
    long_gaps = ticker.gaps_over(0.1, runner.t_start, t_end)
    threads = r.get("parameters", {}).get("threads")
    METRICS.update(latency_gaps_over_100ms=long_gaps, big_threads=threads,
                   cpus=f"{os.cpu_count()} online, {len(os.sched_getaffinity(0))} in affinity, "
                        f"cgroup cpu.max {_read_first_line('/sys/fs/cgroup/cpu.max') or 'n/a'}",
                   latency_max_gap_ms=round(gap * 1000, 1), latency_ticks=n, big_size=BIG_SIZE,
                   big_triangles=tri, big_compute_seconds=round(compute, 2),
                   big_femmesh_build_seconds=round(build, 2),
                   big_store_seconds=round(panel.run.apply_seconds, 2), progress_bar_paints=paints_during)
    check("~1 M triangle mesh computed", ok and panel.run.state == "done" and tri >= 900000, f"{tri} triangles")
    check("event loop never blocked > 200 ms while meshing and building the FemMesh",
          gap < 0.200 and n > 0.5 * (compute + build) / 0.020,
          f"max gap {gap * 1000:.1f} ms over {n} ticks in {compute + build:.1f} s")
    check("panel repainted while meshing (elapsed-time label)", paints_during > (compute + build) / 0.5,
          paints_during)
    log(f"storing the result on the GUI thread took {panel.run.apply_seconds:.1f} s (FemMesh + view)")
    shot_window("window_big_mesh.png")
    press(QtGui.QDialogButtonBox.Ok)
    wait_until(lambda: active_panel() is None, 30)
    FreeCAD.closeDocument(doc.Name)


def run_all():
    obs = ReportObserver()
    mw = main_window()
    mw.setGeometry(QtGui.QGuiApplication.primaryScreen().availableGeometry())
    mw.showMaximized()
    wait_ms(300)
    cv = combo_view()
    if cv is not None:  # room for the task panels in the screenshots
        mw.resizeDocks([cv], [470], QtCore.Qt.Horizontal)
    wait_ms(300)
    steps_failed = []

    def guarded(name, fn, *args):
        try:
            return fn(*args)
        except Exception:
            check(f"step '{name}' raised", False, traceback.format_exc().strip().splitlines()[-1])
            log(traceback.format_exc())
            steps_failed.append(name)
            panel = active_panel()
            if panel is not None:
                try:
                    panel.run.stop()
                    FreeCADGui.Control.closeDialog()
                except Exception:
                    pass
            return None

    guarded("workbench", step_workbench)
    tb = [t for t in mw.findChildren(QtGui.QToolBar) if t.objectName() == "ParaMesh"]
    only_big = os.environ.get("PARAMESH_GUI_ONLY_BIG") == "1"  # for development: the latency run alone
    res = None if only_big else guarded("document", step_document)
    if res:
        doc, wing, analysis = res
        mesh = guarded("surface mesh", step_surface_mesh, doc, wing, analysis)
        guarded("cancel", step_cancel, doc, wing)
        if mesh is not None:
            guarded("second order", step_second_order, doc, mesh)
            guarded("boundary layer", step_boundary_layer, doc, wing, mesh)
            guarded("local size", step_local_size, doc, wing, mesh)
            guarded("quality", step_quality, doc, mesh)
            guarded("export", step_export, doc, mesh)
            guarded("to mesh", step_to_mesh, doc, mesh)
            reopened = guarded("save and reopen", step_save_reopen, doc, mesh)
            if reopened:
                guarded("reopened quality/export", step_reopened_quality_and_export, *reopened)
                FreeCAD.closeDocument(reopened[0].Name)
    if os.environ.get("PARAMESH_GUI_SKIP_BIG") != "1":
        guarded("latency", step_latency)
    wait_ms(200)
    errors = obs.texts()
    check("no error in the Report view", not errors, errors[:5])


def finish():
    passed = sum(1 for _n, ok, _d in CHECKS if ok)
    failed = [(n, d) for n, ok, d in CHECKS if not ok]
    total = time.perf_counter() - _T0
    lines = ["ParaMesh GUI test (FreeCAD %s)" % ".".join(FreeCAD.Version()[:3]),
             f"checks: {passed} passed, {len(failed)} failed, {total:.0f} s"]
    for k in ("m6_triangles", "bl_triangles", "bl_quads", "cancel_seconds", "big_triangles", "big_compute_seconds",
              "latency_max_gap_ms", "latency_gaps_over_100ms", "big_threads", "cpus", "latency_ticks",
              "big_femmesh_build_seconds", "big_store_seconds", "progress_bar_paints"):
        if k in METRICS:
            lines.append(f"  {k}: {METRICS[k]}")
    for n, d in failed:
        lines.append(f"  FAILED: {n}: {d}")
    lines.append(f"screenshots: {len(SHOTS)} in {OUT}")
    lines.append("RESULT: " + ("PASS" if not failed and CHECKS else "FAIL"))
    text = "\n".join(lines) + "\n"
    with open(os.path.join(OUT, "summary.txt"), "w") as f:
        f.write(text)
    with open(os.path.join(OUT, "summary.json"), "w") as f:
        json.dump({"checks": [{"name": n, "ok": ok, "detail": d} for n, ok, d in CHECKS], "metrics": METRICS,
                   "screenshots": SHOTS, "seconds": round(total, 1)}, f, indent=1)
    log(text)
    return 0 if not failed and CHECKS else 1


def main():
    code = 1
    try:
        run_all()
        code = finish()
    except Exception:
        log(traceback.format_exc())
        try:
            finish()
        except Exception:
            pass
    finally:
        _log_file.flush()
        sys.__stdout__.flush()
        os._exit(code)


def _watchdog():
    log(f"WATCHDOG: the GUI test did not finish within {WATCHDOG_S:.0f} s")
    check("finished before the watchdog", False)
    try:
        finish()
    finally:
        os._exit(2)


_timer = threading.Timer(WATCHDOG_S, _watchdog)
_timer.daemon = True
_timer.start()
# backstop that needs no GIL (a blocked main thread can starve the timer above)
faulthandler.dump_traceback_later(WATCHDOG_S + 20, exit=True, file=_fault_file)
QtCore.QTimer.singleShot(0, main)
