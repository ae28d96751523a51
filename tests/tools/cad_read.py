# SPDX-License-Identifier: LGPL-2.1-or-later
"""One way for the independent checkers to read a CAD model with FreeCAD's Part (not ParaMesh):
BREP through Part.Shape.read, STEP and IGES through Part.read. Face numbers are then FreeCAD's
Face1..FaceN. Run with Debian's /usr/bin/python3."""
import sys

sys.path.append('/usr/lib/freecad-python3/lib')
import FreeCAD  # noqa: E402,F401  (FreeCAD before Part)
import Part  # noqa: E402


def read_cad(path):
    if path.lower().endswith(('.brep', '.brp')):
        s = Part.Shape()
        s.read(path)
        return s
    return Part.read(path)
