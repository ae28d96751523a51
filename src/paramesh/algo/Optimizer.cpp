// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/algo/Optimizer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <tuple>

#include "paramesh/algo/Predicates.hpp"
#include "paramesh/size/Sources.hpp"

namespace paramesh {
namespace {
inline int nx(int i) { return i == 2 ? 0 : i + 1; }
inline int pv(int i) { return i == 0 ? 2 : i - 1; }
// a triangle with two corners on one pole node: collapsed in 3D by construction, not a defect
bool poleCollapsed(const TriVertex& a, const TriVertex& b, const TriVertex& c) {
  return ((a.flags | b.flags | c.flags) & VF_POLE) &&
         ((a.node >= 0 && (a.node == b.node || a.node == c.node)) || (b.node >= 0 && b.node == c.node));
}
}  // namespace

double Optimizer::quality(int t) const {
  const Triangle& tr = T_.tris[t];
  const TriVertex &a = T_.verts[tr.v[0]], &b = T_.verts[tr.v[1]], &c = T_.verts[tr.v[2]];
  if (poleCollapsed(a, b, c)) return 1.0;
  return gamma3(a.xyz, b.xyz, c.xyz);
}

namespace {
// a triangle that faces away from the surface: its normal opposes the sum of its vertices' normals
bool facesAway(const TriVertex& p, const TriVertex& q, const TriVertex& r) {
  return dot(cross(q.xyz - p.xyz, r.xyz - p.xyz), p.normal + q.normal + r.normal) < 0;
}
// a triangle on one side of the surface that faces away from it: its normal opposes every vertex
// normal it has, and those agree among themselves (across a fold, vertex normals on its two flanks
// oppose each other and leave a triangle's facing undecided)
bool inverted(const TriVertex& p, const TriVertex& q, const TriVertex& r) {
  const Vec3 n = cross(q.xyz - p.xyz, r.xyz - p.xyz);
  const TriVertex* v[3] = {&p, &q, &r};
  int defined = 0;
  for (int i = 0; i < 3; ++i) {
    if (!(norm2(v[i]->normal) > 0)) continue;
    if (dot(n, v[i]->normal) >= 0) return false;
    for (int j = 0; j < i; ++j)
      if (norm2(v[j]->normal) > 0 && dot(v[i]->normal, v[j]->normal) <= 0) return false;
    ++defined;
  }
  return defined > 0;
}
// an edge whose ends' normals oppose each other runs across a fold
bool acrossFold(const TriVertex& p, const TriVertex& q) { return dot(p.normal, q.normal) < 0; }
}  // namespace

namespace {
// kFacing: the cosine a triangle's normal must keep with a surface normal (~78 degrees)
constexpr double kFacing = 0.2;
// a split point must lie at least this share of the edge's 3D length from either end
constexpr double kMinSplitShare = 0.1;
// an edge crosses a fold when the surface along it runs this much farther from the chord at its
// farthest point than at the chord's projected midpoint
constexpr double kRidgePeak = 1.5;
// a crest split lies at least this share of the edge's 3D length from the edge's ends and from
// the vertices opposite it (a crest near one of them is that vertex's, for a flip, to resolve)
constexpr double kCrestShare = 0.25;
// the same share across a fold whose flanks face opposite ways (the ends' normals more than 90
// degrees apart): there a flip cannot line an edge up with the crest, so the crest is split even
// near a vertex (propeller_and_shaft's blade tips, where a fold closes into a cusp)
constexpr double kCrestShareFold = 0.1;
// below the split floor (half the min-size), an edge is split at a fold's crest only where the
// fold's radius is below 1/kCreaseScale of that floor: a crease at the mesh's scale, which the
// split lines the mesh up with. Wider folds are the min-size's to limit (bottle.brep at
// --min-size 0.5 --curvature-angle 10: crest splits of every short edge made needles, mean
// gamma 0.80)
constexpr double kCreaseScale = 1.5;
// a deviation-driven flip must bring the pair's worst deviation/bound below this share of before
constexpr double kFlipGain = 0.8;
// flips and crest splits for folds make no triangle below this quality that is worse than the
// worst they replace (no collinear triangle)
constexpr double kFoldMinQuality = 1e-3;
// the normal of triangle (a,b,c) makes a cosine of at least minCos with every vertex normal
// (vertices without one do not count); false for a degenerate triangle. n: its unnormalised normal.
bool facesVertexNormals(const TriVertex& a, const TriVertex& b, const TriVertex& c, double minCos, Vec3& n) {
  n = cross(b.xyz - a.xyz, c.xyz - a.xyz);
  const double ln = norm(n);
  if (!(ln > 0)) return false;
  for (const TriVertex* v : {&a, &b, &c})
    if (norm2(v->normal) > 0 && dot(n, v->normal) < minCos * ln) return false;
  return true;
}
}  // namespace

bool Optimizer::valid(int ia, int ib, int ic) const {
  const TriVertex &a = T_.verts[ia], &b = T_.verts[ib], &c = T_.verts[ic];
  if (orient2d(a.uv, b.uv, c.uv) <= 0) return false;
  if (poleCollapsed(a, b, c)) return true;
  // the triangle must face like the surface at each vertex (allowing curvature)
  Vec3 n;
  if (!facesVertexNormals(a, b, c, kFacing, n)) return false;
  // a triangle along a fold's crest (no vertex normal): like the surface at its centroid's foot
  if (a.flags & b.flags & c.flags & VF_CREST) return facesAtCentroid(ia, ib, ic);
  return true;
}

bool Optimizer::facesAtCentroid(int ia, int ib, int ic) const {
  const TriVertex &a = T_.verts[ia], &b = T_.verts[ib], &c = T_.verts[ic];
  Vec3 n;
  if (orient2d(a.uv, b.uv, c.uv) <= 0 || !facesVertexNormals(a, b, c, 0.0, n)) return false;
  Vec2 s = (1.0 / 3) * (a.uv + b.uv + c.uv);
  Vec3 foot, nf;
  if (!C_.project((1.0 / 3) * (a.xyz + b.xyz + c.xyz), s, foot)) return false;
  if (!C_.surf.normal(C_.toParam(s), nf)) return false;
  return dot(n, nf) >= kFacing * norm(n);
}

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
    // the boundary's p-curves disagree (boxed_sphere's corner patches)
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

bool Optimizer::validFlip(int t, int i, int& u, int& a, int& b, int& c, int& d) const {
  const Triangle& tr = T_.tris[t];
  u = tr.n[i];
  if (u < 0 || T_.isConstrained(t, i)) return false;
  const int j = T_.edgeTo(u, t);
  if (j < 0) return false;
  a = tr.v[i];
  b = tr.v[nx(i)];
  c = tr.v[pv(i)];
  d = T_.tris[u].v[j];
  return valid(a, b, d) && valid(a, d, c);
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
    const TriVertex &A = T_.verts[a], &B = T_.verts[b], &Cc = T_.verts[c], &D = T_.verts[d];
    const double q0 = std::min(quality(t), quality(u));
    if (std::min(gamma3(A.xyz, B.xyz, D.xyz), gamma3(A.xyz, D.xyz, Cc.xyz)) < std::min(q0, kFoldMinQuality)) continue;
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

int Optimizer::refineDeviation(double maxDev, double ratio, double minEdge, const std::vector<DeviationZone>* zones) {
  maxDev_ = maxDev;
  devRatio_ = ratio;
  zones_ = zones ? *zones : std::vector<DeviationZone>();
  if (!deviationBounded() || C_.planar) return 0;
  gap_.assign(T_.verts.size(), 0.0);
  for (size_t v = 0; v < T_.verts.size(); ++v) {
    const TriVertex& V = T_.verts[v];
    if (V.node >= 0 && !(V.flags & (VF_SUPER | VF_DEAD))) {
      // how far the node (on a CAD edge that may lie off this face) is from the surface: at most
      // the distance to the point at its (u,v), less where a projection finds a nearer point (the
      // p-curve's (u,v) can map farther than the node is: on the M6's tip, 2.3e-4 against 9e-6,
      // which let centroids 0.0304 of their edge off pass a bound of 0.029). Any surface point
      // bounds the distance, so even a projection that ends outside the domain may lower it.
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
    for (int t : bad) {
      if (T_.tris[t].dead) continue;
      const Triangle tr = T_.tris[t];
      if (deviation(tr.v[0], tr.v[1], tr.v[2]) <= allowedDeviation(tr.v[0], tr.v[1], tr.v[2])) continue;
      // a flip that lines an edge up with a fold, where the other diagonal runs across it (only
      // under the curvature bound: elsewhere the bounds are the nearest-face check's, and the
      // benchmark's default meshes stay as they were)
      if (devRatio_ > 0 && flipForDeviation(t)) {
        ++done;
        continue;
      }
      // the free edge with the largest sag (estimated from the vertex normals), else the longest:
      // across a cone's apex the sag is on the edge opposite the apex, not on the longer sides
      auto pick = [&](bool belowFloor) {
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
      };
      int best = pick(false);
      // across a fold much narrower than the edge, the surface runs far from the chord at the
      // fold's crest only, and the chord's projected midpoint lands on a flank: split at the crest
      Vec2 crest;
      // (not on an edge from a crest vertex: that crest is lined already, and the surface curving
      // away from the chord towards it is its flank's, for a plain split; on propeller_and_shaft
      // with embedded crests, such crest splits were refused next to the crest and left 28
      // triangles beyond the bound against 18, by the run report)
      auto fromCrest = [&](int i) { return ((T_.verts[tr.v[nx(i)]].flags | T_.verts[tr.v[pv(i)]].flags) & VF_CREST) != 0; };
      bool ridge = devRatio_ > 0 && best >= 0 && !fromCrest(best) && ridgePoint(tr.v[nx(best)], tr.v[pv(best)], crest);
      // an edge below the floor may still be split at a crease's crest (kCreaseScale), unless the
      // floor is the user's min-size (setMinSizeReach): that lines the mesh up with the fold, it
      // does not refine it (propeller_and_shaft's blade tips, where
      // the fold's radius falls far below min-size / angle: with collapseForDeviation, the run
      // report's triangles beyond the bound went from 60 to 34, fidelity_check's on the blade
      // faces from 54 to 30)
      if (devRatio_ > 0 && reach_ == 0 && !ridge) {
        const int s = pick(true);
        if (s >= 0 && s != best && !fromCrest(s) && ridgePoint(tr.v[nx(s)], tr.v[pv(s)], crest) &&
            maxCurvature(C_.surf, C_.toParam(crest)) * minEdge > kCreaseScale) {
          best = s;
          ridge = true;
        }
      }
      // A refused crest split is not replaced by the midpoint split (which lands on a flank):
      // measured on propeller_and_shaft's blade Faces 7 and 10, that fallback left 74 triangles
      // beyond the bound against 70. A fold flip that the quality swaps undo can come back in
      // the next round; the rounds are bounded (10).
      if (best >= 0 && splitEdge(t, best, true, ridge ? &crest : nullptr) >= 0) {
        ++done;
        continue;
      }
      // on a fold already lined with crest vertices: a vertex left next to the crest goes
      if (devRatio_ > 0 && collapseForDeviation(t)) {
        ++done;
        continue;
      }
      // no edge to split (all on the boundary, from a pole or too short), or its split refused:
      // insert the (projected) centroid, unless the triangle is already at the smallest size.
      // Under the user's bounds (not the nearest-face zones alone, whose meshes stay as they
      // were) that floor holds after a refused split too: without it, refused splits became
      // centroid insertions that went on below the floor, leaving triangles beyond the bound all
      // the same (propeller_and_shaft --curvature-angle 10: 84 triangles beyond it, 60 with it,
      // by the run report; a torus tube of radius 0.5 at min-size 1: edges down to 0.009)
      if ((best < 0 || devRatio_ > 0 || maxDev_ > 0) && minEdge > 0) {
        const Vec3 &A = T_.verts[tr.v[0]].xyz, &B = T_.verts[tr.v[1]].xyz, &Cc = T_.verts[tr.v[2]].xyz;
        if (std::min({dist(A, B), dist(B, Cc), dist(Cc, A)}) < 2.0 * minEdge) continue;
      }
      const Vec2 s0 = (1.0 / 3) * (T_.verts[tr.v[0]].uv + T_.verts[tr.v[1]].uv + T_.verts[tr.v[2]].uv);
      if (!C_.inDomain(s0)) continue;
      int e = -1;
      const int where = T_.locate(s0, t, &e, Triangulation::kLocalWalk);
      if (where < 0 || (e >= 0 && T_.isConstrained(where, e)) || !T_.insertionIsValid(s0, where, e)) continue;
      TriVertex P = C_.makeVertex(s0);
      {
        const Vec3 &A = T_.verts[tr.v[0]].xyz, &B = T_.verts[tr.v[1]].xyz, &Cc = T_.verts[tr.v[2]].xyz;
        if (T_.insertionClearance(P.xyz, where, e) < Triangulation::kInsertClearance * std::max({dist(A, B), dist(B, Cc), dist(Cc, A)}))
          continue;
      }
      if (e < 0) {  // as for the splits: no new triangle facing away from the surface
        const Triangle& W = T_.tris[where];
        const TriVertex &A = T_.verts[W.v[0]], &B = T_.verts[W.v[1]], &D = T_.verts[W.v[2]];
        if (!facesAway(A, B, D) && (facesAway(A, B, P) || facesAway(B, D, P) || facesAway(D, A, P))) continue;
        // nor one lying on a flank but upside down (where the triangle split runs across a fold,
        // facesAway's summed normals can miss it)
        if (devRatio_ > 0 && (inverted(A, B, P) || inverted(B, D, P) || inverted(D, A, P))) continue;
      }
      const int v = T_.addVertex(P);
      const Triangulation::FlipTest none = [](int, int) { return false; };
      T_.insert(v, where, e, none, nullptr);
      ++done;
    }
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

double Optimizer::edgeRatio(int a, int b) const {
  const TriVertex &A = T_.verts[a], &B = T_.verts[b];
  return dist(A.xyz, B.xyz) / (0.5 * (A.h + B.h));
}

bool Optimizer::flipAllowed(int a, int b, int c, int d) const {
  if (!valid(a, b, d) || !valid(a, d, c)) return false;
  const TriVertex &A = T_.verts[a], &B = T_.verts[b], &Cc = T_.verts[c], &D = T_.verts[d];
  // crease guard: do not fold the pair more than it is, beyond 10 degrees
  const Vec3 n0 = normalized(cross(B.xyz - A.xyz, Cc.xyz - A.xyz));
  const Vec3 n1 = normalized(cross(Cc.xyz - D.xyz, B.xyz - D.xyz));
  const Vec3 m0 = normalized(cross(B.xyz - A.xyz, D.xyz - A.xyz));
  const Vec3 m1 = normalized(cross(D.xyz - A.xyz, Cc.xyz - A.xyz));
  if (dot(m0, m1) < std::min(dot(n0, n1), 0.984807753) - 1e-9) return false;
  if (deviationBounded()) {
    // the new pair keeps its own bounds, or deviates no more than an old triangle that already
    // broke its bound did (before, the old pair's estimated deviation, from the vertex normals,
    // was allowed: it can run above a bound the pair meets, and a pair outside a zone has none,
    // so flips broke zone bounds)
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
  // An edge is seen from both of its triangles. Seen again from the later one, unflipped, with
  // neither triangle changed since the earlier one's last scan, it would get the same answer (up
  // to rounding: from the other side the quad's corners are relabelled): skip it. scanned[t]: the
  // flip count when t's scan ended (-1: not scanned yet, so every later triangle); changed[t]:
  // the flip count of the flip that last rewrote t.
  std::vector<int> scanned(T_.tris.size(), -1), changed(T_.tris.size(), 0);
  for (int t = 0; t < (int)T_.tris.size(); ++t) {
    poll(t);
    if (T_.tris[t].dead || !triInRegion(t)) continue;
    for (int i = 0; i < 3; ++i) {
      const Triangle& tr = T_.tris[t];
      const int u = tr.n[i];
      if (u < 0 || T_.isConstrained(t, i)) continue;
      if (std::max(changed[t], changed[u]) <= scanned[u]) continue;
      const int j = T_.edgeTo(u, t);
      if (j < 0) continue;
      const int a = tr.v[i], b = tr.v[nx(i)], c = tr.v[pv(i)], d = T_.tris[u].v[j];
      const double q0 = std::min(qual(t), qual(u));
      const TriVertex &A = T_.verts[a], &B = T_.verts[b], &Cc = T_.verts[c], &D = T_.verts[d];
      const double q1 = std::min(gamma3(A.xyz, B.xyz, D.xyz), gamma3(A.xyz, D.xyz, Cc.xyz));
      if (!(q1 > q0 + 1e-6)) continue;
      if (!flipAllowed(a, b, c, d)) continue;
      if (T_.flip(t, i)) {
        q[t] = q[u] = std::numeric_limits<double>::quiet_NaN();
        for (int v : {a, b, c, d}) {
          addToRegion(v);
          touch(v);
        }
        ++flips;
        changed[t] = changed[u] = flips;
        i = -1;  // triangle t changed: rescan its edges
      }
    }
    scanned[t] = flips;
  }
  return flips;
}

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
    sum += 0.5 * (x + y) + (0.8660254037844386 * dist(x, y)) * normalized(cross(V.normal, y - x));
  }
  return sum * (1.0 / ring_.size());
}

Optimizer::RingStats Optimizer::ringStats() const {
  // quality(t) and the smallest angle's sine from one set of sides (the smoothing's hottest loop
  // computed the lengths and the area twice)
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

int Optimizer::lengthPass() {
  constexpr double kLo = 0.72, kHi = 1.40;
  int moved = 0;
  std::vector<int> link;
  for (int v = 0; v < (int)T_.verts.size(); ++v) {
    poll(v);
    if (!inRegion(v) || !movableWithRing(v)) continue;
    const TriVertex& V = T_.verts[v];
    link.clear();
    for (int t : ring_) link.push_back(T_.tris[t].v[nx(T_.indexOf(t, v))]);
    auto outOfBand = [&]() {
      int n = 0;
      for (int w : link) {
        const double r = edgeRatio(v, w);
        n += (r < kLo || r > kHi) ? 1 : 0;
      }
      return n;
    };
    const int bad0 = outOfBand();
    if (bad0 == 0) continue;
    // push away from the too near neighbours, pull towards the too far ones
    Vec3 step{0, 0, 0};
    for (int w : link) {
      const TriVertex& W = T_.verts[w];
      const double h = 0.5 * (V.h + W.h), l = dist(V.xyz, W.xyz);
      if (!(l > 0)) continue;
      const Vec3 u = (1.0 / l) * (V.xyz - W.xyz);
      if (l < kLo * h) step += (kLo * 1.02 * h - l) * u;
      if (l > kHi * h) step += (l - kHi * 0.98 * h) * (-1.0 * u);
    }
    if (!(norm2(step) > 0)) continue;
    const RingStats r0 = ringStats();
    if (tryMove(v, V.xyz + step, [&](const RingStats& r1) {
          return outOfBand() < bad0 && r1.sumQ >= 0.98 * r0.sumQ && (r1.minSin >= 0.5 || r1.minSin >= r0.minSin);
        }))
      ++moved;
  }
  return moved;
}

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
  for (int t = 0; t < (int)T_.tris.size(); ++t) {
    poll(t);
    if (T_.tris[t].dead || !triInRegion(t)) continue;
    for (int i = 0; i < 3; ++i) {
      const Triangle& tr = T_.tris[t];
      const int u = tr.n[i];
      if (u < 0 || T_.isConstrained(t, i)) continue;
      const int j = T_.edgeTo(u, t);
      if (j < 0) continue;
      const int a = tr.v[i], b = tr.v[nx(i)], c = tr.v[pv(i)], d = T_.tris[u].v[j];
      // the flip removes edge (b,c) and adds (a,d)
      const int before = dev(a, cnt[a]) + dev(b, cnt[b]) + dev(c, cnt[c]) + dev(d, cnt[d]);
      const int after = dev(a, cnt[a] + 1) + dev(b, cnt[b] - 1) + dev(c, cnt[c] - 1) + dev(d, cnt[d] + 1);
      if (after >= before) continue;
      const double q0 = std::min(quality(t), quality(u));
      const TriVertex &A = T_.verts[a], &B = T_.verts[b], &Cc = T_.verts[c], &D = T_.verts[d];
      const double q1 = std::min(gamma3(A.xyz, B.xyz, D.xyz), gamma3(A.xyz, D.xyz, Cc.xyz));
      if (!(q1 >= qFactor * q0)) continue;
      if (!flipAllowed(a, b, c, d)) continue;
      if (T_.flip(t, i)) {
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
        i = -1;
      }
    }
  }
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
  constexpr double kLo = 0.72, kHi = 1.40;
  // least gain in the ring's summed radius ratio worth a move: below it were three quarters of
  // the moves but 12-25 % of the gain (small-edges-01 d/100, boxed_sphere d/100), and each move
  // costs a projection on the surface
  constexpr double kMinGain = 1e-3;
  // the ring's worst triangle may get worse only while it stays above this (smoothPass's "good"):
  // with 0.5, a sum-raising move on ANC101 (local size on Face15) left a 0.78 triangle 1.77 times
  // the size of its neighbour, the worst growth of test_local_size.py's graded zone
  constexpr double kKeepAbove = 0.8;
  std::vector<char> next(T_.verts.size(), 0);
  std::vector<int> link;
  std::vector<Vec3> far;  // the two other corners of each triangle of the ring
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
    if (pole) continue;  // quality() counts pole triangles as 1: the plain sum below would not
    const int n = (int)ring_.size();
    L /= (double)n;
    auto sumQ = [&](Vec3 x, double* minQ = nullptr) {
      double sum = 0, mn = 1e300;
      for (int k = 0; k < n; ++k) {
        const double q = gamma3(x, far[2 * k], far[2 * k + 1]);
        sum += q;
        mn = std::min(mn, q);
      }
      if (minQ) *minQ = mn;
      return sum;
    };
    double minQ0;
    const double f0 = sumQ(V.xyz, &minQ0);
    if (n - f0 < kMinGain) continue;  // the ring cannot gain more than it lacks
    // one Newton step in the tangent plane, from differences over 1 % of the ring's edge length
    // (the surface's curvature over the step is second order, and tryMove projects the result);
    // a second step gained nothing measurable on small-edges-01
    Vec3 e1 = cross(V.normal, Vec3{1, 0, 0});
    if (norm2(e1) < 0.1) e1 = cross(V.normal, Vec3{0, 1, 0});
    if (!(norm2(e1) > 0)) continue;
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
      if (0.5 * (gx * sx + gy * sy) < 0.5 * kMinGain) continue;  // predicted gain: too small
    } else {  // not concave here: a short step up the gradient
      const double g = std::hypot(gx, gy);
      if (!(g > 0)) continue;
      sx = 0.05 * L * gx / g;
      sy = 0.05 * L * gy / g;
    }
    const double sl = std::hypot(sx, sy);
    if (sl > 0.2 * L) {
      sx *= 0.2 * L / sl;
      sy *= 0.2 * L / sl;
    }
    // the step, or half or a quarter of it, whichever first gains without taking the ring's
    // worst triangle below min(its old value, kKeepAbove)
    const double floorQ = std::min(minQ0, kKeepAbove);
    Vec3 best = V.xyz;
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
    if (!(fb > f0 + kMinGain)) continue;
    auto outOfBand = [&]() {
      int c = 0;
      for (int w : link) {
        const double r = edgeRatio(v, w);
        c += (r < kLo || r > kHi) ? 1 : 0;
      }
      return c;
    };
    const RingStats r0 = ringStats();
    const int bad0 = outOfBand();
    if (tryMove(v, best, [&](const RingStats& r1) {
          return r1.sumQ > r0.sumQ + 1e-9 && r1.minQ >= std::min(r0.minQ, kKeepAbove) &&
                 (r1.minSin >= 0.5 || r1.minSin >= r0.minSin) && outOfBand() <= bad0;
        })) {
      ++moved;
      for (int w : link) next[w] = 1;
    }
  }
  active = std::move(next);
  return moved;
}

int Optimizer::splitPass(double longRatio) {
  struct Cand {
    double r;
    int t, i;
  };
  std::vector<Cand> cands;
  for (int t = 0; t < (int)T_.tris.size(); ++t) {
    if (T_.tris[t].dead) continue;
    for (int i = 0; i < 3; ++i) {
      const Triangle& tr = T_.tris[t];
      if (T_.isConstrained(t, i)) continue;
      if (tr.n[i] >= 0 && tr.n[i] < t) continue;
      const double r = edgeRatio(tr.v[nx(i)], tr.v[pv(i)]);
      if (r > longRatio) cands.push_back({r, t, i});
    }
  }
  std::sort(cands.begin(), cands.end(), [](const Cand& a, const Cand& b) { return a.r > b.r; });
  int splits = 0;
  for (const Cand& c : cands) {
    if (T_.tris[c.t].dead) continue;
    // the edge may have changed since collection: check it again
    const Triangle& tr = T_.tris[c.t];
    const int a = tr.v[nx(c.i)], b = tr.v[pv(c.i)];
    if (T_.isConstrained(c.t, c.i) || edgeRatio(a, b) <= longRatio) continue;
    if (splitEdge(c.t, c.i) >= 0) ++splits;
  }
  return splits;
}

int Optimizer::splitEdge(int t, int i, bool keepFacing, const Vec2* at) {
  if (T_.isConstrained(t, i)) return -1;
  const Triangle& tr = T_.tris[t];
  const int a = tr.v[nx(i)], b = tr.v[pv(i)], c = tr.v[i], u = tr.n[i];
  const Vec2 m = at ? *at : 0.5 * (T_.verts[a].uv + T_.verts[b].uv);
  if (!C_.inDomain(m)) return -1;
  // The new triangles (c, a, m), (c, m, b) and, across the edge, (d, b, m), (d, m, a) must be
  // valid in (u,v) (exact orient2d). Even the (u,v) midpoint can fail: where a swap has rebuilt
  // the edge over the vertex an earlier split put at that very midpoint (a triangle a-m-b of
  // rounding-error area in (u,v), valid in 3D on a strongly folded surface), the split would put
  // a second vertex on the first (propeller_and_shaft's blade folds, --curvature-angle 10).
  if (!T_.insertionIsValid(m, t, i)) return -1;
  TriVertex nv = C_.makeVertex(m);
  int d = -1;
  if (u >= 0)
    for (int k = 0; k < 3; ++k)
      if (T_.tris[u].v[k] != a && T_.tris[u].v[k] != b) d = T_.tris[u].v[k];
  // the 3D midpoint of the chord, projected, is a better split point on curved faces: use it
  // when it keeps the new triangles valid in (u,v) too
  if (!C_.planar && !at) {
    Vec2 s = m;
    Vec3 p;
    if (C_.project(0.5 * (T_.verts[a].xyz + T_.verts[b].xyz), s, p) && C_.inDomain(s) &&
        T_.insertionIsValid(s, t, i)) {
      nv.uv = s;
      nv.xyz = p;
      C_.fill(nv);
    }
  }
  // A crest split of an edge whose ends lie on the two flanks of a fold: the new vertex is on the
  // crest, where the surface normal turns over a width far below the mesh size; it keeps no normal
  // (the triangles on each flank are judged by their flank vertices) and stays where it is
  if (at && acrossFold(T_.verts[a], T_.verts[b])) {
    nv.normal = Vec3{0, 0, 0};
    nv.flags |= VF_CREST;
  }
  // Nor where the surface is so unevenly parametrised that the split point, in 3D, all but
  // lands on an end of the edge (the edge would not get shorter, and the refinement that asked
  // for the split would ask again) or on a vertex opposite: on propeller_and_shaft's blade folds
  // (--curvature-angle 10) such splits stacked clusters of nodes within 1e-6 of each other
  {
    const double l = dist(T_.verts[a].xyz, T_.verts[b].xyz);
    if (std::min(dist(nv.xyz, T_.verts[a].xyz), dist(nv.xyz, T_.verts[b].xyz)) < kMinSplitShare * l ||
        T_.insertionClearance(nv.xyz, t, i) < Triangulation::kInsertClearance * l)
      return -1;
  }
  if (at) {
    // no collinear triangle (kFoldMinQuality)
    const Vec3 &A = T_.verts[a].xyz, &B = T_.verts[b].xyz, &Cc = T_.verts[c].xyz;
    double q0 = quality(t), q1 = std::min(gamma3(Cc, A, nv.xyz), gamma3(Cc, nv.xyz, B));
    if (d >= 0) {
      const Vec3& D = T_.verts[d].xyz;
      q0 = std::min(q0, quality(u));
      q1 = std::min({q1, gamma3(D, B, nv.xyz), gamma3(D, nv.xyz, A)});
    }
    if (q1 < std::min(q0, kFoldMinQuality)) return -1;
    const double l = dist(A, B);
    const double share = (nv.flags & VF_CREST) ? kCrestShareFold : kCrestShare;
    if (dist(nv.xyz, Cc) < share * l || (d >= 0 && dist(nv.xyz, T_.verts[d].xyz) < share * l)) return -1;
  }
  if (keepFacing) {
    // the split must not turn a triangle that faces like the surface into ones that face away
    // (across a nose far smaller than the triangle, the midpoint can land on the other side)
    const TriVertex &A = T_.verts[a], &B = T_.verts[b], &Cc = T_.verts[c];
    // a new triangle on the crest whose other corners lie on the fold's two flanks still runs
    // across the fold; the crest split of its other edge resolves it, so its facing is not judged
    auto away = [&](const TriVertex& P, const TriVertex& Q, const TriVertex& R) {
      if (nv.flags & VF_CREST) {
        const TriVertex* o[3];
        int k = 0;
        for (const TriVertex* x : {&P, &Q, &R})
          if (!(x->flags & VF_CREST)) o[k++] = x;
        if (k == 2 && acrossFold(*o[0], *o[1])) return false;
      }
      return facesAway(P, Q, R);
    };
    if (!facesAway(Cc, A, B) && (away(Cc, A, nv) || away(Cc, nv, B))) return -1;
    if (d >= 0) {
      const TriVertex& D = T_.verts[d];
      if (!facesAway(D, B, A) && (away(D, B, nv) || away(D, nv, A))) return -1;
    }
    // never a triangle lying on a flank upside down
    if (devRatio_ > 0) {
      if (inverted(Cc, A, nv) || inverted(Cc, nv, B)) return -1;
      if (d >= 0 && (inverted(T_.verts[d], B, nv) || inverted(T_.verts[d], nv, A))) return -1;
    }
  }
  const int v = T_.addVertex(nv);
  const Triangulation::FlipTest none = [](int, int) { return false; };
  T_.insert(v, t, i, none, nullptr);
  return v;
}

bool Optimizer::collapse(int t, int i, bool centroidFacing) {
  // collapse edge i of t = (a -> b), where a = v[nx(i)] must be free; b may be anything
  Triangle& tr = T_.tris[t];
  const int a = tr.v[nx(i)], b = tr.v[pv(i)];
  const int u = tr.n[i];
  if (u < 0) return false;
  // ring of a
  bool closed = true;
  std::vector<int> ra;
  T_.ring(a, ra, &closed);
  if (!closed) return false;
  // link condition: common neighbours of a and b are exactly the two opposite vertices
  std::vector<int> na, nb;
  for (int r : ra) {
    int k = T_.indexOf(r, a);
    na.push_back(T_.tris[r].v[nx(k)]);
  }
  std::vector<int> rb;
  bool closedB = true;
  T_.ring(b, rb, &closedB);
  for (int r : rb) {
    int k = T_.indexOf(r, b);
    nb.push_back(T_.tris[r].v[nx(k)]);
    nb.push_back(T_.tris[r].v[pv(k)]);
  }
  std::sort(na.begin(), na.end());
  std::sort(nb.begin(), nb.end());
  nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
  int common = 0;
  for (int x : na)
    if (std::binary_search(nb.begin(), nb.end(), x)) ++common;
  if (common != 2) return false;
  // validity of the relabelled triangles
  for (int r : ra) {
    if (r == t || r == u) continue;
    const Triangle& R = T_.tris[r];
    int k = T_.indexOf(r, a);
    int v0 = R.v[0], v1 = R.v[1], v2 = R.v[2];
    if (k == 0) v0 = b;
    if (k == 1) v1 = b;
    if (k == 2) v2 = b;
    if (!valid(v0, v1, v2) && !(centroidFacing && facesAtCentroid(v0, v1, v2))) return false;
    if (deviationBounded() && !deviationOk(v0, v1, v2, 0)) return false;
  }
  // relink around the two dying triangles
  for (int dying : {t, u}) {
    const Triangle& D = T_.tris[dying];
    const int ka = T_.indexOf(dying, a), kb = T_.indexOf(dying, b);
    // edge opposite b contains a (and x); edge opposite a contains b (and x)
    const int nA = D.n[kb];  // across (a,x): will be relabelled to (b,x)
    const int nB = D.n[ka];  // across (x,b)
    const bool cA = T_.isConstrained(dying, kb), cB = T_.isConstrained(dying, ka);
    const int x = D.v[3 - ka - kb];
    if (nA >= 0) {
      int e = T_.edgeTo(nA, dying);
      T_.tris[nA].n[e] = nB;
      if (cA || cB) T_.tris[nA].cons |= (uint8_t)(1u << e);
    }
    if (nB >= 0) {
      int e = T_.edgeTo(nB, dying);
      T_.tris[nB].n[e] = nA;
      if (cA || cB) T_.tris[nB].cons |= (uint8_t)(1u << e);
    }
    T_.verts[x].tri = nA >= 0 ? nA : nB;
    T_.verts[b].tri = nA >= 0 ? nA : nB;
  }
  for (int r : ra) {
    if (r == t || r == u) continue;
    int k = T_.indexOf(r, a);
    T_.tris[r].v[k] = b;
    T_.verts[b].tri = r;
  }
  T_.tris[t].dead = true;
  T_.tris[u].dead = true;
  T_.verts[a].flags |= VF_DEAD;
  T_.verts[a].tri = -1;
  return true;
}

int Optimizer::collapsePass(double shortRatio, double maxRatio) {
  int n = 0;
  for (int t = 0; t < (int)T_.tris.size(); ++t) {
    poll(t);
    if (T_.tris[t].dead) continue;
    for (int i = 0; i < 3; ++i) {
      const Triangle& tr = T_.tris[t];
      if (T_.isConstrained(t, i) || tr.n[i] < 0) continue;
      int a = tr.v[nx(i)], b = tr.v[pv(i)];
      if (edgeRatio(a, b) >= shortRatio) continue;
      // collapse the free vertex onto the other one
      auto freeV = [&](int v) { return !(T_.verts[v].flags & VF_FIXED); };
      int tt = t, ii = i;
      if (!freeV(a)) {
        if (!freeV(b)) continue;
        // orient so that the free vertex is v[nx(i)]: use the neighbour triangle
        tt = tr.n[i];
        ii = T_.edgeTo(tt, t);
        std::swap(a, b);
      }
      // new edges around b must not get too long
      std::vector<int> ra;
      T_.ring(a, ra);
      bool tooLong = false;
      for (int r : ra) {
        const Triangle& R = T_.tris[r];
        for (int k = 0; k < 3; ++k) {
          int w = R.v[k];
          if (w == a || w == b) continue;
          const TriVertex &B = T_.verts[b], &W = T_.verts[w];
          if (dist(B.xyz, W.xyz) / (0.5 * (B.h + W.h)) > maxRatio) tooLong = true;
        }
      }
      if (tooLong) continue;
      if (collapse(tt, ii)) {
        ++n;
        break;
      }
    }
  }
  return n;
}

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
      const double ideal = 0.8660254037844386 * std::min(h, 1.5 * base);
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
  if (poleCollapsed(a, b, c)) return false;
  return sinMinAngle(a.xyz, b.xyz, c.xyz) < 0.5;  // smallest angle below 30 degrees
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
        const double a = dir * 0.7853981633974483;
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
    if (dot(m0, m1) < 0.984807753) continue;  // crease guard (10 degrees)
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

int Optimizer::countPoorAngles() const { return countPoorAngles(T_, region_); }

int Optimizer::countPoorAngles(const Triangulation& T, const std::vector<char>& region) {
  auto in = [&](int v) { return region.empty() || v >= (int)region.size() || region[v]; };
  int n = 0;
  for (const Triangle& tr : T.tris) {
    if (tr.dead || !(in(tr.v[0]) || in(tr.v[1]) || in(tr.v[2]))) continue;
    const TriVertex &a = T.verts[tr.v[0]], &b = T.verts[tr.v[1]], &c = T.verts[tr.v[2]];
    if (poleCollapsed(a, b, c)) continue;
    if (sinMinAngle(a.xyz, b.xyz, c.xyz) < 0.5) ++n;
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

int Optimizer::splitLongestFree(int t) {
  const Triangle& tr = T_.tris[t];
  int best = -1;
  double bl = -1;
  for (int i = 0; i < 3; ++i) {
    if (T_.isConstrained(t, i) || tr.n[i] < 0) continue;
    const double l = dist(T_.verts[tr.v[nx(i)]].xyz, T_.verts[tr.v[pv(i)]].xyz);
    if (l > bl) {
      bl = l;
      best = i;
    }
  }
  return best >= 0 ? splitEdge(t, best) : -1;
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

int Optimizer::collapsePoorApexes() {
  std::vector<int> cands;
  for (int t = 0; t < (int)T_.tris.size(); ++t)
    if (!T_.tris[t].dead && poorAngle(t)) cands.push_back(t);
  int n = 0;
  for (int t : cands)
    if (!T_.tris[t].dead && poorAngle(t) && collapseApex(t)) ++n;
  return n;
}

bool Optimizer::collapseApex(int t) {
  // free vertices by decreasing angle (a cap's apex stands on the opposite edge), each collapsed
  // onto a neighbour in t, the nearer first
  const Triangle tr = T_.tris[t];
  std::array<std::pair<double, int>, 3> byAngle;
  for (int j = 0; j < 3; ++j) {
    const Vec3 p = T_.verts[tr.v[j]].xyz;
    const Vec3 u = normalized(T_.verts[tr.v[nx(j)]].xyz - p), w = normalized(T_.verts[tr.v[pv(j)]].xyz - p);
    byAngle[j] = {dot(u, w), j};  // cosine: smallest first = largest angle first
  }
  std::sort(byAngle.begin(), byAngle.end());
  for (const auto& ba : byAngle) {
    const int k = ba.second;
    const int vk = tr.v[k];
    if (T_.verts[vk].flags & VF_FIXED) continue;
    // its two edges in t (edge e contains k when e != k), shorter first
    int e1 = nx(k), e2 = pv(k);
    const double l1 = dist(T_.verts[vk].xyz, T_.verts[tr.v[pv(k)]].xyz);  // edge nx(k) = (k, pv(k))
    const double l2 = dist(T_.verts[vk].xyz, T_.verts[tr.v[nx(k)]].xyz);  // edge pv(k) = (nx(k), k)
    if (l2 < l1) std::swap(e1, e2);
    for (int i : {e1, e2}) {
      if (T_.isConstrained(t, i)) continue;
      int tt = t, ii = i;
      if (tr.v[nx(i)] != vk) {
        tt = tr.n[i];
        if (tt < 0) continue;
        ii = T_.edgeTo(tt, t);
        if (ii < 0 || T_.tris[tt].v[nx(ii)] != vk) continue;
      }
      if (collapse(tt, ii, true)) return true;
    }
  }
  return false;
}

void Optimizer::run(int passes) {
  if (passes <= 0) return;
  splitPass(1.6);
  collapsePass(0.55, 1.3);
  // the first smoothing pass tries every vertex, the next ones those touched since
  touched_.assign(T_.verts.size(), 1);
  std::vector<char> active;
  for (int p = 0; p < passes; ++p) {
    int f = swapPass();
    active.swap(touched_);
    touched_.assign(T_.verts.size(), 0);
    int m = smoothPassOver(&active);
    if (f == 0 && m == 0) break;
  }
  touched_.clear();
  swapPass();
  repairFrontApexes(0.8);
}

}  // namespace paramesh
