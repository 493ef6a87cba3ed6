// The three forms of a validation report: the Khronos JSON schema (core/report.hpp), text for
// people grouped by material, and SARIF 2.1.0 for CI code scanning.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/report.hpp"
#include "rules/rule_set.hpp"

namespace gltf_pbr::cli {

// Messages grouped by material (pointers under /materials/N), then the rest of the document;
// ANSI colour when `colour`.
std::string report_text(const Report& report, bool colour);

// One SARIF run with one result per message. A JSON pointer has no line in SARIF's model, so it
// travels as a logical location (kind "member") and in the message.
nlohmann::ordered_json sarif_log(const std::vector<Report>& reports, const RuleSet& rules);

}  // namespace gltf_pbr::cli
