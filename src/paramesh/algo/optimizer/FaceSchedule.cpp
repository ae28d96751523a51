// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file FaceSchedule.cpp
/// The optimisation schedule of one face after the frontal mesh: the default passes, deviation
/// bounds, valence flips, sliver repairs (in batches, then one triangle at a time), size
/// conformity, radius-ratio polish and the curvature bound, in that order.
#include "paramesh/algo/optimizer/FaceSchedule.hpp"

#include <vector>

#include "paramesh/algo/Triangulation.hpp"

namespace paramesh {
namespace {

constexpr int kSliverRounds = 1;
constexpr bool kPerCandidate = true;
constexpr double kPerCandidateBudget = 1e6;  // candidates x face triangles
// valence flips after the first optimisation: rounds (docs/tuning/face_mesher.md), and the least
// share of the pair's worst radius ratio a flip may keep (the smoothing after it restores shapes)
constexpr int kValenceRounds = 2;
constexpr double kValenceQuality = 0.5;
// passes of the radius-ratio polish at the end (the second one revisits the neighbours of the
// vertices the first moved)
constexpr int kPolishPasses = 2;

void refineDeviationFirst(Optimizer& O, const FaceMeshOptions& opt) {
  // the nearest-face check's local bounds and the user's --max-deviation first, so that the
  // repairs below (which keep every bound) clean up after their splits; the curvature angle's
  // relative bound stays at the end (measured: docs/tuning/face_mesher.md)
  if ((!opt.deviationZones.empty() || opt.maxDeviation > 0) &&
      O.refineDeviation(opt.maxDeviation, opt.maxDeviationRatio, opt.minSplitLength, &opt.deviationZones) > 0) {
    O.smoothPass();
    O.swapPass();
  }
}

void regularizeValences(Optimizer& O, const FaceMeshOptions& opt) {
  // valences towards regular (graded zones: triangles around 5- and 7-valent vertices were most
  // of the radius-ratio deficit); the flips are settled within one edge ring of them only
  // (docs/tuning/face_mesher.md)
  if (opt.optimizePasses > 0) {
    std::vector<int> flipped;
    for (int k = 0; k < kValenceRounds; ++k) {
      flipped.clear();
      if (O.valenceSwapPass(kValenceQuality, &flipped) == 0) break;
      O.setRegion(O.regionAround(flipped, 1));  // the next round looks there too, and only there
      O.smoothPass();
      O.swapPass();
      O.smoothPass();
    }
    O.setRegion({});
  }
}

/// Returns the number of repairs kept.
int repairSliverBatches(Optimizer& O, Triangulation& T, const FaceMeshOptions& opt) {
  // Triangles with an angle below 30 degrees that the optimiser left: slivers standing on
  // boundary nodes (narrow parts of the face, next to short segments) and caps whose free apex
  // sits almost on the opposite edge. Three variants from the same start: split the longest
  // free edge of the poor triangles on three boundary nodes, or on two, or collapse the free
  // apex of the poor triangles; each is re-optimised, and the one leaving the fewest poor
  // triangles is kept only if it has fewer than before.
  int repaired = 0;
  // The trials are local: swaps, smoothing and the count of poor triangles run over two edge
  // rings around the candidates (Optimizer::setRegion), so a repair costs O(region).
  for (int round = 0; opt.sliverPass && opt.optimizePasses > 0 && round < kSliverRounds; ++round) {
    const int total = O.countPoorAngles();
    if (total == 0) break;
    std::vector<int> poorTris;
    for (int t = 0; t < (int)T.tris.size(); ++t)
      if (!T.tris[t].dead && O.poorAngle(t)) poorTris.push_back(t);
    const std::vector<char> region = O.regionAround(poorTris, 2);
    const Triangulation start = T;
    Triangulation kept;
    int best = total;
    bool improved = false;
    for (int variant : {3, 2, 0}) {
      if (variant != 3) T = start;
      O.setRegion(region);
      if ((variant > 0 ? O.splitBoundarySlivers(variant) : O.collapsePoorApexes()) == 0) continue;
      O.swapPass();
      O.smoothPass();
      O.swapPass();
      const int c = total + O.countPoorAngles() - Optimizer::countPoorAngles(start, O.region());
      if (c < best) {
        best = c;
        kept = T;
        improved = true;
      }
    }
    O.setRegion({});
    T = improved ? std::move(kept) : start;
    if (!improved) break;
    ++repaired;
  }
  return repaired;
}

/// Returns the number of repairs kept.
int repairSliversOneByOne(Optimizer& O, Triangulation& T, const FaceMeshOptions& opt) {
  int repaired = 0;
  // What the batches left, one triangle at a time (faces small enough for a copy of the face
  // per trial): split, collapse, relocate or flip, kept when the poor triangles around drop.
  if (opt.sliverPass && opt.optimizePasses > 0 && kPerCandidate) {
    std::vector<int> cands;
    for (int t = 0; t < (int)T.tris.size(); ++t)
      if (!T.tris[t].dead && O.poorAngle(t)) cands.push_back(t);
    if (!cands.empty() && (double)cands.size() * (double)T.tris.size() <= kPerCandidateBudget) {
      for (int t : cands) {
        if (T.tris[t].dead || !O.poorAngle(t)) continue;
        const std::vector<char> region = O.regionAround({t}, 2);
        for (int action = 0; action < 4; ++action) {
          Triangulation backup = T;
          O.setRegion(region);
          const bool done = action == 0 ? O.splitLongestFree(t) >= 0
                            : action == 1 ? O.collapseApex(t)
                            : action == 2 ? O.relocateForAngles(t)
                                          : O.flipForAngles(t);
          if (!done) {
            O.setRegion({});
            continue;
          }
          // after a flip, smoothing first: a swap pass would undo it
          if (action == 3) O.smoothPass();
          O.swapPass();
          O.smoothPass();
          O.swapPass();
          const bool better = O.countPoorAngles() < Optimizer::countPoorAngles(backup, O.region());
          O.setRegion({});
          if (better) {
            ++repaired;
            break;
          }
          T = std::move(backup);
        }
      }
    }
  }
  return repaired;
}

}  // namespace

void optimizeFace(Optimizer& O, Triangulation& T, const FaceMeshOptions& opt) {
  O.run(opt.optimizePasses);
  refineDeviationFirst(O, opt);
  regularizeValences(O, opt);
  int repaired = repairSliverBatches(O, T, opt);
  repaired += repairSliversOneByOne(O, T, opt);
  // the repairs were local: one more pass over the whole face lets their surroundings settle
  if (repaired > 0) {
    O.swapPass();
    O.smoothPass();
    O.swapPass();
  }
  // size conformity last: vertices with an edge out of the unit band move where fewer are
  if (opt.optimizePasses > 0) O.lengthPass();
  // then the summed radius ratio, keeping the worst triangles, the angles and the size band;
  // only around irregular valences (docs/tuning/face_mesher.md)
  if (opt.optimizePasses > 0) {
    std::vector<char> active = O.irregularZone();
    for (int k = 0; k < kPolishPasses; ++k)
      if (O.polishPass(active) == 0) break;
  }
  if ((opt.maxDeviation > 0 || opt.maxDeviationRatio > 0 || !opt.deviationZones.empty()) &&
      O.refineDeviation(opt.maxDeviation, opt.maxDeviationRatio, opt.minSplitLength, &opt.deviationZones) > 0) {
    O.smoothPass();
    O.swapPass();
  }
}

}  // namespace paramesh
