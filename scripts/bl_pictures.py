#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Renders the boundary-layer pictures of docs/boundary_layers.md into docs/img/.

Usage (from the repository root, after the build): /usr/bin/python3 scripts/bl_pictures.py [OUTDIR]
The plate with holes is built with FreeCAD's Part (skipped without FreeCAD).
"""
import math
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
import freecad.paramesh as pm  # noqa: E402

DATA = os.path.join(ROOT, "tests", "data")
M6 = os.path.join(DATA, "AileM6_with_sharp_TE.stp")
PROPELLER = os.path.join(DATA, "Propeller.brep")


def plate_with_holes():
    """A 200 x 200 plate with a 40 x 40 square hole and a 12-gon hole (FreeCAD Part)."""
    sys.path.append("/usr/lib/freecad-python3/lib")
    import FreeCAD  # noqa: F401  (before Part)
    import Part
    V = FreeCAD.Vector
    plate = Part.makePlane(200, 200, V(-100, -100, 0))
    square = Part.Face(Part.makePolygon([V(-60, -20, 0), V(-20, -20, 0), V(-20, 20, 0), V(-60, 20, 0),
                                         V(-60, -20, 0)]))
    pts = [V(50 + 25 * math.cos(math.pi * k / 6), 25 * math.sin(math.pi * k / 6), 0) for k in range(12)]
    return plate.cut(square).cut(Part.Face(Part.makePolygon(pts + [pts[0]])))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "docs", "img")
    os.makedirs(out, exist_ok=True)
    p = lambda name: os.path.join(out, name)  # noqa: E731

    le = dict(first_height=0.5, growth=1.2, layers=20)
    r = pm.mesh_shape(M6, size=16.75, boundary_layers=[dict(edges=[21], **le)])
    # a 200-long stretch of the leading edge, seen from ahead and above: rows graded into triangles
    r.render_png(p("bl_m6_leading_edge.png"), width=1100, height=800, azimuth=100, elevation=20,
                 focus=[250, 400, -60, 450, 600, 60])
    # closer, almost along the span: the first rows wrap around the nose on both faces
    r.render_png(p("bl_m6_nose.png"), width=1100, height=800, azimuth=110, elevation=10,
                 focus=[265, 460, -25, 325, 540, 25])

    r = pm.mesh_shape(M6, size=16.75, boundary_layers=[dict(edges=[21, 6], **le)])
    r.render_png(p("bl_m6_tip.png"), width=1100, height=800, azimuth=135, elevation=25,
                 focus=[655, 1150, -5, 725, 1215, 40])

    try:
        shape = plate_with_holes()
    except ImportError:
        print("FreeCAD not available: plate pictures skipped")
    else:
        edges = [1, 2] + list(range(5, 21))
        r = pm.mesh_shape(shape, size=8.0, boundary_layers=[dict(edges=edges, first_height=0.3, growth=1.2,
                                                                  layers=12)])
        r.render_png(p("bl_plate_holes.png"), width=1200, height=600, azimuth=-90, elevation=90,
                     focus=[-68, -32, 0, 82, 32, 0])
        r.render_png(p("bl_plate_corner.png"), width=1000, height=1000, azimuth=-90, elevation=90,
                     focus=[-101, -101, 0, -61, -61, 0])

    r = pm.mesh_shape(PROPELLER, size=6.7934, boundary_layers=[dict(edges=[64, 68, 72, 76], first_height=0.15,
                                                                     growth=1.2, layers=20)])
    r.render_png(p("bl_propeller.png"), width=1100, height=1000, azimuth=35, elevation=40)
    r.render_png(p("bl_propeller_blade.png"), width=1100, height=700, azimuth=-60, elevation=25,
                 focus=[340, 0, 0, 480, 60, 40])
    for name in sorted(os.listdir(out)):
        if name.startswith("bl_") and name.endswith(".png"):
            print(f"{p(name)}: {os.path.getsize(p(name)) // 1024} KB")


if __name__ == "__main__":
    main()
