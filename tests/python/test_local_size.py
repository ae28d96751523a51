# SPDX-License-Identifier: LGPL-2.1-or-later
"""Local sizes stay local: a size of diagonal/1000 on one face of ANC101 inside a global
diagonal/50, measured by the independent tests/tools/local_size_check.py."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import freecad.paramesh as pm

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ANC = os.path.join(ROOT, "tests", "data", "ANC101.stp")
CHECK = os.path.join(ROOT, "tests", "tools", "local_size_check.py")
DIAG = 509.079


@pytest.fixture(scope="module")
def anc_face11(tmp_path_factory):
    H, HL = DIAG / 50, DIAG / 1000
    r = pm.mesh_shape(ANC, size=H, local_sizes=[f"Face11={HL}"])
    out = tmp_path_factory.mktemp("ls") / "anc.msh"
    r.write(out)
    p = subprocess.run([sys.executable, CHECK, str(out), "--face", "11", "--local", repr(HL), "--global", repr(H),
                        "--grading", "1.3"], capture_output=True, text=True)
    return r, json.loads(p.stdout), p.returncode, H, HL


def test_face_has_the_local_size(anc_face11):
    r, c, rc, H, HL = anc_face11
    assert r.report["status"] == "ok"
    assert c["face_pct_in_range"] >= 99.0, c
    assert 1 / 2 ** 0.5 <= c["face_ratio_min"] and c["face_ratio_max"] <= 2 ** 0.5


def test_sizes_grow_at_most_by_the_grading_per_element(anc_face11):
    _, c, rc, H, HL = anc_face11
    assert c["growth_per_element_max"] <= 1.3 * 1.05
    # the neighbour-to-neighbour ratio in the graded zone: typically ~1, rarely above the grading
    assert c["neighbour_ratio_p50_in_graded_zone"] < 1.1
    assert c["neighbour_ratio_p99_in_graded_zone"] < 1.5


def test_back_to_the_global_size_where_the_grading_says(anc_face11):
    _, c, rc, H, HL = anc_face11
    assert rc == 0 and c["ok"]
    # 0.9 H is reached no earlier than the field allows and not much later
    assert 0.8 * c["implied_distance_to_0.9H"] <= c["distance_to_0.9H"] <= 1.5 * c["implied_distance_to_0.9H"]
    far = [b for b in c["bins"] if b["distance"] > 1.5 * c["implied_distance_to_0.9H"]]
    assert far and all(0.85 * H <= b["median_size"] <= 1.1 * H for b in far)


def test_local_size_does_not_bleed_over_whole_faces(anc_face11):
    """Face2 (the plate the hole Face11 goes through) touches the hole: only its part near the
    hole is refined, most of its area keeps the global size (FreeCAD issue #10096 is about the
    opposite: a vertex size that refines whole faces). Measured: 86 % of Face2's area."""
    r, c, rc, H, HL = anc_face11
    t = r.triangles[r.triangle_face == 2]
    X = r.nodes[t]
    area = 0.5 * np.linalg.norm(np.cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0]), axis=1)
    size = sum(np.linalg.norm(X[:, (k + 1) % 3] - X[:, k], axis=1) for k in range(3)) / 3
    assert size.min() < 2 * HL, "Face2 is refined where it meets the hole"
    assert area[size >= 0.7 * H].sum() / area.sum() > 0.8


def test_second_face_and_the_field_law(tmp_path):
    """Face15, a through hole of the base plate 18 mm from two outer walls (the graded zone,
    (H - h_L)/(G - 1) = 32.2 mm, crosses into Face1, Face2, Face6, Face8 and the slot): the same
    requirements hold. The CAD-edge segments, spaced by integrating 1/h of the size field, follow
    h_L + (G - 1) d within a few %, i.e. the field is the graded law; the triangles come out ~10 %
    finer than it in the graded zone (measured 0.906), still inside [1/sqrt2, sqrt2] but for a few."""
    H, HL = DIAG / 50, DIAG / 1000
    r = pm.mesh_shape(ANC, size=H, local_sizes=[f"Face15={HL}"])
    assert r.report["status"] == "ok"
    out = tmp_path / "anc15.msh"
    r.write(out)
    p = subprocess.run([sys.executable, CHECK, str(out), "--face", "15", "--local", repr(HL), "--global", repr(H),
                        "--grading", "1.3"], capture_output=True, text=True)
    c = json.loads(p.stdout)
    assert p.returncode == 0 and c["ok"], c
    assert c["face_pct_in_range"] == 100.0
    assert 1 / 2 ** 0.5 <= c["face_ratio_min"] and c["face_ratio_max"] <= 2 ** 0.5
    seg = c["cad_edge_segments_over_law_in_graded_zone"]
    assert seg["n"] > 50 and 0.95 <= seg["median"] <= 1.05 and seg["p10"] > 0.9 and seg["p90"] < 1.1, seg
    tri = c["triangles_over_law_in_graded_zone"]
    assert 0.85 <= tri["median"] <= 1.05 and tri["p10"] > 1 / 2 ** 0.5 and tri["max"] <= 2 ** 0.5, tri
    # growth away from the face, pair by pair: the grading plus the mesh's own scatter (measured on
    # the face, where the target is constant: p99 1.14, max 1.30-1.37); the single worst of ~6800
    # pairs moves with any change of the optimiser (1.65-1.70 measured), so it gets a fixed bound
    g = c["outward_neighbour_growth_in_graded_zone"]
    base = c["neighbour_ratio_on_face"]
    assert g["median"] <= 1.15 and g["p99"] <= 1.3 * base["p99"] and g["max"] <= 1.75, (g, base)
    assert c["growth_per_element_max"] <= 1.3 * 1.05
    # back to the global size: 0.9 H reached within (H - h_L)/(G - 1) + one global element
    assert c["distance_to_0.9H"] <= (H - HL) / 0.3 + H
    # and the global size far away (beyond 2x that distance, up to 3x)
    far = [b for b in c["bins"] if 2 * (H - HL) / 0.3 < b["distance"] < 3 * (H - HL) / 0.3]
    assert far and all(0.85 * H <= b["median_size"] <= 1.1 * H for b in far)
