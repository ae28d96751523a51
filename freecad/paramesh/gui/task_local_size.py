# SPDX-License-Identifier: LGPL-2.1-or-later
"""Task panel of a ParaMesh local size: the faces, edges or vertices (picked in the 3D view) and
the size near them, and a run box that re-meshes the parent surface mesh."""
import FreeCADGui

from .. import resource_path
from .task_base import MeshTaskPanel, remove_objects
from .widgets import Field, ParamForm, ReferenceList


class TaskLocalSize(MeshTaskPanel):

    def __init__(self, ls_obj, mesh_obj, created=False):
        self.ls = ls_obj
        super().__init__(mesh_obj, ls_obj, created)

    def build_forms(self):
        ls, m = self.ls, self.mesh
        self.refs = ReferenceList(f"Faces, edges, vertices of {m.Part.Label if m.Part else '?'}", m.Part,
                                  ("Face", "Edge", "Vertex"), ls.References,
                                  icon=resource_path("icons", "ParaMesh_LocalSize.svg"))
        self.refs.setToolTip(ls.getDocumentationOfProperty("References"))
        self.params = ParamForm(ls, [Field("Size", "Size", "length", step=0.1)],
                                f"ParaMesh local size — {ls.Label}",
                                icon=resource_path("icons", "ParaMesh_LocalSize.svg"))
        self.refs.pick.setChecked(True)
        self.picking_view()
        return [self.refs, self.params]

    def on_close(self):
        self.refs.stop_picking()
        self.restore_view()

    def write_values(self):
        changed = self.params.write()
        refs = self.refs.references()
        if [(o.Name, tuple(s)) for o, s in self.ls.References] != [(o.Name, tuple(s)) for o, s in refs]:
            names = self.refs.names()
            part = self.mesh.Part
            target = f"App.getDocument({self.ls.Document.Name!r}).getObject({self.ls.Name!r})"
            FreeCADGui.doCommand(
                f"{target}.References = [(App.getDocument({part.Document.Name!r}).getObject({part.Name!r}), "
                f"{tuple(names)!r})]" if names else f"{target}.References = []")
            changed.append("References")
        return bool(changed)

    def discard(self):
        m = self.mesh
        rest = [c for c in m.LocalSizeList if c != self.ls]
        FreeCADGui.doCommand(
            f"App.getDocument({m.Document.Name!r}).getObject({m.Name!r}).LocalSizeList = "
            f"[{', '.join(f'App.getDocument({c.Document.Name!r}).getObject({c.Name!r})' for c in rest)}]")
        remove_objects([self.ls])
