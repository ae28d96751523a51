# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD FEM hand-over: FreeCAD's own example analysis femexamples.ccx_cantilever_faceload (a
steel box 8000 x 1000 x 1000 mm clamped on Face1, 9 MN on Face2, a FEM Gmsh mesh object holding
the example's tet10 mesh), with a MeshRegion and a MeshGroup added to its Gmsh mesh object, is
handed over to ParaMesh and solved again with CalculiX: the constraints untouched, the region a
local size, the group a FemMesh group, the Gmsh-only settings listed, and the tip deflection that of
the example's own mesh and of beam theory."""
import os
import shutil

import numpy as np
import pytest

import FreeCAD
import ObjectsFem

from freecad.paramesh.app.from_gmsh import from_gmsh_mesh

import fem_helpers as fh

needs_ccx = pytest.mark.skipif(shutil.which("ccx") is None, reason="calculix-ccx is not installed")

# the example's beam: L x b x h, E, nu, F (femexamples/ccx_cantilever_base_solid.py, _faceload.py)
L, B, H, E, NU, F = 8000.0, 1000.0, 1000.0, 210000.0, 0.3, 9.0e6
TIMOSHENKO = F * L ** 3 / (3 * E * B * H ** 3 / 12) + F * L / (5.0 / 6.0 * E / (2 * (1 + NU)) * B * H)


def tip_deflection(doc, an, solver):
    for o in list(an.Group):  # an earlier run's results: fh.solve takes the first one it finds
        if o.isDerivedFrom("Fem::FemResultObject") or o.isDerivedFrom("Fem::FemMeshObject") and o.Name.startswith("ResultMesh"):
            an.removeObject(o)
            doc.removeObject(o.Name)
    res, fea = fh.solve(doc, an, solver)
    x, u, _ = fh.result_arrays(res)
    return -u[np.abs(x[:, 0] - L) < 1e-6, 2].mean(), fea


@needs_ccx
def test_femexample_handed_over_from_gmsh_solves_with_constraints_and_groups(tmp_path):
    from femexamples.ccx_cantilever_faceload import setup
    doc = setup(solvertype="ccxtools")
    try:
        an, box, gmsh_mesh = doc.Analysis, doc.Box, doc.Mesh
        solver = [o for o in an.Group if o.isDerivedFrom("Fem::FemSolverObjectPython")][0]
        solver.WorkingDir = str(tmp_path / "gmsh")
        os.makedirs(solver.WorkingDir)
        constraints = sorted(o.Name for o in an.Group if o.isDerivedFrom("Fem::Constraint"))
        # the example's own mesh (a FemMesh in the Gmsh object) solved as it comes
        own, _ = tip_deflection(doc, an, solver)
        # a user's settings on the Gmsh object: sizes, order, a region, a group, a Gmsh-only option
        gmsh_mesh.CharacteristicLengthMax = 250.0
        gmsh_mesh.ElementOrder = "2nd"
        gmsh_mesh.Algorithm2D = "Frontal"
        region = ObjectsFem.makeMeshRegion(doc, gmsh_mesh, 125.0, "TipRegion")
        region.References = [(box, "Face2")]
        group = ObjectsFem.makeMeshGroup(doc, gmsh_mesh, True, "LoadedEnd")
        group.Label = "loaded_end"
        group.References = [(box, ("Face2", "Face6"))]
        doc.recompute()

        pm_mesh, notes = from_gmsh_mesh(gmsh_mesh)
        # the analysis holds the ParaMesh mesh in place of the Gmsh one, constraints as they were
        meshes = [o for o in an.Group if o.isDerivedFrom("Fem::FemMeshObject")]
        assert meshes == [pm_mesh] and gmsh_mesh not in an.Group and gmsh_mesh in doc.Objects
        assert sorted(o.Name for o in an.Group if o.isDerivedFrom("Fem::Constraint")) == constraints
        assert pm_mesh.Status == "ok", pm_mesh.Report
        assert pm_mesh.Part == box and float(pm_mesh.Size) == 250.0 and pm_mesh.ElementOrder == "2nd"
        assert pm_mesh.Volume3D
        assert [float(c.Size) for c in pm_mesh.LocalSizeList] == [125.0]
        assert pm_mesh.Groups == ["loaded_end=Face2,Face6"]
        assert any(n.startswith("Algorithm2D = Frontal") for n in notes), notes
        # the group in the FemMesh: exactly the triangles of Face2 and Face6
        fm = pm_mesh.FemMesh
        names = {fm.getGroupName(g): g for g in fm.Groups}
        per_face = {f["face"]: f["triangles"] for f in pm_mesh.Proxy.last_result(pm_mesh).faces}
        assert len(fm.getGroupElements(names["loaded_end"])) == per_face[2] + per_face[6]
        assert fm.VolumeCount == fm.TetraCount > 1000
        # solved again: the same beam as the example's own mesh and as Timoshenko's beam theory
        solver.WorkingDir = str(tmp_path / "paramesh")
        os.makedirs(solver.WorkingDir)
        ours, fea = tip_deflection(doc, an, solver)
        nodes, elements = fh.read_inp(fea.inp_file_name)
        assert set(elements) == {"C3D10"} and len(elements["C3D10"]) == fm.VolumeCount
        assert fh.cload_total(fea.inp_file_name) == pytest.approx((0, 0, -F), abs=1e-6 * F)
        print(f"tip deflection: example's mesh {own:.3f} mm, ParaMesh {ours:.3f} mm, Timoshenko {TIMOSHENKO:.3f} mm")
        assert abs(ours - own) / own < 0.02
        assert abs(ours - TIMOSHENKO) / TIMOSHENKO < 0.03
    finally:
        FreeCAD.closeDocument(doc.Name)
