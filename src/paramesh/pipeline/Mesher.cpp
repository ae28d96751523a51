// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/pipeline/Mesher.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <cmath>
#include <map>
#include <unordered_map>
#include <mutex>
#include <numeric>
#include <set>
#include <sstream>

#include "paramesh/algo/boundary_layer/BoundaryLayer.hpp"
#include "paramesh/algo/FaceMesher.hpp"
#include "paramesh/algo/FeatureDetect.hpp"
#include "paramesh/algo/HighOrder.hpp"
#include "paramesh/algo/Predicates.hpp"
#include "paramesh/algo/SurfaceContext.hpp"
#include "paramesh/model/Coincidence.hpp"
#include "paramesh/model/EdgeDiscretizer.hpp"
#include "paramesh/model/FaceDomain.hpp"
#include "paramesh/model/NarrowZones.hpp"
#include "paramesh/size/NearestFace.hpp"
#include "paramesh/size/Proximity.hpp"
#include "paramesh/size/SizeField.hpp"
#include "paramesh/size/SourceReach.hpp"
#include "paramesh/stages/edges/EdgeMesh.hpp"
#include "paramesh/stages/faces/FaceBoundaryBuild.hpp"
#include "paramesh/size/Sources.hpp"
#include "paramesh/util/Error.hpp"
#include "paramesh/util/Format.hpp"
#include "paramesh/util/Parallel.hpp"
#include "paramesh/util/SpatialGrid.hpp"
#include "paramesh/util/Timer.hpp"

namespace paramesh {

const char* toString(RunStatus s) {
  switch (s) {
    case RunStatus::Ok: return "ok";
    case RunStatus::Degraded: return "degraded";
    default: return "failed";
  }
}

namespace {

constexpr double kPi = 3.14159265358979323846;
// CAD edges shorter than this fraction of the size field (one segment) may become size sources
constexpr double kShortSegment = 0.5;
// edges closing a strip up to this many sizes wide are divided into rows (kRowHeight: the height of
// an equilateral triangle of side 1)
constexpr double kStripEndMax = 8.0;
constexpr double kRowHeight = 0.8660254037844386;
// corners with a short neighbour segment: the other side's first segment becomes kCornerRatio x the
// short one, growing by kCornerSlope per unit length from the corner
constexpr double kCornerRatio = 1.3;
constexpr double kCornerSlope = 0.5;
constexpr double kCornerMinRatio = 0.35;  // of the size: shorter neighbour segments are left alone
// the nearest-face check meshes again at most this many times
constexpr int kNearestFaceRounds = 6;
/// Coordinates beyond this (model units) are damaged geometry, not a model (resolveParams).
constexpr double kMaxCoordinate = 1e12;
// its size sources act locally: sizes grow away from them by 0.6 per unit length (grading 1.6),
// so that the refinement stays on the thin part (measured: docs/tuning/pipeline.md)
constexpr double kNearestFaceSlope = 0.6;
constexpr double kPredictMargin = 1.5;  // over the budget by this factor: not meshed (docs/tuning/pipeline.md)

// the nearest-face check's local repairs: around a flagged triangle, centroids may lie off their
// own surface at most this fraction of their distance to the other face's tangent plane (a
// triangle is flagged beyond 1/1.1 = 0.91; measured: docs/tuning/pipeline.md)
constexpr double kZoneFraction = 0.8;
// triangles whose centroid lies less than this fraction of the size off their face are never
// candidates of the nearest-face check
constexpr double kOffSurfaceCandidate = 0.045;
// narrow gaps (NarrowZones.hpp): gaps below kStaggerTo of the size are staggered when leader
// spacings exist that keep the slanted edges >= h/sqrt2 and the angles >= atan(2/kStaggerMaxAspect)
// = 31 degrees with a kStaggerWindow margin between the two (gaps from 0.39 h up); the spacing
// stays at most kStaggerMaxSpacing sizes
constexpr double kStaggerTo = 0.58;
constexpr double kStaggerWindow = 1.1;
constexpr double kStaggerMaxSpacing = 1.2;
constexpr double kStaggerMaxAspect = 3.3;
// strips narrower than staggering can serve (below ~0.39 h: every triangle across them has an
// angle below 30 degrees at any spacing in the unit band) and at least kWideStripNodes nodes long
// get the widest spacing in the band, kWideStripSpacing sizes: the fewest such triangles
constexpr int kWideStripNodes = 8;
constexpr double kWideStripSpacing = 1.3;
constexpr double kWideStripMinWidth = 0.15;

size_t elementCount(const SurfaceMesh& m) { return m.triangles.size() + m.quads.size(); }

}  // namespace

struct Mesher::Impl {
  const IGeometryModel& model;
  MeshParams p;
  /// The user set min_size (not the default below): the deviation refinement then makes no edge
  /// shorter than it
  bool minSizeGiven = false;
  Logger log;
  Progress progress;
  Report report;
  SurfaceMesh mesh;
  SizeField field;
  SizeField baseField;  ///< the field without boundary-layer sources (for the BL edges' own spacing)
  std::vector<EdgeMesh> edges;
  std::vector<int> vertexNode;
  Coincidence same;  ///< coincident vertices/edges of unsewn faces
  std::vector<std::array<Vec2, 3>> triUv;         ///< per output triangle: (u,v) of its corners on its face
  std::vector<std::array<Vec2, 4>> quadUv;        ///< per output quad: (u,v) of its corners on its face
  std::vector<std::array<double, 2>> segmentT;    ///< per output segment: edge parameters of its ends
  // boundary layers
  EdgeSpecMap blSpecOf;                 ///< BL spec of each edge (-1: none)
  std::vector<LayerLaw> blLaws;
  std::vector<EdgeBLPoints> blEnds;     ///< outermost-column points on non-BL edges
  std::vector<FaceBLResult::SpecStats> blStats;
  /// (face, spec) whose layer got columns but no element on that face, with its stop counts:
  /// reported as warnings (a layer asked for and not grown is not silent)
  std::map<std::pair<int, int>, FaceBLResult::SpecStats> blEmpty;
  /// faces whose layers were dropped because the face could not be meshed with them: the reason
  std::map<int, std::string> blDropped;
  std::vector<OffSurfaceTriangle> offSurface;  ///< candidates of the nearest-face check (output triangles)
  std::vector<double> triDeviation;            ///< per output triangle: centroid distance to its surface (0: small)
  std::vector<char> staggered_;                ///< per edge: discretised by the narrow-gap stage
  std::vector<std::vector<std::pair<int, double>>> strayPcurves_;  ///< per face: FaceBoundary::strayPcurves
  bool strayLogged_ = false;
  std::vector<std::string> edgeError_;         ///< per edge: why it could not be discretised ("" if it was)
  /// The last discretisation's edge parameters (before createEdgeNodes): a nearest-face round
  /// that leaves the size field as it was (local deviation bounds only) reuses them
  struct EdgeParams {
    bool valid = false;
    std::vector<std::vector<double>> ts;
    std::vector<char> degen;
    std::vector<std::string> errors;
  } lastEdges_;
  /// The previous meshing round of the nearest-face check: a face whose edges kept their nodes
  /// and that no new size source reaches keeps its mesh (the size field there is unchanged, and
  /// meshing a face is deterministic: re-meshing it would give the same elements).
  struct PreviousRound {
    std::vector<FaceMeshResult> results;
    std::vector<FaceReport> reports;
    std::vector<EdgeMesh> edges;
    std::vector<std::vector<Vec3>> points;  ///< per face: its mesh's nodes
  };
  std::unique_ptr<PreviousRound> previous_;
  std::vector<SizeSource> roundSources_;  ///< the sources added since the previous round (slope kNearestFaceSlope)
  std::vector<std::vector<DeviationZone>> zones_;  ///< per face: the nearest-face check's local deviation bounds
  std::vector<char> zonesAdded_;                   ///< per face: zones added since the previous round
  int threads = 1;

  Impl(const IGeometryModel& m, MeshParams params, LogSink sink, ProgressCallback cb)
      : model(m), p(std::move(params)), log(std::move(sink)), progress(std::move(cb)) {}

  /// Adds seconds to a stage: edges, faces and the nearest-face check run once per round, and the
  /// report gives each stage's sum over the rounds (discarded ones too: they are part of total).
  void stage(const char* name, double seconds) {
    for (auto& kv : report.stageSeconds)
      if (kv.first == name) {
        kv.second += seconds;
        return;
      }
    report.stageSeconds.emplace_back(name, seconds);
  }

  // ---------------------------------------------------------------- parameters
  void resolveParams() {
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
    if (p.size == 0) p.size = diag / 50.0;
    if (p.maxSize == 0) p.maxSize = p.size;
    // curvature sizing (for an angle or a deviation) resolves radii down to size/1000 unless told
    // otherwise (fillets, blade tips and leading edges are far smaller than the global size);
    // other sources stop at 1/100
    minSizeGiven = p.minSize > 0;
    if (p.minSize == 0) p.minSize = std::min(p.size, p.maxSize) / (p.curvatureAngle > 0 || p.maxDeviation > 0 ? 1000.0 : 100.0);
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
    for (size_t i = 0; i < p.boundaryLayers.size(); ++i)
      for (int e : p.boundaryLayers[i].edges)
        checkRange(e, model.numEdges(), "Edge", "boundary layer #" + std::to_string(i + 1));
    threads = resolveThreads(p.threads);
    progress.setPointBudget(p.maxElements / 2);  // the proximity measurement meshes too
    report.size = p.size;
    report.minSize = p.minSize;
    report.maxSize = p.maxSize;
    report.curvatureAngle = p.curvatureAngle;
    report.maxDeviation = p.maxDeviation;
    report.grading = p.grading;
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
    mesh.numEdges = model.numEdges();
    mesh.numVertices = model.numVertices();
  }

  // ---------------------------------------------------------------- coincident topology
  void findCoincidentTopology() {
    Timer tm;
    // gaps up to 1e-6 of the diagonal are closed (nodes then stay within 1e-4 h of every face for
    // h >= diagonal/100); larger gaps are real and stay open
    same = findCoincident(model, 2e-7 * model.boundingBox().diagonal());
    if (same.mergedEdges || same.mergedVertices)
      log.info("unsewn CAD: " + std::to_string(same.mergedEdges) + " coincident edges and " +
               std::to_string(same.mergedVertices) + " coincident vertices are meshed as one");
    stage("topology", tm.seconds());
  }

  // ---------------------------------------------------------------- size field
  void buildSizeField() {
    Timer tm;
    const double hmax = std::min(p.size, p.maxSize);
    field = SizeField(hmax, p.grading);
    std::vector<std::vector<SizeSource>> per;
    if (p.curvatureAngle > 0 || p.maxDeviation > 0) {
      const double ang = p.curvatureAngle * kPi / 180.0;
      // edges: chords of boundary edges cannot be refined inside a face, so their sag is bounded
      // by 1D sizes (a boundary chord with sag s leaves ~2s/3 at the centroid of its triangle)
      const double dev = 1.4 * p.maxDeviation * p.size;
      // faces: an equilateral triangle of edge h on a surface of curvature k has its centroid
      // about h^2 k / 6 off it, and the sampler's size for a deviation d is the chord of sag d,
      // sqrt(8 d / k): 3/4 of the bound gives sqrt(6 d / k). Without it the refinement meets the
      // bound alone, split by split: needles (measured: docs/tuning/pipeline.md)
      const double faceDev = 0.75 * p.maxDeviation * p.size;
      const int nf = model.numFaces(), ne = model.numEdges();
      per.resize(nf + ne);
      std::vector<FaceSamplingStats> stats(nf);
      std::vector<char> failed(nf + ne, 0);
      parallelFor(nf + ne, threads, [&](int i) {
        progress.poll();
        try {
          per[i] = i < nf ? faceCurvatureSources(model, i, ang, p.minSize, hmax, faceDev, &stats[i])
                          : edgeCurvatureSources(model, i - nf, ang, p.minSize, hmax, dev);
        } catch (const Cancelled&) {
          throw;
        } catch (...) {
          failed[i] = 1;
        }
      });
      // a face sampled coarser than its sizes, or not at all, gets larger elements than the
      // curvature asks for: say so in the report, not only in the log
      for (int i = 0; i < nf + ne; ++i) {
        if (!failed[i] && !(i < nf && stats[i].truncated)) continue;
        const std::string name = (i < nf ? "Face" : "Edge") + std::to_string(i < nf ? i + 1 : i - nf + 1);
        const std::string w =
            failed[i] ? "curvature sampling failed on " + name + ": its curvature sizes are missing"
                      : "curvature sampling of " + name + " stopped at its budget of " +
                            std::to_string(kFaceSamplingBudget) +
                            " cells: part of the face is sampled coarser than its curvature sizes (a larger min-size or curvature angle samples it in full)";
        report.warnings.push_back(w);
        log.warn(w);
      }
    }
    for (const LocalSize& l : p.localSizes) per.push_back(localSizeSources(model, l));
    for (auto& v : per)
      for (auto& s : v) field.addSource(s.p, std::max(s.h, p.minSize));
    field.build();
    stage("size_field", tm.seconds());
  }

  // ---------------------------------------------------------------- proximity
  void addProximitySources() {
    Timer tm;
    // a first surface mesh with the sizes so far tells where walls and faces are thin
    MeshParams q = p;
    q.proximity = 0;
    q.nearestFaceCheck = false;
    q.nearestFaceBudget = 0;
    q.order = 1;
    q.quads = false;
    q.optimizePasses = 1;
    q.boundaryLayers.clear();
    Mesher first(model, q, {}, [this](double, const std::string&) { return !progress.isCancelled(); });
    MeshOutput coarse = first.run();
    const auto src = proximitySources(coarse.mesh, p.proximity, std::min(p.size, p.maxSize), p.minSize);
    for (const auto& s : src) field.addSource(s.p, s.h);
    field.build();
    log.info("proximity: " + std::to_string(src.size()) + " size sources from thin walls and narrow faces");
    stage("proximity", tm.seconds());
  }

  // ---------------------------------------------------------------- boundary layers (1D part)
  void planBoundaryLayers() {
    if (p.boundaryLayers.empty()) return;
    Timer tm;
    blSpecOf.assign(model.numEdges(), -1);
    for (auto& spec : p.boundaryLayers) {
      if (!spec.autoEdges) continue;
      const auto found = proposeLeadingEdges(model, 0.0, 10.0, 10.0, nullptr, &same.edgeRep);
      for (const RidgeCandidate& rc : found) {
        spec.edges.push_back(rc.edge + 1);
        report.proposedLeadingEdges.push_back({rc.edge + 1, rc.acrossCurvature > 0 ? 1.0 / rc.acrossCurvature : 0.0, rc.ratio});
      }
      log.info("leading edges proposed: " + std::to_string(found.size()));
      if (found.empty()) report.warnings.push_back("no leading edge was found for the automatic boundary layer");
    }
    for (size_t s = 0; s < p.boundaryLayers.size(); ++s) {
      blLaws.push_back(LayerLaw::from(p.boundaryLayers[s]));
      for (int e1 : p.boundaryLayers[s].edges) {
        const int rep = same.edgeRep[e1 - 1];
        for (int e = 0; e < model.numEdges(); ++e)  // coincident edges of unsewn faces grow too
          if (same.edgeRep[e] == rep) {
            if (model.edgeDegenerate(e))
              throw ParameterError("boundary layer #" + std::to_string(s + 1) + ": Edge" + std::to_string(e + 1) +
                                   " is degenerate (a point) and cannot carry a boundary layer");
            blSpecOf[e] = (int)s;
          }
      }
    }
    blStats.assign(blLaws.size(), FaceBLResult::SpecStats());
    blEnds = planEndColumns(model, blSpecOf, blLaws, &same);
    baseField = field;
    // the points of the outermost columns are size sources: edges and faces grade from them
    for (int e = 0; e < model.numEdges(); ++e) {
      const auto& bp = blEnds[e];
      if (bp.fromStart.empty() && bp.fromEnd.empty()) continue;
      auto c = model.makeCurve(e);
      for (int side = 0; side < 2; ++side) {
        const auto& ts = side == 0 ? bp.fromStart : bp.fromEnd;
        Vec3 prev = c->eval(side == 0 ? edgeT0(e) : edgeT1(e));
        for (double t : ts) {
          const Vec3 q = c->eval(t);
          field.addSource(q, std::max(dist(q, prev), p.minSize));
          prev = q;
        }
      }
    }
    field.build();
    stage("boundary_layer_plan", tm.seconds());
  }
  double edgeT0(int e) const {
    double a, b;
    model.edgeRange(e, a, b);
    return a;
  }
  double edgeT1(int e) const {
    double a, b;
    model.edgeRange(e, a, b);
    return b;
  }

  // ---------------------------------------------------------------- edges
  /// Why work on one edge failed ("" when it did not): the message of what it threw, or the
  /// kernel's failure; a cancel goes through.
  static std::string edgeFailure(const std::function<void()>& work) {
    try {
      work();
    } catch (const Cancelled&) {
      throw;
    } catch (const std::exception& x) {
      return x.what();
    } catch (...) {
      return "the geometry kernel failed while evaluating its curve";
    }
    return "";
  }

  void discretizeEdges() {
    const int ne = model.numEdges();
    std::vector<std::vector<double>> ts(ne);
    std::vector<char> degen(ne, 0);
    edgeError_.assign(ne, std::string());
    // an edge the geometry kernel cannot evaluate (a damaged curve) fails alone: it gets no nodes,
    // the faces bounded by it fail naming it, the others are meshed
    auto discretizeOne = [&](int e, const std::function<void()>& body) {
      if (!edgeError_[e].empty()) return;
      edgeError_[e] = edgeFailure(body);
      if (!edgeError_[e].empty()) ts[e].clear();
    };
    // every edge, or those marked in only
    auto discretizeAll = [&](const std::vector<char>* only) {
    parallelFor(ne, threads, [&](int e) { if (only && !(*only)[e]) return; discretizeOne(e, [&] {
      progress.poll();
      double t0, t1;
      model.edgeRange(e, t0, t1);
      if (same.edgeRep[e] != e) return;  // meshed through its representative
      if (model.edgeDegenerate(e)) {
        degen[e] = 1;
        ts[e] = {t0, t1};
        return;
      }
      auto c = model.makeCurve(e);
      const EdgeBLPoints* bp = blEnds.empty() ? nullptr : &blEnds[e];
      if (bp && (!bp->fromStart.empty() || !bp->fromEnd.empty())) {
        // boundary-layer points fixed at the ends, the middle discretised as usual
        const double a = bp->fromStart.empty() ? t0 : bp->fromStart.back();
        const double b = bp->fromEnd.empty() ? t1 : bp->fromEnd.back();
        std::vector<double> t{t0};
        t.insert(t.end(), bp->fromStart.begin(), bp->fromStart.end());
        CurveSampling cs = sampleCurve(*c, a, b, &field);
        const std::vector<double> midT = discretizeCurve(cs, field, 1, kPi / 3.0);
        t.insert(t.end(), midT.begin() + 1, midT.end() - 1);
        t.insert(t.end(), bp->fromEnd.rbegin(), bp->fromEnd.rend());
        t.push_back(t1);
        ts[e] = t;
        return;
      }
      // BL edges keep their spanwise spacing: the layers' own sizes do not refine them
      const SizeField& f = (!blSpecOf.empty() && blSpecOf[e] >= 0) ? baseField : field;
      CurveSampling cs = sampleCurve(*c, t0, t1, &f);
      const int v0 = model.edgeVertex(e, 0), v1 = model.edgeVertex(e, 1);
      const bool closed = (v0 >= 0 && v0 == v1) || dist(cs.p.front(), cs.p.back()) < 1e-9 * (1 + cs.length());
      ts[e] = discretizeCurve(cs, f, closed ? 3 : 1, kPi / 3.0);
    }); });
    };
    discretizeAll(nullptr);
    // CAD edges much shorter than the size field, in chains (a finely detailed boundary) or split
    // into 3+ segments by the turning limit (tight arcs), become size sources at their segment
    // lengths, and the edges are discretised again: the neighbouring edges and the face interiors
    // grade down to them instead of standing long thin triangles on them. Short edges that close
    // a narrow strip are left alone (refining there only multiplies the strip's slivers).
    if (p.shortEdgeSources && blLaws.empty()) {
      // nodes of every edge, and the edges at each (representative) vertex
      std::vector<std::vector<Vec3>> pts(ne);
      parallelFor(ne, threads, [&](int e) {
        if (degen[e] || same.edgeRep[e] != e || ts[e].size() < 2) return;
        discretizeOne(e, [&] {
          auto c = model.makeCurve(e);
          for (double t : ts[e]) pts[e].push_back(c->eval(t));
        });
        if (!edgeError_[e].empty()) pts[e].clear();
      });
      std::vector<std::vector<std::pair<int, int>>> atVertex(model.numVertices());  // (edge, end)
      for (int e = 0; e < ne; ++e) {
        if (pts[e].empty()) continue;
        for (int k = 0; k < 2; ++k) {
          const int v = model.edgeVertex(e, k);
          if (v >= 0) atVertex[same.vertexRep[v]].push_back({e, k});
        }
      }
      auto polyLength = [&](int e) {
        double L = 0;
        for (size_t i = 1; i < pts[e].size(); ++i) L += dist(pts[e][i - 1], pts[e][i]);
        return L;
      };
      auto distToPoly = [&](Vec3 x, int e) {
        double best = 1e300;
        const auto& P = pts[e];
        for (size_t i = 1; i < P.size(); ++i) {
          const Vec3 d = P[i] - P[i - 1];
          const double dd = dot(d, d);
          const double w = dd > 0 ? std::clamp(dot(x - P[i - 1], d) / dd, 0.0, 1.0) : 0.0;
          best = std::min(best, dist(x, P[i - 1] + w * d));
        }
        return best;
      };
      // point of edge e at about arc length s from its end k
      auto along = [&](int e, int k, double sArc) {
        const auto& P = pts[e];
        const int n = (int)P.size();
        double acc = 0;
        for (int i = 1; i < n; ++i) {
          const Vec3 x0 = k == 0 ? P[i - 1] : P[n - i], x1 = k == 0 ? P[i] : P[n - 1 - i];
          const double l = dist(x0, x1);
          if (acc + l >= sArc && l > 0) return x0 + ((sArc - acc) / l) * (x1 - x0);
          acc += l;
        }
        return k == 0 ? P.back() : P.front();
      };
      // A short edge closing a narrow strip (the end of a thin face: its neighbours run on side by
      // side at about its length) is no small feature: refining there only multiplies the
      // strip's slivers.
      auto closesStrip = [&](int e, double l) {
        const int va = model.edgeVertex(e, 0), vb = model.edgeVertex(e, 1);
        if (va < 0 || vb < 0) return false;
        for (const auto& ea : atVertex[same.vertexRep[va]]) {
          if (ea.first == e) continue;
          const double La = polyLength(ea.first);
          if (La < 3 * l) continue;
          const Vec3 x = along(ea.first, ea.second, std::min(0.5 * La, 3 * l));
          for (const auto& eb : atVertex[same.vertexRep[vb]]) {
            if (eb.first == e || eb.first == ea.first) continue;
            if (distToPoly(x, eb.first) < 1.5 * l) return true;
          }
        }
        return false;
      };
      std::vector<char> isShort(ne, 0);
      for (int e = 0; e < ne; ++e) {
        if (pts[e].size() < 2) continue;
        const double L = polyLength(e);
        const double hf = field.size(pts[e][pts[e].size() / 2]);
        isShort[e] = L > 0 && L < kShortSegment * hf && !closesStrip(e, L);
      }
      // a short edge next to another short edge: a finely detailed boundary (one isolated short
      // edge costs a few poor triangles; refining around it would cost hundreds of elements)
      auto inChain = [&](int e) {
        for (int k = 0; k < 2; ++k) {
          const int v = model.edgeVertex(e, k);
          if (v < 0) continue;
          for (const auto& ev : atVertex[same.vertexRep[v]])
            if (ev.first != e && isShort[ev.first]) return true;
        }
        return false;
      };
      std::vector<std::vector<SizeSource>> found(ne);
      parallelFor(ne, threads, [&](int e) {
        // a short edge on its own counts when the turning limit split it into three segments or
        // more: a tight arc (small rounded feature) rather than a mere short chord
        if (!isShort[e] || !(inChain(e) || pts[e].size() > 3)) return;
        const auto& P = pts[e];
        for (size_t i = 1; i < P.size(); ++i) {
          const double hs = std::max(dist(P[i - 1], P[i]), p.minSize);
          if (i == 1) found[e].push_back({P[0], hs});
          found[e].push_back({0.5 * (P[i - 1] + P[i]), hs});
          found[e].push_back({P[i], hs});
        }
      });
      size_t added = 0;
      for (const auto& v : found)
        for (const SizeSource& s : v) {
          field.addSource(s.p, s.h);
          ++added;
        }
      if (added) {
        field.build();
        // again only the edges the new sources reach (grading > 1: a source of size h changes the
        // field within (hmax - h) / (grading - 1) of it); an edge's discretisation queries the
        // field on its curve only, within two segments of its nodes' box
        std::vector<Vec3> at;
        std::vector<double> reach;
        for (const auto& v : found)
          for (const SizeSource& s : v) {
            at.push_back(s.p);
            reach.push_back((field.hmax() - s.h) / field.slope());
          }
        const SourceReach near(std::move(at), std::move(reach));
        std::vector<char> redo(ne, 0);
        for (int e = 0; e < ne; ++e) {
          if (same.edgeRep[e] != e || degen[e]) continue;
          if (pts[e].empty()) {  // no nodes to bound it
            redo[e] = 1;
            continue;
          }
          Box3 b;
          double seg = 0;
          for (size_t i = 0; i < pts[e].size(); ++i) {
            b.add(pts[e][i]);
            if (i) seg = std::max(seg, dist(pts[e][i - 1], pts[e][i]));
          }
          const Vec3 margin{2 * seg, 2 * seg, 2 * seg};
          redo[e] = near.reaches(b.lo - margin, b.hi + margin);
        }
        discretizeAll(&redo);
      }
      // An edge closing a strip a few elements wide ends the rows of triangles that grow from the
      // strip's sides: rows of equilateral triangles are 0.87 h high, so its segments are too
      // (with segments of h the rows cannot end on its nodes and break up along the strip).
      parallelFor(ne, threads, [&](int e) {
        if (pts[e].size() < 2 || !mayRespace(e, degen) || same.edgeRep[e] != e) return;
        const int v0 = model.edgeVertex(e, 0), v1 = model.edgeVertex(e, 1);
        if (v0 < 0 || v1 < 0 || v0 == v1) return;
        const double L = polyLength(e);
        const double hf = field.size(pts[e][pts[e].size() / 2]);
        if (!(L > hf) || L > kStripEndMax * hf || !closesStrip(e, L)) return;
        discretizeOne(e, [&] { ts[e] = discretizeWith(e, [this](Vec3 x) { return kRowHeight * field.size(x); }); });
      });
    }
    splitParallelChords(ts, degen);
    // boundary refinements of the discretisation; a kernel failure in one leaves the edges as
    // they were before it (the mesh stays valid, only less well shaped there)
    auto refineStage = [&](const char* what, const std::function<bool()>& stage) {
      const std::vector<std::vector<double>> before = ts;
      try {
        if (stage()) splitParallelChords(ts, degen);
      } catch (const Cancelled&) {
        throw;
      } catch (const std::exception& e) {
        ts = before;
        log.warn(std::string(what) + " skipped: " + e.what());
      }
    };
    if (p.staggerNarrowGaps && blLaws.empty())
      refineStage("narrow gaps", [&] { return staggerNarrowGaps(ts, degen); });
    if (blLaws.empty()) refineStage("corner spacing", [&] { return matchCornerSegments(ts, degen); });
    lastEdges_ = {true, ts, degen, edgeError_};
    createEdgeNodes(ts, degen);
  }

  /// The edge nodes again from the last discretisation (the size field has not changed since).
  void reuseEdges() {
    edgeError_ = lastEdges_.errors;
    createEdgeNodes(lastEdges_.ts, lastEdges_.degen);
  }

  /// Two edges joining the same two vertices must not both be a single chord.
  void splitParallelChords(std::vector<std::vector<double>>& ts, const std::vector<char>& degen) const {
    const int ne = model.numEdges();
    std::map<std::pair<int, int>, std::vector<int>> byEnds;
    for (int e = 0; e < ne; ++e) {
      if (degen[e] || ts[e].size() != 2) continue;
      int a = model.edgeVertex(e, 0), b = model.edgeVertex(e, 1);
      if (a < 0 || b < 0) continue;
      a = same.vertexRep[a];
      b = same.vertexRep[b];
      byEnds[{std::min(a, b), std::max(a, b)}].push_back(e);
    }
    for (auto& kv : byEnds) {
      if (kv.second.size() < 2) continue;
      for (size_t k = 1; k < kv.second.size(); ++k) {
        int e = kv.second[k];
        ts[e] = {ts[e][0], 0.5 * (ts[e][0] + ts[e][1]), ts[e][1]};
      }
    }
  }

  /// The mesh nodes and 1D elements of every edge from its parameters.
  void createEdgeNodes(const std::vector<std::vector<double>>& ts, const std::vector<char>& degen) {
    const int ne = model.numEdges();
    vertexNode.assign(model.numVertices(), -1);
    edges.assign(ne, EdgeMesh());
    auto nodeOfVertex = [&](int v) {
      const int r = same.vertexRep[v];
      if (vertexNode[r] < 0) vertexNode[r] = mesh.addNode(model.vertexPoint(r), NodeKind::Vertex, r + 1);
      vertexNode[v] = vertexNode[r];
      return vertexNode[v];
    };
    for (int e = 0; e < ne; ++e) {
      const int v0 = model.edgeVertex(e, 0), v1 = model.edgeVertex(e, 1);
      if (v0 >= 0) nodeOfVertex(v0);
      if (v1 >= 0) nodeOfVertex(v1);
    }
    // Interior nodes of different edges that coincide (unsewn patches whose curves agree at the
    // nodes but not everywhere within the merge tolerance) become one node: no duplicate nodes.
    const double eps = 1e-8 * model.boundingBox().diagonal();
    std::unordered_map<uint64_t, std::vector<int>> edgeNodeCells;
    auto cellOf = [eps](Vec3 p, int di, int dj, int dk) {
      const auto q = [eps](double x, int d) { return (uint64_t)((int64_t)std::floor(x / (4 * eps)) + d) & 0x1FFFFF; };
      return (q(p.x, di) << 42) | (q(p.y, dj) << 21) | q(p.z, dk);
    };
    // a curve that leaves the model's box by more than its diagonal is damaged (docs/tuning/pipeline.md)
    Box3 reach = model.boundingBox();
    const double diag = reach.diagonal();
    for (int i = 0; i < 3; ++i) {
      reach.lo[i] -= diag;
      reach.hi[i] += diag;
    }
    auto edgeNode = [&](Vec3 p, int e, double t) {
      for (int di = -1; di <= 1; ++di)
        for (int dj = -1; dj <= 1; ++dj)
          for (int dk = -1; dk <= 1; ++dk) {
            auto it = edgeNodeCells.find(cellOf(p, di, dj, dk));
            if (it == edgeNodeCells.end()) continue;
            for (int nd : it->second)
              if (mesh.nodeEntity[nd] != e + 1 && dist(mesh.nodes[nd], p) <= eps) return nd;
          }
      const int nd = mesh.addNode(p, NodeKind::Edge, e + 1, {t, 0});
      edgeNodeCells[cellOf(p, 0, 0, 0)].push_back(nd);
      return nd;
    };
    for (int e = 0; e < ne; ++e) {
      if (same.edgeRep[e] != e) continue;
      EdgeMesh& em = edges[e];
      em.t = ts[e];
      em.degenerate = degen[e];
      const int v0 = model.edgeVertex(e, 0), v1 = model.edgeVertex(e, 1);
      const size_t n = em.t.size();
      // the points first: an edge that cannot be evaluated, or whose curve leaves the model's box
      // by more than its diagonal (damaged), fails alone and adds no node
      std::vector<Vec3> xyz(n);
      if (!em.degenerate && n > 0) {
        edgeError_[e] = edgeFailure([&] {
          std::unique_ptr<ICurve> c = model.makeCurve(e);
          for (size_t i = 0; i < n; ++i) {
            const Vec3 q = c->eval(em.t[i]);
            for (int k = 0; k < 3; ++k)
              if (!(q[k] >= reach.lo[k] && q[k] <= reach.hi[k]))
                throw InputError("its curve passes through (" + fmt(q.x) + ", " + fmt(q.y) + ", " + fmt(q.z) +
                                 "), far outside the model's bounding box: its geometry is damaged");
            xyz[i] = q;
          }
        });
        if (!edgeError_[e].empty()) {
          em.t.clear();
          continue;
        }
      }
      em.nodes.resize(n);
      for (size_t i = 0; i < n; ++i) {
        if (i == 0 && v0 >= 0) {
          em.nodes[i] = vertexNode[v0];
        } else if (i + 1 == n && v1 >= 0) {
          em.nodes[i] = vertexNode[v1];
        } else if (em.degenerate) {
          em.nodes[i] = v0 >= 0 ? vertexNode[v0] : (v1 >= 0 ? vertexNode[v1] : -1);
        } else {
          em.nodes[i] = edgeNode(xyz[i], e, em.t[i]);
        }
      }
      if (!em.degenerate)
        for (size_t i = 0; i + 1 < n; ++i) {
          if (em.nodes[i] == em.nodes[i + 1]) continue;  // an edge shorter than the merge tolerance
          if (mesh.nodeEntity[em.nodes[i]] != e + 1 && mesh.nodeEntity[em.nodes[i + 1]] != e + 1 &&
              mesh.nodeKind[em.nodes[i]] == NodeKind::Edge && mesh.nodeKind[em.nodes[i + 1]] == NodeKind::Edge &&
              mesh.nodeEntity[em.nodes[i]] == mesh.nodeEntity[em.nodes[i + 1]])
            continue;  // this piece coincides with a piece of another edge: one 1D element
          mesh.segments.push_back({em.nodes[i], em.nodes[i + 1]});
          mesh.segmentEdge.push_back(e + 1);
          segmentT.push_back({em.t[i], em.t[i + 1]});
        }
    }
    // coincident edges take their representative's nodes, with parameters on their own curve
    for (int e = 0; e < ne; ++e) {
      const int r = same.edgeRep[e];
      if (r == e) continue;
      const EdgeMesh& rm = edges[r];
      EdgeMesh& em = edges[e];
      if (!edgeError_[r].empty()) {
        edgeError_[e] = "it coincides with Edge" + std::to_string(r + 1) + ", which failed: " + edgeError_[r];
        continue;
      }
      const size_t n = rm.nodes.size();
      edgeError_[e] = edgeFailure([&] {
        auto c = model.makeCurve(e);
        double t0, t1;
        model.edgeRange(e, t0, t1);
        em.nodes.resize(n);
        em.t.resize(n);
        for (size_t i = 0; i < n; ++i) {
          const size_t j = same.edgeReversed[e] ? n - 1 - i : i;
          em.nodes[i] = rm.nodes[j];
          const double seed = t0 + (t1 - t0) * (double)i / (double)(n - 1);
          em.t[i] = i == 0 ? t0 : (i + 1 == n ? t1 : c->project(mesh.nodes[em.nodes[i]], seed, t0, t1));
        }
      });
      if (!edgeError_[e].empty()) {
        em.nodes.clear();
        em.t.clear();
      }
    }
  }

  // ---------------------------------------------------------------- narrow gaps
  /// The boundary loops of face f as discretised by ts (wire order, inward directions from the
  /// face's outward normal: the face lies to the left of its wires seen from outside). Empty when
  /// the face uses an edge meshed through a coincident one (unsewn CAD).
  std::vector<std::vector<LoopNode>> loopNodes(int f, const std::vector<std::vector<double>>& ts,
                                               const std::vector<char>& degen) const {
    std::vector<std::vector<LoopNode>> loops;
    auto s = model.makeSurface(f);
    const bool rev = model.faceReversed(f);
    const auto& wires = model.faceWires(f);
    for (size_t w = 0; w < wires.size(); ++w) {
      std::vector<LoopNode> L;
      std::vector<Vec3> nrm;
      for (size_t k = 0; k < wires[w].uses.size(); ++k) {
        const EdgeUse& u = wires[w].uses[k];
        const int e = u.edge;
        if (same.edgeRep[e] != e || ts[e].size() < 2) return {};
        if (degen[e]) {
          const int v = model.edgeVertex(e, 0);
          if (v < 0) return {};
          LoopNode ln;
          ln.xyz = model.vertexPoint(v);
          ln.edge = e;
          L.push_back(ln);
          nrm.push_back({0, 0, 0});
          continue;
        }
        auto c = model.makeCurve(e);
        auto pc = model.makePCurve(f, (int)w, (int)k);
        const auto& t = ts[e];
        const size_t n = t.size();
        for (size_t i = 0; i + 1 < n; ++i) {
          const double tt = u.reversed ? t[n - 1 - i] : t[i];
          LoopNode ln;
          ln.xyz = c->eval(tt);
          ln.edge = e;
          Vec3 N{0, 0, 0};
          if (!pc || !s->normal(pc->eval(tt), N)) N = {0, 0, 0};
          L.push_back(ln);
          nrm.push_back(rev ? -1.0 * N : N);
        }
      }
      const int m = (int)L.size();
      if (m < 3) continue;
      for (int i = 0; i < m; ++i) {
        const Vec3 v = cross(nrm[i], L[(i + 1) % m].xyz - L[(i + m - 1) % m].xyz);
        L[i].inward = norm2(v) > 0 ? normalized(v) : Vec3{0, 0, 0};
      }
      loops.push_back(std::move(L));
    }
    return loops;
  }

  /// Narrow gaps (NarrowZones.hpp). Where two sides of a face face each other at a gap w below
  /// kStaggerTo of the size h, one row of triangles spans the gap: nodes opposite each other make
  /// angles below 30 degrees there. Instead, the nodes of one side (the follower edge) go midway
  /// between the projections of the other side's nodes (the leader), and the leader's spacing b
  /// along the gap lies between 2 sqrt(h^2/2 - w^2) (slanted edges h/sqrt2) and 3.3 w (angles 31
  /// degrees). Below w = 0.39 h no spacing does both with a margin: such gaps are left alone (a
  /// single row cannot have good angles there without edges shorter than h/sqrt2). Returns true
  /// when some edge changed.
  bool staggerNarrowGaps(std::vector<std::vector<double>>& ts, const std::vector<char>& degen) {
    const int nf = model.numFaces(), ne = model.numEdges();
    staggered_.assign(ne, 0);
    std::vector<std::vector<NarrowGap>> gaps(nf);
    parallelFor(nf, threads, [&](int f) {
      progress.poll();
      try {
        gaps[f] = findNarrowGaps(loopNodes(f, ts, degen), kStaggerTo * 1.4);
      } catch (const Cancelled&) {
        throw;
      } catch (...) {
        gaps[f].clear();
      }
    });
    // the leader spacing each gap asks for, at both of its ends; pair weights
    struct Want {
      Vec3 x;
      double b;
    };
    std::vector<std::vector<Want>> wants(ne), wide(ne);
    std::map<std::pair<int, int>, int> weight;
    std::map<std::pair<int, int>, std::vector<const NarrowGap*>> tooNarrow;  // (edge, edge across)
    for (const auto& fg : gaps)
      for (const NarrowGap& g : fg) {
        const double h = field.size(g.p);
        const double r = g.width / h;
        if (r >= kStaggerTo) continue;
        // leader spacings between bLen (slanted edges h/sqrt2) and bAng (base angles 31 degrees),
        // with room for the follower's side being a little longer than the leader's
        const double bLen = 2.0 * std::sqrt(std::max(0.5 - r * r, 0.0)) * h, bAng = kStaggerMaxAspect * g.width;
        if (bAng < kStaggerWindow * bLen) {
          if (r > kWideStripMinWidth && g.edgeIn == g.edgeOut && g.edgeIn >= 0 && g.edgeAcross >= 0 && g.edgeAcross != g.edgeIn)
            tooNarrow[{g.edgeIn, g.edgeAcross}].push_back(&g);
          continue;
        }
        const double b = std::min(std::max(h, 1.06 * bLen), std::min(kStaggerMaxSpacing * h, bAng / 1.04));
        const int across = g.edgeAcross;
        if (across < 0 || !mayRespace(across, degen)) continue;
        wants[across].push_back({g.q, b});
        for (int e : {g.edgeIn, g.edgeOut}) {
          if (e >= 0 && e != across && mayRespace(e, degen)) {
            wants[e].push_back({g.p, b});
            ++weight[{std::min(e, across), std::max(e, across)}];
          }
          if (g.edgeIn == g.edgeOut) break;
        }
      }
    // long strips too narrow to stagger: both sides widened (where neither side is staggered)
    for (const auto& kv : tooNarrow) {
      if ((int)kv.second.size() < kWideStripNodes) continue;
      const int e = kv.first.first, a = kv.first.second;
      if (!mayRespace(e, degen) || !mayRespace(a, degen)) continue;
      for (const NarrowGap* g : kv.second) {
        const double b = kWideStripSpacing * field.size(g->p);
        wide[e].push_back({g->p, b});
        wide[a].push_back({g->q, b});
      }
    }
    // the field's size, raised to each wanted spacing near where it is wanted (graded away)
    auto discretizeWidened = [&](int e, const std::vector<Want>& W) {
      ts[e] = discretizeWith(e, [&](Vec3 x) {
        double h = field.size(x);
        for (const Want& w : W) h = std::max(h, w.b - field.slope() * std::max(0.0, dist(x, w.x) - 0.5 * w.b));
        return h;
      });
    };
    std::vector<std::pair<int, std::pair<int, int>>> pairs;
    for (const auto& kv : weight) pairs.push_back({kv.second, kv.first});
    std::stable_sort(pairs.begin(), pairs.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    // roles: an edge leads, follows (its leaders' nodes fixed first) or is free; no cycles
    std::vector<std::vector<int>> leaders(ne);
    std::vector<char> follower(ne, 0), leads(ne, 0);
    auto dependsOn = [&](int x0, int target) {  // does x0 (transitively) follow target?
      std::vector<int> stack{x0};
      std::vector<char> seen(ne, 0);
      while (!stack.empty()) {
        const int x = stack.back();
        stack.pop_back();
        if (x == target) return true;
        if (seen[x]) continue;
        seen[x] = 1;
        for (int y : leaders[x]) stack.push_back(y);
      }
      return false;
    };
    for (const auto& pr : pairs) {
      int a = pr.second.first, b = pr.second.second;
      if (follower[a] && follower[b]) continue;
      if (follower[a] || (leads[b] && !leads[a])) std::swap(a, b);  // b follows a
      if (dependsOn(a, b)) continue;
      leaders[b].push_back(a);
      follower[b] = 1;
      leads[a] = 1;
    }
    int changed = 0;
    // leaders that follow no one: spacing widened along their gaps
    for (int e = 0; e < ne; ++e) {
      if (!leads[e] || follower[e] || wants[e].empty()) continue;
      discretizeWidened(e, wants[e]);
      staggered_[e] = 1;
      ++changed;
    }
    // followers in dependency order, staggered against their leaders' nodes
    std::vector<int> order;
    std::vector<char> placed(ne, 0);
    for (bool more = true; more;) {
      more = false;
      for (int e = 0; e < ne; ++e) {
        if (!follower[e] || placed[e]) continue;
        bool ready = true;
        for (int a : leaders[e]) ready = ready && (!follower[a] || placed[a]);
        if (!ready) continue;
        placed[e] = 1;
        order.push_back(e);
        more = true;
      }
    }
    int staggered = 0;
    for (int b : order) {
      progress.poll();
      auto cb = model.makeCurve(b);
      double t0, t1;
      model.edgeRange(b, t0, t1);
      const std::vector<Vec3> poly = sampleCurve(*cb, t0, t1, &field).p;
      double hMax = 0;
      for (const Vec3& x : poly) hMax = std::max(hMax, field.size(x));
      const SegmentIndex near_b(poly, hMax);
      // the leaders' nodes near b, and their neighbours along the leader
      std::vector<Vec3> near;
      for (int a : leaders[b]) {
        auto ca = model.makeCurve(a);
        std::vector<Vec3> xa;
        for (double t : ts[a]) xa.push_back(ca->eval(t));
        std::vector<char> take(xa.size(), 0);
        for (size_t i = 0; i < xa.size(); ++i)
          if (near_b.nearest(xa[i], kStaggerTo * field.size(xa[i])) >= 0) {
            take[i] = 1;
            if (i > 0) take[i - 1] = 1;
            if (i + 1 < xa.size()) take[i + 1] = 1;
          }
        for (size_t i = 0; i < xa.size(); ++i)
          if (take[i]) near.push_back(xa[i]);
      }
      if (near.size() < 2) continue;
      ts[b] = staggeredParameters(*cb, t0, t1, near, field, kPi / 3.0);
      staggered_[b] = 1;
      ++staggered;
      ++changed;
    }
    int widened = 0;
    for (int e = 0; e < ne; ++e)
      if (!wide[e].empty() && !staggered_[e] && !follower[e]) {
        discretizeWidened(e, wide[e]);
        ++widened;
      }
    if (changed || widened)
      log.info("narrow gaps: " + std::to_string(staggered) + " edges staggered against " +
               std::to_string(changed - staggered) + " widened ones; " + std::to_string(widened) +
               " sides of long narrow strips widened");
    return changed + widened > 0;
  }

  /// May the boundary stages (narrow gaps, corners, strip ends) change edge e's discretisation?
  /// Not a degenerate edge, and in unsewn CAD not a free edge: free edges of unsewn patches often
  /// overlap another patch's free edge in part, and their default discretisations match there.
  bool mayRespace(int e, const std::vector<char>& degen) const {
    if (degen[e]) return false;
    if (!(same.mergedEdges || same.mergedVertices)) return true;
    // faces using the edge or a coincident twin of it
    size_t uses = 0;
    const int r = same.edgeRep[e];
    for (int k = 0; k < model.numEdges() && uses < 2; ++k)
      if (same.edgeRep[k] == r) uses += model.edgeFaces(k).size();
    return uses >= 2;
  }

  /// Parameters of edge e discretised with the given spacing (as discretizeEdges does with the
  /// field: closed edges get at least 3 segments, none turns by more than 60 degrees).
  std::vector<double> discretizeWith(int e, const std::function<double(Vec3)>& spacing) const {
    auto c = model.makeCurve(e);
    double t0, t1;
    model.edgeRange(e, t0, t1);
    const CurveSampling cs = sampleCurve(*c, t0, t1, &field);
    const int v0 = model.edgeVertex(e, 0), v1 = model.edgeVertex(e, 1);
    const bool closed = (v0 >= 0 && v0 == v1) || dist(cs.p.front(), cs.p.back()) < 1e-9 * (1 + cs.length());
    return discretizeCurve(cs, spacing, closed ? 3 : 1, kPi / 3.0);
  }

  /// Corners whose ear triangle would be poor. At a convex face corner of 40 to 110 degrees the
  /// face mesher usually keeps the ear (the corner and its two boundary neighbours) as a triangle;
  /// when one side's first segment is much shorter than the other's (a short CAD edge of one
  /// segment next to a regular one) that triangle has an angle below 30 degrees. The longer side's
  /// edge is discretised again with its segments growing from 1.3 x the short one at the corner
  /// (slope kCornerSlope, so only its first segment or two change). Short segments below
  /// kCornerMinRatio sizes (tiny features) are left alone. Returns true when some edge changed.
  bool matchCornerSegments(std::vector<std::vector<double>>& ts, const std::vector<char>& degen) {
    const int nf = model.numFaces(), ne = model.numEdges();
    struct Want {
      Vec3 v;
      double s;
    };
    std::vector<std::vector<std::vector<std::pair<int, Want>>>> per(nf);
    parallelFor(nf, threads, [&](int f) {
      progress.poll();
      std::vector<std::vector<LoopNode>> loops;
      try {
        loops = loopNodes(f, ts, degen);
      } catch (const Cancelled&) {
        throw;
      } catch (...) {
        return;
      }
      std::vector<std::pair<int, Want>> found;
      for (const auto& L : loops) {
        const int n = (int)L.size();
        if (n < 3) continue;
        for (int i = 0; i < n; ++i) {
          const LoopNode &P = L[(i + n - 1) % n], &V = L[i], &N = L[(i + 1) % n];
          if (P.edge == V.edge || P.edge < 0 || V.edge < 0) continue;  // not a corner
          const double la = dist(P.xyz, V.xyz), lb = dist(V.xyz, N.xyz);
          if (!(la > 0 && lb > 0) || std::max(la, lb) < 1.5 * std::min(la, lb)) continue;
          // a tiny feature (far below the size) would pull a long run of small segments: left alone
          if (std::min(la, lb) < kCornerMinRatio * field.size(V.xyz)) continue;
          const Vec3 u = (1.0 / la) * (P.xyz - V.xyz), w = (1.0 / lb) * (N.xyz - V.xyz);
          if (!(norm2(V.inward) > 0.5) || dot(u + w, V.inward) <= 0) continue;  // reflex corner
          const double ang = std::acos(std::clamp(dot(u, w), -1.0, 1.0)) * 180.0 / kPi;
          if (ang < 40.0 || ang > 110.0) continue;
          // the ear's smallest angle
          const double lc = dist(P.xyz, N.xyz);
          const double ears = std::min({std::asin(std::min(1.0, std::sin(ang * kPi / 180) * la / lc)),
                                        std::asin(std::min(1.0, std::sin(ang * kPi / 180) * lb / lc))}) * 180.0 / kPi;
          if (ears >= 30.0) continue;
          const int longEdge = la > lb ? P.edge : V.edge;
          if (!mayRespace(longEdge, degen) || (staggered_.size() == (size_t)ne && staggered_[longEdge])) continue;
          if (ts[longEdge].size() < 3) continue;  // a single segment cannot be shortened at one end
          found.push_back({longEdge, {V.xyz, kCornerRatio * std::min(la, lb)}});
        }
      }
      per[f].push_back(std::move(found));
    });
    std::vector<std::vector<Want>> wants(ne);
    for (const auto& pf : per)
      for (const auto& fl : pf)
        for (const auto& w : fl) wants[w.first].push_back(w.second);
    int changed = 0;
    for (int e = 0; e < ne; ++e) {
      if (wants[e].empty()) continue;
      const auto& W = wants[e];
      auto spacing = [&](Vec3 x) {
        double h = field.size(x);
        for (const Want& w : W) h = std::min(h, w.s + kCornerSlope * dist(x, w.v));
        return h;
      };
      ts[e] = discretizeWith(e, spacing);
      ++changed;
    }
    if (changed) log.info("corners: " + std::to_string(changed) + " edges re-spaced at corners with a short neighbour segment");
    return changed > 0;
  }

  // ---------------------------------------------------------------- face boundaries
  // ---------------------------------------------------------------- faces with boundary layers
  bool hasBoundaryLayer(int f) const {
    if (blSpecOf.empty()) return false;
    for (const Wire& w : model.faceWires(f))
      for (const EdgeUse& u : w.uses)
        if (blSpecOf[u.edge] >= 0) return true;
    return false;
  }

  /// Hand-off relaxation: the triangles standing on the layers' top edges should be about as tall
  /// as the last row (the size jump across the front). Interior apex nodes of such triangles move,
  /// on the surface, towards the point that gives each of their front triangles a height within
  /// [1/1.3, 1.3] of its row's height, when every triangle around them stays valid and well shaped.
  void relaxHandoff(const ISurface& s, const FaceBLResult& bl, int offset, std::vector<Vec3>& xyz,
                    std::vector<Vec2>& uv, const std::vector<std::array<int, 3>>& tris,
                    std::vector<std::array<Vec2, 3>>& triUv) const {
    auto P = [&](int r) { return r >= 0 ? mesh.nodes[r] : xyz[-r - 1]; };
    auto movable = [&](int r) { return r < 0 && -r - 1 >= offset; };
    // top edges of the layer quads: (a,b) -> row height of the quad below
    std::map<std::pair<int, int>, std::pair<int, double>> quadEdges;  // key -> (uses, height)
    for (const auto& q : bl.quads)
      for (int k = 0; k < 4; ++k) {
        const int a = q[k], b = q[(k + 1) % 4];
        const double h = 0.5 * (dist(P(a), P(q[(k + 3) % 4])) + dist(P(b), P(q[(k + 2) % 4])));
        auto& e = quadEdges[{std::min(a, b), std::max(a, b)}];
        ++e.first;
        e.second = h;
      }
    std::map<int, std::vector<int>> around;  // movable node -> incident triangles
    for (size_t t = 0; t < tris.size(); ++t)
      for (int v : tris[t])
        if (movable(v)) around[v].push_back((int)t);
    auto quality = [&](int t) { return gamma3(P(tris[t][0]), P(tris[t][1]), P(tris[t][2])); };
    // the triangles standing on a top edge with a movable apex, found once (in triangle and edge
    // order, as the passes use them): the passes move nodes, never the connectivity
    struct OnFront {
      int t, k;
      double hl;
    };
    std::vector<OnFront> onFront;
    for (size_t t = 0; t < tris.size(); ++t) {
      const auto& T = tris[t];
      for (int k = 0; k < 3; ++k) {
        const int a = T[k], b = T[(k + 1) % 3], c = T[(k + 2) % 3];
        auto it = quadEdges.find({std::min(a, b), std::max(a, b)});
        if (it == quadEdges.end() || it->second.first != 1 || !movable(c)) continue;
        onFront.push_back({(int)t, k, it->second.second});
      }
    }
    for (int pass = 0; pass < 3; ++pass) {
      std::map<int, std::pair<Vec3, int>> wish;  // apex -> sum of wished positions, count
      for (const OnFront& f : onFront) {
        const auto& T = tris[f.t];
        const int k = f.k;
        const int a = T[k], b = T[(k + 1) % 3], c = T[(k + 2) % 3];
        const double hl = f.hl;
        const Vec3 A = P(a), B = P(b), C = P(c);
        const double L = dist(A, B);
        if (!(L > 0) || !(hl > 0)) continue;
        const Vec3 e = (1.0 / L) * (B - A);
        const Vec3 m = 0.5 * (A + B);
        Vec3 up = (C - m) - dot(C - m, e) * e;  // towards the apex, across the edge
        const double ht = norm(up);
        if (!(ht > 0)) continue;
        up = (1.0 / ht) * up;
        const double target = std::clamp(ht, hl / 1.25, 1.25 * hl);
        if (std::fabs(target - ht) < 1e-3 * hl) continue;
        // keep the apex's position along the edge; change only its height
        const Vec3 want = C + (target - ht) * up;
        auto& w = wish[c];
        w.first += want;
        ++w.second;
      }
      if (wish.empty()) return;
      int moved = 0;
      for (const auto& kv : wish) {
        const int v = kv.first;
        const int i = -v - 1;
        const Vec3 target = (1.0 / kv.second.second) * kv.second.first;
        const auto& inc = around[v];
        double before = 1;
        for (int t : inc) before = std::min(before, quality(t));
        const Vec3 x0 = xyz[i];
        const Vec2 u0 = uv[i];
        for (double step : {1.0, 0.5, 0.25}) {
          // one Newton step on the surface towards x0 + step * (target - x0)
          Vec3 p, du, dv;
          s.d1(u0, p, du, dv);
          const Vec3 d = step * (target - x0);
          const double a11 = dot(du, du), a12 = dot(du, dv), a22 = dot(dv, dv);
          const double det = a11 * a22 - a12 * a12;
          if (!(std::fabs(det) > 0)) break;
          const double r1 = dot(du, d), r2 = dot(dv, d);
          const Vec2 nu{u0.x + (a22 * r1 - a12 * r2) / det, u0.y + (a11 * r2 - a12 * r1) / det};
          xyz[i] = s.eval(nu);
          uv[i] = nu;
          bool ok = true;
          double after = 1;
          for (int t : inc) {
            std::array<Vec2, 3> tu = triUv[t];
            for (int k = 0; k < 3; ++k)
              if (tris[t][k] == v) tu[k] = tu[k] + (nu - u0);
            if (area2(tu[0], tu[1], tu[2]) <= 0) {
              ok = false;
              break;
            }
            const Vec3 A = P(tris[t][0]), B = P(tris[t][1]), C = P(tris[t][2]);
            Vec3 q, su, sv;
            s.d1((1.0 / 3) * (tu[0] + tu[1] + tu[2]), q, su, sv);
            if (dot(cross(B - A, C - A), cross(su, sv)) <= 0) {
              ok = false;
              break;
            }
            after = std::min(after, quality(t));
          }
          if (ok && after >= std::min(before, 0.5)) {  // never below 0.5 unless it was already
            for (int t : inc)
              for (int k = 0; k < 3; ++k)
                if (tris[t][k] == v) triUv[t][k] = triUv[t][k] + (nu - u0);
            ++moved;
            break;
          }
          xyz[i] = x0;
          uv[i] = u0;
        }
      }
      if (!moved) return;
    }
  }

  /// Meshes face f with its boundary layers. When the face cannot be meshed with them (the rows
  /// leave a front the triangulation refuses, or no element), it is meshed without them and the
  /// reason goes to the report's warnings: a layer must never take its face down.
  FaceMeshResult meshFaceWithLayers(int f, const ISurface& s, const FaceBoundary& fb, FaceMeshOptions fo) {
    const FaceMeshOptions plain = fo;
    FaceMeshResult r;
    try {
      r = meshFaceWithLayersOnly(f, s, fb, fo);
    } catch (const Cancelled&) {
      throw;
    } catch (const std::exception& e) {
      r.ok = false;
      r.error = e.what();
    }
    {
      std::lock_guard<std::mutex> g(blMu_);
      blDropped.erase(f);
    }
    if (r.ok) return r;
    FaceMeshResult without = meshFace(s, fb, field, plain, &progress);
    if (!without.ok) {
      r.error += " (and without its boundary layer: " + without.error + ")";
      return r;
    }
    without.quadLayer.assign(without.quads.size(), 0);
    without.triLayer.assign(without.tris.size(), 0);
    std::lock_guard<std::mutex> g(blMu_);
    blDropped[f] = r.error;
    for (size_t k = 0; k < blStats.size(); ++k) blEmpty.erase({f, (int)k});
    return without;
  }

  FaceMeshResult meshFaceWithLayersOnly(int f, const ISurface& s, const FaceBoundary& fb, FaceMeshOptions fo) {
    std::vector<std::vector<LoopPoint>> loops;
    for (const auto& L : fb.loops) {
      std::vector<LoopPoint> lp;
      for (const BoundaryVertex& b : L) lp.push_back({b.uv, b.xyz, b.node, b.edge, b.pole});
      loops.push_back(std::move(lp));
    }
    DomainGuard guard(fb.trueLoops);
    FaceBLResult bl = growFaceLayers(s, model.faceReversed(f), loops, fb.trueLoops, guard, blSpecOf, blLaws, blEnds);
    FaceBoundary inner;
    inner.trueLoops = fb.trueLoops;
    for (const auto& L : bl.loops) {
      std::vector<BoundaryVertex> bv;
      for (const LoopPoint& q : L) {
        BoundaryVertex b;
        b.uv = q.uv;
        b.xyz = q.xyz;
        b.node = q.node;
        b.pole = q.pole;
        b.edge = q.edge;
        bv.push_back(b);
      }
      if (bv.size() >= 3) inner.loops.push_back(std::move(bv));
    }
    // hand-off: the isotropic mesh starts from the front with its spacing, graded away
    SizeField overlay(field.hmax(), p.grading);
    for (const auto& fs : bl.frontSizes) overlay.addSource(fs.first, std::max(fs.second, p.minSize));
    overlay.build();
    fo.overlay = &overlay;
    fo.localNodeOffset = (int)bl.nodes.size();
    // the sliver post-pass would undo the hand-off (it splits and collapses next to the front);
    // relaxHandoff below looks after the triangles on the front instead
    fo.sliverPass = false;
    FaceMeshResult r;
    if (inner.loops.empty()) {
      r.ok = true;  // the layers cover the whole face
    } else {
      r = meshFace(s, inner, field, fo, &progress);
      if (!r.ok) return r;
    }
    std::vector<Vec3> xyz;
    std::vector<Vec2> uv;
    for (const BLNode& n : bl.nodes) {
      xyz.push_back(n.xyz);
      uv.push_back(n.uv);
    }
    xyz.insert(xyz.end(), r.newXyz.begin(), r.newXyz.end());
    uv.insert(uv.end(), r.newUv.begin(), r.newUv.end());
    if (!inner.loops.empty()) relaxHandoff(s, bl, (int)bl.nodes.size(), xyz, uv, r.tris, r.triUv);
    r.newXyz = std::move(xyz);
    r.newUv = std::move(uv);
    r.quadLayer.assign(r.quads.size(), 0);
    r.triLayer.assign(r.tris.size(), 0);
    r.quads.insert(r.quads.end(), bl.quads.begin(), bl.quads.end());
    r.quadUv.insert(r.quadUv.end(), bl.quadUv.begin(), bl.quadUv.end());
    for (int sp : bl.quadSpec) r.quadLayer.push_back(sp + 1);
    for (size_t k = 0; k < bl.tris.size(); ++k) {
      r.tris.push_back(bl.tris[k]);
      r.triUv.push_back(bl.triUv[k]);
      r.triLayer.push_back(bl.triSpec[k] + 1);
    }
    if (r.tris.empty() && r.quads.empty()) {
      r.ok = false;
      r.error = "no element was produced";
      return r;
    }
    {
      std::lock_guard<std::mutex> g(blMu_);
      for (size_t k = 0; k < bl.stats.size(); ++k) {
        auto& a = blStats[k];
        const auto& b = bl.stats[k];
        a.columns += b.columns;
        a.fullColumns += b.fullColumns;
        a.minLayers = std::min(a.minLayers, b.minLayers);
        a.maxLayers = std::max(a.maxLayers, b.maxLayers);
        a.stopBoundary += b.stopBoundary;
        a.stopCollision += b.stopCollision;
        a.stopInvalid += b.stopInvalid;
        a.stopAspect += b.stopAspect;
        a.stopEnd += b.stopEnd;
        a.fans += b.fans;
        a.merges += b.merges;
        a.elements += b.elements;
        if (b.columns > 0 && b.elements == 0)
          blEmpty[{f, (int)k}] = b;
        else
          blEmpty.erase({f, (int)k});
      }
    }
    return r;
  }

  std::mutex blMu_;

  // ---------------------------------------------------------------- faces
  /// The first edge of face f that could not be discretised, or -1.
  int failedEdgeOf(int f) const {
    if (edgeError_.empty()) return -1;
    for (const Wire& w : model.faceWires(f))
      for (const EdgeUse& u : w.uses)
        if (!edgeError_[u.edge].empty()) return u.edge;
    return -1;
  }

  /// Once per run: the faces whose pcurves stray from their 3D edges (tolerant CAD); the worst
  /// named.
  void logStrayPcurves() {
    if (strayLogged_) return;
    strayLogged_ = true;
    int faces = 0, uses = 0, worstFace = -1, worstEdge = -1;
    double worst = 0;
    for (int f = 0; f < (int)strayPcurves_.size(); ++f) {
      if (strayPcurves_[f].empty()) continue;
      ++faces;
      for (const auto& t : strayPcurves_[f]) {
        ++uses;
        if (t.second > worst) {
          worst = t.second;
          worstFace = f;
          worstEdge = t.first;
        }
      }
    }
    if (!faces) return;
    log.info("pcurves off their 3D edges: " + std::to_string(uses) + " edge use" + (uses == 1 ? "" : "s") + " on " +
             std::to_string(faces) + " face" + (faces == 1 ? "" : "s") +
             " (worst: Edge" + std::to_string(worstEdge + 1) +
             " on Face" + std::to_string(worstFace + 1) + ", " + fmt(worst) + " off, edge tolerance " +
             fmt(model.edgeTolerance(worstEdge)) + ")");
  }

  void meshFaces() {
    Timer tm;
    const int nf = model.numFaces();
    strayPcurves_.assign(nf, {});
    std::vector<FaceMeshResult> results(nf);
    report.faces.assign(nf, FaceReport());
    std::atomic<int> done{0};
    // biggest faces first for load balance: estimate by boundary node count
    std::vector<int> order(nf);
    std::iota(order.begin(), order.end(), 0);
    std::vector<size_t> weight(nf, 0);
    for (int f = 0; f < nf; ++f)
      for (const Wire& w : model.faceWires(f))
        for (const EdgeUse& u : w.uses) weight[f] += edges[u.edge].t.size();
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return weight[a] > weight[b]; });
    FaceMeshOptions fo;
    fo.optimizePasses = p.optimizePasses;
    fo.quads = p.quads;
    fo.maxDeviation = p.maxDeviation * p.size;
    // a triangle whose edges subtend the curvature angle t (radians) on a sphere has its centroid
    // t/6 of its edge length off the surface: allow no more (10 degrees: 0.029)
    fo.maxDeviationRatio = p.curvatureAngle > 0 ? p.curvatureAngle * kPi / 180.0 / 6.0 : 0.0;
    // A min-size the user set is a floor for the refinement too: it splits no edge shorter than
    // twice it. Where the curvature bound asks for less, the triangles stay at the min-size and
    // the report says so; splitting on made needles instead (docs/tuning/pipeline.md). The
    // default min-size (size / 1000 with a curvature angle) is the size field's
    // floor, not the user's: below it the refinement still splits down to a quarter of it.
    fo.minSplitLength = minSizeGiven ? 2.0 * p.minSize : 0.5 * p.minSize;
    fo.minSizeReach = minSizeGiven ? minSizeReach() : 0.0;
    fo.reportOffSurface = p.nearestFaceCheck || p.nearestFaceBudget > 0;
    const std::vector<char> reused = reusePreviousRound(results);
    parallelFor(nf, threads, [&](int f) {
      if (reused[f]) return;
      progress.poll();
      Timer ft;
      FaceReport& fr = report.faces[f];
      fr.face = f + 1;
      try {
        auto s = model.makeSurface(f);
        fr.surface = toString(s->kind());
        FaceBoundary fb;
        std::string why;
        const int bad = failedEdgeOf(f);
        if (bad >= 0) {
          fr.ok = false;
          const std::string name = "Edge" + std::to_string(bad + 1), &reason = edgeError_[bad];
          fr.error = "its " + name + " could not be discretised: " +
                     (reason.rfind(name + ": ", 0) == 0 ? reason.substr(name.size() + 2) : reason);
        } else if (!buildFaceBoundary(model, edges, mesh, field, f, *s, fb, why)) {
          fr.ok = false;
          fr.error = why;
        } else if (hasBoundaryLayer(f)) {
          strayPcurves_[f] = fb.strayPcurves;
          results[f] = meshFaceWithLayers(f, *s, fb, fo);
          fr.ok = results[f].ok;
          fr.error = results[f].error;
        } else {
          strayPcurves_[f] = fb.strayPcurves;
          FaceMeshOptions zo;  // with the nearest-face check's zones on this face
          const bool zoned = f < (int)zones_.size() && !zones_[f].empty();
          if (zoned) {
            zo = fo;
            zo.deviationZones = zones_[f];
          }
          results[f] = meshFace(*s, fb, field, zoned ? zo : fo, &progress);
          fr.ok = results[f].ok;
          fr.error = results[f].error;
          fr.rejectedPoints = results[f].rejectedPoints;
        }
      } catch (const Cancelled&) {
        throw;
      } catch (const std::exception& e) {
        fr.ok = false;
        fr.error = e.what();
      } catch (...) {
        fr.ok = false;
        fr.error = "geometry kernel exception";
      }
      fr.seconds = ft.seconds();
      const int k = ++done;
      progress.report(0.15 + 0.8 * k / std::max(nf, 1), "faces");
    }, &order);
    stage("faces", tm.seconds());
    logStrayPcurves();
    // assemble in face order (deterministic)
    Timer ta;
    for (int f = 0; f < nf; ++f) {
      FaceMeshResult& r = results[f];
      FaceReport& fr = report.faces[f];
      if (!fr.ok) {
        log.warn("Face" + std::to_string(f + 1) + " failed: " + fr.error);
        continue;
      }
      const int base = (int)mesh.nodes.size();
      for (size_t k = 0; k < r.newXyz.size(); ++k) mesh.addNode(r.newXyz[k], NodeKind::Face, f + 1, r.newUv[k]);
      triDeviation.resize(mesh.triangles.size() + r.tris.size(), 0.0);
      for (const auto& od : r.offSurface) {
        const int t = (int)mesh.triangles.size() + od.first;
        triDeviation[t] = od.second;
        // deeper than 4.5 % of the mesh size; faces with boundary layers keep their rows as they are
        if (r.triLayer.empty() && od.second > kOffSurfaceCandidate * std::min(p.size, p.maxSize))
          offSurface.push_back({t, od.second});
      }
      const bool rev = model.faceReversed(f);
      for (size_t k = 0; k < r.tris.size(); ++k) {
        auto t = r.tris[k];
        auto uv = r.triUv[k];
        for (int& v : t)
          if (v < 0) v = base + (-v - 1);
        if (rev) {
          std::swap(t[1], t[2]);
          std::swap(uv[1], uv[2]);
        }
        mesh.triangles.push_back(t);
        mesh.triangleFace.push_back(f + 1);
        mesh.triangleLayer.push_back(k < r.triLayer.size() ? r.triLayer[k] : 0);
        triUv.push_back(uv);
      }
      for (size_t k = 0; k < r.quads.size(); ++k) {
        auto q = r.quads[k];
        auto uv = r.quadUv[k];
        for (int& v : q)
          if (v < 0) v = base + (-v - 1);
        if (rev) {
          std::swap(q[1], q[3]);
          std::swap(uv[1], uv[3]);
        }
        mesh.quads.push_back(q);
        mesh.quadFace.push_back(f + 1);
        mesh.quadLayer.push_back(k < r.quadLayer.size() ? r.quadLayer[k] : 0);
        quadUv.push_back(uv);
      }
      fr.triangles = (int)r.tris.size();
      fr.quads = (int)r.quads.size();
      fr.nodes = (int)r.newXyz.size();
      fr.overDeviation = (int)r.deviationMisses.size();
      fr.crestSegments = r.crestSegments;
      fr.crestRowSegments = r.crestRowSegments;
      fr.overDeviationWorst = 0;
      fr.overDeviationRadius = std::numeric_limits<double>::infinity();
      fr.overDeviationResolvable = 0;
      const double reach = minSizeReach();
      for (const FaceMeshResult::DeviationMiss& m : r.deviationMisses) {
        if (reach > 0 && m.radius >= reach) ++fr.overDeviationResolvable;
        const double x = m.deviation / m.allowed;
        if (x > fr.overDeviationWorst) {
          fr.overDeviationWorst = x;
          fr.overDeviationAt[0] = m.at.x;
          fr.overDeviationAt[1] = m.at.y;
          fr.overDeviationAt[2] = m.at.z;
        }
        fr.overDeviationRadius = std::min(fr.overDeviationRadius, m.radius);
      }
    }
    stage("assemble", ta.seconds());
    if (fo.reportOffSurface && blLaws.empty()) {  // kept for the next round of the nearest-face check
      auto prev = std::make_unique<PreviousRound>();
      prev->points.assign(nf, {});
      std::vector<int> seen(mesh.nodes.size(), -1);
      for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const int f = mesh.triangleFace[t] - 1;
        for (int v : mesh.triangles[t])
          if (seen[v] != f) {
            seen[v] = f;
            prev->points[f].push_back(mesh.nodes[v]);
          }
      }
      prev->results = std::move(results);
      prev->reports = report.faces;
      prev->edges = edges;
      previous_ = std::move(prev);
    }
  }

  /// Fills results[f] with the previous round's mesh of every face that can keep it (node
  /// references renumbered); returns which. A face keeps its mesh when each of its edges has the
  /// same nodes as before and no source added since lies within its reach of a node of the face
  /// (h + slope * d >= hmax beyond it: the field there is what it was).
  std::vector<char> reusePreviousRound(std::vector<FaceMeshResult>& results) {
    const int nf = model.numFaces();
    std::vector<char> reused(nf, 0);
    if (!previous_) return reused;
    std::unique_ptr<PreviousRound> prev = std::move(previous_);
    const int ne = model.numEdges();
    std::vector<char> edgeSame(ne, 0);
    for (int e = 0; e < ne && (size_t)e < prev->edges.size(); ++e)
      edgeSame[e] = prev->edges[e].t == edges[e].t && prev->edges[e].degenerate == edges[e].degenerate &&
                    prev->edges[e].nodes.size() == edges[e].nodes.size();
    const double hmax = field.hmax();
    // the field is queried on the surface between the nodes too: one size of margin
    std::vector<Vec3> at;
    std::vector<double> reach;
    for (const SizeSource& src : roundSources_) {
      at.push_back(src.p);
      reach.push_back((hmax - src.h) / kNearestFaceSlope + hmax);
    }
    const SourceReach near(std::move(at), std::move(reach));
    int kept = 0;
    for (int f = 0; f < nf; ++f) {
      bool ok = !prev->points[f].empty() || !prev->reports[f].ok;
      if (f < (int)zonesAdded_.size() && zonesAdded_[f]) ok = false;
      for (const Wire& w : model.faceWires(f))
        for (const EdgeUse& u : w.uses) ok = ok && edgeSame[same.edgeRep[u.edge]];
      if (!ok) continue;
      for (const Vec3& x : prev->points[f]) {
        ok = !near.reaches(x, x);
        if (!ok) break;
      }
      if (!ok) continue;
      // boundary nodes: old id -> new id through the face's edges
      std::unordered_map<int, int> to;
      for (const Wire& w : model.faceWires(f))
        for (const EdgeUse& u : w.uses) {
          const int e = same.edgeRep[u.edge];
          for (size_t i = 0; i < edges[e].nodes.size(); ++i) to[prev->edges[e].nodes[i]] = edges[e].nodes[i];
        }
      FaceMeshResult r = std::move(prev->results[f]);
      auto renumber = [&](int& v) {
        if (v < 0) return true;
        auto it = to.find(v);
        if (it == to.end()) return false;
        v = it->second;
        return true;
      };
      for (auto& t : r.tris)
        for (int& v : t) ok = ok && renumber(v);
      for (auto& q : r.quads)
        for (int& v : q) ok = ok && renumber(v);
      if (!ok) continue;  // a node of another edge (cannot happen with unchanged edges): mesh anew
      results[f] = std::move(r);
      report.faces[f] = prev->reports[f];
      reused[f] = 1;
      ++kept;
    }
    log.info("nearest-face round: " + std::to_string(nf - kept) + " of " + std::to_string(nf) + " faces meshed again");
    report.nearestFaceRemeshed.push_back(nf - kept);
    return reused;
  }

  // ---------------------------------------------------------------- nearest-face check
  /// Size sources for the triangles whose centroid is nearer another face than their own surface;
  /// records how many there are.
  NearestFaceResult nearestFaceCheck() {
    Timer tm;
    // the other face's CAD distance: projection on its surface from the (u,v) of the nearest
    // point of its mesh
    std::vector<std::unique_ptr<ISurface>> surf(model.numFaces());
    auto faceDistance = [&](Vec3 c, int tri, Vec3 q, Vec3* foot) {
      const auto& T = mesh.triangles[tri];
      const Vec3 &a = mesh.nodes[T[0]], &b = mesh.nodes[T[1]], &d = mesh.nodes[T[2]];
      const double meshDist = dist(c, q);
      const int f = mesh.triangleFace[tri] - 1;
      try {
        if (!surf[f]) surf[f] = model.makeSurface(f);
        // barycentric coordinates of q
        const Vec3 n = cross(b - a, d - a);
        const double n2 = norm2(n);
        if (!(n2 > 0)) return meshDist;
        const double wb = dot(cross(q - a, d - a), n) / n2, wd = dot(cross(b - a, q - a), n) / n2;
        const auto& uv = triUv[tri];
        Vec2 s = (1 - wb - wd) * uv[0] + wb * uv[1] + wd * uv[2];
        Vec3 x;
        if (!surf[f]->project(c, s, &x)) return meshDist;
        *foot = x;
        return dist(c, x);
      } catch (...) {
        return meshDist;
      }
    };
    const NearestFaceResult r = nearestFaceSources(mesh, offSurface, p.minSize, &triDeviation, faceDistance);
    report.nearestFaceFlagged.push_back(r.flagged);
    if (r.flagged)
      log.info("nearest-face check: " + std::to_string(r.flagged) +
               " triangles lie nearer another face than their own" +
               (r.sources.empty() ? " (already at min-size)" : ": refined"));
    stage("nearest_face_check", tm.seconds());
    return r;
  }
  /// Local deviation bounds for the flagged triangles (NearestFaceResult::found): a ball around
  /// each on its own face, in which centroids may lie off their surface at most kZoneFraction of
  /// their distance to the other face's tangent plane (never less than a candidate's deviation).
  /// Returns, per flagged triangle, whether it got a zone: one whose centroid already lies in a
  /// zone of its face at least as strict was not mended by it, and gets none.
  std::vector<char> addDeviationZones(const NearestFaceResult& r) {
    const int nf = model.numFaces();
    zones_.resize(nf);
    zonesAdded_.assign(nf, 0);
    std::vector<char> added(r.found.size(), 0);
    std::vector<size_t> before(nf);
    for (int f = 0; f < nf; ++f) before[f] = zones_[f].size();
    for (size_t k = 0; k < r.found.size(); ++k) {
      const int t = (int)r.found[k][0];
      const int f = mesh.triangleFace[t] - 1;
      const auto& T = mesh.triangles[t];
      const Vec3 c = (1.0 / 3) * (mesh.nodes[T[0]] + mesh.nodes[T[1]] + mesh.nodes[T[2]]);
      DeviationZone z;
      z.center = c;
      for (int v : T) z.radius = std::max(z.radius, dist(c, mesh.nodes[v]));
      z.fraction = kZoneFraction;
      z.floor = kOffSurfaceCandidate * std::min(p.size, p.maxSize);
      if (dist(c, r.otherFoot[k]) > 0) {
        z.otherPoint = r.otherFoot[k];
        z.otherNormal = normalized(c - r.otherFoot[k]);
      } else {
        z.allowed = z.fraction * r.found[k][2];
      }
      bool known = false;
      for (size_t i = 0; i < before[f]; ++i) known = known || zones_[f][i].bound(c) <= z.bound(c);
      if (known) continue;
      zones_[f].push_back(z);
      zonesAdded_[f] = 1;
      added[k] = 1;
    }
    return added;
  }
  /// What a meshing round produces (edges, faces, their report entries), to go back to it.
  struct MeshState {
    SurfaceMesh mesh;
    SizeField field;
    std::vector<EdgeMesh> edges;
    std::vector<int> vertexNode;
    std::vector<std::array<Vec2, 3>> triUv;
    std::vector<std::array<Vec2, 4>> quadUv;
    std::vector<std::array<double, 2>> segmentT;
    std::vector<FaceReport> faces;
    std::vector<FaceBLResult::SpecStats> blStats;
    std::map<std::pair<int, int>, FaceBLResult::SpecStats> blEmpty;
    std::map<int, std::string> blDropped;
  };
  MeshState saveState() const {
    return {mesh, field, edges, vertexNode, triUv, quadUv, segmentT, report.faces, blStats, blEmpty, blDropped};
  }
  void restoreState(MeshState&& st) {
    mesh = std::move(st.mesh);
    field = std::move(st.field);
    edges = std::move(st.edges);
    vertexNode = std::move(st.vertexNode);
    triUv = std::move(st.triUv);
    quadUv = std::move(st.quadUv);
    segmentT = std::move(st.segmentT);
    report.faces = std::move(st.faces);
    blStats = std::move(st.blStats);
    blEmpty = std::move(st.blEmpty);
    blDropped = std::move(st.blDropped);
    offSurface.clear();
    triDeviation.clear();
  }

  /// Back to the state before the edges were discretised (the size field is set by the caller).
  void resetMesh() {
    SurfaceMesh m;
    m.numFaces = mesh.numFaces;
    m.numEdges = mesh.numEdges;
    m.numVertices = mesh.numVertices;
    mesh = std::move(m);
    edges.clear();
    vertexNode.clear();
    triUv.clear();
    quadUv.clear();
    segmentT.clear();
    offSurface.clear();
    triDeviation.clear();
    blStats.assign(blStats.size(), FaceBLResult::SpecStats());
  }

  void secondOrder() {
    Timer tm;
    const HighOrderStats st = makeSecondOrder(mesh, model, triUv, quadUv, segmentT);
    report.midNodes = st.midNodes;
    report.straightenedMidNodes = st.straightened;
    report.minScaledJacobian = st.minJacobianRatio;
    if (st.straightened)
      report.warnings.push_back(std::to_string(st.straightened) + " mid-nodes of " + std::to_string(st.invalidElements) +
                                " curved elements were put back on the chord to keep the Jacobian positive");
    stage("second_order", tm.seconds());
  }

  void finish() {
    Timer tq;
    report.nodes = (int)mesh.nodes.size();
    report.triangles = (int)mesh.triangles.size();
    report.quads = (int)mesh.quads.size();
    report.order = mesh.order;
    report.sizeSources = field.numSources();
    report.quality = summarizeQuality(mesh, [this](Vec3 x) { return field.size(x); });
    std::vector<std::string> failed;
    for (const FaceReport& fr : report.faces)
      if (!fr.ok) failed.push_back("Face" + std::to_string(fr.face) + ": " + fr.error);
    if (failed.empty()) {
      report.status = RunStatus::Ok;
      report.message = "meshed " + std::to_string(report.faces.size()) + " faces";
    } else {
      report.status = failed.size() == report.faces.size() ? RunStatus::Failed : RunStatus::Degraded;
      std::string m = std::to_string(failed.size()) + " of " + std::to_string(report.faces.size()) + " faces failed: ";
      for (size_t i = 0; i < failed.size() && i < 5; ++i) m += (i ? "; " : "") + failed[i];
      if (failed.size() > 5) m += "; ...";
      report.message = m;
    }
    for (size_t k = 0; k < blStats.size(); ++k) {
      BoundaryLayerReport b;
      const auto& st = blStats[k];
      b.spec = (int)k + 1;
      for (int e = 0; e < model.numEdges(); ++e)
        if (blSpecOf[e] == (int)k) b.edges.push_back(e + 1);
      b.layersRequested = blLaws[k].layers;
      b.columns = st.columns;
      b.fullColumns = st.fullColumns;
      b.minLayers = st.columns ? st.minLayers : 0;
      b.maxLayers = st.maxLayers;
      b.stopBoundary = st.stopBoundary;
      b.stopCollision = st.stopCollision;
      b.stopInvalid = st.stopInvalid;
      b.stopAspect = st.stopAspect;
      b.stopEdgeEnd = st.stopEnd;
      b.fans = st.fans;
      b.merges = st.merges;
      b.elements = st.elements;
      report.boundaryLayers.push_back(b);
    }
    for (const auto& [face, why] : blDropped) {
      const std::string w = "boundary layers dropped on Face" + std::to_string(face + 1) +
                            ": the face could not be meshed with them (" + why + "); it was meshed without them";
      report.warnings.push_back(w);
      log.warn(w);
    }
    // faces where a layer was asked for and no element grew (no two neighbouring columns share a row)
    for (const auto& [key, st] : blEmpty) {
      std::string edgesOf;
      for (int e : report.boundaryLayers[key.second].edges)  // 1-based, listed just above
        edgesOf += (edgesOf.empty() ? "Edge" : ", Edge") + std::to_string(e);
      std::string why;
      auto add = [&](int n, const char* what) {
        if (n > 0) why += (why.empty() ? "" : ", ") + std::to_string(n) + " " + what;
      };
      add(st.stopBoundary, "at the face boundary");
      add(st.stopCollision, "by a collision");
      add(st.stopInvalid, "folding");
      add(st.stopAspect, "at the aspect limit");
      add(st.stopEnd, "at an edge end or a corner");
      const std::string w = "boundary layer " + std::to_string(key.second + 1) + " (" + edgesOf +
                            ") got no element on Face" + std::to_string(key.first + 1) + " (" +
                            std::to_string(st.columns) + " columns" + (why.empty() ? "" : "; stopped: " + why) + ")";
      report.warnings.push_back(w);
      log.warn(w);
    }
    warnOverDeviation();
    stage("quality", tq.seconds());
  }

  /// The smallest radius of curvature that triangles of the min-size can follow at the curvature
  /// angle (0: no curvature angle).
  double minSizeReach() const { return p.curvatureAngle > 0 ? p.minSize / (p.curvatureAngle * kPi / 180.0) : 0.0; }

  /// One warning for the triangles left beyond the deviation bounds: per face (the five with the
  /// most) how many, the worst, where, and the surface's radius of curvature there; and, where
  /// that radius is below what the min-size can follow at the curvature angle, that the min-size
  /// is what holds the triangles back.
  void warnOverDeviation() {
    std::vector<const FaceReport*> over;
    int total = 0, resolvable = 0;
    double radius = std::numeric_limits<double>::infinity();
    for (const FaceReport& fr : report.faces)
      if (fr.ok && fr.overDeviation > 0) {
        over.push_back(&fr);
        total += fr.overDeviation;
        resolvable += fr.overDeviationResolvable;
        radius = std::min(radius, fr.overDeviationRadius);
      }
    if (over.empty()) return;
    std::stable_sort(over.begin(), over.end(), [](const FaceReport* a, const FaceReport* b) { return a->overDeviation > b->overDeviation; });
    auto num = [](double x, int digits = 3) {
      char b[32];
      std::snprintf(b, sizeof b, "%.*g", digits, x);
      return std::string(b);
    };
    std::string w = std::to_string(total) + " triangle" + (total == 1 ? "" : "s") + " on " + std::to_string(over.size()) +
                    " face" + (over.size() == 1 ? "" : "s") + " beyond the deviation bound after refinement: ";
    // the stray pcurves of a face (largest offset), which bound what its triangles can meet
    auto stray = [&](int face) {
      double off = 0;
      if (face - 1 < (int)strayPcurves_.size())
        for (const auto& t : strayPcurves_[face - 1]) off = std::max(off, t.second);
      return off;
    };
    bool strays = false;
    for (size_t i = 0; i < over.size() && i < 5; ++i) {
      const FaceReport& fr = *over[i];
      w += (i ? "; Face" : "Face") + std::to_string(fr.face) + " " + std::to_string(fr.overDeviation) + " (worst " +
           num(fr.overDeviationWorst) + "x its bound at (" + num(fr.overDeviationAt[0], 6) + ", " + num(fr.overDeviationAt[1], 6) +
           ", " + num(fr.overDeviationAt[2], 6) + "), surface radius down to " + num(fr.overDeviationRadius);
      const double off = stray(fr.face);
      if (off > 0) {
        w += ", pcurves up to " + num(off) + " off its edges";
        strays = true;
      }
      w += ")";
    }
    if (over.size() > 5) w += "; ...";
    if (strays)
      w += ". Where a face's pcurves stray from its edges (tolerant CAD), no node goes between the two (OpenCASCADE's "
           "face, and FreeCAD's FEM node lookup, end at the pcurves), so triangles spanning that gap cannot meet a "
           "bound below it";
    const double reach = minSizeReach();
    if (reach > 0 && radius < reach)
      w += ". " + (resolvable == 0 ? "All " + std::to_string(total) : std::to_string(total - resolvable) + " of them") +
           " lie where the surface's radius of curvature is below min-size / curvature angle (" + num(reach) +
           "): the min-size (" + num(p.minSize) +
           ") keeps the triangles there too large to follow it; a smaller min-size lets them, unless the radius "
           "shrinks towards a point";
    report.warnings.push_back(w);
    log.warn(w);
  }
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
  Impl& d = *d_;
  Timer total;
  d.resolveParams();
  d.findCoincidentTopology();
  d.progress.report(0.0, "size field");
  d.buildSizeField();
  if (d.p.proximity > 0) d.addProximitySources();
  d.planBoundaryLayers();
  // the field so far; the nearest-face check adds its sources to it and the mesh is redone. By
  // default (no --nearest-face-check) the refined mesh is kept only within the triangle budget.
  const bool force = d.p.nearestFaceCheck, check = force || d.p.nearestFaceBudget > 0;
  // the field before the rounds, under each round's field of the sources they add (cheaper than
  // a copy per round: docs/tuning/pipeline.md)
  const std::shared_ptr<const SizeField> field0 = check ? std::make_shared<const SizeField>(d.field) : nullptr;
  std::vector<SizeSource> extra;
  std::unique_ptr<Impl::MeshState> unrefined;
  double predictedGrowth = -1;  // set when a next round was predicted over the budget
  bool sameField = false;       // this round has the last round's size field: its edges too
  for (int round = 0;; ++round) {
    d.progress.report(0.05, "edges");
    {
      Timer te;
      if (sameField && d.lastEdges_.valid)
        d.reuseEdges();
      else
        d.discretizeEdges();
      sameField = false;
      d.stage("edges", te.seconds());
    }
    {
      size_t most = 0;
      int mostEdge = -1;
      for (size_t e = 0; e < d.edges.size(); ++e)
        if (d.edges[e].nodes.size() > most + 1) {
          most = d.edges[e].nodes.size() - 1;
          mostEdge = (int)e;
        }
      d.log.info("edges discretised: " + std::to_string(d.mesh.segments.size()) + " segments, " +
                 std::to_string(d.field.numSources()) + " size sources" +
                 (mostEdge >= 0 ? ", most on Edge" + std::to_string(mostEdge + 1) + " (" + std::to_string(most) + ")" : ""));
    }
    d.progress.report(0.15, "faces");
    d.progress.setPointBudget(d.p.maxElements / 2);  // a triangle mesh has about half as many points
    d.meshFaces();
    if (!check) break;
    const NearestFaceResult nfr = d.nearestFaceCheck();
    if (round == 0 && !force && nfr.flagged) unrefined = std::make_unique<Impl::MeshState>(d.saveState());
    if (!nfr.flagged || round == kNearestFaceRounds) break;
    // first a local bound on the flagged triangles' faces (refined in place, the size field and
    // the edges unchanged); the triangles such a bound did not mend get size sources
    std::vector<SizeSource> src;
    int zoned = 0;
    {
      const std::vector<char> zone = d.addDeviationZones(nfr);
      for (size_t k = 0; k < nfr.found.size(); ++k) {
        if (zone[k]) {
          ++zoned;
        } else if (nfr.firstSource[k] >= 0) {
          src.insert(src.end(), nfr.sources.begin() + nfr.firstSource[k], nfr.sources.begin() + nfr.firstSource[k] + 4);
        }
      }
    }
    if (src.empty() && zoned == 0) break;
    // two rounds in a row without fewer flagged triangles: the refinement does not converge; a
    // single such round happens on the way (measured: docs/tuning/pipeline.md)
    const auto& fl = d.report.nearestFaceFlagged;
    const size_t nr = fl.size();
    if (nr >= 3 && fl[nr - 1] >= fl[nr - 2] && fl[nr - 2] >= fl[nr - 3]) break;
    // over the budget already: no more rounds (the unrefined mesh is taken back below)
    if (unrefined && round > 0 &&
        (double)elementCount(d.mesh) > (1.0 + d.p.nearestFaceBudget) * (double)elementCount(unrefined->mesh))
      break;
    if (src.empty()) {  // zones only: the same field and edges, the zoned faces meshed again
      d.roundSources_.clear();
      d.resetMesh();
      sameField = true;
      continue;
    }
    extra.insert(extra.end(), src.begin(), src.end());
    SizeField next(field0->hmax(), field0->slope() + 1.0);
    next.setUnder(field0);
    for (const SizeSource& s : extra) next.addSource(s.p, std::max(s.h, d.p.minSize), kNearestFaceSlope);
    next.build();
    if (unrefined) {
      // elements go with 1 / h^2: the present mesh, resized to the new field, predicts the next
      // one; far over the budget, meshing again would be wasted (the unrefined mesh is kept). The
      // prediction runs high, hence the margin kPredictMargin
      double count = 0;
      for (const auto& T : d.mesh.triangles) {
        const Vec3 c = (1.0 / 3) * (d.mesh.nodes[T[0]] + d.mesh.nodes[T[1]] + d.mesh.nodes[T[2]]);
        // where the round's sources do not reach, the field is the same as now (they include
        // the last round's): no query of the millions of sources under them
        if (!(next.ownSize(c) < next.hmax())) {
          count += 1.0;
          continue;
        }
        const double r = d.field.size(c) / next.size(c);
        count += r * r;
      }
      count += (double)d.mesh.quads.size();
      const double g = count / (double)std::max<size_t>(1, elementCount(unrefined->mesh)) - 1.0;
      if (g > kPredictMargin * d.p.nearestFaceBudget) {
        predictedGrowth = g;
        break;
      }
    }
    d.roundSources_ = std::move(src);
    d.resetMesh();
    d.field = std::move(next);
  }
  d.previous_.reset();
  if (unrefined) {
    const double growth = std::max(predictedGrowth, (double)elementCount(d.mesh) /
                                                        (double)std::max<size_t>(1, elementCount(unrefined->mesh)) - 1.0);
    d.report.nearestFaceGrowth = growth;
    const int flagged0 = d.report.nearestFaceFlagged.front(), left = d.report.nearestFaceFlagged.back();
    if (left >= flagged0 && predictedGrowth < 0) {  // refining did not help: the unrefined mesh is as good and smaller
      d.restoreState(std::move(*unrefined));
      d.report.nearestFaceOutcome = "kept unrefined";
      d.report.warnings.push_back(
          std::to_string(flagged0) + " triangles have their centroid nearer another CAD face than their own; refining "
          "them left " + std::to_string(left) + ": left unrefined");
      d.log.warn(d.report.warnings.back());
    } else if (growth <= d.p.nearestFaceBudget) {
      d.report.nearestFaceOutcome = "refined";
    } else {
      const int flagged = d.report.nearestFaceFlagged.front();
      d.restoreState(std::move(*unrefined));
      d.report.nearestFaceOutcome = "kept unrefined";
      d.report.warnings.push_back(
          std::to_string(flagged) + " triangles are cut so deep into thin parts that their centroid lies nearer another CAD face "
          "than their own; refining them would add " + (predictedGrowth >= 0 ? "about " : "") +
          std::to_string((int)std::lround(100 * growth)) + (predictedGrowth >= 0 ? " %" : " % or more") +
          " triangles (budget " + fmt(100 * d.p.nearestFaceBudget) +
          " %): left unrefined (--nearest-face-check refines anyway)");
      d.log.warn(d.report.warnings.back());
    }
  }
  if (d.p.order == 2) d.secondOrder();
  d.finish();
  d.stage("total", total.seconds());
  d.progress.report(1.0, "done");
  MeshOutput out;
  out.mesh = std::move(d.mesh);
  out.report = std::move(d.report);
  return out;
}

}  // namespace paramesh
