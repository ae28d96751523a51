// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file SurfaceMesh.hpp
/// The output mesh as indexed structure-of-arrays. Indices are 0-based; CAD entity numbers stored
/// here are 1-based (FreeCAD's Face1/Edge1/Vertex1 numbering).
///
///   triangle (a,b,c): counter-clockwise seen from outside, i.e. (b-a)x(c-a) points along the CAD
///   face's outward normal (face orientation respected).
///   quad (a,b,c,d): same orientation rule.
///   order 2: triangle mid-nodes (ab, bc, ca); quad mid-nodes (ab, bc, cd, da).
///   tetrahedron (a,b,c,d): positive volume, ((b-a)x(c-a)).(d-a) > 0 (Gmsh, VTK and CalculiX
///   order); order 2 mid-nodes (ab, bc, ca, ad, bd, cd) (VTK / CalculiX C3D10 order).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "paramesh/mesh/MeshGroup.hpp"

#include "paramesh/util/Vec.hpp"

namespace paramesh {

/// Dimension of the CAD entity a node lies on (Volume: inside a solid, entity = 1-based solid).
enum class NodeKind : int8_t { Vertex = 0, Edge = 1, Face = 2, Volume = 3 };

struct SurfaceMesh {
  std::vector<Vec3> nodes;           ///< #N node coordinates
  std::vector<NodeKind> nodeKind;    ///< #N CAD entity dimension of each node
  std::vector<int> nodeEntity;       ///< #N 1-based CAD entity index (vertex/edge/face)
  std::vector<Vec2> nodeParam;       ///< #N (t,0) on edges, (u,v) on faces, (0,0) on vertices

  std::vector<std::array<int, 3>> triangles;  ///< #T corner nodes
  std::vector<int> triangleFace;              ///< #T 1-based CAD face
  std::vector<std::array<int, 4>> quads;      ///< #Q corner nodes
  std::vector<int> quadFace;                  ///< #Q 1-based CAD face
  std::vector<int> triangleLayer;             ///< #T 1-based boundary-layer spec, 0: none
  std::vector<int> quadLayer;                 ///< #Q 1-based boundary-layer spec, 0: none

  std::vector<std::array<int, 2>> segments;   ///< #S mesh edges on CAD edges (1D elements)
  std::vector<int> segmentEdge;               ///< #S 1-based CAD edge

  int order = 1;                                ///< 1 or 2
  std::vector<std::array<int, 3>> triangleMid;  ///< #T mid-edge nodes when order == 2
  std::vector<std::array<int, 4>> quadMid;      ///< #Q mid-edge nodes when order == 2
  std::vector<int> segmentMid;                  ///< #S mid nodes when order == 2

  std::vector<std::array<int, 4>> tets;       ///< #K corner nodes (volume fill)
  std::vector<int> tetSolid;                  ///< #K 1-based CAD solid (FreeCAD Solid<i>)
  std::vector<std::array<int, 6>> tetMid;     ///< #K mid-edge nodes when order == 2

  int numFaces = 0, numEdges = 0, numVertices = 0, numSolids = 0;
  /// User groups (MeshGroup.hpp), checked against the model; the writers add the default ones.
  std::vector<MeshGroup> groups;  ///< CAD entity counts (for writers)

  int addNode(Vec3 p, NodeKind k, int entity, Vec2 param = {}) {
    nodes.push_back(p);
    nodeKind.push_back(k);
    nodeEntity.push_back(entity);
    nodeParam.push_back(param);
    return (int)nodes.size() - 1;
  }
};

}  // namespace paramesh
