// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file FillSolids.cpp
/// Volume stage: every solid filled with tetrahedra bounded by its faces' triangles (nglib makes
/// the interior; the surface stays ours), checked against that surface, measured. A solid that
/// cannot be filled is reported with the reason; the others are filled. Reads model, mesh,
/// p.volumeMaxSize, p.maxSize, p.grading, p.volumeOptimize; writes mesh (interior nodes, tets, tetSolid),
/// report.solids, report.tetrahedra.
#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/stages/volume/SolidSurface.hpp"
#include "paramesh/util/Format.hpp"
#include "paramesh/volume/SelfIntersection.hpp"
#include "paramesh/volume/TetQuality.hpp"
#include "paramesh/volume/nglib/NglibFill.hpp"

namespace paramesh {

namespace {

/// "" when the surface does not cross itself; otherwise how many triangle pairs cross and on
/// which faces.
std::string crossingFaces(const SolidSurface& surf, const std::vector<Vec3>& nodes) {
  const auto pairs = crossingTriangles(nodes, surf.triangles);
  if (pairs.empty()) return {};
  std::set<std::pair<int, int>> faces;
  for (const auto& [a, b] : pairs)
    faces.insert({std::min(surf.triangleFace[a], surf.triangleFace[b]), std::max(surf.triangleFace[a], surf.triangleFace[b])});
  std::string s = "its surface mesh crosses itself (" + std::to_string(pairs.size()) +
                  (pairs.size() >= 20 ? "+" : "") + " triangle pairs:";
  int n = 0;
  for (const auto& [a, b] : faces) {
    if (n++ == 5) {
      s += " ...";
      break;
    }
    s += (n > 1 ? ", Face" : " Face") + std::to_string(a) + (a == b ? " with itself" : " x Face" + std::to_string(b));
  }
  return s + ")";
}

}  // namespace

void MeshContext::fillSolids() {
  Timer total;
  std::vector<std::vector<int>> trianglesOfFace(model.numFaces());
  std::vector<int> quadsOfFace(model.numFaces(), 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) trianglesOfFace[mesh.triangleFace[t] - 1].push_back((int)t);
  for (int f : mesh.quadFace) ++quadsOfFace[f - 1];
  NglibOptions opt;
  opt.maxSize = p.volumeMaxSize > 0 ? p.volumeMaxSize : p.maxSize;
  opt.optimizeSteps = p.volumeOptimize;
  opt.grading = std::clamp(p.grading - 1.0, 0.05, 1.0);  // nglib's grading: size growth per size
  const int n = model.numSolids();
  for (int s = 0; s < n; ++s) {
    progress.report(0.9 + 0.05 * s / std::max(1, n), "volume");
    Timer ts;
    SolidReport sr;
    sr.solid = s + 1;
    const SolidSurface surf = solidSurface(model, s, mesh, trianglesOfFace, quadsOfFace);
    sr.faces = surf.faces;
    std::string why = surf.problem;
    if (why.empty()) why = crossingFaces(surf, mesh.nodes);
    if (why.empty()) {
      // the solid's own numbering of its surface nodes
      std::vector<int> local(mesh.nodes.size(), -1), global;
      std::vector<Vec3> pts;
      std::vector<std::array<int, 3>> tris;
      tris.reserve(surf.triangles.size());
      for (const auto& t : surf.triangles) {
        std::array<int, 3> lt;
        for (int k = 0; k < 3; ++k) {
          int& l = local[t[k]];
          if (l < 0) {
            l = (int)pts.size();
            pts.push_back(mesh.nodes[t[k]]);
            global.push_back(t[k]);
          }
          lt[k] = l;
        }
        tris.push_back(lt);
      }
      NglibResult r = fillWithNglib(pts, tris, opt);
      why = r.error;
      std::vector<Vec3> all = pts;
      all.insert(all.end(), r.interior.begin(), r.interior.end());
      if (why.empty()) {
        // nglib orients its tetrahedra the other way round: two corners swapped
        for (auto& t : r.tets) std::swap(t[1], t[2]);
        why = checkFill(all, r.tets, tris);
        if (!why.empty()) why = "the tetrahedra do not fill its surface exactly (" + why + ")";
      }
      if (why.empty()) {
        const TetStats st = tetStats(all, r.tets);
        for (const Vec3& x : r.interior) global.push_back(mesh.addNode(x, NodeKind::Volume, s + 1));
        for (const auto& t : r.tets) {
          mesh.tets.push_back({global[t[0]], global[t[1]], global[t[2]], global[t[3]]});
          mesh.tetSolid.push_back(s + 1);
        }
        sr.ok = true;
        sr.tetrahedra = st.tets;
        sr.nodes = (int)r.interior.size();
        sr.minDihedral = st.minDihedral;
        sr.maxDihedral = st.maxDihedral;
        sr.meanDihedral = st.meanDihedral;
        sr.pctDihedralBelow10 = st.pctBelow10;
        sr.minRadiusRatio = st.minRadiusRatio;
        sr.meanRadiusRatio = st.meanRadiusRatio;
        sr.volume = st.volume;
        report.tetrahedra += st.tets;
      }
    }
    sr.seconds = ts.seconds();
    if (!sr.ok) {
      sr.error = why;
      log.warn("Solid" + std::to_string(s + 1) + " not filled with tetrahedra: " + why);
    } else {
      log.info("Solid" + std::to_string(s + 1) + ": " + std::to_string(sr.tetrahedra) + " tetrahedra, min dihedral " +
               fmt(sr.minDihedral) + " deg, " + fmt(sr.pctDihedralBelow10) + " % below 10 deg, " + fmt(sr.seconds) + " s");
    }
    report.solids.push_back(std::move(sr));
  }
  stage("volume", total.seconds());
}

}  // namespace paramesh
