// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/size/Sources.hpp"

#include <algorithm>
#include <cmath>

#include "paramesh/model/EdgeDiscretizer.hpp"
#include "paramesh/model/FaceDomain.hpp"

namespace paramesh {

double curvatureFromD2(const SurfaceD2& d) {
  const Vec3 c = cross(d.du, d.dv);
  const double lc = norm(c);
  const double E = dot(d.du, d.du), F = dot(d.du, d.dv), G = dot(d.dv, d.dv);
  const double W = E * G - F * F;
  if (!(lc > 1e-12 * std::sqrt(E * G)) || !(W > 0)) return 0.0;
  const Vec3 n = c * (1.0 / lc);
  const double L = dot(d.duu, n), M = dot(d.duv, n), N = dot(d.dvv, n);
  const double K = (L * N - M * M) / W;
  const double H = (E * N - 2 * F * M + G * L) / (2 * W);
  const double k = std::fabs(H) + std::sqrt(std::max(H * H - K, 0.0));
  return std::isfinite(k) ? k : 0.0;
}

double maxCurvature(const ISurface& s, Vec2 uv) {
  SurfaceD2 d;
  s.d2(uv, d);
  return curvatureFromD2(d);
}

double curvatureSize(double k, double angleRad, double deviation, double hmin, double hmax) {
  if (!(k > 0) || !std::isfinite(k)) return hmax;
  double h = hmax;
  // the target is a little below angle * R: mesh edges range up to ~1.3x their target, and the
  // angle is a bound on what an element subtends, not an average
  if (angleRad > 0) h = std::min(h, 0.75 * angleRad / k);
  if (deviation > 0) h = std::min(h, std::sqrt(8.0 * deviation / k));
  return std::clamp(h, hmin, hmax);
}

namespace {

struct FaceSampler {
  const ISurface& s;
  const FaceDomain& dom;
  double angle, deviation, hmin, hmax;
  std::vector<SizeSource>& out;
  long budget;
  long evals = 0;
  bool truncated = false;

  struct Cell {
    Vec2 lo, hi;
    int depthU, depthV;
  };

  /// One evaluation (second derivatives) at the cell centre gives the size asked there and the
  /// cell's 3D extent along u and v (first order); cells larger than the size are split, leaves
  /// emit a source. A cell is halved only across the directions in which it is long (at least
  /// half its other extent), so that leaves are about square in 3D: where the parametrisation is
  /// stretched (blade surfaces near their leading edge) splitting both ways would make leaves
  /// far thinner than the size in one direction and multiply the sources by their aspect ratio.
  /// Level by level (breadth first), so that a face that runs out of its budget is sampled
  /// evenly one level short, not in full up to some cell and at the base grid after it.
  void run(std::vector<Cell> level) {
    std::vector<Cell> next;
    while (!level.empty()) {
      next.clear();
      for (const Cell& q : level) {
        const Vec2 lo = q.lo, hi = q.hi, c = 0.5 * (lo + hi);
        const int depthU = q.depthU, depthV = q.depthV;
        SurfaceD2 d;
        s.d2(c, d);
        ++evals;
        const double k = curvatureFromD2(d);
        const double h = curvatureSize(k, angle, deviation, hmin, hmax);
        const double eu = norm(d.du) * (hi.x - lo.x), ev = norm(d.dv) * (hi.y - lo.y);
        const bool splitU = depthU < 10 && eu >= 0.5 * ev, splitV = depthV < 10 && ev >= 0.5 * eu;
        const bool wanted = (splitU || splitV) && eu + ev > 1.2 * h && h < hmax;
        if (wanted && evals + (long)next.size() >= budget) truncated = true;
        if (wanted && evals + (long)next.size() < budget) {
          if (splitU && splitV) {
            next.push_back({lo, c, depthU + 1, depthV + 1});
            next.push_back({{c.x, lo.y}, {hi.x, c.y}, depthU + 1, depthV + 1});
            next.push_back({{lo.x, c.y}, {c.x, hi.y}, depthU + 1, depthV + 1});
            next.push_back({c, hi, depthU + 1, depthV + 1});
          } else if (splitU) {
            next.push_back({lo, {c.x, hi.y}, depthU + 1, depthV});
            next.push_back({{c.x, lo.y}, hi, depthU + 1, depthV});
          } else {
            next.push_back({lo, {hi.x, c.y}, depthU, depthV + 1});
            next.push_back({{lo.x, c.y}, hi, depthU, depthV + 1});
          }
          continue;
        }
        if (h < hmax && dom.inside(c)) out.push_back({d.p, h});
      }
      level.swap(next);
    }
  }
};

}  // namespace

std::vector<SizeSource> faceCurvatureSources(const IGeometryModel& m, int f, double angleRad, double hmin,
                                             double hmax, double deviation, FaceSamplingStats* stats, long budget) {
  std::vector<SizeSource> out;
  auto s = m.makeSurface(f);
  if (s->kind() == SurfaceKind::Plane) return out;
  FaceDomain dom(m, f, *s);
  UVBox b = dom.box();
  if (!(b.u1 > b.u0) || !(b.v1 > b.v0)) return out;
  // base grid: roughly square cells of 3D size ~ hmax
  auto lenU = [&](double v) {
    double L = 0;
    Vec3 prev = s->eval({b.u0, v});
    for (int i = 1; i <= 16; ++i) {
      Vec3 p = s->eval({b.u0 + (b.u1 - b.u0) * i / 16, v});
      L += dist(p, prev);
      prev = p;
    }
    return L;
  };
  auto lenV = [&](double u) {
    double L = 0;
    Vec3 prev = s->eval({u, b.v0});
    for (int i = 1; i <= 16; ++i) {
      Vec3 p = s->eval({u, b.v0 + (b.v1 - b.v0) * i / 16});
      L += dist(p, prev);
      prev = p;
    }
    return L;
  };
  double Lu = 0, Lv = 0;
  for (int i = 0; i < 3; ++i) {
    Lu = std::max(Lu, lenU(b.v0 + (b.v1 - b.v0) * (i + 0.5) / 3));
    Lv = std::max(Lv, lenV(b.u0 + (b.u1 - b.u0) * (i + 0.5) / 3));
  }
  const int nu = std::clamp((int)std::ceil(Lu / hmax), 4, 256);
  const int nv = std::clamp((int)std::ceil(Lv / hmax), 4, 256);
  FaceSampler fs{*s, dom, angleRad, deviation, hmin, hmax, out, budget};
  std::vector<FaceSampler::Cell> base;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      Vec2 lo{b.u0 + (b.u1 - b.u0) * i / nu, b.v0 + (b.v1 - b.v0) * j / nv};
      Vec2 hi{b.u0 + (b.u1 - b.u0) * (i + 1) / nu, b.v0 + (b.v1 - b.v0) * (j + 1) / nv};
      base.push_back({lo, hi, 0, 0});
    }
  fs.run(std::move(base));
  if (stats) {
    stats->cells = fs.evals;
    stats->truncated = fs.truncated;
  }
  return out;
}

std::vector<SizeSource> edgeCurvatureSources(const IGeometryModel& m, int e, double angleRad, double hmin,
                                             double hmax, double deviation) {
  std::vector<SizeSource> out;
  if (m.edgeDegenerate(e)) return out;
  auto c = m.makeCurve(e);
  if (!c || c->kind() == CurveKind::Line) return out;
  double t0, t1;
  m.edgeRange(e, t0, t1);
  CurveSampling cs = sampleCurve(*c, t0, t1, nullptr);
  for (size_t i = 0; i < cs.t.size(); ++i) {
    Vec3 p, d1, d2;
    c->d2(cs.t[i], p, d1, d2);
    const double l = norm(d1);
    if (!(l > 0)) continue;
    const double k = norm(cross(d1, d2)) / (l * l * l);
    if (!(k > 0) || !std::isfinite(k)) continue;
    const double h = curvatureSize(k, angleRad, deviation, hmin, hmax);
    if (h < hmax) out.push_back({p, h});
  }
  // refine between samples where the size is small compared to the spacing
  std::vector<SizeSource> extra;
  for (size_t i = 0; i + 1 < out.size(); ++i) {
    const double gap = dist(out[i].p, out[i + 1].p);
    const double h = std::min(out[i].h, out[i + 1].h);
    const int k = std::min(64, (int)(gap / h));
    for (int j = 1; j < k; ++j)
      extra.push_back({out[i].p + (double)j / k * (out[i + 1].p - out[i].p), h});
  }
  out.insert(out.end(), extra.begin(), extra.end());
  return out;
}

std::vector<SizeSource> localSizeSources(const IGeometryModel& m, const LocalSize& ls) {
  std::vector<SizeSource> out;
  const double h = ls.size;
  for (int ent : ls.entities) {
    const int i = ent - 1;
    if (ls.kind == LocalSize::Kind::Vertex) {
      out.push_back({m.vertexPoint(i), h});
    } else if (ls.kind == LocalSize::Kind::Edge) {
      if (m.edgeDegenerate(i)) continue;
      auto c = m.makeCurve(i);
      double t0, t1;
      m.edgeRange(i, t0, t1);
      CurveSampling cs = sampleCurve(*c, t0, t1, nullptr);
      const int n = std::max(1, (int)std::ceil(cs.length() / (0.5 * h)));
      size_t j = 0;
      for (int k = 0; k <= n; ++k) {
        const double target = cs.length() * k / n;
        while (j + 1 < cs.s.size() && cs.s[j + 1] < target) ++j;
        if (j + 1 >= cs.s.size()) {
          out.push_back({cs.p.back(), h});
          continue;
        }
        const double w = cs.s[j + 1] > cs.s[j] ? (target - cs.s[j]) / (cs.s[j + 1] - cs.s[j]) : 0;
        out.push_back({cs.p[j] + w * (cs.p[j + 1] - cs.p[j]), h});
      }
    } else {
      auto s = m.makeSurface(i);
      FaceDomain dom(m, i, *s);
      const UVBox b = dom.box();
      // grid fine enough that neighbouring samples are <= h/2 apart in 3D
      double Lu = 0, Lv = 0;
      for (int r = 0; r < 3; ++r) {
        const double v = b.v0 + (b.v1 - b.v0) * (r + 0.5) / 3, u = b.u0 + (b.u1 - b.u0) * (r + 0.5) / 3;
        Vec3 pu = s->eval({b.u0, v}), pv = s->eval({u, b.v0});
        double lu = 0, lv = 0;
        for (int k = 1; k <= 32; ++k) {
          Vec3 qu = s->eval({b.u0 + (b.u1 - b.u0) * k / 32, v});
          Vec3 qv = s->eval({u, b.v0 + (b.v1 - b.v0) * k / 32});
          lu += dist(pu, qu);
          lv += dist(pv, qv);
          pu = qu;
          pv = qv;
        }
        Lu = std::max(Lu, lu);
        Lv = std::max(Lv, lv);
      }
      const int nu = std::clamp((int)std::ceil(Lu / (0.5 * h)), 1, 4000);
      const int nv = std::clamp((int)std::ceil(Lv / (0.5 * h)), 1, 4000);
      for (int a = 0; a <= nu; ++a)
        for (int c = 0; c <= nv; ++c) {
          const Vec2 uv{b.u0 + (b.u1 - b.u0) * a / nu, b.v0 + (b.v1 - b.v0) * c / nv};
          if (dom.inside(uv)) out.push_back({s->eval(uv), h});
        }
      // and its boundary edges, so that the size holds up to the face border
      for (const Wire& w : m.faceWires(i))
        for (const EdgeUse& u : w.uses) {
          LocalSize el;
          el.kind = LocalSize::Kind::Edge;
          el.entities = {u.edge + 1};
          el.size = h;
          auto es = localSizeSources(m, el);
          out.insert(out.end(), es.begin(), es.end());
        }
    }
  }
  return out;
}

}  // namespace paramesh
