// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/algo/SurfaceContext.hpp"

#include <algorithm>
#include <vector>

namespace paramesh {

SurfaceContext::SurfaceContext(const ISurface& s, const SizeField& f) : surf(s), field(f) {
  planar = s.kind() == SurfaceKind::Plane;
  const UVBox b = s.bounds();
  std::vector<double> lu, lv;
  const int n = 6;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      Vec2 p{b.u0 + (b.u1 - b.u0) * (i + 0.5) / (n + 1), b.v0 + (b.v1 - b.v0) * (j + 0.5) / (n + 1)};
      Vec3 x, du, dv;
      s.d1(p, x, du, dv);
      lu.push_back(norm(du));
      lv.push_back(norm(dv));
    }
  auto median = [](std::vector<double>& a) {
    std::nth_element(a.begin(), a.begin() + a.size() / 2, a.end());
    return a[a.size() / 2];
  };
  su = median(lu);
  sv = median(lv);
  if (!(su > 1e-300) || !std::isfinite(su)) su = 1;
  if (!(sv > 1e-300) || !std::isfinite(sv)) sv = 1;
}

void SurfaceContext::fill(TriVertex& v) const {
  Vec3 p, du, dv;
  const Vec2 q = toParam(v.uv);
  surf.d1(q, p, du, dv);
  Vec3 n = cross(du, dv);
  const double ln = norm(n);
  // at a pole one derivative all but vanishes and the cross product's sign is round-off:
  // ISurface::normal then takes the normal from just inside the domain
  if (ln > 1e-10 * (norm2(du) + norm2(dv)) && ln > 0) {
    v.normal = n * (1.0 / ln);
  } else {
    Vec3 nn;
    v.normal = surf.normal(q, nn) ? nn : Vec3{0, 0, 0};
  }
  v.h = size(v.xyz);
  const double ih2 = 1.0 / (v.h * v.h);
  du = du * (1.0 / su);
  dv = dv * (1.0 / sv);
  v.M[0] = dot(du, du) * ih2;
  v.M[1] = dot(du, dv) * ih2;
  v.M[2] = dot(dv, dv) * ih2;
}

bool SurfaceContext::project(Vec3 x, Vec2& s, Vec3& out) const {
  Vec2 q = toParam(s);
  bool ok = surf.project(x, q, &out, 0.01);
  s = toScaled(q);
  return ok;
}

bool SurfaceContext::stepAndProject(Vec2& s, Vec3 target, Vec3& out) const {
  Vec2 q = toParam(s);
  Vec3 p, du, dv;
  surf.d1(q, p, du, dv);
  const Vec3 d = target - p;
  const double E = dot(du, du), F = dot(du, dv), G = dot(dv, dv);
  const double det = E * G - F * F;
  if (det > 1e-300) {
    const double a = dot(du, d), b = dot(dv, d);
    q.x += (G * a - F * b) / det;
    q.y += (E * b - F * a) / det;
  }
  if (planar) {
    out = surf.eval(q);
    s = toScaled(q);
    return true;
  }
  bool ok = surf.project(target, q, &out, 0.01);
  s = toScaled(q);
  return ok;
}

}  // namespace paramesh
