# SPDX-License-Identifier: LGPL-2.1-or-later
"""View provider of a ParaMesh boundary layer (child of a surface mesh in the tree)."""
from .view_base import ViewProviderBase


class ViewProviderBoundaryLayer(ViewProviderBase):
    icon = "ParaMesh_BoundaryLayer"

    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        import FreeCADGui
        from ..app.objects.boundary_layer import parent_mesh
        from .task_boundary_layer import TaskBoundaryLayer
        parent = parent_mesh(vobj.Object)
        if parent is None:
            import FreeCAD
            FreeCAD.Console.PrintWarning(f"{vobj.Object.Label} belongs to no ParaMesh surface mesh\n")
            return False
        created = getattr(self, "created_by_command", False)
        self.created_by_command = False
        FreeCADGui.Control.showDialog(TaskBoundaryLayer(vobj.Object, parent, created=created))
        return True
