# SPDX-License-Identifier: LGPL-2.1-or-later
"""Tier 1: numpy + the native module only (no FreeCAD)."""
