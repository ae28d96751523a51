// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file VtuWriter.cpp
/// The VTK XML UnstructuredGrid writer.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>

#include "paramesh/io/Groups.hpp"
#include "paramesh/io/WriterSupport.hpp"
#include "paramesh/volume/TetQuality.hpp"
#include "paramesh/util/Error.hpp"

namespace paramesh {

// ---------------------------------------------------------------------------------------------
// VTK XML UnstructuredGrid

void writeVtu(const std::string& path, const SurfaceMesh& m) {
  using namespace io;
  checkMeshForWriting(path, m);
  const bool o2 = m.order == 2;
  const std::size_t N = m.nodes.size(), T = m.triangles.size(), Q = m.quads.size(), K = m.tets.size();
  TextOut out(path);
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <UnstructuredGrid>\n";
  // the user's groups: their (tag, dimension) in field data, membership in cell data "group:NAME"
  std::vector<WrittenGroup> user;
  for (WrittenGroup& g : writtenGroups(m))
    if (g.user && g.dim >= 2) user.push_back(std::move(g));
  if (!user.empty()) {
    out << "    <FieldData>\n";
    for (const WrittenGroup& g : user)
      out << "      <DataArray type=\"Int32\" Name=\"" << g.name << "\" NumberOfTuples=\"2\" format=\"ascii\">" << g.tag
          << ' ' << g.dim << "</DataArray>\n";
    out << "    </FieldData>\n";
  }
  out << "    <Piece NumberOfPoints=\"" << N << "\" NumberOfCells=\"" << (T + Q + K) << "\">\n";

  out << "      <PointData Scalars=\"entity\">\n"
         "        <DataArray type=\"Int32\" Name=\"entity_dim\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < N; ++i) out << static_cast<int>(m.nodeKind[i]) << '\n';
  out << "        </DataArray>\n"
         "        <DataArray type=\"Int32\" Name=\"entity\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < N; ++i) out << m.nodeEntity[i] << '\n';
  out << "        </DataArray>\n"
         "      </PointData>\n";

  out << "      <CellData Scalars=\"face\">\n"
         "        <DataArray type=\"Int32\" Name=\"face\" format=\"ascii\">\n";
  for (std::size_t t = 0; t < T; ++t) out << m.triangleFace[t] << '\n';
  for (std::size_t q = 0; q < Q; ++q) out << m.quadFace[q] << '\n';
  for (std::size_t k = 0; k < K; ++k) out << "0\n";
  if (K) {
    out << "        </DataArray>\n"
           "        <DataArray type=\"Int32\" Name=\"solid\" format=\"ascii\">\n";
    for (std::size_t e = 0; e < T + Q; ++e) out << "0\n";
    for (std::size_t k = 0; k < K; ++k) out << m.tetSolid[k] << '\n';
  }
  const bool layers = std::any_of(m.triangleLayer.begin(), m.triangleLayer.end(), [](int l) { return l > 0; }) ||
                      std::any_of(m.quadLayer.begin(), m.quadLayer.end(), [](int l) { return l > 0; });
  if (layers) {  // the boundary-layer spec of each surface cell (1-based; 0: none)
    out << "        </DataArray>\n"
           "        <DataArray type=\"Int32\" Name=\"layer\" format=\"ascii\">\n";
    for (std::size_t t = 0; t < T; ++t) out << (m.triangleLayer.empty() ? 0 : m.triangleLayer[t]) << '\n';
    for (std::size_t q = 0; q < Q; ++q) out << (m.quadLayer.empty() ? 0 : m.quadLayer[q]) << '\n';
    for (std::size_t k = 0; k < K; ++k) out << "0\n";
  }
  for (const WrittenGroup& g : user) {
    out << "        </DataArray>\n"
           "        <DataArray type=\"Int32\" Name=\"group:" << g.name << "\" format=\"ascii\">\n";
    auto in = [&](int e) { return std::binary_search(g.entities.begin(), g.entities.end(), e) ? "1\n" : "0\n"; };
    for (std::size_t t = 0; t < T; ++t) out << (g.dim == 2 ? in(m.triangleFace[t]) : "0\n");
    for (std::size_t q = 0; q < Q; ++q) out << (g.dim == 2 ? in(m.quadFace[q]) : "0\n");
    for (std::size_t k = 0; k < K; ++k) out << (g.dim == 3 ? in(m.tetSolid[k]) : "0\n");
  }
  out << "        </DataArray>\n"
         "        <DataArray type=\"Float64\" Name=\"quality\" format=\"ascii\">\n";
  for (std::size_t t = 0; t < T; ++t) {
    const auto& e = m.triangles[t];
    out << triangleGamma(m.nodes[e[0]], m.nodes[e[1]], m.nodes[e[2]]) << '\n';
  }
  for (std::size_t q = 0; q < Q; ++q) {
    const auto& e = m.quads[q];
    out << quadQuality(m.nodes[e[0]], m.nodes[e[1]], m.nodes[e[2]], m.nodes[e[3]]) << '\n';
  }
  for (std::size_t k = 0; k < K; ++k) {
    const auto& e = m.tets[k];
    out << tetRadiusRatio(m.nodes[e[0]], m.nodes[e[1]], m.nodes[e[2]], m.nodes[e[3]]) << '\n';
  }
  out << "        </DataArray>\n"
         "      </CellData>\n";

  out << "      <Points>\n"
         "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const Vec3& p : m.nodes) out << p.x << ' ' << p.y << ' ' << p.z << '\n';
  out << "        </DataArray>\n"
         "      </Points>\n";

  out << "      <Cells>\n"
         "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (std::size_t t = 0; t < T; ++t) {
    const auto& e = m.triangles[t];
    out << e[0] << ' ' << e[1] << ' ' << e[2];
    if (o2) out << ' ' << m.triangleMid[t][0] << ' ' << m.triangleMid[t][1] << ' ' << m.triangleMid[t][2];
    out << '\n';
  }
  for (std::size_t q = 0; q < Q; ++q) {
    const auto& e = m.quads[q];
    out << e[0] << ' ' << e[1] << ' ' << e[2] << ' ' << e[3];
    if (o2)
      for (int v : m.quadMid[q]) out << ' ' << v;
    out << '\n';
  }
  for (std::size_t k = 0; k < K; ++k) {  // VTK's quadratic tetra has our mid-node order
    const auto& e = m.tets[k];
    out << e[0] << ' ' << e[1] << ' ' << e[2] << ' ' << e[3];
    if (o2)
      for (int v : m.tetMid[k]) out << ' ' << v;
    out << '\n';
  }
  out << "        </DataArray>\n"
         "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  long long off = 0;
  for (std::size_t t = 0; t < T; ++t) out << (off += o2 ? 6 : 3) << '\n';
  for (std::size_t q = 0; q < Q; ++q) out << (off += o2 ? 8 : 4) << '\n';
  for (std::size_t k = 0; k < K; ++k) out << (off += o2 ? 10 : 4) << '\n';
  out << "        </DataArray>\n"
         "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t t = 0; t < T; ++t) out << (o2 ? "22\n" : "5\n");
  for (std::size_t q = 0; q < Q; ++q) out << (o2 ? "23\n" : "9\n");
  for (std::size_t k = 0; k < K; ++k) out << (o2 ? "24\n" : "10\n");
  out << "        </DataArray>\n"
         "      </Cells>\n"
         "    </Piece>\n"
         "  </UnstructuredGrid>\n"
         "</VTKFile>\n";
  out.commit();
}

}  // namespace paramesh
