// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshWriters.cpp
/// What every mesh writer uses: the atomic file, quality measures, the mesh's validation, and
/// the dispatch on the extension (the writers: MshWriter, VtuWriter, StlWriter, InpWriter).
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
#include "paramesh/io/WriterSupport.hpp"
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
    if (k < 0 || k > 3) return "node " + std::to_string(i) + " has an invalid NodeKind";
  }
  if (m.triangleFace.size() != m.triangles.size()) return "triangleFace size differs from triangles";
  if (m.quadFace.size() != m.quads.size()) return "quadFace size differs from quads";
  if (m.segmentEdge.size() != m.segments.size()) return "segmentEdge size differs from segments";
  if (m.tetSolid.size() != m.tets.size()) return "tetSolid size differs from tets";
  if (m.order == 2 && m.tetMid.size() != m.tets.size()) return "order 2 but tetMid does not match the tetrahedra";
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
  if (!(p = scan("tetrahedron", m.tets)).empty()) return p;
  if (m.order == 2) {
    if (!(p = scan("triangle", m.triangleMid)).empty()) return p;
    if (!(p = scan("quad", m.quadMid)).empty()) return p;
    if (!(p = scan("tetrahedron", m.tetMid)).empty()) return p;
    for (std::size_t e = 0; e < m.segmentMid.size(); ++e)
      if (bad(m.segmentMid[e])) return describe("segment", e, m.segmentMid[e]);
  }
  return {};
}

void checkMeshForWriting(const std::string& path, const SurfaceMesh& m) {
  std::string p = findMeshProblem(m);
  if (!p.empty()) throw Error("cannot write '" + path + "': invalid mesh (" + p + ")");
}
}  // namespace io

// ---------------------------------------------------------------------------------------------

void writeMesh(const std::string& path, const SurfaceMesh& m, const WriteOptions& options) {
  std::string ext = io::lowerExtension(path);
  if (ext == ".msh") return writeMsh41(path, m);
  if (ext == ".vtu") return writeVtu(path, m);
  if (ext == ".stl") {
    const bool groups = options.stlGroups ||
                        std::any_of(m.groups.begin(), m.groups.end(), [](const MeshGroup& g) { return g.dim == 2; });
    return groups ? writeStlGroups(path, m) : writeStl(path, m, true);
  }
  if (ext == ".inp") return writeInp(path, m);
  if (ext == ".su2") return writeSu2(path, m);
  if (ext.empty())
    throw Error("cannot write '" + path + "': no file extension (use .msh, .vtu, .stl, .inp or .su2)");
  throw Error("unsupported output format '" + ext + "' for '" + path +
              "' (use .msh, .vtu, .stl, .inp or .su2)");
}

}  // namespace paramesh
