// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file FaceLayers.hpp
/// Internal to the boundary-layer files (src/paramesh/algo/boundary_layer/*.cpp): a column of
/// layer points, and FaceLayers, which grows one face's layers; its methods are defined by concern.
#pragma once
#include <array>
#include <utility>
#include <vector>

#include "paramesh/algo/boundary_layer/BoundaryLayer.hpp"
#include "paramesh/algo/boundary_layer/SegmentBuckets.hpp"

namespace paramesh::bl_detail {

constexpr double kPi = 3.14159265358979323846;

/// The points of one column, from its root on the BL edge up to its top, and its marching state.
struct Column {
  int root = -1;            ///< loop index of the root
  int spec = -1;
  double factor = 1;        ///< step multiplier (merged corner)
  bool fixed = false;       ///< end column: points taken from the loop (neighbour edge nodes)
  bool active = true;
  int stop = 0;             ///< 0 reached N, 1 boundary, 2 collision, 3 invalid quad, 4 aspect, 5 end of edge
  std::vector<Vec2> uv;     ///< points, [0] = root
  std::vector<Vec3> xyz;
  std::vector<int> ref;     ///< node refs: global (>=0) or BL-local -(k+1)
  Vec3 dir;                 ///< current marching direction (unit, tangent plane)
  double wEnd[2] = {0, 0};  ///< blending weights towards the run's start / end outermost column
};

/// The layers of one face: every run of BL segments of its loops gets columns at its points, which
/// march row by row until they stop; the run's elements go to the result and its front replaces the
/// run in the loops. Runs are grown one after the other; later ones stop at the earlier ones.
class FaceLayers {
 public:
  FaceLayers(const ISurface& s, const std::vector<std::vector<LoopPoint>>& loops,
             const std::vector<std::vector<Vec2>>& trueLoops, const DomainGuard& guard, const EdgeSpecMap& specOf,
             const std::vector<LayerLaw>& laws, FaceBLResult& out);

  void run();

 private:
  const ISurface& S_;
  const std::vector<std::vector<LoopPoint>>& loops_;
  const std::vector<std::vector<Vec2>>& trueLoops_;  ///< the guard's loops, index for index with loops_
  const DomainGuard& guard_;
  const EdgeSpecMap& specOf_;
  const std::vector<LayerLaw>& laws_;
  FaceBLResult& out_;
  std::vector<char> specQuads_;
  std::vector<Vec3> otherPts_;  ///< points of already grown runs (collision tests)
  std::vector<double> otherH_;
  /// segments of already grown runs' grids in (u,v): their marched columns and their rows
  struct Seg {
    Vec2 a, b;
    Vec3 A, B;
  };
  std::vector<Seg> otherSegs_;
  SegmentBuckets otherBuckets_;                 ///< otherSegs_ by position
  std::vector<std::pair<int, int>> loopSegs_;  ///< (loop, first point) of every boundary segment
  SegmentBuckets loopBuckets_;                  ///< loopSegs_ by position

  // GrowFaceLayers.cpp: the runs of a loop, their side, their columns from root to front
  void processLoop(int L);
  void growRun(int L, int a, int nseg, bool closed);
  bool isBL(const LoopPoint& p) const;
  int sideOf(int L, int i) const;
  double runSign(int L, int a, int nseg) const;

  // EndColumns.cpp: the outermost columns of an open run, and the lean towards them
  int endColumnLength(int L, int i, int dir, const LayerLaw& law) const;
  void addEndColumn(int L, int i, bool first, int npts, double sgn, Column base, std::vector<Column>& cols) const;
  void leanTowardsEnds(std::vector<Column>& cols, bool closed) const;
  void trimAtApex(int L, int a, int nseg, bool closed, std::vector<Column>& cols) const;

  // CornerFans.cpp: the columns at a run's interior points (merged at convex corners, fans at reflex)
  void addCornerColumns(int L, int i, double sgn, const Column& base, std::vector<Column>& cols);

  // SurfaceStep.cpp: steps of a given 3D length on the surface
  Vec3 normalAt(Vec2 uv) const;
  Vec2 uvStep(Vec2 uv, Vec3 d) const;
  bool step(Vec2 uv, Vec3 x, Vec3 d, double h, Vec2& uvOut, Vec3& xOut) const;
  bool solveInPlane(Vec3 x, Vec3 side, double h, Vec2& q, Vec3& p) const;

  // Marching.cpp: the row-by-row march of a run's columns and their directions
  std::vector<char> ownPoints(int L, const std::vector<Column>& cols) const;
  void march(int L, std::vector<Column>& cols, bool closed);
  void advanceColumns(int L, std::vector<Column>& cols, bool closed, int k, const std::vector<char>& own,
                      std::vector<char>& moved) const;
  void turnColumns(std::vector<Column>& cols, bool closed, int k) const;
  static Vec3 directionOf(const Column& c, int k);
  Vec3 marchDirection(const std::vector<Column>& cols, int i, int k) const;
  static bool samePosition(const Column& a, const Column& b, int k);
  static Vec3 pointAt(const Column& c, int k);
  double rowSpacing(const std::vector<Column>& cols, int i, bool closed) const;

  // CollisionQueries.cpp: what a step or a row meets, of the face's boundary and of the runs before
  bool crossesLoops(Vec2 a, Vec2 b, int skipLoop, int skipA, int skipB) const;
  double boundaryDistance(Vec3 x, double r, int L, int root, const std::vector<char>& own) const;
  bool boundaryPointNear(Vec3 a, Vec3 b, double d, int L, const std::vector<char>& own) const;
  bool closesOnBoundary(Vec3 p, Vec3 x, double d, int L, int root, const std::vector<char>& own) const;
  bool nearOther(Vec3 x, double d) const;
  bool crossesOther(Vec2 a, Vec2 b, Vec3 A, Vec3 B) const;
  bool nearOtherGrid(Vec3 x, double d) const;
  bool otherPointNearRow(Vec3 a, Vec3 b, double d) const;
  void addOther(const Seg& g);
  void recordGrid(const std::vector<Column>& cols, bool closed);

  // CollisionStops.cpp: the rules that stop columns and take their top points back
  void stopAtStoppedNeighbours(std::vector<Column>& cols, bool closed, int k, std::vector<char>& moved) const;
  void stopAtInvalidRows(int L, std::vector<Column>& cols, bool closed, int k, const std::vector<char>& own,
                         const std::vector<char>& moved) const;
  bool quadValid(Vec2 a, Vec2 b, Vec2 c, Vec2 d, Vec3 A, Vec3 B, Vec3 C, Vec3 D) const;
  void untangle(std::vector<Column>& cols, bool closed);
  static void trimNeedles(std::vector<Column>& cols, bool closed);

  // Elements.cpp: a grown run's nodes, statistics and elements
  void emit(int L, int a, int nseg, bool closed, std::vector<Column>& cols);
  int newNode(Vec2 uv, Vec3 x);
  void addQuad(int spec, std::array<int, 4> q, std::array<Vec2, 4> u, std::array<Vec3, 4> x);
  void addTri(int spec, int r0, Vec2 u0, int r1, Vec2 u1, int r2, Vec2 u2);

  // Handoff.cpp: the front handed to the face mesher
  static std::vector<std::pair<int, int>> frontPath(const std::vector<Column>& cols, bool closed);
  void handOff(int L, int a, int nseg, bool closed, const std::vector<Column>& cols);

 public:
  struct Replace {
    int loop = 0, from = 0, to = 0;
    bool whole = false;
    std::vector<LoopPoint> front;
  };
  std::vector<Replace> replaces_;

  void buildLoops();
};

}  // namespace paramesh::bl_detail
