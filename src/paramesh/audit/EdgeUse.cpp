// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file EdgeUse.cpp
/// Audit of how elements share mesh edges: inside each face (two uses running opposite ways, or one
/// on a CAD edge), over the whole mesh (no more uses than the CAD edge has faces), and per closed
/// solid (each edge used once each way by the solid's oriented elements).
#include <algorithm>
#include <cstdint>
#include <unordered_map>

#include "paramesh/audit/MeshAudit.hpp"

namespace paramesh {
namespace {

uint64_t edgeKey(int a, int b) {
  const uint32_t lo = (uint32_t)std::min(a, b), hi = (uint32_t)std::max(a, b);
  return ((uint64_t)lo << 32) | hi;
}

/// One element side: its mesh edge, the face (0-based), and whether it runs from the lower node.
struct HalfEdge {
  uint64_t key;
  int face;
  bool up;
};

std::vector<HalfEdge> halfEdges(const SurfaceMesh& m) {
  std::vector<HalfEdge> h;
  h.reserve(3 * m.triangles.size() + 4 * m.quads.size());
  auto add = [&](const int* c, int n, int face) {
    for (int i = 0; i < n; ++i) {
      const int a = c[i], b = c[(i + 1) % n];
      h.push_back({edgeKey(a, b), face - 1, a < b});
    }
  };
  for (size_t t = 0; t < m.triangles.size(); ++t) add(m.triangles[t].data(), 3, m.triangleFace[t]);
  for (size_t q = 0; q < m.quads.size(); ++q) add(m.quads[q].data(), 4, m.quadFace[q]);
  std::sort(h.begin(), h.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.key != y.key ? x.key < y.key : x.face < y.face;
  });
  return h;
}

/// Element uses of each CAD edge: one per occurrence in a face's wires (a seam counts twice).
std::vector<int> cadEdgeUses(const IGeometryModel& g) {
  std::vector<int> uses(g.numEdges(), 0);
  for (int f = 0; f < g.numFaces(); ++f)
    for (const Wire& w : g.faceWires(f))
      for (const EdgeUse& u : w.uses) ++uses[u.edge];
  return uses;
}

/// Entities collected for one kind of finding (a few named, all counted).
struct Where {
  int count = 0;
  std::vector<int> faces, edges, solids;
  void at(int face0, int edge0) {
    ++count;
    if (face0 >= 0) faces.push_back(face0 + 1);
    if (edge0 >= 0) edges.push_back(edge0 + 1);
  }
};

/// The finding's count into its field of r, and its line when there is one.
void tally(AuditResult& r, int& field, const std::string& what, const Where& w) {
  field = w.count;
  if (w.count) addFinding(r, what, w.count, w.faces, w.edges, w.solids);
}

/// Faces and CAD closure of solid s: false (with the reason in note) when it is not checked.
bool closedInCad(const IGeometryModel& g, int s, const std::vector<SolidFace>& faces, std::string& note) {
  std::vector<int> seen(g.numFaces(), 0);
  std::unordered_map<int, int> uses;
  for (const SolidFace& sf : faces) {
    if (seen[sf.face]++) {
      note = "Solid" + std::to_string(s + 1) + " uses Face" + std::to_string(sf.face + 1) +
             " twice (an internal face): its closure is not checked";
      return false;
    }
    for (const Wire& w : g.faceWires(sf.face))
      for (const EdgeUse& u : w.uses) ++uses[u.edge];
  }
  for (const auto& [e, n] : uses)
    if (n != 2 && !g.edgeDegenerate(e)) {
      note = "Solid" + std::to_string(s + 1) + " is not closed in the CAD (Edge" + std::to_string(e + 1) +
             " has " + std::to_string(n) + " face uses): its closure is not checked";
      return false;
    }
  return true;
}

/// Per 0-based face: it has at least one element.
std::vector<char> facesWithElements(const IGeometryModel& g, const SurfaceMesh& m) {
  std::vector<char> has(g.numFaces(), 0);
  for (int f : m.triangleFace) has[f - 1] = 1;
  for (int f : m.quadFace) has[f - 1] = 1;
  return has;
}

/// A face without elements (one that failed) is one finding; the solids it bounds are not
/// checked for closure (their open edges would only repeat it).
bool hasEmptyFace(const std::vector<SolidFace>& faces, const std::vector<char>& has, int s, std::string& note) {
  for (const SolidFace& sf : faces)
    if (!has[sf.face]) {
      note = "Solid" + std::to_string(s + 1) + " has Face" + std::to_string(sf.face + 1) +
             " without elements: its closure is not checked";
      return true;
    }
  return false;
}

void auditSolids(const AuditInput& in, const std::vector<HalfEdge>& all,
                 const std::unordered_map<uint64_t, int>& cadEdgeOf, AuditResult& r) {
  const IGeometryModel& g = in.model;
  const std::vector<char> has = facesWithElements(g, in.mesh);
  Where empty;
  for (int f = 0; f < g.numFaces(); ++f)
    if (!has[f]) empty.at(f, -1);
  tally(r, r.emptyFaces, "faces without elements", empty);
  Where open, over, misoriented;
  for (int s = 0; s < g.numSolids(); ++s) {
    const std::vector<SolidFace> faces = g.solidFaces(s);
    std::string note;
    if (faces.empty() || hasEmptyFace(faces, has, s, note) || !closedInCad(g, s, faces, note)) {
      ++r.solidsSkipped;
      if (!note.empty()) r.notes.push_back(note);
      continue;
    }
    ++r.solidsChecked;
    std::vector<int> flip(g.numFaces(), -1);  // -1: not in the solid, 0: as is, 1: reversed
    for (const SolidFace& sf : faces) flip[sf.face] = sf.reversed;
    size_t i = 0;
    while (i < all.size()) {
      size_t j = i;
      int n = 0, up = 0, face = -1;
      for (; j < all.size() && all[j].key == all[i].key; ++j) {
        if (flip[all[j].face] < 0) continue;
        ++n;
        up += all[j].up != (flip[all[j].face] == 1);
        face = all[j].face;
      }
      if (n > 0) {
        const auto e = cadEdgeOf.find(all[i].key);
        const int edge = e == cadEdgeOf.end() ? -1 : e->second;
        Where* w = n == 1 ? &open : n > 2 ? &over : up != 1 ? &misoriented : nullptr;
        if (w) {
          w->at(face, edge);
          w->solids.push_back(s + 1);
        }
      }
      i = j;
    }
  }
  tally(r, r.solidOpenEdges, "mesh edges of a closed solid used by one element (open)", open);
  tally(r, r.solidOverusedEdges, "mesh edges of a closed solid used by more than two elements", over);
  tally(r, r.solidMisorientedEdges, "mesh edges of a closed solid whose two elements run the same way (misoriented)",
        misoriented);
}

}  // namespace

void auditEdgeUse(const AuditInput& in, AuditResult& r) {
  const SurfaceMesh& m = in.mesh;
  std::unordered_map<uint64_t, int> cadEdgeOf;  // mesh edge on a CAD edge -> 0-based edge
  cadEdgeOf.reserve(m.segments.size());
  for (size_t k = 0; k < m.segments.size(); ++k)
    cadEdgeOf.emplace(edgeKey(m.segments[k][0], m.segments[k][1]), m.segmentEdge[k] - 1);
  const std::vector<int> cadUses = cadEdgeUses(in.model);
  const std::vector<HalfEdge> all = halfEdges(m);
  Where holes, overFace, misFace, nonManifold;
  size_t i = 0;
  while (i < all.size()) {
    size_t j = i;
    while (j < all.size() && all[j].key == all[i].key) ++j;
    const auto e = cadEdgeOf.find(all[i].key);
    const int edge = e == cadEdgeOf.end() ? -1 : e->second;
    const int expected = edge < 0 ? 2 : std::max(2, cadUses[edge]);
    int uses = 0;  // a coincident face's copy shares its source's edges: not counted again
    for (size_t a = i; a < j; ++a) uses += in.copyFace.empty() || !in.copyFace[all[a].face];
    if (uses > expected) nonManifold.at(all[i].face, edge);
    for (size_t a = i; a < j;) {  // per face
      size_t b = a;
      int up = 0;
      for (; b < j && all[b].face == all[a].face; ++b) up += all[b].up;
      const int n = (int)(b - a);
      if (n == 1 && edge < 0) holes.at(all[a].face, -1);
      else if (n > 2) overFace.at(all[a].face, edge);
      else if (n == 2 && up != 1) misFace.at(all[a].face, edge);
      a = b;
    }
    i = j;
  }
  tally(r, r.openFaceEdges, "mesh edges inside a face used by one element (a hole in the face)", holes);
  tally(r, r.faceOverusedEdges, "mesh edges used by more than two elements of one face", overFace);
  tally(r, r.faceMisorientedEdges, "mesh edges whose two elements of one face run the same way", misFace);
  tally(r, r.nonManifoldEdges, "mesh edges used by more elements than their CAD edge has faces (non-manifold)",
        nonManifold);
  auditSolids(in, all, cadEdgeOf, r);
}

}  // namespace paramesh
