// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshWriters.cpp
/// MSH 4.1, VTU, STL and INP writers of a SurfaceMesh.
#include "paramesh/io/MeshWriters.hpp"

#include <cstdio>
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <system_error>
#include <type_traits>

#include "paramesh/io/Json.hpp"
#include "paramesh/util/Error.hpp"

namespace paramesh {
namespace io {

// ---------------------------------------------------------------------------------------------
// AtomicFile

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  static std::atomic<unsigned> counter{0};
  unsigned long long stamp =
      static_cast<unsigned long long>(std::chrono::steady_clock::now().time_since_epoch().count());
  tmp_ = path_ + "." + std::to_string((stamp ^ (counter++ * 0x9E3779B9ull)) % 1000000007ull) + ".tmp";
  errno = 0;
  out_.open(std::filesystem::u8path(tmp_), std::ios::out | std::ios::binary | std::ios::trunc);
  if (!out_) {
    std::string why = errno ? std::error_code(errno, std::generic_category()).message()
                            : std::string("cannot create the file");
    throw Error("cannot write '" + path_ + "': " + why);
  }
  buf_.reserve(1 << 20);
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  if (out_.is_open()) out_.close();
  std::error_code ec;
  std::filesystem::remove(std::filesystem::u8path(tmp_), ec);
}

void AtomicFile::write(std::string_view data) {
  buf_.append(data.data(), data.size());
  if (buf_.size() >= (1u << 20)) flushBuffer();
}

void AtomicFile::flushBuffer() {
  if (buf_.empty()) return;
  out_.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
  buf_.clear();
  if (!out_) fail("write error (disk full?)");
}

void AtomicFile::commit() {
  if (committed_) return;
  flushBuffer();
  out_.close();
  if (out_.fail()) fail("write error while closing the file");
  std::error_code ec;
  const std::filesystem::path from = std::filesystem::u8path(tmp_);
  const std::filesystem::path to = std::filesystem::u8path(path_);
  std::filesystem::rename(from, to, ec);
  std::error_code ec2;
  if (ec && std::filesystem::is_regular_file(to, ec2)) {
    // Some platforms' rename does not replace an existing file: remove it and retry.
    std::filesystem::remove(to, ec2);
    ec.clear();
    std::filesystem::rename(from, to, ec);
  }
  if (ec) fail("cannot replace the file (" + ec.message() + ")");
  committed_ = true;
}

void AtomicFile::fail(const std::string& what) {
  if (out_.is_open()) out_.close();
  std::error_code ec;
  std::filesystem::remove(std::filesystem::u8path(tmp_), ec);
  committed_ = true;  // nothing left to clean up
  throw Error("cannot write '" + path_ + "': " + what);
}

// ---------------------------------------------------------------------------------------------
// Quality measures

double triangleGamma(const Vec3& a, const Vec3& b, const Vec3& c) {
  double la = dist(b, c), lb = dist(c, a), lc = dist(a, b);
  double area2 = norm2(cross(b - a, c - a)) * 0.25;  // area squared
  double den = (la + lb + lc) * la * lb * lc;
  if (!(den > 0)) return 0.0;
  double g = 16.0 * area2 / den;
  return std::isfinite(g) ? std::min(g, 1.0) : 0.0;
}

double quadQuality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 p[4] = {a, b, c, d};
  Vec3 n = cross(c - a, d - b);
  double nn = norm(n);
  if (!(nn > 0)) return 0.0;
  n *= 1.0 / nn;
  double q = 1.0;
  for (int i = 0; i < 4; ++i) {
    Vec3 e1 = p[(i + 1) % 4] - p[i], e2 = p[(i + 3) % 4] - p[i];
    double den = norm(e1) * norm(e2);
    if (!(den > 0)) return 0.0;
    q = std::min(q, dot(cross(e1, e2), n) / den);
  }
  return std::isfinite(q) ? std::max(-1.0, q) : 0.0;
}

// ---------------------------------------------------------------------------------------------
// Validation

std::string findMeshProblem(const SurfaceMesh& m) {
  const std::size_t n = m.nodes.size();
  if (m.nodeKind.size() != n || m.nodeEntity.size() != n)
    return "nodeKind/nodeEntity sizes differ from the node count";
  for (std::size_t i = 0; i < n; ++i) {
    int k = static_cast<int>(m.nodeKind[i]);
    if (k < 0 || k > 2) return "node " + std::to_string(i) + " has an invalid NodeKind";
  }
  if (m.triangleFace.size() != m.triangles.size()) return "triangleFace size differs from triangles";
  if (m.quadFace.size() != m.quads.size()) return "quadFace size differs from quads";
  if (m.segmentEdge.size() != m.segments.size()) return "segmentEdge size differs from segments";
  if (m.order != 1 && m.order != 2) return "order " + std::to_string(m.order) + " is not 1 or 2";
  if (m.order == 2 && (m.triangleMid.size() != m.triangles.size() ||
                       m.quadMid.size() != m.quads.size() ||
                       m.segmentMid.size() != m.segments.size()))
    return "order 2 but the mid-node arrays do not match the element counts";
  auto bad = [&](int v) { return v < 0 || static_cast<std::size_t>(v) >= n; };
  auto describe = [&](const char* what, std::size_t e, int v) {
    return std::string(what) + " " + std::to_string(e) + " refers to node " + std::to_string(v) +
           " but the mesh has " + std::to_string(n) + " nodes";
  };
  auto scan = [&](const char* what, const auto& elems) -> std::string {
    for (std::size_t e = 0; e < elems.size(); ++e)
      for (int v : elems[e])
        if (bad(v)) return describe(what, e, v);
    return {};
  };
  std::string p;
  if (!(p = scan("triangle", m.triangles)).empty()) return p;
  if (!(p = scan("quad", m.quads)).empty()) return p;
  if (!(p = scan("segment", m.segments)).empty()) return p;
  if (m.order == 2) {
    if (!(p = scan("triangle", m.triangleMid)).empty()) return p;
    if (!(p = scan("quad", m.quadMid)).empty()) return p;
    for (std::size_t e = 0; e < m.segmentMid.size(); ++e)
      if (bad(m.segmentMid[e])) return describe("segment", e, m.segmentMid[e]);
  }
  return {};
}

void checkMeshForWriting(const std::string& path, const SurfaceMesh& m) {
  std::string p = findMeshProblem(m);
  if (!p.empty()) throw Error("cannot write '" + path + "': invalid mesh (" + p + ")");
}

namespace {

// ---------------------------------------------------------------------------------------------
// Helpers

/// Buffered, locale-independent text output on top of an AtomicFile.
class TextOut {
 public:
  explicit TextOut(const std::string& path) : f_(path) {}
  TextOut& operator<<(std::string_view s) {
    f_.write(s);
    return *this;
  }
  TextOut& operator<<(char c) {
    f_.write(std::string_view(&c, 1));
    return *this;
  }
  template <class T, std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, char> &&
                                        !std::is_same_v<T, bool>,
                                    int> = 0>
  TextOut& operator<<(T v) {
    char b[32];
    std::to_chars_result r = std::to_chars(b, b + sizeof b, v);
    f_.write(std::string_view(b, static_cast<std::size_t>(r.ptr - b)));
    return *this;
  }
  /// Doubles with 17 significant digits (like printf "%.17g"): exact round trip.
  TextOut& operator<<(double v) {
    char b[40];
    f_.write(std::string_view(b, formatDouble(v, b, 17)));
    return *this;
  }
  void commit() { f_.commit(); }

 private:
  AtomicFile f_;
};

/// Indices 0..n-1 stably sorted by key(i).
template <class Key>
std::vector<int> sortedBy(std::size_t n, Key key) {
  std::vector<int> idx(n);
  for (std::size_t i = 0; i < n; ++i) idx[i] = static_cast<int>(i);
  std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return key(a) < key(b); });
  return idx;
}

/// Calls f(begin, end) for each run of equal key(idx[k]) in idx.
template <class Key, class F>
void forEachRun(const std::vector<int>& idx, Key key, F f) {
  for (std::size_t b = 0; b < idx.size();) {
    std::size_t e = b + 1;
    while (e < idx.size() && key(idx[e]) == key(idx[b])) ++e;
    f(b, e);
    b = e;
  }
}

std::string lowerExtension(const std::string& path) {
  std::size_t slash = path.find_last_of("/\\");
  std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot);
  for (char& c : ext)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return ext;
}

}  // namespace
}  // namespace io

// ---------------------------------------------------------------------------------------------
// Gmsh MSH 4.1

void writeMsh41(const std::string& path, const SurfaceMesh& m) {
  using namespace io;
  checkMeshForWriting(path, m);
  const bool o2 = m.order == 2;
  const std::size_t N = m.nodes.size();

  // Entities: those claimed by nodes plus those holding elements; boxes from all their nodes.
  std::map<int, Box3> ent[3];
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

  TextOut out(path);
  out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";

  out << "$Entities\n"
      << ent[0].size() << ' ' << ent[1].size() << ' ' << ent[2].size() << " 0\n";
  auto box = [&](const Box3& b) {
    Box3 bb = b;
    if (bb.empty()) bb.lo = bb.hi = Vec3();
    out << bb.lo.x << ' ' << bb.lo.y << ' ' << bb.lo.z << ' ' << bb.hi.x << ' ' << bb.hi.y << ' '
        << bb.hi.z;
  };
  for (const auto& [tag, p] : vertexPos) out << tag << ' ' << p.x << ' ' << p.y << ' ' << p.z << " 0\n";
  for (int d = 1; d <= 2; ++d)
    for (const auto& [tag, b] : ent[d]) {
      out << tag << ' ';
      box(b);
      out << " 0 0\n";  // no physical tags, no boundary entities
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
  const std::size_t numElems = vertexNodes.size() + segOrder.size() + surfOrder.size();
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
  out << "$EndElements\n";
  out.commit();
}

// ---------------------------------------------------------------------------------------------
// VTK XML UnstructuredGrid

void writeVtu(const std::string& path, const SurfaceMesh& m) {
  using namespace io;
  checkMeshForWriting(path, m);
  const bool o2 = m.order == 2;
  const std::size_t N = m.nodes.size(), T = m.triangles.size(), Q = m.quads.size();
  TextOut out(path);
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <UnstructuredGrid>\n"
      << "    <Piece NumberOfPoints=\"" << N << "\" NumberOfCells=\"" << (T + Q) << "\">\n";

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
  out << "        </DataArray>\n"
         "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  long long off = 0;
  for (std::size_t t = 0; t < T; ++t) out << (off += o2 ? 6 : 3) << '\n';
  for (std::size_t q = 0; q < Q; ++q) out << (off += o2 ? 8 : 4) << '\n';
  out << "        </DataArray>\n"
         "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t t = 0; t < T; ++t) out << (o2 ? "22\n" : "5\n");
  for (std::size_t q = 0; q < Q; ++q) out << (o2 ? "23\n" : "9\n");
  out << "        </DataArray>\n"
         "      </Cells>\n"
         "    </Piece>\n"
         "  </UnstructuredGrid>\n"
         "</VTKFile>\n";
  out.commit();
}

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

// ---------------------------------------------------------------------------------------------
// Abaqus / CalculiX

void writeInp(const std::string& path, const SurfaceMesh& m) {
  using namespace io;
  checkMeshForWriting(path, m);
  const bool o2 = m.order == 2;
  TextOut out(path);
  out << "*HEADING\nParaMesh surface mesh\n*NODE\n";
  for (std::size_t i = 0; i < m.nodes.size(); ++i) {
    const Vec3& p = m.nodes[i];
    // CalculiX reads at most 20 characters per number: 12 significant digits always fit
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.12g, %.12g, %.12g", p.x, p.y, p.z);
    out << i + 1 << ", " << buf << '\n';
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
  forEachRun(order, faceKey, [&](std::size_t b, std::size_t e) {
    out << "*ELSET, ELSET=Face" << faceKey(order[b]) << ", GENERATE\n"
        << b + 1 << ", " << e << ", 1\n";
  });
  out.commit();
}

// ---------------------------------------------------------------------------------------------

void writeMesh(const std::string& path, const SurfaceMesh& m) {
  std::string ext = io::lowerExtension(path);
  if (ext == ".msh") return writeMsh41(path, m);
  if (ext == ".vtu") return writeVtu(path, m);
  if (ext == ".stl") return writeStl(path, m, true);
  if (ext == ".inp") return writeInp(path, m);
  if (ext.empty())
    throw Error("cannot write '" + path + "': no file extension (use .msh, .vtu, .stl or .inp)");
  throw Error("unsupported output format '" + ext + "' for '" + path +
              "' (use .msh, .vtu, .stl or .inp)");
}

}  // namespace paramesh
