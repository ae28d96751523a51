// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshContext.hpp
/// The meshing context: what the surface pipeline's stages share (model, parameters, size field,
/// edge meshes, per-face results, report, log, progress). Each stage is a group of methods below,
/// defined in its own file under src/paramesh/stages/<stage>/; the comment of each group says
/// what it reads and writes. Mesher::run calls the stages in order.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "paramesh/algo/boundary_layer/BoundaryLayer.hpp"
#include "paramesh/algo/FaceMesher.hpp"
#include "paramesh/audit/MeshAudit.hpp"
#include "paramesh/model/Coincidence.hpp"
#include "paramesh/model/NarrowZones.hpp"
#include "paramesh/pipeline/Mesher.hpp"
#include "paramesh/pipeline/Tuning.hpp"
#include "paramesh/size/NearestFace.hpp"
#include "paramesh/size/SizeField.hpp"
#include "paramesh/size/Sources.hpp"
#include "paramesh/stages/edges/EdgeMesh.hpp"
#include "paramesh/util/Error.hpp"
#include "paramesh/util/Timer.hpp"

namespace paramesh {

struct EdgePolylines;

struct MeshContext {
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
  /// The edge stage's own state (stages/edges).
  struct EdgeStageState {
    std::vector<char> staggered;      ///< per edge: discretised by the narrow-gap stage
    std::vector<std::string> error;   ///< per edge: why it could not be discretised ("" if it was)
    /// The last discretisation's edge parameters (before createEdgeNodes): a nearest-face round
    /// that leaves the size field as it was (local deviation bounds only) reuses them
    struct EdgeParams {
      bool valid = false;
      std::vector<std::vector<double>> ts;
      std::vector<char> degen;
      std::vector<std::string> errors;
    } last;
  } edgeStage;
  /// The face stage's own state (stages/faces).
  struct FaceStageState {
    std::vector<std::vector<std::pair<int, double>>> strayPcurves;  ///< per face: FaceBoundary::strayPcurves
    bool strayLogged = false;
    std::vector<int> copyOf;    ///< per face: the coincident face whose triangles it takes (-1: none)
    std::vector<int> nodeBase;  ///< per face: mesh index of its first own node (assembly)
  } faceStage;
  /// The previous meshing round of the nearest-face check: a face whose edges kept their nodes
  /// and that no new size source reaches keeps its mesh (the size field there is unchanged, and
  /// meshing a face is deterministic: re-meshing it would give the same elements).
  struct PreviousRound {
    std::vector<FaceMeshResult> results;
    std::vector<FaceReport> reports;
    std::vector<EdgeMesh> edges;
    std::vector<std::vector<Vec3>> points;  ///< per face: its mesh's nodes
  };
  /// The nearest-face rounds' own state (stages/nearest_face).
  struct RoundState {
    std::unique_ptr<PreviousRound> previous;
    std::vector<SizeSource> sources;  ///< the sources added since the previous round (slope kNearestFaceSlope)
    std::vector<std::vector<DeviationZone>> zones;  ///< per face: the nearest-face check's local deviation bounds
    std::vector<char> zonesAdded;                   ///< per face: zones added since the previous round
  } rounds;
  int threads = 1;

  MeshContext(const IGeometryModel& m, MeshParams params, LogSink sink, ProgressCallback cb)
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

  // ================================================================ stages/setup (Setup.cpp)
  // ---------------------------------------------------------------- parameters
  void resolveParams();

  // ---------------------------------------------------------------- coincident topology
  void findCoincidentTopology();

  // ================================================================ stages/sizing (SizeFieldBuild.cpp)
  // ---------------------------------------------------------------- size field
  void buildSizeField();

  // ---------------------------------------------------------------- proximity
  void addProximitySources();

  // ================================================================ stages/layer_plan (LayerPlanning.cpp)
  // ---------------------------------------------------------------- boundary layers (1D part)
  void planBoundaryLayers();
  double edgeT0(int e) const;
  double edgeT1(int e) const;

  // ================================================================ stages/edges
  // ---------------------------------------------------------------- edges (DiscretizeEdges.cpp)
  /// Why work on one edge failed ("" when it did not): the message of what it threw, or the
  /// kernel's failure; a cancel goes through.
  static std::string edgeFailure(const std::function<void()>& work);

  void discretizeEdges();
  /// One edge's work under the kernel-failure guard: an edge the kernel cannot evaluate fails
  /// alone (no nodes, edgeStage.error says why; the faces it bounds fail naming it).
  void discretizeOne(int e, std::vector<std::vector<double>>& ts, const std::function<void()>& body);
  /// Every edge (or those marked in only) discretised by 3D length in the size field.
  void discretizeAll(std::vector<std::vector<double>>& ts, std::vector<char>& degen, const std::vector<char>* only);
  void discretizeEdge(int e, std::vector<std::vector<double>>& ts, std::vector<char>& degen);
  // ---------------------------------------------------------------- short edges (ShortEdges.cpp)
  /// Short CAD edges become size sources (the edges they reach discretised again); edges closing
  /// a strip a few elements wide get row-height segments.
  void refineShortEdges(std::vector<std::vector<double>>& ts, std::vector<char>& degen);
  void addShortEdgeSources(const EdgePolylines& poly, std::vector<std::vector<double>>& ts, std::vector<char>& degen);
  void respaceStripEnds(const EdgePolylines& poly, std::vector<std::vector<double>>& ts, const std::vector<char>& degen);

  /// The edge nodes again from the last discretisation (the size field has not changed since).
  void reuseEdges();

  /// Two edges joining the same two vertices must not both be a single chord.
  void splitParallelChords(std::vector<std::vector<double>>& ts, const std::vector<char>& degen) const;

  /// The mesh nodes and 1D elements of every edge from its parameters.
  void createEdgeNodes(const std::vector<std::vector<double>>& ts, const std::vector<char>& degen);

  // ---------------------------------------------------------------- narrow gaps (NarrowGaps.cpp)
  /// The boundary loops of face f as discretised by ts (wire order, inward directions from the
  /// face's outward normal: the face lies to the left of its wires seen from outside). Empty when
  /// the face uses an edge meshed through a coincident one (unsewn CAD).
  std::vector<std::vector<LoopNode>> loopNodes(int f, const std::vector<std::vector<double>>& ts,
                                               const std::vector<char>& degen) const;

  /// Narrow gaps (NarrowZones.hpp). Where two sides of a face face each other at a gap w below
  /// kStaggerTo of the size h, one row of triangles spans the gap: nodes opposite each other make
  /// angles below 30 degrees there. Instead, the nodes of one side (the follower edge) go midway
  /// between the projections of the other side's nodes (the leader), and the leader's spacing b
  /// along the gap lies between 2 sqrt(h^2/2 - w^2) (slanted edges h/sqrt2) and 3.3 w (angles 31
  /// degrees). Below w = 0.39 h no spacing does both with a margin: such gaps are left alone (a
  /// single row cannot have good angles there without edges shorter than h/sqrt2). Returns true
  /// when some edge changed.
  bool staggerNarrowGaps(std::vector<std::vector<double>>& ts, const std::vector<char>& degen);
  /// Edge b re-spaced against its leaders' nodes near it (false: too few of them).
  bool staggerAgainstLeaders(int b, const std::vector<int>& leadersOfB, std::vector<std::vector<double>>& ts);

  /// May the boundary stages (narrow gaps, corners, strip ends) change edge e's discretisation?
  /// Not a degenerate edge, and in unsewn CAD not a free edge: free edges of unsewn patches often
  /// overlap another patch's free edge in part, and their default discretisations match there.
  bool mayRespace(int e, const std::vector<char>& degen) const;

  /// Parameters of edge e discretised with the given spacing (as discretizeEdges does with the
  /// field: closed edges get at least 3 segments, none turns by more than 60 degrees).
  std::vector<double> discretizeWith(int e, const std::function<double(Vec3)>& spacing) const;

  /// Corners whose ear triangle would be poor. At a convex face corner of 40 to 110 degrees the
  /// face mesher usually keeps the ear (the corner and its two boundary neighbours) as a triangle;
  /// when one side's first segment is much shorter than the other's (a short CAD edge of one
  /// segment next to a regular one) that triangle has an angle below 30 degrees. The longer side's
  /// edge is discretised again with its segments growing from 1.3 x the short one at the corner
  /// (slope kCornerSlope, so only its first segment or two change). Short segments below
  /// kCornerMinRatio sizes (tiny features) are left alone. Returns true when some edge changed.
  bool matchCornerSegments(std::vector<std::vector<double>>& ts, const std::vector<char>& degen);

  // ================================================================ stages/faces
  // ---------------------------------------------------------------- faces with boundary layers (FacesWithLayers.cpp)
  bool hasBoundaryLayer(int f) const;

  /// Hand-off relaxation: the triangles standing on the layers' top edges should be about as tall
  /// as the last row (the size jump across the front). Interior apex nodes of such triangles move,
  /// on the surface, towards the point that gives each of their front triangles a height within
  /// [1/1.3, 1.3] of its row's height, when every triangle around them stays valid and well shaped.
  void relaxHandoff(const ISurface& s, const FaceBLResult& bl, int offset, std::vector<Vec3>& xyz,
                    std::vector<Vec2>& uv, const std::vector<std::array<int, 3>>& tris,
                    std::vector<std::array<Vec2, 3>>& triUv) const;

  /// Meshes face f with its boundary layers. When the face cannot be meshed with them (the rows
  /// leave a front the triangulation refuses, or no element), it is meshed without them and the
  /// reason goes to the report's warnings: a layer must never take its face down.
  FaceMeshResult meshFaceWithLayers(int f, const ISurface& s, const FaceBoundary& fb, FaceMeshOptions fo);

  FaceMeshResult meshFaceWithLayersOnly(int f, const ISurface& s, const FaceBoundary& fb, FaceMeshOptions fo);

  std::mutex blMu_;

  // ---------------------------------------------------------------- faces (MeshFaces.cpp)
  /// The first edge of face f that could not be discretised, or -1.
  int failedEdgeOf(int f) const;

  /// Once per run: the faces whose pcurves stray from their 3D edges (tolerant CAD); the worst
  /// named.
  void logStrayPcurves();

  void meshFaces();
  /// The face mesher's options from the parameters.
  FaceMeshOptions faceOptions() const;
  /// Face f meshed from its boundary (its error in the report when it fails: the others go on).
  void meshOneFace(int f, const FaceMeshOptions& fo, FaceMeshResult& result);
  // ---------------------------------------------------------------- coincident faces (CoincidentFaces.cpp)
  /// Face f has a coincident-face candidate before it (Coincidence::faceCandidate).
  bool isCoincidentCopy(int f) const;
  /// Each candidate copy takes its source's triangles when the source's nodes and triangle
  /// centres lie on it (within the faces' tolerances); otherwise it is meshed as a face of its own.
  void resolveCoincidentFaces(std::vector<FaceMeshResult>& results, const FaceMeshOptions& fo,
                              const std::vector<char>& reused);
  /// from (face src's result) as face f's, with (u,v) on f; false when f is not the same region.
  bool copyFaceMesh(int f, int src, const FaceMeshResult& from, FaceMeshResult& to) const;

  // ================================================================ stages/assemble (Assemble.cpp)
  /// A coincident copy's triangles (its source's orientation) face against its own surface's
  /// S_u x S_v (the two faces' parametrisations run opposite).
  bool copyAgainstSurface(int f, const FaceMeshResult& r, int base) const;
  /// Face f's result appended to the mesh (oriented, numbered) and its report counts.
  /// Assembly: every face's result into mesh, in face order (assemble/Assemble.cpp).
  void assembleFaces(std::vector<FaceMeshResult>& results);
  void assembleFace(int f, const FaceMeshResult& r, int tri0, int quad0, bool rev, std::vector<OffSurfaceTriangle>& off);
  /// The round's results kept for the next nearest-face round (faces it leaves unchanged are reused).
  void keepForNextRound(std::vector<FaceMeshResult>&& results);

  /// Fills results[f] with the previous round's mesh of every face that can keep it (node
  /// references renumbered); returns which. A face keeps its mesh when each of its edges has the
  /// same nodes as before and no source added since lies within its reach of a node of the face
  /// (h + slope * d >= hmax beyond it: the field there is what it was).
  std::vector<char> reusePreviousRound(std::vector<FaceMeshResult>& results);

  // ================================================================ stages/nearest_face
  // ---------------------------------------------------------------- the rounds (MeshRounds.cpp)
  /// Edges and faces, meshed again while the nearest-face check refines (within its budget).
  void meshRounds();
  /// One round: the edges (those of the last round when the field is the same), then the faces.
  void meshRound(bool sameField);
  /// Local deviation bounds on the flagged triangles' faces (counted in zoned); the size sources of
  /// the triangles they do not mend.
  std::vector<SizeSource> roundSources(const NearestFaceResult& nfr, int& zoned);
  // ---------------------------------------------------------------- nearest-face check (NearestFaceCheck.cpp)
  /// Size sources for the triangles whose centroid is nearer another face than their own surface;
  /// records how many there are.
  NearestFaceResult nearestFaceCheck();
  /// Local deviation bounds for the flagged triangles (NearestFaceResult::found): a ball around
  /// each on its own face, in which centroids may lie off their surface at most kZoneFraction of
  /// their distance to the other face's tangent plane (never less than a candidate's deviation).
  /// Returns, per flagged triangle, whether it got a zone: one whose centroid already lies in a
  /// zone of its face at least as strict was not mended by it, and gets none.
  std::vector<char> addDeviationZones(const NearestFaceResult& r);
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
  MeshState saveState() const;
  void restoreState(MeshState&& st);

  /// Back to the state before the edges were discretised (the size field is set by the caller).
  void resetMesh();
  /// The element growth the next round's field would give, predicted from the present mesh.
  double predictGrowth(const SizeField& next, const MeshState& unrefined) const;
  /// After the rounds: keep the refined mesh, or take the unrefined one back (and say why).
  void settleRefinement(MeshState&& unrefined, double predictedGrowth);

  // ================================================================ stages/volume (FillSolids.cpp)
  /// Every solid filled with tetrahedra bounded by its faces' triangles (report.solids says
  /// which could not be, and why).
  void fillSolids();

  // ================================================================ stages/second_order (SecondOrder.cpp)
  void secondOrder();

  // ================================================================ stages/report (Finish.cpp)
  void finish();

  // ================================================================ stages/audit (Audit.cpp)
  /// Before the volume and second-order stages: elements of the surface mesh folded onto a
  /// neighbour or facing against their surface are repaired where moving their face nodes on the
  /// surface mends them (audit/Repair.hpp). Writes mesh, triUv, quadUv, repairedNodes.
  void repairSurface();
  int repairedNodes = 0;
  /// The repair pass's element and edge-use findings and the digest of the mesh they were made
  /// on (audit/MeshDigest.hpp): the final audit reuses them when the mesh is unchanged.
  struct ElementAudit {
    bool valid = false;
    uint64_t digest = 0;
    AuditResult result;
  } elementAudit;
  /// The finished mesh audited (audit/MeshAudit.hpp): report.audit; a finding makes an ok run
  /// degraded, naming the faces and edges. Reads mesh, triUv, quadUv, faceStage.copyOf.
  void audit();
  AuditInput auditInput() const;

  /// The smallest radius of curvature that triangles of the min-size can follow at the curvature
  /// angle (0: no curvature angle).
  double minSizeReach() const { return p.curvatureAngle > 0 ? p.minSize / (p.curvatureAngle * tuning::kPi / 180.0) : 0.0; }

  /// One warning for the triangles left beyond the deviation bounds: per face (the five with the
  /// most) how many, the worst, where, and the surface's radius of curvature there; and, where
  /// that radius is below what the min-size can follow at the curvature angle, that the min-size
  /// is what holds the triangles back.
  void warnOverDeviation();
};

}  // namespace paramesh
