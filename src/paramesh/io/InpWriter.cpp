// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file InpWriter.cpp
/// The Abaqus / CalculiX input writer.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <algorithm>
#include <map>
#include <unordered_map>

#include "paramesh/io/Groups.hpp"
#include "paramesh/io/WriterSupport.hpp"
#include "paramesh/util/Error.hpp"

namespace paramesh {

// ---------------------------------------------------------------------------------------------
// Abaqus / CalculiX

namespace {

/// Numbers as Abaqus set data lines: 16 to a line.
void writeList(io::TextOut& out, const std::vector<int>& ids) {
  for (std::size_t i = 0; i < ids.size(); ++i) out << ids[i] << ((i % 16 == 15 || i + 1 == ids.size()) ? "\n" : ", ");
}

/// The 1-based nodes of the segments on each edge of the user's edge groups: *NSET, NSET=<name>.
void writeEdgeGroups(io::TextOut& out, const SurfaceMesh& m) {
  for (const MeshGroup& g : m.groups) {
    if (g.dim != 1) continue;
    std::vector<int> nodes;
    for (std::size_t s = 0; s < m.segments.size(); ++s)
      if (std::find(g.entities.begin(), g.entities.end(), m.segmentEdge[s]) != g.entities.end()) {
        nodes.push_back(m.segments[s][0] + 1);
        nodes.push_back(m.segments[s][1] + 1);
        if (m.order == 2) nodes.push_back(m.segmentMid[s] + 1);
      }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    if (nodes.empty()) continue;
    out << "*NSET, NSET=" << g.name << '\n';
    writeList(out, nodes);
  }
}

/// The tetrahedra per solid (C3D4 / C3D10 with an ELSET each), then per CAD face its nodes and
/// its tetrahedron faces (CalculiX face numbers: S1 = 123, S2 = 142, S3 = 243, S4 = 341).
void writeInpVolume(io::TextOut& out, const SurfaceMesh& m) {
  using namespace io;
  const bool o2 = m.order == 2;
  auto tetKey = [&](int k) { return m.tetSolid[k]; };
  const std::vector<int> order = sortedBy(m.tets.size(), tetKey);
  out << "*ELEMENT, TYPE=" << (o2 ? "C3D10" : "C3D4") << '\n';
  for (std::size_t k = 0; k < order.size(); ++k) {
    const int t = order[k];
    out << k + 1;
    for (int v : m.tets[t]) out << ", " << v + 1;
    if (o2)
      for (int v : m.tetMid[t]) out << ", " << v + 1;
    out << '\n';
  }
  std::map<int, std::pair<std::size_t, std::size_t>> solidRange;  // solid -> its 1-based elements [b, e]
  forEachRun(order, tetKey, [&](std::size_t b, std::size_t e) {
    out << "*ELSET, ELSET=Solid" << tetKey(order[b]) << ", GENERATE\n" << b + 1 << ", " << e << ", 1\n";
    solidRange[tetKey(order[b])] = {b + 1, e};
  });
  for (const MeshGroup& g : m.groups) {
    if (g.dim != 3) continue;
    std::vector<std::pair<std::size_t, std::size_t>> runs;
    for (int s : g.entities)
      if (const auto it = solidRange.find(s); it != solidRange.end()) runs.push_back(it->second);
    if (runs.empty()) continue;
    out << "*ELSET, ELSET=" << g.name << ", GENERATE\n";
    for (const auto& [b, e] : runs) out << b << ", " << e << ", 1\n";
  }
  // tetrahedron faces by their sorted node triple -> (element, face number)
  constexpr int kFace[4][3] = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
  auto key = [](int a, int b, int c) {
    std::array<int, 3> v{a, b, c};
    std::sort(v.begin(), v.end());
    return (std::uint64_t(v[0]) * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t(v[1]) << 21) ^ std::uint64_t(v[2]);
  };
  std::unordered_multimap<std::uint64_t, std::pair<int, int>> tetFace;
  tetFace.reserve(m.tets.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const auto& t = m.tets[order[k]];
    for (int f = 0; f < 4; ++f)
      tetFace.emplace(key(t[kFace[f][0]], t[kFace[f][1]], t[kFace[f][2]]), std::make_pair(int(k) + 1, f + 1));
  }
  auto sameNodes = [&](const std::array<int, 4>& t, int f, const std::array<int, 3>& tri) {
    std::array<int, 3> a{t[kFace[f][0]], t[kFace[f][1]], t[kFace[f][2]]}, b = tri;
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    return a == b;
  };
  auto faceKey = [&](int t) { return m.triangleFace[t]; };
  const std::vector<int> tris = sortedBy(m.triangles.size(), faceKey);
  std::map<int, std::vector<int>> faceNodes;                    // 0-based
  std::map<int, std::vector<std::pair<int, int>>> faceSides;   // (element, CalculiX face)
  forEachRun(tris, faceKey, [&](std::size_t b, std::size_t e) {
    const int face = faceKey(tris[b]);
    std::vector<int> nodes;
    for (std::size_t k = b; k < e; ++k) {
      const int t = tris[k];
      nodes.insert(nodes.end(), m.triangles[t].begin(), m.triangles[t].end());
      if (o2) nodes.insert(nodes.end(), m.triangleMid[t].begin(), m.triangleMid[t].end());
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    out << "*NSET, NSET=Face" << face << '\n';
    for (std::size_t i = 0; i < nodes.size(); ++i) out << nodes[i] + 1 << ((i % 16 == 15 || i + 1 == nodes.size()) ? ",\n" : ", ");
    std::vector<std::pair<int, int>> sides;  // a face between two solids: both tetrahedra's sides
    for (std::size_t k = b; k < e; ++k) {
      const auto& tri = m.triangles[tris[k]];
      auto range = tetFace.equal_range(key(tri[0], tri[1], tri[2]));
      for (auto it = range.first; it != range.second; ++it)
        if (sameNodes(m.tets[order[it->second.first - 1]], it->second.second - 1, tri)) sides.push_back(it->second);
    }
    faceNodes[face] = nodes;
    faceSides[face] = sides;
    if (sides.empty()) return;
    out << "*SURFACE, NAME=Face" << face << ", TYPE=ELEMENT\n";
    for (const auto& [el, f] : sides) out << el << ", S" << f << '\n';
  });
  // the user's face groups: the union of their faces' node sets and element-face surfaces
  for (const MeshGroup& g : m.groups) {
    if (g.dim != 2) continue;
    std::vector<int> nodes;
    std::vector<std::pair<int, int>> sides;
    for (int f : g.entities) {
      for (int v : faceNodes[f]) nodes.push_back(v + 1);
      sides.insert(sides.end(), faceSides[f].begin(), faceSides[f].end());
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    if (!nodes.empty()) {
      out << "*NSET, NSET=" << g.name << '\n';
      writeList(out, nodes);
    }
    if (!sides.empty()) {
      out << "*SURFACE, NAME=" << g.name << ", TYPE=ELEMENT\n";
      for (const auto& [el, f] : sides) out << el << ", S" << f << '\n';
    }
  }
  writeEdgeGroups(out, m);
}

}  // namespace

void writeInp(const std::string& path, const SurfaceMesh& m) {
  using namespace io;
  checkMeshForWriting(path, m);
  const bool o2 = m.order == 2;
  TextOut out(path);
  out << (m.tets.empty() ? "*HEADING\nParaMesh surface mesh\n*NODE\n" : "*HEADING\nParaMesh volume mesh\n*NODE\n");
  for (std::size_t i = 0; i < m.nodes.size(); ++i) {
    const Vec3& p = m.nodes[i];
    // CalculiX reads at most 20 characters per number: 12 significant digits always fit
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.12g, %.12g, %.12g", p.x, p.y, p.z);
    out << i + 1 << ", " << buf << '\n';
  }
  if (!m.tets.empty()) {
    writeInpVolume(out, m);
    out.commit();
    return;
  }
  const int T = static_cast<int>(m.triangles.size());
  auto surfKey = [&](int e) {
    return e < T ? std::pair<int, int>(m.triangleFace[e], 0)
                 : std::pair<int, int>(m.quadFace[e - T], 1);
  };
  std::vector<int> order = sortedBy(m.triangles.size() + m.quads.size(), surfKey);
  int lastType = -1;  // a new *ELEMENT header only when the element type changes
  forEachRun(order, surfKey, [&](std::size_t b, std::size_t e) {
    bool quad = surfKey(order[b]).second == 1;
    if (lastType != int(quad))
      out << "*ELEMENT, TYPE=" << (quad ? (o2 ? "S8" : "S4") : (o2 ? "S6" : "S3")) << '\n';
    lastType = int(quad);
    for (std::size_t k = b; k < e; ++k) {
      int el = order[k];
      out << k + 1;
      if (!quad) {
        for (int v : m.triangles[el]) out << ", " << v + 1;
        if (o2)
          for (int v : m.triangleMid[el]) out << ", " << v + 1;
      } else {
        for (int v : m.quads[el - T]) out << ", " << v + 1;
        if (o2)
          for (int v : m.quadMid[el - T]) out << ", " << v + 1;
      }
      out << '\n';
    }
  });
  // Elements are numbered face by face, so each face's set is one contiguous range.
  auto faceKey = [&](int e) { return surfKey(e).first; };
  std::map<int, std::vector<std::pair<std::size_t, std::size_t>>> faceRanges;  // face -> [b, e] runs
  forEachRun(order, faceKey, [&](std::size_t b, std::size_t e) {
    out << "*ELSET, ELSET=Face" << faceKey(order[b]) << ", GENERATE\n"
        << b + 1 << ", " << e << ", 1\n";
    faceRanges[faceKey(order[b])].push_back({b + 1, e});
  });
  // the boundary-layer elements of each spec, and the user's face groups
  std::map<int, std::vector<int>> layer;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const int el = order[k];
    const int spec = el < T ? (m.triangleLayer.empty() ? 0 : m.triangleLayer[el])
                            : (m.quadLayer.empty() ? 0 : m.quadLayer[el - T]);
    if (spec > 0) layer[spec].push_back(int(k) + 1);
  }
  for (const auto& [spec, ids] : layer) {
    out << "*ELSET, ELSET=BoundaryLayer" << spec << '\n';
    writeList(out, ids);
  }
  for (const MeshGroup& g : m.groups) {
    if (g.dim != 2) continue;
    std::vector<std::pair<std::size_t, std::size_t>> runs;
    for (int f : g.entities) runs.insert(runs.end(), faceRanges[f].begin(), faceRanges[f].end());
    if (runs.empty()) continue;
    out << "*ELSET, ELSET=" << g.name << ", GENERATE\n";
    for (const auto& [b, e] : runs) out << b << ", " << e << ", 1\n";
  }
  writeEdgeGroups(out, m);
  out.commit();
}

}  // namespace paramesh
