// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Assemble.cpp
/// Assembly stage: each face's result appended to the one mesh in face order (deterministic),
/// its local nodes numbered, reversed faces flipped so every element is oriented with the
/// shape's outward normal; the face's report counts filled; the round kept for the next
/// nearest-face round. Reads the face results, model (orientation); writes mesh, triUv, quadUv,
/// offSurface, triDeviation, report.faces, rounds.previous.
#include <algorithm>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/pipeline/Tuning.hpp"

namespace paramesh {

using namespace tuning;

void MeshContext::assembleFace(int f, FaceMeshResult& r) {
  FaceReport& fr = report.faces[f];
  if (!fr.ok) {
    log.warn("Face" + std::to_string(f + 1) + " failed: " + fr.error);
    return;
  }
  const int src = f < (int)faceStage.copyOf.size() ? faceStage.copyOf[f] : -1;
  // a coincident copy's local nodes are its source face's (assembled before it)
  const int base = src >= 0 ? faceStage.nodeBase[src] : (int)mesh.nodes.size();
  faceStage.nodeBase[f] = base;
  for (size_t k = 0; k < r.newXyz.size(); ++k) mesh.addNode(r.newXyz[k], NodeKind::Face, f + 1, r.newUv[k]);
  triDeviation.resize(mesh.triangles.size() + r.tris.size(), 0.0);
  for (const auto& od : r.offSurface) {
    const int t = (int)mesh.triangles.size() + od.first;
    triDeviation[t] = od.second;
    // deeper than 4.5 % of the mesh size; faces with boundary layers keep their rows as they are
    if (r.triLayer.empty() && od.second > kOffSurfaceCandidate * std::min(p.size, p.maxSize))
      offSurface.push_back({t, od.second});
  }
  bool rev = model.faceReversed(f);
  if (src >= 0) rev = rev != copyAgainstSurface(f, r, base);
  for (size_t k = 0; k < r.tris.size(); ++k) {
    auto t = r.tris[k];
    auto uv = r.triUv[k];
    for (int& v : t)
      if (v < 0) v = base + (-v - 1);
    if (rev) {
      std::swap(t[1], t[2]);
      std::swap(uv[1], uv[2]);
    }
    mesh.triangles.push_back(t);
    mesh.triangleFace.push_back(f + 1);
    mesh.triangleLayer.push_back(k < r.triLayer.size() ? r.triLayer[k] : 0);
    triUv.push_back(uv);
  }
  for (size_t k = 0; k < r.quads.size(); ++k) {
    auto q = r.quads[k];
    auto uv = r.quadUv[k];
    for (int& v : q)
      if (v < 0) v = base + (-v - 1);
    if (rev) {
      std::swap(q[1], q[3]);
      std::swap(uv[1], uv[3]);
    }
    mesh.quads.push_back(q);
    mesh.quadFace.push_back(f + 1);
    mesh.quadLayer.push_back(k < r.quadLayer.size() ? r.quadLayer[k] : 0);
    quadUv.push_back(uv);
  }
  fr.triangles = (int)r.tris.size();
  fr.quads = (int)r.quads.size();
  fr.nodes = (int)r.newXyz.size();
  fr.overDeviation = (int)r.deviationMisses.size();
  fr.crestSegments = r.crestSegments;
  fr.crestRowSegments = r.crestRowSegments;
  fr.overDeviationWorst = 0;
  fr.overDeviationRadius = std::numeric_limits<double>::infinity();
  fr.overDeviationResolvable = 0;
  const double reach = minSizeReach();
  for (const FaceMeshResult::DeviationMiss& m : r.deviationMisses) {
    if (reach > 0 && m.radius >= reach) ++fr.overDeviationResolvable;
    const double x = m.deviation / m.allowed;
    if (x > fr.overDeviationWorst) {
      fr.overDeviationWorst = x;
      fr.overDeviationAt[0] = m.at.x;
      fr.overDeviationAt[1] = m.at.y;
      fr.overDeviationAt[2] = m.at.z;
    }
    fr.overDeviationRadius = std::min(fr.overDeviationRadius, m.radius);
  }
}

bool MeshContext::copyAgainstSurface(int f, const FaceMeshResult& r, int base) const {
  const auto s = model.makeSurface(f);
  int against = 0;
  for (size_t k = 0; k < r.tris.size(); ++k) {
    Vec3 x[3];
    for (int i = 0; i < 3; ++i) {
      const int v = r.tris[k][i];
      x[i] = mesh.nodes[v < 0 ? base + (-v - 1) : v];
    }
    const Vec2 c = (1.0 / 3.0) * (r.triUv[k][0] + r.triUv[k][1] + r.triUv[k][2]);
    Vec3 n;
    if (s->normal(c, n)) against += dot(cross(x[1] - x[0], x[2] - x[0]), n) < 0 ? 1 : -1;
  }
  return against > 0;
}

void MeshContext::keepForNextRound(std::vector<FaceMeshResult>&& results) {
  const int nf = model.numFaces();
  auto prev = std::make_unique<PreviousRound>();
  prev->points.assign(nf, {});
  std::vector<int> seen(mesh.nodes.size(), -1);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const int f = mesh.triangleFace[t] - 1;
    for (int v : mesh.triangles[t])
      if (seen[v] != f) {
        seen[v] = f;
        prev->points[f].push_back(mesh.nodes[v]);
      }
  }
  prev->results = std::move(results);
  prev->reports = report.faces;
  prev->edges = edges;
  rounds.previous = std::move(prev);
}

}  // namespace paramesh
