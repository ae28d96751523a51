// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Corners.cpp
/// Edge stage, corners: at a corner where one side's first segment is much shorter than the
/// other's, the other side is re-spaced to grade from it (the corner's ear keeps its shape).
/// Reads model, field, the edges' parameters; rewrites those parameters.
#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/pipeline/Tuning.hpp"
#include "paramesh/util/Parallel.hpp"
#include "paramesh/model/EdgeDiscretizer.hpp"

namespace paramesh {

using namespace tuning;

bool MeshContext::mayRespace(int e, const std::vector<char>& degen) const {
  if (degen[e]) return false;
  if (!(same.mergedEdges || same.mergedVertices)) return true;
  // faces using the edge or a coincident twin of it
  size_t uses = 0;
  const int r = same.edgeRep[e];
  for (int k = 0; k < model.numEdges() && uses < 2; ++k)
    if (same.edgeRep[k] == r) uses += model.edgeFaces(k).size();
  return uses >= 2;
}

std::vector<double> MeshContext::discretizeWith(int e, const std::function<double(Vec3)>& spacing) const {
  auto c = model.makeCurve(e);
  double t0, t1;
  model.edgeRange(e, t0, t1);
  const CurveSampling cs = sampleCurve(*c, t0, t1, &field);
  const int v0 = model.edgeVertex(e, 0), v1 = model.edgeVertex(e, 1);
  const bool closed = (v0 >= 0 && v0 == v1) || dist(cs.p.front(), cs.p.back()) < 1e-9 * (1 + cs.length());
  return discretizeCurve(cs, spacing, closed ? 3 : 1, kPi / 3.0);
}

bool MeshContext::matchCornerSegments(std::vector<std::vector<double>>& ts, const std::vector<char>& degen) {
  const int nf = model.numFaces(), ne = model.numEdges();
  struct Want {
    Vec3 v;
    double s;
  };
  std::vector<std::vector<std::vector<std::pair<int, Want>>>> per(nf);
  parallelFor(nf, threads, [&](int f) {
    progress.poll();
    std::vector<std::vector<LoopNode>> loops;
    try {
      loops = loopNodes(f, ts, degen);
    } catch (const Cancelled&) {
      throw;
    } catch (...) {
      return;
    }
    std::vector<std::pair<int, Want>> found;
    for (const auto& L : loops) {
      const int n = (int)L.size();
      if (n < 3) continue;
      for (int i = 0; i < n; ++i) {
        const LoopNode &P = L[(i + n - 1) % n], &V = L[i], &N = L[(i + 1) % n];
        if (P.edge == V.edge || P.edge < 0 || V.edge < 0) continue;  // not a corner
        const double la = dist(P.xyz, V.xyz), lb = dist(V.xyz, N.xyz);
        if (!(la > 0 && lb > 0) || std::max(la, lb) < 1.5 * std::min(la, lb)) continue;
        // a tiny feature (far below the size) would pull a long run of small segments: left alone
        if (std::min(la, lb) < kCornerMinRatio * field.size(V.xyz)) continue;
        const Vec3 u = (1.0 / la) * (P.xyz - V.xyz), w = (1.0 / lb) * (N.xyz - V.xyz);
        if (!(norm2(V.inward) > 0.5) || dot(u + w, V.inward) <= 0) continue;  // reflex corner
        const double ang = std::acos(std::clamp(dot(u, w), -1.0, 1.0)) * 180.0 / kPi;
        if (ang < 40.0 || ang > 110.0) continue;
        // the ear's smallest angle
        const double lc = dist(P.xyz, N.xyz);
        const double ears = std::min({std::asin(std::min(1.0, std::sin(ang * kPi / 180) * la / lc)),
                                      std::asin(std::min(1.0, std::sin(ang * kPi / 180) * lb / lc))}) * 180.0 / kPi;
        if (ears >= 30.0) continue;
        const int longEdge = la > lb ? P.edge : V.edge;
        if (!mayRespace(longEdge, degen) || (edgeStage.staggered.size() == (size_t)ne && edgeStage.staggered[longEdge])) continue;
        if (ts[longEdge].size() < 3) continue;  // a single segment cannot be shortened at one end
        found.push_back({longEdge, {V.xyz, kCornerRatio * std::min(la, lb)}});
      }
    }
    per[f].push_back(std::move(found));
  });
  std::vector<std::vector<Want>> wants(ne);
  for (const auto& pf : per)
    for (const auto& fl : pf)
      for (const auto& w : fl) wants[w.first].push_back(w.second);
  int changed = 0;
  for (int e = 0; e < ne; ++e) {
    if (wants[e].empty()) continue;
    const auto& W = wants[e];
    auto spacing = [&](Vec3 x) {
      double h = field.size(x);
      for (const Want& w : W) h = std::min(h, w.s + kCornerSlope * dist(x, w.v));
      return h;
    };
    ts[e] = discretizeWith(e, spacing);
    ++changed;
  }
  if (changed) log.info("corners: " + std::to_string(changed) + " edges re-spaced at corners with a short neighbour segment");
  return changed > 0;
}

}  // namespace paramesh
