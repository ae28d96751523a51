// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file io_fixtures.hpp
/// Helpers shared by the writer and renderer tests (test_io.cpp, test_render.cpp): the hand-built
/// unit cube mesh, reading a file back, and a fixture with a fresh directory per test.
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <string>

#include "paramesh/mesh/SurfaceMesh.hpp"

namespace paramesh::test {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Test meshes

/// Cube corner i = (x,y,z) bits; faces listed counter-clockwise seen from outside.
inline constexpr int kCubeFaces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                              {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
inline const Vec3 kCubeNormals[6] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};

/// Unit cube: 8 vertex nodes, one segment per CAD edge, each face two triangles (a,b,c),(a,c,d)
/// or, with quadTop, face 6 one quad. Order 2 adds edge mid-nodes (NodeKind::Edge) and face
/// diagonal mid-nodes (NodeKind::Face).
inline SurfaceMesh makeCube(bool quadTop, int order) {
  SurfaceMesh m;
  m.order = order;
  m.numFaces = 6, m.numEdges = 12, m.numVertices = 8;
  for (int i = 0; i < 8; ++i)
    m.addNode({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)}, NodeKind::Vertex, i + 1);
  std::map<std::pair<int, int>, int> mids;
  auto key = [](int a, int b) { return std::make_pair(std::min(a, b), std::max(a, b)); };
  for (const auto& f : kCubeFaces)
    for (int k = 0; k < 4; ++k) {
      int a = f[k], b = f[(k + 1) % 4];
      if (mids.count(key(a, b))) continue;
      int edge = static_cast<int>(m.segments.size()) + 1;
      m.segments.push_back({a, b});
      m.segmentEdge.push_back(edge);
      int mid = -1;
      if (order == 2) {
        mid = m.addNode(0.5 * (m.nodes[a] + m.nodes[b]), NodeKind::Edge, edge, {0.5, 0});
        m.segmentMid.push_back(mid);
      }
      mids[key(a, b)] = mid;
    }
  for (int f = 0; f < 6; ++f) {
    const int* q = kCubeFaces[f];
    auto mid = [&](int a, int b) {  // edge mid-node, or a new face node on the diagonal
      auto it = mids.find(key(a, b));
      if (it != mids.end()) return it->second;
      int n = m.addNode(0.5 * (m.nodes[a] + m.nodes[b]), NodeKind::Face, f + 1, {0.5, 0.5});
      mids[key(a, b)] = n;
      return n;
    };
    if (quadTop && f == 5) {
      m.quads.push_back({q[0], q[1], q[2], q[3]});
      m.quadFace.push_back(f + 1);
      if (order == 2)
        m.quadMid.push_back({mid(q[0], q[1]), mid(q[1], q[2]), mid(q[2], q[3]), mid(q[3], q[0])});
      continue;
    }
    for (const auto& t : {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
      m.triangles.push_back(t);
      m.triangleFace.push_back(f + 1);
      if (order == 2) m.triangleMid.push_back({mid(t[0], t[1]), mid(t[1], t[2]), mid(t[2], t[0])});
    }
  }
  return m;
}

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class IoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) / (std::string("paramesh_io_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (std::getenv("PARAMESH_KEEP_TEST_FILES"))
      std::cout << "[ files    ] kept in " << dir_.string() << "\n";
    else
      fs::remove_all(dir_);
  }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  /// Files in the test directory (to check that no temporary file is left behind).
  std::set<std::string> listing() const {
    std::set<std::string> s;
    for (const auto& e : fs::directory_iterator(dir_)) s.insert(e.path().filename().string());
    return s;
  }
  fs::path dir_;
};

}  // namespace paramesh::test
