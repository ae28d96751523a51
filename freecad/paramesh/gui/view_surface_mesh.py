# SPDX-License-Identifier: LGPL-2.1-or-later
"""View provider of the ParaMesh surface mesh (FemGui::ViewProviderFemMeshPython): its boundary
layers and local sizes are its children in the tree; double-click opens the task panel."""
from .view_base import ViewProviderBase

CHILD_TYPES = ("ParaMesh::BoundaryLayer", "ParaMesh::LocalSize")


def _type(obj):
    return getattr(getattr(obj, "Proxy", None), "Type", "")


class ViewProviderSurfaceMesh(ViewProviderBase):
    icon = "ParaMesh_SurfaceMesh"

    def claimChildren(self):
        o = self.Object
        return list(getattr(o, "BoundaryLayerList", [])) + list(getattr(o, "LocalSizeList", []))

    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None  # transform etc.: FreeCAD's default
        from .task_surface_mesh import TaskSurfaceMesh
        import FreeCADGui
        created = getattr(self, "created_by_command", False)
        self.created_by_command = False
        FreeCADGui.Control.showDialog(TaskSurfaceMesh(vobj.Object, created=created))
        return True

    def onDelete(self, vobj, subelements):
        return True

    # drag and drop of boundary layers / local sizes between meshes
    def canDragObjects(self):
        return True

    def canDropObjects(self):
        return True

    def canDragObject(self, obj):
        return _type(obj) in CHILD_TYPES

    def canDropObject(self, obj):
        return _type(obj) in CHILD_TYPES

    def dragObject(self, vobj, obj):
        prop = "BoundaryLayerList" if _type(obj) == CHILD_TYPES[0] else "LocalSizeList"
        items = [c for c in getattr(self.Object, prop) if c != obj]
        setattr(self.Object, prop, items)

    def dropObject(self, vobj, obj):
        prop = "BoundaryLayerList" if _type(obj) == CHILD_TYPES[0] else "LocalSizeList"
        items = list(getattr(self.Object, prop))
        if obj not in items:
            items.append(obj)
            setattr(self.Object, prop, items)
