// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file NarrowZones.hpp
/// Narrow parts of faces: places where two parts of a face's boundary face each other across a gap
/// narrower than the boundary spacing (a thread flank, a ligament between a hole and an edge). One
/// row of triangles spans such a gap, and its shape is decided by how the nodes of the two sides
/// sit relative to each other. For a gap w and a spacing s:
///
///     nodes opposite each other:  right triangles, smallest angle atan(w / s)   (< 30 deg below w = 0.58 s)
///     nodes staggered:            isosceles ones, smallest angle atan(2 w / s)  (< 30 deg below w = 0.29 s)
///
/// findNarrowGaps measures the gaps on a face's boundary loops; staggeredParameters re-places the
/// nodes of one side (the follower edge) midway between the projections of the other side's nodes.
#pragma once
#include <functional>
#include <vector>

#include "paramesh/geom/Geometry.hpp"
#include "paramesh/size/SizeField.hpp"

namespace paramesh {

/// A node of a face's boundary loop, in wire order.
struct LoopNode {
  Vec3 xyz;
  Vec3 inward;    ///< unit, tangent to the face, pointing into it; zero where undefined (a pole)
  int edge = -1;  ///< 0-based CAD edge of the segment from this node to the next
};

/// A boundary node facing another part of its face's boundary across the face.
struct NarrowGap {
  int loop = -1, index = -1;  ///< the node: loops[loop][index]
  int edgeIn = -1, edgeOut = -1;  ///< edges of the segments ending / starting at the node (equal inside an edge)
  int edgeAcross = -1;        ///< edge of the boundary segment across the gap
  Vec3 p, q;                  ///< the node and the nearest point across
  double width = 0;           ///< |q - p|
  double spacing = 0;         ///< mean length of the node's two boundary segments
};

/// Gaps of one face narrower than maxRatio x the local boundary spacing: for each node, the nearest
/// boundary segment that the chord from the node reaches across the face (leaving it into the face
/// and arriving from inside, each within 53 degrees of the inward direction); segments of the
/// node's own edges do not count. A sharp corner between two edges is a gap too, from where its
/// sides come closer than maxRatio spacings. O(n) with a hash grid over the segments.
std::vector<NarrowGap> findNarrowGaps(const std::vector<std::vector<LoopNode>>& loops, double maxRatio);

/// Parameters t0 < ... < t1 of a follower edge: one node midway (in arc length) between the
/// projections of each two consecutive leader nodes (`leader`: 3D points near the curve, any
/// order; consecutive means at most 1.6 local sizes apart), the pieces in between discretised by
/// the size field as usual. Staggered nodes closer than 0.75 sizes to an end are dropped (a shorter
/// end segment would stand a poor triangle in the corner there), unless a leader node stands right
/// across that end (a strip closed by a short edge: half a segment starts its zigzag).
std::vector<double> staggeredParameters(const ICurve& c, double t0, double t1, const std::vector<Vec3>& leader,
                                        const SizeField& field, double maxTurn);

}  // namespace paramesh
