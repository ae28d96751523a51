// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file DiscreteModel.cpp
#include "paramesh/geom/discrete/DiscreteModel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "paramesh/geom/discrete/DiskCuts.hpp"
#include "paramesh/geom/discrete/PatchParam.hpp"
#include "paramesh/util/Error.hpp"

namespace paramesh {
namespace {

/// A feature chain as a polyline parametrised by arc length.
struct Polyline {
  std::vector<Vec3> p;
  std::vector<double> s;  // cumulative length, s[0] = 0
  /// segment index and fraction at t
  std::pair<size_t, double> at(double t) const {
    if (p.size() < 2) return {0, 0.0};
    const auto it = std::upper_bound(s.begin(), s.end(), t);
    size_t i = it == s.begin() ? 0 : (size_t)(it - s.begin()) - 1;
    i = std::min(i, p.size() - 2);
    const double l = s[i + 1] - s[i];
    return {i, l > 0 ? (t - s[i]) / l : 0.0};
  }
};

class DiscreteCurve final : public ICurve {
 public:
  explicit DiscreteCurve(const Polyline* c) : c_(c) {}
  CurveKind kind() const override { return CurveKind::Other; }
  Vec3 eval(double t) const override {
    const auto [i, a] = c_->at(t);
    return (1 - a) * c_->p[i] + a * c_->p[i + 1];
  }
  void d1(double t, Vec3& p, Vec3& dt) const override {
    const auto [i, a] = c_->at(t);
    p = (1 - a) * c_->p[i] + a * c_->p[i + 1];
    const double l = c_->s[i + 1] - c_->s[i];
    dt = l > 0 ? (1.0 / l) * (c_->p[i + 1] - c_->p[i]) : Vec3{0, 0, 0};
  }
  void d2(double t, Vec3& p, Vec3& d1v, Vec3& d2v) const override {
    d1(t, p, d1v);
    d2v = {0, 0, 0};
  }

 private:
  const Polyline* c_;
};

/// One face's parametrisation with a grid over (u,v) to find the triangle at a point.
struct FaceGeometry {
  PatchParam param;
  std::vector<Vec3> xyz;  // per local vertex
  int cells = 1;
  std::vector<std::vector<int>> grid;  // cells x cells over [-1, 1]^2, triangles overlapping each
  int cellOf(double x) const { return std::clamp((int)std::floor((x + 1.0) * 0.5 * cells), 0, cells - 1); }
  void build() {
    cells = std::max(1, (int)std::sqrt((double)param.tris.size() / 2.0));
    grid.assign((size_t)cells * cells, {});
    for (size_t k = 0; k < param.tris.size(); ++k) {
      double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
      for (int c : param.tris[k]) {
        const Vec2 q = param.uv[c];
        u0 = std::min(u0, q.x), u1 = std::max(u1, q.x), v0 = std::min(v0, q.y), v1 = std::max(v1, q.y);
      }
      for (int i = cellOf(u0); i <= cellOf(u1); ++i)
        for (int j = cellOf(v0); j <= cellOf(v1); ++j) grid[(size_t)i * cells + j].push_back((int)k);
    }
  }
  /// The triangle holding q (or nearest to it) and q's barycentric coordinates there, clamped in.
  int locate(Vec2 q, double& b1, double& b2) const {
    int best = -1;
    double bestOut = std::numeric_limits<double>::infinity();
    const int ci = cellOf(q.x), cj = cellOf(q.y);
    for (int r = 0; r < cells && (best < 0 || bestOut > 0); ++r) {
      for (int i = std::max(0, ci - r); i <= std::min(cells - 1, ci + r); ++i)
        for (int j = std::max(0, cj - r); j <= std::min(cells - 1, cj + r); ++j) {
          if (std::max(std::abs(i - ci), std::abs(j - cj)) != r) continue;  // the ring only
          for (int k : grid[(size_t)i * cells + j]) {
            const auto& t = param.tris[k];
            const Vec2 a = param.uv[t[0]], e1 = param.uv[t[1]] - a, e2 = param.uv[t[2]] - a, d = q - a;
            const double det = e1.x * e2.y - e1.y * e2.x;
            if (!(std::abs(det) > 0)) continue;
            const double x = (d.x * e2.y - d.y * e2.x) / det, y = (e1.x * d.y - e1.y * d.x) / det;
            const double outside = std::max({0.0, -x, -y, x + y - 1});
            if (outside < bestOut) bestOut = outside, best = k, b1 = x, b2 = y;
          }
        }
      if (best >= 0 && r >= 1) break;  // the ring around the first hit searched too
    }
    if (best >= 0) {  // clamp into the triangle
      b1 = std::max(0.0, b1), b2 = std::max(0.0, b2);
      const double s = b1 + b2;
      if (s > 1) b1 /= s, b2 /= s;
    }
    return best;
  }
};

class DiscreteSurface final : public ISurface {
 public:
  explicit DiscreteSurface(const FaceGeometry* g) : g_(g) {}
  SurfaceKind kind() const override { return SurfaceKind::Other; }
  Vec3 eval(Vec2 uv) const override {
    Vec3 p, du, dv;
    d1(uv, p, du, dv);
    return p;
  }
  void d1(Vec2 uv, Vec3& p, Vec3& du, Vec3& dv) const override {
    double b1 = 0, b2 = 0;
    const int k = g_->locate(uv, b1, b2);
    if (k < 0) {
      p = du = dv = {0, 0, 0};
      return;
    }
    const auto& t = g_->param.tris[k];
    const Vec3 x0 = g_->xyz[t[0]], x1 = g_->xyz[t[1]], x2 = g_->xyz[t[2]];
    p = x0 + b1 * (x1 - x0) + b2 * (x2 - x0);
    // the affine map's derivatives: [x1-x0 x2-x0] * inverse([uv1-uv0 uv2-uv0])
    const Vec2 e1 = g_->param.uv[t[1]] - g_->param.uv[t[0]], e2 = g_->param.uv[t[2]] - g_->param.uv[t[0]];
    const double det = e1.x * e2.y - e1.y * e2.x;
    const Vec3 a = x1 - x0, b = x2 - x0;
    du = (1.0 / det) * (e2.y * a - e1.y * b);
    dv = (1.0 / det) * (-e2.x * a + e1.x * b);
  }
  void d2(Vec2 uv, SurfaceD2& d) const override {
    d1(uv, d.p, d.du, d.dv);
    d.duu = d.duv = d.dvv = {0, 0, 0};
  }
  UVBox bounds() const override { return {-1, 1, -1, 1}; }
  double uPeriod() const override { return 0; }
  double vPeriod() const override { return 0; }

 private:
  const FaceGeometry* g_;
};

/// A pcurve: the use's boundary vertices' (u,v) at the chain nodes' arc lengths.
class DiscretePCurve final : public IPCurve {
 public:
  DiscretePCurve(const Polyline* c, std::vector<Vec2> uv) : c_(c), uv_(std::move(uv)) {}
  Vec2 eval(double t) const override {
    const auto [i, a] = c_->at(t);
    return (1 - a) * uv_[i] + a * uv_[i + 1];
  }
  void d1(double t, Vec2& p, Vec2& dt) const override {
    const auto [i, a] = c_->at(t);
    p = (1 - a) * uv_[i] + a * uv_[i + 1];
    const double l = c_->s[i + 1] - c_->s[i];
    dt = l > 0 ? (1.0 / l) * (uv_[i + 1] - uv_[i]) : Vec2{0, 0};
  }

 private:
  const Polyline* c_;
  std::vector<Vec2> uv_;
};

class DiscreteModel final : public IGeometryModel {
 public:
  explicit DiscreteModel(DiscreteInput in) : in_(std::move(in)) {
    const TriangleSoup& m = in_.mesh;
    FeatureGraph& g = in_.graph;
    const std::vector<std::string> cutErrors = cutFacesToDisks(m, g);
    for (const Vec3& p : m.points) box_.add(p);
    tol_ = 1e-7 * box_.diagonal();
    curves_.resize(g.edges.size());
    edgeFaces_.resize(g.edges.size());
    for (size_t e = 0; e < g.edges.size(); ++e) {
      Polyline& c = curves_[e];
      for (int n : g.edges[e].nodes) {
        if (!c.p.empty()) c.s.push_back(c.s.back() + dist(c.p.back(), m.points[n]));
        else c.s.push_back(0);
        c.p.push_back(m.points[n]);
      }
    }
    const int nf = (int)g.faceTris.size();
    faces_.resize(nf);
    wires_.resize(nf);
    errors_ = cutErrors;
    for (int f = 0; f < nf; ++f) {
      for (const auto& loop : g.faceLoops[f]) {
        Wire w;
        for (const auto& [e, rev] : loop) {
          w.uses.push_back({e, rev});
          auto& ef = edgeFaces_[e];
          if (std::find(ef.begin(), ef.end(), f) == ef.end()) ef.push_back(f);
        }
        wires_[f].push_back(std::move(w));
      }
      if (!errors_[f].empty()) continue;
      FaceGeometry& fg = faces_[f];
      fg.param = parametrizeFace(m, g, f);
      errors_[f] = fg.param.error;
      if (!errors_[f].empty()) continue;
      for (int n : fg.param.node) fg.xyz.push_back(m.points[n]);
      fg.build();
    }
    // solids: the closed pieces (faces joined across their edges, every edge used twice)
    std::vector<int> piece(nf, -1);
    int np = 0;
    for (int f = 0; f < nf; ++f) {
      if (piece[f] >= 0) continue;
      std::vector<int> stack{f};
      piece[f] = np;
      while (!stack.empty()) {
        const int a = stack.back();
        stack.pop_back();
        for (const Wire& w : wires_[a])
          for (const EdgeUse& u : w.uses)
            for (int b : edgeFaces_[u.edge])
              if (piece[b] < 0) piece[b] = np, stack.push_back(b);
      }
      ++np;
    }
    std::vector<char> closed(np, 1);
    std::vector<int> uses(g.edges.size(), 0);
    for (int f = 0; f < nf; ++f)
      for (const Wire& w : wires_[f])
        for (const EdgeUse& u : w.uses) ++uses[u.edge];
    for (int f = 0; f < nf; ++f)
      for (const Wire& w : wires_[f])
        for (const EdgeUse& u : w.uses)
          if (uses[u.edge] != 2) closed[piece[f]] = 0;
    std::vector<int> solidOfPiece(np, -1);
    for (int p = 0; p < np; ++p)
      if (closed[p]) solidOfPiece[p] = numSolids_++;
    faceSolid_.resize(nf);
    for (int f = 0; f < nf; ++f) faceSolid_[f] = solidOfPiece[piece[f]];
  }

  int numFaces() const override { return (int)faces_.size(); }
  int numEdges() const override { return (int)curves_.size(); }
  int numVertices() const override { return (int)in_.graph.vertexNode.size(); }
  int numSolids() const override { return numSolids_; }
  Vec3 vertexPoint(int v) const override { return in_.mesh.points[in_.graph.vertexNode[v]]; }
  double vertexTolerance(int) const override { return tol_; }
  void edgeRange(int e, double& t0, double& t1) const override {
    t0 = 0;
    t1 = curves_[e].s.back();
  }
  int edgeVertex(int e, int end) const override { return end == 0 ? in_.graph.edges[e].v0 : in_.graph.edges[e].v1; }
  bool edgeDegenerate(int) const override { return false; }
  std::unique_ptr<ICurve> makeCurve(int e) const override { return std::make_unique<DiscreteCurve>(&curves_[e]); }
  double edgeTolerance(int) const override { return tol_; }
  const std::vector<int>& edgeFaces(int e) const override { return edgeFaces_[e]; }
  std::unique_ptr<ISurface> makeSurface(int f) const override {
    if (!errors_[f].empty()) throw InputError(errors_[f]);
    return std::make_unique<DiscreteSurface>(&faces_[f]);
  }
  bool faceReversed(int) const override { return false; }
  const std::vector<Wire>& faceWires(int f) const override { return wires_[f]; }
  std::unique_ptr<IPCurve> makePCurve(int f, int wire, int use) const override {
    if (!errors_[f].empty()) throw InputError(errors_[f]);
    const FaceGeometry& fg = faces_[f];
    const std::vector<int>& lv = fg.param.useVertices[use];
    (void)wire;  // one wire per parametrised face
    std::vector<Vec2> uv;
    for (int v : lv) uv.push_back(fg.param.uv[v]);
    return std::make_unique<DiscretePCurve>(&curves_[wires_[f][0].uses[use].edge], std::move(uv));
  }
  double faceTolerance(int) const override { return tol_; }
  int faceSolid(int f) const override { return faceSolid_[f]; }
  std::vector<SolidFace> solidFaces(int s) const override {
    std::vector<SolidFace> out;
    for (int f = 0; f < (int)faceSolid_.size(); ++f)
      if (faceSolid_[f] == s) out.push_back({f, false});
    return out;
  }
  Box3 boundingBox() const override { return box_; }
  std::string source() const override { return in_.mesh.source; }
  std::vector<std::string> readWarnings() const override { return in_.repair.lines(); }

 private:
  DiscreteInput in_;
  Box3 box_;
  double tol_ = 0;
  std::vector<Polyline> curves_;
  std::vector<std::vector<int>> edgeFaces_;
  std::vector<FaceGeometry> faces_;
  std::vector<std::vector<Wire>> wires_;
  std::vector<std::string> errors_;
  std::vector<int> faceSolid_;
  int numSolids_ = 0;
};

}  // namespace

std::unique_ptr<IGeometryModel> makeDiscreteModel(DiscreteInput input) {
  return std::make_unique<DiscreteModel>(std::move(input));
}

std::unique_ptr<IGeometryModel> loadDiscreteModel(const std::string& path, double featureAngleDeg) {
  return makeDiscreteModel(loadDiscrete(path, featureAngleDeg));
}

}  // namespace paramesh
