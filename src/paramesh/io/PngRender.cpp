// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file PngRender.cpp
/// Z-buffer rasteriser (fixed-point edge functions with a top-left fill rule, so triangles that
/// share an edge neither overlap nor leave cracks) and PNG output through libpng's simplified API.
#include "paramesh/io/PngRender.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "paramesh/io/MeshWriters.hpp"
#include "paramesh/util/Error.hpp"

namespace paramesh {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Rgb {
  float r = 0, g = 0, b = 0;
};

/// HSV (all in [0,1]) to RGB.
Rgb hsv(double h, double s, double v) {
  h = (h - std::floor(h)) * 6.0;
  int i = static_cast<int>(h) % 6;
  double f = h - std::floor(h);
  double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r, g, b;
  switch (i) {
    case 0: r = v, g = t, b = p; break;
    case 1: r = q, g = v, b = p; break;
    case 2: r = p, g = v, b = t; break;
    case 3: r = p, g = q, b = v; break;
    case 4: r = t, g = p, b = v; break;
    default: r = v, g = p, b = q; break;
  }
  return {static_cast<float>(r), static_cast<float>(g), static_cast<float>(b)};
}

/// Pastel colour of a CAD face: golden-ratio hue steps (neighbouring numbers differ clearly)
/// with a hashed saturation/value jitter.
Rgb faceColor(int face) {
  uint32_t h = static_cast<uint32_t>(face) * 2654435761u;
  h ^= h >> 15;
  h *= 2246822519u;
  h ^= h >> 13;
  double hue = 0.12 + 0.618033988749895 * static_cast<double>(face);
  double sat = 0.32 + 0.18 * static_cast<double>(h & 0xFF) / 255.0;
  double val = 0.86 + 0.12 * static_cast<double>((h >> 8) & 0xFF) / 255.0;
  return hsv(hue, sat, val);
}

/// blue (0) -> cyan -> green -> yellow -> red (1).
Rgb qualityColor(double q) {
  static const float stops[5][3] = {
      {0.15f, 0.25f, 0.95f}, {0.10f, 0.85f, 0.95f}, {0.20f, 0.85f, 0.25f}, {0.98f, 0.90f, 0.15f},
      {0.95f, 0.15f, 0.10f}};
  if (!(q > 0)) q = 0;  // also NaN
  if (q > 1) q = 1;
  double s = q * 4.0;
  int i = std::min(3, static_cast<int>(s));
  float f = static_cast<float>(s - i);
  return {stops[i][0] + f * (stops[i + 1][0] - stops[i][0]),
          stops[i][1] + f * (stops[i + 1][1] - stops[i][1]),
          stops[i][2] + f * (stops[i + 1][2] - stops[i][2])};
}

/// A projected vertex: pixel coordinates (x right, y down, pixel centres at i + 0.5) and depth
/// (larger = nearer to the camera).
struct PV {
  double x = 0, y = 0, z = 0;
};

class Raster {
 public:
  Raster(int w, int h)
      : w_(w), h_(h), z_(static_cast<std::size_t>(w) * h, -kInf),
        tol_(static_cast<std::size_t>(w) * h, 0.0f), rgb_(static_cast<std::size_t>(w) * h * 3, 255) {}

  double zNear = std::numeric_limits<double>::infinity();  ///< fragments nearer are discarded
  double depthBias = 0;  ///< constant part of the line depth tolerance
  double slopeCap = 0;   ///< cap of the slope-scaled part of the line depth tolerance

  /// Fills triangle (a,b,c) with a flat colour (either orientation).
  void triangle(const PV& a, const PV& b, const PV& c, const uint8_t col[3]) {
    if (!finite(a) || !finite(b) || !finite(c)) return;
    const double G = kGuard;
    auto inside = [&](const PV& p) {
      return p.x >= -G && p.x <= w_ + G && p.y >= -G && p.y <= h_ + G;
    };
    if (inside(a) && inside(b) && inside(c)) return fill(a, b, c, col);
    // Trivially outside the picture?
    if (std::max({a.x, b.x, c.x}) < 0 || std::min({a.x, b.x, c.x}) > w_ ||
        std::max({a.y, b.y, c.y}) < 0 || std::min({a.y, b.y, c.y}) > h_)
      return;
    // Clip to the guard band (keeps the fixed-point arithmetic in range), then fan.
    PV poly[16], tmp[16];
    int n = 3;
    poly[0] = a, poly[1] = b, poly[2] = c;
    for (int side = 0; side < 4 && n >= 3; ++side) {
      auto dist = [&](const PV& p) {
        switch (side) {
          case 0: return p.x + G;
          case 1: return w_ + G - p.x;
          case 2: return p.y + G;
          default: return h_ + G - p.y;
        }
      };
      int m = 0;
      for (int i = 0; i < n; ++i) {
        const PV &p = poly[i], &q = poly[(i + 1) % n];
        double dp = dist(p), dq = dist(q);
        if (dp >= 0) tmp[m++] = p;
        if ((dp >= 0) != (dq >= 0)) {
          double t = dp / (dp - dq);
          tmp[m++] = {p.x + t * (q.x - p.x), p.y + t * (q.y - p.y), p.z + t * (q.z - p.z)};
        }
      }
      n = m;
      std::copy(tmp, tmp + n, poly);
    }
    for (int i = 1; i + 1 < n; ++i) fill(poly[0], poly[i], poly[i + 1], col);
  }

  /// Draws a 1-pixel line, depth-tested against the triangles with the tolerance of the triangle
  /// that owns each pixel (so edges show on their own faces, hidden edges stay hidden).
  void line(PV a, PV b, const uint8_t col[3]) {
    if (!finite(a) || !finite(b)) return;
    // Liang-Barsky clip to [0,w] x [0,h].
    double t0 = 0, t1 = 1, dx = b.x - a.x, dy = b.y - a.y;
    auto clip = [&](double p, double q) {
      if (p == 0) return q >= 0;
      double r = q / p;
      if (p < 0) {
        if (r > t1) return false;
        t0 = std::max(t0, r);
      } else {
        if (r < t0) return false;
        t1 = std::min(t1, r);
      }
      return true;
    };
    if (!clip(-dx, a.x) || !clip(dx, w_ - a.x) || !clip(-dy, a.y) || !clip(dy, h_ - a.y)) return;
    PV p{a.x + t0 * dx, a.y + t0 * dy, a.z + t0 * (b.z - a.z)};
    PV q{a.x + t1 * dx, a.y + t1 * dy, a.z + t1 * (b.z - a.z)};
    // One pixel per column (x-major) or row (y-major), sampled on the line at the pixel centre's
    // abscissa (clamped to the segment), so no column/row is skipped or doubled.
    const bool xMajor = std::fabs(q.x - p.x) >= std::fabs(q.y - p.y);
    const double u0 = xMajor ? p.x : p.y, u1 = xMajor ? q.x : q.y;
    const double uLo = std::min(u0, u1), uHi = std::max(u0, u1), du = u1 - u0;
    const int limit = (xMajor ? w_ : h_) - 1;
    const int k0 = std::max(0, static_cast<int>(std::floor(uLo)));
    const int k1 = std::min(limit, static_cast<int>(std::floor(uHi)));
    for (int k = k0; k <= k1; ++k) {
      double u = std::clamp(k + 0.5, uLo, uHi);
      double t = du != 0 ? (u - u0) / du : 0.0;
      double x = p.x + t * (q.x - p.x), y = p.y + t * (q.y - p.y), z = p.z + t * (q.z - p.z);
      int ix = std::min(w_ - 1, static_cast<int>(std::floor(x)));
      int iy = std::min(h_ - 1, static_cast<int>(std::floor(y)));
      if (ix < 0 || iy < 0 || z > zNear) continue;
      std::size_t pix = static_cast<std::size_t>(iy) * w_ + ix;
      if (static_cast<float>(z) + tol_[pix] >= z_[pix]) put(pix, col);
    }
  }

  RgbImage take() {
    RgbImage img;
    img.width = w_;
    img.height = h_;
    img.rgb = std::move(rgb_);
    return img;
  }

 private:
  static constexpr float kInf = std::numeric_limits<float>::infinity();
  static constexpr double kGuard = 2048;  ///< pixels beyond the picture kept before clipping
  static constexpr int kSub = 256;        ///< fixed-point sub-pixel steps

  static bool finite(const PV& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
  }
  void put(std::size_t pix, const uint8_t col[3]) {
    uint8_t* d = &rgb_[pix * 3];
    d[0] = col[0], d[1] = col[1], d[2] = col[2];
  }

  void fill(const PV& a, const PV& b, const PV& c, const uint8_t col[3]) {
    int64_t X[3] = {std::llround(a.x * kSub), std::llround(b.x * kSub), std::llround(c.x * kSub)};
    int64_t Y[3] = {std::llround(a.y * kSub), std::llround(b.y * kSub), std::llround(c.y * kSub)};
    double Z[3] = {a.z, b.z, c.z};
    int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (Y[1] - Y[0]) * (X[2] - X[0]);
    if (area == 0) return;
    if (area < 0) {  // make (0,1,2) positive so inside means all edge functions >= 0
      std::swap(X[1], X[2]);
      std::swap(Y[1], Y[2]);
      std::swap(Z[1], Z[2]);
    }
    // Pixel range whose centres (i + 0.5) may lie inside.
    int64_t minX = std::min({X[0], X[1], X[2]}), maxX = std::max({X[0], X[1], X[2]});
    int64_t minY = std::min({Y[0], Y[1], Y[2]}), maxY = std::max({Y[0], Y[1], Y[2]});
    auto ceilDiv = [](int64_t n, int64_t k) { return n >= 0 ? (n + k - 1) / k : -((-n) / k); };
    auto floorDiv = [](int64_t n, int64_t k) { return n >= 0 ? n / k : -((-n + k - 1) / k); };
    int64_t x0 = std::max<int64_t>(0, ceilDiv(minX - kSub / 2, kSub));
    int64_t x1 = std::min<int64_t>(w_ - 1, floorDiv(maxX - kSub / 2, kSub));
    int64_t y0 = std::max<int64_t>(0, ceilDiv(minY - kSub / 2, kSub));
    int64_t y1 = std::min<int64_t>(h_ - 1, floorDiv(maxY - kSub / 2, kSub));
    if (x0 > x1 || y0 > y1) return;

    // Edge functions E_ij(P) = (Xj-Xi)(Py-Yi) - (Yj-Yi)(Px-Xi), for edges 12, 20, 01.
    int64_t dxE[3], dyE[3], rowE[3], bias[3];
    const int64_t px0 = x0 * kSub + kSub / 2, py0 = y0 * kSub + kSub / 2;
    for (int e = 0; e < 3; ++e) {
      int i = (e + 1) % 3, j = (e + 2) % 3;
      int64_t dx = X[j] - X[i], dy = Y[j] - Y[i];
      dxE[e] = dx;
      dyE[e] = dy;
      rowE[e] = dx * (py0 - Y[i]) - dy * (px0 - X[i]);
      // Top-left rule: a pixel centre exactly on an edge belongs to one of its two triangles.
      bias[e] = (dy > 0 || (dy == 0 && dx < 0)) ? 0 : -1;
    }
    // Depth plane in pixel units. Each pixel also records a slope-scaled depth tolerance (like
    // glPolygonOffset, but applied to the lines only, so triangles still compete exactly).
    auto toPixels = [](int64_t v) { return static_cast<double>(v) / kSub; };
    const double fx[3] = {toPixels(X[0]), toPixels(X[1]), toPixels(X[2])};
    const double fy[3] = {toPixels(Y[0]), toPixels(Y[1]), toPixels(Y[2])};
    double det = (fx[1] - fx[0]) * (fy[2] - fy[0]) - (fx[2] - fx[0]) * (fy[1] - fy[0]);
    double gx = ((Z[1] - Z[0]) * (fy[2] - fy[0]) - (Z[2] - Z[0]) * (fy[1] - fy[0])) / det;
    double gy = ((fx[1] - fx[0]) * (Z[2] - Z[0]) - (fx[2] - fx[0]) * (Z[1] - Z[0])) / det;
    // A line sample lies within half a pixel (in x and y) of the centre of the pixel it lands
    // on: allow that much depth change, with a margin.
    const float tol =
        static_cast<float>(depthBias + std::min(slopeCap, 0.6 * (std::fabs(gx) + std::fabs(gy))));
    double zRow = Z[0] + gx * (static_cast<double>(x0) + 0.5 - fx[0]) +
                  gy * (static_cast<double>(y0) + 0.5 - fy[0]);
    const bool clipNear = std::isfinite(zNear);

    for (int64_t y = y0; y <= y1; ++y) {
      int64_t e0 = rowE[0], e1 = rowE[1], e2 = rowE[2];
      double z = zRow;
      std::size_t pix = static_cast<std::size_t>(y) * w_ + static_cast<std::size_t>(x0);
      for (int64_t x = x0; x <= x1; ++x, ++pix) {
        if (((e0 + bias[0]) | (e1 + bias[1]) | (e2 + bias[2])) >= 0 && !(clipNear && z > zNear)) {
          float zs = static_cast<float>(z);
          if (zs > z_[pix]) {
            z_[pix] = zs;
            tol_[pix] = tol;
            put(pix, col);
          }
        }
        e0 -= dyE[0] * kSub;
        e1 -= dyE[1] * kSub;
        e2 -= dyE[2] * kSub;
        z += gx;
      }
      rowE[0] += dxE[0] * kSub;
      rowE[1] += dxE[1] * kSub;
      rowE[2] += dxE[2] * kSub;
      zRow += gy;
    }
  }

  int w_, h_;
  std::vector<float> z_;    ///< depth of the nearest triangle (larger = nearer)
  std::vector<float> tol_;  ///< line depth tolerance of that triangle
  std::vector<uint8_t> rgb_;
};

}  // namespace

/// The view frame (d towards the camera, right, up), the framing of the model or the focus box,
/// and every node's screen position and depth.
struct ViewProjection {
  Vec3 d, right, up;
  Box3 focus;
  double zc = 0, depthRange = 1;
  double cx = 0, cy = 0, scale = 1;  ///< screen centre (model units) and pixels per model unit
  std::vector<PV> pv;
};

ViewProjection project(const SurfaceMesh& m, const RenderOptions& o, int W, int H) {
  // View frame: d points from the model towards the camera.
  const double az = o.azimuthDeg * kPi / 180, el = o.elevationDeg * kPi / 180;
  ViewProjection v;
  Vec3& d = v.d;
  d = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
  Vec3& right = v.right;
  right = {-std::sin(az), std::cos(az), 0.0};
  Vec3& up = v.up;
  up = cross(d, right);

  // Screen-space extents to frame: the model's projected nodes, or the focus box's corners.
  Box3 model;
  for (const Vec3& p : m.nodes) model.add(p);
  if (model.empty()) model.add(Vec3());
  double sx0 = 1e300, sx1 = -1e300, sy0 = 1e300, sy1 = -1e300;
  auto extend = [&](const Vec3& p) {
    double x = dot(p, right), y = dot(p, up);
    sx0 = std::min(sx0, x), sx1 = std::max(sx1, x);
    sy0 = std::min(sy0, y), sy1 = std::max(sy1, y);
  };
  Box3& focus = v.focus;
  if (o.hasFocus) {
    focus.add(o.focusLo);
    focus.add(o.focusHi);
    for (int k = 0; k < 8; ++k)
      extend({(k & 1) ? focus.hi.x : focus.lo.x, (k & 2) ? focus.hi.y : focus.lo.y,
              (k & 4) ? focus.hi.z : focus.lo.z});
  } else if (m.nodes.empty()) {
    extend(Vec3());
  } else {
    for (const Vec3& p : m.nodes) extend(p);
  }
  const double ext = std::max(sx1 - sx0, sy1 - sy0);
  double scale;  // pixels per model unit, 5% margin on each side
  if (!(ext > 0) || !std::isfinite(ext)) {
    scale = 1.0;
  } else {
    scale = 0.9 * std::min(W / std::max(sx1 - sx0, ext * 1e-9), H / std::max(sy1 - sy0, ext * 1e-9));
  }
  const double cx = 0.5 * (sx0 + sx1), cy = 0.5 * (sy0 + sy1);
  v.cx = cx, v.cy = cy, v.scale = scale;
  const Vec3 centre = o.hasFocus ? 0.5 * (focus.lo + focus.hi) : 0.5 * (model.lo + model.hi);
  v.zc = dot(centre, d);
  const double zc = v.zc;

  std::vector<PV>& pv = v.pv;
  pv.resize(m.nodes.size());
  double zMin = 1e300, zMax = -1e300;
  for (std::size_t i = 0; i < m.nodes.size(); ++i) {
    const Vec3& p = m.nodes[i];
    pv[i] = {0.5 * W + (dot(p, right) - cx) * scale, 0.5 * H - (dot(p, up) - cy) * scale,
             dot(p, d) - zc};
    zMin = std::min(zMin, pv[i].z), zMax = std::max(zMax, pv[i].z);
  }
  v.depthRange = zMax > zMin ? zMax - zMin : 1.0;
  return v;
}

RgbImage renderImage(const SurfaceMesh& m, const RenderOptions& o) {
  if (o.width < 1 || o.height < 1 || o.width > 16384 || o.height > 16384)
    throw Error("picture size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                " is out of range (1..16384 pixels each)");
  std::string problem = io::findMeshProblem(m);
  if (!problem.empty()) throw Error("invalid mesh (" + problem + ")");
  const bool o2 = m.order == 2;
  const int W = o.width, H = o.height;

  ViewProjection view = project(m, o, W, H);
  const Vec3 &d = view.d, &right = view.right, &up = view.up;
  const Box3& focus = view.focus;
  const double zc = view.zc, depthRange = view.depthRange, cx = view.cx, cy = view.cy, scale = view.scale;
  std::vector<PV>& pv = view.pv;

  Raster r(W, H);
  r.depthBias = 2e-5 * depthRange;
  r.slopeCap = 0.02 * depthRange;
  if (o.hasFocus && o.clipFront) {
    double nearest = -1e300;
    for (int k = 0; k < 8; ++k)
      nearest = std::max(nearest, dot(Vec3{(k & 1) ? focus.hi.x : focus.lo.x,
                                           (k & 2) ? focus.hi.y : focus.lo.y,
                                           (k & 4) ? focus.hi.z : focus.lo.z},
                                      d) - zc);
    r.zNear = nearest + 0.05 * focus.diagonal();
  }

  auto baseColor = [&](int face, double quality) {
    switch (o.color) {
      case RenderOptions::Color::ByFace: return faceColor(face);
      case RenderOptions::Color::ByQuality: return qualityColor(quality);
      default: return Rgb{0.72f, 0.78f, 0.88f};
    }
  };
  // Flat two-sided Lambert shading with a headlight (light along the view direction).
  auto shade = [&](const Rgb& base, int a, int b, int c, uint8_t out[3]) {
    Vec3 n = cross(m.nodes[b] - m.nodes[a], m.nodes[c] - m.nodes[a]);
    double l = norm(n);
    double lambert = l > 0 ? std::fabs(dot(n, d)) / l : 0.0;
    double k = 0.3 + 0.7 * lambert;
    auto to8 = [&](float v) {
      return static_cast<uint8_t>(std::lround(std::clamp(v * k, 0.0, 1.0) * 255.0));
    };
    out[0] = to8(base.r), out[1] = to8(base.g), out[2] = to8(base.b);
  };
  auto tri = [&](const Rgb& base, int a, int b, int c) {
    uint8_t col[3];
    shade(base, a, b, c, col);
    r.triangle(pv[a], pv[b], pv[c], col);
  };

  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& e = m.triangles[t];
    double q = o.color == RenderOptions::Color::ByQuality
                   ? io::triangleGamma(m.nodes[e[0]], m.nodes[e[1]], m.nodes[e[2]])
                   : 0.0;
    Rgb base = baseColor(m.triangleFace[t], q);
    if (!o2) {
      tri(base, e[0], e[1], e[2]);
    } else {
      const auto& md = m.triangleMid[t];  // ab, bc, ca
      tri(base, e[0], md[0], md[2]);
      tri(base, md[0], e[1], md[1]);
      tri(base, md[2], md[1], e[2]);
      tri(base, md[0], md[1], md[2]);
    }
  }
  for (std::size_t qi = 0; qi < m.quads.size(); ++qi) {
    const auto& e = m.quads[qi];
    double q = o.color == RenderOptions::Color::ByQuality
                   ? io::quadQuality(m.nodes[e[0]], m.nodes[e[1]], m.nodes[e[2]], m.nodes[e[3]])
                   : 0.0;
    Rgb base = baseColor(m.quadFace[qi], q);
    auto quad = [&](const PV& a, const PV& b, const PV& c, const PV& dd, const Vec3& na,
                    const Vec3& nb, const Vec3& nc, const Vec3& nd) {
      // Shade with the quad's mean normal; split along the shorter screen diagonal.
      Vec3 n = cross(nc - na, nd - nb);
      double l = norm(n);
      double k = 0.3 + 0.7 * (l > 0 ? std::fabs(dot(n, d)) / l : 0.0);
      uint8_t col[3];
      const float comp[3] = {base.r, base.g, base.b};
      for (int i = 0; i < 3; ++i)
        col[i] = static_cast<uint8_t>(std::lround(std::clamp(comp[i] * k, 0.0, 1.0) * 255.0));
      double d1 = (c.x - a.x) * (c.x - a.x) + (c.y - a.y) * (c.y - a.y);
      double d2 = (dd.x - b.x) * (dd.x - b.x) + (dd.y - b.y) * (dd.y - b.y);
      if (d1 <= d2) {
        r.triangle(a, b, c, col);
        r.triangle(a, c, dd, col);
      } else {
        r.triangle(a, b, dd, col);
        r.triangle(b, c, dd, col);
      }
    };
    const Vec3 *P = m.nodes.data();
    if (!o2) {
      quad(pv[e[0]], pv[e[1]], pv[e[2]], pv[e[3]], P[e[0]], P[e[1]], P[e[2]], P[e[3]]);
    } else {
      const auto& md = m.quadMid[qi];  // ab, bc, cd, da
      // Centre of the serendipity quad8 at (0,0): -1/4 sum(corners) + 1/2 sum(mids).
      Vec3 c3 = -0.25 * (P[e[0]] + P[e[1]] + P[e[2]] + P[e[3]]) +
                0.5 * (P[md[0]] + P[md[1]] + P[md[2]] + P[md[3]]);
      PV cp{0.5 * W + (dot(c3, right) - cx) * scale, 0.5 * H - (dot(c3, up) - cy) * scale,
            dot(c3, d) - zc};
      quad(pv[e[0]], pv[md[0]], cp, pv[md[3]], P[e[0]], P[md[0]], c3, P[md[3]]);
      quad(pv[md[0]], pv[e[1]], pv[md[1]], cp, P[md[0]], P[e[1]], P[md[1]], c3);
      quad(cp, pv[md[1]], pv[e[2]], pv[md[2]], c3, P[md[1]], P[e[2]], P[md[2]]);
      quad(pv[md[3]], cp, pv[md[2]], pv[e[3]], P[md[3]], c3, P[md[2]], P[e[3]]);
    }
  }

  if (o.edges) {
    const uint8_t ink[3] = {30, 30, 34};
    auto edge = [&](int a, int b, int mid) {
      if (mid < 0) {
        r.line(pv[a], pv[b], ink);
      } else {
        r.line(pv[a], pv[mid], ink);
        r.line(pv[mid], pv[b], ink);
      }
    };
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const auto& e = m.triangles[t];
      for (int k = 0; k < 3; ++k) edge(e[k], e[(k + 1) % 3], o2 ? m.triangleMid[t][k] : -1);
    }
    for (std::size_t q = 0; q < m.quads.size(); ++q) {
      const auto& e = m.quads[q];
      for (int k = 0; k < 4; ++k) edge(e[k], e[(k + 1) % 4], o2 ? m.quadMid[q][k] : -1);
    }
  }
  return r.take();
}

void writePng(const std::string& path, const RgbImage& img) {
  if (img.width < 1 || img.height < 1 ||
      img.rgb.size() != static_cast<std::size_t>(img.width) * img.height * 3)
    throw Error("cannot write '" + path + "': invalid picture size");
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(img.width);
  image.height = static_cast<png_uint_32>(img.height);
  image.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  // First call measures, the second encodes (libpng reports errors in image.message).
  if (!png_image_write_to_memory(&image, nullptr, &size, 0, img.rgb.data(), 0, nullptr) ||
      size == 0) {
    std::string why = image.message[0] ? image.message : "unknown libpng error";
    png_image_free(&image);
    throw Error("cannot write '" + path + "': PNG encoding failed (" + why + ")");
  }
  std::vector<unsigned char> buf(size);
  if (!png_image_write_to_memory(&image, buf.data(), &size, 0, img.rgb.data(), 0, nullptr)) {
    std::string why = image.message[0] ? image.message : "unknown libpng error";
    png_image_free(&image);
    throw Error("cannot write '" + path + "': PNG encoding failed (" + why + ")");
  }
  png_image_free(&image);
  io::AtomicFile f(path);
  f.write(buf.data(), size);
  f.commit();
}

void renderPng(const std::string& path, const SurfaceMesh& m, const RenderOptions& o) {
  RgbImage img;
  try {
    img = renderImage(m, o);
  } catch (const Error& e) {
    throw Error("cannot write '" + path + "': " + e.what());
  }
  writePng(path, img);
}

}  // namespace paramesh
