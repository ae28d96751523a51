// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file test_insertion.cpp
/// Tests of incremental Delaunay insertion with flips, flip and flip back, insertion validity and
/// clearance, vertex rings, compaction, and the domain guard's point-in-face test.
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
