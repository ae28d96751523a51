// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file FaceBoundaryBuild.hpp
/// A face's boundary for the (u,v) mesher, from the discretised edges.
/// Reads: the model's wires and pcurves, the edge meshes and their nodes, the size field.
/// Writes: the FaceBoundary (loops of shared nodes with consistent (u,v), the finely sampled true
/// trim, pcurves that stray from their edges).
#pragma once

#include <string>
#include <vector>

#include "paramesh/algo/FaceMesher.hpp"
#include "paramesh/geom/Geometry.hpp"
#include "paramesh/mesh/SurfaceMesh.hpp"
#include "paramesh/size/SizeField.hpp"
#include "paramesh/stages/edges/EdgeMesh.hpp"

namespace paramesh {

/// A pcurve whose image lies farther than this share of the size from its edge's nodes strays
/// from its edge: the run says so, and why triangles there may stay beyond a deviation bound.
constexpr double kPcurveStray = 1e-3;

/// Builds face f's boundary on surface s; false with the reason in why when a wire is broken
/// (not connected, not closed in (u,v), fewer than 3 distinct points) or the face has none.
bool buildFaceBoundary(const IGeometryModel& model, const std::vector<EdgeMesh>& edges, const SurfaceMesh& mesh,
                       const SizeField& field, int f, const ISurface& s, FaceBoundary& fb, std::string& why);

}  // namespace paramesh
