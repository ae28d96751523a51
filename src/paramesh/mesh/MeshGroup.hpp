// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshGroup.hpp
/// A named group of CAD entities whose elements the writers tag together (Gmsh physical groups,
/// Abaqus sets, SU2 markers, STL solids).
#pragma once
#include <string>
#include <vector>

namespace paramesh {

/// A user group ("inlet=Face3,Face7"): entities of one dimension, 1-based CAD numbers.
/// dim 1: edges (their segments), 2: faces (their triangles and quads), 3: solids (tetrahedra).
struct MeshGroup {
  std::string name;
  int dim = 2;
  std::vector<int> entities;
};

/// Why name cannot name a user group, or "": it must be 1-64 characters of letters, digits and
/// _ . - starting with a letter or _, and not a default group's name (Face<i>, Edge<i>,
/// Vertex<i>, Solid<i>, BoundaryLayer<i>: case-insensitive, as Abaqus compares set names).
std::string groupNameProblem(const std::string& name);

/// "NAME=Face3,Face7" (or Edge<i>, Solid<i>; one kind per group) into a group; throws
/// ParameterError naming what is wrong.
MeshGroup parseGroup(const std::string& text);

}  // namespace paramesh
