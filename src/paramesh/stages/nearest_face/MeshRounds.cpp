// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshRounds.cpp
/// The meshing rounds: edges, then faces, repeated while the nearest-face check finds triangles
/// whose centroid lies nearer another CAD face than their own. Each round adds local deviation
/// bounds or size sources; a round predicted over the triangle budget is not meshed, and the
/// unrefined mesh is taken back when refining does not pay (MeshContext.hpp: reads the size
/// field and parameters; writes mesh, edges, report, and the field of the kept round).
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/pipeline/Tuning.hpp"
#include "paramesh/util/Format.hpp"

namespace paramesh {

using namespace tuning;

void MeshContext::meshRound(bool sameField) {
  progress.report(0.05, "edges");
  {
    Timer te;
    if (sameField && edgeStage.last.valid)
      reuseEdges();
    else
      discretizeEdges();
    stage("edges", te.seconds());
  }
  {
    size_t most = 0;
    int mostEdge = -1;
    for (size_t e = 0; e < edges.size(); ++e)
      if (edges[e].nodes.size() > most + 1) {
        most = edges[e].nodes.size() - 1;
        mostEdge = (int)e;
      }
    log.info("edges discretised: " + std::to_string(mesh.segments.size()) + " segments, " +
             std::to_string(field.numSources()) + " size sources" +
             (mostEdge >= 0 ? ", most on Edge" + std::to_string(mostEdge + 1) + " (" + std::to_string(most) + ")" : ""));
  }
  progress.report(0.15, "faces");
  progress.setPointBudget(p.maxElements / 2);  // a triangle mesh has about half as many points
  meshFaces();
}

std::vector<SizeSource> MeshContext::roundSources(const NearestFaceResult& nfr, int& zoned) {
  // first a local bound on the flagged triangles' faces (refined in place, the size field and
  // the edges unchanged); the triangles such a bound did not mend get size sources
  std::vector<SizeSource> src;
  zoned = 0;
  const std::vector<char> zone = addDeviationZones(nfr);
  for (size_t k = 0; k < nfr.found.size(); ++k) {
    if (zone[k]) {
      ++zoned;
    } else if (nfr.firstSource[k] >= 0) {
      src.insert(src.end(), nfr.sources.begin() + nfr.firstSource[k], nfr.sources.begin() + nfr.firstSource[k] + 4);
    }
  }
  return src;
}

double MeshContext::predictGrowth(const SizeField& next, const MeshState& unrefined) const {
  // elements go with 1 / h^2: the present mesh, resized to the new field, predicts the next
  // one; far over the budget, meshing again would be wasted (the unrefined mesh is kept). The
  // prediction runs high, hence the margin kPredictMargin
  double count = 0;
  for (const auto& T : mesh.triangles) {
    const Vec3 c = (1.0 / 3) * (mesh.nodes[T[0]] + mesh.nodes[T[1]] + mesh.nodes[T[2]]);
    // where the round's sources do not reach, the field is the same as now (they include
    // the last round's): no query of the millions of sources under them
    if (!(next.ownSize(c) < next.hmax())) {
      count += 1.0;
      continue;
    }
    const double r = field.size(c) / next.size(c);
    count += r * r;
  }
  count += (double)mesh.quads.size();
  return count / (double)std::max<size_t>(1, elementCount(unrefined.mesh)) - 1.0;
}

void MeshContext::meshRounds() {
  // the field so far; the nearest-face check adds its sources to it and the mesh is redone. By
  // default (no --nearest-face-check) the refined mesh is kept only within the triangle budget.
  const bool force = p.nearestFaceCheck, check = force || p.nearestFaceBudget > 0;
  // the field before the rounds, under each round's field of the sources they add (cheaper than
  // a copy per round: docs/tuning/pipeline.md)
  const std::shared_ptr<const SizeField> field0 = check ? std::make_shared<const SizeField>(field) : nullptr;
  std::vector<SizeSource> extra;
  std::unique_ptr<MeshState> unrefined;
  double predictedGrowth = -1;  // set when a next round was predicted over the budget
  bool sameField = false;       // this round has the last round's size field: its edges too
  for (int round = 0;; ++round) {
    meshRound(sameField);
    sameField = false;
    if (!check) break;
    const NearestFaceResult nfr = nearestFaceCheck();
    if (round == 0 && !force && nfr.flagged) unrefined = std::make_unique<MeshState>(saveState());
    if (!nfr.flagged || round == kNearestFaceRounds) break;
    int zoned = 0;
    std::vector<SizeSource> src = roundSources(nfr, zoned);
    if (src.empty() && zoned == 0) break;
    // two rounds in a row without fewer flagged triangles: the refinement does not converge; a
    // single such round happens on the way (measured: docs/tuning/pipeline.md)
    const auto& fl = report.nearestFaceFlagged;
    const size_t nr = fl.size();
    if (nr >= 3 && fl[nr - 1] >= fl[nr - 2] && fl[nr - 2] >= fl[nr - 3]) break;
    // over the budget already: no more rounds (the unrefined mesh is taken back below)
    if (unrefined && round > 0 &&
        (double)elementCount(mesh) > (1.0 + p.nearestFaceBudget) * (double)elementCount(unrefined->mesh))
      break;
    if (src.empty()) {  // zones only: the same field and edges, the zoned faces meshed again
      rounds.sources.clear();
      resetMesh();
      sameField = true;
      continue;
    }
    extra.insert(extra.end(), src.begin(), src.end());
    SizeField next(field0->hmax(), field0->slope() + 1.0);
    next.setUnder(field0);
    for (const SizeSource& s : extra) next.addSource(s.p, std::max(s.h, p.minSize), kNearestFaceSlope);
    next.build();
    if (unrefined) {
      const double g = predictGrowth(next, *unrefined);
      if (g > kPredictMargin * p.nearestFaceBudget) {
        predictedGrowth = g;
        break;
      }
    }
    rounds.sources = std::move(src);
    resetMesh();
    field = std::move(next);
  }
  rounds.previous.reset();
  if (unrefined) settleRefinement(std::move(*unrefined), predictedGrowth);
}

void MeshContext::settleRefinement(MeshState&& unrefined, double predictedGrowth) {
  const double growth = std::max(predictedGrowth, (double)elementCount(mesh) /
                                                      (double)std::max<size_t>(1, elementCount(unrefined.mesh)) - 1.0);
  report.nearestFaceGrowth = growth;
  const int flagged0 = report.nearestFaceFlagged.front(), left = report.nearestFaceFlagged.back();
  if (left >= flagged0 && predictedGrowth < 0) {  // refining did not help: the unrefined mesh is as good and smaller
    restoreState(std::move(unrefined));
    report.nearestFaceOutcome = "kept unrefined";
    report.warnings.push_back(
        std::to_string(flagged0) + " triangles have their centroid nearer another CAD face than their own; refining "
        "them left " + std::to_string(left) + ": left unrefined");
    log.warn(report.warnings.back());
  } else if (growth <= p.nearestFaceBudget) {
    report.nearestFaceOutcome = "refined";
  } else {
    const int flagged = report.nearestFaceFlagged.front();
    restoreState(std::move(unrefined));
    report.nearestFaceOutcome = "kept unrefined";
    report.warnings.push_back(
        std::to_string(flagged) + " triangles are cut so deep into thin parts that their centroid lies nearer another CAD face "
        "than their own; refining them would add " + (predictedGrowth >= 0 ? "about " : "") +
        std::to_string((int)std::lround(100 * growth)) + (predictedGrowth >= 0 ? " %" : " % or more") +
        " triangles (budget " + fmt(100 * p.nearestFaceBudget) +
        " %): left unrefined (--nearest-face-check refines anyway)");
    log.warn(report.warnings.back());
  }
}

}  // namespace paramesh
