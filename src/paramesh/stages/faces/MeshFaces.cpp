// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshFaces.cpp
/// Face stage: every face meshed in (u,v) from its boundary (in parallel, a failing face does not
/// take the others down), faces the previous round left unchanged reused, and the results
/// assembled into one conformal, oriented mesh. Reads model, field, edges, vertexNode, rounds.zones;
/// writes mesh (triangles, quads), triUv, quadUv, report.faces, offSurface, triDeviation.
#include <algorithm>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <unordered_map>
#include <vector>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/pipeline/Tuning.hpp"
#include "paramesh/size/SourceReach.hpp"
#include "paramesh/util/Parallel.hpp"
#include "paramesh/model/EdgeDiscretizer.hpp"
#include "paramesh/stages/faces/FaceBoundaryBuild.hpp"
#include "paramesh/util/Format.hpp"

namespace paramesh {

using namespace tuning;

int MeshContext::failedEdgeOf(int f) const {
  if (edgeStage.error.empty()) return -1;
  for (const Wire& w : model.faceWires(f))
    for (const EdgeUse& u : w.uses)
      if (!edgeStage.error[u.edge].empty()) return u.edge;
  return -1;
}

void MeshContext::logStrayPcurves() {
  if (faceStage.strayLogged) return;
  faceStage.strayLogged = true;
  int faces = 0, uses = 0, worstFace = -1, worstEdge = -1;
  double worst = 0;
  for (int f = 0; f < (int)faceStage.strayPcurves.size(); ++f) {
    if (faceStage.strayPcurves[f].empty()) continue;
    ++faces;
    for (const auto& t : faceStage.strayPcurves[f]) {
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

FaceMeshOptions MeshContext::faceOptions() const {
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
  return fo;
}

void MeshContext::meshOneFace(int f, const FaceMeshOptions& fo, FaceMeshResult& result) {
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
      const std::string name = "Edge" + std::to_string(bad + 1), &reason = edgeStage.error[bad];
      fr.error = "its " + name + " could not be discretised: " +
                 (reason.rfind(name + ": ", 0) == 0 ? reason.substr(name.size() + 2) : reason);
    } else if (!buildFaceBoundary(model, edges, mesh, field, f, *s, fb, why)) {
      fr.ok = false;
      fr.error = why;
    } else if (hasBoundaryLayer(f)) {
      faceStage.strayPcurves[f] = fb.strayPcurves;
      result = meshFaceWithLayers(f, *s, fb, fo);
      fr.ok = result.ok;
      fr.error = result.error;
    } else {
      faceStage.strayPcurves[f] = fb.strayPcurves;
      FaceMeshOptions zo;  // with the nearest-face check's zones on this face
      const bool zoned = f < (int)rounds.zones.size() && !rounds.zones[f].empty();
      if (zoned) {
        zo = fo;
        zo.deviationZones = rounds.zones[f];
      }
      result = meshFace(*s, fb, field, zoned ? zo : fo, &progress);
      fr.ok = result.ok;
      fr.error = result.error;
      fr.rejectedPoints = result.rejectedPoints;
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
}

void MeshContext::meshFaces() {
  Timer tm;
  const int nf = model.numFaces();
  faceStage.strayPcurves.assign(nf, {});
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
  const FaceMeshOptions fo = faceOptions();
  const std::vector<char> reused = reusePreviousRound(results);
  parallelFor(nf, threads, [&](int f) {
    if (reused[f] || isCoincidentCopy(f)) return;
    meshOneFace(f, fo, results[f]);
    const int k = ++done;
    progress.report(0.15 + 0.8 * k / std::max(nf, 1), "faces");
  }, &order);
  resolveCoincidentFaces(results, fo, reused);
  stage("faces", tm.seconds());
  logStrayPcurves();
  // assemble in face order (deterministic)
  Timer ta;
  assembleFaces(results);
  stage("assemble", ta.seconds());
  if (fo.reportOffSurface && blLaws.empty()) keepForNextRound(std::move(results));
}

std::vector<char> MeshContext::reusePreviousRound(std::vector<FaceMeshResult>& results) {
  const int nf = model.numFaces();
  std::vector<char> reused(nf, 0);
  if (!rounds.previous) return reused;
  std::unique_ptr<PreviousRound> prev = std::move(rounds.previous);
  const int ne = model.numEdges();
  std::vector<char> edgeSame(ne, 0);
  for (int e = 0; e < ne && (size_t)e < prev->edges.size(); ++e)
    edgeSame[e] = prev->edges[e].t == edges[e].t && prev->edges[e].degenerate == edges[e].degenerate &&
                  prev->edges[e].nodes.size() == edges[e].nodes.size();
  const double hmax = field.hmax();
  // the field is queried on the surface between the nodes too: one size of margin
  std::vector<Vec3> at;
  std::vector<double> reach;
  for (const SizeSource& src : rounds.sources) {
    at.push_back(src.p);
    reach.push_back((hmax - src.h) / kNearestFaceSlope + hmax);
  }
  const SourceReach near(std::move(at), std::move(reach));
  int kept = 0;
  for (int f = 0; f < nf; ++f) {
    // a coincident copy is taken from its source again (its triangles name the source's nodes)
    bool ok = (!prev->points[f].empty() || !prev->reports[f].ok) && !isCoincidentCopy(f);
    if (f < (int)rounds.zonesAdded.size() && rounds.zonesAdded[f]) ok = false;
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

}  // namespace paramesh
