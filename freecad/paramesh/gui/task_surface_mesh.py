# SPDX-License-Identifier: LGPL-2.1-or-later
"""Task panel of a ParaMesh surface mesh: the meshing parameters (with units and the property
tooltips), the boundary layers and local sizes it uses, and the run box."""
import html

import FreeCADGui
from PySide import QtGui

from ..core.report_text import volume_lines
from .task_base import MeshTaskPanel, remove_objects
from .widgets import Field, ParamForm, report_of


def surface_mesh_fields():
    return [
        Field("Size", "Size", "length", step=1.0),
        Field("MinSize", "Minimum size", "length", step=0.1),
        Field("MaxSize", "Maximum size", "length", step=1.0),
        Field("CurvatureAngle", "Curvature angle", "angle", maximum=179.9, step=1.0),
        Field("MaxDeviation", "Max deviation (× size)", "float", maximum=1.0, step=0.01, special="off"),
        Field("Grading", "Grading", "float", minimum=1.01, maximum=10.0, step=0.05, decimals=2),
        Field("ElementOrder", "Element order", "enum", items=["1st", "2nd"]),
        Field("Quads", "Quad-dominant", "bool"),
        Field("Volume3D", "3D (fill solids with tetrahedra)", "bool"),
        Field("VolumeMaxSize", "Max tetrahedron size (0: max size)", "length", step=1.0),
        Field("VolumeOptimize", "Tetrahedron optimisation passes", "int", maximum=10),
        Field("Proximity", "Elements across thin parts", "int", maximum=100, special="off"),
        Field("Threads", "Threads", "int", maximum=1024, special="all cores"),
        Field("OptimizePasses", "Optimisation passes", "int", maximum=100),
        Field("NearestFaceBudget", "Nearest-face refinement budget", "float", maximum=10.0, step=0.05,
              decimals=2, special="off"),
        Field("NearestFaceCheck", "Always refine nearest-face", "bool"),
        Field("MaxElements", "Max elements", "int", minimum=1000, maximum=2 ** 31 - 1),
        Field("CreateMeshFeature", "Also make a Mesh feature", "bool"),
    ]


class TaskSurfaceMesh(MeshTaskPanel):
    """Edits and meshes a ParaMesh surface mesh."""

    def __init__(self, mesh_obj, created=False):
        super().__init__(mesh_obj, mesh_obj, created)

    def build_forms(self):
        m = self.mesh
        self.params = ParamForm(m, surface_mesh_fields(), f"ParaMesh surface mesh — {m.Label}")
        icon = QtGui.QIcon(_icon("ParaMesh_SurfaceMesh"))
        self.params.setWindowIcon(icon)
        if m.Part is not None and not hasattr(m.Part, "Shape") and hasattr(m.Part, "Mesh"):
            what = f"{m.Part.Mesh.CountFacets} facets, remeshed"  # a Mesh object (triangulated input)
        else:
            what = f"{len(m.Part.Shape.Faces)} faces" if m.Part is not None else ""
        part = QtGui.QLabel(f"<b>{m.Part.Label}</b> ({what})" if m.Part else
                            "<span style='color:#c00000'>no Part</span>")
        part.setToolTip(m.getDocumentationOfProperty("Part"))
        self.params.layout_.insertRow(0, "Part", part)
        self.children = QtGui.QLabel()
        self.children.setWordWrap(True)
        self.params.layout_.addRow("Children", self.children)
        self.update_children()
        self.volume = QtGui.QLabel()
        self.volume.setWordWrap(True)
        self.volume.setObjectName("VolumeCounts")
        self.volume.setToolTip("Tetrahedra of the last run, per solid (FreeCAD's Solid<i>; "
                               "the FEM mesh's volume groups have the same names)")
        self.params.layout_.addRow("Tetrahedra", self.volume)
        self.update_volume()
        # the 3D options show only when 3D is ticked: the panel stays short enough for the run box
        # (progress, time, log) to be seen without scrolling
        three_d = self.params.widget("Volume3D")
        three_d.toggled.connect(self._show_3d_options)
        self._show_3d_options(three_d.isChecked())
        return [self.params]

    def _show_3d_options(self, on):
        for prop in ("VolumeMaxSize", "VolumeOptimize"):
            self._show_row(self.params.widget(prop), on)

    def _show_row(self, widget, on):
        label = self.params.layout_.labelForField(widget)
        widget.setVisible(on)
        if label is not None:
            label.setVisible(on)

    def update_volume(self):
        """Shows the tetrahedra per solid of the object's last report (the row is hidden when the
        last run made none)."""
        lines = volume_lines(report_of(self.mesh))
        self.volume.setText("<br>".join(
            f'<span style="color:{"#c00000" if level == "error" else "#202020"}">{html.escape(text)}</span>'
            for level, text in lines))
        self._show_row(self.volume, bool(lines))

    def _run_finished(self, state):
        self.update_volume()
        super()._run_finished(state)

    def update_children(self):
        m = self.mesh
        items = [f"{c.Label} ({', '.join(s for _o, subs in c.References for s in subs) or 'auto'})"
                 for c in list(m.BoundaryLayerList) + list(m.LocalSizeList)]
        self.children.setText("<br>".join(items) if items else
                              "none — add boundary layers and local sizes with the toolbar commands")

    def write_values(self):
        return bool(self.params.write())

    def on_close(self):
        self.restore_view()

    def discard(self):
        m = self.mesh
        remove_objects(list(m.BoundaryLayerList) + list(m.LocalSizeList) + [m.MeshFeature, m])


def _icon(name):
    from .. import resource_path
    return resource_path("icons", name + ".svg")


def open_panel(mesh_obj, created=False):
    panel = TaskSurfaceMesh(mesh_obj, created)
    FreeCADGui.Control.showDialog(panel)
    return panel
