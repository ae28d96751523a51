// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshAudit.cpp
/// The audit's driver and its findings' wording.
#include "paramesh/audit/MeshAudit.hpp"

#include <algorithm>

#include "paramesh/util/Format.hpp"
#include "paramesh/util/Parallel.hpp"
#include "paramesh/util/Timer.hpp"

namespace paramesh {
namespace {

constexpr size_t kNamed = 8;  ///< entities named per finding (the rest counted)

void unique(std::vector<int>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

std::string names(const char* kind, std::vector<int> ids) {
  unique(ids);
  std::string s;
  for (size_t i = 0; i < ids.size() && i < kNamed; ++i) s += (i ? ", " : "") + (kind + std::to_string(ids[i]));
  if (ids.size() > kNamed) s += " and " + std::to_string(ids.size() - kNamed) + " more";
  return s;
}

std::string fmtPoint(Vec3 p) { return "(" + fmt(p.x) + ", " + fmt(p.y) + ", " + fmt(p.z) + ")"; }

void merge(std::vector<int>& into, const std::vector<int>& from) {
  into.insert(into.end(), from.begin(), from.end());
  unique(into);
}

}  // namespace

void addFinding(AuditResult& r, const std::string& what, int count, const std::vector<int>& faces,
                const std::vector<int>& edges, const std::vector<int>& solids, const Vec3* first) {
  std::string line = std::to_string(count) + " " + what;
  std::string where;
  for (const auto& [kind, ids] : {std::make_pair("Solid", &solids), std::make_pair("Face", &faces),
                                  std::make_pair("Edge", &edges)})
    if (!ids->empty()) where += (where.empty() ? "" : "; ") + names(kind, *ids);
  if (first) where += (where.empty() ? "" : "; ") + ("first at " + fmtPoint(*first));
  if (!where.empty()) line += " (" + where + ")";
  r.problems.push_back(line);
  merge(r.faces, faces);
  merge(r.edges, edges);
  merge(r.solids, solids);
}

int auditChunks(int n, int threads, const std::function<void(int, int, int)>& work) {
  const int chunks = (n + kAuditChunk - 1) / kAuditChunk;
  parallelFor(chunks, threads, [&](int c) { work(c * kAuditChunk, std::min(n, (c + 1) * kAuditChunk), c); });
  return chunks;
}

AuditResult auditMesh(const AuditInput& in, double foldAngleDeg) {
  Timer t;
  AuditResult r;
  auditEdgeUse(in, foldAngleDeg, r);
  auditElements(in, r);
  if (in.nodes) auditNodes(in, r);
  r.seconds = t.seconds();
  return r;
}

}  // namespace paramesh
