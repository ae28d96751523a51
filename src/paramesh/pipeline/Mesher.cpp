// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Mesher.cpp
/// The surface pipeline's driver: each step is a stage of MeshContext, in its own folder under
/// src/paramesh/stages/ (setup, sizing, layer_plan, edges, faces, nearest_face, volume, second_order,
/// report).
#include "paramesh/pipeline/Mesher.hpp"

#include <memory>
#include <string>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/util/Error.hpp"
#include "paramesh/util/Format.hpp"
#include "paramesh/util/Timer.hpp"

namespace paramesh {

const char* toString(RunStatus s) {
  switch (s) {
    case RunStatus::Ok: return "ok";
    case RunStatus::Degraded: return "degraded";
    default: return "failed";
  }
}

struct Mesher::Impl : MeshContext {
  using MeshContext::MeshContext;
};

Mesher::Mesher(const IGeometryModel& model, MeshParams params, LogSink sink, ProgressCallback progress)
    : d_(std::make_unique<Impl>(model, std::move(params), std::move(sink), std::move(progress))) {
  d_->p.validate();
}
Mesher::~Mesher() = default;
void Mesher::cancel() { d_->progress.cancel(); }

MeshOutput Mesher::run() {
  try {
    return runUnbudgeted();
  } catch (const Cancelled&) {
    if (!d_->progress.overBudget()) throw;
    throw ParameterError("the mesh would hold more than max_elements = " + std::to_string(d_->p.maxElements) +
                         " elements at size " + fmt(d_->p.size) + " (the model's diagonal is " +
                         fmt(d_->model.boundingBox().diagonal()) +
                         "): use a larger size, or raise max_elements (--max-elements)");
  }
}
MeshOutput Mesher::runUnbudgeted() {
  MeshContext& c = *d_;
  Timer total;
  c.resolveParams();           // setup: defaults, checks on the model and the parameters
  c.findCoincidentTopology();  // setup: coincident vertices and edges of unsewn faces
  c.progress.report(0.0, "size field");
  c.buildSizeField();          // sizing: curvature, deviation, feature and user sources
  if (c.p.proximity > 0) c.addProximitySources();
  c.planBoundaryLayers();      // layer_plan: row heights, end columns on the neighbour edges
  c.meshRounds();              // edges and faces, again while the nearest-face check refines
  c.repairSurface();           // audit: folded / inverted elements mended where moving face nodes can
  if (c.p.volume) c.fillSolids();  // volume: tetrahedra inside each closed solid (nglib)
  if (c.p.order == 2) c.secondOrder();
  c.finish();                  // report: quality, deviation, warnings
  c.audit();                   // audit: closure, conformity, duplicates, folds, nodes on the CAD
  c.stage("total", total.seconds());
  c.progress.report(1.0, "done");
  MeshOutput out;
  out.mesh = std::move(c.mesh);
  out.report = std::move(c.report);
  return out;
}

}  // namespace paramesh
