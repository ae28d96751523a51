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
