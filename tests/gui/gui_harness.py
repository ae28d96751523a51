# SPDX-License-Identifier: LGPL-2.1-or-later
"""What the ParaMesh GUI test's steps share: the paths and settings from the environment, the
check/log record (CHECKS, METRICS, SHOTS, written out by run_gui_test.py), waiting on the event
loop, the Report view observer, and helpers to find and press task-panel buttons, take screenshots,
answer file dialogs and measure event-loop gaps. Runs inside FreeCAD (GUI); imported by
run_gui_test.py and the gui_steps_*.py modules."""
import faulthandler
import json
import os
import sys
import time

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

REPO = os.environ.get("PARAMESH_REPO") or os.getcwd()
OUT = os.environ.get("PARAMESH_GUI_OUT") or os.path.join(REPO, "out", "gui")
M6 = os.path.join(REPO, "tests", "data", "AileM6_with_sharp_TE.stp")
BIG_SIZE = float(os.environ.get("PARAMESH_GUI_BIG_SIZE", "1.9"))  # ~1.0 M triangles on the M6
WATCHDOG_S = float(os.environ.get("PARAMESH_GUI_WATCHDOG", "360"))
os.makedirs(OUT, exist_ok=True)

T0 = time.perf_counter()
LOG_FILE = open(os.path.join(OUT, "gui_test.log"), "w")
FAULT_FILE = open(os.path.join(OUT, "faulthandler.log"), "w")
faulthandler.enable(FAULT_FILE, all_threads=True)
CHECKS = []
METRICS = {}
SHOTS = []


def log(msg):
    line = f"[{time.perf_counter() - T0:7.1f}s] {msg}"
    for stream in (sys.__stdout__, LOG_FILE):
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


def _select_tab(cv, text):
    """Brings the combo view's tab named text to the front."""
    for tw in cv.findChildren(QtGui.QTabWidget):
        for i in range(tw.count()):
            if tw.tabText(i) == text:
                tw.setCurrentIndex(i)


def show_tasks_tab():
    cv = combo_view()
    if cv is None:
        return
    _select_tab(cv, "Tasks")


def show_model_tab(select=None):
    cv = combo_view()
    if cv is None:
        return
    _select_tab(cv, "Model")
    for tree in cv.findChildren(QtGui.QTreeWidget):
        tree.expandAll()
    if select is not None:
        select_only(select.Document, select)
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



def select_only(doc, obj, *sub):
    """Makes obj (or its sub-element, e.g. "Edge21") the only selection, as a click in the tree or
    the 3D view would."""
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, obj.Name, *sub)


def run_panel_command(command, timeout=5):
    """Runs a command that opens a task panel and returns the panel (None when none opened within
    timeout seconds)."""
    FreeCADGui.runCommand(command)
    wait_until(lambda: active_panel() is not None, timeout)
    return active_panel()


def apply_and_wait(panel, timeout):
    """Presses the panel's Apply and waits for its run to end: the run's state, or False when it
    did not end within timeout seconds."""
    press(QtGui.QDialogButtonBox.Apply)
    return wait_run(panel, timeout)

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
