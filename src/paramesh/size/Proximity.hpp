// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Proximity.hpp
/// Proximity sizing: thin walls and narrow faces get at least N elements across. Measured in 3D on
/// a first (coarse) surface mesh: between facing surfaces (opposite normals, the other surface
/// behind the point), and across each face between non-neighbouring parts of its boundary.
#pragma once
#include <vector>

#include "paramesh/mesh/SurfaceMesh.hpp"
#include "paramesh/size/Sources.hpp"

namespace paramesh {

/// Size sources h = gap / n at the points where a gap (wall thickness or face width) is below
/// n * hmax. mesh: a valid surface mesh of the model (triangles with their CAD faces and the node
/// normals implied by their orientation).
std::vector<SizeSource> proximitySources(const SurfaceMesh& mesh, int n, double hmax, double hmin);

}  // namespace paramesh
