// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file test_triangulation.cpp
/// Tests of the exact predicates and of the 2D triangulation: constrained Delaunay triangulation of
/// polygons with holes (segments present and constrained, orientation, domain, area, adjacency,
/// Euler characteristic, local Delaunay property), its failure paths, incremental Delaunay
/// insertion with flips, vertex rings, and the domain guard's point-in-face test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "paramesh/algo/DomainGuard.hpp"
#include "paramesh/algo/Predicates.hpp"
#include "paramesh/algo/Triangulation.hpp"
#include "triangulation_fixtures.hpp"

using namespace paramesh;
using namespace paramesh::test;


// ---------------------------------------------------------------------------------------------
// Predicates

TEST(Predicates, Orient2dBasic) {
  EXPECT_EQ(orient2d({0, 0}, {1, 0}, {0, 1}), 1);
  EXPECT_EQ(orient2d({0, 0}, {0, 1}, {1, 0}), -1);
  EXPECT_EQ(orient2d({0, 0}, {1, 1}, {2, 2}), 0);
  EXPECT_EQ(orient2d({0, 0}, {1, 1}, {1, 1}), 0);
  // points on y = x with perturbations of 2^-50
  const double e = std::ldexp(1.0, -50);
  EXPECT_EQ(orient2d({0.5, 0.5}, {1.5, 1.5}, {0.75, 0.75 + e}), 1);
  EXPECT_EQ(orient2d({0.5, 0.5}, {1.5, 1.5}, {0.75 + e, 0.75}), -1);
  EXPECT_EQ(orient2d({0.5, 0.5}, {1.5, 1.5}, {1.0, 1.0}), 0);
  EXPECT_EQ(orient2d({3.0, 3.0}, {7.0, 7.0}, {5.0 - 4 * e, 5.0 - 4 * e}), 0);
  EXPECT_EQ(orient2d({3.0, 3.0}, {7.0, 7.0}, {5.0 - 4 * e, 5.0}), 1);
}

/// The classic test: a = (0.5 + x u, 0.5 + y u), u = 2^-53, x,y in [0,256), against b = (12,12),
/// c = (24,24). The naive determinant gets the sign wrong on much of this grid; the exact sign is
/// computed with 128-bit integers on coordinates scaled by 2^53.
TEST(Predicates, Orient2dClassicGrid) {
  const double u = std::ldexp(1.0, -53);
  const i128 S = (i128)1 << 53;
  int naiveWrong = 0, checked = 0;
  for (int x = 0; x < 256; ++x)
    for (int y = 0; y < 256; ++y) {
      const Vec2 a{0.5 + x * u, 0.5 + y * u}, b{12, 12}, c{24, 24};
      ASSERT_EQ(a.x, 0.5 + x * u);  // exactly representable
      const int expect = exactSign(S / 2 + x, S / 2 + y, 12 * S, 12 * S, 24 * S, 24 * S);
      ASSERT_EQ(orient2d(a, b, c), expect) << "x " << x << " y " << y;
      // cyclic invariance and antisymmetry
      ASSERT_EQ(orient2d(b, c, a), expect);
      ASSERT_EQ(orient2d(b, a, c), -expect);
      const double naive = (a.x - c.x) * (b.y - c.y) - (a.y - c.y) * (b.x - c.x);
      if ((naive > 0 ? 1 : naive < 0 ? -1 : 0) != expect) ++naiveWrong;
      ++checked;
    }
  EXPECT_EQ(checked, 65536);
  EXPECT_GT(naiveWrong, 0);  // the grid is hard enough to defeat plain floating point
}

/// Random nearly collinear triples on the grid 2^-50 Z^2 (|coord| < 4): c is a rounded point of the
/// line ab plus a perturbation of a few grid units. Exact reference with 128-bit integers.
TEST(Predicates, Orient2dNearlyCollinearRandom) {
  std::mt19937_64 rng(12345);
  const double g = std::ldexp(1.0, -50);
  const int64_t lim = (int64_t)1 << 51;  // |k| * 2^-50 < 2
  std::uniform_int_distribution<int64_t> K(-lim, lim);
  std::uniform_real_distribution<double> T(-1.5, 2.5);
  std::uniform_int_distribution<int> P(-3, 3);
  int zero = 0, pos = 0, neg = 0;
  for (int it = 0; it < 200000; ++it) {
    const int64_t ax = K(rng), ay = K(rng), bx = K(rng), by = K(rng);
    const double t = T(rng);
    int64_t cx = ax + (int64_t)std::llround(t * (double)(bx - ax)) + P(rng);
    int64_t cy = ay + (int64_t)std::llround(t * (double)(by - ay)) + P(rng);
    if (it % 7 == 0) {  // exactly collinear: c = a + k (b - a) / gcd-free multiple
      const int64_t k = P(rng);
      cx = ax + k * ((bx - ax) / 8);
      cy = ay + k * ((by - ay) / 8);
      const Vec2 a{ax * g, ay * g}, b{(ax + (bx - ax) / 8) * g, (ay + (by - ay) / 8) * g}, c{cx * g, cy * g};
      ASSERT_EQ(orient2d(a, b, c), 0);
      ++zero;
      continue;
    }
    const Vec2 a{ax * g, ay * g}, b{bx * g, by * g}, c{cx * g, cy * g};
    const int expect = exactSign(ax, ay, bx, by, cx, cy);
    ASSERT_EQ(orient2d(a, b, c), expect) << it;
    ASSERT_EQ(orient2d(c, a, b), expect) << it;
    ASSERT_EQ(orient2d(a, c, b), -expect) << it;
    (expect == 0 ? zero : expect > 0 ? pos : neg)++;
  }
  EXPECT_GT(pos, 1000);
  EXPECT_GT(neg, 1000);
  EXPECT_GT(zero, 10);
}

TEST(Predicates, SegmentsCross) {
  // proper crossing
  EXPECT_TRUE(segmentsCross({0, 0}, {2, 2}, {0, 2}, {2, 0}));
  EXPECT_TRUE(segmentsCross({0, 0}, {1, 0}, {0.5, -1e-300}, {0.5, 1}));
  // touching at a shared endpoint
  EXPECT_FALSE(segmentsCross({0, 0}, {1, 1}, {1, 1}, {2, 0}));
  EXPECT_FALSE(segmentsCross({0, 0}, {1, 1}, {0, 0}, {-1, 3}));
  // an endpoint of one on the interior of the other (T junction) is not a proper crossing
  EXPECT_FALSE(segmentsCross({0, 0}, {2, 0}, {1, 0}, {1, 1}));
  EXPECT_FALSE(segmentsCross({1, 0}, {1, 1}, {0, 0}, {2, 0}));
  // collinear overlap counts as crossing (interiors overlap), in both orders and directions
  EXPECT_TRUE(segmentsCross({0, 0}, {2, 0}, {1, 0}, {3, 0}));
  EXPECT_TRUE(segmentsCross({1, 0}, {3, 0}, {2, 0}, {0, 0}));
  EXPECT_TRUE(segmentsCross({0, 0}, {3, 3}, {1, 1}, {2, 2}));
  EXPECT_TRUE(segmentsCross({0, 0}, {3, 3}, {0, 0}, {3, 3}));
  EXPECT_TRUE(segmentsCross({0, 0}, {3, 3}, {0, 0}, {1, 1}));
  // collinear, touching at one endpoint only, or disjoint
  EXPECT_FALSE(segmentsCross({0, 0}, {1, 0}, {1, 0}, {2, 0}));
  EXPECT_FALSE(segmentsCross({0, 0}, {1, 0}, {2, 0}, {3, 0}));
  EXPECT_FALSE(segmentsCross({0, 0}, {1, 0}, {-3, 0}, {-2, 0}));
  // disjoint, parallel, and lines crossing outside the segments
  EXPECT_FALSE(segmentsCross({0, 0}, {1, 0}, {0, 1}, {1, 1}));
  EXPECT_FALSE(segmentsCross({0, 0}, {1, 1}, {3, 0}, {2, 1}));
  EXPECT_FALSE(segmentsCross({0, 0}, {1, 0}, {2, -1}, {2, 1}));
  // nearly touching: the crossing is decided exactly
  const double e = std::ldexp(1.0, -52);
  EXPECT_TRUE(segmentsCross({0, 0}, {1, 1}, {0.5, 0.5 + e}, {1, 0}));
  EXPECT_FALSE(segmentsCross({0, 0}, {1, 1}, {0.5 + e, 0.5}, {1, 0}));
}

// ---------------------------------------------------------------------------------------------
// Constrained triangulation of polygons

TEST(Triangulation, SquareWithSquareHole) {
  CdtCase c;
  c.loops = {rectLoop(0, 0, 4, 4), rectLoop(1, 1.5, 3, 2.5, false)};
  c.area = 16 - 2;
  c.eulerChar = 0;
  checkCdt(c, "square with hole");
}

TEST(Triangulation, CombPolygon) {
  CdtCase c;
  std::vector<Vec2> L{{0, 0}, {10, 0}, {10, 1}};
  for (int i = 4; i >= 0; --i) {  // tooth [2i, 2i+1] x [1, 5]
    L.push_back({2.0 * i + 1, 1});
    L.push_back({2.0 * i + 1, 5});
    L.push_back({2.0 * i, 5});
    if (i > 0) L.push_back({2.0 * i, 1});
  }
  // L: (0,0) (10,0) (10,1) (9,1) (9,5) (8,5) (8,1) (7,1) (7,5) ... (1,1) (1,5) (0,5)
  ASSERT_EQ(L.size(), 22u);
  for (size_t i = 0; i + 1 < L.size(); ++i) ASSERT_GT(norm(L[i + 1] - L[i]), 0.5) << i;
  c.area = 10 * 1 + 5 * 4;
  EXPECT_NEAR(loopArea(L), c.area, 1e-12);
  c.loops = {L};
  c.eulerChar = 1;
  checkCdt(c, "comb");
}

TEST(Triangulation, ThousandPointsOnACircle) {
  CdtCase c;
  c.loops = {circleLoop({0.3, -0.2}, 1.0, 1000)};
  c.area = std::fabs(loopArea(c.loops[0]));
  EXPECT_NEAR(c.area, 500 * std::sin(2 * M_PI / 1000), 1e-12);
  c.eulerChar = 1;
  checkCdt(c, "1000-gon");
}

TEST(Triangulation, NestedLoopsByParity) {
  // outer 64-gon, a square hole, an island (triangle) inside the hole, and a small hole in the
  // island's neighbourhood of the annulus: the domain is the annulus (with one more hole) plus the
  // island, by even-odd parity whatever the loop orientations.
  CdtCase c;
  const auto outer = circleLoop({0, 0}, 10, 64);
  const auto hole = rectLoop(-5, -5, 5, 5, true);  // same orientation as the outer loop
  const std::vector<Vec2> island{{-2, -2}, {3, -1}, {0, 3}};
  const auto hole2 = circleLoop({7.5, 0}, 1, 12, 0.1);
  c.loops = {outer, hole, island, hole2};
  c.area = std::fabs(loopArea(outer)) - 100 + std::fabs(loopArea(island)) - std::fabs(loopArea(hole2));
  c.eulerChar = (1 - 2) + 1;  // annulus with two holes, plus a disc
  checkCdt(c, "nested loops");
}

TEST(Triangulation, LShapeWithCollinearPoints) {
  // L = [0,2]x[0,1] u [0,1]x[1,2] with every edge subdivided at spacing 0.25 (collinear points)
  const std::vector<Vec2> corners{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  std::vector<Vec2> L;
  for (size_t i = 0; i < corners.size(); ++i) {
    const Vec2 a = corners[i], b = corners[(i + 1) % corners.size()];
    const int n = (int)std::lround(norm(b - a) / 0.25);
    for (int k = 0; k < n; ++k) L.push_back(a + (double)k / n * (b - a));
  }
  EXPECT_EQ(L.size(), 32u);
  CdtCase c;
  c.loops = {L};
  c.area = 3;
  c.eulerChar = 1;
  checkCdt(c, "L-shape");
}

TEST(Triangulation, RandomStarPolygons) {
  // star-shaped polygons with random radii: deep non-convex notches
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> R(0.2, 1.0);
  for (int k = 0; k < 20; ++k) {
    const int n = 10 + 17 * k;
    std::vector<Vec2> L;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n, r = R(rng);
      L.push_back({r * std::cos(a), r * std::sin(a)});
    }
    CdtCase c;
    c.loops = {L};
    c.area = loopArea(L);
    ASSERT_GT(c.area, 0);
    c.eulerChar = 1;
    c.delaunay = false;  // see RandomStarPolygonsAreConstrainedDelaunay
    checkCdt(c, "star " + std::to_string(n));
  }
}

/// buildConstrained documents a constrained *Delaunay* triangulation: every unconstrained edge must
/// be locally Delaunay.
TEST(Triangulation, RandomStarPolygonsAreConstrainedDelaunay) {
  {
    CdtCase c;
    c.loops = {{{8, 0}, {6, 10}, {-12, 21}, {-32, 0}, {-20, -35}, {16, -28}}};
    c.area = loopArea(c.loops[0]);
    c.eulerChar = 1;
    checkCdt(c, "hexagon");
  }
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> R(0.2, 1.0);
  for (int k = 0; k < 20; ++k) {
    const int n = 10 + 17 * k;
    std::vector<Vec2> L;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n, r = R(rng);
      L.push_back({r * std::cos(a), r * std::sin(a)});
    }
    CdtCase c;
    c.loops = {L};
    c.area = loopArea(L);
    c.eulerChar = 1;
    checkCdt(c, "star " + std::to_string(n));
  }
}

/// Boundaries of more than 20 000 points are inserted in a biased randomised order (brioOrder),
/// not their own: in their own order a long strip flips across the fan of all earlier points
/// (this test took 11.9 s so, 3.5 s now, checks included). The result is a constrained Delaunay
/// triangulation with every documented property.
TEST(Triangulation, LargeBoundariesInRandomisedOrderAreConstrainedDelaunay) {
  {
    // a long strip 1000 x 1, 15 000 points along each long side, in boundary order
    std::vector<Vec2> L;
    const int m = 15000;
    for (int i = 0; i <= m; ++i) L.push_back({1000.0 * i / m, 0.0});
    for (int i = m; i >= 0; --i) L.push_back({1000.0 * i / m + 0.5 * 1000.0 / m, 1.0});
    CdtCase c;
    c.loops = {L};
    c.area = std::fabs(loopArea(L));
    c.eulerChar = 1;
    checkCdt(c, "strip of 30002 points");
  }
  {
    // a random star of 25 000 points with a square hole
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> R(0.6, 1.0);
    std::vector<Vec2> L;
    const int n = 25000;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n, r = R(rng);
      L.push_back({r * std::cos(a), r * std::sin(a)});
    }
    std::vector<Vec2> hole{{-0.2, -0.2}, {-0.2, 0.2}, {0.2, 0.2}, {0.2, -0.2}};
    CdtCase c;
    c.loops = {L, hole};
    c.area = std::fabs(loopArea(L)) - 0.16;
    c.eulerChar = 0;
    checkCdt(c, "star of 25000 points with a hole");
  }
}

TEST(Triangulation, FailurePaths) {
  {  // a bow-tie: its two diagonals cross
    Triangulation T;
    auto segs = addLoops(T, {{{0, 0}, {1, 1}, {1, 0}, {0, 1}}});
    std::string why;
    EXPECT_FALSE(T.buildConstrained(segs, why));
    EXPECT_FALSE(why.empty());
  }
  {  // two loops crossing each other
    Triangulation T;
    auto segs = addLoops(T, {rectLoop(0, 0, 2, 2), rectLoop(1, 1, 3, 3)});
    std::string why;
    EXPECT_FALSE(T.buildConstrained(segs, why));
    EXPECT_FALSE(why.empty());
  }
  {  // duplicate points
    Triangulation T;
    auto segs = addLoops(T, {{{0, 0}, {1, 0}, {1, 1}, {1, 0}, {0, 1}}});
    std::string why;
    EXPECT_FALSE(T.buildConstrained(segs, why));
    EXPECT_FALSE(why.empty());
  }
  {  // duplicate points in two different loops
    Triangulation T;
    auto segs = addLoops(T, {rectLoop(0, 0, 4, 4), rectLoop(0, 0, 1, 1)});
    std::string why;
    EXPECT_FALSE(T.buildConstrained(segs, why));
    EXPECT_FALSE(why.empty());
  }
  {  // too few points / zero extent
    Triangulation T;
    auto segs = addLoops(T, {{{0, 0}, {1, 0}}});
    std::string why;
    EXPECT_FALSE(T.buildConstrained(segs, why));
    EXPECT_FALSE(why.empty());
    Triangulation U;
    segs = addLoops(U, {{{1, 1}, {1, 1}, {1, 1}}});
    why.clear();
    EXPECT_FALSE(U.buildConstrained(segs, why));
    EXPECT_FALSE(why.empty());
  }
}
