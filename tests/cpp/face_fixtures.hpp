// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file face_fixtures.hpp
/// Helpers shared by the face-level tests (test_ops.cpp, test_crest.cpp): a constant size field,
/// a face's boundary discretised as the pipeline does it, the mean of a sample.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

#include "paramesh/algo/FaceMesher.hpp"
#include "paramesh/geom/Geometry.hpp"
#include "paramesh/model/EdgeDiscretizer.hpp"
#include "paramesh/size/SizeField.hpp"

namespace paramesh::test {

/// A constant size field h.
inline SizeField constantField(double h) {
  SizeField f(h, 1.2);
  f.build();
  return f;
}

/// The boundary of face f of m: its wires' edges discretised against `field` (nodes shared at the
/// vertices, node = index in nodeXyz), one loop per wire.
inline void discretizedBoundary(const IGeometryModel& m, const SizeField& field, int f, FaceBoundary& fb,
                                std::vector<Vec3>& nodeXyz) {
  std::map<int, int> vertexNode;
  auto nodeOfVertex = [&](int v) {
    auto it = vertexNode.find(v);
    if (it != vertexNode.end()) return it->second;
    nodeXyz.push_back(m.vertexPoint(v));
    return vertexNode[v] = (int)nodeXyz.size() - 1;
  };
  int wi = 0;
  for (const Wire& w : m.faceWires(f)) {
    std::vector<BoundaryVertex> loop;
    for (size_t k = 0; k < w.uses.size(); ++k) {
      const EdgeUse& use = w.uses[k];
      auto c = m.makeCurve(use.edge);
      auto pc = m.makePCurve(f, wi, (int)k);
      ASSERT_TRUE(c && pc);
      double t0, t1;
      m.edgeRange(use.edge, t0, t1);
      CurveSampling cs = sampleCurve(*c, t0, t1, &field);
      std::vector<double> t = discretizeCurve(cs, field, 1, M_PI / 3);
      std::vector<int> nodes(t.size());
      nodes.front() = nodeOfVertex(m.edgeVertex(use.edge, 0));
      nodes.back() = nodeOfVertex(m.edgeVertex(use.edge, 1));
      for (size_t i = 1; i + 1 < t.size(); ++i) {
        nodeXyz.push_back(c->eval(t[i]));
        nodes[i] = (int)nodeXyz.size() - 1;
      }
      for (size_t i = 0; i + 1 < t.size(); ++i) {  // the last point is the next use's first
        const size_t j = use.reversed ? t.size() - 1 - i : i;
        BoundaryVertex bv;
        bv.uv = pc->eval(t[j]);
        bv.node = nodes[j];
        bv.xyz = nodeXyz[bv.node];
        loop.push_back(bv);
      }
    }
    fb.loops.push_back(loop);
    ++wi;
  }
}

inline double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0 : s / v.size();
}

}  // namespace paramesh::test
