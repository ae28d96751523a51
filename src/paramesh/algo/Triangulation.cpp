// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/algo/Triangulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_map>

#include "paramesh/algo/Predicates.hpp"
#include "paramesh/util/Error.hpp"

namespace paramesh {

namespace {

/// Index of cell (x, y) of a 2^16 x 2^16 grid along a Hilbert curve.
uint64_t hilbertIndex(uint32_t x, uint32_t y) {
  uint64_t d = 0;
  for (uint32_t s = 1u << 15; s > 0; s >>= 1) {
    const uint32_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
    d += (uint64_t)s * s * ((3 * rx) ^ ry);
    if (ry == 0) {
      if (rx == 1) {
        x = (s - 1) - (x & (s - 1)) + (x & ~(s - 1));
        y = (s - 1) - (y & (s - 1)) + (y & ~(s - 1));
      }
      std::swap(x, y);
    }
  }
  return d;
}

/// Biased randomised insertion order (rounds of doubling size, each along a Hilbert curve): a
/// boundary inserted in its own order is the quadratic case of incremental Delaunay (every new
/// point flips across the long fan the previous ones left: screw.step at size 3e-4, 946 458
/// boundary segments, spent over 10 minutes inserting them); in this order it is O(n log n)
/// (test LargeBoundariesInRandomisedOrder...: 3.5 s against 11.9 s, checks included). Deterministic.
std::vector<int> brioOrder(const std::vector<TriVertex>& verts, int n, double x0, double y0, double span) {
  std::vector<std::pair<uint64_t, int>> key(n);
  for (int v = 0; v < n; ++v) {
    uint64_t h = (uint64_t)(v + 1) * 0x9E3779B97F4A7C15ULL;
    h ^= h >> 29;
    h *= 0xBF58476D1CE4E5B9ULL;
    h ^= h >> 32;
    const int level = std::min(40, __builtin_ctzll(h | (1ULL << 40)));  // P(level >= k) = 2^-k
    const double fx = (verts[v].uv.x - x0) / span, fy = (verts[v].uv.y - y0) / span;
    const uint32_t ix = (uint32_t)std::clamp(fx * 65535.0, 0.0, 65535.0);
    const uint32_t iy = (uint32_t)std::clamp(fy * 65535.0, 0.0, 65535.0);
    key[v] = {((uint64_t)(40 - level) << 32) | hilbertIndex(ix, iy), v};
  }
  std::sort(key.begin(), key.end());
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = key[i].second;
  return order;
}
inline int nx(int i) { return i == 2 ? 0 : i + 1; }
inline int pv(int i) { return i == 0 ? 2 : i - 1; }
inline uint64_t edgeKey(int a, int b) { return ((uint64_t)(uint32_t)a << 32) | (uint32_t)b; }
}  // namespace

void Triangulation::setConstrained(int t, int i, bool on) {
  Triangle& T = tris[t];
  if (on)
    T.cons |= (uint8_t)(1u << i);
  else
    T.cons &= (uint8_t)~(1u << i);
  int u = T.n[i];
  if (u >= 0) {
    int j = edgeTo(u, t);
    if (j >= 0) {
      if (on)
        tris[u].cons |= (uint8_t)(1u << j);
      else
        tris[u].cons &= (uint8_t)~(1u << j);
    }
  }
}

int Triangulation::newTri() {
  if (!freeTris_.empty()) {
    int t = freeTris_.back();
    freeTris_.pop_back();
    tris[t] = Triangle();
    return t;
  }
  tris.emplace_back();
  return (int)tris.size() - 1;
}

int Triangulation::locate(Vec2 p, int t, int* onEdge, int maxSteps) const {
  if (onEdge) *onEdge = -1;
  if (t < 0 || tris[t].dead) return -1;
  unsigned rot = 0;
  if (maxSteps <= 0) maxSteps = 4 * (int)tris.size() + 100;
  for (int step = 0; step < maxSteps; ++step) {
    const Triangle& T = tris[t];
    int moved = -1, zeroEdge = -1;
    rot = rot * 1103515245u + 12345u;
    int off = (int)((rot >> 16) % 3);
    for (int k = 0; k < 3; ++k) {
      int i = (k + off) % 3;
      const Vec2 a = verts[T.v[nx(i)]].uv, b = verts[T.v[pv(i)]].uv;
      int o = orient2d(a, b, p);
      if (o < 0) {
        moved = i;
        break;
      }
      if (o == 0) zeroEdge = i;
    }
    if (moved < 0) {
      if (onEdge) *onEdge = zeroEdge;
      return t;
    }
    if (T.n[moved] < 0 || isConstrained(t, moved)) return -1;
    t = T.n[moved];
  }
  return -1;
}

bool Triangulation::insertionIsValid(Vec2 p, int t, int e) const {
  if (t < 0 || tris[t].dead) return false;
  const Triangle& T = tris[t];
  if (e < 0) {
    for (int i = 0; i < 3; ++i)
      if (orient2d(verts[T.v[nx(i)]].uv, verts[T.v[pv(i)]].uv, p) <= 0) return false;
    return true;
  }
  // the triangles (c, a, p), (c, p, b) of t and (d, b, p), (d, p, a) across the edge a-b
  const Vec2 &a = verts[T.v[nx(e)]].uv, &b = verts[T.v[pv(e)]].uv, &c = verts[T.v[e]].uv;
  if (orient2d(c, a, p) <= 0 || orient2d(c, p, b) <= 0) return false;
  const int u = T.n[e];
  if (u < 0) return true;
  const int j = edgeTo(u, t);
  if (j < 0) return false;
  const Vec2& d = verts[tris[u].v[j]].uv;
  return orient2d(d, b, p) > 0 && orient2d(d, p, a) > 0;
}

double Triangulation::insertionClearance(Vec3 x, int t, int e) const {
  const Triangle& T = tris[t];
  double best = std::min({dist(x, verts[T.v[0]].xyz), dist(x, verts[T.v[1]].xyz), dist(x, verts[T.v[2]].xyz)});
  const int u = e >= 0 ? T.n[e] : -1;
  const int j = u >= 0 ? edgeTo(u, t) : -1;
  if (j >= 0) best = std::min(best, dist(x, verts[tris[u].v[j]].xyz));
  return best;
}

bool Triangulation::flipIsValid(int t, int i) const {
  const Triangle& T = tris[t];
  int u = T.n[i];
  if (u < 0) return false;
  int j = edgeTo(u, t);
  if (j < 0) return false;
  const int a = T.v[i], b = T.v[nx(i)], c = T.v[pv(i)], d = tris[u].v[j];
  // new triangles (a,b,d) and (a,d,c)
  return orient2d(verts[a].uv, verts[b].uv, verts[d].uv) > 0 && orient2d(verts[a].uv, verts[d].uv, verts[c].uv) > 0;
}

bool Triangulation::flip(int t, int i) {
  if (!flipIsValid(t, i)) return false;
  Triangle& T = tris[t];
  const int u = T.n[i];
  const int j = edgeTo(u, t);
  Triangle& U = tris[u];
  const int a = T.v[i], b = T.v[nx(i)], c = T.v[pv(i)], d = U.v[j];
  // neighbours and constraint flags of the outer edges
  const int Nca = T.n[nx(i)], Nab = T.n[pv(i)];
  const bool Cca = isConstrained(t, nx(i)), Cab = isConstrained(t, pv(i));
  // in U = (d, c, b) starting at j: U.v[j]=d, U.v[nx(j)]=c, U.v[pv(j)]=b
  const int Nbd = U.n[nx(j)], Ndc = U.n[pv(j)];
  const bool Cbd = isConstrained(u, nx(j)), Cdc = isConstrained(u, pv(j));
  T.v[0] = a; T.v[1] = b; T.v[2] = d;
  T.n[0] = Nbd; T.n[1] = u; T.n[2] = Nab;
  T.cons = (uint8_t)((Cbd ? 1 : 0) | (Cab ? 4 : 0));
  U.v[0] = a; U.v[1] = d; U.v[2] = c;
  U.n[0] = Ndc; U.n[1] = Nca; U.n[2] = t;
  U.cons = (uint8_t)((Cdc ? 1 : 0) | (Cca ? 2 : 0));
  if (Nbd >= 0) { int k = edgeTo(Nbd, u); if (k >= 0) tris[Nbd].n[k] = t; }
  if (Nca >= 0) { int k = edgeTo(Nca, t); if (k >= 0) tris[Nca].n[k] = u; }
  verts[a].tri = t; verts[b].tri = t; verts[d].tri = t; verts[c].tri = u;
  return true;
}

void Triangulation::legalize(std::vector<std::pair<int, int>>& stack, int v, const FlipTest& test,
                             std::vector<int>* touched) {
  int guard = 0;
  while (!stack.empty() && guard++ < 100000) {
    auto [t, i] = stack.back();
    stack.pop_back();
    if (tris[t].dead || tris[t].v[i] != v) {
      int k = indexOf(t, v);
      if (k < 0) continue;
      i = k;
    }
    if (tris[t].n[i] < 0 || isConstrained(t, i)) continue;
    if (!test(t, i)) continue;
    const int u = tris[t].n[i];
    if (!flip(t, i)) continue;
    if (touched) { touched->push_back(t); touched->push_back(u); }
    // after the flip, t = (v, b, d) and u = (v, d, c): the edges opposite v are t:0 and u:0
    stack.emplace_back(t, 0);
    stack.emplace_back(u, 0);
  }
}

void Triangulation::insert(int v, int t, int e, const FlipTest& test, std::vector<int>* touched) {
  std::vector<std::pair<int, int>> stack;
  if (e < 0) {
    Triangle T = tris[t];
    const int a = T.v[0], b = T.v[1], c = T.v[2];
    const int Nbc = T.n[0], Nca = T.n[1], Nab = T.n[2];
    const bool Cbc = T.cons & 1, Cca = T.cons & 2, Cab = T.cons & 4;
    const int t0 = t, t1 = newTri(), t2 = newTri();
    Triangle& A = tris[t0];
    A.v[0] = v; A.v[1] = b; A.v[2] = c; A.n[0] = Nbc; A.n[1] = t1; A.n[2] = t2; A.cons = Cbc ? 1 : 0; A.dead = false;
    Triangle& B = tris[t1];
    B.v[0] = v; B.v[1] = c; B.v[2] = a; B.n[0] = Nca; B.n[1] = t2; B.n[2] = t0; B.cons = Cca ? 1 : 0;
    Triangle& C = tris[t2];
    C.v[0] = v; C.v[1] = a; C.v[2] = b; C.n[0] = Nab; C.n[1] = t0; C.n[2] = t1; C.cons = Cab ? 1 : 0;
    if (Nca >= 0) { int k = edgeTo(Nca, t); if (k >= 0) tris[Nca].n[k] = t1; }
    if (Nab >= 0) { int k = edgeTo(Nab, t); if (k >= 0) tris[Nab].n[k] = t2; }
    verts[v].tri = t0; verts[a].tri = t1; verts[b].tri = t0; verts[c].tri = t0;
    if (touched) { touched->push_back(t0); touched->push_back(t1); touched->push_back(t2); }
    stack = {{t0, 0}, {t1, 0}, {t2, 0}};
  } else {
    Triangle T = tris[t];
    const int a = T.v[e], b = T.v[nx(e)], c = T.v[pv(e)];
    const int u = T.n[e];
    const bool Cedge = isConstrained(t, e);
    const int Nca = T.n[nx(e)], Nab = T.n[pv(e)];
    const bool Cca = isConstrained(t, nx(e)), Cab = isConstrained(t, pv(e));
    const int t0 = t, t1 = newTri();
    int u0 = -1, u1 = -1, d = -1, Ndc = -1, Nbd = -1;
    bool Cdc = false, Cbd = false;
    if (u >= 0) {
      Triangle U = tris[u];
      const int j = edgeTo(u, t);
      PM_CHECK(j >= 0, "triangle adjacency is not symmetric");
      d = U.v[j];
      Nbd = U.n[nx(j)];  // U = (d, c, b): edge opposite c is (b, d)
      Ndc = U.n[pv(j)];  // edge opposite b is (d, c)
      Cbd = isConstrained(u, nx(j));
      Cdc = isConstrained(u, pv(j));
      u0 = u;
      u1 = newTri();
    }
    // t0 = (a,b,v), t1 = (a,v,c)
    Triangle& A = tris[t0];
    A.v[0] = a; A.v[1] = b; A.v[2] = v;
    A.n[0] = u1; A.n[1] = t1; A.n[2] = Nab;
    A.cons = (uint8_t)((Cedge ? 1 : 0) | (Cab ? 4 : 0));
    A.dead = false;
    Triangle& B = tris[t1];
    B.v[0] = a; B.v[1] = v; B.v[2] = c;
    B.n[0] = u0; B.n[1] = Nca; B.n[2] = t0;
    B.cons = (uint8_t)((Cedge ? 1 : 0) | (Cca ? 2 : 0));
    if (Nca >= 0) { int k = edgeTo(Nca, t); if (k >= 0) tris[Nca].n[k] = t1; }
    verts[a].tri = t0; verts[b].tri = t0; verts[c].tri = t1; verts[v].tri = t0;
    if (u >= 0) {
      // u0 = (d,c,v), u1 = (d,v,b)
      Triangle& C = tris[u0];
      C.v[0] = d; C.v[1] = c; C.v[2] = v;
      C.n[0] = t1; C.n[1] = u1; C.n[2] = Ndc;
      C.cons = (uint8_t)((Cedge ? 1 : 0) | (Cdc ? 4 : 0));
      Triangle& D = tris[u1];
      D.v[0] = d; D.v[1] = v; D.v[2] = b;
      D.n[0] = t0; D.n[1] = Nbd; D.n[2] = u0;
      D.cons = (uint8_t)((Cedge ? 1 : 0) | (Cbd ? 2 : 0));
      if (Nbd >= 0) { int k = edgeTo(Nbd, u); if (k >= 0) tris[Nbd].n[k] = u1; }
      verts[d].tri = u0;
      stack.emplace_back(u0, 2);  // edge opposite v in u0 is (d,c)
      stack.emplace_back(u1, 1);  // edge opposite v in u1 is (b,d)
      if (touched) { touched->push_back(u0); touched->push_back(u1); }
    } else {
      A.n[0] = -1;
      B.n[0] = -1;
    }
    if (touched) { touched->push_back(t0); touched->push_back(t1); }
    stack.emplace_back(t0, 2);  // (a,b)
    stack.emplace_back(t1, 1);  // (c,a)
  }
  legalize(stack, v, test, touched);
}

bool Triangulation::delaunayFlip(int t, int i) const {
  const Triangle& T = tris[t];
  int u = T.n[i];
  int j = edgeTo(u, t);
  int d = tris[u].v[j];
  const TriVertex &A = verts[T.v[0]], &B = verts[T.v[1]], &C = verts[T.v[2]];
  if ((A.flags | B.flags | C.flags | verts[d].flags) & VF_SUPER) {
    // keep the auxiliary box out of the circle tests: flip whenever it removes a super vertex edge
    const bool superEdge = (verts[T.v[nx(i)]].flags & VF_SUPER) || (verts[T.v[pv(i)]].flags & VF_SUPER);
    const bool superOpp = (verts[T.v[i]].flags & VF_SUPER) || (verts[d].flags & VF_SUPER);
    if (superEdge && !superOpp) return true;
    if (superOpp) return false;
  }
  return incircle(A.uv, B.uv, C.uv, verts[d].uv) > 0;
}

bool Triangulation::metricFlip(int t, int i) const {
  const Triangle& T = tris[t];
  int u = T.n[i];
  int j = edgeTo(u, t);
  int d = tris[u].v[j];
  const TriVertex *P[4] = {&verts[T.v[0]], &verts[T.v[1]], &verts[T.v[2]], &verts[d]};
  double a = 0, b = 0, c = 0;
  for (auto* p : P) { a += p->M[0]; b += p->M[1]; c += p->M[2]; }
  // Cholesky of the mean metric: x' = (sqrt(a) x + b/sqrt(a) y, sqrt(c - b^2/a) y)
  if (!(a > 0)) return incircle(P[0]->uv, P[1]->uv, P[2]->uv, P[3]->uv) > 0;
  const double sa = std::sqrt(a), r = c - b * b / a;
  if (!(r > 0)) return incircle(P[0]->uv, P[1]->uv, P[2]->uv, P[3]->uv) > 0;
  const double sr = std::sqrt(r), ba = b / sa;
  const Vec2 o = P[3]->uv;
  Vec2 q[4];
  for (int k = 0; k < 4; ++k) {
    Vec2 w = P[k]->uv - o;
    q[k] = {sa * w.x + ba * w.y, sr * w.y};
  }
  const double l1 = std::fabs(q[0].x) + std::fabs(q[0].y), l2 = l1 * l1;  // std::pow(l1, 4) was 1.5 % of a run
  return incircle(q[0], q[1], q[2], q[3]) > 1e-12 * (l2 * l2 + 1e-300);
}

void Triangulation::ring(int v, std::vector<int>& out, bool* closed) const {
  out.clear();
  int t0 = verts[v].tri;
  if (closed) *closed = true;
  if (t0 < 0 || tris[t0].dead) return;
  // rotate clockwise to find the boundary start (if any): across the edge (v, v[nx(k)])... use
  // the edge opposite v[pv(k)], which is (v, next vertex); its neighbour precedes t in CCW order.
  int t = t0;
  int guard = 0;
  while (guard++ < 10000) {
    int k = indexOf(t, v);
    int prev = tris[t].n[pv(k)];  // across edge (v, v[nx(k)])
    if (prev < 0) {
      if (closed) *closed = false;
      break;
    }
    if (prev == t0) break;
    t = prev;
  }
  const int start = t;
  guard = 0;
  t = start;
  do {
    out.push_back(t);
    int k = indexOf(t, v);
    int next = tris[t].n[nx(k)];  // across edge (v, v[pv(k)])
    if (next < 0) break;
    t = next;
  } while (t != start && guard++ < 10000);
}

bool Triangulation::isEmptyEar(int p, int q, const std::vector<int>& chain, size_t m) const {
  const Vec2 P = verts[p].uv, Q = verts[q].uv, C = verts[chain[m]].uv;
  if (orient2d(P, Q, C) <= 0) return false;
  // the polygon's other vertices: none inside or on the ear, no edge across its two new sides
  for (size_t i = 0; i < chain.size(); ++i) {
    if (i == m) continue;
    const Vec2 X = verts[chain[i]].uv;
    if (orient2d(P, Q, X) >= 0 && orient2d(Q, C, X) >= 0 && orient2d(C, P, X) >= 0) return false;
  }
  std::vector<int> ring{p};
  ring.insert(ring.end(), chain.begin(), chain.end());
  ring.push_back(q);
  for (size_t i = 0; i + 1 < ring.size(); ++i) {
    const Vec2 X = verts[ring[i]].uv, Y = verts[ring[i + 1]].uv;
    if (segmentsCross(P, C, X, Y) || segmentsCross(C, Q, X, Y)) return false;
  }
  return true;
}

void Triangulation::triangulatePseudo(int p, int q, const std::vector<int>& chain,
                                      std::vector<std::array<int, 3>>& out, bool exact) const {
  if (chain.empty()) return;
  size_t m = chain.size();
  for (size_t i = 0; i < chain.size(); ++i) {
    if (exact && !isEmptyEar(p, q, chain, i)) continue;
    if (m == chain.size() || incircle(verts[p].uv, verts[q].uv, verts[chain[m]].uv, verts[chain[i]].uv) > 0) m = i;
  }
  if (m == chain.size()) m = 0;  // no empty ear (not a simple polygon): the caller's checks fail
  out.push_back({p, q, chain[m]});
  std::vector<int> left(chain.begin(), chain.begin() + m);
  std::vector<int> right(chain.begin() + m + 1, chain.end());
  triangulatePseudo(p, chain[m], left, out, exact);
  triangulatePseudo(chain[m], q, right, out, exact);
}

bool Triangulation::recoverSegment(int a, int b, std::string& why, int depth) {
  if (depth > 64) {
    why = "too many collinear boundary points";
    return false;
  }
  if (a == b) return true;
  const Vec2 pa = verts[a].uv, pb = verts[b].uv;
  std::vector<int> rt;
  ring(a, rt);
  int start = -1, right = -1, left = -1;
  for (int t : rt) {
    int k = indexOf(t, a);
    int x = tris[t].v[nx(k)], y = tris[t].v[pv(k)];
    if (x == b || y == b) {  // already an edge
      int e = x == b ? pv(k) : nx(k);
      setConstrained(t, e, true);
      return true;
    }
  }
  for (int t : rt) {
    int k = indexOf(t, a);
    int x = tris[t].v[nx(k)], y = tris[t].v[pv(k)];
    int ox = orient2d(pa, verts[x].uv, pb), oy = orient2d(pa, verts[y].uv, pb);
    if (ox == 0 && dot(verts[x].uv - pa, pb - pa) > 0) {  // x lies on segment a-b
      return recoverSegment(a, x, why, depth + 1) && recoverSegment(x, b, why, depth + 1);
    }
    if (oy == 0 && dot(verts[y].uv - pa, pb - pa) > 0) {
      return recoverSegment(a, y, why, depth + 1) && recoverSegment(y, b, why, depth + 1);
    }
    if (ox > 0 && oy < 0) {
      start = t;
      right = x;
      left = y;
      break;
    }
  }
  if (start < 0) {
    why = "cannot find the start of a boundary segment";
    return false;
  }
  std::vector<int> removed{start}, leftChain{left}, rightChain{right};
  int t = start;
  int guard = 0;
  while (guard++ < 1000000) {
    // crossing edge (right, left) of t; move to the neighbour
    int k = indexOf(t, right);
    int e = pv(k);  // edge (left... ) check: edge opposite v[pv(k)] is (v[k], v[nx(k)])
    // find the edge of t made of {right,left}
    e = -1;
    for (int i = 0; i < 3; ++i) {
      int p = tris[t].v[nx(i)], q = tris[t].v[pv(i)];
      if ((p == right && q == left) || (p == left && q == right)) e = i;
    }
    if (e < 0) { why = "internal error while recovering a boundary segment"; return false; }
    if (isConstrained(t, e)) {
      // name where: the two segments' ends in 3D (the user finds the place; a developer the cause)
      auto at = [&](int v) {
        const Vec3& x = verts[v].xyz;
        char buf[96];
        std::snprintf(buf, sizeof buf, "(%.6g, %.6g, %.6g)", x.x, x.y, x.z);
        return std::string(buf);
      };
      why = "two boundary segments cross in (u,v): " + at(a) + "-" + at(b) + " and " + at(right) + "-" + at(left);
      return false;
    }
    int u = tris[t].n[e];
    if (u < 0) { why = "a boundary segment leaves the triangulation"; return false; }
    int j = edgeTo(u, t);
    int z = tris[u].v[j];
    removed.push_back(u);
    if (z == b) break;
    int oz = orient2d(pa, pb, verts[z].uv);
    if (oz == 0) {
      // z lies on the segment: recover a-z and z-b separately (after undoing nothing: the
      // triangulation is unchanged so far)
      return recoverSegment(a, z, why, depth + 1) && recoverSegment(z, b, why, depth + 1);
    }
    if (oz > 0) {
      leftChain.push_back(z);
      left = z;
    } else {
      rightChain.push_back(z);
      right = z;
    }
    t = u;
  }
  // collect boundary of the removed region
  std::sort(removed.begin(), removed.end());
  removed.erase(std::unique(removed.begin(), removed.end()), removed.end());
  struct Outer { int nb; bool cons; };
  std::unordered_map<uint64_t, Outer> outer;  // directed edge (p,q) of the region boundary (CCW)
  for (int r : removed) {
    for (int i = 0; i < 3; ++i) {
      int nb = tris[r].n[i];
      if (nb >= 0 && std::binary_search(removed.begin(), removed.end(), nb)) continue;
      int p = tris[r].v[nx(i)], q = tris[r].v[pv(i)];
      outer[edgeKey(p, q)] = {nb, isConstrained(r, i)};
    }
  }
  std::vector<std::array<int, 3>> nt;
  std::vector<int> rc(rightChain.rbegin(), rightChain.rend());
  triangulatePseudo(a, b, leftChain, nt);
  triangulatePseudo(b, a, rc, nt);
  // the floating-point incircle can pick a wrong apex among nearly collinear chain points (a
  // straight pcurve a few 1e-10 off a parameter line, sheet_metal_54 Face3): triangles come out
  // clockwise. Then the pseudo-polygons again, with only apexes that make an empty ear (exact)
  bool ccw = true;
  for (const auto& tr : nt) ccw = ccw && orient2d(verts[tr[0]].uv, verts[tr[1]].uv, verts[tr[2]].uv) > 0;
  if (!ccw) {
    nt.clear();
    triangulatePseudo(a, b, leftChain, nt, true);
    triangulatePseudo(b, a, rc, nt, true);
  }
  if (nt.size() != removed.size()) {
    why = "boundary recovery produced an inconsistent triangulation";
    return false;
  }
  std::unordered_map<uint64_t, std::pair<int, int>> inner;
  for (size_t k = 0; k < nt.size(); ++k) {
    int id = removed[k];
    Triangle& T = tris[id];
    T = Triangle();
    for (int i = 0; i < 3; ++i) T.v[i] = nt[k][i];
    for (int i = 0; i < 3; ++i) verts[T.v[i]].tri = id;
  }
  for (size_t k = 0; k < nt.size(); ++k) {
    int id = removed[k];
    Triangle& T = tris[id];
    for (int i = 0; i < 3; ++i) {
      int p = T.v[nx(i)], q = T.v[pv(i)];
      auto it = outer.find(edgeKey(p, q));
      if (it != outer.end()) {
        T.n[i] = it->second.nb;
        if (it->second.cons) T.cons |= (uint8_t)(1u << i);
        if (it->second.nb >= 0) {
          Triangle& N = tris[it->second.nb];
          for (int m = 0; m < 3; ++m)
            if (N.v[nx(m)] == q && N.v[pv(m)] == p) N.n[m] = id;
        }
        continue;
      }
      auto jt = inner.find(edgeKey(q, p));
      if (jt != inner.end()) {
        T.n[i] = jt->second.first;
        tris[jt->second.first].n[jt->second.second] = id;
        inner.erase(jt);
      } else {
        inner[edgeKey(p, q)] = {id, i};
      }
    }
  }
  if (!inner.empty()) {
    why = "boundary recovery left unmatched edges";
    return false;
  }
  // mark a-b
  for (int r : removed) {
    int ka = indexOf(r, a), kb = indexOf(r, b);
    if (ka >= 0 && kb >= 0) {
      int e = 3 - ka - kb;
      setConstrained(r, e, true);
      return true;
    }
  }
  why = "boundary segment missing after recovery";
  return false;
}

/// Boundaries up to this many points are inserted in their own order (fast enough, and the
/// meshes of every benchmark case stay as they were); larger ones in brioOrder().
constexpr int kOrderedInsertionMax = 20000;

bool Triangulation::buildConstrained(const std::vector<std::pair<int, int>>& segments, std::string& why) {
  const int nReal = (int)verts.size();
  if (nReal < 3) {
    why = "fewer than 3 boundary points";
    return false;
  }
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (auto& v : verts) {
    x0 = std::min(x0, v.uv.x); x1 = std::max(x1, v.uv.x);
    y0 = std::min(y0, v.uv.y); y1 = std::max(y1, v.uv.y);
  }
  const double span = std::max(x1 - x0, y1 - y0);
  if (!(span > 0) || !std::isfinite(span)) {
    why = "boundary has zero extent in (u,v)";
    return false;
  }
  const double m = 0.5 * span;
  TriVertex s;
  s.flags = VF_SUPER;
  int s0, s1, s2, s3;
  s.uv = {x0 - m, y0 - m}; s0 = addVertex(s);
  s.uv = {x1 + m, y0 - m}; s1 = addVertex(s);
  s.uv = {x1 + m, y1 + m}; s2 = addVertex(s);
  s.uv = {x0 - m, y1 + m}; s3 = addVertex(s);
  tris.clear();
  freeTris_.clear();
  int A = newTri(), B = newTri();
  tris[A].v[0] = s0; tris[A].v[1] = s1; tris[A].v[2] = s2; tris[A].n[1] = B;
  tris[B].v[0] = s0; tris[B].v[1] = s2; tris[B].v[2] = s3; tris[B].n[2] = A;
  verts[s0].tri = A; verts[s1].tri = A; verts[s2].tri = A; verts[s3].tri = B;
  FlipTest dt = [this](int t, int i) { return delaunayFlip(t, i); };
  int last = A;
  std::vector<int> order;
  if (nReal > kOrderedInsertionMax) order = brioOrder(verts, nReal, x0, y0, span);
  for (int k = 0; k < nReal; ++k) {
    const int v = order.empty() ? k : order[k];
    int e;
    int t = locate(verts[v].uv, last, &e);
    if (t < 0) t = locate(verts[v].uv, A, &e);
    if (t < 0) {  // the walks failed: test every triangle (a walk from each was cubic in all)
      const Vec2 q = verts[v].uv;
      for (size_t k = 0; k < tris.size() && t < 0; ++k) {
        const Triangle& T = tris[k];
        if (T.dead) continue;
        int o[3];
        for (int i = 0; i < 3; ++i) o[i] = orient2d(verts[T.v[nx(i)]].uv, verts[T.v[pv(i)]].uv, q);
        if (o[0] >= 0 && o[1] >= 0 && o[2] >= 0) {
          t = (int)k;
          e = o[0] == 0 ? 0 : o[1] == 0 ? 1 : o[2] == 0 ? 2 : -1;
        }
      }
    }
    if (t < 0) {
      why = "point location failed for a boundary point";
      return false;
    }
    // duplicate point?
    for (int k = 0; k < 3; ++k) {
      const Vec2 q = verts[tris[t].v[k]].uv;
      if (q.x == verts[v].uv.x && q.y == verts[v].uv.y) {
        why = "two boundary points coincide in (u,v)";
        return false;
      }
    }
    insert(v, t, e, dt);
    last = verts[v].tri;
  }
  for (auto& sg : segments) {
    if (!recoverSegment(sg.first, sg.second, why)) return false;
  }
  // classify by parity from the super vertices
  std::vector<int8_t> state(tris.size(), -1);
  std::vector<int> queue;
  int seed = verts[s0].tri;
  state[seed] = 0;
  queue.push_back(seed);
  for (size_t qi = 0; qi < queue.size(); ++qi) {
    int t = queue[qi];
    for (int i = 0; i < 3; ++i) {
      int u = tris[t].n[i];
      if (u < 0) continue;
      int8_t s2v = (int8_t)(state[t] ^ (isConstrained(t, i) ? 1 : 0));
      if (state[u] < 0) {
        state[u] = s2v;
        queue.push_back(u);
      } else if (state[u] != s2v) {
        why = "the boundary loops are not closed or cross each other in (u,v)";
        return false;
      }
    }
  }
  int inside = 0;
  for (size_t t = 0; t < tris.size(); ++t) {
    if (tris[t].dead) continue;
    const Triangle& T = tris[t];
    bool sup = (verts[T.v[0]].flags | verts[T.v[1]].flags | verts[T.v[2]].flags) & VF_SUPER;
    if (state[t] != 1 || sup) {
      if (state[t] == 1 && sup) {
        why = "a boundary loop touches the auxiliary box";
        return false;
      }
      tris[t].dead = true;
    } else {
      ++inside;
    }
  }
  if (inside == 0) {
    why = "no triangle inside the boundary";
    return false;
  }
  for (size_t t = 0; t < tris.size(); ++t) {
    if (tris[t].dead) continue;
    for (int i = 0; i < 3; ++i) {
      int u = tris[t].n[i];
      if (u >= 0 && tris[u].dead) tris[t].n[i] = -1;
    }
    for (int i = 0; i < 3; ++i) verts[tris[t].v[i]].tri = (int)t;
  }
  // every boundary vertex must still be used; drop super vertices
  compact();
  // the auxiliary box bent the circle tests near the hull: restore the constrained Delaunay
  // property among the real points by flips (each flip removes a local violation)
  for (int sweep = 0; sweep < 64; ++sweep) {
    int flips = 0;
    for (int t = 0; t < (int)tris.size(); ++t)
      for (int i = 0; i < 3; ++i) {
        const int u = tris[t].n[i];
        if (u < t || isConstrained(t, i)) continue;
        if (delaunayFlip(t, i) && flip(t, i)) ++flips;
      }
    if (!flips) break;
  }
  for (int v = 0; v < (int)verts.size(); ++v)
    if (verts[v].tri < 0) {
      why = "a boundary point is outside the face domain";
      return false;
    }
  return true;
}

std::vector<int> Triangulation::compact() {
  std::vector<int> tmap(tris.size(), -1);
  std::vector<Triangle> nt;
  nt.reserve(tris.size());
  for (size_t t = 0; t < tris.size(); ++t)
    if (!tris[t].dead) {
      tmap[t] = (int)nt.size();
      nt.push_back(tris[t]);
    }
  std::vector<int> used(verts.size(), 0);
  for (auto& T : nt)
    for (int i = 0; i < 3; ++i) used[T.v[i]] = 1;
  std::vector<int> vmap(verts.size(), -1);
  std::vector<TriVertex> nv;
  nv.reserve(verts.size());
  for (size_t v = 0; v < verts.size(); ++v) {
    const bool keep = used[v] || (!(verts[v].flags & (VF_SUPER | VF_DEAD)) && verts[v].node >= 0);
    if (keep) {
      vmap[v] = (int)nv.size();
      nv.push_back(verts[v]);
      nv.back().tri = -1;
    }
  }
  for (auto& T : nt) {
    for (int i = 0; i < 3; ++i) {
      T.v[i] = vmap[T.v[i]];
      T.n[i] = T.n[i] >= 0 ? tmap[T.n[i]] : -1;
    }
  }
  for (size_t t = 0; t < nt.size(); ++t)
    for (int i = 0; i < 3; ++i) nv[nt[t].v[i]].tri = (int)t;
  tris.swap(nt);
  verts.swap(nv);
  freeTris_.clear();
  return vmap;
}

}  // namespace paramesh
