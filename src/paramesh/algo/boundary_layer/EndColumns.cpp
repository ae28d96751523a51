// SPDX-License-Identifier: LGPL-2.1-or-later
// End columns: where an open run ends at a non-BL edge, its outermost column runs along that edge on
// the edge's own nodes (or is marched square to the BL edge); the columns near an end lean towards it.

#include "paramesh/algo/boundary_layer/FaceLayers.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <vector>

namespace paramesh::bl_detail {

namespace {

/// An end column along a neighbouring edge must leave the BL edge at this sine (10 degrees) or more
/// (measured: docs/tuning/boundary_layer.md).
constexpr double kMinEndSine = 0.17364817766693033;

}  // namespace

/// Number of loop points after (dir = +1) or before (dir = -1) index i that form the end column:
/// consecutive distances equal the row heights.
int FaceLayers::endColumnLength(int L, int i, int dir, const LayerLaw& law) const {
  const auto& lp = loops_[L];
  const int n = (int)lp.size();
  int k = 0;
  int cur = ((i % n) + n) % n;  // a run that wraps past the loop's first point passes i >= n
  while (k < law.layers) {
    const int nxt = ((cur + dir) % n + n) % n;
    if (isBL(dir > 0 ? lp[cur] : lp[nxt])) break;
    // nor onto the root of another run: where a non-BL edge of exactly the first height joins
    // two BL edges, both runs' end columns would climb along it onto each other's root, and
    // their first rows would cross (measured: docs/tuning/boundary_layer.md)
    if (isBL(dir > 0 ? lp[nxt] : lp[((nxt - 1) % n + n) % n])) break;
    const double d = dist(lp[cur].xyz, lp[nxt].xyz);
    if (std::fabs(d - law.height(k)) > 1e-3 * law.height(k)) break;
    ++k;
    cur = nxt;
  }
  return k;
}

/// The end column at loop point i, the first point (`first`) or the last of an open run of npts
/// points growing into side sgn; base holds its root and spec.
void FaceLayers::addEndColumn(int L, int i, bool first, int npts, double sgn, Column base,
                              std::vector<Column>& cols) const {
  const auto& lp = loops_[L];
  const int n = (int)lp.size();
  auto at = [&](int j) -> const LoopPoint& { return lp[((j % n) + n) % n]; };
  const LoopPoint& p = at(i);
  const LayerLaw& law = laws_[base.spec];
  // end column: its points are the neighbouring edge's first nodes
  const int dir = first ? -1 : +1;
  int len = endColumnLength(L, i, dir, law);
  // An end column runs along the neighbouring edge. Where that edge carries on almost in
  // line with the BL edge, the column lies along the BL edge's own line: in a run of one
  // segment (no marched column) the rows between the two end columns cross the face, in a
  // longer run the first quad has a straight corner. Such an end gets no column along it:
  // within 30 degrees of straight in a run of one segment, within 10 in a longer one
  // (measured: docs/tuning/boundary_layer.md).
  bool marchEnd = false;
  Vec3 inward{0, 0, 0};  // square to the BL edge, into the face
  if (len > 0) {
    const Vec3 back = at(i - dir).xyz - p.xyz, along = at(i + dir).xyz - p.xyz;
    const double lb = norm(back), la = norm(along);
    const double straight = npts == 2 ? kPi / 6 : kPi / 18;
    // The column must also leave into the face: where the neighbouring edge turns away from
    // the layer's side (a reflex corner of the face), rows along it stand outside the face,
    // and where it leaves almost back along the BL edge (a sliver corner of the face), the
    // first quads get corners of a degree or two. It must leave at 10 degrees or more; in a
    // run of one segment, whose rows join the two end columns directly, at 30 or more
    // (measured: docs/tuning/boundary_layer.md).
    if (lb > 0 && la > 0) {
      const bool inLine = dot(back, along) < -std::cos(straight) * lb * la;
      inward = sgn * normalized(cross(normalAt(p.uv), (-dir / lb) * back));
      const bool known = norm2(inward) > 0;
      if (inLine || (known && dot(along, inward) < (npts == 2 ? 0.5 : kMinEndSine) * la)) len = 0;
      // Such an end gets a column marched square to the BL edge instead, when the
      // neighbouring edge carries on in line (a one-segment edge between tangent arcs got no
      // rows at all) or turns away (a reflex corner): that direction lies inside the face.
      // At a sliver corner it would leave the face at once. (Marching also the ends whose
      // neighbouring edge got no column points, a short one, raised the hand-off jump: not done;
      // measured: docs/tuning/boundary_layer.md.)
      marchEnd = known && (inLine || dot(along, inward) < 0);
    }
  }
  if (marchEnd) {
    Column c = base;
    c.dir = inward;
    cols.push_back(c);
  return;
  }

  base.fixed = true;
  base.active = false;
  base.stop = len >= law.layers ? 0 : 5;
  for (int k = 1; k <= len; ++k) {
    const LoopPoint& q = at(i + dir * k);
    base.uv.push_back(q.uv);
    base.xyz.push_back(q.xyz);
    base.ref.push_back(q.node);
  }
  cols.push_back(base);
}

/// Near a run end, columns lean towards the outermost column (which runs along the neighbouring
/// edge, at whatever angle that edge makes): the weights wEnd of marchDirection.
void FaceLayers::leanTowardsEnds(std::vector<Column>& cols, bool closed) const {
  if (!closed && cols.size() > 2) {
    double thick = 0;
    for (const auto& c : cols) thick = std::max(thick, laws_[c.spec].offset(laws_[c.spec].layers));
    std::vector<double> s(cols.size(), 0);
    for (size_t i = 1; i < cols.size(); ++i) s[i] = s[i - 1] + dist(cols[i].xyz[0], cols[i - 1].xyz[0]);
    const double total = s.back();
    for (size_t i = 0; i < cols.size(); ++i) {
      if (cols[i].fixed) continue;
      auto w = [&](double d) { return std::max(0.0, 1.0 - d / std::max(1.2 * thick, 1e-300)); };
      if (cols.front().fixed && cols.front().xyz.size() > 1) cols[i].wEnd[0] = w(s[i]);
      if (cols.back().fixed && cols.back().xyz.size() > 1) cols[i].wEnd[1] = w(total - s[i]);
    }
  }
}

/// A run whose two end columns run up the sides of a three-sided face to one apex: the last
/// rows leave a region between the top edge and the apex. Rows are taken off both end columns
/// until the loop points next to the two tops stand at least 1/1.5 of the last row's height
/// above the top edge (the layer points stay on the edges, as nodes of the region above), so
/// that the triangles on the top edge are not much flatter than the row below them.
void FaceLayers::trimAtApex(int L, int a, int nseg, bool closed, std::vector<Column>& cols) const {
  if (closed || cols.size() < 2) return;
  Column &c0 = cols.front(), &c1 = cols.back();
  if (!c0.fixed || !c1.fixed || c0.xyz.size() < 2 || c1.xyz.size() < 2) return;
  const auto& lp = loops_[L];
  const int n = (int)lp.size();
  auto idx = [&](int i) { return ((i % n) + n) % n; };
  // far vertex of the first column's edge (walking back from a) and of the last's (forward)
  const int e0 = lp[idx(a - 1)].edge, e1 = lp[idx(a + nseg)].edge;
  if (e0 < 0 || e1 < 0) return;
  int p = a - 1, q = a + nseg + 1, guard = 0;
  while (lp[idx(p - 1)].edge == e0 && ++guard < n) --p;
  while (lp[idx(q)].edge == e1 && ++guard < 2 * n) ++q;
  if (idx(p) != idx(q)) return;  // more than one edge between the two sides: no apex
  const LayerLaw& law = laws_[c0.spec];
  for (;;) {
    const int k = (int)std::min(c0.xyz.size(), c1.xyz.size()) - 1;  // rows of the run's ends
    if (k < 2) return;
    const Vec3 A = c0.xyz[k], B = c1.xyz[k];
    const double w = dist(A, B);
    if (!(w > 0)) return;
    // the loop points next to the two tops (further up the sides, or the apex) stand over the
    // top edge: the triangles on it take one of them
    const Vec3 X = lp[idx(a - k - 1)].xyz, Y = lp[idx(a + nseg + k + 1)].xyz;
    const double depth = std::min(norm(cross(B - A, X - A)), norm(cross(B - A, Y - A))) / w;
    if (depth * 1.5 >= law.height(k - 1)) return;
    for (Column* c : {&c0, &c1}) {
      while ((int)c->xyz.size() > k) {
        c->uv.pop_back();
        c->xyz.pop_back();
        c->ref.pop_back();
      }
      c->stop = 5;
    }
  }
}

}  // namespace paramesh::bl_detail
