// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file SelfIntersection.cpp
#include "paramesh/volume/SelfIntersection.hpp"

#include <algorithm>
#include <cmath>

#include "paramesh/util/SpatialGrid.hpp"
#include "paramesh/volume/TetQuality.hpp"

namespace paramesh {
namespace {

/// Does segment pq pass through the interior of triangle abc (eps: a volume below which a sign
/// counts as zero, i.e. touching is not crossing)?
bool segmentCrosses(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c, double eps) {
  const double sp = tetVolume6(a, b, c, p), sq = tetVolume6(a, b, c, q);
  if (!((sp > eps && sq < -eps) || (sp < -eps && sq > eps))) return false;
  const double s1 = tetVolume6(p, q, a, b), s2 = tetVolume6(p, q, b, c), s3 = tetVolume6(p, q, c, a);
  return (s1 > eps && s2 > eps && s3 > eps) || (s1 < -eps && s2 < -eps && s3 < -eps);
}

}  // namespace

std::vector<std::pair<int, int>> crossingTriangles(const std::vector<Vec3>& nodes,
                                                   const std::vector<std::array<int, 3>>& tris,
                                                   std::size_t maxPairs) {
  std::vector<std::pair<int, int>> out;
  if (tris.empty()) return out;
  double mean = 0;
  for (const auto& t : tris) mean += dist(nodes[t[0]], nodes[t[1]]);
  mean /= tris.size();
  BoxGrid grid(2 * mean);
  auto box = [&](const std::array<int, 3>& t, Vec3& lo, Vec3& hi) {
    lo = hi = nodes[t[0]];
    for (int v : t)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], nodes[v][k]);
        hi[k] = std::max(hi[k], nodes[v][k]);
      }
  };
  for (std::size_t i = 0; i < tris.size(); ++i) {
    Vec3 lo, hi;
    box(tris[i], lo, hi);
    grid.add(static_cast<int>(i), lo, hi);
  }
  std::vector<int> seen(tris.size(), -1);
  for (std::size_t i = 0; i < tris.size() && out.size() < maxPairs; ++i) {
    const auto& A = tris[i];
    Vec3 lo, hi;
    box(A, lo, hi);
    const double l = std::max({dist(nodes[A[0]], nodes[A[1]]), dist(nodes[A[1]], nodes[A[2]]), dist(nodes[A[2]], nodes[A[0]])});
    const double eps = 1e-10 * l * l * l;
    grid.queryBox(lo, hi, [&](int j) {
      if (j <= (int)i || seen[j] == (int)i || out.size() >= maxPairs) return;
      seen[j] = (int)i;
      const auto& B = tris[j];
      int shared = 0;
      for (int a : A) shared += std::count(B.begin(), B.end(), a);
      if (shared >= 2) return;
      bool cross = false;
      // edges of one against the other; with a shared node, only edges not touching it
      for (int pass = 0; pass < 2 && !cross; ++pass) {
        const auto& E = pass ? B : A;
        const auto& T = pass ? A : B;
        for (int e = 0; e < 3 && !cross; ++e) {
          const int p = E[e], q = E[(e + 1) % 3];
          if (std::count(T.begin(), T.end(), p) || std::count(T.begin(), T.end(), q)) continue;
          cross = segmentCrosses(nodes[p], nodes[q], nodes[T[0]], nodes[T[1]], nodes[T[2]], eps);
        }
      }
      if (cross) out.emplace_back((int)i, j);
    });
  }
  return out;
}

}  // namespace paramesh
