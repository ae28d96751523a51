// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file NodeAudit.cpp
/// Audit of the nodes: no two closer than 1e-9 of the model's diagonal, and each on its CAD entity
/// (a vertex node at the vertex, an edge node at C(t) with t in the edge's range, a face node at
/// S(u,v) with (u,v) in the face's parameter box; a mid-node on the CAD or, where it was put back
/// to keep its element valid, at its chord's midpoint), within the entity's tolerance.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <set>

#include "paramesh/audit/MeshAudit.hpp"

namespace paramesh {
namespace {

constexpr double kCoincident = 1e-9;  ///< coincident nodes: closer than this fraction of the diagonal
constexpr double kFloor = 1e-9;       ///< a node's distance to its entity never needs to be below this x diagonal
constexpr double kParamMargin = 1e-6; ///< (u,v) / t may leave their box by this fraction of its span

void auditCoincident(const AuditInput& in, double diag, AuditResult& r) {
  const SurfaceMesh& m = in.mesh;
  const Box3 box = in.model.boundingBox();
  const double tol = kCoincident * diag, cell = diag / (1 << 20);
  if (!(cell > 0)) return;
  auto coord = [&](double x, double lo) {
    return (uint64_t)std::clamp((long long)std::floor((x - lo) / cell) + 2, 0LL, (1LL << 21) - 1);
  };
  std::vector<std::pair<uint64_t, int>> keys;
  keys.reserve(m.nodes.size());
  for (int i = 0; i < (int)m.nodes.size(); ++i) {
    const Vec3 p = m.nodes[i];
    uint64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = coord(p[a] - tol, box.lo[a]);
      hi[a] = coord(p[a] + tol, box.lo[a]);
    }
    for (uint64_t x = lo[0]; x <= hi[0]; ++x)
      for (uint64_t y = lo[1]; y <= hi[1]; ++y)
        for (uint64_t z = lo[2]; z <= hi[2]; ++z) keys.emplace_back((x << 42) | (y << 21) | z, i);
  }
  std::sort(keys.begin(), keys.end());
  std::set<std::pair<int, int>> pairs;
  for (size_t i = 0; i < keys.size();) {
    size_t j = i;
    while (j < keys.size() && keys[j].first == keys[i].first) ++j;
    for (size_t a = i; a < j; ++a)
      for (size_t b = a + 1; b < j; ++b)
        if (dist(m.nodes[keys[a].second], m.nodes[keys[b].second]) <= tol)
          pairs.emplace(keys[a].second, keys[b].second);
    i = j;
  }
  r.coincidentNodes = (int)pairs.size();
  if (pairs.empty()) return;
  std::vector<int> faces, edges;
  for (const auto& [a, b] : pairs)
    for (int n : {a, b}) {
      if (m.nodeKind[n] == NodeKind::Face) faces.push_back(m.nodeEntity[n]);
      if (m.nodeKind[n] == NodeKind::Edge) edges.push_back(m.nodeEntity[n]);
    }
  addFinding(r, "pairs of distinct nodes closer than 1e-9 of the diagonal", r.coincidentNodes, faces, edges);
}

bool inRange(double x, double a, double b, double period) {
  if (period > 0) return true;
  const double margin = kParamMargin * std::max(b - a, 1e-300);
  return x >= a - margin && x <= b + margin;
}

/// Per node: the two corner nodes of the chord it is the middle of (-1: not a mid-node).
std::vector<std::array<int, 2>> chords(const SurfaceMesh& m) {
  std::vector<std::array<int, 2>> c(m.nodes.size(), {-1, -1});
  if (m.order != 2) return c;
  for (size_t t = 0; t < m.triangleMid.size(); ++t)
    for (int i = 0; i < 3; ++i) c[m.triangleMid[t][i]] = {m.triangles[t][i], m.triangles[t][(i + 1) % 3]};
  for (size_t q = 0; q < m.quadMid.size(); ++q)
    for (int i = 0; i < 4; ++i) c[m.quadMid[q][i]] = {m.quads[q][i], m.quads[q][(i + 1) % 4]};
  for (size_t s = 0; s < m.segmentMid.size(); ++s) c[m.segmentMid[s]] = m.segments[s];
  return c;
}

/// One thread's evaluators (made on first use) and findings over a chunk of nodes.
struct NodeChunk {
  std::vector<std::unique_ptr<ISurface>> surf;
  std::vector<UVBox> box;
  std::vector<std::unique_ptr<ICurve>> curve;
  std::vector<char> curveMade;
  std::vector<int> faces, edges;
  int off = 0, checked = 0;
  double worst = 0;
};

/// Distance of node i to its entity, and whether its parameter lies in the entity's range;
/// false for nodes not checked (inside a solid, on a degenerate edge).
bool nodeOffset(const IGeometryModel& g, const SurfaceMesh& m, size_t i, NodeChunk& c, double& d, double& tol,
                bool& inside) {
  const int ent = m.nodeEntity[i] - 1;
  const Vec3 x = m.nodes[i];
  const Vec2 prm = m.nodeParam[i];
  switch (m.nodeKind[i]) {
    case NodeKind::Vertex:
      d = dist(x, g.vertexPoint(ent));
      tol = std::max(tol, g.vertexTolerance(ent));
      return true;
    case NodeKind::Edge: {
      if (!c.curveMade[ent]) c.curve[ent] = g.makeCurve(ent), c.curveMade[ent] = 1;
      if (!c.curve[ent]) return false;  // degenerate edge: its nodes are its vertex's
      double t0, t1;
      g.edgeRange(ent, t0, t1);
      inside = inRange(prm.x, std::min(t0, t1), std::max(t0, t1), 0);
      d = dist(x, c.curve[ent]->eval(prm.x));
      tol = std::max(tol, g.edgeTolerance(ent));
      return true;
    }
    case NodeKind::Face: {
      if (!c.surf[ent]) c.surf[ent] = g.makeSurface(ent), c.box[ent] = c.surf[ent]->bounds();
      const ISurface& s = *c.surf[ent];
      const UVBox& b = c.box[ent];
      inside = inRange(prm.x, b.u0, b.u1, s.uPeriod()) && inRange(prm.y, b.v0, b.v1, s.vPeriod());
      d = dist(x, s.eval(prm));
      tol = std::max(tol, g.faceTolerance(ent));
      return true;
    }
    default:
      return false;  // inside a solid
  }
}

void auditOnCad(const AuditInput& in, double diag, AuditResult& r) {
  const SurfaceMesh& m = in.mesh;
  const IGeometryModel& g = in.model;
  const std::vector<std::array<int, 2>> chord = chords(m);
  const int N = (int)m.nodes.size();
  std::vector<NodeChunk> parts((N + kAuditChunk - 1) / kAuditChunk);
  auditChunks(N, in.threads, [&](int begin, int end, int k) {
    NodeChunk& c = parts[k];
    c.surf.resize(g.numFaces());
    c.box.resize(g.numFaces());
    c.curve.resize(g.numEdges());
    c.curveMade.assign(g.numEdges(), 0);
    for (int i = begin; i < end; ++i) {
      double d = 0, tol = kFloor * diag;
      bool inside = true;
      if (!nodeOffset(g, m, i, c, d, tol, inside)) continue;
      ++c.checked;
      if (chord[i][0] >= 0 && !(d <= tol && inside)) {  // a straightened mid-node sits on its chord
        const double dc = dist(m.nodes[i], 0.5 * (m.nodes[chord[i][0]] + m.nodes[chord[i][1]]));
        if (dc <= kFloor * diag) d = 0, inside = true;
      }
      if (!(d <= tol) || !inside) {
        ++c.off;
        if (m.nodeKind[i] != NodeKind::Vertex) (m.nodeKind[i] == NodeKind::Face ? c.faces : c.edges).push_back(m.nodeEntity[i]);
      }
      c.worst = std::isfinite(d) ? std::max(c.worst, d) : d;
    }
  });
  std::vector<int> faces, edges;
  for (const NodeChunk& c : parts) {
    r.nodesChecked += c.checked;
    r.nodesOffCad += c.off;
    r.worstNodeOffset = std::isfinite(c.worst) ? std::max(r.worstNodeOffset, c.worst) : c.worst;
    faces.insert(faces.end(), c.faces.begin(), c.faces.end());
    edges.insert(edges.end(), c.edges.begin(), c.edges.end());
  }
  if (r.nodesOffCad)
    addFinding(r, "nodes off their CAD entity (farther than its tolerance, or outside its parameter range)", r.nodesOffCad,
               faces, edges);
}

}  // namespace

void auditNodes(const AuditInput& in, AuditResult& r) {
  const double diag = in.model.boundingBox().diagonal();
  auditCoincident(in, diag, r);
  auditOnCad(in, diag, r);
}

}  // namespace paramesh
