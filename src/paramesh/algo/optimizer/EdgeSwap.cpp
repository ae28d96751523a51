// SPDX-License-Identifier: LGPL-2.1-or-later
// Edge flips: the quality-driven swap pass, and the angle-driven flip of the sliver repairs. A flip
// is taken only when both new triangles are valid and the pair folds no more (the crease guard).

#include "paramesh/algo/optimizer/Optimizer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "paramesh/algo/optimizer/OptimizerDetail.hpp"

namespace paramesh {
using namespace optimizer_detail;

namespace {
// crease guard: a flip may not fold a pair beyond 10 degrees (the cosine), unless it already is
constexpr double kCreaseCos = 0.984807753;
}  // namespace

bool Optimizer::edgeQuad(int t, int i, int& u, int& a, int& b, int& c, int& d) const {
  const Triangle& tr = T_.tris[t];
  u = tr.n[i];
  if (u < 0 || T_.isConstrained(t, i)) return false;
  const int j = T_.edgeTo(u, t);
  if (j < 0) return false;
  a = tr.v[i];
  b = tr.v[nx(i)];
  c = tr.v[pv(i)];
  d = T_.tris[u].v[j];
  return true;
}

bool Optimizer::validFlip(int t, int i, int& u, int& a, int& b, int& c, int& d) const {
  return edgeQuad(t, i, u, a, b, c, d) && valid(a, b, d) && valid(a, d, c);
}

double Optimizer::flippedQuality(int a, int b, int c, int d) const {
  const TriVertex &A = T_.verts[a], &B = T_.verts[b], &Cc = T_.verts[c], &D = T_.verts[d];
  return std::min(gamma3(A.xyz, B.xyz, D.xyz), gamma3(A.xyz, D.xyz, Cc.xyz));
}

bool Optimizer::flipAllowed(int a, int b, int c, int d) const {
  if (!valid(a, b, d) || !valid(a, d, c)) return false;
  const TriVertex &A = T_.verts[a], &B = T_.verts[b], &Cc = T_.verts[c], &D = T_.verts[d];
  // crease guard: do not fold the pair more than it is, beyond 10 degrees (kCreaseCos)
  const Vec3 n0 = normalized(cross(B.xyz - A.xyz, Cc.xyz - A.xyz));
  const Vec3 n1 = normalized(cross(Cc.xyz - D.xyz, B.xyz - D.xyz));
  const Vec3 m0 = normalized(cross(B.xyz - A.xyz, D.xyz - A.xyz));
  const Vec3 m1 = normalized(cross(D.xyz - A.xyz, Cc.xyz - A.xyz));
  if (dot(m0, m1) < std::min(dot(n0, n1), kCreaseCos) - 1e-9) return false;
  if (deviationBounded()) {
    // the new pair keeps its own bounds, or deviates no more than an old triangle that already
    // broke its bound did (measured, not estimated: an estimate let flips break zone bounds)
    auto over = [&](int p, int q, int r) {
      const double bound = allowedDeviation(p, q, r);
      if (deviationEstimate(p, q, r) <= 0.5 * bound) return 0.0;
      const double dv = deviation(p, q, r);
      return dv > bound ? dv : 0.0;
    };
    const double allowed = std::max(over(a, b, c), over(d, c, b));
    if (!deviationOk(a, b, d, allowed) || !deviationOk(a, d, c, allowed)) return false;
  }
  return true;
}

int Optimizer::swapPass() {
  int flips = 0;
  // triangle qualities, computed once per pass: a flip rewrites only its two triangles and no
  // vertex moves during the pass (each triangle was evaluated from all three of its edges)
  std::vector<double> q(T_.tris.size(), std::numeric_limits<double>::quiet_NaN());
  auto qual = [&](int t) {
    if (std::isnan(q[t])) q[t] = quality(t);
    return q[t];
  };
  // An edge seen again from its other triangle, neither changed since that one's scan, would get
  // the same answer (up to rounding): skip it. scanned[t]: the flip count when t's scan ended (-1:
  // not yet); changed[t]: the flip count of the flip that last rewrote t.
  std::vector<int> scanned(T_.tris.size(), -1), changed(T_.tris.size(), 0);
  auto visit = [&](int t, int i, int u, int a, int b, int c, int d) {
    if (std::max(changed[t], changed[u]) <= scanned[u]) return false;
    const double q0 = std::min(qual(t), qual(u));
    if (!(flippedQuality(a, b, c, d) > q0 + 1e-6)) return false;
    if (!flipAllowed(a, b, c, d)) return false;
    if (!T_.flip(t, i)) return false;
    q[t] = q[u] = std::numeric_limits<double>::quiet_NaN();
    for (int v : {a, b, c, d}) {
      addToRegion(v);
      touch(v);
    }
    ++flips;
    changed[t] = changed[u] = flips;
    return true;
  };
  sweepFreeEdges(visit, [&](int t) { scanned[t] = flips; });
  return flips;
}

bool Optimizer::flipForAngles(int t) {
  int bestI = -1;
  double best = -1;
  const Triangle& tr = T_.tris[t];
  const double old = sinMinAngle(T_.verts[tr.v[0]].xyz, T_.verts[tr.v[1]].xyz, T_.verts[tr.v[2]].xyz);
  for (int i = 0; i < 3; ++i) {
    int u, a, b, c, d;
    if (!validFlip(t, i, u, a, b, c, d)) continue;
    const TriVertex &A = T_.verts[a], &B = T_.verts[b], &Cc = T_.verts[c], &D = T_.verts[d];
    const Vec3 m0 = normalized(cross(B.xyz - A.xyz, D.xyz - A.xyz));
    const Vec3 m1 = normalized(cross(D.xyz - A.xyz, Cc.xyz - A.xyz));
    if (dot(m0, m1) < kCreaseCos) continue;  // crease guard
    if (deviationBounded()) {
      const double allowed = std::max(deviationEstimate(a, b, c), deviationEstimate(d, c, b));
      if (!deviationOk(a, b, d, allowed) || !deviationOk(a, d, c, allowed)) continue;
    }
    const double q = std::min(sinMinAngle(A.xyz, B.xyz, D.xyz), sinMinAngle(A.xyz, D.xyz, Cc.xyz));
    if (q > best) {
      best = q;
      bestI = i;
    }
  }
  if (bestI < 0 || best < std::min(old, 0.5) * 0.5) return false;
  return T_.flip(t, bestI);
}

}  // namespace paramesh
