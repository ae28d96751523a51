// SPDX-License-Identifier: LGPL-2.1-or-later
// pybind11 glue: paramesh._native. Thin by design: parameters come in as the C++ struct, results go
// out as owned numpy arrays (float64 coordinates, int32 indices), errors as typed Python exceptions.
// The GIL is released while meshing; progress callbacks re-acquire it.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <cmath>
#include <optional>
#include <cstring>
#include <memory>

#include "paramesh/algo/FeatureDetect.hpp"
#include "paramesh/geom/discrete/DiscreteInput.hpp"
#include "paramesh/geom/discrete/DiscreteModel.hpp"
#include "paramesh/geom/occ/OccModel.hpp"
#include "paramesh/model/Coincidence.hpp"
#include "paramesh/io/MeshWriters.hpp"
#include "paramesh/io/PngRender.hpp"
#include "paramesh/pipeline/Mesher.hpp"
#include "paramesh/pipeline/ReportJson.hpp"
#include "paramesh/util/Error.hpp"

namespace py = pybind11;
using namespace paramesh;

namespace {

template <class T>
py::array_t<T> owned(std::vector<T>&& v, std::vector<py::ssize_t> shape) {
  auto* heap = new std::vector<T>(std::move(v));
  py::capsule free(heap, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, heap->data(), free);
}

py::array_t<double> vec3Array(const std::vector<Vec3>& v) {
  std::vector<double> d(v.size() * 3);
  if (!v.empty()) std::memcpy(d.data(), v.data(), d.size() * sizeof(double));
  return owned(std::move(d), {(py::ssize_t)v.size(), 3});
}
py::array_t<double> vec2Array(const std::vector<Vec2>& v) {
  std::vector<double> d(v.size() * 2);
  if (!v.empty()) std::memcpy(d.data(), v.data(), d.size() * sizeof(double));
  return owned(std::move(d), {(py::ssize_t)v.size(), 2});
}
template <size_t K>
py::array_t<int32_t> intArray(const std::vector<std::array<int, K>>& v) {
  std::vector<int32_t> d(v.size() * K);
  for (size_t i = 0; i < v.size(); ++i)
    for (size_t k = 0; k < K; ++k) d[i * K + k] = v[i][k];
  return owned(std::move(d), {(py::ssize_t)v.size(), (py::ssize_t)K});
}
py::array_t<int32_t> intVector(const std::vector<int>& v) {
  std::vector<int32_t> d(v.begin(), v.end());
  return owned(std::move(d), {(py::ssize_t)v.size()});
}

/// Tetrahedra as (K, 4) corners, or (K, 10) corners then mid-nodes when the mesh has them.
py::array_t<int32_t> tetArray(const SurfaceMesh& m) {
  const size_t k = m.tets.size();
  const bool mid = m.order == 2 && m.tetMid.size() == k;
  const size_t w = mid ? 10 : 4;
  std::vector<int32_t> d(k * w);
  for (size_t i = 0; i < k; ++i) {
    for (size_t c = 0; c < 4; ++c) d[i * w + c] = m.tets[i][c];
    if (mid)
      for (size_t c = 0; c < 6; ++c) d[i * w + 4 + c] = m.tetMid[i][c];
  }
  return owned(std::move(d), {(py::ssize_t)k, (py::ssize_t)w});
}

/// A geometry model held by Python (shared so that a Mesher keeps it alive).
struct PyModel {
  std::shared_ptr<IGeometryModel> m;
};

/// A finished run: the mesh and its report, arrays handed out as numpy copies.
struct PyResult {
  SurfaceMesh mesh;
  Report report;
};

/// One meshing job: run() in any thread (GIL released), cancel() from any other thread.
class PyMesher {
 public:
  PyMesher(PyModel model, MeshParams p) : model_(model.m), params_(std::move(p)) { params_.validate(); }

  std::shared_ptr<PyResult> run(py::object progress, py::object log) {
    LogSink sink;
    if (!log.is_none())
      sink = [log](LogLevel l, const std::string& msg) {
        py::gil_scoped_acquire g;
        try {
          log((int)l, msg);
        } catch (py::error_already_set&) {
          // a failing Python log callback must not take the run down
        }
      };
    ProgressCallback cb = [this, progress](double f, const std::string& stage) -> bool {
      if (cancel_.load()) return false;
      if (progress.is_none()) return true;
      py::gil_scoped_acquire g;
      try {
        py::object r = progress(f, stage);
        return r.is_none() || r.cast<bool>();
      } catch (py::error_already_set&) {
        return false;  // an exception in the callback cancels the run
      }
    };
    MeshOutput out;
    {
      Mesher mesher(*model_, params_, sink, cb);
      {
        std::lock_guard<std::mutex> g(mu_);
        active_ = &mesher;
      }
      struct Clear {
        PyMesher* self;
        ~Clear() {
          std::lock_guard<std::mutex> g(self->mu_);
          self->active_ = nullptr;
        }
      } clear{this};
      if (cancel_.load()) throw Cancelled();
      py::gil_scoped_release nogil;
      out = mesher.run();
    }
    auto r = std::make_shared<PyResult>();
    r->mesh = std::move(out.mesh);
    r->report = std::move(out.report);
    return r;
  }

  void cancel() {
    cancel_ = true;
    std::lock_guard<std::mutex> g(mu_);
    if (active_) active_->cancel();
  }

 private:
  std::shared_ptr<IGeometryModel> model_;
  MeshParams params_;
  std::atomic<bool> cancel_{false};
  std::mutex mu_;
  Mesher* active_ = nullptr;
};

/// The exception types (ParaMeshError and its subclasses) and their translator.
void bindErrors(py::module_& mod) {
  static py::exception<Error> exBase(mod, "ParaMeshError", PyExc_RuntimeError);
  // both a ParaMeshError (catch everything of ours) and a ValueError (the caller's input is wrong)
  static py::exception<ParameterError> exParam(mod, "ParameterError",
                                               py::make_tuple(exBase, py::handle(PyExc_ValueError)));
  static py::exception<InputError> exInput(mod, "InputError", py::make_tuple(exBase, py::handle(PyExc_ValueError)));
  static py::exception<Cancelled> exCancel(mod, "Cancelled", exBase.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ParameterError& e) {
      exParam(e.what());
    } catch (const InputError& e) {
      exInput(e.what());
    } catch (const Cancelled& e) {
      exCancel(e.what());
    } catch (const Error& e) {
      exBase(e.what());
    }
  });
}

/// An optional length of MeshParams as a Python property: None when left out (kNotGiven). A
/// given 0 stays 0 (MeshParams::validate refuses it, like the CLI); NaN, how C++ says "left
/// out", is refused here.
template <double MeshParams::*Field>
void optionalLength(py::class_<MeshParams>& c, const char* name) {
  c.def_property(
      name,
      [](const MeshParams& p) -> std::optional<double> {
        if (!isGiven(p.*Field)) return std::nullopt;
        return p.*Field;
      },
      [name](MeshParams& p, std::optional<double> v) {
        if (v && std::isnan(*v)) throw ParameterError(std::string(name) + " must be a number (got nan)");
        p.*Field = !v ? kNotGiven : *v;
      });
}

/// MeshParams and its parts (LocalSize, BoundaryLayerSpec).
void bindParams(py::module_& mod) {
  py::class_<LocalSize> ls(mod, "LocalSize");
  py::enum_<LocalSize::Kind>(ls, "Kind")
      .value("Face", LocalSize::Kind::Face)
      .value("Edge", LocalSize::Kind::Edge)
      .value("Vertex", LocalSize::Kind::Vertex);
  ls.def(py::init<>())
      .def_readwrite("kind", &LocalSize::kind)
      .def_readwrite("entities", &LocalSize::entities)
      .def_readwrite("size", &LocalSize::size);

  py::class_<BoundaryLayerSpec>(mod, "BoundaryLayerSpec")
      .def(py::init<>())
      .def_readwrite("edges", &BoundaryLayerSpec::edges)
      .def_readwrite("first_height", &BoundaryLayerSpec::firstHeight)
      .def_readwrite("growth", &BoundaryLayerSpec::growth)
      .def_readwrite("layers", &BoundaryLayerSpec::layers)
      .def_readwrite("thickness", &BoundaryLayerSpec::thickness)
      .def_readwrite("max_aspect", &BoundaryLayerSpec::maxAspect)
      .def_readwrite("quads", &BoundaryLayerSpec::quads)
      .def_readwrite("auto_edges", &BoundaryLayerSpec::autoEdges);

  py::class_<MeshGroup>(mod, "MeshGroup")
      .def(py::init<>())
      .def_readwrite("name", &MeshGroup::name)
      .def_readwrite("dim", &MeshGroup::dim)
      .def_readwrite("entities", &MeshGroup::entities);
  mod.def("parse_group", &parseGroup, py::arg("text"),
          "'NAME=Face3,Face7' (or Edge<i>s, Solid<i>s) into a MeshGroup; raises ParameterError.");

  py::class_<MeshParams> mp(mod, "MeshParams");
  optionalLength<&MeshParams::size>(mp, "size");
  optionalLength<&MeshParams::minSize>(mp, "min_size");
  optionalLength<&MeshParams::maxSize>(mp, "max_size");
  optionalLength<&MeshParams::volumeMaxSize>(mp, "volume_max_size");
  mp.def(py::init<>())
      .def_readwrite("curvature_angle", &MeshParams::curvatureAngle)
      .def_readwrite("max_deviation", &MeshParams::maxDeviation)
      .def_readwrite("grading", &MeshParams::grading)
      .def_readwrite("threads", &MeshParams::threads)
      .def_readwrite("order", &MeshParams::order)
      .def_readwrite("quads", &MeshParams::quads)
      .def_readwrite("optimize_passes", &MeshParams::optimizePasses)
      .def_readwrite("max_elements", &MeshParams::maxElements)
      .def_readwrite("proximity", &MeshParams::proximity)
      .def_readwrite("nearest_face_check", &MeshParams::nearestFaceCheck)
      .def_readwrite("nearest_face_budget", &MeshParams::nearestFaceBudget)
      .def_readwrite("volume", &MeshParams::volume)
      .def_readwrite("volume_optimize", &MeshParams::volumeOptimize)
      .def_readwrite("local_sizes", &MeshParams::localSizes)
      .def_readwrite("boundary_layers", &MeshParams::boundaryLayers)
      .def_readwrite("groups", &MeshParams::groups)
      .def("validate", &MeshParams::validate, "Raises ParameterError naming the first invalid field.");
}

/// (N, 3) points and (M, 3) 0-based triangles as a triangle soup (an index out of range becomes
/// -1: a facet the repair drops and counts).
TriangleSoup soupFromArrays(py::object points, py::object triangles) {
  const auto P = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(points);
  const auto T = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(triangles);
  if (!P || P.ndim() != 2 || P.shape(1) != 3) throw ParameterError("points must be an (N, 3) array");
  if (!T || T.ndim() != 2 || T.shape(1) != 3) throw ParameterError("triangles must be an (M, 3) array of indices");
  TriangleSoup soup;
  soup.source = "arrays";
  for (py::ssize_t i = 0; i < P.shape(0); ++i) soup.points.push_back({P.at(i, 0), P.at(i, 1), P.at(i, 2)});
  for (py::ssize_t i = 0; i < T.shape(0); ++i) {
    std::array<int, 3> t;
    for (int k = 0; k < 3; ++k) {
      const long long v = T.at(i, k);
      t[k] = v < 0 || v >= (long long)soup.points.size() ? -1 : (int)v;
    }
    soup.triangles.push_back(t);
  }
  return soup;
}

/// The CAD model: loading, topology queries.
void bindModel(py::module_& mod) {
  py::class_<PyModel>(mod, "Model")
      .def_static(
          "from_file",
          [](const std::string& path, double featureAngle) {
            py::gil_scoped_release nogil;
            if (isTriangleFile(path)) return PyModel{std::shared_ptr<IGeometryModel>(loadDiscreteModel(path, featureAngle))};
            return PyModel{std::shared_ptr<IGeometryModel>(loadOccModel(path))};
          },
          py::arg("path"), py::arg("feature_angle") = 40.0,
          "Reads a STEP/IGES/BREP file, or triangulated input (STL/OBJ: faces split at feature_angle).")
      .def_static(
          "from_arrays",
          [](py::object points, py::object triangles, double featureAngle) {
            TriangleSoup soup = soupFromArrays(points, triangles);
            py::gil_scoped_release nogil;
            return PyModel{std::shared_ptr<IGeometryModel>(makeDiscreteModel(discreteFromArrays(std::move(soup), featureAngle)))};
          },
          py::arg("points"), py::arg("triangles"), py::arg("feature_angle") = 40.0,
          "Triangulated input from arrays: (N, 3) points, (M, 3) 0-based triangles.")
      .def_static(
          "from_brep",
          [](const std::string& brep) {
            py::gil_scoped_release nogil;
            return PyModel{std::shared_ptr<IGeometryModel>(loadOccModelFromBrepString(brep))};
          },
          py::arg("brep"), "Reads an OpenCASCADE BREP text (Part.Shape.exportBrepToString()).")
      .def_property_readonly("num_faces", [](const PyModel& m) { return m.m->numFaces(); })
      .def_property_readonly("num_edges", [](const PyModel& m) { return m.m->numEdges(); })
      .def_property_readonly("num_vertices", [](const PyModel& m) { return m.m->numVertices(); })
      .def_property_readonly("num_solids", [](const PyModel& m) { return m.m->numSolids(); })
      .def_property_readonly("diagonal", [](const PyModel& m) { return m.m->boundingBox().diagonal(); })
      .def(
          "propose_leading_edges",
          [](const PyModel& m) {
            const Coincidence same = findCoincident(*m.m, 1e-6 * m.m->boundingBox().diagonal());
            std::vector<RidgeCandidate> found;
            {
              py::gil_scoped_release nogil;
              found = proposeLeadingEdges(*m.m, 0.0, 10.0, 10.0, nullptr, &same.edgeRep);
            }
            py::list out;
            for (const auto& r : found) {
              py::dict d;
              d["edge"] = r.edge + 1;
              d["radius"] = r.acrossCurvature > 0 ? 1.0 / r.acrossCurvature : 0.0;
              d["curvature_ratio"] = std::min(r.ratio, 1e6);
              std::vector<int> twins;
              for (int e = 0; e < m.m->numEdges(); ++e)
                if (same.edgeRep[e] == r.edge && e != r.edge) twins.push_back(e + 1);
              d["coincident_edges"] = twins;
              out.append(d);
            }
            return out;
          },
          "Edges where the surface is smooth but curves far more across than along (rounded "
          "leading edges): list of dicts (edge, radius, curvature_ratio, coincident_edges).")
      .def(
          "edge_faces", [](const PyModel& m, int e) {
            if (e < 1 || e > m.m->numEdges())
              throw ParameterError("Edge" + std::to_string(e) + " does not exist (the model has " +
                                   std::to_string(m.m->numEdges()) + " edges)");
            std::vector<int> f;
            for (int x : m.m->edgeFaces(e - 1)) f.push_back(x + 1);
            return f;
          },
          py::arg("edge"), "1-based faces using a 1-based edge.");
}

/// The meshing result: numpy views, report, writers, rendering.
void bindResult(py::module_& mod) {
  py::class_<PyResult, std::shared_ptr<PyResult>>(mod, "Result")
      .def_property_readonly("nodes", [](const PyResult& r) { return vec3Array(r.mesh.nodes); }, "(N, 3) float64")
      .def_property_readonly("triangles", [](const PyResult& r) { return intArray(r.mesh.triangles); },
                             "(M, 3) int32, 0-based, counter-clockwise seen from outside")
      .def_property_readonly("quads", [](const PyResult& r) { return intArray(r.mesh.quads); }, "(K, 4) int32")
      .def_property_readonly("triangle_face", [](const PyResult& r) { return intVector(r.mesh.triangleFace); },
                             "(M,) int32 1-based CAD face of each triangle")
      .def_property_readonly("quad_face", [](const PyResult& r) { return intVector(r.mesh.quadFace); },
                             "(K,) int32 1-based CAD face of each quad")
      .def_property_readonly("triangle_layer", [](const PyResult& r) { return intVector(r.mesh.triangleLayer); },
                             "(M,) int32 1-based boundary-layer spec of each triangle, 0 outside the layers")
      .def_property_readonly("quad_layer", [](const PyResult& r) { return intVector(r.mesh.quadLayer); },
                             "(K,) int32 1-based boundary-layer spec of each quad, 0 outside the layers")
      .def_property_readonly("node_dim", [](const PyResult& r) {
            std::vector<int> k(r.mesh.nodeKind.size());
            for (size_t i = 0; i < k.size(); ++i) k[i] = (int)r.mesh.nodeKind[i];
            return intVector(k);
          }, "(N,) int32 dimension of the CAD entity of each node (0 vertex, 1 edge, 2 face, 3 inside a solid)")
      .def_property_readonly("node_entity", [](const PyResult& r) { return intVector(r.mesh.nodeEntity); },
                             "(N,) int32 1-based CAD vertex/edge/face/solid number of each node")
      .def_property_readonly("node_param", [](const PyResult& r) { return vec2Array(r.mesh.nodeParam); },
                             "(N, 2) float64: (t, 0) on edges, (u, v) on faces")
      .def_property_readonly("segments", [](const PyResult& r) { return intArray(r.mesh.segments); },
                             "(S, 2) int32 mesh edges on CAD edges")
      .def_property_readonly("segment_edge", [](const PyResult& r) { return intVector(r.mesh.segmentEdge); },
                             "(S,) int32 1-based CAD edge of each segment")
      .def_property_readonly("order", [](const PyResult& r) { return r.mesh.order; })
      .def_property_readonly("triangle_mid", [](const PyResult& r) { return intArray(r.mesh.triangleMid); },
                             "(M, 3) int32 mid-edge nodes (ab, bc, ca) when order == 2")
      .def_property_readonly("quad_mid", [](const PyResult& r) { return intArray(r.mesh.quadMid); },
                             "(K, 4) int32 mid-edge nodes when order == 2")
      .def_property_readonly("tetrahedra", [](const PyResult& r) { return tetArray(r.mesh); },
                             "(K, 4) int32 corners, positive volume ((b-a)x(c-a)).(d-a) > 0; (K, 10) when "
                             "order == 2: corners then the mid-nodes of ab, bc, ca, ad, bd, cd (CalculiX C3D10)")
      .def_property_readonly("tetra_solid", [](const PyResult& r) { return intVector(r.mesh.tetSolid); },
                             "(K,) int32 1-based CAD solid of each tetrahedron (FreeCAD's Solid<i>)")
      .def_property_readonly("num_solids", [](const PyResult& r) { return r.mesh.numSolids; })
      .def_property_readonly(
          "groups",
          [](const PyResult& r) {
            py::list out;
            for (const MeshGroup& g : r.mesh.groups) out.append(py::make_tuple(g.name, g.dim, g.entities));
            return out;
          },
          "the user groups: [(name, dim, [1-based entities])], dim 1 edges, 2 faces, 3 solids")
      .def_property_readonly("report_json", [](const PyResult& r) { return reportToJson(r.report).dump(); })
      .def(
          "write",
          [](const PyResult& r, const std::string& path, bool stlGroups) {
            py::gil_scoped_release nogil;
            WriteOptions o;
            o.stlGroups = stlGroups;
            writeMesh(path, r.mesh, o);
          },
          py::arg("path"), py::arg("stl_groups") = false,
          "Writes .msh (Gmsh 4.1), .vtu, .stl, .inp or .su2 (format from the extension) with the named groups; "
          "stl_groups: .stl as named multi-solid ASCII (the default when the mesh has face groups).")
      .def(
          "render_png",
          [](const PyResult& r, const std::string& path, int width, int height, double az, double el,
             const std::string& color, std::vector<double> focus) {
            RenderOptions o;
            o.width = width;
            o.height = height;
            o.azimuthDeg = az;
            o.elevationDeg = el;
            o.color = color == "quality" ? RenderOptions::Color::ByQuality
                      : color == "uniform" ? RenderOptions::Color::Uniform
                                           : RenderOptions::Color::ByFace;
            if (focus.size() == 6) {
              o.hasFocus = true;
              o.focusLo = {focus[0], focus[1], focus[2]};
              o.focusHi = {focus[3], focus[4], focus[5]};
            } else if (!focus.empty()) {
              throw ParameterError("focus must be [x0, y0, z0, x1, y1, z1]");
            }
            py::gil_scoped_release nogil;
            renderPng(path, r.mesh, o);
          },
          py::arg("path"), py::arg("width") = 1600, py::arg("height") = 1200, py::arg("azimuth") = 35.0,
          py::arg("elevation") = 25.0, py::arg("color") = "face", py::arg("focus") = std::vector<double>{},
          "Renders the mesh to a PNG (software rasteriser).");
}

/// The mesher (runs with the GIL released; cancellable).
void bindMesher(py::module_& mod) {
  py::class_<PyMesher>(mod, "Mesher")
      .def(py::init<PyModel, MeshParams>(), py::arg("model"), py::arg("params"))
      .def("run", &PyMesher::run, py::arg("progress") = py::none(), py::arg("log") = py::none(),
           "Meshes (GIL released). progress(fraction, stage) may return False to cancel; "
           "log(level, message). Returns a Result.")
      .def("cancel", &PyMesher::cancel, "Requests cancellation (thread-safe).");
}

/// The discrete backend's first stages on a file or on arrays: repairs, faces, edges, vertices.
py::dict discreteFeatures(const std::string& path, py::object points, py::object triangles, double angle) {
  DiscreteInput d;
  if (!path.empty()) {
    OccReaderSignalGuard guard;
    d = loadDiscrete(path, angle);
  } else {
    d = discreteFromArrays(soupFromArrays(points, triangles), angle);
  }
  py::dict out;
  std::vector<double> xyz;
  for (const Vec3& p : d.mesh.points) xyz.insert(xyz.end(), {p.x, p.y, p.z});
  out["points"] = owned(std::move(xyz), {(py::ssize_t)d.mesh.points.size(), 3});
  std::vector<int> tri;
  for (const auto& t : d.mesh.triangles) tri.insert(tri.end(), t.begin(), t.end());
  out["triangles"] = owned(std::move(tri), {(py::ssize_t)d.mesh.triangles.size(), 3});
  out["triangle_face"] = owned(std::vector<int>(d.graph.triFace), {(py::ssize_t)d.graph.triFace.size()});
  py::list edges;
  for (const auto& c : d.graph.edges) {
    py::dict e;
    e["nodes"] = c.nodes;
    e["vertices"] = py::make_tuple(c.v0, c.v1);
    e["faces"] = c.faces;
    edges.append(e);
  }
  out["edges"] = edges;
  out["vertex_nodes"] = d.graph.vertexNode;
  py::list loops;
  for (const auto& f : d.graph.faceLoops) loops.append(py::cast(f));
  out["face_loops"] = loops;
  const RepairReport& r = d.repair;
  py::dict rep;
  rep["input_points"] = r.inputPoints;
  rep["input_triangles"] = r.inputTriangles;
  rep["merged_vertices"] = r.mergedVertices;
  rep["non_finite_facets"] = r.nonFiniteFacets;
  rep["degenerate_facets"] = r.degenerateFacets;
  rep["duplicate_facets"] = r.duplicateFacets;
  rep["flipped_facets"] = r.flippedFacets;
  rep["pieces"] = r.pieces;
  rep["closed_pieces"] = r.closedPieces;
  rep["non_manifold_edges"] = r.nonManifoldEdges;
  rep["boundary_edges"] = r.boundaryEdges;
  rep["holes"] = r.holes;
  rep["unorientable_pieces"] = r.unorientablePieces;
  rep["tolerance"] = r.tolerance;
  rep["lines"] = r.lines();
  out["repair"] = rep;
  out["description"] = describeDiscrete(d);
  return out;
}

}  // namespace

PYBIND11_MODULE(_native, mod) {
  mod.doc() = "ParaMesh native core (C++). Use freecad.paramesh, not this module directly.";

  bindErrors(mod);
  bindParams(mod);
  bindModel(mod);
  bindResult(mod);
  bindMesher(mod);
  mod.def("discrete_features", &discreteFeatures, py::arg("path"), py::arg("points") = py::none(),
          py::arg("triangles") = py::none(), py::arg("feature_angle") = 40.0,
          "Triangulated input (an STL/OBJ path, or points and triangles when path is ''): repaired, "
          "split into faces, feature edges and corners.");
}
