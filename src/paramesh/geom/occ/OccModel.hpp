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

/// The OpenCASCADE version the library was built on ("7.6.3").
std::string occtVersion();

/// Reads a model from an OpenCASCADE BREP text (what FreeCAD's Shape.exportBrepToString() gives).
std::unique_ptr<IGeometryModel> loadOccModelFromBrepString(const std::string& brep);

/// For applications, never used by the library itself: while it lives, OpenCASCADE's signal
/// handlers are installed (process-wide; restored to the system default afterwards), so that an
/// access violation inside OpenCASCADE's STEP / IGES / BREP readers on a damaged file becomes an
/// InputError from loadOccModel() instead of a crash. The CLI holds one while it reads the model;
/// a host that installs its own handlers (FreeCAD does) must not use it.
class OccReaderSignalGuard {
 public:
  OccReaderSignalGuard();
  ~OccReaderSignalGuard();
  OccReaderSignalGuard(const OccReaderSignalGuard&) = delete;
  OccReaderSignalGuard& operator=(const OccReaderSignalGuard&) = delete;
};

/// Writes a model file's shape as BREP text (for tests and tools). Throws InputError.
std::string occFileToBrepString(const std::string& path);

}  // namespace paramesh
