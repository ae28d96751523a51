// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file BrepPrecheck.hpp
/// Internal: the structure check run on a BREP text before OpenCASCADE's reader sees it
/// (OccModel.cpp), exposed for its tests. Plain text work, no OpenCASCADE header.
#pragma once
#include <string>

namespace paramesh::detail {

/// What in a BREP text would make OpenCASCADE 7.6's BRepTools::Read loop, throw or read no shape,
/// or "" when its structure is what that reader reads. The check follows the reader token by
/// token at the section level: the version line it looks for, the section headers in the order
/// its readers take them (Polygon3D, PolygonOnTriangulations and Triangulations may be absent
/// where the token the reader then swallows leaves the rest aligned, as OpenCASCADE does), as many
/// shape records (each closed by '*') as the TShapes count, and a root shape reference naming
/// one of them (any orientation code: + - i e, any location index). A text cut short fails here
/// at once: OpenCASCADE's reader can spend minutes on its failed stream.
std::string brepStructureProblem(const std::string& text);

}  // namespace paramesh::detail
