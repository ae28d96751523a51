# SPDX-License-Identifier: LGPL-2.1-or-later
"""Runs a surface mesh's meshing job off the GUI thread.

MeshRunner has four steps: prepare(obj) on the GUI thread (reads the object's parameters and its
Part shape, which must not be touched from another thread), start() runs MeshJob.run in a worker
thread (the C++ core releases the GIL, so the GUI keeps painting), cancel() from any thread, and
collect() returns the MeshResult on the GUI thread, where SurfaceMesh.apply_result stores it.
MeshRunner itself has no Qt dependency, so it can be driven headless; QtMeshRunner adds a Qt
signal emitted when the worker ends.
"""
import os
import sys
import threading
import time

from ..core.api import MeshJob, Cancelled
from ..app.to_femmesh import BuildCancelled, result_to_femmesh


class RunError(Exception):
    """A run that could not be prepared or failed; the message is meant for the user."""


class MeshRunner:
    """One meshing run of a ParaMesh surface mesh object. States: idle, running, done, failed,
    cancelled."""

    def __init__(self):
        self.state = "idle"
        self.job = None
        self.params = None
        self.brep = None
        self.result = None
        self.femmesh = None  # an empty Fem.FemMesh made on the GUI thread, filled by the worker
        self.t_meshed = None  # when the core finished (the worker then fills femmesh)
        self.error = ""
        self.fraction = 0.0
        self.stage = ""
        self.t_start = self.t_end = self.t_cancel = None
        self._messages = []
        self._lock = threading.Lock()
        self._thread = None
        self._cancel = False
        self.on_done = None  # called from the worker thread when it ends

    # -- GUI thread ---------------------------------------------------------------------------------
    def prepare(self, obj):
        """Reads the parameters and the shape of obj (as BREP text: Part objects must be read on the
        GUI thread); raises RunError with a readable message. Parsing the BREP and building the
        mesher happen in the worker, so the GUI thread only does the cheap part."""
        part = getattr(obj, "Part", None)
        from ..app.objects.surface_mesh import is_mesh_feature, mesh_source
        if is_mesh_feature(part):  # triangulated input: its arrays, read here on the GUI thread
            try:
                self.brep = mesh_source(part)
                self.params = obj.Proxy.params(obj)
            except Exception as e:
                raise RunError(str(e)) from e
            self.femmesh = _empty_femmesh()
            self.state = "prepared"
            return self
        if part is None or not hasattr(part, "Shape"):
            raise RunError(f"{obj.Label}: no Part to mesh (set its Part property)")
        shape = part.Shape
        try:
            if shape.isNull():
                raise ValueError(f"{part.Label}: the shape is empty")
            if not shape.Faces:
                raise ValueError(f"{part.Label}: the shape has no face to mesh (type {shape.ShapeType})")
            self.params = obj.Proxy.params(obj)
        except Exception as e:  # ValueError, TypeError from validation: user errors
            raise RunError(str(e)) from e
        self.brep = shape.exportBrepToString()
        self.femmesh = _empty_femmesh()
        self.state = "prepared"
        return self

    def start(self):
        if self.state != "prepared":
            raise RunError("prepare() was not called")
        self.state = "running"
        self.t_start = time.perf_counter()
        self._thread = threading.Thread(target=self._work, name="ParaMeshWorker", daemon=True)
        self._thread.start()

    def collect(self):
        """The MeshResult of a finished run (state 'done'), else None."""
        return self.result if self.state == "done" else None

    def collect_femmesh(self):
        """The Fem.FemMesh the worker built from the result, nodes and elements but no groups yet
        (state 'done'; None without FreeCAD)."""
        return self.femmesh if self.state == "done" else None

    def wait(self, timeout=None):
        if self._thread is not None:
            self._thread.join(timeout)
        return not self.running

    # -- any thread ---------------------------------------------------------------------------------
    @property
    def running(self):
        return self.state == "running"

    @property
    def elapsed(self):
        if self.t_start is None:
            return 0.0
        return (self.t_end or time.perf_counter()) - self.t_start

    @property
    def mesh_seconds(self):
        """Seconds of the core's run alone (elapsed also counts the worker filling the FemMesh)."""
        if self.t_start is None:
            return 0.0
        return (self.t_meshed or self.t_end or time.perf_counter()) - self.t_start

    def cancel(self):
        """Asks the core to stop; the worker ends with state 'cancelled' (the core polls per face
        and inside long loops)."""
        if self.state != "running":
            return
        with self._lock:
            self._cancel = True
            self.t_cancel = time.perf_counter()
            job = self.job
        if job is not None:
            job.cancel()

    def take_messages(self):
        """Log lines (level, text) received since the last call."""
        with self._lock:
            out, self._messages = self._messages, []
        return out

    # -- worker thread ------------------------------------------------------------------------------
    def _progress(self, fraction, stage):
        self.fraction, self.stage = float(fraction), str(stage)
        return not self._cancel

    def _log(self, *args):
        level, text = (args[0], args[1]) if len(args) >= 2 else (1, args[0] if args else "")
        with self._lock:
            self._messages.append((int(level) if isinstance(level, int) else 1, str(text)))

    def _work(self):
        lower_thread_priority()
        try:
            job = MeshJob(self.brep, self.params)
            with self._lock:
                self.job = job
                cancelled = self._cancel
            if cancelled:
                raise Cancelled("cancelled before the start")
            self.result = job.run(progress=self._progress, log=self._log)
            self.t_meshed = time.perf_counter()
            if self.femmesh is not None and not self._cancel:
                self.stage = "building the FEM mesh"
                # Python work shares the GIL with the GUI thread, whose every Qt call releases
                # and re-takes it: a short switch interval keeps each re-take short
                interval = sys.getswitchinterval()
                sys.setswitchinterval(min(interval, 0.0005))
                try:
                    result_to_femmesh(self.result, groups=False, femmesh=self.femmesh,
                                      cancelled=lambda: self._cancel)
                finally:
                    sys.setswitchinterval(interval)
            state = "cancelled" if self._cancel else "done"
        except (Cancelled, BuildCancelled):
            state = "cancelled"
        except Exception as e:  # reported in the panel, never as a traceback dialog
            self.error = f"{type(e).__name__}: {e}" if not str(e) else str(e)
            state = "cancelled" if self._cancel else "failed"
        self.t_end = time.perf_counter()
        self.state = state
        if state != "done":
            self.result = None  # (femmesh stays: a FemMesh must be destroyed on the GUI thread)
        cb = self.on_done
        if cb is not None:
            cb()


def _empty_femmesh():
    """An empty Fem.FemMesh, or None outside FreeCAD. Made here, on the GUI thread: creating and
    destroying FemMeshes changes state they all share, filling one does not."""
    try:
        import FreeCAD  # noqa: F401  (before Fem)
        import Fem
    except ImportError:
        return None
    return Fem.FemMesh()


def lower_thread_priority(step=4):
    """Lowers the calling thread's scheduling priority by `step` nice levels (Linux keeps nice per
    thread, and the mesher's worker threads inherit it from the thread that starts them). Meshing
    then yields a core to the GUI thread and to software OpenGL whenever they wake: measured on the
    GUI test's 1 M triangle run with 8 threads on 2 cores, the longest event-loop stall fell from
    128 ms to 60 ms and the mesh took no longer. Elsewhere (no per-thread nice) it does nothing."""
    if not sys.platform.startswith("linux"):
        return
    try:
        tid = threading.get_native_id()
        os.setpriority(os.PRIO_PROCESS, tid, min(19, os.getpriority(os.PRIO_PROCESS, tid) + step))
    except (AttributeError, OSError):
        pass


def _qt_runner_class():
    from PySide import QtCore

    class QtMeshRunner(QtCore.QObject):
        """MeshRunner whose end is signalled to the GUI thread (queued signal)."""

        finished = QtCore.Signal()

        def __init__(self, parent=None):
            super().__init__(parent)
            self.runner = MeshRunner()
            self.runner.on_done = self.finished.emit

    return QtMeshRunner


_cls = None


def QtMeshRunner(parent=None):
    """A QObject with .runner (MeshRunner) and a .finished signal delivered on the GUI thread."""
    global _cls
    if _cls is None:
        _cls = _qt_runner_class()
    return _cls(parent)
