// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/algo/BoundaryLayer.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <map>
#include <unordered_map>

#include "paramesh/algo/Predicates.hpp"
#include "paramesh/model/Coincidence.hpp"
#include "paramesh/model/EdgeDiscretizer.hpp"
#include "paramesh/util/Error.hpp"

namespace paramesh {

// ------------------------------------------------------------------------------------------ law

double LayerLaw::height(int k) const { return h0 * std::pow(r, k); }

double LayerLaw::offset(int k) const {
  if (std::fabs(r - 1) < 1e-12) return h0 * k;
  return h0 * (std::pow(r, k) - 1) / (r - 1);
}

LayerLaw LayerLaw::from(const BoundaryLayerSpec& s) {
  LayerLaw l;
  l.h0 = s.firstHeight;
  l.r = s.growth;
  l.maxAspect = s.maxAspect;
  l.quads = s.quads;
  if (s.layers > 0) {
    l.layers = s.layers;
  } else {
    // smallest N whose thickness reaches T
    const double T = s.thickness;
    l.layers = std::fabs(s.growth - 1) < 1e-12
                   ? (int)std::ceil(T / s.firstHeight - 1e-9)
                   : (int)std::ceil(std::log(1 + T * (s.growth - 1) / s.firstHeight) / std::log(s.growth) - 1e-9);
    l.layers = std::clamp(l.layers, 1, 1000);
  }
  return l;
}

// ------------------------------------------------------------------------------------ 1D ends

namespace {

/// Parameters along curve c, starting at parameter `from` and moving towards `to`, whose
/// consecutive straight 3D distances are the row heights; stops before the far end.
std::vector<double> marchAlongCurve(const ICurve& c, double from, double to, Vec3 start, const LayerLaw& law,
                                    double* lastHeight) {
  std::vector<double> out;
  const CurveSampling cs = sampleCurve(c, std::min(from, to), std::max(from, to), nullptr);
  const bool forward = to > from;
  // samples ordered from `from`
  std::vector<double> ts(cs.t);
  std::vector<Vec3> ps(cs.p);
  if (!forward) {
    std::reverse(ts.begin(), ts.end());
    std::reverse(ps.begin(), ps.end());
  }
  const Vec3 farEnd = ps.back();
  double t = ts.front();
  Vec3 p = start;  // the CAD vertex (the mesh node), which may sit off the curve within tolerance
  size_t j = 0;
  for (int k = 0; k < law.layers; ++k) {
    const double h = law.height(k);
    // the far end must stay clearly beyond the new point
    if (dist(p, farEnd) < 1.5 * h) break;
    // first sample at chord distance >= h, then bisection on the parameter
    while (j + 1 < ps.size() && dist(ps[j + 1], p) < h) ++j;
    if (j + 1 >= ps.size()) break;
    double a = ts[j], b = ts[j + 1];
    if (dist(c.eval(a), p) > h) a = t;
    for (int it = 0; it < 60; ++it) {
      const double mid = 0.5 * (a + b);
      if (dist(c.eval(mid), p) < h) a = mid;
      else b = mid;
    }
    t = 0.5 * (a + b);
    p = c.eval(t);
    out.push_back(t);
    if (lastHeight) *lastHeight = h;
  }
  return out;
}

}  // namespace

std::vector<EdgeBLPoints> planEndColumns(const IGeometryModel& m, const EdgeSpecMap& specOf,
                                         const std::vector<LayerLaw>& laws, const Coincidence* same) {
  std::vector<EdgeBLPoints> pts(m.numEdges());
  std::vector<double> startH0(m.numEdges(), 0), endH0(m.numEdges(), 0);
  for (int f = 0; f < m.numFaces(); ++f) {
    const auto& wires = m.faceWires(f);
    for (const Wire& w : wires) {
      const int n = (int)w.uses.size();
      for (int k = 0; k < n; ++k) {
        const EdgeUse& u = w.uses[k];
        const int spec = specOf[u.edge];
        if (spec < 0 || m.edgeDegenerate(u.edge)) continue;
        const LayerLaw& law = laws[spec];
        // neighbour uses: next one starts where this use ends, previous one ends where it starts
        for (int side = 0; side < 2; ++side) {
          const EdgeUse& nb = w.uses[side == 0 ? (k + 1) % n : (k + n - 1) % n];
          if (nb.edge == u.edge || specOf[nb.edge] >= 0 || m.edgeDegenerate(nb.edge)) continue;
          // the shared vertex is at the start of the next use's traversal / end of the previous'
          bool atStart = side == 0 ? !nb.reversed : nb.reversed;
          // an edge of an unsewn face is discretised through its representative: the points go
          // there, measured along its curve from its vertex node, so that the face's loop (which
          // takes the representative's nodes) has them at exactly the row heights
          int e = nb.edge;
          if (same && same->edgeRep[e] != e) {
            if (same->edgeReversed[e]) atStart = !atStart;
            e = same->edgeRep[e];
          }
          double t0, t1;
          m.edgeRange(e, t0, t1);
          auto& list = atStart ? pts[e].fromStart : pts[e].fromEnd;
          double& h0 = atStart ? startH0[e] : endH0[e];
          if (!list.empty() && h0 <= law.h0) continue;  // already set by a finer layer
          auto c = m.makeCurve(e);
          double last = 0;
          int vtx = m.edgeVertex(e, atStart ? 0 : 1);
          if (same && vtx >= 0) vtx = same->vertexRep[vtx];
          const Vec3 start = vtx >= 0 ? m.vertexPoint(vtx) : c->eval(atStart ? t0 : t1);
          list = atStart ? marchAlongCurve(*c, t0, t1, start, law, &last) : marchAlongCurve(*c, t1, t0, start, law, &last);
          (atStart ? pts[e].lastHeightStart : pts[e].lastHeightEnd) = last;
          h0 = law.h0;
        }
      }
    }
  }
  // both ends on one short edge: keep the points of each end up to the middle
  for (int e = 0; e < m.numEdges(); ++e) {
    auto& p = pts[e];
    if (p.fromStart.empty() || p.fromEnd.empty()) continue;
    double t0, t1;
    m.edgeRange(e, t0, t1);
    const double mid = 0.5 * (t0 + t1);
    while (!p.fromStart.empty() && p.fromStart.back() >= mid) p.fromStart.pop_back();
    while (!p.fromEnd.empty() && p.fromEnd.back() <= mid) p.fromEnd.pop_back();
  }
  return pts;
}

// ------------------------------------------------------------------------------------ 2D march

namespace {

constexpr double kPi = 3.14159265358979323846;
/// An end column along a neighbouring edge must leave the BL edge at this sine (10 degrees) or more.
constexpr double kMinEndSine = 0.17364817766693033;

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

/// Segments in 3D buckets (cubes of side `cell`): each segment is listed in the buckets met by
/// the boxes of its pieces of at most one cell, so that a query near a point looks at a few
/// buckets instead of every segment (the layer collision tests ran once per step over every
/// segment of the face: +36 % face time on the M6 with 2 852 columns).
class SegmentBuckets {
 public:
  explicit SegmentBuckets(double cell = 1.0) : cell_(cell > 0 && std::isfinite(cell) ? cell : 1.0) {}
  void add(int id, Vec3 a, Vec3 b) {
    const int n = std::clamp((int)std::ceil(dist(a, b) / cell_), 1, 4096);
    Vec3 p = a;
    for (int k = 1; k <= n; ++k) {
      const Vec3 q = a + (double(k) / n) * (b - a);
      forCells(lo(p, q), hi(p, q), [&](int64_t key) {
        auto& v = map_[key];
        if (v.empty() || v.back() != id) v.push_back(id);
      });
      p = q;
    }
  }
  /// Calls f(id) for the segments listed in the buckets that the box [l, h] meets (an id can
  /// come more than once).
  template <class F>
  void visit(Vec3 l, Vec3 h, F&& f) const {
    if (cells(l, h) > (int64_t)map_.size()) {  // a query larger than the listed buckets: all of them
      for (const auto& kv : map_)
        for (int id : kv.second) f(id);
      return;
    }
    forCells(l, h, [&](int64_t key) {
      auto it = map_.find(key);
      if (it != map_.end())
        for (int id : it->second) f(id);
    });
  }
  static Vec3 lo(Vec3 a, Vec3 b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
  static Vec3 hi(Vec3 a, Vec3 b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }

 private:
  double cell_;
  std::unordered_map<int64_t, std::vector<int>> map_;
  int64_t idx(double x) const { return (int64_t)std::floor(x / cell_); }
  int64_t cells(Vec3 l, Vec3 h) const {
    return (idx(h.x) - idx(l.x) + 1) * (idx(h.y) - idx(l.y) + 1) * (idx(h.z) - idx(l.z) + 1);
  }
  template <class F>
  void forCells(Vec3 l, Vec3 h, F&& f) const {
    const int64_t i0 = idx(l.x), i1 = idx(h.x), j0 = idx(l.y), j1 = idx(h.y), k0 = idx(l.z), k1 = idx(h.z);
    for (int64_t i = i0; i <= i1; ++i)
      for (int64_t j = j0; j <= j1; ++j)
        for (int64_t k = k0; k <= k1; ++k)
          f(((i & 0x1FFFFF) << 42) | ((j & 0x1FFFFF) << 21) | (k & 0x1FFFFF));
  }
};

class FaceLayers {
 public:
  FaceLayers(const ISurface& s, const std::vector<std::vector<LoopPoint>>& loops,
             const std::vector<std::vector<Vec2>>& trueLoops, const DomainGuard& guard, const EdgeSpecMap& specOf,
             const std::vector<LayerLaw>& laws, FaceBLResult& out)
      : S_(s), loops_(loops), trueLoops_(trueLoops), guard_(guard), specOf_(specOf), laws_(laws), out_(out) {
    for (const LayerLaw& l : laws) specQuads_.push_back(l.quads);
    out_.stats.assign(laws.size(), FaceBLResult::SpecStats());
    const UVBox b = s.bounds();
    uspan_ = std::max(b.u1 - b.u0, 1e-300);
    vspan_ = std::max(b.v1 - b.v0, 1e-300);
    // buckets about as large as the boundary's segments (the columns' spacing)
    double total = 0;
    int count = 0;
    for (const auto& lp : loops_)
      for (size_t i = 0; i < lp.size(); ++i) {
        total += dist(lp[i].xyz, lp[(i + 1) % lp.size()].xyz);
        ++count;
      }
    const double cell = count ? total / count : 1.0;
    loopBuckets_ = SegmentBuckets(cell);
    otherBuckets_ = SegmentBuckets(cell);
    for (size_t L = 0; L < loops_.size(); ++L)
      for (size_t i = 0; i < loops_[L].size(); ++i) {
        loopSegs_.emplace_back((int)L, (int)i);
        loopBuckets_.add((int)loopSegs_.size() - 1, loops_[L][i].xyz, loops_[L][(i + 1) % loops_[L].size()].xyz);
      }
  }

  void run() {
    for (size_t L = 0; L < loops_.size(); ++L) processLoop((int)L);
  }

 private:
  const ISurface& S_;
  const std::vector<std::vector<LoopPoint>>& loops_;
  const std::vector<std::vector<Vec2>>& trueLoops_;  ///< the guard's loops, index for index with loops_
  const DomainGuard& guard_;
  const EdgeSpecMap& specOf_;
  const std::vector<LayerLaw>& laws_;
  FaceBLResult& out_;
  double uspan_, vspan_;
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

  /// Whether (a, b) (3D chord A B) crosses a column or a row of a run grown before. A column's
  /// steps are tested against the other runs' points by distance (nearOther), which a step can
  /// pass between two columns of another run without coming near either (a V notch's apex fan
  /// ran below the bottom layer's first row); in (u,v), on one face, a crossing is a crossing
  /// whatever the spacing. Segments that cross in (u,v) meet on the surface: their chords lie
  /// within their sags of each other in 3D, well inside a margin of the step's own length.
  bool crossesOther(Vec2 a, Vec2 b, Vec3 A, Vec3 B) const {
    const double m = dist(A, B);
    const Vec3 pad{m, m, m};
    bool hit = false;
    otherBuckets_.visit(SegmentBuckets::lo(A, B) - pad, SegmentBuckets::hi(A, B) + pad, [&](int id) {
      if (!hit && segmentsCross(a, b, otherSegs_[id].a, otherSegs_[id].b)) hit = true;
    });
    return hit;
  }

  /// Only segments within r of x are sure to count: farther ones may or may not (infinity when
  /// none is found).
  double boundaryDistance(Vec3 x, double r, int L, int root, const std::vector<char>& own) const {
    double best = std::numeric_limits<double>::infinity();
    const Vec3 pad{r, r, r};
    loopBuckets_.visit(x - pad, x + pad, [&](int id) {
      const auto [M, i] = loopSegs_[id];
      const auto& lp = loops_[M];
      const int j = (i + 1) % (int)lp.size();
      if (M == L && (i == root || j == root || (own[i] && own[j]))) return;
      best = std::min(best, segmentDistance(x, lp[i].xyz, lp[j].xyz));
    });
    return best;
  }

  /// Whether a boundary point (a loop point other than the run's own in loop L) lies within d of
  /// the row (a, b), farther than d from its ends: a row through a vertex of the boundary touches it without
  /// crossing it, and leaves triangles of zero area beside it (a notch's apex exactly one first
  /// height above a layer: the bottom layer's first row ran through it).
  bool boundaryPointNear(Vec3 a, Vec3 b, double d, int L, const std::vector<char>& own) const {
    const Vec3 e = b - a;
    const double l2 = norm2(e);
    if (!(l2 > 0)) return false;
    const Vec3 pad{d, d, d};
    bool hit = false;
    loopBuckets_.visit(SegmentBuckets::lo(a, b) - pad, SegmentBuckets::hi(a, b) + pad, [&](int id) {
      const auto [M, i] = loopSegs_[id];  // its first point, which lies in the segment's buckets
      if (hit || (M == L && own[i])) return;
      const Vec3& p = loops_[M][i].xyz;
      const double t = dot(p - a, e) / l2;
      if (t <= 0 || t >= 1) return;
      // a point beside an end is that end column's neighbour (an end column marched along a
      // neighbouring edge runs within a hair of that edge's nodes)
      if (dist(p, a + t * e) < d && std::min(dist(p, a), dist(p, b)) > d) hit = true;
    });
    return hit;
  }

  /// A step from p to x that heads into the boundary (closing on it by at least half its length)
  /// and ends within d of it. A column stopped only when it crosses the boundary can end a hair
  /// above it: a V notch's apex fan column ended 0.0011 above the bottom edge (h0 0.03), and the
  /// triangles between them had angles of 0.2 and 179.4 degrees. Columns that run beside the
  /// boundary (the M6's next to its tip edge, rows taller than their distance to it) go on.
  bool closesOnBoundary(Vec3 p, Vec3 x, double d, int L, int root, const std::vector<char>& own) const {
    const double dx = boundaryDistance(x, d, L, root, own);
    if (!(dx < d)) return false;
    // the distance at p is at most dx + |p - x|: a search of that radius finds it
    const double step = dist(p, x);
    return boundaryDistance(p, dx + step, L, root, own) - dx > 0.5 * step;
  }

  /// Whether x lies within d of a column or a row of a run grown before (3D distance to the
  /// segments). The points alone (nearOther) let a column end just below another run's row
  /// between two of its columns, far from both: on a 2-wide curved strip of bearing.iges (Face94)
  /// with layers on both long sides, one run's front ended 0.016 below the other's, and the
  /// triangles between had angles of 0.18 and 179.3 degrees. The distance is a quarter of the
  /// row height (half of it stopped one column at the chamfered corner of
  /// test_layers_meeting_across_a_chamfer_of_exactly_the_first_height, and the rule that stops
  /// columns converging on a stopped neighbour then took the last row off the whole run).
  bool nearOtherGrid(Vec3 x, double d) const {
    const Vec3 pad{d, d, d};
    bool hit = false;
    otherBuckets_.visit(x - pad, x + pad, [&](int id) {
      if (!hit && segmentDistance(x, otherSegs_[id].A, otherSegs_[id].B) < d) hit = true;
    });
    return hit;
  }

  /// Whether a point of a run grown before lies within d of the row (a, b): rows are tested
  /// for crossings, yet a row can pass just below another run's front without crossing it (a
  /// slot's bottom layer ended 0.02 to 0.04 above the base layer's first row, which ran under
  /// the slot between two columns 2 apart: angles of 0.9 and 177.6 degrees).
  bool otherPointNearRow(Vec3 a, Vec3 b, double d) const {
    const Vec3 pad{d, d, d};
    bool hit = false;
    otherBuckets_.visit(SegmentBuckets::lo(a, b) - pad, SegmentBuckets::hi(a, b) + pad, [&](int id) {
      if (!hit && (segmentDistance(otherSegs_[id].A, a, b) < d || segmentDistance(otherSegs_[id].B, a, b) < d))
        hit = true;
    });
    return hit;
  }

  void addOther(const Seg& g) {
    otherSegs_.push_back(g);
    otherBuckets_.add((int)otherSegs_.size() - 1, g.A, g.B);
  }

  /// Records a grown run's grid for the collision tests (crossesOther, nearOtherGrid,
  /// otherPointNearRow): the segments of its marched columns and its rows above the BL edge (end
  /// columns run along the boundary, which crossesLoops guards).
  void recordGrid(const std::vector<Column>& cols, bool closed) {
    const int m = (int)cols.size();
    for (const Column& c : cols)
      if (!c.fixed)
        for (size_t k = 0; k + 1 < c.uv.size(); ++k) addOther({c.uv[k], c.uv[k + 1], c.xyz[k], c.xyz[k + 1]});
    const int pairs = closed ? m : m - 1;
    for (int i = 0; i < pairs; ++i) {
      const Column &A = cols[i], &B = cols[(i + 1) % m];
      const size_t kmax = std::min(A.uv.size(), B.uv.size());
      for (size_t k = 1; k < kmax; ++k) addOther({A.uv[k], B.uv[k], A.xyz[k], B.xyz[k]});
    }
  }

  bool isBL(const LoopPoint& p) const { return p.edge >= 0 && specOf_[p.edge] >= 0; }

  Vec3 normalAt(Vec2 uv) const {
    Vec3 n;
    if (!S_.normal(uv, n)) n = {0, 0, 1};
    return n;
  }

  /// (u,v) step for a 3D tangent step d at uv (first order).
  Vec2 uvStep(Vec2 uv, Vec3 d) const {
    Vec3 p, du, dv;
    S_.d1(uv, p, du, dv);
    const double E = dot(du, du), F = dot(du, dv), G = dot(dv, dv), det = E * G - F * F;
    if (!(det > 1e-300)) return {0, 0};
    const double a = dot(du, d), b = dot(dv, d);
    return {(G * a - F * b) / det, (E * b - F * a) / det};
  }

  /// Point at straight 3D distance h from (uv, x) in direction d, on the surface, in the column's
  /// plane (through x, spanned by d and the surface normal) within 1 % of h.
  bool step(Vec2 uv, Vec3 x, Vec3 d, double h, Vec2& uvOut, Vec3& xOut) const {
    Vec2 q = uv + uvStep(uv, h * d);
    Vec3 target = x + h * d;
    Vec3 p;
    const Vec3 side = normalized(cross(d, normalAt(uv)));  // normal of the column's plane
    auto within = [&](double lenTol, double sideTol) {
      return std::fabs(dist(p, x) - h) <= lenTol * h && std::fabs(dot(p - x, side)) <= sideTol * h;
    };
    // the chord rescaled to h after each projection: enough on smooth faces
    for (int it = 0; it < 4; ++it) {
      if (!S_.project(target, q, &p, 0.0)) return false;
      const double l = dist(p, x);
      if (!(l > 0)) return false;
      if (std::fabs(l - h) <= 1e-7 * h) break;
      target = x + (h / l) * (p - x);
    }
    // Every point of the surface at distance h is a fixed point of that iteration, and where the
    // surface turns away within the step (a step of several radii around a blade's nose: the
    // first projection lands at less than half of h) it converges slowly and slides along the
    // row: columns stopped after four projections as if they had left the face, or leant down to
    // 19 degrees from the edge. There the point is solved for in the column's plane.
    if (!within(1e-7, 1e-2) && !solveInPlane(x, side, h, q, p)) return false;
    uvOut = q;
    xOut = p;
    return within(1e-3, 1e-2) && dot(p - x, d) > 0;
  }

  /// Newton on |S(q) - x| = h and (S(q) - x).side = 0 from q (in/out; p = S(q)), damped, within
  /// the face's parameter bounds. False when the residual stops decreasing above 1e-10 h.
  bool solveInPlane(Vec3 x, Vec3 side, double h, Vec2& q, Vec3& p) const {
    const UVBox b = S_.bounds();
    const bool uFree = S_.uPeriod() > 0, vFree = S_.vPeriod() > 0;
    // both equations as lengths: (|c|^2 - h^2) / 2h is |c| - h to first order
    auto residual = [&](Vec3 c) { return std::hypot((dot(c, c) - h * h) / (2 * h), dot(c, side)); };
    Vec3 du, dv;
    S_.d1(q, p, du, dv);
    double r = residual(p - x);
    for (int it = 0; it < 30 && r > 1e-10 * h; ++it) {
      const Vec3 c = p - x;
      const double f1 = (dot(c, c) - h * h) / (2 * h), f2 = dot(c, side);
      const double a11 = dot(c, du) / h, a12 = dot(c, dv) / h, a21 = dot(du, side), a22 = dot(dv, side);
      const double det = a11 * a22 - a12 * a21;
      if (!(std::fabs(det) > 0)) return false;
      const Vec2 dq{-(a22 * f1 - a12 * f2) / det, -(a11 * f2 - a21 * f1) / det};
      bool better = false;
      for (double t = 1; t > 1e-4 && !better; t *= 0.5) {
        Vec2 qn = q + t * dq;
        if (!uFree) qn.x = std::clamp(qn.x, b.u0, b.u1);
        if (!vFree) qn.y = std::clamp(qn.y, b.v0, b.v1);
        Vec3 pn, dun, dvn;
        S_.d1(qn, pn, dun, dvn);
        const double rn = residual(pn - x);
        if (rn < r) {
          q = qn;
          p = pn;
          du = dun;
          dv = dvn;
          r = rn;
          better = true;
        }
      }
      if (!better) return false;
    }
    return true;
  }

  bool crossesLoops(Vec2 a, Vec2 b, int skipLoop, int skipA, int skipB) const {
    const double x0 = std::min(a.x, b.x), x1 = std::max(a.x, b.x), y0 = std::min(a.y, b.y), y1 = std::max(a.y, b.y);
    for (size_t L = 0; L < loops_.size(); ++L) {
      const auto& lp = loops_[L];
      const int n = (int)lp.size();
      for (int i = 0; i < n; ++i) {
        if ((int)L == skipLoop && (i == skipA || i == skipB)) continue;
        const Vec2 c = lp[i].uv, d = lp[(i + 1) % n].uv;
        if (std::max(c.x, d.x) < x0 || std::min(c.x, d.x) > x1 || std::max(c.y, d.y) < y0 ||
            std::min(c.y, d.y) > y1)
          continue;
        if (segmentsCross(a, b, c, d)) return true;
      }
    }
    return false;
  }

  /// +1 when the face lies to the left of loop L's direction (in (u,v), where the surface normal
  /// S_u x S_v makes left in (u,v) left in 3D) along the segment starting at point i, -1 when it
  /// lies to the right, 0 when the probes disagree or the point is not on the true boundary. The
  /// probes straddle the true boundary (the guard's own polyline) just after the point. A probe
  /// off the segment's chord can land on either side of the boundary: a one-segment arc bulges
  /// far more than any probe's offset (screw.step's Edge12, one 2.5-long arc at a slot's bottom,
  /// got its rows outside its cone face).
  int sideOf(int L, int i) const {
    if (L >= (int)trueLoops_.size()) return 0;
    const auto& F = trueLoops_[L];
    const int m = (int)F.size(), n = (int)loops_[L].size();
    if (m < 3) return 0;
    const Vec2 a = loops_[L][((i % n) + n) % n].uv, b = loops_[L][(((i + 1) % n) + n) % n].uv;
    int k = 0;
    double best = 1e300;
    for (int j = 0; j < m; ++j) {
      const double d = dot(F[j] - a, F[j] - a);
      if (d < best) best = d, k = j;
    }
    const double len = norm(b - a);
    if (!(len > 0) || best > 1e-12 * len * len) return 0;
    int k2 = (k + 1) % m;  // the next distinct point (a collapsed tiny edge repeats one)
    for (int guard = 0; guard < m && F[k2].x == F[k].x && F[k2].y == F[k].y; ++guard) k2 = (k2 + 1) % m;
    const Vec2 p = F[k], q = F[k2];
    const Vec2 d = q - p;
    if (!(norm(d) > 0)) return 0;
    const Vec2 c = 0.5 * (p + q), left{-1e-3 * d.y, 1e-3 * d.x};
    const bool inL = guard_.inside(c + left), inR = guard_.inside(c - left);
    return inL == inR ? 0 : (inL ? 1 : -1);
  }

  void processLoop(int L) {
    const auto& lp = loops_[L];
    const int n = (int)lp.size();
    // segment i = (i, i+1) is BL when its edge is a BL edge
    std::vector<char> bl(n);
    int count = 0;
    for (int i = 0; i < n; ++i) count += bl[i] = isBL(lp[i]) ? 1 : 0;
    if (!count) return;
    // runs of consecutive BL segments
    struct Run {
      int a, nseg;
    };
    std::vector<Run> runs;
    if (count == n) {
      runs.push_back({0, n});
    } else {
      int start = 0;
      while (bl[start] || !bl[(start + 1) % n]) start = (start + 1) % n;  // start: last non-BL before a run
      for (int k = 0, i = (start + 1) % n; k < n; ++k, i = (i + 1) % n) {
        if (bl[i] && !bl[(i + n - 1) % n]) {
          int len = 0;
          while (bl[(i + len) % n] && len < n) ++len;
          runs.push_back({i, len});
        }
      }
    }
    for (const Run& r : runs) growRun(L, r.a, r.nseg, r.nseg == n);
  }

  /// Number of loop points after (dir = +1) or before (dir = -1) index i that form the end column:
  /// consecutive distances equal the row heights.
  int endColumnLength(int L, int i, int dir, const LayerLaw& law) const {
    const auto& lp = loops_[L];
    const int n = (int)lp.size();
    int k = 0;
    int cur = ((i % n) + n) % n;  // a run that wraps past the loop's first point passes i >= n
    while (k < law.layers) {
      const int nxt = ((cur + dir) % n + n) % n;
      if (isBL(dir > 0 ? lp[cur] : lp[nxt])) break;
      // nor onto the root of another run: where a non-BL edge of exactly the first height joins
      // two BL edges, both runs' end columns would climb along it onto each other's root, and
      // their first rows would cross (a chamfered square's corner, chamfer 0.5 = h0: Face1 failed)
      if (isBL(dir > 0 ? lp[nxt] : lp[((nxt - 1) % n + n) % n])) break;
      const double d = dist(lp[cur].xyz, lp[nxt].xyz);
      if (std::fabs(d - law.height(k)) > 1e-3 * law.height(k)) break;
      ++k;
      cur = nxt;
    }
    return k;
  }

  void growRun(int L, int a, int nseg, bool closed) {
    const auto& lp = loops_[L];
    const int n = (int)lp.size();
    auto at = [&](int i) -> const LoopPoint& { return lp[((i % n) + n) % n]; };
    // loop direction sign: +1 when the face lies to the left of the loop (n x t points inside)
    const int mid = a + nseg / 2;
    int side = 0;
    for (int j = 0, step = std::max(1, nseg / 8); j < nseg; j += step) side += sideOf(L, a + j);
    if (side == 0) {
      // no verdict from the true boundary: a probe off the middle segment's chord
      const Vec3 tm = at(mid + 1).xyz - at(mid).xyz;
      const Vec2 uvm = 0.5 * (at(mid).uv + at(mid + 1).uv);
      const Vec3 bm = normalized(cross(normalAt(uvm), tm));
      side = guard_.inside(uvm + uvStep(uvm, 1e-3 * norm(tm) * bm)) ? 1 : -1;
    }
    const double sgn = side > 0 ? 1.0 : -1.0;

    // columns at the run's points (corners may get several)
    std::vector<Column> cols;
    const int npts = closed ? nseg : nseg + 1;
    for (int j = 0; j < npts; ++j) {
      const int i = a + j;
      const LoopPoint& p = at(i);
      const bool first = !closed && j == 0, last = !closed && j == npts - 1;
      const int specIn = at(i - 1).edge >= 0 ? specOf_[at(i - 1).edge] : -1;
      const int specOut = at(i).edge >= 0 ? specOf_[at(i).edge] : -1;
      const int spec = first ? specOut : (last ? specIn : (specOut >= 0 ? specOut : specIn));
      const LayerLaw& law = laws_[spec];
      Column base;
      base.root = ((i % n) + n) % n;
      base.spec = spec;
      base.uv.push_back(p.uv);
      base.xyz.push_back(p.xyz);
      base.ref.push_back(p.node);
      if (first || last) {
        // end column: its points are the neighbouring edge's first nodes
        const int dir = first ? -1 : +1;
        int len = endColumnLength(L, i, dir, law);
        // An end column runs along the neighbouring edge. Where that edge carries on almost in
        // line with the BL edge, the column lies along the BL edge's own line: in a run of one
        // segment (no marched column) the rows between the two end columns cross the face
        // (nist_ctc_01's Edge326 runs tangentially into the arcs of a slot), in a longer run the
        // first quad has a straight corner (bottle.brep's Edge89: corner sine 0). Such an end gets
        // no column along it: within 30 degrees of straight in a run of one segment, within 10 in
        // a longer one (measured: 30 degrees there too cut the column along Edge43 at
        // propeller_and_shaft's blade tip, and the triangles there fell from above 2 to 1.6).
        bool marchEnd = false;
        Vec3 inward{0, 0, 0};  // square to the BL edge, into the face
        if (len > 0) {
          const Vec3 back = at(i - dir).xyz - p.xyz, along = at(i + dir).xyz - p.xyz;
          const double lb = norm(back), la = norm(along);
          const double straight = npts == 2 ? kPi / 6 : kPi / 18;
          // The column must also leave into the face: where the neighbouring edge turns away from
          // the layer's side (a reflex corner of the face), rows along it stand outside the face
          // (screw.step's Edge12, an arc at a slot's bottom whose walls rise away from the cone
          // Face7), and where it leaves almost back along the BL edge (a sliver corner of the
          // face), the first quads get corners of a degree or two (CrankArm's Edge39: 1.6
          // degrees). It must leave at 10 degrees or more; in a run of one segment, whose rows
          // join the two end columns directly, at 30 or more.
          if (lb > 0 && la > 0) {
            const bool inLine = dot(back, along) < -std::cos(straight) * lb * la;
            inward = sgn * normalized(cross(normalAt(p.uv), (-dir / lb) * back));
            const bool known = norm2(inward) > 0;
            if (inLine || (known && dot(along, inward) < (npts == 2 ? 0.5 : kMinEndSine) * la)) len = 0;
            // Such an end gets a column marched square to the BL edge instead, when the
            // neighbouring edge carries on in line (a one-segment edge between tangent arcs got no
            // rows at all) or turns away (a reflex corner): that direction lies inside the face.
            // At a sliver corner it would leave the face at once. (Marching also the ends whose
            // neighbouring edge got no column points, a short one, raised the hand-off jump on the
            // Propeller's blade edges to 1.68, over test_propeller_blade_edges' 1.5: not done.)
            marchEnd = known && (inLine || dot(along, inward) < 0);
          }
        }
        if (marchEnd) {
          Column c = base;
          c.dir = inward;
          cols.push_back(c);
          continue;
        }

        base.fixed = true;
        base.active = false;
        base.stop = len >= law.layers ? 0 : 5;
        for (int k = 1; k <= len; ++k) {
          const LoopPoint& q = at(i + dir * k);
          base.uv.push_back(q.uv);
          base.xyz.push_back(q.xyz);
          base.ref.push_back(q.node);
        }
        cols.push_back(base);
        continue;
      }
      // interior point: tangents of the incoming and outgoing segments
      const Vec3 n0 = normalAt(p.uv);
      const Vec3 tin = normalized(p.xyz - at(i - 1).xyz), tout = normalized(at(i + 1).xyz - p.xyz);
      const Vec3 bin = sgn * normalized(cross(n0, tin)), bout = sgn * normalized(cross(n0, tout));
      const bool vertex = at(i - 1).edge != at(i).edge;
      const double turn = std::atan2(dot(cross(tin, tout), n0) * sgn, dot(tin, tout));  // > 0: face corner < 180
      if (vertex && turn < -kPi / 9) {
        // reflex corner of the face (> 200 degrees): a fan from bin to bout through the outside
        const double ang = -turn;
        const int m = std::max(2, (int)std::ceil(ang / (kPi / 8)));
        for (int f = 0; f <= m; ++f) {
          const double s = (double)f / m;
          // rotate bin towards bout about the normal (the short way round is the fan's way)
          Vec3 d = normalized((1 - s) * bin + s * bout);
          if (norm2((1 - s) * bin + s * bout) < 1e-6) d = normalized(cross(n0, bin) * (sgn > 0 ? -1.0 : 1.0));
          Column c = base;
          c.dir = d;
          cols.push_back(c);
        }
        ++out_.stats[spec].fans;
        continue;
      }
      Column c = base;
      Vec3 d = normalized(bin + bout);
      if (vertex && turn > kPi / 6) {
        // convex corner of the face: one merged column, longer steps keep rows parallel
        const double half = 0.5 * (kPi - turn);
        c.factor = std::min(2.0, 1.0 / std::max(std::sin(half), 0.5));
        ++out_.stats[spec].merges;
      }
      c.dir = d;
      cols.push_back(c);
    }
    // near a run end, columns lean towards the outermost column (which runs along the neighbouring
    // edge, at whatever angle that edge makes): weight 1 at the end, 0 at 1.2 thickness
    if (!closed && cols.size() > 2) {
      double thick = 0;
      for (const auto& c : cols) thick = std::max(thick, laws_[c.spec].offset(laws_[c.spec].layers));
      std::vector<double> s(cols.size(), 0);
      for (size_t i = 1; i < cols.size(); ++i) s[i] = s[i - 1] + dist(cols[i].xyz[0], cols[i - 1].xyz[0]);
      const double total = s.back();
      for (size_t i = 0; i < cols.size(); ++i) {
        if (cols[i].fixed) continue;
        auto w = [&](double d) { return std::max(0.0, 1.0 - d / std::max(1.2 * thick, 1e-300)); };
        if (cols.front().fixed && cols.front().xyz.size() > 1) cols[i].wEnd[0] = w(s[i]);
        if (cols.back().fixed && cols.back().xyz.size() > 1) cols[i].wEnd[1] = w(total - s[i]);
      }
    }
    trimAtApex(L, a, nseg, closed, cols);
    march(L, cols, closed);
    emit(L, a, nseg, closed, cols);
  }

  /// A run whose two end columns run up the sides of a three-sided face to one apex: the last
  /// rows leave a region between the top edge and the apex. Rows are taken off both end columns
  /// until the loop points next to the two tops stand at least 1/1.5 of the last row's height
  /// above the top edge (the layer points stay on the edges, as nodes of the region above), so
  /// that the triangles on the top edge are not much flatter than the row below them.
  void trimAtApex(int L, int a, int nseg, bool closed, std::vector<Column>& cols) const {
    if (closed || cols.size() < 2) return;
    Column &c0 = cols.front(), &c1 = cols.back();
    if (!c0.fixed || !c1.fixed || c0.xyz.size() < 2 || c1.xyz.size() < 2) return;
    const auto& lp = loops_[L];
    const int n = (int)lp.size();
    auto idx = [&](int i) { return ((i % n) + n) % n; };
    // far vertex of the first column's edge (walking back from a) and of the last's (forward)
    const int e0 = lp[idx(a - 1)].edge, e1 = lp[idx(a + nseg)].edge;
    if (e0 < 0 || e1 < 0) return;
    int p = a - 1, q = a + nseg + 1, guard = 0;
    while (lp[idx(p - 1)].edge == e0 && ++guard < n) --p;
    while (lp[idx(q)].edge == e1 && ++guard < 2 * n) ++q;
    if (idx(p) != idx(q)) return;  // more than one edge between the two sides: no apex
    const LayerLaw& law = laws_[c0.spec];
    for (;;) {
      const int k = (int)std::min(c0.xyz.size(), c1.xyz.size()) - 1;  // rows of the run's ends
      if (k < 2) return;
      const Vec3 A = c0.xyz[k], B = c1.xyz[k];
      const double w = dist(A, B);
      if (!(w > 0)) return;
      // the loop points next to the two tops (further up the sides, or the apex) stand over the
      // top edge: the triangles on it take one of them
      const Vec3 X = lp[idx(a - k - 1)].xyz, Y = lp[idx(a + nseg + k + 1)].xyz;
      const double depth = std::min(norm(cross(B - A, X - A)), norm(cross(B - A, Y - A))) / w;
      if (depth * 1.5 >= law.height(k - 1)) return;
      for (Column* c : {&c0, &c1}) {
        while ((int)c->xyz.size() > k) {
          c->uv.pop_back();
          c->xyz.pop_back();
          c->ref.pop_back();
        }
        c->stop = 5;
      }
    }
  }

  /// The run's own points in loop L: its roots and its end columns' points (loop points too).
  std::vector<char> ownPoints(int L, const std::vector<Column>& cols) const {
    std::vector<char> own(loops_[L].size(), 0);
    std::vector<int> nodes;
    for (const Column& c : cols) {
      if (c.root >= 0 && c.root < (int)own.size()) own[c.root] = 1;
      if (c.fixed)
        for (int r : c.ref)
          if (r >= 0) nodes.push_back(r);
    }
    std::sort(nodes.begin(), nodes.end());
    for (size_t i = 0; i < own.size(); ++i)
      if (loops_[L][i].node >= 0 && std::binary_search(nodes.begin(), nodes.end(), loops_[L][i].node)) own[i] = 1;
    return own;
  }

  void march(int L, std::vector<Column>& cols, bool closed) {
    const int m = (int)cols.size();
    const std::vector<char> own = ownPoints(L, cols);
    int maxLayers = 0;
    for (auto& c : cols) maxLayers = std::max(maxLayers, laws_[c.spec].layers);
    for (int k = 0; k < maxLayers; ++k) {
      // 1) advance every active column by its row height
      std::vector<char> moved(m, 0);
      for (int i = 0; i < m; ++i) {
        Column& c = cols[i];
        if (!c.active) continue;
        const LayerLaw& law = laws_[c.spec];
        if (k >= law.layers) {
          c.active = false;
          c.stop = 0;
          continue;
        }
        const double h = law.height(k) * c.factor;
        {
          // hand-off where the row would become much taller than wide (columns converging at a
          // skewed end): the user's aspect limit, and in any case at height > 1.5 x spacing
          const double spacing = rowSpacing(cols, i, closed);
          const double limit = law.maxAspect > 0 ? law.maxAspect : 1.0 / 1.5;
          if (spacing > 0 && spacing / law.height(k) < limit) {
            c.active = false;
            c.stop = 4;
            continue;
          }
        }
        Vec2 uv;
        Vec3 x;
        const bool okStep = step(c.uv.back(), c.xyz.back(), marchDirection(cols, i, k), h, uv, x);
        const bool okIn = okStep && guard_.inside(uv);
        const bool okCross = okIn && !crossesLoops(c.uv.back(), uv, L, k == 0 ? c.root : -1, k == 0 ? ((c.root - 1 + (int)loops_[L].size()) % (int)loops_[L].size()) : -1);
        if (!okCross || closesOnBoundary(c.xyz.back(), x, 0.5 * law.height(k), L, c.root, own)) {
          c.active = false;
          c.stop = 1;
          continue;
        }
        if (nearOther(x, 0.5 * law.height(k)) || crossesOther(c.uv.back(), uv, c.xyz.back(), x) ||
            nearOtherGrid(x, 0.25 * law.height(k))) {
          c.active = false;
          c.stop = 2;
          continue;
        }
        c.uv.push_back(uv);
        c.xyz.push_back(x);
        c.ref.push_back(0);
        moved[i] = 1;
      }
      // 1b) columns converging on a stopped neighbour (a concave corner) stop with it: a new point
      //     closer to a stopped top than the row height would fold the front over it
      for (bool again = true; again;) {
        again = false;
        for (int i = 0; i < m; ++i) {
          Column& c = cols[i];
          if (!moved[i]) continue;
          const double h = laws_[c.spec].height(k);
          for (int j : {i - 1, i + 1}) {
            if (!closed && (j < 0 || j >= m)) continue;
            const Column& o = cols[(j + m) % m];
            if (o.active || o.fixed || o.root == c.root || (int)o.xyz.size() > k + 1) continue;  // o stopped below
            if (dist(c.xyz.back(), o.xyz.back()) < 1.5 * h) {
              c.uv.pop_back();
              c.xyz.pop_back();
              c.ref.pop_back();
              c.active = false;
              c.stop = 2;
              moved[i] = 0;
              again = true;
              break;
            }
          }
        }
      }
      // 2) the new quads must be valid: positive in (u,v), facing like the surface
      bool changed = true;
      while (changed) {
        changed = false;
        for (int i = 0; i + 1 < m || (closed && i < m); ++i) {
          const int j = (i + 1) % m;
          Column &A = cols[i], &B = cols[j];
          if ((int)A.uv.size() < k + 2 || (int)B.uv.size() < k + 2) continue;
          if (!(moved[i] || moved[j])) continue;
          if (A.root == B.root && k == 0) continue;  // fan triangle at a shared root
          // the row between two marched columns must not cross the face's boundary either: each
          // column stays inside, yet a corner of a hole (propeller_and_shaft's blade roots on the
          // hub Face5, 2.7 from the BL circle) can poke between two of them. An end column's
          // points lie on the boundary: its rows touch it there, which is no crossing (only a
          // proper crossing or a collinear overlap counts)
          const bool crossing = crossesLoops(A.uv[k + 1], B.uv[k + 1], -1, -1, -1) ||
                                boundaryPointNear(A.xyz[k + 1], B.xyz[k + 1], 0.25 * laws_[A.spec].height(k), L, own);
          const bool collision = !crossing && (crossesOther(A.uv[k + 1], B.uv[k + 1], A.xyz[k + 1], B.xyz[k + 1]) ||
                                               otherPointNearRow(A.xyz[k + 1], B.xyz[k + 1], 0.25 * laws_[A.spec].height(k)));
          if (!crossing && !collision &&
              quadValid(A.uv[k], B.uv[k], B.uv[k + 1], A.uv[k + 1], A.xyz[k], B.xyz[k], B.xyz[k + 1], A.xyz[k + 1]))
            continue;
          for (Column* c : {&A, &B}) {
            if (c->fixed || (int)c->uv.size() < k + 2) continue;
            c->uv.pop_back();
            c->xyz.pop_back();
            c->ref.pop_back();
            c->active = false;
            c->stop = crossing ? 1 : collision ? 2 : 3;
            changed = true;
          }
        }
      }
      // 2b) a column whose neighbours both stopped below it would stand alone: it stops with them
      trimNeedles(cols, closed);
      // 3) new directions from the new row: b = n x (row tangent), same side as before
      for (int i = 0; i < m; ++i) {
        Column& c = cols[i];
        if (!c.active || (int)c.uv.size() < k + 2) continue;
        const int ip = closed ? (i + m - 1) % m : std::max(i - 1, 0);
        const int in = closed ? (i + 1) % m : std::min(i + 1, m - 1);
        const Vec3 pPrev = pointAt(cols[ip], k + 1), pNext = pointAt(cols[in], k + 1);
        Vec3 t = pNext - pPrev;
        if (norm2(t) < 1e-300) continue;
        const Vec3 nn = normalAt(c.uv.back());
        Vec3 d = normalized(cross(nn, t));
        if (dot(d, c.dir) < 0) d = -d;
        // keep fan columns and corner columns pointing their own way: blend with the old direction
        if (ip == i || in == i || samePosition(cols[ip], cols[i], 0) || samePosition(cols[in], cols[i], 0))
          d = normalized(d + c.dir);
        // near the run ends the rows are skewed by the outermost columns: there the column keeps
        // its own direction (transported into the new tangent plane) instead of the row normal
        const double w = std::max(c.wEnd[0], c.wEnd[1]);
        const Vec3 transported = normalized(c.dir - dot(c.dir, nn) * nn);
        d = normalized((1 - w) * d + w * transported);
        c.dir = normalized(d - dot(d, nn) * nn);
      }
    }
    for (auto& c : cols)
      if (c.active) {
        c.active = false;
        c.stop = 0;
      }
    for (auto& c : cols)
      for (size_t k = 1; k < c.xyz.size(); ++k) {
        otherPts_.push_back(c.xyz[k]);
        otherH_.push_back(laws_[c.spec].height((int)k - 1));
      }
  }

  /// Direction a column has at layer k: marched columns their marching direction, end columns the
  /// direction of their next segment along the edge (or their last one).
  static Vec3 directionOf(const Column& c, int k) {
    if (!c.fixed) return c.dir;
    const size_t n = c.xyz.size();
    if (n < 2) return {0, 0, 0};
    const size_t a = std::min<size_t>(k, n - 2);
    return normalized(c.xyz[a + 1] - c.xyz[a]);
  }

  /// The direction of column i for layer k: its row-orthogonal direction, leaning towards the
  /// outermost columns near the run ends; the lean grows over the first layers, so the first
  /// segment stays orthogonal to the edge.
  Vec3 marchDirection(const std::vector<Column>& cols, int i, int k) const {
    const Column& c = cols[i];
    if (c.wEnd[0] == 0 && c.wEnd[1] == 0) return c.dir;
    const double ramp = std::min(1.0, k / 3.0);
    Vec3 d = c.dir;
    if (c.wEnd[0] > 0) d += (ramp * c.wEnd[0]) * (directionOf(cols.front(), k) - c.dir);
    if (c.wEnd[1] > 0) d += (ramp * c.wEnd[1]) * (directionOf(cols.back(), k) - c.dir);
    const Vec3 nn = normalAt(c.uv.back());
    d = d - dot(d, nn) * nn;
    return norm2(d) > 1e-20 ? normalized(d) : c.dir;
  }

  void smoothDirections(std::vector<Column>& cols, int k, bool closed) const {
    const int m = (int)cols.size();
    for (int it = 0; it < 3; ++it) {
      std::vector<Vec3> nd(m);
      for (int i = 0; i < m; ++i) {
        Column& c = cols[i];
        nd[i] = c.dir;
        if (!c.active || c.fixed) continue;
        Vec3 sum{0, 0, 0};
        int cnt = 0;
        for (int j : {i - 1, i + 1}) {
          if (!closed && (j < 0 || j >= m)) continue;
          const Column& o = cols[(j + m) % m];
          if (o.root == c.root) continue;  // fan siblings keep their spread
          const Vec3 d = directionOf(o, k);
          if (norm2(d) == 0) continue;
          sum += d;
          ++cnt;
        }
        if (!cnt) continue;
        const Vec3 nn = normalAt(c.uv.back());
        Vec3 d = c.dir + (0.5 / cnt) * (sum - (double)cnt * c.dir);
        d = d - dot(d, nn) * nn;
        if (norm2(d) > 1e-20) nd[i] = normalized(d);
      }
      for (int i = 0; i < m; ++i) cols[i].dir = nd[i];
    }
  }

  static bool samePosition(const Column& a, const Column& b, int k) {
    return a.root == b.root && k == 0;
  }

  /// A column's point at layer k, or its top when it stopped lower.
  static Vec3 pointAt(const Column& c, int k) { return c.xyz[std::min<size_t>(k, c.xyz.size() - 1)]; }

  /// Mean distance from column i's current top to its neighbours' points on the same row (fan
  /// siblings at their shared root do not count).
  double rowSpacing(const std::vector<Column>& cols, int i, bool closed) const {
    const int m = (int)cols.size();
    const Column& c = cols[i];
    const size_t k = c.xyz.size() - 1;
    double s = 0;
    int n = 0;
    for (int j : {i - 1, i + 1}) {
      if (!closed && (j < 0 || j >= m)) continue;
      const Column& o = cols[(j + m) % m];
      if (o.root == c.root) continue;  // fan siblings spread with the distance from their root
      const double d = dist(o.xyz[std::min(o.xyz.size() - 1, k)], c.xyz[k]);
      if (d <= 0) continue;
      s += d;
      ++n;
    }
    return n ? s / n : 0;
  }

  bool nearOther(Vec3 x, double d) const {
    for (size_t i = 0; i < otherPts_.size(); ++i)
      if (dist(otherPts_[i], x) < std::max(d, 0.5 * otherH_[i])) return true;
    return false;
  }

  bool quadValid(Vec2 a, Vec2 b, Vec2 c, Vec2 d, Vec3 A, Vec3 B, Vec3 C, Vec3 D) const {
    // both triangulations of the quad positive in (u,v) in the loop's orientation sense
    const int o1 = orient2d(a, b, c), o2 = orient2d(a, c, d), o3 = orient2d(a, b, d), o4 = orient2d(b, c, d);
    const bool pos = o1 > 0 && o2 > 0 && o3 > 0 && o4 > 0;
    const bool neg = o1 < 0 && o2 < 0 && o3 < 0 && o4 < 0;
    if (!pos && !neg) return false;
    // not folded in 3D: the two halves face the same way
    const Vec3 n1 = cross(B - A, C - A), n2 = cross(C - A, D - A);
    if (!(dot(n1, n2) > 0)) return false;
    // and convex in 3D: every corner turns the same way about the quad's normal (a quad convex in
    // (u,v) can have a reflex corner in 3D where the parametrisation is skewed: the ONERA M6's
    // Edge15, at its end column along the tip)
    const Vec3 nq = n1 + n2;
    const Vec3 P[4] = {A, B, C, D};
    for (int i = 0; i < 4; ++i) {
      const Vec3 &p0 = P[(i + 3) % 4], &p1 = P[i], &p2 = P[(i + 1) % 4];
      if (!(dot(cross(p1 - p0, p2 - p1), nq) > 0)) return false;
    }
    return true;
  }

  int newNode(Vec2 uv, Vec3 x) {
    out_.nodes.push_back({uv, x});
    return -(int)out_.nodes.size();
  }

  /// The front polyline (column tops, stairs between different heights) as (column, layer) pairs.
  static std::vector<std::pair<int, int>> frontPath(const std::vector<Column>& cols, bool closed) {
    std::vector<std::pair<int, int>> path;
    const int m = (int)cols.size();
    // a marched end column of an open run: the front runs up it from its root (and down the last)
    if (!closed && m > 0 && !cols[0].fixed)
      for (int k = 0; k + 1 < (int)cols[0].xyz.size(); ++k) path.emplace_back(0, k);
    for (int i = 0; i < m; ++i) {
      const int ka = (int)cols[i].xyz.size() - 1;
      path.emplace_back(i, ka);
      if (!closed && i == m - 1) {
        if (!cols[i].fixed)
          for (int k = ka - 1; k >= 0; --k) path.emplace_back(i, k);
        break;
      }
      const int j = (i + 1) % m;
      const int kb = (int)cols[j].xyz.size() - 1;
      for (int k = ka - 1; k >= kb; --k) path.emplace_back(i, k);
      for (int k = std::min(ka, kb); k < kb; ++k) path.emplace_back(j, k);
    }
    return path;
  }

  /// Safety net: while the front crosses itself (columns converging in a concave corner) or the
  /// face's boundary (a stair between columns of different heights past a hole's corner: a
  /// nist_ctc_01 slot), the tallest marched column involved loses its top layer.
  void untangle(std::vector<Column>& cols, bool closed) {
    for (int guard = 0; guard < 2000; ++guard) {
      const auto path = frontPath(cols, closed);
      const int n = (int)path.size();
      auto uvOf = [&](int q) { return cols[path[q].first].uv[path[q].second]; };
      // the tallest column with at least one row among the path points qs, end columns
      // (fixed) or marched ones (-1: none)
      auto tallest = [&](std::initializer_list<int> qs, bool fixed) {
        int best = -1;
        for (int q : qs) {
          const Column& c = cols[path[q].first];
          if (c.fixed != fixed || c.xyz.size() < 2) continue;
          if (best < 0 || c.xyz.size() > cols[best].xyz.size()) best = path[q].first;
        }
        return best;
      };
      // a segment between two roots runs along the BL edge, one down an end column along its
      // neighbouring edge: both lie on the boundary, which is no crossing
      int bad = -1, stop = 1;
      for (int i = 0; i + 1 < n && bad < 0; ++i) {
        if (path[i].second == 0 && path[i + 1].second == 0) continue;
        if (path[i].first == path[i + 1].first && cols[path[i].first].fixed) continue;
        // crossing the loops' chords, or standing outside the true boundary (a row between two
        // end columns can leave the face without crossing a chord where the boundary between
        // them is one segment of a curved edge)
        if (!crossesLoops(uvOf(i), uvOf(i + 1), -1, -1, -1) && guard_.inside(0.5 * (uvOf(i) + uvOf(i + 1))))
          continue;
        // the taller marched column of the two; else the taller end column (a BL edge of one
        // segment has only its two end columns: a nist_ctc_01 slot, whose rows at 5 above the
        // edge ran across a hole): its top stays a plain point of the neighbouring edge
        int best = tallest({i, i + 1}, false);
        if (best < 0) best = tallest({i, i + 1}, true);
        bad = best >= 0 ? best : -2;
      }
      if (bad < 0) {
        bad = -1;
        stop = 2;
        for (int i = 0; i + 1 < n && bad < 0; ++i)
          for (int j = i + 2; j + 1 < n; ++j) {
            if (segmentsCross(uvOf(i), uvOf(i + 1), uvOf(j), uvOf(j + 1))) {
              // the marched column among the four points with the most layers
              const int best = tallest({i, i + 1, j, j + 1}, false);
              bad = best >= 0 ? best : -2;
              break;
            }
          }
      }
      if (bad < 0) return;  // no crossing, or only fixed columns involved: nothing to trim
      Column& c = cols[bad];
      c.uv.pop_back();
      c.xyz.pop_back();
      c.ref.pop_back();
      c.stop = stop;
    }
  }

  /// A marched column standing above both its neighbours (above its one neighbour at the end of
  /// an open run) has no element beside its upper rows:
  /// the front would run up one side of it and back down the other through the same nodes, a slit
  /// the face mesher refuses ("two boundary points coincide"). Such a column is cut down to its
  /// taller neighbour and stops for that neighbour's reason (a collision when the neighbour simply
  /// has fewer rows by its own law).
  static void trimNeedles(std::vector<Column>& cols, bool closed) {
    const int m = (int)cols.size();
    if (m < (closed ? 3 : 2)) return;
    for (bool again = true; again;) {
      again = false;
      for (int i = 0; i < m; ++i) {
        // the end of an open run has one neighbour (a marched end column; a fixed one lies on
        // the boundary, beside its neighbouring edge)
        const bool end0 = !closed && i == 0, end1 = !closed && i == m - 1;
        Column& c = cols[i];
        const Column &a = cols[end0 ? 1 : (i + m - 1) % m], &b = cols[end1 ? m - 2 : (i + 1) % m];
        const Column& taller = a.xyz.size() >= b.xyz.size() ? a : b;
        if (c.fixed || c.xyz.size() <= taller.xyz.size()) continue;
        while (c.xyz.size() > taller.xyz.size()) {
          c.uv.pop_back();
          c.xyz.pop_back();
          c.ref.pop_back();
        }
        c.active = false;
        c.stop = taller.stop > 0 ? taller.stop : 2;
        again = true;
      }
    }
  }

  void emit(int L, int a, int nseg, bool closed, std::vector<Column>& cols) {
    const auto& lp = loops_[L];
    const int n = (int)lp.size();
    const int m = (int)cols.size();
    untangle(cols, closed);
    trimNeedles(cols, closed);  // untangling may have cut a neighbour down
    recordGrid(cols, closed);
    // node refs for marched points
    for (auto& c : cols)
      for (size_t k = 1; k < c.xyz.size(); ++k)
        if (!c.fixed) c.ref[k] = newNode(c.uv[k], c.xyz[k]);
    // statistics
    for (auto& c : cols) {
      auto& st = out_.stats[c.spec];
      const int layers = (int)c.xyz.size() - 1;
      ++st.columns;
      st.minLayers = std::min(st.minLayers, layers);
      st.maxLayers = std::max(st.maxLayers, layers);
      if (layers >= laws_[c.spec].layers) ++st.fullColumns;
      switch (c.stop) {
        case 1: ++st.stopBoundary; break;
        case 2: ++st.stopCollision; break;
        case 3: ++st.stopInvalid; break;
        case 4: ++st.stopAspect; break;
        case 5: ++st.stopEnd; break;
        default: break;
      }
    }
    // elements between consecutive columns
    const int pairs = closed ? m : m - 1;
    for (int i = 0; i < pairs; ++i) {
      const Column &A = cols[i], &B = cols[(i + 1) % m];
      const int kmax = (int)std::min(A.xyz.size(), B.xyz.size()) - 1;
      for (int k = 0; k < kmax; ++k) {
        if (A.root == B.root && k == 0) {
          // fan: triangle root, B1, A1 (orientation fixed below)
          addTri(A.spec, A.ref[0], A.uv[0], B.ref[1], B.uv[1], A.ref[1], A.uv[1]);
          continue;
        }
        addQuad(A.spec, {A.ref[k], B.ref[k], B.ref[k + 1], A.ref[k + 1]}, {A.uv[k], B.uv[k], B.uv[k + 1], A.uv[k + 1]},
                {A.xyz[k], B.xyz[k], B.xyz[k + 1], A.xyz[k + 1]});
      }
    }
    // the front: tops of the columns with stairs between different heights
    std::vector<LoopPoint> front;
    std::vector<double> layerH;  // height of the row below each front point
    auto push = [&](const Column& c, int k) {
      LoopPoint p;
      p.uv = c.uv[k];
      p.xyz = c.xyz[k];
      p.node = c.ref[k];
      p.edge = -1;
      if (!front.empty() && front.back().node == p.node) return;
      front.push_back(p);
      layerH.push_back(k > 0 ? laws_[c.spec].height(k - 1) : 0.0);
    };
    if (!closed && !cols.front().fixed)  // a marched end column: up from its root
      for (int k = 0; k + 1 < (int)cols.front().xyz.size(); ++k) push(cols.front(), k);
    for (int i = 0; i < m; ++i) {
      const Column& A = cols[i];
      const int ka = (int)A.xyz.size() - 1;
      push(A, ka);
      if (!closed && i == m - 1) {
        if (!A.fixed)
          for (int k = ka - 1; k >= 0; --k) push(A, k);
        break;
      }
      const Column& B = cols[(i + 1) % m];
      const int kb = (int)B.xyz.size() - 1;
      for (int k = ka - 1; k >= kb; --k) push(A, k);   // down column A
      for (int k = std::min(ka, kb); k < kb; ++k) push(B, k);  // up column B
    }
    if (closed && front.size() > 1 && front.front().node == front.back().node) front.pop_back();
    // hand-off sizes: the triangles on the front are about as tall as the last row (so that the
    // size does not jump), within [0.7, 1.5] of the front spacing (so that they stay well shaped)
    for (size_t i = 0; i < front.size(); ++i) {
      const double l0 = i > 0 ? dist(front[i].xyz, front[i - 1].xyz) : 0;
      const double l1 = i + 1 < front.size() ? dist(front[i].xyz, front[i + 1].xyz) : 0;
      const double seg = (l0 > 0 && l1 > 0) ? 0.5 * (l0 + l1) : std::max(l0, l1);
      const double h = layerH[i] > 0 ? std::min(std::max(1.15 * layerH[i], 0.7 * seg), 1.5 * seg) : seg;
      if (h > 0) out_.frontSizes.emplace_back(front[i].xyz, h);
    }
    // replace the run (with its end columns) by the front in this loop
    Replace rp;
    rp.loop = L;
    if (closed) {
      rp.from = 0;
      rp.to = n - 1;
      rp.whole = true;
    } else {
      // the points of fixed end columns are loop points (the neighbouring edges' first nodes)
      const int lenA = cols.front().fixed ? (int)cols.front().xyz.size() - 1 : 0;
      const int lenB = cols.back().fixed ? (int)cols.back().xyz.size() - 1 : 0;
      rp.from = ((a - lenA) % n + n) % n;
      rp.to = ((a + nseg + lenB) % n + n) % n;
    }
    rp.front = std::move(front);
    replaces_.push_back(std::move(rp));
  }

  void addQuad(int spec, std::array<int, 4> q, std::array<Vec2, 4> u, std::array<Vec3, 4> x) {
    if (area2(u[0], u[1], u[2]) + area2(u[0], u[2], u[3]) < 0) {
      std::swap(q[1], q[3]);
      std::swap(u[1], u[3]);
      std::swap(x[1], x[3]);
    }
    if (!specQuads_[spec]) {
      // two triangles along the shorter diagonal
      if (dist(x[0], x[2]) <= dist(x[1], x[3])) {
        addTri(spec, q[0], u[0], q[1], u[1], q[2], u[2]);
        addTri(spec, q[0], u[0], q[2], u[2], q[3], u[3]);
      } else {
        addTri(spec, q[1], u[1], q[2], u[2], q[3], u[3]);
        addTri(spec, q[1], u[1], q[3], u[3], q[0], u[0]);
      }
      return;
    }
    out_.quads.push_back(q);
    out_.quadUv.push_back(u);
    out_.quadSpec.push_back(spec);
    ++out_.stats[spec].elements;
  }
  void addTri(int spec, int r0, Vec2 u0, int r1, Vec2 u1, int r2, Vec2 u2) {
    std::array<int, 3> t{r0, r1, r2};
    std::array<Vec2, 3> u{u0, u1, u2};
    if (area2(u0, u1, u2) < 0) {
      std::swap(t[1], t[2]);
      std::swap(u[1], u[2]);
    }
    out_.tris.push_back(t);
    out_.triUv.push_back(u);
    out_.triSpec.push_back(spec);
    ++out_.stats[spec].elements;
  }

 public:
  struct Replace {
    int loop = 0, from = 0, to = 0;
    bool whole = false;
    std::vector<LoopPoint> front;
  };
  std::vector<Replace> replaces_;

  /// The face loops with every grown run replaced by its front.
  void buildLoops() {
    out_.loops.clear();
    for (size_t L = 0; L < loops_.size(); ++L) {
      const auto& lp = loops_[L];
      const int n = (int)lp.size();
      std::vector<int> owner(n, -1);
      std::vector<const Replace*> mine;
      for (const Replace& r : replaces_)
        if (r.loop == (int)L) mine.push_back(&r);
      if (mine.empty()) {
        out_.loops.push_back(lp);
        continue;
      }
      bool whole = false;
      for (const Replace* r : mine) {
        if (r->whole) {
          whole = true;
          out_.loops.push_back(r->front);
          continue;
        }
        for (int i = r->from;; i = (i + 1) % n) {
          owner[i] = (int)(r - replaces_.data());
          if (i == r->to) break;
        }
      }
      if (whole) continue;
      // start at a point outside every run
      int s0 = -1;
      for (int i = 0; i < n; ++i)
        if (owner[i] < 0) {
          s0 = i;
          break;
        }
      std::vector<LoopPoint> loop;
      if (s0 < 0) {
        // runs cover the whole loop: concatenate fronts in order
        int i = mine.front()->from;
        for (int k = 0; k < n; ++k, i = (i + 1) % n) {
          const Replace& r = replaces_[owner[i]];
          if (i == r.from)
            for (const LoopPoint& q : r.front) loop.push_back(q);
        }
      } else {
        for (int k = 0, i = s0; k < n; ++k, i = (i + 1) % n) {
          if (owner[i] < 0) {
            loop.push_back(lp[i]);
            continue;
          }
          const Replace& r = replaces_[owner[i]];
          if (i == r.from)
            for (const LoopPoint& q : r.front) loop.push_back(q);
        }
      }
      // adjacent runs share their end points: drop repeated nodes
      std::vector<LoopPoint> clean;
      for (const LoopPoint& q : loop)
        if (clean.empty() || clean.back().node != q.node) clean.push_back(q);
      while (clean.size() > 1 && clean.front().node == clean.back().node) clean.pop_back();
      out_.loops.push_back(std::move(clean));
    }
  }
};

}  // namespace

FaceBLResult growFaceLayers(const ISurface& s, bool, const std::vector<std::vector<LoopPoint>>& loops,
                            const std::vector<std::vector<Vec2>>& trueLoops, const DomainGuard& guard,
                            const EdgeSpecMap& specOf, const std::vector<LayerLaw>& laws,
                            const std::vector<EdgeBLPoints>&) {
  FaceBLResult out;
  FaceLayers fl(s, loops, trueLoops, guard, specOf, laws, out);
  fl.run();
  fl.buildLoops();
  return out;
}

}  // namespace paramesh
