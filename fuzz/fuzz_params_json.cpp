// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file fuzz_params_json.cpp
/// libFuzzer harness of the JSON parameter front end (pipeline/ParamsJson.hpp, the CLI's --params
/// FILE.json): applyParamsJson() on the input, then MeshParams::validate(). A ParameterError (one
/// line, naming the key) is the fine refusal; a crash, a sanitizer report (UBSan: a number cast to
/// an integer type it does not fit), a hang, any other exception, or a message that is not one
/// line is a finding. Parameters that pass validate() are written back as JSON and read again:
/// the second reading must give the same values.
#include <cmath>
#include <cstdint>
#include <exception>
#include <stdexcept>
#include <string>
#include <typeinfo>

#include "FuzzSupport.hpp"
#include "paramesh/io/Json.hpp"
#include "paramesh/pipeline/Params.hpp"
#include "paramesh/pipeline/ParamsJson.hpp"
#include "paramesh/util/Error.hpp"

namespace {

using namespace paramesh;

fuzz::Outcomes* gOutcomes = nullptr;

/// A value the caller left out (kNotGiven, a NaN, in the optional lengths) is not written: JSON
/// has no NaN, and a missing key reads back as left out.
void put(Json& j, const char* key, double v) {
  if (!std::isnan(v)) j[key] = v;
}

/// The parameters as the JSON keys of README.md's parameters file.
std::string toJson(const MeshParams& p) {
  Json j = Json::object();
  put(j, "size", p.size);
  put(j, "min_size", p.minSize);
  put(j, "max_size", p.maxSize);
  put(j, "curvature_angle", p.curvatureAngle);
  put(j, "max_deviation", p.maxDeviation);
  put(j, "grading", p.grading);
  j["threads"] = p.threads;
  j["order"] = p.order;
  j["quads"] = p.quads;
  j["volume"] = p.volume;
  put(j, "volume_max_size", p.volumeMaxSize);
  j["volume_optimize"] = p.volumeOptimize;
  j["optimize_passes"] = p.optimizePasses;
  j["max_elements"] = (double)p.maxElements;
  j["proximity"] = p.proximity;
  j["nearest_face_check"] = p.nearestFaceCheck;
  put(j, "nearest_face_budget", p.nearestFaceBudget);
  Json& ls = j["local_sizes"] = Json::array();
  for (const LocalSize& l : p.localSizes) {
    Json o = Json::object();
    const char* kind = l.kind == LocalSize::Kind::Face ? "faces" : l.kind == LocalSize::Kind::Edge ? "edges" : "vertices";
    Json& ents = o[kind] = Json::array();
    for (int e : l.entities) ents.push(e);
    put(o, "size", l.size);
    ls.push(o);
  }
  Json& bls = j["boundary_layers"] = Json::array();
  for (const BoundaryLayerSpec& b : p.boundaryLayers) {
    Json o = Json::object();
    Json& edges = o["edges"] = Json::array();
    for (int e : b.edges) edges.push(e);
    put(o, "first_height", b.firstHeight);
    put(o, "growth", b.growth);
    // 0: derived from the others (left out)
    if (b.layers != 0) o["layers"] = b.layers;
    if (b.thickness != 0) put(o, "thickness", b.thickness);
    if (b.maxAspect != 0) put(o, "max_aspect", b.maxAspect);
    o["quads"] = b.quads;
    bls.push(o);
  }
  return j.dump();
}

bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

void requireSame(const MeshParams& a, const MeshParams& b) {
  const bool scalars = same(a.size, b.size) && same(a.minSize, b.minSize) && same(a.maxSize, b.maxSize) &&
                       same(a.curvatureAngle, b.curvatureAngle) && same(a.maxDeviation, b.maxDeviation) &&
                       same(a.grading, b.grading) && a.threads == b.threads && a.order == b.order &&
                       a.quads == b.quads && a.volume == b.volume && same(a.volumeMaxSize, b.volumeMaxSize) &&
                       a.volumeOptimize == b.volumeOptimize && a.optimizePasses == b.optimizePasses &&
                       a.maxElements == b.maxElements && a.proximity == b.proximity &&
                       a.nearestFaceCheck == b.nearestFaceCheck && same(a.nearestFaceBudget, b.nearestFaceBudget);
  if (!scalars) fuzz::finding("parameters written back as JSON read back different");
  if (a.localSizes.size() != b.localSizes.size() || a.boundaryLayers.size() != b.boundaryLayers.size())
    fuzz::finding("local sizes or boundary layers written back as JSON read back different");
  for (size_t i = 0; i < a.localSizes.size(); ++i)
    if (a.localSizes[i].kind != b.localSizes[i].kind || a.localSizes[i].entities != b.localSizes[i].entities ||
        !same(a.localSizes[i].size, b.localSizes[i].size))
      fuzz::finding("local size %zu read back different", i);
  for (size_t i = 0; i < a.boundaryLayers.size(); ++i) {
    const BoundaryLayerSpec &x = a.boundaryLayers[i], &y = b.boundaryLayers[i];
    if (x.edges != y.edges || !same(x.firstHeight, y.firstHeight) || !same(x.growth, y.growth) ||
        x.layers != y.layers || !same(x.thickness, y.thickness) || !same(x.maxAspect, y.maxAspect) ||
        x.quads != y.quads)
      fuzz::finding("boundary layer %zu read back different", i);
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  gOutcomes = new fuzz::Outcomes("fuzz_params_json");  // lives until exit
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  MeshParams p;
  try {
    applyParamsJson(text, p);
    p.validate();
  } catch (const ParameterError& e) {
    gOutcomes->count(fuzz::refusal(e.what(), "ParameterError", "refused"));
    return 0;
  } catch (const std::exception& e) {
    fuzz::finding("applyParamsJson/validate threw %s (not a ParameterError): %s", typeid(e).name(), e.what());
  } catch (...) {
    fuzz::finding("applyParamsJson/validate threw a non-std exception");
  }
  // accepted: the same parameters once more through their JSON form
  MeshParams q;
  try {
    applyParamsJson(toJson(p), q);
  } catch (const std::exception& e) {
    fuzz::finding("accepted parameters written back as JSON are refused: %s", e.what());
  }
  requireSame(p, q);
  gOutcomes->count("accepted");
  return 0;
}
