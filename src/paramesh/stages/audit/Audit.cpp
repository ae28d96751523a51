// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Audit.cpp
/// Audit stage: the finished mesh checked independently of how it was made (audit/MeshAudit.hpp).
/// A finding turns an ok run into a degraded one (exit 3) whose message names the faces and edges;
/// the counts go to report.audit either way.
#include "paramesh/audit/MeshAudit.hpp"
#include "paramesh/audit/MeshDigest.hpp"
#include "paramesh/audit/Repair.hpp"
#include "paramesh/pipeline/MeshContext.hpp"

namespace paramesh {

AuditInput MeshContext::auditInput() const {
  AuditInput in{model, mesh, triUv, quadUv, {}};
  in.threads = threads;
  in.edgeRep = same.edgeRep;
  in.copyFace.assign(model.numFaces(), 0);
  for (size_t f = 0; f < faceStage.copyOf.size() && f < in.copyFace.size(); ++f) in.copyFace[f] = faceStage.copyOf[f] >= 0;
  return in;
}

void MeshContext::repairSurface() {
  Timer t;
  AuditInput in = auditInput();
  in.nodes = false;  // the repair mends elements only
  const AuditResult first = auditMesh(in);
  elementAudit = {first.badElements.empty(), 0, first};
  if (elementAudit.valid) elementAudit.digest = meshDigest(mesh, triUv, quadUv);
  if (!first.badElements.empty()) {
    repairedNodes = repairBadElements(model, mesh, triUv, quadUv, first.badElements);
    if (repairedNodes) {
      log.info("audit: " + std::to_string(first.badElements.size()) + " folded or inverted elements: " +
               std::to_string(repairedNodes) + " of their face nodes moved on the surface to mend them");
      report.quality = summarizeQuality(mesh, [this](Vec3 x) { return field.size(x); });
    }
  }
  stage("audit", t.seconds());
}

void MeshContext::audit() {
  progress.report(1.0, "audit");
  const AuditInput in = auditInput();
  Timer t;
  if (elementAudit.valid && meshDigest(mesh, triUv, quadUv) == elementAudit.digest) {
    // the mesh the repair pass audited, unchanged since: its element and edge-use findings hold
    report.audit = elementAudit.result;
    auditNodes(in, report.audit);
    report.audit.seconds = t.seconds();
  } else {
    report.audit = auditMesh(in);
  }
  elementAudit = {};
  report.audit.run = true;
  report.audit.repairedNodes = repairedNodes;
  stage("audit", report.audit.seconds);
  for (const std::string& n : report.audit.notes) log.info("audit: " + n);
  if (report.audit.passed()) return;
  std::string m;
  for (const std::string& pr : report.audit.problems) {
    log.warn("audit: " + pr);
    m += (m.empty() ? "" : "; ") + pr;
  }
  if (report.status == RunStatus::Ok) report.status = RunStatus::Degraded;
  report.message += "; the audit found " + m;
}

}  // namespace paramesh
