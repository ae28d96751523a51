// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file EdgeUse.cpp
/// Audit of how elements share mesh edges, in one pass over a table of element sides grouped by
/// mesh edge: inside each face (two uses running opposite ways, or one on a CAD edge; no fold),
/// over the whole mesh (no more uses than the CAD edge has faces, no duplicate element), and per
/// closed solid (each edge used once each way by the solid's oriented elements).
#include <algorithm>
#include <cmath>
#include <climits>
#include <memory>

#include "paramesh/audit/MeshAudit.hpp"

namespace paramesh {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kSegment = INT_MIN;  ///< face of a table entry that is a CAD edge's segment

/// One element side (or segment) on mesh edge (lo, hi): lo is the table row it is in.
struct Side {
  int hi;
  int face;  ///< 0-based face, kSegment for a segment
  int elem;  ///< triangle t, or triangles + quad q; for a segment its 0-based CAD edge
  bool up;   ///< the element runs from lo to hi
};

/// Element sides and segments grouped by their lower node (rows in CSR form), each row sorted
/// by (hi, face): the uses of one mesh edge are consecutive, its segment first. Linear to build.
struct EdgeTable {
  std::vector<int> start;
  std::vector<Side> sides;
};

EdgeTable buildTable(const SurfaceMesh& m, const std::vector<char>& valid, int threads) {
  const int N = (int)m.nodes.size(), T = (int)m.triangles.size(), Q = (int)m.quads.size();
  EdgeTable tab;
  tab.start.assign(N + 1, 0);
  auto each = [&](auto&& add) {
    for (int t = 0; t < T; ++t)
      if (valid[t])
        for (int i = 0; i < 3; ++i) add(m.triangles[t][i], m.triangles[t][(i + 1) % 3], m.triangleFace[t] - 1, t);
    for (int q = 0; q < Q; ++q)
      if (valid[T + q])
        for (int i = 0; i < 4; ++i) add(m.quads[q][i], m.quads[q][(i + 1) % 4], m.quadFace[q] - 1, T + q);
    for (size_t s = 0; s < m.segments.size(); ++s)
      if (valid[T + Q + s]) add(m.segments[s][0], m.segments[s][1], kSegment, m.segmentEdge[s] - 1);
  };
  each([&](int a, int b, int, int) { ++tab.start[std::min(a, b) + 1]; });
  for (int i = 0; i < N; ++i) tab.start[i + 1] += tab.start[i];
  tab.sides.resize(tab.start[N]);
  std::vector<int> fill(tab.start.begin(), tab.start.end() - 1);
  each([&](int a, int b, int face, int elem) { tab.sides[fill[std::min(a, b)]++] = {std::max(a, b), face, elem, a < b}; });
  auditChunks(N, threads, [&](int begin, int end, int) {  // rows apart: the same table for any count
    for (int i = begin; i < end; ++i)
      std::sort(tab.sides.begin() + tab.start[i], tab.sides.begin() + tab.start[i + 1],
                [](const Side& x, const Side& y) { return x.hi != y.hi ? x.hi < y.hi : x.face < y.face; });
  });
  return tab;
}

/// Element uses of each CAD edge: one per occurrence in a face's wires (a seam counts twice).
/// Coincident edges (edgeRep) share their nodes: each edge gets its whole group's uses.
std::vector<int> cadEdgeUses(const IGeometryModel& g, const std::vector<int>& rep) {
  const int E = g.numEdges();
  auto repOf = [&](int e) { return rep.size() == (size_t)E && rep[e] >= 0 && rep[e] < E ? rep[e] : e; };
  std::vector<int> uses(E, 0);
  for (int f = 0; f < g.numFaces(); ++f)
    for (const Wire& w : g.faceWires(f))
      for (const EdgeUse& u : w.uses) ++uses[repOf(u.edge)];
  std::vector<int> group(E);
  for (int e = 0; e < E; ++e) group[e] = uses[repOf(e)];
  return group;
}

/// Entities collected for one kind of finding (a few named, all counted).
struct Where {
  int count = 0;
  std::vector<int> faces, edges, solids;
  Vec3 first{0, 0, 0};  ///< where the first one is
  void at(Vec3 p, int face0, int edge0, int solid0 = -1) {
    if (!count) first = p;
    ++count;
    if (face0 >= 0) faces.push_back(face0 + 1);
    if (edge0 >= 0) edges.push_back(edge0 + 1);
    if (solid0 >= 0) solids.push_back(solid0 + 1);
  }
};

/// The finding's count into its field of r, and its line when there is one.
void tally(AuditResult& r, int& field, const std::string& what, const Where& w) {
  field = w.count;
  if (w.count) addFinding(r, what, w.count, w.faces, w.edges, w.solids, &w.first);
}

/// Is closed solid s to be checked? Not when it uses a face twice (an internal face), has a
/// face without elements (a failed face, named on its own) or is open in the CAD; note says why.
bool checkable(const IGeometryModel& g, int s, const std::vector<SolidFace>& faces, const std::vector<char>& has,
               std::string& note) {
  const std::string solid = "Solid" + std::to_string(s + 1);
  std::vector<int> seen(g.numFaces(), 0), uses(g.numEdges(), 0);
  for (const SolidFace& sf : faces) {
    const std::string face = "Face" + std::to_string(sf.face + 1);
    if (seen[sf.face]++) return note = solid + " uses " + face + " twice (an internal face): its closure is not checked", false;
    if (!has[sf.face]) return note = solid + " has " + face + " without elements: its closure is not checked", false;
    for (const Wire& w : g.faceWires(sf.face))
      for (const EdgeUse& u : w.uses) ++uses[u.edge];
  }
  for (int e = 0; e < g.numEdges(); ++e)
    if (uses[e] && uses[e] != 2 && !g.edgeDegenerate(e))
      return note = solid + " is not closed in the CAD (Edge" + std::to_string(e + 1) + " has " +
                    std::to_string(uses[e]) + " face uses): its closure is not checked",
             false;
  return true;
}

/// Sorted corner nodes of element e (4th -1 for a triangle).
std::array<int, 4> cornerSet(const SurfaceMesh& m, int e) {
  const int T = (int)m.triangles.size();
  std::array<int, 4> c{-1, -1, -1, -1};
  if (e < T) std::copy(m.triangles[e].begin(), m.triangles[e].end(), c.begin() + 1);
  else c = m.quads[e - T];
  std::sort(c.begin(), c.end());
  return c;
}

/// The whole audit of edge use, in one pass over the table's groups (one group per mesh edge).
/// Adds w's count, entities and (when into had none) first place to into.
void absorb(Where& into, const Where& w) {
  if (!w.count) return;
  if (!into.count) into.first = w.first;
  into.count += w.count;
  into.faces.insert(into.faces.end(), w.faces.begin(), w.faces.end());
  into.edges.insert(into.edges.end(), w.edges.begin(), w.edges.end());
  into.solids.insert(into.solids.end(), w.solids.begin(), w.solids.end());
}

/// The checks on each mesh edge's group of uses, over one range of table rows.
struct EdgePass {
  const AuditInput& in;
  const SurfaceMesh& m;
  const std::vector<int>& cadUses;
  const std::vector<std::vector<std::pair<int, bool>>>& solidsOf;  ///< per face: (checked solid, reversed)
  double cosFold;
  std::vector<int> bad;  ///< the folded elements
  std::vector<std::unique_ptr<ISurface>> surf;  ///< per face, made when a fold is judged
  Where holes, overFace, misFace, nonManifold, folds, duplicates, open, over, misoriented;

  bool copy(int f) const { return !in.copyFace.empty() && in.copyFace[f]; }

  /// The findings of a pass over later rows appended to these.
  void absorb(const EdgePass& o) {
    bad.insert(bad.end(), o.bad.begin(), o.bad.end());
    for (auto w : {&EdgePass::holes, &EdgePass::overFace, &EdgePass::misFace, &EdgePass::nonManifold, &EdgePass::folds,
                   &EdgePass::duplicates, &EdgePass::open, &EdgePass::over, &EdgePass::misoriented})
      paramesh::absorb(this->*w, o.*w);
  }

  void group(int lo, const Side* s, int n) {
    const Vec3 mid = 0.5 * (m.nodes[lo] + m.nodes[s[0].hi]);
    const int edge = s[0].face == kSegment ? s[0].elem : -1;
    while (n > 0 && s[0].face == kSegment) ++s, --n;  // coincident CAD edges share their segments
    if (n == 0) return;
    int uses = 0;  // a coincident face's copy shares its source's edges: not counted again
    for (int k = 0; k < n; ++k) uses += !copy(s[k].face);
    if (uses > (edge < 0 ? 2 : std::max(2, cadUses[edge]))) nonManifold.at(mid, s[0].face, edge);
    for (int a = 0; a < n;) {  // per face
      int b = a, up = 0;
      for (; b < n && s[b].face == s[a].face; ++b) up += s[b].up;
      if (b - a == 1 && edge < 0) holes.at(mid, s[a].face, -1);
      else if (b - a > 2) overFace.at(mid, s[a].face, edge);
      else if (b - a == 2 && up != 1) misFace.at(mid, s[a].face, edge);
      else if (b - a == 2 && edge < 0 && n == 2) fold(mid, s[a], s[a + 1]);
      a = b;
    }
    duplicatesOn(lo, mid, s, n);
    solidUse(mid, s, n, edge);
  }

  /// The surface itself turns over between elements a and b (normals at their (u,v) centroids
  /// more than 90 degrees apart: a crease inside the face): their fold follows it.
  bool surfaceTurns(const Side& a, const Side& b) {
    const int T = (int)m.triangles.size();
    if (in.triUv.size() != m.triangles.size() || in.quadUv.size() != m.quads.size()) return false;
    if (!surf[a.face]) surf[a.face] = in.model.makeSurface(a.face);
    Vec3 n[2];
    int k = 0;
    for (const Side* x : {&a, &b}) {
      const int e = x->elem, c = e < T ? 3 : 4;
      const Vec2* uv = e < T ? in.triUv[e].data() : in.quadUv[e - T].data();
      Vec2 ctr{0, 0};
      for (int i = 0; i < c; ++i) ctr = ctr + uv[i];
      if (!surf[a.face]->normal((1.0 / c) * ctr, n[k++])) return false;
    }
    return dot(n[0], n[1]) < 0;
  }

  void fold(Vec3 mid, const Side& a, const Side& b) {
    const Vec3 na = elementNormal(m, a.elem), nb = elementNormal(m, b.elem);
    const double l = norm(na) * norm(nb);
    if (l > 0 && dot(na, nb) < cosFold * l && !surfaceTurns(a, b)) {
      folds.at(mid, a.face, -1);
      bad.push_back(a.elem);
      bad.push_back(b.elem);
    }
  }

  /// Elements with the same corners share their two lowest corners' edge: each pair is found once,
  /// on that edge.
  void duplicatesOn(int lo, Vec3 mid, const Side* s, int n) {
    for (int a = 0; a < n; ++a) {
      if (copy(s[a].face)) continue;  // a copy repeats its source by design
      const std::array<int, 4> ca = cornerSet(m, s[a].elem);
      const int i0 = ca[0] < 0 ? 1 : 0;
      if (ca[i0] != lo || ca[i0 + 1] != s[a].hi) continue;
      for (int b = a + 1; b < n; ++b)
        if (!copy(s[b].face) && cornerSet(m, s[b].elem) == ca) {
          duplicates.at(mid, s[a].face, -1);
          duplicates.faces.push_back(s[b].face + 1);
        }
    }
  }

  void solidUse(Vec3 mid, const Side* s, int n, int edge) {
    std::pair<int, int> count[8];  // (uses, runs lo->hi) per solid touching this edge; few
    int solid[8], k = 0;
    for (int a = 0; a < n; ++a)
      for (const auto& [so, rev] : solidsOf[s[a].face]) {
        int i = 0;
        while (i < k && solid[i] != so) ++i;
        if (i == k) {
          if (k == 8) continue;
          solid[k] = so, count[k++] = {0, 0};
        }
        ++count[i].first;
        count[i].second += s[a].up != rev;
      }
    for (int i = 0; i < k; ++i) {
      const auto [uses, up] = count[i];
      Where* w = uses == 1 ? &open : uses > 2 ? &over : up != 1 ? &misoriented : nullptr;
      if (w) w->at(mid, s[0].face, edge, solid[i]);
    }
  }
};

/// Per triangle, quad and segment (in that order): its nodes and CAD entity exist. Those that do
/// not are one finding and left out of the other checks.
std::vector<char> validEntries(const IGeometryModel& g, const SurfaceMesh& m, AuditResult& r) {
  const int N = (int)m.nodes.size();
  auto nodesOk = [N](const int* c, int n) {
    for (int i = 0; i < n; ++i)
      if (c[i] < 0 || c[i] >= N) return false;
    return true;
  };
  auto in = [](int x, int n) { return x >= 1 && x <= n; };
  std::vector<char> ok;
  ok.reserve(m.triangles.size() + m.quads.size() + m.segments.size());
  for (size_t t = 0; t < m.triangles.size(); ++t)
    ok.push_back(nodesOk(m.triangles[t].data(), 3) && in(m.triangleFace[t], g.numFaces()));
  for (size_t q = 0; q < m.quads.size(); ++q) ok.push_back(nodesOk(m.quads[q].data(), 4) && in(m.quadFace[q], g.numFaces()));
  for (size_t s = 0; s < m.segments.size(); ++s)
    ok.push_back(nodesOk(m.segments[s].data(), 2) && in(m.segmentEdge[s], g.numEdges()));
  r.invalidEntries = (int)std::count(ok.begin(), ok.end(), 0);
  if (r.invalidEntries)
    addFinding(r, "elements or segments referring to a node or CAD entity that does not exist", r.invalidEntries, {});
  return ok;
}

}  // namespace

int elementFace(const SurfaceMesh& m, int e) {
  const int T = (int)m.triangles.size();
  return e < T ? m.triangleFace[e] - 1 : m.quadFace[e - T] - 1;
}

Vec3 elementNormal(const SurfaceMesh& m, int e) {
  const int T = (int)m.triangles.size();
  if (e < T) {
    const auto& t = m.triangles[e];
    return cross(m.nodes[t[1]] - m.nodes[t[0]], m.nodes[t[2]] - m.nodes[t[0]]);
  }
  const auto& q = m.quads[e - T];
  return cross(m.nodes[q[2]] - m.nodes[q[0]], m.nodes[q[3]] - m.nodes[q[1]]);
}

void auditEdgeUse(const AuditInput& in, double foldAngleDeg, AuditResult& r) {
  const IGeometryModel& g = in.model;
  const SurfaceMesh& m = in.mesh;
  const std::vector<int> cadUses = cadEdgeUses(g, in.edgeRep);
  std::vector<std::vector<std::pair<int, bool>>> solidsOf(g.numFaces());
  const double cosFold = std::cos(foldAngleDeg * kPi / 180.0);
  auto newPass = [&] {
    return std::make_unique<EdgePass>(EdgePass{in, m, cadUses, solidsOf, cosFold, {},
                                               std::vector<std::unique_ptr<ISurface>>(g.numFaces()), {}, {}, {}, {}, {},
                                               {}, {}, {}, {}});
  };
  const std::vector<char> valid = validEntries(g, m, r);
  std::vector<char> has(g.numFaces(), 0);
  const int T = (int)m.triangles.size();
  for (int t = 0; t < T; ++t)
    if (valid[t]) has[m.triangleFace[t] - 1] = 1;
  for (size_t q = 0; q < m.quads.size(); ++q)
    if (valid[T + q]) has[m.quadFace[q] - 1] = 1;
  Where empty;
  for (int f = 0; f < g.numFaces(); ++f)
    if (!has[f]) empty.at(Vec3{0, 0, 0}, f, -1);
  r.emptyFaces = empty.count;
  if (empty.count) addFinding(r, "faces without elements", empty.count, empty.faces);
  for (int s = 0; s < g.numSolids(); ++s) {
    const std::vector<SolidFace> faces = g.solidFaces(s);
    std::string note;
    if (faces.empty() || !checkable(g, s, faces, has, note)) {
      ++r.solidsSkipped;
      if (!note.empty()) r.notes.push_back(note);
      continue;
    }
    ++r.solidsChecked;
    for (const SolidFace& sf : faces) solidsOf[sf.face].emplace_back(s, sf.reversed);
  }
  const EdgeTable tab = buildTable(m, valid, in.threads);
  // rows in fixed chunks, each with its own findings, appended in row order: the outcome does
  // not depend on the thread count
  const int N = (int)tab.start.size() - 1;
  std::vector<std::unique_ptr<EdgePass>> parts((N + kAuditChunk - 1) / kAuditChunk);
  auditChunks(N, in.threads, [&](int begin, int end, int chunk) {
    parts[chunk] = newPass();
    EdgePass& part = *parts[chunk];
    for (int lo = begin; lo < end; ++lo)
      for (int a = tab.start[lo], e = tab.start[lo + 1]; a < e;) {
        int b = a;
        while (b < e && tab.sides[b].hi == tab.sides[a].hi) ++b;
        part.group(lo, &tab.sides[a], b - a);
        a = b;
      }
  });
  const std::unique_ptr<EdgePass> all = newPass();
  EdgePass& pass = *all;
  for (const auto& part : parts) pass.absorb(*part);
  r.badElements.insert(r.badElements.end(), pass.bad.begin(), pass.bad.end());
  tally(r, r.openFaceEdges, "mesh edges inside a face used by one element (a hole in the face)", pass.holes);
  tally(r, r.faceOverusedEdges, "mesh edges used by more than two elements of one face", pass.overFace);
  tally(r, r.faceMisorientedEdges, "mesh edges whose two elements of one face run the same way", pass.misFace);
  tally(r, r.nonManifoldEdges, "mesh edges used by more elements than their CAD edge has faces (non-manifold)",
        pass.nonManifold);
  tally(r, r.duplicateElements, "elements with the same nodes as another element", pass.duplicates);
  tally(r, r.folds, "edges inside a face whose two elements fold onto each other (normals over " +
                        std::to_string((int)foldAngleDeg) + " degrees apart)", pass.folds);
  tally(r, r.solidOpenEdges, "mesh edges of a closed solid used by one element (open)", pass.open);
  tally(r, r.solidOverusedEdges, "mesh edges of a closed solid used by more than two elements", pass.over);
  tally(r, r.solidMisorientedEdges, "mesh edges of a closed solid whose two elements run the same way (misoriented)",
        pass.misoriented);
}

}  // namespace paramesh
