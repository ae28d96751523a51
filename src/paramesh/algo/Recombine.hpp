// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Recombine.hpp
/// Quad-dominant meshes: pairs of adjacent triangles merged into well-shaped quads. A greedy
/// matching by quad quality, then augmenting paths (alternating matched / unmatched pairs) that
/// pair left-over triangles. Only pairs across free (unconstrained) edges whose quad is convex in
/// (u,v) and in 3D with every corner below the angle limit are candidates.
#pragma once
#include <array>
#include <vector>

#include "paramesh/algo/Triangulation.hpp"

namespace paramesh {

struct QuadPair {
  int t, u;  ///< the two triangles
  std::array<int, 4> quad;  ///< vertices, counter-clockwise in (u,v)
};

/// Pairs triangles of T (live ones). maxAngleDeg: largest corner angle allowed in a quad.
std::vector<QuadPair> recombine(const Triangulation& T, double maxAngleDeg = 150.0);

/// Quality of a quad in 3D: 1 - max |corner angle - 90| / 90 (1 for a rectangle, <= 0 for a
/// corner of 180 degrees or more). Non-convex quads get a negative value.
double quadQuality(Vec3 a, Vec3 b, Vec3 c, Vec3 d);

}  // namespace paramesh
