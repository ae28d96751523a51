// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file FacesWithLayers.cpp
/// Face stage, faces with boundary layers: the rows grown from the face's layer edges, the
/// isotropic mesh of the rest from the layers' front, and the hand-off relaxation of the
/// triangles standing on the front. Reads model, field, edges, blSpecOf, blLaws; writes the
/// face's result and blStats / blEmpty (under blMu_).
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <mutex>
#include <vector>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/pipeline/Tuning.hpp"
#include "paramesh/algo/SurfaceContext.hpp"
#include "paramesh/algo/Predicates.hpp"

namespace paramesh {

using namespace tuning;

void MeshContext::relaxHandoff(const ISurface& s, const FaceBLResult& bl, int offset, std::vector<Vec3>& xyz,
                  std::vector<Vec2>& uv, const std::vector<std::array<int, 3>>& tris,
                  std::vector<std::array<Vec2, 3>>& triUv) const {
  auto P = [&](int r) { return r >= 0 ? mesh.nodes[r] : xyz[-r - 1]; };
  auto movable = [&](int r) { return r < 0 && -r - 1 >= offset; };
  // top edges of the layer quads: (a,b) -> row height of the quad below
  std::map<std::pair<int, int>, std::pair<int, double>> quadEdges;  // key -> (uses, height)
  for (const auto& q : bl.quads)
    for (int k = 0; k < 4; ++k) {
      const int a = q[k], b = q[(k + 1) % 4];
      const double h = 0.5 * (dist(P(a), P(q[(k + 3) % 4])) + dist(P(b), P(q[(k + 2) % 4])));
      auto& e = quadEdges[{std::min(a, b), std::max(a, b)}];
      ++e.first;
      e.second = h;
    }
  std::map<int, std::vector<int>> around;  // movable node -> incident triangles
  for (size_t t = 0; t < tris.size(); ++t)
    for (int v : tris[t])
      if (movable(v)) around[v].push_back((int)t);
  auto quality = [&](int t) { return gamma3(P(tris[t][0]), P(tris[t][1]), P(tris[t][2])); };
  // the triangles standing on a top edge with a movable apex, found once (in triangle and edge
  // order, as the passes use them): the passes move nodes, never the connectivity
  struct OnFront {
    int t, k;
    double hl;
  };
  std::vector<OnFront> onFront;
  for (size_t t = 0; t < tris.size(); ++t) {
    const auto& T = tris[t];
    for (int k = 0; k < 3; ++k) {
      const int a = T[k], b = T[(k + 1) % 3], c = T[(k + 2) % 3];
      auto it = quadEdges.find({std::min(a, b), std::max(a, b)});
      if (it == quadEdges.end() || it->second.first != 1 || !movable(c)) continue;
      onFront.push_back({(int)t, k, it->second.second});
    }
  }
  for (int pass = 0; pass < 3; ++pass) {
    std::map<int, std::pair<Vec3, int>> wish;  // apex -> sum of wished positions, count
    for (const OnFront& f : onFront) {
      const auto& T = tris[f.t];
      const int k = f.k;
      const int a = T[k], b = T[(k + 1) % 3], c = T[(k + 2) % 3];
      const double hl = f.hl;
      const Vec3 A = P(a), B = P(b), C = P(c);
      const double L = dist(A, B);
      if (!(L > 0) || !(hl > 0)) continue;
      const Vec3 e = (1.0 / L) * (B - A);
      const Vec3 m = 0.5 * (A + B);
      Vec3 up = (C - m) - dot(C - m, e) * e;  // towards the apex, across the edge
      const double ht = norm(up);
      if (!(ht > 0)) continue;
      up = (1.0 / ht) * up;
      const double target = std::clamp(ht, hl / 1.25, 1.25 * hl);
      if (std::fabs(target - ht) < 1e-3 * hl) continue;
      // keep the apex's position along the edge; change only its height
      const Vec3 want = C + (target - ht) * up;
      auto& w = wish[c];
      w.first += want;
      ++w.second;
    }
    if (wish.empty()) return;
    int moved = 0;
    for (const auto& kv : wish) {
      const int v = kv.first;
      const int i = -v - 1;
      const Vec3 target = (1.0 / kv.second.second) * kv.second.first;
      const auto& inc = around[v];
      double before = 1;
      for (int t : inc) before = std::min(before, quality(t));
      const Vec3 x0 = xyz[i];
      const Vec2 u0 = uv[i];
      for (double step : {1.0, 0.5, 0.25}) {
        // one Newton step on the surface towards x0 + step * (target - x0)
        Vec3 p, du, dv;
        s.d1(u0, p, du, dv);
        const Vec3 d = step * (target - x0);
        const double a11 = dot(du, du), a12 = dot(du, dv), a22 = dot(dv, dv);
        const double det = a11 * a22 - a12 * a12;
        if (!(std::fabs(det) > 0)) break;
        const double r1 = dot(du, d), r2 = dot(dv, d);
        const Vec2 nu{u0.x + (a22 * r1 - a12 * r2) / det, u0.y + (a11 * r2 - a12 * r1) / det};
        xyz[i] = s.eval(nu);
        uv[i] = nu;
        bool ok = true;
        double after = 1;
        for (int t : inc) {
          std::array<Vec2, 3> tu = triUv[t];
          for (int k = 0; k < 3; ++k)
            if (tris[t][k] == v) tu[k] = tu[k] + (nu - u0);
          if (area2(tu[0], tu[1], tu[2]) <= 0) {
            ok = false;
            break;
          }
          const Vec3 A = P(tris[t][0]), B = P(tris[t][1]), C = P(tris[t][2]);
          Vec3 q, su, sv;
          s.d1((1.0 / 3) * (tu[0] + tu[1] + tu[2]), q, su, sv);
          if (dot(cross(B - A, C - A), cross(su, sv)) <= 0) {
            ok = false;
            break;
          }
          after = std::min(after, quality(t));
        }
        if (ok && after >= std::min(before, 0.5)) {  // never below 0.5 unless it was already
          for (int t : inc)
            for (int k = 0; k < 3; ++k)
              if (tris[t][k] == v) triUv[t][k] = triUv[t][k] + (nu - u0);
          ++moved;
          break;
        }
        xyz[i] = x0;
        uv[i] = u0;
      }
    }
    if (!moved) return;
  }
}

FaceMeshResult MeshContext::meshFaceWithLayers(int f, const ISurface& s, const FaceBoundary& fb, FaceMeshOptions fo) {
  const FaceMeshOptions plain = fo;
  FaceMeshResult r;
  try {
    r = meshFaceWithLayersOnly(f, s, fb, fo);
  } catch (const Cancelled&) {
    throw;
  } catch (const std::exception& e) {
    r.ok = false;
    r.error = e.what();
  }
  {
    std::lock_guard<std::mutex> g(blMu_);
    blDropped.erase(f);
  }
  if (r.ok) return r;
  FaceMeshResult without = meshFace(s, fb, field, plain, &progress);
  if (!without.ok) {
    r.error += " (and without its boundary layer: " + without.error + ")";
    return r;
  }
  without.quadLayer.assign(without.quads.size(), 0);
  without.triLayer.assign(without.tris.size(), 0);
  std::lock_guard<std::mutex> g(blMu_);
  blDropped[f] = r.error;
  for (size_t k = 0; k < blStats.size(); ++k) blEmpty.erase({f, (int)k});
  return without;
}

FaceMeshResult MeshContext::meshFaceWithLayersOnly(int f, const ISurface& s, const FaceBoundary& fb, FaceMeshOptions fo) {
  std::vector<std::vector<LoopPoint>> loops;
  for (const auto& L : fb.loops) {
    std::vector<LoopPoint> lp;
    for (const BoundaryVertex& b : L) lp.push_back({b.uv, b.xyz, b.node, b.edge, b.pole});
    loops.push_back(std::move(lp));
  }
  DomainGuard guard(fb.trueLoops);
  FaceBLResult bl = growFaceLayers(s, model.faceReversed(f), loops, fb.trueLoops, guard, blSpecOf, blLaws, blEnds);
  FaceBoundary inner;
  inner.trueLoops = fb.trueLoops;
  for (const auto& L : bl.loops) {
    std::vector<BoundaryVertex> bv;
    for (const LoopPoint& q : L) {
      BoundaryVertex b;
      b.uv = q.uv;
      b.xyz = q.xyz;
      b.node = q.node;
      b.pole = q.pole;
      b.edge = q.edge;
      bv.push_back(b);
    }
    if (bv.size() >= 3) inner.loops.push_back(std::move(bv));
  }
  // hand-off: the isotropic mesh starts from the front with its spacing, graded away
  SizeField overlay(field.hmax(), p.grading);
  for (const auto& fs : bl.frontSizes) overlay.addSource(fs.first, std::max(fs.second, p.minSize));
  overlay.build();
  fo.overlay = &overlay;
  fo.localNodeOffset = (int)bl.nodes.size();
  // the sliver post-pass would undo the hand-off (it splits and collapses next to the front);
  // relaxHandoff below looks after the triangles on the front instead
  fo.sliverPass = false;
  FaceMeshResult r;
  if (inner.loops.empty()) {
    r.ok = true;  // the layers cover the whole face
  } else {
    r = meshFace(s, inner, field, fo, &progress);
    if (!r.ok) return r;
  }
  std::vector<Vec3> xyz;
  std::vector<Vec2> uv;
  for (const BLNode& n : bl.nodes) {
    xyz.push_back(n.xyz);
    uv.push_back(n.uv);
  }
  xyz.insert(xyz.end(), r.newXyz.begin(), r.newXyz.end());
  uv.insert(uv.end(), r.newUv.begin(), r.newUv.end());
  if (!inner.loops.empty()) relaxHandoff(s, bl, (int)bl.nodes.size(), xyz, uv, r.tris, r.triUv);
  r.newXyz = std::move(xyz);
  r.newUv = std::move(uv);
  r.quadLayer.assign(r.quads.size(), 0);
  r.triLayer.assign(r.tris.size(), 0);
  r.quads.insert(r.quads.end(), bl.quads.begin(), bl.quads.end());
  r.quadUv.insert(r.quadUv.end(), bl.quadUv.begin(), bl.quadUv.end());
  for (int sp : bl.quadSpec) r.quadLayer.push_back(sp + 1);
  for (size_t k = 0; k < bl.tris.size(); ++k) {
    r.tris.push_back(bl.tris[k]);
    r.triUv.push_back(bl.triUv[k]);
    r.triLayer.push_back(bl.triSpec[k] + 1);
  }
  if (r.tris.empty() && r.quads.empty()) {
    r.ok = false;
    r.error = "no element was produced";
    return r;
  }
  {
    std::lock_guard<std::mutex> g(blMu_);
    for (size_t k = 0; k < bl.stats.size(); ++k) {
      auto& a = blStats[k];
      const auto& b = bl.stats[k];
      a.columns += b.columns;
      a.fullColumns += b.fullColumns;
      a.minLayers = std::min(a.minLayers, b.minLayers);
      a.maxLayers = std::max(a.maxLayers, b.maxLayers);
      a.stopBoundary += b.stopBoundary;
      a.stopCollision += b.stopCollision;
      a.stopInvalid += b.stopInvalid;
      a.stopAspect += b.stopAspect;
      a.stopEnd += b.stopEnd;
      a.fans += b.fans;
      a.merges += b.merges;
      a.elements += b.elements;
      if (b.columns > 0 && b.elements == 0)
        blEmpty[{f, (int)k}] = b;
      else
        blEmpty.erase({f, (int)k});
    }
  }
  return r;
}

}  // namespace paramesh
