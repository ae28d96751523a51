// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file EdgeMesh.hpp
/// One CAD edge's discretisation: curve parameters and the global mesh nodes at them.
#pragma once

#include <vector>

namespace paramesh {

struct EdgeMesh {
  std::vector<double> t;
  std::vector<int> nodes;  // global ids, size t.size()
  bool degenerate = false;
};

}  // namespace paramesh
