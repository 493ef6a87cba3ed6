// Which structure codes the tests exercise: the constructed tests (structure_checks_test.cpp,
// structure_robustness_test.cpp) record every code their inputs raise, the suite runner every
// code a Khronos case expects. At the end of the run the table code -> our tests -> suite cases is
// printed, with the catalogue codes no constructed test raises yet (issue 14 asks for one test per
// code; until every code has one, the uncovered list is printed rather than failing the run).
#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <set>
#include <span>
#include <string>

#include "core/report.hpp"

namespace gltf_pbr::coverage {

struct Table {
  std::map<std::string, std::set<std::string>> constructed;  // code -> test names
  std::map<std::string, int> suite;                          // code -> cases expecting it
};

inline Table& table() {
  static Table t;
  return t;
}

// Validates `bytes` (named `name`, whose extension picks glTF or GLB) with the built-in rules and
// records the codes raised under the running test's name.
Report validate_and_record(const std::filesystem::path& name, std::span<const std::uint8_t> bytes);
// The same for a document given as text.
inline Report validate_text(const std::string& text, const std::filesystem::path& name = "input.gltf") {
  return validate_and_record(name, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}
inline void record_suite_code(const std::string& code) { ++table().suite[code]; }

}  // namespace gltf_pbr::coverage
