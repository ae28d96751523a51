// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file SelfIntersection.hpp
/// Pairs of surface triangles that cross each other: a solid's surface that self-intersects
/// cannot be filled, and the pairs name the faces where it does.
#pragma once
#include <array>
#include <utility>
#include <vector>

#include "paramesh/util/Vec.hpp"

namespace paramesh {

/// Up to maxPairs pairs (i < j) of triangles whose interiors cross: an edge of one passes through
/// the other beyond a relative tolerance. Triangles sharing an edge are not compared; sharing a
/// node, only the edges away from it are. Neighbourhoods through a uniform grid of triangle boxes.
std::vector<std::pair<int, int>> crossingTriangles(const std::vector<Vec3>& nodes,
                                                   const std::vector<std::array<int, 3>>& tris,
                                                   std::size_t maxPairs = 20);

}  // namespace paramesh
