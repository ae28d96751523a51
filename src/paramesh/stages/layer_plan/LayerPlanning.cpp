// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file LayerPlanning.cpp
/// Boundary-layer planning (the 1D part): which edges carry which layer specification, the row
/// laws, and the outermost columns' points on the neighbouring non-layer edges, so that those
/// edges are discretised through them. Reads model, p, baseField; writes blSpecOf, blLaws, blEnds,
/// blStats, field (layer sources).
#include <algorithm>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/pipeline/Tuning.hpp"
#include "paramesh/algo/FeatureDetect.hpp"

namespace paramesh {

using namespace tuning;

void MeshContext::planBoundaryLayers() {
  if (p.boundaryLayers.empty()) return;
  Timer tm;
  blSpecOf.assign(model.numEdges(), -1);
  for (auto& spec : p.boundaryLayers) {
    if (!spec.autoEdges) continue;
    const auto found = proposeLeadingEdges(model, 0.0, 10.0, 10.0, nullptr, &same.edgeRep);
    for (const RidgeCandidate& rc : found) {
      spec.edges.push_back(rc.edge + 1);
      report.proposedLeadingEdges.push_back({rc.edge + 1, rc.acrossCurvature > 0 ? 1.0 / rc.acrossCurvature : 0.0, rc.ratio});
    }
    log.info("leading edges proposed: " + std::to_string(found.size()));
    if (found.empty()) report.warnings.push_back("no leading edge was found for the automatic boundary layer");
  }
  for (size_t s = 0; s < p.boundaryLayers.size(); ++s) {
    blLaws.push_back(LayerLaw::from(p.boundaryLayers[s]));
    for (int e1 : p.boundaryLayers[s].edges) {
      const int rep = same.edgeRep[e1 - 1];
      for (int e = 0; e < model.numEdges(); ++e)  // coincident edges of unsewn faces grow too
        if (same.edgeRep[e] == rep) {
          if (model.edgeDegenerate(e))
            throw ParameterError("boundary layer #" + std::to_string(s + 1) + ": Edge" + std::to_string(e + 1) +
                                 " is degenerate (a point) and cannot carry a boundary layer");
          blSpecOf[e] = (int)s;
        }
    }
  }
  blStats.assign(blLaws.size(), FaceBLResult::SpecStats());
  blEnds = planEndColumns(model, blSpecOf, blLaws, &same);
  baseField = field;
  // the points of the outermost columns are size sources: edges and faces grade from them
  for (int e = 0; e < model.numEdges(); ++e) {
    const auto& bp = blEnds[e];
    if (bp.fromStart.empty() && bp.fromEnd.empty()) continue;
    auto c = model.makeCurve(e);
    for (int side = 0; side < 2; ++side) {
      const auto& ts = side == 0 ? bp.fromStart : bp.fromEnd;
      Vec3 prev = c->eval(side == 0 ? edgeT0(e) : edgeT1(e));
      for (double t : ts) {
        const Vec3 q = c->eval(t);
        field.addSource(q, std::max(dist(q, prev), p.minSize));
        prev = q;
      }
    }
  }
  field.build();
  stage("boundary_layer_plan", tm.seconds());
}

double MeshContext::edgeT0(int e) const {
  double a, b;
  model.edgeRange(e, a, b);
  return a;
}

double MeshContext::edgeT1(int e) const {
  double a, b;
  model.edgeRange(e, a, b);
  return b;
}

bool MeshContext::hasBoundaryLayer(int f) const {
  if (blSpecOf.empty()) return false;
  for (const Wire& w : model.faceWires(f))
    for (const EdgeUse& u : w.uses)
      if (blSpecOf[u.edge] >= 0) return true;
  return false;
}

}  // namespace paramesh
