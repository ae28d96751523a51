// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Setup.cpp
/// Setup stage: resolves the parameters' defaults against the model (size from the diagonal,
/// min size, threads) and refuses damaged input; finds coincident vertices and edges of unsewn
/// faces. Reads model, p; writes p, minSizeGiven, threads, same, report (model counts).
#include <algorithm>
#include <cmath>
#include <string>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/pipeline/Tuning.hpp"
#include "paramesh/util/Parallel.hpp"
#include "paramesh/util/Format.hpp"

namespace paramesh {

using namespace tuning;

namespace {

/// A first row or a layer thicker than the whole model is a typo (a unit, a digit), not a
/// request: a ParameterError naming the spec (i: 0-based).
void checkLayerAgainstModel(const BoundaryLayerSpec& b, size_t i, double diag) {
  const std::string id = describeBoundaryLayer(b, i);
  if (b.firstHeight > diag)
    throw ParameterError(id + ": first height " + fmt(b.firstHeight) + " exceeds the model's diagonal " + fmt(diag));
  const double total = layerThickness(b);
  if (total > diag)
    throw ParameterError(id + ": total thickness " + fmt(total) +
                         (b.thickness > 0 ? std::string()
                                          : " (" + std::to_string(b.layers) + " layers from first height " +
                                                fmt(b.firstHeight) + ", growth " + fmt(b.growth) + ")") +
                         " exceeds the model's diagonal " + fmt(diag));
}

}  // namespace

void MeshContext::resolveParams() {
  p.validate();
  const Box3 box = model.boundingBox();
  const double diag = box.diagonal();
  if (!(diag > 0)) throw InputError("the model has zero extent");
  // damaged numbers make the edge discretisation run for ever (docs/tuning/pipeline.md)
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(box.lo[i]) || !std::isfinite(box.hi[i]) || std::fabs(box.lo[i]) > kMaxCoordinate ||
        std::fabs(box.hi[i]) > kMaxCoordinate)
      throw InputError("the model's bounding box reaches " + fmt(std::max(std::fabs(box.lo[i]), std::fabs(box.hi[i]))) +
                       " (beyond " + fmt(kMaxCoordinate) + " model units): its geometry is damaged");
  if (!isGiven(p.size)) p.size = diag / 50.0;
  if (!isGiven(p.maxSize)) p.maxSize = p.size;
  // curvature sizing (for an angle or a deviation) resolves radii down to size/1000 unless told
  // otherwise (fillets, blade tips and leading edges are far smaller than the global size);
  // other sources stop at 1/100
  minSizeGiven = isGiven(p.minSize);
  if (!minSizeGiven) p.minSize = std::min(p.size, p.maxSize) / (p.curvatureAngle > 0 || p.maxDeviation > 0 ? 1000.0 : 100.0);
  if (!isGiven(p.volumeMaxSize)) p.volumeMaxSize = p.maxSize;
  if (p.minSize > p.maxSize) throw ParameterError("min_size (" + fmt(p.minSize) + ") is larger than max_size (" + fmt(p.maxSize) + ")");
  if (p.size < diag * 1e-6)
    throw ParameterError("size " + fmt(p.size) + " is below 1e-6 of the model diagonal (" + fmt(diag) +
                         "): the mesh would have more than 10^12 elements");
  auto checkRange = [&](int n, int max, const std::string& what, const std::string& ctx) {
    if (n < 1 || n > max)
      throw ParameterError(ctx + ": " + what + std::to_string(n) + " does not exist (the model has " +
                           std::to_string(max) + " " + what + "s)");
  };
  for (size_t i = 0; i < p.localSizes.size(); ++i) {
    const LocalSize& l = p.localSizes[i];
    for (int e : l.entities) {
      if (l.kind == LocalSize::Kind::Face) checkRange(e, model.numFaces(), "Face", "local size #" + std::to_string(i + 1));
      if (l.kind == LocalSize::Kind::Edge) checkRange(e, model.numEdges(), "Edge", "local size #" + std::to_string(i + 1));
      if (l.kind == LocalSize::Kind::Vertex) checkRange(e, model.numVertices(), "Vertex", "local size #" + std::to_string(i + 1));
    }
  }
  for (const MeshGroup& g : p.groups)
    for (int e : g.entities)
      checkRange(e, g.dim == 1 ? model.numEdges() : g.dim == 2 ? model.numFaces() : model.numSolids(),
                 g.dim == 1 ? "Edge" : g.dim == 2 ? "Face" : "Solid", "group '" + g.name + "'");
  for (size_t i = 0; i < p.boundaryLayers.size(); ++i) {
    for (int e : p.boundaryLayers[i].edges)
      checkRange(e, model.numEdges(), "Edge", "boundary layer #" + std::to_string(i + 1));
    checkLayerAgainstModel(p.boundaryLayers[i], i, diag);
  }
  threads = resolveThreads(p.threads);
  progress.setPointBudget(p.maxElements / 2);  // the proximity measurement meshes too
  report.size = p.size;
  report.minSize = p.minSize;
  report.maxSize = p.maxSize;
  report.curvatureAngle = p.curvatureAngle;
  report.maxDeviation = p.maxDeviation;
  report.grading = p.grading;
  report.volume = p.volume;
  report.volumeMaxSize = p.volumeMaxSize;
  report.volumeOptimize = p.volumeOptimize;
  report.threads = threads;
  report.source = model.source();
  for (const std::string& w : model.readWarnings()) {
    report.warnings.push_back(w);
    log.warn(w);
  }
  report.cadFaces = model.numFaces();
  report.cadEdges = model.numEdges();
  report.cadVertices = model.numVertices();
  report.cadSolids = model.numSolids();
  mesh.numFaces = model.numFaces();
  mesh.groups = p.groups;
  mesh.numEdges = model.numEdges();
  mesh.numVertices = model.numVertices();
  mesh.numSolids = model.numSolids();
}

void MeshContext::findCoincidentTopology() {
  Timer tm;
  // gaps up to 1e-6 of the diagonal are closed (nodes then stay within 1e-4 h of every face for
  // h >= diagonal/100); larger gaps are real and stay open
  same = findCoincident(model, 2e-7 * model.boundingBox().diagonal());
  if (same.mergedEdges || same.mergedVertices)
    log.info("unsewn CAD: " + std::to_string(same.mergedEdges) + " coincident edges and " +
             std::to_string(same.mergedVertices) + " coincident vertices are meshed as one");
  stage("topology", tm.seconds());
}

}  // namespace paramesh
