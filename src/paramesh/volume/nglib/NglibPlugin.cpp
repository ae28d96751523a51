// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file NglibPlugin.cpp
/// nglib's volume mesher on our surface triangles (Debian's libnglib-dev, Netgen 6.2): the body
/// of the plugin libparamesh_nglib.so, loaded by fillWithNglib (NglibLoader.cpp) on first use.
/// nglib brings Netgen's libraries, libpython and MPI: loading them only when a volume is filled
/// spares every other run their start-up (docs/benchmark.md).
#include "paramesh/volume/nglib/NglibFill.hpp"

#include <fstream>
#include <mutex>
#include <ostream>
#include <streambuf>

namespace nglib {
#include <nglib.h>
}

// Netgen's message streams and verbosity (libmesh / libngcore): pointed at a sink during a call,
// so that the library prints nothing into its host's console.
namespace netgen {
extern int printmessage_importance;
extern std::ostream* mycout;
extern std::ostream* myerr;
}  // namespace netgen
namespace ngcore {
extern std::ostream* testout;
}  // namespace ngcore

namespace paramesh {
namespace {

/// A stream buffer that drops everything.
class NullBuffer : public std::streambuf {
 protected:
  int overflow(int c) override { return traits_type::not_eof(c); }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

/// nglib's state is global (its parameters, its message streams): one call at a time.
std::mutex& nglibMutex() {
  static std::mutex mu;
  return mu;
}

/// Netgen's streams pointed at a sink for the lifetime of the guard, then restored.
class SilenceNetgen {
 public:
  SilenceNetgen() : cout_(netgen::mycout), cerr_(netgen::myerr), test_(ngcore::testout),
                    importance_(netgen::printmessage_importance) {
    netgen::mycout = &null_;
    netgen::myerr = &null_;
    ngcore::testout = &null_;
    netgen::printmessage_importance = 0;
  }
  ~SilenceNetgen() {
    netgen::mycout = cout_;
    netgen::myerr = cerr_;
    ngcore::testout = test_;
    netgen::printmessage_importance = importance_;
  }

 private:
  NullBuffer buf_;
  std::ostream null_{&buf_};
  std::ostream *cout_, *cerr_, *test_;
  int importance_;
};

/// The nglib mesh, deleted on every path.
struct NgMesh {
  nglib::Ng_Mesh* m = nglib::Ng_NewMesh();
  ~NgMesh() { nglib::Ng_DeleteMesh(m); }
};

}  // namespace

}  // namespace paramesh

extern "C" void paramesh_nglib_fill(const std::vector<paramesh::Vec3>* pointsIn,
                                    const std::vector<std::array<int, 3>>* trianglesIn,
                                    const paramesh::NglibOptions* optionsIn, paramesh::NglibResult* out) {
  using namespace paramesh;
  const std::vector<Vec3>& points = *pointsIn;
  const std::vector<std::array<int, 3>>& triangles = *trianglesIn;
  const NglibOptions& options = *optionsIn;
  NglibResult& r = *out;
  r = NglibResult();
  std::lock_guard<std::mutex> lock(nglibMutex());
  static std::once_flag init;
  std::call_once(init, [] {
    SilenceNetgen quiet;
    nglib::Ng_Init();
  });
  SilenceNetgen quiet;  // after Ng_Init, which points the streams at the console
  try {
    NgMesh mesh;
    for (const Vec3& p : points) {
      double x[3] = {p.x, p.y, p.z};
      nglib::Ng_AddPoint(mesh.m, x);
    }
    for (const auto& t : triangles) {
      int pi[3] = {t[0] + 1, t[1] + 1, t[2] + 1};
      nglib::Ng_AddSurfaceElement(mesh.m, nglib::NG_TRIG, pi);
    }
    nglib::Ng_Meshing_Parameters mp;
    mp.maxh = options.maxSize;
    mp.grading = options.grading;
    mp.optvolmeshenable = options.optimizeSteps > 0;
    mp.optsteps_3d = options.optimizeSteps;
    mp.second_order = 0;
    const nglib::Ng_Result res = nglib::Ng_GenerateVolumeMesh(mesh.m, &mp);
    if (res != nglib::NG_OK) {
      r.error = "nglib could not fill the surface (result " + std::to_string(static_cast<int>(res)) + ")";
      return;
    }
    const int n = static_cast<int>(points.size());
    const int np = nglib::Ng_GetNP(mesh.m), ne = nglib::Ng_GetNE(mesh.m);
    if (np < n) {
      r.error = "nglib dropped surface points (" + std::to_string(np) + " < " + std::to_string(n) + ")";
      return;
    }
    for (int i = 1; i <= n; ++i) {  // the surface is ours: nglib must not have moved it
      double x[3];
      nglib::Ng_GetPoint(mesh.m, i, x);
      const Vec3& p = points[i - 1];
      if (x[0] != p.x || x[1] != p.y || x[2] != p.z) {
        r.error = "nglib moved surface point " + std::to_string(i - 1);
        return;
      }
    }
    r.interior.reserve(np - n);
    for (int i = n + 1; i <= np; ++i) {
      double x[3];
      nglib::Ng_GetPoint(mesh.m, i, x);
      r.interior.push_back({x[0], x[1], x[2]});
    }
    r.tets.reserve(ne);
    for (int e = 1; e <= ne; ++e) {
      int pi[10];
      if (nglib::Ng_GetVolumeElement(mesh.m, e, pi) != nglib::NG_TET) {
        r.error = "nglib made an element that is not a tetrahedron";
        r.tets.clear();
        return;
      }
      r.tets.push_back({pi[0] - 1, pi[1] - 1, pi[2] - 1, pi[3] - 1});
    }
    if (r.tets.empty()) r.error = "nglib made no tetrahedron";
  } catch (const std::exception& e) {
    r.error = std::string("nglib failed: ") + e.what();
  } catch (...) {
    r.error = "nglib failed with an unknown exception";
  }
}
