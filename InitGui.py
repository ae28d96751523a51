# SPDX-License-Identifier: LGPL-2.1-or-later
# ParaMesh workbench entry point (exec()ed by FreeCAD; the workbench is in freecad.paramesh.gui).
import FreeCADGui as _Gui
from freecad.paramesh.gui.workbench import ParaMeshWorkbench
_Gui.addWorkbench(ParaMeshWorkbench())
