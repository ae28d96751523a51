# SPDX-License-Identifier: LGPL-2.1-or-later
"""Damaged CAD files (the cases tests/tools/fuzz_inputs.py found): each gives a clear error or a
warning, never a crash, a hang or a silently partial mesh. Through the CLI (its own process, so a
crash would show as a signal) and through the Python API."""
import json
import os
import re
import subprocess
import time

import numpy as np
import pytest

import freecad.paramesh as pm

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DATA = os.path.join(ROOT, "tests", "data")
CLI = os.path.join(ROOT, "build", "bin", "paramesh")
needs_cli = pytest.mark.skipif(not os.path.exists(CLI), reason="needs build/bin/paramesh")


def run_cli(*args, timeout=60):
    p = subprocess.run([CLI, *args], capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stderr.strip()


def damaged(tmp_path, name, text):
    path = tmp_path / name
    path.write_bytes(text)
    return str(path)


def read(name):
    return open(os.path.join(DATA, name), "rb").read()


def api_error_in_own_process(path, error, **params):
    """The message of the `pm.<error>` that mesh_file(path, **params) raises, run in a python3 of
    its own: a crash shows as a signal there (the Python API has no handler), not as a dead test run."""
    code = ("import sys, freecad.paramesh as pm\n"
            f"try:\n    pm.mesh_file(sys.argv[1], **{params!r})\nexcept pm.{error} as e:\n    print('ERR', e)\n")
    p = subprocess.run(["/usr/bin/python3", "-c", code, path], capture_output=True, text=True, timeout=60,
                       cwd=ROOT, env=dict(os.environ, PYTHONPATH=ROOT))
    assert p.returncode == 0, (p.returncode, p.stderr[-500:])
    assert p.stdout.startswith("ERR"), p.stdout
    return p.stdout


@needs_cli
def test_truncated_brep_is_an_error_not_a_hang(tmp_path):
    # OpenCASCADE's BREP reader looped for over a minute on this cut (fuzz case: wing.brep cut
    # inside its TShapes section)
    text = read("wing.brep")
    cut = damaged(tmp_path, "cut.brep", text[:int(len(text) * 0.8)])
    t = time.monotonic()
    rc, err = run_cli("mesh", cut, "-o", str(tmp_path / "o.msh"))
    assert time.monotonic() - t < 20
    assert rc == 2 and len(err.splitlines()) == 1, (rc, err)
    assert "cut short" in err and "TShapes" in err, err
    with pytest.raises(pm.InputError, match="cut short"):
        pm.mesh_file(cut)


def test_truncated_brep_string_is_an_error():
    text = read("wing.brep").decode()
    with pytest.raises(pm.InputError, match="cut short"):
        pm.mesh_shape(text[:len(text) // 2])


@needs_cli
@pytest.mark.parametrize("name", ["screw.step", "bearing.iges"])
def test_truncated_step_and_iges_are_errors(tmp_path, name):
    # bearing.iges cut at 80 % read as 166 of its 213 faces, silently, before the check
    src = os.path.join(DATA, name) if os.path.exists(os.path.join(DATA, name)) else \
        os.path.join(ROOT, "..", "shared", "models", name)
    if not os.path.exists(src):
        pytest.skip("no " + name)
    text = open(src, "rb").read()
    cut = damaged(tmp_path, "cut" + os.path.splitext(name)[1], text[:int(len(text) * 0.8)])
    rc, err = run_cli("mesh", cut, "-o", str(tmp_path / "o.msh"))
    assert rc == 2 and len(err.splitlines()) == 1 and "cut short" in err, (rc, err)


@needs_cli
def test_reader_crash_becomes_an_error(tmp_path):
    # screw.step without the line of #932 (a CARTESIAN_POINT of a p-curve): OpenCASCADE 7.6's STEP
    # reader dereferenced the missing point (SIGSEGV in StepGeom_CartesianPoint::NbCoordinates).
    # The reader's load check flags the B-spline #917 that lists it; damaged geometry is refused
    # before the transfer, so neither the CLI nor the Python API (which has no signal handler to
    # fall back on) reaches the crash
    lines = read("screw.step").split(b"\n")
    kept = [l for l in lines if not l.startswith(b"#932 =")]
    assert len(kept) == len(lines) - 1
    bad = damaged(tmp_path, "bad.step", b"\n".join(kept))
    rc, err = run_cli("mesh", bad, "-o", str(tmp_path / "o.msh"))
    assert rc == 2 and len(err.splitlines()) == 1, (rc, err)
    assert "#917 (B_SPLINE_CURVE_WITH_KNOTS)" in err and "refers to #932" in err, err
    err = api_error_in_own_process(bad, "ParaMeshError", size=1.0)
    assert "refers to #932" in err, err


@pytest.mark.parametrize("old,new,named", [
    # fuzz cases (fuzz_inputs.py python, seed 14): each one ended a python3 calling mesh_file()
    # with SIGSEGV in OpenCASCADE's STEP translator
    (b"#200 = EDGE_LOOP('',(#201,#202,#211,#217));", b"", "refers to #200"),  # StepShape_FaceBound::Bound
    (b"#2217 = FACE_BOUND('',#2218,.F.);", b"#-434.8321479324626 = FACE_BOUND('',#2218,.F.);",
     "Incorrect syntax"),  # the entity is dropped, its face holds a null bound
])
def test_damaged_face_topology_is_refused(tmp_path, old, new, named):
    text = read("ANC101.stp")
    assert text.count(old) == 1
    bad = damaged(tmp_path, "bad.stp", text.replace(old, new))
    err = api_error_in_own_process(bad, "InputError")
    assert named in err, err


@needs_cli
def test_missing_face_entity_is_reported(tmp_path):
    # screw.step without its first ADVANCED_FACE: the reader drops the face (9 of 10, no solid);
    # the mesh is made of what was read, and the report and stderr say the file is damaged
    lines = read("screw.step").split(b"\n")
    i = next(k for k, l in enumerate(lines) if b"ADVANCED_FACE" in l)
    bad = damaged(tmp_path, "noface.step", b"\n".join(lines[:i] + lines[i + 1:]))
    rep = tmp_path / "r.json"
    rc, err = run_cli("mesh", bad, "-o", str(tmp_path / "o.msh"), "--report", str(rep))
    assert rc == 0, (rc, err)
    r = json.loads(rep.read_text())
    assert r["cad"]["faces"] == 9, r["cad"]
    w = [x for x in r["warnings"] if "damaged entities" in x]
    assert w and "Unresolved Reference" in w[0], r["warnings"]
    assert "damaged entities" in err


def test_sound_files_have_no_damage_warning():
    # boxed_sphere.step has 295 entities whose name is not a quoted string: harmless, not counted
    for name in ["boxed_sphere.step", "screw.step", "ANC101.stp"]:
        r = pm.mesh_file(os.path.join(DATA, name), size=5.0)
        assert not [w for w in r.report.get("warnings", []) if "damaged" in w], (name, r.report["warnings"])
        t = r.triangles
        e = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
        _, c = np.unique(e, axis=0, return_counts=True)
        assert c.max() == 2, name


@needs_cli
def test_fuzzed_copies_never_crash_or_hang(tmp_path):
    """30 seeded mutations of two real models (tests/tools/fuzz_inputs.py): every run ends with a
    sane mesh or a one-line error, none with a signal, a sanitizer report or a time-out."""
    import sys
    tool = os.path.join(ROOT, "tests", "tools", "fuzz_inputs.py")
    p = subprocess.run([sys.executable, tool, CLI, os.path.join(DATA, "screw.step"), os.path.join(DATA, "wing.brep"),
                        "--cases", "30", "--seed", "3", "--timeout", "60", "--out", str(tmp_path / "fail")],
                       capture_output=True, text=True, timeout=1200)
    r = json.loads(p.stdout)
    assert r["failures"] == [], r["failures"]
    assert p.returncode == 0
    # the mutations reach both outcomes: some copies still mesh, others are refused
    assert r["outcomes"].get("meshed", 0) > 0 and sum(v for k, v in r["outcomes"].items() if k.startswith("error")) > 0, r


@needs_cli
def test_size_far_too_small_fails_at_once(tmp_path):
    # screw.step (diagonal 103) at size 3e-4 would need about 10^11 triangles: it spent over 10
    # minutes before the element budget; now the face's area against the budget stops it
    t = time.monotonic()
    rc, err = run_cli("mesh", os.path.join(DATA, "screw.step"), "-o", str(tmp_path / "o.msh"), "--size", "0.0003",
                      timeout=300)
    # the log line and the one-line error (the stage lines "paramesh: edges (0.0 s)" aside)
    lines = [ln for ln in err.splitlines() if not re.match(r"paramesh: [\w -]+ \(\d+\.\d s\)$", ln)]
    assert rc == 1 and "max_elements" in err and len(lines) <= 2, (rc, err)
    assert time.monotonic() - t < 120
    # a budget the mesh really exceeds while meshing, through the Python API
    # (about 4 400 triangles at size 1: over a budget of 2 000, within one of 100 000)
    with pytest.raises(pm.ParameterError, match="max_elements = 2000 "):
        pm.mesh_file(os.path.join(DATA, "screw.step"), size=1.0, max_elements=2000)
    ok = pm.mesh_file(os.path.join(DATA, "screw.step"), size=1.0, max_elements=100000)
    assert 2000 < len(ok.triangles) < 100000
    with pytest.raises(ValueError, match="max_elements"):
        pm.mesh_file(os.path.join(DATA, "screw.step"), max_elements=5)
    rc, err = run_cli("mesh", os.path.join(DATA, "screw.step"), "-o", str(tmp_path / "o.msh"), "--max-elements", "5")
    assert rc == 1 and "--max-elements" in err


@needs_cli
def test_damaged_bspline_edge_gets_a_sane_discretisation(tmp_path):
    # propeller_and_shaft.iges with one pole coordinate of entity 489 changed (33.95781661 -> 7,
    # a fuzz case): Edge78's derivative flips between samples, 748 000 rad of "turning" on 108 mm,
    # and the turning rule asked for 714 480 segments (the run did not end in 200 s)
    src = os.path.join(ROOT, "..", "shared", "models", "propeller_and_shaft.iges")
    if not os.path.exists(src):
        pytest.skip("needs ../shared/models")
    text = open(src, "rb").read()
    old = b"81.203707082,17.882301213,33.95781661,81.057117637,17.636071459,"
    assert text.count(old) == 1
    bad = damaged(tmp_path, "bad.iges", text.replace(old, old.replace(b"33.95781661", b"7")))
    t = time.monotonic()
    p = subprocess.run([CLI, "mesh", bad, "-o", str(tmp_path / "o.msh")], capture_output=True, text=True, timeout=120)
    assert time.monotonic() - t < 30
    assert p.returncode in (0, 3), p.stderr
    line = next(l for l in p.stderr.splitlines() if l.startswith("edges discretised"))
    assert int(line.split("(")[-1].rstrip(")")) < 1000, line
    assert "damaged entities" in p.stderr


@needs_cli
def test_kernel_exception_on_a_damaged_edge_is_an_error(tmp_path):
    # small-edges-01.brep with the parameter range of Edge208's curve representation changed
    # (1.80174462786821 -> -163.238...): BRepAdaptor_Curve threw Standard_ConstructionError, which
    # no handler caught (std::terminate, exit 134); the backend now names the edge
    lines = read("small-edges-01.brep").split(b"\n")
    old = b"1  208 0 1.76241427046867 1.80174462786821"
    k = [i for i, l in enumerate(lines) if l.strip() == old]
    assert len(k) == 1
    lines[k[0]] = b"1  208 0 1.76241427046867 -163.23821840844244"
    bad = damaged(tmp_path, "bad.brep", b"\n".join(lines))
    # the edge fails alone: the face it bounds fails naming it (here the only face: exit 4)
    rc, err = run_cli("mesh", bad, "-o", str(tmp_path / "o.msh"), "--quiet")
    assert rc == 4 and len(err.splitlines()) == 1 and "Face1: its Edge208 could not be discretised" in err, (rc, err)
    r = pm.mesh_file(bad)
    assert r.report["status"] == "failed" and "Edge208" in r.report["faces"][0]["error"], r.report["faces"][0]


def test_error_classes():
    # one base class catches every error of ours; input and parameter errors are ValueErrors too
    for cls in (pm.InputError, pm.ParameterError, pm.Cancelled):
        assert issubclass(cls, pm.ParaMeshError), cls
    assert issubclass(pm.InputError, ValueError) and issubclass(pm.ParameterError, ValueError)
    with pytest.raises(pm.ParaMeshError, match="cannot open"):
        pm.mesh_file(os.path.join(DATA, "no_such_file.step"))
