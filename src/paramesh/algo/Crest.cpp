// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/algo/Crest.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "paramesh/algo/Predicates.hpp"
#include "paramesh/algo/SurfaceContext.hpp"
#include "paramesh/algo/Triangulation.hpp"
#include "paramesh/size/Sources.hpp"

namespace paramesh {
namespace {

/// Local frame of the surface at a scaled (u,v): the tangents per scaled unit, the normal, and the
/// (scaled (u,v)) principal direction of the smaller curvature, along which a crest runs.
struct Frame {
  Vec3 x, ju, jv, n;
  Vec2 along{0, 0};
  double k = 0;  ///< the largest principal curvature, in magnitude
  bool ok = false;
};

Frame frameAt(const SurfaceContext& C, Vec2 s) {
  Frame f;
  SurfaceD2 d;
  C.surf.d2(C.toParam(s), d);
  f.x = d.p;
  f.ju = (1.0 / C.su) * d.du;
  f.jv = (1.0 / C.sv) * d.dv;
  const Vec3 c = cross(f.ju, f.jv);
  const double lc = norm(c);
  const double E = dot(f.ju, f.ju), F = dot(f.ju, f.jv), G = dot(f.jv, f.jv);
  const double W = E * G - F * F;
  if (!(lc > 1e-12 * std::sqrt(E * G)) || !(W > 0)) return f;
  f.n = (1.0 / lc) * c;
  const double L = dot(d.duu, f.n) / (C.su * C.su), M = dot(d.duv, f.n) / (C.su * C.sv),
               N = dot(d.dvv, f.n) / (C.sv * C.sv);
  const double K = (L * N - M * M) / W, H = (E * N - 2 * F * M + G * L) / (2 * W);
  const double root = std::sqrt(std::max(H * H - K, 0.0));
  const double k1 = H + root, k2 = H - root;
  // the curvature of the largest magnitude, and the direction of the other (II - k I) x = 0
  const double kBig = std::fabs(k1) >= std::fabs(k2) ? k1 : k2, kSmall = kBig == k1 ? k2 : k1;
  const Vec2 r1{M - kSmall * F, -(L - kSmall * E)}, r2{N - kSmall * G, -(M - kSmall * F)};
  f.along = dot(r1, r1) >= dot(r2, r2) ? r1 : r2;
  f.k = std::fabs(kBig);
  f.ok = std::isfinite(kBig) && dot(f.along, f.along) > 0;
  return f;
}

/// The scaled (u,v) direction whose tangent image is the 3D vector w (least squares).
Vec2 toUV(const Frame& f, Vec3 w) {
  const double E = dot(f.ju, f.ju), F = dot(f.ju, f.jv), G = dot(f.jv, f.jv);
  const double a = dot(f.ju, w), b = dot(f.jv, w), det = E * G - F * F;
  if (!(det > 0)) return {0, 0};
  return {(G * a - F * b) / det, (E * b - F * a) / det};
}

Vec3 image(const Frame& f, Vec2 d) { return d.x * f.ju + d.y * f.jv; }

/// The face's boundary in T: its constrained edges that are not on a crest (3D segments).
std::vector<std::pair<Vec3, Vec3>> boundarySegments(const Triangulation& T) {
  std::vector<std::pair<Vec3, Vec3>> out;
  for (int t = 0; t < (int)T.tris.size(); ++t) {
    const Triangle& tr = T.tris[t];
    if (tr.dead) continue;
    for (int i = 0; i < 3; ++i) {
      const TriVertex &a = T.verts[tr.v[(i + 1) % 3]], &b = T.verts[tr.v[(i + 2) % 3]];
      if (T.isConstrained(t, i) && !((a.flags | b.flags) & VF_CREST)) out.push_back({a.xyz, b.xyz});
    }
  }
  return out;
}

/// True when a segment of segs passes within r of x.
bool nearAny(const std::vector<std::pair<Vec3, Vec3>>& segs, Vec3 x, double r) {
  for (const auto& s : segs)
    if (segmentDistance(x, s.first, s.second) < r) return true;
  return false;
}

class Tracer {
 public:
  Tracer(const Triangulation& T, const SurfaceContext& C, const CrestOptions& o)
      : T_(T), C_(C), o_(o), bnd_(boundarySegments(T)) {}

  /// Crest point on the scaled (u,v) segment [a, b]: the largest curvature (samples, then golden
  /// section). False when it is not a crease at the mesh's scale.
  bool crestOn(Vec2 a, Vec2 b, Vec2& at, double& k) const {
    auto kAt = [&](double f) { return maxCurvature(C_.surf, C_.toParam(a + f * (b - a))); };
    constexpr int n = 16;
    double best = -1, f0 = 0.5;
    for (int i = 0; i <= n; ++i) {
      const double v = kAt(double(i) / n);
      if (v > best) {
        best = v;
        f0 = double(i) / n;
      }
    }
    constexpr double g = 0.618033988749895;
    double lo = std::max(0.0, f0 - 1.0 / n), hi = std::min(1.0, f0 + 1.0 / n);
    double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo), d1 = kAt(m1), d2 = kAt(m2);
    for (int it = 0; it < 30; ++it) {
      if (d1 > d2) {
        hi = m2, m2 = m1, d2 = d1, m1 = hi - g * (hi - lo), d1 = kAt(m1);
      } else {
        lo = m1, m1 = m2, d1 = d2, m2 = lo + g * (hi - lo), d2 = kAt(m2);
      }
    }
    double f = 0.5 * (lo + hi);
    k = kAt(f);
    if (best > k) {  // the sample itself (the refinement's bracket held no higher point)
      f = f0;
      k = best;
    }
    // the largest at an end of the segment: no ridge inside it
    if (f0 == 0.0 || f0 == 1.0) {
      at = a + f0 * (b - a);
      return false;
    }
    at = a + f * (b - a);
    return crease(at, k);
  }

  bool crease(Vec2 s, double k) const {
    if (!C_.inDomain(s)) return false;
    const Vec3 x = C_.surf.eval(C_.toParam(s));
    const double h = C_.size(x);
    return k * h > o_.creaseScale && clear(x, o_.clearance * h);
  }

  /// No boundary segment, no crest point of another line, and no point of the line being traced
  /// that lies farther than `near` from arc position `arc` along it, within r of x.
  bool clear(Vec3 x, double r, double arc = 0, double near = -1) const {
    if (nearAny(bnd_, x, r)) return false;
    for (const auto& P : pts_)
      for (const Vec3& p : P)
        if (dist(x, p) < r) return false;
    if (near >= 0)
      for (const auto& [p, a] : cur_)
        if (std::fabs(a - arc) > near && dist(x, p) < r) return false;
    return true;
  }

  /// Follows the crest from s (a crest point) in direction sign; appends the points (3D, uv).
  void follow(Vec2 s, double sign, std::vector<Vec2>& uv, std::vector<Vec3>& xyz) {
    double arc = 0;
    Frame f = frameAt(C_, s);
    if (!f.ok) return;
    Vec3 t3 = normalized(image(f, f.along));
    if (sign < 0) t3 = -1.0 * t3;
    for (int step = 0; total_ < o_.maxPoints; ++step, ++total_) {
      const double h = C_.size(f.x), len = 0.25 * h;
      // predict along the crest, then back onto its ridge across it
      Vec2 q = s + len * normalizedUV(f, t3);
      if (!C_.inDomain(q)) return;
      const Frame fq = frameAt(C_, q);
      if (!(norm2(fq.n) > 0)) return;
      const Vec3 c3 = normalized(cross(fq.n, t3));
      const Vec2 cu = normalizedUV(fq, c3);
      Vec2 at;
      double k;
      const bool ok = crestOn(q - 0.5 * len * cu, q + 0.5 * len * cu, at, k);
      if (!ok) return;
      const Frame fn = frameAt(C_, at);
      if (!fn.ok) return;
      const Vec3 d = fn.x - f.x;
      // the step must have gone forward, by about its length
      if (!(dot(d, t3) > 0.5 * len) || norm(d) > 2.0 * len) return;
      arc += sign * norm(d);
      if (!clear(fn.x, o_.clearance * h, arc, 3.0 * o_.clearance * h)) return;
      cur_.push_back({fn.x, arc});
      t3 = normalized(d);
      s = at;
      f = fn;
      uv.push_back(s);
      xyz.push_back(f.x);
    }
  }

  /// The scaled (u,v) step of 3D length 1 along the tangent direction w.
  static Vec2 normalizedUV(const Frame& f, Vec3 w) {
    const Vec2 d = toUV(f, w);
    const double l = norm(image(f, d));
    return l > 0 ? (1.0 / l) * d : Vec2{0, 0};
  }

  std::vector<std::vector<Vec2>> run() {
    // seeds: crest points on the edges whose ends face far apart
    struct Seed {
      double k;
      Vec2 s;
    };
    std::vector<Seed> seeds;
    for (int t = 0; t < (int)T_.tris.size(); ++t) {
      const Triangle& tr = T_.tris[t];
      if (tr.dead) continue;
      for (int i = 0; i < 3; ++i) {
        const int a = tr.v[(i + 1) % 3], b = tr.v[(i + 2) % 3];
        if (a > b && tr.n[i] >= 0) continue;  // each interior edge once
        const TriVertex &A = T_.verts[a], &B = T_.verts[b];
        if (!(norm2(A.normal) > 0 && norm2(B.normal) > 0) || dot(A.normal, B.normal) >= o_.seedCos) continue;
        Vec2 at;
        double k;
        if (crestOn(A.uv, B.uv, at, k)) seeds.push_back({k, at});
      }
    }
    std::sort(seeds.begin(), seeds.end(), [](const Seed& x, const Seed& y) {
      return x.k > y.k || (x.k == y.k && (x.s.x < y.s.x || (x.s.x == y.s.x && x.s.y < y.s.y)));
    });
    std::vector<std::vector<Vec2>> out;
    for (const Seed& sd : seeds) {
      if (total_ >= o_.maxPoints) break;
      const Vec3 x = C_.surf.eval(C_.toParam(sd.s));
      const double h = C_.size(x);
      if (!clear(x, o_.clearance * h)) continue;  // on a line traced already
      cur_.assign(1, {x, 0.0});
      std::vector<Vec2> fwdUV{sd.s}, bwdUV;
      std::vector<Vec3> fwdX{x}, bwdX;
      follow(sd.s, 1, fwdUV, fwdX);
      follow(sd.s, -1, bwdUV, bwdX);
      pts_.emplace_back();
      for (const auto& c : cur_) pts_.back().push_back(c.first);
      std::vector<Vec2> uv(bwdUV.rbegin(), bwdUV.rend());
      std::vector<Vec3> xyz(bwdX.rbegin(), bwdX.rend());
      uv.insert(uv.end(), fwdUV.begin(), fwdUV.end());
      xyz.insert(xyz.end(), fwdX.begin(), fwdX.end());
      // resample by arc length to about the size
      std::vector<double> arc(xyz.size(), 0.0);
      for (size_t i = 1; i < xyz.size(); ++i) arc[i] = arc[i - 1] + dist(xyz[i - 1], xyz[i]);
      const double total = arc.back();
      double hMean = 0;
      for (const Vec3& p : xyz) hMean += C_.size(p);
      hMean /= (double)xyz.size();
      const int n = (int)std::lround(total / hMean);
      if (n < 1) continue;  // shorter than the size: a point the flips can line up with
      std::vector<Vec2> line;
      size_t j = 0;
      for (int i = 0; i <= n; ++i) {
        const double target = total * i / n;
        while (j + 1 < arc.size() && std::fabs(arc[j + 1] - target) <= std::fabs(arc[j] - target)) ++j;
        if (line.empty() || !(line.back().x == uv[j].x && line.back().y == uv[j].y)) line.push_back(uv[j]);
      }
      if (line.size() >= 2) out.push_back(std::move(line));
    }
    return out;
  }

 private:
  const Triangulation& T_;
  const SurfaceContext& C_;
  const CrestOptions& o_;
  std::vector<std::pair<Vec3, Vec3>> bnd_;
  std::vector<std::vector<Vec3>> pts_;  ///< traced points of each line (3D)
  std::vector<std::pair<Vec3, double>> cur_;  ///< the line being traced: points and arc positions
  int total_ = 0;
};

}  // namespace

std::vector<std::vector<Vec2>> traceCrests(const Triangulation& T, const SurfaceContext& C, const CrestOptions& o) {
  if (C.planar) return {};
  Tracer tr(T, C, o);
  return tr.run();
}

namespace {

/// Inserts the polyline (scaled uv) into T as vertices with `flags` (crest vertices get no
/// normal) joined by constrained edges; ids receives the vertices inserted. Returns the segments.
/// The walk stops at constrained edges (the boundary's, the crests'): it starts from the
/// previous vertex of the line, else from every triangle.
int embedLine(Triangulation& T, const SurfaceContext& C, const std::vector<Vec2>& line, uint8_t flags,
              std::vector<int>& ids) {
  int segments = 0;
  const Triangulation::FlipTest delaunay = [&T](int t, int i) { return T.delaunayFlip(t, i); };
  int prev = -1;
  for (const Vec2& s : line) {
    int e = -1;
    int t = prev >= 0 ? T.locate(s, T.verts[prev].tri, &e) : -1;
    for (int k = 0; t < 0 && k < (int)T.tris.size(); ++k) {
      const Triangle& tr = T.tris[k];
      if (tr.dead) continue;
      int zero = -1, neg = 0;
      for (int i = 0; i < 3; ++i) {
        const int o = orient2d(T.verts[tr.v[(i + 1) % 3]].uv, T.verts[tr.v[(i + 2) % 3]].uv, s);
        if (o < 0) neg = 1;
        if (o == 0) zero = i;
      }
      if (!neg) {
        t = k;
        e = zero;
      }
    }
    if (t < 0 || (e >= 0 && T.isConstrained(t, e)) || !T.insertionIsValid(s, t, e)) break;
    TriVertex v = C.makeVertex(s);
    if (flags & VF_CREST) v.normal = Vec3{0, 0, 0};
    v.flags |= flags;
    const int id = T.addVertex(v);
    T.insert(id, t, e, delaunay, nullptr);
    if (prev >= 0) {
      std::string why;
      if (!T.insertSegment(prev, id, why)) break;
      ++segments;
    }
    ids.push_back(id);
    prev = id;
  }
  return segments;
}

}  // namespace

int embedCrests(Triangulation& T, const SurfaceContext& C, const std::vector<std::vector<Vec2>>& crests,
                std::vector<std::vector<int>>* embedded) {
  int segments = 0;
  for (const std::vector<Vec2>& line : crests) {
    std::vector<int> ids;
    segments += embedLine(T, C, line, VF_CREST, ids);
    if (embedded && ids.size() >= 2) embedded->push_back(std::move(ids));
  }
  return segments;
}

namespace {

// A walk across the crest from one of its vertices, on the surface: samples in steps a small
// share of the local radius, with their arc length from the crest.
struct Walk {
  std::vector<Vec2> s;
  std::vector<Vec3> x;
  std::vector<double> arc;
  double spacing = 0;
  bool active = true;
};
// the point at arc length a (interpolated in (u,v) between samples; the caller evaluates it)
bool pointAt(const Walk& w, double a, Vec2& s, Vec3& x) {
  if (w.arc.empty() || a > w.arc.back()) return false;
  const size_t i = std::upper_bound(w.arc.begin(), w.arc.end(), a) - w.arc.begin();
  if (i == 0) {
    s = w.s[0], x = w.x[0];
    return true;
  }
  if (i >= w.arc.size()) {
    s = w.s.back(), x = w.x.back();
    return true;
  }
  const double f = (a - w.arc[i - 1]) / std::max(w.arc[i] - w.arc[i - 1], 1e-300);
  s = w.s[i - 1] + f * (w.s[i] - w.s[i - 1]);
  x = w.x[i - 1] + f * (w.x[i] - w.x[i - 1]);
  return true;
}
// how far the samples strictly between arc a0 (the point x0) and sample i sag from the chord
double sagTo(const Walk& w, double a0, Vec3 x0, size_t i) {
  double m = 0;
  for (size_t k = 0; k < i; ++k)
    if (w.arc[k] > a0) m = std::max(m, segmentDistance(w.x[k], x0, w.x[i]));
  return m;
}

/// The walks across the crest line from each of its vertices, on one side.
std::vector<Walk> walkAcross(const Triangulation& T, const SurfaceContext& C, const std::vector<int>& line, int side) {
  const int n = (int)line.size();
  std::vector<Walk> walks(n);
  for (int j = 0; j < n; ++j) {
    Walk& w = walks[j];
    const TriVertex& V = T.verts[line[j]];
    const Vec3 tangent = normalized(T.verts[line[std::min(j + 1, n - 1)]].xyz - T.verts[line[std::max(j - 1, 0)]].xyz);
    int m = 0;
    if (j > 0) w.spacing += dist(V.xyz, T.verts[line[j - 1]].xyz), ++m;
    if (j + 1 < n) w.spacing += dist(V.xyz, T.verts[line[j + 1]].xyz), ++m;
    w.spacing /= std::max(m, 1);
    Vec2 s = V.uv;
    Frame f = frameAt(C, s);
    if (!f.ok) continue;
    w.s.push_back(s), w.x.push_back(f.x), w.arc.push_back(0);
    for (int step = 0; step < 2100 && w.arc.back() <= 2 * w.spacing; ++step) {
      Vec3 across = normalized(cross(f.n, tangent));
      if (side) across = -1.0 * across;
      const double len = std::clamp(0.05 / std::max(f.k, 1e-300), w.spacing / 1000, w.spacing / 32);
      const Vec2 q = s + len * Tracer::normalizedUV(f, across);
      if (!C.inDomain(q)) break;
      const Frame fq = frameAt(C, q);
      if (!fq.ok) break;
      w.s.push_back(q), w.x.push_back(fq.x), w.arc.push_back(w.arc.back() + dist(fq.x, f.x));
      s = q;
      f = fq;
    }
  }
  return walks;
}

std::vector<std::vector<std::pair<bool, Vec2>>> rowRanks(std::vector<Walk>& walks, const CrestOptions& o,
                                                         const std::vector<std::pair<Vec3, Vec3>>& bnd) {
  const int n = (int)walks.size();
  // One sequence of row distances (arc lengths across) for the whole line, so that the rows
  // run parallel to the crest as a boundary layer's do, each cell between two rows a quad of
  // one width. From each distance, a station still needs rows unless a chord of the spacing
  // from there sags less than the isotropic mesh's triangles may; the next distance is the
  // nearest any such station's flank allows (its chord sagging no more than a row may),
  // grown by at most CrestOptions::rowGrowth over the last row's width.
  std::vector<std::vector<std::pair<bool, Vec2>>> ranks;
  double d = 0, width = 0;
  for (int rank = 0; rank < o.maxRows; ++rank) {
    double next = std::numeric_limits<double>::infinity();
    for (Walk& w : walks) {
      if (!w.active || w.arc.empty()) {
        w.active = false;
        continue;
      }
      // the first sample a spacing away from the point at d
      Vec2 s0;
      Vec3 x0;
      if (!pointAt(w, d, s0, x0)) {
        w.active = false;
        continue;
      }
      size_t end = 0;
      while (end < w.arc.size() && (w.arc[end] <= d || dist(w.x[end], x0) < w.spacing)) ++end;
      if (end >= w.arc.size() || sagTo(w, d, x0, end) <= o.rowStopSag * w.spacing) {
        w.active = false;  // resolved from here (or the walk ended: the boundary is near)
        continue;
      }
      // the farthest sample before `end` whose chord sags no more than a row may (the sag
      // grows with the chord: bisection; at `end` it exceeds the stop's, a row's bound)
      size_t lo = 0;
      while (lo + 1 < end && w.arc[lo + 1] <= d) ++lo;
      if (w.arc[lo] <= d) ++lo;  // the first sample past d: nothing between them sags
      size_t hi = end;
      while (hi - lo > 1) {
        const size_t mid = (lo + hi) / 2;
        (sagTo(w, d, x0, mid) <= o.rowSag * w.spacing ? lo : hi) = mid;
      }
      next = std::min(next, w.arc[lo]);
    }
    if (!std::isfinite(next)) break;
    if (width > 0) next = std::min(next, d + o.rowGrowth * width);
    width = next - d;
    d = next;

    ranks.emplace_back(n, std::pair<bool, Vec2>{false, Vec2{0, 0}});
    for (int j = 0; j < n; ++j) {
      Walk& w = walks[j];
      Vec2 s;
      Vec3 x;
      if (!w.active || !pointAt(w, d, s, x) || nearAny(bnd, x, 0.25 * w.spacing)) {
        w.active = false;
        continue;
      }
      ranks.back()[j] = {true, s};
    }
  }
  return ranks;
}

/// Between two rows nothing else will be inserted, so their diagonals are final: flipped to
/// Delaunay in the surface's metric (see embedCrestRows).
void flipRowDiagonals(Triangulation& T) {
  auto fixed = [&T](int v) { return (T.verts[v].flags & (VF_ROW | VF_CREST)) != 0; };
  for (int pass = 0; pass < 100; ++pass) {
    int flips = 0;
    for (int t = 0; t < (int)T.tris.size(); ++t) {
      for (int i = 0; i < 3; ++i) {
        const Triangle& tr = T.tris[t];
        if (tr.dead || tr.n[i] < 0 || T.isConstrained(t, i)) continue;
        if (!fixed(tr.v[(i + 1) % 3]) || !fixed(tr.v[(i + 2) % 3])) continue;
        if (T.metricFlip(t, i) && T.flip(t, i)) ++flips;
      }
    }
    if (flips == 0) break;
  }
}

}  // namespace

int embedCrestRows(Triangulation& T, const SurfaceContext& C, const std::vector<std::vector<int>>& crests,
                   const CrestOptions& o) {
  // the face's boundary, which no row point may come near
  const std::vector<std::pair<Vec3, Vec3>> bnd = boundarySegments(T);
  std::vector<std::vector<Vec2>> rows;
  for (const std::vector<int>& line : crests) {
    const int n = (int)line.size();
    for (int side = 0; side < 2; ++side) {
      std::vector<Walk> walks = walkAcross(T, C, line, side);
      const std::vector<std::vector<std::pair<bool, Vec2>>> ranks = rowRanks(walks, o, bnd);
      // the row points of one rank at consecutive crest vertices form a polyline
      for (const auto& rank : ranks) {
        std::vector<Vec2> cur;
        for (int j = 0; j <= n; ++j) {
          if (j < n && rank[j].first) {
            cur.push_back(rank[j].second);
            continue;
          }
          if (cur.size() >= 2) rows.push_back(cur);
          cur.clear();
        }
      }
    }
  }
  int segments = 0;
  for (const std::vector<Vec2>& r : rows) {
    std::vector<int> ids;
    segments += embedLine(T, C, r, VF_ROW, ids);
  }
  // Between two rows nothing else will be inserted, so their diagonals are final here. Inserted
  // Delaunay in (u,v), they join points many crest spacings apart where the parametrisation
  // shears (on the blade tips a row lies 0.9 (u,v) units from the next one at 55 degrees to
  // the crest, whose spacing is 0.027: the (u,v)-nearest point across is 18 spacings along, and
  // the strip became fans of caps). Flipped to Delaunay in the surface's metric, they join the
  // points across from each other.
  if (segments > 0) flipRowDiagonals(T);
  return segments;
}

}  // namespace paramesh
