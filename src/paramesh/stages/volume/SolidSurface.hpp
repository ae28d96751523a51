// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file SolidSurface.hpp
/// A solid's boundary as the surface mesh has it: its faces' triangles, oriented out of that
/// solid (a face shared by two solids is used by both, flipped for one), and whether they close.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "paramesh/geom/Geometry.hpp"
#include "paramesh/mesh/SurfaceMesh.hpp"

namespace paramesh {

struct SolidSurface {
  std::vector<int> faces;                       ///< 1-based faces bounding the solid
  std::vector<std::array<int, 3>> triangles;    ///< mesh node indices, counter-clockwise seen from outside
  std::vector<int> triangleFace;                ///< 1-based face of each
  std::string problem;                          ///< why it cannot be filled ("" when closed and oriented)
};

/// trianglesOfFace: per 0-based face, its triangles in m. A surface is refused (problem set) when
/// a face of the solid has no triangle or quads, when it is used twice by the solid (an internal
/// face), or when its triangles do not form a closed, consistently oriented 2-manifold: the
/// problem counts the open, over-used and misoriented mesh edges and names the faces they touch.
/// A closed surface of negative enclosed volume (a solid inside out) is flipped.
SolidSurface solidSurface(const IGeometryModel& g, int solid, const SurfaceMesh& m,
                          const std::vector<std::vector<int>>& trianglesOfFace,
                          const std::vector<int>& quadsOfFace);

}  // namespace paramesh
