// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file occ_fixtures.hpp
/// A model from an OpenCASCADE shape built in a test, through the BREP text the library reads.
#pragma once
#include <BRepTools.hxx>
#include <TopoDS_Shape.hxx>

#include <memory>
#include <sstream>

#include "paramesh/geom/occ/OccModel.hpp"

namespace paramesh::test {

inline std::unique_ptr<IGeometryModel> viaBrep(const TopoDS_Shape& s) {
  std::ostringstream out;
  BRepTools::Write(s, out);
  return loadOccModelFromBrepString(out.str());
}

}  // namespace paramesh::test
