// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Su2Writer.cpp
/// The SU2 native mesh writer (SU2's "Mesh File Format (native)": NDIME, NELEM, NPOIN, NMARK;
/// VTK element type numbers, 0-based node indices).
#include <algorithm>

#include "paramesh/io/Groups.hpp"
#include "paramesh/io/WriterSupport.hpp"
#include "paramesh/util/Error.hpp"

namespace paramesh {

void writeSu2(const std::string& path, const SurfaceMesh& m) {
  using namespace io;
  checkMeshForWriting(path, m);
  if (m.order != 1) throw Error("cannot write '" + path + "': SU2 meshes hold linear elements only (use --order 1)");
  const bool volume = !m.tets.empty();
  TextOut out(path);
  out << "NDIME= 3\n";
  if (volume) {
    out << "NELEM= " << m.tets.size() << '\n';
    for (std::size_t k = 0; k < m.tets.size(); ++k) {
      const auto& t = m.tets[k];
      out << "10 " << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << ' ' << k << '\n';
    }
  } else {
    out << "NELEM= " << m.triangles.size() + m.quads.size() << '\n';
    std::size_t id = 0;
    for (const auto& t : m.triangles) out << "5 " << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << id++ << '\n';
    for (const auto& q : m.quads) out << "9 " << q[0] << ' ' << q[1] << ' ' << q[2] << ' ' << q[3] << ' ' << id++ << '\n';
  }
  out << "NPOIN= " << m.nodes.size() << '\n';
  for (std::size_t i = 0; i < m.nodes.size(); ++i) {
    const Vec3& p = m.nodes[i];
    out << p.x << ' ' << p.y << ' ' << p.z << ' ' << i << '\n';
  }
  // markers: the face groups of a volume mesh, the user's edge groups of a surface mesh
  std::vector<WrittenGroup> markers;
  for (WrittenGroup& g : writtenGroups(m))
    if (g.dim == (volume ? 2 : 1)) markers.push_back(std::move(g));
  out << "NMARK= " << markers.size() << '\n';
  for (const WrittenGroup& g : markers) {
    auto in = [&](int e) { return std::binary_search(g.entities.begin(), g.entities.end(), e); };
    out << "MARKER_TAG= " << g.name << '\n';
    std::size_t n = 0;
    if (volume) {
      for (std::size_t t = 0; t < m.triangles.size(); ++t) n += in(m.triangleFace[t]);
      out << "MARKER_ELEMS= " << n << '\n';
      for (std::size_t t = 0; t < m.triangles.size(); ++t)
        if (in(m.triangleFace[t]))
          out << "5 " << m.triangles[t][0] << ' ' << m.triangles[t][1] << ' ' << m.triangles[t][2] << '\n';
    } else {
      for (std::size_t s = 0; s < m.segments.size(); ++s) n += in(m.segmentEdge[s]);
      out << "MARKER_ELEMS= " << n << '\n';
      for (std::size_t s = 0; s < m.segments.size(); ++s)
        if (in(m.segmentEdge[s])) out << "3 " << m.segments[s][0] << ' ' << m.segments[s][1] << '\n';
    }
  }
  out.commit();
}

}  // namespace paramesh
