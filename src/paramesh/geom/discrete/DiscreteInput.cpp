// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file DiscreteInput.cpp
#include "paramesh/geom/discrete/DiscreteInput.hpp"

#include "paramesh/util/Error.hpp"
#include "paramesh/util/Format.hpp"

namespace paramesh {

DiscreteInput discreteFromArrays(TriangleSoup soup, double featureAngleDeg) {
  if (!(featureAngleDeg > 0 && featureAngleDeg < 180))
    throw ParameterError("feature angle " + fmt(featureAngleDeg) + " degrees: it must be in (0, 180)");
  if (soup.triangles.empty()) throw InputError(soup.source + ": no facet");
  DiscreteInput d;
  d.featureAngle = featureAngleDeg;
  d.repair = repairTriangles(soup);
  d.mesh = std::move(soup);
  d.graph = buildFeatureGraph(d.mesh, featureAngleDeg);
  return d;
}

DiscreteInput loadDiscrete(const std::string& path, double featureAngleDeg) {
  return discreteFromArrays(readTriangleFile(path), featureAngleDeg);
}

std::vector<std::string> describeDiscrete(const DiscreteInput& d) {
  const FeatureGraph& g = d.graph;
  Box3 box;
  for (const Vec3& p : d.mesh.points) box.add(p);
  std::vector<std::string> out;
  out.push_back(d.mesh.source + ": triangulated, " + std::to_string(d.repair.inputTriangles) + " facets, " +
                std::to_string(d.mesh.points.size()) + " distinct vertices, diagonal " + fmt(box.diagonal()) + "; " +
                std::to_string(g.faceTris.size()) + " faces, " + std::to_string(g.edges.size()) + " edges, " +
                std::to_string(g.vertexNode.size()) + " vertices at feature angle " + fmt(d.featureAngle) + "; " +
                std::to_string(d.repair.pieces) + " pieces, " + std::to_string(d.repair.closedPieces) + " closed");
  for (const std::string& l : d.repair.lines()) out.push_back("repair: " + l);
  for (size_t f = 0; f < g.faceTris.size(); ++f) {
    std::string s = "Face" + std::to_string(f + 1) + " " + std::to_string(g.faceTris[f].size()) + " triangles, edges:";
    for (const auto& loop : g.faceLoops[f]) {
      s += " [";
      for (const auto& [e, rev] : loop) s += std::string(" ") + (rev ? "-" : "") + "Edge" + std::to_string(e + 1);
      s += " ]";
    }
    out.push_back(s);
  }
  for (size_t e = 0; e < g.edges.size(); ++e) {
    const auto& c = g.edges[e];
    double len = 0;
    for (size_t i = 1; i < c.nodes.size(); ++i) len += dist(d.mesh.points[c.nodes[i - 1]], d.mesh.points[c.nodes[i]]);
    std::string s = "Edge" + std::to_string(e + 1) + " Vertex" + std::to_string(c.v0 + 1) + " - Vertex" +
                    std::to_string(c.v1 + 1) + ", " + std::to_string(c.nodes.size() - 1) + " segments, length " + fmt(len) +
                    ", faces";
    for (int f : c.faces) s += " " + std::to_string(f + 1);
    out.push_back(s);
  }
  return out;
}

}  // namespace paramesh
