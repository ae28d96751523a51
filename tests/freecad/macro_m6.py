# ParaMesh macro (FreeCAD 0.20): the ONERA M6 wing with a leading-edge boundary layer ->
# Mesh::Feature + FEM mesh, saved as .FCStd.
import sys, FreeCAD, Part, ObjectsFem
import freecad.paramesh as pm
step = sys.argv[1] if len(sys.argv) > 1 else "tests/data/AileM6_with_sharp_TE.stp"
out = sys.argv[2] if len(sys.argv) > 2 else "m6.FCStd"
doc = FreeCAD.newDocument("M6")
wing = doc.addObject("Part::Feature", "Wing")
wing.Shape = Part.read(step)
analysis = ObjectsFem.makeAnalysis(doc, "Analysis")
layer = {"edges": [21, 6], "first_height": 0.5, "growth": 1.2, "layers": 20}  # Edge21: leading edge
fem = pm.make_fem_mesh(doc, wing, analysis, size=16.75, boundary_layers=[layer], create_mesh_feature=True)
doc.saveAs(out)
print(fem.Name, fem.FemMesh.NodeCount, fem.FemMesh.FaceCount, fem.MeshFeature.Mesh.CountFacets)
