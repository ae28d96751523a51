// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshRepair.cpp
#include "paramesh/geom/discrete/MeshRepair.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "paramesh/geom/discrete/EdgeTable.hpp"
#include "paramesh/util/Error.hpp"
#include "paramesh/util/Format.hpp"

namespace paramesh {
namespace {

constexpr size_t kLocated = 5;  ///< problems located per kind (the rest counted)

bool finite(Vec3 p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

/// Union-find with the smallest index as each set's representative (stable numbering).
struct Sets {
  std::vector<int> parent;
  explicit Sets(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

/// Points closer than tol joined (a hash grid of cell tol: neighbours are in the 27 cells around).
void mergeClose(const std::vector<Vec3>& p, const std::vector<char>& used, double tol, Sets& sets) {
  if (!(tol > 0)) return;
  std::unordered_map<long long, std::vector<int>> grid;
  auto key = [&](long long i, long long j, long long k) { return (i * 73856093LL) ^ (j * 19349663LL) ^ (k * 83492791LL); };
  auto cell = [&](double x) { return (long long)std::floor(x / tol); };
  for (int i = 0; i < (int)p.size(); ++i)
    if (used[i]) grid[key(cell(p[i].x), cell(p[i].y), cell(p[i].z))].push_back(i);
  for (int i = 0; i < (int)p.size(); ++i) {
    if (!used[i]) continue;
    const long long ci = cell(p[i].x), cj = cell(p[i].y), ck = cell(p[i].z);
    for (long long a = ci - 1; a <= ci + 1; ++a)
      for (long long b = cj - 1; b <= cj + 1; ++b)
        for (long long c = ck - 1; c <= ck + 1; ++c) {
          auto it = grid.find(key(a, b, c));
          if (it == grid.end()) continue;
          for (int j : it->second)
            if (j > i && dist(p[i], p[j]) <= tol) sets.join(i, j);
        }
  }
}

}  // namespace

std::vector<std::string> RepairReport::lines() const {
  std::vector<std::string> out;
  auto at = [](const std::vector<Vec3>& pts) {
    std::string s;
    for (size_t i = 0; i < pts.size(); ++i)
      s += (i ? ", " : "") + ("(" + fmt(pts[i].x) + ", " + fmt(pts[i].y) + ", " + fmt(pts[i].z) + ")");
    return s.empty() ? s : " at " + s;
  };
  if (mergedVertices) out.push_back("merged " + std::to_string(mergedVertices) + " vertices within " + fmt(tolerance));
  if (nonFiniteFacets) out.push_back("dropped " + std::to_string(nonFiniteFacets) + " facets with a non-finite coordinate");
  if (degenerateFacets) out.push_back("dropped " + std::to_string(degenerateFacets) + " degenerate facets (two equal corners)");
  if (duplicateFacets) out.push_back("dropped " + std::to_string(duplicateFacets) + " duplicate facets");
  if (flippedFacets) out.push_back("turned " + std::to_string(flippedFacets) + " facets to agree with their neighbours' orientation");
  if (nonManifoldEdges) out.push_back(std::to_string(nonManifoldEdges) + " non-manifold edges (used by more than two facets)" + at(nonManifoldAt));
  if (holes) out.push_back(std::to_string(holes) + " holes (" + std::to_string(boundaryEdges) + " edges of one facet)" + at(holeAt));
  if (unorientablePieces) out.push_back(std::to_string(unorientablePieces) + " pieces that cannot be oriented (a Moebius band)");
  return out;
}

RepairReport repairTriangles(TriangleSoup& soup, double mergeRel) {
  RepairReport r;
  r.inputPoints = (int)soup.points.size();
  r.inputTriangles = (int)soup.triangles.size() + soup.readerDropped;
  r.degenerateFacets = soup.readerDropped;
  const int n = (int)soup.points.size();
  // facets with a corner that does not exist or is not finite
  std::vector<std::array<int, 3>> tris;
  tris.reserve(soup.triangles.size());
  for (const auto& t : soup.triangles) {
    bool ok = true;
    for (int v : t) ok = ok && v >= 0 && v < n && finite(soup.points[v]);
    if (ok) tris.push_back(t);
    else ++r.nonFiniteFacets;
  }
  std::vector<char> used(n, 0);
  Box3 box;
  for (const auto& t : tris)
    for (int v : t) used[v] = 1, box.add(soup.points[v]);
  if (tris.empty()) throw InputError(soup.source + ": no facet with finite coordinates");
  r.tolerance = mergeRel * box.diagonal();
  Sets sets(n);
  mergeClose(soup.points, used, r.tolerance, sets);
  // compact: each kept point numbered in first-use order of the facets
  std::vector<int> index(n, -1);
  std::vector<Vec3> points;
  int distinctUsed = 0;
  for (int i = 0; i < n; ++i) distinctUsed += used[i];
  std::vector<std::array<int, 3>> kept;
  kept.reserve(tris.size());
  std::unordered_map<unsigned long long, int> seen;  // sorted corners -> first facet
  seen.reserve(tris.size() * 2);
  for (auto t : tris) {
    for (int& v : t) {
      const int rep = sets.find(v);
      if (index[rep] < 0) index[rep] = (int)points.size(), points.push_back(soup.points[rep]);
      v = index[rep];
    }
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      ++r.degenerateFacets;
      continue;
    }
    std::array<int, 3> s = t;
    std::sort(s.begin(), s.end());
    const unsigned long long k = ((unsigned long long)s[0] * 0x9E3779B97F4A7C15ULL) ^ ((unsigned long long)s[1] << 21) ^ (unsigned long long)s[2];
    auto it = seen.find(k);
    bool dup = false;
    if (it != seen.end()) {
      std::array<int, 3> o = kept[it->second];
      std::sort(o.begin(), o.end());
      dup = o == s;
    }
    if (dup) {
      ++r.duplicateFacets;
      continue;
    }
    if (it == seen.end()) seen.emplace(k, (int)kept.size());
    kept.push_back(t);
  }
  r.mergedVertices = distinctUsed - (int)points.size();
  if (kept.empty()) throw InputError(soup.source + ": every facet is degenerate");
  // orientation per piece, across manifold edges
  const EdgeTable edges(kept, (int)points.size());
  const int T = (int)kept.size();
  std::vector<int> piece(T, -1);
  std::vector<char> flip(T, 0);
  std::vector<int> stack;
  for (int s = 0; s < T; ++s) {
    if (piece[s] >= 0) continue;
    const int id = r.pieces++;
    bool orientable = true, closed = true;
    std::vector<int> members;
    piece[s] = id;
    stack.push_back(s);
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      members.push_back(t);
      for (int i = 0; i < 3; ++i) {
        int a = kept[t][i], b = kept[t][(i + 1) % 3];
        if (flip[t]) std::swap(a, b);
        const auto uses = edges.uses(a, b);
        if (uses.size() != 2) {
          closed = false;
          continue;
        }
        const EdgeTable::Use& o = uses[0].tri == t ? uses[1] : uses[0];
        // o runs a->b in its own order; with o's flip it must run b->a
        const bool oRunsAB = edges.runs(kept[o.tri], a, b);
        const bool want = oRunsAB;  // flip o when it runs the same way
        if (piece[o.tri] < 0) {
          piece[o.tri] = id;
          flip[o.tri] = want;
          stack.push_back(o.tri);
        } else if ((bool)flip[o.tri] != want) {
          orientable = false;
        }
      }
    }
    if (!orientable) ++r.unorientablePieces;
    if (closed && orientable) {
      ++r.closedPieces;
      double vol = 0;  // outward: positive enclosed volume
      for (int t : members) {
        Vec3 a = points[kept[t][0]], b = points[kept[t][1]], c = points[kept[t][2]];
        if (flip[t]) std::swap(b, c);
        vol += dot(a, cross(b, c));
      }
      if (vol < 0)
        for (int t : members) flip[t] = !flip[t];
    }
  }
  for (int t = 0; t < T; ++t)
    if (flip[t]) std::swap(kept[t][1], kept[t][2]), ++r.flippedFacets;
  // what is left: non-manifold edges and holes
  Sets loops((int)points.size());
  std::vector<char> onBoundary(points.size(), 0);
  edges.forEach([&](int a, int b, const std::vector<EdgeTable::Use>& uses) {
    const Vec3 mid = 0.5 * (points[a] + points[b]);
    if (uses.size() > 2) {
      if (r.nonManifoldAt.size() < kLocated) r.nonManifoldAt.push_back(mid);
      ++r.nonManifoldEdges;
    } else if (uses.size() == 1) {
      ++r.boundaryEdges;
      loops.join(a, b);
      onBoundary[a] = onBoundary[b] = 1;
    }
  });
  for (int v = 0; v < (int)points.size(); ++v)
    if (onBoundary[v] && loops.find(v) == v) {
      ++r.holes;
      if (r.holeAt.size() < kLocated) r.holeAt.push_back(points[v]);
    }
  soup.points = std::move(points);
  soup.triangles = std::move(kept);
  return r;
}

}  // namespace paramesh
