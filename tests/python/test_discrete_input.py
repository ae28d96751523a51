# SPDX-License-Identifier: LGPL-2.1-or-later
"""Triangulated input (issue 36), the discrete backend's first stages: reading (OpenCASCADE's
RWStl / RWObj), repair and the feature graph. Measured against the CAD the STL was made from
(FreeCAD MeshPart, linear deflection 5e-4 of the diagonal, its default angular deflection 0.5 rad):
every feature-edge node on a CAD edge, every sharp CAD edge covered by feature edges, closed solids
closed. Damaged files: a clear error naming the file and what is wrong, or a repair reported."""
import math
import os
import struct
import subprocess
import sys

import numpy as np
import pytest

import freecad.paramesh as pm

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MODELS = os.path.join(os.path.dirname(ROOT), "shared", "models")
CLI = os.path.join(ROOT, "build", "bin", "paramesh")
needs_cli = pytest.mark.skipif(not os.path.exists(CLI), reason="needs build/bin/paramesh")
sys.path.append("/usr/lib/freecad-python3/lib")
try:
    import FreeCAD  # noqa: F401  (before Part)
    import Part
    import MeshPart
except ImportError:  # pragma: no cover
    Part = None
needs_freecad = pytest.mark.skipif(Part is None, reason="needs FreeCAD's Part and MeshPart")


def seg_dist(P, A, B):
    """Distance of each point of P to the nearest of the segments (A[j], B[j])."""
    best = np.full(len(P), np.inf)
    d = B - A
    l2 = np.maximum((d * d).sum(1), 1e-300)
    for s in range(0, len(P), 256):
        p = P[s:s + 256, None, :]
        t = np.clip(((p - A[None]) * d[None]).sum(2) / l2[None], 0, 1)
        q = A[None] + t[..., None] * d[None]
        best[s:s + 256] = np.sqrt(((p - q) ** 2).sum(2)).min(1)
    return best


def cad_edges(shape, defl, angle):
    """The CAD's edges as fine polylines (all, and the sharp ones: faces meeting at more than
    angle + 5 degrees at five points along the edge, or a free edge)."""
    A, B, SA, SB = [], [], [], []
    for e in shape.Edges:
        if e.Length < 1e-12:
            continue
        pts = np.array([[v.x, v.y, v.z] for v in e.discretize(Deflection=defl * 0.05)])
        if len(pts) < 2:
            continue
        A.append(pts[:-1])
        B.append(pts[1:])
        faces = shape.ancestorsOfType(e, Part.Face)
        sharp = len(faces) == 1
        if len(faces) == 2:
            angs = []
            for s in np.linspace(0.1, 0.9, 5):
                p = e.valueAt(e.FirstParameter + s * (e.LastParameter - e.FirstParameter))
                n = []
                for f in faces:
                    u, v = f.Surface.parameter(p)
                    q = f.normalAt(u, v)
                    n.append(np.array([q.x, q.y, q.z]))
                angs.append(math.degrees(math.acos(max(-1.0, min(1.0, float(n[0] @ n[1]))))))
            sharp = min(angs) > angle + 5
        if sharp:
            SA.append(pts[:-1])
            SB.append(pts[1:])
    return np.vstack(A), np.vstack(B), (np.vstack(SA) if SA else None), (np.vstack(SB) if SB else None)


def tessellated(tmp_path, name, linear=5e-4):
    shape = Part.Shape()
    shape.read(os.path.join(MODELS, name))
    defl = linear * shape.BoundBox.DiagonalLength
    mesh = MeshPart.meshFromShape(Shape=shape, LinearDeflection=defl, AngularDeflection=0.5, Relative=False)
    stl = str(tmp_path / (name + ".stl"))
    mesh.write(stl)
    return shape, defl, stl


@needs_freecad
@pytest.mark.parametrize("name", ["AileM6_with_sharp_TE.stp", "CrankArm.brep", "screw.step"])
def test_features_of_a_tessellated_model_follow_its_cad_edges(tmp_path, name):
    shape, defl, stl = tessellated(tmp_path, name)
    d = pm.discrete_features(stl, feature_angle=40)
    P = d["points"]
    A, B, SA, SB = cad_edges(shape, defl, 40)
    tol = defl + 1e-6 * shape.BoundBox.DiagonalLength
    nodes = sorted({n for e in d["edges"] for n in e["nodes"]})
    off = seg_dist(P[nodes], A, B)
    assert off.max() <= tol, f"a feature node {off.max() / defl:.2f} deflections from every CAD edge"
    # every sharp CAD edge is covered: its points within the deflection of a feature segment
    fa = np.array([P[e["nodes"][i]] for e in d["edges"] for i in range(len(e["nodes"]) - 1)])
    fb = np.array([P[e["nodes"][i + 1]] for e in d["edges"] for i in range(len(e["nodes"]) - 1)])
    samples = np.vstack([SA, SB])
    missed = seg_dist(samples, fa, fb) > tol
    assert missed.mean() <= 0.001, f"{missed.sum()} of {len(samples)} points of sharp CAD edges not on a feature"
    # closed solids stay closed and outward
    assert d["repair"]["closed_pieces"] == len(shape.Solids)
    assert d["repair"]["holes"] == 0 and d["repair"]["non_manifold_edges"] == 0
    tri = d["triangles"]
    vol = np.einsum("ij,ij->i", P[tri[:, 0]], np.cross(P[tri[:, 1]], P[tri[:, 2]])).sum() / 6
    assert vol == pytest.approx(sum(s.Volume for s in shape.Solids), rel=0.01)
    # faces are the patches between the features: no triangle of one face shares a non-feature
    # edge with another face's
    feat = {tuple(sorted(s)) for e in d["edges"] for s in zip(e["nodes"], e["nodes"][1:])}
    face = d["triangle_face"]
    owner = {}
    for t, c in enumerate(tri):
        for k in range(3):
            key = tuple(sorted((c[k], c[(k + 1) % 3])))
            if key in feat:
                continue
            assert owner.setdefault(key, face[t]) == face[t]


@needs_freecad
def test_m6_trailing_edge_is_one_feature_edge_cutting_the_wing_face(tmp_path):
    shape, defl, stl = tessellated(tmp_path, "AileM6_with_sharp_TE.stp")
    d = pm.discrete_features(stl)
    P = d["points"]
    # the trailing edge: the straight sharp line from the root's (810, 0, 0) to the tip's (1146, 1196, 0)
    te = [e for e in d["edges"] if len(e["faces"]) == 1]
    assert len(te) == 1
    ends = P[[te[0]["nodes"][0], te[0]["nodes"][-1]]]
    want = np.array([[810.5, 0, 0], [1146.6, 1196.3, 0]])
    assert min(np.abs(ends - want).max(), np.abs(ends[::-1] - want).max()) < 1.0
    # the wing face walks it out and back (a seam): one wire with the edge both ways
    f = te[0]["faces"][0]
    e = d["edges"].index(te[0])
    (wire,) = d["face_loops"][f]
    assert (e, False) in [tuple(u) for u in wire] and (e, True) in [tuple(u) for u in wire]


def write_binary_stl(path, tris, count=None):
    with open(path, "wb") as f:
        f.write(b"binary".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris) if count is None else count))
        for t in tris:
            f.write(struct.pack("<3f", 0, 0, 0))
            for p in t:
                f.write(struct.pack("<3f", *p))
            f.write(b"\0\0")


TETRA = [((0, 0, 0), (0, 1, 0), (1, 0, 0)), ((0, 0, 0), (1, 0, 0), (0, 0, 1)),
         ((0, 0, 0), (0, 0, 1), (0, 1, 0)), ((1, 0, 0), (0, 1, 0), (0, 0, 1))]


def test_a_tetrahedron_with_faults_is_repaired_and_each_repair_counted(tmp_path):
    path = str(tmp_path / "t.stl")
    eps = 1e-7  # a corner written one float32 step apart: merged
    tris = [TETRA[0], ((0, 0, 0), (0, 0, 1), (1, 0, 0)),  # the second facet turned inside out
            TETRA[2], ((1 + eps, 0, 0), (0, 1, 0), (0, 0, 1)),
            TETRA[0],                                      # a duplicate
            ((0, 0, 0), (0, 0, 0), (1, 0, 0))]             # degenerate
    write_binary_stl(path, tris)
    d = pm.discrete_features(path)
    r = d["repair"]
    assert r["duplicate_facets"] == 1 and r["degenerate_facets"] == 1 and r["merged_vertices"] == 1
    assert r["closed_pieces"] == 1 and r["holes"] == 0 and len(d["triangles"]) == 4
    assert r["flipped_facets"] >= 1
    P, T = d["points"], d["triangles"]
    vol = np.einsum("ij,ij->i", P[T[:, 0]], np.cross(P[T[:, 1]], P[T[:, 2]])).sum() / 6
    assert vol == pytest.approx(1 / 6, rel=1e-6)  # oriented outward
    assert len(d["edges"]) == 6 and len(d["vertex_nodes"]) == 4 and int(d["triangle_face"].max()) == 3


def test_nan_coordinates_non_manifold_fans_and_holes_are_reported(tmp_path):
    nan = float("nan")
    fan = TETRA + [((0, 0, 0), (0, 1, 0), (-1, 0, 0)), ((nan, 0, 0), (0, 1, 0), (0, 0, 1))]
    d = pm.discrete_features((np.array([p for t in fan for p in t], float), np.arange(3 * len(fan)).reshape(-1, 3)))
    r = d["repair"]
    assert r["non_finite_facets"] == 1
    assert r["non_manifold_edges"] == 1  # the edge (0,0,0)-(0,1,0) of three facets
    assert r["holes"] == 1 and r["boundary_edges"] == 2
    assert any("non-manifold" in l and "(0, 0.5, 0)" in l for l in r["lines"])


@needs_cli
@pytest.mark.parametrize("what,make,message", [
    ("cut short binary", lambda p: open(p, "wb").write(b"\0" * 50), "cut short"),
    ("header lies", lambda p: write_binary_stl(p, TETRA, count=7), "header counts 7 facets"),
    ("no facet", lambda p: write_binary_stl(p, []), "without a facet"),
    ("ascii cut short", lambda p: open(p, "w").write("solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"),
     "ends with an 'endsolid' line"),
])
def test_damaged_stl_gives_a_clear_error(tmp_path, what, make, message):
    path = str(tmp_path / "bad.stl")
    make(path)
    p = subprocess.run([CLI, "info", path], capture_output=True, text=True, timeout=60)
    assert p.returncode == 2, (what, p.stderr)
    assert message in p.stderr and "bad.stl" in p.stderr, (what, p.stderr)
    with pytest.raises(pm.InputError, match=message.replace("(", r"\(")):
        pm.discrete_features(path)


@needs_cli
def test_cli_info_lists_faces_and_edges_and_mesh_remeshes(tmp_path):
    path = str(tmp_path / "t.stl")
    write_binary_stl(path, TETRA)
    p = subprocess.run([CLI, "info", path, "--feature-angle", "30"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0
    lines = p.stdout.splitlines()
    assert "4 faces, 6 edges, 4 vertices at feature angle 30" in lines[0]
    assert sum(l.startswith("Face") for l in lines) == 4 and sum(l.startswith("Edge") for l in lines) == 6
    out = str(tmp_path / "x.stl")
    p = subprocess.run([CLI, "mesh", path, "-o", out, "--size", "0.1"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    d = pm.discrete_features(out)  # the remeshed tetrahedron: closed, the same volume, nodes on its faces
    assert d["repair"]["closed_pieces"] == 1 and d["repair"]["holes"] == 0 and len(d["triangles"]) > 100
    P, T = d["points"], d["triangles"]
    vol = np.einsum("ij,ij->i", P[T[:, 0]], np.cross(P[T[:, 1]], P[T[:, 2]])).sum() / 6
    assert vol == pytest.approx(1 / 6, rel=1e-6)
    on_face = np.isclose(P, 0, atol=1e-6).any(1) | np.isclose(P.sum(1), 1, atol=1e-6)
    assert on_face.all()


@needs_freecad
@pytest.mark.parametrize("name", ["screw.step", "linkrods.step", "AileM6_with_sharp_TE.stp"])
def test_remeshed_stl_is_closed_on_the_cad_and_well_shaped(tmp_path, name):
    """The STL of a model remeshed at diagonal / 100: a closed, consistently oriented surface whose
    nodes lie within the STL's own deflection of the original CAD, with well-shaped triangles."""
    shape, defl, stl = tessellated(tmp_path, name)
    diag = shape.BoundBox.DiagonalLength
    h = diag / 100
    r = pm.mesh_shape(stl, size=h)
    assert r.report["status"] == "ok", r.report["message"]
    P, T = np.asarray(r.nodes), np.asarray(r.triangles)
    # closed and oriented: every mesh edge used once each way
    directed = {}
    for t in T:
        for k in range(3):
            directed[(t[k], t[(k + 1) % 3])] = directed.get((t[k], t[(k + 1) % 3]), 0) + 1
    assert all(c == 1 for c in directed.values()) and all((b, a) in directed for (a, b) in directed)
    vol = np.einsum("ij,ij->i", P[T[:, 0]], np.cross(P[T[:, 1]], P[T[:, 2]])).sum() / 6
    assert vol == pytest.approx(sum(s.Volume for s in shape.Solids), rel=0.01)
    # nodes on the CAD within the input's deflection + 1e-3 h (300 sampled)
    pick = np.random.default_rng(0).choice(len(P), size=min(300, len(P)), replace=False)
    dev = max(Part.Vertex(FreeCAD.Vector(*P[i])).distToShape(shape)[0] for i in pick)
    assert dev <= defl + 1e-3 * h, f"a node {dev:.3g} from the CAD (deflection {defl:.3g})"
    # shape: radius ratio and angles
    a, b, c = (np.linalg.norm(P[T[:, i]] - P[T[:, (i + 1) % 3]], axis=1) for i in range(3))
    s = (a + b + c) / 2
    area = np.sqrt(np.maximum(s * (s - a) * (s - b) * (s - c), 0))
    gamma = 4 * area * area * 4 / (a * b * c * s) / 2  # 2 r_in / r_circ
    assert gamma.mean() >= 0.95
    if name.startswith("AileM6"):  # the sharp trailing edge kept: mesh nodes along all of it
        te0, te1 = np.array([810.5, 0, 0]), np.array([1146.6, 1196.3, 0])
        d = te1 - te0
        t = np.clip((P - te0) @ d / (d @ d), 0, 1)
        on = np.linalg.norm(P - (te0 + t[:, None] * d), axis=1) < 1.0
        ts = np.sort(t[on])
        assert ts[0] < 1e-3 and ts[-1] > 1 - 1e-3 and np.diff(ts).max() * np.linalg.norm(d) < 1.5 * h


@needs_freecad
def test_volume_fills_a_closed_stl_bounded_by_its_surface_mesh(tmp_path):
    """--volume on triangulated input: the tetrahedra's boundary is exactly the remeshed surface,
    none inverted or over-shared, their volume the CAD's within 1 %."""
    shape, defl, stl = tessellated(tmp_path, "screw.step")
    r = pm.mesh_shape(stl, size=shape.BoundBox.DiagonalLength / 100, volume=True)
    assert r.report["status"] == "ok", r.report["message"]
    P, tet, tri = np.asarray(r.nodes), np.asarray(r.tetrahedra), np.asarray(r.triangles)
    assert len(tet) > 1000
    faces = {}
    for t in tet:
        for f in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)):
            k = tuple(sorted(t[list(f)]))
            faces[k] = faces.get(k, 0) + 1
    assert {k for k, n in faces.items() if n == 1} == {tuple(sorted(x)) for x in tri}
    assert max(faces.values()) == 2
    vol = np.einsum("ij,ij->i", P[tet[:, 1]] - P[tet[:, 0]], np.cross(P[tet[:, 2]] - P[tet[:, 0]], P[tet[:, 3]] - P[tet[:, 0]])) / 6
    assert (vol > 0).all()
    assert vol.sum() == pytest.approx(shape.Volume, rel=0.01)
