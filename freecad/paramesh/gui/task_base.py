# SPDX-License-Identifier: LGPL-2.1-or-later
"""Common behaviour of the ParaMesh task panels that end in a meshing run.

Buttons: Apply writes the values (FreeCADGui.doCommand, one undo transaction) and meshes the
surface mesh in a worker thread; OK does the same when something changed and closes when the run
succeeded; Cancel stops a running mesh, and when the panel edits an object a command has just
created and that was never applied, removes it again (no partial object is left behind).
"""
import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from .widgets import RunBox

#: the panel currently shown (scripts and tests drive it through this)
ACTIVE = None


class MeshTaskPanel:
    """Base panel: subclasses build self.forms (widgets) and implement write_values() and, for
    freshly created objects, discard()."""

    title = "ParaMesh"

    def __init__(self, mesh_obj, edit_obj, created=False):
        global ACTIVE
        self.mesh = mesh_obj
        self.obj = edit_obj
        self.created = created
        self.applied_once = False
        self.close_after_run = False
        self.closed = False
        self.run = RunBox()
        self.run.finished.connect(self._run_finished)
        self.form = self.build_forms() + [self.run]
        ACTIVE = self

    # -- to implement --
    def build_forms(self):
        return []

    def write_values(self):
        """Writes widget values to the document; returns True when something changed."""
        return False

    def discard(self):
        """Removes the object this panel created (Cancel before any Apply)."""

    def on_close(self):
        """Restores what the panel changed in the view (selection gates, visibility)."""

    # -- FreeCAD task dialog protocol --
    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Apply | QtGui.QDialogButtonBox.Cancel)

    def clicked(self, button):
        if button == QtGui.QDialogButtonBox.Apply:
            self.apply()

    def needs_run(self, changed):
        m = self.mesh
        return changed or m.FemMesh.NodeCount == 0 or m.Status in ("", "failed") or "Touched" in m.State or any(
            "Touched" in c.State for c in list(m.BoundaryLayerList) + list(m.LocalSizeList))

    def apply(self, close_after=False):
        """Writes the values and starts meshing; returns False when no run was started."""
        if self.run.running:
            self.run.message("warning", "a run is in progress: wait for it or press 'Cancel run'")
            return False
        doc = self.mesh.Document
        doc.openTransaction(f"ParaMesh: edit {self.obj.Label}")
        try:
            changed = self.write_values()
        except Exception as e:
            doc.abortTransaction()
            self.run._fail(str(e))
            return False
        doc.commitTransaction()
        if not self.needs_run(changed) and close_after:
            self.applied_once = True
            return False
        self.close_after_run = close_after
        self.show_mesh()
        return self.run.start(self.mesh)

    def accept(self):
        if self.run.running:
            self.close_after_run = True
            self.run.message("log", "the panel closes when the run ends")
            return False
        started = self.apply(close_after=True)
        if started or self.run.running:
            return False  # closes when the run succeeds (see _run_finished)
        if self.run.state == "failed" and not self.applied_once:
            return False  # keep the panel open to show the error
        self._close()
        return True

    def reject(self):
        self.run.stop()
        discard = self.created and not self.applied_once
        self._close()
        if discard:
            doc = self.mesh.Document
            doc.openTransaction(f"ParaMesh: discard {self.obj.Label}")
            try:
                self.discard()
            finally:
                doc.commitTransaction()
        return True

    # -- helpers --
    def _set_visible(self, obj, on):
        vo = getattr(obj, "ViewObject", None) if obj is not None else None
        if vo is not None:
            vo.Visibility = on

    def picking_view(self):
        """Shows the Part (to pick its elements) and hides the mesh; on_close restores them."""
        self._original = [(o, o.ViewObject.Visibility) for o in (self.mesh.Part, self.mesh)
                          if o is not None and getattr(o, "ViewObject", None) is not None]
        self._set_visible(self.mesh.Part, True)
        self._set_visible(self.mesh, False)

    def show_mesh(self):
        """Shows the mesh (and hides its Part) when a run starts."""
        self._meshed_view = True
        self._set_visible(self.mesh, True)
        self._set_visible(self.mesh.Part, False)

    def restore_view(self):
        if getattr(self, "_meshed_view", False):
            self.show_mesh()
            return
        for o, vis in getattr(self, "_original", []):
            try:
                o.ViewObject.Visibility = vis
            except Exception:  # deleted meanwhile
                pass

    def _run_finished(self, state):
        if state == "done":
            self.applied_once = True
            if self.mesh.Status == "failed":
                self.close_after_run = False
        else:
            self.close_after_run = False
        if self.close_after_run and not self.closed:
            self.close_after_run = False
            QtCore.QTimer.singleShot(0, self._close_dialog)

    def _close_dialog(self):
        if self.closed:
            return
        self._close()
        FreeCADGui.Control.closeDialog()

    def _close(self):
        global ACTIVE
        if self.closed:
            return
        self.closed = True
        self.run.timer.stop()
        try:
            self.on_close()
        finally:
            gdoc = FreeCADGui.getDocument(self.mesh.Document.Name) if self.mesh.Document else None
            if gdoc is not None and gdoc.getInEdit() is not None:
                gdoc.resetEdit()
            if ACTIVE is self:
                ACTIVE = None


def remove_objects(objs):
    """Removes objects (if still there) through doCommand."""
    for o in objs:
        if o is None:
            continue
        try:
            doc, name = o.Document.Name, o.Name
        except Exception:  # already deleted
            continue
        if FreeCAD.getDocument(doc).getObject(name) is not None:
            FreeCADGui.doCommand(f"App.getDocument({doc!r}).removeObject({name!r})")
