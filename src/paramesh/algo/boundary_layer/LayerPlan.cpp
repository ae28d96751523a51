// SPDX-License-Identifier: LGPL-2.1-or-later
// The 1D part, before edge discretisation: where a BL edge ends at a non-BL edge, the points of the
// outermost column, marched along that edge at the row heights (planEndColumns).

#include "paramesh/algo/boundary_layer/BoundaryLayer.hpp"

#include <algorithm>
#include <vector>

#include "paramesh/model/Coincidence.hpp"
#include "paramesh/model/EdgeDiscretizer.hpp"

namespace paramesh {

namespace {

/// Parameters along curve c, starting at parameter `from` and moving towards `to`, whose
/// consecutive straight 3D distances are the row heights; stops before the far end.
std::vector<double> marchAlongCurve(const ICurve& c, double from, double to, Vec3 start, const LayerLaw& law,
                                    double* lastHeight) {
  std::vector<double> out;
  const CurveSampling cs = sampleCurve(c, std::min(from, to), std::max(from, to), nullptr);
  const bool forward = to > from;
  // samples ordered from `from`
  std::vector<double> ts(cs.t);
  std::vector<Vec3> ps(cs.p);
  if (!forward) {
    std::reverse(ts.begin(), ts.end());
    std::reverse(ps.begin(), ps.end());
  }
  const Vec3 farEnd = ps.back();
  double t = ts.front();
  Vec3 p = start;  // the CAD vertex (the mesh node), which may sit off the curve within tolerance
  size_t j = 0;
  for (int k = 0; k < law.layers; ++k) {
    const double h = law.height(k);
    // the far end must stay clearly beyond the new point
    if (dist(p, farEnd) < 1.5 * h) break;
    // first sample at chord distance >= h, then bisection on the parameter
    while (j + 1 < ps.size() && dist(ps[j + 1], p) < h) ++j;
    if (j + 1 >= ps.size()) break;
    double a = ts[j], b = ts[j + 1];
    if (dist(c.eval(a), p) > h) a = t;
    for (int it = 0; it < 60; ++it) {
      const double mid = 0.5 * (a + b);
      if (dist(c.eval(mid), p) < h) a = mid;
      else b = mid;
    }
    t = 0.5 * (a + b);
    p = c.eval(t);
    out.push_back(t);
    if (lastHeight) *lastHeight = h;
  }
  return out;
}

}  // namespace

std::vector<EdgeBLPoints> planEndColumns(const IGeometryModel& m, const EdgeSpecMap& specOf,
                                         const std::vector<LayerLaw>& laws, const Coincidence* same) {
  std::vector<EdgeBLPoints> pts(m.numEdges());
  std::vector<double> startH0(m.numEdges(), 0), endH0(m.numEdges(), 0);
  for (int f = 0; f < m.numFaces(); ++f) {
    const auto& wires = m.faceWires(f);
    for (const Wire& w : wires) {
      const int n = (int)w.uses.size();
      for (int k = 0; k < n; ++k) {
        const EdgeUse& u = w.uses[k];
        const int spec = specOf[u.edge];
        if (spec < 0 || m.edgeDegenerate(u.edge)) continue;
        const LayerLaw& law = laws[spec];
        // neighbour uses: next one starts where this use ends, previous one ends where it starts
        for (int side = 0; side < 2; ++side) {
          const EdgeUse& nb = w.uses[side == 0 ? (k + 1) % n : (k + n - 1) % n];
          if (nb.edge == u.edge || specOf[nb.edge] >= 0 || m.edgeDegenerate(nb.edge)) continue;
          // the shared vertex is at the start of the next use's traversal / end of the previous'
          bool atStart = side == 0 ? !nb.reversed : nb.reversed;
          // an edge of an unsewn face is discretised through its representative: the points go
          // there, measured along its curve from its vertex node, so that the face's loop (which
          // takes the representative's nodes) has them at exactly the row heights
          int e = nb.edge;
          if (same && same->edgeRep[e] != e) {
            if (same->edgeReversed[e]) atStart = !atStart;
            e = same->edgeRep[e];
          }
          double t0, t1;
          m.edgeRange(e, t0, t1);
          auto& list = atStart ? pts[e].fromStart : pts[e].fromEnd;
          double& h0 = atStart ? startH0[e] : endH0[e];
          if (!list.empty() && h0 <= law.h0) continue;  // already set by a finer layer
          auto c = m.makeCurve(e);
          double last = 0;
          int vtx = m.edgeVertex(e, atStart ? 0 : 1);
          if (same && vtx >= 0) vtx = same->vertexRep[vtx];
          const Vec3 start = vtx >= 0 ? m.vertexPoint(vtx) : c->eval(atStart ? t0 : t1);
          list = atStart ? marchAlongCurve(*c, t0, t1, start, law, &last) : marchAlongCurve(*c, t1, t0, start, law, &last);
          (atStart ? pts[e].lastHeightStart : pts[e].lastHeightEnd) = last;
          h0 = law.h0;
        }
      }
    }
  }
  // both ends on one short edge: keep the points of each end up to the middle
  for (int e = 0; e < m.numEdges(); ++e) {
    auto& p = pts[e];
    if (p.fromStart.empty() || p.fromEnd.empty()) continue;
    double t0, t1;
    m.edgeRange(e, t0, t1);
    const double mid = 0.5 * (t0 + t1);
    while (!p.fromStart.empty() && p.fromStart.back() >= mid) p.fromStart.pop_back();
    while (!p.fromEnd.empty() && p.fromEnd.back() <= mid) p.fromEnd.pop_back();
  }
  return pts;
}

}  // namespace paramesh
