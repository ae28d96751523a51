// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Groups.cpp
#include "paramesh/io/Groups.hpp"

#include <algorithm>
#include <set>

namespace paramesh::io {

std::vector<WrittenGroup> writtenGroups(const SurfaceMesh& m) {
  std::vector<WrittenGroup> out;
  // the user's groups first, numbered 1, 2, ... per dimension in the order given
  int users[4] = {0, 0, 0, 0};
  for (const MeshGroup& g : m.groups) {
    WrittenGroup w{g.dim, ++users[g.dim], g.name, g.entities, true};
    std::sort(w.entities.begin(), w.entities.end());
    w.entities.erase(std::unique(w.entities.begin(), w.entities.end()), w.entities.end());
    out.push_back(std::move(w));
  }
  // then the default ones: entity i of a dimension with k user groups has tag k + i
  std::set<int> vertices;
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    if (m.nodeKind[i] == NodeKind::Vertex) vertices.insert(m.nodeEntity[i]);
  for (int v : vertices) out.push_back({0, users[0] + v, "Vertex" + std::to_string(v), {v}, false});
  for (int e : std::set<int>(m.segmentEdge.begin(), m.segmentEdge.end()))
    out.push_back({1, users[1] + e, "Edge" + std::to_string(e), {e}, false});
  std::set<int> faces(m.triangleFace.begin(), m.triangleFace.end());
  faces.insert(m.quadFace.begin(), m.quadFace.end());
  for (int f : faces) out.push_back({2, users[2] + f, "Face" + std::to_string(f), {f}, false});
  for (int s : std::set<int>(m.tetSolid.begin(), m.tetSolid.end()))
    out.push_back({3, users[3] + s, "Solid" + std::to_string(s), {s}, false});
  std::stable_sort(out.begin(), out.end(), [](const WrittenGroup& a, const WrittenGroup& b) {
    return a.dim != b.dim ? a.dim < b.dim : a.tag < b.tag;
  });
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
