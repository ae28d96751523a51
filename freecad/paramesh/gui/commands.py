# SPDX-License-Identifier: LGPL-2.1-or-later
"""The ParaMesh commands. Each one records its document changes as FreeCADGui.doCommand lines
(so they appear in macros) inside one undo transaction, and is active only when it makes sense."""
import os

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from .. import resource_path

SURFACE_MESH = "ParaMesh::SurfaceMesh"
BOUNDARY_LAYER = "ParaMesh::BoundaryLayer"
LOCAL_SIZE = "ParaMesh::LocalSize"


# -- helpers -----------------------------------------------------------------------------------------


def proxy_type(obj):
    return getattr(getattr(obj, "Proxy", None), "Type", "")


def is_surface_mesh(obj):
    return proxy_type(obj) == SURFACE_MESH


def surface_meshes(doc):
    return [o for o in doc.Objects if is_surface_mesh(o)] if doc else []


def meshable(obj):
    """A Part object with faces that is not itself a mesh."""
    if is_surface_mesh(obj) or proxy_type(obj) in (BOUNDARY_LAYER, LOCAL_SIZE):
        return False
    shape = getattr(obj, "Shape", None)
    try:
        return shape is not None and not shape.isNull() and len(shape.Faces) > 0
    except Exception:
        return False


def dialog_open():
    return bool(FreeCADGui.Control.activeDialog())


def target_mesh(doc=None):
    """The surface mesh a command acts on: the selected one, the parent of a selected boundary
    layer / local size, the one meshing the selected Part, or the only one in the document."""
    doc = doc or FreeCAD.ActiveDocument
    if doc is None:
        return None
    meshes = surface_meshes(doc)
    if not meshes:
        return None
    for s in FreeCADGui.Selection.getSelection(doc.Name):
        if is_surface_mesh(s):
            return s
        if proxy_type(s) in (BOUNDARY_LAYER, LOCAL_SIZE):
            for m in meshes:
                if s in m.BoundaryLayerList or s in m.LocalSizeList:
                    return m
        for m in meshes:
            if m.Part == s:
                return m
    return meshes[0] if len(meshes) == 1 else None


def selected_subs(part, prefixes):
    """Sub-element names of part selected in the 3D view, restricted to prefixes."""
    out = []
    if part is None:
        return out
    for s in FreeCADGui.Selection.getSelectionEx(part.Document.Name):
        if s.Object.Name != part.Name:
            continue
        for sub in s.SubElementNames:
            if sub.startswith(tuple(prefixes)) and sub not in out:
                out.append(sub)
    return out


def effective_size(mesh_obj):
    size = float(mesh_obj.Size)
    if size <= 0 and mesh_obj.Part is not None:
        part = mesh_obj.Part
        box = part.Shape.BoundBox if hasattr(part, "Shape") else part.Mesh.BoundBox
        size = box.DiagonalLength / 50.0
    return size or 1.0


def round_sig(x, digits=3):
    if x <= 0:
        return x
    from math import floor, log10
    return round(x, -int(floor(log10(abs(x)))) + digits - 1)


def obj_ref(obj):
    return f"App.getDocument({obj.Document.Name!r}).getObject({obj.Name!r})"


class transaction:
    """An undo transaction around doCommand calls; aborted on error."""

    def __init__(self, doc, name):
        self.doc, self.name = doc, name

    def __enter__(self):
        self.doc.openTransaction(self.name)
        return self

    def __exit__(self, typ, value, tb):
        if typ is None:
            self.doc.commitTransaction()
        else:
            self.doc.abortTransaction()
            FreeCAD.Console.PrintError(f"{self.name}: {value}\n")
            return True  # reported; no traceback dialog
        return False


def open_edit(obj):
    """Opens the task panel of an object a command has just created."""
    vp = getattr(obj.ViewObject, "Proxy", None)
    if vp is not None:
        vp.created_by_command = True
    FreeCADGui.doCommand(f"Gui.getDocument({obj.Document.Name!r}).setEdit({obj.Name!r})")


class Command:
    """Base: resources from the class attributes; the icon file name is the command id."""

    id = ""
    menu = ""
    tooltip = ""
    accel = ""

    def GetResources(self):
        r = {"Pixmap": resource_path("icons", self.id + ".svg"), "MenuText": self.menu, "ToolTip": self.tooltip}
        if self.accel:
            r["Accel"] = self.accel
        return r


# -- commands ----------------------------------------------------------------------------------------


def is_mesh_object(obj):
    """A Mesh::Feature with facets (triangulated input for ParaMesh_Remesh)."""
    return obj.isDerivedFrom("Mesh::Feature") and obj.Mesh.CountFacets > 0


class _CreateMeshCommand(Command):
    """Creates a ParaMesh mesh of each selected object that `accepts`, at its diagonal / 100,
    in one undo step, and opens the last one's task panel."""
    undo = ""
    extra = ()  # commands run on each new mesh (_pm_mesh)
    join_analysis = False

    def accepts(self, obj):
        raise NotImplementedError

    def box(self, obj):
        raise NotImplementedError

    def IsActive(self):
        doc = FreeCAD.ActiveDocument
        if doc is None or dialog_open():
            return False
        return any(self.accepts(o) for o in FreeCADGui.Selection.getSelection(doc.Name))

    def Activated(self):
        doc = FreeCAD.ActiveDocument
        sources = [o for o in FreeCADGui.Selection.getSelection(doc.Name) if self.accepts(o)]
        if not sources:
            return
        analysis = None
        if self.join_analysis:
            try:
                import FemGui
                analysis = FemGui.getActiveAnalysis()
            except Exception:
                analysis = None
            if analysis is not None and analysis.Document != doc:
                analysis = None
        created = []
        with transaction(doc, self.undo):
            FreeCADGui.addModule("freecad.paramesh.app.factories")
            if analysis is not None:
                FreeCADGui.addModule("FemGui")
            for src in sources:
                size = round_sig(self.box(src).DiagonalLength / 100.0, 4)
                FreeCADGui.doCommand(
                    f"_pm_mesh = freecad.paramesh.app.factories.make_surface_mesh("
                    f"App.getDocument({doc.Name!r}), {obj_ref(src)}, size={size!r})")
                for c in self.extra:
                    FreeCADGui.doCommand(c)
                if analysis is not None:
                    FreeCADGui.doCommand("FemGui.getActiveAnalysis().addObject(_pm_mesh)")
                created += [m for m in surface_meshes(doc) if m not in created and m.Part == src][-1:]
        if created:
            open_edit(created[-1])


class SurfaceMeshCommand(_CreateMeshCommand):
    id = "ParaMesh_SurfaceMesh"
    menu = "Surface mesh"
    tooltip = ("Creates a ParaMesh surface mesh (a FEM mesh) of each selected Part object and opens its "
               "parameters; joins the active FEM analysis")
    undo = "Create ParaMesh surface mesh"
    join_analysis = True

    def accepts(self, obj):
        return meshable(obj)

    def box(self, obj):
        return obj.Shape.BoundBox


class RemeshCommand(_CreateMeshCommand):
    id = "ParaMesh_Remesh"
    menu = "Remesh a Mesh object"
    tooltip = ("Remeshes each selected Mesh object (STL, OBJ, a scan) with ParaMesh: faces split at "
               "sharp edges, a ParaMesh mesh (a FEM mesh) and a new Mesh object with its triangles")
    undo = "Remesh with ParaMesh"
    extra = ("_pm_mesh.CreateMeshFeature = True",)

    def accepts(self, obj):
        return is_mesh_object(obj)

    def box(self, obj):
        return obj.Mesh.BoundBox


class BoundaryLayerCommand(Command):
    id = "ParaMesh_BoundaryLayer"
    menu = "Boundary layer"
    tooltip = ("Adds a surface boundary layer to a ParaMesh surface mesh, growing from the selected edges "
               "(select edges of the meshed Part in the 3D view first, or pick them in the panel)")

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and not dialog_open() and target_mesh() is not None

    def Activated(self):
        mesh = target_mesh()
        if mesh is None:
            return
        doc = mesh.Document
        edges = selected_subs(mesh.Part, ("Edge",))
        size = effective_size(mesh)
        before = set(o.Name for o in doc.Objects)
        with transaction(doc, "Create ParaMesh boundary layer"):
            FreeCADGui.addModule("freecad.paramesh.app.factories")
            FreeCADGui.doCommand(
                f"_pm_bl = freecad.paramesh.app.factories.make_boundary_layer(App.getDocument({doc.Name!r}), "
                f"{obj_ref(mesh)}, {edges!r}, first_height={round_sig(size / 20.0, 3)!r}, growth=1.2, layers=10)")
        new = [o for o in doc.Objects if o.Name not in before and proxy_type(o) == BOUNDARY_LAYER]
        if new:
            open_edit(new[0])


class LocalSizeCommand(Command):
    id = "ParaMesh_LocalSize"
    menu = "Local size"
    tooltip = ("Adds a local element size near the selected faces, edges or vertices of the meshed Part "
               "to a ParaMesh surface mesh")

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and not dialog_open() and target_mesh() is not None

    def Activated(self):
        mesh = target_mesh()
        if mesh is None:
            return
        doc = mesh.Document
        refs = selected_subs(mesh.Part, ("Face", "Edge", "Vertex"))
        size = round_sig(effective_size(mesh) / 4.0, 3)
        before = set(o.Name for o in doc.Objects)
        with transaction(doc, "Create ParaMesh local size"):
            FreeCADGui.addModule("freecad.paramesh.app.factories")
            FreeCADGui.doCommand(
                f"_pm_ls = freecad.paramesh.app.factories.make_local_size(App.getDocument({doc.Name!r}), "
                f"{obj_ref(mesh)}, {refs!r}, size={size!r})")
        new = [o for o in doc.Objects if o.Name not in before and proxy_type(o) == LOCAL_SIZE]
        if new:
            open_edit(new[0])


def _meshed_target():
    if FreeCAD.ActiveDocument is None:
        return None
    m = target_mesh()
    return m if m is not None and m.FemMesh.NodeCount > 0 else None


class QualityCommand(Command):
    id = "ParaMesh_Quality"
    menu = "Mesh quality"
    tooltip = ("Shows the quality of a ParaMesh surface mesh: histograms of angles, radius ratio and "
               "edge-length ratio, a colour map on the mesh and the worst elements")

    def IsActive(self):
        return not dialog_open() and _meshed_target() is not None

    def Activated(self):
        mesh = _meshed_target()
        if mesh is None:
            return
        FreeCADGui.addModule("freecad.paramesh.gui.task_quality")
        FreeCADGui.doCommand(f"freecad.paramesh.gui.task_quality.open_quality({obj_ref(mesh)})")


EXPORT_FILTERS = [("Gmsh MSH 4.1 (*.msh)", ".msh"), ("VTK XML unstructured grid (*.vtu)", ".vtu"),
                  ("STL (*.stl)", ".stl"), ("Abaqus / CalculiX (*.inp)", ".inp"),
                  ("I-DEAS universal (*.unv)", ".unv"), ("MED (*.med)", ".med")]
CORE_FORMATS = (".msh", ".vtu", ".stl", ".inp")


def ask_export_path(mesh):
    base = os.path.dirname(mesh.Document.FileName) if mesh.Document.FileName else os.path.expanduser("~")
    filters = ";;".join(f for f, _e in EXPORT_FILTERS)
    path, chosen = QtGui.QFileDialog.getSaveFileName(
        FreeCADGui.getMainWindow(), "Export ParaMesh mesh", os.path.join(base, mesh.Label + ".msh"), filters,
        EXPORT_FILTERS[0][0], QtGui.QFileDialog.DontUseNativeDialog)
    if not path:
        return ""
    if not os.path.splitext(path)[1]:
        path += dict(EXPORT_FILTERS).get(chosen, ".msh")
    return path


def run_in_background(mesh, title):
    """Meshes mesh in a worker thread behind a progress dialog (with Cancel) and stores the result.
    Returns True when the mesh was stored."""
    from .runner import QtMeshRunner, RunError
    from .widgets import settle
    q = QtMeshRunner()
    try:
        q.runner.prepare(mesh)
    except RunError as e:
        QtGui.QMessageBox.warning(FreeCADGui.getMainWindow(), title, str(e))
        return False
    dlg = QtGui.QProgressDialog(title, "Cancel", 0, 1000, FreeCADGui.getMainWindow())
    dlg.setWindowModality(QtCore.Qt.WindowModal)
    dlg.setMinimumDuration(0)
    loop = QtCore.QEventLoop()
    q.finished.connect(loop.quit, QtCore.Qt.QueuedConnection)
    dlg.canceled.connect(q.runner.cancel)
    timer = QtCore.QTimer()
    timer.setInterval(100)

    def tick():
        dlg.setValue(int(1000 * q.runner.fraction))
        dlg.setLabelText(f"{title}\n{q.runner.stage} — {q.runner.elapsed:.1f} s")
        if not q.runner.running:
            loop.quit()
    timer.timeout.connect(tick)
    q.runner.start()
    timer.start()
    if q.runner.running:
        loop.exec_()
    timer.stop()
    dlg.close()
    result = q.runner.collect()
    if result is None:
        if q.runner.state == "failed":
            QtGui.QMessageBox.warning(FreeCADGui.getMainWindow(), title, q.runner.error)
        return False
    mesh.Proxy.apply_result(mesh, result, q.runner.collect_femmesh())
    settle(mesh)
    return True


class ExportCommand(Command):
    id = "ParaMesh_Export"
    menu = "Export mesh…"
    tooltip = "Writes a ParaMesh surface mesh to Gmsh .msh, .vtu, .stl or CalculiX .inp (also .unv, .med)"

    def IsActive(self):
        return not dialog_open() and _meshed_target() is not None

    def Activated(self):
        mesh = _meshed_target()
        if mesh is None:
            return
        path = ask_export_path(mesh)
        if not path:
            return
        ext = os.path.splitext(path)[1].lower()
        if ext in CORE_FORMATS and mesh.Proxy.last_result(mesh) is None:
            # reopened document: the core writes these formats from a run (same parameters, same mesh)
            if not run_in_background(mesh, f"Re-meshing {mesh.Label} to export {os.path.basename(path)}"):
                return
        FreeCADGui.addModule("freecad.paramesh.app.factories")
        try:
            FreeCADGui.doCommand(f"freecad.paramesh.app.factories.export_mesh({obj_ref(mesh)}, {path!r})")
        except Exception as e:
            QtGui.QMessageBox.warning(FreeCADGui.getMainWindow(), "ParaMesh export", str(e))
            return
        FreeCAD.Console.PrintMessage(f"ParaMesh: wrote {path}\n")


class ToMeshCommand(Command):
    id = "ParaMesh_ToMesh"
    menu = "Mesh feature from surface mesh"
    tooltip = ("Creates a Mesh feature (triangles, one segment per CAD face) from a ParaMesh surface mesh "
               "and keeps it up to date when the mesh is re-made")

    def IsActive(self):
        return not dialog_open() and _meshed_target() is not None

    def Activated(self):
        mesh = _meshed_target()
        if mesh is None:
            return
        with transaction(mesh.Document, "ParaMesh: Mesh feature"):
            FreeCADGui.addModule("freecad.paramesh.app.factories")
            FreeCADGui.doCommand(f"_pm_mf = freecad.paramesh.app.factories.make_mesh_feature({obj_ref(mesh)})")
        from .widgets import settle
        settle(mesh)


def _gmsh_target():
    """The one selected FEM Gmsh mesh object, or None."""
    doc = FreeCAD.ActiveDocument
    if doc is None:
        return None
    sel = [o for o in FreeCADGui.Selection.getSelection(doc.Name)
           if getattr(getattr(o, "Proxy", None), "Type", "") == "Fem::FemMeshGmsh"]
    return sel[0] if len(sel) == 1 else None


class FromGmshCommand(Command):
    id = "ParaMesh_FromGmsh"
    menu = "ParaMesh mesh from FEM Gmsh mesh"
    tooltip = ("Turns the selected FEM Gmsh mesh object into a ParaMesh mesh of the same part: its sizes, "
               "order, mesh regions (local sizes) and mesh groups (named groups) carried over; the analysis "
               "then uses the ParaMesh mesh. Settings without a ParaMesh counterpart are listed in the "
               "report view")

    def IsActive(self):
        return not dialog_open() and _gmsh_target() is not None

    def Activated(self):
        gmsh = _gmsh_target()
        if gmsh is None:
            return
        with transaction(gmsh.Document, "ParaMesh: from FEM Gmsh mesh"):
            FreeCADGui.addModule("freecad.paramesh.app.from_gmsh")
            FreeCADGui.doCommand(f"_pm_obj, _pm_notes = freecad.paramesh.app.from_gmsh.from_gmsh_mesh({obj_ref(gmsh)})")


COMMANDS = [SurfaceMeshCommand, RemeshCommand, BoundaryLayerCommand, LocalSizeCommand, QualityCommand, ExportCommand,
            ToMeshCommand, FromGmshCommand]
TOOLBAR = [c.id for c in COMMANDS]
MENU = TOOLBAR

_registered = False


def register():
    global _registered
    if _registered:
        return
    for c in COMMANDS:
        FreeCADGui.addCommand(c.id, c())
    _registered = True
