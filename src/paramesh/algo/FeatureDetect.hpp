// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file FeatureDetect.hpp
/// Automatic leading-edge detection: CAD edges along which the surface is smooth (tangent faces)
/// but curves far more across the edge than along it, on both sides — the rounded nose of a wing
/// or blade split by an edge. Sharp edges (trailing edges, section edges) are not proposed.
#pragma once
#include <vector>

#include "paramesh/geom/Geometry.hpp"

namespace paramesh {

struct RidgeCandidate {
  int edge = -1;            ///< 0-based CAD edge
  double acrossCurvature = 0;   ///< smallest of the two sides' normal curvature across the edge
  double alongCurvature = 0;    ///< largest normal curvature along the edge
  double ratio = 0;             ///< across / along
  double dihedralDeg = 0;       ///< largest angle between the two faces' normals along the edge
  bool peak = false;            ///< the curvature across drops away from the edge on both sides
};

/// Every edge scored; `proposed` receives the edges passing the thresholds: tangent faces
/// (dihedral < maxDihedralDeg), across/along curvature ratio > minRatio, and radius across the
/// edge below maxRadius (0: any). Sorted by edge number.
/// edgeRep (optional): representative of each edge among coincident edges of unsewn faces; an
/// edge and its twins are scored together, and the representative is proposed.
std::vector<RidgeCandidate> proposeLeadingEdges(const IGeometryModel& m, double maxRadius, double minRatio = 10.0,
                                                double maxDihedralDeg = 10.0,
                                                std::vector<RidgeCandidate>* all = nullptr,
                                                const std::vector<int>* edgeRep = nullptr);

}  // namespace paramesh
