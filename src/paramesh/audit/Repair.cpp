// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Repair.cpp
/// Local repair of folded / inverted elements by moving their face nodes on the surface.
#include "paramesh/audit/Repair.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <unordered_map>

#include "paramesh/audit/MeshAudit.hpp"

namespace paramesh {
namespace {

constexpr double kMinAngleDeg = 0.5;  ///< a move may not leave an element angle below this
constexpr int kRounds = 3;            ///< passes over the nodes (a move can free its neighbour's)

struct Repairer {
  const IGeometryModel& g;
  SurfaceMesh& m;
  std::vector<std::array<Vec2, 3>>& triUv;
  std::vector<std::array<Vec2, 4>>& quadUv;
  std::vector<std::unique_ptr<ISurface>> surf;
  std::unordered_map<int, std::vector<int>> ring;  ///< node -> the elements using it
  int T = 0;

  int corners(int e) const { return e < T ? 3 : 4; }
  int node(int e, int i) const { return e < T ? m.triangles[e][i] : m.quads[e - T][i]; }
  Vec2& uv(int e, int i) { return e < T ? triUv[e][i] : quadUv[e - T][i]; }
  int face(int e) const { return elementFace(m, e); }
  const ISurface& surface(int f) {
    if (!surf[f]) surf[f] = g.makeSurface(f);
    return *surf[f];
  }

  /// (bad elements, smallest angle in degrees) of the elements around node v.
  std::pair<int, double> judge(int v) {
    int bad = 0;
    double minAngle = 180;
    for (int e : ring[v]) {
      const int n = corners(e), f = face(e);
      Vec2 c{0, 0};
      for (int i = 0; i < n; ++i) c = c + uv(e, i);
      Vec3 sn;
      if (surface(f).normal((1.0 / n) * c, sn)) {
        if (g.faceReversed(f)) sn = -sn;
        bad += !(dot(elementNormal(m, e), sn) > 0);
      }
      for (int i = 0; i < n; ++i) {
        const Vec3 p = m.nodes[node(e, i)], a = m.nodes[node(e, (i + 1) % n)], b = m.nodes[node(e, (i + n - 1) % n)];
        const double l = norm(a - p) * norm(b - p);
        const double ang = l > 0 ? std::acos(std::clamp(dot(a - p, b - p) / l, -1.0, 1.0)) * 180.0 / 3.14159265358979 : 0.0;
        minAngle = std::min(minAngle, ang);
      }
    }
    return {bad, minAngle};
  }

  /// Node v (and its per-element (u,v)) to surface point x at parameter p.
  void place(int v, Vec3 x, Vec2 p) {
    const ISurface& s = surface(m.nodeEntity[v] - 1);
    m.nodes[v] = x;
    m.nodeParam[v] = p;
    for (int e : ring[v])
      for (int i = 0; i < corners(e); ++i)
        if (node(e, i) == v) {  // keep each element's corner on its side of a seam
          Vec2& q = uv(e, i);
          Vec2 w = p;
          for (int k = 0; k < 2; ++k) {
            const double per = k ? s.vPeriod() : s.uPeriod();
            if (per > 0) w[k] -= per * std::round((w[k] - q[k]) / per);
          }
          q = w;
        }
  }

  /// Tries node v at blends towards the centre of its neighbours; keeps the first move that
  /// leaves no bad element around it. Returns true when it moved.
  bool move(int v) {
    if (judge(v).first == 0) return false;
    Vec3 centre{0, 0, 0};
    int k = 0;
    for (int e : ring[v])
      for (int i = 0; i < corners(e); ++i)
        if (node(e, i) != v) centre += m.nodes[node(e, i)], ++k;
    if (!k) return false;
    centre = (1.0 / k) * centre;
    const Vec3 x0 = m.nodes[v];
    const Vec2 p0 = m.nodeParam[v];
    std::vector<Vec2> old;
    for (int e : ring[v])
      for (int i = 0; i < corners(e); ++i) old.push_back(uv(e, i));
    const ISurface& s = surface(m.nodeEntity[v] - 1);
    for (double w : {1.0, 0.75, 0.5, 0.25}) {
      Vec2 p = p0;
      Vec3 x;
      if (!s.project(x0 + w * (centre - x0), p, &x)) continue;
      place(v, x, p);
      const auto [bad, angle] = judge(v);
      if (bad == 0 && angle >= kMinAngleDeg) return true;
      // back to where it was
      m.nodes[v] = x0;
      m.nodeParam[v] = p0;
      size_t j = 0;
      for (int e : ring[v])
        for (int i = 0; i < corners(e); ++i) uv(e, i) = old[j++];
    }
    return false;
  }
};

}  // namespace

int repairBadElements(const IGeometryModel& g, SurfaceMesh& m, std::vector<std::array<Vec2, 3>>& triUv,
                      std::vector<std::array<Vec2, 4>>& quadUv, const std::vector<int>& bad) {
  if (m.order != 1 || triUv.size() != m.triangles.size() || quadUv.size() != m.quads.size()) return 0;
  Repairer r{g, m, triUv, quadUv, std::vector<std::unique_ptr<ISurface>>(g.numFaces()), {}, (int)m.triangles.size()};
  std::vector<int> movable;  // face nodes of the bad elements, on those elements' face
  for (int e : bad)
    for (int i = 0; i < r.corners(e); ++i) {
      const int v = r.node(e, i);
      if (m.nodeKind[v] == NodeKind::Face && m.nodeEntity[v] - 1 == r.face(e) && !r.ring.count(v)) {
        r.ring[v];
        movable.push_back(v);
      }
    }
  if (movable.empty()) return 0;
  for (int e = 0; e < (int)(m.triangles.size() + m.quads.size()); ++e)
    for (int i = 0; i < r.corners(e); ++i) {
      const auto it = r.ring.find(r.node(e, i));
      if (it != r.ring.end()) it->second.push_back(e);
    }
  std::sort(movable.begin(), movable.end());
  int moved = 0;
  for (int round = 0; round < kRounds; ++round) {
    int now = 0;
    for (int v : movable) now += r.move(v);
    moved += now;
    if (!now) break;
  }
  return moved;
}

}  // namespace paramesh
