// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file SizeField.hpp
/// The target element size h(x) at any 3D point: the global maximum size, lowered near size
/// sources (curvature samples, local sizes, small CAD features, boundary-layer hand-off) and graded
/// in 3D so that it grows by at most the grading ratio per element:
///
///     h(x) = min( hmax, min_i [ h_i + (g - 1) * |x - x_i| ] )
///
/// This is the exact solution of the gradient-limiting problem |grad h| <= g - 1 in Euclidean
/// distance, so local sizes stay local and the grading holds across face boundaries. Queries use a
/// kd-tree with branch-and-bound on the cone bound. Read-only (thread-safe) after build().
#pragma once
#include <memory>
#include <vector>

#include "paramesh/util/Vec.hpp"

namespace paramesh {

class SizeField {
 public:
  SizeField() = default;
  /// hmax: size far from every source; grading g > 1: max ratio between neighbouring elements.
  SizeField(double hmax, double grading) : hmax_(hmax), slope_(grading - 1.0) {}

  /// Adds a point source of size h (ignored when h >= hmax). slope > 0 overrides the grading
  /// slope (g - 1) for this source (a steeper, more local influence). Call build() afterwards.
  void addSource(Vec3 p, double h, double slope = 0);
  /// Removes dominated sources and builds the search tree. O(n log n).
  void build();
  /// Target size at x. O(log n) typical.
  double size(Vec3 x) const;
  /// The size from this field's own sources only (not the field under it).
  double ownSize(Vec3 x) const;
  /// A built field whose sources count as this one's too: size() is the smaller of the two, which
  /// is the field of both source sets, without copying or rebuilding the one under (the
  /// nearest-face rounds add a few sources to millions).
  void setUnder(std::shared_ptr<const SizeField> under) { under_ = std::move(under); }

  double hmax() const { return hmax_; }
  double slope() const { return slope_; }
  size_t numSources() const { return pts_.size() + (under_ ? under_->numSources() : 0); }

 private:
  struct Node {
    Vec3 lo, hi;
    double hmin;
    double smin;     // smallest slope in the subtree
    int begin, end;  // range in pts_
    int left = -1, right = -1;
  };
  int buildNode(int begin, int end, int depth);
  void query(int node, Vec3 x, double& best) const;
  void queryDominating(int node, Vec3 x, double maxSlope, double& best) const;

  double hmax_ = 1.0, slope_ = 0.3;
  std::vector<Vec3> pts_;
  std::vector<double> hs_;
  std::vector<double> ss_;  // per-source slope
  std::vector<Node> nodes_;
  bool built_ = true;
  std::shared_ptr<const SizeField> under_;
};

}  // namespace paramesh
