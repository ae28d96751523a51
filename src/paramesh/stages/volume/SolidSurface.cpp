// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file SolidSurface.cpp
#include "paramesh/stages/volume/SolidSurface.hpp"

#include <algorithm>
#include <cstdint>
#include <set>
#include <unordered_map>

#include "paramesh/volume/TetQuality.hpp"

namespace paramesh {
namespace {

std::string faceList(const std::set<int>& faces) {
  std::string s;
  int n = 0;
  for (int f : faces) {
    if (n++ == 8) {
      s += ", ...";
      break;
    }
    s += (s.empty() ? "Face" : ", Face") + std::to_string(f);
  }
  return s;
}

}  // namespace

SolidSurface solidSurface(const IGeometryModel& g, int solid, const SurfaceMesh& m,
                          const std::vector<std::vector<int>>& trianglesOfFace,
                          const std::vector<int>& quadsOfFace) {
  SolidSurface out;
  const std::vector<SolidFace> sf = g.solidFaces(solid);
  std::vector<int> uses(g.numFaces(), 0);
  std::set<int> empty, twice, withQuads;
  std::vector<int>& triFace = out.triangleFace;
  for (const SolidFace& f : sf) ++uses[f.face];
  for (const SolidFace& f : sf) {
    if (uses[f.face] > 1) twice.insert(f.face + 1);
    if (trianglesOfFace[f.face].empty()) empty.insert(f.face + 1);
    if (quadsOfFace[f.face] > 0) withQuads.insert(f.face + 1);
    if (uses[f.face] > 1) continue;
    out.faces.push_back(f.face + 1);
    for (int t : trianglesOfFace[f.face]) {
      auto v = m.triangles[t];
      if (f.reversed) std::swap(v[1], v[2]);
      out.triangles.push_back(v);
      triFace.push_back(f.face + 1);
    }
  }
  std::sort(out.faces.begin(), out.faces.end());
  if (!twice.empty()) {
    out.problem = "it uses " + faceList(twice) + " on both sides (an internal face)";
    return out;
  }
  if (!empty.empty()) {
    out.problem = faceList(empty) + (empty.size() == 1 ? " has" : " have") + " no triangle";
    return out;
  }
  if (!withQuads.empty()) {
    out.problem = faceList(withQuads) + (withQuads.size() == 1 ? " has" : " have") + " quads";
    return out;
  }
  // every directed edge once, and its reverse once: a closed, consistently oriented 2-manifold
  std::unordered_map<std::uint64_t, std::pair<int, int>> directed;  // edge -> (count, a triangle)
  directed.reserve(out.triangles.size() * 3);
  auto key = [](int a, int b) { return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b); };
  for (std::size_t t = 0; t < out.triangles.size(); ++t)
    for (int e = 0; e < 3; ++e) {
      auto& d = directed[key(out.triangles[t][e], out.triangles[t][(e + 1) % 3])];
      ++d.first;
      d.second = static_cast<int>(t);
    }
  int open = 0, overUsed = 0, misoriented = 0;
  std::set<int> where;
  for (const auto& [k, d] : directed) {
    const int a = static_cast<int>(k >> 32), b = static_cast<int>(k & 0xffffffffu);
    auto rev = directed.find(key(b, a));
    const int back = rev == directed.end() ? 0 : rev->second.first;
    const bool o = d.first == 1 && back == 0, over = d.first > 1, mis = d.first == 1 && back > 1;
    open += o;
    overUsed += over;
    misoriented += mis;
    if (o || over || mis) where.insert(triFace[d.second]);
  }
  if (open || overUsed || misoriented) {
    std::string s = "its surface mesh is not a closed 2-manifold:";
    if (open) s += " " + std::to_string(open) + " open edges";
    if (overUsed) s += std::string(open ? "," : "") + " " + std::to_string(overUsed) + " edges used more than twice";
    if (misoriented) s += std::string(open || overUsed ? "," : "") + " " + std::to_string(misoriented) + " misoriented edges";
    out.problem = s + " (on " + faceList(where) + ")";
    return out;
  }
  // enclosed volume by the divergence theorem: negative when the solid is inside out
  double v6 = 0;
  const Vec3 o = m.nodes[out.triangles[0][0]];
  for (const auto& t : out.triangles) v6 += tetVolume6(o, m.nodes[t[0]], m.nodes[t[1]], m.nodes[t[2]]);
  if (v6 < 0)
    for (auto& t : out.triangles) std::swap(t[1], t[2]);
  return out;
}

}  // namespace paramesh
