// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file BoundaryLayer.hpp
/// Surface boundary layers: rows of stretched quads grown *in the surface* from CAD edges.
///
/// Columns start at the nodes of a boundary-layer (BL) edge and march in 3D: each step goes along
/// the in-surface conormal b = n x t (n the surface normal, t the row tangent, recomputed at every
/// layer), is re-projected on the CAD surface and corrected until its straight 3D length is the row
/// height h_k = h0 r^k. Where a BL edge ends at a non-BL edge, the outermost column runs along that
/// edge and its points become nodes of that edge's discretisation (the mesh stays conformal with the
/// neighbouring face). Corners between two BL edges of one face get a merged column (the face angle
/// is below 180 degrees) or a fan of columns (above). Columns stop at N layers, at the optional
/// aspect limit, or on collision (face boundary, other columns, other layers), and the stop is
/// reported. The last row is the front handed to the isotropic face mesher.
///
///        Q_i^2 ---- Q_{i+1}^2        row k = 2    quads (Q_i^k, Q_{i+1}^k, Q_{i+1}^{k+1}, Q_i^{k+1})
///          |           |
///        Q_i^1 ---- Q_{i+1}^1        row k = 1
///          |           |
///   BL edge P_i ------ P_{i+1}       row k = 0 (edge nodes)
#pragma once
#include <array>
#include <string>
#include <vector>

#include "paramesh/algo/DomainGuard.hpp"
#include "paramesh/geom/Geometry.hpp"
#include "paramesh/pipeline/Params.hpp"

namespace paramesh {

struct Coincidence;

/// Row heights of one specification: h_k = h0 r^k for k = 0..layers-1.
struct LayerLaw {
  double h0 = 0, r = 1;
  int layers = 0;
  double maxAspect = 0;  ///< stop when spacing / h_k falls below this (0: off)
  bool quads = true;     ///< quads, or each quad split into two triangles
  double height(int k) const;
  /// Sum of the first k heights (distance of row k from the edge).
  double offset(int k) const;
  static LayerLaw from(const BoundaryLayerSpec& s);
};

/// One point of a face boundary loop as the BL stage sees it.
struct LoopPoint {
  Vec2 uv;
  Vec3 xyz;
  int node = -1;
  int edge = -1;  ///< 0-based CAD edge of the segment starting at this point (-1 unknown)
  bool pole = false;
};

/// A new (face-local) node created by the BL stage.
struct BLNode {
  Vec2 uv;
  Vec3 xyz;
};

/// Reference to a node in BL output: >= 0 global node, < 0 new local node -(k+1).
struct FaceBLResult {
  std::vector<BLNode> nodes;                ///< new face-local nodes
  std::vector<std::array<int, 4>> quads;    ///< oriented counter-clockwise in (u,v)
  std::vector<std::array<Vec2, 4>> quadUv;  ///< (u,v) of each quad's corners
  std::vector<std::array<int, 3>> tris;     ///< fan triangles at reflex corners
  std::vector<std::array<Vec2, 3>> triUv;
  std::vector<int> quadSpec, triSpec;       ///< the spec (index) each quad / triangle belongs to
  std::vector<std::vector<LoopPoint>> loops;  ///< the face loops with BL regions cut out
  /// Hand-off: (point, size) pairs along the fronts.
  std::vector<std::pair<Vec3, double>> frontSizes;
  // statistics per spec (index into the specs)
  struct SpecStats {
    int columns = 0, fullColumns = 0, minLayers = 1 << 30, maxLayers = 0;
    int stopBoundary = 0, stopCollision = 0, stopInvalid = 0, stopAspect = 0, stopEnd = 0;
    int fans = 0, merges = 0;
    int elements = 0;  ///< quads (or triangles) of the layers
  };
  std::vector<SpecStats> stats;
  std::vector<std::string> warnings;
};

/// Which BL spec (index) each 0-based CAD edge belongs to, -1 for none.
using EdgeSpecMap = std::vector<int>;

/// 1D part, before edge discretisation: the points of the outermost columns along non-BL edges.
/// For each edge, parameters measured from its start (t0 side) and from its end (t1 side), in order
/// of distance from that end; an edge without BL points has empty lists.
struct EdgeBLPoints {
  std::vector<double> fromStart, fromEnd;
  double lastHeightStart = 0, lastHeightEnd = 0;  ///< height of the last row reaching each end
};
/// With `same` (unsewn CAD), the points of an edge meshed through a coincident representative
/// are planned on the representative (its parameters, from its vertex nodes).
std::vector<EdgeBLPoints> planEndColumns(const IGeometryModel& m, const EdgeSpecMap& specOf,
                                         const std::vector<LayerLaw>& laws, const Coincidence* same = nullptr);

/// 2D part: grows the layers inside one face whose loops (in order, as built for meshing) contain
/// BL edges. Node refs of loop points are global; the result's loops replace the face's loops.
/// trueLoops are the loops the guard was built from (the pcurves sampled finely), one per loop.
FaceBLResult growFaceLayers(const ISurface& s, bool faceReversed, const std::vector<std::vector<LoopPoint>>& loops,
                            const std::vector<std::vector<Vec2>>& trueLoops, const DomainGuard& guard,
                            const EdgeSpecMap& specOf, const std::vector<LayerLaw>& laws,
                            const std::vector<EdgeBLPoints>& endPoints);

}  // namespace paramesh
