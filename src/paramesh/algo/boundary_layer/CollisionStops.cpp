// SPDX-License-Identifier: LGPL-2.1-or-later
// Where columns stop: on a stopped neighbour, at a row that crosses the boundary, meets another run
// or makes an invalid quad, and the safety nets on the front (untangle, needles): tops taken back.

#include "paramesh/algo/boundary_layer/FaceLayers.hpp"

#include <algorithm>
#include <initializer_list>
#include <vector>

#include "paramesh/algo/Predicates.hpp"

namespace paramesh::bl_detail {

/// Step 1b) of layer k: columns converging on a stopped neighbour (a concave corner) stop with it:
/// a new point closer to a stopped top than the row height would fold the front over it.
void FaceLayers::stopAtStoppedNeighbours(std::vector<Column>& cols, bool closed, int k,
                                         std::vector<char>& moved) const {
  const int m = (int)cols.size();
  for (bool again = true; again;) {
    again = false;
    for (int i = 0; i < m; ++i) {
      Column& c = cols[i];
      if (!moved[i]) continue;
      const double h = laws_[c.spec].height(k);
      for (int j : {i - 1, i + 1}) {
        if (!closed && (j < 0 || j >= m)) continue;
        const Column& o = cols[(j + m) % m];
        if (o.active || o.fixed || o.root == c.root || (int)o.xyz.size() > k + 1) continue;  // o stopped below
        if (dist(c.xyz.back(), o.xyz.back()) < 1.5 * h) {
          c.uv.pop_back();
          c.xyz.pop_back();
          c.ref.pop_back();
          c.active = false;
          c.stop = 2;
          moved[i] = 0;
          again = true;
          break;
        }
      }
    }
  }
}

/// Step 2) of layer k: the new quads must be valid, positive in (u,v) and facing like the surface,
/// and their rows must neither cross the boundary nor meet another run.
void FaceLayers::stopAtInvalidRows(int L, std::vector<Column>& cols, bool closed, int k, const std::vector<char>& own,
                                   const std::vector<char>& moved) const {
  const int m = (int)cols.size();
  bool changed = true;
  while (changed) {
    changed = false;
    for (int i = 0; i + 1 < m || (closed && i < m); ++i) {
      const int j = (i + 1) % m;
      Column &A = cols[i], &B = cols[j];
      if ((int)A.uv.size() < k + 2 || (int)B.uv.size() < k + 2) continue;
      if (!(moved[i] || moved[j])) continue;
      if (A.root == B.root && k == 0) continue;  // fan triangle at a shared root
      // the row between two marched columns must not cross the face's boundary either: each
      // column stays inside, yet a corner of a hole can poke between two of them (measured:
      // docs/tuning/boundary_layer.md). An end column's
      // points lie on the boundary: its rows touch it there, which is no crossing (only a
      // proper crossing or a collinear overlap counts)
      const bool crossing = crossesLoops(A.uv[k + 1], B.uv[k + 1], -1, -1, -1) ||
                            boundaryPointNear(A.xyz[k + 1], B.xyz[k + 1], 0.25 * laws_[A.spec].height(k), L, own);
      const bool collision = !crossing && (crossesOther(A.uv[k + 1], B.uv[k + 1], A.xyz[k + 1], B.xyz[k + 1]) ||
                                           otherPointNearRow(A.xyz[k + 1], B.xyz[k + 1], 0.25 * laws_[A.spec].height(k)));
      if (!crossing && !collision &&
          quadValid(A.uv[k], B.uv[k], B.uv[k + 1], A.uv[k + 1], A.xyz[k], B.xyz[k], B.xyz[k + 1], A.xyz[k + 1]))
        continue;
      for (Column* c : {&A, &B}) {
        if (c->fixed || (int)c->uv.size() < k + 2) continue;
        c->uv.pop_back();
        c->xyz.pop_back();
        c->ref.pop_back();
        c->active = false;
        c->stop = crossing ? 1 : collision ? 2 : 3;
        changed = true;
      }
    }
  }
}

bool FaceLayers::quadValid(Vec2 a, Vec2 b, Vec2 c, Vec2 d, Vec3 A, Vec3 B, Vec3 C, Vec3 D) const {
  // both triangulations of the quad positive in (u,v) in the loop's orientation sense
  const int o1 = orient2d(a, b, c), o2 = orient2d(a, c, d), o3 = orient2d(a, b, d), o4 = orient2d(b, c, d);
  const bool pos = o1 > 0 && o2 > 0 && o3 > 0 && o4 > 0;
  const bool neg = o1 < 0 && o2 < 0 && o3 < 0 && o4 < 0;
  if (!pos && !neg) return false;
  // not folded in 3D: the two halves face the same way
  const Vec3 n1 = cross(B - A, C - A), n2 = cross(C - A, D - A);
  if (!(dot(n1, n2) > 0)) return false;
  // and convex in 3D: every corner turns the same way about the quad's normal (a quad convex in
  // (u,v) can have a reflex corner in 3D where the parametrisation is skewed: the ONERA M6's
  // Edge15, at its end column along the tip)
  const Vec3 nq = n1 + n2;
  const Vec3 P[4] = {A, B, C, D};
  for (int i = 0; i < 4; ++i) {
    const Vec3 &p0 = P[(i + 3) % 4], &p1 = P[i], &p2 = P[(i + 1) % 4];
    if (!(dot(cross(p1 - p0, p2 - p1), nq) > 0)) return false;
  }
  return true;
}

/// Safety net: while the front crosses itself (columns converging in a concave corner) or the
/// face's boundary (a stair between columns of different heights past a hole's corner: a
/// nist_ctc_01 slot), the tallest marched column involved loses its top layer.
void FaceLayers::untangle(std::vector<Column>& cols, bool closed) {
  for (int guard = 0; guard < 2000; ++guard) {
    const auto path = frontPath(cols, closed);
    const int n = (int)path.size();
    auto uvOf = [&](int q) { return cols[path[q].first].uv[path[q].second]; };
    // the tallest column with at least one row among the path points qs, end columns
    // (fixed) or marched ones (-1: none)
    auto tallest = [&](std::initializer_list<int> qs, bool fixed) {
      int best = -1;
      for (int q : qs) {
        const Column& c = cols[path[q].first];
        if (c.fixed != fixed || c.xyz.size() < 2) continue;
        if (best < 0 || c.xyz.size() > cols[best].xyz.size()) best = path[q].first;
      }
      return best;
    };
    // a segment between two roots runs along the BL edge, one down an end column along its
    // neighbouring edge: both lie on the boundary, which is no crossing
    int bad = -1, stop = 1;
    for (int i = 0; i + 1 < n && bad < 0; ++i) {
      if (path[i].second == 0 && path[i + 1].second == 0) continue;
      if (path[i].first == path[i + 1].first && cols[path[i].first].fixed) continue;
      // crossing the loops' chords, or standing outside the true boundary (a row between two
      // end columns can leave the face without crossing a chord where the boundary between
      // them is one segment of a curved edge)
      if (!crossesLoops(uvOf(i), uvOf(i + 1), -1, -1, -1) && guard_.inside(0.5 * (uvOf(i) + uvOf(i + 1))))
        continue;
      // the taller marched column of the two; else the taller end column (a BL edge of one
      // segment has only its two end columns, whose rows can run across a hole; measured:
      // docs/tuning/boundary_layer.md): its top stays a plain point of the neighbouring edge
      int best = tallest({i, i + 1}, false);
      if (best < 0) best = tallest({i, i + 1}, true);
      bad = best >= 0 ? best : -2;
    }
    if (bad < 0) {
      bad = -1;
      stop = 2;
      for (int i = 0; i + 1 < n && bad < 0; ++i)
        for (int j = i + 2; j + 1 < n; ++j) {
          if (segmentsCross(uvOf(i), uvOf(i + 1), uvOf(j), uvOf(j + 1))) {
            // the marched column among the four points with the most layers
            const int best = tallest({i, i + 1, j, j + 1}, false);
            bad = best >= 0 ? best : -2;
            break;
          }
        }
    }
    if (bad < 0) return;  // no crossing, or only fixed columns involved: nothing to trim
    Column& c = cols[bad];
    c.uv.pop_back();
    c.xyz.pop_back();
    c.ref.pop_back();
    c.stop = stop;
  }
}

/// A marched column standing above both its neighbours (above its one neighbour at the end of
/// an open run) has no element beside its upper rows:
/// the front would run up one side of it and back down the other through the same nodes, a slit
/// the face mesher refuses ("two boundary points coincide"). Such a column is cut down to its
/// taller neighbour and stops for that neighbour's reason (a collision when the neighbour simply
/// has fewer rows by its own law).
void FaceLayers::trimNeedles(std::vector<Column>& cols, bool closed) {
  const int m = (int)cols.size();
  if (m < (closed ? 3 : 2)) return;
  for (bool again = true; again;) {
    again = false;
    for (int i = 0; i < m; ++i) {
      // the end of an open run has one neighbour (a marched end column; a fixed one lies on
      // the boundary, beside its neighbouring edge)
      const bool end0 = !closed && i == 0, end1 = !closed && i == m - 1;
      Column& c = cols[i];
      const Column &a = cols[end0 ? 1 : (i + m - 1) % m], &b = cols[end1 ? m - 2 : (i + 1) % m];
      const Column& taller = a.xyz.size() >= b.xyz.size() ? a : b;
      if (c.fixed || c.xyz.size() <= taller.xyz.size()) continue;
      while (c.xyz.size() > taller.xyz.size()) {
        c.uv.pop_back();
        c.xyz.pop_back();
        c.ref.pop_back();
      }
      c.active = false;
      c.stop = taller.stop > 0 ? taller.stop : 2;
      again = true;
    }
  }
}

}  // namespace paramesh::bl_detail
