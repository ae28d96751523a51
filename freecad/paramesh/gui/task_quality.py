# SPDX-License-Identifier: LGPL-2.1-or-later
"""Mesh quality view: histograms of corner angles, radius ratio and edge-length ratio, a colour
map of element quality on the mesh in the 3D view, and the worst elements (select one to
highlight its nodes and zoom to it)."""
import html

import numpy as np

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from .quality_metrics import METRICS, Quality, colormap

ACTIVE = None


def _qcolor(rgb):
    return QtGui.QColor(int(255 * rgb[0]), int(255 * rgb[1]), int(255 * rgb[2]))


class Histogram(QtGui.QWidget):
    """A bar chart drawn with QPainter (no plotting dependency)."""

    def __init__(self, title, parent=None):
        super().__init__(parent)
        self.title = title
        self.counts = np.zeros(0)
        self.edges = np.zeros(0)
        self.colors = []
        self.marks = []
        self.setMinimumHeight(120)
        self.setSizePolicy(QtGui.QSizePolicy.Expanding, QtGui.QSizePolicy.Fixed)

    def set_data(self, counts, edges, colors=None, marks=(), fmt="{:g}"):
        self.counts, self.edges = np.asarray(counts), np.asarray(edges)
        self.colors = colors or []
        self.marks = list(marks)
        self.fmt = fmt
        self.setToolTip("\n".join(f"{fmt.format(a)} – {fmt.format(b)}: {int(c)}"
                                  for a, b, c in zip(self.edges[:-1], self.edges[1:], self.counts) if c))
        self.update()

    def paintEvent(self, event):
        p = QtGui.QPainter(self)
        p.setRenderHint(QtGui.QPainter.Antialiasing, False)
        r = self.rect()
        p.fillRect(r, QtGui.QColor(255, 255, 255))
        fm = p.fontMetrics()
        th = fm.height()
        left, right, top, bottom = 34, 8, th + 4, th + 6
        plot = QtCore.QRect(r.left() + left, r.top() + top, r.width() - left - right, r.height() - top - bottom)
        p.setPen(QtGui.QColor(30, 30, 30))
        total = int(self.counts.sum()) if len(self.counts) else 0
        p.drawText(r.left() + 4, r.top() + th, f"{self.title}  ({total} values, log scale)")
        if len(self.counts) == 0 or plot.width() <= 0 or plot.height() <= 0:
            p.end()
            return
        cmax = max(1, int(self.counts.max()))
        n = len(self.counts)
        bw = plot.width() / n
        top = np.log10(1.0 + cmax)  # log scale: a few bad elements stay visible next to thousands of good ones
        for i, c in enumerate(self.counts):
            if c <= 0:
                continue
            h = max(2, int(round(plot.height() * np.log10(1.0 + c) / top)))
            col = self.colors[i] if i < len(self.colors) else QtGui.QColor(70, 110, 200)
            p.fillRect(QtCore.QRectF(plot.left() + i * bw + 0.5, plot.bottom() - h + 1, max(1.0, bw - 1), h), col)
        p.setPen(QtGui.QColor(90, 90, 90))
        p.drawLine(plot.bottomLeft(), plot.bottomRight())
        p.drawLine(plot.bottomLeft(), plot.topLeft())
        p.drawText(r.left() + 2, plot.top() + th, str(cmax))
        p.drawText(r.left() + 2, plot.bottom(), "0")
        lo, hi = float(self.edges[0]), float(self.edges[-1])
        for x in [lo, (lo + hi) / 2, hi] + self.marks:
            px = plot.left() + (x - lo) / (hi - lo) * plot.width()
            label = self.fmt.format(x)
            w = fm.horizontalAdvance(label) if hasattr(fm, "horizontalAdvance") else fm.width(label)
            p.drawLine(int(px), plot.bottom(), int(px), plot.bottom() + 3)
            p.drawText(int(min(max(px - w / 2, r.left()), r.right() - w)), r.bottom() - 2, label)
        p.end()


class Legend(QtGui.QWidget):
    def __init__(self, parent=None):
        super().__init__(parent)
        self.low, self.high = "bad", "good"
        self.setMinimumHeight(30)

    def set_labels(self, low, high):
        self.low, self.high = low, high
        self.update()

    def paintEvent(self, event):
        p = QtGui.QPainter(self)
        r = self.rect().adjusted(2, 2, -2, -16)
        g = QtGui.QLinearGradient(r.left(), 0, r.right(), 0)
        for t in np.linspace(0, 1, 9):
            g.setColorAt(float(t), _qcolor(colormap(t)))
        p.fillRect(r, QtGui.QBrush(g))
        p.setPen(QtGui.QColor(30, 30, 30))
        p.drawText(r.left(), self.rect().bottom() - 2, self.low)
        fm = p.fontMetrics()
        w = fm.horizontalAdvance(self.high) if hasattr(fm, "horizontalAdvance") else fm.width(self.high)
        p.drawText(r.right() - w, self.rect().bottom() - 2, self.high)
        p.end()


class TaskQuality:
    """Task panel showing the quality of a ParaMesh surface mesh (or any FEM mesh object)."""

    WORST = 50

    def __init__(self, mesh_obj):
        global ACTIVE
        self.mesh = mesh_obj
        proxy = getattr(mesh_obj, "Proxy", None)
        if proxy is not None and hasattr(proxy, "mesh_arrays"):
            arrays = proxy.mesh_arrays(mesh_obj)
        else:
            from ..app.objects.surface_mesh import femmesh_arrays
            arrays = femmesh_arrays(mesh_obj.FemMesh)
        self.arrays = arrays
        self.quality = Quality(arrays)
        self.form = self._build()
        self.metric = "radius_ratio"
        self.fill()
        FreeCADGui.Selection.clearSelection()  # the selection colour would tint the colour map
        self.apply_colors()
        ACTIVE = self

    def _build(self):
        w = QtGui.QWidget()
        w.setWindowTitle(f"ParaMesh quality — {self.mesh.Label}")
        from .. import resource_path
        w.setWindowIcon(QtGui.QIcon(resource_path("icons", "ParaMesh_Quality.svg")))
        lay = QtGui.QVBoxLayout(w)
        self.summary = QtGui.QLabel()
        self.summary.setWordWrap(True)
        lay.addWidget(self.summary)
        row = QtGui.QHBoxLayout()
        row.addWidget(QtGui.QLabel("Colour by"))
        self.combo = QtGui.QComboBox()
        self.combo.setObjectName("Metric")
        for key, (label, _u, _b, _r) in METRICS.items():
            self.combo.addItem(label, key)
        self.combo.setToolTip("Element quality shown as colours on the mesh; red is worst")
        row.addWidget(self.combo, 1)
        lay.addLayout(row)
        self.legend = Legend()
        lay.addWidget(self.legend)
        self.h_angle = Histogram("Corner angles [°]")
        self.h_angle.setToolTip("All corner angles of all elements")
        self.h_gamma = Histogram("Radius ratio (1 = equilateral / square)")
        self.h_edge = Histogram("Edge-length ratio (longest / shortest)")
        for h in (self.h_angle, self.h_gamma, self.h_edge):
            lay.addWidget(h)
        lay.addWidget(QtGui.QLabel(f"Worst elements (select one to show it):"))
        self.table = QtGui.QTableWidget(0, 5)
        self.table.setObjectName("WorstElements")
        self.table.setHorizontalHeaderLabels(["Element", "Type", "CAD face", "Value", "Min angle"])
        self.table.setSelectionBehavior(QtGui.QAbstractItemView.SelectRows)
        self.table.setSelectionMode(QtGui.QAbstractItemView.SingleSelection)
        self.table.setEditTriggers(QtGui.QAbstractItemView.NoEditTriggers)
        self.table.verticalHeader().setVisible(False)
        self.table.horizontalHeader().setStretchLastSection(True)
        self.table.setMinimumHeight(160)
        lay.addWidget(self.table)
        self.combo.currentIndexChanged.connect(self._metric_changed)
        self.table.itemSelectionChanged.connect(self._row_selected)
        return w

    # -- content --
    def fill(self):
        q = self.quality
        s = q.summary()
        self.summary.setText(
            f"<b>{s['triangles']}</b> triangles, <b>{s['quads']}</b> quads<br>"
            f"angles {s['angle_min']:.1f}° … {s['angle_max']:.1f}°; radius ratio min {s['radius_ratio_min']:.3f}, "
            f"mean {s['radius_ratio_mean']:.3f}; edge ratio max {s['edge_ratio_max']:.3g}")
        c, e = q.histogram("angle")
        self.h_angle.set_data(c, e, marks=[60.0, 90.0], fmt="{:.0f}")
        c, e = q.histogram("radius_ratio")
        centers = 0.5 * (e[:-1] + e[1:])
        self.h_gamma.set_data(c, e, [_qcolor(x) for x in colormap(centers)], fmt="{:.1f}")
        c, e = q.histogram("edge_ratio")
        centers = 0.5 * (e[:-1] + e[1:])
        self.h_edge.set_data(c, e, [_qcolor(x) for x in colormap(1.0 / centers)], fmt="{:.0f}")
        self.fill_table()

    def fill_table(self):
        q = self.quality
        label, unit, better_high, _rng = METRICS[self.metric]
        self.legend.set_labels(f"worst {label.lower()}", "best")
        worst = q.worst(self.metric, self.WORST)
        self.rows = list(worst)
        self.table.blockSignals(True)
        self.table.setRowCount(len(worst))
        vals = q.values(self.metric)
        for r, i in enumerate(worst):
            items = [str(int(q.element_ids[i])), q.kind(i), f"Face{int(q.face[i])}" if q.face[i] else "?",
                     f"{vals[i]:.4g}{unit}", f"{q.min_angle[i]:.2f}°"]
            for c, text in enumerate(items):
                it = QtGui.QTableWidgetItem(text)
                if c == 3:
                    it.setBackground(_qcolor(colormap(q.normalized(self.metric)[i])))
                self.table.setItem(r, c, it)
        self.table.blockSignals(False)
        self.table.resizeColumnsToContents()

    def apply_colors(self):
        vo = getattr(self.mesh, "ViewObject", None)
        if vo is None:
            return 0
        q = self.quality
        value = q.normalized(self.metric)
        rgb = colormap(value)
        ids = getattr(self.arrays, "display_ids", q.element_ids)
        # on a mesh with tetrahedra a tetrahedron shows the colour of its worst surface triangle
        order = np.argsort(-value, kind="stable")  # best first: the worst is written last
        colours = {int(e): tuple(c) for e, c in zip(ids[order].tolist(), rgb[order].tolist())}
        vo.ElementColor = colours
        self.colored_ids = set(colours)
        vo.Visibility = True
        if not hasattr(self, "_display_mode"):
            self._display_mode = vo.DisplayMode
            if "Faces" in vo.listDisplayModes():
                vo.DisplayMode = "Faces"  # colours read better without the dense wireframe
        self.colored = len(ids)
        return self.colored

    def _metric_changed(self, index):
        self.metric = self.combo.itemData(index)
        self.fill_table()
        self.apply_colors()

    def select_row(self, row):
        self.table.selectRow(row)

    def _row_selected(self):
        rows = sorted({i.row() for i in self.table.selectedItems()})
        if not rows:
            return
        i = self.rows[rows[0]]
        self.show_element(i)

    def show_element(self, i):
        """Highlights the nodes of element i and centres the 3D view on it."""
        q = self.quality
        corners = q.corners(i)
        node_ids = [int(self.arrays.node_ids[c]) for c in corners]
        vo = getattr(self.mesh, "ViewObject", None)
        if vo is not None:
            vo.HighlightedNodes = node_ids
        self.highlighted = node_ids
        pts = q.points[corners]
        center = pts.mean(axis=0)
        extent = float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))
        try:
            view = FreeCADGui.getDocument(self.mesh.Document.Name).ActiveView
            cam = view.getCameraNode()
            d = view.getViewDirection()
            size = max(extent * 3.0, 1e-6)
            pos = FreeCAD.Vector(*center) - d * (size * 4.0)
            cam.position.setValue(pos.x, pos.y, pos.z)
            cam.focalDistance.setValue(size * 4.0)
            if hasattr(cam, "height"):
                cam.height.setValue(size)
        except Exception as e:  # no 3D view (e.g. a drawing is active): highlighting is enough
            FreeCAD.Console.PrintLog(f"ParaMesh quality: cannot zoom ({e})\n")
        return node_ids

    # -- task dialog --
    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Close)

    def reset_view(self):
        vo = getattr(self.mesh, "ViewObject", None)
        if vo is not None:
            try:
                vo.ElementColor = {}
                vo.HighlightedNodes = []
                if getattr(self, "_display_mode", None):
                    vo.DisplayMode = self._display_mode
            except Exception:
                pass

    def reject(self):
        global ACTIVE
        self.reset_view()
        if ACTIVE is self:
            ACTIVE = None
        return True

    def accept(self):
        return self.reject()


def open_quality(mesh_obj):
    panel = TaskQuality(mesh_obj)
    FreeCADGui.Control.showDialog(panel)
    return panel
