// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file NarrowGaps.cpp
/// Edge stage, narrow gaps: where two boundary loops of a face come closer than the size, the
/// nodes of the two sides are staggered (or spaced wide in very thin strips) so that the
/// triangles across the gap keep their angles. Reads model, field, the edges' parameters;
/// rewrites those parameters and edgeStage.staggered.
#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/pipeline/Tuning.hpp"
#include "paramesh/util/SpatialGrid.hpp"
#include "paramesh/util/Parallel.hpp"
#include "paramesh/model/EdgeDiscretizer.hpp"

namespace paramesh {

using namespace tuning;

namespace {

/// Roles of the edges across narrow gaps: an edge leads, follows (its leaders' nodes fixed first)
/// or is free; the heaviest pairs decide first, and no cycles. order: the followers in
/// dependency order.
struct GapRoles {
  std::vector<std::vector<int>> leaders;
  std::vector<char> follower, leads;
  std::vector<int> order;
};

GapRoles assignRoles(const std::map<std::pair<int, int>, int>& weight, int ne) {
  GapRoles roles;
  std::vector<std::vector<int>>& leaders = roles.leaders;
  std::vector<char>& follower = roles.follower;
  std::vector<char>& leads = roles.leads;
  std::vector<std::pair<int, std::pair<int, int>>> pairs;
  for (const auto& kv : weight) pairs.push_back({kv.second, kv.first});
  std::stable_sort(pairs.begin(), pairs.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  // roles: an edge leads, follows (its leaders' nodes fixed first) or is free; no cycles
  leaders.assign(ne, {});
  follower.assign(ne, 0);
  leads.assign(ne, 0);
  auto dependsOn = [&](int x0, int target) {  // does x0 (transitively) follow target?
    std::vector<int> stack{x0};
    std::vector<char> seen(ne, 0);
    while (!stack.empty()) {
      const int x = stack.back();
      stack.pop_back();
      if (x == target) return true;
      if (seen[x]) continue;
      seen[x] = 1;
      for (int y : leaders[x]) stack.push_back(y);
    }
    return false;
  };
  for (const auto& pr : pairs) {
    int a = pr.second.first, b = pr.second.second;
    if (follower[a] && follower[b]) continue;
    if (follower[a] || (leads[b] && !leads[a])) std::swap(a, b);  // b follows a
    if (dependsOn(a, b)) continue;
    leaders[b].push_back(a);
    follower[b] = 1;
    leads[a] = 1;
  }
  std::vector<int>& order = roles.order;
  std::vector<char> placed(ne, 0);
  for (bool more = true; more;) {
    more = false;
    for (int e = 0; e < ne; ++e) {
      if (!follower[e] || placed[e]) continue;
      bool ready = true;
      for (int a : leaders[e]) ready = ready && (!follower[a] || placed[a]);
      if (!ready) continue;
      placed[e] = 1;
      order.push_back(e);
      more = true;
    }
  }
  return roles;
}

}  // namespace


std::vector<std::vector<LoopNode>> MeshContext::loopNodes(int f, const std::vector<std::vector<double>>& ts,
                                             const std::vector<char>& degen) const {
  std::vector<std::vector<LoopNode>> loops;
  auto s = model.makeSurface(f);
  const bool rev = model.faceReversed(f);
  const auto& wires = model.faceWires(f);
  for (size_t w = 0; w < wires.size(); ++w) {
    std::vector<LoopNode> L;
    std::vector<Vec3> nrm;
    for (size_t k = 0; k < wires[w].uses.size(); ++k) {
      const EdgeUse& u = wires[w].uses[k];
      const int e = u.edge;
      if (same.edgeRep[e] != e || ts[e].size() < 2) return {};
      if (degen[e]) {
        const int v = model.edgeVertex(e, 0);
        if (v < 0) return {};
        LoopNode ln;
        ln.xyz = model.vertexPoint(v);
        ln.edge = e;
        L.push_back(ln);
        nrm.push_back({0, 0, 0});
        continue;
      }
      auto c = model.makeCurve(e);
      auto pc = model.makePCurve(f, (int)w, (int)k);
      const auto& t = ts[e];
      const size_t n = t.size();
      for (size_t i = 0; i + 1 < n; ++i) {
        const double tt = u.reversed ? t[n - 1 - i] : t[i];
        LoopNode ln;
        ln.xyz = c->eval(tt);
        ln.edge = e;
        Vec3 N{0, 0, 0};
        if (!pc || !s->normal(pc->eval(tt), N)) N = {0, 0, 0};
        L.push_back(ln);
        nrm.push_back(rev ? -1.0 * N : N);
      }
    }
    const int m = (int)L.size();
    if (m < 3) continue;
    for (int i = 0; i < m; ++i) {
      const Vec3 v = cross(nrm[i], L[(i + 1) % m].xyz - L[(i + m - 1) % m].xyz);
      L[i].inward = norm2(v) > 0 ? normalized(v) : Vec3{0, 0, 0};
    }
    loops.push_back(std::move(L));
  }
  return loops;
}

bool MeshContext::staggerAgainstLeaders(int b, const std::vector<int>& leadersOfB, std::vector<std::vector<double>>& ts) {
  progress.poll();
  auto cb = model.makeCurve(b);
  double t0, t1;
  model.edgeRange(b, t0, t1);
  const std::vector<Vec3> poly = sampleCurve(*cb, t0, t1, &field).p;
  double hMax = 0;
  for (const Vec3& x : poly) hMax = std::max(hMax, field.size(x));
  const SegmentIndex near_b(poly, hMax);
  // the leaders' nodes near b, and their neighbours along the leader
  std::vector<Vec3> near;
  for (int a : leadersOfB) {
    auto ca = model.makeCurve(a);
    std::vector<Vec3> xa;
    for (double t : ts[a]) xa.push_back(ca->eval(t));
    std::vector<char> take(xa.size(), 0);
    for (size_t i = 0; i < xa.size(); ++i)
      if (near_b.nearest(xa[i], kStaggerTo * field.size(xa[i])) >= 0) {
        take[i] = 1;
        if (i > 0) take[i - 1] = 1;
        if (i + 1 < xa.size()) take[i + 1] = 1;
      }
    for (size_t i = 0; i < xa.size(); ++i)
      if (take[i]) near.push_back(xa[i]);
  }
  if (near.size() < 2) return false;
  ts[b] = staggeredParameters(*cb, t0, t1, near, field, kPi / 3.0);
  return true;
}

bool MeshContext::staggerNarrowGaps(std::vector<std::vector<double>>& ts, const std::vector<char>& degen) {
  const int nf = model.numFaces(), ne = model.numEdges();
  edgeStage.staggered.assign(ne, 0);
  std::vector<std::vector<NarrowGap>> gaps(nf);
  parallelFor(nf, threads, [&](int f) {
    progress.poll();
    try {
      gaps[f] = findNarrowGaps(loopNodes(f, ts, degen), kStaggerTo * 1.4);
    } catch (const Cancelled&) {
      throw;
    } catch (...) {
      gaps[f].clear();
    }
  });
  // the leader spacing each gap asks for, at both of its ends; pair weights
  struct Want {
    Vec3 x;
    double b;
  };
  std::vector<std::vector<Want>> wants(ne), wide(ne);
  std::map<std::pair<int, int>, int> weight;
  std::map<std::pair<int, int>, std::vector<const NarrowGap*>> tooNarrow;  // (edge, edge across)
  std::vector<std::vector<Want>> caps(ne);
  std::map<std::pair<int, int>, std::vector<Want>> capsAt;  // (edge, edge across): its caps
  auto inLoop = [this](int f, int loop, int e) {
    const auto& wires = model.faceWires(f);
    if (loop < 0 || loop >= (int)wires.size()) return true;
    for (const EdgeUse& u : wires[loop].uses)
      if (same.edgeRep[u.edge] == same.edgeRep[e]) return true;
    return false;
  };
  auto shareVertex = [this](int a, int b) {
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        if (model.edgeVertex(a, i) >= 0 && model.edgeVertex(a, i) == model.edgeVertex(b, j)) return true;
    return false;
  };
  for (int f = 0; f < nf; ++f)
    for (const NarrowGap& g : gaps[f]) {
      const double h = field.size(g.p);
      const double r = g.width / h;
      if (r >= kStaggerTo) continue;
      // leader spacings between bLen (slanted edges h/sqrt2) and bAng (base angles 31 degrees),
      // with room for the follower's side being a little longer than the leader's
      const double bLen = 2.0 * std::sqrt(std::max(0.5 - r * r, 0.0)) * h, bAng = kStaggerMaxAspect * g.width;
      if (bAng < kStaggerWindow * bLen) {
        // too narrow to stagger, between two loops of the face (a hole near its outer boundary):
        // the spacing there is capped so that the triangles across it keep their shape
        const double cap = kGapCapRatio * g.width;
        if (cap < h && g.edgeIn == g.edgeOut && g.edgeIn >= 0 && g.edgeAcross >= 0 &&
            !shareVertex(g.edgeIn, g.edgeAcross) && !inLoop(f, g.loop, g.edgeAcross)) {
          capsAt[{g.edgeIn, g.edgeAcross}].push_back({g.p, cap});
          capsAt[{g.edgeAcross, g.edgeIn}].push_back({g.q, cap});
        }
        if (r > kWideStripMinWidth && g.edgeIn == g.edgeOut && g.edgeIn >= 0 && g.edgeAcross >= 0 && g.edgeAcross != g.edgeIn)
          tooNarrow[{g.edgeIn, g.edgeAcross}].push_back(&g);
        continue;
      }
      const double b = std::min(std::max(h, 1.06 * bLen), std::min(kStaggerMaxSpacing * h, bAng / 1.04));
      const int across = g.edgeAcross;
      if (across < 0 || !mayRespace(across, degen)) continue;
      wants[across].push_back({g.q, b});
      for (int e : {g.edgeIn, g.edgeOut}) {
        if (e >= 0 && e != across && mayRespace(e, degen)) {
          wants[e].push_back({g.p, b});
          ++weight[{std::min(e, across), std::max(e, across)}];
        }
        if (g.edgeIn == g.edgeOut) break;
      }
    }
  // caps only where the two edges come close over a few nodes (a long strip keeps its spacing)
  for (const auto& kv : capsAt)
    if ((int)kv.second.size() < kWideStripNodes)
      caps[kv.first.first].insert(caps[kv.first.first].end(), kv.second.begin(), kv.second.end());
  // long strips too narrow to stagger: both sides widened (where neither side is staggered)
  for (const auto& kv : tooNarrow) {
    if ((int)kv.second.size() < kWideStripNodes) continue;
    const int e = kv.first.first, a = kv.first.second;
    if (!mayRespace(e, degen) || !mayRespace(a, degen)) continue;
    for (const NarrowGap* g : kv.second) {
      const double b = kWideStripSpacing * field.size(g->p);
      wide[e].push_back({g->p, b});
      wide[a].push_back({g->q, b});
    }
  }
  // the field's size, raised to each wanted spacing near where it is wanted (graded away)
  auto discretizeWidened = [&](int e, const std::vector<Want>& W) {
    ts[e] = discretizeWith(e, [&](Vec3 x) {
      double h = field.size(x);
      for (const Want& w : W) h = std::max(h, w.b - field.slope() * std::max(0.0, dist(x, w.x) - 0.5 * w.b));
      for (const Want& c : caps[e]) h = std::min(h, c.b + field.slope() * std::max(0.0, dist(x, c.x) - 0.5 * c.b));
      return h;
    });
  };
  const GapRoles roles = assignRoles(weight, ne);
  const std::vector<std::vector<int>>& leaders = roles.leaders;
  const std::vector<char>&follower = roles.follower, &leads = roles.leads;
  int changed = 0;
  // leaders that follow no one: spacing widened along their gaps
  for (int e = 0; e < ne; ++e) {
    if (!leads[e] || follower[e] || wants[e].empty()) continue;
    discretizeWidened(e, wants[e]);
    edgeStage.staggered[e] = 1;
    ++changed;
  }
  int staggered = 0;
  // followers in dependency order, staggered against their leaders' nodes
  for (int b : roles.order) {
    if (!staggerAgainstLeaders(b, leaders[b], ts)) continue;
    edgeStage.staggered[b] = 1;
    ++staggered;
    ++changed;
  }
  int widened = 0, capped = 0;
  for (int e = 0; e < ne; ++e)
    if (!wide[e].empty() && !edgeStage.staggered[e] && !follower[e]) {
      caps[e].clear();  // a long strip keeps its wide spacing: the fewest poor triangles
      discretizeWidened(e, wide[e]);
      ++widened;
    }
  for (int e = 0; e < ne; ++e)
    if (!caps[e].empty() && !edgeStage.staggered[e] && !follower[e] && wide[e].empty() && mayRespace(e, degen)) {
      discretizeWidened(e, {});
      ++capped;
    }
  if (changed || widened || capped)
    log.info("narrow gaps: " + std::to_string(staggered) + " edges staggered against " +
             std::to_string(changed - staggered) + " widened ones; " + std::to_string(widened) +
             " sides of long narrow strips widened; " + std::to_string(capped) + " edges capped at short narrow gaps");
  return changed + widened + capped > 0;
}

}  // namespace paramesh
