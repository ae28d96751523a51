# SPDX-License-Identifier: LGPL-2.1-or-later
"""Tier 3: the FreeCAD GUI (workbench, commands, view providers, task panels, quality view). The
only part of ParaMesh that imports FreeCADGui, PySide or pivy."""
