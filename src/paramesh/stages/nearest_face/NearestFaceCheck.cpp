// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file NearestFaceCheck.cpp
/// Nearest-face stage, the check: triangles whose centroid lies nearer another CAD face than
/// their own, their size sources or local deviation bounds; and the state a round is rolled back
/// to. Reads mesh, offSurface, triDeviation; writes report.nearestFace*, rounds.zones, rounds.zonesAdded.
#include <algorithm>
#include <memory>
#include <vector>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/pipeline/Tuning.hpp"

namespace paramesh {

using namespace tuning;

NearestFaceResult MeshContext::nearestFaceCheck() {
  Timer tm;
  // the other face's CAD distance: projection on its surface from the (u,v) of the nearest
  // point of its mesh
  std::vector<std::unique_ptr<ISurface>> surf(model.numFaces());
  auto faceDistance = [&](Vec3 c, int tri, Vec3 q, Vec3* foot) {
    const auto& T = mesh.triangles[tri];
    const Vec3 &a = mesh.nodes[T[0]], &b = mesh.nodes[T[1]], &d = mesh.nodes[T[2]];
    const double meshDist = dist(c, q);
    const int f = mesh.triangleFace[tri] - 1;
    try {
      if (!surf[f]) surf[f] = model.makeSurface(f);
      // barycentric coordinates of q
      const Vec3 n = cross(b - a, d - a);
      const double n2 = norm2(n);
      if (!(n2 > 0)) return meshDist;
      const double wb = dot(cross(q - a, d - a), n) / n2, wd = dot(cross(b - a, q - a), n) / n2;
      const auto& uv = triUv[tri];
      Vec2 s = (1 - wb - wd) * uv[0] + wb * uv[1] + wd * uv[2];
      Vec3 x;
      if (!surf[f]->project(c, s, &x)) return meshDist;
      *foot = x;
      return dist(c, x);
    } catch (...) {
      return meshDist;
    }
  };
  const NearestFaceResult r = nearestFaceSources(mesh, offSurface, p.minSize, &triDeviation, faceDistance);
  report.nearestFaceFlagged.push_back(r.flagged);
  if (r.flagged)
    log.info("nearest-face check: " + std::to_string(r.flagged) +
             " triangles lie nearer another face than their own" +
             (r.sources.empty() ? " (already at min-size)" : ": refined"));
  stage("nearest_face_check", tm.seconds());
  return r;
}

std::vector<char> MeshContext::addDeviationZones(const NearestFaceResult& r) {
  const int nf = model.numFaces();
  rounds.zones.resize(nf);
  rounds.zonesAdded.assign(nf, 0);
  std::vector<char> added(r.found.size(), 0);
  std::vector<size_t> before(nf);
  for (int f = 0; f < nf; ++f) before[f] = rounds.zones[f].size();
  for (size_t k = 0; k < r.found.size(); ++k) {
    const int t = (int)r.found[k][0];
    const int f = mesh.triangleFace[t] - 1;
    const auto& T = mesh.triangles[t];
    const Vec3 c = (1.0 / 3) * (mesh.nodes[T[0]] + mesh.nodes[T[1]] + mesh.nodes[T[2]]);
    DeviationZone z;
    z.center = c;
    for (int v : T) z.radius = std::max(z.radius, dist(c, mesh.nodes[v]));
    z.fraction = kZoneFraction;
    z.floor = kOffSurfaceCandidate * std::min(p.size, p.maxSize);
    if (dist(c, r.otherFoot[k]) > 0) {
      z.otherPoint = r.otherFoot[k];
      z.otherNormal = normalized(c - r.otherFoot[k]);
    } else {
      z.allowed = z.fraction * r.found[k][2];
    }
    bool known = false;
    for (size_t i = 0; i < before[f]; ++i) known = known || rounds.zones[f][i].bound(c) <= z.bound(c);
    if (known) continue;
    rounds.zones[f].push_back(z);
    rounds.zonesAdded[f] = 1;
    added[k] = 1;
  }
  return added;
}

MeshContext::MeshState MeshContext::saveState() const {
  return {mesh, field, edges, vertexNode, triUv, quadUv, segmentT, report.faces, blStats, blEmpty, blDropped};
}

void MeshContext::restoreState(MeshState&& st) {
  mesh = std::move(st.mesh);
  field = std::move(st.field);
  edges = std::move(st.edges);
  vertexNode = std::move(st.vertexNode);
  triUv = std::move(st.triUv);
  quadUv = std::move(st.quadUv);
  segmentT = std::move(st.segmentT);
  report.faces = std::move(st.faces);
  blStats = std::move(st.blStats);
  blEmpty = std::move(st.blEmpty);
  blDropped = std::move(st.blDropped);
  offSurface.clear();
  triDeviation.clear();
}

void MeshContext::resetMesh() {
  SurfaceMesh m;
  m.numFaces = mesh.numFaces;
  m.numEdges = mesh.numEdges;
  m.numVertices = mesh.numVertices;
  m.numSolids = mesh.numSolids;
  m.groups = mesh.groups;
  mesh = std::move(m);
  edges.clear();
  vertexNode.clear();
  triUv.clear();
  quadUv.clear();
  segmentT.clear();
  offSurface.clear();
  triDeviation.clear();
  blStats.assign(blStats.size(), FaceBLResult::SpecStats());
}

}  // namespace paramesh
