// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file OptimizerDetail.hpp
/// Internal to the Optimizer's operator files (src/paramesh/algo/optimizer/*.cpp): the small
/// triangle predicates, tuning constants and edge sweep that more than one operator shares.
#pragma once
#include "paramesh/algo/Triangulation.hpp"
#include "paramesh/algo/optimizer/Optimizer.hpp"

namespace paramesh {

template <class Visit, class Done>
void Optimizer::sweepFreeEdges(Visit&& visit, Done&& done) {
  for (int t = 0; t < (int)T_.tris.size(); ++t) {
    poll(t);
    if (T_.tris[t].dead || !triInRegion(t)) continue;
    for (int i = 0; i < 3; ++i) {
      int u, a, b, c, d;
      if (edgeQuad(t, i, u, a, b, c, d) && visit(t, i, u, a, b, c, d)) i = -1;  // t rewritten: rescan
    }
    done(t);
  }
}

}  // namespace paramesh

namespace paramesh::optimizer_detail {

/// The next and the previous corner of a triangle (edge i is opposite corner i).
inline int nx(int i) { return i == 2 ? 0 : i + 1; }
inline int pv(int i) { return i == 0 ? 2 : i - 1; }

/// A triangle with two corners on one pole node: collapsed in 3D by construction, not a defect.
inline bool poleCollapsed(const TriVertex& a, const TriVertex& b, const TriVertex& c) {
  return ((a.flags | b.flags | c.flags) & VF_POLE) &&
         ((a.node >= 0 && (a.node == b.node || a.node == c.node)) || (b.node >= 0 && b.node == c.node));
}

/// A triangle that faces away from the surface: its normal opposes the sum of its vertices' normals.
inline bool facesAway(const TriVertex& p, const TriVertex& q, const TriVertex& r) {
  return dot(cross(q.xyz - p.xyz, r.xyz - p.xyz), p.normal + q.normal + r.normal) < 0;
}

/// A triangle on one side of the surface that faces away from it: its normal opposes every vertex
/// normal it has, and those agree among themselves (across a fold, vertex normals on its two flanks
/// oppose each other and leave a triangle's facing undecided).
inline bool inverted(const TriVertex& p, const TriVertex& q, const TriVertex& r) {
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

/// An edge whose ends' normals oppose each other runs across a fold.
inline bool acrossFold(const TriVertex& p, const TriVertex& q) { return dot(p.normal, q.normal) < 0; }

/// Height of the equilateral triangle on a unit base (sqrt(3) / 2).
inline constexpr double kEquilateralHeight = 0.8660254037844386;

/// Size conformity band of an edge's length over the local size: the unit band [1/sqrt2, sqrt2]
/// with a margin (lengthPass moves vertices into it; polishPass lets no edge leave it).
inline constexpr double kBandLo = 0.72;
inline constexpr double kBandHi = 1.40;

/// A crest split lies at least this share of the edge's 3D length from the edge's ends and from
/// the vertices opposite it (a crest near one of them is that vertex's, for a flip, to resolve).
inline constexpr double kCrestShare = 0.25;
/// The same share across a fold whose flanks face opposite ways (the ends' normals more than 90
/// degrees apart): there no flip lines an edge up with the crest, so the crest is split even near
/// a vertex (where a fold closes into a cusp; measured: docs/tuning/optimizer.md).
inline constexpr double kCrestShareFold = 0.1;

/// Flips and crest splits for folds make no triangle below this quality that is worse than the
/// worst they replace (no collinear triangle).
inline constexpr double kFoldMinQuality = 1e-3;

}  // namespace paramesh::optimizer_detail
