// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/size/SizeField.hpp"

#include <algorithm>
#include <numeric>

#include "paramesh/util/Error.hpp"

namespace paramesh {

void SizeField::addSource(Vec3 p, double h, double slope) {
  if (!(h < hmax_)) return;
  pts_.push_back(p);
  hs_.push_back(h);
  ss_.push_back(slope > 0 ? slope : slope_);
  built_ = false;
}

int SizeField::buildNode(int begin, int end, int depth) {
  Node nd;
  nd.begin = begin;
  nd.end = end;
  nd.lo = {1e300, 1e300, 1e300};
  nd.hi = {-1e300, -1e300, -1e300};
  nd.hmin = 1e300;
  nd.smin = 1e300;
  for (int i = begin; i < end; ++i) {
    nd.smin = std::min(nd.smin, ss_[i]);
    for (int k = 0; k < 3; ++k) {
      nd.lo[k] = std::min(nd.lo[k], pts_[i][k]);
      nd.hi[k] = std::max(nd.hi[k], pts_[i][k]);
    }
    nd.hmin = std::min(nd.hmin, hs_[i]);
  }
  int id = (int)nodes_.size();
  nodes_.push_back(nd);
  if (end - begin > 8 && depth < 60) {
    int axis = 0;
    Vec3 ext = nd.hi - nd.lo;
    if (ext.y > ext[axis]) axis = 1;
    if (ext.z > ext[axis]) axis = 2;
    int mid = (begin + end) / 2;
    // sort an index permutation, then apply to pts_/hs_
    std::vector<int> idx(end - begin);
    std::iota(idx.begin(), idx.end(), begin);
    std::nth_element(idx.begin(), idx.begin() + (mid - begin), idx.end(),
                     [&](int a, int b) { return pts_[a][axis] < pts_[b][axis]; });
    std::vector<Vec3> p(end - begin);
    std::vector<double> h(end - begin), sl(end - begin);
    for (int i = 0; i < end - begin; ++i) {
      p[i] = pts_[idx[i]];
      h[i] = hs_[idx[i]];
      sl[i] = ss_[idx[i]];
    }
    std::copy(p.begin(), p.end(), pts_.begin() + begin);
    std::copy(h.begin(), h.end(), hs_.begin() + begin);
    std::copy(sl.begin(), sl.end(), ss_.begin() + begin);
    int l = buildNode(begin, mid, depth + 1);
    int r = buildNode(mid, end, depth + 1);
    nodes_[id].left = l;
    nodes_[id].right = r;
  }
  return id;
}

void SizeField::build() {
  nodes_.clear();
  if (pts_.empty()) {
    built_ = true;
    return;
  }
  // Sort by size so that small (dominating) sources come first, build, then drop dominated ones.
  std::vector<int> order(pts_.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return hs_[a] < hs_[b]; });
  std::vector<Vec3> p;
  std::vector<double> h, sl;
  p.reserve(order.size());
  h.reserve(order.size());
  for (int i : order) {
    p.push_back(pts_[i]);
    h.push_back(hs_[i]);
    sl.push_back(ss_[i]);
  }
  pts_.swap(p);
  hs_.swap(h);
  ss_.swap(sl);
  buildNode(0, (int)pts_.size(), 0);
  built_ = true;
  // A source dominated at its own position by another one whose slope is not steeper is
  // dominated everywhere (triangle inequality).
  std::vector<Vec3> keepP;
  std::vector<double> keepH, keepS;
  for (size_t i = 0; i < pts_.size(); ++i) {
    double best = hs_[i] * (1 - 1e-12);  // look only for a strictly smaller value (early exit)
    const double start = best;
    queryDominating(0, pts_[i], ss_[i], best);
    if (best >= start) {  // nothing strictly smaller here: keep
      keepP.push_back(pts_[i]);
      keepH.push_back(hs_[i]);
      keepS.push_back(ss_[i]);
    }
  }
  // Equal duplicates: query returns their own value, both kept; acceptable.
  pts_.swap(keepP);
  hs_.swap(keepH);
  ss_.swap(keepS);
  nodes_.clear();
  if (!pts_.empty()) buildNode(0, (int)pts_.size(), 0);
}

void SizeField::query(int id, Vec3 x, double& best) const {
  const Node& nd = nodes_[id];
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    double d = 0;
    if (x[k] < nd.lo[k]) d = nd.lo[k] - x[k];
    else if (x[k] > nd.hi[k]) d = x[k] - nd.hi[k];
    d2 += d * d;
  }
  if (nd.hmin + nd.smin * std::sqrt(d2) >= best) return;
  if (nd.left < 0) {
    for (int i = nd.begin; i < nd.end; ++i) {
      double v = hs_[i] + ss_[i] * dist(x, pts_[i]);
      if (v < best) best = v;
    }
    return;
  }
  // visit the nearer child first
  const Node &L = nodes_[nd.left], &R = nodes_[nd.right];
  auto lb = [&](const Node& n) {
    double dd = 0;
    for (int k = 0; k < 3; ++k) {
      double d = 0;
      if (x[k] < n.lo[k]) d = n.lo[k] - x[k];
      else if (x[k] > n.hi[k]) d = x[k] - n.hi[k];
      dd += d * d;
    }
    return n.hmin + n.smin * std::sqrt(dd);
  };
  if (lb(L) <= lb(R)) {
    query(nd.left, x, best);
    query(nd.right, x, best);
  } else {
    query(nd.right, x, best);
    query(nd.left, x, best);
  }
}

void SizeField::queryDominating(int id, Vec3 x, double maxSlope, double& best) const {
  // like query(), restricted to sources whose slope is <= maxSlope
  const Node& nd = nodes_[id];
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    double d = 0;
    if (x[k] < nd.lo[k]) d = nd.lo[k] - x[k];
    else if (x[k] > nd.hi[k]) d = x[k] - nd.hi[k];
    d2 += d * d;
  }
  if (nd.smin > maxSlope || nd.hmin + nd.smin * std::sqrt(d2) >= best) return;
  if (nd.left < 0) {
    for (int i = nd.begin; i < nd.end; ++i) {
      if (ss_[i] > maxSlope) continue;
      double v = hs_[i] + ss_[i] * dist(x, pts_[i]);
      if (v < best) best = v;
    }
    return;
  }
  // any strictly smaller value decides: stop at the first one found
  const double before = best;
  queryDominating(nd.left, x, maxSlope, best);
  if (best < before) return;
  queryDominating(nd.right, x, maxSlope, best);
}

double SizeField::ownSize(Vec3 x) const {
  PM_CHECK(built_, "SizeField::size() before build()");
  double best = hmax_;
  if (!nodes_.empty()) query(0, x, best);
  return best;
}

double SizeField::size(Vec3 x) const {
  const double own = ownSize(x);
  return under_ ? std::min(own, under_->size(x)) : own;
}

}  // namespace paramesh
