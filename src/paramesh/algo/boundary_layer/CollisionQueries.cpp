// SPDX-License-Identifier: LGPL-2.1-or-later
// What a column's step or a new row meets: the face's boundary (its loops' chords and points) and
// the runs grown before (their points and grids, kept in SegmentBuckets), for the stop rules.

#include "paramesh/algo/boundary_layer/FaceLayers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "paramesh/algo/Predicates.hpp"

namespace paramesh::bl_detail {

bool FaceLayers::crossesLoops(Vec2 a, Vec2 b, int skipLoop, int skipA, int skipB) const {
  const double x0 = std::min(a.x, b.x), x1 = std::max(a.x, b.x), y0 = std::min(a.y, b.y), y1 = std::max(a.y, b.y);
  for (size_t L = 0; L < loops_.size(); ++L) {
    const auto& lp = loops_[L];
    const int n = (int)lp.size();
    for (int i = 0; i < n; ++i) {
      if ((int)L == skipLoop && (i == skipA || i == skipB)) continue;
      const Vec2 c = lp[i].uv, d = lp[(i + 1) % n].uv;
      if (std::max(c.x, d.x) < x0 || std::min(c.x, d.x) > x1 || std::max(c.y, d.y) < y0 ||
          std::min(c.y, d.y) > y1)
        continue;
      if (segmentsCross(a, b, c, d)) return true;
    }
  }
  return false;
}

/// Only segments within r of x are sure to count: farther ones may or may not (infinity when
/// none is found).
double FaceLayers::boundaryDistance(Vec3 x, double r, int L, int root, const std::vector<char>& own) const {
  double best = std::numeric_limits<double>::infinity();
  const Vec3 pad{r, r, r};
  loopBuckets_.visit(x - pad, x + pad, [&](int id) {
    const auto [M, i] = loopSegs_[id];
    const auto& lp = loops_[M];
    const int j = (i + 1) % (int)lp.size();
    if (M == L && (i == root || j == root || (own[i] && own[j]))) return;
    best = std::min(best, segmentDistance(x, lp[i].xyz, lp[j].xyz));
  });
  return best;
}

/// Whether a boundary point (a loop point other than the run's own in loop L) lies within d of
/// the row (a, b), farther than d from its ends: a row through a vertex of the boundary touches it without
/// crossing it, and leaves triangles of zero area beside it (a notch's apex exactly one first
/// height above a layer: the bottom layer's first row ran through it).
bool FaceLayers::boundaryPointNear(Vec3 a, Vec3 b, double d, int L, const std::vector<char>& own) const {
  const Vec3 e = b - a;
  const double l2 = norm2(e);
  if (!(l2 > 0)) return false;
  const Vec3 pad{d, d, d};
  bool hit = false;
  loopBuckets_.visit(SegmentBuckets::lo(a, b) - pad, SegmentBuckets::hi(a, b) + pad, [&](int id) {
    const auto [M, i] = loopSegs_[id];  // its first point, which lies in the segment's buckets
    if (hit || (M == L && own[i])) return;
    const Vec3& p = loops_[M][i].xyz;
    const double t = dot(p - a, e) / l2;
    if (t <= 0 || t >= 1) return;
    // a point beside an end is that end column's neighbour (an end column marched along a
    // neighbouring edge runs within a hair of that edge's nodes)
    if (dist(p, a + t * e) < d && std::min(dist(p, a), dist(p, b)) > d) hit = true;
  });
  return hit;
}

/// A step from p to x that heads into the boundary (closing on it by at least half its length)
/// and ends within d of it. A column stopped only when it crosses the boundary can end a hair
/// above it, with triangles of almost 0 and 180 degrees between (measured:
/// docs/tuning/boundary_layer.md). Columns that run beside the boundary (the M6's next to its
/// tip edge, rows taller than their distance to it) go on.
bool FaceLayers::closesOnBoundary(Vec3 p, Vec3 x, double d, int L, int root, const std::vector<char>& own) const {
  const double dx = boundaryDistance(x, d, L, root, own);
  if (!(dx < d)) return false;
  // the distance at p is at most dx + |p - x|: a search of that radius finds it
  const double step = dist(p, x);
  return boundaryDistance(p, dx + step, L, root, own) - dx > 0.5 * step;
}

bool FaceLayers::nearOther(Vec3 x, double d) const {
  for (size_t i = 0; i < otherPts_.size(); ++i)
    if (dist(otherPts_[i], x) < std::max(d, 0.5 * otherH_[i])) return true;
  return false;
}

/// Whether (a, b) (3D chord A B) crosses a column or a row of a run grown before. A column's
/// steps are tested against the other runs' points by distance (nearOther), which a step can
/// pass between two columns of another run without coming near either (a V notch's apex fan
/// ran below the bottom layer's first row); in (u,v), on one face, a crossing is a crossing
/// whatever the spacing. Segments that cross in (u,v) meet on the surface: their chords lie
/// within their sags of each other in 3D, well inside a margin of the step's own length.
bool FaceLayers::crossesOther(Vec2 a, Vec2 b, Vec3 A, Vec3 B) const {
  const double m = dist(A, B);
  const Vec3 pad{m, m, m};
  bool hit = false;
  otherBuckets_.visit(SegmentBuckets::lo(A, B) - pad, SegmentBuckets::hi(A, B) + pad, [&](int id) {
    if (!hit && segmentsCross(a, b, otherSegs_[id].a, otherSegs_[id].b)) hit = true;
  });
  return hit;
}

/// Whether x lies within d of a column or a row of a run grown before (3D distance to the
/// segments). The points alone (nearOther) let a column end just below another run's row
/// between two of its columns, far from both, with triangles of almost 0 and 180 degrees
/// between. The distance is a quarter of the row height (measured: docs/tuning/boundary_layer.md).
bool FaceLayers::nearOtherGrid(Vec3 x, double d) const {
  const Vec3 pad{d, d, d};
  bool hit = false;
  otherBuckets_.visit(x - pad, x + pad, [&](int id) {
    if (!hit && segmentDistance(x, otherSegs_[id].A, otherSegs_[id].B) < d) hit = true;
  });
  return hit;
}

/// Whether a point of a run grown before lies within d of the row (a, b): rows are tested
/// for crossings, yet a row can pass just below another run's front without crossing it, between
/// two of its columns (measured: docs/tuning/boundary_layer.md).
bool FaceLayers::otherPointNearRow(Vec3 a, Vec3 b, double d) const {
  const Vec3 pad{d, d, d};
  bool hit = false;
  otherBuckets_.visit(SegmentBuckets::lo(a, b) - pad, SegmentBuckets::hi(a, b) + pad, [&](int id) {
    if (!hit && (segmentDistance(otherSegs_[id].A, a, b) < d || segmentDistance(otherSegs_[id].B, a, b) < d))
      hit = true;
  });
  return hit;
}

void FaceLayers::addOther(const Seg& g) {
  otherSegs_.push_back(g);
  otherBuckets_.add((int)otherSegs_.size() - 1, g.A, g.B);
}

/// Records a grown run's grid for the collision tests (crossesOther, nearOtherGrid,
/// otherPointNearRow): the segments of its marched columns and its rows above the BL edge (end
/// columns run along the boundary, which crossesLoops guards).
void FaceLayers::recordGrid(const std::vector<Column>& cols, bool closed) {
  const int m = (int)cols.size();
  for (const Column& c : cols)
    if (!c.fixed)
      for (size_t k = 0; k + 1 < c.uv.size(); ++k) addOther({c.uv[k], c.uv[k + 1], c.xyz[k], c.xyz[k + 1]});
  const int pairs = closed ? m : m - 1;
  for (int i = 0; i < pairs; ++i) {
    const Column &A = cols[i], &B = cols[(i + 1) % m];
    const size_t kmax = std::min(A.uv.size(), B.uv.size());
    for (size_t k = 1; k < kmax; ++k) addOther({A.uv[k], B.uv[k], A.xyz[k], B.xyz[k]});
  }
}

}  // namespace paramesh::bl_detail
