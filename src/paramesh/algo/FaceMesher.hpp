// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file FaceMesher.hpp
/// Meshes one CAD face: boundary CDT in the scaled (u,v) plane, frontal-Delaunay insertion with
/// points placed in 3D (tangent-plane prediction, Newton re-projection on the surface), then 3D
/// optimisation (see optimizer/Optimizer.hpp). Sizes are straight 3D edge lengths against the size field.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "paramesh/algo/DeviationZone.hpp"
#include "paramesh/geom/Geometry.hpp"
#include "paramesh/size/SizeField.hpp"
#include "paramesh/util/Log.hpp"

namespace paramesh {

/// A boundary point of a face: one node of a discretised CAD edge seen from this face.
struct BoundaryVertex {
  Vec2 uv;          ///< parameter on the face (unscaled)
  Vec3 xyz;         ///< 3D position (the shared edge node)
  int node = -1;    ///< global node id (>= 0), or a face-local node -(k+1) (boundary-layer front)
  bool pole = false;  ///< one of several (u,v) images of a degenerate-edge node
  int edge = -1;    ///< 0-based CAD edge of the boundary segment starting here (-1: none)
};

/// The closed loops bounding a face, each a cyclic list of boundary points in (u,v).
struct FaceBoundary {
  std::vector<std::vector<BoundaryVertex>> loops;
  /// Extra constrained segments (pairs of (loop, index)) inside the face, e.g. a boundary-layer
  /// front; unused for plain faces.
  std::vector<std::array<int, 4>> extraSegments;
  /// The true trimmed boundary in (u,v): the pcurves sampled finely (closed loops). New interior
  /// nodes must lie inside it. Empty: no guard (the boundary chords are exact, e.g. polygons).
  std::vector<std::vector<Vec2>> trueLoops;
  /// The edges (0-based) whose pcurve strays from the edge's nodes (more than 1e-3 of the size),
  /// each with the largest distance (3D) between the pcurve's image and a node.
  std::vector<std::pair<int, double>> strayPcurves;
};

struct FaceMeshOptions {
  int optimizePasses = 4;
  double acceptRadius = 0.7071;   ///< frontal: triangles whose metric circumradius is below are accepted
  long maxPoints = 50000000;    ///< hard cap on inserted points (guards against runaway refinement)
  double maxDeviation = 0;      ///< max distance of a triangle centroid from the surface (length); 0: off
  double maxDeviationRatio = 0; ///< max centroid distance from the surface / the triangle's mean edge; 0: off
  double minSplitLength = 0;    ///< deviation refinement splits no edge shorter than this
  bool embedCrests = true;      ///< with maxDeviationRatio: embed the crests of folds narrower than the mesh (Crest.hpp)
  bool crestRows = true;        ///< and grow rows beside them across the fold's shoulders (embedCrestRows)
  /// The user's min-size / curvature angle (0: none): where the surface turns faster than that
  /// radius, the relative deviation bound grows to what triangles at the min-size can meet
  /// (Optimizer::setMinSizeReach)
  double minSizeReach = 0;
  std::vector<DeviationZone> deviationZones;  ///< local deviation bounds (centroid inside a ball)
  int localNodeOffset = 0;      ///< face-local nodes already taken (boundary-layer nodes)
  bool quads = false;           ///< pair triangles into quads (quad-dominant)
  bool sliverPass = true;       ///< post-pass against triangles with angles below 30 degrees
  bool reportOffSurface = false;  ///< fill FaceMeshResult::offSurface (nearest-face check)
  const SizeField* overlay = nullptr;  ///< extra face-local sizes (boundary-layer hand-off); min with the field
};

/// Result of meshing one face. Node references: >= 0 is a global node, < 0 is new local node
/// -(k+1) with coordinates newXyz[k], parameter newUv[k].
struct FaceMeshResult {
  bool ok = false;
  std::string error;                 ///< reason when !ok
  std::vector<Vec3> newXyz;
  std::vector<Vec2> newUv;
  std::vector<std::array<int, 3>> tris;  ///< oriented like S_u x S_v (caller flips reversed faces)
  std::vector<std::array<Vec2, 3>> triUv;  ///< (u,v) of each triangle's corners, contiguous across seams
  std::vector<std::array<int, 4>> quads;   ///< boundary-layer quads (same node-reference rules)
  std::vector<std::array<Vec2, 4>> quadUv;
  /// Boundary-layer spec (1-based) of each triangle / quad, 0 for the isotropic mesh; empty when
  /// the face has no layer.
  std::vector<int> triLayer, quadLayer;
  /// Triangles (index in tris, centroid distance to the face) whose centroid lies more than 2 % of
  /// their mean edge off the face: candidates for the nearest-face check. The distance is the
  /// projection's, or the distance to the face's boundary when the projection's foot falls
  /// outside the trimmed face (a fillet's chord next to its edge).
  std::vector<std::pair<int, double>> offSurface;
  /// Triangles still beyond the deviation bounds (FaceMeshOptions::maxDeviation and
  /// maxDeviationRatio; not the deviationZones) after refinement: where, by how much, and the surface's
  /// radius of curvature under it (the smallest principal radius at the corners, the edges' (u,v)
  /// midpoints and the centroid's foot).
  struct DeviationMiss {
    Vec3 at;
    double deviation = 0, allowed = 0, radius = 0;
  };
  std::vector<DeviationMiss> deviationMisses;
  int rejectedPoints = 0;
  int crestSegments = 0;  ///< constrained edges embedded along fold crests (Crest.hpp)
  int crestRowSegments = 0;  ///< constrained edges of the rows beside them (embedCrestRows)
  int degenerateDropped = 0;
};

/// Meshes one face. Never throws on geometric trouble: returns ok = false with the reason;
/// throws only Cancelled (through progress->poll()).
FaceMeshResult meshFace(const ISurface& surf, const FaceBoundary& boundary, const SizeField& size,
                        const FaceMeshOptions& opt, const Progress* progress);

}  // namespace paramesh
