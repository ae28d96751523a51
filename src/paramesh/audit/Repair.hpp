// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Repair.hpp
/// The local repair of what the audit finds folded or facing against its surface: the face nodes
/// of those elements move, on their surface, towards the centre of their neighbours until every
/// element around them faces along the surface again. Nodes on CAD edges and vertices stay.
#pragma once
#include <array>
#include <vector>

#include "paramesh/geom/Geometry.hpp"
#include "paramesh/mesh/SurfaceMesh.hpp"

namespace paramesh {

/// Moves face nodes of the bad elements (triangle t, or triangles + quad q) of an order-1 surface
/// mesh; triUv / quadUv (per element, its corners' (u,v) on its face) follow. A move is kept only
/// when no element around the node is left facing against its surface or folded, and the worst
/// angle there does not fall. Returns the number of nodes moved.
int repairBadElements(const IGeometryModel& g, SurfaceMesh& m, std::vector<std::array<Vec2, 3>>& triUv,
                      std::vector<std::array<Vec2, 4>>& quadUv, const std::vector<int>& bad);

}  // namespace paramesh
