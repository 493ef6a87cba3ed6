// The hostile-input corpus (tests/hostile_inputs/README.md) through every command: a report or a
// clear error for each input, never a crash, a hang, unbounded memory, an escape sequence on a
// terminal or the contents of a file outside the asset.
#include <gtest/gtest.h>

#include "test_support.hpp"

namespace gltf_pbr {
namespace {

using test::quoted;

// The hand-made corpus, and what the fuzzers found (scripts/fuzz.sh).
std::vector<fs::path> corpus_inputs() {
  std::vector<fs::path> inputs;
  for (const char* folder : {"hostile_inputs", "fuzz_regressions"})
    for (const auto& entry : fs::directory_iterator(fs::path(GLTF_PBR_SOURCE_DIR) / "tests" / folder))
      if (entry.path().extension() == ".gltf" || entry.path().extension() == ".glb") inputs.push_back(entry.path());
  std::sort(inputs.begin(), inputs.end());
  return inputs;
}

// Each command gets 120 s and 4 GiB: ulimit in the plain build, ASan's RSS limit under ASan (which
// reserves terabytes of address space, so ulimit -v cannot apply there).
test::CliResult run_bounded(const std::string& arguments, const test::ScratchDir& scratch) {
  const std::string limits = test::kBuiltWithAddressSanitizer
                                 ? "ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}hard_rss_limit_mb=4096\" timeout 120 "
                                 : "ulimit -v 4194304; timeout 120 ";
  const fs::path out = scratch / "out.txt", err = scratch / "err.txt", script = scratch / "command.sh";
  test::write_text(script, limits + "'" GLTF_PBR_CLI "' " + arguments + "\n");
  const int status = std::system(("bash " + quoted(script) + " >" + quoted(out) + " 2>" + quoted(err)).c_str());
  test::CliResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = test::read_text(out);
  result.err = test::read_text(err);
  return result;
}

TEST(HostileCorpus, EveryInputGetsAReportOrAClearErrorFromEveryCommand) {
  const std::vector<fs::path> inputs = corpus_inputs();
  ASSERT_GE(inputs.size(), 13u);
  const std::string passwd = test::read_text("/etc/passwd");
  const std::string passwd_line = passwd.substr(0, passwd.find('\n'));  // "root:x:0:0:..."
  for (const fs::path& input : inputs) {
    SCOPED_TRACE(input.filename().string());
    test::ScratchDir scratch;
    const std::string file = quoted(input);
    const std::vector<std::pair<std::string, bool>> commands{
        // (arguments, text for people)
        {"convert -v " + file + " -o " + quoted(scratch / "converted"), true},
        {"validate " + file, true},
        {"validate -f json " + file, false},
        {"validate -f sarif " + file, false},
        {"preview --size 64 " + file + " -o " + quoted(scratch / "preview"), true},
    };
    for (const auto& [arguments, for_people] : commands) {
      const test::CliResult r = run_bounded(arguments, scratch);
      const std::string all = r.out + r.err;
      EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << arguments << " exited " << r.exit_code << "\n" << r.err;
      if (r.exit_code == 1 && arguments.starts_with("convert")) {
        EXPECT_NE(r.err.find(input.string()), std::string::npos) << "the error names the file\n" << r.err;
      }
      for (const char* crash : {"terminate called", "Sanitizer", "runtime error:", "Segmentation", "bad_alloc"})
        EXPECT_EQ(all.find(crash), std::string::npos) << arguments << "\n" << all;
      EXPECT_EQ(all.find(passwd_line), std::string::npos) << arguments << " printed /etc/passwd";
      if (for_people) {
        EXPECT_EQ(all.find('\x1b'), std::string::npos) << arguments << " let an escape through:\n" << all;
        EXPECT_EQ(all.find('\x07'), std::string::npos) << arguments;
      }
    }
    if (fs::exists(scratch / "converted")) {
      for (const fs::path& output : test::files_under(scratch / "converted"))
        EXPECT_EQ(test::read_text(output).find(passwd_line), std::string::npos) << output << " holds /etc/passwd";
    }
  }
}

}  // namespace
}  // namespace gltf_pbr
