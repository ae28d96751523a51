#!/usr/bin/env python3
"""Tessellate CAD models with FreeCAD's MeshPart (the discrete-geometry issue's inputs) into binary STL.

    /usr/bin/python3 bench/tessellate.py MODEL [MODEL ...] --out DIR [--linear 5e-4] [--angular 0.5]

--linear: MeshPart's LinearDeflection relative to the bounding-box diagonal (default 5e-4);
--angular: AngularDeflection in radians (default 0.5, MeshPart's own default, a coarse setting).
Writes DIR/NAME.stl and prints one JSON line per model: facets, the absolute deflection asked for.
"""
import argparse
import json
import os
import sys

sys.path.append("/usr/lib/freecad-python3/lib")
import FreeCAD  # noqa: E402  (before Part)
import Part  # noqa: E402
import MeshPart  # noqa: E402


def tessellate(path, out_dir, linear, angular):
    shape = Part.Shape()
    shape.read(path)
    diag = shape.BoundBox.DiagonalLength
    mesh = MeshPart.meshFromShape(Shape=shape, LinearDeflection=linear * diag,
                                  AngularDeflection=angular, Relative=False)
    name = os.path.splitext(os.path.basename(path))[0]
    out = os.path.join(out_dir, name + ".stl")
    mesh.write(out)  # binary STL by extension
    return {"model": path, "stl": out, "facets": mesh.CountFacets, "points": mesh.CountPoints,
            "diagonal": diag, "deflection": linear * diag}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("models", nargs="+")
    ap.add_argument("--out", required=True)
    ap.add_argument("--linear", type=float, default=5e-4)
    ap.add_argument("--angular", type=float, default=0.5)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    for m in a.models:
        print(json.dumps(tessellate(m, a.out, a.linear, a.angular)), flush=True)


if __name__ == "__main__":
    main()
