// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file FeatureGraph.cpp
#include "paramesh/geom/discrete/FeatureGraph.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "paramesh/geom/discrete/EdgeTable.hpp"

namespace paramesh {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNoiseCrease = 0.02;  ///< of the diagonal (docs/discrete.md)


/// Does the corner of the face at node x, between the wire's arrival from node p and its
/// departure to node q (the face on its left), hold the mesh edge (x, y)? Turns about x through
/// the face's triangles from (x, q) towards (x, p). side: directed side (a, b) -> its triangle.
bool cornerHolds(const TriangleSoup& m, const std::unordered_map<unsigned long long, int>& side, int x, int p,
                 int q, int y) {
  int cur = q;
  for (size_t guard = 0; guard < m.triangles.size(); ++guard) {
    auto it = side.find(sideKey(x, cur));
    if (it == side.end()) return false;
    int r = -1;
    for (int v : m.triangles[it->second])
      if (v != x && v != cur) r = v;
    if (r == y) return true;
    if (r == p || r < 0) return false;
    cur = r;
  }
  return false;
}

}  // namespace

std::unordered_map<unsigned long long, int> faceSides(const TriangleSoup& m, const std::vector<int>& tris) {
  std::unordered_map<unsigned long long, int> side;
  for (int t : tris)
    for (int i = 0; i < 3; ++i) side[sideKey(m.triangles[t][i], m.triangles[t][(i + 1) % 3])] = t;
  return side;
}

size_t splicePosition(const TriangleSoup& m, const FeatureGraph& g, const std::unordered_map<unsigned long long, int>& side,
                      const std::vector<std::pair<int, bool>>& o, int v, int next) {
  auto endOf = [&](const std::pair<int, bool>& u) { return u.second ? g.edges[u.first].v0 : g.edges[u.first].v1; };
  size_t k = o.size();
  for (size_t i = 0; i < o.size(); ++i) {
    if (endOf(o[i]) != v) continue;
    if (k == o.size()) k = i;
    const auto& in = g.edges[o[i].first].nodes;
    const auto& out = g.edges[o[(i + 1) % o.size()].first].nodes;
    const int p = o[i].second ? in[1] : in[in.size() - 2];
    const int q = o[(i + 1) % o.size()].second ? out[out.size() - 2] : out[1];
    if (cornerHolds(m, side, g.vertexNode[v], p, q, next)) return i;
  }
  return k;
}

/// Step 6 of buildFeatureGraph: each face's boundary loops, the face on the left of each use;
/// loops that touch at a vertex joined into one wire.
static void buildFaceLoops(const TriangleSoup& m, const EdgeTable& table, FeatureGraph& g) {
  const int nf = (int)g.faceTris.size();
  g.faceLoops.assign(nf, {});
  std::vector<std::vector<std::pair<int, bool>>> uses(nf);
  for (int e = 0; e < (int)g.edges.size(); ++e) {
    const auto& c = g.edges[e];
    for (const auto& u : table.uses(c.nodes[0], c.nodes[1])) {
      const bool along = EdgeTable::runs(m.triangles[u.tri], c.nodes[0], c.nodes[1]);
      auto& fu = uses[g.triFace[u.tri]];
      const std::pair<int, bool> use{e, !along};
      if (std::find(fu.begin(), fu.end(), use) == fu.end()) fu.push_back(use);
    }
  }
  for (int f = 0; f < nf; ++f) {
    auto& left = uses[f];
    std::vector<char> done(left.size(), 0);
    auto startOf = [&](const std::pair<int, bool>& u) { return u.second ? g.edges[u.first].v1 : g.edges[u.first].v0; };
    auto endOf = [&](const std::pair<int, bool>& u) { return u.second ? g.edges[u.first].v0 : g.edges[u.first].v1; };
    for (size_t s = 0; s < left.size(); ++s) {
      if (done[s]) continue;
      std::vector<std::pair<int, bool>> loop{left[s]};
      done[s] = 1;
      const int first = startOf(left[s]);
      int at = endOf(left[s]);
      while (at != first) {
        size_t k = 0;
        while (k < left.size() && (done[k] || startOf(left[k]) != at)) ++k;
        if (k == left.size()) break;  // an open chain of uses (a face with a dangling boundary)
        done[k] = 1;
        loop.push_back(left[k]);
        at = endOf(left[k]);
      }
      g.faceLoops[f].push_back(std::move(loop));
    }
    // loops that touch at a vertex are one wire (a crease walked out and back, a slit): the later
    // loop, turned to start there, spliced into the earlier where that one passes the vertex
    auto& loops = g.faceLoops[f];
    const auto sides = loops.size() > 1 ? faceSides(m, g.faceTris[f]) : std::unordered_map<unsigned long long, int>();
    for (bool spliced = true; spliced;) {
      spliced = false;
      for (size_t i = 0; i < loops.size() && !spliced; ++i)
        for (size_t j = i + 1; j < loops.size() && !spliced; ++j) {
          if (startOf(loops[j].front()) != endOf(loops[j].back())) continue;  // only a closed loop is spliced in
          for (size_t p = 0; p < loops[j].size() && !spliced; ++p) {
            const int v = startOf(loops[j][p]);
            const auto& c = g.edges[loops[j][p].first].nodes;
            const size_t k = splicePosition(m, g, sides, loops[i], v, loops[j][p].second ? c[c.size() - 2] : c[1]);
            if (k == loops[i].size()) continue;
            std::rotate(loops[j].begin(), loops[j].begin() + p, loops[j].end());
            loops[i].insert(loops[i].begin() + k + 1, loops[j].begin(), loops[j].end());
            loops.erase(loops.begin() + j);
            spliced = true;
          }
        }
    }
  }
}

FeatureGraph buildFeatureGraph(const TriangleSoup& m, double featureAngleDeg) {
  FeatureGraph g;
  const int T = (int)m.triangles.size(), N = (int)m.points.size();
  const double cosFeature = std::cos(featureAngleDeg * kPi / 180.0);
  std::vector<Vec3> normal(T);
  for (int t = 0; t < T; ++t) {
    const auto& c = m.triangles[t];
    const Vec3 n = cross(m.points[c[1]] - m.points[c[0]], m.points[c[2]] - m.points[c[0]]);
    const double l = norm(n);
    normal[t] = l > 0 ? (1.0 / l) * n : Vec3{0, 0, 0};
  }
  const EdgeTable table(m.triangles, N);
  // 1. sharp, boundary and non-manifold edges; patches across the others
  std::unordered_map<unsigned long long, char> sharp;  // mesh edge -> 1 when a feature
  table.forEach([&](int a, int b, const std::vector<EdgeTable::Use>& u) {
    const bool feature = u.size() != 2 || dot(normal[u[0].tri], normal[u[1].tri]) < cosFeature;
    if (feature) sharp[edgeKey(a, b)] = 1;
  });
  auto isSharp = [&](int a, int b) { return sharp.count(edgeKey(a, b)) > 0; };
  g.triFace.assign(T, -1);
  std::vector<int> stack;
  int nf = 0;
  for (int s = 0; s < T; ++s) {
    if (g.triFace[s] >= 0) continue;
    g.triFace[s] = nf;
    stack.push_back(s);
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      for (int i = 0; i < 3; ++i) {
        const int a = m.triangles[t][i], b = m.triangles[t][(i + 1) % 3];
        if (isSharp(a, b)) continue;
        for (const auto& u : table.uses(a, b))
          if (g.triFace[u.tri] < 0) g.triFace[u.tri] = nf, stack.push_back(u.tri);
      }
    }
    ++nf;
  }
  g.faceTris.assign(nf, {});
  for (int t = 0; t < T; ++t) g.faceTris[g.triFace[t]].push_back(t);
  // 2. a crease with one face on both sides stays a feature, also where it fades out inside its
  // face (the M6 trailing edge runs into the rounded tip): the face is cut along it, as a CAD
  // face along a seam, and the edge is used twice by that face
  std::vector<std::vector<int>> adj(N);  // feature neighbours of each node
  table.forEach([&](int a, int b, const std::vector<EdgeTable::Use>&) {
    if (!isSharp(a, b)) return;
    adj[a].push_back(b);
    adj[b].push_back(a);
  });
  auto facesOf = [&](int a, int b) {
    std::vector<int> f;
    for (const auto& u : table.uses(a, b)) f.push_back(g.triFace[u.tri]);
    std::sort(f.begin(), f.end());
    f.erase(std::unique(f.begin(), f.end()), f.end());
    return f;
  };
  std::vector<char> corner;
  std::unordered_map<unsigned long long, int> chainOf;  // feature mesh edge -> chain
  std::vector<FeatureGraph::Chain> chains;
  Box3 box;
  for (const Vec3& p : m.points) box.add(p);
  for (;;) {
    // 3. corners: where chains end, branch, turn sharply or change the faces they separate
    corner.assign(N, 0);
    for (int v = 0; v < N; ++v) {
      if (adj[v].empty()) continue;
      if (adj[v].size() != 2) {
        corner[v] = 1;
        continue;
      }
      const int a = adj[v][0], b = adj[v][1];
      const Vec3 d0 = m.points[v] - m.points[a], d1 = m.points[b] - m.points[v];
      const double l = norm(d0) * norm(d1);
      if (facesOf(a, v) != facesOf(v, b) || !(l > 0) || dot(d0, d1) < cosFeature * l) corner[v] = 1;
    }
    // 4. chains between corners; a closed loop without one gets its lowest node as its corner
    chainOf.clear();
    chains.clear();
    auto walk = [&](int from, int next) {
      FeatureGraph::Chain c;
      c.nodes = {from};
      int prev = from, cur = next;
      chainOf[edgeKey(prev, cur)] = (int)chains.size();
      c.nodes.push_back(cur);
      while (!corner[cur]) {
        const int nx = adj[cur][0] == prev ? adj[cur][1] : adj[cur][0];
        prev = cur, cur = nx;
        chainOf[edgeKey(prev, cur)] = (int)chains.size();
        c.nodes.push_back(cur);
      }
      c.faces = facesOf(c.nodes[0], c.nodes[1]);
      chains.push_back(std::move(c));
    };
    for (int v = 0; v < N; ++v)
      if (corner[v])
        for (int w : adj[v])
          if (!chainOf.count(edgeKey(v, w))) walk(v, w);
    for (int v = 0; v < N; ++v)
      for (int w : adj[v]) {
        if (chainOf.count(edgeKey(v, w))) continue;
        int lowest = v, prev = v, cur = w;  // a loop of plain nodes: find its lowest node
        while (cur != v) {
          lowest = std::min(lowest, cur);
          const int nx = adj[cur][0] == prev ? adj[cur][1] : adj[cur][0];
          prev = cur, cur = nx;
        }
        corner[lowest] = 1;
        walk(lowest, std::min(adj[lowest][0], adj[lowest][1]));
      }
    // a short crease that ends inside its face (under kNoiseCrease of the diagonal) is noise of
    // the tessellation, not a feature: dropped, and the chains built again
    bool dropped = false;
    for (const auto& c : chains) {
      if (c.faces.size() != 1 || (adj[c.nodes.front()].size() != 1 && adj[c.nodes.back()].size() != 1)) continue;
      bool inside = true;
      double len = 0;
      for (size_t i = 1; i < c.nodes.size() && inside; ++i) {
        const auto u = table.uses(c.nodes[i - 1], c.nodes[i]);
        inside = u.size() == 2;
        len += dist(m.points[c.nodes[i - 1]], m.points[c.nodes[i]]);
      }
      if (!inside || len >= kNoiseCrease * box.diagonal()) continue;
      for (size_t i = 1; i < c.nodes.size(); ++i) {
        const int x = c.nodes[i - 1], y = c.nodes[i];
        adj[x].erase(std::find(adj[x].begin(), adj[x].end(), y));
        adj[y].erase(std::find(adj[y].begin(), adj[y].end(), x));
      }
      dropped = true;
    }
    if (!dropped) break;
  }
  // 5. stable numbers: edges by first use over the faces' triangles, vertices by the edges
  std::vector<int> number(chains.size(), -1);
  int ne = 0;
  for (int f = 0; f < nf; ++f)
    for (int t : g.faceTris[f])
      for (int i = 0; i < 3; ++i) {
        auto it = chainOf.find(edgeKey(m.triangles[t][i], m.triangles[t][(i + 1) % 3]));
        if (it != chainOf.end() && number[it->second] < 0) number[it->second] = ne++;
      }
  for (auto& k : number)
    if (k < 0) k = ne++;  // a chain beside no face (cannot happen: every feature edge has a facet)
  g.edges.resize(chains.size());
  for (size_t c = 0; c < chains.size(); ++c) g.edges[number[c]] = std::move(chains[c]);
  std::vector<int> vertexOf(N, -1);
  for (auto& e : g.edges)
    for (int* end : {&e.v0, &e.v1}) {
      const int node = end == &e.v0 ? e.nodes.front() : e.nodes.back();
      if (vertexOf[node] < 0) vertexOf[node] = (int)g.vertexNode.size(), g.vertexNode.push_back(node);
      *end = vertexOf[node];
    }
  buildFaceLoops(m, table, g);
  return g;
}

}  // namespace paramesh
