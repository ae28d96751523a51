// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file EdgeTable.hpp
/// The edges of a triangle list and the triangles using each (rows by lower node, CSR): built in
/// linear time, looked up by (a, b) in either order.
#pragma once
#include <algorithm>
#include <array>
#include <vector>

namespace paramesh {

/// Hash keys of mesh edges: the directed side a -> b, and the edge {a, b} in either order.
inline unsigned long long sideKey(int a, int b) { return ((unsigned long long)(unsigned)a << 32) | (unsigned)b; }
inline unsigned long long edgeKey(int a, int b) { return sideKey(std::min(a, b), std::max(a, b)); }

class EdgeTable {
 public:
  struct Use {
    int hi;
    int tri;
  };
  EdgeTable(const std::vector<std::array<int, 3>>& tris, int nodes) : start_(nodes + 1, 0) {
    for (const auto& t : tris)
      for (int i = 0; i < 3; ++i) ++start_[std::min(t[i], t[(i + 1) % 3]) + 1];
    for (int i = 0; i < nodes; ++i) start_[i + 1] += start_[i];
    uses_.resize(start_[nodes]);
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (int k = 0; k < (int)tris.size(); ++k)
      for (int i = 0; i < 3; ++i) {
        const int a = tris[k][i], b = tris[k][(i + 1) % 3];
        uses_[fill[std::min(a, b)]++] = {std::max(a, b), k};
      }
    for (int i = 0; i < nodes; ++i)
      std::sort(uses_.begin() + start_[i], uses_.begin() + start_[i + 1],
                [](const Use& x, const Use& y) { return x.hi != y.hi ? x.hi < y.hi : x.tri < y.tri; });
  }
  /// The triangles using edge (a, b), in triangle order (each Use's hi is max(a, b)).
  std::vector<Use> uses(int a, int b) const {
    const int lo = std::min(a, b), hi = std::max(a, b);
    auto first = uses_.begin() + start_[lo], last = uses_.begin() + start_[lo + 1];
    auto it = std::lower_bound(first, last, hi, [](const Use& u, int h) { return u.hi < h; });
    std::vector<Use> out;
    for (; it != last && it->hi == hi; ++it) out.push_back(*it);
    return out;
  }
  /// True when triangle t has the side a -> b in its corner order.
  static bool runs(const std::array<int, 3>& t, int a, int b) {
    for (int i = 0; i < 3; ++i)
      if (t[i] == a && t[(i + 1) % 3] == b) return true;
    return false;
  }
  /// f(a, b, uses) once per edge, a < b, in (a, b) order.
  template <class F>
  void forEach(F&& f) const {
    std::vector<Use> group;
    for (int lo = 0; lo + 1 < (int)start_.size(); ++lo)
      for (int i = start_[lo]; i < start_[lo + 1];) {
        int j = i;
        group.clear();
        while (j < start_[lo + 1] && uses_[j].hi == uses_[i].hi) group.push_back(uses_[j++]);
        f(lo, uses_[i].hi, group);
        i = j;
      }
  }

 private:
  std::vector<int> start_;
  std::vector<Use> uses_;
};

}  // namespace paramesh
