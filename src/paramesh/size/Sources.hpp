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

/// Curvature sources of face f: sizes h = angle / kappa_max (clamped to [hmin, hmax]) sampled on an
/// adaptive (u,v) grid inside the trimmed face, refined where h is small compared to the cells.
std::vector<SizeSource> faceCurvatureSources(const IGeometryModel& m, int f, double angleRad, double hmin,
                                             double hmax);
/// Curvature sources along edge e (curve curvature).
std::vector<SizeSource> edgeCurvatureSources(const IGeometryModel& m, int e, double angleRad, double hmin,
                                             double hmax);
/// Sources covering the entities of a local size (faces sampled at spacing ~ size).
std::vector<SizeSource> localSizeSources(const IGeometryModel& m, const LocalSize& ls);

}  // namespace paramesh
