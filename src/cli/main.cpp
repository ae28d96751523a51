// SPDX-License-Identifier: LGPL-2.1-or-later
// paramesh: command-line front end of the ParaMesh library.
#include <chrono>
#include <cmath>
#include <mutex>
#include <unistd.h>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "paramesh/geom/discrete/DiscreteInput.hpp"
#include "paramesh/geom/discrete/DiscreteModel.hpp"
#include "paramesh/geom/occ/OccModel.hpp"
#include "paramesh/io/MeshWriters.hpp"
#include "paramesh/io/PngRender.hpp"
#include "paramesh/pipeline/Mesher.hpp"
#include "paramesh/pipeline/ParamsJson.hpp"
#include "paramesh/pipeline/ReportJson.hpp"
#include "paramesh/util/Error.hpp"
#include "paramesh/volume/nglib/NglibFill.hpp"

using namespace paramesh;

namespace {

const char* kUsage =
    "usage:\n"
    "  paramesh mesh MODEL -o OUT [-o OUT2 ...] [options]   mesh a STEP/IGES/BREP model, or remesh\n"
    "                                                       triangulated input (STL/OBJ)\n"
    "  paramesh info MODEL                                  list faces and edges\n"
    "  paramesh info MESH.stl|.obj [--feature-angle DEG]    triangulated input: its repairs, and the faces,\n"
    "                                                       feature edges and corners found in it (default 40)\n"
    "  paramesh --version                                   ParaMesh's, OpenCASCADE's and nglib's versions\n"
    "\n"
    "mesh options:\n"
    "  --feature-angle DEG   STL/OBJ input: facets meeting at more than DEG are split by a\n"
    "                        feature edge the mesh keeps (default 40)\n"
    "  --size H              target element size, > 0 (default: bounding-box diagonal / 50)\n"
    "  --min-size H          smallest size any size source may ask for (default: size/100;\n"
    "                        size/1000 with --curvature-angle or --max-deviation); when given,\n"
    "                        the curvature refinement makes no edge below it either\n"
    "  --max-size H          largest element size (default: size)\n"
    "  --curvature-angle DEG max angle an element may subtend on curved faces/edges (0: off)\n"
    "  --max-deviation R     max chordal deviation from the CAD as a fraction of size\n"
    "                        (default 0: off)\n"
    "  --grading G           max size ratio between neighbouring elements (default 1.3)\n"
    "  --threads N           worker threads (default 0: the CPUs this process may use; the\n"
    "                        mesh does not depend on it)\n"
    "  --optimize N          optimisation passes (default 4)\n"
    "  --max-elements N      stop with an error beyond N elements (default 5e7, about 16 GB)\n"
    "  --report FILE.json    write the run report\n"
    "  --bl-edges E1,E2,...  grow a surface boundary layer from these CAD edges (1-based)\n"
    "  --bl-first-height H0  height of its first row\n"
    "  --bl-growth R         ratio between consecutive rows (default 1.2)\n"
    "  --bl-layers N         number of rows, or\n"
    "  --bl-thickness T      total thickness\n"
    "  --bl-max-aspect A     stop a column when spacing/height falls below A (0: off)\n"
    "  --bl-quads            stretched quads (default); --bl-triangles: each quad split in two\n"
    "  --bl-auto             grow from the automatically detected leading edges (listed in the\n"
    "                        report); without --bl-first-height the last row is about --size\n"
    "  --params FILE.json    parameters (and several boundary-layer specs) from a JSON file\n"
    "  --local-size FaceN=H  local size near a face, edge (EdgeN=H) or vertex (VertexN=H); repeatable\n"
    "  --proximity N         at least N elements across thin walls and narrow faces (0: off)\n"
    "  --nearest-face-check  refine triangles cut so deep into a thin part (> 4.5 % of the size)\n"
    "                        that their centroid is nearer another face than their own, and mesh\n"
    "                        again (at most 6 times; the report says how many remain)\n"
    "  --quads               quad-dominant surface mesh (triangles paired into quads)\n"
    "  --order 1|2           element order; 2 puts mid-edge nodes on the CAD (default 1)\n"
    "  --volume              fill every closed solid with tetrahedra (tet4, tet10 with --order 2)\n"
    "                        bounded by the surface triangles\n"
    "  --volume-max-size H   largest tetrahedron edge inside the solids (default: --max-size)\n"
    "  --volume-optimize N   nglib optimisation passes on the tetrahedra (default 1)\n"
    "  --png FILE.png        render a picture of the mesh\n"
    "  --view AZ,EL          picture view direction in degrees (default 35,25)\n"
    "  --focus X0,Y0,Z0,X1,Y1,Z1  frame only this box in the picture\n"
    "  --group NAME=Face3,Face7  a named group of faces (or Edge<i>s, Solid<i>s) in every output,\n"
    "                        beside the default Face<i> / Solid<i> / BoundaryLayer<i>; repeatable\n"
    "  --stl-groups          .stl: named multi-solid ASCII, one solid per group (OpenFOAM); the\n"
    "                        default with --group\n"
    "  --quiet               no log and no progress on stderr\n"
    "OUT format from its extension: .msh (Gmsh 4.1), .vtu, .stl, .inp (CalculiX), .su2\n"
    "exit codes: 0 ok, 1 usage/parameter error, 2 unreadable input, 3 some faces failed,\n"
    "            4 no face could be meshed, 5 output could not be written\n";

[[noreturn]] void die(int code, const std::string& msg) {
  std::fprintf(stderr, "paramesh: %s\n", msg.c_str());
  std::exit(code);
}

double parseNumber(const std::string& opt, const char* s) {
  char* end = nullptr;
  errno = 0;
  double v = std::strtod(s, &end);
  // nan would read as a length left out (kNotGiven), inf is no size either
  if (!s[0] || *end || errno || !std::isfinite(v)) die(1, "option " + opt + " expects a number, got '" + s + "'");
  return v;
}
/// A boundary-layer value that is derived when left out: a given one must be > 0.
double parsePositive(const std::string& opt, const char* s, const char* leftOut) {
  const double v = parseNumber(opt, s);
  if (!(v > 0)) die(1, "option " + opt + " must be > 0 (got " + std::string(s) + "); leave it out " + leftOut);
  return v;
}
int parseInt(const std::string& opt, const char* s) {
  char* end = nullptr;
  long v = std::strtol(s, &end, 10);
  if (!s[0] || *end) die(1, "option " + opt + " expects an integer, got '" + s + "'");
  return (int)v;
}
std::vector<double> parseList(const std::string& opt, const char* s, size_t n) {
  std::vector<double> v;
  std::stringstream ss(s);
  std::string tok;
  while (std::getline(ss, tok, ',')) v.push_back(parseNumber(opt, tok.c_str()));
  if (v.size() != n) die(1, "option " + opt + " expects " + std::to_string(n) + " comma-separated numbers");
  return v;
}

/// The progress line on stderr: redrawn in place at most 10 times a second on a terminal, one
/// line per stage otherwise. Log lines clear it first. Called from worker threads: locked.
class ProgressLine {
 public:
  ProgressLine() : tty_(isatty(fileno(stderr)) != 0), start_(Clock::now()) {}
  bool update(double fraction, const std::string& stage) {
    std::lock_guard<std::mutex> lock(mu_);
    const double t = seconds();
    if (!tty_) {
      if (stage != stage_) std::fprintf(stderr, "paramesh: %s (%.1f s)\n", stage.c_str(), t);
    } else if (stage != stage_ || t - drawn_ >= 0.1) {
      std::fprintf(stderr, "\r\033[K%-24s %3.0f %%  %6.1f s", stage.c_str(),
                   100.0 * std::min(1.0, std::max(0.0, fraction)), t);
      std::fflush(stderr);
      drawn_ = t;
      shown_ = true;
    }
    stage_ = stage;
    return true;
  }
  /// Clears the line (before a log line, an error or the summary).
  void clear() {
    std::lock_guard<std::mutex> lock(mu_);
    clearLocked();
  }
  void log(const std::string& line) {
    std::lock_guard<std::mutex> lock(mu_);
    clearLocked();
    std::fprintf(stderr, "%s\n", line.c_str());
  }

 private:
  using Clock = std::chrono::steady_clock;
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  void clearLocked() {
    if (tty_ && shown_) std::fputs("\r\033[K", stderr);
    shown_ = false;
    drawn_ = -1;
  }
  bool tty_;
  Clock::time_point start_;
  std::mutex mu_;
  std::string stage_;
  double drawn_ = -1;
  bool shown_ = false;
};

int cmdInfo(int argc, char** argv) {
  if (argc < 3) die(1, "info: missing MODEL");
  if (isTriangleFile(argv[2])) {  // triangulated input: what the discrete backend finds in it
    double angle = 40.0;
    for (int i = 3; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--feature-angle" && i + 1 < argc) angle = parseNumber(a, argv[++i]);
      else die(1, "info: unknown option '" + a + "' (STL/OBJ input takes --feature-angle DEG)");
    }
    try {
      OccReaderSignalGuard guard;
      for (const std::string& line : describeDiscrete(loadDiscrete(argv[2], angle))) std::printf("%s\n", line.c_str());
    } catch (const ParameterError& e) {
      die(1, e.what());
    } catch (const Error& e) {
      die(2, e.what());
    }
    return 0;
  }
  try {
    std::unique_ptr<IGeometryModel> m;
    {
      OccReaderSignalGuard guard;
      m = loadOccModel(argv[2]);
    }
    std::printf("%s: %d faces, %d edges, %d vertices, %d solids, diagonal %.6g\n", argv[2], m->numFaces(),
                m->numEdges(), m->numVertices(), m->numSolids(), m->boundingBox().diagonal());
    for (int f = 0; f < m->numFaces(); ++f) {
      auto s = m->makeSurface(f);
      std::printf("Face%d %s%s edges:", f + 1, toString(s->kind()), m->faceReversed(f) ? " (reversed)" : "");
      for (const Wire& w : m->faceWires(f)) {
        std::printf(" [");
        for (const EdgeUse& u : w.uses) std::printf(" %sEdge%d", u.reversed ? "-" : "", u.edge + 1);
        std::printf(" ]");
      }
      std::printf("\n");
    }
  } catch (const Error& e) {
    die(2, e.what());
  }
  return 0;
}

int cmdMesh(int argc, char** argv) {
  MeshParams p;
  p.threads = 0;  // the CLI uses the CPUs it may (the library's default is 1)
  WriteOptions wo;
  std::string model, report, png;
  std::vector<std::string> outs;
  RenderOptions ro;
  bool quiet = false;
  BoundaryLayerSpec bl;
  bool haveBl = false;
  std::string paramsFile;
  double featureAngle = 40.0;  // triangulated input: dihedral angle of a feature edge
  for (int i = 2; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&]() -> const char* {
      if (i + 1 >= argc) die(1, "option " + a + " needs a value");
      return argv[++i];
    };
    if (a == "-o" || a == "--output") outs.push_back(next());
    else if (a == "--feature-angle") featureAngle = parseNumber(a, next());
    else if (a == "--size") p.size = parseNumber(a, next());
    else if (a == "--min-size") p.minSize = parseNumber(a, next());
    else if (a == "--max-size") p.maxSize = parseNumber(a, next());
    else if (a == "--curvature-angle") p.curvatureAngle = parseNumber(a, next());
    else if (a == "--grading") p.grading = parseNumber(a, next());
    else if (a == "--max-deviation") p.maxDeviation = parseNumber(a, next());
    else if (a == "--threads") p.threads = parseInt(a, next());
    else if (a == "--optimize") p.optimizePasses = parseInt(a, next());
    else if (a == "--max-elements") {
      try {
        p.maxElements = checkedMaxElements(parseNumber(a, next()));
      } catch (const Error& e) {
        die(1, std::string("--max-elements: ") + e.what());
      }
    }
    else if (a == "--order") p.order = parseInt(a, next());
    else if (a == "--bl-edges") {
      bl.edges.clear();
      std::stringstream ss(next());
      std::string tok;
      while (std::getline(ss, tok, ',')) bl.edges.push_back(parseInt(a, tok.c_str()));
      haveBl = true;
    } else if (a == "--bl-first-height") {
      bl.firstHeight = parsePositive(a, next(), "with --bl-auto to have it derived from the size");
      haveBl = true;
    } else if (a == "--bl-growth") { bl.growth = parseNumber(a, next()); haveBl = true; }
    else if (a == "--bl-layers") {
      const char* v = next();
      bl.layers = parseInt(a, v);
      if (bl.layers <= 0)
        die(1, "option --bl-layers must be > 0 (got " + std::string(v) + "); leave it out to derive it from --bl-thickness");
      haveBl = true;
    } else if (a == "--bl-thickness") {
      bl.thickness = parsePositive(a, next(), "to derive it from --bl-layers");
      haveBl = true;
    }
    else if (a == "--bl-max-aspect") { bl.maxAspect = parseNumber(a, next()); haveBl = true; }
    else if (a == "--bl-quads") { bl.quads = true; }
    else if (a == "--bl-auto") { bl.autoEdges = true; haveBl = true; }
    else if (a == "--bl-triangles") { bl.quads = false; }
    else if (a == "--params") paramsFile = next();
    else if (a == "--local-size") {
      // FaceN=size, EdgeN=size or VertexN=size (repeatable)
      try {
        applyParamsJson(std::string("{\"local_sizes\": [\"") + next() + "\"]}", p);
      } catch (const Error& e) {
        die(1, std::string("--local-size: ") + e.what());
      }
    } else if (a == "--group") {
      try {
        p.groups.push_back(parseGroup(next()));
      } catch (const Error& e) {
        die(1, std::string("--group: ") + e.what());
      }
    } else if (a == "--stl-groups") wo.stlGroups = true;
    else if (a == "--proximity") p.proximity = parseInt(a, next());
    else if (a == "--nearest-face-check") p.nearestFaceCheck = true;
    else if (a == "--nearest-face-budget") p.nearestFaceBudget = parseNumber(a, next());
    else if (a == "--no-stagger") p.staggerNarrowGaps = false;
    else if (a == "--quads") p.quads = true;
    else if (a == "--volume") p.volume = true;
    else if (a == "--volume-max-size") p.volumeMaxSize = parseNumber(a, next());
    else if (a == "--volume-optimize") p.volumeOptimize = parseInt(a, next());
    else if (a == "--report") report = next();
    else if (a == "--png") png = next();
    else if (a == "--view") {
      auto v = parseList(a, next(), 2);
      ro.azimuthDeg = v[0];
      ro.elevationDeg = v[1];
    } else if (a == "--focus") {
      auto v = parseList(a, next(), 6);
      ro.hasFocus = true;
      ro.focusLo = {v[0], v[1], v[2]};
      ro.focusHi = {v[3], v[4], v[5]};
    } else if (a == "--quiet") quiet = true;
    else if (!a.empty() && a[0] == '-') die(1, "unknown option " + a);
    else if (model.empty()) model = a;
    else die(1, "unexpected argument '" + a + "'");
  }
  if (!paramsFile.empty()) {
    try {
      applyParamsFile(paramsFile, p);
    } catch (const Error& e) {
      die(1, e.what());
    }
  }
  if (haveBl) {
    if (bl.edges.empty() && !bl.autoEdges) die(1, "--bl-* options need --bl-edges or --bl-auto");
    if (bl.layers == 0 && bl.thickness == 0) {
      if (!bl.autoEdges) die(1, "--bl-* options need --bl-layers or --bl-thickness");
      bl.layers = 20;  // --bl-auto alone: 20 rows, the last one about the surface size
    }
    p.boundaryLayers.push_back(bl);
  }
  if (model.empty()) die(1, "mesh: missing MODEL");
  if (outs.empty() && report.empty() && png.empty()) die(1, "mesh: give an output with -o OUT");
  {
    // the parameters checked before the model is read: a typo is refused at once (an automatic
    // layer's first height, derived below from the model, stands in as 1)
    MeshParams early = p;
    for (auto& b : early.boundaryLayers)
      if (b.autoEdges && b.firstHeight == 0) b.firstHeight = 1;
    try {
      early.validate();
    } catch (const Error& e) {
      die(1, e.what());
    }
  }
  std::unique_ptr<IGeometryModel> geo;
  try {
    OccReaderSignalGuard guard;  // a reader crashing on a damaged file: an error, not a crash
    geo = isTriangleFile(model) ? loadDiscreteModel(model, featureAngle) : loadOccModel(model);
  } catch (const Error& e) {
    die(2, e.what());
  }
  for (auto& b : p.boundaryLayers)
    if (b.autoEdges && b.firstHeight == 0) {
      // the last of N rows about as tall as the surface size (an isotropic hand-off)
      const double size = isGiven(p.size) ? p.size : geo->boundingBox().diagonal() / 50.0;
      const int n = b.layers > 0 ? b.layers : 20;
      b.firstHeight = size / std::pow(b.growth, n - 1);
    }
  ProgressLine line;
  LogSink sink;
  ProgressCallback progress;
  if (!quiet) {
    sink = [&line](LogLevel l, const std::string& m) {
      if (l >= LogLevel::Info) line.log(m);
    };
    progress = [&line](double f, const std::string& stage) { return line.update(f, stage); };
  }
  MeshOutput out;
  try {
    Mesher mesher(*geo, p, sink, progress);
    out = mesher.run();
    line.clear();
  } catch (const ParameterError& e) {
    line.clear();
    die(1, e.what());
  } catch (const InputError& e) {
    line.clear();
    die(2, e.what());
  } catch (const Error& e) {
    line.clear();
    die(4, e.what());
  } catch (const std::exception& e) {
    line.clear();
    die(4, std::string("internal error: ") + e.what());
  } catch (...) {  // an exception of the geometry kernel that its backend did not translate
    line.clear();
    die(4, "internal error: an unexpected exception of the geometry kernel");
  }
  try {
    for (const auto& o : outs) writeMesh(o, out.mesh, wo);
    if (!report.empty()) writeReportJson(report, out.report);
    if (!png.empty()) renderPng(png, out.mesh, ro);
  } catch (const Error& e) {
    die(5, e.what());
  }
  const Report& r = out.report;
  if (!quiet) {
    double total = 0;
    for (auto& kv : r.stageSeconds)
      if (kv.first == "total") total = kv.second;
    std::fprintf(stderr, "%d nodes, %d triangles, %d quads in %.3f s; gamma mean %.4f, min angle %.2f deg\n",
                 r.nodes, r.triangles, r.quads, total, r.quality.gammaMean, r.quality.angleMin);
    if (p.volume)
      std::fprintf(stderr, "%d tetrahedra in %d of %d solids; min dihedral %.2f deg\n", r.tetrahedra,
                   r.solidsFilled(), (int)r.solids.size(), r.tetMinDihedral());
  }
  if (r.status == RunStatus::Degraded) die(3, r.message);
  if (r.status == RunStatus::Failed) die(4, r.message);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "--help")) {
    std::fputs(kUsage, argc < 2 ? stderr : stdout);
    return argc < 2 ? 1 : 0;
  }
  std::string cmd = argv[1];
  if (cmd == "--version" || cmd == "-V") {
    std::printf("paramesh %s\nOpenCASCADE %s\nnglib (Netgen) %s\n", PARAMESH_VERSION, occtVersion().c_str(),
                nglibVersion().c_str());
    return 0;
  }
  if (cmd == "mesh") return cmdMesh(argc, argv);
  if (cmd == "info") return cmdInfo(argc, argv);
  die(1, "unknown command '" + cmd + "' (use mesh or info)");
}
