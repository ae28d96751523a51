// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/algo/FaceMesher.hpp"

#include "paramesh/util/SpatialGrid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <unordered_map>

#include "paramesh/algo/Crest.hpp"
#include "paramesh/algo/optimizer/FaceSchedule.hpp"
#include "paramesh/algo/optimizer/Optimizer.hpp"
#include "paramesh/algo/Predicates.hpp"
#include "paramesh/algo/Recombine.hpp"
#include "paramesh/algo/SurfaceContext.hpp"
#include "paramesh/algo/Triangulation.hpp"
#include "paramesh/size/Sources.hpp"
#include "paramesh/util/Error.hpp"

namespace paramesh {
namespace {

// frontal points: the distance from the front edge is taken at this blend of the front's size
// (the triangle's vertices) and the size field at the predicted point (graded zones: the front is
// the smaller side, so points sized by it alone come out too near)
constexpr double kPointSizeBlend = 0.5;
inline int nx(int i) { return i == 2 ? 0 : i + 1; }
inline int pv(int i) { return i == 0 ? 2 : i - 1; }

/// Cholesky factor of the metric (a,b,c): x' = (ra x + rb y, rc y).
struct Chol {
  double ra = 1, rb = 0, rc = 1;
  bool ok = false;
  explicit Chol(const double* M) {
    if (M[0] > 0) {
      ra = std::sqrt(M[0]);
      rb = M[1] / ra;
      const double r = M[2] - rb * rb;
      if (r > 0) {
        rc = std::sqrt(r);
        ok = true;
      }
    }
  }
  Vec2 fwd(Vec2 w) const { return {ra * w.x + rb * w.y, rc * w.y}; }
  Vec2 inv(Vec2 w) const {
    const double y = w.y / rc;
    return {(w.x - rb * y) / ra, y};
  }
};

/// Frontal-Delaunay refinement (Rebay-style front of accepted triangles, points placed in 3D).
class Frontal {
 public:
  Frontal(Triangulation& T, const SurfaceContext& C, const FaceMeshOptions& o, const Progress* p)
      : T_(T), C_(C), opt_(o), progress_(p) {}

  int rejected = 0;
  long insertedPoints = 0;  ///< points inserted (spent against the progress's point budget)

  void run() {
    grow();
    for (int t = 0; t < (int)T_.tris.size(); ++t) update(t);
    for (int t = 0; t < (int)T_.tris.size(); ++t) pushIfActive(t);
    long inserted = 0, attempts = 0, spent = 0;
    const Triangulation::FlipTest test = [this](int t, int i) { return T_.metricFlip(t, i); };
    std::vector<int> touched;
    while (!heap_.empty()) {
      const Entry e = heap_.top();
      heap_.pop();
      const int t = e.t;
      if (queued_[t] == e.stamp + 1) queued_[t] = 0;
      if (T_.tris[t].dead || stamp_[t] != e.stamp || good_[t]) continue;
      int edge = -1;
      if (!active(t, &edge)) continue;
      // polled per attempt, not per insertion: on a damaged face most attempts can be rejected
      if ((++attempts & 1023) == 0 && progress_) {
        progress_->poll();
        progress_->spend(inserted - spent);
        spent = inserted;
      }
      if (inserted > opt_.maxPoints) break;
      Vec2 s;
      Vec3 p;
      if (!newPoint(t, edge, s, p)) {
        forceGood(t);
        continue;
      }
      int onEdge = -1;
      int where = T_.locate(s, t, &onEdge, Triangulation::kLocalWalk);
      if (where < 0 || (onEdge >= 0 && T_.isConstrained(where, onEdge)) || !T_.insertionIsValid(s, where, onEdge) ||
          tooClose(where, p)) {
        ++rejected;
        forceGood(t);
        continue;
      }
      TriVertex v;
      v.uv = s;
      v.xyz = p;
      C_.fill(v);
      const int vid = T_.addVertex(v);
      const Triangle before = T_.tris[t];
      touched.clear();
      T_.insert(vid, where, onEdge, test, &touched);
      ++inserted;
      grow();
      // the processed triangle, if it survived unchanged, is closed
      if (!T_.tris[t].dead && T_.tris[t].v[0] == before.v[0] && T_.tris[t].v[1] == before.v[1] &&
          T_.tris[t].v[2] == before.v[2])
        forceGood(t);
      for (int u : touched) update(u);
      for (int u : touched) {
        if (T_.tris[u].dead) continue;
        pushIfActive(u);
        for (int k = 0; k < 3; ++k)
          if (T_.tris[u].n[k] >= 0) pushIfActive(T_.tris[u].n[k]);
      }
    }
    if (progress_) progress_->spend(inserted - spent);  // the rest (small faces never reach 1024)
    insertedPoints = inserted;
  }

 private:
  struct Entry {
    double rho;
    int t;
    uint32_t stamp;
    // the largest radius first; equal radii (congruent triangles of a structured start, or
    // inverted ones at 1e300) by triangle index, not by wherever the heap happened to hold them
    bool operator<(const Entry& o) const { return rho < o.rho || (rho == o.rho && t > o.t); }
  };

  void grow() {
    const size_t n = T_.tris.size();
    if (rho_.size() < n) {
      rho_.resize(n, 1e300);
      good_.resize(n, 0);
      stamp_.resize(n, 0);
      queued_.resize(n, 0);
    }
  }

  /// Circumradius of t in its mean metric (unit = target size); +inf when inverted.
  double radius(int t) const {
    const Triangle& tr = T_.tris[t];
    const TriVertex &a = T_.verts[tr.v[0]], &b = T_.verts[tr.v[1]], &c = T_.verts[tr.v[2]];
    double M[3];
    for (int k = 0; k < 3; ++k) M[k] = (a.M[k] + b.M[k] + c.M[k]) / 3.0;
    Chol L(M);
    if (!L.ok) return 1e300;
    const Vec2 B = L.fwd(b.uv - a.uv), Cc = L.fwd(c.uv - a.uv);
    const double ar = cross(B, Cc);
    if (!(ar > 0)) return 1e300;
    const double la = norm(B - Cc), lb = norm(Cc), lc = norm(B);
    return la * lb * lc / (2.0 * ar);
  }

  void update(int t) {
    if (T_.tris[t].dead) return;
    ++stamp_[t];
    rho_[t] = radius(t);
    good_[t] = rho_[t] < opt_.acceptRadius ? 1 : 0;
  }

  void forceGood(int t) {
    ++stamp_[t];
    good_[t] = 1;
    for (int k = 0; k < 3; ++k)
      if (T_.tris[t].n[k] >= 0) pushIfActive(T_.tris[t].n[k]);
  }

  bool active(int t, int* edge) const {
    if (good_[t]) return false;
    const Triangle& tr = T_.tris[t];
    int best = -1;
    double bestLen = -1;
    for (int i = 0; i < 3; ++i) {
      const int u = tr.n[i];
      if (u < 0 || T_.isConstrained(t, i) || good_[u]) {
        const double l = dist(T_.verts[tr.v[nx(i)]].xyz, T_.verts[tr.v[pv(i)]].xyz);
        if (l > bestLen) {
          bestLen = l;
          best = i;
        }
      }
    }
    if (edge) *edge = best;
    return best >= 0;
  }

  void pushIfActive(int t) {
    if (T_.tris[t].dead) return;
    // an entry of t's current state already waiting in the heap would be popped the same
    // (every push after an insertion offered each neighbour of a touched triangle again)
    if (queued_[t] == stamp_[t] + 1) return;
    if (active(t, nullptr)) {
      heap_.push({rho_[t], t, stamp_[t]});
      queued_[t] = stamp_[t] + 1;
    }
  }

  /// The frontal point for front edge `edge` of t, in scaled uv (s) and 3D (p).
  bool newPoint(int t, int edge, Vec2& s, Vec3& p) const {
    const Triangle& tr = T_.tris[t];
    const TriVertex &A = T_.verts[tr.v[nx(edge)]], &B = T_.verts[tr.v[pv(edge)]], &Cv = T_.verts[tr.v[edge]];
    double M[3];
    for (int k = 0; k < 3; ++k) M[k] = (A.M[k] + B.M[k] + Cv.M[k]) / 3.0;
    Chol L(M);
    if (!L.ok) return false;
    const Vec2 b = L.fwd(B.uv - A.uv), c = L.fwd(Cv.uv - A.uv);
    const double len = norm(b);
    if (!(len > 0)) return false;
    const Vec2 mid = 0.5 * b;
    const Vec2 n{-b.y / len, b.x / len};  // left of A->B: towards C
    // circumcentre of (0, b, c) in metric space
    const double d = 2.0 * cross(b, c);
    if (!(d > 0)) return false;
    const double bb = dot(b, b), cc = dot(c, c);
    const Vec2 cen{(c.y * bb - b.y * cc) / d, (b.x * cc - c.x * bb) / d};
    const double q = dot(cen - mid, n);  // signed distance midpoint -> circumcentre
    // height of the equilateral triangle of unit side, not beyond the circumcentre
    double dist = 0.8660254037844386;
    if (q > 0) dist = std::min(dist, q);
    if (!(dist > 1e-3)) return false;
    const Vec2 sPred = A.uv + L.inv(mid + dist * n);
    const double hE = 3.0 / (1.0 / A.h + 1.0 / B.h + 1.0 / Cv.h);
    // the size at the point: the front's, blended with the field's where the point lands. Not
    // on faces with a boundary layer (an overlay): their front starts as the last row, whose
    // hand-off sizes the overlay already grades, and at a blade tip's crease (propeller_and_shaft,
    // first rows of 1 x 3) points sized by the field too made angles of 1.4 degrees
    auto blended = [&](Vec3 x) {
      if (C_.overlay) return hE;
      return (1 - kPointSizeBlend) * hE + kPointSizeBlend * C_.field.size(x);
    };
    if (C_.planar) {
      s = A.uv + L.inv(mid + (dist * blended(C_.surf.eval(C_.toParam(sPred))) / hE) * n);
      p = C_.surf.eval(C_.toParam(s));
      return C_.inDomain(s);
    }
    // 3D placement: from the 3D edge midpoint, in the tangent plane, at the same relative height
    Vec3 nrm = A.normal + B.normal;
    // a front edge along a crest (no normals): the flank of the triangle being processed
    if (norm2(nrm) < 1e-20 && (A.flags & B.flags & VF_CREST) && norm2(Cv.normal) > 0) nrm = Cv.normal;
    if (norm2(nrm) < 1e-20) {
      if (!C_.surf.normal(C_.toParam(0.5 * (A.uv + B.uv)), nrm)) nrm = Cv.normal;
    }
    const Vec3 e3 = B.xyz - A.xyz;
    Vec3 dir = normalized(cross(nrm, e3));
    if (norm2(dir) < 0.5) return false;
    // express the metric distance in 3D: the metric unit is the local size
    const Vec3 mid3 = 0.5 * (A.xyz + B.xyz);
    const Vec3 target = mid3 + (dist * blended(mid3 + (dist * hE) * dir)) * dir;
    s = sPred;
    if (!C_.project(target, s, p)) {
      s = sPred;
      p = C_.surf.eval(C_.toParam(s));
    }
    // reject projections that jumped far away (wrong branch of a closed surface)
    if (dist3(p, target) > 2.0 * dist * hE) {
      s = sPred;
      p = C_.surf.eval(C_.toParam(s));
    }
    return C_.inDomain(s);
  }
  static double dist3(Vec3 a, Vec3 b) { return paramesh::dist(a, b); }

  bool tooClose(int t, Vec3 p) const {
    const Triangle& tr = T_.tris[t];
    for (int k = 0; k < 3; ++k) {
      const TriVertex& v = T_.verts[tr.v[k]];
      if (dist3(v.xyz, p) < 0.4 * v.h) return true;
    }
    for (int k = 0; k < 3; ++k) {
      const int u = tr.n[k];
      if (u < 0) continue;
      const int j = T_.edgeTo(u, t);
      if (j < 0) continue;
      const TriVertex& v = T_.verts[T_.tris[u].v[j]];
      if (dist3(v.xyz, p) < 0.4 * v.h) return true;
    }
    return false;
  }

  Triangulation& T_;
  const SurfaceContext& C_;
  const FaceMeshOptions& opt_;
  const Progress* progress_;
  std::vector<double> rho_;
  std::vector<uint8_t> good_;
  std::vector<uint32_t> stamp_;
  std::vector<uint32_t> queued_;  ///< stamp + 1 of t's entry waiting in the heap; 0: none
  std::priority_queue<Entry> heap_;
};

/// How far the 3D triangle (a, b, c) follows the surface: the cosine between its normal and the
/// surface normal at its (u,v) centroid (scaled uv s0, s1, s2); 1 when flat on it, <= 0 folded
/// over. Returns 2 (no opinion) where the surface normal is undefined.
double triangleFit(const SurfaceContext& C, Vec3 a, Vec3 b, Vec3 c, Vec2 s0, Vec2 s1, Vec2 s2) {
  Vec3 ns;
  if (!C.surf.normal(C.toParam((1.0 / 3) * (s0 + s1 + s2)), ns)) return 2;
  const Vec3 n = cross(b - a, c - a);
  const double ln = norm(n);
  return ln > 0 ? dot(n, ns) / ln : -1;
}

/// bestCornerCos of the 3D triangle, -1 when it is degenerate.
double cornerFit(const TriVertex& a, const TriVertex& b, const TriVertex& c) {
  const Vec3 n = cross(b.xyz - a.xyz, c.xyz - a.xyz);
  return norm(n) > 0 ? bestCornerCos(a, b, c, n) : -1;
}

// a triangle is folded when its normal is more than ~60 degrees off the surface normal at its
// (u,v) centroid, or more than ~78 degrees (the optimiser's validity bound) off every corner's:
// a triangle of boundary nodes only that lies in the plane of a pole's boundary (a half body of
// revolution cut along its axis), whose centroid's normal alone looks fine
constexpr double kFoldCentroid = 0.5, kFoldCorner = 0.2;

/// How far triangle (a, b, c) is from being folded: min over both tests of (fit - bound), < 0 folded.
double foldMargin(const SurfaceContext& C, const TriVertex& a, const TriVertex& b, const TriVertex& c) {
  return std::min(triangleFit(C, a.xyz, b.xyz, c.xyz, a.uv, b.uv, c.uv) - kFoldCentroid,
                  cornerFit(a, b, c) - kFoldCorner);
}

/// Inserts the (u,v) centroid of every folded triangle (foldMargin < 0): small, strongly curved
/// faces whose boundary alone cannot be triangulated faithfully, and triangles of boundary nodes
/// only that cut across a pole (their nodes nearly coplanar in 3D). A few rounds; the centroid
/// always lies inside its triangle.
int refineFolded(Triangulation& T, const SurfaceContext& C) {
  int inserted = 0;
  const Triangulation::FlipTest test = [&T](int t, int i) { return T.metricFlip(t, i); };
  for (int round = 0; round < 6; ++round) {
    std::vector<int> bad;
    for (int t = 0; t < (int)T.tris.size(); ++t) {
      const Triangle& tr = T.tris[t];
      if (tr.dead) continue;
      const TriVertex &a = T.verts[tr.v[0]], &b = T.verts[tr.v[1]], &c = T.verts[tr.v[2]];
      if (a.node >= 0 && (a.node == b.node || a.node == c.node)) continue;  // pole triangle
      if (b.node >= 0 && b.node == c.node) continue;
      if (foldMargin(C, a, b, c) < 0) bad.push_back(t);
    }
    if (bad.empty()) break;
    for (int t : bad) {
      if (T.tris[t].dead) continue;
      const Triangle tr = T.tris[t];
      const TriVertex &a = T.verts[tr.v[0]], &b = T.verts[tr.v[1]], &c = T.verts[tr.v[2]];
      const Vec2 s = (1.0 / 3) * (a.uv + b.uv + c.uv);
      int e = -1;
      const int where = T.locate(s, t, &e, Triangulation::kLocalWalk);
      if (where < 0 || (e >= 0 && T.isConstrained(where, e)) || !T.insertionIsValid(s, where, e) || !C.inDomain(s))
        continue;
      const TriVertex m = C.makeVertex(s);
      // not on a corner in 3D (a strongly uneven parametrisation can put it there)
      if (T.insertionClearance(m.xyz, where, e) <
          Triangulation::kInsertClearance * std::max({dist(a.xyz, b.xyz), dist(b.xyz, c.xyz), dist(c.xyz, a.xyz)}))
        continue;
      // Not where the fold comes from a boundary segment of the triangle, i.e. where the
      // triangle the centroid would stand on that segment is no better: when the segment's chord
      // cuts through a strongly curved corner (a blade tip of radius ~1 at size 9.5) every
      // triangle on it is folded, and the centroids of six rounds converged on the segment, a fan
      // of slivers down to 0.08 degrees.
      const double before = foldMargin(C, a, b, c);
      const TriVertex* corner[3] = {&a, &b, &c};
      bool futile = false;
      for (int i = 0; i < 3 && !futile; ++i) {
        if (!T.isConstrained(t, i)) continue;
        const TriVertex &p = *corner[nx(i)], &q = *corner[pv(i)];
        futile = !(foldMargin(C, p, q, m) > before);
      }
      if (futile) continue;
      const int v = T.addVertex(m);
      T.insert(v, where, e, test);
      ++inserted;
    }
  }
  return inserted;
}

/// The face's elements in FaceMeshResult form: new nodes, references to the boundary's nodes,
/// triangles (or recombined quads), and the triangles lying off the surface.
void emitFace(const Triangulation& T, const SurfaceContext& C, Optimizer& O, const FaceBoundary& boundary,
              const FaceMeshOptions& opt, FaceMeshResult& res) {
  std::vector<int> ref(T.verts.size());
  for (size_t v = 0; v < T.verts.size(); ++v) {
    const TriVertex& V = T.verts[v];
    if (V.node >= 0 || (V.flags & VF_BOUNDARY)) {
      ref[v] = V.node;  // global node, or a face-local boundary-layer node (< 0)
    } else {
      res.newXyz.push_back(V.xyz);
      res.newUv.push_back(C.toParam(V.uv));
      ref[v] = -(opt.localNodeOffset + (int)res.newXyz.size());
    }
  }
  std::vector<char> paired(T.tris.size(), 0);
  if (opt.quads) {
    for (const QuadPair& qp : recombine(T, 150.0)) {
      paired[qp.t] = paired[qp.u] = 1;
      std::array<int, 4> r{ref[qp.quad[0]], ref[qp.quad[1]], ref[qp.quad[2]], ref[qp.quad[3]]};
      res.quads.push_back(r);
      res.quadUv.push_back({C.toParam(T.verts[qp.quad[0]].uv), C.toParam(T.verts[qp.quad[1]].uv),
                            C.toParam(T.verts[qp.quad[2]].uv), C.toParam(T.verts[qp.quad[3]].uv)});
    }
  }
  // distance to the face's boundary loops in 3D: the distance to the trimmed face of a point
  // whose projection's foot falls outside the face
  auto rimDistance = [&](Vec3 x) {
    double best = 1e300;
    for (const auto& loop : boundary.loops)
      for (size_t i = 0; i < loop.size(); ++i)
        best = std::min(best, dist(x, closestOnSegment(x, loop[i].xyz, loop[(i + 1) % loop.size()].xyz)));
    return best;
  };
  for (size_t ti = 0; ti < T.tris.size(); ++ti) {
    const Triangle& tr = T.tris[ti];
    if (tr.dead || paired[ti]) continue;
    std::array<int, 3> r{ref[tr.v[0]], ref[tr.v[1]], ref[tr.v[2]]};
    if (r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) {
      ++res.degenerateDropped;
      continue;
    }
    res.tris.push_back(r);
    res.triUv.push_back({C.toParam(T.verts[tr.v[0]].uv), C.toParam(T.verts[tr.v[1]].uv), C.toParam(T.verts[tr.v[2]].uv)});
    if (opt.reportOffSurface && !C.planar) {
      const Vec3 &A = T.verts[tr.v[0]].xyz, &B = T.verts[tr.v[1]].xyz, &D = T.verts[tr.v[2]].xyz;
      const double L = (dist(A, B) + dist(B, D) + dist(D, A)) / 3.0;
      if (O.deviationEstimate(tr.v[0], tr.v[1], tr.v[2]) > 0.01 * L) {
        bool footOutside = false;
        double d = O.deviation(tr.v[0], tr.v[1], tr.v[2], &footOutside);
        if (d > 0.02 * L && footOutside) d = std::max(d, rimDistance((1.0 / 3) * (A + B + D)));
        if (d > 0.02 * L) res.offSurface.push_back({(int)res.tris.size() - 1, d});
      }
    }
  }
}

}  // namespace

FaceMeshResult meshFace(const ISurface& surf, const FaceBoundary& boundary, const SizeField& size,
                        const FaceMeshOptions& opt, const Progress* progress) {
  FaceMeshResult res;
  try {
    SurfaceContext C(surf, size);
    C.overlay = opt.overlay;
    DomainGuard guard;
    if (!boundary.trueLoops.empty()) {
      std::vector<std::vector<Vec2>> scaled = boundary.trueLoops;
      for (auto& L : scaled)
        for (auto& q : L) q = C.toScaled(q);
      guard = DomainGuard(scaled);
      C.guard = &guard;
    }
    Triangulation T;
    std::vector<std::pair<int, int>> segs;
    for (const auto& loop : boundary.loops) {
      if (loop.size() < 2) continue;
      const int first = (int)T.verts.size();
      for (const BoundaryVertex& b : loop) {
        TriVertex v;
        v.uv = C.toScaled(b.uv);
        v.xyz = b.xyz;
        v.node = b.node;
        v.flags = VF_BOUNDARY | (b.pole ? VF_POLE : 0);
        C.fill(v);
        T.addVertex(v);
      }
      const int n = (int)loop.size();
      for (int i = 0; i < n; ++i) segs.emplace_back(first + i, first + (i + 1) % n);
    }
    std::string why;
    if (!T.buildConstrained(segs, why)) {
      res.error = why;
      return res;
    }
    if (progress) {
      // the fewest points the face can take: its area (the 3D area of the boundary's constrained
      // triangulation) over the equilateral triangle of the largest size, two triangles a point
      double area = 0;
      for (const Triangle& t : T.tris)
        if (!t.dead)
          area += 0.5 * norm(cross(T.verts[t.v[1]].xyz - T.verts[t.v[0]].xyz, T.verts[t.v[2]].xyz - T.verts[t.v[0]].xyz));
      const double hmax = size.hmax();
      if (hmax > 0) progress->require((long)std::min(1e15, area / (0.4330127 * hmax * hmax) / 2));
    }
    // under the curvature bound, folds far narrower than the mesh get their crest embedded: the
    // frontal mesh finds the edges across them, the crests are traced from there, and the face is
    // meshed again from its boundary with the crests as constrained edges. Not when the user set
    // the min-size (minSizeReach): that one wins over the curvature angle
    const bool crests = opt.maxDeviationRatio > 0 && opt.embedCrests && !C.planar && !(opt.minSizeReach > 0);
    Triangulation start;
    if (crests) start = T;
    Frontal fr(T, C, opt, progress);
    fr.run();
    res.rejectedPoints = fr.rejected;
    if (crests) {
      const std::vector<std::vector<Vec2>> lines = traceCrests(T, C);
      if (!lines.empty()) {
        // the first mesh is discarded: its points do not count against the point budget
        if (progress) progress->refund(fr.insertedPoints);
        T = std::move(start);
        std::vector<std::vector<int>> embedded;
        res.crestSegments = embedCrests(T, C, lines, &embedded);
        if (opt.crestRows) res.crestRowSegments = embedCrestRows(T, C, embedded);
        Frontal again(T, C, opt, progress);
        again.run();
        res.rejectedPoints = again.rejected;
      }
    }
    refineFolded(T, C);
    Optimizer O(T, C, progress);
    O.setMinSizeReach(opt.minSizeReach);
    optimizeFace(O, T, opt);
    for (const Optimizer::DeviationMiss& m : O.deviationMisses()) {
      // the surface's sharpest curvature under the triangle: at its corners, its edges' (u,v)
      // midpoints and its centroid's foot (across a crest the foot can lie on a flank)
      double k = maxCurvature(surf, C.toParam(m.foot));
      for (int i = 0; i < 3; ++i) {
        k = std::max(k, maxCurvature(surf, C.toParam(m.corners[i])));
        k = std::max(k, maxCurvature(surf, C.toParam(0.5 * (m.corners[i] + m.corners[(i + 1) % 3]))));
      }
      res.deviationMisses.push_back({m.centroid, m.deviation, m.allowed, k > 0 ? 1.0 / k : std::numeric_limits<double>::infinity()});
    }
    T.compact();
    emitFace(T, C, O, boundary, opt, res);
    if (res.tris.empty() && res.quads.empty()) {
      res.error = "no triangle was produced";
      return res;
    }
    res.ok = true;
  } catch (const Cancelled&) {
    throw;
  } catch (const std::exception& e) {
    res.ok = false;
    res.error = e.what();
  }
  return res;
}

}  // namespace paramesh
