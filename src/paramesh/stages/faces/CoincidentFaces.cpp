// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file CoincidentFaces.cpp
/// Faces that coincide without being shared in the topology (touching solids exported apart, a
/// loose copy of a face beside its solid): the second is not meshed, it takes the first one's
/// triangles (same nodes, its own orientation), so the mesh is conformal across the contact.
/// Reads same.faceCandidate, the face results; writes faceStage.copyOf, the copies' results,
/// report.coincidentFaces.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "paramesh/pipeline/MeshContext.hpp"

namespace paramesh {

namespace {

/// u (or v) shifted by whole periods to within half a period of ref.
double unwrap(double x, double ref, double period) {
  return period > 0 ? x - period * std::round((x - ref) / period) : x;
}

}  // namespace

bool MeshContext::isCoincidentCopy(int f) const {
  return f < (int)same.faceCandidate.size() && same.faceCandidate[f] != f;
}

bool MeshContext::copyFaceMesh(int f, int src, const FaceMeshResult& from, FaceMeshResult& to) const {
  if (!from.ok || from.tris.empty() || !from.quads.empty()) return false;
  const auto sa = model.makeSurface(src);
  const auto sb = model.makeSurface(f);
  const double tol = 2.0 * std::max(model.faceTolerance(src), model.faceTolerance(f)) +
                     1e-6 * model.boundingBox().diagonal();
  auto xyzOf = [&](int v) { return v < 0 ? from.newXyz[-v - 1] : mesh.nodes[v]; };
  std::vector<std::array<Vec2, 3>> uvB(from.tris.size());
  Vec2 seed{0, 0};
  bool seeded = false;
  auto onB = [&](const Vec3& x, Vec2& uv) {
    Vec3 foot;
    if (seeded) {
      uv = seed;
      if (sb->project(x, uv, &foot) && dist(foot, x) <= tol) return seed = uv, true;
    }
    if (!sb->projectGlobal(x, uv, &foot) || dist(foot, x) > tol) return false;
    seeded = true;
    seed = uv;
    return true;
  };
  for (std::size_t t = 0; t < from.tris.size(); ++t) {
    for (int k = 0; k < 3; ++k)
      if (!onB(xyzOf(from.tris[t][k]), uvB[t][k])) return false;
    // the triangle's inside too: the source surface at its (u,v) centroid lies on the copy
    const Vec2 c = (1.0 / 3.0) * (from.triUv[t][0] + from.triUv[t][1] + from.triUv[t][2]);
    Vec2 uc;
    if (!onB(sa->eval(c), uc)) return false;
    for (int k = 1; k < 3; ++k) {
      uvB[t][k].x = unwrap(uvB[t][k].x, uvB[t][0].x, sb->uPeriod());
      uvB[t][k].y = unwrap(uvB[t][k].y, uvB[t][0].y, sb->vPeriod());
    }
  }
  to = FaceMeshResult();
  to.ok = true;
  to.tris = from.tris;
  to.triUv = std::move(uvB);
  return true;
}

void MeshContext::resolveCoincidentFaces(std::vector<FaceMeshResult>& results, const FaceMeshOptions& fo,
                                         const std::vector<char>& reused) {
  const int nf = model.numFaces();
  faceStage.copyOf.assign(nf, -1);
  report.coincidentFaces.clear();
  for (int f = 0; f < nf; ++f) {
    if (!isCoincidentCopy(f) || reused[f]) continue;
    const int src = same.faceCandidate[f];
    if (faceStage.copyOf[src] < 0 && copyFaceMesh(f, src, results[src], results[f])) {
      faceStage.copyOf[f] = src;
      report.faces[f].face = f + 1;
      report.faces[f].ok = true;
      report.faces[f].surface = report.faces[src].surface;
      report.coincidentFaces.push_back({src + 1, f + 1});
      log.info("Face" + std::to_string(src + 1) + " and Face" + std::to_string(f + 1) + " coincide: meshed once");
    } else {
      meshOneFace(f, fo, results[f]);  // same boundary, another surface region: a face of its own
    }
  }
}

}  // namespace paramesh
