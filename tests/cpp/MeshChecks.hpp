// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshChecks.hpp
/// Measured properties of a SurfaceMesh against its geometry model, shared by the end-to-end tests.
#pragma once
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "paramesh/geom/Geometry.hpp"
#include "paramesh/mesh/SurfaceMesh.hpp"

namespace paramesh::test {

struct MeshStats {
  int unusedNodes = 0, duplicateNodes = 0;
  int boundaryEdges = 0, nonManifoldEdges = 0;
  int inconsistentEdges = 0;   ///< interior edges used twice in the same direction
  int flipped = 0;             ///< triangles facing against the CAD normal
  double nodeDevMax = 0;       ///< max |S(uv)-x| (face nodes) / |C(t)-x| (edge nodes)
  double gammaMean = 0, gammaMin = 1, angleMin = 180, pctAngleBelow30 = 0;
  double pctLenInSqrt2 = 0;    ///< against the uniform size h
  int triangles = 0;
};

inline double triGamma(Vec3 a, Vec3 b, Vec3 c) {
  const double la = dist(b, c), lb = dist(c, a), lc = dist(a, b);
  const double ar2 = norm(cross(b - a, c - a));
  const double s = la + lb + lc;
  return s * la * lb * lc > 0 ? 4 * ar2 * ar2 / (s * la * lb * lc) : 0;
}

inline MeshStats measure(const SurfaceMesh& m, const IGeometryModel& g, double h) {
  MeshStats st;
  const size_t nn = m.nodes.size();
  std::vector<int> used(nn, 0);
  for (auto& t : m.triangles)
    for (int v : t) used[v] = 1;
  for (auto& q : m.quads)
    for (int v : q) used[v] = 1;
  for (int u : used) st.unusedNodes += u ? 0 : 1;
  {
    const double tol = 1e-9 * g.boundingBox().diagonal();
    std::set<std::tuple<long long, long long, long long>> keys;
    for (size_t i = 0; i < nn; ++i) {
      auto k = std::make_tuple(std::llround(m.nodes[i].x / tol), std::llround(m.nodes[i].y / tol),
                               std::llround(m.nodes[i].z / tol));
      if (!keys.insert(k).second) ++st.duplicateNodes;
    }
  }
  std::map<std::pair<int, int>, std::pair<int, int>> e;  // undirected -> (count, signed direction sum)
  auto addEdge = [&](int a, int b) {
    auto k = std::make_pair(std::min(a, b), std::max(a, b));
    auto& v = e[k];
    v.first++;
    v.second += a < b ? 1 : -1;
  };
  for (auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) addEdge(t[k], t[(k + 1) % 3]);
  for (auto& q : m.quads)
    for (int k = 0; k < 4; ++k) addEdge(q[k], q[(k + 1) % 4]);
  size_t ok = 0;
  for (auto& kv : e) {
    if (kv.second.first == 1) ++st.boundaryEdges;
    if (kv.second.first > 2) ++st.nonManifoldEdges;
    if (kv.second.first == 2 && kv.second.second != 0) ++st.inconsistentEdges;
    const double r = dist(m.nodes[kv.first.first], m.nodes[kv.first.second]) / h;
    if (r >= 1 / std::sqrt(2.0) && r <= std::sqrt(2.0)) ++ok;
  }
  st.pctLenInSqrt2 = e.empty() ? 0 : 100.0 * ok / e.size();
  // nodes on the CAD
  std::vector<std::unique_ptr<ISurface>> surf(g.numFaces());
  std::vector<std::unique_ptr<ICurve>> curv(g.numEdges());
  for (size_t i = 0; i < nn; ++i) {
    const int ent = m.nodeEntity[i] - 1;
    double d = 0;
    if (m.nodeKind[i] == NodeKind::Face) {
      if (!surf[ent]) surf[ent] = g.makeSurface(ent);
      d = dist(surf[ent]->eval(m.nodeParam[i]), m.nodes[i]);
    } else if (m.nodeKind[i] == NodeKind::Edge) {
      if (!curv[ent]) curv[ent] = g.makeCurve(ent);
      d = dist(curv[ent]->eval(m.nodeParam[i].x), m.nodes[i]);
    } else {
      d = dist(g.vertexPoint(ent), m.nodes[i]);
    }
    st.nodeDevMax = std::max(st.nodeDevMax, d / h);
  }
  // orientation against the CAD normal, sampled at a face node of each triangle (or its centroid)
  double gsum = 0;
  int below30 = 0;
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& T = m.triangles[t];
    const Vec3 a = m.nodes[T[0]], b = m.nodes[T[1]], c = m.nodes[T[2]];
    const double gm = triGamma(a, b, c);
    gsum += gm;
    st.gammaMin = std::min(st.gammaMin, gm);
    const double la = dist(b, c), lb = dist(c, a), lc = dist(a, b);
    auto ang = [](double x, double y, double z) {
      return std::acos(std::clamp((y * y + z * z - x * x) / (2 * y * z), -1.0, 1.0)) * 180 / M_PI;
    };
    const double mn = std::min({ang(la, lb, lc), ang(lb, lc, la), ang(lc, la, lb)});
    st.angleMin = std::min(st.angleMin, mn);
    if (mn < 30) ++below30;
    const int f = m.triangleFace[t] - 1;
    if (!surf[f]) surf[f] = g.makeSurface(f);
    Vec2 uv;
    bool have = false;
    for (int v : T)
      if (m.nodeKind[v] == NodeKind::Face && m.nodeEntity[v] == f + 1) {
        uv = m.nodeParam[v];
        have = true;
        break;
      }
    if (!have) {
      // no face node: project the centroid; from a coarse global start Newton can stop at a
      // local minimum on the domain's edge (the bottle's thread flank, whose normal turns over
      // at its end), so check the foot and search densely when it is off
      const Vec3 cen = (a + b + c) * (1.0 / 3);
      const double lmax = std::max({dist(a, b), dist(b, c), dist(c, a)});
      Vec3 foot;
      if (!surf[f]->projectGlobal(cen, uv, &foot) || dist(foot, cen) > 0.05 * lmax) {
        const UVBox bx = surf[f]->bounds();
        double best = 1e300;
        const int n = 400;
        for (int i = 0; i <= n; ++i)
          for (int j = 0; j <= n; ++j) {
            const Vec2 q{bx.u0 + (bx.u1 - bx.u0) * i / n, bx.v0 + (bx.v1 - bx.v0) * j / n};
            const double dd = dist(surf[f]->eval(q), cen);
            if (dd < best) {
              best = dd;
              uv = q;
            }
          }
        if (!surf[f]->project(cen, uv, &foot) || dist(foot, cen) > 0.5 * lmax) continue;
      }
    }
    Vec3 n;
    if (!surf[f]->normal(uv, n)) continue;
    if (g.faceReversed(f)) n = -n;
    if (dot(n, cross(b - a, c - a)) <= 0) ++st.flipped;
  }
  st.triangles = (int)m.triangles.size();
  st.gammaMean = m.triangles.empty() ? 0 : gsum / m.triangles.size();
  st.pctAngleBelow30 = m.triangles.empty() ? 0 : 100.0 * below30 / m.triangles.size();
  return st;
}

}  // namespace paramesh::test
