// SPDX-License-Identifier: LGPL-2.1-or-later
// The discrete backend (issue 36) on triangulated cubes: repair, the feature graph, the
// parametrisation and a remesh through the unchanged pipeline, measured (also under ASan in CI).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>

#include "paramesh/geom/discrete/DiscreteModel.hpp"
#include "paramesh/pipeline/Mesher.hpp"
#include "paramesh/util/Error.hpp"

using namespace paramesh;

namespace {

/// The unit cube as 12 triangles, outward, each face split along a diagonal.
TriangleSoup cube(double s = 1.0) {
  TriangleSoup c;
  c.source = "cube";
  for (int i = 0; i < 8; ++i) c.points.push_back({s * (i & 1), s * ((i >> 1) & 1), s * ((i >> 2) & 1)});
  const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : q) {
    c.triangles.push_back({f[0], f[1], f[2]});
    c.triangles.push_back({f[0], f[2], f[3]});
  }
  return c;
}

double volume(const SurfaceMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles) v += dot(m.nodes[t[0]], cross(m.nodes[t[1]], m.nodes[t[2]]));
  return v / 6;
}

}  // namespace

TEST(Discrete, CubeHasSixFacesTwelveEdgesEightCorners) {
  const DiscreteInput d = discreteFromArrays(cube());
  EXPECT_EQ(d.graph.faceTris.size(), 6u);
  EXPECT_EQ(d.graph.edges.size(), 12u);
  EXPECT_EQ(d.graph.vertexNode.size(), 8u);
  EXPECT_EQ(d.repair.closedPieces, 1);
  for (const auto& loops : d.graph.faceLoops) {
    ASSERT_EQ(loops.size(), 1u);
    EXPECT_EQ(loops[0].size(), 4u);  // each face bounded by its four edges, in one wire
  }
}

TEST(Discrete, InsideOutFacetsAreTurnedAndCounted) {
  TriangleSoup c = cube();
  std::swap(c.triangles[3][1], c.triangles[3][2]);
  for (auto& t : c.triangles) std::swap(t[1], t[2]);  // all inside out, facet 3 the right way
  const DiscreteInput d = discreteFromArrays(c);
  EXPECT_EQ(d.repair.flippedFacets, 11);  // 11 turned to agree with facet 0, then all 12 outward
  double v = 0;
  for (const auto& t : d.mesh.triangles) v += dot(d.mesh.points[t[0]], cross(d.mesh.points[t[1]], d.mesh.points[t[2]]));
  EXPECT_NEAR(v / 6, 1.0, 1e-12);
}

TEST(Discrete, RemeshedCubeIsClosedOnItsFacesWithSharpEdgesKept) {
  auto model = makeDiscreteModel(discreteFromArrays(cube(10.0)));
  ASSERT_EQ(model->numFaces(), 6);
  ASSERT_EQ(model->numSolids(), 1);
  MeshParams p;
  p.size = 1.0;
  MeshOutput out = Mesher(*model, p).run();
  EXPECT_EQ(out.report.status, RunStatus::Ok) << out.report.message;
  const SurfaceMesh& m = out.mesh;
  EXPECT_GT(m.triangles.size(), 1000u);
  EXPECT_NEAR(volume(m), 1000.0, 1e-6);  // flat faces: the same volume, outward
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : m.triangles)
    for (int i = 0; i < 3; ++i) ++directed[{t[i], t[(i + 1) % 3]}];
  for (const auto& [e, n] : directed) {
    EXPECT_EQ(n, 1);
    EXPECT_EQ(directed.count({e.second, e.first}), 1u);  // closed and consistently oriented
  }
  for (const Vec3& x : m.nodes) {  // every node on the cube's surface
    const double d = std::min({x.x, 10 - x.x, x.y, 10 - x.y, x.z, 10 - x.z});
    EXPECT_NEAR(d, 0.0, 1e-9);
  }
  int onEdges = 0;  // the 12 sharp edges kept: nodes on them, about one per size along each
  for (const Vec3& x : m.nodes) {
    int flat = 0;
    for (double c : {x.x, x.y, x.z}) flat += std::abs(c) < 1e-9 || std::abs(c - 10) < 1e-9;
    onEdges += flat >= 2;
  }
  EXPECT_NEAR(onEdges, 12 * 10 - 4, 12);
  EXPECT_GT(out.report.quality.gammaMean, 0.95);
  EXPECT_GT(out.report.quality.angleMin, 30.0);
}

TEST(Discrete, DamagedBinaryStlIsRefusedNamingTheCount) {
  const std::string path = ::testing::TempDir() + "/lying.stl";
  {
    std::ofstream f(path, std::ios::binary);
    std::string header(80, ' ');
    f.write(header.data(), 80);
    const uint32_t n = 1000;
    f.write(reinterpret_cast<const char*>(&n), 4);
    f.write(std::string(50, '\0').data(), 50);
  }
  try {
    (void)loadDiscreteModel(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("header counts 1000 facets"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}
