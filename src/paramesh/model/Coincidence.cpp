// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/model/Coincidence.hpp"

#include <algorithm>
#include <map>
#include <numeric>

namespace paramesh {

namespace {
int find(std::vector<int>& p, int i) {
  while (p[i] != i) i = p[i] = p[p[i]];
  return i;
}
}  // namespace

Coincidence findCoincident(const IGeometryModel& m, double tol) {
  Coincidence c;
  const int nv = m.numVertices(), ne = m.numEdges();
  c.vertexRep.resize(nv);
  std::iota(c.vertexRep.begin(), c.vertexRep.end(), 0);
  c.edgeRep.resize(ne);
  std::iota(c.edgeRep.begin(), c.edgeRep.end(), 0);
  c.edgeReversed.assign(ne, 0);
  // vertices: sweep along x
  std::vector<Vec3> P(nv);
  for (int v = 0; v < nv; ++v) P[v] = m.vertexPoint(v);
  std::vector<int> order(nv);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return P[a].x < P[b].x; });
  std::vector<int> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  for (int i = 0; i < nv; ++i)
    for (int j = i + 1; j < nv && P[order[j]].x - P[order[i]].x <= tol; ++j)
      if (dist(P[order[i]], P[order[j]]) <= tol) {
        int a = find(parent, order[i]), b = find(parent, order[j]);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
  for (int v = 0; v < nv; ++v) {
    c.vertexRep[v] = find(parent, v);
    if (c.vertexRep[v] != v) ++c.mergedVertices;
  }
  // edges between the same vertex classes
  std::map<std::pair<int, int>, std::vector<int>> groups;
  for (int e = 0; e < ne; ++e) {
    if (m.edgeDegenerate(e)) continue;
    int a = m.edgeVertex(e, 0), b = m.edgeVertex(e, 1);
    if (a < 0 || b < 0) continue;
    a = c.vertexRep[a];
    b = c.vertexRep[b];
    groups[{std::min(a, b), std::max(a, b)}].push_back(e);
  }
  for (auto& kv : groups) {
    auto& es = kv.second;
    if (es.size() < 2) continue;
    // sample each edge once
    struct Sample {
      std::unique_ptr<ICurve> c;
      double t0, t1;
      std::vector<Vec3> pts;
    };
    std::vector<Sample> S(es.size());
    for (size_t i = 0; i < es.size(); ++i) {
      S[i].c = m.makeCurve(es[i]);
      m.edgeRange(es[i], S[i].t0, S[i].t1);
      for (int k = 1; k <= 7; ++k) S[i].pts.push_back(S[i].c->eval(S[i].t0 + (S[i].t1 - S[i].t0) * k / 8.0));
    }
    for (size_t i = 0; i < es.size(); ++i) {
      if (c.edgeRep[es[i]] != es[i]) continue;
      for (size_t j = i + 1; j < es.size(); ++j) {
        if (c.edgeRep[es[j]] != es[j]) continue;
        // does edge j lie on edge i?
        bool same = true;
        for (size_t k = 0; k < S[j].pts.size() && same; ++k) {
          const double frac = (k + 1) / 8.0;
          double best = 1e300;
          for (double seedFrac : {frac, 1.0 - frac}) {
            const double t = S[i].c->project(S[j].pts[k], S[i].t0 + seedFrac * (S[i].t1 - S[i].t0), S[i].t0, S[i].t1);
            best = std::min(best, dist(S[i].c->eval(t), S[j].pts[k]));
          }
          if (best > tol) same = false;
        }
        if (!same) continue;
        c.edgeRep[es[j]] = es[i];
        const int ai = c.vertexRep[m.edgeVertex(es[i], 0)], aj = c.vertexRep[m.edgeVertex(es[j], 0)];
        bool rev = ai != aj;
        if (ai == c.vertexRep[m.edgeVertex(es[i], 1)]) {
          // closed edges: compare the quarter points
          const Vec3 qi = S[i].pts[1], qj = S[j].pts[1], qi3 = S[i].pts[5];
          rev = dist(qj, qi3) < dist(qj, qi);
        }
        c.edgeReversed[es[j]] = rev ? 1 : 0;
        ++c.mergedEdges;
      }
    }
  }
  // faces bounded by the same edges (after merging), degenerate edges left out
  std::map<std::vector<int>, int> firstWith;
  c.faceCandidate.resize(m.numFaces());
  for (int f = 0; f < m.numFaces(); ++f) {
    std::vector<int> key;
    for (const Wire& w : m.faceWires(f))
      for (const EdgeUse& u : w.uses)
        if (!m.edgeDegenerate(u.edge)) key.push_back(c.edgeRep[u.edge]);
    std::sort(key.begin(), key.end());
    c.faceCandidate[f] = key.empty() ? f : firstWith.emplace(std::move(key), f).first->second;
  }
  return c;
}

}  // namespace paramesh
