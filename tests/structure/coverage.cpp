#include "tests/structure/coverage.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "rules/rule_set.hpp"
#include "validators/structure/structure.hpp"

namespace gltf_pbr::coverage {

Report validate_and_record(const std::filesystem::path& name, std::span<const std::uint8_t> bytes) {
  Report report;
  validate_structure(name, bytes, builtin_rules(), StructureOptions{}, report);
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string test_name = test ? std::string(test->test_suite_name()) + "." + test->name() : "?";
  for (const Issue& issue : report.messages) table().constructed[issue.code].insert(test_name);
  return report;
}

namespace {

// Prints the table when every test has run (a gtest environment's TearDown).
class PrintCoverage : public ::testing::Environment {
 public:
  void TearDown() override {
    const Table& t = table();
    std::size_t covered = 0, codes = 0;
    std::string uncovered;
    std::printf("\nstructure code coverage: code | constructed tests | suite cases expecting it\n");
    for (const auto& [code, rule] : builtin_rules().all()) {
      if (rule.file != "rules/structure.json") continue;  // the Khronos catalogue's codes
      ++codes;
      const auto tests = t.constructed.find(rule.code);
      const auto cases = t.suite.find(rule.code);
      const std::size_t test_count = tests == t.constructed.end() ? 0 : tests->second.size();
      if (test_count)
        ++covered;
      else
        uncovered += " " + rule.code;
      std::printf("  %-58s %3zu %3d\n", rule.code.c_str(), test_count, cases == t.suite.end() ? 0 : cases->second);
    }
    std::printf("structure codes raised by a constructed test: %zu of %zu\nnot yet:%s\n", covered, codes,
                uncovered.c_str());
    // Only a run of every test sees every code: CTest runs the whole binary once so
    // (Structure.EveryCatalogueCodeHasAConstructedTest), with this variable set.
    if (std::getenv("GLTF_PBR_REQUIRE_EVERY_CODE") && covered < codes)
      ADD_FAILURE() << "catalogue codes without a constructed test:" << uncovered;
  }
};

const auto* registered = ::testing::AddGlobalTestEnvironment(new PrintCoverage);

}  // namespace
}  // namespace gltf_pbr::coverage
