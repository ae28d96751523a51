# SPDX-License-Identifier: LGPL-2.1-or-later
"""pytest setup shared by tests/python (no FreeCAD) and tests/freecad (FreeCAD App, no GUI).
Run with Debian's /usr/bin/python3: /usr/bin/python3 -m pytest tests/python tests/freecad"""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "tests", "data")
TOOLS = os.path.join(ROOT, "tests", "tools")  # the independent checkers, importable by tests
for p in (ROOT, TOOLS):
    if p not in sys.path:
        sys.path.insert(0, p)
