# SPDX-License-Identifier: LGPL-2.1-or-later
"""Tier 2: FreeCAD App (Part, Mesh, Fem) without the GUI."""
