// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/algo/HighOrder.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

namespace paramesh {

double tri6MinScaledJacobian(const Vec3 x[6], Vec3 n) {
  // shape functions on (r,s): corners N0 = L0(2L0-1) ..., mids N3 = 4 L0 L1 (ab), N4 = 4 L1 L2 (bc),
  // N5 = 4 L2 L0 (ca), with L0 = 1 - r - s, L1 = r, L2 = s
  const Vec3 straight = cross(x[1] - x[0], x[2] - x[0]);
  const double ref = dot(straight, n);
  if (!(std::fabs(ref) > 0)) return 0;
  const double samples[7][2] = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}, {1.0 / 3, 1.0 / 3}};
  double worst = 1e300;
  for (const auto& sm : samples) {
    const double r = sm[0], s = sm[1], L0 = 1 - r - s;
    // dN/dr, dN/ds
    const double dr[6] = {-(4 * L0 - 1), 4 * r - 1, 0, 4 * (L0 - r), 4 * s, -4 * s};
    const double ds[6] = {-(4 * L0 - 1), 0, 4 * s - 1, -4 * r, 4 * r, 4 * (L0 - s)};
    Vec3 xr{0, 0, 0}, xs{0, 0, 0};
    for (int k = 0; k < 6; ++k) {
      xr += dr[k] * x[k];
      xs += ds[k] * x[k];
    }
    worst = std::min(worst, dot(cross(xr, xs), n) / ref);
  }
  return worst;
}

double quad8MinScaledJacobian(const Vec3 x[8], Vec3 n) {
  // serendipity shape functions on (r,s) in [-1,1]^2; corners (-1,-1),(1,-1),(1,1),(-1,1)
  const double cr[4] = {-1, 1, 1, -1}, cs[4] = {-1, -1, 1, 1};
  auto jac = [&](double r, double s) {
    Vec3 xr{0, 0, 0}, xs{0, 0, 0};
    for (int k = 0; k < 4; ++k) {
      const double ri = cr[k], si = cs[k];
      // N = (1+r ri)(1+s si)(r ri + s si - 1)/4
      const double dNr = 0.25 * ri * (1 + s * si) * (2 * r * ri + s * si);
      const double dNs = 0.25 * si * (1 + r * ri) * (r * ri + 2 * s * si);
      xr += dNr * x[k];
      xs += dNs * x[k];
    }
    // mids: ab (s=-1), bc (r=1), cd (s=1), da (r=-1)
    const double m[4][2] = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}};
    for (int k = 0; k < 4; ++k) {
      double dNr, dNs;
      if (m[k][0] == 0) {  // N = (1 - r^2)(1 + s si)/2
        const double si = m[k][1];
        dNr = -r * (1 + s * si);
        dNs = 0.5 * si * (1 - r * r);
      } else {  // N = (1 + r ri)(1 - s^2)/2
        const double ri = m[k][0];
        dNr = 0.5 * ri * (1 - s * s);
        dNs = -s * (1 + r * ri);
      }
      xr += dNr * x[4 + k];
      xs += dNs * x[4 + k];
    }
    return dot(cross(xr, xs), n);
  };
  // the straight quad's Jacobian at its centre
  Vec3 xr = 0.25 * ((x[1] - x[0]) + (x[2] - x[3])), xs = 0.25 * ((x[3] - x[0]) + (x[2] - x[1]));
  const double ref = dot(cross(xr, xs), n);
  if (!(std::fabs(ref) > 0)) return 0;
  double worst = 1e300;
  for (double r : {-1.0, 0.0, 1.0})
    for (double s : {-1.0, 0.0, 1.0}) worst = std::min(worst, jac(r, s) / ref);
  return worst;
}

HighOrderStats makeSecondOrder(SurfaceMesh& m, const IGeometryModel& g,
                               const std::vector<std::array<Vec2, 3>>& triUv,
                               const std::vector<std::array<Vec2, 4>>& quadUv,
                               const std::vector<std::array<double, 2>>& segT) {
  HighOrderStats st;
  std::map<std::pair<int, int>, int> mid;  // undirected edge -> mid node
  auto key = [](int a, int b) { return std::make_pair(std::min(a, b), std::max(a, b)); };
  std::vector<std::unique_ptr<ICurve>> curves(g.numEdges());
  std::vector<std::unique_ptr<ISurface>> surfs(g.numFaces());
  // mids of CAD-edge segments: on the curve
  m.segmentMid.assign(m.segments.size(), -1);
  for (size_t i = 0; i < m.segments.size(); ++i) {
    const int a = m.segments[i][0], b = m.segments[i][1];
    const int e = m.segmentEdge[i] - 1;
    if (!curves[e]) curves[e] = g.makeCurve(e);
    const double t0 = std::min(segT[i][0], segT[i][1]), t1 = std::max(segT[i][0], segT[i][1]);
    const double t = curves[e]->project(0.5 * (m.nodes[a] + m.nodes[b]), 0.5 * (t0 + t1), t0, t1);
    const int v = m.addNode(curves[e]->eval(t), NodeKind::Edge, e + 1, {t, 0});
    mid[key(a, b)] = v;
    m.segmentMid[i] = v;
    ++st.midNodes;
  }
  // mids inside faces: on the surface, from the triangle's own (u,v) (seam-consistent)
  m.triangleMid.assign(m.triangles.size(), {-1, -1, -1});
  std::vector<std::array<Vec3, 3>> chordMid(m.triangles.size());
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& T = m.triangles[t];
    const int f = m.triangleFace[t] - 1;
    for (int k = 0; k < 3; ++k) {
      const int a = T[k], b = T[(k + 1) % 3];
      chordMid[t][k] = 0.5 * (m.nodes[a] + m.nodes[b]);
      auto it = mid.find(key(a, b));
      if (it != mid.end()) {
        m.triangleMid[t][k] = it->second;
        continue;
      }
      if (!surfs[f]) surfs[f] = g.makeSurface(f);
      Vec2 uv = 0.5 * (triUv[t][k] + triUv[t][(k + 1) % 3]);
      Vec3 p;
      if (!surfs[f]->project(chordMid[t][k], uv, &p, 0.01)) p = surfs[f]->eval(uv);
      const int v = m.addNode(p, NodeKind::Face, f + 1, uv);
      mid[key(a, b)] = v;
      m.triangleMid[t][k] = v;
      ++st.midNodes;
    }
  }
  m.quadMid.assign(m.quads.size(), {-1, -1, -1, -1});
  std::vector<std::array<Vec3, 4>> quadChordMid(m.quads.size());
  for (size_t q = 0; q < m.quads.size(); ++q) {
    const auto& Q = m.quads[q];
    const int f = m.quadFace[q] - 1;
    for (int k = 0; k < 4; ++k) {
      const int a = Q[k], b = Q[(k + 1) % 4];
      quadChordMid[q][k] = 0.5 * (m.nodes[a] + m.nodes[b]);
      auto it = mid.find(key(a, b));
      if (it != mid.end()) {
        m.quadMid[q][k] = it->second;
        continue;
      }
      if (!surfs[f]) surfs[f] = g.makeSurface(f);
      Vec2 uv = 0.5 * (quadUv[q][k] + quadUv[q][(k + 1) % 4]);
      Vec3 p;
      if (!surfs[f]->project(quadChordMid[q][k], uv, &p, 0.01)) p = surfs[f]->eval(uv);
      const int v = m.addNode(p, NodeKind::Face, f + 1, uv);
      mid[key(a, b)] = v;
      m.quadMid[q][k] = v;
      ++st.midNodes;
    }
  }
  // validity: straighten the mids of folded elements until none is left
  for (int round = 0; round < 4; ++round) {
    int bad = 0;
    for (size_t t = 0; t < m.triangles.size(); ++t) {
      const auto& T = m.triangles[t];
      const auto& M = m.triangleMid[t];
      Vec3 x[6] = {m.nodes[T[0]], m.nodes[T[1]], m.nodes[T[2]], m.nodes[M[0]], m.nodes[M[1]], m.nodes[M[2]]};
      const Vec3 n = normalized(cross(x[1] - x[0], x[2] - x[0]));
      const double j = tri6MinScaledJacobian(x, n);
      if (j > 0.05) continue;
      ++bad;
      if (round == 0) ++st.invalidElements;
      for (int k = 0; k < 3; ++k) {
        if (dist(m.nodes[M[k]], chordMid[t][k]) == 0) continue;
        m.nodes[M[k]] = chordMid[t][k];
        ++st.straightened;
      }
    }
    for (size_t q = 0; q < m.quads.size(); ++q) {
      const auto& Q = m.quads[q];
      const auto& M = m.quadMid[q];
      Vec3 x[8] = {m.nodes[Q[0]], m.nodes[Q[1]], m.nodes[Q[2]], m.nodes[Q[3]],
                   m.nodes[M[0]], m.nodes[M[1]], m.nodes[M[2]], m.nodes[M[3]]};
      const Vec3 n = normalized(cross(x[2] - x[0], x[3] - x[1]));
      if (quad8MinScaledJacobian(x, n) > 0.05) continue;
      ++bad;
      if (round == 0) ++st.invalidElements;
      for (int k = 0; k < 4; ++k) {
        if (dist(m.nodes[M[k]], quadChordMid[q][k]) == 0) continue;
        m.nodes[M[k]] = quadChordMid[q][k];
        ++st.straightened;
      }
    }
    if (!bad) break;
  }
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& T = m.triangles[t];
    const auto& M = m.triangleMid[t];
    Vec3 x[6] = {m.nodes[T[0]], m.nodes[T[1]], m.nodes[T[2]], m.nodes[M[0]], m.nodes[M[1]], m.nodes[M[2]]};
    st.minJacobianRatio = std::min(st.minJacobianRatio, tri6MinScaledJacobian(x, normalized(cross(x[1] - x[0], x[2] - x[0]))));
  }
  for (size_t q = 0; q < m.quads.size(); ++q) {
    const auto& Q = m.quads[q];
    const auto& M = m.quadMid[q];
    Vec3 x[8] = {m.nodes[Q[0]], m.nodes[Q[1]], m.nodes[Q[2]], m.nodes[Q[3]],
                 m.nodes[M[0]], m.nodes[M[1]], m.nodes[M[2]], m.nodes[M[3]]};
    st.minJacobianRatio = std::min(st.minJacobianRatio, quad8MinScaledJacobian(x, normalized(cross(x[2] - x[0], x[3] - x[1]))));
  }
  m.order = 2;
  return st;
}

}  // namespace paramesh
