// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Groups.cpp
#include "paramesh/io/Groups.hpp"

#include <algorithm>
#include <set>

namespace paramesh::io {

std::vector<WrittenGroup> writtenGroups(const SurfaceMesh& m) {
  std::vector<WrittenGroup> out;
  std::set<int> vertices;
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    if (m.nodeKind[i] == NodeKind::Vertex) vertices.insert(m.nodeEntity[i]);
  for (int v : vertices) out.push_back({0, v, "Vertex" + std::to_string(v), {v}, false});
  const std::set<int> edges(m.segmentEdge.begin(), m.segmentEdge.end());
  for (int e : edges) out.push_back({1, e, "Edge" + std::to_string(e), {e}, false});
  std::set<int> faces(m.triangleFace.begin(), m.triangleFace.end());
  faces.insert(m.quadFace.begin(), m.quadFace.end());
  for (int f : faces) out.push_back({2, f, "Face" + std::to_string(f), {f}, false});
  const std::set<int> solids(m.tetSolid.begin(), m.tetSolid.end());
  for (int s : solids) out.push_back({3, s, "Solid" + std::to_string(s), {s}, false});
  int next[4] = {0, std::max(m.numEdges, edges.empty() ? 0 : *edges.rbegin()) + 1, std::max(m.numFaces, faces.empty() ? 0 : *faces.rbegin()) + 1,
                 std::max(m.numSolids, solids.empty() ? 0 : *solids.rbegin()) + 1};
  for (const MeshGroup& g : m.groups) {
    WrittenGroup w{g.dim, next[g.dim]++, g.name, g.entities, true};
    std::sort(w.entities.begin(), w.entities.end());
    w.entities.erase(std::unique(w.entities.begin(), w.entities.end()), w.entities.end());
    out.push_back(std::move(w));
  }
  return out;
}

std::map<std::pair<int, int>, std::vector<int>> groupTagsByEntity(const std::vector<WrittenGroup>& groups) {
  std::map<std::pair<int, int>, std::vector<int>> out;
  for (const WrittenGroup& g : groups)
    for (int e : g.entities) out[{g.dim, e}].push_back(g.tag);
  for (auto& [key, tags] : out) std::sort(tags.begin(), tags.end());
  return out;
}

}  // namespace paramesh::io
