# SPDX-License-Identifier: LGPL-2.1-or-later
"""Named groups read by the clients solver users run: Gmsh's own reader (python3-gmsh) lists one
physical group per CAD face with the element counts of our report, and a --group with exactly
the elements of its faces; meshio reads MSH, VTU and SU2 with the groups; OpenFOAM's
surfaceCheck takes the named multi-solid STL of closed models, its regions named as ours;
CalculiX's sets (ELSET / NSET / SURFACE) of the INP hold the group's elements and nodes."""
import glob
import json
import os
import re
import shutil
import subprocess

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CLI = os.path.join(ROOT, "build", "bin", "paramesh")
SHARED = os.path.join(os.path.dirname(ROOT), "shared", "models")
DATA = os.path.join(ROOT, "tests", "data")
MODELS = sorted(p for p in glob.glob(os.path.join(SHARED, "*")) if not p.endswith(".md")) or \
    sorted(p for p in glob.glob(os.path.join(DATA, "*")) if not p.endswith(".md"))

pytestmark = pytest.mark.skipif(not os.path.exists(CLI), reason="needs build/bin/paramesh")

gmsh = pytest.importorskip("gmsh")
meshio = pytest.importorskip("meshio")


def run(model, outs, *args, tmp):
    """The CLI on model; returns its report (degraded runs still write their files)."""
    report = os.path.join(tmp, "r.json")
    cmd = [CLI, "mesh", model, "--report", report, "--quiet"] + sum((["-o", o] for o in outs), []) + list(args)
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert p.returncode in (0, 3), p.stderr
    return json.load(open(report))


def gmsh_groups(path):
    """{name: (dim, {element tag, ...})} as Gmsh's reader sees the file."""
    gmsh.initialize(["-noenv"])
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        gmsh.open(path)
        out = {}
        for dim, tag in gmsh.model.getPhysicalGroups():
            elems = set()
            for e in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                _, tags, _ = gmsh.model.mesh.getElements(dim, e)
                for t in tags:
                    elems.update(int(x) for x in t)
            out[gmsh.model.getPhysicalName(dim, tag)] = (dim, elems)
        return out
    finally:
        gmsh.finalize()


@pytest.mark.parametrize("model", MODELS, ids=os.path.basename)
def test_gmsh_reader_lists_one_group_per_face_with_the_report_counts(model, tmp_path):
    msh = str(tmp_path / "m.msh")
    r = run(model, [msh], tmp=str(tmp_path))
    groups = gmsh_groups(msh)
    faces = {f["name"]: f["triangles"] + f["quads"] for f in r["faces"] if f["triangles"] + f["quads"] > 0}
    assert faces, "no face meshed"
    got = {name: len(el) for name, (dim, el) in groups.items() if dim == 2}
    assert got == faces
    assert sum(got.values()) == r["counts"]["triangles"] + r["counts"]["quads"]


def test_user_groups_hold_exactly_their_faces_elements_in_every_format(tmp_path):
    model = os.path.join(DATA, "bottle.brep")
    t = str(tmp_path)
    outs = [os.path.join(t, "b." + x) for x in ("msh", "vtu", "inp", "stl")]
    r = run(model, outs, "--group", "neck=Face3,Face7", "--group", "body=Face16,Face21",
            "--group", "rims=Edge2,Edge3", tmp=t)
    per_face = {f["face"]: f["triangles"] + f["quads"] for f in r["faces"]}
    groups = gmsh_groups(outs[0])
    for name, faces in (("neck", (3, 7)), ("body", (16, 21))):
        dim, el = groups[name]
        assert dim == 2
        union = set().union(*(groups[f"Face{f}"][1] for f in faces))
        assert el == union and len(el) == sum(per_face[f] for f in faces)
    assert groups["rims"][0] == 1 and len(groups["rims"][1]) > 0  # the segments of the two edges
    # meshio: MSH cell sets, VTU cell data and field data
    m = meshio.read(outs[0])
    assert set(m.cell_sets) >= {"neck", "body", "rims", "Face3"}
    assert sum(len(c) for c in m.cell_sets["neck"]) == per_face[3] + per_face[7]
    v = meshio.read(outs[1])
    neck = np.concatenate(v.cell_data["group:neck"])
    face = np.concatenate(v.cell_data["face"])
    assert int(neck.sum()) == per_face[3] + per_face[7]
    assert set(face[neck == 1]) == {3, 7}
    assert list(v.field_data["neck"]) == [1, 2]  # (tag, dim): the user's groups come first
    # INP: ELSET neck = the elements of ELSET Face3 and Face7
    sets = inp_sets(outs[2])
    assert sets["ELSET=neck"] == sets["ELSET=Face3"] | sets["ELSET=Face7"]
    assert len(sets["NSET=rims"]) > 0
    # STL: one solid per group, then the faces no group took
    names = re.findall(r"^solid (\S+)", open(outs[3]).read(), re.M)
    assert names[:2] == ["neck", "body"] and "Face3" not in names and "Face1" in names


def inp_sets(path):
    """{"ELSET=NAME" / "NSET=NAME": {ids}} with GENERATE ranges expanded."""
    sets, cur, gen = {}, None, False
    for line in open(path):
        line = line.strip()
        if line.startswith("*"):
            m = re.match(r"\*(ELSET|NSET), (ELSET|NSET)=([\w.-]+)(, GENERATE)?", line)
            cur = f"{m.group(1)}={m.group(3)}" if m else None
            gen = bool(m and m.group(4))
            if cur:
                sets.setdefault(cur, set())
            continue
        if cur:
            ids = [int(x) for x in line.split(",") if x.strip()]
            if gen:
                sets[cur].update(range(ids[0], ids[1] + 1, ids[2]))
            else:
                sets[cur].update(ids)
    return sets


def test_su2_volume_markers_read_by_meshio(tmp_path):
    t = str(tmp_path)
    su2, msh = os.path.join(t, "v.su2"), os.path.join(t, "v.msh")
    r = run(os.path.join(DATA, "CrankArm.brep"), [su2, msh], "--volume", "--group", "hub=Face1,Face2", tmp=t)
    assert r["status"] == "ok"
    text = open(su2).read()
    markers = dict(re.findall(r"MARKER_TAG= (\S+)\nMARKER_ELEMS= (\d+)", text))
    per_face = {f["name"]: f["triangles"] for f in r["faces"] if f["triangles"]}
    assert {k: int(v) for k, v in markers.items() if k != "hub"} == per_face
    assert int(markers["hub"]) == per_face["Face1"] + per_face["Face2"]
    m = meshio.read(su2)
    tets = sum(len(c.data) for c in m.cells if c.type == "tetra")
    tris = sum(len(c.data) for c in m.cells if c.type == "triangle")
    assert tets == r["counts"]["tetrahedra"] if "tetrahedra" in r["counts"] else tets > 0
    assert tris == sum(per_face.values()) + int(markers["hub"])  # every marker's boundary triangles
    # the volume groups in Gmsh's reader: Solid<i> with the tetrahedra
    groups = gmsh_groups(msh)
    assert sum(len(el) for dim, el in groups.values() if dim == 3) == tets


SURFACE_CHECK = shutil.which("surfaceCheck")


@pytest.mark.skipif(SURFACE_CHECK is None, reason="needs OpenFOAM's surfaceCheck (Debian openfoam)")
@pytest.mark.parametrize("name", ["bottle.brep", "linkrods.step", "AileM6_with_sharp_TE.stp"])
def test_openfoam_surface_check_takes_the_multi_solid_stl(name, tmp_path):
    t = str(tmp_path)
    stl = os.path.join(t, "s.stl")
    r = run(os.path.join(DATA, name), [stl], "--stl-groups", tmp=t)
    env = dict(os.environ, FOAM_ETC="/usr/share/openfoam/etc", WM_PROJECT_DIR="/usr/share/openfoam")
    p = subprocess.run([SURFACE_CHECK, stl], capture_output=True, text=True, cwd=t, env=env, timeout=600)
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    out = p.stdout
    assert "Surface has no illegal triangles." in out
    assert "Surface is closed. All edges connected to two faces." in out
    regions = dict(re.findall(r"^(Face\d+)\t(\d+)$", out, re.M))
    faces = {f["name"]: f["triangles"] + 2 * f["quads"] for f in r["faces"] if f["triangles"] + f["quads"]}
    assert {k: int(v) for k, v in regions.items()} == faces


def test_bad_groups_are_refused_by_name(tmp_path):
    model = os.path.join(DATA, "wing.brep")
    cases = {
        "Face3=Face1": "default group",
        "a b=Face1": "letters, digits",
        "mix=Face1,Edge2": "mixes faces and edges",
        "far=Face999": "Face999 does not exist",
        "empty=": "is no Face",
    }
    for arg, says in cases.items():
        p = subprocess.run([CLI, "mesh", model, "-o", str(tmp_path / "x.msh"), "--group", arg],
                           capture_output=True, text=True, timeout=60)
        assert p.returncode == 1 and says in p.stderr, (arg, p.stderr)
    p = subprocess.run([CLI, "mesh", model, "-o", str(tmp_path / "x.msh"), "--group", "a=Face1",
                        "--group", "A=Face2"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 1 and "given twice" in p.stderr


def test_version_and_progress_lines(tmp_path):
    p = subprocess.run([CLI, "--version"], capture_output=True, text=True, timeout=30)
    lines = p.stdout.splitlines()
    assert p.returncode == 0 and len(lines) == 3
    assert re.match(r"paramesh \d+\.\d+\.\d+$", lines[0])
    assert re.match(r"OpenCASCADE 7\.\d+\.\d+", lines[1]) and lines[2].startswith("nglib (Netgen) 6.")
    model = os.path.join(DATA, "wing.brep")
    # not a terminal: one plain line per stage, in pipeline order; --quiet: nothing
    p = subprocess.run([CLI, "mesh", model, "-o", str(tmp_path / "w.msh")], capture_output=True, text=True, timeout=120)
    stages = re.findall(r"^paramesh: (\w[\w -]*) \(\d+\.\d s\)$", p.stderr, re.M)
    assert p.returncode == 0 and "faces" in stages and stages[-1] == "done", p.stderr
    assert "\r" not in p.stderr
    p = subprocess.run([CLI, "mesh", model, "-o", str(tmp_path / "w.msh"), "--quiet"], capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 0 and p.stderr == ""


def test_python_api_and_params_json_groups(tmp_path):
    from freecad.paramesh.core import api
    model = os.path.join(DATA, "bottle.brep")
    r = api.mesh_shape(model, groups={"neck": ["Face3", "Face7"]})
    per_face = {f["face"]: f["triangles"] for f in json.loads(r._r.report_json)["faces"]}
    r.write(str(tmp_path / "a.msh"))
    r.write(str(tmp_path / "a.stl"))
    m = meshio.read(str(tmp_path / "a.msh"))
    assert sum(len(c) for c in m.cell_sets["neck"]) == per_face[3] + per_face[7]
    assert open(tmp_path / "a.stl").readline().strip() == "solid neck"
    for bad, says in (({"Face1": ["Face3"]}, "default group"), ({"x": ["Face300"]}, "Face300 does not exist"),
                      ({"x": ["Face3", "Edge1"]}, "mixes")):
        with pytest.raises(Exception, match=says):
            api.mesh_shape(model, groups=bad)
    # the parameters JSON: an object of lists or a list of strings, the same groups
    for groups in ({"neck": ["Face3", "Face7"]}, ["neck=Face3,Face7"]):
        params = tmp_path / "p.json"
        params.write_text(json.dumps({"groups": groups}))
        msh = str(tmp_path / "j.msh")
        run(model, [msh], "--params", str(params), tmp=str(tmp_path))
        assert len(gmsh_groups(msh)["neck"][1]) == per_face[3] + per_face[7]


def test_dolfinx_solves_poisson_with_conditions_on_named_groups(tmp_path):
    """dolfinx (0.5, Debian python3-dolfinx) reads our volume MSH through Gmsh's API with cell and
    facet tags; u = 0 on the group 'left' (x = 0), u = 1 on 'right' (x = 10), no flux elsewhere: the
    exact solution x / 10, which linear elements reproduce to round-off."""
    dolfinx = pytest.importorskip("dolfinx")
    pytest.importorskip("dolfinx.io.gmshio")
    code = ("import sys; sys.path.append('/usr/lib/freecad-python3/lib'); import FreeCAD, Part; "
            f"Part.makeBox(10, 4, 3).exportBrep({str(tmp_path / 'box.brep')!r})")
    subprocess.run(["/usr/bin/python3", "-c", code], check=True, capture_output=True, timeout=60)
    msh = str(tmp_path / "box.msh")
    r = run(str(tmp_path / "box.brep"), [msh], "--volume", "--size", "1", "--group", "left=Face1",
            "--group", "right=Face2", tmp=str(tmp_path))
    assert r["status"] == "ok"
    # a subprocess: dolfinx's JIT and MPI stay out of the test process
    script = tmp_path / "poisson.py"
    script.write_text(f"""
import numpy as np
from mpi4py import MPI
import dolfinx, gmsh, ufl
from dolfinx.io import gmshio
from dolfinx.fem.petsc import LinearProblem
from petsc4py.PETSc import ScalarType
gmsh.initialize(); gmsh.option.setNumber("General.Terminal", 0)
gmsh.open({msh!r})
tags = {{gmsh.model.getPhysicalName(d, t): t for d, t in gmsh.model.getPhysicalGroups(2)}}
mesh, cells, facets = gmshio.model_to_mesh(gmsh.model, MPI.COMM_WORLD, 0, gdim=3)
gmsh.finalize()
V = dolfinx.fem.FunctionSpace(mesh, ("CG", 1))
def bc(name, value):
    f = facets.indices[facets.values == tags[name]]
    return dolfinx.fem.dirichletbc(ScalarType(value), dolfinx.fem.locate_dofs_topological(V, 2, f), V), len(f)
(b0, n0), (b1, n1) = bc("left", 0.0), bc("right", 1.0)
u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
a = ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx
L = ufl.inner(dolfinx.fem.Constant(mesh, ScalarType(0)), v) * ufl.dx
uh = LinearProblem(a, L, bcs=[b0, b1], petsc_options={{"ksp_type": "preonly", "pc_type": "lu"}}).solve()
x = V.tabulate_dof_coordinates()
print(mesh.topology.index_map(3).size_local, n0, n1, np.abs(uh.x.array - x[:, 0] / 10).max())
""")
    p = subprocess.run(["/usr/bin/python3", str(script)], capture_output=True, text=True, timeout=600,
                       cwd=str(tmp_path))
    assert p.returncode == 0, p.stderr[-3000:]
    cells, n_left, n_right, err = p.stdout.split()[-4:]
    per_face = {f["name"]: f["triangles"] for f in r["faces"]}
    assert int(cells) == r["volume"]["tetrahedra"]
    assert int(n_left) == per_face["Face1"] and int(n_right) == per_face["Face2"]
    assert float(err) < 1e-10
