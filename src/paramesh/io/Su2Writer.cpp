// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Su2Writer.cpp
/// The SU2 native mesh writer (SU2's "Mesh File Format (native)": NDIME, NELEM, NPOIN, NMARK;
/// VTK element type numbers, 0-based node indices).
#include <map>

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
  // markers: the face groups of a volume mesh, the user's edge groups of a surface mesh; the
  // elements bucketed by entity once (one pass over all elements per marker is quadratic with a
  // default group per face)
  std::vector<WrittenGroup> markers;
  for (WrittenGroup& g : writtenGroups(m))
    if (g.dim == (volume ? 2 : 1)) markers.push_back(std::move(g));
  std::map<int, std::vector<int>> byEntity;
  if (volume)
    for (std::size_t t = 0; t < m.triangles.size(); ++t) byEntity[m.triangleFace[t]].push_back(int(t));
  else
    for (std::size_t s = 0; s < m.segments.size(); ++s) byEntity[m.segmentEdge[s]].push_back(int(s));
  out << "NMARK= " << markers.size() << '\n';
  for (const WrittenGroup& g : markers) {
    std::size_t n = 0;
    for (int e : g.entities)
      if (const auto it = byEntity.find(e); it != byEntity.end()) n += it->second.size();
    out << "MARKER_TAG= " << g.name << "\nMARKER_ELEMS= " << n << '\n';
    for (int e : g.entities) {
      const auto it = byEntity.find(e);
      if (it == byEntity.end()) continue;
      for (int k : it->second) {
        if (volume)
          out << "5 " << m.triangles[k][0] << ' ' << m.triangles[k][1] << ' ' << m.triangles[k][2] << '\n';
        else
          out << "3 " << m.segments[k][0] << ' ' << m.segments[k][1] << '\n';
      }
    }
  }
  out.commit();
}

}  // namespace paramesh
