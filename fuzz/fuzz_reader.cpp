// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file fuzz_reader.cpp
/// libFuzzer harness of the CAD readers and their pre-checks (geom/occ/OccModel.cpp), built three
/// times: PM_FUZZ_FORMAT is "step", "iges" or "brep" (fuzz/CMakeLists.txt).
///
/// STEP and IGES: the input is written to a temporary file with that extension and read with
/// loadOccModel(); BREP: loadOccModelFromBrepString(). An InputError is a fine outcome; then the
/// model that was read is walked as the mesher walks it (every face's surface and p-curves,
/// every edge's curve, evaluated at mid-range), where an InputError is fine too, and so is an
/// OpenCASCADE exception out of an evaluation (the mesher's stages catch those per entity). A crash, a
/// sanitizer report, a hang (-timeout), memory beyond -rss_limit_mb, any other exception, or an
/// error message that is not one line is a finding.
///
/// Signal handlers: by default the reader runs as the CLI runs it, under OccReaderSignalGuard
/// (OpenCASCADE's handlers turn an access violation inside its translators into an InputError);
/// ASan's and libFuzzer's handlers are put back right after, so a crash anywhere else (the model
/// walk) is still caught. PARAMESH_FUZZ_UNGUARDED=1 reads without the guard, as the Python API and
/// FreeCAD do: then a reader crash that the pre-checks did not refuse is a finding too.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <exception>
#include <memory>
#include <string>
#include <typeinfo>

#include "FuzzSupport.hpp"
#include "paramesh/geom/occ/OccModel.hpp"
#include "paramesh/util/Error.hpp"

#ifndef PM_FUZZ_FORMAT
#error "PM_FUZZ_FORMAT must be step, iges or brep"
#endif

namespace {

using namespace paramesh;

const std::string kFormat = PM_FUZZ_FORMAT;
bool gUnguarded = false;
std::string gPath;
fuzz::Outcomes* gOutcomes = nullptr;

std::unique_ptr<IGeometryModel> read(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (kFormat == "brep") return loadOccModelFromBrepString(text);
  FILE* f = std::fopen(gPath.c_str(), "wb");
  if (!f) fuzz::finding("cannot write %s", gPath.c_str());
  if (size && std::fwrite(data, 1, size, f) != size) fuzz::finding("cannot write %s", gPath.c_str());
  std::fclose(f);
  return loadOccModel(gPath);
}

std::unique_ptr<IGeometryModel> readGuarded(const uint8_t* data, size_t size) {
  if (gUnguarded) return read(data, size);
  fuzz::SavedSignals keep;  // restored after the guard's destructor has set SIG_DFL
  OccReaderSignalGuard guard;
  return read(data, size);
}

/// What the mesher's first stages ask of a model, at every face and edge (mid-range).
void walk(const IGeometryModel& g) {
  const Box3 box = g.boundingBox();
  (void)box;
  for (int e = 0; e < g.numEdges(); ++e) {
    double t0 = 0, t1 = 0;
    g.edgeRange(e, t0, t1);
    (void)g.edgeVertex(e, 0);
    (void)g.edgeVertex(e, 1);
    (void)g.edgeFaces(e);
    if (g.edgeDegenerate(e)) continue;
    auto c = g.makeCurve(e);
    if (!c) fuzz::finding("Edge%d: no curve and not degenerate", e + 1);
    Vec3 p, d1, d2;
    c->d2(0.5 * (t0 + t1), p, d1, d2);
  }
  for (int f = 0; f < g.numFaces(); ++f) {
    auto s = g.makeSurface(f);
    if (!s) fuzz::finding("Face%d: no surface", f + 1);
    const UVBox b = s->bounds();
    SurfaceD2 d;
    s->d2({0.5 * (b.u0 + b.u1), 0.5 * (b.v0 + b.v1)}, d);
    (void)g.faceSolid(f);
    const auto& wires = g.faceWires(f);
    for (int w = 0; w < (int)wires.size(); ++w)
      for (int u = 0; u < (int)wires[w].uses.size(); ++u) {
        const int e = wires[w].uses[u].edge;
        if (e < 0 || e >= g.numEdges()) fuzz::finding("Face%d wire %d names edge %d of %d", f + 1, w, e, g.numEdges());
        auto pc = g.makePCurve(f, w, u);
        if (!pc) continue;  // no p-curve stored (the mesher's callers handle it)
        double t0 = 0, t1 = 0;
        g.edgeRange(e, t0, t1);
        Vec2 q, dq;
        pc->d1(0.5 * (t0 + t1), q, dq);
      }
  }
  for (int s = 0; s < g.numSolids(); ++s)
    for (const SolidFace& sf : g.solidFaces(s))
      if (sf.face < 0 || sf.face >= g.numFaces()) fuzz::finding("Solid%d names face %d of %d", s + 1, sf.face, g.numFaces());
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  gUnguarded = fuzz::envFlag("PARAMESH_FUZZ_UNGUARDED");
  const char* tmp = std::getenv("TMPDIR");
  std::string dir = tmp && *tmp ? tmp : (access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp");
  gPath = dir + "/paramesh-fuzz-" + std::to_string(getpid()) + "." + kFormat;
  gOutcomes = new fuzz::Outcomes("fuzz_" + kFormat + (gUnguarded ? " (unguarded)" : ""));  // lives until exit
  std::atexit([] { std::remove(gPath.c_str()); });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::unique_ptr<IGeometryModel> model;
  try {
    model = readGuarded(data, size);
  } catch (const InputError& e) {
    gOutcomes->count(fuzz::refusal(e.what(), "InputError", "refused"));
    return 0;
  } catch (const std::exception& e) {
    fuzz::finding("the reader threw %s (not an InputError): %s", typeid(e).name(), e.what());
  } catch (...) {
    fuzz::finding("the reader threw a non-std exception");
  }
  if (!model) fuzz::finding("the reader returned no model");
  try {
    walk(*model);
  } catch (const InputError& e) {
    gOutcomes->count(fuzz::refusal(e.what(), "InputError", "read, walk refused"));
    return 0;
  } catch (const std::exception& e) {
    fuzz::finding("walking the model threw %s: %s", typeid(e).name(), e.what());
  } catch (...) {
    // a Standard_Failure from an evaluation (not from the factories, which translate theirs): the
    // mesher's stages catch these per edge / face (catch (...) in stages/edges, stages/faces)
    gOutcomes->count("read, walk: kernel exception");
    return 0;
  }
  gOutcomes->count("read");
  return 0;
}
