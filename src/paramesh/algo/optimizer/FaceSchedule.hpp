// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file FaceSchedule.hpp
/// The sequence of optimiser passes and repairs one face gets after its frontal mesh.
#pragma once
#include "paramesh/algo/FaceMesher.hpp"
#include "paramesh/algo/optimizer/Optimizer.hpp"

namespace paramesh {

class Triangulation;

/// Optimises the face triangulation T that O works on (O holds T): size conformity, swaps and
/// smoothing, the deviation bounds of opt, valences, slivers, polish.
void optimizeFace(Optimizer& O, Triangulation& T, const FaceMeshOptions& opt);

}  // namespace paramesh
