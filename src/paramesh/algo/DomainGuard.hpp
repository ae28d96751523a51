// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file DomainGuard.hpp
/// Point-in-face classification in the (u,v) plane against the *true* trimmed boundary (the
/// pcurves sampled finely), not against the mesh's boundary chords. New interior nodes must pass
/// it, so no node lands outside its face where a boundary chord cuts across a curved trim (a hole
/// of radius ~h would otherwise put nodes ~0.13 h off the face).
///
/// Queries are O(1) on average: a uniform grid stores the segments crossing each cell and the
/// parity at each cell centre.
#pragma once
#include <vector>

#include "paramesh/util/Vec.hpp"

namespace paramesh {

class DomainGuard {
 public:
  DomainGuard() = default;
  /// loops: closed polylines (last point != first) in the coordinates the queries will use.
  explicit DomainGuard(const std::vector<std::vector<Vec2>>& loops);
  /// True when p is inside (even-odd rule). Always true for an empty guard.
  bool inside(Vec2 p) const;
  bool empty() const { return segs_.empty(); }

 private:
  struct Seg {
    Vec2 a, b;
  };
  int cellOf(double x, double y, int& i, int& j) const;
  std::vector<Seg> segs_;
  double x0_ = 0, y0_ = 0, dx_ = 1, dy_ = 1;
  int nx_ = 0, ny_ = 0;
  std::vector<int> start_, list_;     // CSR: segments per cell
  std::vector<char> centreInside_;   // parity at each cell's reference point
  std::vector<double> refY_, refX_;  // reference points: y per row, x per cell (near the centres)
};

}  // namespace paramesh
