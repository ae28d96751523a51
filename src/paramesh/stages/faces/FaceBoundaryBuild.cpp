// SPDX-License-Identifier: LGPL-2.1-or-later
// A face's boundary loops for the (u,v) mesher from the shared edge nodes (FaceBoundaryBuild.hpp).
#include "paramesh/stages/faces/FaceBoundaryBuild.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "paramesh/model/FaceDomain.hpp"
#include "paramesh/util/Format.hpp"

namespace paramesh {

namespace {

/// Appends the interior samples of the pcurve between parameters ta and tb (exclusive) until the
/// surface point at the (u,v) chord midpoint is within eps (3D) of the trim curve.
void refineTrim(const ISurface& s, const IPCurve& pc, double ta, double tb, Vec2 ua, Vec2 ub, Vec2 shift,
                       double eps, std::vector<Vec2>& out, int depth) {
  if (depth >= 8) return;
  const double tm = 0.5 * (ta + tb);
  const Vec2 um = pc.eval(tm) + shift;
  const Vec2 chordMid = 0.5 * (ua + ub);
  if (dist(s.eval(um), s.eval(chordMid)) <= eps) return;
  refineTrim(s, pc, ta, tm, ua, um, shift, eps, out, depth + 1);
  out.push_back(um);
  refineTrim(s, pc, tm, tb, um, ub, shift, eps, out, depth + 1);
}

/// Number of (u,v) segments for a degenerate edge a->b: about the length of the first ring of
/// elements around the pole divided by the local size.
int degenerateSegments(const SizeField& field, const ISurface& s, Vec2 a, Vec2 b, Vec3 pole) {
  const double h = field.size(pole);
  const UVBox box = s.bounds();
  const Vec2 d = b - a;
  const double ld = norm(d);
  if (!(ld > 0)) return 1;
  Vec2 nrm{-d.y / ld, d.x / ld};
  const Vec2 mid = 0.5 * (a + b);
  const Vec2 centre{0.5 * (box.u0 + box.u1), 0.5 * (box.v0 + box.v1)};
  if (dot(centre - mid, nrm) < 0) nrm = -1.0 * nrm;
  const double spanN = std::fabs(nrm.x) * (box.u1 - box.u0) + std::fabs(nrm.y) * (box.v1 - box.v0);
  double off = 1e-6 * spanN;
  for (int it = 0; it < 60; ++it) {
    if (dist(s.eval(mid + off * nrm), pole) >= h || off > 0.5 * spanN) break;
    off *= 1.5;
  }
  double L = 0;
  Vec3 prev = s.eval(a + off * nrm);
  for (int i = 1; i <= 32; ++i) {
    Vec3 q = s.eval(a + (i / 32.0) * d + off * nrm);
    L += dist(prev, q);
    prev = q;
  }
  return std::clamp((int)std::lround(L / h), 1, 512);
}

/// Closes wire w's loop (its last node is its first again): drops the copy, tolerates (u,v) gaps
/// below a quarter of the loop's shortest segment, removes (u,v) duplicates, marks collapsed tiny
/// edges as pole copies, and appends the loop and its true trim to fb.
bool closeLoop(size_t w, double span, double up, double vp, std::vector<BoundaryVertex>& loop, std::vector<Vec2>& fine,
               FaceBoundary& fb, std::string& why) {
  // closure
  if (loop.front().node != loop.back().node) {
    why = "wire " + std::to_string(w + 1) + " is not closed";
    return false;
  }
  const Vec2 endUv = loop.back().uv, startUv = loop.front().uv;
  if (norm(endUv - startUv) > 1e-6 * span + 1e-12) {
    const Vec2 wrapped = unwrapNear(endUv, startUv, up, vp);
    if (norm(wrapped - startUv) <= 1e-6 * span + 1e-12)
      why = "wire " + std::to_string(w + 1) + " winds around the periodic surface (no seam): not supported";
    else
      why = "wire " + std::to_string(w + 1) + " does not close in (u,v) (gap " + fmt(norm(endUv - startUv)) + ")";
    // tolerate small gaps (pcurve tolerance) relative to the boundary spacing
    double minSeg = 1e300;
    for (size_t i = 1; i < loop.size(); ++i) minSeg = std::min(minSeg, norm(loop[i].uv - loop[i - 1].uv));
    if (norm(endUv - startUv) > 0.25 * minSeg) return false;
    why.clear();
  }
  loop.pop_back();
  if (!fine.empty()) fine.pop_back();
  fb.trueLoops.push_back(std::move(fine));
  // drop consecutive duplicates in (u,v)
  std::vector<BoundaryVertex> clean;
  for (auto& bv : loop) {
    if (!clean.empty() && clean.back().uv.x == bv.uv.x && clean.back().uv.y == bv.uv.y) continue;
    clean.push_back(bv);
  }
  if (clean.size() >= 2 && clean.front().uv.x == clean.back().uv.x && clean.front().uv.y == clean.back().uv.y)
    clean.pop_back();
  if (clean.size() < 3) {
    why = "wire " + std::to_string(w + 1) + " has fewer than 3 distinct points";
    return false;
  }
  // consecutive images of one node (a collapsed tiny edge) behave like pole copies
  for (size_t i = 0; i < clean.size(); ++i) {
    const size_t j = (i + 1) % clean.size();
    if (clean[i].node == clean[j].node) clean[i].pole = clean[j].pole = true;
  }
  fb.loops.push_back(std::move(clean));
  return true;
}

}  // namespace

bool buildFaceBoundary(const IGeometryModel& model, const std::vector<EdgeMesh>& edges, const SurfaceMesh& mesh,
                       const SizeField& field, int f, const ISurface& s, FaceBoundary& fb, std::string& why) {
  const auto& wires = model.faceWires(f);
  const double up = s.uPeriod(), vp = s.vPeriod();
  const UVBox box = s.bounds();
  const double span = std::max(box.u1 - box.u0, box.v1 - box.v0);
  std::set<int> poleNodes;
  for (const Wire& w : wires)
    for (const EdgeUse& u : w.uses)
      if (edges[u.edge].degenerate)
        for (int nd : edges[u.edge].nodes) poleNodes.insert(nd);
  for (size_t w = 0; w < wires.size(); ++w) {
    std::vector<BoundaryVertex> loop;
    std::vector<Vec2> fine;  // the true boundary, finely sampled
    const Wire& W = wires[w];
    for (size_t k = 0; k < W.uses.size(); ++k) {
      const EdgeUse& use = W.uses[k];
      const EdgeMesh& em = edges[use.edge];
      auto pc = model.makePCurve(f, (int)w, (int)k);
      std::vector<BoundaryVertex> pts;
      std::vector<double> pts_t;
      double pcOff = 0;     // the farthest the pcurve's image lies from this use's nodes / size
      double pcOffAbs = 0;  // the same in 3D
      if (em.degenerate) {
        if (!pc) {
          why = "degenerate Edge" + std::to_string(use.edge + 1) + " has no curve on the face";
          return false;
        }
        Vec2 a = pc->eval(em.t.front()), b = pc->eval(em.t.back());
        if (use.reversed) std::swap(a, b);
        const int node = em.nodes.front();
        const Vec3 pole = mesh.nodes[node];
        const int n = degenerateSegments(field, s, a, b, pole);
        for (int i = 0; i <= n; ++i) {
          BoundaryVertex bv;
          bv.uv = a + ((double)i / n) * (b - a);
          bv.xyz = pole;
          bv.node = node;
          bv.pole = true;
          pts.push_back(bv);
        }
      } else {
        const size_t n = em.t.size();
        for (size_t i = 0; i < n; ++i) {
          const size_t j = use.reversed ? n - 1 - i : i;
          BoundaryVertex bv;
          bv.node = em.nodes[j];
          bv.xyz = mesh.nodes[bv.node];
          Vec2 uv;
          if (pc) {
            uv = pc->eval(em.t[j]);
          } else {
            uv = pts.empty() ? (loop.empty() ? Vec2{0.5 * (box.u0 + box.u1), 0.5 * (box.v0 + box.v1)} : loop.back().uv)
                             : pts.back().uv;
            if (pts.empty() && loop.empty()) s.projectGlobal(bv.xyz, uv);
          }
          // make the (u,v) consistent with the shared 3D node (tolerant CAD, non-same-parameter)
          const double off = dist(s.eval(uv), bv.xyz);
          const double tol = 1e-7 * (1 + norm(bv.xyz)) + 1e-3 * field.size(bv.xyz) * 1e-2;
          if (pc) {
            pcOff = std::max(pcOff, off / field.size(bv.xyz));
            pcOffAbs = std::max(pcOffAbs, off);
          }
          if (off > tol) {
            Vec2 q = uv;
            Vec3 out;
            // a foot on the node is taken even when Newton's convergence test, relative to a
            // residual of round-off size, did not pass (measured: docs/tuning/pipeline.md)
            const bool onFoot = s.project(bv.xyz, q, &out, 0.02) || dist(out, bv.xyz) <= tol;
            if (onFoot && dist(out, bv.xyz) <= off) uv = q;
          }
          bv.uv = uv;
          bv.pole = poleNodes.count(bv.node) > 0;
          pts.push_back(bv);
          pts_t.push_back(em.t[j]);
        }
      }
      // periodic continuity with the previous use
      Vec2 sh{0, 0};
      if (!loop.empty() && !pts.empty()) {
        sh = unwrapNear(pts.front().uv, loop.back().uv, up, vp) - pts.front().uv;
        for (auto& q : pts) q.uv = q.uv + sh;
      }
      // the true boundary between consecutive nodes (curved in (u,v) where the trim is). Where
      // the pcurve strays from the edge's 3D curve (a tolerant edge), the nodes took the
      // projections of their 3D points, but the trim stays the pcurve's: that is the face
      // OpenCASCADE's classifier knows, and FreeCAD's FEM node lookup by face
      // (FemMesh::getNodesByFace, BRepExtrema within the face's tolerance) misses nodes put in
      // the strip between (the projected 3D edges as the trim: docs/tuning/pipeline.md)
      if (pc && !em.degenerate && pcOff > kPcurveStray) fb.strayPcurves.push_back({use.edge, pcOffAbs});
      for (size_t i = 0; i < pts.size(); ++i) {
        if (i == 0 && !fine.empty()) continue;
        if (i > 0 && pc && !em.degenerate)
          refineTrim(s, *pc, pts_t[i - 1], pts_t[i], pts[i - 1].uv, pts[i].uv, sh,
                     1e-5 * field.size(pts[i].xyz), fine, 0);
        fine.push_back(pts[i].uv);
      }
      for (auto& q : pts) q.edge = use.edge;  // the segment starting at q lies on this edge
      for (size_t i = 0; i < pts.size(); ++i) {
        if (!loop.empty() && i == 0) {
          // shared point with the previous use: it now starts a segment of this use
          if (loop.back().node != pts[0].node) {
            why = "wire " + std::to_string(w + 1) + " is not connected at Edge" + std::to_string(use.edge + 1);
            return false;
          }
          loop.back().edge = use.edge;
          continue;
        }
        loop.push_back(pts[i]);
      }
    }
    if (loop.size() < 2) continue;
    if (!closeLoop(w, span, up, vp, loop, fine, fb, why)) return false;
  }
  if (fb.loops.empty()) {
    why = "the face has no wire";
    return false;
  }
  return true;
}

}  // namespace paramesh
