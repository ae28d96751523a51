// SPDX-License-Identifier: LGPL-2.1-or-later
// Chordal deviation: how far a triangle's centroid lies off the surface, the bound it may have,
// and the refinement (flips, crest and sag splits, collapses, centroid insertions) that meets it.

#include "paramesh/algo/optimizer/Optimizer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <vector>

#include "paramesh/algo/Predicates.hpp"
#include "paramesh/algo/optimizer/OptimizerDetail.hpp"
#include "paramesh/size/Sources.hpp"

namespace paramesh {
using namespace optimizer_detail;

namespace {
// an edge crosses a fold when the surface along it runs this much farther from the chord at its
// farthest point than at the chord's projected midpoint
constexpr double kRidgePeak = 1.5;
// below the split floor (half the min-size), an edge is split at a fold's crest only where the
// fold's radius is below 1/kCreaseScale of that floor: a crease at the mesh's scale; wider folds
// are the min-size's to limit (measured: docs/tuning/optimizer.md)
constexpr double kCreaseScale = 1.5;
// a deviation-driven flip must bring the pair's worst deviation/bound below this share of before
constexpr double kFlipGain = 0.8;
}  // namespace

double Optimizer::deviation(int ia, int ib, int ic, bool* footOutside, Vec2* foot) const {
  if (footOutside) *footOutside = false;
  const TriVertex &a = T_.verts[ia], &b = T_.verts[ib], &c = T_.verts[ic];
  if ((a.node >= 0 && (a.node == b.node || a.node == c.node)) || (b.node >= 0 && b.node == c.node)) return 0;
  if (C_.planar) return 0;
  const Vec3 g = (1.0 / 3) * (a.xyz + b.xyz + c.xyz);
  Vec2 s = (1.0 / 3) * (a.uv + b.uv + c.uv);
  Vec3 p;
  const bool ok = C_.project(g, s, p);
  if (footOutside && ok && !C_.inDomain(s)) {
    // outside the trimmed face, and outside the triangle's own (u,v) corners too: a foot among
    // the triangle's own nodes (which lie on the face) is where they say the face is, even when
    // the boundary's p-curves disagree (measured: docs/tuning/optimizer.md)
    const double w0 = orient2d(b.uv, c.uv, s), w1 = orient2d(c.uv, a.uv, s), w2 = orient2d(a.uv, b.uv, s);
    *footOutside = !((w0 >= 0 && w1 >= 0 && w2 >= 0) || (w0 <= 0 && w1 <= 0 && w2 <= 0));
  }
  if (foot) *foot = s;
  return dist(p, g);
}

double Optimizer::deviationEstimate(int ia, int ib, int ic) const {
  // along an edge (x_i, x_j) of a surface of normal curvature k, (n_i - n_j).(x_j - x_i) ~ k L^2
  // = 8 sag; the centroid sits at about half the largest edge sag
  const TriVertex* v[3] = {&T_.verts[ia], &T_.verts[ib], &T_.verts[ic]};
  // a crest vertex has no normal to estimate from: the exact deviation decides
  for (const TriVertex* x : v)
    if (x->flags & VF_CREST) return std::numeric_limits<double>::infinity();
  double m = 0;
  for (int k = 0; k < 3; ++k) {
    const TriVertex &p = *v[k], &q = *v[(k + 1) % 3];
    m = std::max(m, std::fabs(dot(p.normal - q.normal, q.xyz - p.xyz)) / 8.0);
  }
  return m;
}

double Optimizer::allowedDeviation(int a, int b, int c, bool withZones, bool relaxed) const {
  double allowed = maxDev_ > 0 ? maxDev_ : 1e300;
  const Vec3 &A = T_.verts[a].xyz, &B = T_.verts[b].xyz, &Cc = T_.verts[c].xyz;
  if (devRatio_ > 0) {
    const double mean = (dist(A, B) + dist(B, Cc) + dist(Cc, A)) / 3.0;
    double rel = devRatio_ * mean;
    if (relaxed && reach_ > 0) {
      // the surface's turning rate from the vertex normals (|n_p - n_q| / |p - q| ~ 1 / radius)
      const TriVertex* v[3] = {&T_.verts[a], &T_.verts[b], &T_.verts[c]};
      double rate = 0;
      for (int k = 0; k < 3; ++k) {
        const TriVertex &P = *v[k], &Q = *v[(k + 1) % 3];
        const double l = dist(P.xyz, Q.xyz);
        if (norm2(P.normal) > 0 && norm2(Q.normal) > 0 && l > 0) rate = std::max(rate, norm(P.normal - Q.normal) / l);
      }
      rel *= std::max(1.0, reach_ * rate);
    }
    allowed = std::min(allowed, rel);
  }
  if (withZones && !zones_.empty()) {
    const Vec3 g = (1.0 / 3) * (A + B + Cc);
    for (const DeviationZone& z : zones_) allowed = std::min(allowed, z.bound(g));
  }
  return allowed + (gap(a) + gap(b) + gap(c)) / 3.0;
}

bool Optimizer::deviationOk(int a, int b, int c, double allowed) const {
  if (!deviationBounded()) return true;
  allowed = std::max(allowed, allowedDeviation(a, b, c));
  if (deviationEstimate(a, b, c) <= 0.5 * allowed) return true;
  return deviation(a, b, c) <= allowed;
}

bool Optimizer::ridgePoint(int a, int b, Vec2& at) const {
  const TriVertex &A = T_.verts[a], &B = T_.verts[b];
  const Vec3 e = B.xyz - A.xyz;
  const double l2 = norm2(e);
  if (!(l2 > 0)) return false;
  // distance of point p from the chord line, and of the surface point at fraction f of the
  // edge's (u,v) segment
  auto fromChord = [&](Vec3 p) {
    const Vec3 w = p - A.xyz;
    return norm(w - (dot(w, e) / l2) * e);
  };
  auto off = [&](double f) { return fromChord(C_.surf.eval(C_.toParam(A.uv + f * (B.uv - A.uv)))); };
  constexpr int kSamples = 16;
  double best = -1, f0 = 0.5;
  for (int k = 1; k < kSamples; ++k) {
    const double d = off(double(k) / kSamples);
    if (d > best) {
      best = d;
      f0 = double(k) / kSamples;
    }
  }
  // golden-section refinement within the neighbouring samples
  constexpr double kG = 0.618033988749895;
  double lo = f0 - 1.0 / kSamples, hi = f0 + 1.0 / kSamples;
  double m1 = hi - kG * (hi - lo), m2 = lo + kG * (hi - lo), d1 = off(m1), d2 = off(m2);
  for (int it = 0; it < 12; ++it) {
    if (d1 > d2) {
      hi = m2;
      m2 = m1;
      d2 = d1;
      m1 = hi - kG * (hi - lo);
      d1 = off(m1);
    } else {
      lo = m1;
      m1 = m2;
      d1 = d2;
      m2 = lo + kG * (hi - lo);
      d2 = off(m2);
    }
  }
  const double f = 0.5 * (lo + hi);
  const double peak = off(f);
  // the midpoint split's point: the chord's midpoint projected on the surface (without splitEdge's
  // domain and validity checks: a reference distance only)
  Vec2 s = 0.5 * (A.uv + B.uv);
  Vec3 p;
  const double mid = C_.project(0.5 * (A.xyz + B.xyz), s, p) ? fromChord(p) : off(0.5);
  if (!(peak > kRidgePeak * mid)) return false;
  // a crest near an end is that end's to resolve (by a flip): no short edge beside it
  at = A.uv + f * (B.uv - A.uv);
  const Vec3 x = C_.surf.eval(C_.toParam(at));
  const double l = std::sqrt(l2);
  return std::min(dist(x, A.xyz), dist(x, B.xyz)) >= (acrossFold(A, B) ? kCrestShareFold : kCrestShare) * l;
}

bool Optimizer::flipForDeviation(int t) {
  // excess of a triangle: its deviation over its bound (<= 1: within it)
  auto excess = [&](int p, int q, int r) {
    const double bound = allowedDeviation(p, q, r);
    if (deviationEstimate(p, q, r) <= 0.5 * bound) return 0.0;
    return deviation(p, q, r) / bound;
  };
  int bestI = -1;
  double bestX = 0;
  for (int i = 0; i < 3; ++i) {
    int u, a, b, c, d;
    if (!validFlip(t, i, u, a, b, c, d)) continue;
    const double q0 = std::min(quality(t), quality(u));
    if (flippedQuality(a, b, c, d) < std::min(q0, kFoldMinQuality)) continue;
    const double before = std::max(excess(a, b, c), excess(d, c, b));
    const double after = std::max(excess(a, b, d), excess(a, d, c));
    if (after < kFlipGain * before && (bestI < 0 || after < bestX)) {
      bestI = i;
      bestX = after;
    }
  }
  int u, a, b, c, d;
  if (bestI < 0 || !validFlip(t, bestI, u, a, b, c, d) || !T_.flip(t, bestI)) return false;
  for (int v : {a, b, c, d}) {
    addToRegion(v);
    touch(v);
  }
  return true;
}

void Optimizer::measureGaps() {
  gap_.assign(T_.verts.size(), 0.0);
  for (size_t v = 0; v < T_.verts.size(); ++v) {
    const TriVertex& V = T_.verts[v];
    if (V.node >= 0 && !(V.flags & (VF_SUPER | VF_DEAD))) {
      // at most the distance to the point at the node's (u,v), less where a projection finds a
      // nearer point: the p-curve's (u,v) can map farther than the node is (measured:
      // docs/tuning/optimizer.md). Any surface point bounds the distance, even one off the domain.
      gap_[v] = dist(V.xyz, C_.surf.eval(C_.toParam(V.uv)));
      if (gap_[v] > 0) {
        Vec2 s = V.uv;
        Vec3 foot;
        C_.project(V.xyz, s, foot);
        const double d = dist(V.xyz, foot);
        if (std::isfinite(d)) gap_[v] = std::min(gap_[v], d);
      }
    }
  }
}

int Optimizer::sagEdge(int t, const Triangle& tr, double minEdge, bool belowFloor) const {
  // a triangle at a pole: none. Its edges from the pole cannot be split (below), and splitting
  // the one across only narrows the pole's fan (slivers of 8 degrees at the nose of a half body
  // of revolution); its centroid starts a ring nearer the pole
  for (int k = 0; k < 3; ++k)
    if (T_.verts[tr.v[k]].flags & VF_POLE) return -1;
  int best = -1;
  double bs = -1, bl = -1;
  for (int i = 0; i < 3; ++i) {
    if (T_.isConstrained(t, i)) continue;
    const TriVertex &P = T_.verts[tr.v[nx(i)]], &Q = T_.verts[tr.v[pv(i)]];
    // never split an edge from a pole: its neighbour on the pole line would become a
    // triangle with two vertices on one generator and the third at the pole, flat in 3D
    if ((P.flags | Q.flags) & VF_POLE) continue;
    const double l = dist(P.xyz, Q.xyz);
    if (l < minEdge && !belowFloor) continue;
    const double sag = std::fabs(dot(P.normal - Q.normal, Q.xyz - P.xyz)) / 8.0;
    if (sag > bs * 1.25 || (sag >= bs * 0.8 && l > bl)) {
      bs = sag;
      bl = l;
      best = i;
    }
  }
  return best;
}

bool Optimizer::chooseSplit(int t, const Triangle& tr, double minEdge, int& best, Vec2& crest) const {
  best = sagEdge(t, tr, minEdge, false);
  // not on an edge from a crest vertex: that crest is lined already, and the surface curving away
  // from the chord towards it is its flank's, for a plain split (measured: docs/tuning/optimizer.md)
  auto fromCrest = [&](int i) { return ((T_.verts[tr.v[nx(i)]].flags | T_.verts[tr.v[pv(i)]].flags) & VF_CREST) != 0; };
  bool ridge = devRatio_ > 0 && best >= 0 && !fromCrest(best) && ridgePoint(tr.v[nx(best)], tr.v[pv(best)], crest);
  // an edge below the floor may still be split at a crease's crest (kCreaseScale), unless the
  // floor is the user's min-size (setMinSizeReach): that lines the mesh up with the fold, it does
  // not refine it (measured: docs/tuning/optimizer.md)
  if (devRatio_ > 0 && reach_ == 0 && !ridge) {
    const int s = sagEdge(t, tr, minEdge, true);
    if (s >= 0 && s != best && !fromCrest(s) && ridgePoint(tr.v[nx(s)], tr.v[pv(s)], crest) &&
        maxCurvature(C_.surf, C_.toParam(crest)) * minEdge > kCreaseScale) {
      best = s;
      ridge = true;
    }
  }
  return ridge;
}

bool Optimizer::insertCentroid(int t, const Triangle& tr, double minEdge, int best) {
  // Unless the triangle is already at the smallest size. Under the user's bounds (not the
  // nearest-face zones alone, whose meshes stay as they were) that floor holds after a refused
  // split too, else centroid insertions go on below it (measured: docs/tuning/optimizer.md).
  if ((best < 0 || devRatio_ > 0 || maxDev_ > 0) && minEdge > 0) {
    const Vec3 &A = T_.verts[tr.v[0]].xyz, &B = T_.verts[tr.v[1]].xyz, &Cc = T_.verts[tr.v[2]].xyz;
    if (std::min({dist(A, B), dist(B, Cc), dist(Cc, A)}) < 2.0 * minEdge) return false;
  }
  const Vec2 s0 = (1.0 / 3) * (T_.verts[tr.v[0]].uv + T_.verts[tr.v[1]].uv + T_.verts[tr.v[2]].uv);
  if (!C_.inDomain(s0)) return false;
  int e = -1;
  const int where = T_.locate(s0, t, &e, Triangulation::kLocalWalk);
  if (where < 0 || (e >= 0 && T_.isConstrained(where, e)) || !T_.insertionIsValid(s0, where, e)) return false;
  TriVertex P = C_.makeVertex(s0);
  {
    const Vec3 &A = T_.verts[tr.v[0]].xyz, &B = T_.verts[tr.v[1]].xyz, &Cc = T_.verts[tr.v[2]].xyz;
    if (T_.insertionClearance(P.xyz, where, e) < Triangulation::kInsertClearance * std::max({dist(A, B), dist(B, Cc), dist(Cc, A)}))
      return false;
  }
  if (e < 0) {  // as for the splits: no new triangle facing away from the surface
    const Triangle& W = T_.tris[where];
    const TriVertex &A = T_.verts[W.v[0]], &B = T_.verts[W.v[1]], &D = T_.verts[W.v[2]];
    if (!facesAway(A, B, D) && (facesAway(A, B, P) || facesAway(B, D, P) || facesAway(D, A, P))) return false;
    // nor one lying on a flank but upside down (where the triangle split runs across a fold,
    // facesAway's summed normals can miss it)
    if (devRatio_ > 0 && (inverted(A, B, P) || inverted(B, D, P) || inverted(D, A, P))) return false;
    // nor where it would fold two of them onto each other (however the triangle faces)
    if (splitFolds(A.xyz, B.xyz, D.xyz, P.xyz)) return false;
  }
  const int v = T_.addVertex(P);
  const Triangulation::FlipTest none = [](int, int) { return false; };
  T_.insert(v, where, e, none, nullptr);
  return true;
}

bool Optimizer::refineTriangle(int t, double minEdge) {
  const Triangle tr = T_.tris[t];
  if (deviation(tr.v[0], tr.v[1], tr.v[2]) <= allowedDeviation(tr.v[0], tr.v[1], tr.v[2])) return false;
  // a flip that lines an edge up with a fold, where the other diagonal runs across it (only under
  // the curvature bound: elsewhere the bounds are the nearest-face check's; measured:
  // docs/tuning/optimizer.md)
  if (devRatio_ > 0 && flipForDeviation(t)) return true;
  // the free edge with the largest sag (estimated from the vertex normals), else the longest (a
  // cone's apex sags on the edge opposite it); across a fold much narrower than the edge, the
  // chord's projected midpoint lands on a flank: split at the fold's crest
  int best;
  Vec2 crest;
  const bool ridge = chooseSplit(t, tr, minEdge, best, crest);
  // a refused crest split is not replaced by the midpoint split, which lands on a flank; a fold
  // flip the quality swaps undo can come back next round (measured: docs/tuning/optimizer.md)
  if (best >= 0 && splitEdge(t, best, true, ridge ? &crest : nullptr) >= 0) return true;
  // on a fold already lined with crest vertices: a vertex left next to the crest goes
  if (devRatio_ > 0 && collapseForDeviation(t)) return true;
  // no edge to split (all on the boundary, from a pole or too short), or its split refused:
  // insert the (projected) centroid
  return insertCentroid(t, tr, minEdge, best);
}

int Optimizer::refineDeviation(double maxDev, double ratio, double minEdge, const std::vector<DeviationZone>* zones) {
  maxDev_ = maxDev;
  devRatio_ = ratio;
  zones_ = zones ? *zones : std::vector<DeviationZone>();
  if (!deviationBounded() || C_.planar) return 0;
  measureGaps();
  int changes = 0;
  for (int round = 0; round < 10; ++round) {
    std::vector<int> bad;
    for (int t = 0; t < (int)T_.tris.size(); ++t) {
      const Triangle& tr = T_.tris[t];
      if (tr.dead) continue;
      const double allowed = allowedDeviation(tr.v[0], tr.v[1], tr.v[2]);
      if (deviationEstimate(tr.v[0], tr.v[1], tr.v[2]) <= 0.5 * allowed) continue;
      if (deviation(tr.v[0], tr.v[1], tr.v[2]) > allowed) bad.push_back(t);
    }
    if (bad.empty()) break;
    int done = 0;
    for (int t : bad)
      if (!T_.tris[t].dead && refineTriangle(t, minEdge)) ++done;
    changes += done;
    if (!done) break;
    swapPass();
  }
  return changes;
}

bool Optimizer::collapseForDeviation(int t) {
  const Triangle tr = T_.tris[t];
  if (!((T_.verts[tr.v[0]].flags | T_.verts[tr.v[1]].flags | T_.verts[tr.v[2]].flags) & VF_CREST)) return false;
  for (int k = 0; k < 3; ++k) {
    const int a = tr.v[k];
    if (!movableWithRing(a)) continue;  // ring_: a's triangles
    // the ring's worst quality, which no collapse may take below kFoldMinQuality (no collinear
    // triangle) unless it was there already
    double q0 = 1e300;
    for (int r : ring_) q0 = std::min(q0, quality(r));
    // neighbours b of a (each the vertex after a in one ring triangle r): crest vertices first,
    // then the nearest in 3D
    struct Cand {
      bool notCrest;
      double d;
      int r, b;
      bool operator<(const Cand& o) const { return std::tie(notCrest, d, r) < std::tie(o.notCrest, o.d, o.r); }
    };
    std::vector<Cand> cand;
    for (int r : ring_) {
      const int b = T_.tris[r].v[nx(T_.indexOf(r, a))];
      cand.push_back({!(T_.verts[b].flags & VF_CREST), dist(T_.verts[a].xyz, T_.verts[b].xyz), r, b});
    }
    std::sort(cand.begin(), cand.end());
    for (const Cand& c : cand) {
      // the relabelled triangles (a replaced by b; those with b vanish)
      bool ok = true;
      for (int x : ring_) {
        const Triangle& X = T_.tris[x];
        if (X.v[0] == c.b || X.v[1] == c.b || X.v[2] == c.b) continue;
        Vec3 p[3];
        for (int j = 0; j < 3; ++j) p[j] = T_.verts[X.v[j] == a ? c.b : X.v[j]].xyz;
        if (gamma3(p[0], p[1], p[2]) < std::min(q0, kFoldMinQuality)) {
          ok = false;
          break;
        }
      }
      // collapse() checks validity and every deviation bound of the relabelled triangles
      if (ok && collapse(c.r, pv(T_.indexOf(c.r, a)), false)) {
        touch(c.b);
        addToRegion(c.b);
        return true;
      }
    }
  }
  return false;
}

std::vector<Optimizer::DeviationMiss> Optimizer::deviationMisses() const {
  std::vector<DeviationMiss> out;
  if (!(maxDev_ > 0 || devRatio_ > 0) || C_.planar) return out;
  for (const Triangle& tr : T_.tris) {
    if (tr.dead) continue;
    const double allowed = allowedDeviation(tr.v[0], tr.v[1], tr.v[2], false, false);
    if (deviationEstimate(tr.v[0], tr.v[1], tr.v[2]) <= 0.5 * allowed) continue;
    DeviationMiss m;
    m.deviation = deviation(tr.v[0], tr.v[1], tr.v[2], nullptr, &m.foot);
    if (!(m.deviation > allowed)) continue;
    const TriVertex &A = T_.verts[tr.v[0]], &B = T_.verts[tr.v[1]], &Cc = T_.verts[tr.v[2]];
    m.allowed = allowed;
    m.centroid = (1.0 / 3) * (A.xyz + B.xyz + Cc.xyz);
    m.corners[0] = A.uv;
    m.corners[1] = B.uv;
    m.corners[2] = Cc.uv;
    out.push_back(m);
  }
  return out;
}

}  // namespace paramesh
