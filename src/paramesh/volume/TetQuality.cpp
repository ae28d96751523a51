// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file TetQuality.cpp
#include "paramesh/volume/TetQuality.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace paramesh {

double tetVolume6(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return dot(cross(b - a, c - a), d - a);
}

std::array<double, 6> tetDihedrals(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // outward normals of the faces opposite a, b, c, d
  const Vec3 na = cross(c - b, d - b), nb = cross(d - a, c - a), nc = cross(b - a, d - a), nd = cross(c - a, b - a);
  // (outward for a positive tet, all inward for a negative one: the angle is the same)
  auto angle = [](Vec3 n1, Vec3 n2) {
    const double l = norm(n1) * norm(n2);
    if (l <= 0) return 0.0;
    const double c = std::clamp(-dot(n1, n2) / l, -1.0, 1.0);
    return std::acos(c) * 180.0 / 3.14159265358979323846;
  };
  // the dihedral at edge xy is between the two faces containing it: those opposite the other two
  return {angle(nc, nd), angle(nb, nd), angle(nb, nc), angle(na, nd), angle(na, nc), angle(na, nb)};
}

double tetRadiusRatio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double v6 = std::fabs(tetVolume6(a, b, c, d));
  if (v6 <= 0) return 0;
  const double area = 0.5 * (norm(cross(c - b, d - b)) + norm(cross(d - a, c - a)) + norm(cross(b - a, d - a)) +
                             norm(cross(c - a, b - a)));
  const double rin = 0.5 * v6 / area;  // 3V / A
  // circumradius: |a|^2 (b x c) + ... with a at the origin, over 2 (6V)
  const Vec3 u = b - a, v = c - a, w = d - a;
  const Vec3 num = dot(u, u) * cross(v, w) + dot(v, v) * cross(w, u) + dot(w, w) * cross(u, v);
  const double rcirc = norm(num) / (2.0 * v6);
  return rcirc > 0 ? 3.0 * rin / rcirc : 0;
}

TetStats tetStats(const std::vector<Vec3>& nodes, const std::vector<std::array<int, 4>>& tets) {
  TetStats st;
  st.tets = static_cast<int>(tets.size());
  if (tets.empty()) return st;
  double sumAngle = 0, sumRR = 0;
  int below = 0;
  for (const auto& t : tets) {
    const Vec3 &a = nodes[t[0]], &b = nodes[t[1]], &c = nodes[t[2]], &d = nodes[t[3]];
    const double v6 = tetVolume6(a, b, c, d);
    if (v6 <= 0) ++st.inverted;
    st.volume += v6 / 6.0;
    double lo = 180;
    for (double x : tetDihedrals(a, b, c, d)) {
      lo = std::min(lo, x);
      st.maxDihedral = std::max(st.maxDihedral, x);
      sumAngle += x;
    }
    st.minDihedral = std::min(st.minDihedral, lo);
    below += lo < 10.0;
    const double rr = tetRadiusRatio(a, b, c, d);
    st.minRadiusRatio = std::min(st.minRadiusRatio, rr);
    sumRR += rr;
  }
  st.meanDihedral = sumAngle / (6.0 * tets.size());
  st.meanRadiusRatio = sumRR / tets.size();
  st.pctBelow10 = 100.0 * below / tets.size();
  return st;
}

namespace {
/// Key of a triangle's node set.
struct TriKey {
  std::array<int, 3> v;
  bool operator==(const TriKey& o) const { return v == o.v; }
};
struct TriHash {
  std::size_t operator()(const TriKey& k) const {
    return (std::size_t(k.v[0]) * 73856093u) ^ (std::size_t(k.v[1]) * 19349663u) ^ (std::size_t(k.v[2]) * 83492791u);
  }
};
TriKey sortedKey(int a, int b, int c) {
  std::array<int, 3> v{a, b, c};
  std::sort(v.begin(), v.end());
  return {v};
}
/// The rotation of (a,b,c) starting at its smallest node: equal for equally oriented triangles.
std::array<int, 3> rotated(int a, int b, int c) {
  if (a < b && a < c) return {a, b, c};
  if (b < c) return {b, c, a};
  return {c, a, b};
}
}  // namespace

std::string checkFill(const std::vector<Vec3>& nodes, const std::vector<std::array<int, 4>>& tets,
                      const std::vector<std::array<int, 3>>& surface) {
  struct Use {
    int count = 0;
    std::array<int, 3> oriented{};  // the last use's outward orientation
  };
  std::unordered_map<TriKey, Use, TriHash> faces;
  faces.reserve(tets.size() * 3);
  int inverted = 0;
  for (const auto& t : tets) {
    if (tetVolume6(nodes[t[0]], nodes[t[1]], nodes[t[2]], nodes[t[3]]) <= 0) ++inverted;
    // outward faces of a positive tet (a,b,c,d): (a,c,b), (a,b,d), (a,d,c), (b,c,d)
    const int f[4][3] = {{t[0], t[2], t[1]}, {t[0], t[1], t[3]}, {t[0], t[3], t[2]}, {t[1], t[2], t[3]}};
    for (const auto& x : f) {
      Use& u = faces[sortedKey(x[0], x[1], x[2])];
      ++u.count;
      u.oriented = rotated(x[0], x[1], x[2]);
    }
  }
  int overShared = 0, boundary = 0;
  for (const auto& kv : faces) {
    overShared += kv.second.count > 2;
    boundary += kv.second.count == 1;
  }
  int missing = 0, flipped = 0;
  for (const auto& s : surface) {
    auto it = faces.find(sortedKey(s[0], s[1], s[2]));
    if (it == faces.end() || it->second.count != 1) {
      ++missing;
      continue;
    }
    if (it->second.oriented != rotated(s[0], s[1], s[2])) ++flipped;
  }
  const int extra = boundary - (static_cast<int>(surface.size()) - missing);
  std::string why;
  auto add = [&why](int n, const char* what) {
    if (n) why += (why.empty() ? "" : ", ") + std::to_string(n) + " " + what;
  };
  add(inverted, "inverted tetrahedra");
  add(overShared, "tetrahedron faces shared by more than two tetrahedra");
  add(missing, "surface triangles not on the fill's boundary");
  add(flipped, "surface triangles facing into the fill");
  add(extra, "boundary faces of the fill that are not surface triangles");
  return why;
}

}  // namespace paramesh
