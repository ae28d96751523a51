// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file PatchParam.hpp
/// The (u,v) parametrisation of one disk-like face of triangulated input: the face's triangles
/// cut open along its seams (a node on a seam gets one copy per side), the boundary wire laid on
/// the unit circle by 3D arc length, the inside placed by Floater's mean-value weights (positive
/// weights on a disk with a convex boundary: no triangle folds, Tutte/Floater). S(u,v) is the
/// input triangle at (u,v), linearly: the surface is the input's own, exactly.
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "paramesh/geom/discrete/FeatureGraph.hpp"

namespace paramesh {

struct PatchParam {
  std::vector<int> node;                    ///< per local vertex: its mesh node
  std::vector<Vec2> uv;                     ///< per local vertex
  std::vector<std::array<int, 3>> tris;     ///< local corners, oriented as the input (CCW in (u,v))
  /// per wire use (in faceLoops order): the local vertex of each chain node, in the chain's order
  std::vector<std::vector<int>> useVertices;
  std::string error;                        ///< why the face could not be parametrised ("" when it could)
};

/// Parametrises face f of g (after cutFacesToDisks).
PatchParam parametrizeFace(const TriangleSoup& mesh, const FeatureGraph& g, int f);

}  // namespace paramesh
