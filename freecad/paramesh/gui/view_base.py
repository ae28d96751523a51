# SPDX-License-Identifier: LGPL-2.1-or-later
"""View-provider base of the ParaMesh objects. View providers are stored in the GuiDocument by
module path: never move or rename these classes without leaving an alias."""
import FreeCAD
import FreeCADGui

from .. import resource_path


class ViewProviderBase:
    icon = "ParaMeshWorkbench"

    def __init__(self, vobj):
        vobj.Proxy = self
        self.attach(vobj)

    def attach(self, vobj):
        self.ViewObject = vobj
        self.Object = vobj.Object

    def getIcon(self):
        return resource_path("icons", self.icon + ".svg")

    def updateData(self, obj, prop):
        return

    def onChanged(self, vobj, prop):
        return

    def doubleClicked(self, vobj):
        gdoc = FreeCADGui.getDocument(vobj.Object.Document)
        if gdoc.getInEdit() is not None or FreeCADGui.Control.activeDialog():
            FreeCAD.Console.PrintWarning("ParaMesh: close the open task panel first\n")
            return True
        gdoc.setEdit(vobj.Object.Name)
        return True

    def setupContextMenu(self, vobj, menu):
        action = menu.addAction("Edit ParaMesh parameters")
        action.triggered.connect(lambda: self.doubleClicked(vobj))

    def unsetEdit(self, vobj, mode=0):
        FreeCADGui.Control.closeDialog()
        return True

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    def dumps(self):
        return None

    def loads(self, state):
        return None


class ViewProviderChild(ViewProviderBase):
    """A child of a surface mesh (boundary layer, local size): double-click opens `task_class`
    (imported from `task_module` in this package) on the child and its parent mesh."""

    task_module = ""
    task_class = ""

    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        import importlib
        from ..app.objects.boundary_layer import parent_mesh
        task = getattr(importlib.import_module(f"{__package__}.{self.task_module}"), self.task_class)
        parent = parent_mesh(vobj.Object)
        if parent is None:
            FreeCAD.Console.PrintWarning(f"{vobj.Object.Label} belongs to no ParaMesh surface mesh\n")
            return False
        created = getattr(self, "created_by_command", False)
        self.created_by_command = False
        FreeCADGui.Control.showDialog(task(vobj.Object, parent, created=created))
        return True
