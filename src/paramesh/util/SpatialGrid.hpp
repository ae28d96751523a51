// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file SpatialGrid.hpp
/// Closest points on segments and triangles, and a uniform hash grid of boxes for neighbourhood
/// queries (proximity sizing, the nearest-face check).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "paramesh/util/Vec.hpp"

namespace paramesh {

/// Closest point to p on segment [a,b].
inline Vec3 closestOnSegment(Vec3 p, Vec3 a, Vec3 b) {
  const Vec3 d = b - a;
  const double l2 = norm2(d);
  if (!(l2 > 0)) return a;
  const double t = std::clamp(dot(p - a, d) / l2, 0.0, 1.0);
  return a + t * d;
}

/// Closest point to p on triangle (a,b,c) (Voronoi regions of the vertices, edges and face).
inline Vec3 closestOnTriangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double den = 1.0 / (va + vb + vc);
  return a + (vb * den) * ab + (vc * den) * ac;
}

/// Uniform hash grid of boxes: each id is stored in every cell its box overlaps.
class BoxGrid {
 public:
  explicit BoxGrid(double cell) : cell_(cell) {}
  void add(int id, Vec3 lo, Vec3 hi) {
    const auto a = key(lo), b = key(hi);
    for (long i = a[0]; i <= b[0]; ++i)
      for (long j = a[1]; j <= b[1]; ++j)
        for (long k = a[2]; k <= b[2]; ++k) cells_[pack(i, j, k)].push_back(id);
  }
  /// Calls f(id) for the ids of every cell overlapping the cube of half-side r around p (an id
  /// may come more than once).
  template <class F>
  void query(Vec3 p, double r, F&& f) const {
    queryBox(p - Vec3{r, r, r}, p + Vec3{r, r, r}, f);
  }
  /// Same for the box [lo, hi].
  template <class F>
  void queryBox(Vec3 lo, Vec3 hi, F&& f) const {
    const auto a = key(lo), b = key(hi);
    for (long i = a[0]; i <= b[0]; ++i)
      for (long j = a[1]; j <= b[1]; ++j)
        for (long k = a[2]; k <= b[2]; ++k) {
          auto it = cells_.find(pack(i, j, k));
          if (it == cells_.end()) continue;
          for (int id : it->second) f(id);
        }
  }
  /// Number of cells the box [lo, hi] overlaps (to choose between a grid walk and a plain loop).
  double cellsOf(Vec3 lo, Vec3 hi) const {
    const auto a = key(lo), b = key(hi);
    return double(b[0] - a[0] + 1) * double(b[1] - a[1] + 1) * double(b[2] - a[2] + 1);
  }
  bool empty() const { return cells_.empty(); }

 private:
  std::array<long, 3> key(Vec3 p) const { return {index(p.x), index(p.y), index(p.z)}; }
  /// The cell index along one axis, clamped to +-2^52: a coordinate far beyond the cell size (a
  /// tiny cell, a huge box) must not be cast beyond long's range (undefined behaviour, UBSan
  /// float-cast-overflow); NaN is cell 0.
  long index(double x) const {
    const double c = std::floor(x / cell_), lim = 4503599627370496.0;
    return c >= lim ? (long)lim : c <= -lim ? -(long)lim : c == c ? (long)c : 0;
  }
  static uint64_t pack(long i, long j, long k) {
    return ((uint64_t)(i & 0x1FFFFF) << 42) | ((uint64_t)(j & 0x1FFFFF) << 21) | (uint64_t)(k & 0x1FFFFF);
  }
  double cell_;
  std::unordered_map<uint64_t, std::vector<int>> cells_;
};

/// The segments of a polyline in a BoxGrid: nearest segment to a point within a radius.
class SegmentIndex {
 public:
  /// p: the polyline (>= 2 points); cell: grid cell size (about the query radius).
  SegmentIndex(const std::vector<Vec3>& p, double cell) : p_(p), grid_(cell) {
    for (size_t i = 1; i < p_.size(); ++i) {
      Box3 b;
      b.add(p_[i - 1]);
      b.add(p_[i]);
      grid_.add((int)i - 1, b.lo, b.hi);
    }
  }
  /// Segment i ([p[i], p[i+1]]) nearest to x among those within r, and its distance; -1 if none.
  int nearest(Vec3 x, double r, double* d = nullptr) const {
    int best = -1;
    double bd = r;
    grid_.query(x, r, [&](int i) {
      const double di = dist(x, closestOnSegment(x, p_[i], p_[i + 1]));
      if (di <= bd) {
        bd = di;
        best = i;
      }
    });
    if (d) *d = bd;
    return best;
  }

 private:
  const std::vector<Vec3>& p_;
  BoxGrid grid_;
};

}  // namespace paramesh
