// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file StlWriter.cpp
/// The STL writer (binary and ASCII).
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>

#include "paramesh/io/WriterSupport.hpp"
#include "paramesh/util/Error.hpp"

namespace paramesh {

// ---------------------------------------------------------------------------------------------
// STL

void writeStl(const std::string& path, const SurfaceMesh& m, bool binary) {
  using namespace io;
  checkMeshForWriting(path, m);
  // Collect the facets as node triples.
  std::vector<std::array<int, 3>> tris;
  tris.reserve(m.triangles.size() + 2 * m.quads.size());
  for (const auto& t : m.triangles) tris.push_back(t);
  for (const auto& q : m.quads) {
    const Vec3 &a = m.nodes[q[0]], &b = m.nodes[q[1]], &c = m.nodes[q[2]], &d = m.nodes[q[3]];
    if (norm2(c - a) <= norm2(d - b)) {
      tris.push_back({q[0], q[1], q[2]});
      tris.push_back({q[0], q[2], q[3]});
    } else {
      tris.push_back({q[0], q[1], q[3]});
      tris.push_back({q[1], q[2], q[3]});
    }
  }
  if (tris.size() > 0xFFFFFFFFull)
    throw Error("cannot write '" + path + "': too many triangles for STL");
  auto normal = [&](const std::array<int, 3>& t) {
    const Vec3 &a = m.nodes[t[0]], &b = m.nodes[t[1]], &c = m.nodes[t[2]];
    Vec3 n = cross(b - a, c - a);
    double l = norm(n);
    return l > 0 && std::isfinite(l) ? n * (1.0 / l) : Vec3();
  };

  if (!binary) {
    TextOut out(path);
    out << "solid paramesh\n";
    for (const auto& t : tris) {
      Vec3 n = normal(t);
      out << "  facet normal " << n.x << ' ' << n.y << ' ' << n.z << "\n    outer loop\n";
      for (int v : t) {
        const Vec3& p = m.nodes[v];
        out << "      vertex " << p.x << ' ' << p.y << ' ' << p.z << '\n';
      }
      out << "    endloop\n  endfacet\n";
    }
    out << "endsolid paramesh\n";
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
