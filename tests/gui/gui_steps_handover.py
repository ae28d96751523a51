# SPDX-License-Identifier: LGPL-2.1-or-later
"""GUI test step: FreeCAD's own example analysis (femexamples.ccx_cantilever_faceload) with a mesh
group on its FEM Gmsh mesh object, handed over to ParaMesh with the ParaMesh_FromGmsh command: the
analysis then holds the ParaMesh mesh with the group, and the Gmsh-only setting is listed in the
Report view."""
import FreeCAD
import FreeCADGui
from PySide import QtGui

from gui_harness import check, main_window, select_only, shot_view, wait_ms


def step_handover():
    import ObjectsFem
    from femexamples.ccx_cantilever_faceload import setup
    doc = setup(solvertype="ccxtools")
    gmsh, box = doc.Mesh, doc.Box
    gmsh.CharacteristicLengthMax = 250.0
    gmsh.Algorithm2D = "Frontal"
    group = ObjectsFem.makeMeshGroup(doc, gmsh, True, "LoadedEnd")
    group.Label = "loaded_end"
    group.References = [(box, ("Face2",))]
    doc.recompute()
    wait_ms(200)
    from freecad.paramesh.gui import commands
    FreeCADGui.Selection.clearSelection()
    check("from-Gmsh command inactive without a Gmsh mesh selected", not commands.FromGmshCommand().IsActive())
    select_only(doc, gmsh)
    check("from-Gmsh command active with the example's Gmsh mesh selected", commands.FromGmshCommand().IsActive())
    FreeCADGui.runCommand("ParaMesh_FromGmsh")
    wait_ms(500)
    meshes = [o for o in doc.Analysis.Group if o.isDerivedFrom("Fem::FemMeshObject")]
    pm = meshes[0] if len(meshes) == 1 else None
    check("the analysis holds one mesh: the ParaMesh one", pm is not None and pm != gmsh,
          [m.Name for m in meshes])
    if pm is None:
        return
    check("handed-over mesh meshed: 3D, status ok", pm.Status == "ok" and pm.Volume3D
          and pm.FemMesh.VolumeCount > 0, pm.Status)
    fm = pm.FemMesh
    names = [fm.getGroupName(g) for g in fm.Groups]
    check("the MeshGroup is a FemMesh group of the ParaMesh mesh", "loaded_end" in names, names)
    view = main_window().findChild(QtGui.QTextEdit, "Report view")
    text = view.toPlainText() if view is not None else ""
    check("the Gmsh-only setting is listed in the Report view", "Algorithm2D = Frontal" in text, text[-300:])
    check("the replaced Gmsh mesh is hidden", not gmsh.ViewObject.Visibility)
    box.ViewObject.Visibility = False
    FreeCADGui.ActiveDocument.ActiveView.viewIsometric()
    FreeCADGui.SendMsgToActiveView("ViewFit")
    shot_view("handover_cantilever.png")
    FreeCAD.closeDocument(doc.Name)
