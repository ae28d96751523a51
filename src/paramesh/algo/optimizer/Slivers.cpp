// SPDX-License-Identifier: LGPL-2.1-or-later
// Slivers (a smallest angle below 30 degrees) and the bookkeeping of their local repairs: finding
// and counting them, the region around them, splits of boundary slivers, the front's flat apexes.

#include "paramesh/algo/optimizer/Optimizer.hpp"

#include <algorithm>
#include <vector>

#include "paramesh/algo/optimizer/OptimizerDetail.hpp"

namespace paramesh {
using namespace optimizer_detail;

namespace {
// a sliver: smallest 3D angle below 30 degrees (pole triangles vanish in 3D and never count)
bool sliver(const TriVertex& a, const TriVertex& b, const TriVertex& c) {
  if (poleCollapsed(a, b, c)) return false;
  return sinMinAngle(a.xyz, b.xyz, c.xyz) < 0.5;
}
}  // namespace

int Optimizer::repairFrontApexes(double ratio) {
  int moved = 0;
  auto isFront = [&](int v) { return (T_.verts[v].flags & VF_BOUNDARY) && T_.verts[v].node < 0; };
  for (int t = 0; t < (int)T_.tris.size(); ++t) {
    if (T_.tris[t].dead) continue;
    for (int i = 0; i < 3; ++i) {
      const Triangle& tr = T_.tris[t];
      if (!T_.isConstrained(t, i)) continue;
      const int a = tr.v[nx(i)], b = tr.v[pv(i)], c = tr.v[i];
      if (!isFront(a) || !isFront(b)) continue;
      TriVertex& C = T_.verts[c];
      const Vec3 A = T_.verts[a].xyz, B = T_.verts[b].xyz;
      const double base = dist(A, B);
      const double h = 0.5 * (T_.verts[a].h + T_.verts[b].h);
      const double ideal = kEquilateralHeight * std::min(h, 1.5 * base);
      const double ht = norm(cross(B - A, C.xyz - A)) / base;
      if (ht >= ratio * ideal) continue;
      // (VF_FIXED adds VF_SUPER to this set, which no vertex of a live triangle has: the
      // constrained build kills every triangle on the auxiliary box's corners)
      if (C.flags & VF_FIXED) continue;
      const Vec3 n = normalized(T_.verts[a].normal + T_.verts[b].normal);
      const Vec3 dir = normalized(cross(n, B - A));
      const Vec3 goal = 0.5 * (A + B) + ideal * (dot(dir, C.xyz - A) >= 0 ? dir : -dir);
      bool closed = true;
      std::vector<int> rg;
      T_.ring(c, rg, &closed);
      if (!closed) continue;
      double q0 = 1e300;
      for (int r : rg) q0 = std::min(q0, quality(r));
      const Vec2 oldUv = C.uv;
      const Vec3 oldXyz = C.xyz;
      for (double relax : {1.0, 0.8, 0.6, 0.4}) {
        Vec2 s = oldUv;
        Vec3 p;
        if (!C_.stepAndProject(s, oldXyz + relax * (goal - oldXyz), p) || !C_.inDomain(s)) continue;
        C.uv = s;
        C.xyz = p;
        bool ok = true;
        double q1 = 1e300;
        for (int r : rg) {
          const Triangle& R = T_.tris[r];
          if (!valid(R.v[0], R.v[1], R.v[2])) {
            ok = false;
            break;
          }
          q1 = std::min(q1, quality(r));
        }
        // the front triangle gets taller; the ring may lose a little quality, never much
        if (ok && q1 >= std::min(q0, 0.6) * 0.9) {
          C_.fill(C);
          ++moved;
          break;
        }
        C.uv = oldUv;
        C.xyz = oldXyz;
      }
    }
  }
  return moved;
}

bool Optimizer::poorAngle(int t) const {
  const Triangle& tr = T_.tris[t];
  const TriVertex &a = T_.verts[tr.v[0]], &b = T_.verts[tr.v[1]], &c = T_.verts[tr.v[2]];
  return sliver(a, b, c);
}

int Optimizer::countPoorAngles() const { return countPoorAngles(T_, region_); }

int Optimizer::countPoorAngles(const Triangulation& T, const std::vector<char>& region) {
  auto in = [&](int v) { return region.empty() || v >= (int)region.size() || region[v]; };
  int n = 0;
  for (const Triangle& tr : T.tris) {
    if (tr.dead || !(in(tr.v[0]) || in(tr.v[1]) || in(tr.v[2]))) continue;
    const TriVertex &a = T.verts[tr.v[0]], &b = T.verts[tr.v[1]], &c = T.verts[tr.v[2]];
    if (sliver(a, b, c)) ++n;
  }
  return n;
}

std::vector<char> Optimizer::regionAround(const std::vector<int>& tris, int rings) const {
  std::vector<char> in(T_.verts.size(), 0);
  std::vector<int> front, next, rg;
  for (int t : tris)
    for (int v : T_.tris[t].v)
      if (!in[v]) {
        in[v] = 1;
        front.push_back(v);
      }
  for (int r = 0; r < rings; ++r) {
    next.clear();
    for (int v : front) {
      if (T_.verts[v].tri < 0) continue;
      T_.ring(v, rg);
      for (int t : rg)
        for (int w : T_.tris[t].v)
          if (!in[w]) {
            in[w] = 1;
            next.push_back(w);
          }
    }
    front.swap(next);
  }
  return in;
}

int Optimizer::boundaryVertices(int t) const {
  int nb = 0;
  for (int k = 0; k < 3; ++k)
    if (T_.verts[T_.tris[t].v[k]].flags & VF_BOUNDARY) ++nb;
  return nb;
}

int Optimizer::splitBoundarySlivers(int minBoundary) {
  std::vector<int> cands;
  for (int t = 0; t < (int)T_.tris.size(); ++t)
    if (!T_.tris[t].dead && boundaryVertices(t) >= minBoundary && poorAngle(t)) cands.push_back(t);
  int splits = 0;
  for (int t : cands) {
    if (T_.tris[t].dead || boundaryVertices(t) < minBoundary || !poorAngle(t)) continue;
    if (splitLongestFree(t) >= 0) ++splits;
  }
  return splits;
}

}  // namespace paramesh
