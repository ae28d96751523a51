// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/algo/Recombine.hpp"

#include <algorithm>
#include <cmath>

#include "paramesh/algo/Predicates.hpp"

namespace paramesh {

namespace {
inline int nx(int i) { return i == 2 ? 0 : i + 1; }
inline int pv(int i) { return i == 0 ? 2 : i - 1; }

double cornerAngle(Vec3 prev, Vec3 at, Vec3 next) {
  const Vec3 u = prev - at, v = next - at;
  const double c = dot(u, v) / std::max(norm(u) * norm(v), 1e-300);
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI;
}
}  // namespace

double quadQuality(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  const Vec3 P[4] = {a, b, c, d};
  // convex in 3D: the four corner normals agree
  Vec3 ref{0, 0, 0};
  for (int k = 0; k < 4; ++k) ref += cross(P[(k + 1) % 4] - P[k], P[(k + 3) % 4] - P[k]);
  double worst = 0;
  for (int k = 0; k < 4; ++k) {
    if (dot(cross(P[(k + 1) % 4] - P[k], P[(k + 3) % 4] - P[k]), ref) <= 0) return -1;
    worst = std::max(worst, std::fabs(cornerAngle(P[(k + 3) % 4], P[k], P[(k + 1) % 4]) - 90.0));
  }
  return 1.0 - worst / 90.0;
}

std::vector<QuadPair> recombine(const Triangulation& T, double maxAngleDeg) {
  const int nt = (int)T.tris.size();
  // candidate pairs through every free edge
  struct Cand {
    double q;
    int t, u;
    std::array<int, 4> quad;
  };
  std::vector<Cand> cands;
  std::vector<std::array<int, 3>> candOf(nt, {-1, -1, -1});  // per triangle edge: candidate index
  const double minQ = 1.0 - (maxAngleDeg - 90.0) / 90.0;
  for (int t = 0; t < nt; ++t) {
    const Triangle& tr = T.tris[t];
    if (tr.dead) continue;
    for (int i = 0; i < 3; ++i) {
      const int u = tr.n[i];
      if (u < t || T.isConstrained(t, i) || T.tris[u].dead) continue;
      const int j = T.edgeTo(u, t);
      if (j < 0) continue;
      // t = (a, b, c) with edge i = (b, c); u has d opposite: quad a, b, d, c
      const int a = tr.v[i], b = tr.v[nx(i)], c = tr.v[pv(i)], d = T.tris[u].v[j];
      const TriVertex &A = T.verts[a], &B = T.verts[b], &C = T.verts[c], &D = T.verts[d];
      // convex in (u,v)
      if (orient2d(A.uv, B.uv, D.uv) <= 0 || orient2d(B.uv, D.uv, C.uv) <= 0 || orient2d(D.uv, C.uv, A.uv) <= 0 ||
          orient2d(C.uv, A.uv, B.uv) <= 0)
        continue;
      const double q = quadQuality(A.xyz, B.xyz, D.xyz, C.xyz);
      if (q < minQ) continue;
      const int id = (int)cands.size();
      cands.push_back({q, t, u, {a, b, d, c}});
      candOf[t][i] = id;
      candOf[u][j] = id;
    }
  }
  // greedy by quality
  std::vector<int> order(cands.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = (int)k;
  std::sort(order.begin(), order.end(), [&](int x, int y) { return cands[x].q > cands[y].q; });
  std::vector<int> mate(nt, -1);  // matched candidate index per triangle
  for (int k : order) {
    const Cand& c = cands[k];
    if (mate[c.t] < 0 && mate[c.u] < 0) mate[c.t] = mate[c.u] = k;
  }
  // augmenting paths from each unmatched triangle: t0 -(free)- u1 =(matched)= w1 -(free)- u2 ...
  // ending at an unmatched triangle; depth-limited breadth-first search
  for (int t0 = 0; t0 < nt; ++t0) {
    if (T.tris[t0].dead || mate[t0] >= 0) continue;
    struct Node {
      int tri, parent, viaCand;
      bool outer;  // reached by a matched pair (or the start): expands along free pairs
    };
    std::vector<Node> nodes{{t0, -1, -1, true}};
    std::vector<int> seen{t0};
    int found = -1;
    for (size_t head = 0; head < nodes.size() && found < 0 && nodes.size() < 400; ++head) {
      if (!nodes[head].outer) continue;
      const int x = nodes[head].tri;  // an "outer" triangle (unmatched or reached by a matched edge)
      for (int i = 0; i < 3 && found < 0; ++i) {
        const int cid = candOf[x][i];
        if (cid < 0 || mate[x] == cid) continue;
        const Cand& c = cands[cid];
        const int y = c.t == x ? c.u : c.t;
        if (std::find(seen.begin(), seen.end(), y) != seen.end()) continue;
        seen.push_back(y);
        nodes.push_back({y, (int)head, cid, false});
        if (mate[y] < 0) {
          found = (int)nodes.size() - 1;
          break;
        }
        // continue through y's matched partner
        const Cand& m = cands[mate[y]];
        const int z = m.t == y ? m.u : m.t;
        if (std::find(seen.begin(), seen.end(), z) != seen.end()) continue;
        seen.push_back(z);
        nodes.push_back({z, (int)nodes.size() - 1, mate[y], true});
      }
    }
    if (found < 0) continue;
    // flip along the path: edges alternate free (becomes matched) / matched (becomes free)
    std::vector<int> path;
    for (int k = found; nodes[k].parent >= 0; k = nodes[k].parent) path.push_back(nodes[k].viaCand);
    for (size_t k = 0; k < path.size(); k += 2) {
      const Cand& c = cands[path[k]];
      mate[c.t] = mate[c.u] = path[k];
    }
  }
  std::vector<QuadPair> out;
  for (int t = 0; t < nt; ++t) {
    if (mate[t] < 0) continue;
    const Cand& c = cands[mate[t]];
    if (c.t != t) continue;
    out.push_back({c.t, c.u, c.quad});
  }
  return out;
}

}  // namespace paramesh
