#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""A mesh's nodes on spherical faces: their analytic distance from the sphere against what
OpenCASCADE's classifier and `distToShape` (meshcheck's measure) say of them.

usage: sphere_nodes_probe.py MODEL MESH.msh FACE[,FACE...]

Each FACE must be a piece of a sphere whose edges include a circle of the sphere's radius
centred on its centre (boxed_sphere.step's corner octants, Faces 4, 16, 36, 48, 84, 96, 116,
128). For every node of the face's triangles (MSH entity tag = face number) it gives the largest
analytic distance from the sphere, how many nodes the classifier (FreeCAD's `Face.isInside(p,
1e-7, True)`) calls outside the face, and the largest `distToShape` to the face. Nodes on the
sphere that the classifier calls outside lie where the face's pcurves and its 3D edges disagree
(docs/size_control.md). Prints JSON. Run with Debian's /usr/bin/python3."""
import json
import sys

import numpy as np

from cad_read import read_cad
import FreeCAD  # noqa: E402  (imported by cad_read)
import Part  # noqa: E402


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    import meshio
    shape = read_cad(sys.argv[1])
    m = meshio.read(sys.argv[2])
    P = np.asarray(m.points, dtype=float)[:, :3]
    tris, ents = [], []
    for i, cb in enumerate(m.cells):
        if cb.type == "triangle":
            tris.append(cb.data)
            ents.append(m.cell_data["gmsh:geometrical"][i])
    T, E = np.concatenate(tris), np.concatenate(ents)
    out = {}
    for fn in (int(x) for x in sys.argv[3].split(",")):
        face = shape.Faces[fn - 1]
        circle = next(e.Curve for e in face.Edges if hasattr(e.Curve, "Center"))
        centre, radius = np.array(circle.Center), circle.Radius
        nodes = np.unique(T[E == fn])
        analytic = np.abs(np.linalg.norm(P[nodes] - centre, axis=1) - radius)
        d = np.array([Part.Vertex(FreeCAD.Vector(*P[n])).distToShape(face)[0] for n in nodes])
        outside = [not face.isInside(FreeCAD.Vector(*P[n]), 1e-7, True) for n in nodes]
        out["Face%d" % fn] = {
            "nodes": int(len(nodes)),
            "analytic_max": float(analytic.max()),
            "classifier_outside": int(sum(outside)),
            "dist_to_shape_max": float(d.max()),
            "edge_tolerance_max": max(e.Tolerance for e in face.Edges),
        }
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
