// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Mesher.hpp
/// The meshing context: runs the stages BuildModel -> SizeField -> DiscretizeEdges -> MeshFaces ->
/// Assemble -> Quality on a geometry model, with per-face failure isolation, progress, cancel and
/// a log sink. The library never prints: everything goes through the report and the sink.
#pragma once
#include <atomic>
#include <functional>
#include <memory>

#include "paramesh/geom/Geometry.hpp"
#include "paramesh/mesh/SurfaceMesh.hpp"
#include "paramesh/pipeline/Params.hpp"
#include "paramesh/pipeline/Report.hpp"
#include "paramesh/util/Log.hpp"

namespace paramesh {

struct MeshOutput {
  SurfaceMesh mesh;
  Report report;
};

class Mesher {
 public:
  /// The model must outlive the Mesher. Parameters are validated here (throws ParameterError).
  Mesher(const IGeometryModel& model, MeshParams params, LogSink sink = {}, ProgressCallback progress = {});
  ~Mesher();
  /// Runs every stage. Throws Cancelled when cancelled, ParameterError for parameters that do not
  /// fit the model (e.g. an edge number beyond the model, or a size at which the faces would hold
  /// more than max_elements); face failures are reported, not thrown.
  MeshOutput run();
  /// Requests cancellation (thread-safe); run() throws Cancelled soon after.
  void cancel();

 private:
  MeshOutput runUnbudgeted();
  struct Impl;
  std::unique_ptr<Impl> d_;
};

/// Quality summary of a mesh against a size function (h at edge midpoints).
QualitySummary summarizeQuality(const SurfaceMesh& m, const std::function<double(Vec3)>& h);

}  // namespace paramesh
