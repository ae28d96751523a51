// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file TetQuality.hpp
/// Shape measures of tetrahedra: signed volume, dihedral angles, radius ratio; and the
/// topological checks of a tetrahedral fill against the surface it was filled from.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "paramesh/util/Vec.hpp"

namespace paramesh {

/// Six times the signed volume, ((b-a)x(c-a)).(d-a).
double tetVolume6(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
/// The six interior dihedral angles in degrees (edges ab, ac, ad, bc, bd, cd).
std::array<double, 6> tetDihedrals(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
/// 3 r_in / r_circ: 1 for the regular tetrahedron, 0 for a flat one.
double tetRadiusRatio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

struct TetStats {
  int tets = 0;
  double minDihedral = 180, maxDihedral = 0, meanDihedral = 0;  ///< degrees, over all angles
  double pctBelow10 = 0;  ///< % of tetrahedra with some dihedral angle below 10 degrees
  double minRadiusRatio = 1, meanRadiusRatio = 0;
  double volume = 0;
  int inverted = 0;       ///< non-positive volume
};
TetStats tetStats(const std::vector<Vec3>& nodes, const std::vector<std::array<int, 4>>& tets);

/// "" when the tetrahedra fill exactly the closed surface: every tetrahedron positive, every
/// tetrahedron face shared by at most two of them, and the faces used once are the surface
/// triangles (as oriented triangles, outward), each once. Otherwise what is wrong, with counts.
std::string checkFill(const std::vector<Vec3>& nodes, const std::vector<std::array<int, 4>>& tets,
                      const std::vector<std::array<int, 3>>& surface);

}  // namespace paramesh
