// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file ForcedSliver.hpp
/// Whether the mesh's worst triangle is forced by the CAD: all its nodes on CAD edges or vertices,
/// and a CAD edge of its face there far shorter than the size or than its neighbour at a corner.
#pragma once
#include <string>

#include "paramesh/geom/Geometry.hpp"
#include "paramesh/mesh/SurfaceMesh.hpp"
#include "paramesh/size/SizeField.hpp"

namespace paramesh {

/// The warning naming the edge that forces the worst triangle ("the worst triangle, gamma X on
/// FaceN, is forced by EdgeM (length L, h H)"), or "" when the worst triangle is not forced so
/// (or is no sliver: radius ratio at least kForcedBelow).
std::string forcedSliverWarning(const SurfaceMesh& mesh, const IGeometryModel& model, const SizeField& field);

/// Worst triangles at or above this radius ratio are not reported.
inline constexpr double kForcedBelow = 0.25;

}  // namespace paramesh
