// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file TriangleSoup.hpp
/// Triangulated input as read (STL, OBJ; arrays from Python or a FreeCAD Mesh): points and
/// triangles, not yet repaired (discrete/MeshRepair.hpp) nor split into faces and edges
/// (discrete/FeatureGraph.hpp).
#pragma once
#include <array>
#include <string>
#include <vector>

#include "paramesh/util/Vec.hpp"

namespace paramesh {

struct TriangleSoup {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;  ///< 0-based corners, in file order
  std::string source;                         ///< file name, or "arrays"
  int readerDropped = 0;  ///< facets of the file its reader left out (two equal corners)
};

/// True for the file extensions readTriangleFile() reads (.stl, .obj; any case).
bool isTriangleFile(const std::string& path);

/// Reads an STL (ASCII or binary) or OBJ file with OpenCASCADE's readers (RWStl, RWObj: nodes of
/// equal coordinates already shared). A file cut short, a binary STL whose header disagrees with
/// its size, or one without a facet is an InputError naming the file and what is wrong.
TriangleSoup readTriangleFile(const std::string& path);

}  // namespace paramesh
