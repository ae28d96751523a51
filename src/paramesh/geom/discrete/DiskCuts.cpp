// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file DiskCuts.cpp
#include "paramesh/geom/discrete/DiskCuts.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <unordered_map>
#include <unordered_set>

namespace paramesh {
namespace {

using Use = std::pair<int, bool>;

double dist3(const TriangleSoup& m, int a, int b) { return dist(m.points[a], m.points[b]); }

int startOf(const FeatureGraph& g, const Use& u) { return u.second ? g.edges[u.first].v1 : g.edges[u.first].v0; }
int endOf(const FeatureGraph& g, const Use& u) { return u.second ? g.edges[u.first].v0 : g.edges[u.first].v1; }

/// Splits edge e at its node index k (0 < k < last) into e (nodes 0..k) and a new edge (k..last),
/// the node becoming a vertex; every wire using e uses both halves.
void splitChain(FeatureGraph& g, int e, size_t k) {
  FeatureGraph::Chain tail = g.edges[e];
  tail.nodes.assign(g.edges[e].nodes.begin() + k, g.edges[e].nodes.end());
  g.edges[e].nodes.resize(k + 1);
  const int v = (int)g.vertexNode.size();
  g.vertexNode.push_back(tail.nodes.front());
  tail.v0 = v;
  g.edges[e].v1 = v;
  const int e2 = (int)g.edges.size();
  g.edges.push_back(tail);
  for (auto& loops : g.faceLoops)
    for (auto& loop : loops)
      for (size_t i = 0; i < loop.size(); ++i)
        if (loop[i].first == e) {
          const bool rev = loop[i].second;
          const Use first = rev ? Use{e2, true} : Use{e, false}, second = rev ? Use{e, true} : Use{e2, false};
          loop[i] = first;
          loop.insert(loop.begin() + i + 1, second);
          ++i;
        }
}

/// The vertex at mesh node n of a wire, made one (its edge split there) when it is not.
int vertexAt(FeatureGraph& g, const std::vector<Use>& wire, int n) {
  for (const Use& u : wire) {
    const auto& c = g.edges[u.first];
    if (g.vertexNode[c.v0] == n) return c.v0;
    if (g.vertexNode[c.v1] == n) return c.v1;
  }
  for (const Use& u : wire) {
    const auto& nodes = g.edges[u.first].nodes;
    for (size_t k = 1; k + 1 < nodes.size(); ++k)
      if (nodes[k] == n) {
        splitChain(g, u.first, k);
        return (int)g.vertexNode.size() - 1;
      }
  }
  return -1;
}

/// Shortest path of mesh edges of face f (through nodes on no feature edge) from any node of
/// `from` to any node of `to`; empty when there is none.
std::vector<int> shortestPath(const TriangleSoup& m, const std::vector<int>& tris, const std::vector<char>& onFeature,
                              const std::vector<int>& from, const std::vector<int>& to) {
  std::unordered_map<int, std::vector<int>> adj;
  for (int t : tris)
    for (int i = 0; i < 3; ++i) {
      const int a = m.triangles[t][i], b = m.triangles[t][(i + 1) % 3];
      adj[a].push_back(b);
      adj[b].push_back(a);
    }
  std::unordered_set<int> target(to.begin(), to.end());
  std::unordered_map<int, double> dist;
  std::unordered_map<int, int> prev;
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
  for (int s : from) dist[s] = 0, prev[s] = -1, q.push({0.0, s});
  while (!q.empty()) {
    const auto [d, v] = q.top();
    q.pop();
    if (d > dist[v]) continue;
    if (target.count(v)) {
      std::vector<int> path;
      for (int x = v; x >= 0; x = prev[x]) path.push_back(x);
      std::reverse(path.begin(), path.end());
      return path;
    }
    const bool start = prev[v] < 0;
    if (!start && onFeature[v]) continue;  // the path runs inside the face
    for (int w : adj[v]) {
      if (onFeature[w] && !target.count(w)) continue;
      const double nd = d + dist3(m, v, w);
      auto it = dist.find(w);
      if (it == dist.end() || nd < it->second) dist[w] = nd, prev[w] = v, q.push({nd, w});
    }
  }
  return {};
}

}  // namespace

std::vector<std::string> cutFacesToDisks(const TriangleSoup& m, FeatureGraph& g) {
  const int nf = (int)g.faceTris.size();
  std::vector<std::string> why(nf);
  std::vector<char> onFeature(m.points.size(), 0);
  for (const auto& e : g.edges)
    for (int v : e.nodes) onFeature[v] = 1;
  for (int f = 0; f < nf; ++f) {
    auto& loops = g.faceLoops[f];
    if (loops.empty()) {
      why[f] = "Face" + std::to_string(f + 1) + " has no boundary (a closed smooth surface): it cannot be parametrised yet";
      continue;
    }
    const auto sides = loops.size() > 1 ? faceSides(m, g.faceTris[f]) : std::unordered_map<unsigned long long, int>();
    while (loops.size() > 1) {
      // corners of the outer wire (loop 0, with the holes joined so far) and of the next hole
      std::vector<int> outer, hole;  // every node of the outer wire and of the hole
      for (const Use& u : loops[0]) outer.insert(outer.end(), g.edges[u.first].nodes.begin(), g.edges[u.first].nodes.end());
      for (const Use& u : loops[1]) hole.insert(hole.end(), g.edges[u.first].nodes.begin(), g.edges[u.first].nodes.end());
      const std::vector<int> path = shortestPath(m, g.faceTris[f], onFeature, hole, outer);
      if (path.size() < 2) {
        why[f] = "Face" + std::to_string(f + 1) + ": no path of mesh edges inside it from its wire " +
                 std::to_string(2) + " to its outer wire (a strip one triangle wide): it cannot be cut to a disk";
        break;
      }
      FeatureGraph::Chain c;
      c.nodes.assign(path.rbegin(), path.rend());  // outer corner -> hole corner
      // the seam's ends are vertices: an edge is split where the path meets it inside
      c.v0 = vertexAt(g, loops[0], c.nodes.front());
      c.v1 = vertexAt(g, loops[1], c.nodes.back());
      c.faces = {f};
      const int e = (int)g.edges.size();
      g.edges.push_back(c);
      for (size_t i = 1; i + 1 < c.nodes.size(); ++i) onFeature[c.nodes[i]] = 1;
      // the hole rotated to start at the seam's end, spliced into the outer wire at its start
      std::vector<Use> h = loops[1];
      const auto at = std::find_if(h.begin(), h.end(), [&](const Use& u) { return startOf(g, u) == c.v1; });
      std::rotate(h.begin(), at, h.end());
      std::vector<Use> splice{{e, false}};
      splice.insert(splice.end(), h.begin(), h.end());
      splice.push_back({e, true});
      // spliced where the outer wire passes the seam's start with the seam in that corner (a
      // wire can pass a node twice: along both sides of an earlier seam or a crease)
      auto& o = loops[0];
      const size_t k = splicePosition(m, g, sides, o, c.v0, c.nodes[1]);
      o.insert(o.begin() + std::min(k + 1, o.size()), splice.begin(), splice.end());
      loops.erase(loops.begin() + 1);
    }
  }
  return why;
}

}  // namespace paramesh
