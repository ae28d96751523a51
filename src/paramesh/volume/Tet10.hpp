// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Tet10.hpp
/// Second-order tetrahedra: the mid-node of an edge on the surface is the surface triangle's
/// (on the CAD), an interior edge gets its straight midpoint. A tet10 whose Jacobian is not
/// positive everywhere gets its mid-nodes back on the chords (its surface triangles then are
/// straight there too).
#pragma once
#include "paramesh/mesh/SurfaceMesh.hpp"

namespace paramesh {

struct Tet10Stats {
  int midNodes = 0;       ///< interior mid-nodes created
  int straightened = 0;   ///< tet10s whose mid-nodes were put back on the chords
  double minScaledJacobian = 1;  ///< after the fix
};

/// Fills m.tetMid (m must already be order 2: triangleMid set).
Tet10Stats makeTet10(SurfaceMesh& m);

/// min over the corners, mid-edges and centroid of det(J) / det(J of the straight tet); x in
/// tet10 order (corners a,b,c,d, mids ab, bc, ca, ad, bd, cd). 1 for a straight tet, <= 0 folded.
double tet10MinScaledJacobian(const Vec3 x[10]);

}  // namespace paramesh
