// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file DiscretizeEdges.cpp
/// Edge stage: every CAD edge discretised once by 3D length in the size field (short edges become
/// size sources, strips get rows, narrow gaps and corners are re-spaced: NarrowGaps.cpp,
/// Corners.cpp), then the edge nodes created and shared by the faces. Reads model, field, blEnds,
/// same; writes edges, vertexNode, mesh.nodes / segments, segmentT, edgeStage.error, edgeStage.last.
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/pipeline/Tuning.hpp"
#include "paramesh/util/Parallel.hpp"
#include "paramesh/model/EdgeDiscretizer.hpp"
#include "paramesh/util/Format.hpp"

namespace paramesh {

using namespace tuning;

std::string MeshContext::edgeFailure(const std::function<void()>& work) {
  try {
    work();
  } catch (const Cancelled&) {
    throw;
  } catch (const std::exception& x) {
    return x.what();
  } catch (...) {
    return "the geometry kernel failed while evaluating its curve";
  }
  return "";
}

void MeshContext::discretizeEdges() {
  const int ne = model.numEdges();
  std::vector<std::vector<double>> ts(ne);
  std::vector<char> degen(ne, 0);
  edgeStage.error.assign(ne, std::string());
  discretizeAll(ts, degen, nullptr);
  // CAD edges much shorter than the size field, in chains (a finely detailed boundary) or split
  // into 3+ segments by the turning limit (tight arcs), become size sources at their segment
  // lengths, and the edges are discretised again: the neighbouring edges and the face interiors
  // grade down to them instead of standing long thin triangles on them. Short edges that close
  // a narrow strip are left alone (refining there only multiplies the strip's slivers).
  if (p.shortEdgeSources && blLaws.empty()) refineShortEdges(ts, degen);
  splitParallelChords(ts, degen);
  // boundary refinements of the discretisation; a kernel failure in one leaves the edges as
  // they were before it (the mesh stays valid, only less well shaped there)
  auto refineStage = [&](const char* what, const std::function<bool()>& stage) {
    const std::vector<std::vector<double>> before = ts;
    try {
      if (stage()) splitParallelChords(ts, degen);
    } catch (const Cancelled&) {
      throw;
    } catch (const std::exception& e) {
      ts = before;
      log.warn(std::string(what) + " skipped: " + e.what());
    }
  };
  if (p.staggerNarrowGaps && blLaws.empty())
    refineStage("narrow gaps", [&] { return staggerNarrowGaps(ts, degen); });
  if (blLaws.empty()) refineStage("corner spacing", [&] { return matchCornerSegments(ts, degen); });
  edgeStage.last = {true, ts, degen, edgeStage.error};
  createEdgeNodes(ts, degen);
}

void MeshContext::discretizeOne(int e, std::vector<std::vector<double>>& ts, const std::function<void()>& body) {
  // an edge the geometry kernel cannot evaluate (a damaged curve) fails alone: it gets no nodes,
  // the faces bounded by it fail naming it, the others are meshed
  if (!edgeStage.error[e].empty()) return;
  edgeStage.error[e] = edgeFailure(body);
  if (!edgeStage.error[e].empty()) ts[e].clear();
}

void MeshContext::discretizeAll(std::vector<std::vector<double>>& ts, std::vector<char>& degen,
                                const std::vector<char>* only) {
  parallelFor(model.numEdges(), threads, [&](int e) {
    if (only && !(*only)[e]) return;
    discretizeOne(e, ts, [&] { discretizeEdge(e, ts, degen); });
  });
}

void MeshContext::discretizeEdge(int e, std::vector<std::vector<double>>& ts, std::vector<char>& degen) {
  progress.poll();
  double t0, t1;
  model.edgeRange(e, t0, t1);
  if (same.edgeRep[e] != e) return;  // meshed through its representative
  if (model.edgeDegenerate(e)) {
    degen[e] = 1;
    ts[e] = {t0, t1};
    return;
  }
  auto c = model.makeCurve(e);
  const EdgeBLPoints* bp = blEnds.empty() ? nullptr : &blEnds[e];
  if (bp && (!bp->fromStart.empty() || !bp->fromEnd.empty())) {
    // boundary-layer points fixed at the ends, the middle discretised as usual
    const double a = bp->fromStart.empty() ? t0 : bp->fromStart.back();
    const double b = bp->fromEnd.empty() ? t1 : bp->fromEnd.back();
    std::vector<double> t{t0};
    t.insert(t.end(), bp->fromStart.begin(), bp->fromStart.end());
    CurveSampling cs = sampleCurve(*c, a, b, &field);
    const std::vector<double> midT = discretizeCurve(cs, field, 1, kPi / 3.0);
    t.insert(t.end(), midT.begin() + 1, midT.end() - 1);
    t.insert(t.end(), bp->fromEnd.rbegin(), bp->fromEnd.rend());
    t.push_back(t1);
    ts[e] = t;
    return;
  }
  // BL edges keep their spanwise spacing: the layers' own sizes do not refine them
  const SizeField& f = (!blSpecOf.empty() && blSpecOf[e] >= 0) ? baseField : field;
  CurveSampling cs = sampleCurve(*c, t0, t1, &f);
  const int v0 = model.edgeVertex(e, 0), v1 = model.edgeVertex(e, 1);
  const bool closed = (v0 >= 0 && v0 == v1) || dist(cs.p.front(), cs.p.back()) < 1e-9 * (1 + cs.length());
  ts[e] = discretizeCurve(cs, f, closed ? 3 : 1, kPi / 3.0);
}

void MeshContext::reuseEdges() {
  edgeStage.error = edgeStage.last.errors;
  createEdgeNodes(edgeStage.last.ts, edgeStage.last.degen);
}

void MeshContext::splitParallelChords(std::vector<std::vector<double>>& ts, const std::vector<char>& degen) const {
  const int ne = model.numEdges();
  std::map<std::pair<int, int>, std::vector<int>> byEnds;
  for (int e = 0; e < ne; ++e) {
    if (degen[e] || ts[e].size() != 2) continue;
    int a = model.edgeVertex(e, 0), b = model.edgeVertex(e, 1);
    if (a < 0 || b < 0) continue;
    a = same.vertexRep[a];
    b = same.vertexRep[b];
    byEnds[{std::min(a, b), std::max(a, b)}].push_back(e);
  }
  for (auto& kv : byEnds) {
    if (kv.second.size() < 2) continue;
    for (size_t k = 1; k < kv.second.size(); ++k) {
      int e = kv.second[k];
      ts[e] = {ts[e][0], 0.5 * (ts[e][0] + ts[e][1]), ts[e][1]};
    }
  }
}

void MeshContext::createEdgeNodes(const std::vector<std::vector<double>>& ts, const std::vector<char>& degen) {
  const int ne = model.numEdges();
  vertexNode.assign(model.numVertices(), -1);
  edges.assign(ne, EdgeMesh());
  auto nodeOfVertex = [&](int v) {
    const int r = same.vertexRep[v];
    if (vertexNode[r] < 0) vertexNode[r] = mesh.addNode(model.vertexPoint(r), NodeKind::Vertex, r + 1);
    vertexNode[v] = vertexNode[r];
    return vertexNode[v];
  };
  for (int e = 0; e < ne; ++e) {
    const int v0 = model.edgeVertex(e, 0), v1 = model.edgeVertex(e, 1);
    if (v0 >= 0) nodeOfVertex(v0);
    if (v1 >= 0) nodeOfVertex(v1);
  }
  // Interior nodes of different edges that coincide (unsewn patches whose curves agree at the
  // nodes but not everywhere within the merge tolerance) become one node: no duplicate nodes.
  const double eps = 1e-8 * model.boundingBox().diagonal();
  std::unordered_map<uint64_t, std::vector<int>> edgeNodeCells;
  auto cellOf = [eps](Vec3 p, int di, int dj, int dk) {
    const auto q = [eps](double x, int d) { return (uint64_t)((int64_t)std::floor(x / (4 * eps)) + d) & 0x1FFFFF; };
    return (q(p.x, di) << 42) | (q(p.y, dj) << 21) | q(p.z, dk);
  };
  // a curve that leaves the model's box by more than its diagonal is damaged (docs/tuning/pipeline.md)
  Box3 reach = model.boundingBox();
  const double diag = reach.diagonal();
  for (int i = 0; i < 3; ++i) {
    reach.lo[i] -= diag;
    reach.hi[i] += diag;
  }
  auto edgeNode = [&](Vec3 p, int e, double t) {
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj)
        for (int dk = -1; dk <= 1; ++dk) {
          auto it = edgeNodeCells.find(cellOf(p, di, dj, dk));
          if (it == edgeNodeCells.end()) continue;
          for (int nd : it->second)
            if (mesh.nodeEntity[nd] != e + 1 && dist(mesh.nodes[nd], p) <= eps) return nd;
        }
    const int nd = mesh.addNode(p, NodeKind::Edge, e + 1, {t, 0});
    edgeNodeCells[cellOf(p, 0, 0, 0)].push_back(nd);
    return nd;
  };
  for (int e = 0; e < ne; ++e) {
    if (same.edgeRep[e] != e) continue;
    EdgeMesh& em = edges[e];
    em.t = ts[e];
    em.degenerate = degen[e];
    const int v0 = model.edgeVertex(e, 0), v1 = model.edgeVertex(e, 1);
    const size_t n = em.t.size();
    // the points first: an edge that cannot be evaluated, or whose curve leaves the model's box
    // by more than its diagonal (damaged), fails alone and adds no node
    std::vector<Vec3> xyz(n);
    if (!em.degenerate && n > 0) {
      edgeStage.error[e] = edgeFailure([&] {
        std::unique_ptr<ICurve> c = model.makeCurve(e);
        for (size_t i = 0; i < n; ++i) {
          const Vec3 q = c->eval(em.t[i]);
          for (int k = 0; k < 3; ++k)
            if (!(q[k] >= reach.lo[k] && q[k] <= reach.hi[k]))
              throw InputError("its curve passes through (" + fmt(q.x) + ", " + fmt(q.y) + ", " + fmt(q.z) +
                               "), far outside the model's bounding box: its geometry is damaged");
          xyz[i] = q;
        }
      });
      if (!edgeStage.error[e].empty()) {
        em.t.clear();
        continue;
      }
    }
    em.nodes.resize(n);
    for (size_t i = 0; i < n; ++i) {
      if (i == 0 && v0 >= 0) {
        em.nodes[i] = vertexNode[v0];
      } else if (i + 1 == n && v1 >= 0) {
        em.nodes[i] = vertexNode[v1];
      } else if (em.degenerate) {
        em.nodes[i] = v0 >= 0 ? vertexNode[v0] : (v1 >= 0 ? vertexNode[v1] : -1);
      } else {
        em.nodes[i] = edgeNode(xyz[i], e, em.t[i]);
      }
    }
    if (!em.degenerate)
      for (size_t i = 0; i + 1 < n; ++i) {
        if (em.nodes[i] == em.nodes[i + 1]) continue;  // an edge shorter than the merge tolerance
        if (mesh.nodeEntity[em.nodes[i]] != e + 1 && mesh.nodeEntity[em.nodes[i + 1]] != e + 1 &&
            mesh.nodeKind[em.nodes[i]] == NodeKind::Edge && mesh.nodeKind[em.nodes[i + 1]] == NodeKind::Edge &&
            mesh.nodeEntity[em.nodes[i]] == mesh.nodeEntity[em.nodes[i + 1]])
          continue;  // this piece coincides with a piece of another edge: one 1D element
        mesh.segments.push_back({em.nodes[i], em.nodes[i + 1]});
        mesh.segmentEdge.push_back(e + 1);
        segmentT.push_back({em.t[i], em.t[i + 1]});
      }
  }
  // coincident edges take their representative's nodes, with parameters on their own curve
  for (int e = 0; e < ne; ++e) {
    const int r = same.edgeRep[e];
    if (r == e) continue;
    const EdgeMesh& rm = edges[r];
    EdgeMesh& em = edges[e];
    if (!edgeStage.error[r].empty()) {
      edgeStage.error[e] = "it coincides with Edge" + std::to_string(r + 1) + ", which failed: " + edgeStage.error[r];
      continue;
    }
    const size_t n = rm.nodes.size();
    edgeStage.error[e] = edgeFailure([&] {
      auto c = model.makeCurve(e);
      double t0, t1;
      model.edgeRange(e, t0, t1);
      em.nodes.resize(n);
      em.t.resize(n);
      for (size_t i = 0; i < n; ++i) {
        const size_t j = same.edgeReversed[e] ? n - 1 - i : i;
        em.nodes[i] = rm.nodes[j];
        const double seed = t0 + (t1 - t0) * (double)i / (double)(n - 1);
        em.t[i] = i == 0 ? t0 : (i + 1 == n ? t1 : c->project(mesh.nodes[em.nodes[i]], seed, t0, t1));
      }
    });
    if (!edgeStage.error[e].empty()) {
      em.nodes.clear();
      em.t.clear();
    }
  }
}

}  // namespace paramesh
