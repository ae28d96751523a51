// SPDX-License-Identifier: LGPL-2.1-or-later
/// The final mesh audit: sound meshes pass with every count 0; each kind of damage done to a
/// sound mesh (a hole, a duplicate, a flipped or folded element, a node off the CAD, coincident
/// nodes, an inverted tetrahedron) is counted exactly and named; a run whose audit fails is not ok.
#include <gtest/gtest.h>

#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "paramesh/audit/MeshAudit.hpp"
#include "paramesh/audit/Repair.hpp"
#include "paramesh/geom/occ/OccModel.hpp"
#include "paramesh/pipeline/Mesher.hpp"
#include "occ_fixtures.hpp"

using namespace paramesh;

namespace {

std::unique_ptr<IGeometryModel> model(const TopoDS_Shape& s) { return test::viaBrep(s); }

MeshOutput meshOf(const IGeometryModel& g, double size, bool volume = false) {
  MeshParams p;
  p.size = size;
  p.volume = volume;
  return Mesher(g, p).run();
}

/// (u,v) of every triangle corner on its face (global projection: test models are small).
std::vector<std::array<Vec2, 3>> cornerUv(const IGeometryModel& g, const SurfaceMesh& m) {
  std::vector<std::array<Vec2, 3>> uv(m.triangles.size());
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    auto s = g.makeSurface(m.triangleFace[t] - 1);
    for (int i = 0; i < 3; ++i) s->projectGlobal(m.nodes[m.triangles[t][i]], uv[t][i]);
    for (int i = 1; i < 3; ++i)  // the corners on one side of a seam
      for (int k = 0; k < 2; ++k) {
        const double per = k ? s->vPeriod() : s->uPeriod();
        if (per > 0) uv[t][i][k] -= per * std::round((uv[t][i][k] - uv[t][0][k]) / per);
      }
  }
  return uv;
}

AuditResult audit(const IGeometryModel& g, const SurfaceMesh& m, bool withUv = false) {
  const std::vector<std::array<Vec2, 3>> tuv = withUv ? cornerUv(g, m) : std::vector<std::array<Vec2, 3>>{};
  const std::vector<std::array<Vec2, 4>> quv;
  return auditMesh(AuditInput{g, m, tuv, quv, {}});
}

/// A triangle of face f none of whose edges lies on a CAD edge, and one of its corners that is
/// a face node.
int interiorTriangle(const SurfaceMesh& m, int f) {
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    if (m.triangleFace[t] != f) continue;
    bool inner = true;
    for (int n : m.triangles[t]) inner = inner && m.nodeKind[n] == NodeKind::Face;
    if (inner) return (int)t;
  }
  return -1;
}

/// The box most tests damage: 10 x 20 x 30 meshed at size 2.
struct BoxMesh {
  std::unique_ptr<IGeometryModel> g;
  SurfaceMesh m;
};
BoxMesh boxMesh() {
  BoxMesh b{model(BRepPrimAPI_MakeBox(10, 20, 30).Shape()), {}};
  b.m = meshOf(*b.g, 2.0).mesh;
  return b;
}

int total(const AuditResult& r) {
  return r.emptyFaces + r.openFaceEdges + r.faceOverusedEdges + r.faceMisorientedEdges + r.nonManifoldEdges + r.solidOpenEdges +
         r.solidOverusedEdges + r.solidMisorientedEdges + r.duplicateElements + r.folds + r.invertedElements +
         r.invertedTets + r.duplicateTets + r.coincidentNodes + r.nodesOffCad;
}

}  // namespace

TEST(Audit, SoundMeshesPassWithEveryCountZero) {
  // a cone's apex and a sphere's poles: corners there have an arbitrary u, left out of the
  // (u,v) centroid at which an element's orientation is measured
  for (const TopoDS_Shape& s : {BRepPrimAPI_MakeBox(10, 20, 30).Shape(), BRepPrimAPI_MakeCylinder(5.0, 12.0).Shape(),
                                BRepPrimAPI_MakeCone(4.0, 0.0, 9.0).Shape(), BRepPrimAPI_MakeSphere(6.0).Shape()}) {
    auto g = model(s);
    MeshOutput out = meshOf(*g, 2.0);
    EXPECT_EQ(out.report.status, RunStatus::Ok);
    ASSERT_TRUE(out.report.audit.run);
    EXPECT_TRUE(out.report.audit.passed()) << out.report.message;
    EXPECT_EQ(total(out.report.audit), 0);
    EXPECT_EQ(out.report.audit.solidsChecked, 1);
    EXPECT_TRUE(out.report.audit.notes.empty());  // the run's (u,v) let it check orientation too
    EXPECT_EQ(out.report.audit.nodesChecked, (int)out.mesh.nodes.size());
    EXPECT_LT(out.report.audit.worstNodeOffset, 1e-9);
    EXPECT_EQ(total(audit(*g, out.mesh, true)), 0);
  }
}

TEST(Audit, AMissingTriangleIsAHoleInItsFaceAndInTheSolid) {
  auto [g, m] = boxMesh();
  const int t = interiorTriangle(m, 3);
  ASSERT_GE(t, 0);
  m.triangles.erase(m.triangles.begin() + t);
  m.triangleFace.erase(m.triangleFace.begin() + t);
  const AuditResult r = audit(*g, m);
  EXPECT_EQ(r.openFaceEdges, 3);
  EXPECT_EQ(r.solidOpenEdges, 3);
  EXPECT_EQ(total(r), 6);
  EXPECT_EQ(r.faces, std::vector<int>{3});
  EXPECT_EQ(r.solids, std::vector<int>{1});
  EXPECT_FALSE(r.passed());
}

TEST(Audit, ADuplicateTriangleIsCountedAsDuplicateAndNonManifold) {
  auto [g, m] = boxMesh();
  const int t = interiorTriangle(m, 2);
  ASSERT_GE(t, 0);
  m.triangles.push_back(m.triangles[t]);
  m.triangleFace.push_back(2);
  const AuditResult r = audit(*g, m);
  EXPECT_EQ(r.duplicateElements, 1);
  EXPECT_EQ(r.nonManifoldEdges, 3);
  EXPECT_EQ(r.faceOverusedEdges, 3);
  EXPECT_EQ(r.solidOverusedEdges, 3);
}

TEST(Audit, AFlippedTriangleIsMisorientedAndFacesAgainstItsSurface) {
  auto [g, m] = boxMesh();
  const int t = interiorTriangle(m, 5);
  ASSERT_GE(t, 0);
  std::swap(m.triangles[t][1], m.triangles[t][2]);
  const AuditResult r = audit(*g, m, true);
  EXPECT_EQ(r.faceMisorientedEdges, 3);
  EXPECT_EQ(r.solidMisorientedEdges, 3);
  EXPECT_EQ(r.invertedElements, 1);
  EXPECT_EQ(r.folds, 0);  // folds are of consistently oriented neighbours: this one is misoriented
  EXPECT_EQ(r.faces, std::vector<int>{5});
}

TEST(Audit, ANodeMovedOffItsFaceIsFoundWithItsDistance) {
  auto g = model(BRepPrimAPI_MakeCylinder(5.0, 12.0).Shape());
  SurfaceMesh m = meshOf(*g, 1.5).mesh;
  int n = -1;
  for (size_t i = 0; i < m.nodes.size() && n < 0; ++i)
    if (m.nodeKind[i] == NodeKind::Face) n = (int)i;
  ASSERT_GE(n, 0);
  const double d = 1e-3 * g->boundingBox().diagonal();
  m.nodes[n] += Vec3{d, 0, 0} * 1.0;
  const AuditResult r = audit(*g, m);
  EXPECT_EQ(r.nodesOffCad, 1);
  EXPECT_NEAR(r.worstNodeOffset, d, 1e-12);
  EXPECT_EQ(r.faces, std::vector<int>{m.nodeEntity[n]});
}

TEST(Audit, ACoincidentCopyOfANodeIsFound) {
  auto [g, m] = boxMesh();
  const int t = interiorTriangle(m, 1);
  ASSERT_GE(t, 0);
  const int a = m.triangles[t][0];
  m.triangles[t][0] = m.addNode(m.nodes[a] + Vec3{1e-12, 0, 0}, NodeKind::Face, m.nodeEntity[a], m.nodeParam[a]);
  const AuditResult r = audit(*g, m);
  EXPECT_EQ(r.coincidentNodes, 1);
  EXPECT_GT(r.openFaceEdges, 0);  // the triangle no longer shares its two edges at that corner
}

TEST(Audit, AnInvertedTetrahedronIsFound) {
  auto g = model(BRepPrimAPI_MakeBox(10, 10, 10).Shape());
  MeshOutput out = meshOf(*g, 3.0, true);
  ASSERT_TRUE(out.report.audit.passed()) << out.report.message;
  ASSERT_GT(out.mesh.tets.size(), 10u);
  std::swap(out.mesh.tets[7][1], out.mesh.tets[7][2]);
  const AuditResult r = audit(*g, out.mesh);
  EXPECT_EQ(r.invertedTets, 1);
  EXPECT_EQ(r.solids, std::vector<int>{1});
}

TEST(Audit, AFaceWithoutElementsIsNamedAndItsSolidNotCheckedForClosure) {
  auto [g, m] = boxMesh();
  std::vector<std::array<int, 3>> kept;
  std::vector<int> keptFace;
  for (size_t t = 0; t < m.triangles.size(); ++t)
    if (m.triangleFace[t] != 4) kept.push_back(m.triangles[t]), keptFace.push_back(m.triangleFace[t]);
  m.triangles = kept;
  m.triangleFace = keptFace;
  const AuditResult r = audit(*g, m);
  EXPECT_EQ(r.emptyFaces, 1);
  EXPECT_EQ(total(r), 1);
  EXPECT_EQ(r.faces, std::vector<int>{4});
  EXPECT_EQ(r.solidsSkipped, 1);
  EXPECT_TRUE(std::any_of(r.notes.begin(), r.notes.end(), [](const std::string& n) {
    return n.find("Solid1 has Face4 without elements") != std::string::npos;
  }));
}

TEST(Audit, ANodePushedAcrossItsNeighboursIsMovedBackByTheRepair) {
  auto [g, m] = boxMesh();
  const int t = interiorTriangle(m, 6);
  ASSERT_GE(t, 0);
  const int v = m.triangles[t][0];
  // across the opposite side, in the face's plane: the triangles around v fold over
  const Vec3 far = m.nodes[m.triangles[t][1]] + m.nodes[m.triangles[t][2]] - m.nodes[v];
  auto s = g->makeSurface(5);
  Vec2 uv = m.nodeParam[v];
  ASSERT_TRUE(s->project(far, uv, &m.nodes[v]));
  m.nodeParam[v] = uv;
  std::vector<std::array<Vec2, 3>> tuv = cornerUv(*g, m);
  std::vector<std::array<Vec2, 4>> quv;
  const AuditResult before = auditMesh(AuditInput{*g, m, tuv, quv, {}});
  ASSERT_GT(before.invertedElements, 0);
  EXPECT_GT(before.folds, 0);
  EXPECT_EQ(repairBadElements(*g, m, tuv, quv, before.badElements), 1);
  const AuditResult after = auditMesh(AuditInput{*g, m, tuv, quv, {}});
  EXPECT_EQ(total(after), 0) << (after.problems.empty() ? "" : after.problems[0]);
  EXPECT_LT(after.worstNodeOffset, 1e-9);  // moved on its face
}

TEST(Audit, CoincidentEdgesSharingSegmentsAndBadReferencesDoNotCrashIt) {
  // unsewn CAD: two coincident CAD edges give the same mesh edge two segments (a fuzzed
  // wing.brep ended in SIGSEGV here); a triangle naming a node that does not exist is a finding
  auto [g, m] = boxMesh();
  ASSERT_FALSE(m.segments.empty());
  m.segments.push_back(m.segments[0]);
  m.segmentEdge.push_back(m.segmentEdge[0]);
  EXPECT_EQ(total(audit(*g, m)), 0);
  m.triangles.push_back({0, 1, (int)m.nodes.size() + 5});
  m.triangleFace.push_back(1);
  const AuditResult r = audit(*g, m);
  EXPECT_EQ(r.invalidEntries, 1);
  EXPECT_EQ(total(r), 0);  // the bad triangle is left out of the other checks
}

TEST(Audit, ProblemsNameEntitiesAndCountTheRest) {
  AuditResult r;
  addFinding(r, "things", 12, {9, 1, 2, 3, 4, 5, 6, 7, 8, 10, 1}, {4});
  ASSERT_EQ(r.problems.size(), 1u);
  EXPECT_EQ(r.problems[0], "12 things (Face1, Face2, Face3, Face4, Face5, Face6, Face7, Face8 and 2 more; Edge4)");
  EXPECT_EQ(r.faces.size(), 10u);
}
