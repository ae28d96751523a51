// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Crest.hpp
/// Crest lines inside a face: where the surface folds over a width far below the mesh size (a
/// blade's trailing edge closing into a cusp at its tip, modelled inside one B-spline face), no
/// triangle may straddle the fold, and refining isotropically would need edges down to the fold's
/// radius times the curvature angle. The crest is traced on the surface (the ridge of its largest
/// principal curvature) and embedded in the face's triangulation as constrained edges between
/// crest vertices, so the triangles on each flank lie flat on it.
#pragma once
#include <vector>

#include "paramesh/util/Vec.hpp"

namespace paramesh {

class SurfaceContext;
class Triangulation;

struct CrestOptions {
  /// a point belongs to a crest where the largest principal curvature k satisfies k h > this,
  /// h being the size there: a fold of radius below h / creaseScale
  double creaseScale = 1.5;
  /// seeds: mesh edges whose end normals turn by more than this (cosine)
  double seedCos = 0.5;
  /// no crest point nearer the face's boundary (or another crest) than this share of the size
  double clearance = 0.5;
  /// bound on the traced points per face (a surface with ridges everywhere is not a crease)
  int maxPoints = 20000;
};

/// Crest polylines (scaled (u,v) of the surface, spaced by about the size, at least two points
/// each) found from the edges of T (a triangulation of the face, the frontal mesh) that cross a
/// fold. Traced only where the fold is a crease at the mesh's scale (CrestOptions::creaseScale),
/// inside the trimmed domain and away from its boundary (the constrained edges of T).
std::vector<std::vector<Vec2>> traceCrests(const Triangulation& T, const SurfaceContext& C, const CrestOptions& o = {});

/// Inserts the crest polylines into T (a constrained triangulation of the face's boundary) as
/// VF_CREST vertices (no normal) joined by constrained edges. Returns the segments embedded;
/// points that cannot be inserted (coincident, outside) end their polyline there.
int embedCrests(Triangulation& T, const SurfaceContext& C, const std::vector<std::vector<Vec2>>& crests);

}  // namespace paramesh
