# SPDX-License-Identifier: LGPL-2.1-or-later
"""What the boundary-layer tests share (test_boundary_layer.py, test_boundary_layer_ends.py,
test_boundary_layer_meeting.py): the models, the M6 leading-edge layer, and the measures and
assertions through the project's checker, tests/tools/bl_check.py (imported as a module)."""
import os

import pytest

import bl_check as bc  # tests/tools, put on sys.path by tests/conftest.py

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOLS = os.path.join(ROOT, "tests", "tools")
DATA = os.path.join(ROOT, "tests", "data")
M6 = os.path.join(DATA, "AileM6_with_sharp_TE.stp")
WING = os.path.join(DATA, "wing.brep")
PROPELLER = os.path.join(DATA, "Propeller.brep")
BOTTLE = os.path.join(DATA, "bottle.brep")
SCREW = os.path.join(DATA, "screw.step")

M6_SIZE = 16.75
LE = dict(first_height=0.5, growth=1.2, layers=20)   # the M6 leading-edge layer


def _part():
    return bc.import_part()


needs_freecad = pytest.mark.skipif(_part() is None, reason="needs FreeCAD (Part)")


def measure(r, edges, first_height, growth, layers, cad=None, **kw):
    return bc.check(bc.SurfMesh.from_result(r), edges, first_height, growth, layers, cad=cad, **kw)


def assert_rows_exact(res, tol=0.02):
    """First height and growth within tol on every full column, and the checker found columns."""
    assert res["columns"] > 0 and res["full_columns"] > 0
    assert res["height_err_full"]["max"] <= tol, res["height_err_full"]
    assert res["growth_err_full"]["max"] <= tol, res["growth_err_full"]
    assert res["row_err_full"]["max"] <= tol, res["row_err_full"]


def assert_valid_mesh(res, watertight):
    c, q = res["conformity"], res["quads"]
    assert c["ok"], c
    assert c["used_more"] == 0 and c["boundary_off_cad_edges"] == 0 and not c["cracked_cad_edges"]
    assert c["orientation_mismatches"] == 0
    assert c["watertight"] == watertight, c
    assert q["inverted"] == 0, q
