// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file DeviationZone.hpp
/// A local bound on the chordal deviation of a face mesh (the nearest-face check's repairs).
#pragma once
#include <algorithm>
#include <cmath>

#include "paramesh/util/Vec.hpp"

namespace paramesh {

/// A ball in which triangle centroids may lie off the surface by at most `allowed`, or, when
/// `otherNormal` is set, by at most `fraction` times their distance to the plane through
/// `otherPoint` normal to `otherNormal` (the tangent plane of another face, the opposite skin of a
/// thin part), but never less than `floor`: a triangle cut so deep that its centroid was nearer
/// that face is refined until its pieces stay nearer their own face, its neighbours that are not
/// that deep are left alone, and where the two faces meet (the plane distance goes to 0 at their
/// common edge) the floor stops the refinement.
struct DeviationZone {
  Vec3 center;
  double radius = 0;
  double allowed = 1e300;
  double floor = 0;
  Vec3 otherPoint{0, 0, 0}, otherNormal{0, 0, 0};
  double fraction = 0.5;
  /// The bound at centroid g (+inf outside the ball).
  double bound(Vec3 g) const {
    if (!(dist(g, center) < radius)) return 1e300;
    double b = allowed;
    if (norm2(otherNormal) > 0) b = std::min(b, fraction * std::fabs(dot(g - otherPoint, otherNormal)));
    return std::max(b, floor);
  }
};

}  // namespace paramesh
