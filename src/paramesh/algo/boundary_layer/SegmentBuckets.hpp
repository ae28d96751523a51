// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file SegmentBuckets.hpp
/// Internal to the boundary-layer files: a 3D bucket index of segments, so that a collision test
/// near a point looks at the segments of a few buckets instead of every segment of the face.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "paramesh/util/Vec.hpp"

namespace paramesh::bl_detail {

/// Segments in 3D buckets (cubes of side `cell`): each segment is listed in the buckets met by
/// the boxes of its pieces of at most one cell, so that a query near a point looks at a few
/// buckets instead of every segment (the collision tests run once per step; measured:
/// docs/tuning/boundary_layer.md).
class SegmentBuckets {
 public:
  explicit SegmentBuckets(double cell = 1.0) : cell_(cell > 0 && std::isfinite(cell) ? cell : 1.0) {}
  void add(int id, Vec3 a, Vec3 b) {
    const int n = std::clamp((int)std::ceil(dist(a, b) / cell_), 1, 4096);
    Vec3 p = a;
    for (int k = 1; k <= n; ++k) {
      const Vec3 q = a + (double(k) / n) * (b - a);
      forCells(lo(p, q), hi(p, q), [&](int64_t key) {
        auto& v = map_[key];
        if (v.empty() || v.back() != id) v.push_back(id);
      });
      p = q;
    }
  }
  /// Calls f(id) for the segments listed in the buckets that the box [l, h] meets (an id can
  /// come more than once).
  template <class F>
  void visit(Vec3 l, Vec3 h, F&& f) const {
    if (cells(l, h) > (int64_t)map_.size()) {  // a query larger than the listed buckets: all of them
      for (const auto& kv : map_)
        for (int id : kv.second) f(id);
      return;
    }
    forCells(l, h, [&](int64_t key) {
      auto it = map_.find(key);
      if (it != map_.end())
        for (int id : it->second) f(id);
    });
  }
  static Vec3 lo(Vec3 a, Vec3 b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
  static Vec3 hi(Vec3 a, Vec3 b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }

 private:
  double cell_;
  std::unordered_map<int64_t, std::vector<int>> map_;
  int64_t idx(double x) const { return (int64_t)std::floor(x / cell_); }
  int64_t cells(Vec3 l, Vec3 h) const {
    return (idx(h.x) - idx(l.x) + 1) * (idx(h.y) - idx(l.y) + 1) * (idx(h.z) - idx(l.z) + 1);
  }
  template <class F>
  void forCells(Vec3 l, Vec3 h, F&& f) const {
    const int64_t i0 = idx(l.x), i1 = idx(h.x), j0 = idx(l.y), j1 = idx(h.y), k0 = idx(l.z), k1 = idx(h.z);
    for (int64_t i = i0; i <= i1; ++i)
      for (int64_t j = j0; j <= j1; ++j)
        for (int64_t k = k0; k <= k1; ++k)
          f(((i & 0x1FFFFF) << 42) | ((j & 0x1FFFFF) << 21) | (k & 0x1FFFFF));
  }
};

}  // namespace paramesh::bl_detail
