// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file NglibFill.hpp
/// The one place nglib (Netgen's library interface) is called: a closed, outward-oriented
/// triangle surface in, tetrahedra inside it out. The surface points and triangles are kept as
/// given (nglib adds interior points only); the caller checks that the tetrahedra's boundary is
/// the input surface.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "paramesh/util/Vec.hpp"

namespace paramesh {

struct NglibOptions {
  double maxSize = 0;       ///< largest interior edge (> 0)
  double grading = 0.3;     ///< nglib's size grading in (0, 1]: the size may grow by about this per size
  int optimizeSteps = 3;    ///< nglib's 3D optimisation steps (0: none)
};

struct NglibResult {
  std::vector<Vec3> interior;                ///< points nglib added (index n + i in tets)
  std::vector<std::array<int, 4>> tets;      ///< 0-based: < n the input points, >= n interior
  std::string error;                         ///< nglib's failure ("" when it filled the surface)
};

/// Fills the closed surface (points, triangles counter-clockwise seen from outside). nglib keeps
/// global state, so calls are serialised; its console output is silenced for the call. nglib
/// lives in the plugin libparamesh_nglib.so, loaded on the first call (NglibLoader.cpp) from
/// $PARAMESH_NGLIB_PLUGIN, else beside the executable or module holding this library, else the
/// loader's search path; a plugin that cannot be loaded is an Error naming where it looked.
NglibResult fillWithNglib(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                          const NglibOptions& options);

/// The Netgen version of the nglib the library was built on (from Netgen's CMake config).
std::string nglibVersion();

}  // namespace paramesh

/// The plugin's entry point (NglibPlugin.cpp): fills *out as fillWithNglib returns it.
extern "C" void paramesh_nglib_fill(const std::vector<paramesh::Vec3>* points,
                                    const std::vector<std::array<int, 3>>* triangles,
                                    const paramesh::NglibOptions* options, paramesh::NglibResult* out);
