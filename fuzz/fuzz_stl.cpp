// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file fuzz_stl.cpp
/// libFuzzer harness of triangulated input (issue 36): the bytes as an .stl file through
/// loadDiscrete() (framing checks, OpenCASCADE's RWStl, repair, feature graph), with no signal
/// guard (the Python API has none). An InputError is a refusal; anything else, or a result whose
/// indices do not hold together, is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "FuzzSupport.hpp"
#include "paramesh/geom/discrete/DiscreteInput.hpp"
#include "paramesh/util/Error.hpp"

namespace {

using namespace paramesh;

std::string gPath;
fuzz::Outcomes* gOutcomes = nullptr;

void check(const DiscreteInput& d) {
  const int N = (int)d.mesh.points.size(), T = (int)d.mesh.triangles.size();
  for (const auto& t : d.mesh.triangles)
    for (int v : t)
      if (v < 0 || v >= N) fuzz::finding("a repaired triangle names node %d of %d", v, N);
  if ((int)d.graph.triFace.size() != T) fuzz::finding("%zu triangle faces for %d triangles", d.graph.triFace.size(), T);
  for (const auto& e : d.graph.edges) {
    if (e.nodes.size() < 2) fuzz::finding("an edge of %zu nodes", e.nodes.size());
    for (int v : e.nodes)
      if (v < 0 || v >= N) fuzz::finding("an edge names node %d of %d", v, N);
    if (e.v0 < 0 || e.v1 < 0 || e.v0 >= (int)d.graph.vertexNode.size() || e.v1 >= (int)d.graph.vertexNode.size())
      fuzz::finding("an edge names vertex %d / %d of %zu", e.v0, e.v1, d.graph.vertexNode.size());
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* tmp = std::getenv("TMPDIR");
  std::string dir = tmp && *tmp ? tmp : (access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp");
  gPath = dir + "/paramesh-fuzz-" + std::to_string(getpid()) + ".stl";
  gOutcomes = new fuzz::Outcomes("fuzz_stl");  // lives until exit
  std::atexit([] { std::remove(gPath.c_str()); });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FILE* f = std::fopen(gPath.c_str(), "wb");
  if (!f) fuzz::finding("cannot write %s", gPath.c_str());
  if (size && std::fwrite(data, 1, size, f) != size) fuzz::finding("cannot write %s", gPath.c_str());
  std::fclose(f);
  try {
    check(loadDiscrete(gPath));
    gOutcomes->count("read");
  } catch (const InputError& e) {
    gOutcomes->count(fuzz::refusal(e.what(), "InputError", "refused"));
  } catch (const std::exception& e) {
    fuzz::finding("the STL path threw %s (not an InputError): %s", typeid(e).name(), e.what());
  }
  return 0;
}
