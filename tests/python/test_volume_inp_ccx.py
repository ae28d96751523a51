# SPDX-License-Identifier: LGPL-2.1-or-later
"""The CLI's volume INP taken by CalculiX as it is: two boxes touching on a face but exported
as separate solids (no shared topology), meshed with --volume. The contact face is meshed once,
so the two solids' tetrahedra share its nodes: clamped at x = 0 and pulled by a pressure on the
x = 20 end, the whole bar stretches like one bar. The deck uses the INP's own sets: ELSET
Solid<i>, NSET Face<i> (boundary condition) and SURFACE Face<i> (the pressure)."""
import os
import re
import subprocess

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

CLI = os.path.join(ROOT, "build", "bin", "paramesh")
PY = "/usr/bin/python3"


def two_boxes(path):
    """Two 10 mm cubes side by side along x, as two solids of one compound (FreeCAD's Part)."""
    code = ("import sys; sys.path.append('/usr/lib/freecad-python3/lib'); import FreeCAD, Part; "
            "a = Part.makeBox(10, 10, 10); b = Part.makeBox(10, 10, 10, FreeCAD.Vector(10, 0, 0)); "
            f"Part.Compound([a, b]).exportBrep({path!r})")
    subprocess.run([PY, "-c", code], check=True, capture_output=True, timeout=60)


def read_inp(path):
    nodes, sets, elems, section, cur = {}, {}, [], None, None
    for line in open(path):
        line = line.strip()
        if line.startswith("*"):
            section = line.upper()
            m = re.match(r"\*NSET, NSET=(\w+)", line)
            cur = m.group(1) if m else None
            if cur:
                sets[cur] = []
            continue
        if section == "*NODE":
            a = line.split(",")
            nodes[int(a[0])] = np.array([float(x) for x in a[1:4]])
        elif section.startswith("*ELEMENT"):
            elems.append([int(x) for x in line.split(",")[1:] if x.strip()])
        elif cur:
            sets[cur] += [int(x) for x in line.split(",") if x.strip()]
    return nodes, sets, elems


@pytest.mark.skipif(not os.path.exists(CLI), reason="needs build/bin/paramesh")
@pytest.mark.parametrize("order", [1, 2])
def test_touching_boxes_stretch_as_one_bar(tmp_path, order):
    brep, inp = str(tmp_path / "boxes.brep"), str(tmp_path / "boxes.inp")
    two_boxes(brep)
    r = subprocess.run([CLI, "mesh", brep, "-o", inp, "--volume", "--size", "2.5", "--order", str(order)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert "coincide: meshed once" in r.stderr
    nodes, sets, elems = read_inp(inp)
    text = open(inp).read()
    assert ("TYPE=C3D10" if order == 2 else "TYPE=C3D4") in text
    assert "ELSET=Solid1" in text and "ELSET=Solid2" in text
    # every element has a positive volume in CalculiX's corner order
    t = np.array([e[:4] for e in elems])
    P = np.array([nodes[i] for i in range(1, max(nodes) + 1)])
    v = np.einsum("ij,ij->i", np.cross(P[t[:, 1] - 1] - P[t[:, 0] - 1], P[t[:, 2] - 1] - P[t[:, 0] - 1]),
                  P[t[:, 3] - 1] - P[t[:, 0] - 1]) / 6
    assert v.min() > 0
    assert abs(v.sum() - 2000.0) < 1e-6 * 2000
    fixed = next(f for f, ns in sets.items() if all(abs(nodes[n][0]) < 1e-9 for n in ns))
    pulled = next(f for f, ns in sets.items() if all(abs(nodes[n][0] - 20) < 1e-9 for n in ns))
    deck = text + (f"*MATERIAL, NAME=STEEL\n*ELASTIC\n210000, 0.3\n"
                   "*SOLID SECTION, ELSET=Solid1, MATERIAL=STEEL\n*SOLID SECTION, ELSET=Solid2, MATERIAL=STEEL\n"
                   f"*STEP\n*STATIC\n*BOUNDARY\n{fixed}, 1, 3, 0\n*DSLOAD\n{pulled}, P, -10\n"
                   f"*NODE PRINT, NSET={pulled}\nU\n*END STEP\n")
    (tmp_path / "job.inp").write_text(deck)
    c = subprocess.run(["ccx", "-i", "job"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert c.returncode == 0 and "error" not in c.stdout.lower(), c.stdout[-2000:]
    rows = [l.split() for l in open(tmp_path / "job.dat") if re.match(r"^\s+\d+\s+[-\d.]", l)]
    ux = np.array([float(x[1]) for x in rows])
    assert len(ux) == len(set(sets[pulled]))
    # 10 MPa over 20 mm of steel: 9.52e-4 mm without the clamp's lateral restraint; the clamped
    # end (uy = uz = 0) stiffens it a little (measured: 9.37e-4 mm, -1.6 %, tet10 at size 3)
    expected = 10 * 20 / 210000
    assert 0.95 * expected < ux.mean() < 1.0 * expected
    assert ux.min() > 0.9 * expected
