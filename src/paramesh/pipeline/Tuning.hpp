// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Tuning.hpp
/// The surface pipeline's constants, one place for all stages; each is explained in a line or two,
/// and the measurements behind them are in docs/tuning/pipeline.md.
#pragma once
#include <cstddef>

#include "paramesh/mesh/SurfaceMesh.hpp"

namespace paramesh::tuning {
inline constexpr double kPi = 3.14159265358979323846;
// CAD edges shorter than this fraction of the size field (one segment) may become size sources
inline constexpr double kShortSegment = 0.5;
// edges closing a strip up to this many sizes wide are divided into rows (kRowHeight: the height of
// an equilateral triangle of side 1)
inline constexpr double kStripEndMax = 8.0;
inline constexpr double kRowHeight = 0.8660254037844386;
// corners with a short neighbour segment: the other side's first segment becomes kCornerRatio x the
// short one, growing by kCornerSlope per unit length from the corner
inline constexpr double kCornerRatio = 1.3;
inline constexpr double kCornerSlope = 0.5;
inline constexpr double kCornerMinRatio = 0.35;  // of the size: shorter neighbour segments are left alone
// the nearest-face check meshes again at most this many times
inline constexpr int kNearestFaceRounds = 6;
/// Coordinates beyond this (model units) are damaged geometry, not a model (resolveParams).
inline constexpr double kMaxCoordinate = 1e12;
// its size sources act locally: sizes grow away from them by 0.6 per unit length (grading 1.6),
// so that the refinement stays on the thin part (measured: docs/tuning/pipeline.md)
inline constexpr double kNearestFaceSlope = 0.6;
inline constexpr double kPredictMargin = 1.5;  // over the budget by this factor: not meshed (docs/tuning/pipeline.md)

// the nearest-face check's local repairs: around a flagged triangle, centroids may lie off their
// own surface at most this fraction of their distance to the other face's tangent plane (a
// triangle is flagged beyond 1/1.1 = 0.91; measured: docs/tuning/pipeline.md)
inline constexpr double kZoneFraction = 0.8;
// triangles whose centroid lies less than this fraction of the size off their face are never
// candidates of the nearest-face check
inline constexpr double kOffSurfaceCandidate = 0.045;
// narrow gaps (NarrowZones.hpp): gaps below kStaggerTo of the size are staggered when leader
// spacings exist that keep the slanted edges >= h/sqrt2 and the angles >= atan(2/kStaggerMaxAspect)
// = 31 degrees with a kStaggerWindow margin between the two (gaps from 0.39 h up); the spacing
// stays at most kStaggerMaxSpacing sizes
inline constexpr double kStaggerTo = 0.58;
inline constexpr double kStaggerWindow = 1.1;
inline constexpr double kStaggerMaxSpacing = 1.2;
inline constexpr double kStaggerMaxAspect = 3.3;
// strips narrower than staggering can serve (below ~0.39 h: every triangle across them has an
// angle below 30 degrees at any spacing in the unit band) and at least kWideStripNodes nodes long
// get the widest spacing in the band, kWideStripSpacing sizes: the fewest such triangles
inline constexpr int kWideStripNodes = 8;
inline constexpr double kWideStripSpacing = 1.3;
inline constexpr double kWideStripMinWidth = 0.15;
// a gap too narrow to stagger whose sides share no vertex (a hole near an end circle): the
// spacing there at most kGapCapRatio widths, so that the triangle across it, base that spacing and
// apex midway, keeps its shape (measured: docs/tuning/narrow_gaps.md)
inline constexpr double kGapCapRatio = 3.0;

inline size_t elementCount(const SurfaceMesh& m) { return m.triangles.size() + m.quads.size(); }

}  // namespace paramesh::tuning
