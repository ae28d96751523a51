// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Report.hpp
/// What a meshing run reports: overall status, per-face status, per-stage timings, quality.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "paramesh/audit/AuditResult.hpp"

namespace paramesh {

/// Overall outcome: every face meshed / some faces failed (the rest is meshed) / nothing usable.
enum class RunStatus { Ok, Degraded, Failed };
const char* toString(RunStatus s);

struct FaceReport {
  int face = 0;                 ///< 1-based face number
  std::string surface;          ///< surface type
  bool ok = false;
  std::string error;            ///< reason when !ok
  int triangles = 0, quads = 0, nodes = 0;
  int rejectedPoints = 0;       ///< frontal points rejected (diagnostic)
  double seconds = 0;
  /// Triangles whose centroid is still farther from the surface than the deviation bounds allow
  /// (--curvature-angle, --max-deviation; not the nearest-face check's zones) after refinement, and of those: the worst
  /// distance / bound, where it is, and the smallest radius of curvature of the surface under
  /// them (FaceMeshResult::DeviationMiss; infinite: flat there).
  int overDeviation = 0;
  double overDeviationWorst = 0;
  double overDeviationAt[3] = {0, 0, 0};
  double overDeviationRadius = 0;
  /// of overDeviation, those where that radius is at least min-size / curvature angle (the
  /// min-size did not keep them from following the surface); 0 without a curvature angle
  int overDeviationResolvable = 0;
  /// edges embedded along the crests of folds narrower than the mesh (--curvature-angle; Crest.hpp)
  int crestSegments = 0;
  /// edges of the rows grown beside those crests (embedCrestRows)
  int crestRowSegments = 0;
};

/// Quality summary of the surface elements (triangles; quads reported separately).
struct QualitySummary {
  double gammaMin = 0, gammaMean = 0;       ///< radius ratio 2 r_in / r_circ
  double angleMin = 0, angleMax = 0;        ///< degrees
  double pctAngleBelow30 = 0;               ///< % of triangles whose min angle < 30 deg
  double pctLenInSqrt2 = 0;                 ///< % of edges with length / h in [1/sqrt2, sqrt2]
  double lenRatioMean = 0;                  ///< mean of length / h
  int invertedTriangles = 0;                ///< triangles facing against the surface normal
  // quads (quad-dominant meshes and boundary layers)
  double quadAngleMax = 0;                  ///< largest corner angle, degrees
  double quadAspectMean = 0, quadAspectMax = 0;  ///< longest / shortest side
  double quadWarpMax = 0;                   ///< largest angle between the normals of the two halves, degrees
  double pctAreaInQuads = 0;
};

/// Per boundary-layer specification: what was grown and why columns stopped.
struct BoundaryLayerReport {
  int spec = 0;                   ///< 1-based index of the specification
  std::vector<int> edges;         ///< 1-based CAD edges carrying it (coincident edges included)
  int layersRequested = 0;
  int columns = 0, fullColumns = 0, minLayers = 0, maxLayers = 0;
  int stopBoundary = 0;           ///< columns stopped by the face boundary
  int stopCollision = 0;          ///< ... by another layer
  int stopInvalid = 0;            ///< ... because the next quad would fold
  int stopAspect = 0;             ///< ... at the aspect-ratio limit (hand-off)
  int stopEdgeEnd = 0;            ///< outermost columns cut by the end of the edge they run along
  int fans = 0, merges = 0;       ///< corners
  int elements = 0;               ///< quads (or split triangles) in the layers
};

/// An automatically proposed leading edge.
struct ProposedEdge {
  int edge = 0;                 ///< 1-based
  double radius = 0;            ///< radius of curvature across the edge
  double ratio = 0;             ///< across / along curvature
};

/// Per solid: the volume fill (stages/volume).
struct SolidReport {
  int solid = 0;                 ///< 1-based solid number (FreeCAD Solid<i>)
  std::vector<int> faces;        ///< 1-based faces bounding it
  bool ok = false;
  std::string error;             ///< why it was not filled (names the faces or nglib's message)
  int tetrahedra = 0, nodes = 0;  ///< nodes: inside the solid (not on its surface)
  double minDihedral = 0, meanDihedral = 0, maxDihedral = 0;  ///< degrees
  double pctDihedralBelow10 = 0;  ///< % of tetrahedra with a dihedral angle < 10 degrees
  double minRadiusRatio = 0, meanRadiusRatio = 0;  ///< 3 r_in / r_circ (1: regular)
  double volume = 0;             ///< sum of the tetrahedra's volumes
  double seconds = 0;
};

struct Report {
  RunStatus status = RunStatus::Ok;
  std::string message;                      ///< one-line summary (the reason when not Ok)
  std::string source;                       ///< input description
  int cadFaces = 0, cadEdges = 0, cadVertices = 0, cadSolids = 0;
  double size = 0, minSize = 0, maxSize = 0, curvatureAngle = 0, maxDeviation = 0, grading = 0;
  bool volume = false;           ///< the run filled the solids (volume, volume_max_size, volume_optimize)
  double volumeMaxSize = 0;
  int volumeOptimize = 0;
  int threads = 1;
  int nodes = 0, triangles = 0, quads = 0;
  int order = 1;
  int midNodes = 0, straightenedMidNodes = 0;  ///< second order: created / put back on the chord
  double minScaledJacobian = 1;                ///< second order: worst curved element (1 = straight)
  int tetrahedra = 0;                          ///< volume fill: all solids
  int straightenedTets = 0;                    ///< second order: tet10s put back straight (Jacobian)
  double minTetJacobian = 1;                   ///< second order: worst tet10's scaled Jacobian
  std::vector<SolidReport> solids;             ///< volume fill, one per solid of the model
  /// (source, copy) 1-based faces that coincide without being shared: the copy took the source's triangles
  std::vector<std::pair<int, int>> coincidentFaces;
  int solidsFilled() const {
    int n = 0;
    for (const auto& s : solids) n += s.ok;
    return n;
  }
  double tetMinDihedral() const {
    double m = 180;
    for (const auto& s : solids)
      if (s.ok && s.minDihedral < m) m = s.minDihedral;
    return m;
  }
  /// nearest-face check: triangles found nearer another face than their own, per meshing round
  /// (the last entry is the final mesh's count; one entry when the first mesh had none)
  std::vector<int> nearestFaceFlagged;
  /// nearest-face check: faces meshed again in each round after the first (the others kept theirs)
  std::vector<int> nearestFaceRemeshed;
  /// "refined" (kept), "kept unrefined" (over the budget) or "" (not run / nothing flagged)
  std::string nearestFaceOutcome;
  double nearestFaceGrowth = 0;  ///< triangles after refinement / before - 1
  size_t sizeSources = 0;
  std::vector<FaceReport> faces;
  std::vector<BoundaryLayerReport> boundaryLayers;
  std::vector<ProposedEdge> proposedLeadingEdges;  ///< filled when a layer asked for auto edges
  std::vector<std::pair<std::string, double>> stageSeconds;  ///< per stage, summed over nearest-face rounds
  QualitySummary quality;
  AuditResult audit;                        ///< the final audit (stages/audit): never "ok" unless it passed
  std::vector<std::string> warnings;
  std::vector<std::string> extraJson;       ///< "key": value fragments added by optional stages
};

}  // namespace paramesh
