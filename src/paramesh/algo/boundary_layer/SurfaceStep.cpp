// SPDX-License-Identifier: LGPL-2.1-or-later
// Steps on the face's surface: the normal, the (u,v) step of a 3D tangent step, and the point at a
// given straight 3D distance in a column's plane (projections, then Newton in the plane if needed).

#include "paramesh/algo/boundary_layer/FaceLayers.hpp"

#include <algorithm>
#include <cmath>

namespace paramesh::bl_detail {

Vec3 FaceLayers::normalAt(Vec2 uv) const {
  Vec3 n;
  if (!S_.normal(uv, n)) n = {0, 0, 1};
  return n;
}

/// (u,v) step for a 3D tangent step d at uv (first order).
Vec2 FaceLayers::uvStep(Vec2 uv, Vec3 d) const {
  Vec3 p, du, dv;
  S_.d1(uv, p, du, dv);
  const double E = dot(du, du), F = dot(du, dv), G = dot(dv, dv), det = E * G - F * F;
  if (!(det > 1e-300)) return {0, 0};
  const double a = dot(du, d), b = dot(dv, d);
  return {(G * a - F * b) / det, (E * b - F * a) / det};
}

/// Point at straight 3D distance h from (uv, x) in direction d, on the surface, in the column's
/// plane (through x, spanned by d and the surface normal) within 1 % of h.
bool FaceLayers::step(Vec2 uv, Vec3 x, Vec3 d, double h, Vec2& uvOut, Vec3& xOut) const {
  Vec2 q = uv + uvStep(uv, h * d);
  Vec3 target = x + h * d;
  Vec3 p;
  const Vec3 side = normalized(cross(d, normalAt(uv)));  // normal of the column's plane
  auto within = [&](double lenTol, double sideTol) {
    return std::fabs(dist(p, x) - h) <= lenTol * h && std::fabs(dot(p - x, side)) <= sideTol * h;
  };
  // the chord rescaled to h after each projection: enough on smooth faces
  for (int it = 0; it < 4; ++it) {
    if (!S_.project(target, q, &p, 0.0)) return false;
    const double l = dist(p, x);
    if (!(l > 0)) return false;
    if (std::fabs(l - h) <= 1e-7 * h) break;
    target = x + (h / l) * (p - x);
  }
  // Every point of the surface at distance h is a fixed point of that iteration, and where the
  // surface turns away within the step (a step of several radii around a blade's nose: the
  // first projection lands at less than half of h) it converges slowly and slides along the
  // row (measured: docs/tuning/boundary_layer.md). There the point is solved for in the
  // column's plane.
  if (!within(1e-7, 1e-2) && !solveInPlane(x, side, h, q, p)) return false;
  uvOut = q;
  xOut = p;
  return within(1e-3, 1e-2) && dot(p - x, d) > 0;
}

/// Newton on |S(q) - x| = h and (S(q) - x).side = 0 from q (in/out; p = S(q)), damped, within
/// the face's parameter bounds. False when the residual stops decreasing above 1e-10 h.
bool FaceLayers::solveInPlane(Vec3 x, Vec3 side, double h, Vec2& q, Vec3& p) const {
  const UVBox b = S_.bounds();
  const bool uFree = S_.uPeriod() > 0, vFree = S_.vPeriod() > 0;
  // both equations as lengths: (|c|^2 - h^2) / 2h is |c| - h to first order
  auto residual = [&](Vec3 c) { return std::hypot((dot(c, c) - h * h) / (2 * h), dot(c, side)); };
  Vec3 du, dv;
  S_.d1(q, p, du, dv);
  double r = residual(p - x);
  for (int it = 0; it < 30 && r > 1e-10 * h; ++it) {
    const Vec3 c = p - x;
    const double f1 = (dot(c, c) - h * h) / (2 * h), f2 = dot(c, side);
    const double a11 = dot(c, du) / h, a12 = dot(c, dv) / h, a21 = dot(du, side), a22 = dot(dv, side);
    const double det = a11 * a22 - a12 * a21;
    if (!(std::fabs(det) > 0)) return false;
    const Vec2 dq{-(a22 * f1 - a12 * f2) / det, -(a11 * f2 - a21 * f1) / det};
    bool better = false;
    for (double t = 1; t > 1e-4 && !better; t *= 0.5) {
      Vec2 qn = q + t * dq;
      if (!uFree) qn.x = std::clamp(qn.x, b.u0, b.u1);
      if (!vFree) qn.y = std::clamp(qn.y, b.v0, b.v1);
      Vec3 pn, dun, dvn;
      S_.d1(qn, pn, dun, dvn);
      const double rn = residual(pn - x);
      if (rn < r) {
        q = qn;
        p = pn;
        du = dun;
        dv = dvn;
        r = rn;
        better = true;
      }
    }
    if (!better) return false;
  }
  return true;
}

}  // namespace paramesh::bl_detail
