// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/pipeline/Params.hpp"

#include <cctype>
#include <cmath>
#include <sstream>

#include "paramesh/util/Error.hpp"

namespace paramesh {

namespace {
bool finite(double x) { return std::isfinite(x); }
std::string num(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

/// An optional length, when given, is a positive finite number (0 is not "the default": leaving
/// the length out is).
void checkLength(double v, const char* name, const char* byDefault) {
  if (isGiven(v) && !(finite(v) && v > 0))
    throw ParameterError(std::string(name) + " must be a positive length (got " + num(v) + "); leave it out for " +
                         byDefault);
}
}  // namespace

void MeshParams::validate() const {
  checkLength(size, "size", "the default (the bounding-box diagonal / 50)");
  checkLength(minSize, "min_size", "the default (size / 100, or size / 1000 with a curvature angle or a max deviation)");
  checkLength(maxSize, "max_size", "the default (size)");
  checkLength(volumeMaxSize, "volume_max_size", "the default (max_size)");
  if (isGiven(minSize) && isGiven(maxSize) && minSize > maxSize)
    throw ParameterError("min_size (" + num(minSize) + ") is larger than max_size (" + num(maxSize) + ")");
  if (!finite(curvatureAngle) || curvatureAngle < 0 || curvatureAngle >= 180)
    throw ParameterError("curvature_angle must be in [0, 180) degrees (got " + num(curvatureAngle) + ")");
  if (curvatureAngle > 0 && curvatureAngle < 0.5)
    throw ParameterError("curvature_angle below 0.5 degrees would need an unbounded number of elements (got " +
                         num(curvatureAngle) + ")");
  if (!finite(maxDeviation) || maxDeviation < 0 || maxDeviation > 1)
    throw ParameterError("max_deviation must be in [0, 1] (a fraction of size; got " + num(maxDeviation) + ")");
  if (!finite(grading) || grading <= 1.0 || grading > 10)
    throw ParameterError("grading must be in (1, 10] (got " + num(grading) + ")");
  if (threads < 0 || threads > 1024) throw ParameterError("threads must be in [0, 1024] (got " + std::to_string(threads) + ")");
  if (proximity < 0 || proximity > 100)
    throw ParameterError("proximity must be in [0, 100] elements (got " + std::to_string(proximity) + ")");
  if (!finite(nearestFaceBudget) || nearestFaceBudget < 0 || nearestFaceBudget > 10)
    throw ParameterError("nearest_face_budget must be in [0, 10] (a fraction of the triangles; got " +
                         num(nearestFaceBudget) + ")");
  if (order != 1 && order != 2) throw ParameterError("order must be 1 or 2 (got " + std::to_string(order) + ")");
  checkedMaxElements((double)maxElements);
  if (volumeOptimize < 0 || volumeOptimize > 10)
    throw ParameterError("volume_optimize must be in [0, 10] passes (got " + std::to_string(volumeOptimize) + ")");
  if (volume && quads)
    throw ParameterError("volume: the tetrahedra need a triangle surface mesh; leave out quads (--quads)");
  for (size_t i = 0; i < boundaryLayers.size() && volume; ++i)
    if (boundaryLayers[i].quads)
      throw ParameterError("volume: boundary layer #" + std::to_string(i + 1) +
                           " makes quads; the tetrahedra need triangles (give it quads = false, or --bl-triangles)");
  if (optimizePasses < 0 || optimizePasses > 100)
    throw ParameterError("optimize_passes must be in [0, 100] (got " + std::to_string(optimizePasses) + ")");
  for (size_t i = 0; i < localSizes.size(); ++i) {
    const LocalSize& l = localSizes[i];
    if (!finite(l.size) || l.size <= 0)
      throw ParameterError("local size #" + std::to_string(i + 1) + " must be > 0 (got " + num(l.size) + ")");
    if (l.entities.empty()) throw ParameterError("local size #" + std::to_string(i + 1) + " names no entity");
    for (int e : l.entities)
      if (e < 1) throw ParameterError("local size #" + std::to_string(i + 1) + ": entity numbers start at 1 (got " + std::to_string(e) + ")");
  }
  for (size_t i = 0; i < groups.size(); ++i) {
    const MeshGroup& g = groups[i];
    if (const std::string why = groupNameProblem(g.name); !why.empty()) throw ParameterError(why);
    if (g.dim < 1 || g.dim > 3) throw ParameterError("group '" + g.name + "': dim must be 1, 2 or 3");
    if (g.entities.empty()) throw ParameterError("group '" + g.name + "' names no entity");
    for (int e : g.entities)
      if (e < 1) throw ParameterError("group '" + g.name + "': entity numbers start at 1 (got " + std::to_string(e) + ")");
    for (size_t k = 0; k < i; ++k) {
      std::string a = g.name, b = groups[k].name;
      for (char& c : a) c = (char)std::tolower((unsigned char)c);
      for (char& c : b) c = (char)std::tolower((unsigned char)c);
      if (a == b) throw ParameterError("group '" + g.name + "' is given twice (names compare without case)");
    }
  }
  for (size_t i = 0; i < boundaryLayers.size(); ++i) {
    const BoundaryLayerSpec& b = boundaryLayers[i];
    const std::string id = "boundary layer #" + std::to_string(i + 1);
    if (b.edges.empty() && !b.autoEdges) throw ParameterError(id + ": no edge given (give edges or auto)");
    for (int e : b.edges)
      if (e < 1) throw ParameterError(id + ": edge numbers start at 1 (got " + std::to_string(e) + ")");
    if (!finite(b.firstHeight) || b.firstHeight <= 0)
      throw ParameterError(id + ": first_height must be > 0 (got " + num(b.firstHeight) + ")");
    if (!finite(b.growth) || b.growth < 1.0 || b.growth > 5.0)
      throw ParameterError(id + ": growth must be in [1, 5] (got " + num(b.growth) + ")");
    if (b.layers < 0 || b.layers > 1000) throw ParameterError(id + ": layers must be in [1, 1000] (got " + std::to_string(b.layers) + ")");
    if (!finite(b.thickness) || b.thickness < 0) throw ParameterError(id + ": thickness must be >= 0 (got " + num(b.thickness) + ")");
    if (b.layers == 0 && b.thickness == 0) throw ParameterError(id + ": give the number of layers or the thickness");
    if (b.layers > 0 && b.thickness > 0) {
      // consistent pair only: thickness must match h0*(r^N-1)/(r-1) within 1%
      BoundaryLayerSpec byLayers = b;
      byLayers.thickness = 0;
      const double t = layerThickness(byLayers);
      if (std::fabs(t - b.thickness) > 0.01 * b.thickness)
        throw ParameterError(id + ": layers, growth, first_height and thickness disagree (the layers give thickness " +
                             num(t) + ", not " + num(b.thickness) + "); give either layers or thickness");
    }
    if (!finite(b.maxAspect) || b.maxAspect < 0) throw ParameterError(id + ": max_aspect must be >= 0");
  }
}

double layerThickness(const BoundaryLayerSpec& b) {
  if (b.thickness > 0) return b.thickness;
  return b.growth == 1.0 ? b.firstHeight * b.layers : b.firstHeight * (std::pow(b.growth, b.layers) - 1) / (b.growth - 1);
}

std::string describeBoundaryLayer(const BoundaryLayerSpec& b, size_t i) {
  std::string edges;
  for (int e : b.edges) edges += (edges.empty() ? "" : ",") + std::to_string(e);
  if (b.autoEdges) edges += edges.empty() ? "auto edges" : " and auto";
  else edges = (b.edges.size() == 1 ? "edge " : "edges ") + edges;
  return "boundary layer #" + std::to_string(i + 1) + " (" + edges + ")";
}

long checkedMaxElements(double v) {
  if (!(v >= 1000 && v <= 1e10)) throw ParameterError("max_elements must be in [1000, 1e10] (got " + num(v) + ")");
  return (long)v;
}

}  // namespace paramesh
