// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/algo/Predicates.hpp"

#include <cmath>

namespace paramesh {
namespace {

// Error-free transformations: a+b = s+e and a*b = p+e exactly (round-to-nearest).
inline void twoSum(double a, double b, double& s, double& e) {
  s = a + b;
  double bb = s - a;
  e = (a - (s - bb)) + (b - bb);
}
inline void twoProd(double a, double b, double& p, double& e) {
  p = a * b;
  e = std::fma(a, b, -p);
}

// Adds b to the nonoverlapping expansion e[0..n) (increasing magnitude), in place; returns new length.
int growExpansion(double* e, int n, double b) {
  double q = b;
  int m = 0;
  for (int i = 0; i < n; ++i) {
    double s, err;
    twoSum(q, e[i], s, err);
    q = s;
    if (err != 0.0) e[m++] = err;
  }
  if (q != 0.0 || m == 0) e[m++] = q;
  return m;
}

int exactOrient(Vec2 a, Vec2 b, Vec2 c) {
  // det = ax*by - ax*cy - cx*by - ay*bx + ay*cx + cy*bx, each product split exactly in two.
  const double prods[6][2] = {{a.x, b.y}, {-a.x, c.y}, {-c.x, b.y}, {-a.y, b.x}, {a.y, c.x}, {c.y, b.x}};
  double e[16];
  int n = 0;
  for (const auto& pr : prods) {
    double p, err;
    twoProd(pr[0], pr[1], p, err);
    n = growExpansion(e, n, p);
    n = growExpansion(e, n, err);
  }
  for (int i = n - 1; i >= 0; --i)
    if (e[i] != 0.0) return e[i] > 0 ? 1 : -1;
  return 0;
}

}  // namespace

int orient2d(Vec2 a, Vec2 b, Vec2 c) {
  const double l = (a.x - c.x) * (b.y - c.y);
  const double r = (a.y - c.y) * (b.x - c.x);
  const double det = l - r;
  const double bound = 3.3306690738754716e-16 * (std::fabs(l) + std::fabs(r));
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return exactOrient(a, b, c);
}

double incircle(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const double adx = a.x - d.x, ady = a.y - d.y;
  const double bdx = b.x - d.x, bdy = b.y - d.y;
  const double cdx = c.x - d.x, cdy = c.y - d.y;
  const double alift = adx * adx + ady * ady;
  const double blift = bdx * bdx + bdy * bdy;
  const double clift = cdx * cdx + cdy * cdy;
  return alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy) + clift * (adx * bdy - bdx * ady);
}

bool segmentsCross(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const int o1 = orient2d(a, b, c), o2 = orient2d(a, b, d);
  const int o3 = orient2d(c, d, a), o4 = orient2d(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  // collinear overlap counts as crossing when interiors overlap
  if (o1 == 0 && o2 == 0) {
    auto along = [&](Vec2 p) { return dot(p - a, b - a); };
    double L = dot(b - a, b - a), s = along(c), t = along(d);
    if (s > t) std::swap(s, t);
    return t > 0 && s < L && !(s == 0 && t == 0);
  }
  return false;
}

}  // namespace paramesh
