// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/model/NarrowZones.hpp"

#include <algorithm>
#include <cmath>

#include "paramesh/model/EdgeDiscretizer.hpp"
#include "paramesh/util/SpatialGrid.hpp"

namespace paramesh {

namespace {
// staggered nodes nearer an end of the follower than this many sizes are dropped: a shorter first
// segment would stand a poor triangle in the corner there
constexpr double kEndGap = 0.75;
}  // namespace

std::vector<NarrowGap> findNarrowGaps(const std::vector<std::vector<LoopNode>>& loops, double maxRatio) {
  struct Seg {
    int loop, i;
    Vec3 a, b, in;
  };
  std::vector<Seg> segs;
  double total = 0;
  for (size_t L = 0; L < loops.size(); ++L) {
    const auto& lp = loops[L];
    const int n = (int)lp.size();
    for (int i = 0; i < n; ++i) {
      const LoopNode &A = lp[i], &B = lp[(i + 1) % n];
      const Vec3 sum = A.inward + B.inward;
      segs.push_back({(int)L, i, A.xyz, B.xyz, norm2(sum) > 1e-20 ? normalized(sum) : Vec3{0, 0, 0}});
      total += dist(A.xyz, B.xyz);
    }
  }
  std::vector<NarrowGap> out;
  if (segs.size() < 4 || !(total > 0)) return out;
  const double cell = maxRatio * total / (double)segs.size();
  BoxGrid grid(std::max(cell, 1e-300));
  // a segment far longer than the mean (a damaged curve: a fuzzed propeller_and_shaft.iges had
  // one across the model, millions of cells) is tested against every query instead
  std::vector<int> longSegs;
  for (size_t k = 0; k < segs.size(); ++k) {
    Box3 b;
    b.add(segs[k].a);
    b.add(segs[k].b);
    if (grid.cellsOf(b.lo, b.hi) > 4096)
      longSegs.push_back((int)k);
    else
      grid.add((int)k, b.lo, b.hi);
  }
  for (size_t L = 0; L < loops.size(); ++L) {
    const auto& lp = loops[L];
    const int n = (int)lp.size();
    if (n < 3) continue;
    for (int i = 0; i < n; ++i) {
      const LoopNode& P = lp[i];
      if (!(norm2(P.inward) > 0.5)) continue;
      const LoopNode &prev = lp[(i + n - 1) % n], &next = lp[(i + 1) % n];
      const double spacing = 0.5 * (dist(prev.xyz, P.xyz) + dist(P.xyz, next.xyz));
      const double reach = maxRatio * spacing;
      if (!(reach > 0)) continue;
      const int eIn = prev.edge, eOut = P.edge;
      double best = reach;
      int bestSeg = -1;
      Vec3 bestQ = P.xyz;
      auto consider = [&](int k) {
        const Seg& S = segs[k];
        const int e = loops[S.loop][S.i].edge;
        if (e == eIn || e == eOut) return;
        if (S.loop == (int)L && (S.i == i || (S.i + 1) % n == i)) return;
        if (!(norm2(S.in) > 0.5)) return;
        const Vec3 q = closestOnSegment(P.xyz, S.a, S.b);
        const Vec3 d = q - P.xyz;
        const double l = norm(d);
        if (!(l > 1e-9 * spacing) || l >= best) return;
        if (dot(d, P.inward) < 0.6 * l) return;  // leaves the node into the face
        if (dot(d, S.in) > -0.6 * l) return;     // arrives at the other side from inside
        best = l;
        bestSeg = k;
        bestQ = q;
      };
      const Vec3 r{reach, reach, reach};
      if (grid.cellsOf(P.xyz - r, P.xyz + r) > 4096) {  // a node of such a segment: all of them
        for (int k = 0; k < (int)segs.size(); ++k) consider(k);
      } else {
        grid.query(P.xyz, reach, consider);
        for (int k : longSegs) consider(k);
      }
      if (bestSeg < 0) continue;
      NarrowGap g;
      g.loop = (int)L;
      g.index = i;
      g.edgeIn = eIn;
      g.edgeOut = eOut;
      g.edgeAcross = loops[segs[bestSeg].loop][segs[bestSeg].i].edge;
      g.p = P.xyz;
      g.q = bestQ;
      g.width = best;
      g.spacing = spacing;
      out.push_back(g);
    }
  }
  return out;
}

std::vector<double> staggeredParameters(const ICurve& c, double t0, double t1, const std::vector<Vec3>& leader,
                                        const SizeField& field, double maxTurn) {
  const CurveSampling cs = sampleCurve(c, t0, t1, &field);
  const double L = cs.length();
  const size_t m = cs.t.size();
  auto piece = [&](double ta, double tb, std::vector<double>& out) {
    const CurveSampling ps = sampleCurve(c, ta, tb, &field);
    const std::vector<double> t = discretizeCurve(ps, field, 1, maxTurn);
    out.insert(out.end(), t.begin() + 1, t.end());
  };
  std::vector<double> out{t0};
  if (m < 2 || !(L > 0) || leader.size() < 2) {
    piece(t0, t1, out);
    return out;
  }
  // arc length <-> parameter along the sampling (t increases along it)
  auto sOfT = [&](double t) {
    const size_t j = std::upper_bound(cs.t.begin(), cs.t.end(), t) - cs.t.begin();
    if (j == 0) return 0.0;
    if (j >= m) return L;
    const double w = (t - cs.t[j - 1]) / (cs.t[j] - cs.t[j - 1]);
    return cs.s[j - 1] + w * (cs.s[j] - cs.s[j - 1]);
  };
  auto tOfS = [&](double s) {
    const size_t j = std::upper_bound(cs.s.begin(), cs.s.end(), s) - cs.s.begin();
    if (j == 0) return cs.t.front();
    if (j >= m) return cs.t.back();
    const double den = cs.s[j] - cs.s[j - 1];
    const double w = den > 0 ? (s - cs.s[j - 1]) / den : 0.5;
    return cs.t[j - 1] + w * (cs.t[j] - cs.t[j - 1]);
  };
  // projections of the leader nodes, as arc positions (leader nodes farther than two sizes from
  // the follower take no part)
  std::vector<double> sp;
  bool acrossStart = false, acrossEnd = false;
  double hMax = 0;
  for (const Vec3& x : cs.p) hMax = std::max(hMax, field.size(x));
  const SegmentIndex index(cs.p, 2.0 * hMax);
  for (const Vec3& x : leader) {
    const int seg = index.nearest(x, 2.0 * field.size(x));
    if (seg < 0) continue;
    const size_t bestJ = (size_t)seg + 1;
    const double t = c.project(x, 0.5 * (cs.t[bestJ - 1] + cs.t[bestJ]), t0, t1);
    // a foot clamped to an end counts only when it is a true foot (the offset normal to the curve)
    Vec3 p, d;
    c.d1(t, p, d);
    const Vec3 off = x - p;
    if (std::fabs(dot(off, normalized(d))) > 0.1 * norm(off) + 1e-9 * L) continue;
    const double sx = sOfT(t);
    sp.push_back(sx);
    // a leader node across an end (not the end itself: two edges meeting at a sharp corner)
    if (norm(off) > 0.05 * field.size(p)) {
      if (sx < 0.05 * field.size(p)) acrossStart = true;
      if (sx > L - 0.05 * field.size(p)) acrossEnd = true;
    }
  }
  std::sort(sp.begin(), sp.end());
  sp.erase(std::unique(sp.begin(), sp.end(), [&](double a, double b) { return b - a < 1e-9 * L; }), sp.end());
  struct Fixed {
    double s;
    int group;
  };
  std::vector<Fixed> fixed;
  int group = 0;
  for (size_t k = 0; k + 1 < sp.size(); ++k) {
    const double sm = 0.5 * (sp[k] + sp[k + 1]);
    const double h = field.size(c.eval(tOfS(sm)));
    if (sp[k + 1] - sp[k] > 1.6 * h) {
      ++group;
      continue;
    }
    // near an end the staggered node stays when a leader node stands right across that end (the
    // strip closes there, and half a segment makes the zigzag's first triangle); otherwise
    // kEndGap applies
    const double h0 = field.size(cs.p.front()), h1 = field.size(cs.p.back());
    const double gap0 = acrossStart ? 0.25 : kEndGap, gap1 = acrossEnd ? 0.25 : kEndGap;
    if (sm < gap0 * h0 || sm > L - gap1 * h1) {
      ++group;
      continue;
    }
    fixed.push_back({sm, group});
  }
  double prevT = t0;
  int prevGroup = -1;
  for (const Fixed& f : fixed) {
    const double t = tOfS(f.s);
    if (!(t > prevT)) continue;
    if (f.group == prevGroup) out.push_back(t);
    else piece(prevT, t, out);
    prevT = t;
    prevGroup = f.group;
  }
  piece(prevT, t1, out);
  return out;
}

}  // namespace paramesh
