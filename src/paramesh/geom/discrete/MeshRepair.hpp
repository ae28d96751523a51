// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshRepair.hpp
/// What is safe to repair in triangulated input, repaired, and what is not, counted and located:
/// vertices closer than a tolerance relative to the model merged, facets with a non-finite
/// coordinate, degenerate (two equal corners, or no area) and duplicate facets dropped, each
/// connected piece oriented consistently across its manifold edges and, when closed, outward.
/// Non-manifold edges, holes (boundary loops) and pieces that cannot be oriented (a Moebius band)
/// are reported and left as they are.
#pragma once
#include <string>
#include <vector>

#include "paramesh/geom/discrete/TriangleSoup.hpp"

namespace paramesh {

struct RepairReport {
  int inputPoints = 0, inputTriangles = 0;
  int mergedVertices = 0;     ///< input points merged into another within the tolerance
  int nonFiniteFacets = 0;    ///< dropped: a NaN or infinite coordinate
  int degenerateFacets = 0;   ///< dropped: two equal corners after the merge, or zero area
  int duplicateFacets = 0;    ///< dropped: the same three corners as an earlier facet
  int flippedFacets = 0;      ///< turned to agree with their piece's orientation
  int pieces = 0, closedPieces = 0;
  int nonManifoldEdges = 0;   ///< edges of more than two facets (kept; each is a feature edge)
  int boundaryEdges = 0, holes = 0;  ///< edges of one facet; the loops they form
  int unorientablePieces = 0;
  double tolerance = 0;       ///< the merge distance used
  std::vector<Vec3> nonManifoldAt, holeAt;  ///< the first few of each (a point on it)
  /// One line per repair made and per problem left, e.g. "merged 12 vertices within 1.2e-06".
  std::vector<std::string> lines() const;
};

/// Repairs soup in place. mergeRel: the merge tolerance relative to the bounding-box diagonal
/// (default 1e-7: about the rounding of STL's single-precision coordinates).
/// An InputError when nothing is left (no point, or every facet dropped).
RepairReport repairTriangles(TriangleSoup& soup, double mergeRel = 1e-7);

}  // namespace paramesh
