// SPDX-License-Identifier: LGPL-2.1-or-later
// The default schedule of the local operators (the face mesher sequences its own repairs): size
// conformity by splits and collapses first, then swaps and smoothing alternately until neither acts.

#include "paramesh/algo/optimizer/Optimizer.hpp"

#include <vector>

namespace paramesh {

void Optimizer::run(int passes) {
  if (passes <= 0) return;
  // edges beyond 1.6 h split; below 0.55 h collapsed unless an edge beyond 1.3 h appears
  splitPass(1.6);
  collapsePass(0.55, 1.3);
  // the first smoothing pass tries every vertex, the next ones those touched since
  touched_.assign(T_.verts.size(), 1);
  std::vector<char> active;
  for (int p = 0; p < passes; ++p) {
    int f = swapPass();
    active.swap(touched_);
    touched_.assign(T_.verts.size(), 0);
    int m = smoothPassOver(&active);
    if (f == 0 && m == 0) break;
  }
  touched_.clear();
  // a last swap pass for the final positions, then the boundary-layer front's flat triangles
  swapPass();
  repairFrontApexes(0.8);
}

}  // namespace paramesh
