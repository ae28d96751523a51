// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file FuzzSupport.hpp
/// What the libFuzzer harnesses share: the finding (abort, so libFuzzer keeps the input), the
/// one-line rule of paramesh::Error, the signal handlers around OccReaderSignalGuard, outcome
/// counters printed at exit, and the independent mesh checks of the geometry harness.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <csignal>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "paramesh/geom/Geometry.hpp"
#include "paramesh/mesh/SurfaceMesh.hpp"
#include "paramesh/pipeline/Report.hpp"

namespace paramesh::fuzz {

/// A finding: the message on stderr, then abort() (libFuzzer writes the input to crash-<sha1>).
[[noreturn]] inline void finding(const char* fmt, ...) {
  std::va_list ap;
  va_start(ap, fmt);
  std::fputs("==paramesh-fuzz== FINDING: ", stderr);
  std::vfprintf(stderr, fmt, ap);
  std::fputc('\n', stderr);
  va_end(ap);
  std::abort();
}

/// Environment switches (0 when unset).
inline bool envFlag(const char* name) {
  const char* v = std::getenv(name);
  return v && *v && std::strcmp(v, "0") != 0;
}

/// Open bugs the harness lets pass, so that a campaign can go on past them: the names in
/// PARAMESH_FUZZ_KNOWN (comma-separated; scripts/fuzz.sh sets it from the "known NAME" lines of
/// fuzz/regressions/OPEN). Each such input is counted as "known: NAME", never silently.
inline bool known(const char* name) {
  const char* v = std::getenv("PARAMESH_FUZZ_KNOWN");
  if (!v) return false;
  const std::string list = std::string(",") + v + ",";
  return list.find(std::string(",") + name + ",") != std::string::npos;
}

/// paramesh::Error's contract (util/Error.hpp): what() is one non-empty, user-readable line
/// (a key or value of the input quoted back has its control characters escaped).
inline void requireOneLine(const char* what, const char* kind) {
  const std::string s = what ? what : "";
  if (s.empty()) finding("%s with an empty message", kind);
  if (s.find('\n') != std::string::npos || s.find('\r') != std::string::npos)
    finding("%s message is not one line: '%s'", kind, s.c_str());
}

/// The outcome to count for a refusal with message `what` (checked by requireOneLine).
inline std::string refusal(const char* what, const char* kind, const char* outcome) {
  requireOneLine(what, kind);
  return outcome;
}

/// Every signal disposition, saved and put back: OccReaderSignalGuard's destructor restores the
/// system default (SIG_DFL), which would drop the handlers of ASan and libFuzzer (a later SEGV
/// would then end the process without a report and without the crash input).
class SavedSignals {
 public:
  SavedSignals() {
    for (int s = 1; s < kN; ++s)
      if (s != SIGKILL && s != SIGSTOP) sigaction(s, nullptr, &old_[s]);
  }
  ~SavedSignals() {
    for (int s = 1; s < kN; ++s)
      if (s != SIGKILL && s != SIGSTOP) sigaction(s, &old_[s], nullptr);
  }
  SavedSignals(const SavedSignals&) = delete;
  SavedSignals& operator=(const SavedSignals&) = delete;

 private:
  static constexpr int kN = 32;
  struct sigaction old_[kN] = {};
};

/// Outcome counts of a harness, printed every 2^k executions and at exit (libFuzzer's own
/// statistics do not say how many inputs were refused and how many got through).
class Outcomes {
 public:
  explicit Outcomes(std::string harness) : harness_(std::move(harness)) { std::atexit(&Outcomes::printAtExit); instance() = this; }
  void count(const std::string& outcome) {
    std::lock_guard<std::mutex> lock(mu_);
    ++counts_[outcome];
    ++total_;
    if ((total_ & (total_ - 1)) == 0 && total_ >= 1024) printLocked();
  }
  void print() {
    std::lock_guard<std::mutex> lock(mu_);
    printLocked();
  }

 private:
  static Outcomes*& instance() {
    static Outcomes* p = nullptr;
    return p;
  }
  static void printAtExit() {
    if (instance()) instance()->print();
  }
  void printLocked() const {
    std::fprintf(stderr, "==paramesh-fuzz== %s outcomes after %ld inputs:", harness_.c_str(), total_);
    for (const auto& kv : counts_) std::fprintf(stderr, " %s=%ld", kv.first.c_str(), kv.second);
    std::fputc('\n', stderr);
  }
  std::string harness_;
  std::mutex mu_;
  std::map<std::string, long> counts_;
  long total_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Mesh checks (geometry harness): independent of the library's own audit, on purpose.

/// Sorted node pair of a mesh edge.
inline std::pair<int, int> edgeKey(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

/// The element corner loops of the mesh: triangles then quads, with their 1-based face.
template <class F>
void forEachElement(const SurfaceMesh& m, F f) {
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    const auto& t = m.triangles[i];
    f(&t[0], 3, m.triangleFace[i]);
  }
  for (size_t i = 0; i < m.quads.size(); ++i) {
    const auto& q = m.quads[i];
    f(&q[0], 4, m.quadFace[i]);
  }
}

/// Is the CAD solid closed: every non-degenerate edge of its faces' wires used exactly twice
/// (a seam twice by one face), with faces listed as often as the solid uses them.
inline bool cadSolidClosed(const IGeometryModel& g, const std::vector<SolidFace>& faces) {
  std::map<int, int> uses;
  for (const SolidFace& sf : faces)
    for (const Wire& w : g.faceWires(sf.face))
      for (const EdgeUse& u : w.uses)
        if (!g.edgeDegenerate(u.edge)) ++uses[u.edge];
  for (const auto& kv : uses)
    if (kv.second != 2) return false;
  return !uses.empty();
}

/// "" when the mesh is sound, else what is wrong. `faceOk` (1-based face -> meshed) excuses the
/// solids that hold a face the report names as failed from the closure check.
inline std::string checkMesh(const SurfaceMesh& m, const IGeometryModel& g, const Report& r) {
  char buf[512];
  const int nn = (int)m.nodes.size();
  for (int i = 0; i < nn; ++i) {
    const Vec3& p = m.nodes[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      std::snprintf(buf, sizeof buf, "node %d has a non-finite coordinate", i);
      return buf;
    }
  }
  if (m.triangleFace.size() != m.triangles.size() || m.quadFace.size() != m.quads.size())
    return "element and face-id arrays differ in length";
  std::string bad;
  forEachElement(m, [&](const int* v, int n, int face) {
    if (!bad.empty()) return;
    if (face < 1 || face > g.numFaces()) {
      bad = "element on face " + std::to_string(face) + " of " + std::to_string(g.numFaces());
      return;
    }
    for (int k = 0; k < n; ++k) {
      if (v[k] < 0 || v[k] >= nn) { bad = "element node index out of range"; return; }
      for (int l = k + 1; l < n; ++l)
        if (v[k] == v[l]) { bad = "element with a repeated node on Face" + std::to_string(face); return; }
    }
  });
  if (!bad.empty()) return bad;
  // every mesh edge used at most twice, or as often as the CAD edge under it has faces
  std::map<std::pair<int, int>, int> allowed;
  for (size_t i = 0; i < m.segments.size(); ++i) {
    const int e = m.segmentEdge[i] - 1;
    const int nf = (e >= 0 && e < g.numEdges()) ? (int)g.edgeFaces(e).size() : 2;
    auto& a = allowed[edgeKey(m.segments[i][0], m.segments[i][1])];
    a = std::max({a, 2, nf});
  }
  std::map<std::pair<int, int>, int> use;
  forEachElement(m, [&](const int* v, int n, int) {
    for (int k = 0; k < n; ++k) ++use[edgeKey(v[k], v[(k + 1) % n])];
  });
  for (const auto& kv : use) {
    auto it = allowed.find(kv.first);
    const int lim = it == allowed.end() ? 2 : it->second;
    if (kv.second > lim) {
      std::snprintf(buf, sizeof buf, "mesh edge %d-%d used by %d elements (at most %d)", kv.first.first,
                    kv.first.second, kv.second, lim);
      return buf;
    }
  }
  // closed solids: every edge of the solid's elements used exactly twice, once each way once the
  // faces the solid uses reversed are flipped
  std::vector<char> faceOk(g.numFaces() + 1, 1);
  for (const FaceReport& f : r.faces)
    if (f.face >= 1 && f.face <= g.numFaces() && !f.ok) faceOk[f.face] = 0;
  std::vector<std::vector<std::pair<const int*, int>>> byFace(g.numFaces() + 1);
  forEachElement(m, [&](const int* v, int n, int face) { byFace[face].push_back({v, n}); });
  for (int s = 0; s < g.numSolids(); ++s) {
    const std::vector<SolidFace> sf = g.solidFaces(s);
    bool skip = !cadSolidClosed(g, sf);
    for (const SolidFace& f : sf) skip = skip || !faceOk[f.face + 1];
    if (skip) continue;
    std::map<std::pair<int, int>, std::array<int, 2>> dir;  // (a<b) -> uses a->b, b->a
    for (const SolidFace& f : sf)
      for (const auto& el : byFace[f.face + 1])
        for (int k = 0; k < el.second; ++k) {
          int a = el.first[k], b = el.first[(k + 1) % el.second];
          if (f.reversed) std::swap(a, b);
          ++dir[edgeKey(a, b)][a < b ? 0 : 1];
        }
    for (const auto& kv : dir)
      if (kv.second[0] != 1 || kv.second[1] != 1) {
        std::snprintf(buf, sizeof buf,
                      "Solid%d is closed in the CAD but its mesh is not: edge %d-%d used %d+%d times (%s)", s + 1,
                      kv.first.first, kv.first.second, kv.second[0], kv.second[1],
                      kv.second[0] + kv.second[1] == 2 ? "misoriented" : "open or over-used");
        return buf;
      }
  }
  // tetrahedra: positive, and the faces used once are the solid's surface triangles
  if (!m.tets.empty()) {
    if (m.tetSolid.size() != m.tets.size()) return "tet and solid-id arrays differ in length";
    std::map<int, std::map<std::array<int, 3>, int>> once;  // solid -> sorted face -> count
    for (size_t i = 0; i < m.tets.size(); ++i) {
      const auto& t = m.tets[i];
      for (int v : t)
        if (v < 0 || v >= nn) return "tet node index out of range";
      const Vec3 a = m.nodes[t[0]], b = m.nodes[t[1]], c = m.nodes[t[2]], d = m.nodes[t[3]];
      if (!(dot(cross(b - a, c - a), d - a) > 0)) {
        std::snprintf(buf, sizeof buf, "tet %zu of Solid%d is not positive", i, m.tetSolid[i]);
        return buf;
      }
      static const int kFace[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
      for (const auto& fv : kFace) {
        std::array<int, 3> k = {t[fv[0]], t[fv[1]], t[fv[2]]};
        std::sort(k.begin(), k.end());
        ++once[m.tetSolid[i]][k];
      }
    }
    for (const SolidReport& sr : r.solids) {
      if (!sr.ok) continue;
      const std::vector<SolidFace> sf = g.solidFaces(sr.solid - 1);
      std::map<std::array<int, 3>, int> surface;
      bool internal = false;
      for (size_t i = 0; i < sf.size(); ++i)
        for (size_t j = i + 1; j < sf.size(); ++j) internal = internal || sf[i].face == sf[j].face;
      if (internal) continue;
      for (const SolidFace& f : sf)
        for (const auto& el : byFace[f.face + 1])
          if (el.second == 3) {
            std::array<int, 3> k = {el.first[0], el.first[1], el.first[2]};
            std::sort(k.begin(), k.end());
            ++surface[k];
          }
      std::map<std::array<int, 3>, int> boundary;
      for (const auto& kv : once[sr.solid])
        if (kv.second == 1) boundary.insert(kv);
        else if (kv.second > 2) return "a tet face of Solid" + std::to_string(sr.solid) + " is shared by more than two tets";
      if (boundary != surface) {
        std::snprintf(buf, sizeof buf, "Solid%d: the tets' boundary (%zu triangles) is not its surface (%zu)",
                      sr.solid, boundary.size(), surface.size());
        return buf;
      }
    }
  }
  return "";
}

}  // namespace paramesh::fuzz
