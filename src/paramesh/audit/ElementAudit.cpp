// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file ElementAudit.cpp
/// Audit of the elements themselves: elements facing against their face's outward normal, and
/// non-positive or duplicate tetrahedra (duplicates and folds of surface elements: EdgeUse.cpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>

#include "paramesh/audit/MeshAudit.hpp"

namespace paramesh {
namespace {

/// (u,v) where the surface degenerates (a pole, an apex): one of S_u, S_v vanishes against the other.
bool atSingularPoint(const ISurface& s, Vec2 uv) {
  Vec3 p, du, dv;
  s.d1(uv, p, du, dv);
  const double a = norm(du), b = norm(dv);
  return !(std::min(a, b) > 1e-9 * std::max(a, b));
}

int countDuplicates(const std::vector<std::array<int, 4>>& tets) {
  std::vector<std::array<int, 4>> keys(tets);
  for (auto& k : keys) std::sort(k.begin(), k.end());
  std::sort(keys.begin(), keys.end());
  int n = 0;
  for (size_t i = 1; i < keys.size(); ++i) n += keys[i] == keys[i - 1];
  return n;
}

void auditTets(const AuditInput& in, AuditResult& r) {
  const SurfaceMesh& m = in.mesh;
  r.duplicateTets = countDuplicates(m.tets);
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

/// Elements whose normal points against their face's outward normal at their (u,v) centroid.
void auditOrientation(const AuditInput& in, AuditResult& r) {
  const SurfaceMesh& m = in.mesh;
  if (in.triUv.size() != m.triangles.size() || in.quadUv.size() != m.quads.size()) {
    r.notes.push_back("the elements' (u,v) are not known: their orientation against the surface is not checked");
    return;
  }
  const IGeometryModel& g = in.model;
  std::vector<char> hasDegenerateEdge(g.numFaces(), 0);  // where a pole or apex may be
  for (int f = 0; f < g.numFaces(); ++f)
    for (const Wire& w : g.faceWires(f))
      for (const EdgeUse& u : w.uses) hasDegenerateEdge[f] |= g.edgeDegenerate(u.edge);
  struct Part {
    std::vector<int> bad, faces;
    Vec3 first{0, 0, 0};
  };
  const int T = (int)m.triangles.size(), Q = (int)m.quads.size();
  std::vector<Part> parts((T + Q + kAuditChunk - 1) / kAuditChunk);
  auditChunks(T + Q, in.threads, [&](int begin, int end, int chunk) {
    Part& part = parts[chunk];
    std::vector<std::unique_ptr<ISurface>> surf(g.numFaces());  // one thread's evaluators
    for (int e = begin; e < end; ++e) {
      const int f = elementFace(m, e);
      if (f < 0 || (!in.copyFace.empty() && in.copyFace[f])) continue;
      if (!surf[f]) surf[f] = g.makeSurface(f);
      const Vec2* uv = e < T ? in.triUv[e].data() : in.quadUv[e - T].data();
      const int corners = e < T ? 3 : 4;
      bool singular[4] = {false, false, false, false};  // a corner at a pole or apex has an arbitrary u (or v)
      Vec2 c{0, 0};
      int used = 0;
      for (int i = 0; i < corners; ++i) {
        singular[i] = hasDegenerateEdge[f] && atSingularPoint(*surf[f], uv[i]);
        if (!singular[i]) c = c + uv[i], ++used;
      }
      if (!used) continue;
      c = (1.0 / used) * c;
      Vec3 n;
      if (!surf[f]->normal(c, n)) continue;
      if (g.faceReversed(f)) n = -1.0 * n;
      const Vec3 en = elementNormal(m, e);
      bool against = dot(en, n) < 0;
      for (int i = 0; i < corners && against; ++i) {  // where the surface turns over (a crease inside
        Vec3 nc;                                      // the face) some corner sees it facing along
        if (singular[i] || !surf[f]->normal(uv[i], nc)) continue;
        if (g.faceReversed(f)) nc = -1.0 * nc;
        against = dot(en, nc) < 0;
      }
      if (against) {
        if (part.bad.empty()) part.first = surf[f]->eval(c);
        part.bad.push_back(e);
        part.faces.push_back(f + 1);
      }
    }
  });
  std::vector<int> faces;
  const Vec3* first = nullptr;
  for (const Part& part : parts) {
    if (!first && !part.bad.empty()) first = &part.first;
    r.badElements.insert(r.badElements.end(), part.bad.begin(), part.bad.end());
    faces.insert(faces.end(), part.faces.begin(), part.faces.end());
    r.invertedElements += (int)part.bad.size();
  }
  if (r.invertedElements)
    addFinding(r, "elements facing against their face's outward normal", r.invertedElements, faces, {}, {}, first);
}

}  // namespace

void auditElements(const AuditInput& in, AuditResult& r) {
  auditTets(in, r);
  auditOrientation(in, r);
}

}  // namespace paramesh
