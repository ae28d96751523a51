// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file FaceDomain.hpp
/// Helpers on a face's trimmed (u,v) domain: wire polygons sampled from the pcurves (with the
/// periodic shifts that make each wire a closed loop), and point-in-domain classification.
#pragma once
#include <vector>

#include "paramesh/algo/DomainGuard.hpp"
#include "paramesh/geom/Geometry.hpp"

namespace paramesh {

class FaceDomain {
 public:
  /// Samples every wire of face f (perUse points per edge use).
  FaceDomain(const IGeometryModel& m, int f, const ISurface& s, int perUse = 24);
  /// Even-odd classification of (u,v) against all loops (grid-accelerated, O(1) average).
  bool inside(Vec2 uv) const;
  const std::vector<std::vector<Vec2>>& loops() const { return loops_; }
  /// Bounding box of the loops in (u,v).
  UVBox box() const { return box_; }

 private:
  std::vector<std::vector<Vec2>> loops_;
  UVBox box_;
  DomainGuard guard_;
};

/// Shifts q by whole periods so that it is as close as possible to ref (periods of 0 are ignored).
Vec2 unwrapNear(Vec2 q, Vec2 ref, double uPeriod, double vPeriod);

}  // namespace paramesh
