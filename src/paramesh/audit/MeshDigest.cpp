// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshDigest.cpp
#include "paramesh/audit/MeshDigest.hpp"

#include <cstring>
#include <type_traits>

namespace paramesh {
namespace {

/// Word-wise multiply-xor mixing (not cryptographic: it tells an unchanged mesh from a changed one).
class Digest {
 public:
  template <class T>
  void add(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable<T>::value, "raw bytes");
    word(v.size());
    const auto* b = reinterpret_cast<const unsigned char*>(v.data());
    const size_t n = v.size() * sizeof(T);
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
      uint64_t w;
      std::memcpy(&w, b + i, 8);
      word(w);
    }
    uint64_t tail = 0;
    if (n > i) std::memcpy(&tail, b + i, n - i);  // (an empty vector's data() may be null)
    word(tail);
  }
  uint64_t value() const { return h_; }

 private:
  void word(uint64_t w) {
    h_ ^= w + 0x9e3779b97f4a7c15ULL + (h_ << 6) + (h_ >> 2);
    h_ *= 0xff51afd7ed558ccdULL;
    h_ ^= h_ >> 33;
  }
  uint64_t h_ = 0xcbf29ce484222325ULL;
};

}  // namespace

uint64_t meshDigest(const SurfaceMesh& m, const std::vector<std::array<Vec2, 3>>& triUv,
                    const std::vector<std::array<Vec2, 4>>& quadUv) {
  Digest d;
  d.add(m.nodes);
  d.add(m.nodeKind);
  d.add(m.nodeEntity);
  d.add(m.nodeParam);
  d.add(m.triangles);
  d.add(m.triangleFace);
  d.add(m.quads);
  d.add(m.quadFace);
  d.add(m.segments);
  d.add(m.segmentEdge);
  d.add(m.triangleMid);
  d.add(m.quadMid);
  d.add(m.segmentMid);
  d.add(m.tets);
  d.add(m.tetSolid);
  d.add(m.tetMid);
  d.add(triUv);
  d.add(quadUv);
  return d.value();
}

}  // namespace paramesh
