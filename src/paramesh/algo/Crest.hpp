// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Crest.hpp
/// Crest lines inside a face: where the surface folds over a width far below the mesh size (a
/// blade's trailing edge closing into a cusp at its tip, modelled inside one B-spline face), no
/// triangle may straddle the fold, and refining isotropically would need edges down to the fold's
/// radius times the curvature angle. The crest is traced on the surface (the ridge of its largest
/// principal curvature) and embedded in the face's triangulation as constrained edges between
/// crest vertices, so the triangles on each flank lie flat on it. Where the flanks keep turning
/// beside the crest, rows parallel to it (graded like a boundary layer's) line its shoulders.
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
  /// rows beside a crest: a row may sag from its chord across by this share of the crest's
  /// spacing (the triangles between two rows then lie within about a third of the curvature
  /// bound's 0.03 of their mean edge from the surface)
  double rowSag = 0.012;
  /// no more rows where a chord of the spacing sags by at most this share of it (an equilateral
  /// triangle of that side then lies within the curvature bound's 0.03 of it)
  double rowStopSag = 0.02;
  /// a row is at most this many times as wide as the one before it
  double rowGrowth = 2.0;
  /// at most this many rows on each side of a crest vertex
  int maxRows = 8;
};

/// Crest polylines (scaled (u,v) of the surface, spaced by about the size, at least two points
/// each) found from the edges of T (a triangulation of the face, the frontal mesh) that cross a
/// fold. Traced only where the fold is a crease at the mesh's scale (CrestOptions::creaseScale),
/// inside the trimmed domain and away from its boundary (the constrained edges of T).
std::vector<std::vector<Vec2>> traceCrests(const Triangulation& T, const SurfaceContext& C, const CrestOptions& o = {});

/// Inserts the crest polylines into T (a constrained triangulation of the face's boundary) as
/// VF_CREST vertices (no normal) joined by constrained edges. Returns the segments embedded;
/// points that cannot be inserted (coincident, outside) end their polyline there.
/// `embedded`, when given, receives the crest polylines as inserted (vertex ids of T).
int embedCrests(Triangulation& T, const SurfaceContext& C, const std::vector<std::vector<Vec2>>& crests,
                std::vector<std::vector<int>>* embedded = nullptr);

/// Rows beside embedded crests: a crest's flanks can keep turning fast within a few hundredths of
/// the size from it (propeller_and_shaft's blade tips: 55 degrees within 0.02 mm, against a size
/// of 0.038 mm), so a triangle with one edge on the crest and its apex a size away on the flank
/// cuts the fold's shoulder. From each crest vertex (a station), each flank is walked across the
/// crest on the surface. One sequence of distances across serves a whole crest line and flank:
/// each row as far from the last as every station still in need lets its chord sag by at most
/// CrestOptions::rowSag of the crest's spacing (and at most rowGrowth times the last row's
/// width); a station needs no more rows where a chord of the spacing sags by at most rowStopSag
/// of it. The points of one row are inserted as VF_ROW vertices (never moved) joined by
/// constrained edges, so the triangles between two rows are stretched along the crest and lie
/// flat across it; their diagonals are flipped to Delaunay in the surface's metric. Returns the
/// row segments embedded.
int embedCrestRows(Triangulation& T, const SurfaceContext& C, const std::vector<std::vector<int>>& crests,
                   const CrestOptions& o = {});

}  // namespace paramesh
