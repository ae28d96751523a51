// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/pipeline/ReportJson.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

#include "paramesh/util/Error.hpp"

namespace paramesh {

namespace {

Json names(const char* kind, const std::vector<int>& ids) {
  Json a = Json::array();
  for (int i : ids) a.push(kind + std::to_string(i));
  return a;
}

}  // namespace

Json auditToJson(const AuditResult& a) {
  Json j = Json::object();
  j["passed"] = a.passed();
  Json& c = j["counts"];
  const std::pair<const char*, int> counts[] = {
      {"invalid_entries", a.invalidEntries},         {"empty_faces", a.emptyFaces},                 {"open_face_edges", a.openFaceEdges},          {"face_overused_edges", a.faceOverusedEdges},
      {"face_misoriented_edges", a.faceMisorientedEdges}, {"non_manifold_edges", a.nonManifoldEdges},
      {"solid_open_edges", a.solidOpenEdges},        {"solid_overused_edges", a.solidOverusedEdges},
      {"solid_misoriented_edges", a.solidMisorientedEdges}, {"duplicate_elements", a.duplicateElements},
      {"folds", a.folds},                            {"inverted_elements", a.invertedElements},
      {"inverted_tets", a.invertedTets},             {"duplicate_tets", a.duplicateTets},
      {"coincident_nodes", a.coincidentNodes},       {"nodes_off_cad", a.nodesOffCad}};
  for (const auto& [k, v] : counts) c[k] = v;
  j["solids_checked"] = a.solidsChecked;
  j["solids_skipped"] = a.solidsSkipped;
  j["nodes_checked"] = a.nodesChecked;
  j["repaired_nodes"] = a.repairedNodes;
  j["worst_node_offset"] = a.worstNodeOffset;
  j["faces"] = names("Face", a.faces);
  j["edges"] = names("Edge", a.edges);
  j["solids"] = names("Solid", a.solids);
  Json& pr = j["problems"];
  pr = Json::array();
  for (const auto& s : a.problems) pr.push(s);
  Json& no = j["notes"];
  no = Json::array();
  for (const auto& s : a.notes) no.push(s);
  j["seconds"] = a.seconds;
  return j;
}

Json reportToJson(const Report& r) {
  Json j = Json::object();
  j["status"] = toString(r.status);
  j["message"] = r.message;
  j["source"] = r.source;
  Json& cad = j["cad"];
  cad["faces"] = r.cadFaces;
  cad["edges"] = r.cadEdges;
  cad["vertices"] = r.cadVertices;
  cad["solids"] = r.cadSolids;
  Json& par = j["parameters"];
  par["size"] = r.size;
  par["min_size"] = r.minSize;
  par["max_size"] = r.maxSize;
  par["curvature_angle"] = r.curvatureAngle;
  par["max_deviation"] = r.maxDeviation;
  par["grading"] = r.grading;
  par["threads"] = r.threads;
  if (r.volume) {
    par["volume"] = true;
    par["volume_max_size"] = r.volumeMaxSize;
    par["volume_optimize"] = r.volumeOptimize;
  }
  Json& cnt = j["counts"];
  cnt["nodes"] = r.nodes;
  cnt["triangles"] = r.triangles;
  cnt["quads"] = r.quads;
  cnt["size_sources"] = r.sizeSources;
  if (!r.nearestFaceFlagged.empty()) {
    Json& nf = j["nearest_face_check"];
    Json& rounds = nf["flagged_per_round"];
    for (int k : r.nearestFaceFlagged) rounds.push(k);
    if (!r.nearestFaceRemeshed.empty()) {
      Json& again = nf["faces_remeshed_per_round"];
      for (int k : r.nearestFaceRemeshed) again.push(k);
    }
    // the kept mesh's count: the first round's when the refinement was not kept
    nf["remaining"] = r.nearestFaceOutcome == "kept unrefined" ? r.nearestFaceFlagged.front() : r.nearestFaceFlagged.back();
    if (!r.nearestFaceOutcome.empty()) {
      nf["outcome"] = r.nearestFaceOutcome;
      nf["triangle_growth"] = r.nearestFaceGrowth;
    }
  }
  if (r.order == 2) {
    Json& ho = j["second_order"];
    ho["mid_nodes"] = r.midNodes;
    ho["straightened_mid_nodes"] = r.straightenedMidNodes;
    ho["min_scaled_jacobian"] = r.minScaledJacobian;
  }
  if (!r.coincidentFaces.empty()) {
    Json& cf = j["coincident_faces"];
    for (const auto& [a, b] : r.coincidentFaces) {
      Json pair = Json::array();
      pair.push(a);
      pair.push(b);
      cf.push(std::move(pair));
    }
  }
  if (!r.solids.empty()) {
    Json& vol = j["volume"];
    vol["tetrahedra"] = r.tetrahedra;
    vol["solids_filled"] = r.solidsFilled();
    if (r.order == 2) {
      vol["straightened_tet10"] = r.straightenedTets;
      vol["min_tet10_scaled_jacobian"] = r.minTetJacobian;
    }
    Json& sl = vol["solids"];
    for (const SolidReport& s : r.solids) {
      Json o = Json::object();
      o["solid"] = s.solid;
      o["ok"] = s.ok;
      if (!s.ok) o["error"] = s.error;
      Json& fs = o["faces"];
      fs = Json::array();
      for (int f : s.faces) fs.push(f);
      o["tetrahedra"] = s.tetrahedra;
      o["interior_nodes"] = s.nodes;
      o["min_dihedral"] = s.minDihedral;
      o["mean_dihedral"] = s.meanDihedral;
      o["max_dihedral"] = s.maxDihedral;
      o["pct_dihedral_below_10"] = s.pctDihedralBelow10;
      o["min_radius_ratio"] = s.minRadiusRatio;
      o["mean_radius_ratio"] = s.meanRadiusRatio;
      o["volume"] = s.volume;
      o["seconds"] = s.seconds;
      sl.push(std::move(o));
    }
  }
  Json& st = j["seconds"];
  for (const auto& kv : r.stageSeconds) st[kv.first] = kv.second;
  Json& q = j["quality"];
  q["gamma_min"] = r.quality.gammaMin;
  q["gamma_mean"] = r.quality.gammaMean;
  q["angle_min"] = r.quality.angleMin;
  q["angle_max"] = r.quality.angleMax;
  q["pct_angle_lt_30"] = r.quality.pctAngleBelow30;
  q["pct_len_in_sqrt2"] = r.quality.pctLenInSqrt2;
  q["len_ratio_mean"] = r.quality.lenRatioMean;
  if (r.quads > 0) {
    q["quad_angle_max"] = r.quality.quadAngleMax;
    q["quad_aspect_mean"] = r.quality.quadAspectMean;
    q["quad_aspect_max"] = r.quality.quadAspectMax;
    q["quad_warp_max"] = r.quality.quadWarpMax;
    q["pct_area_in_quads"] = r.quality.pctAreaInQuads;
  }
  Json& faces = j["faces"];
  faces = Json::array();
  for (const FaceReport& f : r.faces) {
    Json fj = Json::object();
    fj["face"] = f.face;
    fj["name"] = "Face" + std::to_string(f.face);
    fj["surface"] = f.surface;
    fj["status"] = f.ok ? "ok" : "failed";
    if (!f.ok) fj["error"] = f.error;
    fj["triangles"] = f.triangles;
    fj["quads"] = f.quads;
    fj["interior_nodes"] = f.nodes;
    fj["seconds"] = f.seconds;
    if (f.crestSegments > 0) fj["crest_segments"] = f.crestSegments;
    if (f.crestRowSegments > 0) fj["crest_row_segments"] = f.crestRowSegments;
    if (f.overDeviation > 0) {
      Json& od = fj["over_deviation_bound"];
      od["triangles"] = f.overDeviation;
      od["worst_over_bound"] = f.overDeviationWorst;
      Json& at = od["worst_at"];
      at = Json::array();
      for (double x : f.overDeviationAt) at.push(x);
      if (std::isfinite(f.overDeviationRadius)) od["surface_radius_min"] = f.overDeviationRadius;
      if (r.curvatureAngle > 0) od["radius_above_min_size_reach"] = f.overDeviationResolvable;
    }
    faces.push(std::move(fj));
  }
  if (!r.boundaryLayers.empty()) {
    Json& bl = j["boundary_layers"];
    bl = Json::array();
    for (const auto& b : r.boundaryLayers) {
      Json x = Json::object();
      x["spec"] = b.spec;
      Json& ed = x["edges"];
      ed = Json::array();
      for (int e : b.edges) ed.push("Edge" + std::to_string(e));
      x["layers_requested"] = b.layersRequested;
      x["columns"] = b.columns;
      x["full_columns"] = b.fullColumns;
      x["layers_min"] = b.minLayers;
      x["layers_max"] = b.maxLayers;
      x["elements"] = b.elements;
      Json& st = x["stops"];
      st["face_boundary"] = b.stopBoundary;
      st["collision"] = b.stopCollision;
      st["folding"] = b.stopInvalid;
      st["aspect"] = b.stopAspect;
      st["edge_end"] = b.stopEdgeEnd;
      x["fans"] = b.fans;
      x["merges"] = b.merges;
      bl.push(std::move(x));
    }
  }
  if (!r.proposedLeadingEdges.empty()) {
    Json& pe = j["proposed_leading_edges"];
    pe = Json::array();
    for (const auto& e : r.proposedLeadingEdges) {
      Json x = Json::object();
      x["edge"] = "Edge" + std::to_string(e.edge);
      x["radius"] = e.radius;
      x["curvature_ratio"] = std::min(e.ratio, 1e6);
      pe.push(std::move(x));
    }
  }
  if (r.audit.run) j["audit"] = auditToJson(r.audit);
  Json& w = j["warnings"];
  w = Json::array();
  for (const auto& s : r.warnings) w.push(s);
  return j;
}

void writeReportJson(const std::string& path, const Report& r) {
  std::ofstream out(path);
  if (!out) throw Error("cannot write the report '" + path + "'");
  out << reportToJson(r).dump(1) << "\n";
  if (!out) throw Error("cannot write the report '" + path + "'");
}

}  // namespace paramesh
