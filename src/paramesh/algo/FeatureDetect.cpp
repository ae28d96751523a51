// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/algo/FeatureDetect.hpp"

#include <algorithm>
#include <cmath>

namespace paramesh {

namespace {

/// Normal curvature of the surface at uv in the 3D tangent direction d.
double normalCurvature(const SurfaceD2& s, Vec3 d) {
  const Vec3 c = cross(s.du, s.dv);
  const double lc = norm(c);
  if (!(lc > 0)) return 0;
  const Vec3 n = c * (1.0 / lc);
  // d = a S_u + b S_v (least squares in the tangent plane)
  const double E = dot(s.du, s.du), F = dot(s.du, s.dv), G = dot(s.dv, s.dv), W = E * G - F * F;
  if (!(W > 0)) return 0;
  const double p = dot(s.du, d), q = dot(s.dv, d);
  const double a = (G * p - F * q) / W, b = (E * q - F * p) / W;
  const double I = E * a * a + 2 * F * a * b + G * b * b;
  const double II = dot(s.duu, n) * a * a + 2 * dot(s.duv, n) * a * b + dot(s.dvv, n) * b * b;
  return I > 0 ? std::fabs(II / I) : 0;
}

/// Walks on the surface from (uv, p) along the tangent direction dir (small re-projected steps,
/// direction transported) and returns the normal curvature in the walking direction at each step
/// (index k at distance (k+1) * step). Stops early when the walk leaves the face's parameter box.
std::vector<double> curvatureProfile(const ISurface& s, Vec2 uv, Vec3 p, Vec3 dir, double step, int n) {
  std::vector<double> out;
  const UVBox box = s.bounds();
  const double mu = 1e-9 * (box.u1 - box.u0), mv = 1e-9 * (box.v1 - box.v0);
  for (int k = 0; k < n; ++k) {
    SurfaceD2 d;
    s.d2(uv, d);
    const double E = dot(d.du, d.du), F = dot(d.du, d.dv), G = dot(d.dv, d.dv), W = E * G - F * F;
    if (!(W > 0)) break;
    const Vec3 st = step * dir;
    const double a = dot(d.du, st), b = dot(d.dv, st);
    Vec2 q{uv.x + (G * a - F * b) / W, uv.y + (E * b - F * a) / W};
    Vec3 np;
    s.project(p + st, q, &np, 0.0);
    const bool uper = s.uPeriod() > 0, vper = s.vPeriod() > 0;
    if ((!uper && (q.x <= box.u0 + mu || q.x >= box.u1 - mu)) || (!vper && (q.y <= box.v0 + mv || q.y >= box.v1 - mv)))
      break;  // left the face's parameter box
    const Vec3 moved = np - p;
    if (norm(moved) < 0.5 * step) break;
    SurfaceD2 e;
    s.d2(q, e);
    const Vec3 n = normalized(cross(e.du, e.dv));
    Vec3 nd = normalized(moved);
    nd = nd - dot(nd, n) * n;
    if (norm2(nd) < 1e-20) break;
    dir = normalized(nd);
    uv = q;
    p = np;
    out.push_back(normalCurvature(e, dir));
  }
  return out;
}

}  // namespace

std::vector<RidgeCandidate> proposeLeadingEdges(const IGeometryModel& m, double maxRadius, double minRatio,
                                                double maxDihedralDeg, std::vector<RidgeCandidate>* all,
                                                const std::vector<int>* edgeRep) {
  std::vector<RidgeCandidate> out, scored;
  const double cosMax = std::cos(maxDihedralDeg * M_PI / 180.0);
  // faces around each edge, through coincident twins (unsewn faces) when edgeRep is given
  std::vector<std::vector<std::pair<int, int>>> around(m.numEdges());  // (face, member edge)
  for (int e = 0; e < m.numEdges(); ++e) {
    const int r = edgeRep ? (*edgeRep)[e] : e;
    for (int f : m.edgeFaces(e)) around[r].emplace_back(f, e);
  }
  for (int e = 0; e < m.numEdges(); ++e) {
    if (m.edgeDegenerate(e) || (edgeRep && (*edgeRep)[e] != e)) continue;
    const auto& faces = around[e];
    if (faces.size() != 2) continue;  // a ridge is between two faces (free and seam edges are not)
    auto curve = m.makeCurve(e);
    double t0, t1;
    m.edgeRange(e, t0, t1);
    RidgeCandidate rc;
    rc.edge = e;
    rc.acrossCurvature = 1e300;
    double minDot = 1;
    bool ok = true;
    bool peak = true;  // the curvature across is a local maximum at the edge, on both sides
    const int ns = 9;
    for (int k = 1; k < ns && ok; ++k) {
      const double t = t0 + (t1 - t0) * k / ns;
      Vec3 p, dt;
      curve->d1(t, p, dt);
      const Vec3 tan = normalized(dt);
      Vec3 normals[2];
      for (int side = 0; side < 2; ++side) {
        const int f = faces[side].first, member = faces[side].second;
        auto s = m.makeSurface(f);
        // seed from the pcurve of (any) use of e in f
        Vec2 uv{0, 0};
        bool seeded = false;
        const auto& wires = m.faceWires(f);
        for (size_t w = 0; w < wires.size() && !seeded; ++w)
          for (size_t u = 0; u < wires[w].uses.size(); ++u)
            if (wires[w].uses[u].edge == member) {
              if (auto pc = m.makePCurve(f, (int)w, (int)u)) {
                // the twin's parameter differs: seed from the twin's curve point nearest to p
                double a0, a1;
                m.edgeRange(member, a0, a1);
                double tm = t;
                if (member != e) {
                  auto mc = m.makeCurve(member);
                  tm = mc->project(p, a0 + (a1 - a0) * (t - t0) / (t1 - t0), std::min(a0, a1), std::max(a0, a1));
                }
                uv = pc->eval(tm);
                seeded = true;
              }
              break;
            }
        if (!seeded && !s->projectGlobal(p, uv)) {
          ok = false;
          break;
        }
        s->project(p, uv, nullptr, 0.0);
        SurfaceD2 d;
        s->d2(uv, d);
        Vec3 n = normalized(cross(d.du, d.dv));
        if (m.faceReversed(f)) n = -n;
        normals[side] = n;
        Vec3 across = normalized(cross(n, tan));
        const double k0 = normalCurvature(d, across);
        rc.acrossCurvature = std::min(rc.acrossCurvature, k0);
        rc.alongCurvature = std::max(rc.alongCurvature, normalCurvature(d, tan));
        if (k0 > 0 && k == ns / 2) {
          // into the face: the across direction pointing inside is the one whose step stays in it
          // a nose: the curvature across peaks near the edge (within 2 radii, the split line may
          // sit a little off the nose) and is much lower 6 radii into the face; a uniformly
          // round face (a wing-tip cap) is not a leading edge
          const double r0 = 1.0 / k0;
          std::vector<double> prof;
          for (double sgn2 : {1.0, -1.0}) {
            auto pr = curvatureProfile(*s, uv, p, sgn2 * across, 0.25 * r0, 24);
            if (pr.size() > prof.size()) prof = pr;  // the walk that stays in the face
          }
          double kpeak = k0, k1 = -1;
          for (size_t q = 0; q < prof.size(); ++q) {
            if (q < 8) kpeak = std::max(kpeak, prof[q]);
          }
          if (prof.size() == 24) k1 = prof.back();
          if (!(k1 >= 0 && k1 < 0.5 * kpeak)) peak = false;
        }
      }
      if (ok) minDot = std::min(minDot, dot(normals[0], normals[1]));
    }
    if (!ok) continue;
    rc.dihedralDeg = std::acos(std::clamp(minDot, -1.0, 1.0)) * 180.0 / M_PI;
    rc.ratio = rc.acrossCurvature / std::max(rc.alongCurvature, 1e-12 * rc.acrossCurvature + 1e-300);
    const bool smooth = minDot >= cosMax;
    const bool sharpEnough = maxRadius <= 0 || rc.acrossCurvature * maxRadius >= 1.0;
    rc.peak = peak;
    if (smooth && sharpEnough && peak && rc.ratio >= minRatio) out.push_back(rc);
    scored.push_back(rc);
  }
  // a leading edge continues over smooth, tangent-continuous edges curving as much across it (a
  // rounded wing tip): follow them from the proposed edges
  auto tangentAt = [&](int e, int end) {
    auto c = m.makeCurve(e);
    double t0, t1;
    m.edgeRange(e, t0, t1);
    Vec3 p, d;
    c->d1(end == 0 ? t0 : t1, p, d);
    return normalized(d);
  };
  for (size_t k = 0; k < out.size(); ++k) {
    const RidgeCandidate base = out[k];
    if (!base.peak) continue;  // only confirmed noses propagate
    for (int end = 0; end < 2; ++end) {
      const int v = m.edgeVertex(base.edge, end);
      if (v < 0) continue;
      const Vec3 tb = tangentAt(base.edge, end);
      for (const RidgeCandidate& c : scored) {
        if (c.edge == base.edge || c.dihedralDeg >= maxDihedralDeg) continue;
        if (std::any_of(out.begin(), out.end(), [&](const RidgeCandidate& o) { return o.edge == c.edge; })) continue;
        for (int ce = 0; ce < 2; ++ce) {
          if (m.edgeVertex(c.edge, ce) != v) continue;
          const double cosT = std::fabs(dot(tb, tangentAt(c.edge, ce)));
          // the continuation curves about as much across (a rounded tip too small to confirm a
          // peak on its own still continues the edge)
          if (cosT > std::cos(20.0 * M_PI / 180.0) &&
              c.acrossCurvature >= (c.peak ? 0.5 : 0.75) * base.acrossCurvature)
            out.push_back(c);
        }
      }
    }
  }
  std::sort(out.begin(), out.end(), [](const RidgeCandidate& a, const RidgeCandidate& b) { return a.edge < b.edge; });
  if (all) *all = scored;
  return out;
}

}  // namespace paramesh
