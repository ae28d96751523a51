// SPDX-License-Identifier: LGPL-2.1-or-later
// Row heights of a boundary-layer spec: h_k = h0 r^k, their running sums (the distance of row k
// from the edge), and the number of layers a total thickness asks for.

#include "paramesh/algo/boundary_layer/BoundaryLayer.hpp"

#include <algorithm>
#include <cmath>

namespace paramesh {

double LayerLaw::height(int k) const { return h0 * std::pow(r, k); }

double LayerLaw::offset(int k) const {
  if (std::fabs(r - 1) < 1e-12) return h0 * k;
  return h0 * (std::pow(r, k) - 1) / (r - 1);
}

LayerLaw LayerLaw::from(const BoundaryLayerSpec& s) {
  LayerLaw l;
  l.h0 = s.firstHeight;
  l.r = s.growth;
  l.maxAspect = s.maxAspect;
  l.quads = s.quads;
  if (s.layers > 0) {
    l.layers = s.layers;
  } else {
    // smallest N whose thickness reaches T
    const double T = s.thickness;
    l.layers = std::fabs(s.growth - 1) < 1e-12
                   ? (int)std::ceil(T / s.firstHeight - 1e-9)
                   : (int)std::ceil(std::log(1 + T * (s.growth - 1) / s.firstHeight) / std::log(s.growth) - 1e-9);
    l.layers = std::clamp(l.layers, 1, 1000);
  }
  return l;
}

}  // namespace paramesh
