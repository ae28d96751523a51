// SPDX-License-Identifier: LGPL-2.1-or-later
// Vertex relocation: a free vertex moves on the surface when its ring gets better and stays valid
// (smoothing towards equilateral apexes, size conformity, the sliver repairs' angle search).

#include "paramesh/algo/optimizer/Optimizer.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "paramesh/algo/optimizer/OptimizerDetail.hpp"

namespace paramesh {
using namespace optimizer_detail;

bool Optimizer::moveTo(TriVertex& V, Vec2 from, Vec3 goal) const {
  Vec2 s = from;
  Vec3 p;
  if (!C_.stepAndProject(s, goal, p) || !C_.inDomain(s)) return false;
  V.uv = s;
  V.xyz = p;
  return true;
}

bool Optimizer::ringValid() const {
  for (int t : ring_) {
    const Triangle& tr = T_.tris[t];
    if (!valid(tr.v[0], tr.v[1], tr.v[2]) || !deviationOk(tr.v[0], tr.v[1], tr.v[2], 0)) return false;
  }
  return true;
}

Vec3 Optimizer::ringApexMean(int v) const {
  const TriVertex& V = T_.verts[v];
  Vec3 sum{0, 0, 0};
  for (int t : ring_) {
    const int k = T_.indexOf(t, v);
    const Triangle& tr = T_.tris[t];
    const Vec3 x = T_.verts[tr.v[nx(k)]].xyz, y = T_.verts[tr.v[pv(k)]].xyz;
    sum += 0.5 * (x + y) + (kEquilateralHeight * dist(x, y)) * normalized(cross(V.normal, y - x));
  }
  return sum * (1.0 / ring_.size());
}

Optimizer::RingStats Optimizer::ringStats() const {
  // quality(t) and the smallest angle's sine from one set of sides: the smoothing's hottest loop
  RingStats r;
  for (int t : ring_) {
    const Triangle& R = T_.tris[t];
    const TriVertex &A = T_.verts[R.v[0]], &B = T_.verts[R.v[1]], &Cc = T_.verts[R.v[2]];
    const TriSides sides = triSides(A.xyz, B.xyz, Cc.xyz);
    const double q = poleCollapsed(A, B, Cc) ? 1.0 : radiusRatio(sides);
    r.minQ = std::min(r.minQ, q);
    r.sumQ += q;
    r.minSin = std::min(r.minSin, sinMinAngle(sides));
  }
  return r;
}

bool Optimizer::tryMove(int v, Vec3 goal, const std::function<bool(const RingStats&)>& accept) {
  TriVertex& V = T_.verts[v];
  const Vec2 oldUv = V.uv;
  const Vec3 oldXyz = V.xyz;
  for (double relax : {1.0, 0.5}) {
    if (moveTo(V, oldUv, oldXyz + relax * (goal - oldXyz)) && ringValid() && accept(ringStats())) {
      C_.fill(V);
      return true;
    }
    V.uv = oldUv;
    V.xyz = oldXyz;
  }
  return false;
}

bool Optimizer::movableWithRing(int v) {
  const TriVertex& V = T_.verts[v];
  if ((V.flags & VF_FIXED) || V.tri < 0) return false;
  bool closed = true;
  T_.ring(v, ring_, &closed);
  return closed && ring_.size() >= 3;
}

int Optimizer::smoothPass() { return smoothPassOver(nullptr); }

int Optimizer::smoothPassOver(std::vector<char>* active) {
  int moved = 0;
  for (int v = 0; v < (int)T_.verts.size(); ++v) {
    poll(v);
    if (active && v < (int)active->size() && !(*active)[v]) continue;
    if (!inRegion(v) || !movableWithRing(v)) continue;
    const RingStats r0 = ringStats();
    // the ring's worst triangle gets better, or the ring gets better on average while its worst
    // stays good (above 0.8 and at most 2 % lower)
    if (tryMove(v, ringApexMean(v), [&](const RingStats& r1) {
          return r1.minQ > r0.minQ + 1e-9 ||
                 (r1.sumQ > r0.sumQ + 1e-9 && r1.minQ >= std::min(r0.minQ, 0.8) * 0.98 && r1.minQ > 0.8 * 0.98);
        })) {
      ++moved;
      if (!touched_.empty()) {
        // for the next pass, and for the rest of this one (a neighbour after v in the order
        // now sees a ring it has not been tried on)
        touch(v);
        for (int t : ring_)
          for (int k = 0; k < 3; ++k) {
            const int w = T_.tris[t].v[k];
            touch(w);
            if (active && w < (int)active->size()) (*active)[w] = 1;
          }
      }
    }
  }
  return moved;
}

int Optimizer::outOfBand(int v, const std::vector<int>& link) const {
  int n = 0;
  for (int w : link) {
    const double r = edgeRatio(v, w);
    n += (r < kBandLo || r > kBandHi) ? 1 : 0;
  }
  return n;
}

int Optimizer::lengthPass() {
  int moved = 0;
  std::vector<int> link;
  for (int v = 0; v < (int)T_.verts.size(); ++v) {
    poll(v);
    if (!inRegion(v) || !movableWithRing(v)) continue;
    const TriVertex& V = T_.verts[v];
    link.clear();
    for (int t : ring_) link.push_back(T_.tris[t].v[nx(T_.indexOf(t, v))]);
    const int bad0 = outOfBand(v, link);
    if (bad0 == 0) continue;
    // push away from the too near neighbours, pull towards the too far ones
    Vec3 step{0, 0, 0};
    for (int w : link) {
      const TriVertex& W = T_.verts[w];
      const double h = 0.5 * (V.h + W.h), l = dist(V.xyz, W.xyz);
      if (!(l > 0)) continue;
      const Vec3 u = (1.0 / l) * (V.xyz - W.xyz);
      if (l < kBandLo * h) step += (kBandLo * 1.02 * h - l) * u;
      if (l > kBandHi * h) step += (l - kBandHi * 0.98 * h) * (-1.0 * u);
    }
    if (!(norm2(step) > 0)) continue;
    const RingStats r0 = ringStats();
    if (tryMove(v, V.xyz + step, [&](const RingStats& r1) {
          return outOfBand(v, link) < bad0 && r1.sumQ >= 0.98 * r0.sumQ && (r1.minSin >= 0.5 || r1.minSin >= r0.minSin);
        }))
      ++moved;
  }
  return moved;
}

bool Optimizer::relocateForAngles(int t) {
  bool movedAny = false;
  const Triangle tr = T_.tris[t];
  for (int k = 0; k < 3; ++k) {
    const int v = tr.v[k];
    if (!movableWithRing(v)) continue;
    TriVertex& V = T_.verts[v];
    auto ringMin = [&]() {
      double m = 1e300;
      for (int r : ring_) {
        const Triangle& R = T_.tris[r];
        m = std::min(m, sinMinAngle(T_.verts[R.v[0]].xyz, T_.verts[R.v[1]].xyz, T_.verts[R.v[2]].xyz));
      }
      return m;
    };
    // candidates: the ring's centroid and its equilateral apexes' mean, and halfway to each
    Vec3 centroid{0, 0, 0};
    for (int r : ring_) centroid += T_.verts[T_.tris[r].v[nx(T_.indexOf(r, v))]].xyz;
    centroid = centroid * (1.0 / ring_.size());
    const Vec3 apexMean = ringApexMean(v);
    const Vec2 oldUv = V.uv;
    const Vec3 oldXyz = V.xyz;
    const double m0 = ringMin();
    double best = m0;
    Vec2 bestUv = oldUv;
    Vec3 bestXyz = oldXyz;
    auto tryGoal = [&](Vec3 goal, Vec2 from) {
      if (!moveTo(V, from, goal)) return;
      const double m = ringValid() ? ringMin() : -1;
      if (m > best + 1e-9) {
        best = m;
        bestUv = V.uv;
        bestXyz = V.xyz;
      }
      V.uv = oldUv;
      V.xyz = oldXyz;
    };
    for (const Vec3 goal : {centroid, apexMean, 0.5 * (oldXyz + centroid), 0.5 * (oldXyz + apexMean)})
      tryGoal(goal, oldUv);
    // then a pattern search in the tangent plane around the best so far
    Vec3 e1 = cross(V.normal, Vec3{1, 0, 0});
    if (norm2(e1) < 0.1) e1 = cross(V.normal, Vec3{0, 1, 0});
    e1 = normalized(e1);
    const Vec3 e2 = normalized(cross(V.normal, e1));
    for (double step = 0.15 * V.h; step > 0.02 * V.h; step *= 0.5) {
      for (int dir = 0; dir < 8; ++dir) {
        const double a = dir * 0.7853981633974483;  // 45 degrees
        const Vec3 base = bestXyz;
        tryGoal(base + step * (std::cos(a) * e1 + std::sin(a) * e2), bestUv);
      }
    }
    if (best > m0 + 1e-9) {
      V.uv = bestUv;
      V.xyz = bestXyz;
      C_.fill(V);
      movedAny = true;
    }
  }
  return movedAny;
}

}  // namespace paramesh
