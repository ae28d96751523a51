// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Groups.hpp
/// The named groups every writer tags: the default ones (Face<i>, Solid<i>) and the user's
/// (SurfaceMesh::groups), numbered as Gmsh numbers physical groups: a (dimension, tag) pair.
#pragma once
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "paramesh/mesh/SurfaceMesh.hpp"

namespace paramesh::io {

struct WrittenGroup {
  int dim = 2;
  int tag = 0;  ///< unique within its dimension
  std::string name;
  std::vector<int> entities;  ///< 1-based CAD numbers, ascending
  bool user = false;
};

/// The user groups first, tags 1, 2, ... per dimension in the order given (Gmsh numbers physical
/// groups in definition order; a reader keeping one tag per facet, as dolfinx does, keeps the
/// lowest: the user's). Then the default ones, each with tag k + i for entity i where k is the
/// number of user groups of its dimension (tag = entity number without user groups):
/// Vertex<i> (dim 0) for each CAD vertex holding a node, Edge<i> (dim 1) for each edge holding
/// segments, Face<i> (dim 2) for each face holding elements, Solid<i> (dim 3) for each solid
/// holding tetrahedra: every element has a group (readers such as meshio expect it).
std::vector<WrittenGroup> writtenGroups(const SurfaceMesh& m);

/// (dim, entity) -> the tags of the groups holding it, ascending.
std::map<std::pair<int, int>, std::vector<int>> groupTagsByEntity(const std::vector<WrittenGroup>& groups);

}  // namespace paramesh::io
