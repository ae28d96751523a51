// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Coincidence.hpp
/// Finds CAD vertices and edges that coincide geometrically without being shared topologically
/// (unsewn faces, IGES patches). Coincident edges are discretised once and share their nodes, so
/// the mesh is watertight where the CAD is closed up to its tolerance.
#pragma once
#include <vector>

#include "paramesh/geom/Geometry.hpp"

namespace paramesh {

struct Coincidence {
  std::vector<int> vertexRep;      ///< representative of each vertex (itself when unique)
  std::vector<int> edgeRep;        ///< representative of each edge (itself when unique)
  std::vector<char> edgeReversed;  ///< the edge runs opposite to its representative
  int mergedVertices = 0, mergedEdges = 0;
  /// Per face: the first face bounded by the same (coincident) edges, itself when none. Only a
  /// candidate: whether the two faces are one surface region is checked once the first one is
  /// meshed (a hemisphere and the disk closing it share their boundary too).
  std::vector<int> faceCandidate;
};

/// Vertices closer than tol and edges whose curves lie within tol of each other (between
/// coincident vertices) are merged; faces bounded by the same merged edges are paired as
/// candidates. tol is an absolute length.
Coincidence findCoincident(const IGeometryModel& m, double tol);

}  // namespace paramesh
