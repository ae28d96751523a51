// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file test_io.cpp
/// Tests of the mesh writers (MSH 4.1, STL, VTU, INP), the PNG renderer and the JSON writer on a
/// hand-built unit cube (6 CAD faces, 12 edges, 8 vertices) and its quad / order-2 variants.
/// Set PARAMESH_KEEP_TEST_FILES=1 to keep the written files (their directory is printed by the
/// test log), e.g. to check them with tests/tools/check_msh_meshio.py.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "paramesh/io/Json.hpp"
#include "paramesh/io/MeshWriters.hpp"
#include "paramesh/io/PngRender.hpp"
#include "paramesh/mesh/SurfaceMesh.hpp"
#include "paramesh/util/Error.hpp"
#include "io_fixtures.hpp"

namespace fs = std::filesystem;
using namespace paramesh;
using namespace paramesh::test;

namespace {

/// Node count of a Gmsh element type.
int gmshNodes(int type) {
  switch (type) {
    case 15: return 1;
    case 1: return 2;
    case 8: return 3;
    case 2: return 3;
    case 9: return 6;
    case 3: return 4;
    case 16: return 8;
    default: return -1;
  }
}

// ---------------------------------------------------------------------------------------------
// A small MSH 4.1 ASCII reader

struct Msh {
  std::string format;
  std::map<int, std::array<double, 6>> entities[3];  ///< tag -> box (points: x y z x y z)
  std::size_t declaredNodes = 0, declaredElems = 0;
  struct Node {
    int dim, entity;
    Vec3 p;
  };
  std::map<long, Node> nodes;
  struct Elem {
    long tag;
    int dim, entity, type;
    std::vector<long> nodes;
  };
  std::vector<Elem> elems;
};

Msh readMsh(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  Msh msh;
  std::string line;
  while (std::getline(in, line)) {
    if (line == "$MeshFormat") {
      std::getline(in, msh.format);
      std::getline(in, line);
      EXPECT_EQ(line, "$EndMeshFormat");
    } else if (line == "$PhysicalNames") {
      std::size_t n;
      in >> n;
      for (std::size_t i = 0; i < n; ++i) {
        int dim, tag;
        std::string name;
        in >> dim >> tag >> name;
        const char* kind[] = {"\"Vertex", "\"Edge", "\"Face", "\"Solid"};
        EXPECT_EQ(name, kind[dim] + std::to_string(tag) + "\"");
      }
      in >> line;
      EXPECT_EQ(line, "$EndPhysicalNames");
    } else if (line == "$Entities") {
      std::size_t n[4];
      in >> n[0] >> n[1] >> n[2] >> n[3];
      EXPECT_EQ(n[3], 0u);
      for (int d = 0; d < 3; ++d)
        for (std::size_t i = 0; i < n[d]; ++i) {
          int tag;
          std::array<double, 6> b{};
          in >> tag >> b[0] >> b[1] >> b[2];
          if (d == 0) {
            b[3] = b[0], b[4] = b[1], b[5] = b[2];
          } else {
            in >> b[3] >> b[4] >> b[5];
          }
          std::size_t nPhys, nBound;
          in >> nPhys;
          // an entity holding elements has its default group (Vertex<i> / Edge<i> / Face<i>:
          // tag = entity number) first; one holding only nodes has none
          std::vector<int> phys(nPhys);
          for (int& t : phys) in >> t;
          if (nPhys) EXPECT_EQ(phys[0], tag);
          if (d > 0) {
            in >> nBound;
            EXPECT_EQ(nBound, 0u);
          }
          EXPECT_TRUE(msh.entities[d].emplace(tag, b).second) << "duplicate entity " << tag;
        }
      in >> line;
      EXPECT_EQ(line, "$EndEntities");
    } else if (line == "$Nodes") {
      std::size_t blocks, minTag, maxTag;
      in >> blocks >> msh.declaredNodes >> minTag >> maxTag;
      for (std::size_t b = 0; b < blocks; ++b) {
        int dim, ent, param;
        std::size_t count;
        in >> dim >> ent >> param >> count;
        EXPECT_EQ(param, 0);
        std::vector<long> tags(count);
        for (auto& t : tags) in >> t;
        for (long t : tags) {
          Msh::Node n{dim, ent, {}};
          in >> n.p.x >> n.p.y >> n.p.z;
          EXPECT_TRUE(msh.nodes.emplace(t, n).second) << "node tag " << t << " written twice";
        }
      }
      if (msh.declaredNodes) {
        EXPECT_EQ(minTag, 1u);
        EXPECT_EQ(maxTag, msh.declaredNodes);
      }
      in >> line;
      EXPECT_EQ(line, "$EndNodes");
    } else if (line == "$Elements") {
      std::size_t blocks, minTag, maxTag;
      in >> blocks >> msh.declaredElems >> minTag >> maxTag;
      for (std::size_t b = 0; b < blocks; ++b) {
        int dim, ent, type;
        std::size_t count;
        in >> dim >> ent >> type >> count;
        int nn = gmshNodes(type);
        EXPECT_GT(nn, 0) << "unexpected element type " << type;
        for (std::size_t k = 0; k < count; ++k) {
          Msh::Elem e{0, dim, ent, type, std::vector<long>(std::max(nn, 0))};
          in >> e.tag;
          for (long& v : e.nodes) in >> v;
          msh.elems.push_back(e);
        }
      }
      if (msh.declaredElems) {
        EXPECT_EQ(minTag, 1u);
        EXPECT_EQ(maxTag, msh.declaredElems);
      }
      in >> line;
      EXPECT_EQ(line, "$EndElements");
    }
  }
  return msh;
}

// ---------------------------------------------------------------------------------------------
// Files

std::size_t countOf(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

/// Whitespace-separated values of the DataArray named name in a VTU text.
std::vector<std::string> vtuArray(const std::string& vtu, const std::string& name) {
  std::size_t p = vtu.find("Name=\"" + name + "\"");
  EXPECT_NE(p, std::string::npos) << name;
  if (p == std::string::npos) return {};
  p = vtu.find('>', p) + 1;
  std::size_t e = vtu.find("</DataArray>", p);
  std::istringstream in(vtu.substr(p, e - p));
  std::vector<std::string> v;
  for (std::string w; in >> w;) v.push_back(w);
  return v;
}

/// Checks an MSH file against the mesh it was written from.
void checkMsh(const std::string& path, const SurfaceMesh& m) {
  Msh msh = readMsh(path);
  EXPECT_EQ(msh.format, "4.1 0 8");
  // Nodes: each once, tags = index + 1, exact coordinates, in the entity they claim.
  ASSERT_EQ(msh.declaredNodes, m.nodes.size());
  ASSERT_EQ(msh.nodes.size(), m.nodes.size());
  for (const auto& [tag, n] : msh.nodes) {
    ASSERT_GE(tag, 1);
    ASSERT_LE(tag, static_cast<long>(m.nodes.size()));
    std::size_t i = static_cast<std::size_t>(tag - 1);
    EXPECT_EQ(n.p.x, m.nodes[i].x);
    EXPECT_EQ(n.p.y, m.nodes[i].y);
    EXPECT_EQ(n.p.z, m.nodes[i].z);
    EXPECT_EQ(n.dim, static_cast<int>(m.nodeKind[i]));
    EXPECT_EQ(n.entity, m.nodeEntity[i]);
    EXPECT_TRUE(msh.entities[n.dim].count(n.entity)) << "node entity missing from $Entities";
  }
  // Elements: consecutive tags; the multiset of (entity, type, nodes) equals the mesh's.
  ASSERT_EQ(msh.declaredElems, msh.elems.size());
  for (std::size_t k = 0; k < msh.elems.size(); ++k) EXPECT_EQ(msh.elems[k].tag, long(k + 1));
  const bool o2 = m.order == 2;
  std::multiset<std::pair<std::pair<int, int>, std::vector<long>>> expect, got;
  auto add = [&](int ent, int type, std::vector<long> v) {
    expect.insert({{ent, type}, std::move(v)});
  };
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    if (m.nodeKind[i] == NodeKind::Vertex) add(m.nodeEntity[i], 15, {long(i) + 1});
  for (std::size_t s = 0; s < m.segments.size(); ++s) {
    std::vector<long> v{m.segments[s][0] + 1L, m.segments[s][1] + 1L};
    if (o2) v.push_back(m.segmentMid[s] + 1L);
    add(m.segmentEdge[s], o2 ? 8 : 1, v);
  }
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    std::vector<long> v;
    for (int n : m.triangles[t]) v.push_back(n + 1L);
    if (o2)
      for (int n : m.triangleMid[t]) v.push_back(n + 1L);
    add(m.triangleFace[t], o2 ? 9 : 2, v);
  }
  for (std::size_t q = 0; q < m.quads.size(); ++q) {
    std::vector<long> v;
    for (int n : m.quads[q]) v.push_back(n + 1L);
    if (o2)
      for (int n : m.quadMid[q]) v.push_back(n + 1L);
    add(m.quadFace[q], o2 ? 16 : 3, v);
  }
  std::map<int, int> dimOfType = {{15, 0}, {1, 1}, {8, 1}, {2, 2}, {9, 2}, {3, 2}, {16, 2}};
  for (const auto& e : msh.elems) {
    EXPECT_EQ(e.dim, dimOfType[e.type]);
    EXPECT_TRUE(msh.entities[e.dim].count(e.entity)) << "element entity missing from $Entities";
    for (long v : e.nodes) EXPECT_TRUE(msh.nodes.count(v)) << "element uses unknown node " << v;
    got.insert({{e.entity, e.type}, e.nodes});
  }
  EXPECT_TRUE(expect == got) << "elements differ from the mesh";
  // Entity boxes contain their elements' nodes.
  for (const auto& e : msh.elems) {
    const auto& b = msh.entities[e.dim].at(e.entity);
    for (long v : e.nodes) {
      const Vec3& p = msh.nodes.at(v).p;
      for (int k = 0; k < 3; ++k) {
        EXPECT_LE(b[k], p[k]);
        EXPECT_GE(b[k + 3], p[k]);
      }
    }
  }
}

std::map<int, std::size_t> typeCounts(const std::string& path) {
  std::map<int, std::size_t> c;
  for (const auto& e : readMsh(path).elems) ++c[e.type];
  return c;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// MSH 4.1

TEST_F(IoTest, MshCubeTriangles) {
  SurfaceMesh m = makeCube(false, 1);
  ASSERT_EQ(m.nodes.size(), 8u);
  std::string p = file("cube.msh");
  writeMsh41(p, m);
  checkMsh(p, m);
  Msh msh = readMsh(p);
  EXPECT_EQ(msh.entities[0].size(), 8u);
  EXPECT_EQ(msh.entities[1].size(), 12u);
  EXPECT_EQ(msh.entities[2].size(), 6u);
  for (int f = 1; f <= 6; ++f) EXPECT_TRUE(msh.entities[2].count(f)) << f;
  EXPECT_EQ(msh.nodes.size(), 8u);  // corners shared by 3 faces, written once
  auto c = typeCounts(p);
  EXPECT_EQ(c[15], 8u);
  EXPECT_EQ(c[1], 12u);
  EXPECT_EQ(c[2], 12u);
  EXPECT_EQ(c.size(), 3u);
  // Each face entity holds exactly its two triangles, whose nodes lie on that cube side.
  std::map<int, int> perFace;
  for (const auto& e : msh.elems)
    if (e.type == 2) {
      ++perFace[e.entity];
      const Vec3& n = kCubeNormals[e.entity - 1];
      for (long v : e.nodes) {
        const Vec3& q = msh.nodes.at(v).p;
        EXPECT_DOUBLE_EQ(dot(q - Vec3(0.5, 0.5, 0.5), n), 0.5);
      }
    }
  for (int f = 1; f <= 6; ++f) EXPECT_EQ(perFace[f], 2) << "face " << f;
  // Entity box of face 2 (x = 1).
  const auto& b = msh.entities[2].at(2);
  EXPECT_EQ(b[0], 1.0);
  EXPECT_EQ(b[3], 1.0);
  EXPECT_EQ(b[1], 0.0);
  EXPECT_EQ(b[4], 1.0);
}

TEST_F(IoTest, MshQuadAndOrder2) {
  {
    SurfaceMesh m = makeCube(true, 1);
    std::string p = file("cube_quad.msh");
    writeMsh41(p, m);
    checkMsh(p, m);
    auto c = typeCounts(p);
    EXPECT_EQ(c[2], 10u);
    EXPECT_EQ(c[3], 1u);
    for (const auto& e : readMsh(p).elems) {
      if (e.type == 3) {
        EXPECT_EQ(e.entity, 6);
      }
    }
  }
  {
    SurfaceMesh m = makeCube(false, 2);
    ASSERT_EQ(m.nodes.size(), 8u + 12u + 6u);
    std::string p = file("cube_o2.msh");
    writeMsh41(p, m);
    checkMsh(p, m);
    auto c = typeCounts(p);
    EXPECT_EQ(c[15], 8u);
    EXPECT_EQ(c[8], 12u);
    EXPECT_EQ(c[9], 12u);
    Msh msh = readMsh(p);
    // Mid-nodes are in their entities: 12 on curves, 6 on surfaces.
    int onCurve = 0, onSurface = 0;
    for (const auto& entry : msh.nodes) {
      onCurve += entry.second.dim == 1;
      onSurface += entry.second.dim == 2;
    }
    EXPECT_EQ(onCurve, 12);
    EXPECT_EQ(onSurface, 6);
  }
  {
    SurfaceMesh m = makeCube(true, 2);
    std::string p = file("cube_quad_o2.msh");
    writeMsh41(p, m);
    checkMsh(p, m);
    auto c = typeCounts(p);
    EXPECT_EQ(c[9], 10u);
    EXPECT_EQ(c[16], 1u);
    EXPECT_EQ(c[8], 12u);
  }
}

TEST_F(IoTest, MshOrphanNodesGetTheirEntity) {
  SurfaceMesh m = makeCube(false, 1);
  m.addNode({2, 2, 2}, NodeKind::Face, 9);   // claims a face without elements
  m.addNode({3, 3, 3}, NodeKind::Edge, 20);  // claims an edge without segments
  std::string p = file("orphans.msh");
  writeMsh41(p, m);
  checkMsh(p, m);
  Msh msh = readMsh(p);
  EXPECT_TRUE(msh.entities[2].count(9));
  EXPECT_TRUE(msh.entities[1].count(20));
  EXPECT_EQ(msh.entities[2].at(9)[0], 2.0);
  EXPECT_EQ(msh.nodes.at(9).entity, 9);
  EXPECT_EQ(msh.nodes.at(10).dim, 1);
}

TEST_F(IoTest, MshEmptyMesh) {
  SurfaceMesh m;
  std::string p = file("empty.msh");
  writeMsh41(p, m);
  Msh msh = readMsh(p);
  EXPECT_EQ(msh.format, "4.1 0 8");
  EXPECT_EQ(msh.nodes.size(), 0u);
  EXPECT_EQ(msh.elems.size(), 0u);
  EXPECT_EQ(countOf(readFile(p), "$Nodes"), 0u);  // Gmsh writes no empty sections either
}

// ---------------------------------------------------------------------------------------------
// STL

TEST_F(IoTest, StlBinaryAndAscii) {
  for (bool quadTop : {false, true}) {
    SurfaceMesh m = makeCube(quadTop, 1);
    std::string p = file(quadTop ? "quad.stl" : "tri.stl");
    writeStl(p, m, true);
    std::string s = readFile(p);
    ASSERT_EQ(s.size(), 84u + 50u * 12u);  // the quad counts as two triangles
    EXPECT_NE(s.compare(0, 5, "solid"), 0);
    uint32_t n = 0;
    for (int k = 0; k < 4; ++k) n |= uint32_t(uint8_t(s[80 + k])) << (8 * k);
    EXPECT_EQ(n, 12u);
    auto f32 = [&](std::size_t off) {
      uint32_t u = 0;
      for (int k = 0; k < 4; ++k) u |= uint32_t(uint8_t(s[off + k])) << (8 * k);
      float f;
      std::memcpy(&f, &u, 4);
      return double(f);
    };
    for (uint32_t t = 0; t < n; ++t) {
      std::size_t r = 84 + 50 * std::size_t(t);
      Vec3 nrm{f32(r), f32(r + 4), f32(r + 8)};
      Vec3 v[3];
      for (int i = 0; i < 3; ++i) v[i] = {f32(r + 12 + 12 * i), f32(r + 16 + 12 * i), f32(r + 20 + 12 * i)};
      EXPECT_NEAR(norm(nrm), 1.0, 1e-6);
      Vec3 expect = normalized(cross(v[1] - v[0], v[2] - v[0]));
      EXPECT_NEAR(norm(nrm - expect), 0.0, 1e-6);
      // Outward: along the direction from the cube centre to the facet centroid.
      Vec3 c = (1.0 / 3) * (v[0] + v[1] + v[2]) - Vec3(0.5, 0.5, 0.5);
      EXPECT_NEAR(dot(nrm, c), 0.5, 1e-6);
    }
  }
  SurfaceMesh m = makeCube(true, 1);
  std::string p = file("ascii.stl");
  writeStl(p, m, false);
  std::string s = readFile(p);
  EXPECT_EQ(s.compare(0, 14, "solid paramesh"), 0);
  EXPECT_EQ(countOf(s, "facet normal"), 12u);
  EXPECT_EQ(countOf(s, "vertex "), 36u);
  EXPECT_EQ(countOf(s, "endsolid"), 1u);
}

// ---------------------------------------------------------------------------------------------
// VTU

TEST_F(IoTest, Vtu) {
  struct Case {
    bool quad;
    int order;
    const char* tri;
    const char* qd;
  };
  for (const Case& c : {Case{false, 1, "5", "9"}, Case{true, 1, "5", "9"},
                        Case{true, 2, "22", "23"}}) {
    SurfaceMesh m = makeCube(c.quad, c.order);
    std::string p = file("cube.vtu");
    writeVtu(p, m);
    std::string s = readFile(p);
    const std::size_t cells = m.triangles.size() + m.quads.size();
    EXPECT_NE(s.find("NumberOfPoints=\"" + std::to_string(m.nodes.size()) + "\""), std::string::npos);
    EXPECT_NE(s.find("NumberOfCells=\"" + std::to_string(cells) + "\""), std::string::npos);
    auto types = vtuArray(s, "types");
    ASSERT_EQ(types.size(), cells);
    EXPECT_EQ(std::size_t(std::count(types.begin(), types.end(), c.tri)), m.triangles.size());
    EXPECT_EQ(std::size_t(std::count(types.begin(), types.end(), c.qd)), m.quads.size());
    auto offsets = vtuArray(s, "offsets");
    std::size_t perTri = c.order == 2 ? 6 : 3, perQuad = c.order == 2 ? 8 : 4;
    ASSERT_EQ(offsets.size(), cells);
    EXPECT_EQ(offsets.back(), std::to_string(perTri * m.triangles.size() + perQuad * m.quads.size()));
    EXPECT_EQ(vtuArray(s, "connectivity").size(), perTri * m.triangles.size() + perQuad * m.quads.size());
    auto face = vtuArray(s, "face");
    ASSERT_EQ(face.size(), cells);
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
      EXPECT_EQ(face[t], std::to_string(m.triangleFace[t]));
    auto quality = vtuArray(s, "quality");
    ASSERT_EQ(quality.size(), cells);
    for (std::size_t t = 0; t < m.triangles.size(); ++t)  // right isosceles: 2 (sqrt2 - 1)
      EXPECT_NEAR(std::stod(quality[t]), 2 * (std::sqrt(2.0) - 1), 1e-12);
    for (std::size_t q = 0; q < m.quads.size(); ++q)
      EXPECT_NEAR(std::stod(quality[m.triangles.size() + q]), 1.0, 1e-12);
    EXPECT_EQ(vtuArray(s, "entity_dim").size(), m.nodes.size());
    EXPECT_EQ(vtuArray(s, "entity").size(), m.nodes.size());
    EXPECT_NE(s.find("</VTKFile>"), std::string::npos);
  }
}

// ---------------------------------------------------------------------------------------------
// INP

TEST_F(IoTest, Inp) {
  struct Case {
    bool quad;
    int order;
    const char* triType;
    const char* quadType;
    std::size_t triNodes, quadNodes;
  };
  for (const Case& c : {Case{true, 1, "S3", "S4", 3, 4}, Case{true, 2, "S6", "S8", 6, 8}}) {
    SurfaceMesh m = makeCube(c.quad, c.order);
    std::string p = file("cube.inp");
    writeMesh(p, m);
    std::istringstream in(readFile(p));
    std::string line, section, type;
    std::size_t nodes = 0;
    std::map<std::string, std::size_t> elems;  // per type
    std::map<long, std::string> typeOf;
    std::map<std::string, std::pair<long, long>> sets;
    std::string pendingSet;
    while (std::getline(in, line)) {
      if (line.empty()) continue;
      if (line[0] == '*') {
        section = line.substr(0, line.find(','));
        if (section == "*ELEMENT") type = line.substr(line.find("TYPE=") + 5);
        if (section == "*ELSET") {
          EXPECT_NE(line.find("GENERATE"), std::string::npos);
          std::size_t a = line.find("ELSET=") + 6;
          pendingSet = line.substr(a, line.find(',', a) - a);
        }
        continue;
      }
      if (section != "*NODE" && section != "*ELEMENT" && section != "*ELSET") continue;
      std::vector<long> v;
      std::istringstream ls(line);
      for (std::string w; std::getline(ls, w, ',');) v.push_back(std::stol(w));
      if (section == "*NODE") {
        ++nodes;
        EXPECT_EQ(v[0], long(nodes));
      } else if (section == "*ELEMENT") {
        ++elems[type];
        typeOf[v[0]] = type;
        EXPECT_EQ(v.size() - 1, type == c.triType ? c.triNodes : c.quadNodes);
      } else if (section == "*ELSET") {
        ASSERT_EQ(v.size(), 3u);
        sets[pendingSet] = {v[0], v[1]};
      }
    }
    EXPECT_EQ(nodes, m.nodes.size());
    EXPECT_EQ(elems[c.triType], 10u);
    EXPECT_EQ(elems[c.quadType], 1u);
    ASSERT_EQ(sets.size(), 6u);
    long total = 0;
    for (int f = 1; f <= 6; ++f) {
      auto it = sets.find("Face" + std::to_string(f));
      ASSERT_NE(it, sets.end()) << f;
      total += it->second.second - it->second.first + 1;
      EXPECT_EQ(it->second.second - it->second.first + 1, f == 6 ? 1 : 2);
      if (f == 6) {
        EXPECT_EQ(typeOf[it->second.first], c.quadType);
      }
    }
    EXPECT_EQ(total, 11);
  }
}

// ---------------------------------------------------------------------------------------------
// Dispatch and errors

TEST_F(IoTest, WriteMeshDispatchAndErrors) {
  SurfaceMesh m = makeCube(false, 1);
  writeMesh(file("a.MSH"), m);
  EXPECT_EQ(readFile(file("a.MSH")).compare(0, 11, "$MeshFormat"), 0);
  writeMesh(file("a.vtu"), m);
  EXPECT_EQ(readFile(file("a.vtu")).compare(0, 5, "<?xml"), 0);
  writeMesh(file("a.stl"), m);
  EXPECT_EQ(readFile(file("a.stl")).size(), 84u + 50u * 12u);
  try {
    writeMesh(file("a.xyz"), m);
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unsupported output format '.xyz'"), std::string::npos);
  }
  EXPECT_THROW(writeMesh(file("noextension"), m), Error);
  // Unwritable path: the message names it.
  std::string bad = file("no_such_dir/x.msh");
  try {
    writeMsh41(bad, m);
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
  // An inconsistent mesh throws and leaves an existing file (and the directory) untouched.
  std::string before = readFile(file("a.vtu"));
  auto files = listing();
  SurfaceMesh broken = m;
  broken.triangles[3][1] = 100;
  for (const char* ext : {"a.msh", "a.vtu", "a.stl", "a.inp"})
    EXPECT_THROW(writeMesh(file(ext), broken), Error) << ext;
  EXPECT_EQ(readFile(file("a.vtu")), before);
  EXPECT_EQ(listing(), files);
  SurfaceMesh missingMid = makeCube(false, 2);
  missingMid.triangleMid.pop_back();
  EXPECT_THROW(writeMsh41(file("o2.msh"), missingMid), Error);
  EXPECT_EQ(listing(), files);
}

TEST(IoAtomicFile, UncommittedLeavesNothing) {
  fs::path dir = fs::path(::testing::TempDir()) / "paramesh_io_atomic";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string p = (dir / "f.txt").string();
  {
    io::AtomicFile f(p);
    f.write("partial");
  }  // destroyed without commit
  EXPECT_TRUE(fs::is_empty(dir));
  {
    io::AtomicFile f(p);
    f.write("done");
    f.commit();
  }
  EXPECT_EQ(readFile(p), "done");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  fs::remove_all(dir);
}

// ---------------------------------------------------------------------------------------------
// Quality

TEST(IoQuality, TriangleAndQuad) {
  EXPECT_NEAR(io::triangleGamma({0, 0, 0}, {1, 0, 0}, {0.5, std::sqrt(3.0) / 2, 0}), 1.0, 1e-12);
  EXPECT_NEAR(io::triangleGamma({0, 0, 0}, {1, 0, 0}, {0, 1, 0}), 2 * (std::sqrt(2.0) - 1), 1e-12);
  EXPECT_EQ(io::triangleGamma({0, 0, 0}, {1, 0, 0}, {2, 0, 0}), 0.0);
  EXPECT_EQ(io::triangleGamma({0, 0, 0}, {0, 0, 0}, {0, 0, 0}), 0.0);
  EXPECT_NEAR(io::quadQuality({0, 0, 0}, {3, 0, 0}, {3, 1, 0}, {0, 1, 0}), 1.0, 1e-12);
  EXPECT_NEAR(io::quadQuality({0, 0, 0}, {1, 0, 0}, {2, 1, 0}, {1, 1, 0}), std::sqrt(0.5), 1e-12);
  EXPECT_LT(io::quadQuality({0, 0, 0}, {2, 0, 0}, {0.5, 0.5, 0}, {0, 2, 0}), 0.0);  // non-convex
  EXPECT_EQ(io::quadQuality({0, 0, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}), 0.0);
}


// ---------------------------------------------------------------------------------------------
// JSON

TEST(IoJson, Dump) {
  Json j = Json::object();
  j["int"] = 3;
  j["neg"] = -42L;
  j["big"] = 1234567890123LL;
  j["dbl"] = 0.1;
  j["third"] = 1.0 / 3.0;
  j["whole"] = 2.0;
  j["nan"] = std::nan("");
  j["inf"] = -HUGE_VAL;
  j["t"] = true;
  j["n"] = nullptr;
  j["s"] = "a\"b\\c\n\t\x01 é";
  j["list"].push(Json(1.5));
  j["list"].push(Json("x"));
  j["list"].push(Json::object());
  j["empty"] = Json::array();
  j["int"] = 4;  // overwrite keeps the position
  EXPECT_EQ(j.dump(),
            "{\"int\":4,\"neg\":-42,\"big\":1234567890123,\"dbl\":0.1,"
            "\"third\":0.3333333333333333,\"whole\":2,\"nan\":null,\"inf\":null,\"t\":true,"
            "\"n\":null,\"s\":\"a\\\"b\\\\c\\n\\t\\u0001 é\",\"list\":[1.5,\"x\",{}],\"empty\":[]}");
  EXPECT_EQ(j.size(), 13u);
  EXPECT_TRUE(j.contains("list"));
  EXPECT_FALSE(j.contains("nope"));
  EXPECT_EQ(j.at("list").size(), 3u);
  EXPECT_THROW(j.at("nope"), Error);
  EXPECT_THROW(j["int"].push(Json(1)), Error);
  EXPECT_THROW(j["list"]["k"], Error);

  Json p = Json::object();
  p["a"] = 1;
  p["b"].push(Json(2));
  p["b"].push(Json(3));
  EXPECT_EQ(p.dump(2), "{\n  \"a\": 1,\n  \"b\": [\n    2,\n    3\n  ]\n}");
  // Invalid UTF-8 is replaced so the output stays valid JSON.
  EXPECT_EQ(Json(std::string("x\xff")).dump(), "\"x\\ufffd\"");
  EXPECT_EQ(Json(1e300).dump(), "1e+300");
  EXPECT_EQ(Json(static_cast<unsigned long long>(-1)).dump(), "18446744073709551616");  // a double
}
