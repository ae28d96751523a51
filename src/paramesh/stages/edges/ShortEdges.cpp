// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file ShortEdges.cpp
/// Edge stage, short edges: CAD edges much shorter than the size field (chains of them, or tight
/// arcs) become size sources and the edges they reach are discretised again; edges closing a strip
/// a few elements wide get segments of a row's height. Reads model, same, field; writes field
/// (sources) and the edges' parameters.
#include <algorithm>
#include <functional>
#include <utility>
#include <vector>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/pipeline/Tuning.hpp"
#include "paramesh/size/SourceReach.hpp"
#include "paramesh/util/Parallel.hpp"

namespace paramesh {

using namespace tuning;

/// The nodes of every edge as 3D polylines, and the edges at each (representative) vertex.
struct EdgePolylines {
  const IGeometryModel& model;
  const Coincidence& same;
  std::vector<std::vector<Vec3>> pts;
  std::vector<std::vector<std::pair<int, int>>> atVertex;  // (edge, end)

  double polyLength(int e) const;
  double distToPoly(Vec3 x, int e) const;
  Vec3 along(int e, int k, double sArc) const;
  bool closesStrip(int e, double l) const;
  bool inChain(int e, const std::vector<char>& isShort) const;
};

double EdgePolylines::polyLength(int e) const {
  double L = 0;
  for (size_t i = 1; i < pts[e].size(); ++i) L += dist(pts[e][i - 1], pts[e][i]);
  return L;
}

double EdgePolylines::distToPoly(Vec3 x, int e) const {
  double best = 1e300;
  const auto& P = pts[e];
  for (size_t i = 1; i < P.size(); ++i) {
    const Vec3 d = P[i] - P[i - 1];
    const double dd = dot(d, d);
    const double w = dd > 0 ? std::clamp(dot(x - P[i - 1], d) / dd, 0.0, 1.0) : 0.0;
    best = std::min(best, dist(x, P[i - 1] + w * d));
  }
  return best;
}

/// Point of edge e at about arc length s from its end k.
Vec3 EdgePolylines::along(int e, int k, double sArc) const {
  const auto& P = pts[e];
  const int n = (int)P.size();
  double acc = 0;
  for (int i = 1; i < n; ++i) {
    const Vec3 x0 = k == 0 ? P[i - 1] : P[n - i], x1 = k == 0 ? P[i] : P[n - 1 - i];
    const double l = dist(x0, x1);
    if (acc + l >= sArc && l > 0) return x0 + ((sArc - acc) / l) * (x1 - x0);
    acc += l;
  }
  return k == 0 ? P.back() : P.front();
}

/// A short edge closing a narrow strip (the end of a thin face: its neighbours run on side by
/// side at about its length) is no small feature: refining there only multiplies the strip's
/// slivers.
bool EdgePolylines::closesStrip(int e, double l) const {
  const int va = model.edgeVertex(e, 0), vb = model.edgeVertex(e, 1);
  if (va < 0 || vb < 0) return false;
  for (const auto& ea : atVertex[same.vertexRep[va]]) {
    if (ea.first == e) continue;
    const double La = polyLength(ea.first);
    if (La < 3 * l) continue;
    const Vec3 x = along(ea.first, ea.second, std::min(0.5 * La, 3 * l));
    for (const auto& eb : atVertex[same.vertexRep[vb]]) {
      if (eb.first == e || eb.first == ea.first) continue;
      if (distToPoly(x, eb.first) < 1.5 * l) return true;
    }
  }
  return false;
}

/// A short edge next to another short edge: a finely detailed boundary (one isolated short edge
/// costs a few poor triangles; refining around it would cost hundreds of elements).
bool EdgePolylines::inChain(int e, const std::vector<char>& isShort) const {
  for (int k = 0; k < 2; ++k) {
    const int v = model.edgeVertex(e, k);
    if (v < 0) continue;
    for (const auto& ev : atVertex[same.vertexRep[v]])
      if (ev.first != e && isShort[ev.first]) return true;
  }
  return false;
}

void MeshContext::refineShortEdges(std::vector<std::vector<double>>& ts, std::vector<char>& degen) {
  const int ne = model.numEdges();
  EdgePolylines poly{model, same, std::vector<std::vector<Vec3>>(ne),
                     std::vector<std::vector<std::pair<int, int>>>(model.numVertices())};
  std::vector<std::vector<Vec3>>& pts = poly.pts;
  std::vector<std::vector<std::pair<int, int>>>& atVertex = poly.atVertex;
  // nodes of every edge, and the edges at each (representative) vertex
  parallelFor(ne, threads, [&](int e) {
    if (degen[e] || same.edgeRep[e] != e || ts[e].size() < 2) return;
    discretizeOne(e, ts, [&] {
      auto c = model.makeCurve(e);
      for (double t : ts[e]) pts[e].push_back(c->eval(t));
    });
    if (!edgeStage.error[e].empty()) pts[e].clear();
  });
  for (int e = 0; e < ne; ++e) {
    if (pts[e].empty()) continue;
    for (int k = 0; k < 2; ++k) {
      const int v = model.edgeVertex(e, k);
      if (v >= 0) atVertex[same.vertexRep[v]].push_back({e, k});
    }
  }
  addShortEdgeSources(poly, ts, degen);
  respaceStripEnds(poly, ts, degen);
}

void MeshContext::addShortEdgeSources(const EdgePolylines& poly, std::vector<std::vector<double>>& ts,
                                      std::vector<char>& degen) {
  const int ne = model.numEdges();
  const std::vector<std::vector<Vec3>>& pts = poly.pts;
  std::vector<char> isShort(ne, 0);
  for (int e = 0; e < ne; ++e) {
    if (pts[e].size() < 2) continue;
    const double L = poly.polyLength(e);
    const double hf = field.size(pts[e][pts[e].size() / 2]);
    isShort[e] = L > 0 && L < kShortSegment * hf && !poly.closesStrip(e, L);
  }
  std::vector<std::vector<SizeSource>> found(ne);
  parallelFor(ne, threads, [&](int e) {
    // a short edge on its own counts when the turning limit split it into three segments or
    // more: a tight arc (small rounded feature) rather than a mere short chord
    if (!isShort[e] || !(poly.inChain(e, isShort) || pts[e].size() > 3)) return;
    const auto& P = pts[e];
    for (size_t i = 1; i < P.size(); ++i) {
      const double hs = std::max(dist(P[i - 1], P[i]), p.minSize);
      if (i == 1) found[e].push_back({P[0], hs});
      found[e].push_back({0.5 * (P[i - 1] + P[i]), hs});
      found[e].push_back({P[i], hs});
    }
  });
  size_t added = 0;
  for (const auto& v : found)
    for (const SizeSource& s : v) {
      field.addSource(s.p, s.h);
      ++added;
    }
  if (added) {
    field.build();
    // again only the edges the new sources reach (grading > 1: a source of size h changes the
    // field within (hmax - h) / (grading - 1) of it); an edge's discretisation queries the
    // field on its curve only, within two segments of its nodes' box
    std::vector<Vec3> at;
    std::vector<double> reach;
    for (const auto& v : found)
      for (const SizeSource& s : v) {
        at.push_back(s.p);
        reach.push_back((field.hmax() - s.h) / field.slope());
      }
    const SourceReach near(std::move(at), std::move(reach));
    std::vector<char> redo(ne, 0);
    for (int e = 0; e < ne; ++e) {
      if (same.edgeRep[e] != e || degen[e]) continue;
      if (pts[e].empty()) {  // no nodes to bound it
        redo[e] = 1;
        continue;
      }
      Box3 b;
      double seg = 0;
      for (size_t i = 0; i < pts[e].size(); ++i) {
        b.add(pts[e][i]);
        if (i) seg = std::max(seg, dist(pts[e][i - 1], pts[e][i]));
      }
      const Vec3 margin{2 * seg, 2 * seg, 2 * seg};
      redo[e] = near.reaches(b.lo - margin, b.hi + margin);
    }
    discretizeAll(ts, degen, &redo);
  }
}

void MeshContext::respaceStripEnds(const EdgePolylines& poly, std::vector<std::vector<double>>& ts,
                                   const std::vector<char>& degen) {
  const int ne = model.numEdges();
  const std::vector<std::vector<Vec3>>& pts = poly.pts;
  // An edge closing a strip a few elements wide ends the rows of triangles that grow from the
  // strip's sides: rows of equilateral triangles are 0.87 h high, so its segments are too
  // (with segments of h the rows cannot end on its nodes and break up along the strip).
  parallelFor(ne, threads, [&](int e) {
    if (pts[e].size() < 2 || !mayRespace(e, degen) || same.edgeRep[e] != e) return;
    const int v0 = model.edgeVertex(e, 0), v1 = model.edgeVertex(e, 1);
    if (v0 < 0 || v1 < 0 || v0 == v1) return;
    const double L = poly.polyLength(e);
    const double hf = field.size(pts[e][pts[e].size() / 2]);
    if (!(L > hf) || L > kStripEndMax * hf || !poly.closesStrip(e, L)) return;
    discretizeOne(e, ts, [&] { ts[e] = discretizeWith(e, [this](Vec3 x) { return kRowHeight * field.size(x); }); });
  });
}

}  // namespace paramesh
