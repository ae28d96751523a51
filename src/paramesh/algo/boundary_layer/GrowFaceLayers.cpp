// SPDX-License-Identifier: LGPL-2.1-or-later
// The 2D part's driver: growFaceLayers, and FaceLayers' walk over a face's loops: the runs of BL
// segments, the side of the face each run grows into, and each run's columns from root to front.

#include "paramesh/algo/boundary_layer/FaceLayers.hpp"

#include <algorithm>
#include <vector>

namespace paramesh {

FaceBLResult growFaceLayers(const ISurface& s, bool, const std::vector<std::vector<LoopPoint>>& loops,
                            const std::vector<std::vector<Vec2>>& trueLoops, const DomainGuard& guard,
                            const EdgeSpecMap& specOf, const std::vector<LayerLaw>& laws,
                            const std::vector<EdgeBLPoints>&) {
  FaceBLResult out;
  bl_detail::FaceLayers fl(s, loops, trueLoops, guard, specOf, laws, out);
  fl.run();
  fl.buildLoops();
  return out;
}

namespace bl_detail {

FaceLayers::FaceLayers(const ISurface& s, const std::vector<std::vector<LoopPoint>>& loops,
                       const std::vector<std::vector<Vec2>>& trueLoops, const DomainGuard& guard,
                       const EdgeSpecMap& specOf, const std::vector<LayerLaw>& laws, FaceBLResult& out)
    : S_(s), loops_(loops), trueLoops_(trueLoops), guard_(guard), specOf_(specOf), laws_(laws), out_(out) {
  for (const LayerLaw& l : laws) specQuads_.push_back(l.quads);
  out_.stats.assign(laws.size(), FaceBLResult::SpecStats());
  // buckets about as large as the boundary's segments (the columns' spacing)
  double total = 0;
  int count = 0;
  for (const auto& lp : loops_)
    for (size_t i = 0; i < lp.size(); ++i) {
      total += dist(lp[i].xyz, lp[(i + 1) % lp.size()].xyz);
      ++count;
    }
  const double cell = count ? total / count : 1.0;
  loopBuckets_ = SegmentBuckets(cell);
  otherBuckets_ = SegmentBuckets(cell);
  for (size_t L = 0; L < loops_.size(); ++L)
    for (size_t i = 0; i < loops_[L].size(); ++i) {
      loopSegs_.emplace_back((int)L, (int)i);
      loopBuckets_.add((int)loopSegs_.size() - 1, loops_[L][i].xyz, loops_[L][(i + 1) % loops_[L].size()].xyz);
    }
}

void FaceLayers::run() {
  for (size_t L = 0; L < loops_.size(); ++L) processLoop((int)L);
}

bool FaceLayers::isBL(const LoopPoint& p) const { return p.edge >= 0 && specOf_[p.edge] >= 0; }

void FaceLayers::processLoop(int L) {
  const auto& lp = loops_[L];
  const int n = (int)lp.size();
  // segment i = (i, i+1) is BL when its edge is a BL edge
  std::vector<char> bl(n);
  int count = 0;
  for (int i = 0; i < n; ++i) count += bl[i] = isBL(lp[i]) ? 1 : 0;
  if (!count) return;
  // runs of consecutive BL segments
  struct Run {
    int a, nseg;
  };
  std::vector<Run> runs;
  if (count == n) {
    runs.push_back({0, n});
  } else {
    int start = 0;
    while (bl[start] || !bl[(start + 1) % n]) start = (start + 1) % n;  // start: last non-BL before a run
    for (int k = 0, i = (start + 1) % n; k < n; ++k, i = (i + 1) % n) {
      if (bl[i] && !bl[(i + n - 1) % n]) {
        int len = 0;
        while (bl[(i + len) % n] && len < n) ++len;
        runs.push_back({i, len});
      }
    }
  }
  for (const Run& r : runs) growRun(L, r.a, r.nseg, r.nseg == n);
}

/// +1 when the face lies to the left of loop L's direction (in (u,v), where the surface normal
/// S_u x S_v makes left in (u,v) left in 3D) along the segment starting at point i, -1 when it
/// lies to the right, 0 when the probes disagree or the point is not on the true boundary. The
/// probes straddle the true boundary (the guard's own polyline) just after the point. A probe
/// off the segment's chord can land on either side of the boundary: a one-segment arc bulges
/// far more than any probe's offset (measured: docs/tuning/boundary_layer.md).
int FaceLayers::sideOf(int L, int i) const {
  if (L >= (int)trueLoops_.size()) return 0;
  const auto& F = trueLoops_[L];
  const int m = (int)F.size(), n = (int)loops_[L].size();
  if (m < 3) return 0;
  const Vec2 a = loops_[L][((i % n) + n) % n].uv, b = loops_[L][(((i + 1) % n) + n) % n].uv;
  int k = 0;
  double best = 1e300;
  for (int j = 0; j < m; ++j) {
    const double d = dot(F[j] - a, F[j] - a);
    if (d < best) best = d, k = j;
  }
  const double len = norm(b - a);
  if (!(len > 0) || best > 1e-12 * len * len) return 0;
  int k2 = (k + 1) % m;  // the next distinct point (a collapsed tiny edge repeats one)
  for (int guard = 0; guard < m && F[k2].x == F[k].x && F[k2].y == F[k].y; ++guard) k2 = (k2 + 1) % m;
  const Vec2 p = F[k], q = F[k2];
  const Vec2 d = q - p;
  if (!(norm(d) > 0)) return 0;
  const Vec2 c = 0.5 * (p + q), left{-1e-3 * d.y, 1e-3 * d.x};
  const bool inL = guard_.inside(c + left), inR = guard_.inside(c - left);
  return inL == inR ? 0 : (inL ? 1 : -1);
}

/// The side run (a, nseg) of loop L grows into, as the sign of n x t: +1 when the face lies to
/// the left of the loop, -1 when it lies to the right.
double FaceLayers::runSign(int L, int a, int nseg) const {
  const auto& lp = loops_[L];
  const int n = (int)lp.size();
  auto at = [&](int i) -> const LoopPoint& { return lp[((i % n) + n) % n]; };
  // loop direction sign: +1 when the face lies to the left of the loop (n x t points inside)
  const int mid = a + nseg / 2;
  int side = 0;
  for (int j = 0, step = std::max(1, nseg / 8); j < nseg; j += step) side += sideOf(L, a + j);
  if (side == 0) {
    // no verdict from the true boundary: a probe off the middle segment's chord
    const Vec3 tm = at(mid + 1).xyz - at(mid).xyz;
    const Vec2 uvm = 0.5 * (at(mid).uv + at(mid + 1).uv);
    const Vec3 bm = normalized(cross(normalAt(uvm), tm));
    side = guard_.inside(uvm + uvStep(uvm, 1e-3 * norm(tm) * bm)) ? 1 : -1;
  }
  return side > 0 ? 1.0 : -1.0;
}

void FaceLayers::growRun(int L, int a, int nseg, bool closed) {
  const auto& lp = loops_[L];
  const int n = (int)lp.size();
  auto at = [&](int i) -> const LoopPoint& { return lp[((i % n) + n) % n]; };
  const double sgn = runSign(L, a, nseg);

  // columns at the run's points (corners may get several)
  std::vector<Column> cols;
  const int npts = closed ? nseg : nseg + 1;
  for (int j = 0; j < npts; ++j) {
    const int i = a + j;
    const LoopPoint& p = at(i);
    const bool first = !closed && j == 0, last = !closed && j == npts - 1;
    const int specIn = at(i - 1).edge >= 0 ? specOf_[at(i - 1).edge] : -1;
    const int specOut = at(i).edge >= 0 ? specOf_[at(i).edge] : -1;
    const int spec = first ? specOut : (last ? specIn : (specOut >= 0 ? specOut : specIn));
    Column base;
    base.root = ((i % n) + n) % n;
    base.spec = spec;
    base.uv.push_back(p.uv);
    base.xyz.push_back(p.xyz);
    base.ref.push_back(p.node);
    if (first || last) {
      addEndColumn(L, i, first, npts, sgn, base, cols);
      continue;
    }
    addCornerColumns(L, i, sgn, base, cols);
  }
  leanTowardsEnds(cols, closed);
  trimAtApex(L, a, nseg, closed, cols);
  march(L, cols, closed);
  emit(L, a, nseg, closed, cols);
}

}  // namespace bl_detail
}  // namespace paramesh
