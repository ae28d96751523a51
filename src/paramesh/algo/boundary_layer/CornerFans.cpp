// SPDX-License-Identifier: LGPL-2.1-or-later
// Columns at a run's interior points: one column square to the rows, one merged column with longer
// steps at a convex corner of the face, a fan of columns through the outside at a reflex corner.

#include "paramesh/algo/boundary_layer/FaceLayers.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace paramesh::bl_detail {

/// The columns at loop point i inside a run growing into side sgn; base holds their root and spec.
void FaceLayers::addCornerColumns(int L, int i, double sgn, const Column& base, std::vector<Column>& cols) {
  const auto& lp = loops_[L];
  const int n = (int)lp.size();
  auto at = [&](int j) -> const LoopPoint& { return lp[((j % n) + n) % n]; };
  const LoopPoint& p = at(i);
  const int spec = base.spec;
  // interior point: tangents of the incoming and outgoing segments
  const Vec3 n0 = normalAt(p.uv);
  const Vec3 tin = normalized(p.xyz - at(i - 1).xyz), tout = normalized(at(i + 1).xyz - p.xyz);
  const Vec3 bin = sgn * normalized(cross(n0, tin)), bout = sgn * normalized(cross(n0, tout));
  const bool vertex = at(i - 1).edge != at(i).edge;
  const double turn = std::atan2(dot(cross(tin, tout), n0) * sgn, dot(tin, tout));  // > 0: face corner < 180
  if (vertex && turn < -kPi / 9) {
    // reflex corner of the face (> 200 degrees): a fan from bin to bout through the outside
    const double ang = -turn;
    const int m = std::max(2, (int)std::ceil(ang / (kPi / 8)));
    for (int f = 0; f <= m; ++f) {
      const double s = (double)f / m;
      // rotate bin towards bout about the normal (the short way round is the fan's way)
      Vec3 d = normalized((1 - s) * bin + s * bout);
      if (norm2((1 - s) * bin + s * bout) < 1e-6) d = normalized(cross(n0, bin) * (sgn > 0 ? -1.0 : 1.0));
      Column c = base;
      c.dir = d;
      cols.push_back(c);
    }
    ++out_.stats[spec].fans;
    return;
  }
  Column c = base;
  Vec3 d = normalized(bin + bout);
  if (vertex && turn > kPi / 6) {
    // convex corner of the face: one merged column, longer steps keep rows parallel
    const double half = 0.5 * (kPi - turn);
    c.factor = std::min(2.0, 1.0 / std::max(std::sin(half), 0.5));
    ++out_.stats[spec].merges;
  }
  c.dir = d;
  cols.push_back(c);
}

}  // namespace paramesh::bl_detail
