// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/geom/Geometry.hpp"

#include <algorithm>
#include <cmath>

namespace paramesh {

const char* toString(SurfaceKind k) {
  switch (k) {
    case SurfaceKind::Plane: return "plane";
    case SurfaceKind::Cylinder: return "cylinder";
    case SurfaceKind::Cone: return "cone";
    case SurfaceKind::Sphere: return "sphere";
    case SurfaceKind::Torus: return "torus";
    case SurfaceKind::BSpline: return "bspline";
    case SurfaceKind::Bezier: return "bezier";
    case SurfaceKind::Revolution: return "revolution";
    case SurfaceKind::Extrusion: return "extrusion";
    case SurfaceKind::Offset: return "offset";
    default: return "other";
  }
}

bool ISurface::normal(Vec2 uv, Vec3& n) const {
  Vec3 p, du, dv;
  d1(uv, p, du, dv);
  Vec3 c = cross(du, dv);
  double lc = norm(c), l1 = norm(du), l2 = norm(dv);
  // singular when one derivative vanishes next to the other (a pole: |S_u| ~ 1e-16 |S_v|, and
  // its sign flips with round-off in u or v just past the pole)
  if (lc > 1e-10 * std::max(l1 * l1 + l2 * l2, 1e-300)) {
    n = c * (1.0 / lc);
    return true;
  }
  // Singular point (pole, apex): estimate from a nearby non-singular point towards the domain centre.
  UVBox b = bounds();
  Vec2 c0{0.5 * (b.u0 + b.u1), 0.5 * (b.v0 + b.v1)};
  for (double eps : {1e-6, 1e-4, 1e-3}) {
    Vec2 q = uv + eps * (c0 - uv);
    d1(q, p, du, dv);
    c = cross(du, dv);
    lc = norm(c);
    if (lc > 1e-300) {
      n = c * (1.0 / lc);
      return true;
    }
  }
  return false;
}

namespace {
struct Limits {
  double lo[2], hi[2];
};
Limits limitsOf(const ISurface& s, double margin) {
  UVBox b = s.bounds();
  Limits L;
  double su = b.u1 - b.u0, sv = b.v1 - b.v0;
  L.lo[0] = s.uPeriod() > 0 ? -1e300 : b.u0 - margin * su;
  L.hi[0] = s.uPeriod() > 0 ? 1e300 : b.u1 + margin * su;
  L.lo[1] = s.vPeriod() > 0 ? -1e300 : b.v0 - margin * sv;
  L.hi[1] = s.vPeriod() > 0 ? 1e300 : b.v1 + margin * sv;
  return L;
}
}  // namespace

bool ISurface::project(Vec3 x, Vec2& uv, Vec3* out, double margin) const {
  const Limits L = limitsOf(*this, margin);
  const UVBox b = bounds();
  const double maxStepU = 0.5 * std::max(b.u1 - b.u0, 1e-12);
  const double maxStepV = 0.5 * std::max(b.v1 - b.v0, 1e-12);
  SurfaceD2 d;
  d2(uv, d);
  Vec3 r = d.p - x;
  double f = norm2(r);
  bool ok = false;
  for (int it = 0; it < 30; ++it) {
    const double g0 = dot(r, d.du), g1 = dot(r, d.dv);
    const double E = dot(d.du, d.du), F = dot(d.du, d.dv), G = dot(d.dv, d.dv);
    // zero-cosine convergence test: the residual is normal to the surface
    const double rn = std::sqrt(f);
    if (rn < 1e-15 * (1.0 + norm(x)) ||
        (std::fabs(g0) <= 1e-10 * rn * std::sqrt(E) + 1e-300 &&
         std::fabs(g1) <= 1e-10 * rn * std::sqrt(G) + 1e-300)) {
      ok = true;
      break;
    }
    double h00 = E + dot(r, d.duu), h01 = F + dot(r, d.duv), h11 = G + dot(r, d.dvv);
    double det = h00 * h11 - h01 * h01;
    if (!(h00 > 0 && det > 1e-14 * (h00 * h11 + 1e-300))) {  // not convex: Gauss-Newton
      h00 = E;
      h01 = F;
      h11 = G;
      det = h00 * h11 - h01 * h01;
    }
    const double reg = 1e-12 * (h00 + h11) + 1e-300;
    if (det < reg * (h00 + h11)) {  // singular (pole): Levenberg-Marquardt regularisation
      h00 += reg * 1e4;
      h11 += reg * 1e4;
      det = h00 * h11 - h01 * h01;
    }
    double su = -(h11 * g0 - h01 * g1) / det;
    double sv = -(-h01 * g0 + h00 * g1) / det;
    // damp
    double scale = 1.0;
    if (std::fabs(su) > maxStepU) scale = std::min(scale, maxStepU / std::fabs(su));
    if (std::fabs(sv) > maxStepV) scale = std::min(scale, maxStepV / std::fabs(sv));
    su *= scale;
    sv *= scale;
    // line search on the distance; near the foot point the change of |S - x|^2 is below its
    // round-off, so a step that does not increase it beyond that is accepted as well
    bool improved = false;
    const double roundoff = 8e-16 * (norm(x) + norm(d.p)) * std::sqrt(f) + 1e-300;
    for (int ls = 0; ls < 12; ++ls) {
      Vec2 q{std::clamp(uv.x + su, L.lo[0], L.hi[0]), std::clamp(uv.y + sv, L.lo[1], L.hi[1])};
      SurfaceD2 dq;
      d2(q, dq);
      Vec3 rq = dq.p - x;
      double fq = norm2(rq);
      if (fq <= f + roundoff) {
        const double du = std::fabs(q.x - uv.x), dv = std::fabs(q.y - uv.y);
        uv = q;
        d = dq;
        r = rq;
        f = fq;
        improved = true;
        // parameter step negligible: converged
        if (du <= 1e-15 * (1 + std::fabs(uv.x)) + 1e-16 * (b.u1 - b.u0) &&
            dv <= 1e-15 * (1 + std::fabs(uv.y)) + 1e-16 * (b.v1 - b.v0))
          ok = true;
        break;
      }
      su *= 0.5;
      sv *= 0.5;
    }
    if (!improved) {
      ok = true;  // cannot improve: a local minimum up to round-off
      break;
    }
    if (ok) break;
  }
  if (out) *out = d.p;
  return ok;
}

bool ISurface::projectGlobal(Vec3 x, Vec2& uv, Vec3* out) const {
  const UVBox b = bounds();
  const int n = 24;
  double best = 1e300;
  Vec2 bestUv{b.u0, b.v0};
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      Vec2 q{b.u0 + (b.u1 - b.u0) * i / n, b.v0 + (b.v1 - b.v0) * j / n};
      double dd = norm2(eval(q) - x);
      if (dd < best) {
        best = dd;
        bestUv = q;
      }
    }
  uv = bestUv;
  return project(x, uv, out);
}

double ICurve::project(Vec3 x, double t, double t0, double t1) const {
  t = std::clamp(t, t0, t1);
  Vec3 p, d1v, d2v;
  for (int it = 0; it < 30; ++it) {
    d2(t, p, d1v, d2v);
    Vec3 r = p - x;
    double g = dot(r, d1v);
    double h = dot(d1v, d1v) + dot(r, d2v);
    if (h <= 0) h = dot(d1v, d1v);
    if (h <= 1e-300) break;
    double step = -g / h;
    double maxStep = 0.5 * (t1 - t0);
    step = std::clamp(step, -maxStep, maxStep);
    double tn = std::clamp(t + step, t0, t1);
    if (std::fabs(tn - t) <= 1e-15 * (1 + std::fabs(t)) + 1e-14 * (t1 - t0)) {
      t = tn;
      break;
    }
    // accept only if it does not increase the distance much
    if (norm2(eval(tn) - x) > norm2(r) * (1 + 1e-12)) {
      tn = t + 0.5 * (tn - t);
    }
    t = tn;
  }
  return t;
}

}  // namespace paramesh
