# SPDX-License-Identifier: LGPL-2.1-or-later
"""GUI test steps on a finished mesh: the quality view, export to every format, the Mesh
feature, saving and reopening the document, and the quality view and export after reopening."""
import os

import FreeCAD
import FreeCADGui
from PySide import QtGui

from gui_harness import (METRICS, OUT, check, combo_view, fill_file_dialog, press, report, select_only,
                        shot_view, shot_widget, shot_window, show_tasks_tab, wait_ms, wait_until, zoom_to)


def step_quality(doc, mesh):
    from freecad.paramesh.gui import task_quality
    select_only(doc, mesh)
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
        select_only(doc, mesh)
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
    select_only(doc, mesh)
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
    select_only(doc, m)
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
