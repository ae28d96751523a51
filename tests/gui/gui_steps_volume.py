# SPDX-License-Identifier: LGPL-2.1-or-later
"""GUI test step: the surface-mesh panel's 3D option on the two-solid CrankArm: the tetrahedra per
solid in the panel and the Report view, the FEM mesh's volumes and groups, 3D with quads refused
in the panel."""
import os

import FreeCAD
import FreeCADGui
from PySide import QtGui

from gui_harness import (METRICS, REPO, active_panel, apply_and_wait, check, combo_view, main_window, press,
                        report, run_panel_command, select_only, shot_widget, shot_window, show_tasks_tab,
                        wait_until)

CRANK = os.path.join(REPO, "tests", "data", "CrankArm.brep")


def _report_view_text():
    view = main_window().findChild(QtGui.QTextEdit, "Report view")
    return view.toPlainText() if view is not None else ""


def step_volume():
    import Part
    doc = FreeCAD.newDocument("Crank")
    crank = doc.addObject("Part::Feature", "CrankArm")
    crank.Shape = Part.read(CRANK)
    doc.recompute()
    FreeCADGui.ActiveDocument.ActiveView.viewIsometric()
    select_only(doc, crank)
    panel = run_panel_command("ParaMesh_SurfaceMesh")
    check("3D panel: opened on the CrankArm", panel is not None)
    if panel is None:
        return
    show_tasks_tab()
    mesh = panel.mesh
    three_d, vmax = panel.params.widget("Volume3D"), panel.params.widget("VolumeMaxSize")
    check("3D is off by default, its options and the tetrahedra row hidden",
          mesh.Volume3D is False and not three_d.isChecked() and vmax.isHidden()
          and panel.volume.isHidden())
    check("3D and max tetrahedron size have tooltips", bool(three_d.toolTip()) and bool(vmax.toolTip()))
    panel.params.set_value("Volume3D", True)
    check("ticking 3D shows its options", not vmax.isHidden() and not panel.params.widget("VolumeOptimize").isHidden())
    panel.params.set_value("Size", 4.0)
    # 3D needs triangles: quads are refused, as a normal error in the panel
    panel.params.set_value("Quads", True)
    state = apply_and_wait(panel, 60)
    check("3D with quads is refused in the panel", state == "failed" and "quads" in panel.run.error.lower(),
          f"{state} {panel.run.error[:160]}")
    panel.params.set_value("Quads", False)
    before = len(_report_view_text())
    state = apply_and_wait(panel, 120)
    r = report(mesh)
    vol = r.get("volume", {})
    solids = vol.get("solids", [])
    fm = mesh.FemMesh
    check("3D run: every solid filled", state == "done" and mesh.Status == "ok" and len(solids) == 2
          and vol.get("solids_filled") == 2, f"{state} {mesh.Status} {r.get('message')}")
    check("FEM mesh holds the reported tetrahedra and the surface triangles",
          fm.VolumeCount == fm.TetraCount == vol.get("tetrahedra", -1) > 1000
          and fm.FaceCount == r["counts"]["triangles"], (fm.VolumeCount, vol.get("tetrahedra"), fm.FaceCount))
    groups = {fm.getGroupName(g): g for g in fm.Groups}
    check("FEM mesh has a volume group per solid",
          all(len(fm.getGroupElements(groups.get(f"Solid{s['solid']}", -1))) == s["tetrahedra"]
              for s in solids if f"Solid{s['solid']}" in groups) and {"Solid1", "Solid2"} <= set(groups),
          sorted(g for g in groups if g.startswith("Solid")))
    text = panel.volume.text()
    check("the panel lists the tetrahedra per solid", not panel.volume.isHidden() and
          all(f"Solid{s['solid']}: {s['tetrahedra']} tetrahedra" in text for s in solids), text[:300])
    check("the run summary gives the tetrahedra in all",
          f"{vol.get('tetrahedra')} tetrahedra in 2 of 2 solid" in panel.run.summary.text(),
          panel.run.summary.text()[:300])
    wanted = [f"Solid{s['solid']}: {s['tetrahedra']} tetrahedra" for s in solids]
    # the Report view receives console messages as queued events: give it the event loop
    shown = wait_until(lambda: all(w in _report_view_text()[before:] for w in wanted), 5)
    check("the Report view lists the tetrahedra per solid", shown, _report_view_text()[before:][-400:])
    METRICS["crank_tetrahedra"] = [s["tetrahedra"] for s in solids]
    FreeCADGui.ActiveDocument.ActiveView.fitAll()
    shot_widget(combo_view(), "task_surface_mesh_3d.png")
    shot_window("window_surface_mesh_3d.png")
    press(QtGui.QDialogButtonBox.Ok)
    check("OK closes the 3D panel", wait_until(lambda: active_panel() is None, 10))
    check("3D stored in the object", mesh.Volume3D is True and "Touched" not in mesh.State, mesh.State)
    _quality_on_tetrahedra(doc, mesh)
    FreeCAD.closeDocument(doc.Name)


def _quality_on_tetrahedra(doc, mesh):
    """The quality view of a 3D mesh colours the tetrahedra behind the surface triangles (FreeCAD
    draws only the volumes' faces of such a mesh)."""
    from freecad.paramesh.gui import task_quality
    select_only(doc, mesh)
    FreeCADGui.runCommand("ParaMesh_Quality")
    q = task_quality.ACTIVE if wait_until(lambda: task_quality.ACTIVE is not None, 10) else None
    check("quality view opens on the 3D mesh", q is not None)
    if q is None:
        return
    fm = mesh.FemMesh
    volumes = set(fm.Volumes)
    colours = q.colored_ids  # (FreeCAD 0.20 cannot read ElementColor back)
    check("quality view rates every surface triangle of the 3D mesh", len(q.quality) == fm.FaceCount, len(q.quality))
    check("its colours go to the tetrahedra FreeCAD draws",
          bool(colours) and set(colours) <= volumes, (len(colours), len(set(colours) - volumes)))
    FreeCADGui.ActiveDocument.ActiveView.fitAll()
    shot_window("window_quality_3d.png")
    press(QtGui.QDialogButtonBox.Close)
    check("quality view on the 3D mesh closed", wait_until(lambda: task_quality.ACTIVE is None, 5))
