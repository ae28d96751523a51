// SPDX-License-Identifier: LGPL-2.1-or-later
// The report's quality summary of a surface mesh: angles, radius ratios and edge lengths against
// the size field.
#include <algorithm>
#include <cmath>
#include <vector>

#include "paramesh/algo/SurfaceContext.hpp"
#include "paramesh/pipeline/Mesher.hpp"

namespace paramesh {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

QualitySummary summarizeQuality(const SurfaceMesh& m, const std::function<double(Vec3)>& h) {
  QualitySummary q;
  const size_t nt = m.triangles.size();
  if (nt == 0 && m.quads.empty()) return q;
  double gsum = 0, gmin = 1e300, amin = 1e300, amax = 0;
  size_t below30 = 0;
  for (const auto& t : m.triangles) {
    const Vec3 a = m.nodes[t[0]], b = m.nodes[t[1]], c = m.nodes[t[2]];
    const TriSides sides = triSides(a, b, c);
    const double la = sides.la, lb = sides.lb, lc = sides.lc;
    const double g = radiusRatio(sides);
    gsum += g;
    gmin = std::min(gmin, g);
    auto ang = [](double x, double y, double z) {  // angle opposite x
      const double c = (y * y + z * z - x * x) / (2 * y * z);
      return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / kPi;
    };
    double A = ang(la, lb, lc), B = ang(lb, lc, la), C = 180.0 - A - B;
    const double mn = std::min({A, B, C}), mx = std::max({A, B, C});
    amin = std::min(amin, mn);
    amax = std::max(amax, mx);
    if (mn < 30) ++below30;
  }
  if (nt > 0) {
    q.gammaMean = gsum / nt;
    q.gammaMin = gmin;
    q.angleMin = amin;
    q.angleMax = amax;
    q.pctAngleBelow30 = 100.0 * below30 / nt;
  }
  // unique edges, in (low node, high node) order: bucketed by the low node (a counting sort),
  // then each node's few high ends sorted and deduplicated (cheaper than sorting all sides:
  // docs/tuning/pipeline.md)
  const int nn = (int)m.nodes.size();
  std::vector<int> start(nn + 1, 0);
  auto sides = [&](auto&& visit) {
    for (const auto& t : m.triangles)
      for (int k = 0; k < 3; ++k) visit(t[k], t[(k + 1) % 3]);
    for (const auto& t : m.quads)
      for (int k = 0; k < 4; ++k) visit(t[k], t[(k + 1) % 4]);
  };
  sides([&](int a, int b) { ++start[std::min(a, b) + 1]; });
  for (int i = 0; i < nn; ++i) start[i + 1] += start[i];
  std::vector<int> high(start[nn]);
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    sides([&](int a, int b) { high[fill[std::min(a, b)]++] = std::max(a, b); });
  }
  std::vector<std::pair<int, int>> E;
  E.reserve(high.size() / 2 + 1);
  for (int i = 0; i < nn; ++i) {
    auto b = high.begin() + start[i], e = high.begin() + start[i + 1];
    std::sort(b, e);
    for (auto it = b; it != e; ++it)
      if (it == b || *it != *(it - 1)) E.emplace_back(i, *it);
  }
  size_t ok = 0;
  double rsum = 0;
  for (auto& e : E) {
    const Vec3 a = m.nodes[e.first], b = m.nodes[e.second];
    const double r = dist(a, b) / h(0.5 * (a + b));
    rsum += r;
    if (r >= 1 / std::sqrt(2.0) && r <= std::sqrt(2.0)) ++ok;
  }
  q.pctLenInSqrt2 = E.empty() ? 0 : 100.0 * ok / E.size();
  q.lenRatioMean = E.empty() ? 0 : rsum / E.size();
  // quads
  double areaT = 0, areaQ = 0, aspSum = 0;
  for (const auto& t : m.triangles) areaT += 0.5 * norm(cross(m.nodes[t[1]] - m.nodes[t[0]], m.nodes[t[2]] - m.nodes[t[0]]));
  for (const auto& Q : m.quads) {
    const Vec3 P[4] = {m.nodes[Q[0]], m.nodes[Q[1]], m.nodes[Q[2]], m.nodes[Q[3]]};
    const Vec3 n1 = cross(P[1] - P[0], P[2] - P[0]), n2 = cross(P[2] - P[0], P[3] - P[0]);
    areaQ += 0.5 * (norm(n1) + norm(n2));
    double lmin = 1e300, lmax = 0;
    for (int k = 0; k < 4; ++k) {
      const Vec3 u = P[(k + 3) % 4] - P[k], v = P[(k + 1) % 4] - P[k];
      const double c = dot(u, v) / std::max(norm(u) * norm(v), 1e-300);
      q.quadAngleMax = std::max(q.quadAngleMax, std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / kPi);
      lmin = std::min(lmin, norm(v));
      lmax = std::max(lmax, norm(v));
    }
    const double asp = lmin > 0 ? lmax / lmin : 1e300;
    aspSum += asp;
    q.quadAspectMax = std::max(q.quadAspectMax, asp);
    const double cw = dot(n1, n2) / std::max(norm(n1) * norm(n2), 1e-300);
    q.quadWarpMax = std::max(q.quadWarpMax, std::acos(std::clamp(cw, -1.0, 1.0)) * 180.0 / kPi);
  }
  if (!m.quads.empty()) q.quadAspectMean = aspSum / m.quads.size();
  q.pctAreaInQuads = areaT + areaQ > 0 ? 100.0 * areaQ / (areaT + areaQ) : 0;
  return q;
}

}  // namespace paramesh
