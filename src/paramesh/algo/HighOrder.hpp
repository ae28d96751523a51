// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file HighOrder.hpp
/// Second-order elements: a mid-edge node on every mesh edge, placed on the CAD (on the CAD edge's
/// curve for edges along CAD edges, on the face's surface otherwise), then a validity check of the
/// curved elements: where the Jacobian of a curved triangle is not positive (against the surface
/// normal), its mid-nodes fall back to the straight chord midpoint and it is reported.
#pragma once
#include <array>
#include <vector>

#include "paramesh/geom/Geometry.hpp"
#include "paramesh/mesh/SurfaceMesh.hpp"

namespace paramesh {

struct HighOrderStats {
  int midNodes = 0;           ///< mid-edge nodes created
  int straightened = 0;       ///< mid-nodes put back on the chord to keep elements valid
  int invalidElements = 0;    ///< elements whose curved form had a non-positive Jacobian
  double minJacobianRatio = 1;  ///< min over elements of (min scaled Jacobian) after the fix
};

/// Makes m second order. triUv / quadUv: (u,v) of each element's corners on its face; segT: edge
/// parameters of each segment's ends.
HighOrderStats makeSecondOrder(SurfaceMesh& m, const IGeometryModel& g,
                               const std::vector<std::array<Vec2, 3>>& triUv,
                               const std::vector<std::array<Vec2, 4>>& quadUv,
                               const std::vector<std::array<double, 2>>& segT);

/// Scaled Jacobian of a 6-node triangle (corners a,b,c, mids ab,bc,ca) at its corners, mid-edges and
/// centroid, measured against normal n: min over samples of (J . n) / |straight J|. 1 for a straight
/// triangle, <= 0 when the curved element folds.
double tri6MinScaledJacobian(const Vec3 x[6], Vec3 n);
/// The same for an 8-node quad (corners a,b,c,d, mids ab,bc,cd,da), at corners, mid-edges and centre,
/// against the Jacobian of the straight quad at its centre.
double quad8MinScaledJacobian(const Vec3 x[8], Vec3 n);

}  // namespace paramesh
