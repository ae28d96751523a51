# SPDX-License-Identifier: LGPL-2.1-or-later
"""The FreeCAD-free Python API: dtypes, shapes, measured mesh properties, errors, threads."""
import json
import os
import threading
import time

import numpy as np
import pytest

import freecad.paramesh as pm

DATA = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "data")
M6 = os.path.join(DATA, "AileM6_with_sharp_TE.stp")
SCREW = os.path.join(DATA, "screw.step")


def edges_of(tris):
    e = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    return np.unique(e, axis=0, return_counts=True)


def test_arrays_have_strict_dtypes_and_shapes():
    r = pm.mesh_shape(SCREW, size=2.0)
    assert r.nodes.dtype == np.float64 and r.nodes.ndim == 2 and r.nodes.shape[1] == 3
    assert r.triangles.dtype == np.int32 and r.triangles.shape[1] == 3
    assert r.quads.dtype == np.int32 and r.quads.shape == (0, 4)
    assert r.triangle_face.dtype == np.int32 and r.triangle_face.shape == (len(r.triangles),)
    assert r.face_of_element.shape == (len(r.triangles) + len(r.quads),)
    assert r.node_dim.shape == (len(r.nodes),) and set(np.unique(r.node_dim)) <= {0, 1, 2}
    assert r.triangles.min() >= 0 and r.triangles.max() < len(r.nodes)
    assert r.nodes.flags["C_CONTIGUOUS"] and r.triangles.flags["C_CONTIGUOUS"]
    # arrays are owned copies: mutating them does not change the result
    r.nodes[0, 0] += 1.0
    assert r.report["counts"]["nodes"] == len(r.nodes)


def test_closed_solid_is_watertight_and_sized():
    r = pm.mesh_shape(SCREW, size=2.0)
    _, cnt = edges_of(r.triangles)
    assert (cnt == 2).all(), "every edge of a closed solid is shared by exactly two triangles"
    e, _ = edges_of(r.triangles)
    L = np.linalg.norm(r.nodes[e[:, 0]] - r.nodes[e[:, 1]], axis=1) / 2.0
    assert ((L > 2 ** -0.5) & (L < 2 ** 0.5)).mean() > 0.95
    assert r.report["status"] == "ok" and r.report["quality"]["gamma_mean"] > 0.95
    assert set(np.unique(r.triangle_face)) == set(range(1, 11)), "FreeCAD face numbers 1..10"


def test_report_lists_every_face_and_stage():
    r = pm.mesh_shape(M6, size=40.0)
    rep = r.report
    assert [f["name"] for f in rep["faces"]] == [f"Face{i}" for i in range(1, 12)]
    assert all(f["status"] == "ok" for f in rep["faces"])
    for stage in ("size_field", "edges", "faces", "total"):
        assert rep["seconds"][stage] >= 0
    assert json.loads(json.dumps(rep)) == rep


def test_brep_string_and_file_give_the_same_mesh():
    a = pm.mesh_file(os.path.join(DATA, "wing.brep"), size=0.1)
    with open(os.path.join(DATA, "wing.brep")) as f:
        b = pm.mesh_brep(f.read(), size=0.1)
    assert np.array_equal(a.triangles, b.triangles) and np.allclose(a.nodes, b.nodes)


def test_write_and_render(tmp_path):
    r = pm.mesh_shape(SCREW, size=3.0)
    for ext in ("msh", "vtu", "stl", "inp"):
        r.write(tmp_path / f"s.{ext}")
        assert (tmp_path / f"s.{ext}").stat().st_size > 1000
    r.render_png(tmp_path / "s.png", width=320, height=240)
    assert (tmp_path / "s.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("kw, exc, words", [
    ({"size": -1.0}, ValueError, "size"),
    ({"size": "big"}, TypeError, "size"),
    ({"grading": 1.0}, ValueError, "grading"),
    ({"curvature_angle": float("nan")}, ValueError, "curvature_angle"),
    ({"threads": 2.5}, ValueError, "threads"),
    ({"order": 3}, ValueError, "order"),
    ({"sise": 1.0}, TypeError, "sise"),
    ({"boundary_layers": [{"edges": [0], "first_height": 0.5, "layers": 3}]}, ValueError, "start at 1"),
    ({"boundary_layers": [{"edges": [2], "first_height": -1, "layers": 3}]}, ValueError, "first_height"),
    ({"local_sizes": ["Face3:0.5"]}, ValueError, "Face3"),
])
def test_bad_parameters_raise_clear_errors(kw, exc, words):
    with pytest.raises(exc) as e:
        pm.mesh_shape(SCREW, **kw)
    assert words in str(e.value)


def test_bad_entity_numbers_name_the_entity():
    with pytest.raises(pm.ParameterError) as e:
        pm.mesh_shape(SCREW, size=2.0, local_sizes=["Face99=0.1"])
    assert "Face99" in str(e.value)
    with pytest.raises(pm.ParameterError) as e:
        pm.mesh_shape(M6, size=40.0, boundary_layers=[{"edges": [99], "first_height": 0.5, "layers": 3}])
    assert "Edge99" in str(e.value)


def test_bad_inputs_raise_clear_errors(tmp_path):
    with pytest.raises(pm.InputError, match="not a BREP string"):
        pm.mesh_brep("this is not a BREP\nat all")
    with pytest.raises(pm.InputError, match="cannot open"):
        pm.mesh_file(tmp_path / "missing.step")
    bad = tmp_path / "bad.step"
    bad.write_text("ISO-10303-21; garbage")
    with pytest.raises(pm.InputError):
        pm.mesh_file(bad)
    with pytest.raises(pm.InputError, match="format"):
        pm.mesh_file(tmp_path / "x.xyz")
    with pytest.raises(pm.InputError, match="cannot open"):  # OBJ is triangulated input now
        pm.mesh_file(tmp_path / "x.obj")
    with pytest.raises(TypeError):
        pm.mesh_shape(42)


def test_progress_reports_stages_in_order():
    seen = []
    pm.mesh_shape(SCREW, size=2.0, progress=lambda f, s: seen.append((f, s)) or True)
    fr = [f for f, _ in seen]
    assert fr == sorted(fr) and fr[0] == 0.0 and fr[-1] == 1.0
    assert {"faces", "done"} <= {s for _, s in seen}


def test_cancel_from_another_thread_is_fast_and_leaves_nothing():
    job = pm.MeshJob(os.path.join(DATA, "bottle.brep"), size=0.05)  # ~ 10^7 triangles: minutes
    out = {}

    def work():
        try:
            out["result"] = job.run()
        except pm.Cancelled as e:
            out["cancelled"] = str(e)

    t = threading.Thread(target=work)
    t.start()
    time.sleep(0.5)
    t0 = time.perf_counter()
    job.cancel()
    t.join(10)
    dt = time.perf_counter() - t0
    assert not t.is_alive()
    assert "cancelled" in out and "result" not in out
    assert dt < 0.5, f"cancel took {dt:.3f} s"


def test_gil_is_released_while_meshing():
    job = pm.MeshJob(os.path.join(DATA, "bottle.brep"), size=0.3)
    ticks = []
    done = threading.Event()

    def ticker():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.005)

    t = threading.Thread(target=ticker)
    t.start()
    t0 = time.perf_counter()
    job.run()
    elapsed = time.perf_counter() - t0
    done.set()
    t.join()
    assert elapsed > 0.2
    gaps = np.diff(ticks)
    assert gaps.max() < 0.1, f"Python thread starved for {gaps.max():.3f} s while meshing"
