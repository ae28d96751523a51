// SPDX-License-Identifier: LGPL-2.1-or-later
// Towards regular valences where the radius ratio falls short in a graded mesh: valence-driven
// flips, and the polish pass's Newton steps on the summed radius ratio of a vertex's ring.

#include "paramesh/algo/optimizer/Optimizer.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "paramesh/algo/optimizer/OptimizerDetail.hpp"

namespace paramesh {
using namespace optimizer_detail;

namespace {
// least gain in the ring's summed radius ratio worth a move: each move costs a projection on the
// surface (measured: docs/tuning/optimizer.md)
constexpr double kMinGain = 1e-3;
// the ring's worst triangle may get worse only while it stays above this, smoothPass's "good"
// (measured: docs/tuning/optimizer.md)
constexpr double kKeepAbove = 0.8;

// The summed radius ratio (and the worst, into minQ) of a ring with its centre vertex at x; far
// holds the two other corners of each triangle of the ring.
struct RingSum {
  const std::vector<Vec3>& far;
  double operator()(Vec3 x, double* minQ = nullptr) const {
    const int n = (int)far.size() / 2;
    double sum = 0, mn = 1e300;
    for (int k = 0; k < n; ++k) {
      const double q = gamma3(x, far[2 * k], far[2 * k + 1]);
      sum += q;
      mn = std::min(mn, q);
    }
    if (minQ) *minQ = mn;
    return sum;
  }
};

// One Newton step of V in its tangent plane from differences over 1 % of the mean edge L (tryMove
// projects it), else a short gradient step; at most 0.2 L, halved until it gains with the worst
// triangle kept above min(minQ0, kKeepAbove). best: that point; false when it gains < kMinGain.
bool newtonStep(const RingSum& sumQ, const TriVertex& V, double L, double f0, double minQ0, Vec3& best) {
  Vec3 e1 = cross(V.normal, Vec3{1, 0, 0});
  if (norm2(e1) < 0.1) e1 = cross(V.normal, Vec3{0, 1, 0});
  if (!(norm2(e1) > 0)) return false;
  e1 = normalized(e1);
  const Vec3 e2 = normalized(cross(V.normal, e1));
  const double d = 1e-2 * L;
  const double fx = sumQ(V.xyz + d * e1), fX = sumQ(V.xyz - d * e1);
  const double fy = sumQ(V.xyz + d * e2), fY = sumQ(V.xyz - d * e2);
  const double fxy = sumQ(V.xyz + d * (e1 + e2));
  const double gx = (fx - fX) / (2 * d), gy = (fy - fY) / (2 * d);
  const double hxx = (fx - 2 * f0 + fX) / (d * d), hyy = (fy - 2 * f0 + fY) / (d * d);
  const double hxy = (fxy - fx - fy + f0) / (d * d);
  const double det = hxx * hyy - hxy * hxy;
  double sx, sy;
  if (hxx < 0 && det > 0) {
    sx = -(hyy * gx - hxy * gy) / det;
    sy = -(hxx * gy - hxy * gx) / det;
    if (0.5 * (gx * sx + gy * sy) < 0.5 * kMinGain) return false;  // predicted gain: too small
  } else {  // not concave here: a short step up the gradient
    const double g = std::hypot(gx, gy);
    if (!(g > 0)) return false;
    sx = 0.05 * L * gx / g;
    sy = 0.05 * L * gy / g;
  }
  const double sl = std::hypot(sx, sy);
  if (sl > 0.2 * L) {
    sx *= 0.2 * L / sl;
    sy *= 0.2 * L / sl;
  }
  const double floorQ = std::min(minQ0, kKeepAbove);
  best = V.xyz;
  double fb = f0;
  for (int h = 0; h < 3; ++h, sx *= 0.5, sy *= 0.5) {
    const Vec3 x = V.xyz + sx * e1 + sy * e2;
    double mn;
    const double f = sumQ(x, &mn);
    if (f > fb && mn >= floorQ) {
      fb = f;
      best = x;
      break;
    }
  }
  return fb > f0 + kMinGain;
}
}  // namespace

int Optimizer::valenceSwapPass(double qFactor, std::vector<int>* changed) {
  const int nv = (int)T_.verts.size();
  std::vector<int> cnt(nv, 0), target(nv, 6);
  std::vector<double> angle(nv, 0.0);
  for (const Triangle& tr : T_.tris) {
    if (tr.dead) continue;
    for (int k = 0; k < 3; ++k) {
      const int v = tr.v[k];
      ++cnt[v];
      if (T_.verts[v].flags & VF_BOUNDARY) {
        const Vec3 p = T_.verts[v].xyz;
        const Vec3 a = normalized(T_.verts[tr.v[nx(k)]].xyz - p), b = normalized(T_.verts[tr.v[pv(k)]].xyz - p);
        angle[v] += std::acos(std::clamp(dot(a, b), -1.0, 1.0));
      }
    }
  }
  // triangles at a vertex: 6 inside; at the boundary the count nearest its angle / 60 degrees
  for (int v = 0; v < nv; ++v)
    if (T_.verts[v].flags & VF_BOUNDARY) target[v] = std::max(1, (int)std::lround(angle[v] / 1.0471975511965976));
  auto dev = [&](int v, int c) {
    if (T_.verts[v].flags & (VF_SUPER | VF_DEAD | VF_POLE)) return 0;
    const int d = c - target[v];
    return d * d;
  };
  int flips = 0;
  auto visit = [&](int t, int i, int u, int a, int b, int c, int d) {
    // the flip removes edge (b,c) and adds (a,d)
    const int before = dev(a, cnt[a]) + dev(b, cnt[b]) + dev(c, cnt[c]) + dev(d, cnt[d]);
    const int after = dev(a, cnt[a] + 1) + dev(b, cnt[b] - 1) + dev(c, cnt[c] - 1) + dev(d, cnt[d] + 1);
    if (after >= before) return false;
    const double q0 = std::min(quality(t), quality(u));
    if (!(flippedQuality(a, b, c, d) >= qFactor * q0)) return false;
    if (!flipAllowed(a, b, c, d)) return false;
    if (!T_.flip(t, i)) return false;
    ++cnt[a];
    ++cnt[d];
    --cnt[b];
    --cnt[c];
    for (int v : {a, b, c, d}) addToRegion(v);
    if (changed) {
      changed->push_back(t);
      changed->push_back(u);
    }
    ++flips;
    return true;
  };
  sweepFreeEdges(visit, [](int) {});
  return flips;
}

std::vector<char> Optimizer::irregularZone() const {
  std::vector<int> count(T_.verts.size(), 0);
  for (const Triangle& tr : T_.tris)
    if (!tr.dead)
      for (int v : tr.v) ++count[v];
  std::vector<char> zone(T_.verts.size(), 0);
  for (const Triangle& tr : T_.tris) {
    if (tr.dead) continue;
    for (int v : tr.v)
      if (!(T_.verts[v].flags & VF_FIXED) && count[v] != 6) {
        for (int w : tr.v) zone[w] = 1;
        break;
      }
  }
  return zone;
}

int Optimizer::polishPass(std::vector<char>& active) {
  std::vector<char> next(T_.verts.size(), 0);
  std::vector<int> link;
  std::vector<Vec3> far;  // the two other corners of each triangle of the ring
  const RingSum sumQ{far};
  int moved = 0;
  for (int v = 0; v < (int)T_.verts.size(); ++v) {
    poll(v);
    if (v >= (int)active.size() || !active[v] || !inRegion(v) || !movableWithRing(v)) continue;
    TriVertex& V = T_.verts[v];
    link.clear();
    far.clear();
    double L = 0;
    bool pole = false;
    for (int t : ring_) {
      const Triangle& tr = T_.tris[t];
      const int k = T_.indexOf(t, v);
      const TriVertex &W = T_.verts[tr.v[nx(k)]], &W2 = T_.verts[tr.v[pv(k)]];
      link.push_back(tr.v[nx(k)]);
      far.push_back(W.xyz);
      far.push_back(W2.xyz);
      pole = pole || ((W.flags | W2.flags) & VF_POLE);
      L += dist(V.xyz, W.xyz);
    }
    if (pole) continue;  // quality() counts pole triangles as 1: the plain sum would not
    const int n = (int)ring_.size();
    L /= (double)n;
    double minQ0;
    const double f0 = sumQ(V.xyz, &minQ0);
    if (n - f0 < kMinGain) continue;  // the ring cannot gain more than it lacks
    // one step only (measured: docs/tuning/optimizer.md)
    Vec3 best;
    if (!newtonStep(sumQ, V, L, f0, minQ0, best)) continue;
    const RingStats r0 = ringStats();
    const int bad0 = outOfBand(v, link);
    if (tryMove(v, best, [&](const RingStats& r1) {
          return r1.sumQ > r0.sumQ + 1e-9 && r1.minQ >= std::min(r0.minQ, kKeepAbove) &&
                 (r1.minSin >= 0.5 || r1.minSin >= r0.minSin) && outOfBand(v, link) <= bad0;
        })) {
      ++moved;
      for (int w : link) next[w] = 1;
    }
  }
  active = std::move(next);
  return moved;
}

}  // namespace paramesh
