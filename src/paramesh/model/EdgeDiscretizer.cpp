// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/model/EdgeDiscretizer.hpp"

#include <algorithm>
#include <cmath>

namespace paramesh {

namespace {
struct Sampler {
  const ICurve& c;
  const SizeField* f;
  CurveSampling& out;
  void rec(double ta, Vec3 pa, Vec3 da, double tb, Vec3 pb, Vec3 db, int depth) {
    const double tm = 0.5 * (ta + tb);
    Vec3 pm, dm;
    c.d1(tm, pm, dm);
    const double chord = dist(pa, pb);
    const double dev = dist(pm, 0.5 * (pa + pb));
    bool split = depth < 3;
    if (!split && depth < 18) {
      // chord error, tangent turning, or too coarse for the size field
      const double ca = dot(normalized(da), normalized(db));
      if (dev > 0.005 * chord || ca < 0.995) split = true;
      else if (f && chord > 0.2 * f->size(pm)) split = true;
    }
    if (split) {
      rec(ta, pa, da, tm, pm, dm, depth + 1);
      rec(tm, pm, dm, tb, pb, db, depth + 1);
    } else {
      out.t.push_back(tb);
      out.p.push_back(pb);
      const double ang = std::acos(std::clamp(dot(normalized(da), normalized(db)), -1.0, 1.0));
      if (std::isfinite(ang)) out.turning += ang;
    }
  }
};
}  // namespace

CurveSampling sampleCurve(const ICurve& c, double t0, double t1, const SizeField* field) {
  CurveSampling cs;
  Vec3 pa, da, pb, db;
  c.d1(t0, pa, da);
  cs.t.push_back(t0);
  cs.p.push_back(pa);
  Sampler s{c, field, cs};
  // start from 4 spans so that closed curves are not mistaken for points
  const int n0 = 4;
  for (int k = 0; k < n0; ++k) {
    const double ta = t0 + (t1 - t0) * k / n0, tb = t0 + (t1 - t0) * (k + 1) / n0;
    c.d1(ta, pa, da);
    c.d1(tb, pb, db);
    s.rec(ta, pa, da, tb, pb, db, 0);
  }
  cs.s.resize(cs.p.size());
  cs.s[0] = 0;
  for (size_t i = 1; i < cs.p.size(); ++i) cs.s[i] = cs.s[i - 1] + dist(cs.p[i - 1], cs.p[i]);
  return cs;
}

std::vector<double> discretizeCurve(const CurveSampling& cs, const SizeField& field, int minSegments,
                                    double maxTurn) {
  return discretizeCurve(cs, [&field](Vec3 x) { return field.size(x); }, minSegments, maxTurn);
}

std::vector<double> discretizeCurve(const CurveSampling& cs, const std::function<double(Vec3)>& size, int minSegments,
                                    double maxTurn) {
  const size_t m = cs.t.size();
  std::vector<double> F(m, 0.0);
  double prev = 1.0 / size(cs.p[0]);
  for (size_t i = 1; i < m; ++i) {
    const double cur = 1.0 / size(cs.p[i]);
    F[i] = F[i - 1] + 0.5 * (prev + cur) * (cs.s[i] - cs.s[i - 1]);
    prev = cur;
  }
  const double total = F.back();
  int n = (int)std::lround(total);
  n = std::max(n, 1);
  n = std::max(n, minSegments);
  // at most maxTurn of tangent turning per segment, but the turning asks for at most 10 x the
  // size's count plus two full turns at the limit: a damaged B-spline whose derivative flips
  // between samples (a fuzzed propeller_and_shaft.iges: 748 000 rad of "turning" on a 108 mm
  // edge) asked for 714 480 segments
  if (maxTurn > 0) {
    const double byTurn = std::ceil(cs.turning / maxTurn - 1e-9);
    n = std::max(n, (int)std::min(byTurn, 10.0 * std::ceil(total) + std::ceil(4 * M_PI / maxTurn) + 6.0));
  }
  std::vector<double> t(n + 1);
  t[0] = cs.t.front();
  t[n] = cs.t.back();
  if (total <= 0) {
    for (int k = 1; k < n; ++k) t[k] = t[0] + (t[n] - t[0]) * k / n;
    return t;
  }
  size_t j = 0;
  for (int k = 1; k < n; ++k) {
    const double target = total * k / n;
    while (j + 1 < m && F[j + 1] < target) ++j;
    const double a = F[j], b = F[j + 1];
    const double w = b > a ? (target - a) / (b - a) : 0.5;
    t[k] = cs.t[j] + w * (cs.t[j + 1] - cs.t[j]);
  }
  return t;
}

}  // namespace paramesh
