// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file test_size_edges.cpp
/// Tests of the size field (exact cone formula against brute force, dominated-source removal,
/// gradient bound), of the edge discretiser (curve length and turning, equidistribution for
/// constant and graded sizes, minimum segment counts on closed curves) and of the curvature size
/// sources (principal curvature of analytic surfaces, cylinder face sources), and of the
/// nearest-face check (distances to other faces, their deviation bound, the CAD callback, sizes).
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRepTools.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <gp_Ax2.hxx>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <sstream>
#include <vector>

#include "paramesh/geom/Geometry.hpp"
#include "paramesh/geom/occ/OccModel.hpp"
#include "paramesh/model/EdgeDiscretizer.hpp"
#include "paramesh/size/NearestFace.hpp"
#include "paramesh/size/SizeField.hpp"
#include "paramesh/size/Sources.hpp"
#include "paramesh/util/Error.hpp"
#include "occ_fixtures.hpp"

using namespace paramesh;

namespace {

using test::viaBrep;

int faceOfKind(const IGeometryModel& m, SurfaceKind k) {
  for (int f = 0; f < m.numFaces(); ++f)
    if (m.makeSurface(f)->kind() == k) return f;
  return -1;
}

int edgeOfKind(const IGeometryModel& m, CurveKind k) {
  for (int e = 0; e < m.numEdges(); ++e)
    if (!m.edgeDegenerate(e) && m.makeCurve(e)->kind() == k) return e;
  return -1;
}

double bruteSize(const std::vector<Vec3>& p, const std::vector<double>& h, double hmax, double slope, Vec3 x) {
  double best = hmax;
  for (size_t i = 0; i < p.size(); ++i) best = std::min(best, h[i] + slope * dist(x, p[i]));
  return best;
}

/// x(t) = (10 t^2, 3 t^2, 0) on [0.1, 1]: a straight segment with a speed that varies tenfold, so
/// that equal parameter steps are far from equal lengths.
class QuadraticLine final : public ICurve {
 public:
  CurveKind kind() const override { return CurveKind::Other; }
  Vec3 eval(double t) const override { return {10 * t * t, 3 * t * t, 0}; }
  void d1(double t, Vec3& p, Vec3& d) const override {
    p = eval(t);
    d = {20 * t, 6 * t, 0};
  }
  void d2(double t, Vec3& p, Vec3& d, Vec3& dd) const override {
    d1(t, p, d);
    dd = {20, 6, 0};
  }
};

/// Segment chord lengths of a discretisation.
std::vector<double> chords(const ICurve& c, const std::vector<double>& t) {
  std::vector<double> l;
  for (size_t i = 1; i < t.size(); ++i) l.push_back(dist(c.eval(t[i - 1]), c.eval(t[i])));
  return l;
}

void expectIncreasing(const std::vector<double>& t) {
  for (size_t i = 1; i < t.size(); ++i) EXPECT_LT(t[i - 1], t[i]) << i;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Size field

TEST(SizeField, MatchesBruteForce) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> P(0, 10), H(0.02, 1.2), Q(-3, 13);
  const double hmax = 1.0, g = 1.3;
  std::vector<Vec3> pts;
  std::vector<double> hs;
  SizeField f(hmax, g);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p{P(rng), P(rng), P(rng)};
    const double h = H(rng);
    pts.push_back(p);
    hs.push_back(h);
    f.addSource(p, h);
  }
  // sources at or above hmax are ignored, the others kept until build()
  const size_t below = std::count_if(hs.begin(), hs.end(), [&](double h) { return h < hmax; });
  EXPECT_EQ(f.numSources(), below);
  f.build();
  EXPECT_LT(f.numSources(), below);  // dense sources: many are dominated and removed
  EXPECT_GT(f.numSources(), 0u);
  EXPECT_DOUBLE_EQ(f.hmax(), hmax);
  EXPECT_NEAR(f.slope(), g - 1, 1e-15);
  double maxRel = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 x{Q(rng), Q(rng), Q(rng)};
    const double ref = bruteSize(pts, hs, hmax, g - 1, x);
    maxRel = std::max(maxRel, std::fabs(f.size(x) - ref) / ref);
  }
  EXPECT_LE(maxRel, 1e-12);
  // at the sources themselves
  for (int i = 0; i < 2000; i += 7) {
    const double ref = bruteSize(pts, hs, hmax, g - 1, pts[i]);
    EXPECT_NEAR(f.size(pts[i]), ref, 1e-12 * ref);
    EXPECT_LE(f.size(pts[i]), std::min(hs[i], hmax) * (1 + 1e-12));
  }
  // far away: hmax
  EXPECT_EQ(f.size({1000, 1000, 1000}), hmax);
}

TEST(SizeField, FieldUnderAnotherIsTheUnionOfTheirSources) {
  // the nearest-face rounds put a few steep sources over the whole field instead of copying and
  // rebuilding it: the result must be the field of both source sets
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> P(0, 10), H(0.05, 1.2), Q(-3, 13);
  const double hmax = 1.0, g = 1.3, steep = 1.0;
  std::vector<Vec3> pts;
  std::vector<double> hs, ss;
  auto base = std::make_shared<SizeField>(hmax, g);
  for (int i = 0; i < 3000; ++i) {
    const Vec3 p{P(rng), P(rng), P(rng)};
    const double h = H(rng);
    pts.push_back(p);
    hs.push_back(h);
    ss.push_back(g - 1);
    base->addSource(p, h);
  }
  base->build();
  const size_t nBase = base->numSources();
  SizeField top(hmax, g);
  top.setUnder(base);
  for (int i = 0; i < 20; ++i) {
    const Vec3 p{P(rng), P(rng), P(rng)};
    const double h = 0.01 * H(rng);
    pts.push_back(p);
    hs.push_back(h);
    ss.push_back(steep);
    top.addSource(p, h, steep);
  }
  top.build();
  EXPECT_EQ(top.numSources(), nBase + 20);
  int touched = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 x = i % 4 == 0 ? pts[3000 + (i / 4) % 20] + Vec3{0.05, 0, 0} : Vec3{Q(rng), Q(rng), Q(rng)};
    double ref = hmax;
    for (size_t k = 0; k < pts.size(); ++k) ref = std::min(ref, hs[k] + ss[k] * dist(x, pts[k]));
    EXPECT_NEAR(top.size(x), ref, 1e-12 * ref);
    EXPECT_LE(top.size(x), base->size(x));
    if (top.ownSize(x) < hmax) ++touched;
    if (!(top.ownSize(x) < hmax)) EXPECT_EQ(top.size(x), base->size(x));  // out of the new sources' reach
  }
  EXPECT_GT(touched, 900);  // the points next to the steep sources
}

TEST(SizeField, DominatedSourcesChangeNothing) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> P(0, 10), H(0.05, 0.8), Q(-2, 12), D(-1, 1);
  const double hmax = 1.0, g = 1.25, s = g - 1;
  std::vector<Vec3> pts;
  std::vector<double> hs;
  SizeField a(hmax, g), b(hmax, g);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p{P(rng), P(rng), P(rng)};
    const double h = H(rng);
    pts.push_back(p);
    hs.push_back(h);
    a.addSource(p, h);
    b.addSource(p, h);
  }
  // b also gets 2000 sources each strictly dominated by one of the above
  for (int i = 0; i < 2000; ++i) {
    const Vec3 d{D(rng), D(rng), D(rng)};
    b.addSource(pts[i] + d, hs[i] + s * norm(d) * 1.01 + 1e-3);
  }
  a.build();
  b.build();
  EXPECT_EQ(a.numSources(), b.numSources());
  for (int i = 0; i < 2000; ++i) {
    const Vec3 x{Q(rng), Q(rng), Q(rng)};
    const double ref = bruteSize(pts, hs, hmax, s, x);
    EXPECT_NEAR(a.size(x), ref, 1e-12 * ref);
    EXPECT_NEAR(b.size(x), ref, 1e-12 * ref);
  }
  // an empty field is hmax everywhere; size() before build() is an internal error
  SizeField e(0.7, 1.2);
  e.build();
  EXPECT_EQ(e.size({1, 2, 3}), 0.7);
  SizeField u(1.0, 1.2);
  u.addSource({0, 0, 0}, 0.1);
  EXPECT_THROW(u.size({0, 0, 0}), InternalError);
}

TEST(SizeField, GradientBound) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> P(0, 5), H(0.01, 0.5), Q(-1, 6), S(-1, 1);
  const double g = 1.15, s = g - 1;
  SizeField f(0.6, g);
  for (int i = 0; i < 2000; ++i) f.addSource({P(rng), P(rng), P(rng)}, H(rng));
  f.build();
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 x{Q(rng), Q(rng), Q(rng)};
    const double scale = std::pow(10.0, -4 + 4 * (i % 5) / 4.0);  // pairs from 1e-4 to 1 apart
    const Vec3 y = x + scale * Vec3{S(rng), S(rng), S(rng)};
    const double d = dist(x, y);
    worst = std::max(worst, std::fabs(f.size(x) - f.size(y)) - s * d);
    EXPECT_LE(f.size(x), 0.6);
    EXPECT_GT(f.size(x), 0.0);
  }
  EXPECT_LE(worst, 1e-14);
}

// ---------------------------------------------------------------------------------------------
// Edge discretiser

TEST(EdgeDiscretizer, CircleSamplingLengthAndTurning) {
  const double R = 2.5;
  auto m = viaBrep(BRepPrimAPI_MakeCylinder(R, 4).Shape());
  const int e = edgeOfKind(*m, CurveKind::Circle);
  ASSERT_GE(e, 0);
  auto c = m->makeCurve(e);
  double t0, t1;
  m->edgeRange(e, t0, t1);
  const double L = 2 * M_PI * R;
  // with a size field (as the mesher samples edges): length within 1e-4
  SizeField field(R / 10, 1.2);
  field.build();
  CurveSampling cs = sampleCurve(*c, t0, t1, &field);
  EXPECT_NEAR(cs.length(), L, 1e-4 * L);
  EXPECT_LE(cs.length(), L);  // chords are never longer than the arc
  EXPECT_NEAR(cs.turning, 2 * M_PI, 1e-6);
  ASSERT_EQ(cs.t.size(), cs.p.size());
  ASSERT_EQ(cs.t.size(), cs.s.size());
  EXPECT_EQ(cs.t.front(), t0);
  EXPECT_EQ(cs.t.back(), t1);
  expectIncreasing(cs.t);
  EXPECT_EQ(cs.s.front(), 0.0);
  for (size_t i = 0; i < cs.t.size(); ++i) {
    EXPECT_LE(dist(cs.p[i], c->eval(cs.t[i])), 1e-12 * R);
    if (i == 0) continue;
    EXPECT_NEAR(cs.s[i] - cs.s[i - 1], dist(cs.p[i], cs.p[i - 1]), 1e-12 * R);
    // fine enough for the field: chords below 0.2 h
    EXPECT_LE(dist(cs.p[i], cs.p[i - 1]), 0.2 * R / 10 * (1 + 1e-9));
  }
  // geometry only: the chord-error criterion (deviation <= 1% of the chord, i.e. arcs up to
  // ~0.08 rad) bounds the length error by ~theta^2/24 = 2.7e-4
  CurveSampling cg = sampleCurve(*c, t0, t1, nullptr);
  EXPECT_NEAR(cg.length(), L, 2.7e-4 * L);
  EXPECT_NEAR(cg.turning, 2 * M_PI, 1e-6);
  EXPECT_GE(cg.t.size(), 33u);
  // half circle
  CurveSampling ch = sampleCurve(*c, t0, t0 + M_PI, &field);
  EXPECT_NEAR(ch.length(), 0.5 * L, 1e-4 * L);
  EXPECT_NEAR(ch.turning, M_PI, 1e-6);
}

/// Requirement: the sampled length of a circle is within 1e-4 of 2 pi r whatever the size field.
TEST(EdgeDiscretizer, CircleLengthWithin1e4AtAnySize) {
  const double R = 2.5;
  auto m = viaBrep(BRepPrimAPI_MakeCylinder(R, 4).Shape());
  const int e = edgeOfKind(*m, CurveKind::Circle);
  auto c = m->makeCurve(e);
  double t0, t1;
  m->edgeRange(e, t0, t1);
  const double L = 2 * M_PI * R;
  EXPECT_NEAR(sampleCurve(*c, t0, t1, nullptr).length(), L, 1e-4 * L);
  for (double h : {0.3, 1.3, 100.0}) {
    SizeField f(h, 1.2);
    f.build();
    EXPECT_NEAR(sampleCurve(*c, t0, t1, &f).length(), L, 1e-4 * L) << "h " << h;
  }
}

TEST(EdgeDiscretizer, ConstantSizeEquidistributes) {
  // a circle, a straight line and a line with a tenfold varying parameter speed
  const double R = 2.5;
  auto m = viaBrep(BRepPrimAPI_MakeCylinder(R, 4).Shape());
  auto circle = m->makeCurve(edgeOfKind(*m, CurveKind::Circle));
  const int lineEdge = edgeOfKind(*m, CurveKind::Line);
  ASSERT_GE(lineEdge, 0);
  auto line = m->makeCurve(lineEdge);
  double l0, l1;
  m->edgeRange(lineEdge, l0, l1);
  QuadraticLine quad;
  struct Case {
    const ICurve* c;
    double t0, t1, L;
  };
  const Case cases[] = {{circle.get(), 0, 2 * M_PI, 2 * M_PI * R},
                        {line.get(), l0, l1, 4.0},
                        {&quad, 0.1, 1.0, std::hypot(10.0, 3.0) * 0.99}};
  for (const Case& k : cases) {
    for (double h : {0.07, 0.3, 0.55, 1.3}) {
      SCOPED_TRACE("L " + std::to_string(k.L) + " h " + std::to_string(h));
      SizeField f(h, 1.2);
      f.build();
      CurveSampling cs = sampleCurve(*k.c, k.t0, k.t1, &f);
      // 1e-4 when the field makes chords short (h <= 0.6 R here); with coarse sizes the chord-error
      // criterion alone decides (see CircleLengthWithin1e4AtAnySize)
      EXPECT_NEAR(cs.length(), k.L, (h <= 0.6 ? 1e-4 : 2.7e-4) * k.L);
      std::vector<double> t = discretizeCurve(cs, f, 1, 0.0);
      const int n = (int)t.size() - 1;
      EXPECT_EQ(n, std::max(1, (int)std::lround(cs.length() / h)));
      EXPECT_EQ(t.front(), k.t0);
      EXPECT_EQ(t.back(), k.t1);
      expectIncreasing(t);
      for (double l : chords(*k.c, t)) EXPECT_NEAR(l, k.L / n, 0.02 * k.L / n);
    }
  }
}

TEST(EdgeDiscretizer, GradedFromAPointSource) {
  // a straight box edge of length 10 and a circle of length 2 pi 2.5, each with a point source of
  // size h/10 at its start vertex, grading 1.2
  auto box = viaBrep(BRepPrimAPI_MakeBox(10, 1, 1).Shape());
  auto cyl = viaBrep(BRepPrimAPI_MakeCylinder(2.5, 4).Shape());
  int longEdge = -1;
  for (int e = 0; e < box->numEdges(); ++e) {
    double a, b;
    box->edgeRange(e, a, b);
    if (dist(box->vertexPoint(box->edgeVertex(e, 0)), box->vertexPoint(box->edgeVertex(e, 1))) > 9) longEdge = e;
  }
  ASSERT_GE(longEdge, 0);
  const int circleEdge = edgeOfKind(*cyl, CurveKind::Circle);
  ASSERT_GE(circleEdge, 0);
  struct Case {
    const IGeometryModel* m;
    int e;
  };
  for (const Case& k : {Case{box.get(), longEdge}, Case{cyl.get(), circleEdge}}) {
    auto c = k.m->makeCurve(k.e);
    double t0, t1;
    k.m->edgeRange(k.e, t0, t1);
    const double h = 1.0, g = 1.2, hs = h / 10;
    SizeField f(h, g);
    f.addSource(c->eval(t0), hs);
    f.build();
    CurveSampling cs = sampleCurve(*c, t0, t1, &f);
    std::vector<double> t = discretizeCurve(cs, f, 1, 0.0);
    expectIncreasing(t);
    const std::vector<double> l = chords(*c, t);
    ASSERT_GE(l.size(), 10u);
    // neighbouring segments differ by at most the grading: the exact equidistribution of a linear
    // size h0 + (g-1) s gives the ratio exp(g-1) = 1.221; allow 5% over g
    double worst = 0;
    for (size_t i = 1; i < l.size(); ++i) worst = std::max(worst, std::max(l[i] / l[i - 1], l[i - 1] / l[i]));
    EXPECT_LE(worst, g * 1.05);
    const double smallest = *std::min_element(l.begin(), l.end());
    EXPECT_GE(smallest / hs, 0.7);
    EXPECT_LE(smallest / hs, 1.4);
    EXPECT_LT(smallest, l[l.size() / 2]);  // graded: small at the source, larger away from it
    // every segment close to the size field at its midpoint
    for (size_t i = 0; i < l.size(); ++i) {
      const double hm = f.size(c->eval(0.5 * (t[i] + t[i + 1])));
      EXPECT_GT(l[i] / hm, 0.7) << i;
      EXPECT_LT(l[i] / hm, 1.4) << i;
    }
  }
}

TEST(EdgeDiscretizer, ClosedCurveMinimumSegments) {
  const double R = 2.5;
  auto m = viaBrep(BRepPrimAPI_MakeCylinder(R, 4).Shape());
  const int e = edgeOfKind(*m, CurveKind::Circle);
  auto c = m->makeCurve(e);
  double t0, t1;
  m->edgeRange(e, t0, t1);
  EXPECT_EQ(m->edgeVertex(e, 0), m->edgeVertex(e, 1));  // closed edge
  SizeField huge(1e6, 1.2);
  huge.build();
  CurveSampling cs = sampleCurve(*c, t0, t1, &huge);
  EXPECT_NEAR(cs.length(), 2 * M_PI * R, 2.7e-4 * 2 * M_PI * R);
  // minimum count (as the mesher asks for closed curves)
  std::vector<double> t = discretizeCurve(cs, huge, 3, 0.0);
  EXPECT_GE(t.size() - 1, 3u);
  for (double l : chords(*c, t)) EXPECT_GT(l, R);  // three real, non-degenerate segments
  // turning limit alone: pi/3 gives at least 6 segments on the full circle, none turning more
  t = discretizeCurve(cs, huge, 1, M_PI / 3);
  EXPECT_GE(t.size() - 1, 6u);
  for (size_t i = 1; i < t.size(); ++i) EXPECT_LE(t[i] - t[i - 1], M_PI / 3 + 1e-6);  // t is the angle
  // both
  t = discretizeCurve(cs, huge, 3, M_PI / 3);
  EXPECT_GE(t.size() - 1, 6u);
  // a finer turning limit
  t = discretizeCurve(cs, huge, 3, M_PI / 12);
  EXPECT_GE(t.size() - 1, 24u);
}

// ---------------------------------------------------------------------------------------------
// Curvature

TEST(Curvature, AnalyticSurfaces) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0.1, 0.9);
  auto inner = [&](const UVBox& b) { return Vec2{b.u0 + (b.u1 - b.u0) * U(rng), b.v0 + (b.v1 - b.v0) * U(rng)}; };
  {  // sphere. Every point is umbilic (H^2 - K = 0), where |H| + sqrt(H^2 - K) turns the round-off
     // of H^2 - K into ~sqrt(eps) relative: 1e-7 there, 1e-9 elsewhere.
    const double R = 3.5;
    auto m = viaBrep(BRepPrimAPI_MakeSphere(gp_Pnt(1, 2, 3), R).Shape());
    auto s = m->makeSurface(0);
    for (int i = 0; i < 50; ++i) EXPECT_NEAR(maxCurvature(*s, inner(s->bounds())), 1 / R, 1e-7 / R);
  }
  {  // cylinder
    const double R = 0.75;
    auto m = viaBrep(BRepPrimAPI_MakeCylinder(R, 3).Shape());
    auto s = m->makeSurface(faceOfKind(*m, SurfaceKind::Cylinder));
    for (int i = 0; i < 50; ++i) EXPECT_NEAR(maxCurvature(*s, inner(s->bounds())), 1 / R, 1e-9 / R);
  }
  {  // torus: 1/r everywhere (|cos v / (R + r cos v)| < 1/r), both curvatures checked at the equators
    const double R = 5, r = 1.5;
    auto m = viaBrep(BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), R, r).Shape());
    auto s = m->makeSurface(0);
    EXPECT_NEAR(maxCurvature(*s, {0.3, 0.0}), 1 / r, 1e-9 / r);     // outer equator
    EXPECT_NEAR(maxCurvature(*s, {1.3, M_PI}), 1 / r, 1e-9 / r);    // inner equator
    EXPECT_NEAR(maxCurvature(*s, {2.0, 0.5 * M_PI}), 1 / r, 1e-9 / r);  // top circle
    for (int i = 0; i < 50; ++i) EXPECT_NEAR(maxCurvature(*s, inner(s->bounds())), 1 / r, 1e-9 / r);
  }
  {  // plane
    auto m = viaBrep(BRepPrimAPI_MakeBox(1, 2, 3).Shape());
    for (int f = 0; f < 6; ++f) {
      auto s = m->makeSurface(f);
      EXPECT_EQ(maxCurvature(*s, inner(s->bounds())), 0.0);
    }
  }
  {  // B-spline saddle (2u, 3v, u^2 - v^2): at the origin z = x^2/4 - y^2/9, curvatures 1/2, -2/9
    const double greville[4] = {0.0, 0.25, 0.75, 1.0};
    const double sq[4] = {0.0, 0.0, 0.5, 1.0};
    TColgp_Array2OfPnt poles(1, 4, 1, 4);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) poles(i + 1, j + 1) = gp_Pnt(2.0 * greville[i], 3.0 * greville[j], sq[i] - sq[j]);
    TColStd_Array1OfReal knots(1, 3);
    knots(1) = 0.0;
    knots(2) = 0.5;
    knots(3) = 1.0;
    TColStd_Array1OfInteger mults(1, 3);
    mults(1) = 3;
    mults(2) = 1;
    mults(3) = 3;
    Handle(Geom_BSplineSurface) bs = new Geom_BSplineSurface(poles, knots, knots, mults, mults, 2, 2);
    auto m = viaBrep(BRepBuilderAPI_MakeFace(bs, 1e-7).Face());
    auto s = m->makeSurface(0);
    EXPECT_NEAR(maxCurvature(*s, {0.0, 0.0}), 0.5, 1e-9);
    EXPECT_NEAR(maxCurvature(*s, {0.0, 1e-3}), 0.5, 1e-5);
  }
}

TEST(Curvature, StretchedCellsSplitAcrossTheirLengthOnly) {
  // a long cylinder: the base grid (at most 256 cells a side) has cells 8 times longer than wide;
  // leaves come out about square in 3D, so the sources are about area / (leaf size)^2, not the
  // aspect ratio times more
  const double R = 2.5, H = 2000, angle = 10 * M_PI / 180, h = 0.75 * R * angle;
  auto m = viaBrep(BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), R, H).Shape());
  const int f = faceOfKind(*m, SurfaceKind::Cylinder);
  ASSERT_GE(f, 0);
  const std::vector<SizeSource> src = faceCurvatureSources(*m, f, angle, 0.01, 2.0);
  const double area = 2 * M_PI * R * H;
  EXPECT_LE((double)src.size(), 4.5 * area / (h * h));  // measured 3.6 (splitting both ways: 5.1)
  // and they still cover the face: every point within h of a source
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> A(0, 2 * M_PI), Z(0, H);
  SizeField near(2.0, 100.0);  // slope 99: the size at x tells the distance to the nearest source
  for (const SizeSource& s : src) near.addSource(s.p, 0.01);
  near.build();
  for (int i = 0; i < 500; ++i) {
    const double a = A(rng), z = Z(rng);
    const Vec3 p{R * std::cos(a), R * std::sin(a), z};
    EXPECT_LE((near.size(p) - 0.01) / 99.0, h) << "at z = " << z;
  }
}

TEST(Curvature, CylinderFaceSources) {
  const double R = 2.5, H = 4, angle = 10 * M_PI / 180;
  const gp_Pnt loc(1, -1, 0.5);
  auto m = viaBrep(BRepPrimAPI_MakeCylinder(gp_Ax2(loc, gp_Dir(0, 0, 1)), R, H).Shape());
  const int f = faceOfKind(*m, SurfaceKind::Cylinder);
  ASSERT_GE(f, 0);
  // the target is 0.75 R angle so that elements (edges up to ~1.3x target) subtend <= angle
  const double hExpect = 0.75 * R * angle;  // 0.327
  std::vector<SizeSource> src = faceCurvatureSources(*m, f, angle, 0.01, 2.0);
  ASSERT_FALSE(src.empty());
  for (const SizeSource& s : src) {
    EXPECT_NEAR(s.h, hExpect, 1e-9 * hExpect);
    EXPECT_NEAR(std::hypot(s.p.x - loc.X(), s.p.y - loc.Y()), R, 1e-9 * R);  // on the cylinder
    EXPECT_GE(s.p.z, loc.Z() - 1e-9);
    EXPECT_LE(s.p.z, loc.Z() + H + 1e-9);
  }
  // the sources cover the face: every point is within ~2 h of one of them
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> A(0, 2 * M_PI), Z(0, H);
  for (int i = 0; i < 200; ++i) {
    const double a = A(rng), z = Z(rng);
    const Vec3 p{loc.X() + R * std::cos(a), loc.Y() + R * std::sin(a), loc.Z() + z};
    double best = 1e300;
    for (const SizeSource& s : src) best = std::min(best, dist(p, s.p));
    EXPECT_LE(best, 2 * hExpect);
  }
  // clamping: up to hmin, and nothing at or above hmax
  for (const SizeSource& s : faceCurvatureSources(*m, f, angle, 1.0, 2.0)) EXPECT_NEAR(s.h, 1.0, 1e-12);
  EXPECT_FALSE(faceCurvatureSources(*m, f, angle, 1.0, 2.0).empty());
  EXPECT_TRUE(faceCurvatureSources(*m, f, angle, 0.01, 0.3).empty());
  // a planar cap gives no source
  for (int g = 0; g < m->numFaces(); ++g) {
    if (g != f) {
      EXPECT_TRUE(faceCurvatureSources(*m, g, angle, 0.01, 2.0).empty());
    }
  }
  // used in a size field, the size on the cylinder is 0.75 R angle
  SizeField field(2.0, 1.2);
  for (const SizeSource& s : src) field.addSource(s.p, s.h);
  field.build();
  for (int i = 0; i < 50; ++i) {
    const double a = A(rng), z = Z(rng);
    const Vec3 p{loc.X() + R * std::cos(a), loc.Y() + R * std::sin(a), loc.Z() + z};
    EXPECT_GE(field.size(p), hExpect * (1 - 1e-12));
    EXPECT_LE(field.size(p), hExpect + 0.2 * 2 * hExpect);
  }
}

TEST(Curvature, SamplingBudgetIsReported) {
  // a cylinder of R 2.5, H 4 at 10 degrees: sizes 0.327 everywhere, sampled in full well below
  // the default budget; with a budget of 20 cells the sampler stops splitting, says so, and its
  // sources no longer cover the face within 2 h
  const double R = 2.5, H = 4, angle = 10 * M_PI / 180, h = 0.75 * R * angle;
  auto m = viaBrep(BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), R, H).Shape());
  const int f = faceOfKind(*m, SurfaceKind::Cylinder);
  ASSERT_GE(f, 0);
  FaceSamplingStats full, cut;
  const std::vector<SizeSource> all = faceCurvatureSources(*m, f, angle, 0.01, 2.0, 0, &full);
  const std::vector<SizeSource> few = faceCurvatureSources(*m, f, angle, 0.01, 2.0, 0, &cut, 20);
  EXPECT_FALSE(full.truncated);
  EXPECT_GT(full.cells, 20);
  EXPECT_TRUE(cut.truncated);
  EXPECT_LT(cut.cells, full.cells);  // the base grid (cells about hmax across) is always evaluated
  EXPECT_LT(few.size(), all.size());
  auto farthest = [&](const std::vector<SizeSource>& src) {
    double worst = 0;
    for (int i = 0; i < 64; ++i)
      for (int j = 0; j <= 16; ++j) {
        const double a = 2 * M_PI * i / 64, z = H * j / 16;
        const Vec3 p{R * std::cos(a), R * std::sin(a), z};
        double best = 1e300;
        for (const SizeSource& s : src) best = std::min(best, dist(p, s.p));
        worst = std::max(worst, best);
      }
    return worst;
  };
  EXPECT_LE(farthest(all), 2 * h);
  EXPECT_GT(farthest(few), 2 * h);
  // level by level: a budget that stops the sampling short (measured: 328 of the 2 720 cells,
  // 254 of the 2 048 sources) still covers the whole face evenly, every point within 0.55 of a
  // source against 2 h = 0.65 (depth first, the first cells would be sampled in full and the
  // rest left at the base grid)
  FaceSamplingStats part;
  const std::vector<SizeSource> even = faceCurvatureSources(*m, f, angle, 0.01, 2.0, 0, &part, 200);
  EXPECT_TRUE(part.truncated);
  EXPECT_LT(even.size(), all.size());
  EXPECT_LE(farthest(even), 2 * h);
}

TEST(Curvature, CircleEdgeSources) {
  const double R = 2.5, angle = 10 * M_PI / 180;
  auto m = viaBrep(BRepPrimAPI_MakeCylinder(R, 4).Shape());
  const int e = edgeOfKind(*m, CurveKind::Circle);
  std::vector<SizeSource> src = edgeCurvatureSources(*m, e, angle, 0.01, 2.0);
  ASSERT_GE(src.size(), 10u);
  for (const SizeSource& s : src) {
    EXPECT_NEAR(s.h, 0.75 * R * angle, 1e-9);
    EXPECT_NEAR(std::hypot(s.p.x, s.p.y), R, 1e-3 * R);  // on (or on a chord of) the circle
  }
  // a straight edge has no curvature source
  const int l = edgeOfKind(*m, CurveKind::Line);
  ASSERT_GE(l, 0);
  EXPECT_TRUE(edgeCurvatureSources(*m, l, angle, 0.01, 2.0).empty());
}

namespace {
// Face 1: one triangle in z = 0 (centroid (1/3, 1/3, 0)); face 2: a large triangle in the plane
// z = -gap under it (facing it, like the other skin of a thin blade).
paramesh::SurfaceMesh twoSkins(double gap) {
  using paramesh::Vec3;
  paramesh::SurfaceMesh m;
  for (Vec3 p : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{-5, -5, -gap}, Vec3{5, -5, -gap}, Vec3{0, 5, -gap}})
    m.addNode(p, paramesh::NodeKind::Face, 1, {0, 0});
  m.triangles = {{0, 1, 2}, {3, 4, 5}};
  m.triangleFace = {1, 2};
  m.triangleLayer = {0, 0};
  return m;
}
}  // namespace

TEST(NearestFace, FlagsATriangleNearerTheOtherSkin) {
  using namespace paramesh;
  // own deviation 0.5: the other skin at 0.3 is nearer (flagged), at 0.6 it is not (0.6 > 1.1 x 0.5)
  const auto near = nearestFaceSources(twoSkins(0.3), {{0, 0.5}}, 1e-3);
  ASSERT_EQ(near.flagged, 1);
  ASSERT_EQ(near.found.size(), 1u);
  EXPECT_NEAR(near.found[0][2], 0.3, 1e-12);  // distance from the centroid to the other skin
  // size: mean edge (2 + sqrt 2)/3 times sqrt(0.5 * 0.3 / 0.5), at the centroid and the 3 nodes
  ASSERT_EQ(near.sources.size(), 4u);
  const double L = (2 + std::sqrt(2.0)) / 3;
  for (const auto& s : near.sources) EXPECT_NEAR(s.h, L * std::sqrt(0.3), 1e-12);
  EXPECT_NEAR(near.sources[0].p.x, 1.0 / 3, 1e-12);
  EXPECT_EQ(nearestFaceSources(twoSkins(0.6), {{0, 0.5}}, 1e-3).flagged, 0);
  // already at min-size: flagged but no source
  const auto small = nearestFaceSources(twoSkins(0.3), {{0, 0.5}}, 1.0);
  EXPECT_EQ(small.flagged, 1);
  EXPECT_TRUE(small.sources.empty());
}

TEST(NearestFace, OtherFaceDeviationAndCadDistance) {
  using namespace paramesh;
  // the other skin's mesh at 0.7 (> 0.55, not flagged on the mesh alone); with a deviation of 0.2
  // on that triangle its CAD face may be as near as 0.5, so the CAD distance decides
  const SurfaceMesh m = twoSkins(0.7);
  EXPECT_EQ(nearestFaceSources(m, {{0, 0.5}}, 1e-3).flagged, 0);
  const std::vector<double> dev{0.0, 0.2};
  int calls = 0;
  const FaceDistance cadNear = [&](Vec3 c, int tri, Vec3 q, Vec3*) {
    ++calls;
    EXPECT_EQ(tri, 1);
    EXPECT_NEAR(dist(c, q), 0.7, 1e-12);  // the closest point of the other face's mesh
    return 0.45;
  };
  const auto r = nearestFaceSources(m, {{0, 0.5}}, 1e-3, &dev, cadNear);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(r.flagged, 1);
  EXPECT_NEAR(r.found[0][2], 0.45, 1e-12);
  const FaceDistance cadFar = [](Vec3, int, Vec3, Vec3*) { return 0.65; };
  EXPECT_EQ(nearestFaceSources(m, {{0, 0.5}}, 1e-3, &dev, cadFar).flagged, 0);
  // a deviation too small to bring the CAD face within reach: no CAD query at all
  const std::vector<double> dev2{0.0, 0.1};
  calls = 0;
  EXPECT_EQ(nearestFaceSources(m, {{0, 0.5}}, 1e-3, &dev2, cadNear).flagged, 0);
  EXPECT_EQ(calls, 0);
}
