// The GLB container codes (glTF 2.0 spec 4.4, "GLB File Format Specification"), one constructed
// file each and a near miss, with the issues in the order the reference reports them. Each case
// was also run through the npm gltf-validator (2.0.0-dev.3.10), which gives the same codes, offsets
// and order; its INVALID_JSON text differs (the npm build parses with JavaScript's JSON.parse).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "tests/structure/coverage.hpp"

namespace gltf_pbr {
namespace {

constexpr std::uint32_t kJson = 0x4E4F534A, kBin = 0x004E4942, kOther = 0x5A595857;

struct Chunk {
  std::uint32_t type;
  std::string data;  // padded to 4 bytes: JSON with spaces, anything else with zeros
};

void put_u32(std::vector<std::uint8_t>& bytes, std::uint32_t value) {
  std::uint8_t raw[4];
  std::memcpy(raw, &value, 4);  // GLB is little-endian, as are the hosts we build for
  bytes.insert(bytes.end(), raw, raw + 4);
}

// A GLB of `chunks`; its header declares `declared_length`, or its real length when that is 0,
// and `tail` follows the last chunk undeclared.
std::vector<std::uint8_t> glb(const std::vector<Chunk>& chunks, std::uint32_t declared_length = 0,
                              const char* magic = "glTF", const std::string& tail = "") {
  std::vector<std::uint8_t> body;
  for (const Chunk& chunk : chunks) {
    std::string data = chunk.data;
    while (data.size() % 4) data += chunk.type == kJson ? ' ' : '\0';
    put_u32(body, static_cast<std::uint32_t>(data.size()));
    put_u32(body, chunk.type);
    body.insert(body.end(), data.begin(), data.end());
  }
  body.insert(body.end(), tail.begin(), tail.end());
  std::vector<std::uint8_t> bytes(magic, magic + 4);
  put_u32(bytes, 2);
  put_u32(bytes, declared_length ? declared_length : static_cast<std::uint32_t>(12 + body.size()));
  bytes.insert(bytes.end(), body.begin(), body.end());
  return bytes;
}

const std::string kDocument = R"({"asset":{"version":"2.0"}})";                                     // 28 bytes padded
const std::string kBufferDocument = R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":4}]})";  // 56 bytes
const std::string kFourBytes(4, '\0');

// Each issue as "CODE @offset" or "CODE /pointer", in report order.
std::vector<std::string> issues_of(const std::vector<std::uint8_t>& bytes) {
  std::vector<std::string> found;
  for (const Issue& issue : coverage::validate_and_record("x.glb", bytes).messages)
    found.push_back(issue.code + (issue.offset ? " @" + std::to_string(*issue.offset) : " " + issue.pointer));
  return found;
}

using Issues = std::vector<std::string>;

TEST(GlbContainer, AFileThatIsNotGlbIsRefusedByItsMagic) {
  EXPECT_EQ(issues_of(glb({{kJson, kDocument}}, 0, "glTX")), Issues{"GLB_INVALID_MAGIC @0"});
  EXPECT_EQ(issues_of(glb({{kJson, kDocument}})), Issues{});
}

TEST(GlbContainer, ALengthTooSmallIsMeasuredAgainstEveryChunkAndTheRealEnd) {
  EXPECT_EQ(issues_of(glb({{kJson, kDocument}, {kOther, "abcd"}}, 8)),
            (Issues{"GLB_LENGTH_TOO_SMALL @8", "GLB_CHUNK_TOO_BIG @12", "GLB_CHUNK_TOO_BIG @48",
                    "GLB_UNKNOWN_CHUNK_TYPE @48", "GLB_LENGTH_MISMATCH @60"}));
  // Large enough for the header: no GLB_LENGTH_TOO_SMALL, the chunks still measured.
  EXPECT_EQ(issues_of(glb({{kJson, kDocument}, {kOther, "abcd"}}, 16)),
            (Issues{"GLB_CHUNK_TOO_BIG @12", "GLB_CHUNK_TOO_BIG @48", "GLB_UNKNOWN_CHUNK_TYPE @48",
                    "GLB_LENGTH_MISMATCH @60"}));
}

TEST(GlbContainer, ChunkOrderJsonFirstThenBinAndEachOnce) {
  // (The buffer is not used by anything: UNUSED_OBJECT, as the reference reports too.)
  EXPECT_EQ(issues_of(glb({{kBin, kFourBytes}, {kJson, kBufferDocument}})),
            (Issues{"GLB_UNEXPECTED_FIRST_CHUNK @12", "UNUSED_OBJECT /buffers/0"}));
  EXPECT_EQ(issues_of(glb({{kJson, kBufferDocument}, {kOther, "abcd"}, {kBin, kFourBytes}})),
            (Issues{"GLB_UNKNOWN_CHUNK_TYPE @76", "GLB_UNEXPECTED_BIN_CHUNK @88", "UNUSED_OBJECT /buffers/0"}));
  EXPECT_EQ(issues_of(glb({{kJson, kBufferDocument}, {kBin, kFourBytes}, {kOther, "abcd"}})),
            (Issues{"GLB_UNKNOWN_CHUNK_TYPE @88", "UNUSED_OBJECT /buffers/0"}));
  EXPECT_EQ(issues_of(glb({{kJson, kBufferDocument}, {kBin, kFourBytes}, {kBin, kFourBytes}})),
            (Issues{"GLB_DUPLICATE_CHUNK @88", "UNUSED_OBJECT /buffers/0"}));
  EXPECT_EQ(issues_of(glb({{kJson, kDocument}, {kJson, kDocument}})), (Issues{"GLB_DUPLICATE_CHUNK @48"}));
}

TEST(GlbContainer, EmptyChunks) {
  EXPECT_EQ(issues_of(glb({{kJson, kDocument}, {kBin, ""}})), (Issues{"GLB_EMPTY_BIN_CHUNK @48"}));
  EXPECT_EQ(issues_of(glb({{kJson, ""}})), (Issues{"GLB_EMPTY_CHUNK @12"}));
  // Whatever follows an empty JSON chunk ends its text, which is then no JSON.
  EXPECT_EQ(issues_of(glb({{kJson, ""}, {kOther, "abcd"}})),
            (Issues{"GLB_EMPTY_CHUNK @12", "GLB_UNKNOWN_CHUNK_TYPE @20", "INVALID_JSON "}));
  EXPECT_EQ(issues_of(glb({{kJson, ""}}, 0, "glTF", std::string("\x04\0", 2))),
            (Issues{"GLB_EMPTY_CHUNK @12", "INVALID_JSON ", "GLB_UNEXPECTED_END_OF_CHUNK_HEADER @22"}));
}

TEST(GlbContainer, AStreamThatEndsInsideAChunkHeader) {
  EXPECT_EQ(issues_of(glb({{kJson, kDocument}}, 0, "glTF", std::string("\x04\0\0\0", 4))),
            (Issues{"GLB_UNEXPECTED_END_OF_CHUNK_HEADER @52"}));
}

TEST(GlbContainer, TheBinChunkHoldsBufferZeroWithAtMostThreeBytesOfPadding) {
  // Both are found as the buffers are loaded, after the unused objects.
  EXPECT_EQ(issues_of(glb({{kJson, kBufferDocument}})),
            (Issues{"UNUSED_OBJECT /buffers/0", "BUFFER_MISSING_GLB_DATA /buffers/0"}));
  EXPECT_EQ(issues_of(glb({{kJson, kBufferDocument}, {kBin, std::string(12, '\0')}})),
            (Issues{"UNUSED_OBJECT /buffers/0", "BUFFER_GLB_CHUNK_TOO_BIG /buffers/0"}));
  const std::string one_byte = R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":1}]})";
  EXPECT_EQ(issues_of(glb({{kJson, one_byte}, {kBin, kFourBytes}})), Issues{"UNUSED_OBJECT /buffers/0"});
}

TEST(GlbContainer, AStreamThatEndsInsideAChunkLoadsNoResources) {
  // The same document names a missing file: found when the stream is whole, not when it is cut.
  const std::string external = R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":4,"uri":"missing.bin"}]})";
  const auto whole = issues_of(glb({{kJson, external}}));
  EXPECT_NE(std::find(whole.begin(), whole.end(), "IO_ERROR /buffers/0/uri"), whole.end());
  const auto cut = issues_of(glb({{kJson, external}}, 0, "glTF", std::string("\x10\0\0\0BIN\0\0\0", 10)));
  ASSERT_FALSE(cut.empty());
  EXPECT_EQ(cut.back(), "GLB_UNEXPECTED_END_OF_CHUNK_DATA @" + std::to_string(glb({{kJson, external}}).size() + 10));
  EXPECT_EQ(std::find(cut.begin(), cut.end(), "IO_ERROR /buffers/0/uri"), cut.end());
}

TEST(GlbContainer, ADataUriThatParsesIsInTheGlbBeforeItsMediaTypeIsJudged) {
  // DATA_URI_GLB follows the URI's syntax and base64, and comes before the media type checks
  // (the reference's order on constructed files); an invalid URI declares no media type.
  const auto image = [](const std::string& uri) {
    return issues_of(
        glb({{kJson, R"({"asset":{"version":"2.0"},"images":[{"uri":")" + uri + R"("}],"textures":[{"source":0}]})"}}));
  };
  const std::string png =
      "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR4nGNgYGD4DwABBAEAwS2OUAAAAABJRU5ErkJggg==";
  EXPECT_EQ(image("data:image/jpeg;base64," + png), (Issues{"URI_GLB /images/0/uri", "DATA_URI_GLB /images/0/uri",
                                                            "INVALID_URI /images/0/uri", "UNUSED_OBJECT /textures/0"}));
  EXPECT_EQ(image("data:text/plain;base64," + png), (Issues{"URI_GLB /images/0/uri", "DATA_URI_GLB /images/0/uri",
                                                            "INVALID_URI /images/0/uri", "UNUSED_OBJECT /textures/0"}));
  EXPECT_EQ(image("data:image/png;base64,@@@@"),
            (Issues{"URI_GLB /images/0/uri", "INVALID_URI /images/0/uri", "UNUSED_OBJECT /textures/0"}));
  EXPECT_EQ(issues_of(glb(
                {{kJson,
                  R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":3,"uri":"data:text/plain;base64,AAAA"}]})"}})),
            (Issues{"URI_GLB /buffers/0/uri", "DATA_URI_GLB /buffers/0/uri",
                    "BUFFER_DATA_URI_MIME_TYPE_INVALID /buffers/0/uri", "UNUSED_OBJECT /buffers/0"}));
}

}  // namespace
}  // namespace gltf_pbr
