// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Tet10.cpp
#include "paramesh/volume/Tet10.hpp"

#include <algorithm>
#include <cstdint>
#include <unordered_map>

#include "paramesh/volume/TetQuality.hpp"

namespace paramesh {
namespace {

/// The tet10 edges in mid-node order: ab, bc, ca, ad, bd, cd.
constexpr int kEdge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};

std::uint64_t edgeKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}

double det3(const Vec3& a, const Vec3& b, const Vec3& c) { return dot(a, cross(b, c)); }

}  // namespace

double tet10MinScaledJacobian(const Vec3 x[10]) {
  const double straight = tetVolume6(x[0], x[1], x[2], x[3]);
  if (straight <= 0) return -1;
  // node index of the mid-node between corners i and j
  int mid[4][4];
  for (int e = 0; e < 6; ++e) mid[kEdge[e][0]][kEdge[e][1]] = mid[kEdge[e][1]][kEdge[e][0]] = 4 + e;
  // samples in barycentric coordinates: corners, mid-edges, centroid
  double samples[11][4] = {};
  for (int i = 0; i < 4; ++i) samples[i][i] = 1;
  for (int e = 0; e < 6; ++e) samples[4 + e][kEdge[e][0]] = samples[4 + e][kEdge[e][1]] = 0.5;
  for (int i = 0; i < 4; ++i) samples[10][i] = 0.25;
  double worst = 1e300;
  for (const auto& L : samples) {
    // dx/dxi_k for xi_k = lambda_k (k = 1..3), lambda_0 = 1 - xi_1 - xi_2 - xi_3
    Vec3 J[3];
    for (int k = 1; k <= 3; ++k) {
      Vec3 g{0, 0, 0};
      for (int i = 0; i < 4; ++i) {
        const double dli = (i == k) - (i == 0);
        g = g + ((4 * L[i] - 1) * dli) * x[i];
      }
      for (int e = 0; e < 6; ++e) {
        const int i = kEdge[e][0], j = kEdge[e][1];
        const double dli = (i == k) - (i == 0), dlj = (j == k) - (j == 0);
        g = g + (4 * (dli * L[j] + dlj * L[i])) * x[mid[i][j]];
      }
      J[k - 1] = g;
    }
    worst = std::min(worst, det3(J[0], J[1], J[2]) / straight);
  }
  return worst;
}

Tet10Stats makeTet10(SurfaceMesh& m) {
  Tet10Stats st;
  std::unordered_map<std::uint64_t, int> midOf;
  midOf.reserve(m.triangles.size() * 2 + m.tets.size() * 2);
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& v = m.triangles[t];
    for (int e = 0; e < 3; ++e) midOf.emplace(edgeKey(v[e], v[(e + 1) % 3]), m.triangleMid[t][e]);
  }
  m.tetMid.resize(m.tets.size());
  for (std::size_t k = 0; k < m.tets.size(); ++k) {
    const auto& v = m.tets[k];
    for (int e = 0; e < 6; ++e) {
      const int a = v[kEdge[e][0]], b = v[kEdge[e][1]];
      auto [it, added] = midOf.emplace(edgeKey(a, b), -1);
      if (added) {
        it->second = m.addNode(0.5 * (m.nodes[a] + m.nodes[b]), NodeKind::Volume, m.tetSolid[k]);
        ++st.midNodes;
      }
      m.tetMid[k][e] = it->second;
    }
  }
  // straightening a tet moves mid-nodes its neighbours share: check again until none is left.
  // The last pass changes nothing, so its values are the final ones (straightened tets: 1).
  std::vector<char> straight(m.tets.size(), 0);
  for (bool changed = true; changed;) {
    changed = false;
    double passMin = 1;
    for (std::size_t k = 0; k < m.tets.size(); ++k) {
      if (straight[k]) continue;
      Vec3 x[10];
      for (int i = 0; i < 4; ++i) x[i] = m.nodes[m.tets[k][i]];
      for (int e = 0; e < 6; ++e) x[4 + e] = m.nodes[m.tetMid[k][e]];
      const double q = tet10MinScaledJacobian(x);
      if (q > 0) {
        passMin = std::min(passMin, q);
        continue;
      }
      // back on the chords: its curved surface edges become straight (valid, off the CAD there)
      for (int e = 0; e < 6; ++e) {
        const int a = m.tets[k][kEdge[e][0]], b = m.tets[k][kEdge[e][1]];
        m.nodes[m.tetMid[k][e]] = 0.5 * (m.nodes[a] + m.nodes[b]);
      }
      straight[k] = 1;
      ++st.straightened;
      changed = true;
    }
    st.minScaledJacobian = passMin;
  }
  return st;
}

}  // namespace paramesh
