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

using namespace paramesh;

namespace {

inline int nx(int i) { return i == 2 ? 0 : i + 1; }
inline int pv(int i) { return i == 0 ? 2 : i - 1; }

using i128 = __int128;

/// Exact sign of orient2d for points whose coordinates are integers (already scaled).
int exactSign(i128 ax, i128 ay, i128 bx, i128 by, i128 cx, i128 cy) {
  const i128 d = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
  return d > 0 ? 1 : (d < 0 ? -1 : 0);
}

// ---------------------------------------------------------------------------------------------
// Triangulation helpers

using Loops = std::vector<std::vector<Vec2>>;

/// Adds the loops' points as vertices (node = index) and returns the closing segments.
std::vector<std::pair<int, int>> addLoops(Triangulation& T, const Loops& loops) {
  std::vector<std::pair<int, int>> segs;
  for (const auto& L : loops) {
    const int first = (int)T.verts.size();
    for (const Vec2& p : L) {
      TriVertex v;
      v.uv = p;
      v.node = (int)T.verts.size();
      v.flags = VF_BOUNDARY;
      T.addVertex(v);
    }
    const int n = (int)L.size();
    for (int i = 0; i < n; ++i) segs.emplace_back(first + i, first + (i + 1) % n);
  }
  return segs;
}

double loopArea(const std::vector<Vec2>& L) {
  double a = 0;
  for (size_t i = 0, j = L.size() - 1; i < L.size(); j = i++) a += cross(L[j], L[i]);
  return 0.5 * a;
}

bool insideEvenOdd(const Loops& loops, Vec2 p) {
  bool in = false;
  for (const auto& L : loops)
    for (size_t i = 0, j = L.size() - 1; i < L.size(); j = i++) {
      const Vec2 a = L[i], b = L[j];
      if ((a.y > p.y) != (b.y > p.y)) {
        const double x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
        if (p.x < x) in = !in;
      }
    }
  return in;
}

double triArea(const Triangulation& T, int t) {
  const Triangle& tr = T.tris[t];
  return 0.5 * area2(T.verts[tr.v[0]].uv, T.verts[tr.v[1]].uv, T.verts[tr.v[2]].uv);
}

double totalArea(const Triangulation& T) {
  double a = 0;
  for (int t = 0; t < (int)T.tris.size(); ++t)
    if (!T.tris[t].dead) a += triArea(T, t);
  return a;
}

/// Structural validity: live triangles counter-clockwise (exact), distinct vertices, adjacency
/// symmetric across the same two vertices, constraint bits equal on both sides, vertex->triangle
/// references live and incident. Returns the number of violations (each also reported once).
int checkStructure(const Triangulation& T) {
  int bad = 0;
  auto fail = [&](const std::string& what) {
    if (bad++ < 5) ADD_FAILURE() << what;
  };
  for (int t = 0; t < (int)T.tris.size(); ++t) {
    const Triangle& tr = T.tris[t];
    if (tr.dead) continue;
    if (tr.v[0] == tr.v[1] || tr.v[1] == tr.v[2] || tr.v[0] == tr.v[2]) fail("repeated vertex in triangle " + std::to_string(t));
    if (orient2d(T.verts[tr.v[0]].uv, T.verts[tr.v[1]].uv, T.verts[tr.v[2]].uv) <= 0)
      fail("triangle " + std::to_string(t) + " is not counter-clockwise");
    for (int i = 0; i < 3; ++i) {
      const int u = tr.n[i];
      if (u < 0) continue;
      if (u >= (int)T.tris.size() || T.tris[u].dead) {
        fail("triangle " + std::to_string(t) + " has a dead/invalid neighbour");
        continue;
      }
      const int a = tr.v[nx(i)], b = tr.v[pv(i)];
      int j = -1;
      for (int k = 0; k < 3; ++k)
        if (T.tris[u].v[nx(k)] == b && T.tris[u].v[pv(k)] == a) j = k;
      if (j < 0) {
        fail("neighbour " + std::to_string(u) + " of " + std::to_string(t) + " does not share the edge");
        continue;
      }
      if (T.tris[u].n[j] != t) fail("adjacency not symmetric between " + std::to_string(t) + " and " + std::to_string(u));
      if (T.isConstrained(t, i) != T.isConstrained(u, j)) fail("constraint flag differs across an edge");
    }
  }
  for (int v = 0; v < (int)T.verts.size(); ++v) {
    const int t = T.verts[v].tri;
    if (t < 0) continue;
    if (T.tris[t].dead || T.indexOf(t, v) < 0) fail("vertex " + std::to_string(v) + " points to a wrong triangle");
  }
  return bad;
}

/// Undirected edges of the live triangles -> number of uses.
std::map<std::pair<int, int>, int> edgeUses(const Triangulation& T) {
  std::map<std::pair<int, int>, int> e;
  for (const Triangle& tr : T.tris) {
    if (tr.dead) continue;
    for (int i = 0; i < 3; ++i) {
      const int a = tr.v[nx(i)], b = tr.v[pv(i)];
      e[{std::min(a, b), std::max(a, b)}]++;
    }
  }
  return e;
}

/// V - E + F of the live triangles.
int euler(const Triangulation& T) {
  std::set<int> vs;
  int f = 0;
  for (const Triangle& tr : T.tris) {
    if (tr.dead) continue;
    ++f;
    for (int v : tr.v) vs.insert(v);
  }
  return (int)vs.size() - (int)edgeUses(T).size() + f;
}

/// Max over unconstrained interior edges of the incircle value, relative to the 4th power of the
/// quad's size (<= 0 means locally Delaunay).
double maxIncircleViolation(const Triangulation& T) {
  double worst = -1e300;
  for (int t = 0; t < (int)T.tris.size(); ++t) {
    const Triangle& tr = T.tris[t];
    if (tr.dead) continue;
    for (int i = 0; i < 3; ++i) {
      const int u = tr.n[i];
      if (u < 0 || T.isConstrained(t, i)) continue;
      const int j = T.edgeTo(u, t);
      const Vec2 a = T.verts[tr.v[0]].uv, b = T.verts[tr.v[1]].uv, c = T.verts[tr.v[2]].uv;
      const Vec2 d = T.verts[T.tris[u].v[j]].uv;
      double m = 0;
      for (Vec2 p : {b, c, d}) m = std::max(m, norm(p - a));
      worst = std::max(worst, incircle(a, b, c, d) / std::pow(m, 4));
    }
  }
  return worst;
}

struct CdtCase {
  Loops loops;
  double area;       ///< expected area of the even-odd domain
  int eulerChar;     ///< components - holes
  bool delaunay = true;  ///< also check the constrained Delaunay property
};

/// Builds the CDT of the loops and checks every documented property.
void checkCdt(const CdtCase& c, const std::string& name) {
  SCOPED_TRACE(name);
  Triangulation T;
  auto segs = addLoops(T, c.loops);
  const int n = (int)T.verts.size();
  std::vector<Vec2> uv0;
  for (auto& v : T.verts) uv0.push_back(v.uv);
  std::string why;
  ASSERT_TRUE(T.buildConstrained(segs, why)) << why;
  // the input vertices keep their indices and positions; the auxiliary vertices are gone
  ASSERT_EQ((int)T.verts.size(), n);
  for (int v = 0; v < n; ++v) {
    EXPECT_EQ(T.verts[v].uv.x, uv0[v].x);
    EXPECT_EQ(T.verts[v].uv.y, uv0[v].y);
    EXPECT_FALSE(T.verts[v].flags & VF_SUPER);
    EXPECT_GE(T.verts[v].tri, 0) << "vertex " << v << " unused";
  }
  EXPECT_EQ(checkStructure(T), 0);
  // every segment is an edge, constrained; every constrained or boundary edge is a segment
  std::set<std::pair<int, int>> segSet;
  for (auto [a, b] : segs) segSet.insert({std::min(a, b), std::max(a, b)});
  std::set<std::pair<int, int>> found;
  for (int t = 0; t < (int)T.tris.size(); ++t) {
    const Triangle& tr = T.tris[t];
    EXPECT_FALSE(tr.dead);
    for (int i = 0; i < 3; ++i) {
      const int a = tr.v[nx(i)], b = tr.v[pv(i)];
      const std::pair<int, int> k{std::min(a, b), std::max(a, b)};
      const bool isSeg = segSet.count(k) > 0;
      if (isSeg) {
        found.insert(k);
        EXPECT_TRUE(T.isConstrained(t, i)) << "segment " << a << "-" << b << " not constrained";
      } else {
        EXPECT_FALSE(T.isConstrained(t, i)) << "edge " << a << "-" << b << " constrained but not a segment";
        EXPECT_GE(tr.n[i], 0) << "domain boundary edge " << a << "-" << b << " is not a segment";
      }
    }
  }
  EXPECT_EQ(found.size(), segSet.size()) << "missing segments";
  // triangles inside the domain, total area
  int outside = 0;
  for (int t = 0; t < (int)T.tris.size(); ++t) {
    const Triangle& tr = T.tris[t];
    const Vec2 g = (1.0 / 3.0) * (T.verts[tr.v[0]].uv + T.verts[tr.v[1]].uv + T.verts[tr.v[2]].uv);
    if (!insideEvenOdd(c.loops, g)) ++outside;
  }
  EXPECT_EQ(outside, 0);
  EXPECT_NEAR(totalArea(T), c.area, 1e-12 * c.area);
  EXPECT_EQ(euler(T), c.eulerChar);
  // no edge used more than twice (manifold)
  for (auto& kv : edgeUses(T)) EXPECT_LE(kv.second, 2);
  // constrained Delaunay: every unconstrained edge is locally Delaunay
  if (c.delaunay) {
    EXPECT_LE(maxIncircleViolation(T), 1e-12);
  }
}

std::vector<Vec2> rectLoop(double x0, double y0, double x1, double y1, bool ccw = true) {
  std::vector<Vec2> L{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  if (!ccw) std::reverse(L.begin(), L.end());
  return L;
}

std::vector<Vec2> circleLoop(Vec2 c, double r, int n, double phase = 0) {
  std::vector<Vec2> L;
  for (int i = 0; i < n; ++i) {
    const double a = phase + 2 * M_PI * i / n;
    L.push_back({c.x + r * std::cos(a), c.y + r * std::sin(a)});
  }
  return L;
}

}  // namespace

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

// ---------------------------------------------------------------------------------------------
// Incremental insertion, flips, rings

namespace {

/// Unit square CDT, then `pts` inserted with the Delaunay flip test.
void insertPoints(Triangulation& T, const std::vector<Vec2>& pts) {
  auto segs = addLoops(T, {rectLoop(0, 0, 1, 1)});
  std::string why;
  ASSERT_TRUE(T.buildConstrained(segs, why)) << why;
  const Triangulation::FlipTest dt = [&T](int t, int i) { return T.delaunayFlip(t, i); };
  int last = 0;
  for (const Vec2& p : pts) {
    int e = -1;
    const int t = T.locate(p, last, &e);
    ASSERT_GE(t, 0) << "locate failed for (" << p.x << "," << p.y << ")";
    // the located triangle contains p (on its edge e when e >= 0)
    const Triangle& tr = T.tris[t];
    for (int i = 0; i < 3; ++i) {
      const int o = orient2d(T.verts[tr.v[nx(i)]].uv, T.verts[tr.v[pv(i)]].uv, p);
      ASSERT_GE(o, 0);
      if (i == e) {
        ASSERT_EQ(o, 0);
      }
    }
    TriVertex v;
    v.uv = p;
    const int id = T.addVertex(v);
    std::vector<int> touched;
    T.insert(id, t, e, dt, &touched);
    ASSERT_FALSE(touched.empty());
    ASSERT_GE(T.verts[id].tri, 0);
    ASSERT_GE(T.indexOf(T.verts[id].tri, id), 0);
    last = T.verts[id].tri;
  }
}

}  // namespace

TEST(Triangulation, RandomInsertionIsDelaunay) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> U(0.001, 0.999);
  std::vector<Vec2> pts;
  for (int i = 0; i < 3000; ++i) pts.push_back({U(rng), U(rng)});
  Triangulation T;
  insertPoints(T, pts);
  EXPECT_EQ(checkStructure(T), 0);
  EXPECT_NEAR(totalArea(T), 1.0, 1e-12);
  EXPECT_EQ(euler(T), 1);
  int live = 0;
  for (auto& tr : T.tris) live += tr.dead ? 0 : 1;
  // a triangulation of n points with h on the convex hull has 2n - h - 2 triangles
  EXPECT_EQ(live, 2 * 3004 - 4 - 2);
  EXPECT_LE(maxIncircleViolation(T), 1e-12);
  // the four hull edges stay constrained
  int cons = 0;
  for (int t = 0; t < (int)T.tris.size(); ++t)
    for (int i = 0; i < 3; ++i)
      if (T.isConstrained(t, i)) {
        ++cons;
        EXPECT_LT(T.tris[t].n[i], 0);
      }
  EXPECT_EQ(cons, 4);
}

TEST(Triangulation, GridInsertionOnEdgesIsDelaunay) {
  // points of an 11x11 grid in random order: many land exactly on existing edges (cocircular,
  // collinear), including on the constrained boundary of the square
  std::vector<Vec2> pts;
  for (int i = 0; i <= 10; ++i)
    for (int j = 0; j <= 10; ++j) {
      if ((i == 0 || i == 10) && (j == 0 || j == 10)) continue;  // the corners exist already
      pts.push_back({i / 10.0, j / 10.0});
    }
  std::mt19937 rng(7);
  std::shuffle(pts.begin(), pts.end(), rng);
  Triangulation T;
  insertPoints(T, pts);
  EXPECT_EQ(checkStructure(T), 0);
  EXPECT_NEAR(totalArea(T), 1.0, 1e-12);
  EXPECT_EQ(euler(T), 1);
  int live = 0;
  for (auto& tr : T.tris) live += tr.dead ? 0 : 1;
  EXPECT_EQ(live, 200);  // 2 * 10 * 10 cells
  EXPECT_LE(maxIncircleViolation(T), 1e-12);
  // the boundary of the square is split into 40 constrained edges without neighbours
  int cons = 0;
  for (int t = 0; t < (int)T.tris.size(); ++t)
    for (int i = 0; i < 3; ++i)
      if (T.isConstrained(t, i)) {
        ++cons;
        EXPECT_LT(T.tris[t].n[i], 0);
      }
  EXPECT_EQ(cons, 40);
}

TEST(Triangulation, FlipAndFlipBack) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0.01, 0.99);
  std::vector<Vec2> pts;
  for (int i = 0; i < 200; ++i) pts.push_back({U(rng), U(rng)});
  Triangulation T;
  insertPoints(T, pts);
  int flipped = 0, refused = 0;
  for (int t = 0; t < (int)T.tris.size(); ++t) {
    for (int i = 0; i < 3; ++i) {
      const Triangle before = T.tris[t];
      const int u = before.n[i];
      if (u < 0) {
        EXPECT_FALSE(T.flip(t, i));
        continue;
      }
      const int a = before.v[i], b = before.v[nx(i)], c = before.v[pv(i)];
      const int d = T.tris[u].v[T.edgeTo(u, t)];
      const bool convex = orient2d(T.verts[a].uv, T.verts[b].uv, T.verts[d].uv) > 0 &&
                          orient2d(T.verts[a].uv, T.verts[d].uv, T.verts[c].uv) > 0;
      EXPECT_EQ(T.flipIsValid(t, i), convex);
      const double area0 = triArea(T, t) + triArea(T, u);
      if (!T.flip(t, i)) {
        EXPECT_FALSE(convex);
        ++refused;
        for (int k = 0; k < 3; ++k) EXPECT_EQ(T.tris[t].v[k], before.v[k]);
        continue;
      }
      ++flipped;
      // the new diagonal is a-d: t and u now both contain a and d, not both b and c
      EXPECT_GE(T.indexOf(t, a), 0);
      EXPECT_GE(T.indexOf(t, d), 0);
      EXPECT_GE(T.indexOf(u, a), 0);
      EXPECT_GE(T.indexOf(u, d), 0);
      EXPECT_NEAR(triArea(T, t) + triArea(T, u), area0, 1e-15);
      ASSERT_EQ(checkStructure(T), 0) << "after flipping " << t << ":" << i;
      // flip back across the same diagonal
      const int e = T.edgeTo(t, u);
      ASSERT_GE(e, 0);
      ASSERT_TRUE(T.flip(t, e));
      EXPECT_EQ(checkStructure(T), 0);
      std::set<int> vt(T.tris[t].v, T.tris[t].v + 3), vu(T.tris[u].v, T.tris[u].v + 3);
      EXPECT_TRUE((vt.count(b) && vt.count(c)) && (vu.count(b) && vu.count(c)));
      break;  // t changed numbering: move on
    }
  }
  EXPECT_GT(flipped, 100);
  // after flip/flip-back the triangulation is Delaunay again (each flip back restored the pair)
  EXPECT_LE(maxIncircleViolation(T), 1e-12);
  EXPECT_NEAR(totalArea(T), 1.0, 1e-12);
  (void)refused;
}

TEST(Triangulation, InsertionValidityAndClearance) {
  // For random points inside and on edges of a Delaunay triangulation: insertionIsValid agrees
  // with inserting (every new triangle counter-clockwise); at a vertex, or on an edge other than
  // the one named, it is false. insertionClearance is the distance to the nearest split corner.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(0.05, 0.95), W(0.05, 0.95);
  std::vector<Vec2> pts;
  for (int i = 0; i < 60; ++i) pts.push_back({U(rng), U(rng)});
  Triangulation T;
  insertPoints(T, pts);
  for (TriVertex& v : T.verts) v.xyz = {v.uv.x, v.uv.y, 0.0};
  int checked = 0, onEdge = 0, offEdge = 0;
  for (int t = 0; t < (int)T.tris.size(); ++t) {
    const Triangle& tr = T.tris[t];
    if (tr.dead) continue;
    const Vec2 &a = T.verts[tr.v[0]].uv, &b = T.verts[tr.v[1]].uv, &c = T.verts[tr.v[2]].uv;
    if (orient2d(a, b, c) <= 0) continue;
    // inside: valid; clearance = nearest of the three corners
    const double w0 = W(rng), w1 = W(rng) * (1 - w0);
    const Vec2 p = a + w1 * (b - a) + (1 - w0 - w1) * (c - a);
    if (orient2d(a, b, p) > 0 && orient2d(b, c, p) > 0 && orient2d(c, a, p) > 0) {
      EXPECT_TRUE(T.insertionIsValid(p, t, -1));
      const Vec3 x{p.x, p.y, 0.0};
      EXPECT_NEAR(T.insertionClearance(x, t, -1),
                  std::min({norm(p - a), norm(p - b), norm(p - c)}), 1e-15);
      ++checked;
    }
    // at a corner: never valid, inside or on either edge through it
    for (int k = 0; k < 3; ++k) {
      const Vec2 q = T.verts[tr.v[k]].uv;
      EXPECT_FALSE(T.insertionIsValid(q, t, -1));
      EXPECT_FALSE(T.insertionIsValid(q, t, nx(k)));
      EXPECT_FALSE(T.insertionIsValid(q, t, pv(k)));
      EXPECT_EQ(T.insertionClearance({q.x, q.y, 0.0}, t, -1), 0.0);
    }
    // the midpoint of edge 0 (b-c), rounded: exactly on the edge or just off it (the case that
    // stacked coincident nodes on propeller_and_shaft). As an interior point it is valid only
    // when strictly inside; on the edge when the four new triangles are counter-clockwise.
    const Vec2 m = 0.5 * (b + c);
    EXPECT_EQ(T.insertionIsValid(m, t, -1), orient2d(a, b, m) > 0 && orient2d(b, c, m) > 0 && orient2d(c, a, m) > 0);
    ++(orient2d(b, c, m) == 0 ? onEdge : offEdge);
    if (orient2d(b, c, m) == 0) {
      EXPECT_FALSE(T.insertionIsValid(m, t, 1));
    }
    const int u = tr.n[0];
    if (u >= 0 && orient2d(b, c, m) == 0 && orient2d(a, b, m) > 0 && orient2d(c, a, m) > 0) {
      const Vec2& d = T.verts[T.tris[u].v[T.edgeTo(u, t)]].uv;
      EXPECT_EQ(T.insertionIsValid(m, t, 0), orient2d(d, c, m) > 0 && orient2d(d, m, b) > 0);
      EXPECT_NEAR(T.insertionClearance({m.x, m.y, 0.0}, t, 0),
                  std::min({norm(m - a), norm(m - b), norm(m - c), norm(m - d)}), 1e-15);
    }
  }
  EXPECT_GT(checked, 50);
  EXPECT_GT(onEdge, 10);
  EXPECT_GT(offEdge, 10);
}

TEST(Triangulation, RingsAreCounterClockwise) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> U(0.02, 0.98);
  std::vector<Vec2> pts;
  for (int i = 0; i < 300; ++i) pts.push_back({U(rng), U(rng)});
  pts.push_back({0.5, 0.0});  // on the boundary
  pts.push_back({1.0, 0.25});
  Triangulation T;
  insertPoints(T, pts);
  ASSERT_EQ(checkStructure(T), 0);
  std::vector<std::vector<int>> incident(T.verts.size());
  for (int t = 0; t < (int)T.tris.size(); ++t)
    if (!T.tris[t].dead)
      for (int v : T.tris[t].v) incident[v].push_back(t);
  int interior = 0, boundary = 0;
  for (int v = 0; v < (int)T.verts.size(); ++v) {
    std::vector<int> ring;
    bool closed = true;
    T.ring(v, ring, &closed);
    const Vec2 p = T.verts[v].uv;
    const bool onBoundary = p.x == 0 || p.x == 1 || p.y == 0 || p.y == 1;
    EXPECT_EQ(closed, !onBoundary) << "vertex " << v;
    (onBoundary ? boundary : interior)++;
    // the ring is exactly the set of incident triangles
    std::vector<int> a = ring, b = incident[v];
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    EXPECT_EQ(a, b) << "vertex " << v;
    // consecutive triangles share the edge (v, y) -> (v, x): counter-clockwise order
    double angle = 0;
    for (size_t k = 0; k < ring.size(); ++k) {
      const Triangle& t = T.tris[ring[k]];
      const int i = T.indexOf(ring[k], v);
      const Vec2 x = T.verts[t.v[nx(i)]].uv, y = T.verts[t.v[pv(i)]].uv;
      angle += std::atan2(cross(x - p, y - p), dot(x - p, y - p));
      if (k + 1 < ring.size() || closed) {
        const Triangle& s = T.tris[ring[(k + 1) % ring.size()]];
        const int j = T.indexOf(ring[(k + 1) % ring.size()], v);
        EXPECT_EQ(s.v[nx(j)], t.v[pv(i)]) << "vertex " << v << " ring position " << k;
      }
    }
    if (!onBoundary) {
      EXPECT_NEAR(angle, 2 * M_PI, 1e-9);
    } else {
      // a boundary ring starts and ends at a boundary edge; corners span pi/2, sides pi
      const Triangle& f = T.tris[ring.front()];
      EXPECT_LT(f.n[pv(T.indexOf(ring.front(), v))], 0);
      const Triangle& l = T.tris[ring.back()];
      EXPECT_LT(l.n[nx(T.indexOf(ring.back(), v))], 0);
      const bool corner = (p.x == 0 || p.x == 1) && (p.y == 0 || p.y == 1);
      EXPECT_NEAR(angle, corner ? 0.5 * M_PI : M_PI, 1e-9);
    }
  }
  EXPECT_EQ(boundary, 6);
  EXPECT_EQ(interior, 300);
}

TEST(Triangulation, CompactDropsDeadTriangles) {
  std::vector<Vec2> pts{{0.3, 0.3}, {0.7, 0.4}, {0.5, 0.8}};
  Triangulation T;
  insertPoints(T, pts);
  const size_t n = T.tris.size();
  // kill one triangle (as a collapse would) after detaching it from its neighbours
  int victim = -1;
  for (int t = 0; t < (int)n && victim < 0; ++t)
    if (!T.tris[t].dead) victim = t;
  const double area = totalArea(T) - triArea(T, victim);
  for (int i = 0; i < 3; ++i) {
    const int u = T.tris[victim].n[i];
    if (u >= 0) T.tris[u].n[T.edgeTo(u, victim)] = -1;
  }
  T.tris[victim].dead = true;
  auto vmap = T.compact();
  EXPECT_EQ(T.tris.size(), n - 1);
  EXPECT_EQ(vmap.size(), 7u);
  EXPECT_EQ(checkStructure(T), 0);
  EXPECT_NEAR(totalArea(T), area, 1e-15);
}

// A face with a notch cut in from its top edge down to the middle of its height (ANC101's Face41:
// [0, 39.2] x [-10, 0] less [9.48, 28.3] x [-5, 0], its boundary sampled at uneven points). With
// an odd number of cell rows, the row through the middle of the box has its centre line on the
// notch's bottom segment: the guard's reference points lay on the boundary, and a band above the
// notch's bottom read as inside, the band below as outside. Every box proportion and sampling
// here, against the plain even-odd rule.
TEST(DomainGuard, NotchBottomOnACellRowCentre) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(0, 1);
  int checked = 0, wrong = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const double W = 10 + 40 * U(rng), H = 2 + 10 * U(rng), y0 = -H, ym = -H / 2;
    const double a = W * (0.1 + 0.3 * U(rng)), b = W * (0.6 + 0.3 * U(rng));
    const int k = 1 + trial % 17;  // points per side: the grid's rows and columns vary
    std::vector<Vec2> L;
    auto side = [&](Vec2 p, Vec2 q) {
      for (int i = 0; i < k; ++i) L.push_back(p + ((double)i / k) * (q - p));
    };
    side({0, 0}, {a, 0});
    side({a, 0}, {a, ym});
    side({a, ym}, {b, ym});
    side({b, ym}, {b, 0});
    side({b, 0}, {W, 0});
    side({W, 0}, {W, y0});
    side({W, y0}, {0, y0});
    side({0, y0}, {0, 0});
    DomainGuard g({L});
    for (int q = 0; q < 200; ++q) {
      const double x = W * U(rng);
      const double y = q % 2 ? ym + (U(rng) - 0.5) * 2e-3 * H : y0 + H * U(rng);  // half of them by the notch's bottom
      if (std::fabs(y - ym) < 1e-9 * H || std::fabs(y) < 1e-9 || std::fabs(y - y0) < 1e-9) continue;
      if (std::fabs(x - a) < 1e-9 * W || std::fabs(x - b) < 1e-9 * W || x <= 0 || x >= W) continue;
      const bool expect = y < ym || x < a || x > b;
      ++checked;
      if (g.inside({x, y}) != expect) ++wrong;
    }
  }
  EXPECT_GT(checked, 50000);
  EXPECT_EQ(wrong, 0);
}
