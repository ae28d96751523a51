// SPDX-License-Identifier: LGPL-2.1-or-later
/// Volume stage: tetrahedra filling closed solids from our surface triangles (nglib inside),
/// their shape measures, tet10 mid-nodes, conformal contacts and coincident faces.
#include <gtest/gtest.h>

#include <BRepBuilderAPI_Copy.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Pnt.hxx>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "paramesh/geom/occ/OccModel.hpp"
#include "paramesh/pipeline/Mesher.hpp"
#include "paramesh/stages/volume/SolidSurface.hpp"
#include "paramesh/volume/SelfIntersection.hpp"
#include "paramesh/volume/Tet10.hpp"
#include "paramesh/volume/TetQuality.hpp"

using namespace paramesh;

namespace {

std::string toBrep(const TopoDS_Shape& s) {
  std::ostringstream o;
  BRepTools::Write(s, o);
  return o.str();
}

TopoDS_Shape compound(std::initializer_list<TopoDS_Shape> parts) {
  BRep_Builder b;
  TopoDS_Compound c;
  b.MakeCompound(c);
  for (const auto& p : parts) b.Add(c, p);
  return c;
}

MeshOutput meshVolume(const IGeometryModel& g, double size, int order = 1) {
  MeshParams p;
  p.size = size;
  p.volume = true;
  p.order = order;
  return Mesher(g, p).run();
}

/// The surface triangles of solid s (1-based faces of its report), oriented out of it.
std::vector<std::array<int, 3>> surfaceOf(const IGeometryModel& g, int s, const SurfaceMesh& m) {
  std::vector<std::vector<int>> tof(g.numFaces());
  std::vector<int> qof(g.numFaces(), 0);
  for (std::size_t t = 0; t < m.triangles.size(); ++t) tof[m.triangleFace[t] - 1].push_back((int)t);
  return solidSurface(g, s, m, tof, qof).triangles;
}

std::vector<std::array<int, 4>> tetsOf(const SurfaceMesh& m, int solid) {
  std::vector<std::array<int, 4>> out;
  for (std::size_t k = 0; k < m.tets.size(); ++k)
    if (m.tetSolid[k] == solid) out.push_back(m.tets[k]);
  return out;
}

}  // namespace

TEST(TetQuality, RegularAndCornerTetrahedra) {
  const Vec3 a{1, 1, 1}, b{1, -1, -1}, c{-1, -1, 1}, d{-1, 1, -1};  // regular, positive
  ASSERT_GT(tetVolume6(a, b, c, d), 0);
  for (double x : tetDihedrals(a, b, c, d)) EXPECT_NEAR(x, std::acos(1.0 / 3.0) * 180 / M_PI, 1e-9);
  EXPECT_NEAR(tetRadiusRatio(a, b, c, d), 1.0, 1e-12);
  const Vec3 o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  const auto dh = tetDihedrals(o, x, y, z);  // edges ox, oy, oz: 90; xy, xz, yz: acos(1/sqrt3)
  EXPECT_NEAR(dh[0], 90, 1e-9);
  EXPECT_NEAR(dh[2], 90, 1e-9);
  EXPECT_NEAR(dh[5], std::acos(1 / std::sqrt(3.0)) * 180 / M_PI, 1e-9);
  EXPECT_NEAR(tetVolume6(o, x, y, z), 1.0, 1e-15);
  EXPECT_LT(tetRadiusRatio(o, x, y, {0.3, 0.3, 1e-6}), 1e-4);  // nearly flat
}

TEST(Tet10, StraightIsOneAndFoldedIsNotPositive) {
  Vec3 x[10] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int e[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  for (int k = 0; k < 6; ++k) x[4 + k] = 0.5 * (x[e[k][0]] + x[e[k][1]]);
  EXPECT_NEAR(tet10MinScaledJacobian(x), 1.0, 1e-12);
  x[4] = {0.5, 0.0, 0.1};  // mid-node of ab bent a little towards d: still valid
  const double bent = tet10MinScaledJacobian(x);
  EXPECT_GT(bent, 0.0);
  EXPECT_LT(bent, 1.0);
  x[4] = {0.5, 0.0, 1.2};  // pushed through the opposite face: folded
  EXPECT_LE(tet10MinScaledJacobian(x), 0.0);
}

TEST(Volume, BoxIsFilledExactlyFromItsSurface) {
  auto g = loadOccModelFromBrepString(toBrep(BRepPrimAPI_MakeBox(10, 20, 30).Shape()));
  MeshOutput out = meshVolume(*g, 3.0);
  const SurfaceMesh& m = out.mesh;
  ASSERT_EQ(out.report.status, RunStatus::Ok) << out.report.message;
  ASSERT_EQ(out.report.solids.size(), 1u);
  const SolidReport& s = out.report.solids[0];
  ASSERT_TRUE(s.ok) << s.error;
  EXPECT_EQ(s.tetrahedra, (int)m.tets.size());
  EXPECT_GT(s.tetrahedra, 6000 / 3.0 / 3.0 / 3.0 * 5);  // about 6 tets per h^3 cube, at least 5
  EXPECT_NEAR(s.volume, 6000.0, 6000.0 * 1e-9);
  EXPECT_EQ(checkFill(m.nodes, m.tets, surfaceOf(*g, 0, m)), "");
  const TetStats st = tetStats(m.nodes, m.tets);
  EXPECT_EQ(st.inverted, 0);
  EXPECT_GT(st.minDihedral, 8.0);
  EXPECT_GT(st.meanRadiusRatio, 0.75);
  // interior nodes are Volume nodes of Solid1, strictly inside
  int interior = 0;
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    if (m.nodeKind[i] == NodeKind::Volume) {
      ++interior;
      EXPECT_EQ(m.nodeEntity[i], 1);
      const Vec3& p = m.nodes[i];
      EXPECT_TRUE(p.x > 0 && p.x < 10 && p.y > 0 && p.y < 20 && p.z > 0 && p.z < 30);
    }
  EXPECT_EQ(interior, s.nodes);
  // the interior spacing follows the surface size: mean tet edge within [0.6, 1.4] h
  double sum = 0;
  int n = 0;
  for (const auto& t : m.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) sum += dist(m.nodes[t[i]], m.nodes[t[j]]), ++n;
  EXPECT_GT(sum / n, 0.6 * 3.0);
  EXPECT_LT(sum / n, 1.4 * 3.0);
}

TEST(Volume, VolumeMaxSizeRefinesTheInterior) {
  auto g = loadOccModelFromBrepString(toBrep(BRepPrimAPI_MakeBox(30, 30, 30).Shape()));
  MeshParams p;
  p.size = 5.0;
  p.volume = true;
  const int coarse = (int)Mesher(*g, p).run().mesh.tets.size();
  p.volumeMaxSize = 2.5;
  MeshOutput fine = Mesher(*g, p).run();
  ASSERT_TRUE(fine.report.solids.at(0).ok) << fine.report.solids[0].error;
  EXPECT_GT((int)fine.mesh.tets.size(), 3 * coarse);  // (5 / 2.5)^3 = 8 x inside, less near the surface
  EXPECT_NEAR(fine.report.solids[0].volume, 27000.0, 27000.0 * 1e-9);
}

TEST(Volume, Tet10OnACylinderHasCurvedBoundaryAndPositiveJacobians) {
  auto g = loadOccModelFromBrepString(toBrep(BRepPrimAPI_MakeCylinder(5.0, 10.0).Shape()));
  MeshOutput out = meshVolume(*g, 2.0, 2);
  const SurfaceMesh& m = out.mesh;
  ASSERT_TRUE(out.report.solids.at(0).ok) << out.report.solids[0].error;
  ASSERT_EQ(m.tetMid.size(), m.tets.size());
  EXPECT_GT(out.report.minTetJacobian, 0.0);
  // mid-nodes of surface edges on the lateral face lie on the cylinder (radius 5)
  std::set<int> surfaceMids;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (int v : m.triangleMid[t]) surfaceMids.insert(v);
  int onCylinder = 0, interiorStraight = 0;
  for (std::size_t k = 0; k < m.tets.size(); ++k) {
    const int e[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
    for (int i = 0; i < 6; ++i) {
      const int v = m.tetMid[k][i];
      const Vec3 mid = 0.5 * (m.nodes[m.tets[k][e[i][0]]] + m.nodes[m.tets[k][e[i][1]]]);
      if (!surfaceMids.count(v)) {
        EXPECT_LT(dist(m.nodes[v], mid), 1e-12);  // interior mid-nodes straight
        ++interiorStraight;
      } else if (m.nodeKind[v] == NodeKind::Face && m.nodeEntity[v] == 1) {
        const Vec3& x = m.nodes[v];
        EXPECT_NEAR(std::hypot(x.x, x.y), 5.0, 1e-9);
        ++onCylinder;
      }
    }
  }
  EXPECT_GT(onCylinder, 100);
  EXPECT_GT(interiorStraight, 100);
  // volume of the curved tet10 mesh is nearer pi r^2 h than the straight tets' (inscribed)
  EXPECT_LT(out.report.solids[0].volume, M_PI * 25 * 10);
  EXPECT_GT(out.report.solids[0].volume, 0.98 * M_PI * 25 * 10);
}

TEST(Volume, TouchingBoxesWithoutSharedTopologyAreConformal) {
  const TopoDS_Shape a = BRepPrimAPI_MakeBox(10, 10, 10).Shape();
  const TopoDS_Shape b = BRepPrimAPI_MakeBox(gp_Pnt(10, 0, 0), 10, 10, 10).Shape();
  auto g = loadOccModelFromBrepString(toBrep(compound({a, b})));
  ASSERT_EQ(g->numSolids(), 2);
  MeshOutput out = meshVolume(*g, 2.0);
  const SurfaceMesh& m = out.mesh;
  ASSERT_EQ(out.report.coincidentFaces.size(), 1u);
  const auto [src, copy] = out.report.coincidentFaces[0];
  ASSERT_EQ(out.report.solids.size(), 2u);
  for (int s = 0; s < 2; ++s) {
    ASSERT_TRUE(out.report.solids[s].ok) << out.report.solids[s].error;
    EXPECT_EQ(checkFill(m.nodes, tetsOf(m, s + 1), surfaceOf(*g, s, m)), "");
  }
  // one triangulation on the contact: the same node triples on both faces, no coincident nodes
  std::set<std::array<int, 3>> onSrc, onCopy;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    auto v = m.triangles[t];
    std::sort(v.begin(), v.end());
    if (m.triangleFace[t] == src) onSrc.insert(v);
    if (m.triangleFace[t] == copy) onCopy.insert(v);
  }
  EXPECT_FALSE(onSrc.empty());
  EXPECT_EQ(onSrc, onCopy);
  double closest = 1e300;
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    for (std::size_t j = i + 1; j < m.nodes.size(); ++j) closest = std::min(closest, dist(m.nodes[i], m.nodes[j]));
  EXPECT_GT(closest, 0.1);
  EXPECT_NEAR(out.report.solids[0].volume + out.report.solids[1].volume, 2000.0, 2000.0 * 1e-9);
}

TEST(Volume, LooseCopyOfAFaceIsMeshedOnce) {
  const TopoDS_Shape cyl = BRepPrimAPI_MakeCylinder(5.0, 20.0).Shape();
  TopExp_Explorer ex(cyl, TopAbs_FACE);  // the first face: the lateral one
  const TopoDS_Shape loose = BRepBuilderAPI_Copy(ex.Current()).Shape();
  auto g = loadOccModelFromBrepString(toBrep(compound({cyl, loose})));
  MeshOutput out = meshVolume(*g, 2.0);
  ASSERT_EQ(out.report.coincidentFaces.size(), 1u);
  ASSERT_TRUE(out.report.solids.at(0).ok) << out.report.solids[0].error;
  const SurfaceMesh& m = out.mesh;
  EXPECT_EQ(checkFill(m.nodes, m.tets, surfaceOf(*g, 0, m)), "");
  const auto [src, copy] = out.report.coincidentFaces[0];
  int a = 0, b = 0;
  for (int f : m.triangleFace) a += f == src, b += f == copy;
  EXPECT_GT(a, 50);
  EXPECT_EQ(a, b);
}

TEST(Volume, AnOpenSurfaceIsRefusedNamingItsFace) {
  auto g = loadOccModelFromBrepString(toBrep(BRepPrimAPI_MakeBox(10, 10, 10).Shape()));
  MeshParams p;
  p.size = 3.0;
  SurfaceMesh m = Mesher(*g, p).run().mesh;
  std::vector<std::vector<int>> tof(g->numFaces());
  std::vector<int> qof(g->numFaces(), 0);
  for (std::size_t t = 0; t < m.triangles.size(); ++t) tof[m.triangleFace[t] - 1].push_back((int)t);
  const int dropped = tof[3].back();  // a triangle of Face4 missing
  tof[3].pop_back();
  const SolidSurface s = solidSurface(*g, 0, m, tof, qof);
  EXPECT_NE(s.problem.find("3 open edges"), std::string::npos) << s.problem;
  EXPECT_NE(s.problem.find("Face4"), std::string::npos) << s.problem;
  (void)dropped;
  tof[3].clear();
  EXPECT_NE(solidSurface(*g, 0, m, tof, qof).problem.find("Face4 has no triangle"), std::string::npos);
}

TEST(Volume, QuadsAreRefusedWithTheReason) {
  MeshParams p;
  p.volume = true;
  p.quads = true;
  try {
    p.validate();
    FAIL() << "volume with quads accepted";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("triangle surface"), std::string::npos);
  }
}

TEST(SelfIntersection, CrossingTrianglesAreFoundTouchingOnesAreNot) {
  std::vector<Vec3> x = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0},           // A in z = 0
                         {0.5, 0.5, -1}, {0.5, 0.5, 1}, {1.5, 1.5, 1},  // B pierces A
                         {0, 0, 0}, {-1, 0, 1}, {0, -1, 1}};          // C touches A's corner only
  std::vector<std::array<int, 3>> t = {{0, 1, 2}, {3, 4, 5}, {0, 7, 8}};
  auto pairs = crossingTriangles(x, t);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0], std::make_pair(0, 1));
  // a closed box surface from the mesher has none
  auto g = loadOccModelFromBrepString(toBrep(BRepPrimAPI_MakeBox(10, 10, 10).Shape()));
  MeshParams p;
  p.size = 2.0;
  SurfaceMesh m = Mesher(*g, p).run().mesh;
  EXPECT_TRUE(crossingTriangles(m.nodes, m.triangles).empty());
  // one node pushed through the opposite face: crossings found
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    if (m.nodeKind[i] == NodeKind::Face && m.nodes[i].z == 10.0) {
      m.nodes[i].z = -1.0;
      break;
    }
  EXPECT_FALSE(crossingTriangles(m.nodes, m.triangles).empty());
}
