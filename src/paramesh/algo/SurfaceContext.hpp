// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file SurfaceContext.hpp
/// What the face algorithms know about one face's surface: the scaled parameter plane
/// (u' = u*su, v' = v*sv, so that unit steps are roughly unit 3D lengths), evaluation, projection,
/// sizes, and the per-vertex metric J^T J / h^2.
#pragma once

#include <algorithm>
#include <cmath>

#include "paramesh/algo/DomainGuard.hpp"
#include "paramesh/algo/Triangulation.hpp"
#include "paramesh/geom/Geometry.hpp"
#include "paramesh/size/SizeField.hpp"

namespace paramesh {

class SurfaceContext {
 public:
  SurfaceContext(const ISurface& s, const SizeField& f);

  const ISurface& surf;
  const SizeField& field;
  double su = 1, sv = 1;  ///< parameter scales
  bool planar = false;
  const DomainGuard* guard = nullptr;  ///< true trimmed domain, in scaled (u,v)
  const SizeField* overlay = nullptr;  ///< face-local sizes, combined by min with the field

  /// True when the scaled parameter s lies inside the face's true trimmed domain.
  bool inDomain(Vec2 s) const { return !guard || guard->inside(s); }

  Vec2 toParam(Vec2 s) const { return {s.x / su, s.y / sv}; }
  Vec2 toScaled(Vec2 p) const { return {p.x * su, p.y * sv}; }

  /// The size at x: the field's, or the overlay's where that is smaller.
  double size(Vec3 x) const { return overlay ? std::min(field.size(x), overlay->size(x)) : field.size(x); }
  /// Fills normal, h and metric of v from its uv (and xyz, which must be set).
  void fill(TriVertex& v) const;
  /// A new interior vertex at scaled parameter s (evaluates xyz).
  TriVertex makeVertex(Vec2 s) const {
    TriVertex v;
    v.uv = s;
    v.xyz = surf.eval(toParam(s));
    fill(v);
    return v;
  }
  /// Projects x onto the surface starting from scaled seed s (in/out); returns false on failure.
  bool project(Vec3 x, Vec2& s, Vec3& out) const;
  /// 3D point reached from scaled uv s by the tangent-plane step d (first order), then projected.
  bool stepAndProject(Vec2& s, Vec3 target, Vec3& out) const;
};

/// The side lengths (la opposite a, ...) and twice the area of a 3D triangle: what its radius
/// ratio and its smallest angle are computed from (once, where both are needed).
struct TriSides {
  double la, lb, lc, area2;
};
inline TriSides triSides(Vec3 a, Vec3 b, Vec3 c) {
  return {dist(b, c), dist(c, a), dist(a, b), norm(cross(b - a, c - a))};
}
/// Radius-ratio quality 2 r_in / r_circ (1 equilateral, 0 degenerate).
inline double radiusRatio(const TriSides& t) {
  const double s = t.la + t.lb + t.lc;
  const double den = s * t.la * t.lb * t.lc;
  if (!(den > 0)) return 0.0;
  return 4.0 * t.area2 * t.area2 / den;  // = 8 A^2 / (s' * abc) with s' = s/2
}
/// sin of the smallest angle: 2 area / (product of the two longest sides)
inline double sinMinAngle(const TriSides& t) {
  const double mx = std::max({t.la, t.lb, t.lc}), mn = std::min({t.la, t.lb, t.lc});
  const double mid = t.la + t.lb + t.lc - mx - mn;
  return mx > 0 && mid > 0 ? t.area2 / (mx * mid) : 0.0;
}
inline double gamma3(Vec3 a, Vec3 b, Vec3 c) { return radiusRatio(triSides(a, b, c)); }

/// True for an edge between two boundary vertices whose surface normals are more than 120 degrees
/// apart: the surface turns back on itself between them (across a half body of revolution or a
/// half cylinder narrower than the mesh), so the chord runs through the body, where a neighbouring
/// face bounded by the same CAD edges may have the same chord.
inline bool wrapsAcross(const TriVertex& p, const TriVertex& q) {
  return (p.flags & q.flags & VF_BOUNDARY) && norm2(p.normal) > 0 && norm2(q.normal) > 0 &&
         dot(p.normal, q.normal) < -0.5;
}
inline double sinMinAngle(Vec3 a, Vec3 b, Vec3 c) { return sinMinAngle(triSides(a, b, c)); }

/// True when an edge of triangle (a, b, c) wrapsAcross.
inline bool anyWrapsAcross(const TriVertex& a, const TriVertex& b, const TriVertex& c) {
  return wrapsAcross(a, b) || wrapsAcross(b, c) || wrapsAcross(c, a);
}

/// The largest cosine between a triangle's normal n (not zero) and its corners' surface normals;
/// corners without one do not count, 2 when none has one.
inline double bestCornerCos(const TriVertex& a, const TriVertex& b, const TriVertex& c, Vec3 n) {
  const double ln = norm(n);
  double best = -2;
  for (const TriVertex* v : {&a, &b, &c})
    if (norm2(v->normal) > 0) best = std::max(best, dot(n, v->normal) / ln);
  return best < -1 ? 2 : best;
}

/// Whether two of the triangles (a, b, p), (b, c, p), (c, a, p) that a point p inside triangle
/// (a, b, c) makes face more than 120 degrees apart in 3D: p would fold them onto each other.
/// Across a strip narrower than its chords' sagitta (a thread run-out on a cylinder) every
/// triangle lies across the surface, and a node inside one does that.
inline bool splitFolds(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
  const Vec3 n[3] = {cross(b - a, p - a), cross(c - b, p - b), cross(a - c, p - c)};
  for (int i = 0; i < 3; ++i) {
    const Vec3 &x = n[i], &y = n[(i + 1) % 3];
    const double l = norm(x) * norm(y);
    if (l > 0 && dot(x, y) < -0.5 * l) return true;
  }
  return false;
}

}  // namespace paramesh
