# SPDX-License-Identifier: LGPL-2.1-or-later
"""GUI test step: a Mesh object (MeshPart's STL of screw.step) remeshed with ParaMesh_Remesh: the
same task panel and background run as the CAD path, a ParaMesh mesh (FEM) and a new, closed Mesh
object whose triangles are well shaped."""
import os

import FreeCAD
import FreeCADGui
from PySide import QtGui

from gui_harness import active_panel, apply_and_wait, check, press, select_only, shot_view, surface_meshes, wait_ms

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def step_remesh():
    import Mesh
    doc = FreeCAD.newDocument("Remesh")
    src = doc.addObject("Mesh::Feature", "Scan")
    src.Mesh = Mesh.Mesh(os.path.join(ROOT, "tests", "data", "screw_meshpart.stl"))
    doc.recompute()
    from freecad.paramesh.gui import commands
    FreeCADGui.Selection.clearSelection()
    check("remesh command inactive without a Mesh object selected", not commands.RemeshCommand().IsActive())
    select_only(doc, src)
    check("remesh command active with the Mesh object selected", commands.RemeshCommand().IsActive())
    FreeCADGui.runCommand("ParaMesh_Remesh")
    wait_ms(300)
    panel = active_panel()
    meshes = surface_meshes(doc)
    check("remesh created one ParaMesh mesh of the Mesh object and opened its panel",
          panel is not None and len(meshes) == 1 and meshes[0].Part == src)
    if panel is None or len(meshes) != 1:
        return
    pm = meshes[0]
    state = apply_and_wait(panel, 60)
    check("the remesh ran in the panel and ended ok", state == "done" and pm.Status == "ok", (state, pm.Status))
    press(QtGui.QDialogButtonBox.Ok)
    wait_ms(300)
    mf = pm.MeshFeature
    check("a new Mesh object holds the remeshed triangles", mf is not None and mf.Mesh.CountFacets > 1000,
          mf.Mesh.CountFacets if mf else None)
    if mf is None:
        return
    check("the new Mesh object is closed (a solid) like its input", mf.Mesh.isSolid() and src.Mesh.isSolid())
    vol_in, vol_out = src.Mesh.Volume, mf.Mesh.Volume
    check("the remeshed volume is the input's within 0.5 %", abs(vol_out - vol_in) <= 5e-3 * abs(vol_in), (vol_in, vol_out))
    check("the FEM mesh has the triangles", pm.FemMesh.FaceCount == mf.Mesh.CountFacets,
          (pm.FemMesh.FaceCount, mf.Mesh.CountFacets))
    src.ViewObject.Visibility = False
    pm.ViewObject.Visibility = False
    mf.ViewObject.DisplayMode = "Flat Lines"  # the remeshed triangles' edges in the screenshot
    FreeCADGui.ActiveDocument.ActiveView.viewIsometric()
    FreeCADGui.SendMsgToActiveView("ViewFit")
    shot_view("remesh_screw.png")
    FreeCAD.closeDocument(doc.Name)
