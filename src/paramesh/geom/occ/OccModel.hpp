// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file OccModel.hpp
/// OpenCASCADE backend of IGeometryModel. This header exposes no OCC type: the implementation is
/// private, so OCC headers stay inside geom/occ/.
#pragma once
#include <memory>
#include <string>

#include "paramesh/geom/Geometry.hpp"

namespace paramesh {

/// Reads a STEP (.step/.stp), IGES (.iges/.igs) or BREP (.brep/.brp) file; the format comes from
/// the extension. Throws InputError with the reason when the file cannot be read or has no face.
std::unique_ptr<IGeometryModel> loadOccModel(const std::string& path);

/// Reads a model from an OpenCASCADE BREP text (what FreeCAD's Shape.exportBrepToString() gives).
std::unique_ptr<IGeometryModel> loadOccModelFromBrepString(const std::string& brep);

/// Writes a model file's shape as BREP text (for tests and tools). Throws InputError.
std::string occFileToBrepString(const std::string& path);

}  // namespace paramesh
