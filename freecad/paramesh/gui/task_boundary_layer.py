# SPDX-License-Identifier: LGPL-2.1-or-later
"""Task panel of a ParaMesh boundary layer: the edges it grows from (picked in the 3D view, or
proposed automatically), first height, growth, layers or thickness, and a run box that re-meshes
the parent surface mesh."""
import FreeCADGui
from PySide import QtGui

from .. import resource_path
from .task_base import MeshTaskPanel, remove_objects
from .widgets import Field, ParamForm, ReferenceList


def boundary_layer_fields():
    return [
        Field("FirstHeight", "First height", "length", step=0.1),
        Field("Growth", "Growth ratio", "float", minimum=1.0, maximum=5.0, step=0.05, decimals=3),
        Field("Layers", "Layers", "int", maximum=1000, special="from thickness"),
        Field("Thickness", "Thickness", "length", step=1.0),
        Field("MaxAspect", "Max aspect ratio", "float", maximum=1e6, step=1.0, special="off"),
        Field("Quads", "Quadrilaterals", "bool"),
        Field("AutoEdges", "Also detected leading edges", "bool"),
    ]


def propose_function():
    """freecad.paramesh.propose_leading_edges when the core provides it, else None."""
    import freecad.paramesh as pm
    return getattr(pm, "propose_leading_edges", None)


class TaskBoundaryLayer(MeshTaskPanel):

    def __init__(self, bl_obj, mesh_obj, created=False):
        self.bl = bl_obj
        super().__init__(mesh_obj, bl_obj, created)

    def build_forms(self):
        bl, m = self.bl, self.mesh
        self.refs = ReferenceList(f"Edges of {m.Part.Label if m.Part else '?'}", m.Part, ("Edge",),
                                  bl.References, icon=resource_path("icons", "ParaMesh_BoundaryLayer.svg"))
        self.refs.setToolTip(bl.getDocumentationOfProperty("References"))
        self.propose = QtGui.QPushButton("Propose leading edges automatically")
        self.propose.setObjectName("ProposeLeadingEdges")
        self.propose.setToolTip("Adds the edges along which the surface curves far more across than along "
                                "(rounded leading edges of wings and blades)")
        self.propose.clicked.connect(self.propose_edges)
        self.refs.extra.addWidget(self.propose)
        self.propose.setVisible(propose_function() is not None)
        self.proposal = QtGui.QLabel("")
        self.proposal.setWordWrap(True)
        self.refs.layout().addWidget(self.proposal)
        self.params = ParamForm(bl, boundary_layer_fields(), f"ParaMesh boundary layer — {bl.Label}",
                                icon=resource_path("icons", "ParaMesh_BoundaryLayer.svg"))
        self.thickness_label = QtGui.QLabel()
        self.thickness_label.setWordWrap(True)
        self.params.layout_.addRow("Resulting", self.thickness_label)
        for prop in ("FirstHeight", "Thickness"):
            self.params.widget(prop).valueChanged.connect(self.update_info)
        for prop in ("Growth", "Layers"):
            self.params.widget(prop).valueChanged.connect(self.update_info)
        self.update_info()
        self.refs.pick.setChecked(True)  # clicking edges adds them, like FEM's reference panels
        self.picking_view()
        return [self.refs, self.params]

    def update_info(self, *args):
        v = self.params.values()
        h, g, n, t = v["FirstHeight"], v["Growth"], v["Layers"], v["Thickness"]
        if n > 0:
            total = h * n if abs(g - 1) < 1e-12 else h * (g ** n - 1) / (g - 1)
            self.thickness_label.setText(f"thickness {total:.4g} mm, last row {h * g ** (n - 1):.4g} mm")
        elif t > 0 and h > 0:
            import math
            k = t / h if abs(g - 1) < 1e-12 else math.log(1 + t * (g - 1) / h) / math.log(g)
            self.thickness_label.setText(f"about {math.ceil(k - 1e-9)} layers")
        else:
            self.thickness_label.setText("give Layers or Thickness")

    def propose_edges(self):
        fn = propose_function()
        if fn is None or self.mesh.Part is None:
            return []
        try:
            found = fn(self.mesh.Part.Shape)
        except Exception as e:
            self.proposal.setText(f"<span style='color:#c00000'>{e}</span>")
            return []
        names = []
        for d in found:
            edges = [d["edge"]] + list(d.get("coincident_edges", []) if isinstance(d, dict) else [])
            for e in edges:
                if self.refs.add(f"Edge{int(e)}"):
                    names.append(f"Edge{int(e)}")
        text = ", ".join(f"Edge{d['edge']} (radius {d.get('radius', 0):.3g} mm)" for d in found)
        self.proposal.setText(f"Proposed: {text}" if found else "No leading edge found.")
        return names

    def on_close(self):
        self.refs.stop_picking()
        self.restore_view()

    def write_values(self):
        changed = self.params.write()
        refs = self.refs.references()
        if [(o.Name, tuple(s)) for o, s in self.bl.References] != [(o.Name, tuple(s)) for o, s in refs]:
            names = self.refs.names()
            part = self.mesh.Part
            FreeCADGui.doCommand(
                f"App.getDocument({self.bl.Document.Name!r}).getObject({self.bl.Name!r}).References = "
                f"[(App.getDocument({part.Document.Name!r}).getObject({part.Name!r}), {tuple(names)!r})]"
                if names else
                f"App.getDocument({self.bl.Document.Name!r}).getObject({self.bl.Name!r}).References = []")
            changed.append("References")
        return bool(changed)

    def discard(self):
        m = self.mesh
        rest = [c for c in m.BoundaryLayerList if c != self.bl]
        FreeCADGui.doCommand(
            f"App.getDocument({m.Document.Name!r}).getObject({m.Name!r}).BoundaryLayerList = "
            f"[{', '.join(f'App.getDocument({c.Document.Name!r}).getObject({c.Name!r})' for c in rest)}]")
        remove_objects([self.bl])


