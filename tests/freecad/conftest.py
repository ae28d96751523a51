# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD App (no GUI) from Debian's /usr/bin/python3."""
import sys

for p in ("/usr/lib/freecad-python3/lib", "/usr/share/freecad/Mod/Fem", "/usr/share/freecad/Mod",
          "/usr/share/freecad/Ext"):
    if p not in sys.path:
        sys.path.append(p)

import FreeCAD  # noqa: E402,F401  (before Part, or Part segfaults)
