// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshDigest.hpp
/// A 64-bit digest of everything the element and edge-use audits read (nodes, elements, their
/// faces and (u,v), segments, tetrahedra, mid-nodes): two audits of meshes with equal digests
/// find the same, so the final audit can reuse the repair pass's findings when nothing changed.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "paramesh/mesh/SurfaceMesh.hpp"

namespace paramesh {

uint64_t meshDigest(const SurfaceMesh& m, const std::vector<std::array<Vec2, 3>>& triUv,
                    const std::vector<std::array<Vec2, 4>>& quadUv);

}  // namespace paramesh
