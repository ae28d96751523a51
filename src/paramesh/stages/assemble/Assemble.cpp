// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Assemble.cpp
/// Assembly stage: each face's result placed in the one mesh in face order (deterministic: the
/// slots are counted first, then the faces fill theirs in parallel), its local nodes numbered,
/// reversed faces flipped so every element is oriented with the shape's outward normal; the face's report counts filled; the round kept for the next
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
#include "paramesh/util/Parallel.hpp"

namespace paramesh {

using namespace tuning;

void MeshContext::assembleFaces(std::vector<FaceMeshResult>& results) {
  const int nf = model.numFaces();
  faceStage.nodeBase.assign(nf, 0);
  // where each face's nodes and elements go: the face order fixes the numbering (deterministic)
  struct Slot {
    int node = -1, tri = 0, quad = 0;
  };
  std::vector<Slot> at(nf);
  int N = (int)mesh.nodes.size(), T = (int)mesh.triangles.size(), Q = (int)mesh.quads.size();
  bool any = false;
  for (int f = 0; f < nf; ++f) {
    const FaceReport& fr = report.faces[f];
    if (!fr.ok) {
      log.warn("Face" + std::to_string(f + 1) + " failed: " + fr.error);
      continue;
    }
    any = true;
    const FaceMeshResult& r = results[f];
    const int src = f < (int)faceStage.copyOf.size() ? faceStage.copyOf[f] : -1;
    // a coincident copy's local nodes are its source face's (assembled before it)
    faceStage.nodeBase[f] = src >= 0 ? faceStage.nodeBase[src] : N;
    at[f] = {N, T, Q};
    N += (int)r.newXyz.size();
    T += (int)r.tris.size();
    Q += (int)r.quads.size();
  }
  mesh.nodes.resize(N);
  mesh.nodeKind.resize(N, NodeKind::Face);
  mesh.nodeEntity.resize(N, 0);
  mesh.nodeParam.resize(N);
  mesh.triangles.resize(T);
  mesh.triangleFace.resize(T, 0);
  mesh.triangleLayer.resize(T, 0);
  triUv.resize(T);
  mesh.quads.resize(Q);
  mesh.quadFace.resize(Q, 0);
  mesh.quadLayer.resize(Q, 0);
  quadUv.resize(Q);
  if (any) triDeviation.resize(T, 0.0);
  parallelFor(nf, threads, [&](int f) {
    if (at[f].node < 0) return;
    const FaceMeshResult& r = results[f];
    for (size_t k = 0; k < r.newXyz.size(); ++k) {
      const size_t i = at[f].node + k;
      mesh.nodes[i] = r.newXyz[k];
      mesh.nodeKind[i] = NodeKind::Face;
      mesh.nodeEntity[i] = f + 1;
      mesh.nodeParam[i] = r.newUv[k];
    }
  });
  // orientation: a copy's against its source's nodes, all written now
  std::vector<char> rev(nf, 0);
  for (int f = 0; f < nf; ++f) {
    if (at[f].node < 0) continue;
    rev[f] = model.faceReversed(f);
    const int src = f < (int)faceStage.copyOf.size() ? faceStage.copyOf[f] : -1;
    if (src >= 0) rev[f] = rev[f] != copyAgainstSurface(f, results[f], faceStage.nodeBase[f]);
  }
  std::vector<std::vector<OffSurfaceTriangle>> off(nf);
  parallelFor(nf, threads, [&](int f) {
    if (at[f].node < 0) return;
    assembleFace(f, results[f], at[f].tri, at[f].quad, rev[f], off[f]);
  });
  for (const auto& o : off) offSurface.insert(offSurface.end(), o.begin(), o.end());
}

void MeshContext::assembleFace(int f, const FaceMeshResult& r, int tri0, int quad0, bool rev,
                               std::vector<OffSurfaceTriangle>& off) {
  FaceReport& fr = report.faces[f];
  const int base = faceStage.nodeBase[f];
  for (const auto& od : r.offSurface) {
    const int t = tri0 + od.first;
    triDeviation[t] = od.second;
    // deeper than 4.5 % of the mesh size; faces with boundary layers keep their rows as they are
    if (r.triLayer.empty() && od.second > kOffSurfaceCandidate * std::min(p.size, p.maxSize))
      off.push_back({t, od.second});
  }
  for (size_t k = 0; k < r.tris.size(); ++k) {
    auto t = r.tris[k];
    auto uv = r.triUv[k];
    for (int& v : t)
      if (v < 0) v = base + (-v - 1);
    if (rev) {
      std::swap(t[1], t[2]);
      std::swap(uv[1], uv[2]);
    }
    const size_t i = tri0 + k;
    mesh.triangles[i] = t;
    mesh.triangleFace[i] = f + 1;
    mesh.triangleLayer[i] = k < r.triLayer.size() ? r.triLayer[k] : 0;
    triUv[i] = uv;
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
    const size_t i = quad0 + k;
    mesh.quads[i] = q;
    mesh.quadFace[i] = f + 1;
    mesh.quadLayer[i] = k < r.quadLayer.size() ? r.quadLayer[k] : 0;
    quadUv[i] = uv;
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
