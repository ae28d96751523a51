// SPDX-License-Identifier: LGPL-2.1-or-later
// Edge splits: at the surface point of an edge's chord midpoint (size conformity, slivers) or at a
// fold's crest (deviation refinement), refused wherever a new triangle would be invalid or degenerate.

#include "paramesh/algo/optimizer/Optimizer.hpp"

#include <algorithm>
#include <vector>

#include "paramesh/algo/optimizer/OptimizerDetail.hpp"

namespace paramesh {
using namespace optimizer_detail;

namespace {
// a split point must lie at least this share of the edge's 3D length from either end
constexpr double kMinSplitShare = 0.1;
}  // namespace

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
  // valid in (u,v) (exact orient2d): even the (u,v) midpoint can fail, where a swap rebuilt the
  // edge over an earlier split's vertex at that very midpoint (measured: docs/tuning/optimizer.md).
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
  // Nor where the surface is so unevenly parametrised that the split point, in 3D, all but lands
  // on an end of the edge (which would not get shorter, so the refinement would ask again) or on a
  // vertex opposite: such splits stack clusters of nodes (measured: docs/tuning/optimizer.md)
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

}  // namespace paramesh
