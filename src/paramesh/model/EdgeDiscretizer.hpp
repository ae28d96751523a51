// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file EdgeDiscretizer.hpp
/// Discretises a CAD edge once, by 3D length against the size field: the integral of ds/h along
/// the curve is equidistributed. Every face adjacent to the edge reuses the result.
#pragma once
#include <functional>
#include <vector>

#include "paramesh/geom/Geometry.hpp"
#include "paramesh/size/SizeField.hpp"

namespace paramesh {

/// A dense polyline on a curve (adaptive in chord error and size), with cumulative 3D length.
struct CurveSampling {
  std::vector<double> t;
  std::vector<Vec3> p;
  std::vector<double> s;   ///< cumulative chord length
  double turning = 0;      ///< total turning angle of the curve (radians)
  double length() const { return s.empty() ? 0 : s.back(); }
};

/// Samples curve c on [t0,t1] finely enough for length and size integration (O(length/h) points,
/// more where the curve bends). `field` may be null (geometry only).
CurveSampling sampleCurve(const ICurve& c, double t0, double t1, const SizeField* field);

/// Parameters t_0 = t0 < ... < t_n = t1 of an n-segment discretisation whose 3D segment lengths
/// follow the size field; n >= minSegments, and n >= turning / maxTurn so that no segment turns
/// by more than maxTurn radians.
std::vector<double> discretizeCurve(const CurveSampling& cs, const SizeField& field, int minSegments,
                                    double maxTurn);
/// Same with any size function (e.g. the field widened along a narrow gap).
std::vector<double> discretizeCurve(const CurveSampling& cs, const std::function<double(Vec3)>& size, int minSegments,
                                    double maxTurn);

}  // namespace paramesh
