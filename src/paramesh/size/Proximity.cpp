// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/size/Proximity.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include "paramesh/util/SpatialGrid.hpp"

namespace paramesh {


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
  BoxGrid grid(std::max(reach, 1e-12));
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
    BoxGrid sg(std::max(reach, 1e-12));
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
