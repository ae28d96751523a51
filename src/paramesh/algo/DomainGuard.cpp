// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/algo/DomainGuard.hpp"

#include <algorithm>
#include <cmath>

namespace paramesh {

namespace {
// does segment [a,b] cross segment [p,q]? (proper or touching; used for parity with a ray that
// avoids vertices in practice)
bool crosses(Vec2 a, Vec2 b, Vec2 p, Vec2 q) {
  auto orient = [](Vec2 u, Vec2 v, Vec2 w) { return (v.x - u.x) * (w.y - u.y) - (v.y - u.y) * (w.x - u.x); };
  const double d1 = orient(a, b, p), d2 = orient(a, b, q), d3 = orient(p, q, a), d4 = orient(p, q, b);
  return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0));
}

// x where segment (a, b) crosses the horizontal line at y (the segment spans y)
double crossingX(Vec2 a, Vec2 b, double y) { return a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y); }

// the k-th trial offset (k >= 1) of a reference point off its cell's centre, in cells: +0.0123, -0.0123,
// +0.0246, ... (at most 0.39 after 63 trials, so the point stays in its cell)
double nudge(int k) { return (k % 2 ? 1 : -1) * ((k + 1) / 2) * 0.0123; }
}  // namespace

DomainGuard::DomainGuard(const std::vector<std::vector<Vec2>>& loops) {
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (const auto& L : loops) {
    const size_t n = L.size();
    if (n < 3) continue;
    for (size_t i = 0; i < n; ++i) {
      segs_.push_back({L[i], L[(i + 1) % n]});
      xmin = std::min(xmin, L[i].x);
      xmax = std::max(xmax, L[i].x);
      ymin = std::min(ymin, L[i].y);
      ymax = std::max(ymax, L[i].y);
    }
  }
  if (segs_.empty()) return;
  const double w = std::max(xmax - xmin, 1e-300), h = std::max(ymax - ymin, 1e-300);
  const double m = 1e-6 * std::max(w, h);
  x0_ = xmin - m;
  y0_ = ymin - m;
  // about 2 segments per cell on average, square-ish cells
  const double cells = std::max(1.0, segs_.size() / 2.0);
  const double aspect = (w + 2 * m) / (h + 2 * m);
  nx_ = std::clamp((int)std::ceil(std::sqrt(cells * aspect)), 1, 2048);
  ny_ = std::clamp((int)std::ceil(cells / nx_), 1, 2048);
  dx_ = (w + 2 * m) / nx_;
  dy_ = (h + 2 * m) / ny_;
  // bin segments by their bounding box (conservative)
  std::vector<int> count(nx_ * ny_ + 1, 0);
  auto forCells = [&](const Seg& s, auto&& fn) {
    int i0, j0, i1, j1;
    cellOf(std::min(s.a.x, s.b.x), std::min(s.a.y, s.b.y), i0, j0);
    cellOf(std::max(s.a.x, s.b.x), std::max(s.a.y, s.b.y), i1, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) fn(j * nx_ + i);
  };
  for (const Seg& s : segs_) forCells(s, [&](int c) { ++count[c + 1]; });
  for (int c = 0; c < nx_ * ny_; ++c) count[c + 1] += count[c];
  start_ = count;
  list_.resize(count.back());
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (int k = 0; k < (int)segs_.size(); ++k) forCells(segs_[k], [&](int c) { list_[fill[c]++] = k; });
  // Each cell keeps a reference point, near its centre, whose parity is known; a query flips it
  // for each segment between the two. The reference must not lie on the boundary's line work: a
  // row through a vertex, or a reference on a segment, counts a crossing on one side and not on
  // the other (ANC101's Face41 has a horizontal segment at v = -5 exactly on a row's centre line:
  // a band of the row above it read as inside, the face's notch, and the band below as outside).
  // So each row's y is moved off every vertex's y, and each cell's x off its segments.
  std::vector<double> vy;
  for (const Seg& sg : segs_) vy.push_back(sg.a.y);
  std::sort(vy.begin(), vy.end());
  const double clearY = 1e-7 * dy_, clearX = 1e-7 * std::max(dx_, dy_);
  refY_.assign(ny_, 0);
  for (int j = 0; j < ny_; ++j) {
    double y = y0_ + (j + 0.5) * dy_;
    for (int k = 1; k < 64; ++k) {
      const auto it = std::lower_bound(vy.begin(), vy.end(), y - clearY);
      if (it == vy.end() || *it > y + clearY) break;
      y = y0_ + (j + 0.5) * dy_ + nudge(k) * dy_;  // stays in the row
    }
    refY_[j] = y;
  }
  refX_.assign(nx_ * ny_, 0);
  for (int j = 0; j < ny_; ++j)
    for (int i = 0; i < nx_; ++i) {
      const int c = j * nx_ + i;
      double x = x0_ + (i + 0.5) * dx_;
      for (int k = 1; k < 64; ++k) {
        bool clear = true;
        for (int q = start_[c]; q < start_[c + 1] && clear; ++q) {
          const Seg& sg = segs_[list_[q]];
          if ((sg.a.y > refY_[j]) == (sg.b.y > refY_[j])) continue;  // does not cross the row
          if (std::fabs(crossingX(sg.a, sg.b, refY_[j]) - x) <= clearX) clear = false;
        }
        if (clear) break;
        x = x0_ + (i + 0.5) * dx_ + nudge(k) * dx_;
      }
      refX_[c] = x;
    }
  // parity at each reference point: sweep each row from the left with a horizontal ray. Each
  // segment is offered to the rows its y range spans (testing every segment against every row
  // was O(segments^1.5): 2.8 % of nist_ctc_01 d/100's instructions)
  centreInside_.assign(nx_ * ny_, 0);
  std::vector<std::vector<double>> rows(ny_);
  for (const Seg& sg : segs_) {
    int j0 = 0, j1 = ny_ - 1;  // a non-finite end: every row, as before
    if (std::isfinite(sg.a.y) && std::isfinite(sg.b.y)) {
      // the rows whose reference y_j lies in [lo, hi): estimated, then widened while the next row
      // out still lies inside (y_j never decreases with j: each moves by less than half a row)
      const double lo = std::min(sg.a.y, sg.b.y), hi = std::max(sg.a.y, sg.b.y);
      j0 = (int)std::clamp(std::floor((lo - y0_) / dy_ - 0.5), 0.0, (double)ny_ - 1);
      j1 = (int)std::clamp(std::ceil((hi - y0_) / dy_ - 0.5), 0.0, (double)ny_ - 1);
      while (j0 > 0 && refY_[j0 - 1] >= lo) --j0;
      while (j1 < ny_ - 1 && refY_[j1 + 1] < hi) ++j1;
    }
    for (int j = j0; j <= j1; ++j) {
      const double y = refY_[j];
      if ((sg.a.y > y) != (sg.b.y > y)) rows[j].push_back(crossingX(sg.a, sg.b, y));
    }
  }
  for (int j = 0; j < ny_; ++j) {
    std::vector<double>& xs = rows[j];
    std::sort(xs.begin(), xs.end());
    for (int i = 0; i < nx_; ++i) {
      const double x = refX_[j * nx_ + i];
      centreInside_[j * nx_ + i] = (char)((std::lower_bound(xs.begin(), xs.end(), x) - xs.begin()) & 1);
    }
  }
}

int DomainGuard::cellOf(double x, double y, int& i, int& j) const {
  i = std::clamp((int)std::floor((x - x0_) / dx_), 0, nx_ - 1);
  j = std::clamp((int)std::floor((y - y0_) / dy_), 0, ny_ - 1);
  return j * nx_ + i;
}

bool DomainGuard::inside(Vec2 p) const {
  if (segs_.empty()) return true;
  if (p.x < x0_ || p.y < y0_ || p.x > x0_ + nx_ * dx_ || p.y > y0_ + ny_ * dy_) return false;
  int i, j;
  const int c = cellOf(p.x, p.y, i, j);
  const Vec2 centre{refX_[c], refY_[j]};
  bool in = centreInside_[c];
  for (int k = start_[c]; k < start_[c + 1]; ++k) {
    const Seg& s = segs_[list_[k]];
    if (crosses(s.a, s.b, p, centre)) in = !in;
  }
  return in;
}

}  // namespace paramesh
