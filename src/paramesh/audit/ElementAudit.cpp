// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file ElementAudit.cpp
/// Audit of the elements themselves: duplicates (the same nodes as another element), folds (two
/// elements of one face folded onto each other across an interior edge), elements facing against
/// their face's outward normal, and non-positive or duplicate tetrahedra.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <unordered_set>

#include "paramesh/audit/MeshAudit.hpp"

namespace paramesh {
namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3 elementNormal(const SurfaceMesh& m, int e) {  // e < T: triangle, else quad e - T
  const int T = (int)m.triangles.size();
  if (e < T) {
    const auto& t = m.triangles[e];
    return cross(m.nodes[t[1]] - m.nodes[t[0]], m.nodes[t[2]] - m.nodes[t[0]]);
  }
  const auto& q = m.quads[e - T];
  return cross(m.nodes[q[2]] - m.nodes[q[0]], m.nodes[q[3]] - m.nodes[q[1]]);
}

/// (u,v) where the surface degenerates (a pole, an apex): one of S_u, S_v vanishes against the other.
bool atSingularPoint(const ISurface& s, Vec2 uv) {
  Vec3 p, du, dv;
  s.d1(uv, p, du, dv);
  const double a = norm(du), b = norm(dv);
  return !(std::min(a, b) > 1e-9 * std::max(a, b));
}

int elementFace(const SurfaceMesh& m, int e) {
  const int T = (int)m.triangles.size();
  return e < T ? m.triangleFace[e] - 1 : m.quadFace[e - T] - 1;
}

template <size_t N>
int countDuplicates(const std::vector<std::array<int, N>>& elems, const std::vector<int>* face,
                    const std::vector<char>& copyFace, std::vector<int>& faces) {
  std::vector<std::pair<std::array<int, N>, int>> keys;
  keys.reserve(elems.size());
  for (size_t i = 0; i < elems.size(); ++i) {
    const int f = face ? (*face)[i] - 1 : -1;
    if (f >= 0 && !copyFace.empty() && copyFace[f]) continue;  // a copy repeats its source by design
    std::array<int, N> k = elems[i];
    std::sort(k.begin(), k.end());
    keys.emplace_back(k, f);
  }
  std::sort(keys.begin(), keys.end());
  int n = 0;
  for (size_t i = 1; i < keys.size(); ++i)
    if (keys[i].first == keys[i - 1].first) {
      ++n;
      if (keys[i].second >= 0) faces.insert(faces.end(), {keys[i - 1].second + 1, keys[i].second + 1});
    }
  return n;
}

void auditDuplicates(const AuditInput& in, AuditResult& r) {
  const SurfaceMesh& m = in.mesh;
  std::vector<int> faces;
  r.duplicateElements = countDuplicates(m.triangles, &m.triangleFace, in.copyFace, faces) +
                        countDuplicates(m.quads, &m.quadFace, in.copyFace, faces);
  if (r.duplicateElements) addFinding(r, "elements with the same nodes as another element", r.duplicateElements, faces);
  std::vector<int> none;
  r.duplicateTets = countDuplicates(m.tets, nullptr, in.copyFace, none);
  int inverted = 0;
  std::vector<int> solids;
  for (size_t k = 0; k < m.tets.size(); ++k) {
    const auto& t = m.tets[k];
    const Vec3 a = m.nodes[t[0]];
    if (!(dot(cross(m.nodes[t[1]] - a, m.nodes[t[2]] - a), m.nodes[t[3]] - a) > 0)) {
      ++inverted;
      solids.push_back(m.tetSolid[k]);
    }
  }
  r.invertedTets = inverted;
  if (r.duplicateTets) addFinding(r, "tetrahedra with the same nodes as another", r.duplicateTets, {});
  if (inverted) addFinding(r, "tetrahedra of zero or negative volume", inverted, {}, {}, solids);
}

/// Interior edges of a face (two elements of that face, not on a CAD edge) folding beyond the angle.
void auditFolds(const AuditInput& in, double foldAngleDeg, AuditResult& r) {
  const SurfaceMesh& m = in.mesh;
  std::unordered_set<uint64_t> onCad;
  auto key = [](int a, int b) { return ((uint64_t)(uint32_t)std::min(a, b) << 32) | (uint32_t)std::max(a, b); };
  for (const auto& s : m.segments) onCad.insert(key(s[0], s[1]));
  struct Side {
    uint64_t key;
    int elem;
  };
  std::vector<Side> sides;
  const int T = (int)m.triangles.size();
  for (int t = 0; t < T; ++t)
    for (int i = 0; i < 3; ++i) sides.push_back({key(m.triangles[t][i], m.triangles[t][(i + 1) % 3]), t});
  for (int q = 0; q < (int)m.quads.size(); ++q)
    for (int i = 0; i < 4; ++i) sides.push_back({key(m.quads[q][i], m.quads[q][(i + 1) % 4]), T + q});
  std::sort(sides.begin(), sides.end(), [](const Side& a, const Side& b) { return a.key < b.key; });
  const double cosFold = std::cos(foldAngleDeg * kPi / 180.0);
  std::vector<int> faces;
  int folds = 0;
  for (size_t i = 0; i + 1 < sides.size(); ++i) {
    if (sides[i].key != sides[i + 1].key || (i + 2 < sides.size() && sides[i + 2].key == sides[i].key)) continue;
    if ((i > 0 && sides[i - 1].key == sides[i].key) || onCad.count(sides[i].key)) continue;
    const int a = sides[i].elem, b = sides[i + 1].elem;
    if (elementFace(m, a) != elementFace(m, b)) continue;
    const Vec3 na = elementNormal(m, a), nb = elementNormal(m, b);
    const double l = norm(na) * norm(nb);
    if (l > 0 && dot(na, nb) < cosFold * l) {
      ++folds;
      faces.push_back(elementFace(m, a) + 1);
    }
  }
  r.folds = folds;
  if (folds)
    addFinding(r, "edges inside a face whose two elements fold onto each other (normals over " +
                      std::to_string((int)foldAngleDeg) + " degrees apart)", folds, faces);
}

/// Elements whose normal points against their face's outward normal at their (u,v) centroid.
void auditOrientation(const AuditInput& in, AuditResult& r) {
  const SurfaceMesh& m = in.mesh;
  if (in.triUv.size() != m.triangles.size() || in.quadUv.size() != m.quads.size()) {
    r.notes.push_back("the elements' (u,v) are not known: their orientation against the surface is not checked");
    return;
  }
  const IGeometryModel& g = in.model;
  std::vector<std::unique_ptr<ISurface>> surf(g.numFaces());
  std::vector<int> faces;
  int inverted = 0;
  const int T = (int)m.triangles.size(), Q = (int)m.quads.size();
  for (int e = 0; e < T + Q; ++e) {
    const int f = elementFace(m, e);
    if (f < 0 || (!in.copyFace.empty() && in.copyFace[f])) continue;
    if (!surf[f]) surf[f] = g.makeSurface(f);
    const Vec2* uv = e < T ? in.triUv[e].data() : in.quadUv[e - T].data();
    const int corners = e < T ? 3 : 4;
    Vec2 c{0, 0};
    int used = 0;
    for (int i = 0; i < corners; ++i)  // a corner at a pole or apex has an arbitrary u (or v)
      if (!atSingularPoint(*surf[f], uv[i])) c = c + uv[i], ++used;
    if (!used) continue;
    c = (1.0 / used) * c;
    Vec3 n;
    if (!surf[f]->normal(c, n)) continue;
    if (g.faceReversed(f)) n = -1.0 * n;
    if (dot(elementNormal(m, e), n) < 0) {
      ++inverted;
      faces.push_back(f + 1);
    }
  }
  r.invertedElements = inverted;
  if (inverted) addFinding(r, "elements facing against their face's outward normal", inverted, faces);
}

}  // namespace

void auditElements(const AuditInput& in, double foldAngleDeg, AuditResult& r) {
  auditDuplicates(in, r);
  auditFolds(in, foldAngleDeg, r);
  auditOrientation(in, r);
}

}  // namespace paramesh
