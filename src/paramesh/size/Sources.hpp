// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Sources.hpp
/// Size sources computed from the CAD: curvature of faces and edges, and user local sizes.
#pragma once
#include <vector>

#include "paramesh/geom/Geometry.hpp"
#include "paramesh/pipeline/Params.hpp"
#include "paramesh/size/SizeField.hpp"

namespace paramesh {

struct SizeSource {
  Vec3 p;
  double h;
};

/// Maximum absolute principal curvature of the surface at uv (0 where undefined).
double maxCurvature(const ISurface& s, Vec2 uv);
/// The same from already evaluated derivatives.
double curvatureFromD2(const SurfaceD2& d);

/// Size asked by curvature kappa: the smaller of 0.75 angle/kappa (so that elements, whose edges
/// range up to ~1.3x the target, subtend at most `angle` radians; 0: off) and sqrt(8 deviation / kappa) (chordal deviation at most `deviation`, a length;
/// 0: off), clamped to [hmin, hmax].
double curvatureSize(double kappa, double angleRad, double deviation, double hmin, double hmax);

/// How the adaptive sampling of one face went.
struct FaceSamplingStats {
  long cells = 0;          ///< cells evaluated (one second-derivative evaluation each)
  bool truncated = false;  ///< the cell budget stopped splits the sizes asked for
};

/// Cells one face's curvature sampling may evaluate (propeller_and_shaft's blade faces take
/// 541 666 at --curvature-angle 10).
constexpr long kFaceSamplingBudget = 2000000;

/// Curvature sources of face f (sizes from curvatureSize with kappa = max principal curvature)
/// sampled on an adaptive (u,v) grid inside the trimmed face, refined where h is small compared to
/// the cells. Past `budget` cells no cell is split any more (the base grid, cells about hmax
/// across, is still evaluated): the rest of the face is sampled coarser than its sizes
/// (stats->truncated tells; the caller reports it).
std::vector<SizeSource> faceCurvatureSources(const IGeometryModel& m, int f, double angleRad, double hmin,
                                             double hmax, double deviation = 0, FaceSamplingStats* stats = nullptr,
                                             long budget = kFaceSamplingBudget);
/// Curvature sources along edge e (curve curvature).
std::vector<SizeSource> edgeCurvatureSources(const IGeometryModel& m, int e, double angleRad, double hmin,
                                             double hmax, double deviation = 0);
/// Sources covering the entities of a local size (faces sampled at spacing ~ size).
std::vector<SizeSource> localSizeSources(const IGeometryModel& m, const LocalSize& ls);

}  // namespace paramesh
