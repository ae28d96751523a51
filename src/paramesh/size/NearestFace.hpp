// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file NearestFace.hpp
/// The nearest-face check. A triangle belongs to its CAD face: its centroid should lie nearer that
/// face than any other. A coarse triangle on a strongly curved part of a thin body (a blade tip, a
/// fillet against a flat cap) can cut so deep that its centroid is nearer the opposite skin or the
/// neighbouring face: it then misrepresents the geometry (and an independent checker that assigns
/// triangles to the nearest face sees it on the wrong face). Such triangles are found on the
/// assembled mesh and turned into size sources; the caller meshes again with them.
#pragma once
#include <functional>
#include <vector>

#include "paramesh/mesh/SurfaceMesh.hpp"
#include "paramesh/size/Sources.hpp"

namespace paramesh {

/// A triangle whose centroid lies `deviation` off its own face (measured by the face mesher: the
/// projection on its surface, or the distance to the face's boundary when the projection's foot
/// falls outside the trimmed face).
struct OffSurfaceTriangle {
  int tri = -1;
  double deviation = 0;
};

struct NearestFaceResult {
  int flagged = 0;                  ///< triangles nearer another face's mesh than their own surface
  std::vector<SizeSource> sources;  ///< sizes that bring them back (empty when none can be refined)
  std::vector<std::array<double, 3>> found;  ///< per flagged triangle: index, own deviation, distance to the other face
  std::vector<Vec3> otherFoot;               ///< per flagged triangle: the nearest point found on the other face
  std::vector<int> firstSource;              ///< per flagged triangle: its first source (4 in a row), -1: none
};

/// Distance from point c to the CAD face of mesh triangle `tri`, given the closest point of that
/// triangle to c (a seed for a projection on the face's surface); sets *foot to the point of the
/// face it measured to (left at `closest` when it found none).
using FaceDistance = std::function<double(Vec3 c, int tri, Vec3 closest, Vec3* foot)>;

/// For every candidate, the distance from its centroid to each other face near it: first on the
/// mesh (the nearest triangle of each other face whose distance, lowered by that triangle's own
/// deviation `triangleDeviation` when given, is within reach), then on the CAD through
/// `faceDistance` (when given). A candidate is flagged when that distance is below `margin` times
/// its own deviation. Its size target: its mean edge times sqrt(0.5 other / own) (chordal
/// deviation goes with the square of the size), between 0.3 and 0.7 of the mean edge, at its
/// centroid and its three nodes; none below hmin. Linear in the mesh size (one pass over the
/// elements through a hash grid of the candidates).
NearestFaceResult nearestFaceSources(const SurfaceMesh& mesh, const std::vector<OffSurfaceTriangle>& candidates,
                                     double hmin, const std::vector<double>* triangleDeviation = nullptr,
                                     const FaceDistance& faceDistance = nullptr, double margin = 1.1);

}  // namespace paramesh
