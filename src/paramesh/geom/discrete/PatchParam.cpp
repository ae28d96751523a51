// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file PatchParam.cpp
#include "paramesh/geom/discrete/PatchParam.hpp"
#include "paramesh/geom/discrete/EdgeTable.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

namespace paramesh {
namespace {

constexpr double kPi = 3.14159265358979323846;

int findSet(std::vector<int>& p, int i) {
  while (p[i] != i) i = p[i] = p[p[i]];
  return i;
}

}  // namespace

PatchParam parametrizeFace(const TriangleSoup& m, const FeatureGraph& g, int f) {
  PatchParam out;
  const std::string name = "Face" + std::to_string(f + 1);
  const std::vector<int>& T = g.faceTris[f];
  const auto& loops = g.faceLoops[f];
  if (loops.size() != 1) {
    out.error = name + " is not a disk (" + std::to_string(loops.size()) + " wires)";
    return out;
  }
  // the cut edges: every mesh edge of the chains of the face's wire (seams included)
  std::unordered_set<unsigned long long> cut;
  for (const auto& [e, rev] : loops[0]) {
    const auto& n = g.edges[e].nodes;
    for (size_t i = 1; i < n.size(); ++i) cut.insert(edgeKey(n[i - 1], n[i]));
  }
  // corners (t, i) joined across the face's uncut edges: each class is one local vertex
  std::unordered_map<unsigned long long, int> side;  // directed (a, b) -> corner index 3k + i of a in T[k]
  for (size_t k = 0; k < T.size(); ++k)
    for (int i = 0; i < 3; ++i) side[sideKey(m.triangles[T[k]][i], m.triangles[T[k]][(i + 1) % 3])] = (int)(3 * k + i);
  std::vector<int> parent(3 * T.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto join = [&](int x, int y) {
    x = findSet(parent, x), y = findSet(parent, y);
    if (x != y) parent[std::max(x, y)] = std::min(x, y);
  };
  for (size_t k = 0; k < T.size(); ++k)
    for (int i = 0; i < 3; ++i) {
      const int a = m.triangles[T[k]][i], b = m.triangles[T[k]][(i + 1) % 3];
      if (cut.count(edgeKey(a, b))) continue;
      auto it = side.find(sideKey(b, a));  // the neighbour across (a, b) runs b -> a
      if (it == side.end()) continue;
      const int nk = it->second / 3, ni = it->second % 3;
      join((int)(3 * k + i), (int)(3 * nk + (ni + 1) % 3));  // a in both
      join((int)(3 * k + (i + 1) % 3), it->second);          // b in both
    }
  std::vector<int> local(3 * T.size(), -1);
  for (size_t c = 0; c < local.size(); ++c) {
    const int r = findSet(parent, (int)c);
    if (local[r] < 0) local[r] = (int)out.node.size(), out.node.push_back(m.triangles[T[c / 3]][c % 3]);
    local[c] = local[r];
  }
  out.tris.resize(T.size());
  for (size_t k = 0; k < T.size(); ++k)
    for (int i = 0; i < 3; ++i) out.tris[k][i] = local[3 * k + i];
  const int V = (int)out.node.size();
  // the boundary: each use's chain walked with the face on its left
  std::vector<int> ring;
  out.useVertices.reserve(loops[0].size());
  for (const auto& [e, rev] : loops[0]) {
    std::vector<int> n = g.edges[e].nodes;
    if (rev) std::reverse(n.begin(), n.end());
    std::vector<int> lv(n.size(), -1);
    for (size_t i = 0; i + 1 < n.size(); ++i) {
      auto it = side.find(sideKey(n[i], n[i + 1]));
      if (it == side.end()) {
        out.error = name + ": its wire runs along Edge" + std::to_string(e + 1) + " against its triangles";
        return out;
      }
      lv[i] = local[it->second];
      lv[i + 1] = local[3 * (it->second / 3) + (it->second % 3 + 1) % 3];
      ring.push_back(lv[i]);
    }
    if (rev) std::reverse(lv.begin(), lv.end());
    out.useVertices.push_back(std::move(lv));
  }
  // Euler characteristic of the cut face: a disk has V - E + F = 1
  std::unordered_set<unsigned long long> localEdges;
  for (const auto& t : out.tris)
    for (int i = 0; i < 3; ++i) localEdges.insert(edgeKey(t[i], t[(i + 1) % 3]));
  const long chi = (long)V - (long)localEdges.size() + (long)T.size();
  std::vector<char> onRing(V, 0);
  for (int v : ring) {
    if (onRing[v]) {
      out.error = name + ": its boundary passes a point twice (a pinched face)";
      return out;
    }
    onRing[v] = 1;
  }
  if (chi != 1) {
    out.error = name + " is not a disk after its cuts (Euler characteristic " + std::to_string(chi) + "): a handle";
    return out;
  }
  // the boundary on the unit circle by 3D arc length
  out.uv.assign(V, {0, 0});
  const Vec3* P = m.points.data();
  double L = 0;
  std::vector<double> s(ring.size() + 1, 0);
  for (size_t i = 0; i < ring.size(); ++i) s[i + 1] = L += dist(P[out.node[ring[i]]], P[out.node[ring[(i + 1) % ring.size()]]]);
  for (size_t i = 0; i < ring.size(); ++i) {
    const double a = 2 * kPi * s[i] / L;
    out.uv[ring[i]] = {std::cos(a), std::sin(a)};
  }
  // the inside: mean-value weights, sum_j w_ij (x_i - x_j) = 0
  std::vector<int> row(V, -1);
  int n = 0;
  for (int v = 0; v < V; ++v)
    if (!onRing[v]) row[v] = n++;
  if (n > 0) {
    std::vector<Eigen::Triplet<double>> A;
    Eigen::VectorXd bu = Eigen::VectorXd::Zero(n), bv = Eigen::VectorXd::Zero(n);
    std::vector<double> diag(n, 0);
    for (const auto& t : out.tris)
      for (int i = 0; i < 3; ++i) {
        const int a = t[i], b = t[(i + 1) % 3], c = t[(i + 2) % 3];
        if (row[a] < 0) continue;
        const Vec3 xa = P[out.node[a]], xb = P[out.node[b]], xc = P[out.node[c]];
        const double lb = dist(xa, xb), lc = dist(xa, xc);
        const double cosA = lb > 0 && lc > 0 ? std::clamp(dot(xb - xa, xc - xa) / (lb * lc), -1.0, 1.0) : 1.0;
        const double h = std::tan(0.5 * std::acos(cosA)) + 1e-12;  // tan(half the angle at a)
        for (const auto& [o, l] : {std::make_pair(b, lb), std::make_pair(c, lc)}) {
          const double w = h / std::max(l, 1e-300);
          diag[row[a]] += w;
          if (row[o] >= 0) A.emplace_back(row[a], row[o], -w);
          else bu[row[a]] += w * out.uv[o].x, bv[row[a]] += w * out.uv[o].y;
        }
      }
    for (int i = 0; i < n; ++i) A.emplace_back(i, i, diag[i]);
    Eigen::SparseMatrix<double> M(n, n);
    M.setFromTriplets(A.begin(), A.end());
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
    lu.compute(M);
    if (lu.info() != Eigen::Success) {
      out.error = name + ": its parametrisation's linear system is singular";
      return out;
    }
    const Eigen::VectorXd u = lu.solve(bu), w = lu.solve(bv);
    for (int v = 0; v < V; ++v)
      if (row[v] >= 0) out.uv[v] = {u[row[v]], w[row[v]]};
  }
  return out;
}

}  // namespace paramesh
