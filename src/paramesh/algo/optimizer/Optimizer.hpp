// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Optimizer.hpp
/// 3D local operators on a face triangulation and the driver loop that applies them (one file an
/// operator beside this header; their shared predicates in OptimizerDetail.hpp). Every
/// decision uses straight 3D edge lengths and 3D triangle quality; every operation is checked for
/// validity in (u,v) (exact orientation) and in 3D (triangle normal against the surface normal).
/// Boundary and pole vertices never move; constrained edges are never flipped, split or collapsed.
#pragma once
#include "paramesh/algo/DeviationZone.hpp"
#include "paramesh/algo/SurfaceContext.hpp"
#include "paramesh/algo/Triangulation.hpp"
#include "paramesh/util/Log.hpp"

#include <functional>
#include <vector>

namespace paramesh {

class Optimizer {
 public:
  /// progress (optional) is polled regularly so that a cancel request stops long passes quickly.
  Optimizer(Triangulation& T, const SurfaceContext& C, const Progress* progress = nullptr)
      : T_(T), C_(C), progress_(progress) {}

  /// Flips edges while the min 3D quality of the pair improves. Returns the number of flips.
  int swapPass();
  /// Moves each free vertex towards the mean of the equilateral apexes of its ring (projected on
  /// the surface) when the ring's min quality improves. Returns the number of moves.
  int smoothPass();
  /// Size conformity: moves each free vertex with an edge outside [0.72, 1.4] of the local size
  /// (out of the unit band [1/sqrt2, sqrt2] with a margin) along the edges' directions so that
  /// fewer of its edges are out, when its ring stays valid, no triangle of the ring drops below
  /// 30 degrees that was not, and the ring's quality drops by at most 2 %. Returns the moves.
  int lengthPass();
  /// Edge flips that bring vertex valences closer to regular (6 inside; at the boundary the
  /// triangle count closest to its angle / 60 degrees) while the pair's worst radius ratio stays
  /// above qFactor times the old one. The two triangles of each flip are appended to `changed`
  /// (optional). Returns the flips.
  int valenceSwapPass(double qFactor, std::vector<int>* changed = nullptr);
  /// Vertices of the triangles that have a free vertex whose valence is not 6 (one flag per
  /// vertex): where the radius ratio falls short in a graded mesh.
  std::vector<char> irregularZone() const;
  /// One Newton step, in its tangent plane, per free vertex flagged in `active` (one flag per
  /// vertex) towards the largest summed radius ratio of its ring; a move is kept when the sum
  /// gains at least 1e-3, the ring's worst triangle stays above min(its old value, 0.8), and no
  /// new angle below 30 degrees and no new edge out of [0.72, 1.4] h appear. On return `active`
  /// flags the neighbours of the moved vertices (what the next pass visits). About 15 ring
  /// evaluations per visited vertex. Returns the moves.
  int polishPass(std::vector<char>& active);
  /// Splits edges longer than `longRatio` * h (3D), longest first. Returns the number of splits.
  int splitPass(double longRatio);
  /// Splits edge i of triangle t at its surface midpoint (projected 3D chord midpoint when valid).
  /// Returns the new vertex, or -1 when the edge is constrained or the midpoint leaves the face
  /// (or, with keepFacing, when a new triangle would face away from the surface where the one it
  /// came from did not).
  /// at (optional): the split point in scaled (u,v), on the edge's (u,v) segment, used as is
  /// (a fold's crest, from refineDeviation); such a split is also refused when a new triangle
  /// falls below gamma kFoldMinQuality and below the pair it replaces, or when the point lies
  /// within kCrestShare of the edge's length from a vertex opposite the edge.
  int splitEdge(int t, int i, bool keepFacing = false, const Vec2* at = nullptr);
  /// Collapses edges shorter than `shortRatio` * h when no edge longer than maxRatio * h appears.
  int collapsePass(double shortRatio, double maxRatio);
  /// Triangles standing on a boundary-layer front edge (both ends face-local boundary nodes)
  /// whose height is below `ratio` x the equilateral height of the local size: their apex (when
  /// free) moves towards the ideal position if the ring stays valid. Returns the number of moves.
  int repairFrontApexes(double ratio);
  /// True when the smallest 3D angle of triangle t is below 30 degrees (pole triangles: false).
  bool poorAngle(int t) const;
  int countPoorAngles() const;
  /// Moves the free vertices of t (to their ring's centroid, its equilateral apexes' mean, or
  /// halfway) when that raises the smallest angle of their ring; true when one moved.
  bool relocateForAngles(int t);
  /// Flips the free edge of t whose flip gives the pair the largest smallest angle, when the new
  /// pair is valid, keeps the crease guard and is no worse than min(old pair, 30 degrees) (a step
  /// the quality-driven swap pass would not take, for the smoothing after it); true when flipped.
  bool flipForAngles(int t);
  /// Splits the longest free edge of every triangle with at least minBoundary vertices on the
  /// boundary and a smallest angle below 30 degrees. Returns the number of splits.
  int splitBoundarySlivers(int minBoundary = 3);
  /// Collapses the free vertex at the largest angle of every triangle with an angle below 30
  /// degrees onto a neighbour (shorter edge first) when the ring stays valid. Returns the number.
  int collapsePoorApexes();
  /// collapsePoorApexes() for one triangle; true when a vertex was collapsed. The triangles left
  /// need only face like the surface at their centroid (collapse(t, i, true)); the caller keeps
  /// the result only when the poor triangles around drop.
  bool collapseApex(int t);
  /// Splits the longest free edge of t; returns the new vertex or -1.
  int splitLongestFree(int t);
  /// Number of vertices of t on the boundary.
  int boundaryVertices(int t) const;
  /// The default schedule: split/collapse, then alternate swaps and smoothing.
  void run(int passes);

  /// Restricts swapPass, smoothPass and countPoorAngles to the triangles with a vertex in the
  /// region (one flag per vertex; empty: the whole face). Vertices added later count as inside,
  /// and each flip adds its four vertices, so every triangle an operation changes stays inside:
  /// local repairs then cost O(region), not O(face).
  void setRegion(std::vector<char> region) { region_ = std::move(region); }
  const std::vector<char>& region() const { return region_; }
  /// Vertices within `rings` edge rings of the given triangles' vertices (a region flag vector).
  std::vector<char> regionAround(const std::vector<int>& tris, int rings) const;
  /// Triangles of T below 30 degrees with a vertex in `region` (empty: all), e.g. a copy of the
  /// triangulation before a local repair, to compare with countPoorAngles() over the same region.
  static int countPoorAngles(const Triangulation& T, const std::vector<char>& region);

  /// Distance from the centroid of triangle (a,b,c) to the surface (chordal deviation).
  /// footOutside (optional): set when the projection converged to a point outside the trimmed face.
  /// foot (optional): the projection's foot, scaled (u,v) (left as it is when no projection runs: 0).
  double deviation(int a, int b, int c, bool* footOutside = nullptr, Vec2* foot = nullptr) const;
  /// Cheap upper estimate of deviation() from the vertex normals (no surface evaluation).
  double deviationEstimate(int a, int b, int c) const;
  /// Refines triangles whose chordal deviation exceeds maxDev (a length; 0: no absolute bound) or
  /// ratio times their mean 3D edge length (0: no relative bound): splits the free edge with the
  /// largest sag (the longest on a tie), or inserts the centroid. The part of a triangle's
  /// deviation that its boundary nodes already have (CAD edges lying off the surface within their
  /// tolerance) is not counted: refining cannot remove it. Afterwards swaps and smoothing never
  /// create such triangles.
  /// Edges shorter than minEdge are not split.
  /// zones (optional): local bounds, the smallest of the balls holding a triangle's centroid.
  int refineDeviation(double maxDev, double ratio = 0, double minEdge = 0,
                      const std::vector<DeviationZone>* zones = nullptr);
  /// The user's min-size / curvature angle (0: none). The relative deviation bound of a triangle
  /// whose vertex normals turn faster than 1/reach per unit length (the surface's radius below
  /// reach) grows by reach x that rate: a triangle with edges at the min-size on such a surface
  /// then meets it, and the refinement neither goes below the min-size nor flips the triangles
  /// into needles to chase a bound the min-size forbids. deviationMisses() still reports against
  /// the plain bound.
  void setMinSizeReach(double reach) { reach_ = reach; }
  /// A triangle still beyond its deviation bound after refineDeviation.
  struct DeviationMiss {
    double deviation = 0;  ///< centroid distance to the surface
    double allowed = 0;    ///< its bound (the CAD-gap share of its nodes included)
    Vec3 centroid;
    Vec2 foot;             ///< the centroid's foot on the surface, scaled (u,v)
    Vec2 corners[3];       ///< the triangle's corners, scaled (u,v)
  };
  /// The triangles beyond the absolute and relative bounds of the last refineDeviation (the
  /// user's --max-deviation and --curvature-angle; its local zones, the nearest-face check's own
  /// means, are not counted), measured as refineDeviation measures them; none on a planar face.
  std::vector<DeviationMiss> deviationMisses() const;
  /// 3D quality of triangle t (pole-degenerate triangles count as 1: they vanish in 3D).
  double quality(int t) const;
  /// True when triangle (a,b,c) is valid: counter-clockwise in (u,v) and facing like the surface.
  bool valid(int a, int b, int c) const;

 private:
  double edgeRatio(int a, int b) const;
  /// Edges from v to the vertices of link outside [kBandLo, kBandHi] of the local size.
  int outOfBand(int v, const std::vector<int>& link) const;
  /// The point of edge (a,b)'s (u,v) segment where the surface runs farthest from the 3D chord,
  /// when it is markedly farther (kRidgePeak) than the chord's projected midpoint, i.e. the edge
  /// crosses a fold narrower than itself, and not near an end (kCrestShare); false otherwise.
  bool ridgePoint(int a, int b, Vec2& at) const;
  /// refineDeviation's parts. gap_ for every node vertex (see gap()).
  void measureGaps();
  /// The free edge of t (tr: its corners) with the largest sag estimated from the vertex normals,
  /// the longest on a near tie; none from a pole, none shorter than minEdge unless belowFloor.
  /// -1: none.
  int sagEdge(int t, const Triangle& tr, double minEdge, bool belowFloor) const;
  /// The edge of t to split into best (-1: none); true when it is to be split at a fold's crest,
  /// then at `crest`.
  bool chooseSplit(int t, const Triangle& tr, double minEdge, int& best, Vec2& crest) const;
  /// Inserts the projected centroid of t (tr: its corners, best: the edge chooseSplit found) when
  /// t is not at the smallest size and no new triangle is refused; true when inserted.
  bool insertCentroid(int t, const Triangle& tr, double minEdge, int best);
  /// One step of refineDeviation on triangle t when it is still beyond its bound (a flip, a split,
  /// a collapse or a centroid insertion); true when the mesh changed.
  bool refineTriangle(int t, double minEdge);
  /// Triangle t, over its deviation bound, has a crest vertex: one of its free vertices, left
  /// next to a fold's crest, collapses onto a neighbour (crest vertices first, then the nearest)
  /// when the triangles it leaves are valid, within their deviation bounds, and none collinear
  /// (kFoldMinQuality) that was not. True when one collapsed.
  bool collapseForDeviation(int t);
  /// Flips the free edge of t (over its deviation bound) whose flip lowers the pair's worst
  /// deviation/bound most, by at least a fifth (kFlipGain), with both new triangles valid (no
  /// crease guard: lining an edge up with a fold folds the pair on purpose). True when flipped.
  bool flipForDeviation(int t);
  /// Edge i of t is free and shared with triangle u = (d,c,b), t being (a,b,c) (a the corner
  /// opposite the edge): the quad a flip of the edge rewrites into (a,b,d), (a,d,c).
  bool edgeQuad(int t, int i, int& u, int& a, int& b, int& c, int& d) const;
  /// edgeQuad(), and flipping the edge gives two valid triangles (a,b,d), (a,d,c).
  bool validFlip(int t, int i, int& u, int& a, int& b, int& c, int& d) const;
  /// Visits the free interior edges of the live triangles in the region, triangle by triangle, as
  /// visit(t, i, u, a, b, c, d) (edgeQuad's names); when visit returns true (it rewrote t), t's
  /// edges are visited again from the first. done(t) runs once t's edges are through.
  template <class Visit, class Done>
  void sweepFreeEdges(Visit&& visit, Done&& done);
  /// The worst 3D quality of the pair (a,b,d), (a,d,c) that flipping edge (b,c) of (a,b,c),
  /// (d,c,b) makes.
  double flippedQuality(int a, int b, int c, int d) const;
  /// Quality figures of ring_: worst and summed radius ratio, worst sine of the smallest angle.
  struct RingStats {
    double minQ = 1e300, sumQ = 0, minSin = 1e300;
  };
  RingStats ringStats() const;
  /// Vertex v may move (not on the boundary, a pole, the super-triangle or dead) and its ring is a
  /// closed fan of at least 3 triangles, left in ring_.
  bool movableWithRing(int v);
  /// Moves vertex v (whose ring is ring_) towards goal, then halfway, keeping the first position
  /// where the ring is valid and accept(its stats) holds; false, v unchanged, otherwise.
  bool tryMove(int v, Vec3 goal, const std::function<bool(const RingStats&)>& accept);
  /// Collapses edge i of t onto its far vertex. The relabelled triangles must be valid(); with
  /// centroidFacing, facesAtCentroid() is enough (collapseApex: a cap across a thin nose).
  bool collapse(int t, int i, bool centroidFacing = false);
  /// Valid in (u,v), facing away from no vertex normal, and facing like the surface (within
  /// ~78 degrees) at the projection of its centroid: across a nose much thinner than itself a
  /// triangle makes 80-90 degrees with the seam's normals (measured: docs/tuning/optimizer.md).
  bool facesAtCentroid(int a, int b, int c) const;
  bool deviationOk(int a, int b, int c, double allowed) const;
  /// Flipping edge (b,c) of triangles (a,b,c) and (d,c,b) into (a,b,d), (a,d,c) keeps both valid,
  /// does not fold the pair beyond the crease guard (10 degrees, or its present fold) and keeps
  /// the deviation bounds.
  bool flipAllowed(int a, int b, int c, int d) const;
  /// Puts V at the surface point nearest goal (projection started at `from`); false, V unchanged,
  /// when the projection fails or leaves the face.
  bool moveTo(TriVertex& V, Vec2 from, Vec3 goal) const;
  /// True when every triangle of ring_ is valid and within the deviation bound.
  bool ringValid() const;
  /// Mean of the apexes of the equilateral triangles standing on the far edges of ring_ (the ring
  /// of v), in v's tangent plane: the smoothing target.
  Vec3 ringApexMean(int v) const;
  /// Deviation triangle (a,b,c) may have under the absolute and relative bounds and, with
  /// withZones, the local zones (+inf: none).
  /// relaxed: with setMinSizeReach, the relative bound grown where the min-size forbids it.
  double allowedDeviation(int a, int b, int c, bool withZones = true, bool relaxed = true) const;
  /// Distance of vertex v from the surface at its (u,v): nonzero only for nodes of CAD edges
  /// that lie off the face within the edge's tolerance.
  double gap(int v) const { return v < (int)gap_.size() ? gap_[v] : 0.0; }
  Triangulation& T_;
  const SurfaceContext& C_;
  std::vector<int> ring_;
  /// run()'s passes (empty outside them): the vertices whose ring moved or changed since the
  /// last smoothing pass (a flip marks its four vertices, a move the vertex and its link); the
  /// next smoothing pass tries those only, since any other would be tried on exactly what was
  /// refused before
  std::vector<char> touched_;
  void touch(int v) {
    if (v < (int)touched_.size()) touched_[v] = 1;
  }
  /// smoothPass over the vertices marked in active only (nullptr: all); a move marks its link
  /// in active too
  int smoothPassOver(std::vector<char>* active);
  double maxDev_ = 0;    ///< absolute deviation bound; 0: none
  double devRatio_ = 0;  ///< deviation bound relative to the mean edge length; 0: none
  double reach_ = 0;     ///< setMinSizeReach
  std::vector<DeviationZone> zones_;  ///< local deviation bounds
  bool deviationBounded() const { return maxDev_ > 0 || devRatio_ > 0 || !zones_.empty(); }
  std::vector<double> gap_;
  std::vector<char> region_;
  bool inRegion(int v) const { return region_.empty() || v >= (int)region_.size() || region_[v]; }
  bool triInRegion(int t) const {
    const Triangle& tr = T_.tris[t];
    return inRegion(tr.v[0]) || inRegion(tr.v[1]) || inRegion(tr.v[2]);
  }
  void addToRegion(int v) {
    if (!region_.empty() && v < (int)region_.size()) region_[v] = 1;
  }
  const Progress* progress_ = nullptr;
  void poll(int i) const {
    if (progress_ && (i & 1023) == 0) progress_->poll();
  }
};

}  // namespace paramesh
