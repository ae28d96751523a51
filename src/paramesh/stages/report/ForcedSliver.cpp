// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file ForcedSliver.cpp
/// Report: the CAD edge forcing the worst triangle, when one does (ForcedSliver.hpp).
#include "paramesh/stages/report/ForcedSliver.hpp"

#include <algorithm>
#include <cstdio>
#include <vector>

#include "paramesh/algo/SurfaceContext.hpp"

namespace paramesh {
namespace {
// a CAD edge forces the sliver when shorter than this share of the size, or than this share of
// a neighbouring edge of the face at a corner of the triangle (and shorter than the size)
constexpr double kFarShorter = 0.25;

std::string num(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", x);
  return b;
}
}  // namespace

std::string forcedSliverWarning(const SurfaceMesh& mesh, const IGeometryModel& model, const SizeField& field) {
  const auto& N = mesh.nodes;
  int worst = -1;
  double q = kForcedBelow;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& T = mesh.triangles[t];
    const double g = gamma3(N[T[0]], N[T[1]], N[T[2]]);
    if (g < q) {
      q = g;
      worst = (int)t;
    }
  }
  if (worst < 0) return "";
  const auto& T = mesh.triangles[worst];
  // on the CAD: all three nodes, or the two ends of a side lying along a tiny edge (whatever the
  // apex, a triangle on a side e long stands at least about 2 e / gamma from it)
  int onCad = 0, apex = -1;
  for (int k = 0; k < 3; ++k) {
    const NodeKind kind = mesh.nodeKind[T[k]];
    if (kind == NodeKind::Vertex || kind == NodeKind::Edge) ++onCad;
    else apex = k;
  }
  if (onCad < 2) return "";
  const int face = mesh.triangleFace[worst] - 1;
  if (face < 0 || face >= model.numFaces()) return "";
  // the face's edges and their meshed lengths (the sum of their segments)
  std::vector<double> length(model.numEdges(), 0.0);
  for (size_t s = 0; s < mesh.segments.size(); ++s) {
    const int e = mesh.segmentEdge[s] - 1;
    if (e >= 0 && e < (int)length.size()) length[e] += dist(N[mesh.segments[s][0]], N[mesh.segments[s][1]]);
  }
  std::vector<int> faceEdges;
  for (const Wire& w : model.faceWires(face))
    for (const EdgeUse& u : w.uses)
      if (!model.edgeDegenerate(u.edge)) faceEdges.push_back(u.edge);
  const double h = field.size((1.0 / 3) * (N[T[0]] + N[T[1]] + N[T[2]]));
  // the face's edges at the triangle's nodes: a node's own edge, a vertex's edges in the face
  int forcing = -1;
  double best = 1e300;
  auto consider = [&](int e, double neighbour) {
    const double L = length[e];
    if (!(L > 0)) return;
    const bool tiny = L < kFarShorter * h, corner = onCad == 3 && L < h && L < kFarShorter * neighbour;
    if ((tiny || corner) && L < best) {
      best = L;
      forcing = e;
    }
  };
  for (int k = 0; k < 3; ++k) {
    if (k == apex) continue;
    const int v = T[k], ent = mesh.nodeEntity[v] - 1;
    if (mesh.nodeKind[v] == NodeKind::Edge) {
      if (std::find(faceEdges.begin(), faceEdges.end(), ent) != faceEdges.end()) consider(ent, 0);
      continue;
    }
    std::vector<int> at;  // the face's edges ending at this vertex
    for (int e : faceEdges)
      if (model.edgeVertex(e, 0) == ent || model.edgeVertex(e, 1) == ent) at.push_back(e);
    double longest = 0;
    for (int e : at) longest = std::max(longest, length[e]);
    for (int e : at) consider(e, longest);
  }
  if (forcing < 0) return "";
  return "the worst triangle, gamma " + num(q) + " on Face" + std::to_string(face + 1) + ", is forced by Edge" +
         std::to_string(forcing + 1) + " (length " + num(best) + ", h " + num(h) + ")";
}

}  // namespace paramesh
