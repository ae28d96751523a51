# SPDX-License-Identifier: LGPL-2.1-or-later
"""Proximity sizing (proximity=N): thin walls and narrow faces get at least N elements across,
measured by the independent tests/tools/across_check.py on the written MSH file."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import freecad.paramesh as pm

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DATA = os.path.join(ROOT, "tests", "data")
SHEET = os.path.join(DATA, "sheet_metal_54.brep")  # 1.2 mm sheet, diagonal 85.57 mm
ACROSS = os.path.join(ROOT, "tests", "tools", "across_check.py")


def across(msh, h, n):
    out = subprocess.run([sys.executable, ACROSS, str(msh), "--size", repr(h), "--min", str(n)],
                         capture_output=True, text=True)
    return out.returncode, json.loads(out.stdout)


@pytest.mark.parametrize("div", [25, 50, 100])
def test_sheet_metal_walls_get_three_elements_across(tmp_path, div):
    h = 85.5652 / div
    plain = pm.mesh_shape(SHEET, size=h)
    plain.write(tmp_path / "plain.msh")
    rc, before = across(tmp_path / "plain.msh", h, 3)
    assert rc == 1 and before["faces_below_min"] > 0, "without proximity the 1.2 mm rims are too coarse"
    r = pm.mesh_shape(SHEET, size=h, proximity=3)
    assert r.report["status"] == "ok"
    r.write(tmp_path / "prox.msh")
    rc, after = across(tmp_path / "prox.msh", h, 3)
    assert rc == 0 and after["faces_below_min"] == 0, after["worst"]
    assert after["min_elements_across"] >= 3.0
    # still conformal and closed (the model is a closed shell)
    def open_edges(res):
        t = res.triangles
        e = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
        _, c = np.unique(e, axis=0, return_counts=True)
        assert c.max() <= 2
        return int((c == 1).sum())
    assert open_edges(r) == open_edges(plain) == 0
    # the size sources follow the 3D gaps: a 1.2 mm wall asks for about 1.2 / 3 mm elements
    t = r.triangles
    L = np.linalg.norm(r.nodes[t[:, 0]] - r.nodes[t[:, 1]], axis=1)
    assert np.median(L) < 0.6


def test_proximity_is_a_validated_parameter():
    with pytest.raises(ValueError, match="proximity"):
        pm.mesh_shape(SHEET, proximity=-1)
    with pytest.raises(ValueError, match="proximity"):
        pm.mesh_shape(SHEET, proximity=1.5)
