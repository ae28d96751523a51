# SPDX-License-Identifier: LGPL-2.1-or-later
"""The input checks through the Python API (docs/robustness.md, "Input checks"): the native
parameters' optional lengths are None when left out, a layer taller than the model is a
ParameterError naming the spec, a layer that grows no element makes the run degraded, and a
BREP text whose root reference is internal or external (OpenCASCADE's DRAW writes "i1 0") is
meshed. The C++ side is tests/cpp/test_input_checks.cpp."""
import math
import os

import pytest

import freecad.paramesh as pm
from freecad.paramesh import _native

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
WING = os.path.join(ROOT, "tests", "data", "wing.brep")  # 4 faces, diagonal 5.03083
LENGTHS = ("size", "min_size", "max_size", "volume_max_size")


def test_native_lengths_left_out_are_none():
    n = _native.MeshParams()
    for name in LENGTHS:
        assert getattr(n, name) is None, name
        setattr(n, name, 2.5)
        assert getattr(n, name) == 2.5
        setattr(n, name, None)
        assert getattr(n, name) is None
        # a given 0 is kept, and refused by validate() (left out is None)
        setattr(n, name, 0.0)
        assert getattr(n, name) == 0.0
        with pytest.raises(pm.ParameterError, match=fr"^{name} must be a positive length \(got 0\)"):
            n.validate()
        with pytest.raises(pm.ParameterError, match=f"{name} must be a number"):
            setattr(n, name, math.nan)
        setattr(n, name, -1.0)
        with pytest.raises(pm.ParameterError, match=fr"^{name} must be a positive length \(got -1\)"):
            n.validate()
        setattr(n, name, None)
    n.validate()


def test_sizes_left_out_are_the_defaults():
    par = pm.mesh_file(WING).report["parameters"]
    assert par["size"] == pytest.approx(5.03083 / 50, rel=1e-5)
    assert par["max_size"] == par["size"]
    assert par["min_size"] == pytest.approx(par["size"] / 100)


def test_size_zero_is_refused_through_the_wrapper():
    with pytest.raises(ValueError, match="size"):  # pm.ParameterError is a ValueError too
        pm.mesh_file(WING, size=0)
    for name in ("min_size", "max_size", "volume_max_size"):
        with pytest.raises(ValueError, match=rf"^{name} must be > 0, got 0\.0$"):
            pm.mesh_file(WING, **{name: 0})
    # left out (None) is the default: diagonal / 50 (5.03083 / 50)
    r = pm.mesh_file(WING, size=None)
    assert abs(r.report["parameters"]["size"] - 5.03083 / 50) < 1e-5, r.report["parameters"]


def test_layer_taller_than_the_model_is_refused():
    with pytest.raises(pm.ParameterError, match=r"^boundary layer #1 \(edges 3,5\): first height 500 exceeds "
                                                r"the model's diagonal 5\.03083$"):
        pm.mesh_file(WING, boundary_layers=[dict(edges=[3, 5], first_height=500, layers=3)])
    with pytest.raises(pm.ParameterError, match=r"^boundary layer #1 \(edge 2\): total thickness 6 exceeds"):
        pm.mesh_file(WING, boundary_layers=[dict(edges=[2], first_height=0.01, thickness=6)])


def test_layer_that_grows_nowhere_makes_the_run_degraded():
    r = pm.mesh_file(WING, boundary_layers=[dict(edges=[1], first_height=2, layers=1)])
    assert r.report["status"] == "degraded"
    assert r.report["boundary_layers"][0]["elements"] == 0
    assert "boundary layer 1 (Edge1, Edge7) produced no element on any face" in r.report["message"]
    assert not r.failed_faces and len(r.triangles) > 0  # every face meshed: degraded by the layer alone
    r = pm.mesh_file(WING, boundary_layers=[dict(edges=[1], first_height=0.01, layers=3)])
    assert r.report["status"] == "ok" and r.report["boundary_layers"][0]["elements"] > 0


@pytest.mark.parametrize("root", ["i1 0", "e1 0", "-1 0", "+1"])
def test_brep_root_of_any_orientation_is_meshed(root):
    text = open(WING).read()
    text = text[:text.rindex("*") + 1] + "\n\n" + root + "\n"
    r = pm.mesh_brep(text)
    assert r.report["status"] == "ok" and set(r.triangle_face) == {1, 2, 3, 4}
