// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file SecondOrder.cpp
/// Second-order stage: mid-nodes on the CAD (tria6 / quad8 / line3), straightened where a curved
/// element's Jacobian would not stay positive; tet10 mid-nodes (Tet10.hpp). Reads model, triUv, quadUv, segmentT; writes mesh,
/// report (mid-node counts, min scaled Jacobian).

#include "paramesh/pipeline/MeshContext.hpp"
#include "paramesh/pipeline/Tuning.hpp"
#include "paramesh/algo/HighOrder.hpp"
#include "paramesh/volume/Tet10.hpp"

namespace paramesh {

using namespace tuning;

void MeshContext::secondOrder() {
  Timer tm;
  const HighOrderStats st = makeSecondOrder(mesh, model, triUv, quadUv, segmentT);
  report.midNodes = st.midNodes;
  report.straightenedMidNodes = st.straightened;
  report.minScaledJacobian = st.minJacobianRatio;
  if (st.straightened)
    report.warnings.push_back(std::to_string(st.straightened) + " mid-nodes of " + std::to_string(st.invalidElements) +
                              " curved elements were put back on the chord to keep the Jacobian positive");
  if (!mesh.tets.empty()) {
    const Tet10Stats ts = makeTet10(mesh);
    report.midNodes += ts.midNodes;
    report.straightenedTets = ts.straightened;
    report.minTetJacobian = ts.minScaledJacobian;
    if (ts.straightened)
      report.warnings.push_back(std::to_string(ts.straightened) +
                                " curved tet10s were made straight to keep their Jacobian positive");
  }
  stage("second_order", tm.seconds());
}

}  // namespace paramesh
