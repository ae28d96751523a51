# SPDX-License-Identifier: LGPL-2.1-or-later
"""Widgets shared by the ParaMesh task panels: a parameter form bound to document properties, a
sub-element reference list fed by the 3D selection, and the meshing run box (progress bar with
the stage, elapsed time, Cancel, log, errors naming the failing faces)."""
import html
import json

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from .runner import QtMeshRunner, RunError
from ..core.report_text import volume_lines

# -- parameter form ----------------------------------------------------------------------------------


class Field:
    """One editable property: kind is length, angle, float, int, bool or enum."""

    def __init__(self, prop, label, kind, minimum=0.0, maximum=1e9, step=None, decimals=3, items=None,
                 special=None):
        self.prop, self.label, self.kind = prop, label, kind
        self.minimum, self.maximum, self.step, self.decimals = minimum, maximum, step, decimals
        self.items = items
        self.special = special  # text shown at the minimum (e.g. "auto")
        self.widget = None


def _quantity_box(unit):
    w = FreeCADGui.UiLoader().createWidget("Gui::QuantitySpinBox")
    w.setProperty("unit", unit)
    return w


class ParamForm(QtGui.QWidget):
    """A form of Fields bound to an object's properties; tooltips come from the property
    documentation (the same text as the property editor's)."""

    def __init__(self, obj, fields, title, parent=None, icon=None):
        super().__init__(parent)
        self.obj = obj
        self.fields = fields
        self.setWindowTitle(title)
        if icon:
            self.setWindowIcon(QtGui.QIcon(icon))
        self.layout_ = QtGui.QFormLayout(self)
        for f in fields:
            f.widget = self._make(f)
            tip = obj.getDocumentationOfProperty(f.prop) if f.prop in obj.PropertiesList else ""
            f.widget.setToolTip(tip)
            label = QtGui.QLabel(f.label)
            label.setToolTip(tip)
            self.layout_.addRow(label, f.widget)
        self.load()

    def _make(self, f):
        if f.kind in ("length", "angle"):
            w = _quantity_box("mm" if f.kind == "length" else "deg")
            w.setProperty("minimum", f.minimum)
            w.setProperty("maximum", f.maximum)
            if f.step:
                w.setProperty("singleStep", f.step)
        elif f.kind == "float":
            w = QtGui.QDoubleSpinBox()
            w.setDecimals(f.decimals)
            w.setRange(f.minimum, f.maximum)
            w.setSingleStep(f.step or 0.1)
        elif f.kind == "int":
            w = QtGui.QSpinBox()
            w.setRange(int(f.minimum), int(min(f.maximum, 2 ** 31 - 1)))
        elif f.kind == "bool":
            w = QtGui.QCheckBox()
        elif f.kind == "enum":
            w = QtGui.QComboBox()
            w.addItems(f.items)
        else:
            raise ValueError(f.kind)
        if f.special and f.kind in ("float", "int"):
            w.setSpecialValueText(f.special)
        w.setObjectName(f.prop)
        return w

    def widget(self, prop):
        for f in self.fields:
            if f.prop == prop:
                return f.widget
        raise KeyError(prop)

    def load(self):
        for f in self.fields:
            v = getattr(self.obj, f.prop)
            w = f.widget
            if f.kind in ("length", "angle"):
                w.setProperty("rawValue", float(v.Value if hasattr(v, "Value") else v))
            elif f.kind == "float":
                w.setValue(float(v))
            elif f.kind == "int":
                w.setValue(int(v))
            elif f.kind == "bool":
                w.setChecked(bool(v))
            elif f.kind == "enum":
                w.setCurrentIndex(max(0, w.findText(str(v))))

    def values(self):
        out = {}
        for f in self.fields:
            w = f.widget
            if f.kind in ("length", "angle"):
                out[f.prop] = float(w.property("rawValue"))
            elif f.kind == "float":
                out[f.prop] = float(w.value())
            elif f.kind == "int":
                out[f.prop] = int(w.value())
            elif f.kind == "bool":
                out[f.prop] = bool(w.isChecked())
            elif f.kind == "enum":
                out[f.prop] = str(w.currentText())
        return out

    def set_value(self, prop, value):
        """Sets a widget as a user would (used by scripts and tests)."""
        for f in self.fields:
            if f.prop == prop:
                w = f.widget
                if f.kind in ("length", "angle"):
                    w.setProperty("rawValue", float(value))
                elif f.kind in ("float", "int"):
                    w.setValue(value)
                elif f.kind == "bool":
                    w.setChecked(bool(value))
                else:
                    w.setCurrentIndex(w.findText(str(value)))
                return
        raise KeyError(prop)

    def changed_values(self):
        """{prop: value} of the widgets that differ from the object."""
        out = {}
        for prop, v in self.values().items():
            cur = getattr(self.obj, prop)
            cur = float(cur.Value) if hasattr(cur, "Value") else cur
            if isinstance(v, float):
                if abs(float(cur) - v) > 1e-12 * max(1.0, abs(v)):
                    out[prop] = v
            elif cur != v:
                out[prop] = v
        return out

    def write(self):
        """Writes the changed values to the object through FreeCADGui.doCommand (macro-recordable);
        returns the names of the changed properties."""
        changed = self.changed_values()
        write_properties(self.obj, changed)
        return list(changed)


def obj_expr(obj):
    return f"App.getDocument({obj.Document.Name!r}).getObject({obj.Name!r})"


def write_properties(obj, values):
    for prop, v in values.items():
        FreeCADGui.doCommand(f"{obj_expr(obj)}.{prop} = {v!r}")


# -- references --------------------------------------------------------------------------------------


class _SelectionObserver:
    def __init__(self, callback):
        self.callback = callback

    def addSelection(self, doc, obj, sub, pos):
        self.callback(doc, obj, sub)


class _Gate:
    def __init__(self, prefixes, part):
        self.prefixes, self.part = prefixes, part

    def allow(self, doc, obj, sub):
        if self.part is not None and obj is not None and obj.Name != self.part.Name:
            return False
        return bool(sub) and sub.startswith(self.prefixes)


class ReferenceList(QtGui.QWidget):
    """Sub-elements (EdgeN, FaceN, VertexN) of the meshed Part. While 'Pick in 3D view' is on, a
    click on an allowed sub-element in the 3D view adds it (a second click removes it)."""

    changed = QtCore.Signal()

    def __init__(self, title, part, prefixes, references=(), parent=None, icon=None):
        super().__init__(parent)
        self.setWindowTitle(title)
        if icon:
            self.setWindowIcon(QtGui.QIcon(icon))
        self.part = part
        self.prefixes = tuple(prefixes)
        self._observer = None
        self._gate = False
        lay = QtGui.QVBoxLayout(self)
        kinds = ", ".join(p.lower() + "s" for p in self.prefixes)
        help_ = QtGui.QLabel(f"Click {kinds} of <b>{part.Label if part else '?'}</b> in the 3D view.")
        help_.setWordWrap(True)
        lay.addWidget(help_)
        self.list = QtGui.QListWidget()
        self.list.setSelectionMode(QtGui.QAbstractItemView.ExtendedSelection)
        self.list.setMaximumHeight(110)
        self.list.setObjectName("References")
        lay.addWidget(self.list)
        row = QtGui.QHBoxLayout()
        self.pick = QtGui.QPushButton("Pick in 3D view")
        self.pick.setCheckable(True)
        self.pick.setToolTip("While on, clicking an allowed element in the 3D view adds it to the list "
                             "(clicking it again removes it)")
        self.add_sel = QtGui.QPushButton("Add selected")
        self.add_sel.setToolTip("Adds the elements currently selected in the 3D view")
        self.remove = QtGui.QPushButton("Remove")
        self.remove.setToolTip("Removes the highlighted list entries")
        for b in (self.pick, self.add_sel, self.remove):
            row.addWidget(b)
        lay.addLayout(row)
        self.extra = QtGui.QHBoxLayout()  # panels add buttons here
        lay.addLayout(self.extra)
        self.pick.toggled.connect(self._toggle_pick)
        self.add_sel.clicked.connect(self.add_selection)
        self.remove.clicked.connect(self.remove_selected)
        self.list.itemSelectionChanged.connect(self._highlight)
        for _obj, subs in references or []:
            for s in subs:
                self.add(s, emit=False)

    def names(self):
        return [self.list.item(i).text() for i in range(self.list.count())]

    def references(self):
        names = self.names()
        return [(self.part, tuple(names))] if names and self.part is not None else []

    def add(self, sub, emit=True):
        if not sub.startswith(self.prefixes) or sub in self.names():
            return False
        self.list.addItem(sub)
        if emit:
            self.changed.emit()
        return True

    def remove_names(self, names):
        for i in reversed(range(self.list.count())):
            if self.list.item(i).text() in names:
                self.list.takeItem(i)
        self.changed.emit()

    def add_selection(self):
        n = 0
        for s in FreeCADGui.Selection.getSelectionEx():
            if self.part is not None and s.Object.Name != self.part.Name:
                continue
            for sub in s.SubElementNames:
                n += self.add(sub)
        return n

    def remove_selected(self):
        self.remove_names({it.text() for it in self.list.selectedItems()})

    def _highlight(self):
        if self.part is None:
            return
        FreeCADGui.Selection.clearSelection()
        for it in self.list.selectedItems():
            FreeCADGui.Selection.addSelection(self.part.Document.Name, self.part.Name, it.text())

    def _on_pick(self, doc, obj, sub):
        if self.part is None or obj != self.part.Name or not sub or not sub.startswith(self.prefixes):
            return
        if sub in self.names():
            if not self.list.signalsBlocked():
                self.remove_names({sub})
        else:
            self.add(sub)

    def _toggle_pick(self, on):
        if on and self._observer is None:
            self._observer = _SelectionObserver(self._on_pick)
            FreeCADGui.Selection.addObserver(self._observer)
            FreeCADGui.Selection.addSelectionGate(_Gate(self.prefixes, self.part))
            self._gate = True
        elif not on:
            self.stop_picking()

    def stop_picking(self):
        if self._observer is not None:
            FreeCADGui.Selection.removeObserver(self._observer)
            self._observer = None
        if self._gate:
            FreeCADGui.Selection.removeSelectionGate()
            self._gate = False
        if self.pick.isChecked():
            self.pick.blockSignals(True)
            self.pick.setChecked(False)
            self.pick.blockSignals(False)


# -- run box -----------------------------------------------------------------------------------------


def report_lines(report):
    """(level, text) lines summarising a run report: counts, the tetrahedra per solid, quality,
    and every face (or solid) that did not mesh cleanly with its reason."""
    out = []
    c = report.get("counts", {})
    status = report.get("status", "?")
    if c:
        out.append(("info", f"{c.get('nodes', 0)} nodes, {c.get('triangles', 0)} triangles, "
                            f"{c.get('quads', 0)} quads"))
    out += volume_lines(report)
    q = report.get("quality") or {}
    if q:
        out.append(("info", f"min angle {q.get('angle_min', 0):.1f}°, max angle {q.get('angle_max', 0):.1f}°, "
                            f"radius ratio min {q.get('gamma_min', 0):.3f} / mean {q.get('gamma_mean', 0):.3f}"))
    for f in report.get("faces", []) or []:
        if f.get("status", "ok") != "ok":
            err = f.get("error") or f.get("message") or f.get("status")
            out.append(("error" if f.get("status") == "failed" else "warning",
                        f"{f.get('name', 'Face%s' % f.get('face', '?'))} ({f.get('surface', '?')}): "
                        f"{f.get('status')} — {err}"))
    for w in report.get("warnings", []) or []:
        out.append(("warning", str(w)))
    if status != "ok" and report.get("message"):
        out.insert(0, ("error" if status == "failed" else "warning", f"{status}: {report['message']}"))
    return out


_COLORS = {"error": "#c00000", "warning": "#b06000", "info": "#202020", "ok": "#006000", "log": "#505050"}


class RunBox(QtGui.QWidget):
    """Progress, log, elapsed time and Cancel of a meshing run of a surface mesh object. The mesh
    is computed by a worker thread; the result is applied on the GUI thread when it ends."""

    finished = QtCore.Signal(str)  # state: done, failed, cancelled

    def __init__(self, parent=None):
        super().__init__(parent)
        self._logged = set()  # messages of the core's log sink shown during the current run
        self.setWindowTitle("Meshing (Apply / OK run it in the background)")
        from .. import resource_path
        self.setWindowIcon(QtGui.QIcon(resource_path("icons", "ParaMesh_SurfaceMesh.svg")))
        lay = QtGui.QVBoxLayout(self)
        self.bar = QtGui.QProgressBar()
        self.bar.setRange(0, 1000)
        self.bar.setValue(0)
        self.bar.setFormat("idle")
        self.bar.setTextVisible(True)
        row = QtGui.QHBoxLayout()
        row.addWidget(self.bar, 1)
        self.cancel_button = QtGui.QPushButton("Cancel run")
        self.cancel_button.setToolTip("Stops the running mesh; the object keeps its previous mesh")
        self.cancel_button.setEnabled(False)
        row.addWidget(self.cancel_button)
        lay.addLayout(row)
        self.bar.setMinimumWidth(120)
        self.time_label = QtGui.QLabel("Time: -")
        lay.addWidget(self.time_label)
        self.summary = QtGui.QLabel("")
        self.summary.setWordWrap(True)
        self.summary.setTextFormat(QtCore.Qt.RichText)
        self.summary.setObjectName("Summary")
        lay.addWidget(self.summary)
        self.log = QtGui.QTextEdit()
        self.log.setReadOnly(True)
        self.log.setMinimumHeight(90)
        self.log.setObjectName("Log")
        lay.addWidget(self.log)
        self.cancel_button.clicked.connect(self.cancel)
        self.timer = QtCore.QTimer(self)
        self.timer.setInterval(200)
        self.timer.timeout.connect(self._tick)
        self.qrunner = None
        self.obj = None
        self.on_applied = None
        self.state = "idle"
        self.last_seconds = 0.0
        self.apply_seconds = 0.0
        self.cancel_seconds = None
        self.error = ""

    # -- API --
    @property
    def running(self):
        return self.qrunner is not None and self.qrunner.runner.running

    @property
    def runner(self):
        return self.qrunner.runner if self.qrunner is not None else None

    def start(self, obj, on_applied=None):
        """Starts meshing obj in a worker thread; False (with the reason shown) if it cannot start."""
        if self.running:
            self.message("warning", "a run is already in progress")
            return False
        self.obj, self.on_applied = obj, on_applied
        self.error = ""
        self.cancel_seconds = None
        self.log.clear()
        self.summary.setText("")
        self.qrunner = QtMeshRunner(self)
        try:
            self.qrunner.runner.prepare(obj)
        except RunError as e:
            self._fail(str(e))
            return False
        self.qrunner.finished.connect(self._on_finished, QtCore.Qt.QueuedConnection)
        self.state = "running"
        self._logged = set()
        self.bar.setValue(0)
        self.bar.setFormat("starting")
        self.cancel_button.setEnabled(True)
        self.message("log", f"meshing {obj.Part.Label} (size {float(obj.Size):g} mm, "
                            f"{len(obj.BoundaryLayerList)} boundary layer(s), {len(obj.LocalSizeList)} local size(s))")
        self.qrunner.runner.start()
        self.timer.start()
        return True

    def cancel(self):
        if self.running:
            self.message("warning", "cancelling…")
            self.qrunner.runner.cancel()

    def stop(self, timeout=5.0):
        """Cancels a running mesh and waits for the worker (used when the panel closes)."""
        if self.running:
            self.qrunner.runner.cancel()
            self.qrunner.runner.wait(timeout)

    def message(self, level, text):
        color = _COLORS.get(level, "#202020")
        self.log.append(f'<span style="color:{color}">{html.escape(text)}</span>')

    def _log_message(self, level, text):
        """A message of the core's log sink during the run (remembered: the report's warnings
        repeat them, and the log shows each once)."""
        self._logged.add(text)
        self.message("warning" if level >= 2 else "log", text)

    # -- internals --
    def _fail(self, text):
        self.state = "failed"
        self.error = text
        self.bar.setFormat("failed")
        self.summary.setText(f'<span style="color:{_COLORS["error"]}"><b>Error:</b> {html.escape(text)}</span>')
        self.message("error", text)
        self.cancel_button.setEnabled(False)
        self.finished.emit("failed")

    def _tick(self):
        import time as _t
        t0 = _t.perf_counter()
        try:
            self._tick_impl()
        finally:
            dt = _t.perf_counter() - t0
            self.tick_max = max(getattr(self, "tick_max", 0.0), dt)

    def _tick_impl(self):
        r = self.runner
        if r is None:
            return
        for level, text in r.take_messages():
            self._log_message(level, text)
        if r.running:
            # touch only what changed: every repaint of a widget next to the OpenGL view costs a
            # window composition (tens of ms with software OpenGL)
            value = int(1000 * min(1.0, max(0.0, r.fraction)))
            if value != self.bar.value():
                self.bar.setValue(value)
            fmt = f"%p% — {r.stage or 'starting'}"
            if fmt != self.bar.format():
                self.bar.setFormat(fmt)
            self.time_label.setText(f"Time: {r.elapsed:.1f} s")
        elif self.state == "running":  # the finished signal was lost: handle the end here
            self._on_finished()

    @QtCore.Slot()
    def _on_finished(self):
        if self.state != "running":
            return
        self.timer.stop()
        r = self.runner
        for level, text in r.take_messages():
            self._log_message(level, text)
        self.cancel_button.setEnabled(False)
        self.last_seconds = r.elapsed
        self.time_label.setText(f"Time: {r.elapsed:.1f} s")
        if r.state == "cancelled":
            self.state = "cancelled"
            self.cancel_seconds = (r.t_end - r.t_cancel) if r.t_cancel else None
            self.bar.setFormat("cancelled")
            self.summary.setText(f'<span style="color:{_COLORS["warning"]}">Cancelled after {r.elapsed:.1f} s: '
                                 'the mesh was not changed.</span>')
            self.message("warning", "cancelled" + (f" ({1000 * self.cancel_seconds:.0f} ms after the request)"
                                                   if self.cancel_seconds is not None else ""))
            self.finished.emit("cancelled")
            return
        if r.state == "failed":
            self._fail(r.error)
            return
        result = r.collect()
        self.bar.setValue(1000)
        self.bar.setFormat("applying the result…")
        QtGui.QApplication.processEvents(QtCore.QEventLoop.ExcludeUserInputEvents)
        import time
        t0 = time.perf_counter()
        try:
            obj = self.obj
            obj.Proxy.apply_result(obj, result, r.collect_femmesh())
            settle(obj)
        except Exception as e:  # shown in the panel
            self._fail(f"could not store the mesh: {e}")
            return
        self.apply_seconds = time.perf_counter() - t0
        report = result.report
        status = report.get("status", "ok")
        self.bar.setFormat("done" if status == "ok" else status)
        lines = report_lines(report)
        for level, text in lines:
            if text not in self._logged:  # a warning already logged during the run
                self.message(level, text)
        self._logged = set()
        color = _COLORS["ok"] if status == "ok" else _COLORS["error" if status == "failed" else "warning"]
        head = {"ok": "Meshed", "degraded": "Meshed with problems", "failed": "Failed"}.get(status, status)
        body = "<br>".join(f'<span style="color:{_COLORS[level]}">{html.escape(t)}</span>' for level, t in lines[:8])
        # the worker's FemMesh fill (after the core's run) is part of storing the mesh
        store = r.elapsed - r.mesh_seconds + self.apply_seconds
        self.summary.setText(f'<span style="color:{color}"><b>{head}</b> in {r.mesh_seconds:.1f} s '
                             f'(+{store:.1f} s to store)</span><br>{body}')
        self.state = "done"
        if status == "failed":
            self.error = report.get("message", "failed")
        if self.on_applied is not None:
            self.on_applied(result)
        self.finished.emit("done")


def settle(mesh_obj):
    """After a result was stored from the panel: the object and its children are up to date, so a
    later recompute must not mesh again on the GUI thread."""
    for o in [mesh_obj] + list(mesh_obj.BoundaryLayerList) + list(mesh_obj.LocalSizeList):
        o.purgeTouched()
    mf = getattr(mesh_obj, "MeshFeature", None)
    if mf is not None:
        mf.purgeTouched()


def report_of(obj):
    try:
        return json.loads(obj.Report or "{}")
    except ValueError:
        return {}
