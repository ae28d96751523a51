// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file test_narrow.cpp
/// Narrow gaps (NarrowZones.hpp): the gap finder on analytic loops (a strip, a hole near an edge,
/// corner wedges), the staggered node placement on a straight follower, and the effect on real
/// thin faces: the bottle's thread flanks (Face2, Face4: 0.375-0.49 wide at size 0.94) and the
/// M6's trailing-edge strips (Face5, Face8: 2.6-4.6 wide at size 8.4), measured on the mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "MeshChecks.hpp"
#include "paramesh/geom/occ/OccModel.hpp"
#include "paramesh/model/NarrowZones.hpp"
#include "paramesh/pipeline/Mesher.hpp"

using namespace paramesh;

namespace {

/// A closed polygon loop in the plane z = 0 through corners c (in order), each side split into
/// segments of about `spacing`; the face lies to the left (counter-clockwise outer loop) or to the
/// right (clockwise hole), so inward = +z x tangent for both.
std::vector<LoopNode> polygonLoop(const std::vector<Vec3>& c, double spacing, int firstEdge) {
  std::vector<LoopNode> L;
  for (size_t k = 0; k < c.size(); ++k) {
    const Vec3 a = c[k], b = c[(k + 1) % c.size()];
    const int n = std::max(1, (int)std::lround(dist(a, b) / spacing));
    for (int i = 0; i < n; ++i) {
      LoopNode ln;
      ln.xyz = a + ((double)i / n) * (b - a);
      ln.edge = firstEdge + (int)k;
      L.push_back(ln);
    }
  }
  const int m = (int)L.size();
  for (int i = 0; i < m; ++i)
    L[i].inward = normalized(cross(Vec3{0, 0, 1}, L[(i + 1) % m].xyz - L[(i + m - 1) % m].xyz));
  return L;
}

/// A circle loop (hole: clockwise) of radius r around centre.
std::vector<LoopNode> circleHole(Vec3 centre, double r, int n, int edge) {
  std::vector<LoopNode> L(n);
  for (int i = 0; i < n; ++i) {
    const double a = -2.0 * M_PI * i / n;  // clockwise
    L[i].xyz = centre + Vec3{r * std::cos(a), r * std::sin(a), 0};
    L[i].edge = edge;
  }
  for (int i = 0; i < n; ++i) L[i].inward = normalized(cross(Vec3{0, 0, 1}, L[(i + 1) % n].xyz - L[(i + n - 1) % n].xyz));
  return L;
}

class Line final : public ICurve {
 public:
  Line(Vec3 a, Vec3 b) : a_(a), b_(b) {}
  CurveKind kind() const override { return CurveKind::Line; }
  Vec3 eval(double t) const override { return a_ + t * (b_ - a_); }
  void d1(double t, Vec3& p, Vec3& d) const override {
    p = eval(t);
    d = b_ - a_;
  }
  void d2(double t, Vec3& p, Vec3& d, Vec3& dd) const override {
    d1(t, p, d);
    dd = {0, 0, 0};
  }

 private:
  Vec3 a_, b_;
};

double minAngleDeg(Vec3 a, Vec3 b, Vec3 c) {
  auto ang = [](Vec3 p, Vec3 q, Vec3 r) {
    return std::acos(std::clamp(dot(normalized(q - p), normalized(r - p)), -1.0, 1.0)) * 180.0 / M_PI;
  };
  return std::min({ang(a, b, c), ang(b, c, a), ang(c, a, b)});
}

struct FaceStats {
  int triangles = 0, below30 = 0;
};

std::map<int, FaceStats> perFace(const SurfaceMesh& m) {
  std::map<int, FaceStats> s;
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& T = m.triangles[t];
    FaceStats& f = s[m.triangleFace[t]];
    ++f.triangles;
    if (minAngleDeg(m.nodes[T[0]], m.nodes[T[1]], m.nodes[T[2]]) < 30) ++f.below30;
  }
  return s;
}

MeshOutput meshFile(const char* file, double h, bool stagger) {
  auto g = loadOccModel(std::string(PARAMESH_TEST_DATA) + "/" + file);
  MeshParams p;
  p.size = h;
  p.staggerNarrowGaps = stagger;
  Mesher m(*g, p);
  return m.run();
}

}  // namespace

TEST(NarrowGaps, StripSidesFaceEachOther) {
  // a 20 x 0.4 strip, spacing 1: every node of the long sides faces the other side at 0.4
  const auto L = polygonLoop({{0, 0, 0}, {20, 0, 0}, {20, 0.4, 0}, {0, 0.4, 0}}, 1.0, 0);
  const auto gaps = findNarrowGaps({L}, 0.6);
  int bottom = 0, top = 0;
  for (const NarrowGap& g : gaps) {
    EXPECT_NEAR(g.width, 0.4, 1e-9);
    EXPECT_NE(g.edgeAcross, g.edgeOut);
    if (g.edgeOut == 0 && g.edgeIn == 0) ++bottom;
    if (g.edgeOut == 2 && g.edgeIn == 2) ++top;
    EXPECT_TRUE(g.edgeAcross == 0 || g.edgeAcross == 2) << "the short ends are corners, not gaps";
  }
  EXPECT_EQ(bottom, 19);  // interior nodes of the 20-segment side
  EXPECT_EQ(top, 19);
  // wider than 0.6 of the spacing: nothing
  EXPECT_TRUE(findNarrowGaps({polygonLoop({{0, 0, 0}, {20, 0, 0}, {20, 0.7, 0}, {0, 0.7, 0}}, 1.0, 0)}, 0.6).empty());
}

TEST(NarrowGaps, LigamentBetweenHoleAndEdgeButNotAcrossTheHole) {
  // a 20 x 10 plate with a hole of radius 2 whose rim passes 0.3 from the bottom edge
  const auto outer = polygonLoop({{0, 0, 0}, {20, 0, 0}, {20, 10, 0}, {0, 10, 0}}, 0.8, 0);
  const auto hole = circleHole({10, 2.3, 0}, 2.0, 16, 4);
  const auto gaps = findNarrowGaps({outer, hole}, 0.6);
  ASSERT_FALSE(gaps.empty());
  double minWidth = 1e300;
  for (const NarrowGap& g : gaps) {
    // only between the bottom edge and the hole's rim, through the ligament (y < 0.6)
    EXPECT_LT(std::max(g.p.y, g.q.y), 0.6);
    EXPECT_TRUE((g.edgeOut == 0 && g.edgeAcross == 4) || (g.edgeOut == 4 && g.edgeAcross == 0));
    minWidth = std::min(minWidth, g.width);
  }
  EXPECT_NEAR(minWidth, 0.3, 0.05);
}

TEST(NarrowGaps, SharpCornersFromWhereTheirSidesComeClose) {
  // a 60 degree corner: its sides are never closer than 0.6 of the spacing: no gap
  EXPECT_TRUE(findNarrowGaps({polygonLoop({{0, 0, 0}, {20, 0, 0}, {10, 10 * std::sqrt(3.0), 0}}, 1.0, 0)}, 0.6).empty());
  // a 10 degree wedge: the nodes of one side within r = 0.6 / sin 10 deg = 3.5 spacings of the tip
  // face the other side, at r sin 10 deg
  const double a = 10.0 * M_PI / 180.0;
  const auto gaps = findNarrowGaps({polygonLoop({{0, 0, 0}, {20, 0, 0}, {20, 20 * std::tan(a), 0}}, 1.0, 0)}, 0.6);
  ASSERT_FALSE(gaps.empty());
  for (const NarrowGap& g : gaps) {
    const double r = norm(g.p);
    EXPECT_LT(r, 0.6 * g.spacing / std::sin(a) + 1e-9);
    EXPECT_NEAR(g.width, r * std::sin(a), 1e-6 * r);
  }
}

TEST(NarrowGaps, StaggeredNodesSitMidwayBetweenLeaderProjections) {
  // follower: the x axis from 0 to 10; leader nodes at x = 0..10 step 1, 0.4 above it
  Line follower({0, 0, 0}, {10, 0, 0});
  std::vector<Vec3> leader;
  for (int i = 0; i <= 10; ++i) leader.push_back({(double)i, 0.4, 0});
  SizeField field(1.0, 1.3);
  field.build();
  const std::vector<double> t = staggeredParameters(follower, 0.0, 1.0, leader, field, M_PI / 3);
  ASSERT_GE(t.size(), 3u);
  EXPECT_DOUBLE_EQ(t.front(), 0.0);
  EXPECT_DOUBLE_EQ(t.back(), 1.0);
  // interior nodes at 0.5, 1.5, ..., 9.5 (x = 10 t): leader nodes stand right across both ends
  // (a strip closed by short edges), so the half segments there start the zigzag
  ASSERT_EQ(t.size(), 12u);
  for (size_t k = 1; k + 1 < t.size(); ++k) EXPECT_NEAR(10 * t[k], k - 0.5, 1e-6) << k;
  // two edges meeting at a sharp corner: the leader's first node is the follower's own end; a
  // half segment there would stand a poor triangle in the corner: dropped, the end piece split
  std::vector<Vec3> wedge;
  for (int i = 0; i <= 10; ++i) wedge.push_back({(double)i, 0.04 * i, 0});
  std::vector<double> x;
  for (double v : staggeredParameters(follower, 0.0, 1.0, wedge, field, M_PI / 3)) x.push_back(10 * v);
  ASSERT_GE(x.size(), 3u);
  EXPECT_GT(x[1], 0.7);
}

TEST(NarrowGaps, StaggeredBetweenRegularPiecesAwayFromTheGap) {
  // leader nodes only over x in [4, 7]: nodes midway there, the rest discretised by size (1.0)
  Line follower({0, 0, 0}, {10, 0, 0});
  std::vector<Vec3> leader;
  for (int i = 4; i <= 7; ++i) leader.push_back({(double)i, 0.4, 0});
  SizeField field(1.0, 1.3);
  field.build();
  const std::vector<double> t = staggeredParameters(follower, 0.0, 1.0, leader, field, M_PI / 3);
  std::vector<double> x;
  for (double v : t) x.push_back(10 * v);
  for (double mid : {4.5, 5.5, 6.5})
    EXPECT_TRUE(std::any_of(x.begin(), x.end(), [&](double v) { return std::fabs(v - mid) < 1e-6; })) << mid;
  for (size_t k = 1; k < x.size(); ++k) {
    EXPECT_GT(x[k] - x[k - 1], 0.5) << k;
    EXPECT_LT(x[k] - x[k - 1], 1.5) << k;
  }
}

TEST(NarrowGaps, BottleThreadFlanksGetGoodAngles) {
  // bottle.brep at diagonal/100: the thread flanks Face2 and Face4 are one row of triangles
  // 0.375-0.49 wide (0.4-0.52 of the size). Nodes opposite each other left 124 and 66 of their
  // ~200 triangles below 30 degrees; staggered, with the spacing widened, a few dozen at most.
  const double h = 93.94147114027967 / 100;
  const MeshOutput off = meshFile("bottle.brep", h, false);
  const MeshOutput on = meshFile("bottle.brep", h, true);
  auto a = perFace(off.mesh), b = perFace(on.mesh);
  EXPECT_GT(a[2].below30 + a[4].below30, 100);
  EXPECT_LE(b[2].below30 + b[4].below30, 40);
  EXPECT_GT(b[2].triangles, 140);
  // and nothing else got worse
  int restOff = 0, restOn = 0;
  for (auto& kv : a)
    if (kv.first != 2 && kv.first != 4) restOff += kv.second.below30;
  for (auto& kv : b)
    if (kv.first != 2 && kv.first != 4) restOn += kv.second.below30;
  EXPECT_LE(restOn, restOff);
  const auto st = paramesh::test::measure(on.mesh, *loadOccModel(std::string(PARAMESH_TEST_DATA) + "/bottle.brep"), h);
  EXPECT_EQ(st.boundaryEdges, 0);
  EXPECT_EQ(st.nonManifoldEdges, 0);
  EXPECT_EQ(st.flipped, 0);
  EXPECT_GE(st.pctLenInSqrt2, 99.0);
}

TEST(NarrowGaps, M6TrailingEdgeStripsWithoutShortEdges) {
  // the M6's trailing edge: two plane strips (Face5, Face8) 2.6-4.6 wide; at diagonal/200
  // (h = 8.4) nodes opposite each other made nearly all of their triangles poor. Staggered, with
  // the leader's spacing widened so that the slanted edges stay >= h/sqrt2, most are good and the
  // strips have fewer short edges than before.
  const double h = 1675.004499542725 / 200;
  const MeshOutput off = meshFile("AileM6_with_sharp_TE.stp", h, false);
  const MeshOutput on = meshFile("AileM6_with_sharp_TE.stp", h, true);
  auto a = perFace(off.mesh), b = perFace(on.mesh);
  EXPECT_GT(a[5].below30, 0.8 * a[5].triangles);
  EXPECT_LT(b[5].below30, 0.25 * b[5].triangles);
  EXPECT_LT(b[8].below30, 0.25 * b[8].triangles);
  auto shortEdges = [&](const SurfaceMesh& m, int face) {
    std::set<std::pair<int, int>> E;
    for (size_t t = 0; t < m.triangles.size(); ++t) {
      if (m.triangleFace[t] != face) continue;
      for (int k = 0; k < 3; ++k) {
        const int u = m.triangles[t][k], v = m.triangles[t][(k + 1) % 3];
        E.insert({std::min(u, v), std::max(u, v)});
      }
    }
    int n = 0;
    for (auto& e : E) n += dist(m.nodes[e.first], m.nodes[e.second]) < h / std::sqrt(2.0) ? 1 : 0;
    return n;
  };
  EXPECT_LT(shortEdges(on.mesh, 5), shortEdges(off.mesh, 5));
  EXPECT_LT(shortEdges(on.mesh, 8), shortEdges(off.mesh, 8));
}
