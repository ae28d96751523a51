// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/size/NearestFace.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "paramesh/util/SpatialGrid.hpp"

namespace paramesh {

NearestFaceResult nearestFaceSources(const SurfaceMesh& m, const std::vector<OffSurfaceTriangle>& cand, double hmin,
                                     const std::vector<double>* triDev, const FaceDistance& faceDistance,
                                     double margin) {
  NearestFaceResult out;
  if (cand.empty()) return out;
  const size_t nc = cand.size();
  std::vector<Vec3> c(nc);
  std::vector<double> reach(nc);
  double rmax = 0;
  for (size_t i = 0; i < nc; ++i) {
    const auto& T = m.triangles[cand[i].tri];
    c[i] = (1.0 / 3) * (m.nodes[T[0]] + m.nodes[T[1]] + m.nodes[T[2]]);
    reach[i] = margin * cand[i].deviation;
    rmax = std::max(rmax, reach[i]);
  }
  if (!(rmax > 0)) return out;
  // cells no smaller than a typical element, so that an element overlaps few cells
  double ext = 0;
  const size_t nt = m.triangles.size();
  for (size_t t = 0; t < nt; ++t) {
    const auto& T = m.triangles[t];
    ext += std::max({dist(m.nodes[T[0]], m.nodes[T[1]]), dist(m.nodes[T[1]], m.nodes[T[2]]), dist(m.nodes[T[2]], m.nodes[T[0]])});
  }
  const double cell = std::max(rmax, nt ? ext / (double)nt : rmax);
  BoxGrid grid(cell);
  for (size_t i = 0; i < nc; ++i) grid.add((int)i, c[i] - Vec3{reach[i], reach[i], reach[i]}, c[i] + Vec3{reach[i], reach[i], reach[i]});
  // per candidate, per other face within reach: its nearest element (mesh distance, element, point)
  struct Near {
    double l;
    int tri;  // -1 for a quad half
    Vec3 q;
  };
  std::vector<std::map<int, Near>> near(nc);
  auto visit = [&](int face, int tri, Vec3 a, Vec3 b, Vec3 d, double dev) {
    Box3 box;
    box.add(a);
    box.add(b);
    box.add(d);
    box.lo = box.lo - Vec3{dev, dev, dev};
    box.hi = box.hi + Vec3{dev, dev, dev};
    auto test = [&](int i) {
      if (m.triangleFace[cand[i].tri] == face) return;
      const Vec3 q = closestOnTriangle(c[i], a, b, d);
      const double l = dist(c[i], q);
      if (l - dev >= reach[i]) return;
      auto it = near[i].find(face);
      if (it == near[i].end() || l < it->second.l) near[i][face] = {l, tri, q};
    };
    if (grid.cellsOf(box.lo, box.hi) <= 64) {
      grid.queryBox(box.lo, box.hi, test);
    } else {  // an element much larger than the cells: test the candidates directly
      for (size_t i = 0; i < nc; ++i) test((int)i);
    }
  };
  for (size_t t = 0; t < nt; ++t) {
    const auto& T = m.triangles[t];
    visit(m.triangleFace[t], (int)t, m.nodes[T[0]], m.nodes[T[1]], m.nodes[T[2]],
          triDev && t < triDev->size() ? (*triDev)[t] : 0.0);
  }
  for (size_t q = 0; q < m.quads.size(); ++q) {
    const auto& Q = m.quads[q];
    visit(m.quadFace[q], -1, m.nodes[Q[0]], m.nodes[Q[1]], m.nodes[Q[2]], 0.0);
    visit(m.quadFace[q], -1, m.nodes[Q[0]], m.nodes[Q[2]], m.nodes[Q[3]], 0.0);
  }
  for (size_t i = 0; i < nc; ++i) {
    double other = 1e300;
    Vec3 foot = c[i];
    for (const auto& kv : near[i]) {
      const Near& n = kv.second;
      Vec3 x = n.q;
      const double d = (faceDistance && n.tri >= 0) ? faceDistance(c[i], n.tri, n.q, &x) : n.l;
      if (d < other) {
        other = d;
        foot = x;
      }
    }
    if (!(other < reach[i])) continue;
    ++out.flagged;
    out.found.push_back({(double)cand[i].tri, cand[i].deviation, other});
    out.otherFoot.push_back(foot);
    const auto& T = m.triangles[cand[i].tri];
    const double L = (dist(m.nodes[T[0]], m.nodes[T[1]]) + dist(m.nodes[T[1]], m.nodes[T[2]]) +
                      dist(m.nodes[T[2]], m.nodes[T[0]])) / 3.0;
    const double f = std::clamp(std::sqrt(0.5 * other / cand[i].deviation), 0.3, 0.7);
    const double h = f * L;
    if (h < hmin) {  // already as small as allowed
      out.firstSource.push_back(-1);
      continue;
    }
    out.firstSource.push_back((int)out.sources.size());
    out.sources.push_back({c[i], h});
    for (int v : T) out.sources.push_back({m.nodes[v], h});
  }
  return out;
}

}  // namespace paramesh
