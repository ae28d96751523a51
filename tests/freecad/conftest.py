# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD App (no GUI) from Debian's /usr/bin/python3."""
import os
import sys

# pytest imports every conftest.py as the module "conftest": when tests/python and tests/freecad
# run together (scripts/test.sh), `from conftest import ROOT` in a test may get this one, so it
# names the repository root as tests/conftest.py does
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

for p in ("/usr/lib/freecad-python3/lib", "/usr/share/freecad/Mod/Fem", "/usr/share/freecad/Mod",
          "/usr/share/freecad/Ext"):
    if p not in sys.path:
        sys.path.append(p)

import FreeCAD  # noqa: E402,F401  (before Part, or Part segfaults)
