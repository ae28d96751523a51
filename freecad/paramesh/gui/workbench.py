# SPDX-License-Identifier: LGPL-2.1-or-later
"""The ParaMesh workbench (registered by the repository's InitGui.py)."""
import FreeCADGui

from .. import resource_path


class ParaMeshWorkbench(FreeCADGui.Workbench):
    """Surface meshes of Part objects for FEM and CFD: parameters, boundary layers, local sizes,
    quality and export."""

    MenuText = "ParaMesh"
    ToolTip = "ParaMesh: parametric CAD surface meshes with surface boundary layers"
    Icon = resource_path("icons", "ParaMeshWorkbench.svg")

    def Initialize(self):
        from . import commands
        commands.register()
        self.appendToolbar("ParaMesh", commands.TOOLBAR)
        self.appendMenu("&ParaMesh", commands.MENU)
        FreeCADGui.addIconPath(resource_path("icons"))

    def Activated(self):
        return

    def Deactivated(self):
        return

    def ContextMenu(self, recipient):
        from . import commands
        self.appendContextMenu("ParaMesh", commands.TOOLBAR)

    def GetClassName(self):
        return "Gui::PythonWorkbench"
