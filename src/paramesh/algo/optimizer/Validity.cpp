// SPDX-License-Identifier: LGPL-2.1-or-later
// The checks every operator applies to the triangles it would make: 3D quality, validity in
// (u,v) and facing like the surface, so no operation can fold or flip the mesh over the face.

#include "paramesh/algo/optimizer/Optimizer.hpp"

#include "paramesh/algo/Predicates.hpp"
#include "paramesh/algo/optimizer/OptimizerDetail.hpp"

namespace paramesh {
using namespace optimizer_detail;

namespace {
// the cosine a triangle's normal must keep with a surface normal (~78 degrees)
constexpr double kFacing = 0.2;
// the normal of triangle (a,b,c) makes a cosine of at least minCos with every vertex normal
// (vertices without one do not count); false for a degenerate triangle. n: its unnormalised normal.
bool facesVertexNormals(const TriVertex& a, const TriVertex& b, const TriVertex& c, double minCos, Vec3& n) {
  n = cross(b.xyz - a.xyz, c.xyz - a.xyz);
  const double ln = norm(n);
  if (!(ln > 0)) return false;
  for (const TriVertex* v : {&a, &b, &c})
    if (norm2(v->normal) > 0 && dot(n, v->normal) < minCos * ln) return false;
  return true;
}
}  // namespace

double Optimizer::quality(int t) const {
  const Triangle& tr = T_.tris[t];
  const TriVertex &a = T_.verts[tr.v[0]], &b = T_.verts[tr.v[1]], &c = T_.verts[tr.v[2]];
  if (poleCollapsed(a, b, c)) return 1.0;
  return gamma3(a.xyz, b.xyz, c.xyz);
}

bool Optimizer::valid(int ia, int ib, int ic) const {
  const TriVertex &a = T_.verts[ia], &b = T_.verts[ib], &c = T_.verts[ic];
  if (orient2d(a.uv, b.uv, c.uv) <= 0) return false;
  if (poleCollapsed(a, b, c)) return true;
  if (anyWrapsAcross(a, b, c)) return false;
  // the triangle must face like the surface at each vertex (allowing curvature)
  Vec3 n;
  if (!facesVertexNormals(a, b, c, kFacing, n)) return false;
  // a triangle along a fold's crest (no vertex normal): like the surface at its centroid's foot
  if (a.flags & b.flags & c.flags & VF_CREST) return facesAtCentroid(ia, ib, ic);
  return true;
}

bool Optimizer::facesAtCentroid(int ia, int ib, int ic) const {
  const TriVertex &a = T_.verts[ia], &b = T_.verts[ib], &c = T_.verts[ic];
  Vec3 n;
  if (orient2d(a.uv, b.uv, c.uv) <= 0 || !facesVertexNormals(a, b, c, 0.0, n)) return false;
  if (anyWrapsAcross(a, b, c)) return false;
  // and like it at one corner at least: a triangle square to every corner's normal lies across
  // the surface, e.g. in the plane of the boundary around a pole (a half body of revolution)
  if (norm(n) > 0 && bestCornerCos(a, b, c, n) < kFacing) return false;
  Vec2 s = (1.0 / 3) * (a.uv + b.uv + c.uv);
  Vec3 foot, nf;
  if (!C_.project((1.0 / 3) * (a.xyz + b.xyz + c.xyz), s, foot)) return false;
  if (!C_.surf.normal(C_.toParam(s), nf)) return false;
  return dot(n, nf) >= kFacing * norm(n);
}

double Optimizer::edgeRatio(int a, int b) const {
  const TriVertex &A = T_.verts[a], &B = T_.verts[b];
  return dist(A.xyz, B.xyz) / (0.5 * (A.h + B.h));
}

}  // namespace paramesh
