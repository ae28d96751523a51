// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MshWriter.cpp
/// The Gmsh MSH 4.1 writer.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>

#include "paramesh/io/Groups.hpp"
#include "paramesh/io/WriterSupport.hpp"
#include "paramesh/util/Error.hpp"

namespace paramesh {

// ---------------------------------------------------------------------------------------------
// Gmsh MSH 4.1

void writeMsh41(const std::string& path, const SurfaceMesh& m) {
  using namespace io;
  checkMeshForWriting(path, m);
  const bool o2 = m.order == 2;
  const std::size_t N = m.nodes.size();

  // Entities: those claimed by nodes plus those holding elements; boxes from all their nodes.
  std::map<int, Box3> ent[4];
  std::map<int, Vec3> vertexPos;  // a point entity's coordinates: those of its first node
  for (std::size_t i = 0; i < N; ++i) {
    ent[static_cast<int>(m.nodeKind[i])][m.nodeEntity[i]].add(m.nodes[i]);
    if (m.nodeKind[i] == NodeKind::Vertex) vertexPos.emplace(m.nodeEntity[i], m.nodes[i]);
  }
  for (std::size_t s = 0; s < m.segments.size(); ++s) {
    Box3& b = ent[1][m.segmentEdge[s]];
    for (int v : m.segments[s]) b.add(m.nodes[v]);
    if (o2) b.add(m.nodes[m.segmentMid[s]]);
  }
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    Box3& b = ent[2][m.triangleFace[t]];
    for (int v : m.triangles[t]) b.add(m.nodes[v]);
    if (o2)
      for (int v : m.triangleMid[t]) b.add(m.nodes[v]);
  }
  for (std::size_t q = 0; q < m.quads.size(); ++q) {
    Box3& b = ent[2][m.quadFace[q]];
    for (int v : m.quads[q]) b.add(m.nodes[v]);
    if (o2)
      for (int v : m.quadMid[q]) b.add(m.nodes[v]);
  }

  for (std::size_t k = 0; k < m.tets.size(); ++k) {
    Box3& b = ent[3][m.tetSolid[k]];
    for (int v : m.tets[k]) b.add(m.nodes[v]);
  }

  // physical groups: the default ones (Face<i>, Solid<i>) and the user's
  const std::vector<WrittenGroup> groups = writtenGroups(m);
  const auto tagsOf = groupTagsByEntity(groups);
  TextOut out(path);
  out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  if (!groups.empty()) {
    out << "$PhysicalNames\n" << groups.size() << '\n';
    for (const WrittenGroup& g : groups) out << g.dim << ' ' << g.tag << " \"" << g.name << "\"\n";
    out << "$EndPhysicalNames\n";
  }
  auto physical = [&](int dim, int tag) {
    const auto it = tagsOf.find({dim, tag});
    if (it == tagsOf.end()) {
      out << " 0";
      return;
    }
    out << ' ' << it->second.size();
    for (int t : it->second) out << ' ' << t;
  };

  out << "$Entities\n"
      << ent[0].size() << ' ' << ent[1].size() << ' ' << ent[2].size() << ' ' << ent[3].size() << '\n';
  auto box = [&](const Box3& b) {
    Box3 bb = b;
    if (bb.empty()) bb.lo = bb.hi = Vec3();
    out << bb.lo.x << ' ' << bb.lo.y << ' ' << bb.lo.z << ' ' << bb.hi.x << ' ' << bb.hi.y << ' '
        << bb.hi.z;
  };
  for (const auto& [tag, p] : vertexPos) {
    out << tag << ' ' << p.x << ' ' << p.y << ' ' << p.z;
    physical(0, tag);
    out << '\n';
  }
  for (int d = 1; d <= 3; ++d)
    for (const auto& [tag, b] : ent[d]) {
      out << tag << ' ';
      box(b);
      physical(d, tag);
      out << " 0\n";  // no boundary entities
    }
  out << "$EndEntities\n";

  if (N == 0) {  // like Gmsh: an empty mesh has no $Nodes / $Elements sections
    out.commit();
    return;
  }

  // Nodes, one block per (dimension, entity), ascending tags within a block.
  auto nodeKey = [&](int i) {
    return std::pair<int, int>(static_cast<int>(m.nodeKind[i]), m.nodeEntity[i]);
  };
  std::vector<int> nodeOrder = sortedBy(N, nodeKey);
  std::size_t nodeBlocks = 0;
  forEachRun(nodeOrder, nodeKey, [&](std::size_t, std::size_t) { ++nodeBlocks; });
  out << "$Nodes\n" << nodeBlocks << ' ' << N << " 1 " << N << '\n';
  forEachRun(nodeOrder, nodeKey, [&](std::size_t b, std::size_t e) {
    int i0 = nodeOrder[b];
    out << static_cast<int>(m.nodeKind[i0]) << ' ' << m.nodeEntity[i0] << " 0 " << (e - b) << '\n';
    for (std::size_t k = b; k < e; ++k) out << nodeOrder[k] + 1 << '\n';
    for (std::size_t k = b; k < e; ++k) {
      const Vec3& p = m.nodes[nodeOrder[k]];
      out << p.x << ' ' << p.y << ' ' << p.z << '\n';
    }
  });
  out << "$EndNodes\n";

  // Elements: points, segments per edge, then per face its triangles and its quads.
  std::vector<int> vertexNodes;
  for (int i : nodeOrder)
    if (m.nodeKind[i] == NodeKind::Vertex) vertexNodes.push_back(i);
  auto vertexKey = [&](int i) { return m.nodeEntity[i]; };
  auto segKey = [&](int s) { return m.segmentEdge[s]; };
  std::vector<int> segOrder = sortedBy(m.segments.size(), segKey);
  // Surface elements: index < T are triangles, index >= T quad (index - T).
  const int T = static_cast<int>(m.triangles.size());
  auto surfKey = [&](int e) {
    return e < T ? std::pair<int, int>(m.triangleFace[e], 0)
                 : std::pair<int, int>(m.quadFace[e - T], 1);
  };
  std::vector<int> surfOrder = sortedBy(m.triangles.size() + m.quads.size(), surfKey);

  std::size_t blocks = 0;
  auto countRun = [&](std::size_t, std::size_t) { ++blocks; };
  forEachRun(vertexNodes, vertexKey, countRun);
  forEachRun(segOrder, segKey, countRun);
  forEachRun(surfOrder, surfKey, countRun);
  auto tetKey = [&](int k) { return m.tetSolid[k]; };
  std::vector<int> tetOrder = sortedBy(m.tets.size(), tetKey);
  forEachRun(tetOrder, tetKey, countRun);
  const std::size_t numElems = vertexNodes.size() + segOrder.size() + surfOrder.size() + tetOrder.size();
  out << "$Elements\n"
      << blocks << ' ' << numElems << ' ' << (numElems ? 1 : 0) << ' ' << numElems << '\n';
  std::size_t tag = 0;
  forEachRun(vertexNodes, vertexKey, [&](std::size_t b, std::size_t e) {
    out << "0 " << m.nodeEntity[vertexNodes[b]] << " 15 " << (e - b) << '\n';
    for (std::size_t k = b; k < e; ++k) out << ++tag << ' ' << vertexNodes[k] + 1 << '\n';
  });
  forEachRun(segOrder, segKey, [&](std::size_t b, std::size_t e) {
    out << "1 " << m.segmentEdge[segOrder[b]] << ' ' << (o2 ? 8 : 1) << ' ' << (e - b) << '\n';
    for (std::size_t k = b; k < e; ++k) {
      int s = segOrder[k];
      out << ++tag << ' ' << m.segments[s][0] + 1 << ' ' << m.segments[s][1] + 1;
      if (o2) out << ' ' << m.segmentMid[s] + 1;
      out << '\n';
    }
  });
  forEachRun(surfOrder, surfKey, [&](std::size_t b, std::size_t e) {
    auto [face, isQuad] = surfKey(surfOrder[b]);
    int type = isQuad ? (o2 ? 16 : 3) : (o2 ? 9 : 2);
    out << "2 " << face << ' ' << type << ' ' << (e - b) << '\n';
    for (std::size_t k = b; k < e; ++k) {
      int el = surfOrder[k];
      out << ++tag;
      if (el < T) {
        for (int v : m.triangles[el]) out << ' ' << v + 1;
        if (o2)
          for (int v : m.triangleMid[el]) out << ' ' << v + 1;
      } else {
        for (int v : m.quads[el - T]) out << ' ' << v + 1;
        if (o2)
          for (int v : m.quadMid[el - T]) out << ' ' << v + 1;
      }
      out << '\n';
    }
  });
  // tet10: Gmsh's mid-node order is ab, bc, ca, da, dc, db (ours ab, bc, ca, ad, bd, cd)
  constexpr int kGmshMid[6] = {0, 1, 2, 3, 5, 4};
  forEachRun(tetOrder, tetKey, [&](std::size_t b, std::size_t e) {
    out << "3 " << m.tetSolid[tetOrder[b]] << ' ' << (o2 ? 11 : 4) << ' ' << (e - b) << '\n';
    for (std::size_t k = b; k < e; ++k) {
      const int t = tetOrder[k];
      out << ++tag;
      for (int v : m.tets[t]) out << ' ' << v + 1;
      if (o2)
        for (int i : kGmshMid) out << ' ' << m.tetMid[t][i] + 1;
      out << '\n';
    }
  });
  out << "$EndElements\n";
  out.commit();
}

}  // namespace paramesh
