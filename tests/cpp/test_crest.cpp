// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file test_crest.cpp
/// Tests of crest embedding under the curvature angle: folds far below the size get their crest
/// traced and embedded, rows beside it follow its shoulders, and neighbouring crests stay valid.
#include <gtest/gtest.h>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <BRepTools.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Ax3.hxx>
#include <gp_Cylinder.hxx>
#include <gp_Dir.hxx>
#include <gp_Pln.hxx>
#include <gp_Pnt.hxx>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>
#include "paramesh/algo/Crest.hpp"
#include "paramesh/algo/FaceMesher.hpp"
#include "paramesh/algo/optimizer/Optimizer.hpp"
#include "paramesh/algo/Predicates.hpp"
#include "paramesh/algo/SurfaceContext.hpp"
#include "paramesh/algo/Triangulation.hpp"
#include "paramesh/geom/Geometry.hpp"
#include "paramesh/geom/occ/OccModel.hpp"
#include "paramesh/model/EdgeDiscretizer.hpp"
#include "paramesh/size/SizeField.hpp"
#include "face_fixtures.hpp"

using namespace paramesh;
using namespace paramesh::test;

namespace {
/// The quadratic B-spline section with poles xz (x, z) and the given knots and multiplicities,
/// extruded over y in [0, 4], as a one-face model.
std::unique_ptr<IGeometryModel> extrudedSection(const std::vector<std::array<double, 2>>& xz,
                                                const std::vector<double>& knots, const std::vector<int>& mults) {
  const int n = (int)xz.size(), k = (int)knots.size();
  TColgp_Array2OfPnt poles(1, n, 1, 2);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2; ++j) poles.SetValue(i + 1, j + 1, gp_Pnt(xz[i][0], 4.0 * j, xz[i][1]));
  TColStd_Array1OfReal uk(1, k), vk(1, 2);
  TColStd_Array1OfInteger um(1, k), vm(1, 2);
  for (int i = 0; i < k; ++i) uk(i + 1) = knots[i], um(i + 1) = mults[i];
  vk(1) = 0, vk(2) = 1, vm(1) = 2, vm(2) = 2;
  Handle(Geom_BSplineSurface) S = new Geom_BSplineSurface(poles, uk, vk, um, vm, 2, 1);
  TopoDS_Face face = BRepBuilderAPI_MakeFace(S, 1e-7).Face();
  std::ostringstream out;
  BRepTools::Write(face, out);
  return loadOccModelFromBrepString(out.str());
}

/// A face folded along x = 0: the quadratic B-spline section through poles (-1, m), (-e, m e),
/// (e, m e), (1, m) in (x, z), extruded over y in [0, 4]. Its flanks (slopes -m and m) meet over
/// a crest at (0, y, m e) whose radius (a few e^2 / m) lies far below the mesh size.
std::unique_ptr<IGeometryModel> foldedFace(double e, double m) {
  return extrudedSection({{-1, m}, {-e, m * e}, {e, m * e}, {1, m}}, {0, 0.5, 1}, {3, 1, 3});
}

/// How a face mesh of foldedFace follows the surface: triangles over 0.03 of their mean edge
/// (distance: an upper bound, a projection's foot seeded at the centroid's and each corner's
/// (u,v)) and the worst ratio, counted on the triangles `counted` accepts (corners and centroid);
/// triangles facing away from the surface at their centroid's (u,v), counted on all.
struct FoldFit {
  int over = 0, away = 0;
  double worst = 0;
};
FoldFit foldFit(const FaceMeshResult& r, const std::vector<Vec3>& nodeXyz, const ISurface& surf,
                const std::function<bool(Vec3, Vec3, Vec3, Vec3)>& counted) {
  FoldFit f;
  auto xyz = [&](int ref) { return ref >= 0 ? nodeXyz[ref] : r.newXyz[-ref - 1]; };
  for (size_t k = 0; k < r.tris.size(); ++k) {
    const auto& t = r.tris[k];
    const Vec3 a = xyz(t[0]), b = xyz(t[1]), c = xyz(t[2]);
    const Vec3 g = (1.0 / 3) * (a + b + c);
    const Vec2 s = (1.0 / 3) * (r.triUv[k][0] + r.triUv[k][1] + r.triUv[k][2]);
    Vec3 n;
    EXPECT_TRUE(surf.normal(s, n));
    if (!(dot(cross(b - a, c - a), n) > 0)) ++f.away;
    if (!counted(a, b, c, g)) continue;
    double d = 1e300;
    for (Vec2 uv : {s, r.triUv[k][0], r.triUv[k][1], r.triUv[k][2]}) {
      Vec3 p;
      if (surf.project(g, uv, &p)) d = std::min(d, dist(g, p));
    }
    const double ratio = d / ((dist(a, b) + dist(b, c) + dist(c, a)) / 3);
    f.worst = std::max(f.worst, ratio);
    if (ratio > 0.03 + 1e-9) ++f.over;
  }
  return f;
}

/// A face folded three times along x = -0.3, 0 and 0.3 (a W section of slopes +-m, each corner
/// rounded over +-e by a uniform quadratic B-spline), extruded over y in [0, 4].
std::unique_ptr<IGeometryModel> wFoldedFace(double e, double m) {
  return extrudedSection({{-1, 0.7 * m}, {-0.3 - e, m * e}, {-0.3 + e, m * e}, {-e, m * (0.3 - e)}, {e, m * (0.3 - e)},
                          {0.3 - e, m * e}, {0.3 + e, m * e}, {1, 0.7 * m}},
                         {0, 1 / 6.0, 2 / 6.0, 3 / 6.0, 4 / 6.0, 5 / 6.0, 1}, {3, 1, 1, 1, 1, 1, 3});
}

/// foldedFace(e, m) with its boundary discretised at the constant size 0.2.
struct FoldCase {
  std::unique_ptr<IGeometryModel> model;
  std::unique_ptr<ISurface> surf;
  SizeField field = constantField(0.2);
  std::vector<Vec3> nodeXyz;
  FaceBoundary fb;
};
void makeFoldCase(double e, double m, FoldCase& c, bool w = false) {
  c.model = w ? wFoldedFace(e, m) : foldedFace(e, m);
  c.surf = c.model->makeSurface(0);
  ASSERT_NO_FATAL_FAILURE(discretizedBoundary(*c.model, c.field, 0, c.fb, c.nodeXyz));
}
}  // namespace

TEST(Ops, CrestOfAFoldFarBelowTheSizeIsEmbedded) {
  // folds of 90, 143 and 158 degrees (flank slopes 1, 3, 5) at h = 0.2 with centroids bounded to
  // 0.03 of their mean edge (the curvature angle's bound): isotropic refinement would need edges
  // of the crest's radius x 10 degrees. The crest is traced and embedded, so every triangle lies on
  // one flank. Measured on the triangles clear of the two ends y = 0 and y = 4, whose boundary
  // this test discretises at the constant size (the pipeline gives edges curvature sizes too): a
  // segment there cuts across the fold whatever the face mesher does
  int plainOver = 0;
  for (double slope : {1.0, 3.0, 5.0}) {
    SCOPED_TRACE("slope " + std::to_string(slope));
    FoldCase fc;
    ASSERT_NO_FATAL_FAILURE(makeFoldCase(0.02, slope, fc));
    const auto& surf = fc.surf;
    const SizeField& field = fc.field;
    const std::vector<Vec3>& nodeXyz = fc.nodeXyz;
    const FaceBoundary& fb = fc.fb;
    FaceMeshOptions opt;
    opt.maxDeviationRatio = 0.03;
    opt.minSplitLength = 0.05;
    // vertices on the crest (0, y, 0.02 slope); the fit clear of the ends
    auto measure = [&](const FaceMeshResult& r, int& over, double& worst, int& onCrest, int& away) {
      onCrest = 0;
      for (const Vec3& x : r.newXyz)
        if (std::fabs(x.x) < 1e-4 && std::fabs(x.z - 0.02 * slope) < 1e-4) ++onCrest;
      const FoldFit f = foldFit(r, nodeXyz, *surf, [](Vec3 a, Vec3 b, Vec3 c, Vec3) {
        return !(std::min({a.y, b.y, c.y}) < 1e-9 || std::max({a.y, b.y, c.y}) > 4 - 1e-9);
      });
      over = f.over, worst = f.worst, away = f.away;
    };
    opt.embedCrests = false;
    const FaceMeshResult plain = meshFace(*surf, fb, field, opt, nullptr);
    ASSERT_TRUE(plain.ok) << plain.error;
    opt.embedCrests = true;
    const FaceMeshResult lined = meshFace(*surf, fb, field, opt, nullptr);
    ASSERT_TRUE(lined.ok) << lined.error;
    int over0, over1, crest0, crest1, away0, away1;
    double worst0, worst1;
    ASSERT_NO_FATAL_FAILURE(measure(plain, over0, worst0, crest0, away0));
    ASSERT_NO_FATAL_FAILURE(measure(lined, over1, worst1, crest1, away1));
    plainOver += over0 + away0;
    // the crest runs 4 long and its line keeps half a size from both ends: 19 segments of 0.2
    EXPECT_EQ(lined.crestSegments, 19);
    EXPECT_GE(crest1, 20) << "vertices on the crest (0, y, 0.02 slope)";
    EXPECT_EQ(over1, 0) << "worst " << worst1;
    EXPECT_LT(worst1, 0.02);
    EXPECT_EQ(away1, 0);
    // the first (discarded) frontal mesh is refunded: a point budget of 1.5 x the final mesh's new
    // vertices holds (counting both frontal meshes spends about twice them)
    Progress budget;
    budget.setPointBudget((long)(1.5 * lined.newXyz.size()));
    const FaceMeshResult again = meshFace(*surf, fb, field, opt, &budget);
    EXPECT_TRUE(again.ok && !budget.overBudget()) << again.error;
    EXPECT_EQ(again.tris.size(), lined.tris.size());
    std::printf("[ measured ] slope %.0f: without the crest %d over 0.03 (worst %.4f), %d facing away; with it %d "
                "(worst %.4f), %d\n", slope, over0, worst0, away0, over1, worst1, away1);
  }
  EXPECT_GT(plainOver, 0) << "the folds are beyond the crest splits alone";
}

TEST(Ops, RowsBesideACrestFollowItsShoulders) {
  // folds whose flanks keep turning well away from the crest (the quadratic sections reach their
  // slope only a few e from it, as propeller_and_shaft's blade tips do within 0.02 mm at a size
  // of 0.038): a triangle with an edge on the crest and its apex a size away on the flank cuts
  // the shoulder. The deviation refinement is off (no split shorter than the size, as the
  // min-size floor forbids them on the blades), so the mesh before it is what is measured. Rows
  // along the crest, set where the flank would sag from their chord, keep every triangle within
  // the bound. Measured clear of the ends y = 0 and y = 4 (their boundary segments, at the
  // constant size, cut across the fold)
  int plainOver = 0;
  for (const auto& [e, slope] : std::vector<std::pair<double, double>>{{0.1, 2}, {0.1, 4}, {0.15, 2}, {0.15, 4}, {0.25, 2}, {0.25, 4}}) {
    SCOPED_TRACE("e " + std::to_string(e) + " slope " + std::to_string(slope));
    FoldCase c;
    ASSERT_NO_FATAL_FAILURE(makeFoldCase(e, slope, c));
    FaceMeshOptions opt;
    opt.maxDeviationRatio = 0.03;
    opt.minSplitLength = 10;  // no split: refinement off
    auto clearOfEnds = [](Vec3, Vec3, Vec3, Vec3 g) { return g.y >= 0.3 && g.y <= 3.7; };
    opt.crestRows = false;
    const FaceMeshResult plain = meshFace(*c.surf, c.fb, c.field, opt, nullptr);
    ASSERT_TRUE(plain.ok) << plain.error;
    opt.crestRows = true;
    const FaceMeshResult rows = meshFace(*c.surf, c.fb, c.field, opt, nullptr);
    ASSERT_TRUE(rows.ok) << rows.error;
    const FoldFit f0 = foldFit(plain, c.nodeXyz, *c.surf, clearOfEnds), f1 = foldFit(rows, c.nodeXyz, *c.surf, clearOfEnds);
    plainOver += f0.over;
    EXPECT_EQ(rows.crestSegments, 19);
    // at least one row on each flank, the crest's whole length
    EXPECT_GE(rows.crestRowSegments, 2 * 19);
    EXPECT_EQ(f1.over, 0) << "worst " << f1.worst;
    EXPECT_LT(f1.worst, 0.02);
    EXPECT_EQ(f1.away, 0);
    std::printf("[ measured ] e %.2f slope %.0f: %d crest and %d row segments; without the rows %d over 0.03 (worst "
                "%.4f), %d facing away; with them %d (worst %.4f), %d; %zu / %zu triangles\n",
                e, slope, rows.crestSegments, rows.crestRowSegments, f0.over, f0.worst, f0.away, f1.over, f1.worst,
                f1.away, plain.tris.size(), rows.tris.size());
  }
  EXPECT_GT(plainOver, 0) << "the shoulders are beyond a crest alone";
}

TEST(Ops, RowsOfNeighbouringCrestsStayValid) {
  // three crests 0.3 apart (1.5 sizes) whose shoulders reach into each other's (a row checks the
  // face's boundary for clearance, not other crests): whatever is embedded, the mesh stays valid
  // and within the bound. Measured: 2-3 crests of 19 segments, 76-377 row segments, worst
  // 0.016-0.030, none facing away
  for (const auto& [e, slope] : std::vector<std::pair<double, double>>{{0.02, 3}, {0.06, 3}, {0.1, 2}, {0.1, 4}}) {
    SCOPED_TRACE("e " + std::to_string(e) + " slope " + std::to_string(slope));
    FoldCase c;
    ASSERT_NO_FATAL_FAILURE(makeFoldCase(e, slope, c, true));
    FaceMeshOptions opt;
    opt.maxDeviationRatio = 0.03;
    opt.minSplitLength = 0.05;
    const FaceMeshResult r = meshFace(*c.surf, c.fb, c.field, opt, nullptr);
    ASSERT_TRUE(r.ok) << r.error;
    const FoldFit f = foldFit(r, c.nodeXyz, *c.surf, [](Vec3, Vec3, Vec3, Vec3 g) { return g.y >= 0.3 && g.y <= 3.7; });
    std::printf("[ measured ] W e %.2f slope %.0f: %d crest and %d row segments; %d over 0.03 (worst %.4f), %d facing away; %zu triangles\n",
                e, slope, r.crestSegments, r.crestRowSegments, f.over, f.worst, f.away, r.tris.size());
    EXPECT_GE(r.crestSegments, 2 * 19);
    EXPECT_GT(r.crestRowSegments, 0);
    EXPECT_EQ(f.over, 0) << "worst " << f.worst;
    EXPECT_EQ(f.away, 0);
  }
}

