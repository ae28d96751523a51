// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/size/Proximity.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

namespace paramesh {

namespace {

/// Closest point to p on segment [a,b].
Vec3 closestOnSegment(Vec3 p, Vec3 a, Vec3 b) {
  const Vec3 d = b - a;
  const double l2 = norm2(d);
  if (!(l2 > 0)) return a;
  const double t = std::clamp(dot(p - a, d) / l2, 0.0, 1.0);
  return a + t * d;
}

/// Closest point to p on triangle (a,b,c).
Vec3 closestOnTriangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double den = 1.0 / (va + vb + vc);
  return a + (vb * den) * ab + (vc * den) * ac;
}

/// Uniform hash grid of boxes (triangles or segments) for radius queries.
class Grid {
 public:
  explicit Grid(double cell) : cell_(cell) {}
  void add(int id, Vec3 lo, Vec3 hi) {
    const auto a = key(lo), b = key(hi);
    for (long i = a[0]; i <= b[0]; ++i)
      for (long j = a[1]; j <= b[1]; ++j)
        for (long k = a[2]; k <= b[2]; ++k) cells_[pack(i, j, k)].push_back(id);
  }
  template <class F>
  void query(Vec3 p, double r, F&& f) const {
    const auto a = key(p - Vec3{r, r, r}), b = key(p + Vec3{r, r, r});
    for (long i = a[0]; i <= b[0]; ++i)
      for (long j = a[1]; j <= b[1]; ++j)
        for (long k = a[2]; k <= b[2]; ++k) {
          auto it = cells_.find(pack(i, j, k));
          if (it == cells_.end()) continue;
          for (int id : it->second) f(id);
        }
  }

 private:
  std::array<long, 3> key(Vec3 p) const {
    return {(long)std::floor(p.x / cell_), (long)std::floor(p.y / cell_), (long)std::floor(p.z / cell_)};
  }
  static uint64_t pack(long i, long j, long k) {
    return ((uint64_t)(i & 0x1FFFFF) << 42) | ((uint64_t)(j & 0x1FFFFF) << 21) | (uint64_t)(k & 0x1FFFFF);
  }
  double cell_;
  std::unordered_map<uint64_t, std::vector<int>> cells_;
};

}  // namespace

std::vector<SizeSource> proximitySources(const SurfaceMesh& m, int n, double hmax, double hmin) {
  std::vector<SizeSource> out;
  // the target keeps a margin: mesh edges range up to ~1.3x their target
  const double across = 1.25 * n;
  if (n <= 0 || m.triangles.empty()) return out;
  const double reach = n * hmax;  // gaps wider than this need no refinement
  const size_t nt = m.triangles.size();
  // triangle normals (outward, as the mesh is oriented) and node normals per face
  std::vector<Vec3> tn(nt);
  for (size_t t = 0; t < nt; ++t) {
    const auto& T = m.triangles[t];
    tn[t] = normalized(cross(m.nodes[T[1]] - m.nodes[T[0]], m.nodes[T[2]] - m.nodes[T[0]]));
  }
  // 1) facing surfaces: from each triangle centroid, the nearest triangle of another face whose
  //    normal is opposite and which lies behind (inside the wall)
  Grid grid(std::max(reach, 1e-12));
  for (size_t t = 0; t < nt; ++t) {
    const auto& T = m.triangles[t];
    Box3 b;
    for (int v : T) b.add(m.nodes[v]);
    grid.add((int)t, b.lo, b.hi);
  }
  for (size_t t = 0; t < nt; ++t) {
    const auto& T = m.triangles[t];
    const Vec3 c = (1.0 / 3) * (m.nodes[T[0]] + m.nodes[T[1]] + m.nodes[T[2]]);
    double best = reach;
    grid.query(c, reach, [&](int u) {
      if (m.triangleFace[u] == m.triangleFace[t]) return;
      if (dot(tn[u], tn[t]) > -0.5) return;  // not facing
      const auto& U = m.triangles[u];
      const Vec3 q = closestOnTriangle(c, m.nodes[U[0]], m.nodes[U[1]], m.nodes[U[2]]);
      const Vec3 d = q - c;
      const double l = norm(d);
      if (!(l > 0) || l >= best) return;
      if (dot(d, tn[t]) > -0.5 * l) return;  // the other surface must be behind, across the wall
      best = l;
    });
    if (best < reach) out.push_back({c, std::max(best / across, hmin)});
  }
  // 2) narrow faces: across each face, between parts of its boundary that face each other. The
  //    boundary is oriented by its triangles (face interior on the left), so a chord counts only
  //    when it leaves the boundary into the face and arrives at the other side from inside (a hole
  //    or a notch across empty space is not a narrow face).
  struct Seg {
    int a, b;  // oriented a -> b, face interior on the left
    Vec3 in;   // unit inward direction (in the face's tangent plane)
  };
  std::map<int, std::vector<Seg>> boundary;  // face -> boundary segments
  {
    std::map<std::tuple<int, int, int>, std::pair<int, int>> uses;  // (face,min,max) -> (count, triangle*3+k)
    for (size_t t = 0; t < nt; ++t) {
      const auto& T = m.triangles[t];
      for (int k = 0; k < 3; ++k) {
        const int a = T[k], b = T[(k + 1) % 3];
        auto& u = uses[{m.triangleFace[t], std::min(a, b), std::max(a, b)}];
        ++u.first;
        u.second = (int)t * 3 + k;
      }
    }
    for (const auto& kv : uses) {
      if (kv.second.first != 1) continue;
      const int t = kv.second.second / 3, k = kv.second.second % 3;
      const auto& T = m.triangles[t];
      const int a = T[k], b = T[(k + 1) % 3];
      boundary[std::get<0>(kv.first)].push_back({a, b, normalized(cross(tn[t], m.nodes[b] - m.nodes[a]))});
    }
  }
  for (const auto& fb : boundary) {
    const auto& segs = fb.second;
    std::unordered_map<int, std::vector<int>> nodeSegs;
    for (size_t s = 0; s < segs.size(); ++s) {
      nodeSegs[segs[s].a].push_back((int)s);
      nodeSegs[segs[s].b].push_back((int)s);
    }
    Grid sg(std::max(reach, 1e-12));
    for (size_t s = 0; s < segs.size(); ++s) {
      Box3 b;
      b.add(m.nodes[segs[s].a]);
      b.add(m.nodes[segs[s].b]);
      sg.add((int)s, b.lo, b.hi);
    }
    for (const auto& ns : nodeSegs) {
      const int v = ns.first;
      const Vec3 p = m.nodes[v];
      Vec3 in{0, 0, 0};
      for (int s : ns.second) in += segs[s].in;
      if (!(norm(in) > 1e-9)) continue;  // a cusp: no inward direction
      in = normalized(in);
      double best = reach;
      Vec3 bestQ = p;
      sg.query(p, reach, [&](int s) {
        if (segs[s].a == v || segs[s].b == v) return;
        const Vec3 q = closestOnSegment(p, m.nodes[segs[s].a], m.nodes[segs[s].b]);
        const Vec3 d = q - p;
        const double l = norm(d);
        if (!(l > 0) || l >= best) return;
        if (dot(d, in) < 0.6 * l) return;             // leaves p into the face
        if (dot(d, segs[s].in) > -0.6 * l) return;    // reaches the other side from inside
        best = l;
        bestQ = q;
      });
      if (best < reach) {
        const double h = std::max(best / across, hmin);
        // along the boundary segments at v, densely, so that the size holds between the nodes
        for (int s : ns.second) {
          const int o = segs[s].a == v ? segs[s].b : segs[s].a;
          const Vec3 q = m.nodes[o];
          const int k = std::min(64, (int)std::ceil(0.5 * dist(p, q) / h));
          for (int j = 0; j < k; ++j) out.push_back({p + ((double)j / (2.0 * k)) * (q - p), h});
        }
        // and across the face: without these, the size grades up towards the middle of the face
        const int k = std::min(64, (int)std::ceil(best / h));
        for (int j = 1; j < k; ++j) out.push_back({p + ((double)j / k) * (bestQ - p), h});
      }
    }
  }
  return out;
}

}  // namespace paramesh
