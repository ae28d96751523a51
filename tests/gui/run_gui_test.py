# SPDX-License-Identifier: LGPL-2.1-or-later
"""ParaMesh GUI test, run inside FreeCAD 0.20 (GUI) under Xvfb: `bash tests/gui/run.sh`.

Drives the workbench as a user would: activates it, imports the ONERA M6 wing, runs every command
through FreeCADGui.runCommand, fills and presses the task panels, cancels a long mesh, meshes with a
leading-edge boundary layer, opens the quality view, exports, saves and reopens the document, and
measures the event-loop latency while a ~1 million triangle mesh is computed. Screenshots go to
$PARAMESH_GUI_OUT (default out/gui). Writes summary.txt / summary.json there and quits FreeCAD with
status 0 (all checks passed) or 1.

This file is the driver: it runs the steps in order, each guarded, writes the summary and
holds the watchdog. The steps are in gui_steps_setup.py (workbench, document, surface mesh,
cancel, second order), gui_steps_children.py (boundary layer, local size), gui_steps_output.py
(quality, export, Mesh feature, save and reopen), gui_steps_volume.py (the 3D option on a
two-solid part) and gui_steps_latency.py; what they share
(check, log, waiting, screenshots, panel helpers) is in gui_harness.py.
"""
import faulthandler
import json
import os
import sys
import threading
import time
import traceback

# FreeCAD runs this file as a macro: its folder is put on sys.path for the modules beside it
HERE = os.path.join(os.environ.get("PARAMESH_REPO") or os.getcwd(), "tests", "gui")
if HERE not in sys.path:
    sys.path.insert(0, HERE)

import FreeCAD  # noqa: E402
import FreeCADGui  # noqa: E402
from PySide import QtCore, QtGui  # noqa: E402

from gui_harness import (CHECKS, FAULT_FILE, LOG_FILE, METRICS, OUT, SHOTS, T0, WATCHDOG_S,  # noqa: E402
                         ReportObserver, active_panel, check, combo_view, log, main_window, wait_ms)
from gui_steps_setup import (step_cancel, step_document, step_second_order, step_surface_mesh,  # noqa: E402
                             step_workbench)
from gui_steps_children import step_boundary_layer, step_local_size  # noqa: E402
from gui_steps_output import (step_export, step_quality, step_reopened_quality_and_export,  # noqa: E402
                              step_save_reopen, step_to_mesh)
from gui_steps_latency import step_latency  # noqa: E402
from gui_steps_volume import step_volume  # noqa: E402
from gui_steps_handover import step_handover  # noqa: E402
from gui_steps_remesh import step_remesh  # noqa: E402


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
        guarded("volume", step_volume)
        guarded("hand-over from Gmsh", step_handover)
        guarded("remesh a Mesh object", step_remesh)
    if os.environ.get("PARAMESH_GUI_SKIP_BIG") != "1":
        guarded("latency", step_latency)
    wait_ms(200)
    errors = obs.texts()
    check("no error in the Report view", not errors, errors[:5])


def finish():
    passed = sum(1 for _n, ok, _d in CHECKS if ok)
    failed = [(n, d) for n, ok, d in CHECKS if not ok]
    total = time.perf_counter() - T0
    lines = ["ParaMesh GUI test (FreeCAD %s)" % ".".join(FreeCAD.Version()[:3]),
             f"checks: {passed} passed, {len(failed)} failed, {total:.0f} s"]
    for k in ("m6_triangles", "bl_triangles", "bl_quads", "cancel_seconds", "big_triangles", "big_compute_seconds",
              "latency_max_gap_ms", "latency_gaps_over_100ms", "big_threads", "cpus", "latency_ticks",
              "big_femmesh_build_seconds", "big_store_seconds", "progress_bar_paints", "crank_tetrahedra"):
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
        LOG_FILE.flush()
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
faulthandler.dump_traceback_later(WATCHDOG_S + 20, exit=True, file=FAULT_FILE)
QtCore.QTimer.singleShot(0, main)
