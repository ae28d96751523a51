// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/model/FaceDomain.hpp"

#include <algorithm>
#include <cmath>

namespace paramesh {

Vec2 unwrapNear(Vec2 q, Vec2 ref, double up, double vp) {
  if (up > 0) q.x += up * std::round((ref.x - q.x) / up);
  if (vp > 0) q.y += vp * std::round((ref.y - q.y) / vp);
  return q;
}

FaceDomain::FaceDomain(const IGeometryModel& m, int f, const ISurface& s, int perUse) {
  box_ = {1e300, -1e300, 1e300, -1e300};
  const auto& wires = m.faceWires(f);
  const double up = s.uPeriod(), vp = s.vPeriod();
  for (size_t w = 0; w < wires.size(); ++w) {
    std::vector<Vec2> poly;
    for (size_t k = 0; k < wires[w].uses.size(); ++k) {
      const EdgeUse& use = wires[w].uses[k];
      auto pc = m.makePCurve(f, (int)w, (int)k);
      if (!pc) continue;
      double t0, t1;
      m.edgeRange(use.edge, t0, t1);
      std::vector<Vec2> pts;
      for (int i = 0; i <= perUse; ++i) {
        double t = t0 + (t1 - t0) * i / perUse;
        pts.push_back(pc->eval(t));
      }
      if (use.reversed) std::reverse(pts.begin(), pts.end());
      if (!poly.empty()) {
        const Vec2 shifted = unwrapNear(pts.front(), poly.back(), up, vp);
        const Vec2 d = shifted - pts.front();
        for (auto& p : pts) p = p + d;
        poly.insert(poly.end(), pts.begin() + 1, pts.end());
      } else {
        poly = pts;
      }
    }
    if (poly.size() >= 3) {
      for (auto& p : poly) {
        box_.u0 = std::min(box_.u0, p.x);
        box_.u1 = std::max(box_.u1, p.x);
        box_.v0 = std::min(box_.v0, p.y);
        box_.v1 = std::max(box_.v1, p.y);
      }
      loops_.push_back(std::move(poly));
    }
  }
  if (loops_.empty()) box_ = s.bounds();
  guard_ = DomainGuard(loops_);
}

bool FaceDomain::inside(Vec2 p) const { return guard_.inside(p); }

}  // namespace paramesh
