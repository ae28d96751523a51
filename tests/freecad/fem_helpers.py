# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD 0.20 FEM analyses for the CalculiX tests: an analysis with a CalculiX solver and steel,
fixed and force constraints on CAD faces, a headless run through femtools.ccxtools, and readers of
what it wrote (the .inp's nodes and elements, the .dat's reaction totals)."""
import re

import numpy as np

import FreeCAD
import Part
import ObjectsFem

STEEL = {"Name": "Steel", "YoungsModulus": "210000 MPa", "PoissonRatio": "0.3", "Density": "7900 kg/m^3"}


def analysis(name, shape, workdir):
    """A new document with a Part::Feature holding shape, an analysis with a CalculiX solver
    (working directory workdir) and the steel material. Returns (doc, part, analysis, solver)."""
    doc = FreeCAD.newDocument(name)
    part = doc.addObject("Part::Feature", "Part")
    part.Shape = shape
    an = ObjectsFem.makeAnalysis(doc, "Analysis")
    solver = ObjectsFem.makeSolverCalculixCcxTools(doc, "CCX")
    solver.WorkingDir = str(workdir)
    an.addObject(solver)
    mat = ObjectsFem.makeMaterialSolid(doc, "Steel")
    m = mat.Material
    m.update(STEEL)
    mat.Material = m
    an.addObject(mat)
    return doc, part, an, solver


def fix(doc, an, part, faces, name="Clamp"):
    """A fixed constraint on the 1-based CAD faces (or 'EdgeN' / 'FaceN' names)."""
    c = ObjectsFem.makeConstraintFixed(doc, name)
    c.References = [(part, tuple(_names(faces)))]
    an.addObject(c)
    return c


def force(doc, an, part, faces, newtons, direction, name="Load"):
    """A force of newtons in total spread over the CAD faces, along the vector direction (given to
    FreeCAD as a construction line, which is what its Direction property takes)."""
    d = FreeCAD.Vector(*direction)
    line = doc.addObject("Part::Feature", name + "Direction")
    line.Shape = Part.makeLine(FreeCAD.Vector(0, 0, 0), d)
    c = ObjectsFem.makeConstraintForce(doc, name)
    c.References = [(part, tuple(_names(faces)))]
    c.Force = newtons
    c.Direction = (line, ["Edge1"])
    an.addObject(c)
    return c


def _names(faces):
    return [f if isinstance(f, str) else f"Face{f}" for f in faces]


def solve(doc, an, solver):
    """Writes the .inp with FreeCAD's CalculiX writer, runs ccx and loads the results. Returns
    (result object, FemToolsCcx) with fea.inp_file_name the deck CalculiX ran."""
    from femtools import ccxtools
    doc.recompute()
    fea = ccxtools.FemToolsCcx(an, solver)
    fea.update_objects()
    fea.setup_working_dir(solver.WorkingDir)
    fea.setup_ccx()
    msg = fea.check_prerequisites()
    assert not msg, msg
    fea.write_inp_file()
    fea.ccx_run()
    fea.load_results()
    res = [o for o in an.Group if o.isDerivedFrom("Fem::FemResultObject")]
    assert res, f"CalculiX produced no result: {getattr(fea, 'ccx_stdout', '')}"
    return res[0], fea


def result_arrays(res):
    """(node coordinates (N, 3), displacements (N, 3), von Mises (N,)) of a mechanical result."""
    rm = res.Mesh.FemMesh
    x = np.array([tuple(rm.getNodeById(n)) for n in res.NodeNumbers])
    u = np.array([tuple(v) for v in res.DisplacementVectors])
    return x, u, np.asarray(res.vonMises, dtype=float)


def _deck(path):
    """(keyword line upper-cased without blanks, data line) for each data line of an Abaqus deck."""
    head = ""
    with open(path) as f:
        for line in f:
            s = line.strip()
            if not s or s.startswith("**"):
                continue
            if s.startswith("*"):
                head = s.upper().replace(" ", "")
            else:
                yield head, s


def read_inp(path):
    """Nodes {id: (x, y, z)} and elements {type: (E, n) array of node ids} of an Abaqus deck
    (*NODE and *ELEMENT blocks, one element a line as FreeCAD writes them)."""
    nodes, elements = {}, {}
    for head, s in _deck(path):
        if head == "*NODE" or head.startswith("*NODE,"):
            p = s.split(",")
            nodes[int(p[0])] = tuple(float(v) for v in p[1:4])
        elif head.startswith("*ELEMENT,"):
            etype = re.search(r"TYPE=([A-Z0-9]+)", head).group(1)
            elements.setdefault(etype, []).append([int(v) for v in s.rstrip(",").split(",")[1:]])
    return nodes, {k: np.array(v, dtype=np.int64) for k, v in elements.items()}


def cload_total(path):
    """The sum (fx, fy, fz) of the *CLOAD node loads of an Abaqus deck."""
    total = np.zeros(3)
    for head, s in _deck(path):
        if head.startswith("*CLOAD"):
            _node, dof, value = s.split(",")[:3]
            total[int(dof) - 1] += float(value)
    return total


def corner_volumes(nodes, tets):
    """Signed volumes of the straight tetrahedra on the first four nodes of each row (CalculiX
    C3D4/C3D10 order: positive when the element is valid)."""
    ids = sorted(nodes)
    index = np.full(max(ids) + 1, -1, dtype=np.int64)
    index[ids] = np.arange(len(ids))
    xyz = np.array([nodes[i] for i in ids])
    p = xyz[index[tets[:, :4]]]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6


def reaction_totals(dat_path):
    """{set name: (fx, fy, fz)} from the 'total force' blocks of a CalculiX .dat file."""
    out, name = {}, None
    with open(dat_path) as f:
        for line in f:
            m = re.search(r"total force \(fx,fy,fz\) for set (\S+)", line)
            if m:
                name = m.group(1)
                continue
            vals = line.split()
            if name and len(vals) == 3:
                out[name] = tuple(float(v) for v in vals)
                name = None
    return out
