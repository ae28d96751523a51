# SPDX-License-Identifier: LGPL-2.1-or-later
# ParaMesh (FreeCAD exec()s this file at start-up, also without GUI). The code lives in the
# package freecad.paramesh; make sure this Mod folder's freecad/ joins the freecad namespace even
# when another module imported `freecad` before this folder was put on sys.path.
import pkgutil as _pkgutil
import freecad as _freecad
_freecad.__path__ = _pkgutil.extend_path(_freecad.__path__, "freecad")
