// SPDX-License-Identifier: LGPL-2.1-or-later
// The march of a run's columns, row by row: each active column steps by its row height along its
// direction, the stop rules run (CollisionStops.cpp), and the directions turn square to the new row.

#include "paramesh/algo/boundary_layer/FaceLayers.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <vector>

namespace paramesh::bl_detail {

/// The run's own points in loop L: its roots and its end columns' points (loop points too).
std::vector<char> FaceLayers::ownPoints(int L, const std::vector<Column>& cols) const {
  std::vector<char> own(loops_[L].size(), 0);
  std::vector<int> nodes;
  for (const Column& c : cols) {
    if (c.root >= 0 && c.root < (int)own.size()) own[c.root] = 1;
    if (c.fixed)
      for (int r : c.ref)
        if (r >= 0) nodes.push_back(r);
  }
  std::sort(nodes.begin(), nodes.end());
  for (size_t i = 0; i < own.size(); ++i)
    if (loops_[L][i].node >= 0 && std::binary_search(nodes.begin(), nodes.end(), loops_[L][i].node)) own[i] = 1;
  return own;
}

void FaceLayers::march(int L, std::vector<Column>& cols, bool closed) {
  const int m = (int)cols.size();
  const std::vector<char> own = ownPoints(L, cols);
  int maxLayers = 0;
  for (auto& c : cols) maxLayers = std::max(maxLayers, laws_[c.spec].layers);
  for (int k = 0; k < maxLayers; ++k) {
    // 1) advance every active column by its row height
    std::vector<char> moved(m, 0);
    advanceColumns(L, cols, closed, k, own, moved);
    // 1b) columns converging on a stopped neighbour (a concave corner) stop with it: a new point
    //     closer to a stopped top than the row height would fold the front over it
    stopAtStoppedNeighbours(cols, closed, k, moved);
    // 2) the new quads must be valid: positive in (u,v), facing like the surface
    stopAtInvalidRows(L, cols, closed, k, own, moved);
    // 2b) a column whose neighbours both stopped below it would stand alone: it stops with them
    trimNeedles(cols, closed);
    // 3) new directions from the new row: b = n x (row tangent), same side as before
    turnColumns(cols, closed, k);
  }
  for (auto& c : cols)
    if (c.active) {
      c.active = false;
      c.stop = 0;
    }
  for (auto& c : cols)
    for (size_t k = 1; k < c.xyz.size(); ++k) {
      otherPts_.push_back(c.xyz[k]);
      otherH_.push_back(laws_[c.spec].height((int)k - 1));
    }
}

/// Step 1) of layer k: every active column advances by its row height, or stops (its N layers,
/// the aspect limit, the face's boundary, another run); moved[i] marks those that advanced.
void FaceLayers::advanceColumns(int L, std::vector<Column>& cols, bool closed, int k, const std::vector<char>& own,
                                std::vector<char>& moved) const {
  const int m = (int)cols.size();
  for (int i = 0; i < m; ++i) {
    Column& c = cols[i];
    if (!c.active) continue;
    const LayerLaw& law = laws_[c.spec];
    if (k >= law.layers) {
      c.active = false;
      c.stop = 0;
      continue;
    }
    const double h = law.height(k) * c.factor;
    {
      // hand-off where the row would become much taller than wide (columns converging at a
      // skewed end): the user's aspect limit, and in any case at height > 1.5 x spacing
      const double spacing = rowSpacing(cols, i, closed);
      const double limit = law.maxAspect > 0 ? law.maxAspect : 1.0 / 1.5;
      if (spacing > 0 && spacing / law.height(k) < limit) {
        c.active = false;
        c.stop = 4;
        continue;
      }
    }
    Vec2 uv;
    Vec3 x;
    const bool okStep = step(c.uv.back(), c.xyz.back(), marchDirection(cols, i, k), h, uv, x);
    const bool okIn = okStep && guard_.inside(uv);
    const bool okCross = okIn && !crossesLoops(c.uv.back(), uv, L, k == 0 ? c.root : -1, k == 0 ? ((c.root - 1 + (int)loops_[L].size()) % (int)loops_[L].size()) : -1);
    if (!okCross || closesOnBoundary(c.xyz.back(), x, 0.5 * law.height(k), L, c.root, own)) {
      c.active = false;
      c.stop = 1;
      continue;
    }
    if (nearOther(x, 0.5 * law.height(k)) || crossesOther(c.uv.back(), uv, c.xyz.back(), x) ||
        nearOtherGrid(x, 0.25 * law.height(k))) {
      c.active = false;
      c.stop = 2;
      continue;
    }
    c.uv.push_back(uv);
    c.xyz.push_back(x);
    c.ref.push_back(0);
    moved[i] = 1;
  }
}

/// Step 3) of layer k: new directions from the new row, b = n x (row tangent), same side as before.
void FaceLayers::turnColumns(std::vector<Column>& cols, bool closed, int k) const {
  const int m = (int)cols.size();
  for (int i = 0; i < m; ++i) {
    Column& c = cols[i];
    if (!c.active || (int)c.uv.size() < k + 2) continue;
    const int ip = closed ? (i + m - 1) % m : std::max(i - 1, 0);
    const int in = closed ? (i + 1) % m : std::min(i + 1, m - 1);
    const Vec3 pPrev = pointAt(cols[ip], k + 1), pNext = pointAt(cols[in], k + 1);
    Vec3 t = pNext - pPrev;
    if (norm2(t) < 1e-300) continue;
    const Vec3 nn = normalAt(c.uv.back());
    Vec3 d = normalized(cross(nn, t));
    if (dot(d, c.dir) < 0) d = -d;
    // keep fan columns and corner columns pointing their own way: blend with the old direction
    if (ip == i || in == i || samePosition(cols[ip], cols[i], 0) || samePosition(cols[in], cols[i], 0))
      d = normalized(d + c.dir);
    // near the run ends the rows are skewed by the outermost columns: there the column keeps
    // its own direction (transported into the new tangent plane) instead of the row normal
    const double w = std::max(c.wEnd[0], c.wEnd[1]);
    const Vec3 transported = normalized(c.dir - dot(c.dir, nn) * nn);
    d = normalized((1 - w) * d + w * transported);
    c.dir = normalized(d - dot(d, nn) * nn);
  }
}

/// Direction a column has at layer k: marched columns their marching direction, end columns the
/// direction of their next segment along the edge (or their last one).
Vec3 FaceLayers::directionOf(const Column& c, int k) {
  if (!c.fixed) return c.dir;
  const size_t n = c.xyz.size();
  if (n < 2) return {0, 0, 0};
  const size_t a = std::min<size_t>(k, n - 2);
  return normalized(c.xyz[a + 1] - c.xyz[a]);
}

/// The direction of column i for layer k: its row-orthogonal direction, leaning towards the
/// outermost columns near the run ends; the lean grows over the first layers, so the first
/// segment stays orthogonal to the edge.
Vec3 FaceLayers::marchDirection(const std::vector<Column>& cols, int i, int k) const {
  const Column& c = cols[i];
  if (c.wEnd[0] == 0 && c.wEnd[1] == 0) return c.dir;
  const double ramp = std::min(1.0, k / 3.0);
  Vec3 d = c.dir;
  if (c.wEnd[0] > 0) d += (ramp * c.wEnd[0]) * (directionOf(cols.front(), k) - c.dir);
  if (c.wEnd[1] > 0) d += (ramp * c.wEnd[1]) * (directionOf(cols.back(), k) - c.dir);
  const Vec3 nn = normalAt(c.uv.back());
  d = d - dot(d, nn) * nn;
  return norm2(d) > 1e-20 ? normalized(d) : c.dir;
}

bool FaceLayers::samePosition(const Column& a, const Column& b, int k) {
  return a.root == b.root && k == 0;
}

/// A column's point at layer k, or its top when it stopped lower.
Vec3 FaceLayers::pointAt(const Column& c, int k) { return c.xyz[std::min<size_t>(k, c.xyz.size() - 1)]; }

/// Mean distance from column i's current top to its neighbours' points on the same row (fan
/// siblings at their shared root do not count).
double FaceLayers::rowSpacing(const std::vector<Column>& cols, int i, bool closed) const {
  const int m = (int)cols.size();
  const Column& c = cols[i];
  const size_t k = c.xyz.size() - 1;
  double s = 0;
  int n = 0;
  for (int j : {i - 1, i + 1}) {
    if (!closed && (j < 0 || j >= m)) continue;
    const Column& o = cols[(j + m) % m];
    if (o.root == c.root) continue;  // fan siblings spread with the distance from their root
    const double d = dist(o.xyz[std::min(o.xyz.size() - 1, k)], c.xyz[k]);
    if (d <= 0) continue;
    s += d;
    ++n;
  }
  return n ? s / n : 0;
}

}  // namespace paramesh::bl_detail
