// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file triangulation_fixtures.hpp
/// Helpers shared by the triangulation tests (test_triangulation.cpp, test_insertion.cpp): exact
/// orientation, loop areas and parity, structural validity, Euler characteristic, incircle
/// violations, and the constrained Delaunay checks of a polygon case.
#pragma once
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

namespace paramesh::test {


inline int nx(int i) { return i == 2 ? 0 : i + 1; }
inline int pv(int i) { return i == 0 ? 2 : i - 1; }

using i128 = __int128;

/// Exact sign of orient2d for points whose coordinates are integers (already scaled).
inline int exactSign(i128 ax, i128 ay, i128 bx, i128 by, i128 cx, i128 cy) {
  const i128 d = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
  return d > 0 ? 1 : (d < 0 ? -1 : 0);
}

// ---------------------------------------------------------------------------------------------
// Triangulation helpers

using Loops = std::vector<std::vector<Vec2>>;

/// Adds the loops' points as vertices (node = index) and returns the closing segments.
inline std::vector<std::pair<int, int>> addLoops(Triangulation& T, const Loops& loops) {
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

inline double loopArea(const std::vector<Vec2>& L) {
  double a = 0;
  for (size_t i = 0, j = L.size() - 1; i < L.size(); j = i++) a += cross(L[j], L[i]);
  return 0.5 * a;
}

inline bool insideEvenOdd(const Loops& loops, Vec2 p) {
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

inline double triArea(const Triangulation& T, int t) {
  const Triangle& tr = T.tris[t];
  return 0.5 * area2(T.verts[tr.v[0]].uv, T.verts[tr.v[1]].uv, T.verts[tr.v[2]].uv);
}

inline double totalArea(const Triangulation& T) {
  double a = 0;
  for (int t = 0; t < (int)T.tris.size(); ++t)
    if (!T.tris[t].dead) a += triArea(T, t);
  return a;
}

/// Structural validity: live triangles counter-clockwise (exact), distinct vertices, adjacency
/// symmetric across the same two vertices, constraint bits equal on both sides, vertex->triangle
/// references live and incident. Returns the number of violations (each also reported once).
inline int checkStructure(const Triangulation& T) {
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
inline std::map<std::pair<int, int>, int> edgeUses(const Triangulation& T) {
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
inline int euler(const Triangulation& T) {
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
inline double maxIncircleViolation(const Triangulation& T) {
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
inline void checkCdt(const CdtCase& c, const std::string& name) {
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

inline std::vector<Vec2> rectLoop(double x0, double y0, double x1, double y1, bool ccw = true) {
  std::vector<Vec2> L{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  if (!ccw) std::reverse(L.begin(), L.end());
  return L;
}

inline std::vector<Vec2> circleLoop(Vec2 c, double r, int n, double phase = 0) {
  std::vector<Vec2> L;
  for (int i = 0; i < n; ++i) {
    const double a = phase + 2 * M_PI * i / n;
    L.push_back({c.x + r * std::cos(a), c.y + r * std::sin(a)});
  }
  return L;
}

}  // namespace paramesh::test
