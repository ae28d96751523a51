// SPDX-License-Identifier: LGPL-2.1-or-later
// The hand-off to the isotropic face mesher: a run's front (column tops, stairs between heights),
// the sizes along it, and the face loops with every grown run replaced by its front.

#include "paramesh/algo/boundary_layer/FaceLayers.hpp"

#include <algorithm>
#include <utility>
#include <vector>

namespace paramesh::bl_detail {

/// The front polyline (column tops, stairs between different heights) as (column, layer) pairs.
std::vector<std::pair<int, int>> FaceLayers::frontPath(const std::vector<Column>& cols, bool closed) {
  std::vector<std::pair<int, int>> path;
  const int m = (int)cols.size();
  // a marched end column of an open run: the front runs up it from its root (and down the last)
  if (!closed && m > 0 && !cols[0].fixed)
    for (int k = 0; k + 1 < (int)cols[0].xyz.size(); ++k) path.emplace_back(0, k);
  for (int i = 0; i < m; ++i) {
    const int ka = (int)cols[i].xyz.size() - 1;
    path.emplace_back(i, ka);
    if (!closed && i == m - 1) {
      if (!cols[i].fixed)
        for (int k = ka - 1; k >= 0; --k) path.emplace_back(i, k);
      break;
    }
    const int j = (i + 1) % m;
    const int kb = (int)cols[j].xyz.size() - 1;
    for (int k = ka - 1; k >= kb; --k) path.emplace_back(i, k);
    for (int k = std::min(ka, kb); k < kb; ++k) path.emplace_back(j, k);
  }
  return path;
}

/// The front of a grown run, its hand-off sizes, and the loop points it replaces.
void FaceLayers::handOff(int L, int a, int nseg, bool closed, const std::vector<Column>& cols) {
  const auto& lp = loops_[L];
  const int n = (int)lp.size();
  const int m = (int)cols.size();
  // the front: tops of the columns with stairs between different heights
  std::vector<LoopPoint> front;
  std::vector<double> layerH;  // height of the row below each front point
  auto push = [&](const Column& c, int k) {
    LoopPoint p;
    p.uv = c.uv[k];
    p.xyz = c.xyz[k];
    p.node = c.ref[k];
    p.edge = -1;
    if (!front.empty() && front.back().node == p.node) return;
    front.push_back(p);
    layerH.push_back(k > 0 ? laws_[c.spec].height(k - 1) : 0.0);
  };
  if (!closed && !cols.front().fixed)  // a marched end column: up from its root
    for (int k = 0; k + 1 < (int)cols.front().xyz.size(); ++k) push(cols.front(), k);
  for (int i = 0; i < m; ++i) {
    const Column& A = cols[i];
    const int ka = (int)A.xyz.size() - 1;
    push(A, ka);
    if (!closed && i == m - 1) {
      if (!A.fixed)
        for (int k = ka - 1; k >= 0; --k) push(A, k);
      break;
    }
    const Column& B = cols[(i + 1) % m];
    const int kb = (int)B.xyz.size() - 1;
    for (int k = ka - 1; k >= kb; --k) push(A, k);   // down column A
    for (int k = std::min(ka, kb); k < kb; ++k) push(B, k);  // up column B
  }
  if (closed && front.size() > 1 && front.front().node == front.back().node) front.pop_back();
  // hand-off sizes: the triangles on the front are about as tall as the last row (so that the
  // size does not jump), within [0.7, 1.5] of the front spacing (so that they stay well shaped)
  for (size_t i = 0; i < front.size(); ++i) {
    const double l0 = i > 0 ? dist(front[i].xyz, front[i - 1].xyz) : 0;
    const double l1 = i + 1 < front.size() ? dist(front[i].xyz, front[i + 1].xyz) : 0;
    const double seg = (l0 > 0 && l1 > 0) ? 0.5 * (l0 + l1) : std::max(l0, l1);
    const double h = layerH[i] > 0 ? std::min(std::max(1.15 * layerH[i], 0.7 * seg), 1.5 * seg) : seg;
    if (h > 0) out_.frontSizes.emplace_back(front[i].xyz, h);
  }
  // replace the run (with its end columns) by the front in this loop
  Replace rp;
  rp.loop = L;
  if (closed) {
    rp.from = 0;
    rp.to = n - 1;
    rp.whole = true;
  } else {
    // the points of fixed end columns are loop points (the neighbouring edges' first nodes)
    const int lenA = cols.front().fixed ? (int)cols.front().xyz.size() - 1 : 0;
    const int lenB = cols.back().fixed ? (int)cols.back().xyz.size() - 1 : 0;
    rp.from = ((a - lenA) % n + n) % n;
    rp.to = ((a + nseg + lenB) % n + n) % n;
  }
  rp.front = std::move(front);
  replaces_.push_back(std::move(rp));
}

/// The face loops with every grown run replaced by its front.
void FaceLayers::buildLoops() {
  out_.loops.clear();
  for (size_t L = 0; L < loops_.size(); ++L) {
    const auto& lp = loops_[L];
    const int n = (int)lp.size();
    std::vector<int> owner(n, -1);
    std::vector<const Replace*> mine;
    for (const Replace& r : replaces_)
      if (r.loop == (int)L) mine.push_back(&r);
    if (mine.empty()) {
      out_.loops.push_back(lp);
      continue;
    }
    bool whole = false;
    for (const Replace* r : mine) {
      if (r->whole) {
        whole = true;
        out_.loops.push_back(r->front);
        continue;
      }
      for (int i = r->from;; i = (i + 1) % n) {
        owner[i] = (int)(r - replaces_.data());
        if (i == r->to) break;
      }
    }
    if (whole) continue;
    // start at a point outside every run
    int s0 = -1;
    for (int i = 0; i < n; ++i)
      if (owner[i] < 0) {
        s0 = i;
        break;
      }
    std::vector<LoopPoint> loop;
    if (s0 < 0) {
      // runs cover the whole loop: concatenate fronts in order
      int i = mine.front()->from;
      for (int k = 0; k < n; ++k, i = (i + 1) % n) {
        const Replace& r = replaces_[owner[i]];
        if (i == r.from)
          for (const LoopPoint& q : r.front) loop.push_back(q);
      }
    } else {
      for (int k = 0, i = s0; k < n; ++k, i = (i + 1) % n) {
        if (owner[i] < 0) {
          loop.push_back(lp[i]);
          continue;
        }
        const Replace& r = replaces_[owner[i]];
        if (i == r.from)
          for (const LoopPoint& q : r.front) loop.push_back(q);
      }
    }
    // adjacent runs share their end points: drop repeated nodes
    std::vector<LoopPoint> clean;
    for (const LoopPoint& q : loop)
      if (clean.empty() || clean.back().node != q.node) clean.push_back(q);
    while (clean.size() > 1 && clean.front().node == clean.back().node) clean.pop_back();
    out_.loops.push_back(std::move(clean));
  }
}

}  // namespace paramesh::bl_detail
