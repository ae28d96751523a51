// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file SizeFieldBuild.cpp
/// Sizing stage: the size field from curvature, deviation, feature and user sources, and the
/// proximity sources across thin gaps. Reads model, p; writes field, baseField, log.
#include <algorithm>
#include <string>
#include <vector>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/pipeline/Tuning.hpp"
#include "paramesh/util/Parallel.hpp"
#include "paramesh/size/Proximity.hpp"

namespace paramesh {

using namespace tuning;

void MeshContext::buildSizeField() {
  Timer tm;
  const double hmax = std::min(p.size, p.maxSize);
  field = SizeField(hmax, p.grading);
  std::vector<std::vector<SizeSource>> per;
  if (p.curvatureAngle > 0 || p.maxDeviation > 0) {
    const double ang = p.curvatureAngle * kPi / 180.0;
    // edges: chords of boundary edges cannot be refined inside a face, so their sag is bounded
    // by 1D sizes (a boundary chord with sag s leaves ~2s/3 at the centroid of its triangle)
    const double dev = 1.4 * p.maxDeviation * p.size;
    // faces: an equilateral triangle of edge h on a surface of curvature k has its centroid
    // about h^2 k / 6 off it, and the sampler's size for a deviation d is the chord of sag d,
    // sqrt(8 d / k): 3/4 of the bound gives sqrt(6 d / k). Without it the refinement meets the
    // bound alone, split by split: needles (measured: docs/tuning/pipeline.md)
    const double faceDev = 0.75 * p.maxDeviation * p.size;
    const int nf = model.numFaces(), ne = model.numEdges();
    per.resize(nf + ne);
    std::vector<FaceSamplingStats> stats(nf);
    std::vector<char> failed(nf + ne, 0);
    parallelFor(nf + ne, threads, [&](int i) {
      progress.poll();
      try {
        per[i] = i < nf ? faceCurvatureSources(model, i, ang, p.minSize, hmax, faceDev, &stats[i])
                        : edgeCurvatureSources(model, i - nf, ang, p.minSize, hmax, dev);
      } catch (const Cancelled&) {
        throw;
      } catch (...) {
        failed[i] = 1;
      }
    });
    // a face sampled coarser than its sizes, or not at all, gets larger elements than the
    // curvature asks for: say so in the report, not only in the log
    for (int i = 0; i < nf + ne; ++i) {
      if (!failed[i] && !(i < nf && stats[i].truncated)) continue;
      const std::string name = (i < nf ? "Face" : "Edge") + std::to_string(i < nf ? i + 1 : i - nf + 1);
      const std::string w =
          failed[i] ? "curvature sampling failed on " + name + ": its curvature sizes are missing"
                    : "curvature sampling of " + name + " stopped at its budget of " +
                          std::to_string(kFaceSamplingBudget) +
                          " cells: part of the face is sampled coarser than its curvature sizes (a larger min-size or curvature angle samples it in full)";
      report.warnings.push_back(w);
      log.warn(w);
    }
  }
  for (const LocalSize& l : p.localSizes) per.push_back(localSizeSources(model, l));
  for (auto& v : per)
    for (auto& s : v) field.addSource(s.p, std::max(s.h, p.minSize));
  field.build();
  stage("size_field", tm.seconds());
}

void MeshContext::addProximitySources() {
  Timer tm;
  // a first surface mesh with the sizes so far tells where walls and faces are thin
  MeshParams q = p;
  q.proximity = 0;
  q.nearestFaceCheck = false;
  q.nearestFaceBudget = 0;
  q.order = 1;
  q.quads = false;
  q.optimizePasses = 1;
  q.boundaryLayers.clear();
  Mesher first(model, q, {}, [this](double, const std::string&) { return !progress.isCancelled(); });
  MeshOutput coarse = first.run();
  const auto src = proximitySources(coarse.mesh, p.proximity, std::min(p.size, p.maxSize), p.minSize);
  for (const auto& s : src) field.addSource(s.p, s.h);
  field.build();
  log.info("proximity: " + std::to_string(src.size()) + " size sources from thin walls and narrow faces");
  stage("proximity", tm.seconds());
}

}  // namespace paramesh
