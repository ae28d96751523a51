// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file StlWriter.cpp
/// The STL writer (binary and ASCII).
#include <algorithm>
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
// STL

namespace {

/// The facets as node triples, and the CAD face of each.
void facets(const SurfaceMesh& m, std::vector<std::array<int, 3>>& tris, std::vector<int>& face) {
  tris.reserve(m.triangles.size() + 2 * m.quads.size());
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    tris.push_back(m.triangles[t]);
    face.push_back(m.triangleFace[t]);
  }
  for (std::size_t k = 0; k < m.quads.size(); ++k) {
    const auto& q = m.quads[k];
    const Vec3 &a = m.nodes[q[0]], &b = m.nodes[q[1]], &c = m.nodes[q[2]], &d = m.nodes[q[3]];
    if (norm2(c - a) <= norm2(d - b)) {
      tris.push_back({q[0], q[1], q[2]});
      tris.push_back({q[0], q[2], q[3]});
    } else {
      tris.push_back({q[0], q[1], q[3]});
      tris.push_back({q[1], q[2], q[3]});
    }
    face.push_back(m.quadFace[k]);
    face.push_back(m.quadFace[k]);
  }
}

Vec3 facetNormal(const SurfaceMesh& m, const std::array<int, 3>& t) {
  const Vec3 &a = m.nodes[t[0]], &b = m.nodes[t[1]], &c = m.nodes[t[2]];
  Vec3 n = cross(b - a, c - a);
  double l = norm(n);
  return l > 0 && std::isfinite(l) ? n * (1.0 / l) : Vec3();
}

/// One ASCII "solid NAME ... endsolid NAME" of the facets `which`.
void asciiSolid(io::TextOut& out, const SurfaceMesh& m, const std::string& name,
                const std::vector<std::array<int, 3>>& tris, const std::vector<int>& which) {
  out << "solid " << name << '\n';
  for (int i : which) {
    const Vec3 n = facetNormal(m, tris[i]);
    out << "  facet normal " << n.x << ' ' << n.y << ' ' << n.z << "\n    outer loop\n";
    for (int v : tris[i]) {
      const Vec3& p = m.nodes[v];
      out << "      vertex " << p.x << ' ' << p.y << ' ' << p.z << '\n';
    }
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid " << name << '\n';
}

}  // namespace

void writeStlGroups(const std::string& path, const SurfaceMesh& m) {
  using namespace io;
  checkMeshForWriting(path, m);
  std::vector<std::array<int, 3>> tris;
  std::vector<int> face;
  facets(m, tris, face);
  // the user's face groups in their order (a facet in two goes to the first), then Face<i>
  std::vector<char> taken(tris.size(), 0);
  TextOut out(path);
  for (const MeshGroup& g : m.groups) {
    if (g.dim != 2) continue;
    std::vector<int> which;
    for (std::size_t i = 0; i < tris.size(); ++i)
      if (!taken[i] && std::find(g.entities.begin(), g.entities.end(), face[i]) != g.entities.end()) {
        which.push_back(int(i));
        taken[i] = 1;
      }
    if (!which.empty()) asciiSolid(out, m, g.name, tris, which);
  }
  std::map<int, std::vector<int>> rest;
  for (std::size_t i = 0; i < tris.size(); ++i)
    if (!taken[i]) rest[face[i]].push_back(int(i));
  for (const auto& [f, which] : rest) asciiSolid(out, m, "Face" + std::to_string(f), tris, which);
  out.commit();
}

void writeStl(const std::string& path, const SurfaceMesh& m, bool binary) {
  using namespace io;
  checkMeshForWriting(path, m);
  std::vector<std::array<int, 3>> tris;
  std::vector<int> face;
  facets(m, tris, face);
  if (tris.size() > 0xFFFFFFFFull)
    throw Error("cannot write '" + path + "': too many triangles for STL");
  auto normal = [&](const std::array<int, 3>& t) { return facetNormal(m, t); };

  if (!binary) {
    std::vector<int> all(tris.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = int(i);
    TextOut out(path);
    asciiSolid(out, m, "paramesh", tris, all);
    out.commit();
    return;
  }

  AtomicFile f(path);
  char header[80] = {};
  const char title[] = "ParaMesh binary STL";  // must not start with "solid"
  std::copy(title, title + sizeof title - 1, header);
  f.write(header, sizeof header);
  auto putU32 = [](unsigned char* p, uint32_t v) {
    for (int k = 0; k < 4; ++k) p[k] = static_cast<unsigned char>((v >> (8 * k)) & 0xFF);
  };
  auto putF32 = [&](unsigned char* p, double v) {
    float x = static_cast<float>(v);
    uint32_t u;
    static_assert(sizeof u == sizeof x, "32-bit float expected");
    std::memcpy(&u, &x, sizeof u);
    putU32(p, u);
  };
  unsigned char rec[50];
  putU32(rec, static_cast<uint32_t>(tris.size()));
  f.write(rec, 4);
  for (const auto& t : tris) {
    Vec3 n = normal(t);
    for (int k = 0; k < 3; ++k) putF32(rec + 4 * k, n[k]);
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k) putF32(rec + 12 + 12 * v + 4 * k, m.nodes[t[v]][k]);
    rec[48] = rec[49] = 0;
    f.write(rec, sizeof rec);
  }
  f.commit();
}

}  // namespace paramesh
