// ResultCache keeps a result only while the files its key was taken from still hold those bytes.
#include "api/result_cache.hpp"

#include <fcntl.h>
#include <sys/stat.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "test_support.hpp"

namespace gltf_pbr {
namespace {

// Rewrites the file itself (same inode), as an editor saving in place does.
void write_in_place(const fs::path& file, const std::string& text) { std::ofstream(file, std::ios::binary) << text; }

timespec status_changed(const fs::path& file) {
  struct stat status {};
  EXPECT_EQ(::stat(file.c_str(), &status), 0);
  return status.st_ctim;
}

bool same_time(const timespec& a, const timespec& b) { return a.tv_sec == b.tv_sec && a.tv_nsec == b.tv_nsec; }

// An input naming one external buffer, and a key taken of both.
struct KeyedInput {
  explicit KeyedInput(const fs::path& folder)
      : cache(folder / "cache"), input(folder / "in.gltf"), buffer(folder / "in.bin") {
    write_in_place(buffer, "0123456789abcdef");
    write_in_place(input, R"({"asset":{"version":"2.0"},"buffers":[{"uri":"in.bin","byteLength":16}]})");
    key = cache.key(input, "test settings", false).value();
  }
  ResultCache cache;
  fs::path input, buffer;
  std::string key;
};

// A key of an input the cache has not seen hashes its bytes and lists the files it names: from one
// read of the file (convert then reads it once more, on a miss).
TEST(ResultCache, AKeyOfANewInputReadsItOnce) {
  test::ScratchDir scratch;
  const long documents = work_counters().documents_read;
  KeyedInput keyed(scratch.path());
  EXPECT_EQ(work_counters().documents_read - documents, 1);
  // The key is of the buffer it names too: changing the buffer changes the key.
  write_in_place(keyed.buffer, "fedcba9876543210");
  EXPECT_NE(keyed.cache.key(keyed.input, "test settings", false), keyed.key);
}

TEST(ResultCache, KeepsAResultWhoseSourceOnlyGainedAHardLinkMeanwhile) {
  test::ScratchDir scratch;
  KeyedInput keyed(scratch.path());
  const timespec before = status_changed(keyed.buffer);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));     // past the file system's time tick
  fs::create_hard_link(keyed.buffer, scratch / "elsewhere.bin");  // as another job's library copy does
  ASSERT_FALSE(same_time(status_changed(keyed.buffer), before)) << "the link left the status-change time alone";

  keyed.cache.store(keyed.key, nlohmann::json::object(), {});
  EXPECT_EQ(keyed.cache.stats_json()["stored"], 1) << keyed.cache.stats_json().dump();
}

TEST(ResultCache, RefusesAResultWhoseSourceChangedUnderItsOldModificationTime) {
  test::ScratchDir scratch;
  KeyedInput keyed(scratch.path());
  struct stat status {};
  ASSERT_EQ(::stat(keyed.buffer.c_str(), &status), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  write_in_place(keyed.buffer, "fedcba9876543210");  // same size; then the old mtime put back
  const timespec times[2] = {status.st_atim, status.st_mtim};
  ASSERT_EQ(::utimensat(AT_FDCWD, keyed.buffer.c_str(), times, 0), 0);

  keyed.cache.store(keyed.key, nlohmann::json::object(), {});
  EXPECT_EQ(keyed.cache.stats_json()["stored"], 0);
  EXPECT_EQ(keyed.cache.stats_json()["notStored"], 1);
}

}  // namespace
}  // namespace gltf_pbr
