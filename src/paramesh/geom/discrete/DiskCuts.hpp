// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file DiskCuts.hpp
/// Each face of a feature graph made a topological disk for its parametrisation: a face with
/// holes gets, per hole, a seam from one of the hole's corners to a corner of its outer wire
/// along the shortest path of mesh edges inside the face (a new edge used twice by that face,
/// as the seam of a CAD cylinder). The wires are rewired to walk each seam out and back.
#pragma once
#include <string>
#include <vector>

#include "paramesh/geom/discrete/FeatureGraph.hpp"

namespace paramesh {

/// Cuts g's faces in place. Returns, per face, "" or why it cannot be made a disk (no boundary:
/// a closed smooth surface; no path inside the face from a hole to the outer wire).
std::vector<std::string> cutFacesToDisks(const TriangleSoup& mesh, FeatureGraph& g);

}  // namespace paramesh
