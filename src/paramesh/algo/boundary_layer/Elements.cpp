// SPDX-License-Identifier: LGPL-2.1-or-later
// A grown run's output: node refs for its marched points, its per-spec statistics, the quads (or
// triangle pairs) between consecutive columns and the fan triangles at shared roots.

#include "paramesh/algo/boundary_layer/FaceLayers.hpp"

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include "paramesh/algo/Predicates.hpp"

namespace paramesh::bl_detail {

void FaceLayers::emit(int L, int a, int nseg, bool closed, std::vector<Column>& cols) {
  const int m = (int)cols.size();
  untangle(cols, closed);
  trimNeedles(cols, closed);  // untangling may have cut a neighbour down
  recordGrid(cols, closed);
  // node refs for marched points
  for (auto& c : cols)
    for (size_t k = 1; k < c.xyz.size(); ++k)
      if (!c.fixed) c.ref[k] = newNode(c.uv[k], c.xyz[k]);
  // statistics
  for (auto& c : cols) {
    auto& st = out_.stats[c.spec];
    const int layers = (int)c.xyz.size() - 1;
    ++st.columns;
    st.minLayers = std::min(st.minLayers, layers);
    st.maxLayers = std::max(st.maxLayers, layers);
    if (layers >= laws_[c.spec].layers) ++st.fullColumns;
    switch (c.stop) {
      case 1: ++st.stopBoundary; break;
      case 2: ++st.stopCollision; break;
      case 3: ++st.stopInvalid; break;
      case 4: ++st.stopAspect; break;
      case 5: ++st.stopEnd; break;
      default: break;
    }
  }
  // elements between consecutive columns
  const int pairs = closed ? m : m - 1;
  for (int i = 0; i < pairs; ++i) {
    const Column &A = cols[i], &B = cols[(i + 1) % m];
    const int kmax = (int)std::min(A.xyz.size(), B.xyz.size()) - 1;
    for (int k = 0; k < kmax; ++k) {
      if (A.root == B.root && k == 0) {
        // fan: triangle root, B1, A1 (orientation fixed below)
        addTri(A.spec, A.ref[0], A.uv[0], B.ref[1], B.uv[1], A.ref[1], A.uv[1]);
        continue;
      }
      addQuad(A.spec, {A.ref[k], B.ref[k], B.ref[k + 1], A.ref[k + 1]}, {A.uv[k], B.uv[k], B.uv[k + 1], A.uv[k + 1]},
              {A.xyz[k], B.xyz[k], B.xyz[k + 1], A.xyz[k + 1]});
    }
  }
  handOff(L, a, nseg, closed, cols);
}

int FaceLayers::newNode(Vec2 uv, Vec3 x) {
  out_.nodes.push_back({uv, x});
  return -(int)out_.nodes.size();
}

void FaceLayers::addQuad(int spec, std::array<int, 4> q, std::array<Vec2, 4> u, std::array<Vec3, 4> x) {
  if (area2(u[0], u[1], u[2]) + area2(u[0], u[2], u[3]) < 0) {
    std::swap(q[1], q[3]);
    std::swap(u[1], u[3]);
    std::swap(x[1], x[3]);
  }
  if (!specQuads_[spec]) {
    // two triangles along the shorter diagonal
    if (dist(x[0], x[2]) <= dist(x[1], x[3])) {
      addTri(spec, q[0], u[0], q[1], u[1], q[2], u[2]);
      addTri(spec, q[0], u[0], q[2], u[2], q[3], u[3]);
    } else {
      addTri(spec, q[1], u[1], q[2], u[2], q[3], u[3]);
      addTri(spec, q[1], u[1], q[3], u[3], q[0], u[0]);
    }
    return;
  }
  out_.quads.push_back(q);
  out_.quadUv.push_back(u);
  out_.quadSpec.push_back(spec);
  ++out_.stats[spec].elements;
}

void FaceLayers::addTri(int spec, int r0, Vec2 u0, int r1, Vec2 u1, int r2, Vec2 u2) {
  std::array<int, 3> t{r0, r1, r2};
  std::array<Vec2, 3> u{u0, u1, u2};
  if (area2(u0, u1, u2) < 0) {
    std::swap(t[1], t[2]);
    std::swap(u[1], u[2]);
  }
  out_.tris.push_back(t);
  out_.triUv.push_back(u);
  out_.triSpec.push_back(spec);
  ++out_.stats[spec].elements;
}

}  // namespace paramesh::bl_detail
