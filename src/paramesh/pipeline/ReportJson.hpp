// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file ReportJson.hpp
/// The JSON form of a run report (the schema is documented in README.md, "JSON report").
#pragma once
#include <string>

#include "paramesh/io/Json.hpp"
#include "paramesh/pipeline/Report.hpp"

namespace paramesh {

Json reportToJson(const Report& r);
/// The "audit" section of the report.
Json auditToJson(const AuditResult& a);
/// Writes reportToJson(r) to path (indented). Throws Error when the file cannot be written.
void writeReportJson(const std::string& path, const Report& r);

}  // namespace paramesh
