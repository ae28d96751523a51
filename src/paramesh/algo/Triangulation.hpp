// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Triangulation.hpp
/// A 2D triangulation in a face's (scaled) parameter plane with adjacency, constrained edges and
/// per-vertex 3D data. It is the working structure of the face mesher: boundary CDT, frontal
/// insertion, and the 3D local operators (flip, split, collapse, relocate) all act on it.
///
/// Numbering convention (per triangle, counter-clockwise in (u,v)):
///
///            v[2]
///            /  \          n[i]   = triangle across the edge opposite v[i], -1 if none
///       e1  /    \  e0     edge i = (v[(i+1)%3], v[(i+2)%3])
///          /      \        cons bit i = edge i is constrained (a CAD boundary segment)
///       v[0]------v[1]
///             e2
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <functional>
#include <vector>

#include "paramesh/util/Vec.hpp"

namespace paramesh {

/// Vertex flags.
enum : uint8_t {
  VF_BOUNDARY = 1,  ///< on a CAD edge (or a degenerate edge): never moved
  VF_POLE = 2,      ///< a copy of a degenerate (pole) node: several uv images, one 3D point
  VF_SUPER = 4,     ///< auxiliary bounding vertex of the initial triangulation
  VF_DEAD = 8,      ///< removed by a collapse
  VF_CREST = 16,    ///< on the crest of a fold narrower than the mesh: no normal (zero), never moved
  VF_ROW = 32,      ///< on a row beside a crest (Crest.hpp): never moved
};
/// Vertices the optimiser never moves or collapses away.
constexpr uint8_t VF_FIXED = VF_BOUNDARY | VF_POLE | VF_SUPER | VF_DEAD | VF_CREST | VF_ROW;

struct TriVertex {
  Vec2 uv;          ///< scaled (u,v)
  Vec3 xyz;         ///< 3D position on the surface
  Vec3 normal;      ///< unit surface normal S_u x S_v (zero when undefined)
  double h = 0;     ///< target size at the vertex
  double M[3] = {1, 0, 1};  ///< metric (a, b, c) = J^T J / h^2 in scaled (u,v)
  int node = -1;    ///< global node id (boundary vertices) or -1 (created by the face mesher)
  int tri = -1;     ///< one incident live triangle
  uint8_t flags = 0;
};

struct Triangle {
  int v[3] = {-1, -1, -1};
  int n[3] = {-1, -1, -1};
  uint8_t cons = 0;
  bool dead = false;
};

class Triangulation {
 public:
  std::vector<TriVertex> verts;
  std::vector<Triangle> tris;

  int addVertex(const TriVertex& v) {
    verts.push_back(v);
    return (int)verts.size() - 1;
  }
  bool isConstrained(int t, int i) const { return (tris[t].cons >> i) & 1; }
  void setConstrained(int t, int i, bool on);
  /// Index (0..2) of vertex v in triangle t, or -1.
  int indexOf(int t, int v) const {
    const Triangle& T = tris[t];
    return T.v[0] == v ? 0 : T.v[1] == v ? 1 : T.v[2] == v ? 2 : -1;
  }
  /// Index in triangle t of the edge shared with neighbour nb, or -1.
  int edgeTo(int t, int nb) const {
    const Triangle& T = tris[t];
    return T.n[0] == nb ? 0 : T.n[1] == nb ? 1 : T.n[2] == nb ? 2 : -1;
  }

  /// Builds the constrained Delaunay triangulation of the existing vertices and segments
  /// (pairs of vertex indices), removes everything outside the segments' loops (by parity), and the
  /// auxiliary vertices. Returns false with a reason on failure (crossing segments, open loops).
  bool buildConstrained(const std::vector<std::pair<int, int>>& segments, std::string& why);

  /// Walks from triangle `start` to the triangle containing p. Returns -1 when the walk leaves the
  /// triangulation or would cross a constrained edge. *onEdge receives the edge index when p lies
  /// exactly on an edge of the result (else -1). maxSteps > 0 bounds the walk (-1 when it runs
  /// out); by default 4 x the triangles.
  int locate(Vec2 p, int start, int* onEdge = nullptr, int maxSteps = 0) const;
  /// Walk length for points next to their start triangle (the frontal insertion, the optimiser's
  /// splits): a walk that long means a damaged (folded) triangulation, not a far point (a fuzzed
  /// propeller_and_shaft.iges face walked 4n steps per point, a quadratic hang).
  static constexpr int kLocalWalk = 256;

  /// Flip predicate: should the edge i of triangle t be flipped (given a convex quad)?
  using FlipTest = std::function<bool(int t, int i)>;
  /// Inserts vertex v (already added) lying in triangle t (or on its edge e >= 0), then restores the
  /// local criterion by flips. Triangles created/modified are appended to *touched.
  void insert(int v, int t, int e, const FlipTest& test, std::vector<int>* touched = nullptr);
  /// Flips edge i of triangle t if the quad is strictly convex; returns false otherwise.
  bool flip(int t, int i);
  /// True when flipping edge i of t keeps both triangles counter-clockwise (exact test).
  bool flipIsValid(int t, int i) const;
  /// True when inserting a point at p into triangle t (e < 0) or on its edge e makes only
  /// counter-clockwise triangles (exact test). False when p coincides with a vertex, or lies on a
  /// triangle's edge other than e: the insertion would make a triangle of zero area in (u,v).
  bool insertionIsValid(Vec2 p, int t, int e) const;
  /// The 3D distance from x to the nearest corner of the triangles that inserting a point into
  /// triangle t (e < 0) or on its edge e would split.
  double insertionClearance(Vec3 x, int t, int e) const;
  /// The refinements insert no point nearer a corner than this share of the split edge's (or
  /// the refined triangle's longest edge's) 3D length: on a very unevenly parametrised surface a
  /// (u,v) midpoint or centroid can land on a corner in 3D.
  static constexpr double kInsertClearance = 0.01;

  /// Ordered ring of triangles around vertex v (counter-clockwise); *closed = false when v is on
  /// the triangulation boundary (then the ring starts at the boundary).
  void ring(int v, std::vector<int>& out, bool* closed = nullptr) const;

  /// Euclidean Delaunay flip test in (u,v).
  bool delaunayFlip(int t, int i) const;
  /// Flip test in the mean metric of the four vertices.
  bool metricFlip(int t, int i) const;

  /// Makes a-b an edge of the triangulation (retriangulating the triangles it crosses) and
  /// constrains it; false with a reason when a constrained edge is in the way.
  bool insertSegment(int a, int b, std::string& why) { return recoverSegment(a, b, why); }

  /// Drops dead triangles and vertices no triangle uses, keeping order. Returns old->new vertex map.
  std::vector<int> compact();

 private:
  int newTri();
  std::vector<int> freeTris_;
  bool recoverSegment(int a, int b, std::string& why, int depth = 0);
  /// Triangulates the pseudo-polygon p, q, chain (left of p->q) by apexes chosen by incircle;
  /// with exact, only among the apexes making an empty ear (exact predicates; slower).
  void triangulatePseudo(int p, int q, const std::vector<int>& chain, std::vector<std::array<int, 3>>& out,
                         bool exact = false) const;
  /// True when (p, q, chain[m]) is counter-clockwise, holds no other vertex of the pseudo-polygon
  /// and its sides p-chain[m], chain[m]-q cross none of the polygon's edges.
  bool isEmptyEar(int p, int q, const std::vector<int>& chain, size_t m) const;
  void legalize(std::vector<std::pair<int, int>>& stack, int v, const FlipTest& test, std::vector<int>* touched);
};

}  // namespace paramesh
