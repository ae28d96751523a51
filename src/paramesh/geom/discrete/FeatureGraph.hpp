// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file FeatureGraph.hpp
/// The CAD-like topology of a repaired triangulation: feature edges (dihedral angle over the
/// feature angle, boundary and non-manifold edges) chained into curves between corners, and the
/// patches between them as faces. Numbering is stable: faces in order of their first input
/// triangle, edges in order of first use walking the faces' triangles, vertices in order of
/// first use by the edges. These become the discrete backend's faces, edges and vertices.
#pragma once
#include <array>
#include <unordered_map>
#include <vector>

#include "paramesh/geom/discrete/TriangleSoup.hpp"

namespace paramesh {

struct FeatureGraph {
  struct Chain {
    std::vector<int> nodes;  ///< mesh nodes along the edge, first to last (closed: first == last)
    int v0 = -1, v1 = -1;    ///< 0-based vertices at its ends
    std::vector<int> faces;  ///< 0-based faces beside it, ascending
  };
  std::vector<int> triFace;                ///< per triangle: 0-based face
  std::vector<std::vector<int>> faceTris;  ///< per face: its triangles, ascending
  std::vector<Chain> edges;
  std::vector<int> vertexNode;             ///< per vertex: its mesh node
  /// Per face: its boundary as closed loops of edge uses (0-based edge, reversed), each loop
  /// running with the face's triangles (the face on its left).
  std::vector<std::vector<std::vector<std::pair<int, bool>>>> faceLoops;
};

/// The directed sides (a, b) of a face's triangles (sideKey) -> the triangle.
std::unordered_map<unsigned long long, int> faceSides(const TriangleSoup& mesh, const std::vector<int>& tris);

/// Where a wire passes vertex v with the mesh edge (v's node, next) in the corner its face has
/// there (sides: faceSides of that face): the index of the use arriving at v (a wire may pass a
/// vertex more than once, along both sides of a crease or a seam). The first passage when none
/// holds it, size() when the wire does not pass v.
size_t splicePosition(const TriangleSoup& mesh, const FeatureGraph& g,
                      const std::unordered_map<unsigned long long, int>& sides,
                      const std::vector<std::pair<int, bool>>& wire, int v, int next);

/// featureAngleDeg: a mesh edge between two facets whose normals differ by more than this is a
/// feature. Sharp turns of more than the same angle along a chain of feature edges are corners.
FeatureGraph buildFeatureGraph(const TriangleSoup& mesh, double featureAngleDeg = 40.0);

}  // namespace paramesh
