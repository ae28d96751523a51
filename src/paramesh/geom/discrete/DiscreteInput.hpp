// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file DiscreteInput.hpp
/// Triangulated input read, repaired and split into faces, edges and vertices (the discrete
/// backend's first stages), and its description for `paramesh info`.
#pragma once
#include <string>
#include <vector>

#include "paramesh/geom/discrete/FeatureGraph.hpp"
#include "paramesh/geom/discrete/MeshRepair.hpp"
#include "paramesh/geom/discrete/TriangleSoup.hpp"

namespace paramesh {

struct DiscreteInput {
  TriangleSoup mesh;  ///< repaired
  RepairReport repair;
  FeatureGraph graph;
  double featureAngle = 40.0;
};

/// Reads (readTriangleFile), repairs (repairTriangles) and finds the features of a file.
DiscreteInput loadDiscrete(const std::string& path, double featureAngleDeg = 40.0);
/// The same from arrays (points, 0-based triangles).
DiscreteInput discreteFromArrays(TriangleSoup soup, double featureAngleDeg = 40.0);

/// Lines for `paramesh info`: the counts, each repair and problem, then one line per face and edge.
std::vector<std::string> describeDiscrete(const DiscreteInput& d);

}  // namespace paramesh
