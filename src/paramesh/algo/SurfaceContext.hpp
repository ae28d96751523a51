// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file SurfaceContext.hpp
/// What the face algorithms know about one face's surface: the scaled parameter plane
/// (u' = u*su, v' = v*sv, so that unit steps are roughly unit 3D lengths), evaluation, projection,
/// sizes, and the per-vertex metric J^T J / h^2.
#pragma once
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

/// Radius-ratio quality 2 r_in / r_circ of a 3D triangle (1 equilateral, 0 degenerate).
inline double gamma3(Vec3 a, Vec3 b, Vec3 c) {
  const double la = dist(b, c), lb = dist(c, a), lc = dist(a, b);
  const double area2 = norm(cross(b - a, c - a));  // twice the area
  const double s = la + lb + lc;
  const double den = s * la * lb * lc;
  if (!(den > 0)) return 0.0;
  return 4.0 * area2 * area2 / den;  // = 8 A^2 / (s' * abc) with s' = s/2
}

}  // namespace paramesh
