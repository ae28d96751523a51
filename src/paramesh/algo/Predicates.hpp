// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Predicates.hpp
/// Geometric predicates in the (u,v) plane. orient2d is exact (floating-point filter, then exact
/// expansion arithmetic), so topological decisions never depend on round-off.
#pragma once
#include "paramesh/util/Vec.hpp"

namespace paramesh {

/// Sign of the signed area of (a,b,c): > 0 counter-clockwise, < 0 clockwise, 0 collinear. Exact.
int orient2d(Vec2 a, Vec2 b, Vec2 c);

/// Twice the signed area of (a,b,c) in floating point (not exact; for magnitudes only).
inline double area2(Vec2 a, Vec2 b, Vec2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

/// > 0 when d lies strictly inside the circle through the counter-clockwise a,b,c (floating point).
double incircle(Vec2 a, Vec2 b, Vec2 c, Vec2 d);

/// True when the closed segments [a,b] and [c,d] properly cross (share an interior point, not an
/// endpoint). Exact.
bool segmentsCross(Vec2 a, Vec2 b, Vec2 c, Vec2 d);

}  // namespace paramesh
