// SPDX-License-Identifier: LGPL-2.1-or-later
// Edge collapses: a free vertex merges into a neighbour, to remove edges far below the local size
// or a sliver's apex, when the link condition holds and every relabelled triangle stays valid.

#include "paramesh/algo/optimizer/Optimizer.hpp"

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include "paramesh/algo/optimizer/OptimizerDetail.hpp"

namespace paramesh {
using namespace optimizer_detail;

bool Optimizer::collapse(int t, int i, bool centroidFacing) {
  // collapse edge i of t = (a -> b), where a = v[nx(i)] must be free; b may be anything
  Triangle& tr = T_.tris[t];
  const int a = tr.v[nx(i)], b = tr.v[pv(i)];
  const int u = tr.n[i];
  if (u < 0) return false;
  // ring of a
  bool closed = true;
  std::vector<int> ra;
  T_.ring(a, ra, &closed);
  if (!closed) return false;
  // link condition: common neighbours of a and b are exactly the two opposite vertices
  std::vector<int> na, nb;
  for (int r : ra) {
    int k = T_.indexOf(r, a);
    na.push_back(T_.tris[r].v[nx(k)]);
  }
  std::vector<int> rb;
  bool closedB = true;
  T_.ring(b, rb, &closedB);
  for (int r : rb) {
    int k = T_.indexOf(r, b);
    nb.push_back(T_.tris[r].v[nx(k)]);
    nb.push_back(T_.tris[r].v[pv(k)]);
  }
  std::sort(na.begin(), na.end());
  std::sort(nb.begin(), nb.end());
  nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
  int common = 0;
  for (int x : na)
    if (std::binary_search(nb.begin(), nb.end(), x)) ++common;
  if (common != 2) return false;
  // validity of the relabelled triangles
  for (int r : ra) {
    if (r == t || r == u) continue;
    const Triangle& R = T_.tris[r];
    int k = T_.indexOf(r, a);
    int v0 = R.v[0], v1 = R.v[1], v2 = R.v[2];
    if (k == 0) v0 = b;
    if (k == 1) v1 = b;
    if (k == 2) v2 = b;
    if (!valid(v0, v1, v2) && !(centroidFacing && facesAtCentroid(v0, v1, v2))) return false;
    if (deviationBounded() && !deviationOk(v0, v1, v2, 0)) return false;
  }
  // relink around the two dying triangles
  for (int dying : {t, u}) {
    const Triangle& D = T_.tris[dying];
    const int ka = T_.indexOf(dying, a), kb = T_.indexOf(dying, b);
    // edge opposite b contains a (and x); edge opposite a contains b (and x)
    const int nA = D.n[kb];  // across (a,x): will be relabelled to (b,x)
    const int nB = D.n[ka];  // across (x,b)
    const bool cA = T_.isConstrained(dying, kb), cB = T_.isConstrained(dying, ka);
    const int x = D.v[3 - ka - kb];
    if (nA >= 0) {
      int e = T_.edgeTo(nA, dying);
      T_.tris[nA].n[e] = nB;
      if (cA || cB) T_.tris[nA].cons |= (uint8_t)(1u << e);
    }
    if (nB >= 0) {
      int e = T_.edgeTo(nB, dying);
      T_.tris[nB].n[e] = nA;
      if (cA || cB) T_.tris[nB].cons |= (uint8_t)(1u << e);
    }
    T_.verts[x].tri = nA >= 0 ? nA : nB;
    T_.verts[b].tri = nA >= 0 ? nA : nB;
  }
  for (int r : ra) {
    if (r == t || r == u) continue;
    int k = T_.indexOf(r, a);
    T_.tris[r].v[k] = b;
    T_.verts[b].tri = r;
  }
  T_.tris[t].dead = true;
  T_.tris[u].dead = true;
  T_.verts[a].flags |= VF_DEAD;
  T_.verts[a].tri = -1;
  return true;
}

int Optimizer::collapsePass(double shortRatio, double maxRatio) {
  int n = 0;
  for (int t = 0; t < (int)T_.tris.size(); ++t) {
    poll(t);
    if (T_.tris[t].dead) continue;
    for (int i = 0; i < 3; ++i) {
      const Triangle& tr = T_.tris[t];
      if (T_.isConstrained(t, i) || tr.n[i] < 0) continue;
      int a = tr.v[nx(i)], b = tr.v[pv(i)];
      if (edgeRatio(a, b) >= shortRatio) continue;
      // collapse the free vertex onto the other one
      auto freeV = [&](int v) { return !(T_.verts[v].flags & VF_FIXED); };
      int tt = t, ii = i;
      if (!freeV(a)) {
        if (!freeV(b)) continue;
        // orient so that the free vertex is v[nx(i)]: use the neighbour triangle
        tt = tr.n[i];
        ii = T_.edgeTo(tt, t);
        std::swap(a, b);
      }
      // new edges around b must not get too long
      std::vector<int> ra;
      T_.ring(a, ra);
      bool tooLong = false;
      for (int r : ra) {
        const Triangle& R = T_.tris[r];
        for (int k = 0; k < 3; ++k) {
          int w = R.v[k];
          if (w == a || w == b) continue;
          const TriVertex &B = T_.verts[b], &W = T_.verts[w];
          if (dist(B.xyz, W.xyz) / (0.5 * (B.h + W.h)) > maxRatio) tooLong = true;
        }
      }
      if (tooLong) continue;
      if (collapse(tt, ii)) {
        ++n;
        break;
      }
    }
  }
  return n;
}

int Optimizer::collapsePoorApexes() {
  std::vector<int> cands;
  for (int t = 0; t < (int)T_.tris.size(); ++t)
    if (!T_.tris[t].dead && poorAngle(t)) cands.push_back(t);
  int n = 0;
  for (int t : cands)
    if (!T_.tris[t].dead && poorAngle(t) && collapseApex(t)) ++n;
  return n;
}

bool Optimizer::collapseApex(int t) {
  // free vertices by decreasing angle (a cap's apex stands on the opposite edge), each collapsed
  // onto a neighbour in t, the nearer first
  const Triangle tr = T_.tris[t];
  std::array<std::pair<double, int>, 3> byAngle;
  for (int j = 0; j < 3; ++j) {
    const Vec3 p = T_.verts[tr.v[j]].xyz;
    const Vec3 u = normalized(T_.verts[tr.v[nx(j)]].xyz - p), w = normalized(T_.verts[tr.v[pv(j)]].xyz - p);
    byAngle[j] = {dot(u, w), j};  // cosine: smallest first = largest angle first
  }
  std::sort(byAngle.begin(), byAngle.end());
  for (const auto& ba : byAngle) {
    const int k = ba.second;
    const int vk = tr.v[k];
    if (T_.verts[vk].flags & VF_FIXED) continue;
    // its two edges in t (edge e contains k when e != k), shorter first
    int e1 = nx(k), e2 = pv(k);
    const double l1 = dist(T_.verts[vk].xyz, T_.verts[tr.v[pv(k)]].xyz);  // edge nx(k) = (k, pv(k))
    const double l2 = dist(T_.verts[vk].xyz, T_.verts[tr.v[nx(k)]].xyz);  // edge pv(k) = (nx(k), k)
    if (l2 < l1) std::swap(e1, e2);
    for (int i : {e1, e2}) {
      if (T_.isConstrained(t, i)) continue;
      int tt = t, ii = i;
      if (tr.v[nx(i)] != vk) {
        tt = tr.n[i];
        if (tt < 0) continue;
        ii = T_.edgeTo(tt, t);
        if (ii < 0 || T_.tris[tt].v[nx(ii)] != vk) continue;
      }
      if (collapse(tt, ii, true)) return true;
    }
  }
  return false;
}

}  // namespace paramesh
