// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file DiscreteModel.hpp
/// The discrete backend of the geometry interface: triangulated input (discrete/DiscreteInput.hpp)
/// as faces (each a disk-like patch parametrised on the unit disk, discrete/PatchParam.hpp),
/// edges (feature chains as polylines, t = arc length) and vertices, so that every stage of the
/// mesher runs on it unchanged. Closed pieces are solids.
#pragma once
#include <memory>
#include <string>

#include "paramesh/geom/Geometry.hpp"
#include "paramesh/geom/discrete/DiscreteInput.hpp"

namespace paramesh {

/// A face that cannot be parametrised (a closed smooth surface, a handle) makes makeSurface()
/// throw an InputError naming it: the other faces mesh.
std::unique_ptr<IGeometryModel> makeDiscreteModel(DiscreteInput input);

/// Reads an STL/OBJ file into a discrete model (loadDiscrete, then makeDiscreteModel).
std::unique_ptr<IGeometryModel> loadDiscreteModel(const std::string& path, double featureAngleDeg = 40.0);

}  // namespace paramesh
