// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file SourceReach.hpp
/// Where new size sources change a graded size field: the pipeline re-meshes only what they reach.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "paramesh/util/SpatialGrid.hpp"

namespace paramesh {

/// Which boxes a set of size sources reaches: source i changes the size field within reach[i]
/// of it (h + slope * d < hmax), nowhere else.
class SourceReach {
 public:
  SourceReach(std::vector<Vec3> p, std::vector<double> reach)
      : p_(std::move(p)), reach_(std::move(reach)), grid_(cellFor(reach_)) {
    for (size_t i = 0; i < p_.size(); ++i) {
      const Vec3 r{reach_[i], reach_[i], reach_[i]};
      grid_.add((int)i, p_[i] - r, p_[i] + r);
    }
  }
  /// True when some source lies nearer the box [lo, hi] than its reach (a point: lo = hi).
  bool reaches(Vec3 lo, Vec3 hi) const {
    bool hit = false;
    grid_.queryBox(lo, hi, [&](int i) {
      if (hit) return;
      double d2 = 0;
      for (int k = 0; k < 3; ++k) {
        const double q = std::max({lo[k] - p_[i][k], 0.0, p_[i][k] - hi[k]});
        d2 += q * q;
      }
      hit = std::sqrt(d2) < reach_[i];
    });
    return hit;
  }

 private:
  static double cellFor(const std::vector<double>& reach) {
    double r = 0;
    for (double x : reach) r = std::max(r, x);
    // no source reaches anywhere (every reach 0): any cell will do; 1e-300 put every point
    // ~1e300 cells from the origin
    return r > 0 ? r : 1.0;
  }
  std::vector<Vec3> p_;
  std::vector<double> reach_;
  BoxGrid grid_;
};

}  // namespace paramesh
