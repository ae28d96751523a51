// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Finish.cpp
/// Report stage: counts, quality summary, deviation from the CAD, layer and stray-pcurve warnings,
/// and the run's status (degraded when faces or solids failed, or a layer grew no element). Reads mesh, report.faces, blStats, blEmpty, blDropped; writes report.
#include <algorithm>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/pipeline/Tuning.hpp"
#include "paramesh/stages/report/ForcedSliver.hpp"

namespace paramesh {

using namespace tuning;

void MeshContext::finish() {
  Timer tq;
  report.nodes = (int)mesh.nodes.size();
  report.triangles = (int)mesh.triangles.size();
  report.quads = (int)mesh.quads.size();
  report.order = mesh.order;
  report.sizeSources = field.numSources();
  report.quality = summarizeQuality(mesh, [this](Vec3 x) { return field.size(x); });
  if (const std::string w = forcedSliverWarning(mesh, model, field); !w.empty()) report.warnings.push_back(w);
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
  std::string unfilled;
  for (const SolidReport& sr : report.solids)
    if (!sr.ok) unfilled += (unfilled.empty() ? "" : "; ") + ("Solid" + std::to_string(sr.solid) + ": " + sr.error);
  if (!unfilled.empty() && report.status != RunStatus::Failed) {
    report.status = RunStatus::Degraded;
    report.message += (failed.empty() ? "; " : "; and ") + std::string("solids not filled with tetrahedra: ") + unfilled;
  } else if (!report.solids.empty() && report.status == RunStatus::Ok) {
    report.message += ", " + std::to_string(report.tetrahedra) + " tetrahedra in " + std::to_string(report.solids.size()) +
                      " solids";
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
  // why a layer's columns gave no element: its stop counts
  auto stops = [](const FaceBLResult::SpecStats& st) {
    std::string why;
    auto add = [&](int n, const char* what) {
      if (n > 0) why += (why.empty() ? "" : ", ") + std::to_string(n) + " " + what;
    };
    add(st.stopBoundary, "at the face boundary");
    add(st.stopCollision, "by a collision");
    add(st.stopInvalid, "folding");
    add(st.stopAspect, "at the aspect limit");
    add(st.stopEnd, "at an edge end or a corner");
    return std::to_string(st.columns) + " columns" + (why.empty() ? "" : "; stopped: " + why);
  };
  auto edgesOf = [this](int spec) {
    std::string s;
    for (int e : report.boundaryLayers[spec].edges)  // 1-based, listed just above
      s += (s.empty() ? "Edge" : ", Edge") + std::to_string(e);
    return s.empty() ? std::string("no edge found") : s;
  };
  // faces where a layer was asked for and no element grew (no two neighbouring columns share a row)
  for (const auto& [key, st] : blEmpty) {
    const std::string w = "boundary layer " + std::to_string(key.second + 1) + " (" + edgesOf(key.second) +
                          ") got no element on Face" + std::to_string(key.first + 1) + " (" + stops(st) + ")";
    report.warnings.push_back(w);
    log.warn(w);
  }
  // a layer asked for that grew no element on any face: the run did not give what was asked
  std::string empty;
  for (size_t k = 0; k < report.boundaryLayers.size(); ++k)
    if (report.boundaryLayers[k].elements == 0)
      empty += (empty.empty() ? "" : "; ") + ("boundary layer " + std::to_string(k + 1) + " (" + edgesOf((int)k) +
                                              ") produced no element on any face (" + stops(blStats[k]) + ")");
  if (!empty.empty() && report.status != RunStatus::Failed) {
    report.status = RunStatus::Degraded;
    report.message += "; " + empty;
  }
  warnOverDeviation();
  stage("quality", tq.seconds());
}

void MeshContext::warnOverDeviation() {
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
    if (face - 1 < (int)faceStage.strayPcurves.size())
      for (const auto& t : faceStage.strayPcurves[face - 1]) off = std::max(off, t.second);
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

}  // namespace paramesh
